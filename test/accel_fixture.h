/*
 * accel_fixture.h — shared by the accel tests: test memory, ray sets, a brute-force reference and result
 * comparison. Header-only (static functions); include after hz_test.h.
 *
 * The brute-force reference runs the watertight test of src/accel/bvh.h on every triangle, so any kernel must
 * reproduce it exactly (same t bits, same triangle under the equal-t rule): a missed or extra hit means the
 * tree or the traversal lost something.
 */
#ifndef HZ_TEST_ACCEL_FIXTURE_H
#define HZ_TEST_ACCEL_FIXTURE_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../src/accel/bvh.h"
#include "hz/accel.h"
#include "hz/hash.h"
#include "hz/meshgen.h"

typedef struct fx_bounds {
    float lo[3], hi[3];
} fx_bounds_t;

static __attribute__((unused)) fx_bounds_t fx_mesh_bounds(const hz_mesh_t *m)
{
    fx_bounds_t b = { { INFINITY, INFINITY, INFINITY }, { -INFINITY, -INFINITY, -INFINITY } };
    for (uint32_t i = 0; i < m->vertex_count; i++)
        for (int k = 0; k < 3; k++) {
            float p = m->pos[4u * i + (uint32_t)k];
            if (!isfinite(p))
                continue;
            b.lo[k] = fminf(b.lo[k], p);
            b.hi[k] = fmaxf(b.hi[k], p);
        }
    return b;
}

static __attribute__((unused)) float fx_unit(hz_rng_t *r)
{
    return hz_u32_to_unit(hz_rng_u32(r));
}

static __attribute__((unused)) void fx_set_ray(hz_rayhit_t *rh, const float o[3], const float d[3], float tnear, float tfar, uint32_t id)
{
    memset(rh, 0, sizeof *rh);
    rh->ray.org_x = o[0], rh->ray.org_y = o[1], rh->ray.org_z = o[2];
    rh->ray.dir_x = d[0], rh->ray.dir_y = d[1], rh->ray.dir_z = d[2];
    rh->ray.tnear = tnear;
    rh->ray.tfar = tfar;
    rh->ray.mask = 0xFFFFFFFFu;
    rh->ray.id = id;
    rh->hit.geom_id = HZ_ACCEL_INVALID_ID;
    rh->hit.prim_id = HZ_ACCEL_INVALID_ID;
    rh->hit.inst_id[0] = HZ_ACCEL_INVALID_ID;
}

/* Random rays: origins in the bounds grown by half their size, uniform directions; every 8th ray has one
 * direction component exactly 0 and every 32nd two (axis-parallel); every 16th ray gets a finite tfar. */
static __attribute__((unused)) void fx_random_rays(hz_rayhit_t *out, uint32_t n, fx_bounds_t b, uint64_t seed)
{
    hz_rng_t r;
    hz_rng_seed(&r, seed, 3);
    for (uint32_t i = 0; i < n; i++) {
        float o[3], d[3];
        for (int k = 0; k < 3; k++) {
            float ext = b.hi[k] - b.lo[k];
            o[k] = b.lo[k] - 0.5f * ext + 2.0f * ext * fx_unit(&r);
        }
        /* hz_sincosf and sqrt are bit-exact on every ISA, so the rays (and the golden digest) are too */
        float z = 2.0f * fx_unit(&r) - 1.0f, ph = 2.0f * HZ_PI * fx_unit(&r), sp, cp;
        float s = hz_sqrtf(hz_maxf(0.0f, 1.0f - z * z));
        hz_sincosf(ph, &sp, &cp);
        d[0] = s * cp, d[1] = s * sp, d[2] = z;
        if (i % 8 == 3)
            d[hz_rng_below(&r, 3)] = 0.0f;
        if (i % 32 == 5) {
            int k = (int)hz_rng_below(&r, 3);
            d[k] = 0.0f, d[(k + 1) % 3] = 0.0f;
            d[(k + 2) % 3] = fx_unit(&r) < 0.5f ? -1.0f : 1.0f;
        }
        if (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f)
            d[2] = 1.0f;
        float tfar = INFINITY;
        if (i % 16 == 7) {
            float ext = fmaxf(b.hi[0] - b.lo[0], fmaxf(b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]));
            tfar = ext * fx_unit(&r);
        }
        fx_set_ray(&out[i], o, d, 0.0f, tfar, i);
    }
}

