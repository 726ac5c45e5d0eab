/*
 * src/accel/bvh.h — the native BVH's memory layout and the pieces its kernels share (internal to src/accel).
 *
 * Contract
 *  Layout. A tree of wide nodes (HZ_BVH_WIDTH children: 8 on AVX2, 4 on NEON and scalar boards) in depth-first
 *  pre-order (node 0 is the root, every child node has a larger index than its parent, which refit relies on),
 *  plus triangle blocks of HZ_BVH_WIDTH slots holding the triangles' vertices in SoA form (v[vertex][axis][slot])
 *  with the triangle index per slot: the watertight test reads them directly, with no index indirection.
 *  A leaf is a run of 1..HZ_BVH_WIDTH consecutive slots inside one block (leaves are packed next-fit, so blocks
 *  are on average more than half full). Spatial splits may put one triangle in several leaves.
 *  Child words: bit 31 set = leaf (bits 28..30 count - 1, bits 0..27 first slot); bits 31..30 = 00 = inner
 *  node index; 01 = reserved for the motion-blur node type (MSBVH: a node carrying boxes at t0 and t1 that
 *  traversal interpolates at ray.time; HZ_BVH_EMPTY uses this type's all-ones value). Empty child slots have
 *  inverted boxes (lo = +inf, hi = -inf), so every box test rejects them without a branch.
 *  Depth: the builder bounds the binary tree to HZ_BVH_MAX_DEPTH levels, so HZ_BVH_STACK entries always suffice.
 *
 *  Ray/triangle test. hz_bvh_ray_prep and hz_bvh_tri_test define the exact float operations (order included)
 *  of the watertight test; every kernel (scalar, AVX2, NEON) performs the same operations lane by lane, so
 *  their t values are bit-identical, and the tie rule (equal t: lower prim_id) makes the closest hit
 *  independent of traversal order. Box tests only need to be conservative: (plane - org) * (1 / dir) with the
 *  far distance enlarged by HZ_BVH_ROBUST (Ize 2013, 1 + 2 gamma(3)). A zero direction component gives an
 *  infinite reciprocal; a ray lying in a slab's plane then makes 0 * inf = NaN for that plane, and every kernel
 *  folds slab distances so that a NaN drops out (x86 max/min return their second operand on NaN, so NaN-prone
 *  values go first and the running value second; NEON uses maxNum/minNum): the ray counts as inside that slab,
 *  which is the right answer for a closed box. (Replacing zero components by a tiny epsilon instead would put
 *  the in-plane ray's exit at t = 0 and lose hits on box faces.)
 */
#ifndef HZ_ACCEL_BVH_H
#define HZ_ACCEL_BVH_H

#include "hz/accel.h"

#define HZ_BVH_W HZ_BVH_WIDTH
#define HZ_BVH_MAX_DEPTH 80
#define HZ_BVH_STACK (HZ_BVH_MAX_DEPTH * (HZ_BVH_W - 1) + 2)

#define HZ_BVH_LEAF 0x80000000u
#define HZ_BVH_EMPTY 0x7FFFFFFFu
#define HZ_BVH_SLOT_MASK 0x0FFFFFFFu
#define HZ_BVH_PRIM_ANYHIT 0x80000000u /* in block prim words: the triangle has HZ_ACCEL_TRI_ANYHIT */
#define HZ_BVH_PRIM_MASK 0x7FFFFFFFu
#define HZ_BVH_PRIM_PAD 0x7FFFFFFFu    /* prim word of an unused slot */

#define HZ_BVH_ROBUST 1.00000048f      /* 1 + 4 * 2^-23 >= 1 + 2 gamma(3) */
/* Nodes are culled against the best hit so far only when they start beyond tfar * HZ_BVH_CULL: a triangle's t
 * (from the watertight test) and its box's entry distance (from the slab test) round differently, and a
 * triangle whose t lies a few ulps before its box's computed entry must still be found, by every kernel. */
#define HZ_BVH_CULL 1.0009765625f      /* 1 + 2^-10 */

