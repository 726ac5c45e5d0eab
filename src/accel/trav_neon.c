/*
 * NEON kernels over 4-wide nodes and 4-slot triangle blocks (AArch64):
 *  - single ray: one ray against the 4 child boxes of a node at once, nearest child first; one ray against the
 *    4 triangles of a block at once;
 *  - frustum packet (coherent rays): 4 rays whose direction signs and watertight-test axes agree are tested
 *    against a node's boxes through the packet's interval bounds; leaf children are tested right away against
 *    the lanes whose own slab test reaches them; other packets run as single rays;
 *  - the masked form (HZ_ACCEL_KERNEL_SIMD_MASKED) runs single rays here: with 4 lanes, per-lane box tests of
 *    every child cost as much as the single-ray traversals they would replace.
 * The same float operations as the scalar reference (bvh.h), so results are bit-identical. The structure
 * follows trav_avx2.c; NEON's maxNum/minNum drop a NaN operand on either side (see bvh.h).
 */
#include <arm_neon.h>

#include "bvh.h"

#define W 4

HZ_INLINE unsigned movemask(uint32x4_t m)
{
    static const uint32_t bits[4] = { 1, 2, 4, 8 };
    return vaddvq_u32(vandq_u32(m, vld1q_u32(bits)));
}

HZ_INLINE float32x4_t ld(const hz_bvh_node_t *n, size_t off)
{
    return vld1q_f32((const float *)(const void *)((const char *)n + off));
}

HZ_INLINE unsigned slot_mask(uint32_t slot, uint32_t n)
{
    return ((1u << n) - 1u) << (slot % W);
}

/* The watertight test of 4 triangles (or one triangle's broadcast vertices against 4 rays): lanes that pass the
 * edge tests with det != 0, and t, V, W, det (the scalar reference's operations, lane by lane). */
HZ_INLINE unsigned woop4(float32x4_t akx, float32x4_t aky, float32x4_t akz, float32x4_t bkx, float32x4_t bky,
                         float32x4_t bkz, float32x4_t ckx, float32x4_t cky, float32x4_t ckz, float32x4_t sx,
                         float32x4_t sy, float32x4_t sz, float32x4_t *t, float32x4_t *v, float32x4_t *w,
                         float32x4_t *det)
{
    const float32x4_t ax = vsubq_f32(akx, vmulq_f32(sx, akz)), ay = vsubq_f32(aky, vmulq_f32(sy, akz));
    const float32x4_t bx = vsubq_f32(bkx, vmulq_f32(sx, bkz)), by = vsubq_f32(bky, vmulq_f32(sy, bkz));
    const float32x4_t cx = vsubq_f32(ckx, vmulq_f32(sx, ckz)), cy = vsubq_f32(cky, vmulq_f32(sy, ckz));
    const float32x4_t U = vsubq_f32(vmulq_f32(cx, by), vmulq_f32(cy, bx));
    const float32x4_t V = vsubq_f32(vmulq_f32(ax, cy), vmulq_f32(ay, cx));
    const float32x4_t Wv = vsubq_f32(vmulq_f32(bx, ay), vmulq_f32(by, ax));
    const float32x4_t z = vdupq_n_f32(0.0f);
    const uint32x4_t neg = vorrq_u32(vorrq_u32(vcltq_f32(U, z), vcltq_f32(V, z)), vcltq_f32(Wv, z));
    const uint32x4_t pos = vorrq_u32(vorrq_u32(vcgtq_f32(U, z), vcgtq_f32(V, z)), vcgtq_f32(Wv, z));
    const float32x4_t d = vaddq_f32(vaddq_f32(U, V), Wv);
    const uint32x4_t ok = vbicq_u32(vmvnq_u32(vceqq_f32(d, z)), vandq_u32(neg, pos));
    const unsigned m = movemask(ok);
    if (!m)
        return 0;
    /* t from the plane, as hz_bvh_tri_test (see there), operation for operation */
    const float32x4_t e1x = vsubq_f32(bkx, akx), e1y = vsubq_f32(bky, aky), e1z = vsubq_f32(bkz, akz);
    const float32x4_t e2x = vsubq_f32(ckx, akx), e2y = vsubq_f32(cky, aky), e2z = vsubq_f32(ckz, akz);
    const float32x4_t nx = vsubq_f32(vmulq_f32(e1y, e2z), vmulq_f32(e1z, e2y));
    const float32x4_t ny = vsubq_f32(vmulq_f32(e1z, e2x), vmulq_f32(e1x, e2z));
    const float32x4_t nz = vsubq_f32(vmulq_f32(e1x, e2y), vmulq_f32(e1y, e2x));
    const float32x4_t num = vaddq_f32(vaddq_f32(vmulq_f32(nx, akx), vmulq_f32(ny, aky)), vmulq_f32(nz, akz));
    const float32x4_t den = vaddq_f32(vaddq_f32(vmulq_f32(nx, sx), vmulq_f32(ny, sy)), nz);
    const float32x4_t tt = vdivq_f32(vmulq_f32(num, sz), den);
    *t = tt, *v = V, *w = Wv, *det = d;
    return m & movemask(vcltq_f32(vabsq_f32(tt), vdupq_n_f32(__builtin_inff())));
}

