/*
 * shade_kernel.h — hz_shade_surfaces (src/render/shade.h) written once over a vector type; included by shade_avx2.c and
 * shade_neon.c after they define the operations below on their registers:
 *   vf (floats), vi (int32), vm (lane masks);
 *   vf_load vf_store vf_set1 vf_add vf_sub vf_mul vf_div vf_sqrt vf_abs vf_gt vf_lt vf_sel(m, a, b)
 *   vm_and vm_bits (bit i: lane i set)
 *   vi_load vi_store vi_set1 vi_add vi_sub vi_mul vi_and vi_or vi_srl(x, n) vi_lt vi_sel vf_from_vi vi_trunc
 *   vf_floor vf_as_vi vi_as_vf vf_gather(base, index) vi_gather(base, index)
 * Every float operation is the IEEE one, rounded once, in the order of the scalar twin (shade_packet.c): the
 * kernel is that code, lane-parallel, so the results are the same bits. Steps that branch per lane on data
 * (pose keys, the material) run per lane through the shared helpers of shade_internal.h; a texture's mip
 * levels are walked once per packet there, and each lane's level is chosen lane-parallel.
 */
#ifndef HZ_SHADE_KERNEL_H
#define HZ_SHADE_KERNEL_H

#include "hz/image.h"
#include "shade_internal.h"

#define KL HZ_SHADE_LANES

typedef struct kv3 {
    vf x, y, z;
} kv3_t;

static inline kv3_t k_v3_load(const float *x, const float *y, const float *z)
{
    kv3_t r = { vf_load(x), vf_load(y), vf_load(z) };
    return r;
}

static inline kv3_t k_sub(kv3_t a, kv3_t b)
{
    kv3_t r = { vf_sub(a.x, b.x), vf_sub(a.y, b.y), vf_sub(a.z, b.z) };
    return r;
}

static inline kv3_t k_scale(kv3_t a, vf s)
{
    kv3_t r = { vf_mul(a.x, s), vf_mul(a.y, s), vf_mul(a.z, s) };
    return r;
}

static inline vf k_dot(kv3_t a, kv3_t b)
{
    return vf_add(vf_add(vf_mul(a.x, b.x), vf_mul(a.y, b.y)), vf_mul(a.z, b.z));
}

static inline kv3_t k_cross(kv3_t a, kv3_t b)
{
    kv3_t r = { vf_sub(vf_mul(a.y, b.z), vf_mul(a.z, b.y)), vf_sub(vf_mul(a.z, b.x), vf_mul(a.x, b.z)),
                vf_sub(vf_mul(a.x, b.y), vf_mul(a.y, b.x)) };
    return r;
}

/* w a + u b + v c, left to right, as the scalar bary. */
static inline vf k_bary1(vf a, vf b, vf c, vf w, vf u, vf v)
{
    return vf_add(vf_add(vf_mul(w, a), vf_mul(u, b)), vf_mul(v, c));
}

static inline kv3_t k_bary(const float (*p)[KL], vf w, vf u, vf v)
{
    kv3_t r = { k_bary1(vf_load(p[0]), vf_load(p[3]), vf_load(p[6]), w, u, v),
                k_bary1(vf_load(p[1]), vf_load(p[4]), vf_load(p[7]), w, u, v),
                k_bary1(vf_load(p[2]), vf_load(p[5]), vf_load(p[8]), w, u, v) };
    return r;
}

static inline vm k_finite(vf x)
{
    return vf_lt(vf_abs(x), vf_set1(__builtin_inff())); /* false for NaN */
}

/* hz_v3_normalize: a / sqrt(a.a) where that is safe; the lanes of `live` where it is not (non-finite, zero,
 * tiny or huge vectors) take hz_v3_normalize itself. l2 is a.a. */