typedef struct HZ_ALIGNED(64) hz_bvh_node {
    float lo_x[HZ_BVH_W], hi_x[HZ_BVH_W];
    float lo_y[HZ_BVH_W], hi_y[HZ_BVH_W];
    float lo_z[HZ_BVH_W], hi_z[HZ_BVH_W];
    uint32_t child[HZ_BVH_W];
    uint32_t pad[HZ_BVH_W]; /* rounds the node to cache lines; room for MSBVH bookkeeping */
} hz_bvh_node_t;

typedef struct HZ_ALIGNED(32) hz_bvh_block {
    float v[3][3][HZ_BVH_W]; /* [vertex][axis][slot] */
    uint32_t prim[HZ_BVH_W]; /* triangle index | HZ_BVH_PRIM_ANYHIT, or HZ_BVH_PRIM_PAD */
} hz_bvh_block_t;

/* Boxes of one node's children at one time key: the first six arrays of hz_bvh_node_t. */
typedef struct HZ_ALIGNED(32) hz_bvh_mbox {
    float lo_x[HZ_BVH_W], hi_x[HZ_BVH_W];
    float lo_y[HZ_BVH_W], hi_y[HZ_BVH_W];
    float lo_z[HZ_BVH_W], hi_z[HZ_BVH_W];
} hz_bvh_mbox_t;

typedef struct hz_bvh {
    hz_bvh_node_t *nodes;
    hz_bvh_block_t *blocks;
    uint32_t node_count, block_count, leaf_count;
    uint32_t depth;
    bool has_anyhit; /* some triangle carries HZ_ACCEL_TRI_ANYHIT */
    /* Motion (msbvh.c; time_keys >= 2). Static trees have time_keys 0 and the kernels never look further. The
     * triangles at key k are in kblocks[k] (same slots as `blocks`, which is one of them); a ray at (seg, f)
     * tests the slot-wise lerp of kblocks[seg] and kblocks[seg + 1]. With key_boxes, node i's child boxes at
     * key k are mbox[i * time_keys + k] and traversal lerps them the same way; without (swept), the nodes'
     * own boxes bound every key and are used as they are. Per-node segments (mref != NULL, see "Motion
     * segments per node" in hz/accel.h): node i's boxes are mbox[o .. o + 2^m] with mref[i] = o << 2 | m, at
     * every 2^(key_level - m)-th key; time_keys = 2^key_level + 1. */
    uint32_t time_keys;
    bool key_boxes;
    hz_accel_blur_t blur;
    hz_bvh_mbox_t *mbox;
    uint32_t *mref;
    uint32_t key_level;
    uint64_t key_sets; /* mbox entries in use */
    hz_bvh_block_t *kblocks[HZ_ACCEL_MAX_TIME_KEYS];
    uint8_t *clipped; /* per block slot, 1: a piece of a triangle spatial splits cut (MSBVH only, else NULL) */
} hz_bvh_t;

/* Per-query traversal counters of every kernel (nodes visited, triangles tested), added to ctx->stats when the
 * query ends; with HZ_FEATURE_STATS 0 they compile to nothing. */
typedef struct hz_bvh_counters {
    uint64_t nodes, tris;
} hz_bvh_counters_t;

#if HZ_FEATURE_STATS
#define HZ_BVH_COUNT(k, field, n) ((k)->field += (n))
#else
#define HZ_BVH_COUNT(k, field, n) ((void)0)
#endif

HZ_INLINE void hz_bvh_counters_flush(hz_accel_ctx_t *ctx, const hz_bvh_counters_t *k)
{
#if HZ_FEATURE_STATS
    if (ctx && ctx->stats) {
        hz_accel_stats_t *st = ctx->stats;
        st->nodes += k->nodes;
        st->tris += k->tris;
        if (k->nodes > st->ray_nodes_max)
            st->ray_nodes_max = (uint32_t)k->nodes;
        if (k->tris > st->ray_tris_max)
            st->ray_tris_max = (uint32_t)k->tris;
    }
#else
    (void)ctx;
    (void)k;
#endif
}

