/*
 * latency.h — the `hzrt latency` subcommand (see `hzrt latency --help`): display-locked latency and v-sync
 * analysis. Returns the process exit status: 0, HZ_EXIT_USAGE, HZ_EXIT_NOLOCK, or 64 + hz status code.
 * HZ_EXIT_NOLOCK: the run completed and its files were written, but the lock verdict (hz/lockv.h) says the
 * v-sync model never held a lock worth reporting; no period is printed.
 */
#ifndef HZ_PORT_LATENCY_H
#define HZ_PORT_LATENCY_H

#include <stdbool.h>

#include "renderopts.h"
#include "show.h"

#define HZ_EXIT_NOLOCK 3

int hz_cmd_latency(int argc, char **argv);

/* The render options into c's scene (after hz_ropts_check; the scene's prepare hook resolves focus names): 0 or
 * HZ_EXIT_USAGE. */
int hz_show_from_ropts(hz_show_cfg_t *c, hz_ropts_t *ro, const char *scene);

#endif