static inline kv3_t k_normalize(kv3_t a, vf l2, uint32_t live)
{
    vm ok = vm_and(vm_and(vm_and(k_finite(a.x), k_finite(a.y)), vm_and(k_finite(a.z), k_finite(l2))),
                   vf_gt(l2, vf_set1(0.0f)));
    kv3_t r = k_scale(a, vf_div(vf_set1(1.0f), vf_sqrt(l2)));
    uint32_t slow = live & ~vm_bits(ok);
    if (slow) {
        float ax[KL] HZ_ALIGNED(32), ay[KL] HZ_ALIGNED(32), az[KL] HZ_ALIGNED(32);
        float rx[KL] HZ_ALIGNED(32), ry[KL] HZ_ALIGNED(32), rz[KL] HZ_ALIGNED(32);
        vf_store(ax, a.x), vf_store(ay, a.y), vf_store(az, a.z);
        vf_store(rx, r.x), vf_store(ry, r.y), vf_store(rz, r.z);
        for (uint32_t i = 0; i < KL; i++)
            if (slow >> i & 1u) {
                hz_vec3_t n = hz_v3_normalize(hz_v3(ax[i], ay[i], az[i]));
                rx[i] = n.x, ry[i] = n.y, rz[i] = n.z;
            }
        r = k_v3_load(rx, ry, rz);
    }
    return r;
}

/* hz_floorf, lane-parallel: the ISA's floor (vf_floor), the same bits. */
static inline vf k_floor(vf x) { return vf_floor(x); }

/* hz_log2_approx, lane-parallel. */
static inline vf k_log2(vf x)
{
    vm ok = vm_and(vf_gt(x, vf_set1(0.0f)), k_finite(x));
    vi bits = vf_as_vi(x);
    vi e = vi_sub(vi_and(vi_srl(bits, 23), vi_set1(0xff)), vi_set1(127));
    vf m = vi_as_vf(vi_or(vi_and(bits, vi_set1(0x007fffff)), vi_set1(0x3f800000)));
    vf r = vf_sub(vf_add(vf_from_vi(e), vf_mul(vf_add(vf_mul(vf_set1(-0.34484843f), m), vf_set1(2.02466578f)), m)),
                  vf_set1(1.67487759f));
    return vf_sel(ok, r, vf_set1(-126.0f));
}

/* One texel per lane: linear rgb and alpha (texture.c's fetch). */
static inline void k_texel(const hz_scene_t *s, vi idx, vf out[4])
{
    vi t = vi_gather((const int32_t *)(const void *)s->texels, idx);
    const float *dec = (const float *)(const void *)hz_srgb8_decode_bits;
    vi m8 = vi_set1(0xff);
    out[0] = vf_gather(dec, vi_and(t, m8));
    out[1] = vf_gather(dec, vi_and(vi_srl(t, 8), m8));
    out[2] = vf_gather(dec, vi_and(vi_srl(t, 16), m8));
    out[3] = vf_mul(vf_from_vi(vi_srl(t, 24)), vf_set1(1.0f / 255.0f));
}

/* Texel coordinate i in [-1, n] wrapped into [0, n): texture.c's wrap on the only values bilinear gives it
 * (u - floor(u) lies in [0, 1], so (u - floor(u)) n - 0.5 in [-0.5, n - 0.5]). */
static inline vi k_wrap(vi i, vi n)
{
    i = vi_sel(vi_lt(i, vi_set1(0)), vi_add(i, n), i);
    return vi_sel(vi_lt(i, n), i, vi_sub(i, n));
}

/* Bilinear samples at (tu, tv) on each lane's level (first texel, width, height); lanes outside `on` (all
 * bits set: gather) read texel 0. */
