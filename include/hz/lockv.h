/*
 * hz/lockv.h — the lock verdict: did a v-sync trace give the model a lock worth reporting, and what rate did
 * the locked stretches measure?
 *
 * Contract (integer-only, freestanding, allocation-free):
 *  - Fed every event of the v-sync model (hz/vsync.h) in the order hz_vsync_pop() gives them. A locked
 *    stretch is a run of accepted edges without a re-acquisition: it starts at the first accepted edge and at
 *    every accepted edge flagged `relock`.
 *  - A stretch qualifies when it holds at least min_run accepted edges. The measured period comes only from
 *    qualifying stretches: sum of (last - first edge time) over sum of (last - first slot), i.e. each
 *    stretch's end-to-end mean period weighted by its length. The nominal period is never echoed: without a
 *    qualifying stretch the period is 0.
 *  - The verdict is HZ_LOCK_OK, or a mask of every reason that holds:
 *      HZ_LOCK_NO_RUN    no stretch of min_run accepted edges
 *      HZ_LOCK_RELOCKS   relocks > max_relock_ppm of the accepted edges
 *      HZ_LOCK_SPURIOUS  spurious edges > max_spurious_ppm of all edges fed to the model
 *      HZ_LOCK_MISSED    missed pulses > max_missed_ppm of the slots the accepted edges span (accepted + missed)
 *    Fractions compare exactly (integer cross-multiplication): a count at the limit passes.
 *  - far: locked, a nominal period was given, and the measured one differs from it by more than
 *    far_ppm (default HZ_LOCK_FAR_PPM): the caller warns that --hz does not match the display.
 * Defaults (a 0 in the configuration): min_run 32, relocks 1%, spurious 10%, missed 10%, far 1%.
 */
#ifndef HZ_LOCKV_H
#define HZ_LOCKV_H

#include <stdint.h>

#include "hz/vsync.h"

#define HZ_LOCK_MIN_RUN 32u
#define HZ_LOCK_RELOCK_PPM 10000u
#define HZ_LOCK_SPURIOUS_PPM 100000u
#define HZ_LOCK_MISSED_PPM 100000u
#define HZ_LOCK_FAR_PPM 10000u
#define HZ_LOCK_NONE 0xfffffffeu /* a limit of 0: not one such edge */
#define HZ_LOCK_ANY 0xffffffffu  /* no limit */

enum { HZ_LOCK_OK = 0, HZ_LOCK_NO_RUN = 1, HZ_LOCK_RELOCKS = 2, HZ_LOCK_SPURIOUS = 4, HZ_LOCK_MISSED = 8 };

typedef struct hz_lockv_cfg {
    uint32_t min_run;                 /* accepted edges a stretch needs; 0: HZ_LOCK_MIN_RUN */
    uint32_t max_relock_ppm;          /* 0: the default; HZ_LOCK_NONE: 0%; HZ_LOCK_ANY: no limit */
    uint32_t max_spurious_ppm;
    uint32_t max_missed_ppm;
    uint32_t far_ppm;
    int64_t nominal_period_ns;        /* 0: none (no ppm, no far warning) */
} hz_lockv_cfg_t;

typedef struct hz_lockv_result {
    int verdict;                      /* HZ_LOCK_OK or a mask of HZ_LOCK_* reasons */
    uint64_t inputs, accepted, spurious, relocks, missed;
    uint64_t stretches, qualifying, longest; /* longest: accepted edges of the longest stretch */
    uint64_t qualifying_edges;        /* accepted edges in qualifying stretches */
    uint64_t span_slots;              /* slots covered by qualifying stretches (end to end) */
    int64_t span_ns;
    int64_t period_q16;               /* measured period, Q16.16 ns; 0 without a qualifying stretch */
    int64_t offset_ppb;               /* against the nominal period; 0 without one or without a period */
    int far;
    hz_lockv_cfg_t cfg;               /* with the defaults filled in */
} hz_lockv_result_t;

typedef struct hz_lockv {
    hz_lockv_cfg_t cfg;
    uint64_t inputs, accepted, spurious, relocks, missed;
    uint64_t stretches, qualifying, qualifying_edges, longest, span_slots;
    int64_t span_ns;
    int in_stretch;
    uint64_t cur_n;
    int64_t cur_slot0, cur_t0, cur_slot1, cur_t1;
} hz_lockv_t;

void hz_lockv_init(hz_lockv_t *l, const hz_lockv_cfg_t *cfg);
void hz_lockv_event(hz_lockv_t *l, const hz_vsync_event_t *ev);
/* The verdict over everything fed so far (the state stays usable). */
void hz_lockv_result(const hz_lockv_t *l, hz_lockv_result_t *r);

#endif /* HZ_LOCKV_H */
