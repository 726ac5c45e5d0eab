/*
 * bench_adaptive.h — hzbench's adaptive supersampling group (seed 003): fixed 9 spp against --mode adaptive at
 * several tau_alpha on the same scenes, size and threads, in one run; the frame split into presample, subpixel
 * test and extra samples; live lanes per extra-sample packet; PSNR (sRGB 8-bit) against a 256-spp reference.
 *
 * The last method is adaptive at tau 1 with the focus objects (seed 003's "focused" row, the --focus-objects
 * option): the objects that fill at least a fifth of the central ninth of the frame in the reference (the
 * fixation region), else the one that fills most of it; it is left out (its fields NaN, empty in the CSV) where
 * that region shows only background. Every method's PSNR is also taken over the pixels whose reference primary
 * hit is a focus object (focus_psnr_srgb8_db), so the focused row's quality where the viewer looks is compared
 * with the others'.
 *
 * Contract: for each scene present in scenes_dir (conference, sponza, CornellBox-Mirror, lost-empire; missing
 * ones are reported and skipped) the renderers are created from the board pools; a round renders, per method,
 * `warm` untimed then `frames` timed frames at scene time `t` (the same frame each time, so every method and round
 * draws identical work), the methods taking turns at going first. A frame is begin_frame to end_frame with all
 * passes on `threads` threads; each pass is timed on its own (the adaptive mode's passes are presample, test,
 * extra). Figures are medians over rounds; the reference (full mode, ref_spp stratified samples, its own seed) is
 * rendered once per scene. rays_per_pixel counts camera rays; lanes_per_packet = extra camera rays / their
 * packets (adaptive only). Rows go to csv_path (if set) with exactly the columns
 *   scene,method,tau,ms,presample_ms,test_ms,extra_ms,rays_per_pixel,lanes_per_packet,psnr_srgb8_db,
 *   focus_objects,focus_share,focus_psnr_srgb8_db
 * (focus_objects: the ids separated by spaces; focus_share: the fraction of the frame's pixels that show them)
 * (fields that do not apply to fixed 9 spp — tau, test_ms, extra_ms, lanes_per_packet — left empty; its
 * presample_ms is its one trace pass). Returns the rows written, or -1 with err set.
 */
#ifndef HZ_BENCH_ADAPTIVE_H
#define HZ_BENCH_ADAPTIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/adaptive_mask.h"
#include "hz/status.h"

#define HZ_BENCH_ADAPTIVE_MAX_ROUNDS 15
#define HZ_BENCH_ADAPTIVE_TAUS 3
#define HZ_BENCH_ADAPTIVE_METHODS (2 + HZ_BENCH_ADAPTIVE_TAUS) /* 9 spp, adaptive at each tau, focused */
#define HZ_BENCH_ADAPTIVE_SCENES 4
#define HZ_BENCH_ADAPTIVE_MAX_ROWS (HZ_BENCH_ADAPTIVE_SCENES * HZ_BENCH_ADAPTIVE_METHODS)

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
    char method[16];         /* "full-9spp", "adaptive" or "adaptive-focus" */
    double tau;              /* adaptive: tau_alpha; NaN for full */
    double ms, pass_ms[3];   /* frame; presample (or full's trace pass), test, extra */
    double rays_per_pixel, lanes_per_packet, psnr_srgb8_db;
    uint32_t focus_count;    /* the scene's focus objects (the same on each of its rows); 0: none */
    uint16_t focus[HZ_AMASK_MAX_FOCUS];
    double focus_share;      /* fraction of the frame's pixels whose reference primary hit is a focus object */
    double focus_psnr_srgb8_db; /* PSNR over those pixels; NaN without focus objects */
} hz_bench_adaptive_row_t;

int hz_bench_adaptive(const hz_bench_adaptive_opts_t *o, hz_bench_adaptive_row_t *rows, int max_rows,
                      hz_error_t *err);

/* --check-fit: the scenes, the reference and the methods' renderers against the board's arenas (bench_fit.h). */
struct hz_bench_fit;
void hz_bench_adaptive_fit(const hz_bench_adaptive_opts_t *o, struct hz_bench_fit *fit);

#endif
