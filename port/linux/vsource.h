/*
 * vsource.h — the Linux port's v-sync sources and sinks that need no device (the devices are in devices.h and
 * drm_port.h): the real clock, the simulated display, VCD/CSV replay and the null sink. The interfaces are
 * hz/display.h.
 */
#ifndef HZ_PORT_VSOURCE_H
#define HZ_PORT_VSOURCE_H

#include <stdint.h>

#include "hz/display.h"
#include "hz/vsynth.h"

/* The timebase on CLOCK_MONOTONIC. */
void hz_tb_init_real(hz_timebase_t *tb);

/* Simulated display: edges from a synthetic trace (hz/vsynth.h) starting at time 0. */
hz_status_t hz_vsource_sim(hz_vsource_t *s, const hz_vsynth_cfg_t *cfg, hz_error_t *err);
/* Replay of a recorded trace: VCD (signal "" = the only 1-bit signal) or CSV (see hz/traceio.h). */
hz_status_t hz_vsource_vcd(hz_vsource_t *s, const char *path, const char *signal, hz_error_t *err);
hz_status_t hz_vsource_csv(hz_vsource_t *s, const char *path, hz_error_t *err);
/* A sink that shows nothing (simulations, capture-only runs). */
void hz_sink_null(hz_sink_t *s);

#endif
