/*
 * AVX2 kernels over 8-wide nodes and 8-slot triangle blocks:
 *  - single ray: one ray against the 8 child boxes of a node at once, nearest child first; one ray against the
 *    8 triangles of a block at once;
 *  - frustum packet (coherent rays): 8 rays whose direction signs and dominant axes agree are tested against a
 *    node's 8 boxes through the packet's interval bounds (one 8-wide test per node for the whole packet, always
 *    conservative), then leaf triangles against all 8 rays; other packets run as single rays;
 *  - masked packet (incoherent rays): per-lane box tests of each child with lane masks on the stack; subtrees
 *    that only a few lanes reach continue as single rays (active-mask compaction).
 * All use exactly the scalar reference's ray/triangle operations (bvh.h), so results are bit-identical.
 */
#include <immintrin.h>

#include "bvh.h"

#define W 8
#define MASKED_SWITCH 2 /* masked packet: subtrees reached by this many lanes or fewer go on as single rays */

typedef struct entry {
    uint32_t c;
    float d;
} entry_t;

typedef struct mentry {
    uint32_t c;
    uint32_t m; /* lanes */
    float d;
} mentry_t;

HZ_INLINE __m256 ld(const hz_bvh_node_t *n, size_t off)
{
    return _mm256_load_ps((const float *)(const void *)((const char *)n + off));
}

#if W == 8
/* Lane mask vector (all ones where bit i of m is set). */
HZ_INLINE __m256 lanes_of(unsigned m)
{
    const __m256i bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32((int)m), bits), bits));
}
#endif

/* ---------------------------------------------------------------------------------------------------------
 * single ray */
typedef struct sray {
    __m256 ox, oy, oz, rdx, rdy, rdz;
    size_t nx, ny, nz, fx, fy, fz; /* byte offsets of the near and far planes in a node */
    /* watertight test */
    __m256 okx, oky, okz, sx, sy, sz, tnear, inf;
    int kx, ky, kz;
} sray_t;

static void sray_init(sray_t *s, const hz_bvh_ray_t *r)
{
    s->ox = _mm256_set1_ps(r->org[0]);
    s->oy = _mm256_set1_ps(r->org[1]);
    s->oz = _mm256_set1_ps(r->org[2]);
    s->rdx = _mm256_set1_ps(r->rdir[0]);
    s->rdy = _mm256_set1_ps(r->rdir[1]);
    s->rdz = _mm256_set1_ps(r->rdir[2]);
    const size_t a = offsetof(hz_bvh_node_t, hi_x) - offsetof(hz_bvh_node_t, lo_x);
    s->nx = offsetof(hz_bvh_node_t, lo_x) + (r->rdir[0] < 0.0f ? a : 0);
    s->ny = offsetof(hz_bvh_node_t, lo_y) + (r->rdir[1] < 0.0f ? a : 0);
    s->nz = offsetof(hz_bvh_node_t, lo_z) + (r->rdir[2] < 0.0f ? a : 0);
    s->fx = offsetof(hz_bvh_node_t, lo_x) + (r->rdir[0] < 0.0f ? 0 : a);
    s->fy = offsetof(hz_bvh_node_t, lo_y) + (r->rdir[1] < 0.0f ? 0 : a);
    s->fz = offsetof(hz_bvh_node_t, lo_z) + (r->rdir[2] < 0.0f ? 0 : a);
    s->kx = r->kx, s->ky = r->ky, s->kz = r->kz;
    s->okx = _mm256_set1_ps(r->org[r->kx]);
    s->oky = _mm256_set1_ps(r->org[r->ky]);
    s->okz = _mm256_set1_ps(r->org[r->kz]);
    s->sx = _mm256_set1_ps(r->sx);
    s->sy = _mm256_set1_ps(r->sy);
    s->sz = _mm256_set1_ps(r->sz);
    s->tnear = _mm256_set1_ps(r->tnear);
    s->inf = _mm256_set1_ps(__builtin_inff());
}

HZ_INLINE unsigned node_hit(const hz_bvh_node_t *n, const sray_t *s, __m256 tfar, __m256 *tmin_out)
{
    const __m256 tnx = _mm256_mul_ps(_mm256_sub_ps(ld(n, s->nx), s->ox), s->rdx);
    const __m256 tny = _mm256_mul_ps(_mm256_sub_ps(ld(n, s->ny), s->oy), s->rdy);
    const __m256 tnz = _mm256_mul_ps(_mm256_sub_ps(ld(n, s->nz), s->oz), s->rdz);
    const __m256 tfx = _mm256_mul_ps(_mm256_sub_ps(ld(n, s->fx), s->ox), s->rdx);
    const __m256 tfy = _mm256_mul_ps(_mm256_sub_ps(ld(n, s->fy), s->oy), s->rdy);
    const __m256 tfz = _mm256_mul_ps(_mm256_sub_ps(ld(n, s->fz), s->oz), s->rdz);
    /* NaN-prone slab distances first: max/min return the second operand on NaN (see bvh.h) */
    const __m256 tmin = _mm256_max_ps(tnz, _mm256_max_ps(tny, _mm256_max_ps(tnx, s->tnear)));
    const __m256 tmax = _mm256_min_ps(
        _mm256_mul_ps(_mm256_min_ps(tfz, _mm256_min_ps(tfy, _mm256_min_ps(tfx, s->inf))),
                      _mm256_set1_ps(HZ_BVH_ROBUST)),
        tfar);
    *tmin_out = tmin;
    return (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(tmin, tmax, _CMP_LE_OQ));
}

/* The watertight test with hz_bvh_tri_test's operations, lane by lane, on triangles whose vertices a, b, c are
 * already relative to the ray origin in the ray's permuted axes (kx, ky, kz): lanes of lm that pass with
 * t >= tnear and t <= tfar; t and the edge weights V, W, det in the out vectors (written only when lanes pass).
 * The single-ray form (one ray, eight triangles) and the frustum packet's (eight rays, one triangle) differ only
 * in how they load those vectors, so both call this: one definition keeps their results bit-identical. */
HZ_INLINE unsigned woop8(__m256 akx, __m256 aky, __m256 akz, __m256 bkx, __m256 bky, __m256 bkz, __m256 ckx,
                         __m256 cky, __m256 ckz, __m256 sx, __m256 sy, __m256 sz, __m256 tnear, __m256 tfar,
                         unsigned lm, __m256 *t_out, __m256 *v_out, __m256 *w_out, __m256 *det_out)
{
    const __m256 ax = _mm256_sub_ps(akx, _mm256_mul_ps(sx, akz));
    const __m256 ay = _mm256_sub_ps(aky, _mm256_mul_ps(sy, akz));
    const __m256 bx = _mm256_sub_ps(bkx, _mm256_mul_ps(sx, bkz));
    const __m256 by = _mm256_sub_ps(bky, _mm256_mul_ps(sy, bkz));
    const __m256 cx = _mm256_sub_ps(ckx, _mm256_mul_ps(sx, ckz));
    const __m256 cy = _mm256_sub_ps(cky, _mm256_mul_ps(sy, ckz));
    const __m256 U = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
    const __m256 V = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
    const __m256 Wv = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));
    const __m256 z = _mm256_setzero_ps();
    const __m256 neg = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(U, z, _CMP_LT_OQ), _mm256_cmp_ps(V, z, _CMP_LT_OQ)),
                                    _mm256_cmp_ps(Wv, z, _CMP_LT_OQ));
    const __m256 pos = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(U, z, _CMP_GT_OQ), _mm256_cmp_ps(V, z, _CMP_GT_OQ)),
                                    _mm256_cmp_ps(Wv, z, _CMP_GT_OQ));
    const __m256 det = _mm256_add_ps(_mm256_add_ps(U, V), Wv);
    const __m256 ok = _mm256_andnot_ps(_mm256_and_ps(neg, pos), _mm256_cmp_ps(det, z, _CMP_NEQ_UQ));
    unsigned m = (unsigned)_mm256_movemask_ps(ok) & lm;
    if (!m)
        return 0;
    /* t from the plane, as hz_bvh_tri_test (see there), operation for operation */
    const __m256 e1x = _mm256_sub_ps(bkx, akx), e1y = _mm256_sub_ps(bky, aky), e1z = _mm256_sub_ps(bkz, akz);
    const __m256 e2x = _mm256_sub_ps(ckx, akx), e2y = _mm256_sub_ps(cky, aky), e2z = _mm256_sub_ps(ckz, akz);
    const __m256 nx = _mm256_sub_ps(_mm256_mul_ps(e1y, e2z), _mm256_mul_ps(e1z, e2y));
    const __m256 ny = _mm256_sub_ps(_mm256_mul_ps(e1z, e2x), _mm256_mul_ps(e1x, e2z));
    const __m256 nz = _mm256_sub_ps(_mm256_mul_ps(e1x, e2y), _mm256_mul_ps(e1y, e2x));
    const __m256 num =
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(nx, akx), _mm256_mul_ps(ny, aky)), _mm256_mul_ps(nz, akz));
    const __m256 den = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(nx, sx), _mm256_mul_ps(ny, sy)), nz);
    const __m256 t = _mm256_div_ps(_mm256_mul_ps(num, sz), den);
    const __m256 fin = _mm256_cmp_ps(_mm256_andnot_ps(_mm256_set1_ps(-0.0f), t), _mm256_set1_ps(__builtin_inff()),
                                     _CMP_LT_OQ);
    const __m256 in = _mm256_and_ps(
        fin, _mm256_and_ps(_mm256_cmp_ps(t, tnear, _CMP_GE_OQ), _mm256_cmp_ps(t, tfar, _CMP_LE_OQ)));
    *t_out = t, *v_out = V, *w_out = Wv, *det_out = det;
    return m & (unsigned)_mm256_movemask_ps(in);
}

