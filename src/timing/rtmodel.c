/* Synthetic render-time models (see hz/rtmodel.h). */
#include "hz/rtmodel.h"

hz_status_t hz_rtm_init(hz_rtm_t *m, const hz_rtm_cfg_t *cfg, hz_error_t *err)
{
    const hz_rtm_cfg_t *c = cfg;
    if (c->kind < HZ_RTM_CONST || c->kind > HZ_RTM_STEP)
        return hz_error_set(err, HZ_E_INVALID_ARG, "render-time model: unknown kind %d", (int)c->kind);
    if (c->a_ns < 0 || c->b_ns < 0 || c->wake_ns < 0)
        return hz_error_set(err, HZ_E_INVALID_ARG, "render-time model: negative time");
    if ((c->kind == HZ_RTM_UNIFORM || c->kind == HZ_RTM_TRIANGLE) && c->b_ns < c->a_ns)
        return hz_error_set(err, HZ_E_INVALID_ARG, "render-time model: upper bound %lld ns below lower %lld ns",
                            (long long)c->b_ns, (long long)c->a_ns);
    if (c->kind == HZ_RTM_TRIANGLE && c->frames < 2)
        return hz_error_set(err, HZ_E_INVALID_ARG, "render-time model: triangle period must be >= 2 frames");
    if (c->rate_ppm > 1000000)
        return hz_error_set(err, HZ_E_INVALID_ARG, "render-time model: spike rate above 100%%");
    m->cfg = *c;
    hz_rng_seed(&m->rng, c->seed, 0x72746dull);
    return HZ_OK;
}

static int64_t uniform(hz_rng_t *r, int64_t lo, int64_t hi)
{
    uint64_t span = (uint64_t)(hi - lo) + 1u;
    uint64_t x = ((uint64_t)hz_rng_u32(r) << 32) | hz_rng_u32(r);
    return lo + (int64_t)(x % span);
}

void hz_rtm_next(hz_rtm_t *m, uint64_t frame, int64_t *render_ns, int64_t *wake_late_ns)
{
    const hz_rtm_cfg_t *c = &m->cfg;
    /* Fixed draws per frame keep the sequence independent of the model's parameters. */
    int64_t u = uniform(&m->rng, c->a_ns, c->b_ns > c->a_ns ? c->b_ns : c->a_ns);
    int spike = c->rate_ppm && hz_rng_below(&m->rng, 1000000u) < c->rate_ppm;
    *wake_late_ns = uniform(&m->rng, 0, c->wake_ns);
    switch (c->kind) {
    case HZ_RTM_CONST: *render_ns = c->a_ns; break;
    case HZ_RTM_UNIFORM: *render_ns = u; break;
    case HZ_RTM_SPIKES: *render_ns = spike ? c->b_ns : c->a_ns; break;
    case HZ_RTM_TRIANGLE: {
        uint64_t half = c->frames / 2, ph = frame % c->frames;
        uint64_t up = ph < half ? ph : c->frames - ph;
        *render_ns = c->a_ns + (int64_t)(((uint64_t)(c->b_ns - c->a_ns) * up) / (half ? half : 1));
        break;
    }
    default: *render_ns = frame < c->frames ? c->a_ns : c->b_ns; break;
    }
}

int64_t hz_rtm_max_ns(const hz_rtm_cfg_t *c)
{
    return c->kind == HZ_RTM_CONST ? c->a_ns : (c->a_ns > c->b_ns ? c->a_ns : c->b_ns);
}