static inline void k_bilinear(const hz_scene_t *s, vi vfirst, vi vw, vi vh, vi onv, vf tu, vf tv, vf out[4])
{
    vf fu = vf_sub(vf_mul(vf_sub(tu, k_floor(tu)), vf_from_vi(vw)), vf_set1(0.5f));
    vf fv = vf_sub(vf_mul(vf_sub(tv, k_floor(tv)), vf_from_vi(vh)), vf_set1(0.5f));
    vf x0f = k_floor(fu), y0f = k_floor(fv);
    vf ax = vf_sub(fu, x0f), ay = vf_sub(fv, y0f);
    vi x0 = vi_trunc(x0f), y0 = vi_trunc(y0f);
    vi one = vi_set1(1);
    vi x1 = k_wrap(vi_add(x0, one), vw), y1 = k_wrap(vi_add(y0, one), vh);
    x0 = k_wrap(x0, vw), y0 = k_wrap(y0, vh);
    vi r0 = vi_add(vfirst, vi_mul(y0, vw)), r1 = vi_add(vfirst, vi_mul(y1, vw));
    vi ia = vi_and(vi_add(r0, x0), onv), ib = vi_and(vi_add(r0, x1), onv);
    vi ic = vi_and(vi_add(r1, x0), onv), id = vi_and(vi_add(r1, x1), onv);
    vf a[4], b[4], cc[4], d[4];
    k_texel(s, ia, a);
    k_texel(s, ib, b);
    k_texel(s, ic, cc);
    k_texel(s, id, d);
    for (int k = 0; k < 4; k++) {
        vf top = vf_add(a[k], vf_mul(vf_sub(b[k], a[k]), ax));
        vf bot = vf_add(cc[k], vf_mul(vf_sub(d[k], cc[k]), ax));
        out[k] = vf_add(top, vf_mul(vf_sub(bot, top), ay));
    }
}

/* Each lane's sample of texture tex[lane] at (tu, tv) with its mip level from lod_base, for the lanes of
 * `lanes` (texture.c's hz_texture_sample: bilinear, wrapped); lanes of `foot` take the mean of the footprint's
 * taps with gradients g (hz_shade_sample_lane). */
