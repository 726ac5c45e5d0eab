/* Stochastic transparency at a blended hit (seed 004; thresholds in src/pattern/dither.c, hz/dither.h): the
 * any-hit decision of a camera path's stochastic ray and of a stochastic fragment's shadow ray, and the
 * per-triangle dither maps they use. The float inputs (alpha, barycentrics) become fixed point here; everything
 * after is integer. */
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

/* A group starts where the object changes or where a triangle's vertex-index range does not overlap the
 * group's so far: a baker that writes each particle (quad, sprite, small closed mesh) with vertices of its own,
 * one after the other, gets one group per particle; a mesh whose triangles share vertices across their index
 * order stays one group. The key a group's maps are hashed from: the object id for a group that starts with
 * its object (an object of one group keeps the maps it always had), else 2^16 + the group's first triangle. */
void hz_transp_maps(const hz_scene_t *s, uint32_t *maps)
{
    uint32_t key = 0, glo = 0, ghi = 0, gobj = 0;
    for (uint32_t t = 0; t < s->triangle_count; t++) {
        const uint32_t *v = s->tri + (size_t)t * 3;
        uint32_t lo = v[0], hi = v[0], obj = s->tri_info[t] >> 16;
        for (int k = 1; k < 3; k++) {
            lo = v[k] < lo ? v[k] : lo;
            hi = v[k] > hi ? v[k] : hi;
        }
        if (t == 0 || obj != gobj) {
            key = obj, glo = lo, ghi = hi, gobj = obj;
        } else if (hi < glo || lo > ghi) {
            key = 0x10000u + t, glo = lo, ghi = hi;
        } else {
            glo = lo < glo ? lo : glo;
            ghi = hi > ghi ? hi : ghi;
        }
        maps[t] = HZ_TRANSP_MAPS_PACK(hz_dither_map_index(key, 0), hz_dither_map_index(key, 1),
                                      hz_dither_dtaa_perm(key, 0), hz_dither_dtaa_perm(key, 1));
    }
}

void hz_transp_cells(hz_worker_t *w)
{
    const struct hz_renderer *r = w->r;
    const hz_transp_t m = r->f.opts.transparency;
    const uint32_t width = r->f.opts.width, f = w->b.dither_frame;
    if (m == HZ_TRANSP_RR)
        return;
    for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++) {
        uint32_t px = w->b.pixel[slot];
        if (px == UINT32_MAX)
            continue;
        uint32_t x = px % width, y = px / width;
        w->dither_cell[slot] = m == HZ_TRANSP_DTAA || m == HZ_TRANSP_DTAA_STAR ? hz_dither_dtaa_cell(x, y, f)
                                                                                : hz_dither_std_cell(x, y, f);
    }
}

/* The largest alpha byte of texture t's level 0, the level hz_texture_alpha reads (a texture whose flags say it is
 * opaque is taken at its word: 255, an upper bound whatever its texels hold). */
static uint32_t level0_alpha_max(const hz_scene_t *s, const hz_texture_t *t)
{
    if (!(t->flags & 1u))
        return 255u;
    const uint8_t *p = s->texels + (size_t)t->first_texel * 4u;
    const size_t n = (size_t)t->width * t->height;
    uint32_t m = 0;
    for (size_t i = 0; i < n && m < 255u; i++)
        m = p[4 * i + 3] > m ? p[4 * i + 3] : m;
    return m;
}

/* Whether every texture coordinate a hit on triangle t can have is finite: its vertices' are, and small enough
 * that the barycentric mix (weights within [-1, 1] by the traversal's test) stays finite. Else hz_texture_alpha
 * may answer 1 for it. */
static bool uv_finite(const hz_scene_t *s, uint32_t t)
{
    for (int k = 0; k < 3; k++) {
        const float *uv = s->uv + (size_t)s->tri[(size_t)t * 3 + (unsigned)k] * 2;
        if (!(hz_absf(uv[0]) <= 0x1p100f && hz_absf(uv[1]) <= 0x1p100f))
            return false;
    }
    return true;
}

/* Margin over the bound's own rounding: the bilinear mix of texels at most M can exceed M by an ulp or two, and
 * alpha * texture is a product of floats; a relative error of 2^-20 moves a Q16 value by less than 1. */
#define BOUND_SLACK 16u