HZ_INLINE bool hz_bvh_is_leaf(uint32_t c) { return (c & HZ_BVH_LEAF) != 0; }
HZ_INLINE uint32_t hz_bvh_leaf_count(uint32_t c) { return ((c >> 28) & 7u) + 1u; }
HZ_INLINE uint32_t hz_bvh_leaf_slot(uint32_t c) { return c & HZ_BVH_SLOT_MASK; }
HZ_INLINE uint32_t hz_bvh_make_leaf(uint32_t slot, uint32_t count)
{
    return HZ_BVH_LEAF | ((count - 1u) << 28) | slot;
}

/* ---- per-ray precomputation ---- */
typedef struct hz_bvh_ray {
    float org[3], dir[3];
    float rdir[3];   /* 1 / dir for box tests, +-inf for zero components */
    int kx, ky, kz;  /* watertight test: kz = dominant axis, kx/ky keep the winding */
    float sx, sy, sz;
    float tnear, tfar;
    uint32_t seg; /* motion: key pair (seg, seg + 1) and weight f of seg + 1 (hz_accel_time_segment) */
    float f;
    float fm[4]; /* per-node segments: the weight at level m (fm[key_level] = f; hz_bvh_ray_levels) */
} hz_bvh_ray_t;

/* The weights of a ray at `time` (seg already set by hz_accel_time_segment for 2^level + 1 keys) at every
 * level: t * 2^m - (seg >> (level - m)), exact in floats (t * 2^m is exact, and the difference of two floats
 * within a factor 2 of each other is). */
HZ_INLINE void hz_bvh_ray_levels(hz_bvh_ray_t *r, float time, uint32_t level)
{
    const float t = time >= 0.0f ? (time <= 1.0f ? time : 1.0f) : 0.0f; /* as hz_accel_time_segment */
    for (uint32_t m = 0; m < level; m++)
        r->fm[m] = t * (float)(1u << m) - (float)(r->seg >> (level - m));
    r->fm[level] = r->f;
}

/* Returns false for a ray the contract rules out (non-finite origin or direction, zero direction,
 * !(tnear <= tfar)): callers treat it as a miss without traversing. */
HZ_INLINE bool hz_bvh_ray_prep(hz_bvh_ray_t *r, float ox, float oy, float oz, float dx, float dy, float dz,
                               float tnear, float tfar)
{
    r->org[0] = ox, r->org[1] = oy, r->org[2] = oz;
    r->dir[0] = dx, r->dir[1] = dy, r->dir[2] = dz;
    r->rdir[0] = 1.0f / dx; /* +-inf for +-0 */
    r->rdir[1] = 1.0f / dy;
    r->rdir[2] = 1.0f / dz;
    int kz = 0;
    if (hz_absf(dy) > hz_absf(r->dir[kz]))
        kz = 1;
    if (hz_absf(dz) > hz_absf(r->dir[kz]))
        kz = 2;
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (r->dir[kz] < 0.0f) {
        int t = kx;
        kx = ky;
        ky = t;
    }
    r->kx = kx, r->ky = ky, r->kz = kz;
    /* shear constants from the reciprocal (no further division; the packet preparation does the same) */
    r->sx = r->dir[kx] * r->rdir[kz];
    r->sy = r->dir[ky] * r->rdir[kz];
    r->sz = r->rdir[kz];
    r->tnear = tnear;
    r->tfar = tfar;
    r->seg = 0;
    r->f = 0.0f;
    return hz_isfinitef(ox) && hz_isfinitef(oy) && hz_isfinitef(oz) && hz_isfinitef(dx) && hz_isfinitef(dy) &&
           hz_isfinitef(dz) && (dx != 0.0f || dy != 0.0f || dz != 0.0f) && tnear <= tfar && !hz_isnanf(tfar);
}

/* The watertight test of one block slot (Woop, Benthin, Wald 2013, without the double-precision fallback:
 * shared edges are evaluated from the same two vertices in both triangles, so their signs agree exactly and a
 * zero counts as inside for both). Returns false when the ray's line misses or the triangle is degenerate;
 * otherwise t (not yet range-checked) and the edge weights U, V, W with det = U + V + W. */
