/*
 * hz/vsynth.h — synthetic v-sync traces with ground truth, for tests and the simulated display.
 *
 * Contract (integer-only, deterministic for a seed on every ISA):
 *  - Slot n's ideal edge is t0 + sum of the periods before it; the period of slot n is the nominal one scaled
 *    by (1 + drift_n), drift_n in parts per billion ramping linearly from drift_ppb_start (slot 0) to
 *    drift_ppb_end (slot `slots` - 1); with slots == 0 the trace never ends and the drift stays at the start
 *    value. Ideal times accumulate in Q16.16 ns, so no rounding drift builds up.
 *  - A real edge lands uniformly within [-jitter_ns, +jitter_ns] of its ideal time, unless the pulse is lost
 *    (probability miss_ppm per million slots). Glitches (probability glitch_ppm per slot) land uniformly
 *    between P/8 and 7P/8 after a slot's ideal time, i.e. clearly off the grid; bounces (bounce_ppm per real
 *    edge) follow a real edge by 1..bounce_max_ns. jitter_ns must stay below P/16 - bounce_max_ns so that
 *    edges come out in time order.
 *  - Every edge says which slot it belongs to (glitches: the slot they follow) and whether it is real.
 */
#ifndef HZ_VSYNTH_H
#define HZ_VSYNTH_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/hash.h"
#include "hz/status.h"

typedef struct hz_vsynth_cfg {
    int64_t period_q16;      /* nominal period, ns * 65536 (hz_vsync_period_q16_from_mhz) */
    int64_t t0_ns;           /* ideal time of slot 0 */
    int64_t jitter_ns;
    int32_t drift_ppb_start, drift_ppb_end;
    uint64_t slots;          /* trace length in refreshes; 0: endless */
    uint32_t miss_ppm, glitch_ppm, bounce_ppm;
    int64_t bounce_max_ns;   /* 0: 20 us */
    uint64_t seed;
} hz_vsynth_cfg_t;

typedef struct hz_vsynth_edge {
    int64_t t_ns;
    int64_t slot;
    uint8_t real;  /* 1: the display's edge; 0: glitch or bounce */
    uint8_t rising; /* always 1: traces carry the v-sync polarity only */
} hz_vsynth_edge_t;

typedef struct hz_vsynth {
    hz_vsynth_cfg_t cfg;
    hz_rng_t rng;
    uint64_t slot;       /* next slot to generate */
    int64_t ideal_q16;   /* ideal time of `slot`, Q16 ns, relative to t0 */
    hz_vsynth_edge_t out[3];
    uint32_t out_n, out_i;
    uint64_t real_edges, lost, glitches, bounces;
} hz_vsynth_t;

hz_status_t hz_vsynth_init(hz_vsynth_t *g, const hz_vsynth_cfg_t *cfg, hz_error_t *err);
/* Next edge in time order; false at the end of a finite trace. */
bool hz_vsynth_next(hz_vsynth_t *g, hz_vsynth_edge_t *e);
/* True period of slot n (Q16 ns), drift applied. */
int64_t hz_vsynth_period_q16(const hz_vsynth_t *g, uint64_t slot);
/* Ideal (jitter-free) time of the slot that will be generated next. */
int64_t hz_vsynth_ideal_ns(const hz_vsynth_t *g);

#endif /* HZ_VSYNTH_H */
