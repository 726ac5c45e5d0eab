/* Stochastic transparency at a blended hit (seed 004; thresholds in src/pattern/dither.c, hz/dither.h): the
 * any-hit decision of a camera path's stochastic ray and of a stochastic fragment's shadow ray. The float
 * inputs (alpha, barycentrics, the hit's side) become fixed point here; everything after is integer. */
#include "hz/dither.h"
#include "render_internal.h"

#if HZ_FEATURE_TRANSPARENCY /* the any-hit callback calls these only in builds with transparency */

static uint32_t to_q16(float a)
{
    if (!(a > 0.0f))
        return 0u;
    if (a >= 1.0f)
        return HZ_DITHER_ONE;
    return (uint32_t)(a * 65536.0f);
}

/* Hit-point key for Russian roulette: the primitive and its barycentrics in Q16. */
static uint32_t rr_threshold(uint32_t prim, float u, float v, uint32_t frame)
{
    return hz_dither_rr_threshold(prim, to_q16(u), to_q16(v), frame);
}

/* Which side of the triangle a camera-path ray meets: its direction is the hit point minus the eye (every
 * stochastic ray lies on a camera ray's line: continuations through blended layers do not bend it). */
static unsigned back_side(const struct hz_renderer *r, uint32_t prim, float u, float v)
{
    const hz_scene_t *s = r->scene;
    const uint32_t *t = s->tri + (size_t)prim * 3;
    const float *a = s->pos + (size_t)t[0] * 4, *b = s->pos + (size_t)t[1] * 4, *c = s->pos + (size_t)t[2] * 4;
    hz_vec3_t e1 = hz_v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]), e2 = hz_v3(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
    float w = 1.0f - u - v;
    hz_vec3_t p = hz_v3(w * a[0] + u * b[0] + v * c[0], w * a[1] + u * b[1] + v * c[1], w * a[2] + u * b[2] + v * c[2]);
    return hz_v3_dot(hz_v3_cross(e1, e2), hz_v3_sub(p, r->view.eye)) > 0.0f ? 1u : 0u;
}

bool hz_transp_keep(hz_worker_t *w, uint32_t prim, float u, float v, float alpha, uint32_t slot)
{
    const struct hz_renderer *r = w->r;
    uint32_t a = to_q16(alpha);
    if (a <= HZ_DITHER_MIN_ALPHA)
        return false;
    w->dither_touched[slot % HZ_TILE_PIXELS] = 1;
    if (a >= HZ_DITHER_ONE)
        return true;
    uint32_t px = w->b.pixel[slot % HZ_TILE_PIXELS];
    uint32_t x = px % r->f.opts.width, y = px / r->f.opts.width, f = w->b.dither_frame;
    uint32_t object = r->scene->tri_info[prim] >> 16, t;
    switch (r->f.opts.transparency) {
    case HZ_TRANSP_RR:
        t = rr_threshold(prim, u, v, f);
        break;
    case HZ_TRANSP_DTAA:
        t = hz_dither_dtaa_threshold(x, y, f, -1);
        break;
    case HZ_TRANSP_DTAA_STAR:
        t = hz_dither_dtaa_threshold(x, y, f, (int)hz_dither_dtaa_perm(object, back_side(r, prim, u, v)));
        break;
    default: /* std, hybrid */
        t = hz_dither_std_threshold(x, y, f, hz_dither_map_index(object, back_side(r, prim, u, v)));
        break;
    }
    return hz_dither_keep(a, t);
}

bool hz_transp_shadow_blocks(const hz_worker_t *w, uint32_t prim, float u, float v, float alpha)
{
    return hz_dither_keep(to_q16(alpha), rr_threshold(prim ^ 0x80000000u, u, v, w->b.dither_frame));
}

#endif

unsigned hz_transp_mv_align(hz_transp_t t)
{
    return t == HZ_TRANSP_DTAA || t == HZ_TRANSP_DTAA_STAR ? 5u : t == HZ_TRANSP_RR ? 1u : 3u;
}
