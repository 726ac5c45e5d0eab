/*
 * renderopts.h — the render options every command that draws a scene takes (`hzrt render`, `hzrt latency
 * --render scene`, `hzrt show`), from one table: each option's value kind, limits, the modes it acts in and its
 * help line. The help text is printed from the table, limits included; the parser checks what the table says.
 *
 * Contract:
 *  - hz_ropts_take() looks at argv[i]: when it is a render option it checks the value against the table (a bad
 *    value prints why, naming the option, and returns -HZ_EXIT_USAGE), stores it and returns how many arguments
 *    it used (1 or 2); 0 when argv[i] is not a render option.
 *  - hz_ropts_check() runs after the whole command line: an option given for another mode than the one chosen is
 *    refused (it would do nothing), as are --blur-bvh without a shutter and --blur-bvh with Embree.
 *  - Every option here works with every sink and v-sync source; what depends on the sink is the command's.
 */
#ifndef HZ_PORT_RENDEROPTS_H
#define HZ_PORT_RENDEROPTS_H

#include <stdio.h>

#include "adaptive_cli.h"
#include "hz/accel.h"
#include "hz/render.h"
#include "hz/scenetime.h"

typedef struct hz_ropts {
    hz_render_opts_t opts;         /* mode and every option of level 0 (size and rate: the command's) */
    hz_accel_backend_t backend;
    hz_accel_blur_t blur;
    const char *blur_arg;          /* --blur-bvh as given (NULL: default) */
    int threads;                   /* 0: one per core */
    hz_time_ns_t start;            /* --start */
    hz_adaptive_cli_t adaptive;
    const char *given[64];         /* the render options on the command line, for the mode check */
    int given_n;
    const char *cmd;               /* names the command in messages */
} hz_ropts_t;

void hz_ropts_defaults(hz_ropts_t *r, const char *cmd, hz_render_mode_t mode);
int hz_ropts_take(hz_ropts_t *r, int argc, char **argv, int i);
int hz_ropts_check(hz_ropts_t *r);
/* The options' help lines (with their limits and modes). */
void hz_ropts_usage(FILE *f);

#endif
