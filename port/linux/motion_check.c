/* The motion BVH against brute force at each ray's time (see motion_check.h). */
#include "motion_check.h"

#include <stdio.h>
#include <string.h>

#include "clock.h"
#include "hz/hash.h"
#include "hz/meshgen.h"

static float rnd01(uint32_t *st)
{
    *st = hz_hash32(*st + 0x9e3779b9u);
    return (float)(*st >> 8) * (1.0f / 16777216.0f);
}

void hz_mcheck_bounds(const hz_accel_geom_t *g, float lo[3], float hi[3])
{
    for (int c = 0; c < 3; c++)
        lo[c] = __builtin_inff(), hi[c] = -__builtin_inff();
    const uint32_t nk = g->time_keys >= 2u ? g->time_keys : 1u;
    for (uint32_t k = 0; k < nk; k++)
        for (uint32_t v = 0; v < g->vertex_count; v++)
            for (int c = 0; c < 3; c++) {
                float x = (g->time_keys >= 2u ? g->pos_keys[k] : g->pos)[4u * (size_t)v + (size_t)c];
                if (x == x && x - x == 0.0f) {
                    lo[c] = x < lo[c] ? x : lo[c];
                    hi[c] = x > hi[c] ? x : hi[c];
                }
            }
}

void hz_mcheck_ray(const hz_accel_geom_t *g, const float lo[3], const float hi[3], uint64_t i, uint32_t seed,
                   hz_rayhit_t *rh)
{
    uint32_t st = hz_hash2((uint32_t)i ^ seed, (uint32_t)(i >> 32) + 17u);
    float time = rnd01(&st);
    const uint32_t nk = g->time_keys >= 2u ? g->time_keys : 2u;
    if ((i & 7u) == 5u)
        time = (float)(uint32_t)(rnd01(&st) * (float)nk) / (float)(nk - 1u);
    float o[3], d[3];
    for (int k = 0; k < 3; k++) {
        float ext = hi[k] - lo[k];
        o[k] = lo[k] - 0.1f * ext + 1.2f * ext * rnd01(&st);
    }
    if ((i & 1u) == 0 && g->tri_count) {
        uint32_t t = (uint32_t)(rnd01(&st) * (float)g->tri_count);
        if (t >= g->tri_count)
            t = g->tri_count - 1u;
        float b1 = rnd01(&st), b2 = rnd01(&st);
        if (b1 + b2 > 1.0f)
            b1 = 1.0f - b1, b2 = 1.0f - b2;
        const hz_vec3_t p = hz_meshgen_tri_point(g, t, time, b1, b2);
        d[0] = p.x - o[0], d[1] = p.y - o[1], d[2] = p.z - o[2];
    } else {
        for (int k = 0; k < 3; k++)
            d[k] = 2.0f * rnd01(&st) - 1.0f;
    }
    if (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f)
        d[2] = 1.0f;
    memset(rh, 0, sizeof *rh);
    rh->ray.org_x = o[0], rh->ray.org_y = o[1], rh->ray.org_z = o[2];
    rh->ray.dir_x = d[0], rh->ray.dir_y = d[1], rh->ray.dir_z = d[2];
    rh->ray.tnear = 0.0f;
    rh->ray.tfar = __builtin_inff();
    rh->ray.time = time;
    rh->ray.mask = 0xFFFFFFFFu;
    rh->ray.id = (uint32_t)i;
    rh->hit.geom_id = HZ_ACCEL_INVALID_ID;
    rh->hit.prim_id = HZ_ACCEL_INVALID_ID;
}

static bool same_hit(const hz_rayhit_t *a, const hz_rayhit_t *b)
{
    return a->ray.tfar == b->ray.tfar && a->hit.prim_id == b->hit.prim_id && a->hit.u == b->hit.u &&
           a->hit.v == b->hit.v && a->hit.ng_x == b->hit.ng_x && a->hit.ng_y == b->hit.ng_y && a->hit.ng_z == b->hit.ng_z;
}