static void k_sample(const hz_shade_ctx_t *c, const int32_t *tex, uint32_t lanes, vf tu, vf tv,
                     const float *lod_base, const float (*g)[KL], uint32_t foot, float rgba[4][KL])
{
    const hz_scene_t *s = c->scene;
    float su[KL] HZ_ALIGNED(32), sv[KL] HZ_ALIGNED(32);
    int32_t first[KL] HZ_ALIGNED(32), w[KL] HZ_ALIGNED(32), h[KL] HZ_ALIGNED(32), on[KL] HZ_ALIGNED(32);
    int32_t level[KL] HZ_ALIGNED(32);
    vf_store(su, tu), vf_store(sv, tv);
    for (uint32_t i = 0; i < KL; i++) {
        first[i] = 0, w[i] = h[i] = 1, on[i] = 0;
        rgba[0][i] = rgba[1][i] = rgba[2][i] = rgba[3][i] = 1.0f;
    }
    /* Lanes with a texture and finite coordinates (hz_texture_usable; the others read the constant 1), a
     * texture at a time: its levels once, each lane's level lane-parallel (hz_texture_level_of: lod + 0.5 where
     * finite, else 0; 0 at or below 0, else truncated after the min with the top level). */
    const uint32_t finite_uv = vm_bits(vm_and(k_finite(tu), k_finite(tv)));
    const vf lod_lanes = vf_load(lod_base);
    uint32_t gather = 0, todo = HZ_FEATURE_TEXTURES ? lanes : 0u;
    while (todo) {
        const int32_t t = tex[__builtin_ctz(todo)];
        uint32_t same = 0;
        for (uint32_t i = 0; i < KL; i++)
            same |= (uint32_t)(tex[i] == t) << i;
        same &= todo;
        todo &= ~same;
        if (t < 0 || (uint32_t)t >= s->texture_count || !(same &= finite_uv))
            continue;
        hz_shade_levels_t lv;
        hz_shade_levels_head(s, t, &lv);
        const vf lod = vf_add(lod_lanes, vf_set1(lv.size_term));
        const vf l = vf_sel(k_finite(lod), vf_add(lod, vf_set1(0.5f)), vf_set1(0.0f));
        const vf top = vf_set1((float)lv.top);
        const vi lvl = vi_trunc(vf_sel(vf_lt(l, top), l, top));
        vi_store(level, vi_sel(vf_gt(l, vf_set1(0.0f)), lvl, vi_set1(0)));
        int32_t deepest = 0;
        for (uint32_t m = same; m; m &= m - 1u)
            deepest = level[__builtin_ctz(m)] > deepest ? level[__builtin_ctz(m)] : deepest;
        hz_shade_levels_walk(s, t, deepest, &lv);
        for (uint32_t m = same; m; m &= m - 1u) {
            const uint32_t i = (uint32_t)__builtin_ctz(m);
            const int32_t k = level[i];
            if (!(lv.far >> k & 1u)) {
                first[i] = lv.first[k], w[i] = lv.w[k], h[i] = lv.h[k];
                on[i] = -1, gather |= 1u << i;
                continue;
            }
            float px[4], gi[4];
            const float *gl = NULL; /* g is read only in the footprint's lanes */
            if (foot >> i & 1u)
                gi[0] = g[0][i], gi[1] = g[1][i], gi[2] = g[2][i], gi[3] = g[3][i], gl = gi;
            hz_shade_sample_lane(s, t, su[i], sv[i], lod_base[i], gl, px);
            rgba[0][i] = px[0], rgba[1][i] = px[1], rgba[2][i] = px[2], rgba[3][i] = px[3];
        }
    }
    if (!gather)
        return;
    vi vw = vi_load(w), vh = vi_load(h), vfirst = vi_load(first);
    /* Lanes that do not gather read texel 0 (their coordinates may be anything). */
    vi onv = vi_load(on);
    const uint32_t taps = gather & foot;
    uint32_t keep = 0;
    if (taps) {
        /* hz_shade_sample_lane's taps, lane-parallel; a lane with a tap that is not finite keeps its centre sample (its
         * taps are read at the centre, never at a wild index). */
        vf gux = vf_load(g[0]), guy = vf_load(g[1]), gvx = vf_load(g[2]), gvy = vf_load(g[3]);
        vm finite = vm_and(k_finite(tu), k_finite(tv));
        vf acc[4];
        for (uint32_t k = 0; k < HZ_SHADE_TAPS; k++) {
            vf ox = vf_set1(hz_shade_tap_offset(k % HZ_SHADE_TAP_SIDE));
            vf oy = vf_set1(hz_shade_tap_offset(k / HZ_SHADE_TAP_SIDE));
            vf su_k = vf_add(tu, vf_add(vf_mul(ox, gux), vf_mul(oy, guy)));
            vf sv_k = vf_add(tv, vf_add(vf_mul(ox, gvx), vf_mul(oy, gvy)));
            vm ok = vm_and(k_finite(su_k), k_finite(sv_k));
            finite = vm_and(finite, ok);
            vf b[4];
            k_bilinear(s, vfirst, vw, vh, onv, vf_sel(ok, su_k, tu), vf_sel(ok, sv_k, tv), b);
            for (int ch = 0; ch < 4; ch++)
                acc[ch] = k ? vf_add(acc[ch], b[ch]) : b[ch];
        }
        keep = taps & vm_bits(finite);
        for (int ch = 0; ch < 4; ch++)
            acc[ch] = vf_mul(acc[ch], vf_set1(1.0f / (float)HZ_SHADE_TAPS));
        float mean[KL] HZ_ALIGNED(32);
        for (int ch = 0; ch < 4; ch++) {
            vf_store(mean, acc[ch]);
            for (uint32_t i = 0; i < KL; i++)
                if (keep >> i & 1u)
                    rgba[ch][i] = mean[i];
        }
    }
    /* the centre sample, for the lanes without (finite) taps: made only where one needs it */
    if (!(gather & ~keep))
        return;
    vf res[4];
    k_bilinear(s, vfirst, vw, vh, onv, tu, tv, res);
    float out[KL] HZ_ALIGNED(32);
    for (int k = 0; k < 4; k++) {
        vf_store(out, res[k]);
        for (uint32_t i = 0; i < KL; i++)
            if ((gather & ~keep) >> i & 1u)
                rgba[k][i] = out[i];
    }
}