/* One ray against the slots `lm` of block b (see woop8). */
HZ_INLINE unsigned leaf_hit(const hz_bvh_block_t *b, unsigned lm, const sray_t *s, float tfar, __m256 *t_out,
                            __m256 *v_out, __m256 *w_out, __m256 *det_out)
{
    return woop8(_mm256_sub_ps(_mm256_load_ps(b->v[0][s->kx]), s->okx),
                 _mm256_sub_ps(_mm256_load_ps(b->v[0][s->ky]), s->oky),
                 _mm256_sub_ps(_mm256_load_ps(b->v[0][s->kz]), s->okz),
                 _mm256_sub_ps(_mm256_load_ps(b->v[1][s->kx]), s->okx),
                 _mm256_sub_ps(_mm256_load_ps(b->v[1][s->ky]), s->oky),
                 _mm256_sub_ps(_mm256_load_ps(b->v[1][s->kz]), s->okz),
                 _mm256_sub_ps(_mm256_load_ps(b->v[2][s->kx]), s->okx),
                 _mm256_sub_ps(_mm256_load_ps(b->v[2][s->ky]), s->oky),
                 _mm256_sub_ps(_mm256_load_ps(b->v[2][s->kz]), s->okz), s->sx, s->sy, s->sz, s->tnear,
                 _mm256_set1_ps(tfar), lm, t_out, v_out, w_out, det_out);
}

HZ_INLINE unsigned slot_mask(uint32_t slot, uint32_t n)
{
    return ((1u << n) - 1u) << (slot % W);
}

/* Children a node test hit (mask m, entry distances tmin): the nearest becomes *cur, the others go on the
 * stack farthest first, so the nearest of them is popped next. Two hits take one compare; more are sorted in
 * registers: keys are the distances' float bits (distances are >= 0, so their bits order like the floats) with
 * the child's slot in the low 3 bits, a bitonic network sorts the 8 keys, and the sorted children and distances
 * are stored with one vector store each (the stack keeps children and distances in separate arrays). Stored
 * distances lose their low 3 bits: they round down, so culling by them stays conservative. */
#if W == 8
/* One compare-exchange stage: lane i meets lane i ^ j; lanes in `hi` take the larger key. */
#define SORT_STAGE(v, p0, p1, p2, p3, p4, p5, p6, p7, h0, h1, h2, h3, h4, h5, h6, h7)                              \
    do {                                                                                                           \
        const __m256i p_ = _mm256_permutevar8x32_epi32(v, _mm256_setr_epi32(p0, p1, p2, p3, p4, p5, p6, p7));       \
        v = _mm256_blendv_epi8(_mm256_min_epu32(v, p_), _mm256_max_epu32(v, p_),                                   \
                               _mm256_setr_epi32(h0, h1, h2, h3, h4, h5, h6, h7));                                 \
    } while (0)

/* Bitonic network, ascending; stages (k, j) = (2,1) (4,2) (4,1) (8,4) (8,2) (8,1): a lane takes the larger key
 * when (lane & j) != 0 differs from (lane & k) != 0. */
HZ_INLINE __m256i sort8(__m256i v)
{
    SORT_STAGE(v, 1, 0, 3, 2, 5, 4, 7, 6, 0, -1, -1, 0, 0, -1, -1, 0);
    SORT_STAGE(v, 2, 3, 0, 1, 6, 7, 4, 5, 0, 0, -1, -1, -1, -1, 0, 0);
    SORT_STAGE(v, 1, 0, 3, 2, 5, 4, 7, 6, 0, -1, 0, -1, -1, 0, -1, 0);
    SORT_STAGE(v, 4, 5, 6, 7, 0, 1, 2, 3, 0, 0, 0, 0, -1, -1, -1, -1);
    SORT_STAGE(v, 2, 3, 0, 1, 6, 7, 4, 5, 0, 0, -1, -1, 0, 0, -1, -1);
    SORT_STAGE(v, 1, 0, 3, 2, 5, 4, 7, 6, 0, -1, 0, -1, 0, -1, 0, -1);
    return v;
}
#endif

HZ_INLINE void order_children(const hz_bvh_node_t *n, unsigned m, __m256 tmin, uint32_t *cur, uint32_t *st_c,
                              float *st_d, int *sp)
{
    const int cnt = __builtin_popcount(m);
    if (cnt == 1) {
        *cur = n->child[__builtin_ctz(m)];
        return;
    }
    float d[W] HZ_ALIGNED(32);
    _mm256_store_ps(d, tmin);
    if (cnt == 2) {
        unsigned i0 = (unsigned)__builtin_ctz(m), i1 = (unsigned)__builtin_ctz(m & (m - 1));
        bool swap = d[i1] < d[i0];
        unsigned near = swap ? i1 : i0, far = swap ? i0 : i1;
        st_c[*sp] = n->child[far];
        st_d[*sp] = d[far];
        (*sp)++;
        *cur = n->child[near];
        return;
    }
#if W == 8
    const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i seven = _mm256_set1_epi32(7);
    const __m256i hitm = _mm256_castps_si256(lanes_of(m));
    __m256i key = _mm256_or_si256(_mm256_andnot_si256(seven, _mm256_castps_si256(_mm256_max_ps(tmin, _mm256_setzero_ps()))),
                                  iota);
    key = _mm256_blendv_epi8(_mm256_set1_epi32(-1), key, hitm);
    const __m256i sorted = sort8(key);
    const __m256i kids = _mm256_permutevar8x32_epi32(_mm256_load_si256((const __m256i *)(const void *)n->child),
                                                     _mm256_and_si256(sorted, seven));
    const __m256i dists = _mm256_andnot_si256(seven, sorted);
    /* lanes 0 .. cnt-2 of the stores: the hits from the farthest (sorted[cnt - 1]) down to sorted[1] */
    const __m256i rev = _mm256_sub_epi32(_mm256_set1_epi32(cnt - 1), iota);
    _mm256_storeu_si256((__m256i *)(void *)(st_c + *sp), _mm256_permutevar8x32_epi32(kids, rev));
    _mm256_storeu_si256((__m256i *)(void *)(st_d + *sp), _mm256_permutevar8x32_epi32(dists, rev));
    *sp += cnt - 1;
    *cur = (uint32_t)_mm256_cvtsi256_si32(kids);
#else
    entry_t h[W];
    int c = 0;
    for (unsigned mm = m; mm; mm &= mm - 1) {
        unsigned i = (unsigned)__builtin_ctz(mm);
        entry_t e = { n->child[i], d[i] };
        int j = c++;
        while (j > 0 && h[j - 1].d < e.d) { /* descending: nearest last */
            h[j] = h[j - 1];
            j--;
        }
        h[j] = e;
    }
    for (int i = 0; i < c - 1; i++) {
        st_c[*sp] = h[i].c;
        st_d[*sp] = h[i].d;
        (*sp)++;
    }
    *cur = h[c - 1].c;
#endif
}