/* Pinhole camera rays in w x h pixel order, looking from eye to the bounds' centre. */
static __attribute__((unused)) void fx_camera_rays(hz_rayhit_t *out, uint32_t w, uint32_t h, const float eye[3], fx_bounds_t b)
{
    float c[3], f[3], up[3] = { 0, 1, 0 }, rgt[3], u[3];
    for (int k = 0; k < 3; k++)
        c[k] = 0.5f * (b.lo[k] + b.hi[k]), f[k] = c[k] - eye[k];
    float fl = hz_sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int k = 0; k < 3; k++)
        f[k] /= fl;
    rgt[0] = f[1] * up[2] - f[2] * up[1], rgt[1] = f[2] * up[0] - f[0] * up[2], rgt[2] = f[0] * up[1] - f[1] * up[0];
    float rl = hz_sqrtf(rgt[0] * rgt[0] + rgt[1] * rgt[1] + rgt[2] * rgt[2]);
    for (int k = 0; k < 3; k++)
        rgt[k] /= rl;
    u[0] = rgt[1] * f[2] - rgt[2] * f[1], u[1] = rgt[2] * f[0] - rgt[0] * f[2], u[2] = rgt[0] * f[1] - rgt[1] * f[0];
    const float tanh = 0.6f;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            float sx = ((float)x + 0.5f) / (float)w * 2.0f - 1.0f, sy = 1.0f - ((float)y + 0.5f) / (float)h * 2.0f;
            float d[3];
            for (int k = 0; k < 3; k++)
                d[k] = f[k] + sx * tanh * rgt[k] + sy * tanh * u[k];
            fx_set_ray(&out[y * w + x], eye, d, 0.0f, INFINITY, y * w + x);
        }
}

/* Brute force: the exact test of every triangle; returns the prim (or HZ_ACCEL_INVALID_ID) and its t. */
typedef bool (*fx_accept_fn)(uint32_t prim);

static __attribute__((unused)) uint32_t fx_brute(const hz_accel_geom_t *g, const hz_rayhit_t *rh, float *t_out, fx_accept_fn accept)
{
    hz_bvh_ray_t r;
    *t_out = rh->ray.tfar;
    if (!hz_bvh_ray_prep(&r, rh->ray.org_x, rh->ray.org_y, rh->ray.org_z, rh->ray.dir_x, rh->ray.dir_y,
                         rh->ray.dir_z, rh->ray.tnear, rh->ray.tfar))
        return HZ_ACCEL_INVALID_ID;
    uint32_t best = HZ_ACCEL_INVALID_ID;
    float best_t = rh->ray.tfar;
    hz_bvh_block_t b;
    memset(&b, 0, sizeof b);
    for (uint32_t t = 0; t < g->tri_count; t++) {
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 3; k++)
                b.v[v][k][0] = g->pos[4u * g->tri[3u * t + (uint32_t)v] + (uint32_t)k];
        float tt, U, V, Wd, det;
        if (!hz_bvh_tri_test(&b, 0, &r, &tt, &U, &V, &Wd, &det))
            continue;
        if (!(tt >= r.tnear) || !hz_bvh_better(tt, t, best_t, best))
            continue;
        if (accept && g->tri_flags && (g->tri_flags[t] & HZ_ACCEL_TRI_ANYHIT) && !accept(t))
            continue;
        best = t;
        best_t = tt;
    }
    *t_out = best_t;
    return best;
}

/* Runs the rays through intersect1 with the given kernel into out (a copy of in). */
static __attribute__((unused)) void fx_trace1(const hz_accel_t *a, hz_accel_kernel_t k, const hz_rayhit_t *in, hz_rayhit_t *out, uint32_t n,
                      hz_accel_ctx_t *base)
{
    hz_accel_ctx_t ctx;
    if (base)
        ctx = *base;
    else
        hz_accel_ctx_init(&ctx);
    ctx.kernel = k;
    for (uint32_t i = 0; i < n; i++) {
        out[i] = in[i];
        hz_accel_intersect1(a, &ctx, &out[i]);
    }
}

/* Same rays as packets of width pw (4 or 8), lane i of packet p = ray p * pw + i; lanes whose ray index has
 * (index % 7 == 6) are switched off when `holes` (they must stay untouched). */
