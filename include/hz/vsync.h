/*
 * hz/vsync.h — the v-sync model: turns raw edge timestamps (integer ns) into a display clock.
 *
 * Contract (integer-only, freestanding, allocation-free; all state lives in hz_vsync_t):
 *  - Every input edge gets exactly one event, accepted (HZ_VSYNC_EDGE, with its slot = refresh number) or
 *    rejected (HZ_VSYNC_SPURIOUS, with the reason). Feed edges with hz_vsync_push() and drain the events with
 *    hz_vsync_pop() after every push; hz_vsync_flush() at the end of a trace settles what is still pending.
 *    Events come in decision order: spurious edges as soon as they are recognised, accepted edges one edge
 *    late (an edge stays tentative until an edge of a later slot arrives, so that of two edges in one slot the
 *    one nearer the prediction wins). `index` says where each edge was in the input.
 *  - Lock: the first HZ_VSYNC_ACQ edges are buffered; the anchor that puts the most of them on one grid of the
 *    nominal period (or, with nominal_period_ns == 0, the median interval) wins. Without a majority of them on
 *    a grid the oldest is rejected (HZ_VSYNC_WHY_NOLOCK) and acquisition goes on.
 *  - Locked: an edge more than the tolerance away from the predicted time of its nearest slot is off-grid
 *    (spurious); so is every edge closer than P/2 to an accepted one, since it shares its slot. A gap of about
 *    k periods between accepted edges counts k - 1 missed pulses (missed_before of the later edge).
 *    HZ_VSYNC_RELOCK off-grid edges in a row mean the display moved (mode change, source restart): the model
 *    re-acquires, keeps the slot numbering continuous and counts a relock.
 *  - Estimate: least squares t = anchor + slot * period over the last `window` accepted edges (integer
 *    arithmetic with 128-bit intermediates; the period is kept in Q16.16 ns, i.e. 1/65536 ns resolution).
 *    Residuals beyond 6 median absolute deviations (at least 1 us) are left out of a second fit. Until the
 *    window spans HZ_VSYNC_SPAN_FOR_SLOPE slots only the phase is fitted and the period stays at the nominal
 *    (or acquired) one. The tolerance is 8 robust standard deviations (1.4826 MAD) of the residuals, at least
 *    tol_min_ns (default P/64) and at most P/4 (P/8 while the slope is not fitted yet).
 *  - residual_ns of an accepted edge is its time minus the model's prediction before the edge entered the fit
 *    (an innovation: the prediction error a pacer would have seen).
 *  - Timestamps must increase; a timestamp not after the previous input's is rejected (WHY_BACKWARDS).
 */
#ifndef HZ_VSYNC_H
#define HZ_VSYNC_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/status.h"

#define HZ_VSYNC_WINDOW_MAX 256
#define HZ_VSYNC_WINDOW_DEFAULT 128
#define HZ_VSYNC_ACQ 8
#define HZ_VSYNC_RELOCK 4
#define HZ_VSYNC_SPAN_FOR_SLOPE 16
#define HZ_VSYNC_QUEUE 32

typedef struct hz_vsync_cfg {
    int64_t nominal_period_ns; /* expected period; 0: learn it from the first edges */
    uint32_t window;           /* accepted edges in the fit, 8..HZ_VSYNC_WINDOW_MAX; 0: the default */
    int64_t tol_min_ns;        /* smallest acceptance half-width; 0: period / 64 (also widens the P/8 used while
                                  acquiring, for sources with millisecond jitter) */
} hz_vsync_cfg_t;

enum hz_vsync_kind { HZ_VSYNC_EDGE = 1, HZ_VSYNC_SPURIOUS = 2 };

enum hz_vsync_why {
    HZ_VSYNC_WHY_NONE = 0,  /* accepted */
    HZ_VSYNC_WHY_OFFGRID,   /* too far from every predicted edge */
    HZ_VSYNC_WHY_DUPLICATE, /* a second edge in a slot (closer than P/2 to an accepted one), farther off */
    HZ_VSYNC_WHY_BACKWARDS, /* timestamp not after the previous input's */
    HZ_VSYNC_WHY_NOLOCK     /* seen while acquiring and on no common grid with the others */
};