/* ---------------------------------------------------------------------------------------------------------
 * single ray */
typedef struct sray {
    float32x4_t ox, oy, oz, rdx, rdy, rdz, tnear, inf;
    size_t nx, ny, nz, fx, fy, fz;
    float32x4_t okx, oky, okz, sx, sy, sz;
    int kx, ky, kz;
} sray_t;

static void sray_init(sray_t *s, const hz_bvh_ray_t *r)
{
    s->ox = vdupq_n_f32(r->org[0]), s->oy = vdupq_n_f32(r->org[1]), s->oz = vdupq_n_f32(r->org[2]);
    s->rdx = vdupq_n_f32(r->rdir[0]), s->rdy = vdupq_n_f32(r->rdir[1]), s->rdz = vdupq_n_f32(r->rdir[2]);
    const size_t a = offsetof(hz_bvh_node_t, hi_x) - offsetof(hz_bvh_node_t, lo_x);
    s->nx = offsetof(hz_bvh_node_t, lo_x) + (r->rdir[0] < 0.0f ? a : 0);
    s->ny = offsetof(hz_bvh_node_t, lo_y) + (r->rdir[1] < 0.0f ? a : 0);
    s->nz = offsetof(hz_bvh_node_t, lo_z) + (r->rdir[2] < 0.0f ? a : 0);
    s->fx = offsetof(hz_bvh_node_t, lo_x) + (r->rdir[0] < 0.0f ? 0 : a);
    s->fy = offsetof(hz_bvh_node_t, lo_y) + (r->rdir[1] < 0.0f ? 0 : a);
    s->fz = offsetof(hz_bvh_node_t, lo_z) + (r->rdir[2] < 0.0f ? 0 : a);
    s->kx = r->kx, s->ky = r->ky, s->kz = r->kz;
    s->okx = vdupq_n_f32(r->org[r->kx]), s->oky = vdupq_n_f32(r->org[r->ky]), s->okz = vdupq_n_f32(r->org[r->kz]);
    s->sx = vdupq_n_f32(r->sx), s->sy = vdupq_n_f32(r->sy), s->sz = vdupq_n_f32(r->sz);
    s->tnear = vdupq_n_f32(r->tnear);
    s->inf = vdupq_n_f32(__builtin_inff());
}

HZ_INLINE unsigned node_hit(const hz_bvh_node_t *n, const sray_t *s, float32x4_t cull, float32x4_t *tmin_out)
{
    const float32x4_t tnx = vmulq_f32(vsubq_f32(ld(n, s->nx), s->ox), s->rdx);
    const float32x4_t tny = vmulq_f32(vsubq_f32(ld(n, s->ny), s->oy), s->rdy);
    const float32x4_t tnz = vmulq_f32(vsubq_f32(ld(n, s->nz), s->oz), s->rdz);
    const float32x4_t tfx = vmulq_f32(vsubq_f32(ld(n, s->fx), s->ox), s->rdx);
    const float32x4_t tfy = vmulq_f32(vsubq_f32(ld(n, s->fy), s->oy), s->rdy);
    const float32x4_t tfz = vmulq_f32(vsubq_f32(ld(n, s->fz), s->oz), s->rdz);
    const float32x4_t tmin = vmaxnmq_f32(vmaxnmq_f32(tnx, tny), vmaxnmq_f32(tnz, s->tnear));
    const float32x4_t tmax =
        vminnmq_f32(vmulq_f32(vminnmq_f32(vminnmq_f32(tfx, tfy), tfz), vdupq_n_f32(HZ_BVH_ROBUST)), cull);
    *tmin_out = tmin;
    return movemask(vcleq_f32(tmin, tmax));
}