static __attribute__((unused)) void fx_trace_packets(const hz_accel_t *a, hz_accel_kernel_t k, uint32_t flags, int pw, bool holes,
                             const hz_rayhit_t *in, hz_rayhit_t *out, uint32_t n, hz_accel_ctx_t *base)
{
    hz_accel_ctx_t ctx;
    if (base)
        ctx = *base;
    else
        hz_accel_ctx_init(&ctx);
    ctx.kernel = k;
    ctx.flags = flags;
    for (uint32_t p0 = 0; p0 < n; p0 += (uint32_t)pw) {
        hz_rayhit8_t P8 HZ_ALIGNED(32);
        hz_rayhit4_t P4 HZ_ALIGNED(16);
        int32_t valid[8];
        memset(&P8, 0x5C, sizeof P8);
        memset(&P4, 0x5C, sizeof P4);
        for (int i = 0; i < pw; i++) {
            uint32_t j = p0 + (uint32_t)i;
            valid[i] = (j < n && !(holes && j % 7 == 6)) ? -1 : 0;
            if (j >= n)
                continue;
            const hz_rayhit_t *r = &in[j];
#define FX_PUT(P, i)                                                                                               \
    do {                                                                                                           \
        (P).ray.org_x[i] = r->ray.org_x, (P).ray.org_y[i] = r->ray.org_y, (P).ray.org_z[i] = r->ray.org_z;         \
        (P).ray.tnear[i] = r->ray.tnear, (P).ray.dir_x[i] = r->ray.dir_x, (P).ray.dir_y[i] = r->ray.dir_y;         \
        (P).ray.dir_z[i] = r->ray.dir_z, (P).ray.time[i] = r->ray.time, (P).ray.tfar[i] = r->ray.tfar;             \
        (P).ray.mask[i] = r->ray.mask, (P).ray.id[i] = r->ray.id, (P).ray.flags[i] = r->ray.flags;                 \
        (P).hit.ng_x[i] = r->hit.ng_x, (P).hit.ng_y[i] = r->hit.ng_y, (P).hit.ng_z[i] = r->hit.ng_z;               \
        (P).hit.u[i] = r->hit.u, (P).hit.v[i] = r->hit.v, (P).hit.prim_id[i] = r->hit.prim_id;                     \
        (P).hit.geom_id[i] = r->hit.geom_id, (P).hit.inst_id[0][i] = r->hit.inst_id[0];                            \
    } while (0)
            if (pw == 8)
                FX_PUT(P8, i);
            else
                FX_PUT(P4, i);
        }
        if (pw == 8)
            hz_accel_intersect8(valid, a, &ctx, &P8);
        else
            hz_accel_intersect4(valid, a, &ctx, &P4);
        for (int i = 0; i < pw && p0 + (uint32_t)i < n; i++) {
            hz_rayhit_t *o = &out[p0 + (uint32_t)i];
            *o = in[p0 + (uint32_t)i];
#define FX_GET(P, i)                                                                                               \
    do {                                                                                                           \
        o->ray.org_x = (P).ray.org_x[i], o->ray.org_y = (P).ray.org_y[i], o->ray.org_z = (P).ray.org_z[i];         \
        o->ray.tnear = (P).ray.tnear[i], o->ray.dir_x = (P).ray.dir_x[i], o->ray.dir_y = (P).ray.dir_y[i];         \
        o->ray.dir_z = (P).ray.dir_z[i], o->ray.time = (P).ray.time[i], o->ray.tfar = (P).ray.tfar[i];             \
        o->ray.mask = (P).ray.mask[i], o->ray.id = (P).ray.id[i], o->ray.flags = (P).ray.flags[i];                 \
        o->hit.ng_x = (P).hit.ng_x[i], o->hit.ng_y = (P).hit.ng_y[i], o->hit.ng_z = (P).hit.ng_z[i];               \
        o->hit.u = (P).hit.u[i], o->hit.v = (P).hit.v[i], o->hit.prim_id = (P).hit.prim_id[i];                     \
        o->hit.geom_id = (P).hit.geom_id[i], o->hit.inst_id[0] = (P).hit.inst_id[0][i];                            \
    } while (0)
            if (pw == 8)
                FX_GET(P8, i);
            else
                FX_GET(P4, i);
        }
    }
}

/* Occlusion of the same rays through occluded1 / occluded4 / occluded8; out[i] = 1 when occluded. */
static __attribute__((unused)) void fx_occlusion(const hz_accel_t *a, hz_accel_kernel_t k, uint32_t flags, int pw, const hz_rayhit_t *in,
                         uint8_t *out, uint32_t n, hz_accel_ctx_t *base)
{
    hz_accel_ctx_t ctx;
    if (base)
        ctx = *base;
    else
        hz_accel_ctx_init(&ctx);
    ctx.kernel = k;
    ctx.flags = flags;
    for (uint32_t p0 = 0; p0 < n; p0 += (uint32_t)(pw ? pw : 1)) {
        if (pw == 0) {
            hz_ray_t r = in[p0].ray;
            hz_accel_occluded1(a, &ctx, &r);
            out[p0] = r.tfar == -INFINITY;
            continue;
        }
        hz_ray8_t R8 HZ_ALIGNED(32);
        hz_ray4_t R4 HZ_ALIGNED(16);
        int32_t valid[8];
        for (int i = 0; i < pw; i++) {
            uint32_t j = p0 + (uint32_t)i;
            valid[i] = j < n ? -1 : 0;
            const hz_ray_t *r = &in[j < n ? j : p0].ray;
#define FX_PUTR(R, i)                                                                                              \
    do {                                                                                                           \
        (R).org_x[i] = r->org_x, (R).org_y[i] = r->org_y, (R).org_z[i] = r->org_z, (R).tnear[i] = r->tnear;        \
        (R).dir_x[i] = r->dir_x, (R).dir_y[i] = r->dir_y, (R).dir_z[i] = r->dir_z, (R).time[i] = r->time;          \
        (R).tfar[i] = r->tfar, (R).mask[i] = r->mask, (R).id[i] = r->id, (R).flags[i] = r->flags;                  \
    } while (0)
            if (pw == 8)
                FX_PUTR(R8, i);
            else
                FX_PUTR(R4, i);
        }
        if (pw == 8)
            hz_accel_occluded8(valid, a, &ctx, &R8);
        else
            hz_accel_occluded4(valid, a, &ctx, &R4);
        for (int i = 0; i < pw && p0 + (uint32_t)i < n; i++)
            out[p0 + (uint32_t)i] = (pw == 8 ? R8.tfar[i] : R4.tfar[i]) == -INFINITY;
    }
}

