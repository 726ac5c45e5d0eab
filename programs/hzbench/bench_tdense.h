/*
 * bench_tdense.h — hzbench's temporally dense group: displayed-frame time of tdense (one sample per 2x2 tile
 * and frame, seed 001) against full-frame 1 spp + TAA on the same scene, size and threads, in one run.
 *
 * Contract: for each scene (the built-in one, then sponza.hzb and conference.hzb from scenes_dir when they
 * exist; missing ones are reported and skipped), both renderers are created from the board pools and run
 * `rounds` rounds; a round renders, per mode, `warm` untimed then `frames` timed frames from scene time
 * `start` at `hz` (history reset first, so every round sees the same frames), the modes taking turns at going
 * first. A frame's time is begin_frame to end_frame with all passes on `threads` threads (scene animation,
 * accel refit, tracing and the resolve: what a displayed frame costs). Figures are medians over rounds, the
 * ratio (TAA ms / tdense ms) is taken per round; the parts of a frame (begin_frame: animation, refit and
 * camera; the trace pass; the resolve pass) are timed too, to show what limits the ratio. Returns the rows
 * written, or -1 with err set.
 */
#ifndef HZ_BENCH_TDENSE_H
#define HZ_BENCH_TDENSE_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/status.h"

#define HZ_BENCH_TDENSE_MAX_ROUNDS 15

typedef struct hz_bench_tdense_opts {
    const char *scenes_dir;
    uint32_t width, height;
    int threads;
    int rounds;             /* 1..HZ_BENCH_TDENSE_MAX_ROUNDS */
    uint32_t warm, frames;
    float start;
    uint32_t hz;
    bool progress;
} hz_bench_tdense_opts_t;

typedef struct hz_bench_tdense_row {
    char scene[32];
    double tdense_ms, taa_ms;      /* median over rounds of the mean displayed-frame time */
    double ratio, ratio_min, ratio_max;
    double tdense_rays, taa_rays;  /* rays of the last frame (primary + shadow + secondary) */
    double part_ms[2][3];          /* [tdense, taa][begin_frame, trace pass, resolve pass], medians */
} hz_bench_tdense_row_t;

int hz_bench_tdense(const hz_bench_tdense_opts_t *o, hz_bench_tdense_row_t *rows, int max_rows, hz_error_t *err);

/* --check-fit: the scenes and both renderers against the board's arenas (bench_fit.h). */
struct hz_bench_fit;
void hz_bench_tdense_fit(const hz_bench_tdense_opts_t *o, struct hz_bench_fit *fit);

#endif