HZ_INLINE unsigned leaf_hit(const hz_bvh_block_t *b, unsigned lm, const sray_t *s, float tfar, float32x4_t *t,
                            float32x4_t *v, float32x4_t *w, float32x4_t *det)
{
    unsigned m = woop4(vsubq_f32(vld1q_f32(b->v[0][s->kx]), s->okx), vsubq_f32(vld1q_f32(b->v[0][s->ky]), s->oky),
                       vsubq_f32(vld1q_f32(b->v[0][s->kz]), s->okz), vsubq_f32(vld1q_f32(b->v[1][s->kx]), s->okx),
                       vsubq_f32(vld1q_f32(b->v[1][s->ky]), s->oky), vsubq_f32(vld1q_f32(b->v[1][s->kz]), s->okz),
                       vsubq_f32(vld1q_f32(b->v[2][s->kx]), s->okx), vsubq_f32(vld1q_f32(b->v[2][s->ky]), s->oky),
                       vsubq_f32(vld1q_f32(b->v[2][s->kz]), s->okz), s->sx, s->sy, s->sz, t, v, w, det) &
                 lm;
    if (!m)
        return 0;
    return m & movemask(vandq_u32(vcgeq_f32(*t, s->tnear), vcleq_f32(*t, vdupq_n_f32(tfar))));
}

/* The hit children of a node: the nearest becomes *cur, the others go on the stack farthest first. */
HZ_INLINE void order_children(const hz_bvh_node_t *n, unsigned m, float32x4_t tmin, uint32_t *cur, uint32_t *st_c,
                              float *st_d, int *sp)
{
    if (!(m & (m - 1))) {
        *cur = n->child[__builtin_ctz(m)];
        return;
    }
    float d[W];
    vst1q_f32(d, tmin);
    unsigned idx[W], c = 0;
    for (unsigned mm = m; mm; mm &= mm - 1) {
        unsigned i = (unsigned)__builtin_ctz(mm), j = c++;
        while (j > 0 && d[idx[j - 1]] < d[i]) { /* descending: nearest last */
            idx[j] = idx[j - 1];
            j--;
        }
        idx[j] = i;
    }
    for (unsigned i = 0; i + 1 < c; i++) {
        st_c[*sp] = n->child[idx[i]];
        st_d[*sp] = d[idx[i]];
        (*sp)++;
    }
    *cur = n->child[idx[c - 1]];
}

/* Motion: the node and the block as the ray sees them at its time, with hz_bvh_node_at / hz_bvh_block_at's
 * operations (g = 1 - f in scalar, then g * a + f * b lane by lane with separate vmulq/vaddq, no FMA):
 * bit-identical to the scalar kernel. */
HZ_INLINE float32x4_t lerp4(float32x4_t g, float32x4_t f, const float *a, const float *b)
{
    return vaddq_f32(vmulq_f32(g, vld1q_f32(a)), vmulq_f32(f, vld1q_f32(b)));
}

HZ_INLINE const hz_bvh_node_t *node_at(const hz_bvh_t *bvh, uint32_t i, const hz_bvh_ray_t *r, hz_bvh_node_t *tmp)
{
    if (!bvh->key_boxes)
        return &bvh->nodes[i];
    const float *a = bvh->mbox[(size_t)i * bvh->time_keys + r->seg].lo_x, *b = a + 6 * W;
    const float32x4_t f = vdupq_n_f32(r->f), g = vdupq_n_f32(1.0f - r->f);
    for (int j = 0; j < 6; j++)
        vst1q_f32(tmp->lo_x + W * j, lerp4(g, f, a + W * j, b + W * j));
    vst1q_u32(tmp->child, vld1q_u32(bvh->nodes[i].child));
    return tmp;
}