void hz_mcheck_batch(const hz_accel_t *a, const hz_accel_geom_t *g, const hz_rayhit_t *rays, int lanes,
                     hz_accel_stats_t *stats, hz_mcheck_counts_t *c)
{
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    hz_rayhit_t ref[8], got[8];
    hz_rayhit8_t pk;
    int32_t valid[8];
    memset(&pk, 0, sizeof pk);
    lanes = lanes < 0 ? 0 : lanes > 8 ? 8 : lanes;
    for (int l = 0; l < 8; l++) {
        valid[l] = l < lanes ? -1 : 0;
        if (l >= lanes)
            continue;
        ref[l] = rays[l];
        ref[l].hit.geom_id = HZ_ACCEL_INVALID_ID, ref[l].hit.prim_id = HZ_ACCEL_INVALID_ID;
        got[l] = ref[l];
        hz_ray_t occ = ref[l].ray;
        hz_accel_brute_intersect1(g, &ref[l]);
        ctx.stats = stats; /* per-ray figures of the closest-hit queries */
        hz_accel_intersect1(a, &ctx, &got[l]);
        ctx.stats = NULL;
        hz_accel_occluded1(a, &ctx, &occ);
        const bool rh = ref[l].hit.prim_id != HZ_ACCEL_INVALID_ID, gh = got[l].hit.prim_id != HZ_ACCEL_INVALID_ID;
        const bool oh = occ.tfar == -__builtin_inff();
        c->rays++;
        c->hits += rh;
        if (rh && !gh)
            c->misses++;
        else if (rh != gh || (rh && !same_hit(&ref[l], &got[l])))
            c->mismatches++;
        else if (rh != oh)
            rh ? c->misses++ : c->mismatches++;
        /* the same ray in an 8-wide packet */
        const hz_ray_t *q = &rays[l].ray;
        pk.ray.org_x[l] = q->org_x, pk.ray.org_y[l] = q->org_y, pk.ray.org_z[l] = q->org_z;
        pk.ray.dir_x[l] = q->dir_x, pk.ray.dir_y[l] = q->dir_y, pk.ray.dir_z[l] = q->dir_z;
        pk.ray.tnear[l] = q->tnear, pk.ray.tfar[l] = q->tfar, pk.ray.time[l] = q->time;
        pk.ray.mask[l] = q->mask, pk.ray.id[l] = q->id;
        pk.hit.geom_id[l] = HZ_ACCEL_INVALID_ID, pk.hit.prim_id[l] = HZ_ACCEL_INVALID_ID;
    }
    hz_accel_intersect8(valid, a, &ctx, &pk);
    for (int l = 0; l < lanes; l++) {
        hz_rayhit_t p1 = ref[l];
        p1.ray.tfar = pk.ray.tfar[l], p1.hit.prim_id = pk.hit.prim_id[l], p1.hit.u = pk.hit.u[l];
        p1.hit.v = pk.hit.v[l], p1.hit.ng_x = pk.hit.ng_x[l], p1.hit.ng_y = pk.hit.ng_y[l];
        p1.hit.ng_z = pk.hit.ng_z[l];
        if (ref[l].hit.prim_id != HZ_ACCEL_INVALID_ID ? !same_hit(&ref[l], &p1)
                                                      : p1.hit.prim_id != HZ_ACCEL_INVALID_ID)
            c->mismatches++;
    }
}

void hz_mcheck_run(const hz_accel_t *a, const hz_accel_geom_t *g, uint64_t n, uint32_t seed, bool progress,
                   hz_accel_stats_t *stats, hz_mcheck_counts_t *c)
{
    float lo[3], hi[3];
    hz_mcheck_bounds(g, lo, hi);
    int64_t last = hz_clock_ns();
    for (uint64_t i0 = 0; i0 < n; i0 += 8) {
        hz_rayhit_t rays[8];
        const int lanes = n - i0 < 8 ? (int)(n - i0) : 8;
        for (int l = 0; l < lanes; l++)
            hz_mcheck_ray(g, lo, hi, i0 + (uint64_t)l, seed, &rays[l]);
        hz_mcheck_batch(a, g, rays, lanes, stats, c);
        int64_t now = hz_clock_ns();
        if (progress && now - last > 2000000000LL) {
            fprintf(stderr, "motion-check: %llu of %llu rays ...\n", (unsigned long long)(i0 + 8),
                    (unsigned long long)n);
            last = now;
        }
    }
}
