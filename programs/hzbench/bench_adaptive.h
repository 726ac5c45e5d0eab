/*
 * bench_adaptive.h — hzbench's adaptive supersampling group (seed 003): fixed 9 spp against --mode adaptive at
 * several tau_alpha on the same scenes, size and threads, in one run; the frame split into presample, subpixel
 * test and extra samples; live lanes per extra-sample packet; PSNR (sRGB 8-bit) against a 256-spp reference.
 *
 * Contract: for each scene present in scenes_dir (conference, sponza, CornellBox-Mirror, lost-empire; missing
 * ones are reported and skipped) the renderers are created from the board pools; a round renders, per method,
 * `warm` untimed then `frames` timed frames at scene time `t` (the same frame each time, so every method and round
 * draws identical work), the methods taking turns at going first. A frame is begin_frame to end_frame with all
 * passes on `threads` threads; each pass is timed on its own (the adaptive mode's passes are presample, test,
 * extra). Figures are medians over rounds; the reference (full mode, ref_spp stratified samples, its own seed) is
 * rendered once per scene. rays_per_pixel counts camera rays; lanes_per_packet = extra camera rays / their
 * packets (adaptive only). Rows go to csv_path (if set) with exactly the columns
 *   scene,method,tau,ms,presample_ms,test_ms,extra_ms,rays_per_pixel,lanes_per_packet,psnr_srgb8_db
 * (fields that do not apply to fixed 9 spp — tau, test_ms, extra_ms, lanes_per_packet — left empty; its
 * presample_ms is its one trace pass). Returns the rows written, or -1 with err set.
 */
#ifndef HZ_BENCH_ADAPTIVE_H
#define HZ_BENCH_ADAPTIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/status.h"

#define HZ_BENCH_ADAPTIVE_MAX_ROUNDS 15
#define HZ_BENCH_ADAPTIVE_TAUS 3

typedef struct hz_bench_adaptive_opts {
    const char *scenes_dir;
    const char *csv_path;
    uint32_t width, height;
    int threads;
    int rounds;              /* 1..HZ_BENCH_ADAPTIVE_MAX_ROUNDS */
    uint32_t warm, frames;
    float t;                 /* scene time of the frame */
    uint32_t ref_spp;
    bool progress;
} hz_bench_adaptive_opts_t;

typedef struct hz_bench_adaptive_row {
    char scene[32];
    char method[16];         /* "full-9spp" or "adaptive" */
    double tau;              /* adaptive: tau_alpha; NaN for full */
    double ms, pass_ms[3];   /* frame; presample (or full's trace pass), test, extra */
    double rays_per_pixel, lanes_per_packet, psnr_srgb8_db;
} hz_bench_adaptive_row_t;

int hz_bench_adaptive(const hz_bench_adaptive_opts_t *o, hz_bench_adaptive_row_t *rows, int max_rows,
                      hz_error_t *err);

/* --check-fit: the scenes, the reference and the methods' renderers against the board's arenas (bench_fit.h). */
struct hz_bench_fit;
void hz_bench_adaptive_fit(const hz_bench_adaptive_opts_t *o, struct hz_bench_fit *fit);

#endif
