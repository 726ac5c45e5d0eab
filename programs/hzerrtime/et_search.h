/*
 * et_search.h — adaptive supersampling at its operating point (seed 003, Table 2): per scene and adaptive
 * family (`adaptive`, `adaptive-bilinear`), the largest threshold tau_alpha whose PSNR (sRGB 8-bit) reaches
 * full-frame 9 spp's on the same frames, found by bisection, and what it costs against 9 spp.
 *
 * Contract:
 *  - hz_et_adaptive_search(seq, reference, family, row9, row16, cfg, probes, max_probes, &nprobes, &result, err)
 *    runs `family` (a method of hz_et_render_methods, whose params are an hz_et_render_params_t) at thresholds
 *    chosen one after another, each a whole errtime run (hz_et_run: same reference, frames and scoring as every
 *    other row), and appends one row per probe to probes[] (method "<family>-search", knob "tau"). Probes: tau 1
 *    (if it already reaches row9's PSNR it is the answer), then HZ_ET_SEARCH_TAU_MIN (if it does not, no tau
 *    does: the result says so), then HZ_ET_SEARCH_STEPS bisections in log(tau) between the largest tau that
 *    reached and the smallest that did not. PSNR falls as tau grows only on average (it is measured, not
 *    modelled): the answer is the largest probed tau that reached, never an interpolation.
 *  - The result compares the answer's row with row9 and row16 (full-frame 9 and 16 spp of the same run): PSNR
 *    and mean FLIP side by side, time and camera rays as ratios to 9 spp's (medians of the measured frames).
 *  - hz_et_write_search_csv / _markdown write the results (temporary file + rename; errors name the path);
 *    hz_et_print_search prints the Markdown table.
 */
#ifndef HZ_ERRTIME_SEARCH_H
#define HZ_ERRTIME_SEARCH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "errtime.h"
#include "et_report.h"

#define HZ_ET_SEARCH_TAU_MIN 0.02
#define HZ_ET_SEARCH_STEPS 5
#define HZ_ET_SEARCH_PROBES 7 /* runs per search: 2 + HZ_ET_SEARCH_STEPS */

typedef struct hz_et_search {
    char scene[64], method[48];
    uint32_t width, height, probes;
    bool reached;            /* some probed tau reached 9 spp's PSNR */
    double tau;              /* the largest that did (else the smallest probed) */
    double psnr, flip, ms, camera_rays;          /* that probe's row */
    double psnr9, psnr16, flip9, flip16, ms9, ms16;
    double time_vs_9, rays_vs_9;                 /* ms / ms9, camera rays per pixel / 9 */
} hz_et_search_t;

hz_status_t hz_et_adaptive_search(const hz_et_sequence_t *seq, const hz_et_method_t *reference,
                                  const hz_et_method_t *family, const hz_et_row_t *row9, const hz_et_row_t *row16,
                                  const hz_et_config_t *cfg, hz_et_row_t *probes, size_t max_probes, size_t *nprobes,
                                  hz_et_search_t *result, hz_error_t *err);

#define HZ_ET_SEARCH_CSV_HEADER                                                                                  \
    "scene,method,width,height,probes,reached,tau,psnr_srgb8_db,psnr_9spp_db,psnr_16spp_db,flip_mean,"          \
    "flip_9spp,flip_16spp,ms_median,ms_9spp,ms_16spp,time_vs_9spp,camera_rays_per_pixel,sample_ratio_9spp"

hz_status_t hz_et_write_search_csv(const char *path, const hz_et_search_t *r, size_t n, hz_error_t *err);
hz_status_t hz_et_write_search_markdown(const char *path, const hz_et_search_t *r, size_t n, hz_error_t *err);
void hz_et_print_search(FILE *f, const hz_et_search_t *r, size_t n);

#endif