/* The same rays as tiles: calls of np packets of width pw (4 or 8) through hz_accel_intersect8n / 4n; lane i of
 * packet p of call c = ray (c * np + p) * pw + i; holes as in fx_trace_packets. With `occ` (non-NULL) occlusion
 * through occluded8n / 4n instead: occ[i] = 1 when ray i is occluded. */
#define FX_TILE_MAX 64
static __attribute__((unused)) void fx_trace_tiles(const hz_accel_t *a, hz_accel_kernel_t k, uint32_t flags, int pw, int np,
                                                  bool holes, const hz_rayhit_t *in, hz_rayhit_t *out, uint8_t *occ,
                                                  uint32_t n, hz_accel_ctx_t *base)
{
    static hz_rayhit8_t P8[FX_TILE_MAX] HZ_ALIGNED(32);
    static hz_rayhit4_t P4[FX_TILE_MAX] HZ_ALIGNED(16);
    static hz_ray8_t R8[FX_TILE_MAX] HZ_ALIGNED(32);
    static hz_ray4_t R4[FX_TILE_MAX] HZ_ALIGNED(16);
    static int32_t valid[8 * FX_TILE_MAX];
    hz_accel_ctx_t ctx;
    if (base)
        ctx = *base;
    else
        hz_accel_ctx_init(&ctx);
    ctx.kernel = k;
    ctx.flags = flags;
    const uint32_t per = (uint32_t)(pw * np);
    for (uint32_t c0 = 0; c0 < n; c0 += per) {
        memset(P8, 0x5C, sizeof P8);
        memset(P4, 0x5C, sizeof P4);
        for (uint32_t q = 0; q < per; q++) {
            const uint32_t j = c0 + q, p = q / (uint32_t)pw;
            const int i = (int)(q % (uint32_t)pw);
            valid[q] = (j < n && !(holes && j % 7 == 6)) ? -1 : 0;
            const hz_rayhit_t *r = &in[j < n ? j : c0];
            if (pw == 8) {
                FX_PUT(P8[p], i);
                R8[p] = P8[p].ray;
            } else {
                FX_PUT(P4[p], i);
                R4[p] = P4[p].ray;
            }
        }
        const uint32_t cnt = (n - c0 < per ? n - c0 : per);
        const uint32_t npk = (cnt + (uint32_t)pw - 1u) / (uint32_t)pw;
        if (occ) {
            if (pw == 8)
                hz_accel_occluded8n(valid, a, &ctx, R8, npk);
            else
                hz_accel_occluded4n(valid, a, &ctx, R4, npk);
            for (uint32_t q = 0; q < cnt; q++)
                occ[c0 + q] = (pw == 8 ? R8[q / 8].tfar[q % 8] : R4[q / 4].tfar[q % 4]) == -INFINITY;
            continue;
        }
        if (pw == 8)
            hz_accel_intersect8n(valid, a, &ctx, P8, npk);
        else
            hz_accel_intersect4n(valid, a, &ctx, P4, npk);
        for (uint32_t q = 0; q < cnt; q++) {
            hz_rayhit_t *o = &out[c0 + q];
            const int i = (int)(q % (uint32_t)pw);
            *o = in[c0 + q];
            if (pw == 8)
                FX_GET(P8[q / 8], i);
            else
                FX_GET(P4[q / 4], i);
        }
    }
}

/* Whole-record equality of two hit results (ray and hit bytes). */
static __attribute__((unused)) bool fx_same(const hz_rayhit_t *a, const hz_rayhit_t *b)
{
    return memcmp(a, b, sizeof *a) == 0;
}

#endif
