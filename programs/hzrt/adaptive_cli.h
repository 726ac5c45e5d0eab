/*
 * adaptive_cli.h — what `--mode adaptive` (seed 003, hz/adaptive.h) needs on the command line beyond the option
 * table (renderopts.c holds its options): the focus-object list and the map file checked before the run, focus
 * names resolved once the scene is loaded, the map of active subpixels (Fig. 7's colours) and the summary figures.
 *
 * Contract:
 *  - hz_adaptive_cli_focus_ok() checks the form of a --focus-objects list (comma-separated, no empty item, no
 *    item longer than an object name, at most HZ_AMASK_MAX_FOCUS items); hz_adaptive_cli_map_ok() checks an
 *    --adaptive-map name (a file name before one of .png, .ppm, .pfm; .png only in builds with libpng). On
 *    failure both put the reason in why and return false: the command line is wrong (exit status 2).
 *  - hz_adaptive_cli_resolve turns the list into ids once the scene is loaded, by the one naming rule for
 *    objects: an item is an id (0..objects-1) or a name, and a name takes every object called so (object names
 *    may repeat: an OBJ's groups often do), a shell pattern (fnmatch) every object it matches. An id out of range
 *    or a name that matches nothing is HZ_E_INVALID_ARG naming it and the objects; ids come out sorted, each once.
 *  - hz_adaptive_map_write writes the last frame's mask as an image: black, red, green, blue, white for 0..4
 *    active subpixels (the file's extension picks PNG, PPM or PFM). Temp file + rename, as every sink.
 */
#ifndef HZ_PORT_ADAPTIVE_CLI_H
#define HZ_PORT_ADAPTIVE_CLI_H

#include <stdio.h>

#include "hz/render.h"
#include "summary.h"

typedef struct hz_adaptive_cli {
    const char *map_path;  /* --adaptive-map */
    const char *focus;     /* --focus-objects, unresolved */
} hz_adaptive_cli_t;

bool hz_adaptive_cli_focus_ok(const char *list, char *why, size_t cap);
bool hz_adaptive_cli_map_ok(const char *path, char *why, size_t cap);
hz_status_t hz_adaptive_cli_resolve(const hz_adaptive_cli_t *st, const hz_scene_t *scene, hz_adaptive_opts_t *ao,
                                    hz_error_t *err);
hz_status_t hz_adaptive_map_write(const char *path, const hz_renderer_t *r, uint32_t width, uint32_t height,
                                  hz_error_t *err);
/* Summary figures from the run's total stats over `frames` frames of width x height. */
void hz_adaptive_summary(const hz_render_stats_t *total, uint32_t frames, uint32_t width, uint32_t height,
                         bool mirrors, hz_summary_adaptive_t *out);

#endif
