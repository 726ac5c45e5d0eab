/*
 * latency.h — the `hzrt latency` subcommand (see `hzrt latency --help`): display-locked latency and v-sync
 * analysis. Returns the process exit status: 0, HZ_EXIT_USAGE, or 64 + hz status code.
 */
#ifndef HZ_PORT_LATENCY_H
#define HZ_PORT_LATENCY_H

int hz_cmd_latency(int argc, char **argv);

#endif