/* Motion: the node and the block as the ray sees them at its time, with hz_bvh_node_at / hz_bvh_block_at's
 * operations (g = 1 - f in scalar, then g * a + f * b lane by lane: bit-identical to the scalar kernel). */
HZ_INLINE const hz_bvh_node_t *node_at(const hz_bvh_t *bvh, uint32_t i, const hz_bvh_ray_t *r, hz_bvh_node_t *tmp)
{
    if (!bvh->key_boxes)
        return &bvh->nodes[i];
    const float *a = bvh->mbox[(size_t)i * bvh->time_keys + r->seg].lo_x, *b = a + 6 * W;
    const __m256 f = _mm256_set1_ps(r->f), g = _mm256_set1_ps(1.0f - r->f);
    for (int j = 0; j < 6; j++)
        _mm256_store_ps(tmp->lo_x + W * j, _mm256_add_ps(_mm256_mul_ps(g, _mm256_load_ps(a + W * j)),
                                                         _mm256_mul_ps(f, _mm256_load_ps(b + W * j))));
    _mm256_store_si256((__m256i *)(void *)tmp->child,
                       _mm256_load_si256((const __m256i *)(const void *)bvh->nodes[i].child));
    return tmp;
}

HZ_INLINE const hz_bvh_block_t *block_at(const hz_bvh_t *bvh, uint32_t blk, const hz_bvh_ray_t *r,
                                         hz_bvh_block_t *tmp)
{
    const float *a = &bvh->kblocks[r->seg][blk].v[0][0][0], *b = &bvh->kblocks[r->seg + 1u][blk].v[0][0][0];
    const __m256 f = _mm256_set1_ps(r->f), g = _mm256_set1_ps(1.0f - r->f);
    for (int j = 0; j < 9; j++)
        _mm256_store_ps(&tmp->v[0][0][0] + W * j, _mm256_add_ps(_mm256_mul_ps(g, _mm256_load_ps(a + W * j)),
                                                                _mm256_mul_ps(f, _mm256_load_ps(b + W * j))));
    _mm256_store_si256((__m256i *)(void *)tmp->prim,
                       _mm256_load_si256((const __m256i *)(const void *)bvh->kblocks[r->seg][blk].prim));
    return tmp;
}

/* Closest hit of one ray from node word `start` on, continuing a search with best (r->tfar, *best); `motion`
 * (a constant at every call) reads nodes and blocks at the ray's time. */
HZ_INLINE void closest_core(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, const sray_t *s,
                            uint32_t start, hz_bvh_best_t *best, uint32_t ray_id, int lane, hz_bvh_counters_t *k,
                            const bool motion)
{
    (void)k; /* counters exist only with HZ_FEATURE_STATS */
    hz_bvh_node_t ntmp;
    hz_bvh_block_t btmp;
    uint32_t st_c[HZ_BVH_STACK + W];
    float st_d[HZ_BVH_STACK + W];
    int sp = 0;
    uint32_t cur = start;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    __m256 tfar = _mm256_set1_ps(r->tfar * HZ_BVH_CULL); /* for culling nodes (see bvh.h) */
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = motion ? node_at(bvh, cur, r, &ntmp) : &bvh->nodes[cur];
            __m256 tmin;
            HZ_BVH_COUNT(k, nodes, 1);
            unsigned m = node_hit(n, s, tfar, &tmin);
            if (m) {
                order_children(n, m, tmin, &cur, st_c, st_d, &sp);
                continue;
            }
        } else {
            const uint32_t slot = hz_bvh_leaf_slot(cur), cnt = hz_bvh_leaf_count(cur);
            const hz_bvh_block_t *b = motion ? block_at(bvh, slot / W, r, &btmp) : &bvh->blocks[slot / W];
            __m256 t, V, Wv, det;
            HZ_BVH_COUNT(k, tris, cnt);
            unsigned m = leaf_hit(b, slot_mask(slot, cnt), s, r->tfar, &t, &V, &Wv, &det);
            if (m) {
                float tv[W] HZ_ALIGNED(32), vv[W] HZ_ALIGNED(32), wv[W] HZ_ALIGNED(32), dv[W] HZ_ALIGNED(32);
                _mm256_store_ps(tv, t);
                _mm256_store_ps(vv, V);
                _mm256_store_ps(wv, Wv);
                _mm256_store_ps(dv, det);
                do {
                    unsigned i = (unsigned)__builtin_ctz(m);
                    m &= m - 1;
                    uint32_t pw = b->prim[i], prim = pw & HZ_BVH_PRIM_MASK;
                    if (!hz_bvh_better(tv[i], prim, r->tfar, best->prim))
                        continue;
                    uint32_t hs = (slot / W) * W + i;
                    if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT) && !hz_bvh_anyhit(bvh, ctx, hs, r, tv[i], ray_id, lane))
                        continue;
                    r->tfar = tv[i];
                    best->prim = prim, best->slot = hs;
                    best->v = vv[i], best->w = wv[i], best->det = dv[i];
                } while (m);
                tfar = _mm256_set1_ps(r->tfar * HZ_BVH_CULL);
            }
        }
        for (;;) {
            if (sp == 0)
                return;
            --sp;
            if (st_d[sp] <= r->tfar * HZ_BVH_CULL) {
                cur = st_c[sp];
                break;
            }
        }
    }
}

static void closest_from(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, const sray_t *s,
                         uint32_t start, hz_bvh_best_t *best, uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    closest_core(bvh, ctx, r, s, start, best, ray_id, lane, k, false);
}

static void closest_motion(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, const sray_t *s,
                           hz_bvh_best_t *best, uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    closest_core(bvh, ctx, r, s, 0, best, ray_id, lane, k, true);
}

void hz_bvh_simd_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, hz_bvh_best_t *best,
                         uint32_t ray_id, int lane)
{
    sray_t s;
    hz_bvh_counters_t k = { 0, 0 };
    sray_init(&s, r);
    if (bvh->time_keys)
        closest_motion(bvh, ctx, r, &s, best, ray_id, lane, &k);
    else
        closest_from(bvh, ctx, r, &s, 0, best, ray_id, lane, &k);
    hz_bvh_counters_flush(ctx, &k);
}

HZ_INLINE bool any_core(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, const sray_t *s,
                        uint32_t start, uint32_t ray_id, int lane, hz_bvh_counters_t *k, const bool motion)
{
    (void)k; /* counters exist only with HZ_FEATURE_STATS */
    hz_bvh_node_t ntmp;
    hz_bvh_block_t btmp;
    entry_t stack[HZ_BVH_STACK];
    int sp = 0;
    uint32_t cur = start;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    const __m256 tfar = _mm256_set1_ps(r->tfar * HZ_BVH_CULL); /* for culling nodes (see bvh.h) */
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = motion ? node_at(bvh, cur, r, &ntmp) : &bvh->nodes[cur];
            __m256 tmin;
            HZ_BVH_COUNT(k, nodes, 1);
            unsigned m = node_hit(n, s, tfar, &tmin);
            if (m) {
                cur = n->child[__builtin_ctz(m)];
                m &= m - 1;
                while (m) {
                    stack[sp++].c = n->child[__builtin_ctz(m)];
                    m &= m - 1;
                }
                continue;
            }
        } else {
            const uint32_t slot = hz_bvh_leaf_slot(cur), cnt = hz_bvh_leaf_count(cur);
            const hz_bvh_block_t *b = motion ? block_at(bvh, slot / W, r, &btmp) : &bvh->blocks[slot / W];
            __m256 t, V, Wv, det;
            HZ_BVH_COUNT(k, tris, cnt);
            unsigned m = leaf_hit(b, slot_mask(slot, cnt), s, r->tfar, &t, &V, &Wv, &det);
            if (m) {
                if (!anyhit)
                    return true;
                float tv[W] HZ_ALIGNED(32);
                _mm256_store_ps(tv, t);
                do {
                    unsigned i = (unsigned)__builtin_ctz(m);
                    m &= m - 1;
                    if (!(b->prim[i] & HZ_BVH_PRIM_ANYHIT) ||
                        hz_bvh_anyhit(bvh, ctx, (slot / W) * W + i, r, tv[i], ray_id, lane))
                        return true;
                } while (m);
            }
        }
        if (sp == 0)
            return false;
        cur = stack[--sp].c;
    }
}

