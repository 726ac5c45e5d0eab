/*
 * latency.h — the `hzrt latency` subcommand (see `hzrt latency --help`): display-locked latency and v-sync
 * analysis. Returns the process exit status: 0, HZ_EXIT_USAGE, HZ_EXIT_NOLOCK, or 64 + hz status code.
 * HZ_EXIT_NOLOCK: the run completed and its files were written, but the lock verdict (hz/lockv.h) says the
 * v-sync model never held a lock worth reporting; no period is printed.
 */
#ifndef HZ_PORT_LATENCY_H
#define HZ_PORT_LATENCY_H

#define HZ_EXIT_NOLOCK 3

int hz_cmd_latency(int argc, char **argv);

#endif
