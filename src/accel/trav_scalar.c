/*
 * The scalar reference traversal: one ray, one child and one triangle at a time. It defines the results the
 * SIMD kernels must reproduce bit for bit (see bvh.h), and serves boards without SIMD.
 */
#include "bvh.h"

typedef struct entry {
    uint32_t c;
    float d;
} entry_t;

/* Children of node n the ray's [tnear, tfar] overlaps, nearest first, into out (entry distances). */
static int node_hits(const hz_bvh_node_t *n, const hz_bvh_ray_t *r, entry_t *out)
{
    const float *lo[3] = { n->lo_x, n->lo_y, n->lo_z }, *hi[3] = { n->hi_x, n->hi_y, n->hi_z };
    int m = 0;
    for (int i = 0; i < HZ_BVH_W; i++) {
        float tmin = r->tnear, tmax = __builtin_inff();
        for (int k = 0; k < 3; k++) {
            float a = (lo[k][i] - r->org[k]) * r->rdir[k];
            float b = (hi[k][i] - r->org[k]) * r->rdir[k];
            float tn = r->rdir[k] < 0.0f ? b : a, tf = r->rdir[k] < 0.0f ? a : b;
            tmin = hz_maxf(tn, tmin); /* a NaN slab distance (ray in the plane) drops out */
            tmax = hz_minf(tf, tmax);
        }
        tmax = hz_minf(tmax * HZ_BVH_ROBUST, r->tfar * HZ_BVH_CULL);
        if (tmin <= tmax) {
            int j = m++;
            while (j > 0 && out[j - 1].d > tmin) { /* keep sorted ascending */
                out[j] = out[j - 1];
                j--;
            }
            out[j].c = n->child[i];
            out[j].d = tmin;
        }
    }
    return m;
}

/* The traversals below are written once for both kinds of tree: `motion` is a constant at each call, so the
 * static instance is the plain loop, and the motion one reads every node and block at the ray's time (the lerp
 * of its key pair, bvh.h). */
HZ_INLINE void closest_core(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, hz_bvh_best_t *best,
                            uint32_t ray_id, int lane, const bool motion)
{
    hz_bvh_node_t ntmp;
    hz_bvh_block_t btmp;
    entry_t stack[HZ_BVH_STACK];
    hz_bvh_counters_t k = { 0, 0 };
    int sp = 0;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    stack[sp].c = 0;
    stack[sp++].d = r->tnear;
    while (sp > 0) {
        entry_t e = stack[--sp];
        if (e.d > r->tfar * HZ_BVH_CULL)
            continue;
        if (!hz_bvh_is_leaf(e.c)) {
            entry_t hits[HZ_BVH_W];
            k.nodes++;
            int m = node_hits(motion ? hz_bvh_node_at(bvh, e.c, r, &ntmp) : &bvh->nodes[e.c], r, hits);
            for (int i = m; i-- > 0;) /* farthest pushed first */
                stack[sp++] = hits[i];
            continue;
        }
        uint32_t slot = hz_bvh_leaf_slot(e.c), n = hz_bvh_leaf_count(e.c);
        const hz_bvh_block_t *b =
            motion ? hz_bvh_block_at(bvh, slot / HZ_BVH_W, r, &btmp) : &bvh->blocks[slot / HZ_BVH_W];
        for (uint32_t s = slot % HZ_BVH_W; s < slot % HZ_BVH_W + n; s++) {
            float t, U, V, W, det;
            k.tris++;
            if (!hz_bvh_tri_test(b, s, r, &t, &U, &V, &W, &det))
                continue;
            uint32_t pw = b->prim[s], prim = pw & HZ_BVH_PRIM_MASK;
            if (!(t >= r->tnear) || !hz_bvh_better(t, prim, r->tfar, best->prim))
                continue;
            uint32_t hs = (slot / HZ_BVH_W) * HZ_BVH_W + s;
            if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT) && !hz_bvh_anyhit(bvh, ctx, hs, t, V, W, det, ray_id, lane))
                continue;
            r->tfar = t;
            best->prim = prim;
            best->slot = hs;
            best->v = V, best->w = W, best->det = det;
        }
    }
    hz_bvh_counters_flush(ctx, &k);
}

void hz_bvh_scalar_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, hz_bvh_best_t *best,
                           uint32_t ray_id, int lane)
{
    if (bvh->time_keys)
        closest_core(bvh, ctx, r, best, ray_id, lane, true);
    else
        closest_core(bvh, ctx, r, best, ray_id, lane, false);
}

HZ_INLINE bool any_core(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, uint32_t ray_id, int lane,
                        const bool motion)
{
    hz_bvh_node_t ntmp;
    hz_bvh_block_t btmp;
    entry_t stack[HZ_BVH_STACK];
    hz_bvh_counters_t k = { 0, 0 };
    int sp = 0;
    bool hit = false;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    stack[sp].c = 0;
    stack[sp++].d = r->tnear;
    while (sp > 0 && !hit) {
        entry_t e = stack[--sp];
        if (!hz_bvh_is_leaf(e.c)) {
            entry_t hits[HZ_BVH_W];
            k.nodes++;
            int m = node_hits(motion ? hz_bvh_node_at(bvh, e.c, r, &ntmp) : &bvh->nodes[e.c], r, hits);
            for (int i = m; i-- > 0;)
                stack[sp++] = hits[i];
            continue;
        }
        uint32_t slot = hz_bvh_leaf_slot(e.c), n = hz_bvh_leaf_count(e.c);
        const hz_bvh_block_t *b =
            motion ? hz_bvh_block_at(bvh, slot / HZ_BVH_W, r, &btmp) : &bvh->blocks[slot / HZ_BVH_W];
        for (uint32_t s = slot % HZ_BVH_W; s < slot % HZ_BVH_W + n && !hit; s++) {
            float t, U, V, W, det;
            k.tris++;
            if (!hz_bvh_tri_test(b, s, r, &t, &U, &V, &W, &det))
                continue;
            if (!(t >= r->tnear) || !(t <= r->tfar))
                continue;
            uint32_t hs = (slot / HZ_BVH_W) * HZ_BVH_W + s;
            if (anyhit && (b->prim[s] & HZ_BVH_PRIM_ANYHIT) &&
                !hz_bvh_anyhit(bvh, ctx, hs, t, V, W, det, ray_id, lane))
                continue;
            hit = true;
        }
    }
    hz_bvh_counters_flush(ctx, &k);
    return hit;
}

bool hz_bvh_scalar_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, uint32_t ray_id, int lane)
{
    return bvh->time_keys ? any_core(bvh, ctx, r, ray_id, lane, true) : any_core(bvh, ctx, r, ray_id, lane, false);
}