static bool any_from(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, const sray_t *s, uint32_t start,
                     uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    return any_core(bvh, ctx, r, s, start, ray_id, lane, k, false);
}

static bool any_motion(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, const sray_t *s,
                       uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    return any_core(bvh, ctx, r, s, 0, ray_id, lane, k, true);
}

bool hz_bvh_simd_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, uint32_t ray_id, int lane)
{
    sray_t s;
    hz_bvh_counters_t k = { 0, 0 };
    sray_init(&s, r);
    bool hit = bvh->time_keys ? any_motion(bvh, ctx, r, &s, ray_id, lane, &k)
                              : any_from(bvh, ctx, r, &s, 0, ray_id, lane, &k);
    hz_bvh_counters_flush(ctx, &k);
    return hit;
}

/* ---------------------------------------------------------------------------------------------------------
 * packets */
typedef struct packet {
    hz_bvh_ray_t r[W];
    unsigned active;
    uint32_t id[W];
    hz_bvh_best_t best[W];
} packet_t;

static unsigned packet_init(packet_t *p, const int32_t *valid, const hz_ray8_t *ray)
{
    p->active = 0;
    for (int i = 0; i < W; i++) {
        hz_bvh_best_init(&p->best[i]);
        p->id[i] = ray->id[i];
        if (!valid[i])
            continue;
        if (hz_bvh_ray_prep(&p->r[i], ray->org_x[i], ray->org_y[i], ray->org_z[i], ray->dir_x[i], ray->dir_y[i],
                            ray->dir_z[i], ray->tnear[i], ray->tfar[i]))
            p->active |= 1u << i;
    }
    return p->active;
}

HZ_INLINE float hmax8(__m256 v)
{
    __m128 m = _mm_max_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    m = _mm_max_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
}

HZ_INLINE float hmin8(__m256 v)
{
    __m128 m = _mm_min_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    m = _mm_min_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
}

/* Horizontal minima of 8 vectors at once: lane i of the result is the minimum of v[i]'s lanes. */
HZ_INLINE __m256 hmin8x8(const __m256 *v)
{
    const __m256 a01 = _mm256_min_ps(_mm256_unpacklo_ps(v[0], v[1]), _mm256_unpackhi_ps(v[0], v[1]));
    const __m256 a23 = _mm256_min_ps(_mm256_unpacklo_ps(v[2], v[3]), _mm256_unpackhi_ps(v[2], v[3]));
    const __m256 a45 = _mm256_min_ps(_mm256_unpacklo_ps(v[4], v[5]), _mm256_unpackhi_ps(v[4], v[5]));
    const __m256 a67 = _mm256_min_ps(_mm256_unpacklo_ps(v[6], v[7]), _mm256_unpackhi_ps(v[6], v[7]));
    /* per 128-bit half: a01 = [v0 v1 v0 v1] partial minima; combine pairs into [v0 v1 v2 v3] */
    const __m256 b03 = _mm256_min_ps(_mm256_shuffle_ps(a01, a23, 0x44), _mm256_shuffle_ps(a01, a23, 0xEE));
    const __m256 b47 = _mm256_min_ps(_mm256_shuffle_ps(a45, a67, 0x44), _mm256_shuffle_ps(a45, a67, 0xEE));
    return _mm256_min_ps(_mm256_permute2f128_ps(b03, b47, 0x20), _mm256_permute2f128_ps(b03, b47, 0x31));
}

static void lanes_tfar(const packet_t *p, float *tf)
{
    for (int i = 0; i < W; i++)
        tf[i] = (p->active >> i) & 1u ? p->r[i].tfar : -__builtin_inff();
}

/* The frustum form works on the packet as vectors throughout: preparation (the same operations as
 * hz_bvh_ray_prep, lane by lane), traversal, and the hit attributes at the end. It needs every active lane to
 * share the direction signs and the watertight test's axes (kx, ky, kz), and finite reciprocals; other packets
 * go lane by lane. */
typedef struct frustum {
    unsigned active;
    size_t nx, ny, nz, fx, fy, fz;         /* near and far planes (the direction signs) */
    __m256 on[3], of[3], rmin[3], rmax[3]; /* origins for the near and far planes, reciprocal ranges */
    __m256 tnear;                          /* smallest tnear of the packet */
    /* lanes, for leaf boxes and the leaf test */
    __m256 o[3], r[3];
    __m256 okx, oky, okz, sx, sy, sz, ltnear, ltfar;
    int kx, ky, kz;
    unsigned negs; /* bit k: the packet's direction is negative on axis k */
} frustum_t;

/* The packet's interval bounds over the lanes `lanes` (f->o, f->r and f->negs set; tn the lanes' tnear): minima
 * of o, r and tnear, maxima (as minima of negatives) of o and r, eight horizontal minima at once. Lanes that
 * drop out only shrink the bounds: signs and axes stay those of the whole packet. */
static void frustum_bounds(frustum_t *f, __m256 lanes, __m256 tn)
{
    const __m256 inf = _mm256_set1_ps(__builtin_inff()), sign = _mm256_set1_ps(-0.0f);
    __m256 mins[8], mins2[8];
    for (int k = 0; k < 3; k++) {
        mins[k] = _mm256_blendv_ps(inf, f->o[k], lanes);
        mins[3 + k] = _mm256_blendv_ps(inf, f->r[k], lanes);
        mins2[k] = _mm256_xor_ps(_mm256_blendv_ps(_mm256_xor_ps(inf, sign), f->o[k], lanes), sign);
        mins2[3 + k] = _mm256_xor_ps(_mm256_blendv_ps(_mm256_xor_ps(inf, sign), f->r[k], lanes), sign);
    }
    mins[6] = _mm256_blendv_ps(inf, tn, lanes);
    mins[7] = mins2[6] = mins2[7] = inf;
    /* lo: minima of o (lanes 0-2), r (3-5), tnear (6); hi: maxima of o and r; selected and broadcast in
     * registers (stores of scalars read back as vectors stalled store forwarding) */
    const __m256 lo = hmin8x8(mins), hi = _mm256_xor_ps(hmin8x8(mins2), sign);
    const __m256 neg = lanes_of(f->negs);
    const __m256 on = _mm256_blendv_ps(hi, lo, neg), of = _mm256_blendv_ps(lo, hi, neg);
    for (int k = 0; k < 3; k++) {
        /* near plane: lower bound of (plane - o) * r over the packet; far plane: upper bound */
        f->on[k] = _mm256_permutevar8x32_ps(on, _mm256_set1_epi32(k));
        f->of[k] = _mm256_permutevar8x32_ps(of, _mm256_set1_epi32(k));
        f->rmin[k] = _mm256_permutevar8x32_ps(lo, _mm256_set1_epi32(3 + k));
        f->rmax[k] = _mm256_permutevar8x32_ps(hi, _mm256_set1_epi32(3 + k));
    }
    f->tnear = _mm256_permutevar8x32_ps(lo, _mm256_set1_epi32(6));
}

HZ_INLINE __m256 lane_abs(__m256 x)
{
    return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), x);
}

