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

typedef struct counters {
    uint64_t nodes, tris;
} counters_t;

static void flush(hz_accel_ctx_t *ctx, const counters_t *k)
{
    (void)k; /* counters are compiled out unless HZ_FEATURE_STATS */
#if HZ_FEATURE_STATS
    if (ctx && ctx->stats) {
        ctx->stats->nodes += k->nodes;
        ctx->stats->tris += k->tris;
    }
#else
    (void)ctx;
    (void)k;
#endif
}

#if HZ_FEATURE_STATS
#define COUNT(k, field, n) ((k)->field += (n))
#else
#define COUNT(k, field, n) ((void)0)
#endif

HZ_INLINE __m256 ld(const hz_bvh_node_t *n, size_t off)
{
    return _mm256_load_ps((const float *)(const void *)((const char *)n + off));
}

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

/* One ray against the slots `lm` of block b: lanes that pass the watertight test with t >= tnear and
 * t <= tfar; t in *t_out. */
HZ_INLINE unsigned leaf_hit(const hz_bvh_block_t *b, unsigned lm, const sray_t *s, float tfar, __m256 *t_out)
{
    const __m256 akx = _mm256_sub_ps(_mm256_load_ps(b->v[0][s->kx]), s->okx);
    const __m256 aky = _mm256_sub_ps(_mm256_load_ps(b->v[0][s->ky]), s->oky);
    const __m256 akz = _mm256_sub_ps(_mm256_load_ps(b->v[0][s->kz]), s->okz);
    const __m256 bkx = _mm256_sub_ps(_mm256_load_ps(b->v[1][s->kx]), s->okx);
    const __m256 bky = _mm256_sub_ps(_mm256_load_ps(b->v[1][s->ky]), s->oky);
    const __m256 bkz = _mm256_sub_ps(_mm256_load_ps(b->v[1][s->kz]), s->okz);
    const __m256 ckx = _mm256_sub_ps(_mm256_load_ps(b->v[2][s->kx]), s->okx);
    const __m256 cky = _mm256_sub_ps(_mm256_load_ps(b->v[2][s->ky]), s->oky);
    const __m256 ckz = _mm256_sub_ps(_mm256_load_ps(b->v[2][s->kz]), s->okz);
    const __m256 ax = _mm256_sub_ps(akx, _mm256_mul_ps(s->sx, akz));
    const __m256 ay = _mm256_sub_ps(aky, _mm256_mul_ps(s->sy, akz));
    const __m256 bx = _mm256_sub_ps(bkx, _mm256_mul_ps(s->sx, bkz));
    const __m256 by = _mm256_sub_ps(bky, _mm256_mul_ps(s->sy, bkz));
    const __m256 cx = _mm256_sub_ps(ckx, _mm256_mul_ps(s->sx, ckz));
    const __m256 cy = _mm256_sub_ps(cky, _mm256_mul_ps(s->sy, ckz));
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
    const __m256 az = _mm256_mul_ps(s->sz, akz), bz = _mm256_mul_ps(s->sz, bkz), cz = _mm256_mul_ps(s->sz, ckz);
    const __m256 T =
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(U, az), _mm256_mul_ps(V, bz)), _mm256_mul_ps(Wv, cz));
    const __m256 t = _mm256_div_ps(T, det);
    const __m256 in = _mm256_and_ps(_mm256_cmp_ps(t, s->tnear, _CMP_GE_OQ),
                                    _mm256_cmp_ps(t, _mm256_set1_ps(tfar), _CMP_LE_OQ));
    *t_out = t;
    return m & (unsigned)_mm256_movemask_ps(in);
}

HZ_INLINE unsigned slot_mask(uint32_t slot, uint32_t n)
{
    return ((1u << n) - 1u) << (slot % W);
}

