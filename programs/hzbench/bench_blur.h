/*
 * bench_blur.h — hzbench's motion-blur group: temporally dense rendering with the shutter open, one MSBVH key
 * interval per 4-subframe cycle (hz_render_opts_t.tdense_cycle_keys: keys posed and the accel refitted once per
 * cycle) against posing and refitting every subframe, same scene, size, threads, pose keys and accel, in one run.
 *
 * Contract: for each scene (the built-in one, then sponza-rotated.hzb and furball-sway.hzb from scenes_dir when
 * they exist; missing ones are reported and skipped) one set of pose keys (K for the cycle's interval, which the
 * per-subframe renderer shares) and one native motion accel (cfg.blur = `blur`) are built, two tdense renderers
 * created, and `rounds` rounds run; a round renders, per mode, `warm` untimed then `frames` timed frames from
 * scene time `start` at `hz` with the shutter `shutter`, the modes taking turns at going first. Figures are
 * medians over rounds of the mean displayed-frame time (begin_frame to end_frame) and of its parts (begin_frame:
 * animation, pose keys and refit; the trace pass), plus the refits per frame. Returns the rows written, or -1
 * with err set.
 */
#ifndef HZ_BENCH_BLUR_H
#define HZ_BENCH_BLUR_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/accel.h"
#include "hz/status.h"

#define HZ_BENCH_BLUR_MAX_ROUNDS 15

typedef struct hz_bench_blur_opts {
    const char *scenes_dir;
    uint32_t width, height;
    int threads;
    int rounds;             /* 1..HZ_BENCH_BLUR_MAX_ROUNDS */
    uint32_t warm, frames;  /* frames: a multiple of 4 keeps whole cycles */
    float start, shutter;
    uint32_t hz;
    hz_accel_blur_t blur;
    bool progress;
} hz_bench_blur_opts_t;

typedef struct hz_bench_blur_row {
    char scene[32];
    uint32_t time_keys;
    double ms[2];            /* [per cycle, per subframe]: displayed-frame time, median over rounds */
    double begin_ms[2];      /* begin_frame (animation + pose keys + refit) */
    double trace_ms[2];      /* the trace pass */
    double refits[2];        /* accel refits per displayed frame */
    double ratio;            /* per-subframe ms / per-cycle ms, median over rounds */
} hz_bench_blur_row_t;

int hz_bench_blur(const hz_bench_blur_opts_t *o, hz_bench_blur_row_t *rows, int max_rows, hz_error_t *err);

/* --check-fit: the scenes, both renderers and the motion BVH against the board's arenas (bench_fit.h). */
struct hz_bench_fit;
void hz_bench_blur_fit(const hz_bench_blur_opts_t *o, struct hz_bench_fit *fit);

#endif