static bool frustum_init(frustum_t *f, const int32_t *valid, const hz_ray8_t *ray)
{
    const __m256 inf = _mm256_set1_ps(__builtin_inff()), zero = _mm256_setzero_ps();
    const __m256 o[3] = { _mm256_load_ps(ray->org_x), _mm256_load_ps(ray->org_y), _mm256_load_ps(ray->org_z) };
    const __m256 d[3] = { _mm256_load_ps(ray->dir_x), _mm256_load_ps(ray->dir_y), _mm256_load_ps(ray->dir_z) };
    const __m256 tn = _mm256_load_ps(ray->tnear), tf = _mm256_load_ps(ray->tfar);
    /* hz_bvh_ray_prep's contract check, lane by lane */
    __m256 ok = _mm256_castsi256_ps(
        _mm256_xor_si256(_mm256_cmpeq_epi32(_mm256_loadu_si256((const __m256i *)(const void *)valid),
                                            _mm256_setzero_si256()),
                         _mm256_set1_epi32(-1)));
    __m256 nonzero = zero;
    for (int k = 0; k < 3; k++) {
        ok = _mm256_and_ps(ok, _mm256_cmp_ps(lane_abs(o[k]), inf, _CMP_LT_OQ));
        ok = _mm256_and_ps(ok, _mm256_cmp_ps(lane_abs(d[k]), inf, _CMP_LT_OQ));
        nonzero = _mm256_or_ps(nonzero, _mm256_cmp_ps(d[k], zero, _CMP_NEQ_OQ));
    }
    ok = _mm256_and_ps(_mm256_and_ps(ok, nonzero), _mm256_cmp_ps(tn, tf, _CMP_LE_OQ));
    f->active = (unsigned)_mm256_movemask_ps(ok);
    const unsigned act = f->active;
    if (__builtin_popcount(act) < 2)
        return false;
    const __m256 r[3] = { _mm256_div_ps(_mm256_set1_ps(1.0f), d[0]), _mm256_div_ps(_mm256_set1_ps(1.0f), d[1]),
                          _mm256_div_ps(_mm256_set1_ps(1.0f), d[2]) };
    /* dominant axis: kz = 0; |dy| > |d[kz]| -> 1; |dz| > |d[kz]| -> 2 (as in hz_bvh_ray_prep) */
    const __m256 ax = lane_abs(d[0]), ay = lane_abs(d[1]), az = lane_abs(d[2]);
    const __m256 y_over = _mm256_cmp_ps(ay, ax, _CMP_GT_OQ);
    const __m256 a_kz = _mm256_blendv_ps(ax, ay, y_over);
    const __m256 z_over = _mm256_cmp_ps(az, a_kz, _CMP_GT_OQ);
    const unsigned my = (unsigned)_mm256_movemask_ps(y_over) & act, mz = (unsigned)_mm256_movemask_ps(z_over) & act;
    int kz;
    if (mz == act)
        kz = 2;
    else if (mz == 0 && my == act)
        kz = 1;
    else if (mz == 0 && my == 0)
        kz = 0;
    else
        return false;
    const unsigned neg_kz = (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(d[kz], zero, _CMP_LT_OQ)) & act;
    if (neg_kz != 0 && neg_kz != act)
        return false;
    int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
    if (neg_kz) {
        int t = kx;
        kx = ky;
        ky = t;
    }
    const __m256 lanes = lanes_of(act);
    /* one sign per axis, finite reciprocals (a zero component makes 0 * inf in interval bounds) */
    unsigned negs = 0;
    for (int k = 0; k < 3; k++) {
        const unsigned neg = (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(r[k], zero, _CMP_LT_OQ)) & act;
        const unsigned fin = (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(lane_abs(r[k]), inf, _CMP_LT_OQ)) & act;
        if ((neg != 0 && neg != act) || fin != act)
            return false;
        negs |= (neg != 0) << k;
    }
    f->negs = negs;
    for (int k = 0; k < 3; k++)
        f->o[k] = o[k], f->r[k] = r[k];
    frustum_bounds(f, lanes, tn);
    /* near and far planes of the boxes by the direction signs (one assignment each: the compiler's vector
     * packing of an array of them cost a store-forwarding stall per packet) */
    const size_t a = offsetof(hz_bvh_node_t, hi_x) - offsetof(hz_bvh_node_t, lo_x);
    f->nx = offsetof(hz_bvh_node_t, lo_x) + ((negs & 1u) ? a : 0);
    f->ny = offsetof(hz_bvh_node_t, lo_y) + ((negs & 2u) ? a : 0);
    f->nz = offsetof(hz_bvh_node_t, lo_z) + ((negs & 4u) ? a : 0);
    f->fx = offsetof(hz_bvh_node_t, lo_x) + ((negs & 1u) ? 0 : a);
    f->fy = offsetof(hz_bvh_node_t, lo_y) + ((negs & 2u) ? 0 : a);
    f->fz = offsetof(hz_bvh_node_t, lo_z) + ((negs & 4u) ? 0 : a);
    f->ltnear = _mm256_blendv_ps(inf, tn, lanes);
    f->ltfar = _mm256_blendv_ps(_mm256_sub_ps(zero, inf), tf, lanes);
    f->kx = kx, f->ky = ky, f->kz = kz;
    f->okx = o[kx], f->oky = o[ky], f->okz = o[kz];
    /* shear constants exactly as hz_bvh_ray_prep computes them */
    f->sx = _mm256_mul_ps(d[kx], r[kz]);
    f->sy = _mm256_mul_ps(d[ky], r[kz]);
    f->sz = r[kz];
    return true;
}

HZ_INLINE __m256 fr_near(const hz_bvh_node_t *n, size_t off, const frustum_t *f, int k)
{
    const __m256 a = _mm256_sub_ps(ld(n, off), f->on[k]);
    return _mm256_min_ps(_mm256_mul_ps(a, f->rmin[k]), _mm256_mul_ps(a, f->rmax[k]));
}

HZ_INLINE __m256 fr_far(const hz_bvh_node_t *n, size_t off, const frustum_t *f, int k)
{
    const __m256 a = _mm256_sub_ps(ld(n, off), f->of[k]);
    return _mm256_max_ps(_mm256_mul_ps(a, f->rmin[k]), _mm256_mul_ps(a, f->rmax[k]));
}

HZ_INLINE unsigned fr_node_hit(const hz_bvh_node_t *n, const frustum_t *f, __m256 tfar_max, __m256 *tmin_out)
{
    const __m256 tmin = _mm256_max_ps(_mm256_max_ps(fr_near(n, f->nx, f, 0), fr_near(n, f->ny, f, 1)),
                                      _mm256_max_ps(fr_near(n, f->nz, f, 2), f->tnear));
    const __m256 tmax = _mm256_min_ps(
        _mm256_mul_ps(_mm256_min_ps(_mm256_min_ps(fr_far(n, f->fx, f, 0), fr_far(n, f->fy, f, 1)),
                                    fr_far(n, f->fz, f, 2)),
                      _mm256_set1_ps(HZ_BVH_ROBUST)),
        tfar_max);
    *tmin_out = tmin;
    return (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(tmin, tmax, _CMP_LE_OQ));
}

/* One triangle (block slot s) against the packet's lanes `lm`: lanes with a watertight hit at t in [tnear, tfar]
 * (see woop8; the plane distance is computed only when a lane of lm passes the edge tests). */
HZ_INLINE unsigned fr_tri_hit(const hz_bvh_block_t *b, unsigned s, const frustum_t *f, __m256 tfar, unsigned lm,
                              __m256 *t_out, __m256 *v_out, __m256 *w_out, __m256 *det_out)
{
    return woop8(_mm256_sub_ps(_mm256_set1_ps(b->v[0][f->kx][s]), f->okx),
                 _mm256_sub_ps(_mm256_set1_ps(b->v[0][f->ky][s]), f->oky),
                 _mm256_sub_ps(_mm256_set1_ps(b->v[0][f->kz][s]), f->okz),
                 _mm256_sub_ps(_mm256_set1_ps(b->v[1][f->kx][s]), f->okx),
                 _mm256_sub_ps(_mm256_set1_ps(b->v[1][f->ky][s]), f->oky),
                 _mm256_sub_ps(_mm256_set1_ps(b->v[1][f->kz][s]), f->okz),
                 _mm256_sub_ps(_mm256_set1_ps(b->v[2][f->kx][s]), f->okx),
                 _mm256_sub_ps(_mm256_set1_ps(b->v[2][f->ky][s]), f->oky),
                 _mm256_sub_ps(_mm256_set1_ps(b->v[2][f->kz][s]), f->okz), f->sx, f->sy, f->sz, f->ltnear, tfar,
                 lm, t_out, v_out, w_out, det_out);
}

/* Lanes whose own ray meets child j of node n within [tnear, cull[lane]] (the lane's slab test, the signs shared
 * by the packet): a leaf is tested only against these lanes. */
HZ_INLINE unsigned fr_lanes_hit(const hz_bvh_node_t *n, unsigned j, const frustum_t *f, __m256 cull)
{
    const char *c = (const char *)n + 4u * j;
    const __m256 tnx = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss((const float *)(const void *)(c + f->nx)), f->o[0]), f->r[0]);
    const __m256 tny = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss((const float *)(const void *)(c + f->ny)), f->o[1]), f->r[1]);
    const __m256 tnz = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss((const float *)(const void *)(c + f->nz)), f->o[2]), f->r[2]);
    const __m256 tfx = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss((const float *)(const void *)(c + f->fx)), f->o[0]), f->r[0]);
    const __m256 tfy = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss((const float *)(const void *)(c + f->fy)), f->o[1]), f->r[1]);
    const __m256 tfz = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss((const float *)(const void *)(c + f->fz)), f->o[2]), f->r[2]);
    const __m256 tmin = _mm256_max_ps(_mm256_max_ps(tnx, tny), _mm256_max_ps(tnz, f->ltnear));
    const __m256 tmax = _mm256_min_ps(
        _mm256_mul_ps(_mm256_min_ps(_mm256_min_ps(tfx, tfy), tfz), _mm256_set1_ps(HZ_BVH_ROBUST)), cull);
    return (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(tmin, tmax, _CMP_LE_OQ));
}