/* Closest hit of one ray from node word `start` on, continuing a search with best (r->tfar, *prim, *slot). */
static void closest_from(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, const sray_t *s,
                         uint32_t start, uint32_t *best_prim, uint32_t *best_slot, uint32_t ray_id, int lane,
                         counters_t *k)
{
    (void)k; /* counters are compiled out unless HZ_FEATURE_STATS */
    entry_t stack[HZ_BVH_STACK];
    int sp = 0;
    uint32_t cur = start;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    __m256 tfar = _mm256_set1_ps(r->tfar);
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            __m256 tmin;
            COUNT(k, nodes, 1);
            unsigned m = node_hit(n, s, tfar, &tmin);
            if (m) {
                unsigned i0 = (unsigned)__builtin_ctz(m);
                m &= m - 1;
                if (!m) {
                    cur = n->child[i0];
                    continue;
                }
                float d[W] HZ_ALIGNED(32);
                _mm256_store_ps(d, tmin);
                entry_t h[W];
                int c = 0;
                h[c].c = n->child[i0], h[c++].d = d[i0];
                do {
                    unsigned i = (unsigned)__builtin_ctz(m);
                    m &= m - 1;
                    entry_t e = { n->child[i], d[i] };
                    int j = c++;
                    while (j > 0 && h[j - 1].d < e.d) { /* descending: nearest last */
                        h[j] = h[j - 1];
                        j--;
                    }
                    h[j] = e;
                } while (m);
                for (int i = 0; i < c - 1; i++)
                    stack[sp++] = h[i];
                cur = h[c - 1].c;
                continue;
            }
        } else {
            const uint32_t slot = hz_bvh_leaf_slot(cur), cnt = hz_bvh_leaf_count(cur);
            const hz_bvh_block_t *b = &bvh->blocks[slot / W];
            __m256 t;
            COUNT(k, tris, cnt);
            unsigned m = leaf_hit(b, slot_mask(slot, cnt), s, r->tfar, &t);
            if (m) {
                float tv[W] HZ_ALIGNED(32);
                _mm256_store_ps(tv, t);
                do {
                    unsigned i = (unsigned)__builtin_ctz(m);
                    m &= m - 1;
                    uint32_t pw = b->prim[i], prim = pw & HZ_BVH_PRIM_MASK;
                    if (!hz_bvh_better(tv[i], prim, r->tfar, *best_prim))
                        continue;
                    uint32_t hs = (slot / W) * W + i;
                    if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT) && !hz_bvh_anyhit(bvh, ctx, hs, r, tv[i], ray_id, lane))
                        continue;
                    r->tfar = tv[i];
                    *best_prim = prim;
                    *best_slot = hs;
                } while (m);
                tfar = _mm256_set1_ps(r->tfar);
            }
        }
        for (;;) {
            if (sp == 0)
                return;
            entry_t e = stack[--sp];
            if (e.d <= r->tfar) {
                cur = e.c;
                break;
            }
        }
    }
}

uint32_t hz_bvh_simd_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, uint32_t ray_id, int lane)
{
    sray_t s;
    counters_t k = { 0, 0 };
    uint32_t prim = HZ_ACCEL_INVALID_ID, slot = HZ_ACCEL_INVALID_ID;
    sray_init(&s, r);
    closest_from(bvh, ctx, r, &s, 0, &prim, &slot, ray_id, lane, &k);
    flush(ctx, &k);
    return slot;
}

static bool any_from(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, const sray_t *s, uint32_t start,
                     uint32_t ray_id, int lane, counters_t *k)
{
    (void)k; /* counters are compiled out unless HZ_FEATURE_STATS */
    entry_t stack[HZ_BVH_STACK];
    int sp = 0;
    uint32_t cur = start;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    const __m256 tfar = _mm256_set1_ps(r->tfar);
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            __m256 tmin;
            COUNT(k, nodes, 1);
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
            const hz_bvh_block_t *b = &bvh->blocks[slot / W];
            __m256 t;
            COUNT(k, tris, cnt);
            unsigned m = leaf_hit(b, slot_mask(slot, cnt), s, r->tfar, &t);
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

bool hz_bvh_simd_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, uint32_t ray_id, int lane)
{
    sray_t s;
    counters_t k = { 0, 0 };
    sray_init(&s, r);
    bool hit = any_from(bvh, ctx, r, &s, 0, ray_id, lane, &k);
    flush(ctx, &k);
    return hit;
}

/* ---------------------------------------------------------------------------------------------------------
 * packets */
typedef struct packet {
    hz_bvh_ray_t r[W];
    unsigned active;
    uint32_t id[W];
    uint32_t best_prim[W], best_slot[W];
} packet_t;

