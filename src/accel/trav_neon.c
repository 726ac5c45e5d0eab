/*
 * NEON kernels over 4-wide nodes and 4-slot triangle blocks, a lane-for-lane port of trav_avx2.c (keep the two
 * in step):
 *  - single ray: one ray against the 4 child boxes of a node at once, nearest child first; one ray against the
 *    4 triangles of a block at once;
 *  - frustum packet (coherent rays): 4 rays whose direction signs and dominant axes agree are tested against a
 *    node's 4 boxes through the packet's interval bounds (one 4-wide test per node for the whole packet, always
 *    conservative), then leaf triangles against all 4 rays; other packets run as single rays;
 *  - masked packet (incoherent rays): per-lane box tests of each child with lane masks on the stack; subtrees
 *    that only a few lanes reach continue as single rays (active-mask compaction).
 * All use exactly the scalar reference's ray/triangle operations (bvh.h), so results are bit-identical.
 */
#include <arm_neon.h>

#include "bvh.h"

#define W 4
#define MASKED_SWITCH 1 /* masked packet: subtrees reached by this many lanes or fewer go on as single rays */

/* The AVX2 file's operations on 4 lanes. Masks live in float registers as all-ones / all-zero lanes, as they
 * do on x86, so the kernels read the same. */
typedef float32x4_t vq_t;
enum { CMP_LT, CMP_LE, CMP_GT, CMP_GE, CMP_NEQ };
HZ_INLINE vq_t vq_set1_ps(float x) { return vdupq_n_f32(x); }
HZ_INLINE vq_t vq_setzero_ps(void) { return vdupq_n_f32(0.0f); }
HZ_INLINE vq_t vq_load_ps(const float *p) { return vld1q_f32(p); }
HZ_INLINE vq_t vq_loadu_ps(const float *p) { return vld1q_f32(p); }
HZ_INLINE void vq_store_ps(float *p, vq_t v) { vst1q_f32(p, v); }
HZ_INLINE vq_t vq_add_ps(vq_t a, vq_t b) { return vaddq_f32(a, b); }
HZ_INLINE vq_t vq_sub_ps(vq_t a, vq_t b) { return vsubq_f32(a, b); }
HZ_INLINE vq_t vq_mul_ps(vq_t a, vq_t b) { return vmulq_f32(a, b); }
HZ_INLINE vq_t vq_div_ps(vq_t a, vq_t b) { return vdivq_f32(a, b); }
/* maxNum/minNum: a NaN operand drops out, whichever side it is on (x86 needs it first, see bvh.h) */
HZ_INLINE vq_t vq_min_ps(vq_t a, vq_t b) { return vminnmq_f32(a, b); }
HZ_INLINE vq_t vq_max_ps(vq_t a, vq_t b) { return vmaxnmq_f32(a, b); }
HZ_INLINE vq_t vq_cmp_ps(vq_t a, vq_t b, int op)
{
    uint32x4_t m;
    switch (op) {
    case CMP_LT: m = vcltq_f32(a, b); break;
    case CMP_LE: m = vcleq_f32(a, b); break;
    case CMP_GT: m = vcgtq_f32(a, b); break;
    case CMP_GE: m = vcgeq_f32(a, b); break;
    default: m = vmvnq_u32(vceqq_f32(a, b)); break; /* not equal, or unordered */
    }
    return vreinterpretq_f32_u32(m);
}
HZ_INLINE vq_t vq_or_ps(vq_t a, vq_t b)
{
    return vreinterpretq_f32_u32(vorrq_u32(vreinterpretq_u32_f32(a), vreinterpretq_u32_f32(b)));
}
HZ_INLINE vq_t vq_and_ps(vq_t a, vq_t b)
{
    return vreinterpretq_f32_u32(vandq_u32(vreinterpretq_u32_f32(a), vreinterpretq_u32_f32(b)));
}
HZ_INLINE vq_t vq_andnot_ps(vq_t a, vq_t b) /* ~a & b */
{
    return vreinterpretq_f32_u32(vbicq_u32(vreinterpretq_u32_f32(b), vreinterpretq_u32_f32(a)));
}
HZ_INLINE vq_t vq_blendv_ps(vq_t a, vq_t b, vq_t m) /* m ? b : a, m all-ones or all-zero per lane */
{
    return vbslq_f32(vreinterpretq_u32_f32(m), b, a);
}
HZ_INLINE int vq_movemask_ps(vq_t m)
{
    static const uint32_t bits[4] = { 1, 2, 4, 8 };
    return (int)vaddvq_u32(vandq_u32(vreinterpretq_u32_f32(m), vld1q_u32(bits)));
}

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