HZ_INLINE const hz_bvh_block_t *block_at(const hz_bvh_t *bvh, uint32_t blk, const hz_bvh_ray_t *r,
                                         hz_bvh_block_t *tmp)
{
    const float *a = &bvh->kblocks[r->seg][blk].v[0][0][0], *b = &bvh->kblocks[r->seg + 1u][blk].v[0][0][0];
    const float32x4_t f = vdupq_n_f32(r->f), g = vdupq_n_f32(1.0f - r->f);
    for (int j = 0; j < 9; j++)
        vst1q_f32(&tmp->v[0][0][0] + W * j, lerp4(g, f, a + W * j, b + W * j));
    vst1q_u32(tmp->prim, vld1q_u32(bvh->kblocks[r->seg][blk].prim));
    return tmp;
}

/* `motion` is a constant at every call: the static instance is the plain loop. */
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
    float32x4_t cull = vdupq_n_f32(r->tfar * HZ_BVH_CULL); /* see bvh.h */
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = motion ? node_at(bvh, cur, r, &ntmp) : &bvh->nodes[cur];
            float32x4_t tmin;
            HZ_BVH_COUNT(k, nodes, 1);
            unsigned m = node_hit(n, s, cull, &tmin);
            if (m) {
                order_children(n, m, tmin, &cur, st_c, st_d, &sp);
                continue;
            }
        } else {
            const uint32_t slot = hz_bvh_leaf_slot(cur), cnt = hz_bvh_leaf_count(cur);
            const hz_bvh_block_t *b = motion ? block_at(bvh, slot / W, r, &btmp) : &bvh->blocks[slot / W];
            float32x4_t t, V, Wv, det;
            HZ_BVH_COUNT(k, tris, cnt);
            unsigned m = leaf_hit(b, slot_mask(slot, cnt), s, r->tfar, &t, &V, &Wv, &det);
            if (m) {
                float tv[W], vv[W], wv[W], dv[W];
                vst1q_f32(tv, t), vst1q_f32(vv, V), vst1q_f32(wv, Wv), vst1q_f32(dv, det);
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
                cull = vdupq_n_f32(r->tfar * HZ_BVH_CULL);
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

static void closest_from(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, const sray_t *s, uint32_t start,
                         hz_bvh_best_t *best, uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    closest_core(bvh, ctx, r, s, start, best, ray_id, lane, k, false);
}

void hz_bvh_simd_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, hz_bvh_best_t *best,
                         uint32_t ray_id, int lane)
{
    sray_t s;
    hz_bvh_counters_t k = { 0, 0 };
    sray_init(&s, r);
    if (bvh->time_keys)
        closest_core(bvh, ctx, r, &s, 0, best, ray_id, lane, &k, true);
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
    uint32_t stack[HZ_BVH_STACK + W];
    int sp = 0;
    uint32_t cur = start;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    const float32x4_t cull = vdupq_n_f32(r->tfar * HZ_BVH_CULL);
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = motion ? node_at(bvh, cur, r, &ntmp) : &bvh->nodes[cur];
            float32x4_t tmin;
            HZ_BVH_COUNT(k, nodes, 1);
            unsigned m = node_hit(n, s, cull, &tmin);
            if (m) {
                cur = n->child[__builtin_ctz(m)];
                for (m &= m - 1; m; m &= m - 1)
                    stack[sp++] = n->child[__builtin_ctz(m)];
                continue;
            }
        } else {
            const uint32_t slot = hz_bvh_leaf_slot(cur), cnt = hz_bvh_leaf_count(cur);
            const hz_bvh_block_t *b = motion ? block_at(bvh, slot / W, r, &btmp) : &bvh->blocks[slot / W];
            float32x4_t t, V, Wv, det;
            HZ_BVH_COUNT(k, tris, cnt);
            unsigned m = leaf_hit(b, slot_mask(slot, cnt), s, r->tfar, &t, &V, &Wv, &det);
            if (m) {
                if (!anyhit)
                    return true;
                float tv[W];
                vst1q_f32(tv, t);
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
        cur = stack[--sp];
    }
}

static bool any_from_node(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, const sray_t *s,
                          uint32_t start, uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    return any_core(bvh, ctx, r, s, start, ray_id, lane, k, false);
}

bool hz_bvh_simd_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, uint32_t ray_id, int lane)
{
    sray_t s;
    hz_bvh_counters_t k = { 0, 0 };
    sray_init(&s, r);
    bool hit = bvh->time_keys ? any_core(bvh, ctx, r, &s, 0, ray_id, lane, &k, true)
                              : any_from_node(bvh, ctx, r, &s, 0, ray_id, lane, &k);
    hz_bvh_counters_flush(ctx, &k);
    return hit;
}

