/* The frame-budget governor (see hz/governor.h). */
#include "hz/governor.h"

#include "hz/base.h"

#define DEF_DWELL_NS 300000000
#define DEF_FIT_PM 900
#define DEF_UP_PM 700
#define DEF_K_Q8 768
#define MAX_COST_NS 10000000000LL /* observations are clamped to 10 s: the arithmetic below stays in range */

hz_status_t hz_gov_init(hz_gov_t *g, const hz_gov_cfg_t *cfg, hz_error_t *err)
{
    hz_memset(g, 0, sizeof *g);
    if (cfg->levels < 1 || cfg->levels > HZ_GOV_MAX_LEVELS)
        return hz_error_set(err, HZ_E_INVALID_ARG, "governor: %u levels, not 1..%d", cfg->levels, HZ_GOV_MAX_LEVELS);
    for (uint32_t i = 0; i < cfg->levels; i++) {
        if (cfg->weight_q16[i] == 0 || cfg->weight_q16[i] > (1u << 24))
            return hz_error_set(err, HZ_E_INVALID_ARG, "governor: level %u has weight %u (Q16), not 1..2^24", i,
                                cfg->weight_q16[i]);
        if (i > 0 && cfg->weight_q16[i] > cfg->weight_q16[i - 1])
            return hz_error_set(err, HZ_E_INVALID_ARG, "governor: level %u costs more than level %u", i, i - 1);
    }
    g->cfg = *cfg;
    if (!g->cfg.dwell_ns)
        g->cfg.dwell_ns = DEF_DWELL_NS;
    if (!g->cfg.fit_pm)
        g->cfg.fit_pm = DEF_FIT_PM;
    if (!g->cfg.up_pm)
        g->cfg.up_pm = DEF_UP_PM;
    if (!g->cfg.k_q8)
        g->cfg.k_q8 = DEF_K_Q8;
    return HZ_OK;
}

/* x * num / den without overflow for the ranges here (x <= 2^40, num, den <= 2^24 + ...). */
static int64_t scale(int64_t x, uint64_t num, uint64_t den)
{
    return den ? (int64_t)(((uint64_t)x * num) / den) : x;
}

/* Mean and deviation of level l: its own, or the nearest known level's scaled by the weights. */
static int known_estimate(const hz_gov_t *g, uint32_t l, int64_t *mean, int64_t *dev)
{
    if (g->mean_ns[l] > 0) {
        *mean = g->mean_ns[l], *dev = g->dev_ns[l];
        return 1;
    }
    for (uint32_t d = 1; d < g->cfg.levels; d++) {
        for (int side = 0; side < 2; side++) {
            int64_t k = side ? (int64_t)l + d : (int64_t)l - d;
            if (k < 0 || k >= (int64_t)g->cfg.levels || g->mean_ns[k] <= 0)
                continue;
            uint32_t wl = g->cfg.weight_q16[l], wk = g->cfg.weight_q16[k];
            *mean = scale(g->mean_ns[k], wl, wk);
            *dev = scale(g->dev_ns[k], wl, wk);
            return 1;
        }
    }
    return 0;
}

int64_t hz_gov_predict(const hz_gov_t *g, uint32_t level)
{
    int64_t m, d;
    if (level >= g->cfg.levels || !known_estimate(g, level, &m, &d))
        return 0;
    return m + (d * (int64_t)g->cfg.k_q8 >> 8);
}

/* Up fast (half the step), down slowly (1/16). */
static int64_t follow(int64_t est, int64_t target)
{
    return target > est ? est + (target - est + 1) / 2 : est - (est - target) / 16;
}

static int64_t median3(int64_t a, int64_t b, int64_t c)
{
    int64_t lo = a < b ? a : b, hi = a < b ? b : a;
    return c < lo ? lo : c > hi ? hi : c;
}

