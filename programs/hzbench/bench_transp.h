/*
 * bench_transp.h — hzbench's transparency group (seed 004): per-frame time along a smoke scene's camera path
 * (hz_bench_transp_scenes: sponza-smoke.hzb, 12000 alpha-blended particles in Sponza's atrium flown through, and
 * smoke-column.hzb, a dense column of 6000 circled at a constant distance; one light with shadows through the
 * particles) for exact compositing,
 * Russian roulette, STD, DTAA, the hybrids and STD with Russian-roulette shadow rays (--rr-shadows) against
 * its deep shadows, in one run.
 *
 * Contract: one TAA renderer per method (1 spp + the TAA resolve, the paper's set-up) from the board pools at
 * width x height on `threads` threads. `frames` frames at scene times spread evenly over the camera path
 * (t_i = i * duration / frames); each round renders every frame with every method, the methods taking turns at
 * going first; a frame's time is begin_frame to end_frame (all passes) and the figure per (method, frame) is
 * the minimum over rounds (the machine is shared: the least disturbed run). p50 and p99 are over the frames
 * (nearest rank), rays per frame the mean of primary + shadow + secondary rays. Per stochastic method, the cost
 * of one rejected blended layer: the renderer's any-hit decision (hz_render_dither_decide) on every blended
 * triangle of the scene after the last frame, timed over the rejected ones only, repeated until 20 ms have
 * passed; reject_ns its time per layer (minimum over rounds), reject_share the share of candidates rejected
 * (0 for exact). A missing scene file is
 * reported and the group returns 0 rows; other failures return -1 with err set.
 */
#ifndef HZ_BENCH_TRANSP_H
#define HZ_BENCH_TRANSP_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/dither.h"
#include "hz/status.h"

#define HZ_BENCH_TRANSP_METHODS 8
#define HZ_BENCH_TRANSP_MAX_FRAMES 256

/* The group's scenes, in the order it runs them: {name, file in the scenes folder} (also --check-fit's list). */
#define HZ_BENCH_TRANSP_SCENES 2
extern const char *const hz_bench_transp_scenes[HZ_BENCH_TRANSP_SCENES][2];

typedef struct hz_bench_transp_opts {
    const char *scenes_dir;
    const char *const *scene; /* an entry of hz_bench_transp_scenes; NULL: the first */
    uint32_t width, height;
    int threads;
    int rounds;
    uint32_t frames;
    bool progress;
} hz_bench_transp_opts_t;

typedef struct hz_bench_transp_row {
    char scene[32], method[24];
    uint32_t frames;
    double p50_ms, p99_ms, rays_per_frame;
    double reject_ns, reject_share; /* one rejected blended layer's decision; the share rejected */
    double frame_ms[HZ_BENCH_TRANSP_MAX_FRAMES]; /* per frame along the path (frame i at scene time t_s[i]) */
    double t_s[HZ_BENCH_TRANSP_MAX_FRAMES];
} hz_bench_transp_row_t;

int hz_bench_transp(const hz_bench_transp_opts_t *o, hz_bench_transp_row_t rows[HZ_BENCH_TRANSP_METHODS],
                    hz_error_t *err);

/* --check-fit: the smoke scenes and every method's renderer against the board's arenas (bench_fit.h). */
struct hz_bench_fit;
void hz_bench_transp_fit(const hz_bench_transp_opts_t *o, struct hz_bench_fit *fit);

/* The same per-layer cost for method t on `scene` ("builtin": its 160 particles have untextured blended
 * materials, the cheap path; sponza-smoke's sprites take their alpha from a texture), after one TAA frame at
 * width x height on one thread: *ns per rejected layer, *share rejected. HZ_OK or err set. */
hz_status_t hz_bench_transp_layers(const char *scene, hz_transp_t t, uint32_t width, uint32_t height, double *ns,
                                   double *share, hz_error_t *err);

#endif
