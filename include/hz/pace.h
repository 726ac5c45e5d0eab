/*
 * hz/pace.h — frame pacing: when to start frame n so that it is done before its target edge.
 *
 * Contract (integer-only, freestanding):
 *  - The pacer keeps the last `window` frame costs, a cost being done - planned start: the render time plus
 *    however late the render thread woke up. Its budget is the `percentile` (nearest rank, per-mille x10) of
 *    those costs plus `guard_ns` (default P/16). The default percentile is 1000, the window's maximum: a
 *    nearest-rank p99.9 of 1024 costs is the second largest, which lets a lone spike through and, for rare
 *    spikes, misses up to 0.08% of frames; the maximum bounds it at 0.036% (below). Until HZ_PACE_WARMUP
 *    costs are known the budget is the whole period minus the latch lead: frames start right after an edge.
 *  - hz_pace_plan picks the target: the earliest slot j >= min_slot (and at least `lookahead` slots after the
 *    last edge at or before now) whose predicted edge leaves room for the budget and the latch lead
 *    (edge_j - latch - budget >= now), and the start time edge_j - latch - budget. Starting as late as that
 *    is what keeps latency (scan-out minus render start) at budget + latch.
 *  - With render times below 80% of the period and the window's maximum as the budget, only a cost larger
 *    than every one of the last `window` can miss: for independent spikes at rate r that happens at rate
 *    r (1 - r)^window, at most 1 / (e window) = 0.036% of frames for window 1024. A step to a slower scene
 *    misses once and is then in the window.
 *  - The caller must plan with a locked v-sync model (hz_vsync_locked).
 */
#ifndef HZ_PACE_H
#define HZ_PACE_H

#include <stdint.h>

#include "hz/status.h"
#include "hz/vsync.h"

#define HZ_PACE_WINDOW_MAX 1024
#define HZ_PACE_WARMUP 8

typedef struct hz_pace_cfg {
    uint32_t window;     /* costs kept, 16..HZ_PACE_WINDOW_MAX; 0: the maximum */
    uint32_t percentile; /* per-mille x10, 500..1000; 0: 1000 (the window's maximum) */
    int64_t guard_ns;    /* added to the percentile; < 0: period / 16 */
    int64_t latch_ns;    /* a frame must be submitted this long before its edge (>= 0) */
    uint32_t lookahead;  /* target at least this many edges ahead (>= 1; 0 means 1) */
    int cap;             /* 1: the budget never exceeds lookahead periods - latch: a frame that costs more misses
                          * its edge instead of raising the latency of the window's later frames (what a governor
                          * that keeps frames within the period wants); 0: no cap */
} hz_pace_cfg_t;

typedef struct hz_pace_plan {
    int64_t slot;       /* target edge's slot */
    int64_t edge_ns;    /* its predicted time */
    int64_t start_ns;   /* when to start rendering */
    int64_t budget_ns;  /* cost allowance used for this plan */
    int64_t period_ns;  /* the model's period at planning time */
} hz_pace_plan_t;

typedef struct hz_pace {
    hz_pace_cfg_t cfg;
    int64_t cost[HZ_PACE_WINDOW_MAX];
    int64_t scratch[HZ_PACE_WINDOW_MAX];
    uint32_t n, next;
    uint64_t observed;
} hz_pace_t;

hz_status_t hz_pace_init(hz_pace_t *p, const hz_pace_cfg_t *cfg, hz_error_t *err);
/* Forgets the costs so far (they describe another workload: the governor changed the quality level); the
 * budget starts again from the warm-up's whole period. */
void hz_pace_forget(hz_pace_t *p);
/* Records one frame's cost (done - planned start, >= 0; negative values count as 0). */
void hz_pace_observe(hz_pace_t *p, int64_t cost_ns);
/* The budget for a model period (what the next plan would use). */
int64_t hz_pace_budget(hz_pace_t *p, int64_t period_ns);
void hz_pace_plan(hz_pace_t *p, const hz_vsync_t *v, int64_t now_ns, int64_t min_slot, hz_pace_plan_t *out);

#endif /* HZ_PACE_H */
