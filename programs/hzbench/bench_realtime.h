/*
 * bench_realtime.h — hzbench's real-time group: where a displayed frame's time goes at a real size,
 * and how far the whole frame is from the cost of its traversal alone.
 *
 * Contract: for each scene (the built-in one, then sponza.hzb and conference.hzb from scenes_dir; missing ones
 * are reported and skipped) and each mode (tdense, then TAA) a renderer is created from the board pools over a
 * recording wrapper around the scene's native accel. A round renders `warm` untimed, then `frames` timed
 * frames from scene time `start` at `hz` on `threads` threads (history reset first, so every round sees the
 * same frames); the modes take turns at going first. Per frame it measures begin_frame (animation, refit,
 * camera), the trace pass and the resolve pass (hz_render_run_frame_parts), with the wrapper only forwarding
 * calls. Each round then renders the same frames again with the wrapper timing every accel call: the time
 * inside accel calls (summed over threads, divided by the thread count) is `trace`, and the first pass's trace
 * pass minus that is `shade` (ray generation, shading, G-buffer writes). The timing pass's clock reads (two
 * per packet) stay out of the frame times. p50 and p99 are over every timed frame of every round; the parts are
 * medians over rounds of their per-frame means. After the first round the same round runs
 * again with the reconstruction's scalar twins (same frames, same bits): `resolve_scalar_ms`, its resolve part,
 * side by side with the SIMD one (not part of the frame figures). Every round also renders its frames once with
 * a barrier between the trace and the resolve pass (opts.serial_passes: the same frames): `serial_p50_ms`, their
 * p50, against the overlapped frames' p50.
 *
 * The last frame of the first round's timing pass is also recorded: every ray packet the renderer traced, as it was
 * given (lanes, coherence flag). `embree_trace_ms` replays them through Embree (8-ray packets, no any-hit
 * callback, no shading) built over the same pose, spread over the same threads, median of `rounds` replays;
 * `overhead` = frame p50 / embree_trace_ms. Boards without Embree leave both NaN.
 *
 * Returns the rows written (2 per scene), or -1 with err set.
 */
#ifndef HZ_BENCH_REALTIME_H
#define HZ_BENCH_REALTIME_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/status.h"

#define HZ_BENCH_REALTIME_MAX_ROUNDS 9
#define HZ_BENCH_REALTIME_MAX_FRAMES 512

typedef struct hz_bench_realtime_opts {
    const char *scenes_dir;
    uint32_t width, height;
    int threads;
    int rounds;             /* 1..HZ_BENCH_REALTIME_MAX_ROUNDS */
    uint32_t warm, frames;  /* frames 1..HZ_BENCH_REALTIME_MAX_FRAMES */
    float start;
    uint32_t hz;
    bool progress;
    bool compare_shading;   /* tdense with the packet shading against its scalar twin, instead of tdense and TAA */
} hz_bench_realtime_opts_t;

typedef struct hz_bench_realtime_row {
    char scene[32];
    const char *mode;      /* "tdense" or "taa" ("tdense-scalar": compare_shading's twin) */
    int threads;
    double p50_ms, p99_ms;
    double begin_ms, trace_ms, shade_ms, resolve_ms;
    double embree_trace_ms, overhead;
    double resolve_scalar_ms; /* the resolve pass with its scalar twin (hz_render_set_scalar_recon), round 0 */
    double serial_p50_ms;     /* p50 with a barrier between trace and resolve (hz_render_set_serial_passes) */
    double primary, shadow, secondary; /* rays of the recorded frame */
} hz_bench_realtime_row_t;

int hz_bench_realtime(const hz_bench_realtime_opts_t *o, hz_bench_realtime_row_t *rows, int max_rows,
                      hz_error_t *err);

/* --check-fit: the scenes and both renderers against the board's arenas (bench_fit.h). */
struct hz_bench_fit;
void hz_bench_realtime_fit(const hz_bench_realtime_opts_t *o, struct hz_bench_fit *fit);

#endif
