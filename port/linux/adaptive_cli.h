/*
 * adaptive_cli.h — the command line of `--mode adaptive` (seed 003, hz/adaptive.h) for `hzrt render`: the nine
 * thresholds, --tau, --normal-angle, --focus-objects and --adaptive-map; the map of active subpixels (Fig. 7's
 * colours) and the summary figures.
 *
 * Contract:
 *  - hz_adaptive_cli_option(opt, value, ...) returns 0 when opt is not one of these options, 1 or 2 for the
 *    arguments it consumed, and -HZ_EXIT_USAGE after printing why a value is bad (naming the option).
 *  - hz_adaptive_cli_check refuses (HZ_EXIT_USAGE, naming the first one) any of these options outside
 *    --mode adaptive, where they would do nothing.
 *  - --focus-objects takes object ids or names (hzrt info lists them), comma-separated; hz_adaptive_cli_resolve
 *    turns them into ids once the scene is loaded (an unknown name or an id out of range is HZ_E_INVALID_ARG).
 *  - hz_adaptive_map_write writes the last frame's mask as an image: black, red, green, blue, white for 0..4
 *    active subpixels (the file's extension picks PNG, PPM or PFM). Temp file + rename, as every sink.
 */
#ifndef HZ_PORT_ADAPTIVE_CLI_H
#define HZ_PORT_ADAPTIVE_CLI_H

#include <stdio.h>

#include "hz/render.h"
#include "summary.h"

typedef struct hz_adaptive_cli {
    const char *first;     /* first adaptive option given (for the error outside adaptive mode) */
    const char *map_path;  /* --adaptive-map */
    const char *focus;     /* --focus-objects, unresolved */
} hz_adaptive_cli_t;

int hz_adaptive_cli_option(const char *opt, const char *value, hz_adaptive_opts_t *ao, hz_adaptive_cli_t *st);
int hz_adaptive_cli_check(const hz_adaptive_cli_t *st, hz_render_mode_t mode);
void hz_adaptive_cli_usage(FILE *f);
hz_status_t hz_adaptive_cli_resolve(const hz_adaptive_cli_t *st, const hz_scene_t *scene, hz_adaptive_opts_t *ao,
                                    hz_error_t *err);
hz_status_t hz_adaptive_map_write(const char *path, const hz_renderer_t *r, uint32_t width, uint32_t height,
                                  hz_error_t *err);
/* Summary figures from the run's total stats over `frames` frames of width x height. */
void hz_adaptive_summary(const hz_render_stats_t *total, uint32_t frames, uint32_t width, uint32_t height,
                         bool mirrors, hz_summary_adaptive_t *out);

#endif
