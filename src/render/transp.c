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

bool hz_transp_keep(hz_worker_t *w, uint32_t prim, float u, float v, uint32_t a, uint32_t slot, unsigned back)
{
    const struct hz_renderer *r = w->r;
    if (a <= HZ_DITHER_MIN_ALPHA)
        return false;
    slot %= HZ_TILE_PIXELS;
    w->dither_touched[slot] = 1;
    if (a >= HZ_DITHER_ONE)
        return true;
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

uint32_t hz_transp_alpha_q16(float alpha)
{
    return to_q16(alpha);
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