HZ_INLINE bool hz_bvh_tri_test(const hz_bvh_block_t *b, unsigned s, const hz_bvh_ray_t *r, float *t_out,
                               float *u_out, float *v_out, float *w_out, float *det_out)
{
    const float akx = b->v[0][r->kx][s] - r->org[r->kx];
    const float aky = b->v[0][r->ky][s] - r->org[r->ky];
    const float akz = b->v[0][r->kz][s] - r->org[r->kz];
    const float bkx = b->v[1][r->kx][s] - r->org[r->kx];
    const float bky = b->v[1][r->ky][s] - r->org[r->ky];
    const float bkz = b->v[1][r->kz][s] - r->org[r->kz];
    const float ckx = b->v[2][r->kx][s] - r->org[r->kx];
    const float cky = b->v[2][r->ky][s] - r->org[r->ky];
    const float ckz = b->v[2][r->kz][s] - r->org[r->kz];
    const float ax = akx - r->sx * akz, ay = aky - r->sy * akz;
    const float bx = bkx - r->sx * bkz, by = bky - r->sy * bkz;
    const float cx = ckx - r->sx * ckz, cy = cky - r->sy * ckz;
    const float U = cx * by - cy * bx;
    const float V = ax * cy - ay * cx;
    const float W = bx * ay - by * ax;
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f))
        return false;
    const float det = U + V + W;
    if (det == 0.0f)
        return false;
    /* t from the triangle's plane (normal from the unsheared edges, in the permuted axes), not from the edge
     * weights (sum of U az + V bz + W cz): those carry an absolute error of about ulp(|vertex - origin|) each,
     * which the sum cancels down to the hit distance, so a needle of length L and width w got t wrong by
     * about eps L^2 / w (10% for 1000:1, the sign for 10^5:1: rays leaked out of thin closed tubes). The
     * direction in these axes is (sx, sy, 1) / sz. A ray parallel to the plane gives no finite t: no hit. */
    const float e1x = bkx - akx, e1y = bky - aky, e1z = bkz - akz;
    const float e2x = ckx - akx, e2y = cky - aky, e2z = ckz - akz;
    const float nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
    const float num = nx * akx + ny * aky + nz * akz;
    const float den = nx * r->sx + ny * r->sy + nz;
    const float t = num * r->sz / den;
    if (!hz_isfinitef(t))
        return false;
    *t_out = t;
    *u_out = U, *v_out = V, *w_out = W, *det_out = det;
    return true;
}

/* Candidate (t, prim) beats the best so far (best_t, best_prim): closer, or as close with a lower index. */
HZ_INLINE bool hz_bvh_better(float t, uint32_t prim, float best_t, uint32_t best_prim)
{
    return t < best_t || (t == best_t && prim < best_prim);
}

/* The closest hit so far: block slot, triangle, and the watertight test's edge weights of vertices 1 and 2
 * with their sum det (u = v * (1 / det), v = w * (1 / det): every kernel computes exactly this). */
typedef struct hz_bvh_best {
    uint32_t slot, prim; /* HZ_ACCEL_INVALID_ID: none */
    float v, w, det;
} hz_bvh_best_t;

HZ_INLINE void hz_bvh_best_init(hz_bvh_best_t *b)
{
    b->slot = b->prim = HZ_ACCEL_INVALID_ID;
    b->v = b->w = 0.0f;
    b->det = 1.0f;
}

/* Barycentrics and the geometric normal (v1 - v0) x (v2 - v0) of a recorded hit (r: the ray, for its time). */
void hz_bvh_best_finish(const hz_bvh_t *bvh, const hz_bvh_best_t *b, float *ng, float *u, float *v);
void hz_bvh_best_finish_at(const hz_bvh_t *bvh, const hz_bvh_best_t *b, const hz_bvh_ray_t *r, float *ng, float *u,
                           float *v);

/* ---- motion: the node and block a ray at (r->seg, r->f) sees (scalar forms; the SIMD kernels do the same
 * products and sums lane by lane, so every kernel sees bit-identical boxes and triangles) ---- */