void hz_gov_observe(hz_gov_t *g, uint32_t level, int64_t cost_ns)
{
    if (level >= g->cfg.levels)
        return;
    int64_t raw = cost_ns < 1 ? 1 : cost_ns > MAX_COST_NS ? MAX_COST_NS : cost_ns;
    /* A lone slow frame (the machine, not the scene) is not a load step: the estimate takes the median of the
     * level's last three frames, so a step counts from its second frame and a spike not at all. */
    int64_t c = g->recent_n >= 2 && g->recent_level == level ? median3(g->recent[0], g->recent[1], raw) : raw;
    if (g->recent_level != level)
        g->recent_n = 0;
    g->recent[0] = g->recent[1];
    g->recent[1] = raw;
    g->recent_n += g->recent_n < 2;
    g->recent_level = level;
    int64_t m, d;
    if (!known_estimate(g, level, &m, &d)) {
        /* the first observation: every level from it by weight */
        g->mean_ns[level] = c;
        g->dev_ns[level] = c / 8;
        g->seen++;
        return;
    }
    int64_t dev_now = c > m ? c - m : m - c;
    g->mean_ns[level] = follow(m, c);
    g->dev_ns[level] = d + (dev_now - d) / 16;
    if (g->mean_ns[level] < 1)
        g->mean_ns[level] = 1;
    /* the surprise, Q16, carried to the other known levels' means; their deviations follow this level's
     * relative deviation (the noise is mostly the machine's, shared by every level) */
    uint64_t s = (uint64_t)c * 65536u / (uint64_t)m;
    s = s < 4096u ? 4096u : s > (16u << 16) ? (16u << 16) : s;
    uint64_t rel = (uint64_t)g->dev_ns[level] * 65536u / (uint64_t)g->mean_ns[level];
    rel = rel > (4u << 16) ? (4u << 16) : rel;
    for (uint32_t j = 0; j < g->cfg.levels; j++) {
        if (j == level || g->mean_ns[j] <= 0)
            continue;
        int64_t target = scale(g->mean_ns[j], s, 65536u);
        g->mean_ns[j] = follow(g->mean_ns[j], target);
        if (g->mean_ns[j] < 1)
            g->mean_ns[j] = 1;
        g->dev_ns[j] = follow(g->dev_ns[j], scale(g->mean_ns[j], rel, 65536u));
    }
    g->seen++;
}

static int fits(const hz_gov_t *g, uint32_t level, int64_t budget, uint32_t pm)
{
    int64_t p = hz_gov_predict(g, level);
    return p > 0 && p <= budget / 1000 * (int64_t)pm + budget % 1000 * (int64_t)pm / 1000;
}

static uint32_t change(hz_gov_t *g, uint32_t to, int64_t now, int forced)
{
    if (to != g->level) {
        g->level = to;
        g->changed_ns = now;
        g->have_change = 1;
        g->changes++;
        g->forced += forced != 0;
    }
    return g->level;
}

uint32_t hz_gov_start(hz_gov_t *g, int64_t now_ns, int64_t budget_ns)
{
    uint32_t to = 0, last = g->cfg.levels - 1;
    while (to < last && !fits(g, to, budget_ns, g->cfg.up_pm))
        to++;
    g->level = to;
    g->changed_ns = now_ns;
    g->have_change = 1;
    return to;
}

uint32_t hz_gov_pick(hz_gov_t *g, int64_t now_ns, int64_t budget_ns)
{
    if (g->cfg.levels < 2 || budget_ns <= 0)
        return change(g, 0, now_ns, 0);
    if (g->seen == 0)
        return g->level;
    const uint32_t cur = g->level, last = g->cfg.levels - 1;
    if (!fits(g, cur, budget_ns, 1000)) {
        /* a deadline at risk: the best level that fits with margin, now */
        uint32_t to = cur;
        while (to < last && !fits(g, to, budget_ns, g->cfg.fit_pm))
            to++;
        return change(g, to, now_ns, 1);
    }
    if (g->have_change && now_ns - g->changed_ns < g->cfg.dwell_ns)
        return cur;
    if (cur < last && !fits(g, cur, budget_ns, g->cfg.fit_pm))
        return change(g, cur + 1, now_ns, 0); /* close to the edge for a while: one step down */
    if (cur > 0 && fits(g, cur - 1, budget_ns, g->cfg.up_pm))
        return change(g, cur - 1, now_ns, 0);
    return cur;
}