void hz_transp_bounds(const hz_scene_t *s, bool textures, uint32_t *bound)
{
    for (uint32_t i = 0; i < s->material_count; i++) {
        const hz_material_t *m = &s->materials[i];
        uint32_t b = HZ_DITHER_ONE;
        if (m->alpha_mode == HZ_ALPHA_BLEND) {
            /* untextured, or a texture index with no texture (hz_texture_alpha answers 1): the alpha itself */
            b = to_q16(m->alpha);
            if (HZ_FEATURE_TEXTURES && textures && m->alpha_texture >= 0 &&
                (uint32_t)m->alpha_texture < s->texture_count) {
                const float tmax = (float)level0_alpha_max(s, &s->textures[m->alpha_texture]) * (1.0f / 255.0f);
                b = to_q16(m->alpha * tmax) + BOUND_SLACK;
            }
            b = b > HZ_DITHER_ONE ? HZ_DITHER_ONE : b;
        }
        bound[i] = b;
    }
    if (!(HZ_FEATURE_TEXTURES && textures))
        return;
    /* A hit whose texture coordinates are not finite reads alpha 1: the material's own alpha bounds it then. */
    for (uint32_t t = 0; t < s->triangle_count; t++) {
        const uint32_t mi = s->tri_info[t] & 0xffffu;
        if (mi >= s->material_count || s->materials[mi].alpha_mode != HZ_ALPHA_BLEND ||
            s->materials[mi].alpha_texture < 0 || uv_finite(s, t))
            continue;
        const uint32_t own = to_q16(s->materials[mi].alpha);
        bound[mi] = own > bound[mi] ? own : bound[mi];
    }
}

/* The method's decision for a layer of opacity a (Q16, strictly between 0.01 and 1); every method keeps a layer
 * iff its opacity reaches a threshold that does not depend on it, so the decision never falls as a grows. */
static bool decide(const hz_worker_t *w, uint32_t prim, float u, float v, uint32_t a, uint32_t slot, unsigned back)
{
    const struct hz_renderer *r = w->r;
    const uint32_t maps = r->tri_maps[prim];
    switch (r->f.opts.transparency) {
    case HZ_TRANSP_RR:
        return hz_dither_keep(a, rr_threshold(prim, u, v, w->b.dither_frame));
    case HZ_TRANSP_DTAA:
        return hz_dither_dtaa_keep(a, -1, w->dither_cell[slot]);
    case HZ_TRANSP_DTAA_STAR:
        return hz_dither_dtaa_keep(a, (int)HZ_TRANSP_MAPS_PERM(maps, back), w->dither_cell[slot]);
    default: /* std, hybrid */
        return hz_dither_std_keep(a, HZ_TRANSP_MAPS_STD(maps, back), w->dither_cell[slot]);
    }
}

bool hz_transp_keep(hz_worker_t *w, uint32_t prim, float u, float v, uint32_t a, uint32_t slot, unsigned back)
{
    if (a <= HZ_DITHER_MIN_ALPHA)
        return false;
    slot %= HZ_TILE_PIXELS;
    w->dither_touched[slot] = 1;
    if (a >= HZ_DITHER_ONE)
        return true;
    return decide(w, prim, u, v, a, slot, back);
}

bool hz_transp_rejects(const hz_worker_t *w, uint32_t prim, float u, float v, uint32_t bound, uint32_t slot,
                       unsigned back)
{
    if (bound <= HZ_DITHER_MIN_ALPHA)
        return true; /* hz_transp_keep rejects it and leaves the slot untouched */
    slot %= HZ_TILE_PIXELS;
    /* A layer above 0.01 marks the slot: only once it is marked does the decision alone say all */
    if (bound >= HZ_DITHER_ONE || !w->dither_touched[slot])
        return false;
    return !decide(w, prim, u, v, bound, slot, back);
}

uint32_t hz_transp_alpha_q16(float alpha)
{
    return to_q16(alpha);
}

uint32_t hz_transp_shadow_threshold(const hz_worker_t *w, uint32_t prim, float u, float v)
{
    return rr_threshold(prim ^ 0x80000000u, u, v, w->b.dither_frame);
}

#endif

unsigned hz_transp_mv_align(hz_transp_t t)
{
    return t == HZ_TRANSP_DTAA || t == HZ_TRANSP_DTAA_STAR ? 5u : t == HZ_TRANSP_RR ? 1u : 3u;
}
