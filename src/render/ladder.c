/* The governor's quality levels (see hz/ladder.h). */
#include "hz/ladder.h"

#include "hz/fmt.h"

/* Prior cost of one pixel of a mode, relative to TAA's (1 camera ray per pixel and a resolve): tdense traces a
 * quarter of the pixels (seed 001: about 3.5x cheaper than TAA at the same size), full mode spp rays without a
 * resolve, adaptive a presample and a quarter to a half of the pixels' subpixels again (seed 003). The governor
 * corrects these from what it measures; they only order the levels and seed the first predictions. */
static float mode_cost(const hz_render_opts_t *o)
{
    switch (o->mode) {
    case HZ_MODE_TDENSE: return 0.3f;
    case HZ_MODE_FULL: return 0.8f * (float)o->spp;
    case HZ_MODE_ADAPTIVE: return 2.0f;
    default: return 1.0f;
    }
}

typedef struct knobs {
    uint32_t bounces;  /* at most */
    float hybrid;      /* exact or hybrid below this X become hybrid:X (0: leave) */
    float tau_scale;   /* adaptive thresholds x this (1: leave) */
} knobs_t;

typedef struct scene_uses {
    bool mirrors, blend;
} scene_uses_t;

static float knob_cost(const hz_render_opts_t *base, const hz_render_opts_t *o, const scene_uses_t *u)
{
    float c = 1.0f;
    if (u->mirrors)
        for (uint32_t b = o->max_bounces; b < base->max_bounces; b++)
            c *= 0.85f; /* each bounce fewer: a share of the mirror rays */
    if (u->blend) {
        float xb = base->transparency == HZ_TRANSP_HYBRID ? base->hybrid_x : 0.0f;
        float xo = o->transparency == HZ_TRANSP_HYBRID ? o->hybrid_x : 0.0f;
        if (base->transparency == HZ_TRANSP_EXACT || base->transparency == HZ_TRANSP_HYBRID)
            c *= 1.0f - 0.55f * (xo - xb); /* hybrid:1 shades one layer where exact composites them all */
    }
    if (o->mode == HZ_MODE_ADAPTIVE && base->mode == HZ_MODE_ADAPTIVE && o->adaptive.tau[0] > base->adaptive.tau[0])
        c *= 0.8f;
    return c;
}

static uint32_t scaled(uint32_t v, uint32_t num, uint32_t den)
{
    uint32_t s = (v * num + den / 2) / den;
    return s < HZ_LADDER_MIN_SIZE ? (v < HZ_LADDER_MIN_SIZE ? v : HZ_LADDER_MIN_SIZE) : s;
}

static hz_render_mode_t fallback(hz_render_mode_t m)
{
    switch (m) {
    case HZ_MODE_ADAPTIVE: return HZ_MODE_TAA;
    case HZ_MODE_TAA:
    case HZ_MODE_FULL: return HZ_MODE_TDENSE;
    default: return m;
    }
}

static hz_render_opts_t level_opts(const hz_render_opts_t *base, const scene_uses_t *u, hz_render_mode_t mode,
                                   uint32_t num, uint32_t den, const knobs_t *k)
{
    hz_render_opts_t o = *base;
    o.width = scaled(base->width, num, den);
    o.height = scaled(base->height, num, den);
    if (mode != base->mode) {
        o.mode = mode;
        o.msaa4 = false;
        o.spp = 1;
        if (base->mode == HZ_MODE_ADAPTIVE)
            o.shutter = 0.0f;
    }
    if (u->mirrors && o.max_bounces > k->bounces)
        o.max_bounces = k->bounces;
    if (u->blend && k->hybrid > 0.0f &&
        (o.transparency == HZ_TRANSP_EXACT || (o.transparency == HZ_TRANSP_HYBRID && o.hybrid_x < k->hybrid))) {
        o.transparency = HZ_TRANSP_HYBRID;
        o.hybrid_x = k->hybrid;
    }
    if (o.mode == HZ_MODE_ADAPTIVE && k->tau_scale > 1.0f)
        for (int t = 0; t < HZ_TAU_COUNT; t++) {
            float v = o.adaptive.tau[t] * k->tau_scale;
            o.adaptive.tau[t] = v > 1.0f ? 1.0f : v;
        }
    return o;
}