static inline vf k_len(kv3_t a)
{
    return vf_sqrt(k_dot(a, a));
}

static inline vf k_max(vf a, vf b)
{
    return vf_sel(vf_gt(a, b), a, b); /* hz_maxf */
}

static inline vf k_min(vf a, vf b)
{
    return vf_sel(vf_lt(a, b), a, b); /* hz_minf */
}

/* accel.c's offset_component: 256 ulps per unit of normal away from the origin, a fixed step near it. */
static inline vf k_offset(vf p, vf n, float origin, float float_scale)
{
    vf near = vf_add(p, vf_mul(vf_set1(float_scale), n));
    vi of = vi_trunc(vf_mul(vf_set1(256.0f), n));
    vi bits = vi_add(vf_as_vi(p), vi_sel(vf_lt(p, vf_set1(0.0f)), vi_sub(vi_set1(0), of), of));
    return vf_sel(vf_lt(vf_abs(p), vf_set1(origin)), near, vi_as_vf(bits));
}

/* hz_terminator_skip on the scene's own pose: vertices a, b, c and normals n[3] (pos[] / nrm[] layout). */
static inline vf k_skip(const float (*pos)[KL], const float (*nrm)[KL], kv3_t ng)
{
    kv3_t a = k_v3_load(pos[0], pos[1], pos[2]), b = k_v3_load(pos[3], pos[4], pos[5]);
    kv3_t cc = k_v3_load(pos[6], pos[7], pos[8]);
    vf e = k_max(k_len(k_sub(b, a)), k_max(k_len(k_sub(cc, b)), k_len(k_sub(a, cc))));
    vf cmin = vf_set1(1.0f);
    for (int i = 0; i < 3; i++) {
        kv3_t n = k_v3_load(nrm[i * 3], nrm[i * 3 + 1], nrm[i * 3 + 2]);
        vf len = k_len(n);
        vf cs = vf_div(vf_abs(k_dot(n, ng)), len);
        cmin = vf_sel(vf_gt(len, vf_set1(0.0f)), k_min(cmin, cs), cmin);
    }
    vm curved = vm_and(vm_and(vf_lt(cmin, vf_set1(0.9999f)), vf_gt(e, vf_set1(0.0f))), vf_lt(e, vf_set1(3.0e38f)));
    vf sn = vf_sqrt(vf_sub(vf_set1(1.0f), vf_mul(cmin, cmin)));
    vf skip = k_min(vf_mul(vf_mul(vf_set1(0.5f), e), sn), vf_mul(vf_set1(0.25f), e));
    return vf_sel(curved, skip, vf_set1(0.0f));
}

/* Shadow-ray origin, terminator skip and the first HZ_SHADE_LIGHTS lights (hz_shade_light_lane). pos / nrm hold
 * the scene's own vertices and normals of the lanes' triangles. */