/* ---------------------------------------------------------------------------------------------------------
 * packets of 4 */
typedef struct packet {
    hz_bvh_ray_t r[W];
    unsigned active;
    uint32_t id[W];
    hz_bvh_best_t best[W];
} packet_t;

static unsigned packet_init(packet_t *p, const int32_t *valid, const hz_ray4_t *ray)
{
    p->active = 0;
    for (int i = 0; i < W; i++) {
        hz_bvh_best_init(&p->best[i]);
        p->id[i] = ray->id[i];
        if (valid[i] && hz_bvh_ray_prep(&p->r[i], ray->org_x[i], ray->org_y[i], ray->org_z[i], ray->dir_x[i],
                                        ray->dir_y[i], ray->dir_z[i], ray->tnear[i], ray->tfar[i]))
            p->active |= 1u << i;
    }
    return p->active;
}

/* Frustum form: every active lane shares the direction signs and (kx, ky, kz), reciprocals are finite. */
typedef struct frustum {
    size_t nx, ny, nz, fx, fy, fz;
    float32x4_t on[3], of[3], rmin[3], rmax[3], tnear;
    float32x4_t o[3], r[3], okx, oky, okz, sx, sy, sz, ltnear;
    int kx, ky, kz;
} frustum_t;

static bool frustum_init(frustum_t *f, const packet_t *p, unsigned active)
{
    if (__builtin_popcount(active) < 2)
        return false;
    const int first = __builtin_ctz(active);
    const hz_bvh_ray_t *r0 = &p->r[first];
    float omin[3], omax[3], rmn[3], rmx[3], tn = r0->tnear;
    for (int k = 0; k < 3; k++)
        omin[k] = omax[k] = r0->org[k], rmn[k] = rmx[k] = r0->rdir[k];
    for (unsigned m = active; m; m &= m - 1) {
        const hz_bvh_ray_t *r = &p->r[__builtin_ctz(m)];
        if (r->kx != r0->kx || r->ky != r0->ky || r->kz != r0->kz)
            return false;
        for (int k = 0; k < 3; k++) {
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
        f->on[k] = vdupq_n_f32(neg ? omin[k] : omax[k]);
        f->of[k] = vdupq_n_f32(neg ? omax[k] : omin[k]);
        f->rmin[k] = vdupq_n_f32(rmn[k]);
        f->rmax[k] = vdupq_n_f32(rmx[k]);
    }
    f->nx = nn[0], f->ny = nn[1], f->nz = nn[2];
    f->fx = ff[0], f->fy = ff[1], f->fz = ff[2];
    f->tnear = vdupq_n_f32(tn);
    f->kx = r0->kx, f->ky = r0->ky, f->kz = r0->kz;
    float o[3][W], rr[3][W], okx[W], oky[W], okz[W], sx[W], sy[W], sz[W], ltn[W];
    for (int i = 0; i < W; i++) {
        const bool on = (active >> i) & 1u;
        const hz_bvh_ray_t *r = &p->r[on ? i : first];
        for (int k = 0; k < 3; k++)
            o[k][i] = r->org[k], rr[k][i] = r->rdir[k];
        okx[i] = r->org[f->kx], oky[i] = r->org[f->ky], okz[i] = r->org[f->kz];
        sx[i] = r->sx, sy[i] = r->sy, sz[i] = r->sz;
        ltn[i] = on ? r->tnear : __builtin_inff();
    }
    for (int k = 0; k < 3; k++)
        f->o[k] = vld1q_f32(o[k]), f->r[k] = vld1q_f32(rr[k]);
    f->okx = vld1q_f32(okx), f->oky = vld1q_f32(oky), f->okz = vld1q_f32(okz);
    f->sx = vld1q_f32(sx), f->sy = vld1q_f32(sy), f->sz = vld1q_f32(sz);
    f->ltnear = vld1q_f32(ltn);
    return true;
}

HZ_INLINE float32x4_t fr_near(const hz_bvh_node_t *n, size_t off, const frustum_t *f, int k)
{
    const float32x4_t a = vsubq_f32(ld(n, off), f->on[k]);
    return vminnmq_f32(vmulq_f32(a, f->rmin[k]), vmulq_f32(a, f->rmax[k]));
}

HZ_INLINE float32x4_t fr_far(const hz_bvh_node_t *n, size_t off, const frustum_t *f, int k)
{
    const float32x4_t a = vsubq_f32(ld(n, off), f->of[k]);
    return vmaxnmq_f32(vmulq_f32(a, f->rmin[k]), vmulq_f32(a, f->rmax[k]));
}

HZ_INLINE unsigned fr_node_hit(const hz_bvh_node_t *n, const frustum_t *f, float32x4_t cull, float32x4_t *tmin_out)
{
    const float32x4_t tmin = vmaxnmq_f32(vmaxnmq_f32(fr_near(n, f->nx, f, 0), fr_near(n, f->ny, f, 1)),
                                         vmaxnmq_f32(fr_near(n, f->nz, f, 2), f->tnear));
    const float32x4_t tmax = vminnmq_f32(
        vmulq_f32(vminnmq_f32(vminnmq_f32(fr_far(n, f->fx, f, 0), fr_far(n, f->fy, f, 1)), fr_far(n, f->fz, f, 2)),
                  vdupq_n_f32(HZ_BVH_ROBUST)),
        cull);
    *tmin_out = tmin;
    return movemask(vcleq_f32(tmin, tmax));
}

/* Lanes whose own ray reaches child j of n within [tnear, cull[lane]]. */
HZ_INLINE unsigned fr_lanes_hit(const hz_bvh_node_t *n, unsigned j, const frustum_t *f, float32x4_t cull)
{
    const char *c = (const char *)n + 4u * j;
#define PLANE(off) vdupq_n_f32(*(const float *)(const void *)(c + (off)))
    const float32x4_t tnx = vmulq_f32(vsubq_f32(PLANE(f->nx), f->o[0]), f->r[0]);
    const float32x4_t tny = vmulq_f32(vsubq_f32(PLANE(f->ny), f->o[1]), f->r[1]);
    const float32x4_t tnz = vmulq_f32(vsubq_f32(PLANE(f->nz), f->o[2]), f->r[2]);
    const float32x4_t tfx = vmulq_f32(vsubq_f32(PLANE(f->fx), f->o[0]), f->r[0]);
    const float32x4_t tfy = vmulq_f32(vsubq_f32(PLANE(f->fy), f->o[1]), f->r[1]);
    const float32x4_t tfz = vmulq_f32(vsubq_f32(PLANE(f->fz), f->o[2]), f->r[2]);
#undef PLANE
    const float32x4_t tmin = vmaxnmq_f32(vmaxnmq_f32(tnx, tny), vmaxnmq_f32(tnz, f->ltnear));
    const float32x4_t tmax =
        vminnmq_f32(vmulq_f32(vminnmq_f32(vminnmq_f32(tfx, tfy), tfz), vdupq_n_f32(HZ_BVH_ROBUST)), cull);
    return movemask(vcleq_f32(tmin, tmax));
}

/* One triangle against the packet's lanes `lm`. */
HZ_INLINE unsigned fr_tri_hit(const hz_bvh_block_t *b, unsigned s, const frustum_t *f, float32x4_t tfar, unsigned lm,
                              float32x4_t *t, float32x4_t *v, float32x4_t *w, float32x4_t *det)
{
#define VB(vtx, k) vsubq_f32(vdupq_n_f32(b->v[vtx][f->k][s]), f->o##k)
    unsigned m = woop4(VB(0, kx), VB(0, ky), VB(0, kz), VB(1, kx), VB(1, ky), VB(1, kz), VB(2, kx), VB(2, ky),
                       VB(2, kz), f->sx, f->sy, f->sz, t, v, w, det);
#undef VB
    m &= lm;
    if (!m)
        return 0;
    return m & movemask(vandq_u32(vcgeq_f32(*t, f->ltnear), vcleq_f32(*t, tfar)));
}

static void lanes_tfar(const packet_t *p, float *tf)
{
    for (int i = 0; i < W; i++)
        tf[i] = (p->active >> i) & 1u ? p->r[i].tfar : -__builtin_inff();
}

static void frustum_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, packet_t *p, const frustum_t *f,
                            hz_bvh_counters_t *k)
{
    (void)k; /* counters exist only with HZ_FEATURE_STATS */
    uint32_t st_c[HZ_BVH_STACK + W];
    float st_d[HZ_BVH_STACK + W];
    int sp = 0;
    uint32_t cur = 0;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    float tfa[W];
    lanes_tfar(p, tfa);
    float32x4_t tfar = vld1q_f32(tfa);
    float cull_max = vmaxvq_f32(tfar) * HZ_BVH_CULL;
    for (;;) {
        const hz_bvh_node_t *n = &bvh->nodes[cur]; /* always an inner node: leaves are tested from their parent */
        float32x4_t tmin;
        HZ_BVH_COUNT(k, nodes, 1);
        unsigned m = fr_node_hit(n, f, vdupq_n_f32(cull_max), &tmin);
        unsigned leafbits = 0;
        for (int j = 0; j < W; j++)
            leafbits |= (unsigned)((m >> j) & 1u && hz_bvh_is_leaf(n->child[j])) << j;
        float d[W];
        vst1q_f32(d, tmin);
        unsigned order[W], nl = 0;
        for (unsigned lb = leafbits; lb; lb &= lb - 1) {
            unsigned j = (unsigned)__builtin_ctz(lb), q = nl++;
            while (q > 0 && d[order[q - 1]] > d[j]) {
                order[q] = order[q - 1];
                q--;
            }
            order[q] = j;
        }
        for (unsigned q = 0; q < nl && d[order[q]] <= cull_max; q++) {
            const unsigned j = order[q];
            const unsigned lanes =
                fr_lanes_hit(n, j, f, vmulq_f32(tfar, vdupq_n_f32(HZ_BVH_CULL))) & p->active;
            if (!lanes)
                continue;
            const uint32_t cw = n->child[j], slot = hz_bvh_leaf_slot(cw), cnt = hz_bvh_leaf_count(cw);
            const hz_bvh_block_t *b = &bvh->blocks[slot / W];
            HZ_BVH_COUNT(k, tris, (uint64_t)cnt * (uint64_t)__builtin_popcount(lanes));
            for (unsigned s = slot % W; s < slot % W + cnt; s++) {
                float32x4_t t, V, Wv, det;
                unsigned mm = fr_tri_hit(b, s, f, tfar, lanes, &t, &V, &Wv, &det);
                if (!mm)
                    continue;
                const uint32_t pw = b->prim[s], prim = pw & HZ_BVH_PRIM_MASK, hs = (slot / W) * W + s;
                float tv[W], vv[W], wv[W], dv[W];
                vst1q_f32(tv, t), vst1q_f32(vv, V), vst1q_f32(wv, Wv), vst1q_f32(dv, det);
                do {
                    unsigned i = (unsigned)__builtin_ctz(mm);
                    mm &= mm - 1;
                    hz_bvh_ray_t *r = &p->r[i];
                    if (!hz_bvh_better(tv[i], prim, r->tfar, p->best[i].prim))
                        continue;
                    if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT) && !hz_bvh_anyhit(bvh, ctx, hs, r, tv[i], p->id[i], (int)i))
                        continue;
                    r->tfar = tv[i];
                    tfa[i] = tv[i];
                    p->best[i].prim = prim, p->best[i].slot = hs;
                    p->best[i].v = vv[i], p->best[i].w = wv[i], p->best[i].det = dv[i];
                } while (mm);
                tfar = vld1q_f32(tfa);
                cull_max = vmaxvq_f32(tfar) * HZ_BVH_CULL;
            }
        }
        const unsigned inner = m & ~leafbits;
        if (inner) {
            order_children(n, inner, tmin, &cur, st_c, st_d, &sp);
            continue;
        }
        for (;;) {
            if (sp == 0)
                return;
            --sp;
            if (st_d[sp] <= cull_max) {
                cur = st_c[sp];
                break;
            }
        }
    }
}