static unsigned packet_init(packet_t *p, const int32_t *valid, const hz_ray8_t *ray)
{
    p->active = 0;
    for (int i = 0; i < W; i++) {
        p->best_prim[i] = p->best_slot[i] = HZ_ACCEL_INVALID_ID;
        p->id[i] = ray->id[i];
        if (!valid[i])
            continue;
        if (hz_bvh_ray_prep(&p->r[i], ray->org_x[i], ray->org_y[i], ray->org_z[i], ray->dir_x[i], ray->dir_y[i],
                            ray->dir_z[i], ray->tnear[i], ray->tfar[i]))
            p->active |= 1u << i;
    }
    return p->active;
}

/* Frustum form: needs every active lane to share the direction signs and the dominant axis (kx, ky, kz). */
typedef struct frustum {
    size_t nx, ny, nz, fx, fy, fz;
    __m256 on[3], of[3], rmin[3], rmax[3]; /* origins for the near and far planes, reciprocal ranges */
    __m256 tnear;                          /* smallest tnear of the packet */
    /* lanes, for the leaf test */
    __m256 okx, oky, okz, sx, sy, sz, ltnear;
    int kx, ky, kz;
} frustum_t;

static bool frustum_init(frustum_t *f, const packet_t *p)
{
    int first = __builtin_ctz(p->active);
    const hz_bvh_ray_t *r0 = &p->r[first];
    float omin[3], omax[3], rmn[3], rmx[3], tn = r0->tnear;
    for (int k = 0; k < 3; k++)
        omin[k] = omax[k] = r0->org[k], rmn[k] = rmx[k] = r0->rdir[k];
    for (unsigned m = p->active; m; m &= m - 1) {
        const hz_bvh_ray_t *r = &p->r[__builtin_ctz(m)];
        if (r->kx != r0->kx || r->ky != r0->ky || r->kz != r0->kz)
            return false;
        for (int k = 0; k < 3; k++) {
            /* interval bounds need finite reciprocals of one sign (a zero component makes 0 * inf) */
            if ((r->rdir[k] < 0.0f) != (r0->rdir[k] < 0.0f) || !hz_isfinitef(r->rdir[k]))
                return false;
            omin[k] = hz_minf(omin[k], r->org[k]), omax[k] = hz_maxf(omax[k], r->org[k]);
            rmn[k] = hz_minf(rmn[k], r->rdir[k]), rmx[k] = hz_maxf(rmx[k], r->rdir[k]);
        }
        tn = hz_minf(tn, r->tnear);
    }
    const size_t a = offsetof(hz_bvh_node_t, hi_x) - offsetof(hz_bvh_node_t, lo_x);
    const size_t base[3] = { offsetof(hz_bvh_node_t, lo_x), offsetof(hz_bvh_node_t, lo_y),
                             offsetof(hz_bvh_node_t, lo_z) };
    size_t nn[3], ff[3];
    for (int k = 0; k < 3; k++) {
        bool neg = r0->rdir[k] < 0.0f;
        nn[k] = base[k] + (neg ? a : 0);
        ff[k] = base[k] + (neg ? 0 : a);
        /* near plane: lower bound of (plane - o) * r over the packet; far plane: upper bound (see bvh.h) */
        f->on[k] = _mm256_set1_ps(neg ? omin[k] : omax[k]);
        f->of[k] = _mm256_set1_ps(neg ? omax[k] : omin[k]);
        f->rmin[k] = _mm256_set1_ps(rmn[k]);
        f->rmax[k] = _mm256_set1_ps(rmx[k]);
    }
    f->nx = nn[0], f->ny = nn[1], f->nz = nn[2];
    f->fx = ff[0], f->fy = ff[1], f->fz = ff[2];
    f->tnear = _mm256_set1_ps(tn);
    f->kx = r0->kx, f->ky = r0->ky, f->kz = r0->kz;
    float okx[W], oky[W], okz[W], sx[W], sy[W], sz[W], ltn[W];
    for (int i = 0; i < W; i++) {
        const hz_bvh_ray_t *r = &p->r[(p->active >> i) & 1u ? i : first];
        okx[i] = r->org[f->kx], oky[i] = r->org[f->ky], okz[i] = r->org[f->kz];
        sx[i] = r->sx, sy[i] = r->sy, sz[i] = r->sz;
        ltn[i] = (p->active >> i) & 1u ? r->tnear : __builtin_inff();
    }
    f->okx = _mm256_loadu_ps(okx), f->oky = _mm256_loadu_ps(oky), f->okz = _mm256_loadu_ps(okz);
    f->sx = _mm256_loadu_ps(sx), f->sy = _mm256_loadu_ps(sy), f->sz = _mm256_loadu_ps(sz);
    f->ltnear = _mm256_loadu_ps(ltn);
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

/* One triangle (block slot s) against the packet's lanes: lanes with a watertight hit at t in [tnear, tfar]. */
HZ_INLINE unsigned fr_tri_hit(const hz_bvh_block_t *b, unsigned s, const frustum_t *f, __m256 tfar, __m256 *t_out)
{
    const __m256 akx = _mm256_sub_ps(_mm256_set1_ps(b->v[0][f->kx][s]), f->okx);
    const __m256 aky = _mm256_sub_ps(_mm256_set1_ps(b->v[0][f->ky][s]), f->oky);
    const __m256 akz = _mm256_sub_ps(_mm256_set1_ps(b->v[0][f->kz][s]), f->okz);
    const __m256 bkx = _mm256_sub_ps(_mm256_set1_ps(b->v[1][f->kx][s]), f->okx);
    const __m256 bky = _mm256_sub_ps(_mm256_set1_ps(b->v[1][f->ky][s]), f->oky);
    const __m256 bkz = _mm256_sub_ps(_mm256_set1_ps(b->v[1][f->kz][s]), f->okz);
    const __m256 ckx = _mm256_sub_ps(_mm256_set1_ps(b->v[2][f->kx][s]), f->okx);
    const __m256 cky = _mm256_sub_ps(_mm256_set1_ps(b->v[2][f->ky][s]), f->oky);
    const __m256 ckz = _mm256_sub_ps(_mm256_set1_ps(b->v[2][f->kz][s]), f->okz);
    const __m256 ax = _mm256_sub_ps(akx, _mm256_mul_ps(f->sx, akz));
    const __m256 ay = _mm256_sub_ps(aky, _mm256_mul_ps(f->sy, akz));
    const __m256 bx = _mm256_sub_ps(bkx, _mm256_mul_ps(f->sx, bkz));
    const __m256 by = _mm256_sub_ps(bky, _mm256_mul_ps(f->sy, bkz));
    const __m256 cx = _mm256_sub_ps(ckx, _mm256_mul_ps(f->sx, ckz));
    const __m256 cy = _mm256_sub_ps(cky, _mm256_mul_ps(f->sy, ckz));
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
    unsigned m = (unsigned)_mm256_movemask_ps(ok);
    if (!m)
        return 0;
    const __m256 az = _mm256_mul_ps(f->sz, akz), bz = _mm256_mul_ps(f->sz, bkz), cz = _mm256_mul_ps(f->sz, ckz);
    const __m256 T =
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(U, az), _mm256_mul_ps(V, bz)), _mm256_mul_ps(Wv, cz));
    const __m256 t = _mm256_div_ps(T, det);
    const __m256 in =
        _mm256_and_ps(_mm256_cmp_ps(t, f->ltnear, _CMP_GE_OQ), _mm256_cmp_ps(t, tfar, _CMP_LE_OQ));
    *t_out = t;
    return m & (unsigned)_mm256_movemask_ps(in);
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

