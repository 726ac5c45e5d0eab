/*
 * showopts.h — the options of the frame loop's run that `hzrt render`, `hzrt latency` and `hzrt show` share
 * (source, sink, output, the simulated display, the lock verdict, run length, pacing, the governor), from one
 * table (opttab.h) that knows each option's limits, the sources, sinks and frames it acts with, and the commands
 * that take it. The help is printed from the table.
 *
 * Contract:
 *  - hz_sopts_take() looks at argv[*i]: when it is one of these options it checks the value against the table (a
 *    bad one prints why, naming the option, and returns -HZ_EXIT_USAGE), stores it in c, moves *i past its value
 *    and returns 1; 0 when argv[*i] is not one of them (or not one `cmd` takes).
 *  - hz_sopts_check() runs once the run's source, sink, frames and clock are known (run_where: HZ_OW_* bits of
 *    each group): an option given where it does nothing is refused, naming what it acts with (exit status 2).
 *  - hz_sopts_settings() writes, as JSON members, the effective value of each image-changing option in the table
 *    (hz_show_run stores the effective frame size, marker and governor in c).
 */
#ifndef HZ_PORT_SHOWOPTS_H
#define HZ_PORT_SHOWOPTS_H

#include <stdbool.h>
#include <stdio.h>

#include "optwhere.h"
#include "renderopts.h"
#include "show.h"

int hz_sopts_take(hz_show_cfg_t *c, unsigned cmd, int argc, char **argv, int *i);
/* One argument of a command that takes both tables (render, show, latency): the run options of `cmd`, then the
 * render options. Returns 1 when one of them took argv[*i] (*i left on its last value), 0 when neither knows it,
 * or minus the exit status of a bad value (already reported). */
int hz_opts_take(hz_show_cfg_t *c, unsigned cmd, hz_ropts_t *r, int argc, char **argv, int *i);
int hz_sopts_check(const hz_show_cfg_t *c, unsigned run_where);
void hz_sopts_usage(FILE *f, unsigned cmd);
void hz_sopts_settings(FILE *f, const hz_show_cfg_t *c, bool *first);
const hz_opt_t *hz_sopts_table(size_t *n);

#endif