static void k_lights(const hz_shade_ctx_t *c, uint32_t mask, const float (*pos)[KL], const float (*nrm)[KL], kv3_t p,
                     kv3_t ng, kv3_t ns, hz_shade_out_t *o)
{
    float scale = c->offset_scale;
    if (!(scale > 0.0f) || !hz_isfinitef(scale))
        scale = 1.0f;
    const float origin = scale * (1.0f / 32.0f), float_scale = scale * (1.0f / 65536.0f);
    kv3_t n = k_normalize(ng, k_dot(ng, ng), mask);
    kv3_t ol = { k_offset(p.x, n.x, origin, float_scale), k_offset(p.y, n.y, origin, float_scale),
                 k_offset(p.z, n.z, origin, float_scale) };
    vf skip = c->scene->nrm ? k_skip(pos, nrm, ng) : vf_set1(0.0f);
    vf_store(o->lox, ol.x), vf_store(o->loy, ol.y), vf_store(o->loz, ol.z), vf_store(o->skip, skip);
    const uint32_t nl = c->light_count < HZ_SHADE_LIGHTS ? c->light_count : HZ_SHADE_LIGHTS;
    const vm has_skip = vf_gt(skip, vf_set1(0.0f));
    for (uint32_t l = 0; l < HZ_SHADE_LIGHTS; l++)
        o->lit[l] = 0;
    for (uint32_t l = 0; l < nl; l++) {
        const hz_light_t *lt = &c->lights[l];
        hz_shade_light_t *out = &o->light[l];
        kv3_t lp = { vf_set1(lt->position[0]), vf_set1(lt->position[1]), vf_set1(lt->position[2]) };
        kv3_t L = k_sub(lp, ol);
        vf dist2 = k_dot(L, L);
        vf dist = vf_sqrt(dist2);
        vm far = vf_gt(dist, vf_set1(0.0f));
        kv3_t ls = k_scale(L, vf_div(vf_set1(1.0f), dist));
        kv3_t ld = { vf_sel(far, ls.x, ns.x), vf_sel(far, ls.y, ns.y), vf_sel(far, ls.z, ns.z) };
        vf cs = k_dot(ns, ld);
        vm ok = vm_and(vm_and(vf_gt(cs, vf_set1(0.0f)), vf_gt(k_dot(ng, ld), vf_set1(0.0f))), far);
        vf fall = lt->falloff == HZ_FALLOFF_INV_SQUARE ? vf_div(vf_set1(1.0f), dist2) : vf_set1(1.0f);
        vf k = vf_mul(vf_mul(cs, vf_set1(HZ_SHADE_INV_PI)), fall);
        vf tmax = vf_mul(dist, vf_set1(1.0f - 1e-4f));
        vf k0 = k_min(skip, tmax);
        vf_store(out->ox, vf_sel(has_skip, vf_add(ol.x, vf_mul(ld.x, k0)), ol.x));
        vf_store(out->oy, vf_sel(has_skip, vf_add(ol.y, vf_mul(ld.y, k0)), ol.y));
        vf_store(out->oz, vf_sel(has_skip, vf_add(ol.z, vf_mul(ld.z, k0)), ol.z));
        vf_store(out->dx, ld.x), vf_store(out->dy, ld.y), vf_store(out->dz, ld.z);
        vf_store(out->tmax, vf_sel(has_skip, vf_sub(tmax, k0), tmax));
        vf_store(out->k, k);
        o->lit[l] = vm_bits(ok) & mask;
    }
}