/* Occlusion: lanes drop out as they find a hit. As on AVX2, the frustum test of a node's boxes only preselects:
 * each child it passes gets the lanes' own slab tests and goes on with the lanes that meet it (lane masks on
 * the stack), and a subtree that one lane reaches goes on as that single ray. The bounds follow the live lanes
 * (recomputed when lanes drop out). */
static unsigned frustum_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, packet_t *p, const frustum_t *f0, hz_bvh_counters_t *k)
{
    uint32_t st_c[HZ_BVH_STACK + W];
    unsigned st_m[HZ_BVH_STACK + W];
    int sp = 0;
    uint32_t cur = 0;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    frustum_t fl;
    const frustum_t *f = f0;
    float tfa[W];
    lanes_tfar(p, tfa);
    float32x4_t tfar = vld1q_f32(tfa);
    float32x4_t cull = vmulq_f32(tfar, vdupq_n_f32(HZ_BVH_CULL));
    float32x4_t vcull_max = vdupq_n_f32(vmaxvq_f32(tfar) * HZ_BVH_CULL);
    unsigned live = p->active, cm = live; /* cm: the live lanes that reach cur */
    for (;;) {
        unsigned done = 0;
        if ((cm & (cm - 1)) == 0) {
            const unsigned i = (unsigned)__builtin_ctz(cm);
            sray_t sr;
            sray_init(&sr, &p->r[i]);
            if (any_from_node(bvh, ctx, &p->r[i], &sr, cur, p->id[i], (int)i, k))
                done = cm;
        } else {
            const hz_bvh_node_t *n = &bvh->nodes[cur];
            float32x4_t tmin;
            HZ_BVH_COUNT(k, nodes, 1);
            const unsigned m = fr_node_hit(n, f, vcull_max, &tmin);
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
                    float32x4_t t, V, Wv, det;
                    unsigned mm = fr_tri_hit(b, s, f, tfar, lanes, &t, &V, &Wv, &det);
                    if (!mm)
                        continue;
                    if (anyhit && (b->prim[s] & HZ_BVH_PRIM_ANYHIT)) {
                        float tv[W];
                        vst1q_f32(tv, t);
                        for (unsigned x = mm; x; x &= x - 1) {
                            unsigned i = (unsigned)__builtin_ctz(x);
                            if (!hz_bvh_anyhit(bvh, ctx, (slot / W) * W + s, &p->r[i], tv[i], p->id[i], (int)i))
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
            for (unsigned x = done; x; x &= x - 1)
                tfa[__builtin_ctz(x)] = -__builtin_inff();
            tfar = vld1q_f32(tfa);
            cull = vmulq_f32(tfar, vdupq_n_f32(HZ_BVH_CULL));
            vcull_max = vdupq_n_f32(vmaxvq_f32(tfar) * HZ_BVH_CULL);
            if ((live & (live - 1)) && frustum_init(&fl, p, live))
                f = &fl;
        }
        for (;;) {
            if (sp == 0)
                return p->active & ~live;
            --sp;
            cm = st_m[sp] & live;
            if (cm) {
                cur = st_c[sp];
                break;
            }
        }
    }
    return p->active;
}

static void write_hits(const hz_bvh_t *bvh, const packet_t *p, hz_rayhit4_t *rh)
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

void hz_bvh_simd_intersectw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_rayhit4_t *rh,
                            hz_accel_kernel_t kernel)
{
    packet_t p;
    hz_bvh_counters_t k = { 0, 0 };
    if (!packet_init(&p, valid, &rh->ray))
        return;
    frustum_t f;
    if (kernel == HZ_ACCEL_KERNEL_SIMD_PACKET && frustum_init(&f, &p, p.active)) {
        frustum_closest(bvh, ctx, &p, &f, &k);
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

void hz_bvh_simd_occludedw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_ray4_t *ray,
                           hz_accel_kernel_t kernel)
{
    packet_t p;
    hz_bvh_counters_t k = { 0, 0 };
    if (!packet_init(&p, valid, ray))
        return;
    unsigned hit = 0;
    frustum_t f;
    if (kernel == HZ_ACCEL_KERNEL_SIMD_PACKET && frustum_init(&f, &p, p.active)) {
        hit = frustum_any(bvh, ctx, &p, &f, &k);
    } else {
        for (unsigned m = p.active; m; m &= m - 1) {
            unsigned i = (unsigned)__builtin_ctz(m);
            sray_t s;
            sray_init(&s, &p.r[i]);
            if (any_from_node(bvh, ctx, &p.r[i], &s, 0, p.id[i], (int)i, &k))
                hit |= 1u << i;
        }
    }
    for (unsigned m = hit; m; m &= m - 1)
        ray->tfar[__builtin_ctz(m)] = -__builtin_inff();
    hz_bvh_counters_flush(ctx, &k);
}