HZ_INLINE void hz_bvh_lerp_floats(float *d, const float *a, const float *b, float f, int n)
{
    const float g = 1.0f - f; /* as hz_accel_lerp_key */
    for (int i = 0; i < n; i++)
        d[i] = g * a[i] + f * b[i];
}

/* The two box sets of node i a ray at (seg, f) lerps (the result and the one after it) and its weight there:
 * the ray's key pair, or with per-node segments the node's own segment and level weight. */
HZ_INLINE const hz_bvh_mbox_t *hz_bvh_node_keys(const hz_bvh_t *bvh, uint32_t i, const hz_bvh_ray_t *r, float *f)
{
    if (bvh->mref) {
        const uint32_t w = bvh->mref[i], m = w & 3u;
        *f = r->fm[m];
        return &bvh->mbox[(size_t)(w >> 2) + (r->seg >> (bvh->key_level - m))];
    }
    *f = r->f;
    return &bvh->mbox[(size_t)i * bvh->time_keys + r->seg];
}

HZ_INLINE const hz_bvh_node_t *hz_bvh_node_at(const hz_bvh_t *bvh, uint32_t i, const hz_bvh_ray_t *r,
                                              hz_bvh_node_t *tmp)
{
    if (!bvh->key_boxes)
        return &bvh->nodes[i];
    float f;
    const hz_bvh_mbox_t *a = hz_bvh_node_keys(bvh, i, r, &f);
    hz_bvh_lerp_floats(tmp->lo_x, a[0].lo_x, a[1].lo_x, f, 6 * HZ_BVH_W);
    for (int c = 0; c < HZ_BVH_W; c++)
        tmp->child[c] = bvh->nodes[i].child[c];
    return tmp;
}

HZ_INLINE const hz_bvh_block_t *hz_bvh_block_at(const hz_bvh_t *bvh, uint32_t blk, const hz_bvh_ray_t *r,
                                                hz_bvh_block_t *tmp)
{
    const hz_bvh_block_t *a = &bvh->kblocks[r->seg][blk], *b = &bvh->kblocks[r->seg + 1u][blk];
    hz_bvh_lerp_floats(&tmp->v[0][0][0], &a->v[0][0][0], &b->v[0][0][0], r->f, 9 * HZ_BVH_W);
    for (int c = 0; c < HZ_BVH_W; c++)
        tmp->prim[c] = a->prim[c];
    return tmp;
}

/* Asks the any-hit callback about block slot `slot`, hit at t with edge weights V, W and determinant det: the
 * watertight test's own values (every kernel's are hz_bvh_tri_test's bit for bit), so the callback's barycentrics
 * and side are those the closest hit would report, without testing the triangle again. True = the hit counts. */
bool hz_bvh_anyhit(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, uint32_t slot, float t, float V, float W, float det,
                   uint32_t ray_id, int lane);

/* ---- kernels ---- */
/* Scalar reference (every board): fills *best (hz_bvh_best_init first) and r->tfar with the closest hit. */
void hz_bvh_scalar_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, hz_bvh_best_t *best,
                           uint32_t ray_id, int lane);
bool hz_bvh_scalar_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, uint32_t ray_id, int lane);

#if defined(HZ_SIMD_AVX2) || defined(HZ_SIMD_NEON)
#define HZ_BVH_HAS_SIMD 1
#if defined(HZ_SIMD_AVX2)
typedef hz_rayhit8_t hz_bvh_rayhitw_t;
typedef hz_ray8_t hz_bvh_rayw_t;
#else
typedef hz_rayhit4_t hz_bvh_rayhitw_t;
typedef hz_ray4_t hz_bvh_rayw_t;
#endif
/* The SIMD kernels (trav_kernel.h, built by trav_avx2.c / trav_neon.c); the same results as the scalar ones.
 * One ray against all children of a node at once: */
void hz_bvh_simd_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, hz_bvh_best_t *best,
                         uint32_t ray_id, int lane);
bool hz_bvh_simd_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, uint32_t ray_id, int lane);
/* Packets of HZ_BVH_W rays: `kernel` HZ_ACCEL_KERNEL_SIMD_PACKET traces them as a tile (one packet), anything
 * else lane by lane as single rays. */