HZ_INLINE vq_t ld(const hz_bvh_node_t *n, size_t off)
{
    return vq_load_ps((const float *)(const void *)((const char *)n + off));
}

/* ---------------------------------------------------------------------------------------------------------
 * single ray */
typedef struct sray {
    vq_t ox, oy, oz, rdx, rdy, rdz;
    size_t nx, ny, nz, fx, fy, fz; /* byte offsets of the near and far planes in a node */
    /* watertight test */
    vq_t okx, oky, okz, sx, sy, sz, tnear, inf;
    int kx, ky, kz;
} sray_t;

static void sray_init(sray_t *s, const hz_bvh_ray_t *r)
{
    s->ox = vq_set1_ps(r->org[0]);
    s->oy = vq_set1_ps(r->org[1]);
    s->oz = vq_set1_ps(r->org[2]);
    s->rdx = vq_set1_ps(r->rdir[0]);
    s->rdy = vq_set1_ps(r->rdir[1]);
    s->rdz = vq_set1_ps(r->rdir[2]);
    const size_t a = offsetof(hz_bvh_node_t, hi_x) - offsetof(hz_bvh_node_t, lo_x);
    s->nx = offsetof(hz_bvh_node_t, lo_x) + (r->rdir[0] < 0.0f ? a : 0);
    s->ny = offsetof(hz_bvh_node_t, lo_y) + (r->rdir[1] < 0.0f ? a : 0);
    s->nz = offsetof(hz_bvh_node_t, lo_z) + (r->rdir[2] < 0.0f ? a : 0);
    s->fx = offsetof(hz_bvh_node_t, lo_x) + (r->rdir[0] < 0.0f ? 0 : a);
    s->fy = offsetof(hz_bvh_node_t, lo_y) + (r->rdir[1] < 0.0f ? 0 : a);
    s->fz = offsetof(hz_bvh_node_t, lo_z) + (r->rdir[2] < 0.0f ? 0 : a);
    s->kx = r->kx, s->ky = r->ky, s->kz = r->kz;
    s->okx = vq_set1_ps(r->org[r->kx]);
    s->oky = vq_set1_ps(r->org[r->ky]);
    s->okz = vq_set1_ps(r->org[r->kz]);
    s->sx = vq_set1_ps(r->sx);
    s->sy = vq_set1_ps(r->sy);
    s->sz = vq_set1_ps(r->sz);
    s->tnear = vq_set1_ps(r->tnear);
    s->inf = vq_set1_ps(__builtin_inff());
}

HZ_INLINE unsigned node_hit(const hz_bvh_node_t *n, const sray_t *s, vq_t tfar, vq_t *tmin_out)
{
    const vq_t tnx = vq_mul_ps(vq_sub_ps(ld(n, s->nx), s->ox), s->rdx);
    const vq_t tny = vq_mul_ps(vq_sub_ps(ld(n, s->ny), s->oy), s->rdy);
    const vq_t tnz = vq_mul_ps(vq_sub_ps(ld(n, s->nz), s->oz), s->rdz);
    const vq_t tfx = vq_mul_ps(vq_sub_ps(ld(n, s->fx), s->ox), s->rdx);
    const vq_t tfy = vq_mul_ps(vq_sub_ps(ld(n, s->fy), s->oy), s->rdy);
    const vq_t tfz = vq_mul_ps(vq_sub_ps(ld(n, s->fz), s->oz), s->rdz);
    /* NaN-prone slab distances first: max/min return the second operand on NaN (see bvh.h) */
    const vq_t tmin = vq_max_ps(tnz, vq_max_ps(tny, vq_max_ps(tnx, s->tnear)));
    const vq_t tmax = vq_min_ps(
        vq_mul_ps(vq_min_ps(tfz, vq_min_ps(tfy, vq_min_ps(tfx, s->inf))),
                      vq_set1_ps(HZ_BVH_ROBUST)),
        tfar);
    *tmin_out = tmin;
    return (unsigned)vq_movemask_ps(vq_cmp_ps(tmin, tmax, CMP_LE));
}

/* One ray against the slots `lm` of block b: lanes that pass the watertight test with t >= tnear and
 * t <= tfar; t in *t_out. */