/* Asks the any-hit callback about lane i of the packet (the ray prepared as the scalar kernels do). */
static bool fr_anyhit(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, uint32_t slot, const hz_ray8_t *ray, unsigned i,
                      float t)
{
    hz_bvh_ray_t r;
    hz_bvh_ray_prep(&r, ray->org_x[i], ray->org_y[i], ray->org_z[i], ray->dir_x[i], ray->dir_y[i], ray->dir_z[i],
                    ray->tnear[i], ray->tfar[i]);
    return hz_bvh_anyhit(bvh, ctx, slot, &r, t, ray->id[i], (int)i);
}

/* Frustum traversal, closest hit. The best hit of every lane lives in vectors (t, triangle, slot, weights):
 * a triangle updates all lanes it beats at once; any-hit triangles go lane by lane through the callback. At
 * the end the hit attributes are computed for all lanes at once (the same operations as hz_bvh_best_finish)
 * and stored into the lanes that hit. */
static void frustum_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const frustum_t *f, hz_rayhit8_t *rh,
                            hz_bvh_counters_t *k)
{
    (void)k; /* counters exist only with HZ_FEATURE_STATS */
    uint32_t st_c[HZ_BVH_STACK + W];
    float st_d[HZ_BVH_STACK + W];
    int sp = 0;
    uint32_t cur = 0;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    __m256 tfar = f->ltfar;
    __m256i bprim = _mm256_set1_epi32(0x7FFFFFFF), bslot = _mm256_set1_epi32(-1);
    __m256 bv = _mm256_setzero_ps(), bw = _mm256_setzero_ps(), bdet = _mm256_set1_ps(1.0f);
    float tfar_max = hmax8(tfar) * HZ_BVH_CULL; /* for culling nodes (see bvh.h) */
    __m256 vtfar_max = _mm256_set1_ps(tfar_max);
    for (;;) {
        /* cur is an inner node here: leaf children are tested at once, against the lanes that reach them
         * (nearest first), inner children go through the ordered stack */
        const hz_bvh_node_t *n = &bvh->nodes[cur];
        __m256 tmin;
        HZ_BVH_COUNT(k, nodes, 1);
        unsigned m = fr_node_hit(n, f, vtfar_max, &tmin);
        const unsigned leafbits =
            (unsigned)_mm256_movemask_ps(_mm256_load_ps((const float *)(const void *)n->child)) & m;
        if (leafbits) {
            float d[W] HZ_ALIGNED(32);
            _mm256_store_ps(d, tmin);
            unsigned order[W], nl = 0;
            for (unsigned lm = leafbits; lm; lm &= lm - 1) {
                unsigned j = (unsigned)__builtin_ctz(lm), q = nl++;
                while (q > 0 && d[order[q - 1]] > d[j]) {
                    order[q] = order[q - 1];
                    q--;
                }
                order[q] = j;
            }
            bool changed = false;
            for (unsigned q = 0; q < nl; q++) {
                const unsigned j = order[q];
                if (d[j] > tfar_max)
                    break;
                const unsigned lanes =
                    fr_lanes_hit(n, j, f, _mm256_mul_ps(tfar, _mm256_set1_ps(HZ_BVH_CULL))) & f->active;
                if (!lanes)
                    continue;
                const uint32_t cw = n->child[j], slot = hz_bvh_leaf_slot(cw), cnt = hz_bvh_leaf_count(cw);
                const hz_bvh_block_t *b = &bvh->blocks[slot / W];
                HZ_BVH_COUNT(k, tris, (uint64_t)cnt * (uint64_t)__builtin_popcount(lanes));
                for (unsigned s = slot % W; s < slot % W + cnt; s++) {
                    __m256 t, V, Wv, det;
                    unsigned mm = fr_tri_hit(b, s, f, tfar, lanes, &t, &V, &Wv, &det);
                    if (!mm)
                        continue;
                    const uint32_t pw = b->prim[s], prim = pw & HZ_BVH_PRIM_MASK, hs = (slot / W) * W + s;
                    const __m256i vprim = _mm256_set1_epi32((int)prim);
                    /* t < best, or t == best and a lower triangle index (best starts at 0x7FFFFFFF) */
                    __m256 better = _mm256_or_ps(
                        _mm256_cmp_ps(t, tfar, _CMP_LT_OQ),
                        _mm256_and_ps(_mm256_cmp_ps(t, tfar, _CMP_EQ_OQ),
                                      _mm256_castsi256_ps(_mm256_cmpgt_epi32(bprim, vprim))));
                    unsigned bm = (unsigned)_mm256_movemask_ps(better) & mm;
                    if (!bm)
                        continue;
                    if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT)) {
                        float tv[W] HZ_ALIGNED(32);
                        _mm256_store_ps(tv, t);
                        for (unsigned x = bm; x; x &= x - 1) {
                            unsigned i = (unsigned)__builtin_ctz(x);
                            if (!fr_anyhit(bvh, ctx, hs, &rh->ray, i, tv[i]))
                                bm &= ~(1u << i);
                        }
                        if (!bm)
                            continue;
                    }
                    better = lanes_of(bm);
                    tfar = _mm256_blendv_ps(tfar, t, better);
                    bv = _mm256_blendv_ps(bv, V, better);
                    bw = _mm256_blendv_ps(bw, Wv, better);
                    bdet = _mm256_blendv_ps(bdet, det, better);
                    bprim = _mm256_blendv_epi8(bprim, vprim, _mm256_castps_si256(better));
                    bslot = _mm256_blendv_epi8(bslot, _mm256_set1_epi32((int)hs), _mm256_castps_si256(better));
                    changed = true;
                }
                if (changed) {
                    tfar_max = hmax8(tfar) * HZ_BVH_CULL;
                    vtfar_max = _mm256_set1_ps(tfar_max);
                }
            }
        }
        const unsigned inner = m & ~leafbits;
        if (inner) {
            order_children(n, inner, tmin, &cur, st_c, st_d, &sp);
            continue;
        }
        for (;;) {
            if (sp == 0)
                goto done;
            --sp;
            if (st_d[sp] <= tfar_max) {
                cur = st_c[sp];
                break;
            }
        }
    }
done:;
    const __m256i hitm = _mm256_cmpgt_epi32(bslot, _mm256_set1_epi32(-1));
    if (_mm256_testz_si256(hitm, hitm))
        return;
    /* attributes, as hz_bvh_best_finish: u = v * (1 / det), Ng = (v1 - v0) x (v2 - v0) from the block */
    const __m256 rdet = _mm256_div_ps(_mm256_set1_ps(1.0f), bdet);
    const __m256 u = _mm256_mul_ps(bv, rdet), vv = _mm256_mul_ps(bw, rdet);
    /* float index of slot s's vertex 0, x: block (s / W) * (sizeof block / 4) + s % W */
    const __m256i sl = _mm256_and_si256(bslot, hitm);
    const __m256i idx = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_srli_epi32(sl, 3),
                                                            _mm256_set1_epi32((int)(sizeof(hz_bvh_block_t) / 4))),
                                         _mm256_and_si256(sl, _mm256_set1_epi32(7)));
    const float *base = &bvh->blocks[0].v[0][0][0];
    __m256 vx[3][3];
    for (int vi = 0; vi < 3; vi++)
        for (int c = 0; c < 3; c++)
            vx[vi][c] = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), base,
                                                 _mm256_add_epi32(idx, _mm256_set1_epi32((vi * 3 + c) * W)),
                                                 _mm256_castsi256_ps(hitm), 4);
    __m256 e1[3], e2[3];
    for (int c = 0; c < 3; c++) {
        e1[c] = _mm256_sub_ps(vx[1][c], vx[0][c]);
        e2[c] = _mm256_sub_ps(vx[2][c], vx[0][c]);
    }
    const __m256 ngx = _mm256_sub_ps(_mm256_mul_ps(e1[1], e2[2]), _mm256_mul_ps(e1[2], e2[1]));
    const __m256 ngy = _mm256_sub_ps(_mm256_mul_ps(e1[2], e2[0]), _mm256_mul_ps(e1[0], e2[2]));
    const __m256 ngz = _mm256_sub_ps(_mm256_mul_ps(e1[0], e2[1]), _mm256_mul_ps(e1[1], e2[0]));
    _mm256_maskstore_ps(rh->ray.tfar, hitm, tfar);
    _mm256_maskstore_ps(rh->hit.u, hitm, u);
    _mm256_maskstore_ps(rh->hit.v, hitm, vv);
    _mm256_maskstore_ps(rh->hit.ng_x, hitm, ngx);
    _mm256_maskstore_ps(rh->hit.ng_y, hitm, ngy);
    _mm256_maskstore_ps(rh->hit.ng_z, hitm, ngz);
    _mm256_maskstore_epi32((int *)(void *)rh->hit.prim_id, hitm, bprim);
    _mm256_maskstore_epi32((int *)(void *)rh->hit.geom_id, hitm, _mm256_setzero_si256());
    _mm256_maskstore_epi32((int *)(void *)rh->hit.inst_id[0], hitm, _mm256_set1_epi32(-1));
}

