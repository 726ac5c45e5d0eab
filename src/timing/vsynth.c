/* Synthetic v-sync traces with ground truth (see hz/vsynth.h). */
#include "hz/vsynth.h"

#include "wide.h"

#define Q16 65536

hz_status_t hz_vsynth_init(hz_vsynth_t *g, const hz_vsynth_cfg_t *cfg, hz_error_t *err)
{
    hz_vsynth_cfg_t c = *cfg;
    if (c.bounce_max_ns == 0)
        c.bounce_max_ns = 20000;
    if (c.period_q16 < 1000 * (int64_t)Q16)
        return hz_error_set(err, HZ_E_INVALID_ARG, "synthetic v-sync: period below 1 us");
    int64_t p = c.period_q16 / Q16;
    if (c.jitter_ns < 0 || c.bounce_max_ns < 0 || c.jitter_ns + c.bounce_max_ns >= p / 16)
        return hz_error_set(err, HZ_E_INVALID_ARG,
                            "synthetic v-sync: jitter %lld ns + bounce %lld ns must stay below P/16 = %lld ns",
                            (long long)c.jitter_ns, (long long)c.bounce_max_ns, (long long)(p / 16));
    if (c.miss_ppm > 500000 || c.glitch_ppm > 1000000 || c.bounce_ppm > 1000000)
        return hz_error_set(err, HZ_E_INVALID_ARG,
                            "synthetic v-sync: miss rate must be <= 50%%, glitch and bounce rates <= 100%%");
    if (c.drift_ppb_start < -100000000 || c.drift_ppb_start > 100000000 || c.drift_ppb_end < -100000000 ||
        c.drift_ppb_end > 100000000)
        return hz_error_set(err, HZ_E_INVALID_ARG, "synthetic v-sync: drift beyond +-10%%");
    hz_vsynth_t zero = { 0 };
    *g = zero;
    g->cfg = c;
    hz_rng_seed(&g->rng, c.seed, 0x7653796eull);
    return HZ_OK;
}

int64_t hz_vsynth_period_q16(const hz_vsynth_t *g, uint64_t slot)
{
    const hz_vsynth_cfg_t *c = &g->cfg;
    int64_t ppb = c->drift_ppb_start;
    if (c->slots > 1) {
        uint64_t s = slot < c->slots ? slot : c->slots - 1;
        ppb += hz_muldiv((int64_t)c->drift_ppb_end - c->drift_ppb_start, (int64_t)s, (int64_t)(c->slots - 1));
    }
    return c->period_q16 + hz_muldiv(c->period_q16, ppb, 1000000000);
}

int64_t hz_vsynth_ideal_ns(const hz_vsynth_t *g)
{
    return g->cfg.t0_ns + (g->ideal_q16 + Q16 / 2) / Q16;
}

/* Uniform in [lo, hi] (inclusive), 64-bit span. */
static int64_t uniform(hz_rng_t *r, int64_t lo, int64_t hi)
{
    uint64_t span = (uint64_t)(hi - lo) + 1u;
    uint64_t x = ((uint64_t)hz_rng_u32(r) << 32) | hz_rng_u32(r);
    return lo + (int64_t)(span ? x % span : x);
}

static bool chance(hz_rng_t *r, uint32_t ppm)
{
    return ppm && hz_rng_below(r, 1000000u) < ppm;
}

bool hz_vsynth_next(hz_vsynth_t *g, hz_vsynth_edge_t *e)
{
    while (g->out_i == g->out_n) {
        const hz_vsynth_cfg_t *c = &g->cfg;
        if (c->slots && g->slot >= c->slots)
            return false;
        g->out_n = g->out_i = 0;
        int64_t ideal = hz_vsynth_ideal_ns(g);
        int64_t p = hz_vsynth_period_q16(g, g->slot);
        int64_t p_ns = p / Q16;
        /* Draw every random number unconditionally so that one setting does not reshuffle the others. */
        int64_t jit = uniform(&g->rng, -c->jitter_ns, c->jitter_ns);
        bool lost = chance(&g->rng, c->miss_ppm);
        bool bounce = chance(&g->rng, c->bounce_ppm);
        int64_t bounce_dt = uniform(&g->rng, 1, c->bounce_max_ns);
        bool glitch = chance(&g->rng, c->glitch_ppm);
        int64_t glitch_dt = uniform(&g->rng, p_ns / 8, p_ns - p_ns / 8);
        hz_vsynth_edge_t ed = { 0 };
        ed.slot = (int64_t)g->slot;
        ed.rising = 1;
        if (!lost) {
            ed.t_ns = ideal + jit;
            ed.real = 1;
            g->out[g->out_n++] = ed;
            g->real_edges++;
            if (bounce) {
                ed.t_ns += bounce_dt;
                ed.real = 0;
                g->out[g->out_n++] = ed;
                g->bounces++;
            }
        } else {
            g->lost++;
        }
        if (glitch) {
            ed.t_ns = ideal + glitch_dt;
            ed.real = 0;
            g->out[g->out_n++] = ed;
            g->glitches++;
        }
        g->ideal_q16 += p;
        g->slot++;
    }
    *e = g->out[g->out_i++];
    return true;
}
