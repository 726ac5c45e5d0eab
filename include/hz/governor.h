/*
 * hz/governor.h — the frame-budget governor: before each frame, the quality level whose predicted cost fits the
 * pacing budget, with hysteresis so that quality does not flicker.
 *
 * Contract (integer-only, freestanding; all memory in hz_gov_t):
 *  - Levels are numbered 0 (the best quality, the configuration the user asked for) to levels - 1 (the
 *    cheapest). Each has a prior cost weight relative to level 0 (Q16: 65536 = as costly as level 0), e.g. its
 *    share of the pixels times its mode's relative cost; the weights must not grow with the level.
 *  - Costs are predicted from measured ones, each frame's cost taken as the median of its level's last three (a
 *    lone slow frame is the machine's hiccup, not a load step: it moves nothing; a step counts from its second
 *    frame). Each level that has been rendered keeps its own estimate: a mean
 *    that follows a rise at once (half the step per frame) and a fall slowly (1/16), and the mean deviation;
 *    its prediction is mean + k x deviation, a high quantile rather than the mean, because a frame longer than
 *    the budget is a missed deadline. An observation also scales every other known level's estimate by the
 *    surprise it brought (observed / predicted mean, at the same up-fast, down-slow rates), so a load step at
 *    one level moves all predictions at once, and moves their deviations towards its own relative deviation
 *    (the noise is mostly the machine's). A level never rendered is predicted from the nearest known level
 *    by the ratio of their weights; this is how fixed per-frame costs, which weights do not know, get learned.
 *  - hz_gov_pick returns the level for the next frame. Down: when the current level's prediction exceeds the
 *    budget (a deadline is at risk) it drops at once to the best level predicted to fit with margin, ignoring
 *    the dwell. Up: only after dwell_ns without a change, and only to the next better level, whose prediction
 *    must fit the budget with the (larger) up margin. Nothing else changes the level: no flicker between two
 *    levels whose costs straddle the budget.
 *  - With budget_ns <= 0 or a single level it returns level 0 (nothing sets a pace: keep full quality).
 *  - Counts: time spent at each level (the caller adds it) and changes, for the report.
 */
#ifndef HZ_GOVERNOR_H
#define HZ_GOVERNOR_H

#include <stdint.h>

#include "hz/status.h"

#define HZ_GOV_MAX_LEVELS 16

typedef struct hz_gov_cfg {
    uint32_t levels;                          /* 1..HZ_GOV_MAX_LEVELS */
    uint32_t weight_q16[HZ_GOV_MAX_LEVELS];   /* prior cost of each level relative to level 0, non-increasing */
    int64_t dwell_ns;        /* least time between two changes that are not forced (0: 300 ms) */
    uint32_t fit_pm;         /* a level fits when its prediction <= budget x fit_pm / 1000 (0: 900) */
    uint32_t up_pm;          /* going up needs prediction <= budget x up_pm / 1000 (0: 700) */
    uint32_t k_q8;           /* deviations added to the mean, Q8 (0: 3.0) */
} hz_gov_cfg_t;

typedef struct hz_gov {
    hz_gov_cfg_t cfg;
    uint32_t level;          /* the level of the frame being rendered */
    int64_t changed_ns;      /* when the level last changed */
    int have_change;
    int64_t mean_ns[HZ_GOV_MAX_LEVELS]; /* 0: never rendered */
    int64_t dev_ns[HZ_GOV_MAX_LEVELS];
    uint64_t seen;           /* observations so far */
    int64_t recent[2];       /* the last two costs, of recent_level */
    uint32_t recent_n, recent_level;
    uint64_t changes, forced; /* level changes, and those a deadline at risk forced */
} hz_gov_t;

hz_status_t hz_gov_init(hz_gov_t *g, const hz_gov_cfg_t *cfg, hz_error_t *err);
uint32_t hz_gov_pick(hz_gov_t *g, int64_t now_ns, int64_t budget_ns);
void hz_gov_observe(hz_gov_t *g, uint32_t level, int64_t cost_ns);
/* After the levels have been measured once (each observed): starts at the best level predicted to fit the budget
 * with the up margin, and starts the dwell there. */
uint32_t hz_gov_start(hz_gov_t *g, int64_t now_ns, int64_t budget_ns);
/* The predicted high-quantile cost of a level (0 before any observation). */
int64_t hz_gov_predict(const hz_gov_t *g, uint32_t level);

#endif