/* Frustum traversal, occlusion: lanes drop out as they find a hit; children in any order. The frustum test of a
 * node's eight boxes (one test for the packet, loose where origins spread: shadow rays start on a surface) only
 * preselects: each child it passes gets the lanes' own slab tests, and goes on with the lanes that meet it, so
 * the packet visits about the union of its rays' nodes (on Lost Empire's shadow rays the frustum alone passed
 * some 45 times as many leaf boxes as any lane met). A subtree that one lane reaches goes on as that single
 * ray. The packet's bounds are those of its live lanes: when lanes drop out they are recomputed (shadow rays
 * in architecture: the lanes still unoccluded travel furthest). */
static unsigned frustum_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const frustum_t *f0, const hz_ray8_t *ray,
                            hz_bvh_counters_t *k)
{
    uint32_t st_c[HZ_BVH_STACK + W];
    unsigned st_m[HZ_BVH_STACK + W];
    int sp = 0;
    uint32_t cur = 0;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    frustum_t fl;
    const frustum_t *f = f0;
    __m256 tfar = f->ltfar;
    __m256 cull = _mm256_mul_ps(tfar, _mm256_set1_ps(HZ_BVH_CULL)); /* per lane, for culling (see bvh.h) */
    __m256 vtfar_max = _mm256_set1_ps(hmax8(tfar) * HZ_BVH_CULL);
    unsigned live = f->active, cm = live; /* cm: the live lanes that reach cur */
    int single_lane = -1;                 /* the lane prepared in r1 / s1 */
    hz_bvh_ray_t r1;
    sray_t s1;
    for (;;) {
        unsigned done = 0;
        if ((cm & (cm - 1)) == 0) {
            /* one lane reaches this subtree: it goes on alone, with its own box tests */
            const unsigned i = (unsigned)__builtin_ctz(cm);
            if ((int)i != single_lane) {
                hz_bvh_ray_prep(&r1, ray->org_x[i], ray->org_y[i], ray->org_z[i], ray->dir_x[i], ray->dir_y[i],
                                ray->dir_z[i], ray->tnear[i], ray->tfar[i]);
                sray_init(&s1, &r1);
                single_lane = (int)i;
            }
            if (any_from(bvh, ctx, &r1, &s1, cur, ray->id[i], (int)i, k))
                done = cm;
        } else {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            __m256 tmin;
            HZ_BVH_COUNT(k, nodes, 1);
            const unsigned m = fr_node_hit(n, f, vtfar_max, &tmin);
            for (unsigned cb = m; cb; cb &= cb - 1) {
                const unsigned j = (unsigned)__builtin_ctz(cb);
                unsigned lanes = fr_lanes_hit(n, j, f, cull) & cm & ~done;
                if (!lanes)
                    continue;
                const uint32_t cw = n->child[j];
                if (!hz_bvh_is_leaf(cw)) {
                    st_c[sp] = cw;
                    st_m[sp] = lanes;
                    sp++;
                    continue;
                }
                const uint32_t slot = hz_bvh_leaf_slot(cw), cnt = hz_bvh_leaf_count(cw);
                const hz_bvh_block_t *b = &bvh->blocks[slot / W];
                HZ_BVH_COUNT(k, tris, (uint64_t)cnt * (uint64_t)__builtin_popcount(lanes));
                for (unsigned s = slot % W; s < slot % W + cnt && lanes; s++) {
                    __m256 t, V, Wv, det;
                    unsigned mm = fr_tri_hit(b, s, f, tfar, lanes, &t, &V, &Wv, &det);
                    if (!mm)
                        continue;
                    const uint32_t pw = b->prim[s], hs = (slot / W) * W + s;
                    if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT)) {
                        float tv[W] HZ_ALIGNED(32);
                        _mm256_store_ps(tv, t);
                        for (unsigned x = mm; x; x &= x - 1) {
                            unsigned i = (unsigned)__builtin_ctz(x);
                            if (!fr_anyhit(bvh, ctx, hs, ray, i, tv[i]))
                                mm &= ~(1u << i);
                        }
                    }
                    done |= mm;
                    lanes &= ~mm;
                }
                if (done == cm)
                    break;
            }
        }
        if (done) {
            live &= ~done;
            if (!live)
                break;
            tfar = _mm256_blendv_ps(tfar, _mm256_set1_ps(-__builtin_inff()), lanes_of(done));
            cull = _mm256_mul_ps(tfar, _mm256_set1_ps(HZ_BVH_CULL));
            if (live & (live - 1)) {
                if (f != &fl) {
                    fl = *f0;
                    f = &fl;
                }
                fl.active = live;
                frustum_bounds(&fl, lanes_of(live), fl.ltnear);
            }
            vtfar_max = _mm256_set1_ps(hmax8(tfar) * HZ_BVH_CULL);
        }
        for (;;) {
            if (sp == 0)
                return f0->active & ~live;
            --sp;
            cm = st_m[sp] & live;
            if (cm) {
                cur = st_c[sp];
                break;
            }
        }
    }
    return f0->active;
}