static void lanes_tfar(const packet_t *p, float *tf)
{
    for (int i = 0; i < W; i++)
        tf[i] = (p->active >> i) & 1u ? p->r[i].tfar : -__builtin_inff();
}

/* Frustum traversal, closest hit. */
static void frustum_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, packet_t *p, const frustum_t *f,
                            counters_t *k)
{
    (void)k; /* counters are compiled out unless HZ_FEATURE_STATS */
    entry_t stack[HZ_BVH_STACK];
    int sp = 0;
    uint32_t cur = 0;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    float tfa[W] HZ_ALIGNED(32);
    lanes_tfar(p, tfa);
    __m256 tfar = _mm256_load_ps(tfa);
    float tfar_max = hmax8(tfar);
    __m256 vtfar_max = _mm256_set1_ps(tfar_max);
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            __m256 tmin;
            COUNT(k, nodes, 1);
            unsigned m = fr_node_hit(n, f, vtfar_max, &tmin);
            if (m) {
                unsigned i0 = (unsigned)__builtin_ctz(m);
                m &= m - 1;
                if (!m) {
                    cur = n->child[i0];
                    continue;
                }
                float d[W] HZ_ALIGNED(32);
                _mm256_store_ps(d, tmin);
                entry_t h[W];
                int c = 0;
                h[c].c = n->child[i0], h[c++].d = d[i0];
                do {
                    unsigned i = (unsigned)__builtin_ctz(m);
                    m &= m - 1;
                    entry_t e = { n->child[i], d[i] };
                    int j = c++;
                    while (j > 0 && h[j - 1].d < e.d) {
                        h[j] = h[j - 1];
                        j--;
                    }
                    h[j] = e;
                } while (m);
                for (int i = 0; i < c - 1; i++)
                    stack[sp++] = h[i];
                cur = h[c - 1].c;
                continue;
            }
        } else {
            const uint32_t slot = hz_bvh_leaf_slot(cur), cnt = hz_bvh_leaf_count(cur);
            const hz_bvh_block_t *b = &bvh->blocks[slot / W];
            bool changed = false;
            COUNT(k, tris, (uint64_t)cnt * (uint64_t)__builtin_popcount(p->active));
            for (unsigned s = slot % W; s < slot % W + cnt; s++) {
                __m256 t;
                unsigned m = fr_tri_hit(b, s, f, tfar, &t) & p->active;
                if (!m)
                    continue;
                const uint32_t pw = b->prim[s], prim = pw & HZ_BVH_PRIM_MASK, hs = (slot / W) * W + s;
                float tv[W] HZ_ALIGNED(32);
                _mm256_store_ps(tv, t);
                do {
                    unsigned i = (unsigned)__builtin_ctz(m);
                    m &= m - 1;
                    hz_bvh_ray_t *r = &p->r[i];
                    if (!hz_bvh_better(tv[i], prim, r->tfar, p->best_prim[i]))
                        continue;
                    if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT) && !hz_bvh_anyhit(bvh, ctx, hs, r, tv[i], p->id[i], (int)i))
                        continue;
                    r->tfar = tv[i];
                    tfa[i] = tv[i];
                    p->best_prim[i] = prim;
                    p->best_slot[i] = hs;
                    changed = true;
                } while (m);
            }
            if (changed) {
                tfar = _mm256_load_ps(tfa);
                tfar_max = hmax8(tfar);
                vtfar_max = _mm256_set1_ps(tfar_max);
            }
        }
        for (;;) {
            if (sp == 0)
                return;
            entry_t e = stack[--sp];
            if (e.d <= tfar_max) {
                cur = e.c;
                break;
            }
        }
    }
}

