/* Frame pacing from recent frame costs and the v-sync model (see hz/pace.h). */
#include "hz/pace.h"

#include "hz/tstat.h"

hz_status_t hz_pace_init(hz_pace_t *p, const hz_pace_cfg_t *cfg, hz_error_t *err)
{
    hz_pace_cfg_t c = *cfg;
    if (c.window == 0)
        c.window = HZ_PACE_WINDOW_MAX;
    if (c.percentile == 0)
        c.percentile = 1000;
    if (c.lookahead == 0)
        c.lookahead = 1;
    if (c.window < 16 || c.window > HZ_PACE_WINDOW_MAX)
        return hz_error_set(err, HZ_E_INVALID_ARG, "pacing: window of %u frames is outside [16, %u]", c.window,
                            (unsigned)HZ_PACE_WINDOW_MAX);
    if (c.percentile < 500 || c.percentile > 1000)
        return hz_error_set(err, HZ_E_INVALID_ARG,
                            "pacing: percentile %u.%u is outside [50, 100]", c.percentile / 10, c.percentile % 10);
    if (c.latch_ns < 0)
        return hz_error_set(err, HZ_E_INVALID_ARG, "pacing: negative latch lead %lld ns", (long long)c.latch_ns);
    if (c.lookahead > 16)
        return hz_error_set(err, HZ_E_INVALID_ARG, "pacing: lookahead of %u edges is more than 16", c.lookahead);
    hz_pace_t zero = { 0 };
    *p = zero;
    p->cfg = c;
    return HZ_OK;
}

void hz_pace_observe(hz_pace_t *p, int64_t cost_ns)
{
    p->cost[p->next] = cost_ns < 0 ? 0 : cost_ns;
    p->next = (p->next + 1) % p->cfg.window;
    if (p->n < p->cfg.window)
        p->n++;
    p->observed++;
}

void hz_pace_forget(hz_pace_t *p)
{
    p->n = 0;
    p->next = 0;
}

/* a + b for b >= 0, saturated at INT64_MAX: a cost near INT64_MAX (a stalled clock) must give the largest
 * budget, not wrap to a negative one. */
static int64_t sat_add(int64_t a, int64_t b)
{
    return a > INT64_MAX - b ? INT64_MAX : a + b;
}

int64_t hz_pace_budget(hz_pace_t *p, int64_t period_ns)
{
    int64_t whole = period_ns - p->cfg.latch_ns;
    if (whole < period_ns / 2)
        whole = period_ns / 2;
    if (p->n < HZ_PACE_WARMUP)
        return whole;
    for (uint32_t i = 0; i < p->n; i++)
        p->scratch[i] = p->cost[i];
    uint64_t rank = ((uint64_t)p->n * p->cfg.percentile + 999u) / 1000u;
    int64_t pct = hz_select_i64(p->scratch, p->n, (size_t)(rank ? rank - 1 : 0));
    int64_t guard = p->cfg.guard_ns < 0 ? period_ns / 16 : p->cfg.guard_ns;
    int64_t budget = sat_add(pct, guard < 0 ? 0 : guard);
    if (p->cfg.cap) {
        int64_t cap = (int64_t)p->cfg.lookahead * period_ns - p->cfg.latch_ns;
        if (cap < whole)
            cap = whole;
        budget = budget < cap ? budget : cap;
    }
    return budget;
}

void hz_pace_plan(hz_pace_t *p, const hz_vsync_t *v, int64_t now, int64_t min_slot, hz_pace_plan_t *out)
{
    int64_t period = hz_vsync_period_ns(v);
    int64_t budget = hz_pace_budget(p, period);
    /* The last edge at or before now, then the lookahead. */
    int64_t current = hz_vsync_slot_at_or_after(v, now + 1) - 1;
    if (min_slot < current + (int64_t)p->cfg.lookahead)
        min_slot = current + (int64_t)p->cfg.lookahead;
    int64_t slot = hz_vsync_slot_at_or_after(v, sat_add(sat_add(now, budget), p->cfg.latch_ns));
    if (slot < min_slot)
        slot = min_slot;
    out->slot = slot;
    out->edge_ns = hz_vsync_slot_time(v, slot);
    out->start_ns = out->edge_ns - p->cfg.latch_ns < INT64_MIN + 1 + budget ? now
                                                                        : out->edge_ns - p->cfg.latch_ns - budget;
    if (out->start_ns < now)
        out->start_ns = now;
    out->budget_ns = budget;
    out->period_ns = period;
}