/* Masked packet, closest hit: per-lane box tests, lane masks on the stack, single rays once few lanes remain. */
static void masked_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, packet_t *p, hz_bvh_counters_t *k)
{
    mentry_t stack[HZ_BVH_STACK];
    int sp = 0;
    float ox[W], oy[W], oz[W], rx[W], ry[W], rz[W], tn[W], tfa[W] HZ_ALIGNED(32);
    for (int i = 0; i < W; i++) {
        const hz_bvh_ray_t *r = &p->r[(p->active >> i) & 1u ? i : __builtin_ctz(p->active)];
        ox[i] = r->org[0], oy[i] = r->org[1], oz[i] = r->org[2];
        rx[i] = r->rdir[0], ry[i] = r->rdir[1], rz[i] = r->rdir[2];
        tn[i] = r->tnear;
    }
    lanes_tfar(p, tfa);
    for (int i = 0; i < W; i++) /* tfa holds culling distances (see bvh.h) */
        tfa[i] *= HZ_BVH_CULL;
    const __m256 vox = _mm256_loadu_ps(ox), voy = _mm256_loadu_ps(oy), voz = _mm256_loadu_ps(oz);
    const __m256 vrx = _mm256_loadu_ps(rx), vry = _mm256_loadu_ps(ry), vrz = _mm256_loadu_ps(rz);
    const __m256 vtn = _mm256_loadu_ps(tn), robust = _mm256_set1_ps(HZ_BVH_ROBUST);
    const __m256 vinf = _mm256_set1_ps(__builtin_inff()), zero = _mm256_setzero_ps();
    const __m256 negx = _mm256_cmp_ps(vrx, zero, _CMP_LT_OQ), negy = _mm256_cmp_ps(vry, zero, _CMP_LT_OQ);
    const __m256 negz = _mm256_cmp_ps(vrz, zero, _CMP_LT_OQ);
    __m256 tfar = _mm256_load_ps(tfa);
    sray_t sr[W];
    for (unsigned m = p->active; m; m &= m - 1)
        sray_init(&sr[__builtin_ctz(m)], &p->r[__builtin_ctz(m)]);
    uint32_t cur = 0;
    unsigned lanes = p->active;
    for (;;) {
        if (__builtin_popcount(lanes) <= MASKED_SWITCH) {
            for (unsigned m = lanes; m; m &= m - 1) {
                unsigned i = (unsigned)__builtin_ctz(m);
                closest_from(bvh, ctx, &p->r[i], &sr[i], cur, &p->best[i], p->id[i], (int)i, k);
                tfa[i] = p->r[i].tfar * HZ_BVH_CULL;
            }
            tfar = _mm256_load_ps(tfa);
        } else if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            HZ_BVH_COUNT(k, nodes, 1);
            mentry_t h[W];
            int c = 0;
            for (int j = 0; j < W; j++) {
                if (n->child[j] == HZ_BVH_EMPTY)
                    continue;
                const __m256 t0x = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(n->lo_x[j]), vox), vrx);
                const __m256 t1x = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(n->hi_x[j]), vox), vrx);
                const __m256 t0y = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(n->lo_y[j]), voy), vry);
                const __m256 t1y = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(n->hi_y[j]), voy), vry);
                const __m256 t0z = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(n->lo_z[j]), voz), vrz);
                const __m256 t1z = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(n->hi_z[j]), voz), vrz);
                /* near/far by the sign of each lane's direction, NaN-prone values first (see bvh.h) */
                const __m256 tnx = _mm256_blendv_ps(t0x, t1x, negx), tfx = _mm256_blendv_ps(t1x, t0x, negx);
                const __m256 tny = _mm256_blendv_ps(t0y, t1y, negy), tfy = _mm256_blendv_ps(t1y, t0y, negy);
                const __m256 tnz = _mm256_blendv_ps(t0z, t1z, negz), tfz = _mm256_blendv_ps(t1z, t0z, negz);
                const __m256 tmin = _mm256_max_ps(tnz, _mm256_max_ps(tny, _mm256_max_ps(tnx, vtn)));
                const __m256 tmax = _mm256_min_ps(
                    _mm256_mul_ps(_mm256_min_ps(tfz, _mm256_min_ps(tfy, _mm256_min_ps(tfx, vinf))), robust), tfar);
                const __m256 hit = _mm256_cmp_ps(tmin, tmax, _CMP_LE_OQ);
                unsigned m = (unsigned)_mm256_movemask_ps(hit) & lanes;
                if (!m)
                    continue;
                float d = hmin8(_mm256_blendv_ps(_mm256_set1_ps(__builtin_inff()), tmin, hit));
                mentry_t e = { n->child[j], m, d };
                int q = c++;
                while (q > 0 && h[q - 1].d < e.d) {
                    h[q] = h[q - 1];
                    q--;
                }
                h[q] = e;
            }
            if (c > 0) {
                for (int i = 0; i < c - 1; i++)
                    stack[sp++] = h[i];
                cur = h[c - 1].c;
                lanes = h[c - 1].m;
                continue;
            }
        } else {
            const uint32_t slot = hz_bvh_leaf_slot(cur), cnt = hz_bvh_leaf_count(cur);
            const hz_bvh_block_t *b = &bvh->blocks[slot / W];
            const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
            HZ_BVH_COUNT(k, tris, (uint64_t)cnt * (uint64_t)__builtin_popcount(lanes));
            for (unsigned lm = lanes; lm; lm &= lm - 1) {
                unsigned i = (unsigned)__builtin_ctz(lm);
                hz_bvh_ray_t *r = &p->r[i];
                __m256 t, V, Wv, det;
                unsigned m = leaf_hit(b, slot_mask(slot, cnt), &sr[i], r->tfar, &t, &V, &Wv, &det);
                if (!m)
                    continue;
                float tv[W] HZ_ALIGNED(32), vv[W] HZ_ALIGNED(32), wv[W] HZ_ALIGNED(32), dv[W] HZ_ALIGNED(32);
                _mm256_store_ps(tv, t);
                _mm256_store_ps(vv, V);
                _mm256_store_ps(wv, Wv);
                _mm256_store_ps(dv, det);
                do {
                    unsigned s = (unsigned)__builtin_ctz(m);
                    m &= m - 1;
                    uint32_t pw = b->prim[s], prim = pw & HZ_BVH_PRIM_MASK, hs = (slot / W) * W + s;
                    if (!hz_bvh_better(tv[s], prim, r->tfar, p->best[i].prim))
                        continue;
                    if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT) && !hz_bvh_anyhit(bvh, ctx, hs, r, tv[s], p->id[i], (int)i))
                        continue;
                    r->tfar = tv[s];
                    p->best[i].prim = prim, p->best[i].slot = hs;
                    p->best[i].v = vv[s], p->best[i].w = wv[s], p->best[i].det = dv[s];
                } while (m);
                tfa[i] = r->tfar * HZ_BVH_CULL;
            }
            tfar = _mm256_load_ps(tfa);
        }
        /* pop, dropping lanes whose best hit is already closer than the subtree */
        for (;;) {
            if (sp == 0)
                return;
            mentry_t e = stack[--sp];
            unsigned m = e.m & (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(_mm256_set1_ps(e.d), tfar, _CMP_LE_OQ));
            if (m) {
                cur = e.c;
                lanes = m;
                break;
            }
        }
    }
}

static void write_hits(const hz_bvh_t *bvh, const packet_t *p, hz_rayhit8_t *rh)
{
    for (unsigned m = p->active; m; m &= m - 1) {
        unsigned i = (unsigned)__builtin_ctz(m);
        if (p->best[i].slot == HZ_ACCEL_INVALID_ID)
            continue;
        float ng[3];
        hz_bvh_best_finish(bvh, &p->best[i], ng, &rh->hit.u[i], &rh->hit.v[i]);
        rh->ray.tfar[i] = p->r[i].tfar;
        rh->hit.ng_x[i] = ng[0], rh->hit.ng_y[i] = ng[1], rh->hit.ng_z[i] = ng[2];
        rh->hit.prim_id[i] = p->best[i].prim;
        rh->hit.geom_id[i] = 0;
        rh->hit.inst_id[0][i] = HZ_ACCEL_INVALID_ID;
    }
}

void hz_bvh_simd_intersectw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_rayhit8_t *rh,
                            hz_accel_kernel_t kernel)
{
    hz_bvh_counters_t k = { 0, 0 };
    frustum_t f;
    if (kernel == HZ_ACCEL_KERNEL_SIMD_PACKET && frustum_init(&f, valid, &rh->ray)) {
        frustum_closest(bvh, ctx, &f, rh, &k);
        hz_bvh_counters_flush(ctx, &k);
        return;
    }
    packet_t p;
    if (!packet_init(&p, valid, &rh->ray))
        return;
    if (kernel == HZ_ACCEL_KERNEL_SIMD_MASKED) {
        masked_closest(bvh, ctx, &p, &k);
    } else {
        for (unsigned m = p.active; m; m &= m - 1) {
            unsigned i = (unsigned)__builtin_ctz(m);
            sray_t s;
            sray_init(&s, &p.r[i]);
            closest_from(bvh, ctx, &p.r[i], &s, 0, &p.best[i], p.id[i], (int)i, &k);
        }
    }
    write_hits(bvh, &p, rh);
    hz_bvh_counters_flush(ctx, &k);
}

void hz_bvh_simd_occludedw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_ray8_t *ray,
                           hz_accel_kernel_t kernel)
{
    hz_bvh_counters_t k = { 0, 0 };
    unsigned hit = 0;
    frustum_t f;
    if (kernel == HZ_ACCEL_KERNEL_SIMD_PACKET && frustum_init(&f, valid, ray)) {
        hit = frustum_any(bvh, ctx, &f, ray, &k);
    } else {
        packet_t p;
        if (!packet_init(&p, valid, ray))
            return;
        /* the masked form brings nothing to occlusion (no ordering, early exit per lane): single rays */
        for (unsigned m = p.active; m; m &= m - 1) {
            unsigned i = (unsigned)__builtin_ctz(m);
            sray_t s;
            sray_init(&s, &p.r[i]);
            if (any_from(bvh, ctx, &p.r[i], &s, 0, p.id[i], (int)i, &k))
                hit |= 1u << i;
        }
    }
    for (unsigned m = hit; m; m &= m - 1)
        ray->tfar[__builtin_ctz(m)] = -__builtin_inff();
    hz_bvh_counters_flush(ctx, &k);
}