void hz_shade_surfaces(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t mask, hz_shade_out_t *o)
{
    const hz_scene_t *s = c->scene;
    if (!mask)
        return;
    if (s->triangle_count > 0x2aaaaaaau || s->vertex_count > 0x1fffffffu) { /* beyond 32-bit gather indices */
        hz_shade_surfaces_scalar(c, in, mask, o);
        return;
    }
    float pos[9][KL] HZ_ALIGNED(32), nrm[9][KL] HZ_ALIGNED(32);
    vi prim3 = vi_mul(vi_load((const int32_t *)(const void *)in->prim), vi_set1(3));
    const int32_t *tri = (const int32_t *)(const void *)s->tri;
    vi vid[3] = { vi_gather(tri, prim3), vi_gather(tri, vi_add(prim3, vi_set1(1))),
                  vi_gather(tri, vi_add(prim3, vi_set1(2))) };
    if (HZ_FEATURE_MOTION && c->keys) {
        hz_shade_fetch_scalar(c, in, mask, pos, nrm);
    } else {
        for (int k = 0; k < 3; k++) {
            vi i4 = vi_mul(vid[k], vi_set1(4));
            for (int a = 0; a < 3; a++) {
                vf_store(pos[k * 3 + a], vf_gather(s->pos + a, i4));
                if (s->nrm)
                    vf_store(nrm[k * 3 + a], vf_gather(s->nrm + a, i4));
            }
        }
    }
    vf u = vf_load(in->u), v = vf_load(in->v);
    vf w = vf_sub(vf_sub(vf_set1(1.0f), u), v);
    kv3_t d = k_v3_load(in->dx, in->dy, in->dz);
    kv3_t p0 = k_v3_load(pos[0], pos[1], pos[2]), p1 = k_v3_load(pos[3], pos[4], pos[5]);
    kv3_t p2 = k_v3_load(pos[6], pos[7], pos[8]);
    kv3_t p = k_bary((const float (*)[KL])pos, w, u, v);
    const kv3_t e1 = k_sub(p1, p0), e2 = k_sub(p2, p0);
    kv3_t ngr = k_cross(e1, e2);
    vf l2 = k_dot(ngr, ngr);
    vf area2 = vf_sqrt(l2);
    kv3_t ng = k_normalize(ngr, l2, mask);
    vf dn = k_dot(ng, d);
    vf flip = vf_sel(vf_gt(dn, vf_set1(0.0f)), vf_set1(-1.0f), vf_set1(1.0f));
    kv3_t ngf = k_scale(ng, flip), ns = ngf;
    if (s->nrm) {
        kv3_t nb = k_bary((const float (*)[KL])nrm, w, u, v);
        kv3_t n = k_scale(k_normalize(nb, k_dot(nb, nb), mask), flip);
        vm up = vf_gt(k_dot(n, ngf), vf_set1(0.0f));
        ns.x = vf_sel(up, n.x, ngf.x), ns.y = vf_sel(up, n.y, ngf.y), ns.z = vf_sel(up, n.z, ngf.z);
    }
    vf_store(o->px, p.x), vf_store(o->py, p.y), vf_store(o->pz, p.z);
    vf_store(o->ngx, ngf.x), vf_store(o->ngy, ngf.y), vf_store(o->ngz, ngf.z);
    vf_store(o->nsx, ns.x), vf_store(o->nsy, ns.y), vf_store(o->nsz, ns.z);
    if (HZ_FEATURE_MOTION && c->keys) { /* the terminator skip looks at the scene's own pose */
        for (int k = 0; k < 3; k++) {
            vi i4 = vi_mul(vid[k], vi_set1(4));
            for (int a = 0; a < 3; a++) {
                vf_store(pos[k * 3 + a], vf_gather(s->pos + a, i4));
                if (s->nrm)
                    vf_store(nrm[k * 3 + a], vf_gather(s->nrm + a, i4));
            }
        }
    }
    k_lights(c, mask, (const float (*)[KL])pos, (const float (*)[KL])nrm, p, ngf, ns, o);

    hz_shade_lane_tex_t lt[KL];
    uint32_t any = 0, base = 0, alpha = 0;
    int32_t base_tex[KL], alpha_tex[KL];
    for (uint32_t i = 0; i < KL; i++) {
        base_tex[i] = alpha_tex[i] = -1;
        if (!(mask >> i & 1u))
            continue;
        hz_shade_lane_material(c, in, i, o, &lt[i]);
        if (!lt[i].any)
            continue;
        any |= 1u << i;
        base_tex[i] = lt[i].base, alpha_tex[i] = lt[i].alpha;
        base |= (lt[i].base >= 0 ? 1u : 0u) << i;
        alpha |= (lt[i].alpha >= 0 ? 1u : 0u) << i;
    }
    if (!HZ_FEATURE_TEXTURES || !any)
        return;
    const float *uv = s->uv;
    vi i2[3] = { vi_add(vid[0], vid[0]), vi_add(vid[1], vid[1]), vi_add(vid[2], vid[2]) };
    vf a0 = vf_gather(uv, i2[0]), a1 = vf_gather(uv + 1, i2[0]);
    vf b0 = vf_gather(uv, i2[1]), b1 = vf_gather(uv + 1, i2[1]);
    vf c0 = vf_gather(uv, i2[2]), c1 = vf_gather(uv + 1, i2[2]);
    vf tu = k_bary1(a0, b0, c0, w, u, v), tv = k_bary1(a1, b1, c1, w, u, v);
    vf cr = vf_sub(vf_mul(vf_sub(b0, a0), vf_sub(c1, a1)), vf_mul(vf_sub(c0, a0), vf_sub(b1, a1)));
    vf uv_area2 = vf_abs(cr);
    vf cs = vf_abs(dn);
    vf width = vf_add(vf_load(in->cone_w), vf_mul(vf_load(in->cone_s), vf_load(in->t)));
    vf lod = vf_sub(vf_add(vf_mul(vf_set1(0.5f), k_log2(vf_div(uv_area2, area2))), k_log2(width)), k_log2(cs));
    /* The footprint's gradients (hz_shade_footprint_lane, lane-parallel), on the triangle at the ray's time. */
    float fg[4][KL] HZ_ALIGNED(32);
    uint32_t foot = 0;
    if (HZ_FEATURE_TEXTURES && c->footprint) {
        const hz_shade_footprint_t *fp = c->footprint;
        vf dnr = k_dot(d, ngr); /* l2 is the twin's |N|^2 for the unnormalised normal N = ngr */
        const kv3_t fv = { vf_set1(fp->f[0]), vf_set1(fp->f[1]), vf_set1(fp->f[2]) };
        vf tq = vf_mul(vf_load(in->eye_dist), k_dot(d, fv));
        kv3_t q1 = k_cross(e2, ngr), q2 = k_cross(ngr, e1);
        vf du1 = vf_sub(b0, a0), dv1 = vf_sub(b1, a1), du2 = vf_sub(c0, a0), dv2 = vf_sub(c1, a1);
        vm ok = vf_gt(vf_load(in->eye_dist), vf_set1(0.0f));
        for (int axis = 0; axis < 2; axis++) {
            const float *ev = axis ? fp->ey : fp->ex;
            kv3_t e = { vf_set1(ev[0]), vf_set1(ev[1]), vf_set1(ev[2]) };
            vf k = vf_div(k_dot(e, ngr), dnr);
            kv3_t a = k_scale(k_sub(e, k_scale(d, k)), tq);
            vf beta = vf_div(k_dot(a, q1), l2), gamma = vf_div(k_dot(a, q2), l2);
            vf gu = vf_add(vf_mul(beta, du1), vf_mul(gamma, du2));
            vf gv = vf_add(vf_mul(beta, dv1), vf_mul(gamma, dv2));
            ok = vm_and(ok, vm_and(k_finite(gu), k_finite(gv)));
            vf_store(fg[axis], gu), vf_store(fg[2 + axis], gv);
        }
        foot = vm_bits(ok) & mask;
    }
    float lod_base[KL] HZ_ALIGNED(32), stu[KL] HZ_ALIGNED(32), stv[KL] HZ_ALIGNED(32);
    vf_store(lod_base, lod), vf_store(stu, tu), vf_store(stv, tv);
    float rgba[4][KL] HZ_ALIGNED(32);
    if (base) {
        k_sample(c, base_tex, base, tu, tv, lod_base, (const float (*)[KL])fg, foot & base, rgba);
        for (uint32_t i = 0; i < KL; i++)
            if (base >> i & 1u) {
                o->albedo[0][i] *= rgba[0][i], o->albedo[1][i] *= rgba[1][i], o->albedo[2][i] *= rgba[2][i];
                o->textured[i] = 1;
                if (lt[i].base_alpha)
                    o->alpha[i] *= rgba[3][i];
            }
    }
    if (alpha) {
        k_sample(c, alpha_tex, alpha, tu, tv, lod_base, (const float (*)[KL])fg, foot & alpha, rgba);
        for (uint32_t i = 0; i < KL; i++)
            if (alpha >> i & 1u) {
                o->alpha[i] *= rgba[3][i];
                o->textured[i] = 1;
            }
    }
    for (uint32_t i = 0; i < KL; i++)
        if (any >> i & 1u)
            o->tu[i] = stu[i], o->tv[i] = stv[i];
}

#endif