static void frustum_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, packet_t *p, const frustum_t *f, unsigned *hit,
                        counters_t *k)
{
    (void)k; /* counters are compiled out unless HZ_FEATURE_STATS */
    entry_t stack[HZ_BVH_STACK];
    int sp = 0;
    uint32_t cur = 0;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    float tfa[W] HZ_ALIGNED(32);
    lanes_tfar(p, tfa);
    __m256 tfar = _mm256_load_ps(tfa);
    __m256 vtfar_max = _mm256_set1_ps(hmax8(tfar));
    unsigned live = p->active;
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            __m256 tmin;
            COUNT(k, nodes, 1);
            unsigned m = fr_node_hit(n, f, vtfar_max, &tmin);
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
            const hz_bvh_block_t *b = &bvh->blocks[slot / W];
            bool changed = false;
            COUNT(k, tris, (uint64_t)cnt * (uint64_t)__builtin_popcount(live));
            for (unsigned s = slot % W; s < slot % W + cnt && live; s++) {
                __m256 t;
                unsigned m = fr_tri_hit(b, s, f, tfar, &t) & live;
                if (!m)
                    continue;
                const uint32_t pw = b->prim[s], hs = (slot / W) * W + s;
                if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT)) {
                    float tv[W] HZ_ALIGNED(32);
                    _mm256_store_ps(tv, t);
                    for (unsigned mm = m; mm; mm &= mm - 1) {
                        unsigned i = (unsigned)__builtin_ctz(mm);
                        if (!hz_bvh_anyhit(bvh, ctx, hs, &p->r[i], tv[i], p->id[i], (int)i))
                            m &= ~(1u << i);
                    }
                }
                if (m) {
                    live &= ~m;
                    for (unsigned mm = m; mm; mm &= mm - 1)
                        tfa[__builtin_ctz(mm)] = -__builtin_inff();
                    changed = true;
                }
            }
            if (!live)
                break;
            if (changed) {
                tfar = _mm256_load_ps(tfa);
                vtfar_max = _mm256_set1_ps(hmax8(tfar));
            }
        }
        if (sp == 0)
            break;
        cur = stack[--sp].c;
    }
    *hit = p->active & ~live;
}

