/*
 * et_report.h — errtime's results and the files it writes: CSV, a Markdown table and an SVG chart.
 *
 * Contract:
 *  - One hz_et_row_t per method and knob setting on one scene (errtime's driver fills them, see errtime.h).
 *  - hz_et_pareto marks, per scene, the rows no other row beats on both axes: pareto_flip for (ms_median lower,
 *    flip lower), pareto_psnr for (ms_median lower, psnr_srgb8 higher). A row equal to another on both axes
 *    stays on the front; rows with a NaN coordinate never are.
 *  - CSV: a header line, then one line per row, columns as in HZ_ET_CSV_HEADER; numbers in C locale; infinite
 *    PSNR is written "inf"; text fields are quoted when they hold a comma, quote or newline.
 *  - Markdown: per scene, a "### scene" heading with the sequence, then one table with a line per row; where the
 *    scene has rows of both adaptive-colour-only and adaptive-multiple, a second table pairs them by tau-col
 *    (seed 003's Fig. 7: sample ratio against 16 spp, PSNR, FLIP, time; "-" where a pair lacks its partner).
 *  - SVG: one chart for one scene, two panels side by side: mean FLIP (lower is better) and PSNR on sRGB 8-bit
 *    (higher is better) against ms per displayed frame (median) on a log axis; one polyline per method through
 *    its settings in knob order, each point labelled with its knob value; Pareto-front points ringed and joined
 *    by a dashed step line. Infinite PSNR is drawn at the top edge and labelled "inf". Text is XML-escaped.
 *  - Every writer goes through fileio.h (temporary file + rename); errors name the path.
 */
#ifndef HZ_ERRTIME_REPORT_H
#define HZ_ERRTIME_REPORT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "hz/status.h"

typedef struct hz_et_row {
    char scene[64];
    char method[48];
    char knob[24];         /* knob label, e.g. "spp" */
    double value;          /* knob value, e.g. 4 */
    uint32_t width, height;
    uint32_t frames;       /* displayed frames rendered */
    uint32_t measured;     /* frames after warm-up: timed and scored */
    uint32_t refresh_hz;
    uint32_t di_k;         /* frames the eye integrates: refresh / 60 */
    double ms_median, ms_p99;
    double rays_per_frame; /* mean over measured frames */
    double psnr_srgb8;     /* dB, from the mean MSE over measured frames; +inf if identical */
    double psnr_linear;
    double ssim;           /* mean over measured frames */
    double flip;           /* mean FLIP, mean over measured frames */
    double di_flip;        /* display-integrated: mean over windows of k frames */
    double di_psnr_srgb8;
    double camera_rays_per_pixel; /* camera rays per pixel and displayed frame (NaN: the method does not say);
                                   * the CSV's sample_ratio_9spp is this / 9 */
    bool pareto_flip, pareto_psnr;
} hz_et_row_t;

#define HZ_ET_CSV_HEADER                                                                                         \
    "scene,method,knob,value,width,height,frames,measured,refresh_hz,ms_median,ms_p99,rays_per_frame,"           \
    "psnr_srgb8_db,psnr_linear_db,ssim,flip_mean,di_k,di_flip_mean,di_psnr_srgb8_db,pareto_flip,pareto_psnr,"      \
    "camera_rays_per_pixel,sample_ratio_9spp"

void hz_et_pareto(hz_et_row_t *rows, size_t n);

/* A CSV text field: as it is, or quoted (quotes doubled) when it holds a comma, quote or line break. */
void hz_et_csv_text(FILE *f, const char *s);

hz_status_t hz_et_write_csv(const char *path, const hz_et_row_t *rows, size_t n, hz_error_t *err);
hz_status_t hz_et_write_markdown(const char *path, const hz_et_row_t *rows, size_t n, hz_error_t *err);
void hz_et_print_markdown(FILE *f, const hz_et_row_t *rows, size_t n);
/* Rows of other scenes are ignored. */
hz_status_t hz_et_write_svg(const char *path, const hz_et_row_t *rows, size_t n, const char *scene, hz_error_t *err);

#endif