/* One packet of a motion tree (key boxes) through the motion packet kernel (trav_kernel.h); false, with nothing
 * written, where its lanes do not form a frustum packet (the caller then traces them one by one). The hits are
 * the single-ray motion kernel's, bit for bit. */
bool hz_bvh_simd_intersect_motion(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx,
                                  hz_bvh_rayhitw_t *rh);
/* The same for occlusion (blocked lanes get tfar = -inf). */
bool hz_bvh_simd_occluded_motion(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_rayw_t *ray);
void hz_bvh_simd_intersectw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx,
                            hz_bvh_rayhitw_t *rh, hz_accel_kernel_t kernel);
void hz_bvh_simd_occludedw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_rayw_t *r,
                           hz_accel_kernel_t kernel);
/* n consecutive packets of HZ_BVH_W rays (valid: n * HZ_BVH_W words): with HZ_ACCEL_KERNEL_SIMD_PACKET traced
 * together as tiles of up to 256 rays (large coherent packets), else lane by lane. Static trees only. */
void hz_bvh_simd_intersect_tile(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx,
                                hz_bvh_rayhitw_t *rh, uint32_t n, hz_accel_kernel_t kernel);
void hz_bvh_simd_occluded_tile(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_rayw_t *r,
                               uint32_t n, hz_accel_kernel_t kernel);
#endif

/* ---- build (bvh_build.c) ---- */
typedef struct hz_bvh_build_out {
    uint32_t ref_count, spatial_splits, budget_stops, tri_skipped, tasks_rebuilt;
    float sah_cost;
    size_t bytes_peak; /* arena bytes in use at the build's peak (scratch + result) */
} hz_bvh_build_out_t;

/* Builds bvh (arrays allocated from `arena`, scratch released) for geometry g. */
hz_status_t hz_bvh_build(hz_bvh_t *bvh, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                         hz_arena_t *arena, hz_bvh_build_out_t *out, hz_error_t *err);
/* Recomputes triangle copies and boxes from g->pos (bvh_build.c). */
void hz_bvh_refit(hz_bvh_t *bvh, const hz_accel_geom_t *g);

/* Copies triangle `prim` of g (positions from `pos`) into block slot s, with its any-hit flag; a triangle with
 * a non-finite coordinate becomes degenerate (all zeros: never hit). Returns false for that case. */
bool hz_bvh_fill_slot(hz_bvh_block_t *bl, uint32_t s, const hz_accel_geom_t *g, const float *pos, uint32_t prim);

/* ---- motion (msbvh.c) ---- */
/* Builds the motion BVH of cfg->blur for g (time_keys >= 2) into bvh, all from `arena`. */
hz_status_t hz_bvh_motion_build(hz_bvh_t *bvh, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                                hz_arena_t *arena, hz_bvh_build_out_t *out, hz_error_t *err);
/* Re-reads g's keys: triangle copies, and boxes per key (the MSBVH's pieces re-clipped against the previous
 * boxes), up the tree. */
void hz_bvh_motion_refit(hz_bvh_t *bvh, const hz_accel_geom_t *g);
/* SAH cost of the wide tree (boxes averaged over the keys), relative to the root; also for static trees. */
float hz_bvh_wide_sah(const hz_bvh_t *bvh);
/* Extra kept bytes a motion build of `refs` references with K keys needs at most beyond the static tree's. */
uint64_t hz_bvh_motion_kept_bound(uint64_t refs, uint32_t keys, hz_accel_blur_t blur, uint32_t vertex_count);
/* Moves every array of bvh by `delta` bytes (after the caller moved the bytes). */
void hz_bvh_relocate(hz_bvh_t *bvh, ptrdiff_t delta);

/* Upper bounds on the wide nodes and blocks a build of `refs` references produces. */
uint64_t hz_bvh_nodes_bound(uint64_t refs);
uint64_t hz_bvh_blocks_bound(uint64_t refs);
uint64_t hz_bvh_scratch_bound(uint32_t tri_count, uint64_t refs);

#endif /* HZ_ACCEL_BVH_H */