/* Masked packet, closest hit: per-lane box tests, lane masks on the stack, single rays once few lanes remain. */
static void masked_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, packet_t *p, counters_t *k)
{
    (void)k; /* counters are compiled out unless HZ_FEATURE_STATS */
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
                closest_from(bvh, ctx, &p->r[i], &sr[i], cur, &p->best_prim[i], &p->best_slot[i], p->id[i], (int)i,
                             k);
                tfa[i] = p->r[i].tfar;
            }
            tfar = _mm256_load_ps(tfa);
        } else if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            COUNT(k, nodes, 1);
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
            COUNT(k, tris, (uint64_t)cnt * (uint64_t)__builtin_popcount(lanes));
            for (unsigned lm = lanes; lm; lm &= lm - 1) {
                unsigned i = (unsigned)__builtin_ctz(lm);
                hz_bvh_ray_t *r = &p->r[i];
                __m256 t;
                unsigned m = leaf_hit(b, slot_mask(slot, cnt), &sr[i], r->tfar, &t);
                if (!m)
                    continue;
                float tv[W] HZ_ALIGNED(32);
                _mm256_store_ps(tv, t);
                do {
                    unsigned s = (unsigned)__builtin_ctz(m);
                    m &= m - 1;
                    uint32_t pw = b->prim[s], prim = pw & HZ_BVH_PRIM_MASK, hs = (slot / W) * W + s;
                    if (!hz_bvh_better(tv[s], prim, r->tfar, p->best_prim[i]))
                        continue;
                    if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT) && !hz_bvh_anyhit(bvh, ctx, hs, r, tv[s], p->id[i], (int)i))
                        continue;
                    r->tfar = tv[s];
                    p->best_prim[i] = prim;
                    p->best_slot[i] = hs;
                } while (m);
                tfa[i] = r->tfar;
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
        uint32_t slot = p->best_slot[i];
        if (slot == HZ_ACCEL_INVALID_ID)
            continue;
        float ng[3];
        hz_bvh_hit_attributes(bvh, slot, &p->r[i], ng, &rh->hit.u[i], &rh->hit.v[i]);
        rh->ray.tfar[i] = p->r[i].tfar;
        rh->hit.ng_x[i] = ng[0], rh->hit.ng_y[i] = ng[1], rh->hit.ng_z[i] = ng[2];
        rh->hit.prim_id[i] = p->best_prim[i];
        rh->hit.geom_id[i] = 0;
        rh->hit.inst_id[0][i] = HZ_ACCEL_INVALID_ID;
    }
}

void hz_bvh_simd_intersectw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_rayhit8_t *rh,
                            hz_accel_kernel_t kernel)
{
    packet_t p;
    counters_t k = { 0, 0 };
    if (!packet_init(&p, valid, &rh->ray))
        return;
    frustum_t f;
    if (kernel == HZ_ACCEL_KERNEL_SIMD_PACKET && __builtin_popcount(p.active) > 1 && frustum_init(&f, &p)) {
        frustum_closest(bvh, ctx, &p, &f, &k);
    } else if (kernel == HZ_ACCEL_KERNEL_SIMD_MASKED) {
        masked_closest(bvh, ctx, &p, &k);
    } else {
        for (unsigned m = p.active; m; m &= m - 1) {
            unsigned i = (unsigned)__builtin_ctz(m);
            sray_t s;
            sray_init(&s, &p.r[i]);
            closest_from(bvh, ctx, &p.r[i], &s, 0, &p.best_prim[i], &p.best_slot[i], p.id[i], (int)i, &k);
        }
    }
    write_hits(bvh, &p, rh);
    flush(ctx, &k);
}

void hz_bvh_simd_occludedw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_ray8_t *ray,
                           hz_accel_kernel_t kernel)
{
    packet_t p;
    counters_t k = { 0, 0 };
    if (!packet_init(&p, valid, ray))
        return;
    unsigned hit = 0;
    frustum_t f;
    if (kernel == HZ_ACCEL_KERNEL_SIMD_PACKET && __builtin_popcount(p.active) > 1 && frustum_init(&f, &p)) {
        frustum_any(bvh, ctx, &p, &f, &hit, &k);
    } else {
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
    flush(ctx, &k);
}