typedef struct hz_vsync_event {
    int64_t t_ns;
    int64_t slot;           /* accepted: refresh number; spurious: nearest slot (0 before the first lock) */
    int64_t residual_ns;    /* t - prediction (see above) */
    uint64_t index;         /* 0-based position of the edge in the input */
    uint32_t missed_before; /* accepted: slots without an edge since the previous accepted edge */
    uint8_t kind;           /* enum hz_vsync_kind */
    uint8_t why;            /* enum hz_vsync_why */
    uint8_t relock;         /* accepted: first edge after a (re)acquisition that followed a lock */
} hz_vsync_event_t;

typedef struct hz_vsync_counts {
    uint64_t inputs, accepted, spurious, missed, relocks;
    uint64_t offgrid, duplicate, backwards, nolock;
} hz_vsync_counts_t;

typedef struct hz_vsync {
    hz_vsync_cfg_t cfg;
    /* model: predicted time of slot s = anchor_t + (s - anchor_slot) * period_q16 / 65536 */
    bool locked, ever_locked;
    int64_t anchor_slot, anchor_t, period_q16;
    int64_t nominal_q16;
    int64_t tol_ns, sigma_ns;
    /* accepted edges in the fit window (ring) */
    int64_t ring_slot[HZ_VSYNC_WINDOW_MAX], ring_t[HZ_VSYNC_WINDOW_MAX];
    uint32_t ring_n, ring_next;
    int64_t scratch[HZ_VSYNC_WINDOW_MAX];
    int64_t fit_x[HZ_VSYNC_WINDOW_MAX], fit_y[HZ_VSYNC_WINDOW_MAX], fit_e[HZ_VSYNC_WINDOW_MAX];
    uint8_t fit_use[HZ_VSYNC_WINDOW_MAX];
    /* tentative accepted edge */
    bool has_pending;
    hz_vsync_event_t pending;
    bool has_last;
    int64_t last_slot;
    /* input order */
    bool any_input;
    int64_t last_input_t;
    /* acquisition buffer */
    int64_t acq_t[HZ_VSYNC_ACQ];
    uint64_t acq_index[HZ_VSYNC_ACQ];
    uint32_t acq_n;
    uint32_t rejects_in_row;
    hz_vsync_counts_t counts;
    /* output queue */
    hz_vsync_event_t queue[HZ_VSYNC_QUEUE];
    uint32_t q_head, q_n;
} hz_vsync_t;

/* Validates cfg (window range, non-negative periods) and resets the model. */
hz_status_t hz_vsync_init(hz_vsync_t *v, const hz_vsync_cfg_t *cfg, hz_error_t *err);

void hz_vsync_push(hz_vsync_t *v, int64_t t_ns);
/* Settles buffered and tentative edges (end of input). The model stays usable. */
void hz_vsync_flush(hz_vsync_t *v);
/* Next event, oldest first; false when none is waiting. */
bool hz_vsync_pop(hz_vsync_t *v, hz_vsync_event_t *ev);

bool hz_vsync_locked(const hz_vsync_t *v);
/* Period estimate in Q16.16 nanoseconds, and rounded to whole nanoseconds. 0 before the first lock. */
int64_t hz_vsync_period_q16(const hz_vsync_t *v);
int64_t hz_vsync_period_ns(const hz_vsync_t *v);
/* Predicted time of a slot's edge. */
int64_t hz_vsync_slot_time(const hz_vsync_t *v, int64_t slot);
/* The first slot whose predicted edge is at or after t (the anchor slot, 0, before the first lock; at the ends
 * of the int64 range, where predictions saturate, the slot nearest to it). */
int64_t hz_vsync_slot_at_or_after(const hz_vsync_t *v, int64_t t);
/* Current acceptance half-width and robust residual standard deviation (ns). */
int64_t hz_vsync_tolerance_ns(const hz_vsync_t *v);
int64_t hz_vsync_sigma_ns(const hz_vsync_t *v);
/* Frequency error of the estimate against the nominal period, in parts per billion (positive: the period
 * is longer than nominal); 0 without a nominal period. */
int64_t hz_vsync_offset_ppb(const hz_vsync_t *v);
const hz_vsync_counts_t *hz_vsync_counts(const hz_vsync_t *v);

/* Q16.16-ns period of a refresh rate given in millihertz (60000 = 60 Hz); 0 for 0. */
int64_t hz_vsync_period_q16_from_mhz(uint64_t millihertz);

#endif /* HZ_VSYNC_H */
