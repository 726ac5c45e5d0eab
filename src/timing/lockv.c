/* The lock verdict over a v-sync model's events (see hz/lockv.h). */
#include "hz/lockv.h"

#include "wide.h"

#define Q16 65536

void hz_lockv_init(hz_lockv_t *l, const hz_lockv_cfg_t *cfg)
{
    hz_lockv_t zero = { 0 };
    *l = zero;
    l->cfg = *cfg;
    if (!l->cfg.min_run)
        l->cfg.min_run = HZ_LOCK_MIN_RUN;
    if (!l->cfg.max_relock_ppm)
        l->cfg.max_relock_ppm = HZ_LOCK_RELOCK_PPM;
    if (!l->cfg.max_spurious_ppm)
        l->cfg.max_spurious_ppm = HZ_LOCK_SPURIOUS_PPM;
    if (!l->cfg.max_missed_ppm)
        l->cfg.max_missed_ppm = HZ_LOCK_MISSED_PPM;
    if (!l->cfg.far_ppm)
        l->cfg.far_ppm = HZ_LOCK_FAR_PPM;
    if (l->cfg.nominal_period_ns < 0)
        l->cfg.nominal_period_ns = 0;
}

/* Folds the current stretch into the totals when it qualifies. */
static void close_stretch(const hz_lockv_t *l, uint64_t *qualifying, uint64_t *edges, uint64_t *span_slots,
                          int64_t *span_ns)
{
    if (!l->in_stretch || l->cur_n < l->cfg.min_run || l->cur_slot1 <= l->cur_slot0)
        return;
    (*qualifying)++;
    *edges += l->cur_n;
    *span_slots += (uint64_t)(l->cur_slot1 - l->cur_slot0);
    *span_ns += l->cur_t1 - l->cur_t0;
}

void hz_lockv_event(hz_lockv_t *l, const hz_vsync_event_t *ev)
{
    l->inputs++;
    if (ev->kind != HZ_VSYNC_EDGE) {
        l->spurious++;
        return;
    }
    l->accepted++;
    l->missed += ev->missed_before;
    if (!l->in_stretch || ev->relock) {
        if (l->in_stretch)
            close_stretch(l, &l->qualifying, &l->qualifying_edges, &l->span_slots, &l->span_ns);
        if (ev->relock)
            l->relocks++;
        l->stretches++;
        l->in_stretch = 1;
        l->cur_n = 0;
        l->cur_slot0 = ev->slot;
        l->cur_t0 = ev->t_ns;
    }
    l->cur_n++;
    l->cur_slot1 = ev->slot;
    l->cur_t1 = ev->t_ns;
    if (l->cur_n > l->longest)
        l->longest = l->cur_n;
}

/* count > ppm/1e6 of total, exactly. */
static int over(uint64_t count, uint64_t total, uint32_t ppm)
{
    if (ppm == HZ_LOCK_ANY)
        return 0;
    if (ppm == HZ_LOCK_NONE)
        return count > 0;
    hz_u128_t a = hz_u128_mul(count, 1000000u), b = hz_u128_mul(total, ppm);
    return a.hi > b.hi || (a.hi == b.hi && a.lo > b.lo);
}

void hz_lockv_result(const hz_lockv_t *l, hz_lockv_result_t *r)
{
    hz_lockv_result_t zero = { 0 };
    *r = zero;
    r->cfg = l->cfg;
    r->inputs = l->inputs;
    r->accepted = l->accepted;
    r->spurious = l->spurious;
    r->relocks = l->relocks;
    r->missed = l->missed;
    r->stretches = l->stretches;
    r->longest = l->longest;
    r->qualifying = l->qualifying;
    r->span_slots = l->span_slots;
    r->span_ns = l->span_ns;
    r->qualifying_edges = l->qualifying_edges;
    close_stretch(l, &r->qualifying, &r->qualifying_edges, &r->span_slots, &r->span_ns);
    if (r->qualifying == 0)
        r->verdict |= HZ_LOCK_NO_RUN;
    if (over(l->relocks, l->accepted, l->cfg.max_relock_ppm))
        r->verdict |= HZ_LOCK_RELOCKS;
    if (over(l->spurious, l->inputs, l->cfg.max_spurious_ppm))
        r->verdict |= HZ_LOCK_SPURIOUS;
    if (over(l->missed, l->accepted + l->missed, l->cfg.max_missed_ppm))
        r->verdict |= HZ_LOCK_MISSED;
    if (r->span_slots > 0 && r->span_slots < (uint64_t)INT64_MAX)
        r->period_q16 = hz_muldiv(r->span_ns, Q16, (int64_t)r->span_slots);
    int64_t nom = l->cfg.nominal_period_ns;
    if (r->period_q16 > 0 && nom > 0) {
        r->offset_ppb = hz_muldiv(r->period_q16 - nom * Q16, 1000000000, nom * Q16);
        r->far = hz_abs64(r->offset_ppb) > (uint64_t)l->cfg.far_ppm * 1000u;
    }
}