static void name_level(hz_ladder_level_t *lv, const hz_render_opts_t *base)
{
    const hz_render_opts_t *o = &lv->opts;
    size_t n = hz_fmt(lv->name, sizeof lv->name, "%s %ux%u", hz_render_mode_name(o->mode), o->width, o->height);
    if (o->mode == HZ_MODE_FULL && o->spp > 1 && n < sizeof lv->name)
        n += hz_fmt(lv->name + n, sizeof lv->name - n, " %u spp", o->spp);
    if (o->max_bounces != base->max_bounces && n < sizeof lv->name)
        n += hz_fmt(lv->name + n, sizeof lv->name - n, ", %u bounce%s", o->max_bounces, o->max_bounces == 1 ? "" : "s");
    if ((o->transparency != base->transparency || o->hybrid_x != base->hybrid_x) && n < sizeof lv->name)
        n += hz_fmt(lv->name + n, sizeof lv->name - n, ", hybrid:%s", o->hybrid_x >= 1.0f ? "1" : "0.5");
    if (o->mode == HZ_MODE_ADAPTIVE && base->mode == HZ_MODE_ADAPTIVE && o->adaptive.tau[0] != base->adaptive.tau[0] &&
        n < sizeof lv->name)
        hz_fmt(lv->name + n, sizeof lv->name - n, ", thresholds x2");
}

hz_status_t hz_ladder_build(hz_ladder_t *l, const hz_scene_t *scene, const hz_render_opts_t *base, hz_error_t *err)
{
    hz_memset(l, 0, sizeof *l);
    hz_status_t s = hz_render_opts_check(base, err);
    if (s != HZ_OK)
        return s;
    scene_uses_t u;
    u.mirrors = HZ_FEATURE_MIRRORS && (scene->features & HZ_FEAT_MIRROR) && base->max_bounces > 0;
    u.blend = HZ_FEATURE_TRANSPARENCY && (scene->features & HZ_FEAT_BLEND);
    const knobs_t k0 = { base->max_bounces, 0.0f, 1.0f }, k1 = { 1, 0.5f, 2.0f }, k2 = { 0, 1.0f, 2.0f };
    const hz_render_mode_t m = base->mode, f1 = fallback(m), f2 = fallback(f1);
    struct { hz_render_mode_t mode; uint32_t num, den; const knobs_t *k; } cand[] = {
        { m, 1, 1, &k0 }, { m, 1, 1, &k1 }, { m, 3, 4, &k1 }, { m, 1, 2, &k1 }, { m, 1, 2, &k2 },
        { f1, 1, 2, &k2 }, { f1, 1, 3, &k2 }, { f2, 1, 3, &k2 }, { f2, 1, 4, &k2 }, { f2, 1, 6, &k2 },
        { f2, 1, 8, &k2 }, { f2, 1, 12, &k2 }, { f2, 1, 16, &k2 },
    };
    const float base_cost = mode_cost(base) * (float)base->width * (float)base->height;
    float last = 0.0f;
    for (size_t i = 0; i < HZ_ARRAY_LEN(cand) && l->count < HZ_GOV_MAX_LEVELS; i++) {
        hz_render_opts_t o = level_opts(base, &u, cand[i].mode, cand[i].num, cand[i].den, cand[i].k);
        float cost = mode_cost(&o) * (float)o.width * (float)o.height * knob_cost(base, &o, &u);
        float w = cost / base_cost;
        if (i > 0 && !(w < last * 0.97f))
            continue; /* not cheaper than the level before: nothing to give up here */
        if (hz_render_opts_check(&o, err) != HZ_OK)
            continue;
        hz_ladder_level_t *lv = &l->level[l->count];
        lv->opts = o;
        lv->scale_num = cand[i].num, lv->scale_den = cand[i].den;
        name_level(lv, base);
        uint32_t wq = (uint32_t)(w * 65536.0f + 0.5f);
        l->gov.weight_q16[l->count] = i == 0 ? 65536u : wq < 1u ? 1u : wq;
        l->count++;
        last = w;
    }
    l->gov.levels = l->count;
    return HZ_OK;
}

hz_status_t hz_ladder_reserve(const hz_ladder_t *l, const hz_scene_t *scene, size_t *bytes, hz_error_t *err)
{
    *bytes = 0;
    for (uint32_t i = 0; i < l->count; i++) {
        hz_render_plan_t p;
        hz_render_opts_t o = l->level[i].opts;
        o.reserve_bytes = 0;
        hz_status_t s = hz_render_plan(scene, &o, &p, err);
        if (s != HZ_OK)
            return s;
        *bytes = p.region_bytes > *bytes ? p.region_bytes : *bytes;
    }
    return HZ_OK;
}