HZ_INLINE unsigned leaf_hit(const hz_bvh_block_t *b, unsigned lm, const sray_t *s, float tfar, vq_t *t_out)
{
    const vq_t akx = vq_sub_ps(vq_load_ps(b->v[0][s->kx]), s->okx);
    const vq_t aky = vq_sub_ps(vq_load_ps(b->v[0][s->ky]), s->oky);
    const vq_t akz = vq_sub_ps(vq_load_ps(b->v[0][s->kz]), s->okz);
    const vq_t bkx = vq_sub_ps(vq_load_ps(b->v[1][s->kx]), s->okx);
    const vq_t bky = vq_sub_ps(vq_load_ps(b->v[1][s->ky]), s->oky);
    const vq_t bkz = vq_sub_ps(vq_load_ps(b->v[1][s->kz]), s->okz);
    const vq_t ckx = vq_sub_ps(vq_load_ps(b->v[2][s->kx]), s->okx);
    const vq_t cky = vq_sub_ps(vq_load_ps(b->v[2][s->ky]), s->oky);
    const vq_t ckz = vq_sub_ps(vq_load_ps(b->v[2][s->kz]), s->okz);
    const vq_t ax = vq_sub_ps(akx, vq_mul_ps(s->sx, akz));
    const vq_t ay = vq_sub_ps(aky, vq_mul_ps(s->sy, akz));
    const vq_t bx = vq_sub_ps(bkx, vq_mul_ps(s->sx, bkz));
    const vq_t by = vq_sub_ps(bky, vq_mul_ps(s->sy, bkz));
    const vq_t cx = vq_sub_ps(ckx, vq_mul_ps(s->sx, ckz));
    const vq_t cy = vq_sub_ps(cky, vq_mul_ps(s->sy, ckz));
    const vq_t U = vq_sub_ps(vq_mul_ps(cx, by), vq_mul_ps(cy, bx));
    const vq_t V = vq_sub_ps(vq_mul_ps(ax, cy), vq_mul_ps(ay, cx));
    const vq_t Wv = vq_sub_ps(vq_mul_ps(bx, ay), vq_mul_ps(by, ax));
    const vq_t z = vq_setzero_ps();
    const vq_t neg = vq_or_ps(vq_or_ps(vq_cmp_ps(U, z, CMP_LT), vq_cmp_ps(V, z, CMP_LT)),
                                    vq_cmp_ps(Wv, z, CMP_LT));
    const vq_t pos = vq_or_ps(vq_or_ps(vq_cmp_ps(U, z, CMP_GT), vq_cmp_ps(V, z, CMP_GT)),
                                    vq_cmp_ps(Wv, z, CMP_GT));
    const vq_t det = vq_add_ps(vq_add_ps(U, V), Wv);
    const vq_t ok = vq_andnot_ps(vq_and_ps(neg, pos), vq_cmp_ps(det, z, CMP_NEQ));
    unsigned m = (unsigned)vq_movemask_ps(ok) & lm;
    if (!m)
        return 0;
    const vq_t az = vq_mul_ps(s->sz, akz), bz = vq_mul_ps(s->sz, bkz), cz = vq_mul_ps(s->sz, ckz);
    const vq_t T =
        vq_add_ps(vq_add_ps(vq_mul_ps(U, az), vq_mul_ps(V, bz)), vq_mul_ps(Wv, cz));
    const vq_t t = vq_div_ps(T, det);
    const vq_t in = vq_and_ps(vq_cmp_ps(t, s->tnear, CMP_GE),
                                    vq_cmp_ps(t, vq_set1_ps(tfar), CMP_LE));
    *t_out = t;
    return m & (unsigned)vq_movemask_ps(in);
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
    vq_t tfar = vq_set1_ps(r->tfar);
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            vq_t tmin;
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
                vq_store_ps(d, tmin);
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
            vq_t t;
            COUNT(k, tris, cnt);
            unsigned m = leaf_hit(b, slot_mask(slot, cnt), s, r->tfar, &t);
            if (m) {
                float tv[W] HZ_ALIGNED(32);
                vq_store_ps(tv, t);
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
                tfar = vq_set1_ps(r->tfar);
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
    const vq_t tfar = vq_set1_ps(r->tfar);
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            vq_t tmin;
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
            vq_t t;
            COUNT(k, tris, cnt);
            unsigned m = leaf_hit(b, slot_mask(slot, cnt), s, r->tfar, &t);
            if (m) {
                if (!anyhit)
                    return true;
                float tv[W] HZ_ALIGNED(32);
                vq_store_ps(tv, t);
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

static unsigned packet_init(packet_t *p, const int32_t *valid, const hz_ray4_t *ray)
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
    vq_t on[3], of[3], rmin[3], rmax[3]; /* origins for the near and far planes, reciprocal ranges */
    vq_t tnear;                          /* smallest tnear of the packet */
    /* lanes, for the leaf test */
    vq_t okx, oky, okz, sx, sy, sz, ltnear;
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
        f->on[k] = vq_set1_ps(neg ? omin[k] : omax[k]);
        f->of[k] = vq_set1_ps(neg ? omax[k] : omin[k]);
        f->rmin[k] = vq_set1_ps(rmn[k]);
        f->rmax[k] = vq_set1_ps(rmx[k]);
    }
    f->nx = nn[0], f->ny = nn[1], f->nz = nn[2];
    f->fx = ff[0], f->fy = ff[1], f->fz = ff[2];
    f->tnear = vq_set1_ps(tn);
    f->kx = r0->kx, f->ky = r0->ky, f->kz = r0->kz;
    float okx[W], oky[W], okz[W], sx[W], sy[W], sz[W], ltn[W];
    for (int i = 0; i < W; i++) {
        const hz_bvh_ray_t *r = &p->r[(p->active >> i) & 1u ? i : first];
        okx[i] = r->org[f->kx], oky[i] = r->org[f->ky], okz[i] = r->org[f->kz];
        sx[i] = r->sx, sy[i] = r->sy, sz[i] = r->sz;
        ltn[i] = (p->active >> i) & 1u ? r->tnear : __builtin_inff();
    }
    f->okx = vq_loadu_ps(okx), f->oky = vq_loadu_ps(oky), f->okz = vq_loadu_ps(okz);
    f->sx = vq_loadu_ps(sx), f->sy = vq_loadu_ps(sy), f->sz = vq_loadu_ps(sz);
    f->ltnear = vq_loadu_ps(ltn);
    return true;
}

HZ_INLINE vq_t fr_near(const hz_bvh_node_t *n, size_t off, const frustum_t *f, int k)
{
    const vq_t a = vq_sub_ps(ld(n, off), f->on[k]);
    return vq_min_ps(vq_mul_ps(a, f->rmin[k]), vq_mul_ps(a, f->rmax[k]));
}

HZ_INLINE vq_t fr_far(const hz_bvh_node_t *n, size_t off, const frustum_t *f, int k)
{
    const vq_t a = vq_sub_ps(ld(n, off), f->of[k]);
    return vq_max_ps(vq_mul_ps(a, f->rmin[k]), vq_mul_ps(a, f->rmax[k]));
}

HZ_INLINE unsigned fr_node_hit(const hz_bvh_node_t *n, const frustum_t *f, vq_t tfar_max, vq_t *tmin_out)
{
    const vq_t tmin = vq_max_ps(vq_max_ps(fr_near(n, f->nx, f, 0), fr_near(n, f->ny, f, 1)),
                                      vq_max_ps(fr_near(n, f->nz, f, 2), f->tnear));
    const vq_t tmax = vq_min_ps(
        vq_mul_ps(vq_min_ps(vq_min_ps(fr_far(n, f->fx, f, 0), fr_far(n, f->fy, f, 1)),
                                    fr_far(n, f->fz, f, 2)),
                      vq_set1_ps(HZ_BVH_ROBUST)),
        tfar_max);
    *tmin_out = tmin;
    return (unsigned)vq_movemask_ps(vq_cmp_ps(tmin, tmax, CMP_LE));
}

/* One triangle (block slot s) against the packet's lanes: lanes with a watertight hit at t in [tnear, tfar]. */
HZ_INLINE unsigned fr_tri_hit(const hz_bvh_block_t *b, unsigned s, const frustum_t *f, vq_t tfar, vq_t *t_out)
{
    const vq_t akx = vq_sub_ps(vq_set1_ps(b->v[0][f->kx][s]), f->okx);
    const vq_t aky = vq_sub_ps(vq_set1_ps(b->v[0][f->ky][s]), f->oky);
    const vq_t akz = vq_sub_ps(vq_set1_ps(b->v[0][f->kz][s]), f->okz);
    const vq_t bkx = vq_sub_ps(vq_set1_ps(b->v[1][f->kx][s]), f->okx);
    const vq_t bky = vq_sub_ps(vq_set1_ps(b->v[1][f->ky][s]), f->oky);
    const vq_t bkz = vq_sub_ps(vq_set1_ps(b->v[1][f->kz][s]), f->okz);
    const vq_t ckx = vq_sub_ps(vq_set1_ps(b->v[2][f->kx][s]), f->okx);
    const vq_t cky = vq_sub_ps(vq_set1_ps(b->v[2][f->ky][s]), f->oky);
    const vq_t ckz = vq_sub_ps(vq_set1_ps(b->v[2][f->kz][s]), f->okz);
    const vq_t ax = vq_sub_ps(akx, vq_mul_ps(f->sx, akz));
    const vq_t ay = vq_sub_ps(aky, vq_mul_ps(f->sy, akz));
    const vq_t bx = vq_sub_ps(bkx, vq_mul_ps(f->sx, bkz));
    const vq_t by = vq_sub_ps(bky, vq_mul_ps(f->sy, bkz));
    const vq_t cx = vq_sub_ps(ckx, vq_mul_ps(f->sx, ckz));
    const vq_t cy = vq_sub_ps(cky, vq_mul_ps(f->sy, ckz));
    const vq_t U = vq_sub_ps(vq_mul_ps(cx, by), vq_mul_ps(cy, bx));
    const vq_t V = vq_sub_ps(vq_mul_ps(ax, cy), vq_mul_ps(ay, cx));
    const vq_t Wv = vq_sub_ps(vq_mul_ps(bx, ay), vq_mul_ps(by, ax));
    const vq_t z = vq_setzero_ps();
    const vq_t neg = vq_or_ps(vq_or_ps(vq_cmp_ps(U, z, CMP_LT), vq_cmp_ps(V, z, CMP_LT)),
                                    vq_cmp_ps(Wv, z, CMP_LT));
    const vq_t pos = vq_or_ps(vq_or_ps(vq_cmp_ps(U, z, CMP_GT), vq_cmp_ps(V, z, CMP_GT)),
                                    vq_cmp_ps(Wv, z, CMP_GT));
    const vq_t det = vq_add_ps(vq_add_ps(U, V), Wv);
    const vq_t ok = vq_andnot_ps(vq_and_ps(neg, pos), vq_cmp_ps(det, z, CMP_NEQ));
    unsigned m = (unsigned)vq_movemask_ps(ok);
    if (!m)
        return 0;
    const vq_t az = vq_mul_ps(f->sz, akz), bz = vq_mul_ps(f->sz, bkz), cz = vq_mul_ps(f->sz, ckz);
    const vq_t T =
        vq_add_ps(vq_add_ps(vq_mul_ps(U, az), vq_mul_ps(V, bz)), vq_mul_ps(Wv, cz));
    const vq_t t = vq_div_ps(T, det);
    const vq_t in =
        vq_and_ps(vq_cmp_ps(t, f->ltnear, CMP_GE), vq_cmp_ps(t, tfar, CMP_LE));
    *t_out = t;
    return m & (unsigned)vq_movemask_ps(in);
}

HZ_INLINE float hmax8(vq_t v)
{
    return vmaxvq_f32(v);
}

HZ_INLINE float hmin8(vq_t v)
{
    return vminvq_f32(v);
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
    vq_t tfar = vq_load_ps(tfa);
    float tfar_max = hmax8(tfar);
    vq_t vtfar_max = vq_set1_ps(tfar_max);
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            vq_t tmin;
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
                vq_store_ps(d, tmin);
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
                vq_t t;
                unsigned m = fr_tri_hit(b, s, f, tfar, &t) & p->active;
                if (!m)
                    continue;
                const uint32_t pw = b->prim[s], prim = pw & HZ_BVH_PRIM_MASK, hs = (slot / W) * W + s;
                float tv[W] HZ_ALIGNED(32);
                vq_store_ps(tv, t);
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
                tfar = vq_load_ps(tfa);
                tfar_max = hmax8(tfar);
                vtfar_max = vq_set1_ps(tfar_max);
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
    vq_t tfar = vq_load_ps(tfa);
    vq_t vtfar_max = vq_set1_ps(hmax8(tfar));
    unsigned live = p->active;
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            vq_t tmin;
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
                vq_t t;
                unsigned m = fr_tri_hit(b, s, f, tfar, &t) & live;
                if (!m)
                    continue;
                const uint32_t pw = b->prim[s], hs = (slot / W) * W + s;
                if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT)) {
                    float tv[W] HZ_ALIGNED(32);
                    vq_store_ps(tv, t);
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
                tfar = vq_load_ps(tfa);
                vtfar_max = vq_set1_ps(hmax8(tfar));
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
    const vq_t vox = vq_loadu_ps(ox), voy = vq_loadu_ps(oy), voz = vq_loadu_ps(oz);
    const vq_t vrx = vq_loadu_ps(rx), vry = vq_loadu_ps(ry), vrz = vq_loadu_ps(rz);
    const vq_t vtn = vq_loadu_ps(tn), robust = vq_set1_ps(HZ_BVH_ROBUST);
    const vq_t vinf = vq_set1_ps(__builtin_inff()), zero = vq_setzero_ps();
    const vq_t negx = vq_cmp_ps(vrx, zero, CMP_LT), negy = vq_cmp_ps(vry, zero, CMP_LT);
    const vq_t negz = vq_cmp_ps(vrz, zero, CMP_LT);
    vq_t tfar = vq_load_ps(tfa);
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
            tfar = vq_load_ps(tfa);
        } else if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            COUNT(k, nodes, 1);
            mentry_t h[W];
            int c = 0;
            for (int j = 0; j < W; j++) {
                if (n->child[j] == HZ_BVH_EMPTY)
                    continue;
                const vq_t t0x = vq_mul_ps(vq_sub_ps(vq_set1_ps(n->lo_x[j]), vox), vrx);
                const vq_t t1x = vq_mul_ps(vq_sub_ps(vq_set1_ps(n->hi_x[j]), vox), vrx);
                const vq_t t0y = vq_mul_ps(vq_sub_ps(vq_set1_ps(n->lo_y[j]), voy), vry);
                const vq_t t1y = vq_mul_ps(vq_sub_ps(vq_set1_ps(n->hi_y[j]), voy), vry);
                const vq_t t0z = vq_mul_ps(vq_sub_ps(vq_set1_ps(n->lo_z[j]), voz), vrz);
                const vq_t t1z = vq_mul_ps(vq_sub_ps(vq_set1_ps(n->hi_z[j]), voz), vrz);
                /* near/far by the sign of each lane's direction, NaN-prone values first (see bvh.h) */
                const vq_t tnx = vq_blendv_ps(t0x, t1x, negx), tfx = vq_blendv_ps(t1x, t0x, negx);
                const vq_t tny = vq_blendv_ps(t0y, t1y, negy), tfy = vq_blendv_ps(t1y, t0y, negy);
                const vq_t tnz = vq_blendv_ps(t0z, t1z, negz), tfz = vq_blendv_ps(t1z, t0z, negz);
                const vq_t tmin = vq_max_ps(tnz, vq_max_ps(tny, vq_max_ps(tnx, vtn)));
                const vq_t tmax = vq_min_ps(
                    vq_mul_ps(vq_min_ps(tfz, vq_min_ps(tfy, vq_min_ps(tfx, vinf))), robust), tfar);
                const vq_t hit = vq_cmp_ps(tmin, tmax, CMP_LE);
                unsigned m = (unsigned)vq_movemask_ps(hit) & lanes;
                if (!m)
                    continue;
                float d = hmin8(vq_blendv_ps(vq_set1_ps(__builtin_inff()), tmin, hit));
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
                vq_t t;
                unsigned m = leaf_hit(b, slot_mask(slot, cnt), &sr[i], r->tfar, &t);
                if (!m)
                    continue;
                float tv[W] HZ_ALIGNED(32);
                vq_store_ps(tv, t);
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
            tfar = vq_load_ps(tfa);
        }
        /* pop, dropping lanes whose best hit is already closer than the subtree */
        for (;;) {
            if (sp == 0)
                return;
            mentry_t e = stack[--sp];
            unsigned m = e.m & (unsigned)vq_movemask_ps(vq_cmp_ps(vq_set1_ps(e.d), tfar, CMP_LE));
            if (m) {
                cur = e.c;
                lanes = m;
                break;
            }
        }
    }
}

static void write_hits(const hz_bvh_t *bvh, const packet_t *p, hz_rayhit4_t *rh)
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

void hz_bvh_simd_intersectw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_rayhit4_t *rh,
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

void hz_bvh_simd_occludedw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_ray4_t *ray,
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
