/*
 * renderopts.h — the render options every command that draws a scene takes (`hzrt render`, `hzrt latency
 * --render scene`, `hzrt show`), from one table (opttab.h): each option's value kind, limits, the modes it acts
 * in, whether it changes the image, and its help line. The help text is printed from the table, limits included;
 * the parser checks what the table says; summary.json's settings are written from it.
 *
 * Contract:
 *  - hz_ropts_take() looks at argv[i]: when it is a render option it checks the value against the table (a bad
 *    value prints why, naming the option, and returns -HZ_EXIT_USAGE), stores it and returns how many arguments
 *    it used (1 or 2); 0 when argv[i] is not a render option. Values that need nothing but the command line are
 *    checked here: the --focus-objects list's form, the --adaptive-map file name and extension.
 *  - hz_ropts_check() runs after the whole command line: an option given for another mode than the one chosen is
 *    refused (it would do nothing), as are --blur-bvh without a shutter, --blur-bvh with Embree and --rr-shadows
 *    without a stochastic --transparency.
 *  - Every option here works with every sink and v-sync source; what depends on the sink is the command's.
 *  - hz_ropts_settings() writes, as JSON members, the value each image-changing option of the table had in the
 *    run (`eff`: the options as rendered, focus names resolved): every option that acts in the run's mode, given
 *    or not, so two runs that differ in any of them record different settings.
 *  - hz_ropts_table() gives the table (tests walk it).
 */
#ifndef HZ_PORT_RENDEROPTS_H
#define HZ_PORT_RENDEROPTS_H

#include <stdio.h>

#include "adaptive_cli.h"
#include "hz/accel.h"
#include "hz/render.h"
#include "hz/scenetime.h"
#include "optwhere.h"

typedef struct hz_ropts {
    hz_render_opts_t opts;         /* mode and every option of level 0 (size and rate: the command's) */
    hz_accel_backend_t backend;
    hz_accel_blur_t blur;
    const char *blur_arg;          /* --blur-bvh as given (NULL: default) */
    hz_accel_rigid_t rigid;
    const char *rigid_arg;         /* --rigid as given (NULL: default) */
    hz_accel_segments_t segments;
    const char *segments_arg;      /* --motion-segments as given (NULL: default) */
    int threads;                   /* 0: one per core */
    hz_time_ns_t start;            /* --start */
    hz_adaptive_cli_t adaptive;    /* --focus-objects (unresolved), --adaptive-map */
    const hz_opt_t *given[64];     /* the render options on the command line, for the mode check */
    int given_n;
    const char *cmd;               /* names the command in messages */
} hz_ropts_t;

void hz_ropts_defaults(hz_ropts_t *r, const char *cmd, hz_render_mode_t mode);
int hz_ropts_take(hz_ropts_t *r, int argc, char **argv, int i);
int hz_ropts_check(hz_ropts_t *r);
/* The options' help lines (with their limits and modes). */
void hz_ropts_usage(FILE *f);
/* JSON members ("key": value, ...) of the image-changing options; *first: no comma before the first member. */
void hz_ropts_settings(FILE *f, const hz_ropts_t *r, const hz_render_opts_t *eff, bool *first);
const hz_opt_t *hz_ropts_table(size_t *n);
/* The scene source's prepare hook (scenesrc.h), ctx an hz_ropts_t: resolves --focus-objects in the loaded scene;
 * says (unless muted) when a stochastic --transparency meets a scene with nothing blended. */
hz_status_t hz_ropts_prepare(void *ctx, const hz_scene_t *scene, hz_render_opts_t *opts, hz_error_t *err);

#endif
