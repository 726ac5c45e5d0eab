/*
 * trav_kernel.h — the native SIMD traversal kernels, written once over a lane type; included by trav_avx2.c (8
 * lanes) and trav_neon.c (4 lanes) after they define these operations on their registers:
 *   KW (lanes, = HZ_BVH_WIDTH), vf (floats), vm (lane masks), vi (int32)
 *   vf_set1 vf_load vf_store (aligned) vf_add vf_sub vf_mul vf_div vf_abs vf_hmin vf_hmax vf_lane0
 *   vf_fmadd(a, b, c) = a * b + c rounded once (the single ray's slab test only: boxes need no bits of the twin)
 *   vf_hmins(v, out): out[i] = the smallest lane of v[i], for i < KW (no NaN lanes)
 *   vf_maxn(a, b) vf_minn(a, b): max / min where only `a` may be NaN, and then the result is b (x86 max/min
 *     return their second operand on NaN, NEON's maxNum/minNum the number: the same for these calls)
 *   vf_lt vf_le vf_gt vf_ge vf_eq (false on NaN), vf_neu (a != b, true on NaN)
 *   vm_and vm_or vm_andn(a, b) = a & ~b, vm_bits (bit i: lane i), vm_of(bits), vf_sel(m, a, b) = m ? a : b
 *   vi_set1 vi_load vi_store (aligned) vi_storeu vi_iota vi_and vi_or vi_andn vi_add vi_sub vi_shl(x, n) vi_lane0
 *   vi_sel(m, a, b) vi_gt vi_eq (signed) vm_as_vi vi_signs (bit i: lane i's bit 31) vi_perm(v, idx) (lane i = lane idx[i] & (KW - 1) of v) vi_sort
 *   (ascending as unsigned) vf_as_vi vi_as_vf
 * Every float operation of the ray preparation and the triangle test is the IEEE one, rounded once, in the order
 * of the scalar reference (trav_scalar.c, bvh.h's hz_bvh_ray_prep / hz_bvh_tri_test): the kernels return its
 * bits on every ISA. Box tests only need to be conservative (bvh.h): the single ray's fused one
 * (node_hit_fused) computes its distances differently and visits nodes in a slightly different order.
 *
 * Kernels
 *  - single ray: one ray against a node's KW child boxes at once (nearest child first, the rest on a stack
 *    sorted in registers), one ray against a block's KW triangles at once; closest hit and occlusion, static and
 *    motion trees (motion reads every node and block at the ray's time);
 *  - packet: KW rays sharing direction signs and watertight axes, one interval test per node for the packet,
 *    leaves against the lanes that reach them, occlusion with lane masks on the stack (see "packets" below);
 *  - tile (large coherent packets, Wald 2001 / Overbeck 2008 / Fuetterling 2015): up to TILE_RAYS rays of up to
 *    TILE_RAYS / KW packets traced together. Rays are grouped by direction octant and watertight axes (a camera
 *    tile is one group), each group compacted into chunks of KW lanes. Per node, ONE interval-arithmetic test of
 *    the KW child boxes for the whole group (the group's origin box and reciprocal-direction ranges); each child
 *    it passes gets the first and the last chunk of the current range whose own rays reach it (an active-ray
 *    range), leaves are tested lane-wise chunk by chunk, inner children go on a stack nearest first with their
 *    ranges. When every ray of a group shares its origin bit for bit (camera rays), the ray-independent part of
 *    the watertight test (vertices relative to the origin, edges, the plane's normal and distance) is computed
 *    once per leaf for all chunks. Occlusion: lanes drop out as they are blocked, the group stops when all are;
 *    a subtree that one ray reaches goes on as that single ray; rays that share their far end (shadow rays
 *    towards one point light) are bounded from that end (the interval test from a tiny end box back along the
 *    rays), which is tight where the origins spread. Rays with a zero direction component, and small groups
 *    (a call whose rays share no directions: fewer than TILE_MIN_GROUP rays), go as single rays.
 */
#ifndef HZ_ACCEL_TRAV_KERNEL_H
#define HZ_ACCEL_TRAV_KERNEL_H

#include "bvh.h"

#define W KW
typedef char trav_kw_matches[KW == HZ_BVH_W ? 1 : -1];

HZ_INLINE vf ldn(const hz_bvh_node_t *n, size_t off)
{
    return vf_load((const float *)(const void *)((const char *)n + off));
}

HZ_INLINE unsigned slot_mask(uint32_t slot, uint32_t n)
{
    return ((1u << n) - 1u) << (slot % W);
}

/* The watertight test (hz_bvh_tri_test's operations, lane by lane) on triangles whose vertices a, b, c are
 * already relative to the ray origin in the ray's permuted axes (kx, ky, kz): lanes of lm that pass with
 * tnear <= t <= tfar; t and the edge weights V, W, det in the out vectors (written only when a lane passes the
 * edge tests). One ray against KW triangles and KW rays against one triangle differ only in how they load
 * these vectors: one definition keeps them bit-identical. */
HZ_INLINE unsigned woop(vf akx, vf aky, vf akz, vf bkx, vf bky, vf bkz, vf ckx, vf cky, vf ckz, vf sx, vf sy, vf sz,
                        vf tnear, vf tfar, unsigned lm, vf *t_out, vf *v_out, vf *w_out, vf *det_out)
{
    const vf ax = vf_sub(akx, vf_mul(sx, akz)), ay = vf_sub(aky, vf_mul(sy, akz));
    const vf bx = vf_sub(bkx, vf_mul(sx, bkz)), by = vf_sub(bky, vf_mul(sy, bkz));
    const vf cx = vf_sub(ckx, vf_mul(sx, ckz)), cy = vf_sub(cky, vf_mul(sy, ckz));
    const vf U = vf_sub(vf_mul(cx, by), vf_mul(cy, bx));
    const vf V = vf_sub(vf_mul(ax, cy), vf_mul(ay, cx));
    const vf Wv = vf_sub(vf_mul(bx, ay), vf_mul(by, ax));
    const vf z = vf_set1(0.0f);
    const vm neg = vm_or(vm_or(vf_lt(U, z), vf_lt(V, z)), vf_lt(Wv, z));
    const vm pos = vm_or(vm_or(vf_gt(U, z), vf_gt(V, z)), vf_gt(Wv, z));
    const vf det = vf_add(vf_add(U, V), Wv);
    const unsigned m = vm_bits(vm_andn(vf_neu(det, z), vm_and(neg, pos))) & lm;
    if (!m)
        return 0;
    /* t from the plane, as hz_bvh_tri_test (see there), operation for operation */
    const vf e1x = vf_sub(bkx, akx), e1y = vf_sub(bky, aky), e1z = vf_sub(bkz, akz);
    const vf e2x = vf_sub(ckx, akx), e2y = vf_sub(cky, aky), e2z = vf_sub(ckz, akz);
    const vf nx = vf_sub(vf_mul(e1y, e2z), vf_mul(e1z, e2y));
    const vf ny = vf_sub(vf_mul(e1z, e2x), vf_mul(e1x, e2z));
    const vf nz = vf_sub(vf_mul(e1x, e2y), vf_mul(e1y, e2x));
    const vf num = vf_add(vf_add(vf_mul(nx, akx), vf_mul(ny, aky)), vf_mul(nz, akz));
    const vf den = vf_add(vf_add(vf_mul(nx, sx), vf_mul(ny, sy)), nz);
    const vf t = vf_div(vf_mul(num, sz), den);
    const vm in = vm_and(vf_lt(vf_abs(t), vf_set1(__builtin_inff())), vm_and(vf_ge(t, tnear), vf_le(t, tfar)));
    *t_out = t, *v_out = V, *w_out = Wv, *det_out = det;
    return m & vm_bits(in);
}

/* =========================================================================================================
 * single ray */
typedef struct sray {
    vf ox, oy, oz, rdx, rdy, rdz;
    /* The fused slab test (node_hit_fused): -(o * rd) per axis and the slack its rounding needs; `fused` says
     * it applies (finite reciprocals and products), else the ray takes slab_hit. */
    vf nox, noy, noz;
    float slack;
    int fused;
    size_t nx, ny, nz, fx, fy, fz; /* byte offsets of the near and far planes in a node */
    /* watertight test */
    vf okx, oky, okz, sx, sy, sz, tnear, inf;
    int kx, ky, kz;
} sray_t;

static void sray_init(sray_t *s, const hz_bvh_ray_t *r)
{
    s->ox = vf_set1(r->org[0]), s->oy = vf_set1(r->org[1]), s->oz = vf_set1(r->org[2]);
    s->rdx = vf_set1(r->rdir[0]), s->rdy = vf_set1(r->rdir[1]), s->rdz = vf_set1(r->rdir[2]);
    const size_t a = offsetof(hz_bvh_node_t, hi_x) - offsetof(hz_bvh_node_t, lo_x);
    s->nx = offsetof(hz_bvh_node_t, lo_x) + (r->rdir[0] < 0.0f ? a : 0);
    s->ny = offsetof(hz_bvh_node_t, lo_y) + (r->rdir[1] < 0.0f ? a : 0);
    s->nz = offsetof(hz_bvh_node_t, lo_z) + (r->rdir[2] < 0.0f ? a : 0);
    s->fx = offsetof(hz_bvh_node_t, lo_x) + (r->rdir[0] < 0.0f ? 0 : a);
    s->fy = offsetof(hz_bvh_node_t, lo_y) + (r->rdir[1] < 0.0f ? 0 : a);
    s->fz = offsetof(hz_bvh_node_t, lo_z) + (r->rdir[2] < 0.0f ? 0 : a);
    s->kx = r->kx, s->ky = r->ky, s->kz = r->kz;
    s->okx = vf_set1(r->org[r->kx]), s->oky = vf_set1(r->org[r->ky]), s->okz = vf_set1(r->org[r->kz]);
    s->sx = vf_set1(r->sx), s->sy = vf_set1(r->sy), s->sz = vf_set1(r->sz);
    s->tnear = vf_set1(r->tnear);
    s->inf = vf_set1(__builtin_inff());
    const float od0 = r->org[0] * r->rdir[0], od1 = r->org[1] * r->rdir[1], od2 = r->org[2] * r->rdir[2];
    s->nox = vf_set1(-od0), s->noy = vf_set1(-od1), s->noz = vf_set1(-od2);
    /* each o * rd is off by at most 2^-24 of itself (2^-150 below the normal range), node_hit_fused's near and
     * far distances by as much each way, so the far bound needs twice the largest: the sum times 2^-22 is at
     * least twice that again, room for this sum's own rounding */
    s->slack = (hz_absf(od0) + hz_absf(od1) + hz_absf(od2)) * 0x1p-22f + 0x1p-126f;
    /* an infinite reciprocal makes a product infinite or NaN, and so the slack; one that overflows only sends
     * the ray to slab_hit */
    s->fused = hz_isfinitef(s->slack);
}

/* Children whose boxes, near planes (nx, ny, nz) and far planes (fx, fy, fz) as the ray's signs pick them, the
 * ray meets before `cull` (a distance for culling, see bvh.h); entry distances in *tmin_out. */
HZ_INLINE unsigned slab_hit(vf nx, vf ny, vf nz, vf fx, vf fy, vf fz, const sray_t *s, vf cull, vf *tmin_out)
{
    const vf tnx = vf_mul(vf_sub(nx, s->ox), s->rdx);
    const vf tny = vf_mul(vf_sub(ny, s->oy), s->rdy);
    const vf tnz = vf_mul(vf_sub(nz, s->oz), s->rdz);
    const vf tfx = vf_mul(vf_sub(fx, s->ox), s->rdx);
    const vf tfy = vf_mul(vf_sub(fy, s->oy), s->rdy);
    const vf tfz = vf_mul(vf_sub(fz, s->oz), s->rdz);
    /* NaN-prone slab distances first: they drop out (see bvh.h) */
    const vf tmin = vf_maxn(tnz, vf_maxn(tny, vf_maxn(tnx, s->tnear)));
    const vf tmax = vf_minn(vf_mul(vf_minn(tfz, vf_minn(tfy, vf_minn(tfx, s->inf))), vf_set1(HZ_BVH_ROBUST)), cull);
    *tmin_out = tmin;
    return vm_bits(vf_le(tmin, tmax));
}

/* Children of n the ray meets before `cull`; entry distances in *tmin_out. */
HZ_INLINE unsigned node_hit(const hz_bvh_node_t *n, const sray_t *s, vf cull, vf *tmin_out)
{
    return slab_hit(ldn(n, s->nx), ldn(n, s->ny), ldn(n, s->nz), ldn(n, s->fx), ldn(n, s->fy), ldn(n, s->fz), s, cull,
                    tmin_out);
}

/* The single ray's constants of node_hit_fused, kept in locals for the whole search (through the ray's struct
 * every node reloaded them: with the planes, four loads a plane). */
typedef struct fray {
    vf rdx, rdy, rdz, nox, noy, noz, tnear, slack, robust;
    size_t nx, ny, nz, fx, fy, fz;
} fray_t;

HZ_INLINE fray_t fray_of(const sray_t *s)
{
    fray_t f;
    f.rdx = s->rdx, f.rdy = s->rdy, f.rdz = s->rdz, f.nox = s->nox, f.noy = s->noy, f.noz = s->noz;
    f.tnear = s->tnear, f.slack = vf_set1(s->slack), f.robust = vf_set1(HZ_BVH_ROBUST);
    f.nx = s->nx, f.ny = s->ny, f.nz = s->nz, f.fx = s->fx, f.fy = s->fy, f.fz = s->fz;
    return f;
}

/* node_hit with one fused multiply-add per plane, p * rd + (-(o * rd)) instead of (p - o) * rd: half the
 * operations and half the latency. Conservative as slab_hit: -(o * rd) is off the exact product by at most
 * 2^-24 of it, so each distance is the correctly rounded (p - o) * rd moved by at most that much, and the far
 * bound adds twice the largest of them (f->slack, also in `cull`) to HZ_BVH_ROBUST's factor, which covers the
 * reciprocal's rounding and the last one as it does for slab_hit's three. Only for rays with s->fused: a zero
 * direction component's infinite reciprocal would make every plane's distance NaN (inf - inf) and lose the
 * side of the plane the ray lies on. The distances differ from slab_hit's in their last bits; hits do not
 * (bvh.h: the closest hit does not depend on the order of the visits), and entry distances only order and
 * cull, both with margins. */
HZ_INLINE unsigned node_hit_fused(const hz_bvh_node_t *n, const fray_t *f, vf cull, vf *tmin_out)
{
    const vf tnx = vf_fmadd(ldn(n, f->nx), f->rdx, f->nox);
    const vf tny = vf_fmadd(ldn(n, f->ny), f->rdy, f->noy);
    const vf tnz = vf_fmadd(ldn(n, f->nz), f->rdz, f->noz);
    const vf tfx = vf_fmadd(ldn(n, f->fx), f->rdx, f->nox);
    const vf tfy = vf_fmadd(ldn(n, f->fy), f->rdy, f->noy);
    const vf tfz = vf_fmadd(ldn(n, f->fz), f->rdz, f->noz);
    const vf tmin = vf_maxn(vf_maxn(tnx, tny), vf_maxn(tnz, f->tnear));
    const vf tmax = vf_fmadd(vf_minn(vf_minn(tfx, tfy), tfz), f->robust, f->slack);
    *tmin_out = tmin;
    /* tmin <= min(tmax, cull) as two compares: the next node's address waits on this mask, and the cull's
     * compare runs beside the far distance's chain instead of adding a min to it (no NaN here: finite
     * reciprocals and products give finite or infinite distances, never inf - inf) */
    return vm_bits(vm_and(vf_le(tmin, tmax), vf_le(tmin, cull)));
}

/* One ray against the slots `lm` of block b (see woop). */
HZ_INLINE unsigned leaf_hit(const hz_bvh_block_t *b, unsigned lm, const sray_t *s, float tfar, vf *t_out, vf *v_out,
                            vf *w_out, vf *det_out)
{
    return woop(vf_sub(vf_load(b->v[0][s->kx]), s->okx), vf_sub(vf_load(b->v[0][s->ky]), s->oky),
                vf_sub(vf_load(b->v[0][s->kz]), s->okz), vf_sub(vf_load(b->v[1][s->kx]), s->okx),
                vf_sub(vf_load(b->v[1][s->ky]), s->oky), vf_sub(vf_load(b->v[1][s->kz]), s->okz),
                vf_sub(vf_load(b->v[2][s->kx]), s->okx), vf_sub(vf_load(b->v[2][s->ky]), s->oky),
                vf_sub(vf_load(b->v[2][s->kz]), s->okz), s->sx, s->sy, s->sz, s->tnear, vf_set1(tfar), lm, t_out,
                v_out, w_out, det_out);
}

/* Children a node test hit (mask m, entry distances tmin): the nearest becomes *cur, the others go on the
 * stack farthest first, so the nearest of them is popped next. Two hits take one compare; more are sorted in
 * registers: keys are the distances' float bits (distances are >= 0, so their bits order like the floats) with
 * the child's slot in the low bits, and the sorted children and distances are stored with one vector store
 * each (the stack keeps children and distances in separate arrays, with KW entries of slack). Stored distances
 * lose their low bits: they round down, so culling by them stays conservative. */
HZ_INLINE void order_children(const hz_bvh_node_t *n, unsigned m, vf tmin, uint32_t *cur, uint32_t *st_c,
                              float *st_d, int *sp)
{
    const int cnt = __builtin_popcount(m);
    if (cnt == 1) {
        *cur = n->child[__builtin_ctz(m)];
        return;
    }
    if (cnt == 2) {
        float d[W] HZ_ALIGNED(32);
        vf_store(d, tmin);
        const unsigned i0 = (unsigned)__builtin_ctz(m), i1 = (unsigned)__builtin_ctz(m & (m - 1));
        const bool swap = d[i1] < d[i0];
        const unsigned near = swap ? i1 : i0, far = swap ? i0 : i1;
        st_c[*sp] = n->child[far];
        st_d[*sp] = d[far];
        (*sp)++;
        *cur = n->child[near];
        return;
    }
    const vi low = vi_set1(W - 1), iota = vi_iota();
    vi key = vi_or(vi_andn(vf_as_vi(vf_maxn(tmin, vf_set1(0.0f))), low), iota);
    key = vi_sel(vm_of(m), key, vi_set1(-1));
    const vi sorted = vi_sort(key);
    const vi kids = vi_perm(vi_load(n->child), vi_and(sorted, low));
    const vi dists = vi_andn(sorted, low);
    /* lanes 0 .. cnt-2 of the stores: the hits from the farthest (sorted[cnt - 1]) down to sorted[1] */
    const vi back = vi_and(vi_sub(vi_set1(cnt - 1), iota), low); /* lane i: cnt - 1 - i (lanes >= cnt: slack) */
    vi_storeu(st_c + *sp, vi_perm(kids, back));
    vi_storeu(st_d + *sp, vi_perm(dists, back));
    *sp += cnt - 1;
    *cur = (uint32_t)vi_lane0(kids);
}

/* Motion: the node and the block as the ray sees them at its time, with hz_bvh_node_at / hz_bvh_block_at's
 * operations (g = 1 - f in scalar, then g * a + f * b lane by lane: bit-identical to the scalar kernel), lerped
 * straight into the tests: a lerped copy in memory put a store and a reload on every visit's dependency chain. A
 * key box set has the layout of a node's first six arrays, so the ray's plane offsets address it as well. */
#define TRAV_SAME_PLANE(p) (offsetof(hz_bvh_node_t, p) == offsetof(hz_bvh_mbox_t, p))
typedef char trav_mbox_matches_node[TRAV_SAME_PLANE(lo_x) && TRAV_SAME_PLANE(hi_x) && TRAV_SAME_PLANE(lo_y) &&
                                            TRAV_SAME_PLANE(hi_y) && TRAV_SAME_PLANE(lo_z) && TRAV_SAME_PLANE(hi_z)
                                        ? 1
                                        : -1];
#undef TRAV_SAME_PLANE

HZ_INLINE vf lerp_planes(const char *a, const char *b, size_t off, vf g, vf f)
{
    return vf_add(vf_mul(g, vf_load((const float *)(const void *)(a + off))),
                  vf_mul(f, vf_load((const float *)(const void *)(b + off))));
}

/* node_hit on node i at the ray's time. */
HZ_INLINE unsigned node_hit_at(const hz_bvh_t *bvh, uint32_t i, const hz_bvh_ray_t *r, const sray_t *s, vf cull,
                               vf *tmin_out)
{
    if (!bvh->key_boxes)
        return node_hit(&bvh->nodes[i], s, cull, tmin_out);
    float fs;
    const char *a = (const char *)(const void *)hz_bvh_node_keys(bvh, i, r, &fs), *b = a + sizeof(hz_bvh_mbox_t);
    const vf f = vf_set1(fs), g = vf_set1(1.0f - fs);
    return slab_hit(lerp_planes(a, b, s->nx, g, f), lerp_planes(a, b, s->ny, g, f), lerp_planes(a, b, s->nz, g, f),
                    lerp_planes(a, b, s->fx, g, f), lerp_planes(a, b, s->fy, g, f), lerp_planes(a, b, s->fz, g, f),
                    s, cull, tmin_out);
}

/* Axis ax of vertex v of the blocks at a ray's two keys (a, b), at its time (weights g, f), minus o (the ray
 * origin on that axis). */
HZ_INLINE vf vertex_at(const hz_bvh_block_t *a, const hz_bvh_block_t *b, int v, int ax, vf g, vf f, vf o)
{
    return vf_sub(vf_add(vf_mul(g, vf_load(a->v[v][ax])), vf_mul(f, vf_load(b->v[v][ax]))), o);
}

/* leaf_hit on a block at the ray's time: a and b are the block at the ray's two keys (kblocks[seg], [seg + 1]). */
HZ_INLINE unsigned leaf_hit_at(const hz_bvh_block_t *a, const hz_bvh_block_t *b, const hz_bvh_ray_t *r, unsigned lm,
                               const sray_t *s, float tfar, vf *t_out, vf *v_out, vf *w_out, vf *det_out)
{
    const vf f = vf_set1(r->f), g = vf_set1(1.0f - r->f);
    return woop(vertex_at(a, b, 0, s->kx, g, f, s->okx), vertex_at(a, b, 0, s->ky, g, f, s->oky),
                vertex_at(a, b, 0, s->kz, g, f, s->okz), vertex_at(a, b, 1, s->kx, g, f, s->okx),
                vertex_at(a, b, 1, s->ky, g, f, s->oky), vertex_at(a, b, 1, s->kz, g, f, s->okz),
                vertex_at(a, b, 2, s->kx, g, f, s->okx), vertex_at(a, b, 2, s->ky, g, f, s->oky),
                vertex_at(a, b, 2, s->kz, g, f, s->okz), s->sx, s->sy, s->sz, s->tnear, vf_set1(tfar), lm, t_out,
                v_out, w_out, det_out);
}

/* Closest hit of one ray from node word `start` on, continuing a search with best (r->tfar, *best); `motion`
 * (a constant at every call) reads nodes and blocks at the ray's time. The tree's arrays and the best hit live
 * in locals: through the pointers the compiler reloaded them at every node (the node's address waited on two
 * loads). */
HZ_INLINE void closest_core(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, const sray_t *s,
                            uint32_t start, hz_bvh_best_t *best_io, uint32_t ray_id, int lane,
                            hz_bvh_counters_t *k_io, const bool motion, const bool fused)
{
    hz_bvh_counters_t kl = *k_io, *k = &kl; /* in registers: through the pointer every count was a store */
    (void)k; /* counters exist only with HZ_FEATURE_STATS */
    uint32_t st_c[HZ_BVH_STACK + W];
    float st_d[HZ_BVH_STACK + W];
    int sp = 0;
    uint32_t cur = start;
    const hz_bvh_node_t *const nodes = bvh->nodes;
    const hz_bvh_block_t *const blocks = bvh->blocks;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    hz_bvh_best_t best = *best_io;
    const fray_t fr = fray_of(s);
    const float slack = fused ? s->slack : 0.0f; /* node_hit_fused's entry distances may be that much late */
    float tfar = r->tfar, cull_s = tfar * HZ_BVH_CULL + slack; /* for culling nodes (see bvh.h) */
    vf cull = vf_set1(cull_s);
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &nodes[cur]; /* motion trees keep their children there too */
            vf tmin;
            HZ_BVH_COUNT(k, nodes, 1);
            unsigned m = motion  ? node_hit_at(bvh, cur, r, s, cull, &tmin)
                         : fused ? node_hit_fused(n, &fr, cull, &tmin)
                                 : node_hit(n, s, cull, &tmin);
            if (m) {
                order_children(n, m, tmin, &cur, st_c, st_d, &sp);
                continue;
            }
        } else {
            const uint32_t slot = hz_bvh_leaf_slot(cur), cnt = hz_bvh_leaf_count(cur);
            const hz_bvh_block_t *b = motion ? &bvh->kblocks[r->seg][slot / W] : &blocks[slot / W];
            vf t, V, Wv, det;
            HZ_BVH_COUNT(k, tris, cnt);
            unsigned m = motion ? leaf_hit_at(b, &bvh->kblocks[r->seg + 1u][slot / W], r, slot_mask(slot, cnt), s,
                                              tfar, &t, &V, &Wv, &det)
                                : leaf_hit(b, slot_mask(slot, cnt), s, tfar, &t, &V, &Wv, &det);
            if (m) {
                float tv[W] HZ_ALIGNED(32), vv[W] HZ_ALIGNED(32), wv[W] HZ_ALIGNED(32), dv[W] HZ_ALIGNED(32);
                vf_store(tv, t), vf_store(vv, V), vf_store(wv, Wv), vf_store(dv, det);
                do {
                    const unsigned i = (unsigned)__builtin_ctz(m);
                    m &= m - 1;
                    const uint32_t pw = b->prim[i], prim = pw & HZ_BVH_PRIM_MASK;
                    if (!hz_bvh_better(tv[i], prim, tfar, best.prim))
                        continue;
                    const uint32_t hs = (slot / W) * W + i;
                    if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT)) {
                        r->tfar = tfar; /* the callback's ray as the caller sees it */
                        if (!hz_bvh_anyhit(bvh, ctx, hs, tv[i], vv[i], wv[i], dv[i], ray_id, lane))
                            continue;
                    }
                    tfar = tv[i];
                    best.prim = prim, best.slot = hs;
                    best.v = vv[i], best.w = wv[i], best.det = dv[i];
                } while (m);
                cull_s = tfar * HZ_BVH_CULL + slack;
                cull = vf_set1(cull_s);
            }
        }
        for (;;) {
            if (sp == 0) {
                r->tfar = tfar;
                *best_io = best;
                *k_io = kl;
                return;
            }
            --sp;
            if (st_d[sp] <= cull_s) {
                cur = st_c[sp];
                break;
            }
        }
    }
}

/* The static tree's closest-hit search with the box test the ray takes (sray_t's `fused`). */
HZ_INLINE void closest_static(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, const sray_t *s,
                              uint32_t start, hz_bvh_best_t *best, uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    if (s->fused)
        closest_core(bvh, ctx, r, s, start, best, ray_id, lane, k, false, true);
    else
        closest_core(bvh, ctx, r, s, start, best, ray_id, lane, k, false, false);
}

/* closest_static out of line: the packet and tile kernels call it for lanes that go on alone (a copy inlined at
 * each of their call sites would only grow them). */
static void closest_from(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, const sray_t *s,
                         uint32_t start, hz_bvh_best_t *best, uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    closest_static(bvh, ctx, r, s, start, best, ray_id, lane, k);
}

static void closest_motion(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, const sray_t *s,
                           hz_bvh_best_t *best, uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    closest_core(bvh, ctx, r, s, 0, best, ray_id, lane, k, true, false);
}

void hz_bvh_simd_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_ray_t *r, hz_bvh_best_t *best,
                         uint32_t ray_id, int lane)
{
    sray_t s;
    hz_bvh_counters_t k = { 0, 0 };
    sray_init(&s, r);
    /* the static search inline, not through closest_from: that call's prologue, epilogue and spilled arguments
     * were about a twelfth of an incoherent ray's instructions (any is the same) */
    if (bvh->time_keys)
        closest_motion(bvh, ctx, r, &s, best, ray_id, lane, &k);
    else
        closest_static(bvh, ctx, r, &s, 0, best, ray_id, lane, &k);
    hz_bvh_counters_flush(ctx, &k);
}

HZ_INLINE bool any_core(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, const sray_t *s,
                        uint32_t start, uint32_t ray_id, int lane, hz_bvh_counters_t *k_io, const bool motion,
                        const bool fused)
{
    hz_bvh_counters_t kl = *k_io, *k = &kl; /* in registers: through the pointer every count was a store */
    bool hit = false;
    (void)k; /* counters exist only with HZ_FEATURE_STATS */
    uint32_t stack[HZ_BVH_STACK + W];
    int sp = 0;
    uint32_t cur = start;
    const hz_bvh_node_t *const nodes = bvh->nodes;
    const hz_bvh_block_t *const blocks = bvh->blocks;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    const float tfar = r->tfar;
    const fray_t fr = fray_of(s);
    const vf cull = vf_set1(tfar * HZ_BVH_CULL + (fused ? s->slack : 0.0f)); /* for culling nodes (see bvh.h) */
    for (;;) {
        if (!hz_bvh_is_leaf(cur)) {
            const hz_bvh_node_t *n = &nodes[cur]; /* motion trees keep their children there too */
            vf tmin;
            HZ_BVH_COUNT(k, nodes, 1);
            unsigned m = motion  ? node_hit_at(bvh, cur, r, s, cull, &tmin)
                         : fused ? node_hit_fused(n, &fr, cull, &tmin)
                                 : node_hit(n, s, cull, &tmin);
            if (m) {
                cur = n->child[__builtin_ctz(m)];
                for (m &= m - 1; m; m &= m - 1)
                    stack[sp++] = n->child[__builtin_ctz(m)];
                continue;
            }
        } else {
            const uint32_t slot = hz_bvh_leaf_slot(cur), cnt = hz_bvh_leaf_count(cur);
            const hz_bvh_block_t *b = motion ? &bvh->kblocks[r->seg][slot / W] : &blocks[slot / W];
            vf t, V, Wv, det;
            HZ_BVH_COUNT(k, tris, cnt);
            unsigned m = motion ? leaf_hit_at(b, &bvh->kblocks[r->seg + 1u][slot / W], r, slot_mask(slot, cnt), s,
                                              tfar, &t, &V, &Wv, &det)
                                : leaf_hit(b, slot_mask(slot, cnt), s, tfar, &t, &V, &Wv, &det);
            if (m) {
                if (!anyhit) {
                    hit = true;
                    break;
                }
                float tv[W] HZ_ALIGNED(32), vv[W] HZ_ALIGNED(32), wv[W] HZ_ALIGNED(32), dv[W] HZ_ALIGNED(32);
                vf_store(tv, t), vf_store(vv, V), vf_store(wv, Wv), vf_store(dv, det);
                do {
                    const unsigned i = (unsigned)__builtin_ctz(m);
                    m &= m - 1;
                    if (!(b->prim[i] & HZ_BVH_PRIM_ANYHIT) ||
                        hz_bvh_anyhit(bvh, ctx, (slot / W) * W + i, tv[i], vv[i], wv[i], dv[i], ray_id, lane))
                        hit = true;
                } while (m && !hit);
                if (hit)
                    break;
            }
        }
        if (sp == 0)
            break;
        cur = stack[--sp];
    }
    *k_io = kl;
    return hit;
}

/* The static tree's occlusion search with the box test the ray takes (sray_t's `fused`). */
HZ_INLINE bool any_static(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, const sray_t *s,
                          uint32_t start, uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    return s->fused ? any_core(bvh, ctx, r, s, start, ray_id, lane, k, false, true)
                    : any_core(bvh, ctx, r, s, start, ray_id, lane, k, false, false);
}

/* any_static out of line, for the same callers. */
static bool any_from(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, const sray_t *s,
                     uint32_t start, uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    return any_static(bvh, ctx, r, s, start, ray_id, lane, k);
}

static bool any_motion(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, const sray_t *s,
                       uint32_t start, uint32_t ray_id, int lane, hz_bvh_counters_t *k)
{
    return any_core(bvh, ctx, r, s, start, ray_id, lane, k, true, false);
}

bool hz_bvh_simd_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_ray_t *r, uint32_t ray_id, int lane)
{
    sray_t s;
    hz_bvh_counters_t k = { 0, 0 };
    sray_init(&s, r);
    const bool hit = bvh->time_keys ? any_motion(bvh, ctx, r, &s, 0, ray_id, lane, &k)
                                    : any_static(bvh, ctx, r, &s, 0, ray_id, lane, &k);
    hz_bvh_counters_flush(ctx, &k);
    return hit;
}

/* Children of a node in order of entry distance d (nearest first): their slots in ord, their count returned. */
HZ_INLINE unsigned sort_by(unsigned m, const float *d, unsigned *ord)
{
    unsigned c = 0;
    for (; m; m &= m - 1) {
        const unsigned j = (unsigned)__builtin_ctz(m);
        unsigned q = c++;
        while (q > 0 && d[ord[q - 1]] > d[j]) {
            ord[q] = ord[q - 1];
            q--;
        }
        ord[q] = j;
    }
    return c;
}

/* =========================================================================================================
 * packets: KW rays sharing their direction signs and watertight axes, traced together through a node's boxes
 * with the packet's interval bounds (one test for the packet), leaf children tested right away against the
 * lanes whose own slab test reaches them; occlusion keeps lane masks on the stack, shrinks its bounds to the
 * live lanes and continues a subtree that one lane reaches as that single ray. This is the tile traversal of
 * one chunk, kept in its own lean form: for single packets it was a third faster than the general tile code
 * doing the same work (the same node visits and triangle tests). */
typedef struct frustum {
    unsigned active;
    size_t nx, ny, nz, fx, fy, fz; /* near and far planes (the direction signs) */
    vf on[3], of[3], rmin[3], rmax[3]; /* origins for the near and far planes, reciprocal ranges */
    vf tnear;                      /* smallest tnear of the packet */
    /* lanes, for leaf boxes and the leaf test */
    vf o[3], r[3];
    vf okx, oky, okz, sx, sy, sz, ltnear, ltfar;
    int kx, ky, kz;
    unsigned negs; /* bit k: the packet's direction is negative on axis k */
} frustum_t;

/* The packet's interval bounds over the lanes `lanes` (tn the lanes' tnear): minima of o, r and tnear, maxima (as
 * minima of negatives) of o and r, KW horizontal minima at once. Lanes that drop out only shrink the bounds. */
static void frustum_bounds(frustum_t *f, unsigned lanes, vf tn)
{
    const vf inf = vf_set1(__builtin_inff()), zero = vf_set1(0.0f);
    const vm lm = vm_of(lanes);
    vf v[16];
    float r[16] HZ_ALIGNED(32);
    for (int k = 0; k < 3; k++) {
        v[k] = vf_sel(lm, f->o[k], inf);
        v[3 + k] = vf_sel(lm, f->r[k], inf);
        v[7 + k] = vf_sel(lm, vf_sub(zero, f->o[k]), inf);
        v[10 + k] = vf_sel(lm, vf_sub(zero, f->r[k]), inf);
    }
    v[6] = vf_sel(lm, tn, inf);
    for (int q = 13; q < 16; q++)
        v[q] = inf;
    for (int q = 0; q < 13; q += W)
        vf_hmins(v + q, r + q);
    for (int k = 0; k < 3; k++) {
        const float olo = r[k], ohi = -r[7 + k];
        const bool neg = (f->negs >> k) & 1u;
        f->on[k] = vf_set1(neg ? olo : ohi);
        f->of[k] = vf_set1(neg ? ohi : olo);
        f->rmin[k] = vf_set1(r[3 + k]);
        f->rmax[k] = vf_set1(-r[10 + k]);
    }
    f->tnear = vf_set1(r[6]);
}

/* A packet whose active lanes (at least two) share the direction signs and the watertight axes, with finite
 * reciprocals; false for any other (it goes through the tile code, which groups its lanes). */
static bool frustum_init(frustum_t *f, const int32_t *valid, const hz_bvh_rayw_t *ray)
{
    const vf inf = vf_set1(__builtin_inff()), zero = vf_set1(0.0f);
    const vf o[3] = { vf_load(ray->org_x), vf_load(ray->org_y), vf_load(ray->org_z) };
    const vf d[3] = { vf_load(ray->dir_x), vf_load(ray->dir_y), vf_load(ray->dir_z) };
    const vf tn = vf_load(ray->tnear), tf = vf_load(ray->tfar);
    unsigned vb = 0;
    for (int i = 0; i < W; i++)
        vb |= (unsigned)(valid[i] != 0) << i;
    vm ok = vm_of(vb), nonzero = vm_of(0);
    for (int k = 0; k < 3; k++) {
        ok = vm_and(ok, vm_and(vf_lt(vf_abs(o[k]), inf), vf_lt(vf_abs(d[k]), inf)));
        nonzero = vm_or(nonzero, vf_neu(d[k], zero));
    }
    ok = vm_and(vm_and(ok, nonzero), vf_le(tn, tf)); /* hz_bvh_ray_prep's contract check, lane by lane */
    const unsigned act = vm_bits(ok);
    f->active = act;
    if (__builtin_popcount(act) < 2)
        return false;
    vf r[3];
    unsigned negs = 0;
    for (int k = 0; k < 3; k++) {
        r[k] = vf_div(vf_set1(1.0f), d[k]);
        const unsigned neg = vm_bits(vf_lt(r[k], zero)) & act;
        const unsigned fin = vm_bits(vf_lt(vf_abs(r[k]), inf)) & act;
        if ((neg != 0 && neg != act) || fin != act)
            return false;
        negs |= (unsigned)(neg != 0) << k;
    }
    /* dominant axis: kz = 0; |dy| > |d[kz]| -> 1; |dz| > |d[kz]| -> 2 (as in hz_bvh_ray_prep) */
    const vf ax = vf_abs(d[0]), ay = vf_abs(d[1]), az = vf_abs(d[2]);
    const vm y_over = vf_gt(ay, ax);
    const vm z_over = vf_gt(az, vf_sel(y_over, ay, ax));
    const unsigned my = vm_bits(y_over) & act, mz = vm_bits(z_over) & act;
    int kz;
    if (mz == act)
        kz = 2;
    else if (mz == 0 && my == act)
        kz = 1;
    else if (mz == 0 && my == 0)
        kz = 0;
    else
        return false;
    int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
    if ((negs >> kz) & 1u) {
        const int t = kx;
        kx = ky;
        ky = t;
    }
    f->negs = negs;
    for (int k = 0; k < 3; k++)
        f->o[k] = o[k], f->r[k] = r[k];
    frustum_bounds(f, act, tn);
    const size_t a = offsetof(hz_bvh_node_t, hi_x) - offsetof(hz_bvh_node_t, lo_x);
    f->nx = offsetof(hz_bvh_node_t, lo_x) + ((negs & 1u) ? a : 0);
    f->ny = offsetof(hz_bvh_node_t, lo_y) + ((negs & 2u) ? a : 0);
    f->nz = offsetof(hz_bvh_node_t, lo_z) + ((negs & 4u) ? a : 0);
    f->fx = offsetof(hz_bvh_node_t, lo_x) + ((negs & 1u) ? 0 : a);
    f->fy = offsetof(hz_bvh_node_t, lo_y) + ((negs & 2u) ? 0 : a);
    f->fz = offsetof(hz_bvh_node_t, lo_z) + ((negs & 4u) ? 0 : a);
    const vm lanes = vm_of(act);
    f->ltnear = vf_sel(lanes, tn, inf);
    f->ltfar = vf_sel(lanes, tf, vf_sub(zero, inf));
    f->kx = kx, f->ky = ky, f->kz = kz;
    f->okx = o[kx], f->oky = o[ky], f->okz = o[kz];
    /* shear constants exactly as hz_bvh_ray_prep computes them */
    f->sx = vf_mul(d[kx], r[kz]);
    f->sy = vf_mul(d[ky], r[kz]);
    f->sz = r[kz];
    return true;
}

/* The packet's interval test of boxes given by their near planes (qnx, qny, qnz) and far planes (qfx, ...). */
HZ_INLINE unsigned fr_planes_hit(vf qnx, vf qny, vf qnz, vf qfx, vf qfy, vf qfz, const frustum_t *f, vf tfar_max,
                                 vf *tmin_out)
{
    const vf pnx = vf_sub(qnx, f->on[0]), pny = vf_sub(qny, f->on[1]);
    const vf pnz = vf_sub(qnz, f->on[2]);
    const vf pfx = vf_sub(qfx, f->of[0]), pfy = vf_sub(qfy, f->of[1]);
    const vf pfz = vf_sub(qfz, f->of[2]);
    const vf nx = vf_minn(vf_mul(pnx, f->rmin[0]), vf_mul(pnx, f->rmax[0]));
    const vf ny = vf_minn(vf_mul(pny, f->rmin[1]), vf_mul(pny, f->rmax[1]));
    const vf nz = vf_minn(vf_mul(pnz, f->rmin[2]), vf_mul(pnz, f->rmax[2]));
    const vf fx = vf_maxn(vf_mul(pfx, f->rmin[0]), vf_mul(pfx, f->rmax[0]));
    const vf fy = vf_maxn(vf_mul(pfy, f->rmin[1]), vf_mul(pfy, f->rmax[1]));
    const vf fz = vf_maxn(vf_mul(pfz, f->rmin[2]), vf_mul(pfz, f->rmax[2]));
    const vf tmin = vf_maxn(vf_maxn(nx, ny), vf_maxn(nz, f->tnear));
    const vf tmax = vf_minn(vf_mul(vf_minn(vf_minn(fx, fy), fz), vf_set1(HZ_BVH_ROBUST)), tfar_max);
    *tmin_out = tmin;
    return vm_bits(vf_le(tmin, tmax));
}

HZ_INLINE unsigned fr_node_hit(const hz_bvh_node_t *n, const frustum_t *f, vf tfar_max, vf *tmin_out)
{
    return fr_planes_hit(ldn(n, f->nx), ldn(n, f->ny), ldn(n, f->nz), ldn(n, f->fx), ldn(n, f->fy), ldn(n, f->fz), f,
                         tfar_max, tmin_out);
}

/* Lanes whose own ray meets child j of node n within [tnear, cull[lane]] (the lane's slab test). */
HZ_INLINE unsigned fr_lanes_hit(const hz_bvh_node_t *n, unsigned j, const frustum_t *f, vf cull)
{
    const char *c = (const char *)n + 4u * j;
#define PLANE(off) vf_set1(*(const float *)(const void *)(c + (off)))
    const vf tnx = vf_mul(vf_sub(PLANE(f->nx), f->o[0]), f->r[0]);
    const vf tny = vf_mul(vf_sub(PLANE(f->ny), f->o[1]), f->r[1]);
    const vf tnz = vf_mul(vf_sub(PLANE(f->nz), f->o[2]), f->r[2]);
    const vf tfx = vf_mul(vf_sub(PLANE(f->fx), f->o[0]), f->r[0]);
    const vf tfy = vf_mul(vf_sub(PLANE(f->fy), f->o[1]), f->r[1]);
    const vf tfz = vf_mul(vf_sub(PLANE(f->fz), f->o[2]), f->r[2]);
#undef PLANE
    const vf tmin = vf_maxn(vf_maxn(tnx, tny), vf_maxn(tnz, f->ltnear));
    const vf tmax = vf_minn(vf_mul(vf_minn(vf_minn(tfx, tfy), tfz), vf_set1(HZ_BVH_ROBUST)), cull);
    return vm_bits(vf_le(tmin, tmax));
}

/* One triangle (block slot s) against the packet's lanes lm (see woop). */
HZ_INLINE unsigned fr_tri_hit(const hz_bvh_block_t *b, unsigned s, const frustum_t *f, vf tfar, unsigned lm,
                              vf *t_out, vf *v_out, vf *w_out, vf *det_out)
{
    return woop(vf_sub(vf_set1(b->v[0][f->kx][s]), f->okx), vf_sub(vf_set1(b->v[0][f->ky][s]), f->oky),
                vf_sub(vf_set1(b->v[0][f->kz][s]), f->okz), vf_sub(vf_set1(b->v[1][f->kx][s]), f->okx),
                vf_sub(vf_set1(b->v[1][f->ky][s]), f->oky), vf_sub(vf_set1(b->v[1][f->kz][s]), f->okz),
                vf_sub(vf_set1(b->v[2][f->kx][s]), f->okx), vf_sub(vf_set1(b->v[2][f->ky][s]), f->oky),
                vf_sub(vf_set1(b->v[2][f->kz][s]), f->okz), f->sx, f->sy, f->sz, f->ltnear, tfar, lm, t_out,
                v_out, w_out, det_out);
}

/* The rays of a call: packets of KW lanes (a packet kernel's one packet, or a tile's source packets). */
typedef struct tsrc {
    const hz_bvh_rayw_t *ray; /* the first packet's rays; `stride` bytes from one packet to the next */
    size_t stride;
    uint32_t n; /* packets */
} tsrc_t;

HZ_INLINE const hz_bvh_rayw_t *src_packet(const tsrc_t *s, uint32_t p)
{
    return (const hz_bvh_rayw_t *)(const void *)((const char *)s->ray + (size_t)p * s->stride);
}

/* Lane i of a single packet is lane i of its call. */
static const uint16_t packet_lanes[W] = { 0, 1, 2, 3,
#if W > 4
                                          4, 5, 6, 7
#endif
};

/* Asks the any-hit callback about the lanes lm of a test's hits on block slot `slot` (its t, V, W, det), lane i
 * being lane li[i] of the call's rays s; returns the lanes it accepts. */
static unsigned lanes_anyhit(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const tsrc_t *s, const uint16_t *li,
                             uint32_t slot, unsigned lm, vf t, vf V, vf Wv, vf det)
{
    float tv[W] HZ_ALIGNED(32), vv[W] HZ_ALIGNED(32), wv[W] HZ_ALIGNED(32), dv[W] HZ_ALIGNED(32);
    vf_store(tv, t), vf_store(vv, V), vf_store(wv, Wv), vf_store(dv, det);
    for (unsigned x = lm; x; x &= x - 1) {
        const unsigned i = (unsigned)__builtin_ctz(x);
        const uint32_t id = src_packet(s, li[i] / W)->id[li[i] % W];
        if (!hz_bvh_anyhit(bvh, ctx, slot, tv[i], vv[i], wv[i], dv[i], id, (int)(li[i] % W)))
            lm &= ~(1u << i);
    }
    return lm;
}

/* lanes_anyhit for one packet's lanes. */
static unsigned packet_anyhit(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const hz_bvh_rayw_t *ray, uint32_t slot,
                              unsigned lm, vf t, vf V, vf Wv, vf det)
{
    const tsrc_t s = { ray, sizeof *ray, 1 };
    return lanes_anyhit(bvh, ctx, &s, packet_lanes, slot, lm, t, V, Wv, det);
}

/* A packet's best hits so far, lane by lane (the closest-hit packet kernels; the distances live apart). */
typedef struct pbest {
    vf v, w, det, n[3]; /* edge weights, determinant and geometric normal (hz_bvh_best_finish's) */
    vi prim, slot;      /* triangle (0x7FFFFFFF: none) and block slot (-1: none) */
} pbest_t;

HZ_INLINE void pbest_init(pbest_t *b)
{
    b->v = b->w = vf_set1(0.0f);
    b->det = vf_set1(1.0f);
    b->n[0] = b->n[1] = b->n[2] = vf_set1(0.0f);
    b->prim = vi_set1(0x7FFFFFFF);
    b->slot = vi_set1(-1);
}

/* The lanes `better` take the hit (t, V, W, det) on triangle prim at block slot hs, with normal (n0, n1, n2). */
HZ_INLINE void pbest_take(pbest_t *b, vf *tfar, vm better, vf t, vf V, vf Wv, vf det, vi prim, uint32_t hs, vf n0,
                          vf n1, vf n2)
{
    *tfar = vf_sel(better, t, *tfar);
    b->v = vf_sel(better, V, b->v);
    b->w = vf_sel(better, Wv, b->w);
    b->det = vf_sel(better, det, b->det);
    b->prim = vi_sel(better, prim, b->prim);
    b->slot = vi_sel(better, vi_set1((int32_t)hs), b->slot);
    b->n[0] = vf_sel(better, n0, b->n[0]);
    b->n[1] = vf_sel(better, n1, b->n[1]);
    b->n[2] = vf_sel(better, n2, b->n[2]);
}

/* The best hits into rh, in the lanes that hit: u = v * (1 / det) as hz_bvh_best_finish. */
static void packet_put_hits(hz_bvh_rayhitw_t *rh, vf tfar, const pbest_t *b)
{
    const vm hitm = vi_gt(b->slot, vi_set1(-1));
    if (!vm_bits(hitm))
        return;
    const vf rdet = vf_div(vf_set1(1.0f), b->det);
    vf_store(rh->ray.tfar, vf_sel(hitm, tfar, vf_load(rh->ray.tfar)));
    vf_store(rh->hit.u, vf_sel(hitm, vf_mul(b->v, rdet), vf_load(rh->hit.u)));
    vf_store(rh->hit.v, vf_sel(hitm, vf_mul(b->w, rdet), vf_load(rh->hit.v)));
    vf_store(rh->hit.ng_x, vf_sel(hitm, b->n[0], vf_load(rh->hit.ng_x)));
    vf_store(rh->hit.ng_y, vf_sel(hitm, b->n[1], vf_load(rh->hit.ng_y)));
    vf_store(rh->hit.ng_z, vf_sel(hitm, b->n[2], vf_load(rh->hit.ng_z)));
    vi_store(rh->hit.prim_id, vi_sel(hitm, b->prim, vi_load(rh->hit.prim_id)));
    vi_store(rh->hit.geom_id, vi_sel(hitm, vi_set1(0), vi_load(rh->hit.geom_id)));
    vi_store(rh->hit.inst_id[0], vi_sel(hitm, vi_set1(-1), vi_load(rh->hit.inst_id[0])));
}

/* Closest hits of a packet. The best hit of every lane lives in vectors (t, triangle, slot, weights, normal); a
 * triangle updates all lanes it beats at once; any-hit triangles go lane by lane through the callback. */
static void frustum_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const frustum_t *f, hz_bvh_rayhitw_t *rh,
                            hz_bvh_counters_t *k)
{
    (void)k; /* counters exist only with HZ_FEATURE_STATS */
    uint32_t st_c[HZ_BVH_STACK + W];
    float st_d[HZ_BVH_STACK + W];
    int sp = 0;
    uint32_t cur = 0;
    const hz_bvh_node_t *const nodes = bvh->nodes;
    const hz_bvh_block_t *const blocks = bvh->blocks;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    vf tfar = f->ltfar;
    pbest_t pb;
    pbest_init(&pb);
    float tfar_max = vf_hmax(tfar) * HZ_BVH_CULL; /* for culling nodes (see bvh.h) */
    vf vtfar_max = vf_set1(tfar_max);
    for (;;) {
        /* cur is an inner node here: leaf children are tested at once, against the lanes that reach them
         * (nearest first), inner children go through the ordered stack */
        const hz_bvh_node_t *n = &nodes[cur];
        vf tmin;
        HZ_BVH_COUNT(k, nodes, 1);
        const unsigned m = fr_node_hit(n, f, vtfar_max, &tmin);
        const unsigned leafbits = vi_signs(vi_load(n->child)) & m;
        if (leafbits) {
            float d[W] HZ_ALIGNED(32);
            vf_store(d, tmin);
            unsigned order[W];
            const unsigned nl = sort_by(leafbits, d, order);
            bool changed = false;
            for (unsigned q = 0; q < nl; q++) {
                const unsigned j = order[q];
                if (d[j] > tfar_max)
                    break;
                const unsigned lanes = fr_lanes_hit(n, j, f, vf_mul(tfar, vf_set1(HZ_BVH_CULL))) & f->active;
                if (!lanes)
                    continue;
                const uint32_t cw = n->child[j], slot = hz_bvh_leaf_slot(cw), cnt = hz_bvh_leaf_count(cw);
                const hz_bvh_block_t *b = &blocks[slot / W];
                HZ_BVH_COUNT(k, tris, (uint64_t)cnt * (uint64_t)__builtin_popcount(lanes));
                for (unsigned s = slot % W; s < slot % W + cnt; s++) {
                    vf t, V, Wv, det;
                    const unsigned mm = fr_tri_hit(b, s, f, tfar, lanes, &t, &V, &Wv, &det);
                    if (!mm)
                        continue;
                    const uint32_t pw = b->prim[s], prim = pw & HZ_BVH_PRIM_MASK, hs = (slot / W) * W + s;
                    const vi vprim = vi_set1((int32_t)prim);
                    /* t < best, or t == best and a lower triangle index (best starts at 0x7FFFFFFF) */
                    unsigned bm = vm_bits(vm_or(vf_lt(t, tfar), vm_and(vf_eq(t, tfar), vi_gt(pb.prim, vprim)))) & mm;
                    if (!bm)
                        continue;
                    if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT) &&
                        !(bm = packet_anyhit(bvh, ctx, &rh->ray, hs, bm, t, V, Wv, det)))
                        continue;
                    float e1[3], e2[3]; /* the normal as hz_bvh_best_finish computes it */
                    for (int c = 0; c < 3; c++) {
                        e1[c] = b->v[1][c][s] - b->v[0][c][s];
                        e2[c] = b->v[2][c][s] - b->v[0][c][s];
                    }
                    pbest_take(&pb, &tfar, vm_of(bm), t, V, Wv, det, vprim, hs,
                               vf_set1(e1[1] * e2[2] - e1[2] * e2[1]), vf_set1(e1[2] * e2[0] - e1[0] * e2[2]),
                               vf_set1(e1[0] * e2[1] - e1[1] * e2[0]));
                    changed = true;
                }
                if (changed) {
                    tfar_max = vf_hmax(tfar) * HZ_BVH_CULL;
                    vtfar_max = vf_set1(tfar_max);
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
done:
    packet_put_hits(rh, tfar, &pb);
}

/* =========================================================================================================
 * motion packets: a frustum packet (frustum_init: shared direction signs and watertight axes) whose lanes each
 * sit at their own time. A node's interval test takes the union of its boxes over the segments the lanes sit
 * in, each lerped at its lanes' smallest and largest weight there (a lane's lerp at a weight between those lies
 * between the two up to a few ulps: 12 units in the last place of 2^-24 of the larger key plane's magnitude at
 * most, so the union is widened by 2^-19 of it), so it only preselects; leaf children get each lane's
 * own slab test on the boxes lerped at its time, and their triangles each lane's own lerped vertices: the
 * single-ray motion kernel's operations lane by lane (node_hit_at, leaf_hit_at, hz_bvh_best_finish_at), so the
 * hits are bit for bit the single rays'. Inner nodes cost one test per packet instead of one per lane. */
#define MFR_SINGLE_LANES 2 /* a subtree that this many lanes or fewer reach goes on as single rays */

typedef struct mtimes {
    vf f[4], g[4];         /* per level m: the lanes' weights there (hz_bvh_ray_levels) and 1 - weight */
    unsigned lanes[4][8];  /* per level m and segment v there: the active lanes that sit in it */
    unsigned present[4];   /* per level: bit v where lanes[m][v] is not empty */
    float wlo[4][8], whi[4][8]; /* per level and segment: its lanes' smallest and largest weight */
    uint32_t level;        /* the finest level: 2^level segments between the keys (bvh->key_level) */
} mtimes_t;

static void mtimes_init(mtimes_t *mt, const hz_bvh_t *bvh, const hz_bvh_rayw_t *ray, unsigned act)
{
    const uint32_t L = bvh->key_level;
    float fm[4][W] HZ_ALIGNED(32);
    hz_memset(mt->lanes, 0, sizeof mt->lanes);
    hz_memset(mt->present, 0, sizeof mt->present);
    mt->level = L;
    for (unsigned l = 0; l < W; l++) {
        hz_bvh_ray_t r; /* as the single-ray path times its rays (accel.c ray_time) */
        hz_accel_time_segment(ray->time[l], bvh->time_keys, &r.seg, &r.f);
        hz_bvh_ray_levels(&r, ray->time[l], L);
        for (uint32_t m = 0; m <= L; m++) {
            fm[m][l] = r.fm[m];
            if (act >> l & 1u) {
                const uint32_t v = r.seg >> (L - m);
                mt->lanes[m][v] |= 1u << l;
                mt->present[m] |= 1u << v;
            }
        }
    }
    for (uint32_t m = 0; m <= L; m++)
        for (unsigned pv = mt->present[m]; pv; pv &= pv - 1) {
            const unsigned v = (unsigned)__builtin_ctz(pv);
            float lo = 2.0f, hi = -1.0f;
            for (unsigned x = mt->lanes[m][v]; x; x &= x - 1) {
                const float w = fm[m][__builtin_ctz(x)];
                lo = w < lo ? w : lo, hi = w > hi ? w : hi;
            }
            mt->wlo[m][v] = lo, mt->whi[m][v] = hi;
        }
    for (uint32_t m = 0; m <= L; m++) {
        mt->f[m] = vf_load(fm[m]);
        mt->g[m] = vf_sub(vf_set1(1.0f), mt->f[m]); /* 1 - f, as the single ray's scalar */
    }
}

/* Node i's first box set (the sets of its segments follow) and the level m of its segments. */
HZ_INLINE const hz_bvh_mbox_t *mt_sets(const hz_bvh_t *bvh, uint32_t i, const mtimes_t *mt, uint32_t *m)
{
    if (bvh->mref) {
        const uint32_t w = bvh->mref[i];
        *m = w & 3u;
        return &bvh->mbox[w >> 2];
    }
    *m = mt->level;
    return &bvh->mbox[(size_t)i * bvh->time_keys];
}

HZ_INLINE vf mt_margin(vf a, vf b)
{
    return vf_mul(vf_minn(vf_maxn(vf_abs(a), vf_abs(b)), vf_set1(3.40282347e38f)), vf_set1(1.9073486328125e-6f));
}

/* The packet's interval test of a node's children over the lanes' segments (see above): sets and m from
 * mt_sets. */
HZ_INLINE unsigned mfr_node_hit(const hz_bvh_mbox_t *sets, uint32_t m, const frustum_t *f, const mtimes_t *mt,
                                vf tfar_max, vf *tmin_out)
{
    vf lo[3], hi[3];
    for (unsigned pv = mt->present[m], first = 1; pv; pv &= pv - 1, first = 0) {
        const unsigned v = (unsigned)__builtin_ctz(pv);
        const hz_bvh_mbox_t *a = &sets[v], *b = a + 1;
        const float *const al[3] = { a->lo_x, a->lo_y, a->lo_z }, *const bl[3] = { b->lo_x, b->lo_y, b->lo_z };
        const float *const ah[3] = { a->hi_x, a->hi_y, a->hi_z }, *const bh[3] = { b->hi_x, b->hi_y, b->hi_z };
        const vf f0 = vf_set1(mt->wlo[m][v]), g0 = vf_set1(1.0f - mt->wlo[m][v]);
        const vf f1 = vf_set1(mt->whi[m][v]), g1 = vf_set1(1.0f - mt->whi[m][v]);
        for (int k = 0; k < 3; k++) {
            const vf la = vf_load(al[k]), lb = vf_load(bl[k]), ha = vf_load(ah[k]), hb = vf_load(bh[k]);
            const vf l0 = vf_add(vf_mul(g0, la), vf_mul(f0, lb)), l1 = vf_add(vf_mul(g1, la), vf_mul(f1, lb));
            const vf h0 = vf_add(vf_mul(g0, ha), vf_mul(f0, hb)), h1 = vf_add(vf_mul(g1, ha), vf_mul(f1, hb));
            const vf l = vf_sub(vf_minn(l0, l1), mt_margin(la, lb)), h = vf_add(vf_maxn(h0, h1), mt_margin(ha, hb));
            lo[k] = first ? l : vf_minn(lo[k], l);
            hi[k] = first ? h : vf_maxn(hi[k], h);
        }
    }
    const unsigned ng = f->negs;
    return fr_planes_hit(ng & 1u ? hi[0] : lo[0], ng & 2u ? hi[1] : lo[1], ng & 4u ? hi[2] : lo[2],
                         ng & 1u ? lo[0] : hi[0], ng & 2u ? lo[1] : hi[1], ng & 4u ? lo[2] : hi[2], f, tfar_max,
                         tmin_out);
}

/* Lanes whose own ray meets child j of a node (sets, m from mt_sets) at its time within [tnear, cull[lane]]
 * (node_hit_at's boxes). */
HZ_INLINE unsigned mfr_lanes_hit(const hz_bvh_mbox_t *sets, uint32_t m, unsigned j, const frustum_t *f,
                                 const mtimes_t *mt, vf cull)
{
    const size_t off[6] = { f->nx, f->ny, f->nz, f->fx, f->fy, f->fz };
    vf pl[6];
    for (unsigned pv = mt->present[m], first = 1; pv; pv &= pv - 1, first = 0) {
        const unsigned v = (unsigned)__builtin_ctz(pv);
        const char *a = (const char *)(const void *)&sets[v] + 4u * j;
        const char *b = (const char *)(const void *)&sets[v + 1] + 4u * j;
        const vm in = vm_of(mt->lanes[m][v]);
        for (int q = 0; q < 6; q++) {
            const vf x = vf_add(vf_mul(mt->g[m], vf_set1(*(const float *)(const void *)(a + off[q]))),
                                vf_mul(mt->f[m], vf_set1(*(const float *)(const void *)(b + off[q]))));
            pl[q] = first ? x : vf_sel(in, x, pl[q]);
        }
    }
    const vf tnx = vf_mul(vf_sub(pl[0], f->o[0]), f->r[0]);
    const vf tny = vf_mul(vf_sub(pl[1], f->o[1]), f->r[1]);
    const vf tnz = vf_mul(vf_sub(pl[2], f->o[2]), f->r[2]);
    const vf tfx = vf_mul(vf_sub(pl[3], f->o[0]), f->r[0]);
    const vf tfy = vf_mul(vf_sub(pl[4], f->o[1]), f->r[1]);
    const vf tfz = vf_mul(vf_sub(pl[5], f->o[2]), f->r[2]);
    const vf tmin = vf_maxn(vf_maxn(tnx, tny), vf_maxn(tnz, f->ltnear));
    const vf tmax = vf_minn(vf_mul(vf_minn(vf_minn(tfx, tfy), tfz), vf_set1(HZ_BVH_ROBUST)), cull);
    return vm_bits(vf_le(tmin, tmax));
}

/* Slot s of block blk at each lane's time (hz_bvh_block_at's lerp, lane by lane): P[vertex][axis]. */
HZ_INLINE void mt_vertices(const hz_bvh_t *bvh, uint32_t blk, unsigned s, const mtimes_t *mt, vf P[3][3])
{
    const uint32_t L = mt->level;
    for (unsigned pv = mt->present[L], first = 1; pv; pv &= pv - 1, first = 0) {
        const unsigned v = (unsigned)__builtin_ctz(pv);
        const hz_bvh_block_t *a = &bvh->kblocks[v][blk], *b = &bvh->kblocks[v + 1][blk];
        const vm in = vm_of(mt->lanes[L][v]);
        for (int q = 0; q < 3; q++)
            for (int ax = 0; ax < 3; ax++) {
                const vf x = vf_add(vf_mul(mt->g[L], vf_set1(a->v[q][ax][s])),
                                    vf_mul(mt->f[L], vf_set1(b->v[q][ax][s])));
                P[q][ax] = first ? x : vf_sel(in, x, P[q][ax]);
            }
    }
}

/* Closest hits of a motion packet: frustum_closest's traversal, except that every child the interval test passes
 * also gets the lanes' own tests and goes on with the lanes that meet it (the interval test over a segment's
 * weights is loose where the motion is large against a node: without the lane tests, a packet of scattered
 * times visited more nodes than its rays one by one). */
static void mfr_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const frustum_t *f, const mtimes_t *mt,
                        hz_bvh_rayhitw_t *rh, hz_bvh_counters_t *k)
{
    (void)k; /* counters exist only with HZ_FEATURE_STATS */
    uint32_t st_c[HZ_BVH_STACK + W];
    float st_d[HZ_BVH_STACK + W];
    unsigned st_m[HZ_BVH_STACK + W];
    int sp = 0;
    unsigned cm = f->active; /* the lanes that reach cur */
    uint32_t cur = 0;
    const hz_bvh_node_t *const nodes = bvh->nodes;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    vf tfar = f->ltfar;
    pbest_t pb;
    pbest_init(&pb);
    float tfar_max = vf_hmax(tfar) * HZ_BVH_CULL; /* for culling nodes (see bvh.h) */
    vf vtfar_max = vf_set1(tfar_max);
    for (;;) {
        if (__builtin_popcount(cm) <= MFR_SINGLE_LANES) {
            /* few lanes reach this subtree: they go on as single rays at their times, from their best hits */
            float tv[W] HZ_ALIGNED(32), vv[W] HZ_ALIGNED(32), wv[W] HZ_ALIGNED(32), dv[W] HZ_ALIGNED(32);
            float n0[W] HZ_ALIGNED(32), n1[W] HZ_ALIGNED(32), n2[W] HZ_ALIGNED(32);
            int32_t pv[W] HZ_ALIGNED(32), sv[W] HZ_ALIGNED(32);
            vf_store(tv, tfar), vf_store(vv, pb.v), vf_store(wv, pb.w), vf_store(dv, pb.det);
            vf_store(n0, pb.n[0]), vf_store(n1, pb.n[1]), vf_store(n2, pb.n[2]);
            vi_store(pv, pb.prim), vi_store(sv, pb.slot);
            for (unsigned x = cm; x; x &= x - 1) {
                const unsigned l = (unsigned)__builtin_ctz(x);
                hz_bvh_ray_t r;
                if (!hz_bvh_ray_prep(&r, rh->ray.org_x[l], rh->ray.org_y[l], rh->ray.org_z[l], rh->ray.dir_x[l],
                                     rh->ray.dir_y[l], rh->ray.dir_z[l], rh->ray.tnear[l], tv[l]))
                    continue;
                hz_accel_time_segment(rh->ray.time[l], bvh->time_keys, &r.seg, &r.f);
                if (bvh->mref)
                    hz_bvh_ray_levels(&r, rh->ray.time[l], bvh->key_level);
                sray_t s1;
                sray_init(&s1, &r);
                hz_bvh_best_t best;
                best.slot = sv[l] < 0 ? HZ_ACCEL_INVALID_ID : (uint32_t)sv[l];
                best.prim = sv[l] < 0 ? HZ_ACCEL_INVALID_ID : (uint32_t)pv[l];
                best.v = vv[l], best.w = wv[l], best.det = dv[l];
                const uint32_t before = best.slot;
                closest_core(bvh, ctx, &r, &s1, cur, &best, rh->ray.id[l], (int)l, k, true, false);
                if (best.slot == before)
                    continue;
                tv[l] = r.tfar, pv[l] = (int32_t)best.prim, sv[l] = (int32_t)best.slot;
                vv[l] = best.v, wv[l] = best.w, dv[l] = best.det;
                float ng[3], u, v; /* u and v come again from the lane's weights at the end */
                hz_bvh_best_finish_at(bvh, &best, &r, ng, &u, &v);
                n0[l] = ng[0], n1[l] = ng[1], n2[l] = ng[2];
            }
            tfar = vf_load(tv), pb.v = vf_load(vv), pb.w = vf_load(wv), pb.det = vf_load(dv);
            pb.n[0] = vf_load(n0), pb.n[1] = vf_load(n1), pb.n[2] = vf_load(n2);
            pb.prim = vi_load(pv), pb.slot = vi_load(sv);
            tfar_max = vf_hmax(tfar) * HZ_BVH_CULL;
            vtfar_max = vf_set1(tfar_max);
            goto pop;
        }
        const hz_bvh_node_t *n = &nodes[cur];
        vf tmin;
        HZ_BVH_COUNT(k, nodes, 1);
        uint32_t lvl;
        const hz_bvh_mbox_t *sets = mt_sets(bvh, cur, mt, &lvl);
        const unsigned m = mfr_node_hit(sets, lvl, f, mt, vtfar_max, &tmin);
        const unsigned leafbits = vi_signs(vi_load(n->child)) & m;
        if (leafbits) {
            float d[W] HZ_ALIGNED(32);
            vf_store(d, tmin);
            unsigned order[W];
            const unsigned nl = sort_by(leafbits, d, order);
            bool changed = false;
            for (unsigned q = 0; q < nl; q++) {
                const unsigned j = order[q];
                if (d[j] > tfar_max)
                    break;
                const unsigned lanes = mfr_lanes_hit(sets, lvl, j, f, mt, vf_mul(tfar, vf_set1(HZ_BVH_CULL))) & cm;
                if (!lanes)
                    continue;
                const uint32_t cw = n->child[j], slot = hz_bvh_leaf_slot(cw), cnt = hz_bvh_leaf_count(cw);
                const uint32_t blk = slot / W;
                HZ_BVH_COUNT(k, tris, (uint64_t)cnt * (uint64_t)__builtin_popcount(lanes));
                for (unsigned s = slot % W; s < slot % W + cnt; s++) {
                    vf P[3][3], t, V, Wv, det;
                    mt_vertices(bvh, blk, s, mt, P);
                    const unsigned mm =
                        woop(vf_sub(P[0][f->kx], f->okx), vf_sub(P[0][f->ky], f->oky), vf_sub(P[0][f->kz], f->okz),
                             vf_sub(P[1][f->kx], f->okx), vf_sub(P[1][f->ky], f->oky), vf_sub(P[1][f->kz], f->okz),
                             vf_sub(P[2][f->kx], f->okx), vf_sub(P[2][f->ky], f->oky), vf_sub(P[2][f->kz], f->okz),
                             f->sx, f->sy, f->sz, f->ltnear, tfar, lanes, &t, &V, &Wv, &det);
                    if (!mm)
                        continue;
                    const uint32_t pw = bvh->kblocks[0][blk].prim[s], prim = pw & HZ_BVH_PRIM_MASK, hs = blk * W + s;
                    const vi vprim = vi_set1((int32_t)prim);
                    /* t < best, or t == best and a lower triangle index (best starts at 0x7FFFFFFF) */
                    unsigned bm = vm_bits(vm_or(vf_lt(t, tfar), vm_and(vf_eq(t, tfar), vi_gt(pb.prim, vprim)))) & mm;
                    if (!bm)
                        continue;
                    if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT) &&
                        !(bm = packet_anyhit(bvh, ctx, &rh->ray, hs, bm, t, V, Wv, det)))
                        continue;
                    /* the normal of the triangle at each lane's time, as hz_bvh_best_finish_at computes it */
                    vf e1[3], e2[3];
                    for (int c = 0; c < 3; c++) {
                        e1[c] = vf_sub(P[1][c], P[0][c]);
                        e2[c] = vf_sub(P[2][c], P[0][c]);
                    }
                    pbest_take(&pb, &tfar, vm_of(bm), t, V, Wv, det, vprim, hs,
                               vf_sub(vf_mul(e1[1], e2[2]), vf_mul(e1[2], e2[1])),
                               vf_sub(vf_mul(e1[2], e2[0]), vf_mul(e1[0], e2[2])),
                               vf_sub(vf_mul(e1[0], e2[1]), vf_mul(e1[1], e2[0])));
                    changed = true;
                }
                if (changed) {
                    tfar_max = vf_hmax(tfar) * HZ_BVH_CULL;
                    vtfar_max = vf_set1(tfar_max);
                }
            }
        }
        unsigned inner = m & ~leafbits, im[W];
        if (inner) {
            const vf cull = vf_mul(tfar, vf_set1(HZ_BVH_CULL));
            for (unsigned x = inner; x; x &= x - 1) {
                const unsigned j = (unsigned)__builtin_ctz(x);
                im[j] = mfr_lanes_hit(sets, lvl, j, f, mt, cull) & cm;
                if (!im[j])
                    inner &= ~(1u << j);
            }
        }
        if (inner) {
            float d[W] HZ_ALIGNED(32);
            vf_store(d, tmin);
            unsigned order[W];
            const unsigned ni = sort_by(inner, d, order);
            for (unsigned q = ni - 1u; q > 0; q--) /* farthest first: the nearest is popped next */
                st_c[sp] = n->child[order[q]], st_d[sp] = d[order[q]], st_m[sp] = im[order[q]], sp++;
            cur = n->child[order[0]], cm = im[order[0]];
            continue;
        }
    pop:
        for (;;) {
            if (sp == 0)
                goto done;
            --sp;
            if (st_d[sp] <= tfar_max) {
                cur = st_c[sp], cm = st_m[sp];
                break;
            }
        }
    }
done:
    packet_put_hits(rh, tfar, &pb);
}

/* Occlusion of a packet: lanes drop out as they find a hit; children in any order. The interval test of a
 * node's boxes only preselects: each child it passes gets the lanes' own slab tests, and goes on with the lanes
 * that meet it, so the packet visits about the union of its rays' nodes. A subtree that one lane reaches goes on
 * as that single ray. The bounds are those of the live lanes: when lanes drop out they are recomputed.
 * Returns the blocked lanes. `motion` (a constant at every call): the motion packet's tests (mfr_closest), and a
 * subtree that two lanes or fewer reach goes on as single rays at their times. */
HZ_INLINE unsigned any_packet_core(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const frustum_t *f0, const mtimes_t *mt,
                                   const hz_bvh_rayw_t *ray, hz_bvh_counters_t *k, const bool motion)
{
    uint32_t st_c[HZ_BVH_STACK + W];
    unsigned st_m[HZ_BVH_STACK + W];
    int sp = 0;
    uint32_t cur = 0;
    const hz_bvh_node_t *const nodes = bvh->nodes;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    frustum_t fl;
    const frustum_t *f = f0;
    vf tfar = f->ltfar;
    vf cull = vf_mul(tfar, vf_set1(HZ_BVH_CULL)); /* per lane, for culling (see bvh.h) */
    vf vtfar_max = vf_set1(vf_hmax(tfar) * HZ_BVH_CULL);
    unsigned live = f->active, cm = live; /* cm: the live lanes that reach cur */
    int single_lane = -1;                 /* the lane prepared in r1 / s1 */
    hz_bvh_ray_t r1;
    sray_t s1;
    for (;;) {
        unsigned done = 0;
        if (__builtin_popcount(cm) <= (motion ? MFR_SINGLE_LANES : 1)) {
            /* few lanes reach this subtree: each goes on alone, with its own box tests */
            for (unsigned x = cm; x; x &= x - 1) {
            const unsigned i = (unsigned)__builtin_ctz(x);
            if ((int)i != single_lane) {
                hz_bvh_ray_prep(&r1, ray->org_x[i], ray->org_y[i], ray->org_z[i], ray->dir_x[i], ray->dir_y[i],
                                ray->dir_z[i], ray->tnear[i], ray->tfar[i]);
                if (motion) {
                    hz_accel_time_segment(ray->time[i], bvh->time_keys, &r1.seg, &r1.f);
                    if (bvh->mref)
                        hz_bvh_ray_levels(&r1, ray->time[i], bvh->key_level);
                }
                sray_init(&s1, &r1);
                single_lane = (int)i;
            }
            if (motion ? any_motion(bvh, ctx, &r1, &s1, cur, ray->id[i], (int)i, k)
                       : any_from(bvh, ctx, &r1, &s1, cur, ray->id[i], (int)i, k))
                done |= 1u << i;
            }
        } else {
            const hz_bvh_node_t *n = &nodes[cur];
            vf tmin;
            HZ_BVH_COUNT(k, nodes, 1);
            uint32_t lvl = 0;
            const hz_bvh_mbox_t *sets = motion ? mt_sets(bvh, cur, mt, &lvl) : NULL;
            const unsigned m =
                motion ? mfr_node_hit(sets, lvl, f, mt, vtfar_max, &tmin) : fr_node_hit(n, f, vtfar_max, &tmin);
            for (unsigned cb = m; cb; cb &= cb - 1) {
                const unsigned j = (unsigned)__builtin_ctz(cb);
                unsigned lanes =
                    (motion ? mfr_lanes_hit(sets, lvl, j, f, mt, cull) : fr_lanes_hit(n, j, f, cull)) & cm & ~done;
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
                const uint32_t blk = slot / W;
                HZ_BVH_COUNT(k, tris, (uint64_t)cnt * (uint64_t)__builtin_popcount(lanes));
                for (unsigned s = slot % W; s < slot % W + cnt && lanes; s++) {
                    vf t, V, Wv, det;
                    unsigned mm;
                    if (motion) {
                        vf P[3][3];
                        mt_vertices(bvh, blk, s, mt, P);
                        mm = woop(vf_sub(P[0][f->kx], f->okx), vf_sub(P[0][f->ky], f->oky), vf_sub(P[0][f->kz], f->okz),
                                  vf_sub(P[1][f->kx], f->okx), vf_sub(P[1][f->ky], f->oky), vf_sub(P[1][f->kz], f->okz),
                                  vf_sub(P[2][f->kx], f->okx), vf_sub(P[2][f->ky], f->oky), vf_sub(P[2][f->kz], f->okz),
                                  f->sx, f->sy, f->sz, f->ltnear, tfar, lanes, &t, &V, &Wv, &det);
                    } else {
                        mm = fr_tri_hit(&bvh->blocks[blk], s, f, tfar, lanes, &t, &V, &Wv, &det);
                    }
                    if (!mm)
                        continue;
                    const uint32_t hs = blk * W + s;
                    if (anyhit && ((motion ? bvh->kblocks[0] : bvh->blocks)[blk].prim[s] & HZ_BVH_PRIM_ANYHIT))
                        mm = packet_anyhit(bvh, ctx, ray, hs, mm, t, V, Wv, det);
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
            tfar = vf_sel(vm_of(done), vf_set1(-__builtin_inff()), tfar);
            cull = vf_mul(tfar, vf_set1(HZ_BVH_CULL));
            if (live & (live - 1)) {
                if (f != &fl) {
                    fl = *f0;
                    f = &fl;
                }
                fl.active = live;
                frustum_bounds(&fl, live, fl.ltnear);
            }
            vtfar_max = vf_set1(vf_hmax(tfar) * HZ_BVH_CULL);
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

static unsigned frustum_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const frustum_t *f0, const hz_bvh_rayw_t *ray,
                            hz_bvh_counters_t *k)
{
    return any_packet_core(bvh, ctx, f0, NULL, ray, k, false);
}

static unsigned mfr_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const frustum_t *f0, const mtimes_t *mt,
                        const hz_bvh_rayw_t *ray, hz_bvh_counters_t *k)
{
    return any_packet_core(bvh, ctx, f0, mt, ray, k, true);
}

/* =========================================================================================================
 * tiles: large coherent packets */
#define TILE_RAYS 256u
#define TILE_CHUNKS (TILE_RAYS / W)
/* Groups of fewer rays go as single rays (incoherent packets split into many small groups, whose interval
 * bounds are loose: diffuse rays as packets ran at a third of their single-ray speed with groups of 2). */
#define TILE_MIN_GROUP (W / 2 > 2 ? W / 2 : 2)
#define KEY_NONE 0xFFu   /* lane without a (valid) ray */
#define KEY_SINGLE 0xFEu /* a zero direction component: the interval bounds need finite reciprocals */

/* Bounds of the shear constants (sx, sy) of some rays, as broadcast vectors (tile_cull). */
typedef struct tshear {
    vf sxlo, sxhi, sylo, syhi;
} tshear_t;

/* KW rays of one group: per-lane slab and watertight-test data, and the best hit so far. Lanes without a ray
 * have tnear = +inf and tfar = cull = -inf, so no test passes for them. */
typedef struct tchunk {
    vf o[3], d[3], r[3];
    vf okx, oky, okz, sx, sy, sz;
    vf tnear, tfar, cull; /* cull = tfar * HZ_BVH_CULL (see bvh.h) */
    tshear_t sh;          /* bounds of the live lanes' shear constants (tile_cull) */
    vf bv, bw, bdet;      /* closest: the best hit's edge weights */
    vf bng[3];            /* closest: its geometric normal (hz_bvh_best_finish's) */
    vi bprim, bslot;      /* closest: its triangle (0x7FFFFFFF: none) and block slot (-1: none) */
} tchunk_t;

/* The interval bounds of a group: near and far plane offsets by the direction signs, origin bounds for the
 * near and far planes, reciprocal ranges, and the smallest tnear. */
typedef struct tbounds {
    size_t nx, ny, nz, fx, fy, fz;
    vf on[3], of[3], rmin[3], rmax[3];
    vf tnear;
} tbounds_t;

typedef struct tgroup {
    tchunk_t ch[TILE_CHUNKS];
    unsigned live[TILE_CHUNKS];     /* lanes with a ray still searching */
    float cmax[TILE_CHUNKS];        /* closest: largest cull distance of the chunk's live lanes */
    uint16_t src[TILE_CHUNKS][W];   /* the lane's index in the call's rays: packet * KW + lane */
    uint32_t nch;
    unsigned negs;                  /* bit k: the group's direction is negative on axis k */
    int kx, ky, kz;
    size_t nx, ny, nz, fx, fy, fz;  /* forward near / far plane offsets (per-lane slab tests) */
    bool common;                    /* every ray starts at the same point, bit for bit */
    bool direct;                    /* chunk c is packet c of the call, lane for lane */
    float org[3];                   /* that point */
    bool reversed;                  /* occlusion: bounds from the rays' common far end */
    float ia_tmax;                  /* occlusion: the interval test's far limit */
    tbounds_t b;
} tgroup_t;

/* The rays of the call as arrays (the packet structs of the board's width, read through these). */
/* Per lane of the call: KEY_NONE, KEY_SINGLE, or the group key (direction signs | kz << 3), with
 * hz_bvh_ray_prep's contract check and axis choice, a packet at a time; act[p]: packet p's lanes with a group
 * key. Returns the key every such lane shares, or KEY_NONE when they differ (or there are none) or some lane
 * is KEY_SINGLE. */
static unsigned tile_keys(const tsrc_t *s, const int32_t *valid, int32_t *key, unsigned *act)
{
    const vf inf = vf_set1(__builtin_inff()), zero = vf_set1(0.0f);
    unsigned common = KEY_NONE;
    bool mixed = false;
    for (uint32_t p = 0; p < s->n; p++) {
        const hz_bvh_rayw_t *ray = src_packet(s, p);
        unsigned vb = 0;
        for (int i = 0; i < W; i++)
            vb |= (unsigned)(valid[(size_t)p * W + (unsigned)i] != 0) << i;
        vm ok = vm_of(vb), nonzero = vm_of(0), fin = vm_of((1u << W) - 1u);
        vi kv = vi_set1(0);
        vf ad[3];
        for (int k = 0; k < 3; k++) {
            const vf o = vf_load(k == 0 ? ray->org_x : k == 1 ? ray->org_y : ray->org_z);
            const vf d = vf_load(k == 0 ? ray->dir_x : k == 1 ? ray->dir_y : ray->dir_z);
            ok = vm_and(ok, vm_and(vf_lt(vf_abs(o), inf), vf_lt(vf_abs(d), inf)));
            nonzero = vm_or(nonzero, vf_neu(d, zero));
            const vf r = vf_div(vf_set1(1.0f), d);
            fin = vm_and(fin, vf_lt(vf_abs(r), inf));
            kv = vi_or(kv, vi_and(vm_as_vi(vf_lt(r, zero)), vi_set1(1 << k)));
            ad[k] = vf_abs(d);
        }
        ok = vm_and(vm_and(ok, nonzero), vf_le(vf_load(ray->tnear), vf_load(ray->tfar))); /* false on NaN */
        const vm y_over = vf_gt(ad[1], ad[0]);
        const vm z_over = vf_gt(ad[2], vf_sel(y_over, ad[1], ad[0]));
        kv = vi_or(kv, vi_sel(z_over, vi_set1(16), vi_sel(y_over, vi_set1(8), vi_set1(0))));
        kv = vi_sel(fin, kv, vi_set1(KEY_SINGLE));
        kv = vi_sel(ok, kv, vi_set1(KEY_NONE));
        int32_t *kp = key + (size_t)p * W;
        vi_storeu(kp, kv);
        const unsigned okb = vm_bits(ok), grp = okb & vm_bits(fin);
        act[p] = grp;
        if (okb != grp)
            mixed = true;
        for (unsigned x = grp; x && !mixed; x &= x - 1) {
            const unsigned k = (unsigned)kp[__builtin_ctz(x)];
            if (common == KEY_NONE)
                common = k;
            else if (k != common)
                mixed = true;
        }
    }
    return mixed ? KEY_NONE : common;
}

/* The group key's axes and plane offsets. */
static void tile_axes(tgroup_t *g, unsigned key)
{
    const unsigned negs = key & 7u;
    const int kz = (int)(key >> 3);
    int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
    if ((negs >> kz) & 1u) {
        const int t = kx;
        kx = ky;
        ky = t;
    }
    g->negs = negs, g->kx = kx, g->ky = ky, g->kz = kz;
    const size_t a = offsetof(hz_bvh_node_t, hi_x) - offsetof(hz_bvh_node_t, lo_x);
    g->nx = offsetof(hz_bvh_node_t, lo_x) + ((negs & 1u) ? a : 0);
    g->ny = offsetof(hz_bvh_node_t, lo_y) + ((negs & 2u) ? a : 0);
    g->nz = offsetof(hz_bvh_node_t, lo_z) + ((negs & 4u) ? a : 0);
    g->fx = offsetof(hz_bvh_node_t, lo_x) + ((negs & 1u) ? 0 : a);
    g->fy = offsetof(hz_bvh_node_t, lo_y) + ((negs & 2u) ? 0 : a);
    g->fz = offsetof(hz_bvh_node_t, lo_z) + ((negs & 4u) ? 0 : a);
    g->reversed = false;
}

/* Chunk c from vectors: per-lane preparation as hz_bvh_ray_prep, lanes `live` (the others get empty ranges). */
HZ_INLINE void chunk_set(tgroup_t *g, uint32_t c, const vf *o, const vf *d, vf tn, vf tf, unsigned live)
{
    tchunk_t *ch = &g->ch[c];
    const vm lm = vm_of(live);
    for (int k = 0; k < 3; k++) {
        ch->o[k] = o[k];
        ch->d[k] = d[k];
        ch->r[k] = vf_div(vf_set1(1.0f), d[k]); /* as hz_bvh_ray_prep */
    }
    ch->okx = o[g->kx], ch->oky = o[g->ky], ch->okz = o[g->kz];
    /* shear constants exactly as hz_bvh_ray_prep computes them */
    ch->sx = vf_mul(d[g->kx], ch->r[g->kz]);
    ch->sy = vf_mul(d[g->ky], ch->r[g->kz]);
    ch->sz = ch->r[g->kz];
    const vf inf = vf_set1(__builtin_inff()), ninf = vf_set1(-__builtin_inff());
    ch->sh.sxlo = vf_set1(vf_hmin(vf_sel(lm, ch->sx, inf)));
    ch->sh.sxhi = vf_set1(vf_hmax(vf_sel(lm, ch->sx, ninf)));
    ch->sh.sylo = vf_set1(vf_hmin(vf_sel(lm, ch->sy, inf)));
    ch->sh.syhi = vf_set1(vf_hmax(vf_sel(lm, ch->sy, ninf)));
    ch->tnear = vf_sel(lm, tn, vf_set1(__builtin_inff()));
    ch->tfar = vf_sel(lm, tf, vf_set1(-__builtin_inff()));
    ch->cull = vf_mul(ch->tfar, vf_set1(HZ_BVH_CULL));
    ch->bv = vf_set1(0.0f), ch->bw = vf_set1(0.0f), ch->bdet = vf_set1(1.0f);
    ch->bng[0] = ch->bng[1] = ch->bng[2] = vf_set1(0.0f);
    ch->bprim = vi_set1(0x7FFFFFFF), ch->bslot = vi_set1(-1);
    g->live[c] = live;
    g->cmax[c] = vf_hmax(ch->cull);
}

/* Every ray of the call in one group: packet p is chunk p as it is (no compaction), loaded as vectors. */
static void tile_load_direct(tgroup_t *g, const tsrc_t *s, const unsigned *act, unsigned key)
{
    tile_axes(g, key);
    g->nch = s->n;
    g->direct = true;
    uint32_t p0 = 0;
    while (p0 + 1u < s->n && !act[p0])
        p0++;
    const hz_bvh_rayw_t *r0 = src_packet(s, p0);
    const unsigned l0 = (unsigned)__builtin_ctz(act[p0] | (1u << (W - 1)));
    g->org[0] = r0->org_x[l0], g->org[1] = r0->org_y[l0], g->org[2] = r0->org_z[l0];
    vi ob[3];
    for (int k = 0; k < 3; k++) {
        int32_t bits;
        hz_memcpy(&bits, &g->org[k], 4);
        ob[k] = vi_set1(bits);
    }
    unsigned same = 0, all = 0;
    for (uint32_t c = 0; c < s->n; c++) {
        const hz_bvh_rayw_t *ray = src_packet(s, c);
        const vf o[3] = { vf_load(ray->org_x), vf_load(ray->org_y), vf_load(ray->org_z) };
        const vf d[3] = { vf_load(ray->dir_x), vf_load(ray->dir_y), vf_load(ray->dir_z) };
        chunk_set(g, c, o, d, vf_load(ray->tnear), vf_load(ray->tfar), act[c]);
        const vm eq = vm_and(vm_and(vi_eq(vf_as_vi(o[0]), ob[0]), vi_eq(vf_as_vi(o[1]), ob[1])),
                             vi_eq(vf_as_vi(o[2]), ob[2]));
        same += (unsigned)__builtin_popcount(vm_bits(eq) & act[c]);
        all += (unsigned)__builtin_popcount(act[c]);
        for (unsigned i = 0; i < W; i++)
            g->src[c][i] = (uint16_t)(c * W + i);
    }
    g->common = same == all;
}

/* Loads the rays lanes[0..n) (lane indices of the call, all with group key `key`) into the group's chunks,
 * compacted. */
static void tile_load(tgroup_t *g, const tsrc_t *s, const uint16_t *lanes, uint32_t n, unsigned key)
{
    tile_axes(g, key);
    g->nch = (n + W - 1u) / W;
    g->direct = false;
    const float inf = __builtin_inff();
    const hz_bvh_rayw_t *r0 = src_packet(s, lanes[0] / W);
    const unsigned l0 = lanes[0] % W;
    g->org[0] = r0->org_x[l0], g->org[1] = r0->org_y[l0], g->org[2] = r0->org_z[l0];
    uint32_t ob[3];
    hz_memcpy(ob, g->org, sizeof ob);
    bool common = true;
    for (uint32_t c = 0; c < g->nch; c++) {
        float o[3][W] HZ_ALIGNED(32), d[3][W] HZ_ALIGNED(32), tn[W] HZ_ALIGNED(32), tf[W] HZ_ALIGNED(32);
        unsigned live = 0;
        for (unsigned i = 0; i < W; i++) {
            const uint32_t q = c * W + i;
            const uint16_t li = q < n ? lanes[q] : lanes[0];
            const hz_bvh_rayw_t *r = src_packet(s, li / W);
            const unsigned l = li % W;
            o[0][i] = r->org_x[l], o[1][i] = r->org_y[l], o[2][i] = r->org_z[l];
            d[0][i] = r->dir_x[l], d[1][i] = r->dir_y[l], d[2][i] = r->dir_z[l];
            tn[i] = q < n ? r->tnear[l] : inf;
            tf[i] = q < n ? r->tfar[l] : -inf;
            g->src[c][i] = q < n ? li : 0xFFFFu;
            if (q < n) {
                live |= 1u << i;
                uint32_t bits[3];
                const float ov[3] = { o[0][i], o[1][i], o[2][i] };
                hz_memcpy(bits, ov, sizeof bits);
                common = common && bits[0] == ob[0] && bits[1] == ob[1] && bits[2] == ob[2];
            }
        }
        const vf ov[3] = { vf_load(o[0]), vf_load(o[1]), vf_load(o[2]) };
        const vf dv[3] = { vf_load(d[0]), vf_load(d[1]), vf_load(d[2]) };
        chunk_set(g, c, ov, dv, vf_load(tn), vf_load(tf), live);
    }
    g->common = common;
}

/* Bounds over the live lanes, in one pass: the forward interval bounds (origins, reciprocals, tnear) into g->b,
 * and with `occl` (occlusion) the far limit g->ia_tmax (the live lanes' largest cull distance) and, where every
 * live ray has a finite end, the bounds from the far ends instead when those are closer together than the
 * origins (g->reversed): ends e = o + tfar d, back along -d for s in [0, tfar - tnear] (each segment point is
 * e - s d). The computed ends are off the exact ones by a few ulps: the end box is widened by 2^-16 of the
 * coordinates' magnitudes, far more than that and than the slab tests' own tolerance (the per-lane tests,
 * which decide, accept boxes within about 2^-21 of a segment), so the interval test only ever drops boxes that
 * no lane's test would accept. Minima go through vf_hmins KW at a time (maxima as minima of negatives). */
enum { B_OLO = 0, B_RLO = 3, B_TN = 6, B_OHI = 7, B_RHI = 10, B_CULL = 13, B_ELO = 14, B_EHI = 17, B_SMAX = 20,
       B_ALL = 21 };

static void tile_bounds(tgroup_t *g, bool occl)
{
    const vf inf = vf_set1(__builtin_inff()), zero = vf_set1(0.0f);
    vf v[(B_ALL + W - 1) / W * W];
    for (int q = 0; q < B_ALL; q++)
        v[q] = inf;
    for (int q = B_ALL; q < (int)(sizeof v / sizeof v[0]); q++)
        v[q] = inf;
    bool fin = occl && !g->common;
    for (uint32_t c = 0; c < g->nch; c++) {
        if (!g->live[c])
            continue;
        const tchunk_t *ch = &g->ch[c];
        const vm m = vm_of(g->live[c]);
        for (int k = 0; k < 3; k++) {
            v[B_OLO + k] = vf_minn(vf_sel(m, ch->o[k], inf), v[B_OLO + k]);
            v[B_OHI + k] = vf_minn(vf_sel(m, vf_sub(zero, ch->o[k]), inf), v[B_OHI + k]);
            v[B_RLO + k] = vf_minn(vf_sel(m, ch->r[k], inf), v[B_RLO + k]);
            v[B_RHI + k] = vf_minn(vf_sel(m, vf_sub(zero, ch->r[k]), inf), v[B_RHI + k]);
        }
        v[B_TN] = vf_minn(vf_sel(m, ch->tnear, inf), v[B_TN]);
        if (!occl)
            continue;
        v[B_CULL] = vf_minn(vf_sel(m, vf_sub(zero, ch->cull), inf), v[B_CULL]);
        if (!fin)
            continue;
        fin = vm_bits(vm_and(m, vf_lt(vf_abs(ch->tfar), inf))) == g->live[c];
        vf e[3], mag = zero;
        for (int k = 0; k < 3; k++) {
            const vf td = vf_mul(ch->tfar, ch->d[k]);
            e[k] = vf_add(ch->o[k], td);
            mag = vf_maxn(vf_add(vf_add(vf_abs(ch->o[k]), vf_abs(td)), vf_abs(e[k])), mag);
        }
        const vf pad = vf_add(vf_mul(mag, vf_set1(1.0f / 65536.0f)), vf_set1(1e-30f));
        for (int k = 0; k < 3; k++) {
            v[B_ELO + k] = vf_minn(vf_sel(m, vf_sub(e[k], pad), inf), v[B_ELO + k]);
            v[B_EHI + k] = vf_minn(vf_sel(m, vf_sub(vf_sub(zero, e[k]), pad), inf), v[B_EHI + k]);
        }
        v[B_SMAX] = vf_minn(vf_sel(m, vf_sub(ch->tnear, ch->tfar), inf), v[B_SMAX]);
    }
    float r[(B_ALL + W - 1) / W * W] HZ_ALIGNED(32);
    const int nq = occl ? (fin ? B_ALL : B_ELO) : B_CULL;
    for (int q = 0; q < nq; q += W)
        vf_hmins(v + q, r + q);
    tbounds_t *b = &g->b;
    float ospread = 0.0f, espread = 0.0f;
    for (int k = 0; k < 3; k++) {
        const float olo = r[B_OLO + k], ohi = -r[B_OHI + k];
        const bool neg = (g->negs >> k) & 1u;
        /* near plane: lower bound of (plane - o) * r over the group; far plane: upper bound */
        b->on[k] = vf_set1(neg ? olo : ohi);
        b->of[k] = vf_set1(neg ? ohi : olo);
        b->rmin[k] = vf_set1(r[B_RLO + k]);
        b->rmax[k] = vf_set1(-r[B_RHI + k]);
        ospread += ohi - olo;
        if (fin)
            espread += -r[B_EHI + k] - r[B_ELO + k];
    }
    b->tnear = vf_set1(r[B_TN]);
    b->nx = g->nx, b->ny = g->ny, b->nz = g->nz, b->fx = g->fx, b->fy = g->fy, b->fz = g->fz;
    g->reversed = false;
    if (!occl)
        return;
    g->ia_tmax = -r[B_CULL];
    if (!fin || !(espread < ospread))
        return;
    /* from the ends: origin box E, reciprocals of -d (-r: the negated forward range), s in [0, smax] */
    const size_t a = offsetof(hz_bvh_node_t, hi_x) - offsetof(hz_bvh_node_t, lo_x);
    const size_t base[3] = { offsetof(hz_bvh_node_t, lo_x), offsetof(hz_bvh_node_t, lo_y),
                             offsetof(hz_bvh_node_t, lo_z) };
    size_t nn[3], ff[3];
    for (int k = 0; k < 3; k++) {
        const float elo = r[B_ELO + k], ehi = -r[B_EHI + k];
        const bool neg = !((g->negs >> k) & 1u); /* the reversed direction's sign */
        b->on[k] = vf_set1(neg ? elo : ehi);
        b->of[k] = vf_set1(neg ? ehi : elo);
        b->rmin[k] = vf_set1(r[B_RHI + k]);  /* min of -r = -max r */
        b->rmax[k] = vf_set1(-r[B_RLO + k]); /* max of -r = -min r */
        nn[k] = base[k] + (neg ? a : 0);
        ff[k] = base[k] + (neg ? 0 : a);
    }
    b->nx = nn[0], b->ny = nn[1], b->nz = nn[2], b->fx = ff[0], b->fy = ff[1], b->fz = ff[2];
    b->tnear = zero;
    g->ia_tmax = -r[B_SMAX] * HZ_BVH_CULL; /* max(tfar - tnear), widened */
    g->reversed = true;
}

/* The group's children of n whose interval bounds meet [b->tnear, tmax]; entry distances in *tmin_out. The
 * bounds enclose every live lane's (o, r) and the float operations are monotone, so this passes every box that
 * some lane's own slab test (below) passes. */
HZ_INLINE unsigned ia_node_hit(const hz_bvh_node_t *n, const tbounds_t *b, vf tmax_lim, vf *tmin_out)
{
    /* written out per axis: as a loop over arrays GCC kept the planes' offsets and the slab distances in memory */
    const vf pnx = vf_sub(ldn(n, b->nx), b->on[0]), pny = vf_sub(ldn(n, b->ny), b->on[1]);
    const vf pnz = vf_sub(ldn(n, b->nz), b->on[2]);
    const vf pfx = vf_sub(ldn(n, b->fx), b->of[0]), pfy = vf_sub(ldn(n, b->fy), b->of[1]);
    const vf pfz = vf_sub(ldn(n, b->fz), b->of[2]);
    const vf nx = vf_minn(vf_mul(pnx, b->rmin[0]), vf_mul(pnx, b->rmax[0]));
    const vf ny = vf_minn(vf_mul(pny, b->rmin[1]), vf_mul(pny, b->rmax[1]));
    const vf nz = vf_minn(vf_mul(pnz, b->rmin[2]), vf_mul(pnz, b->rmax[2]));
    const vf fx = vf_maxn(vf_mul(pfx, b->rmin[0]), vf_mul(pfx, b->rmax[0]));
    const vf fy = vf_maxn(vf_mul(pfy, b->rmin[1]), vf_mul(pfy, b->rmax[1]));
    const vf fz = vf_maxn(vf_mul(pfz, b->rmin[2]), vf_mul(pfz, b->rmax[2]));
    const vf tmin = vf_maxn(vf_maxn(nx, ny), vf_maxn(nz, b->tnear));
    const vf tmax = vf_minn(vf_mul(vf_minn(vf_minn(fx, fy), fz), vf_set1(HZ_BVH_ROBUST)), tmax_lim);
    *tmin_out = tmin;
    return vm_bits(vf_le(tmin, tmax));
}

/* The forward near / far plane offsets of a group, passed by value so they stay in registers (through pointers
 * the build's -fno-strict-aliasing reloaded them after every store). */
typedef struct tplanes {
    size_t nx, ny, nz, fx, fy, fz;
} tplanes_t;

/* Lanes of chunk ch whose own ray meets child j of n within [tnear, cull] (the scalar reference's slab test). */
HZ_INLINE unsigned lanes_hit(const hz_bvh_node_t *n, unsigned j, tplanes_t pl, const tchunk_t *ch)
{
    const char *c = (const char *)n + 4u * j;
#define PLANE(off) vf_set1(*(const float *)(const void *)(c + (off)))
    const vf tnx = vf_mul(vf_sub(PLANE(pl.nx), ch->o[0]), ch->r[0]);
    const vf tny = vf_mul(vf_sub(PLANE(pl.ny), ch->o[1]), ch->r[1]);
    const vf tnz = vf_mul(vf_sub(PLANE(pl.nz), ch->o[2]), ch->r[2]);
    const vf tfx = vf_mul(vf_sub(PLANE(pl.fx), ch->o[0]), ch->r[0]);
    const vf tfy = vf_mul(vf_sub(PLANE(pl.fy), ch->o[1]), ch->r[1]);
    const vf tfz = vf_mul(vf_sub(PLANE(pl.fz), ch->o[2]), ch->r[2]);
#undef PLANE
    const vf tmin = vf_maxn(vf_maxn(tnx, tny), vf_maxn(tnz, ch->tnear));
    const vf tmax = vf_minn(vf_mul(vf_minn(vf_minn(tfx, tfy), tfz), vf_set1(HZ_BVH_ROBUST)), ch->cull);
    return vm_bits(vf_le(tmin, tmax));
}

/* The first and the last chunk in [a, b] with live lanes that reach child j; false when none does. *l0: the
 * first chunk's lanes. */
HZ_INLINE bool child_range(const hz_bvh_node_t *n, unsigned j, tplanes_t pl, const tgroup_t *g, unsigned a,
                           unsigned b, unsigned *first, unsigned *last, unsigned *l0)
{
    unsigned c = a, l = 0;
    for (; c <= b; c++)
        if ((l = lanes_hit(n, j, pl, &g->ch[c]) & g->live[c]) != 0)
            break;
    if (c > b)
        return false;
    unsigned e = b;
    while (e > c && !(lanes_hit(n, j, pl, &g->ch[e]) & g->live[e]))
        e--;
    *first = c, *last = e, *l0 = l;
    return true;
}

/* The ray-independent part of the watertight test for the slots of block b, when every ray starts at org: the
 * vertices relative to it in the group's axes, the plane's normal and its distance term (hz_bvh_tri_test's
 * operations; in the per-lane form every lane computes these same values). */
typedef struct tpre {
    float a[3][W] HZ_ALIGNED(32), bb[3][W] HZ_ALIGNED(32), c[3][W] HZ_ALIGNED(32);
    float n[3][W] HZ_ALIGNED(32), num[W] HZ_ALIGNED(32);
    /* edge functions U, V, W as affine functions of a ray's shear (sx, sy): e0 + sx ex + sy ey, and a bound em on
     * how far the float test's value can be from it (see tile_cull) */
    float e0[3][W] HZ_ALIGNED(32), ex[3][W] HZ_ALIGNED(32), ey[3][W] HZ_ALIGNED(32), em[3][W] HZ_ALIGNED(32);
} tpre_t;

/* Edge function P x Q of woop (Px Qy - Py Qx with P = (pkx - sx pkz, pky - sy pkz), Q likewise) expands exactly
 * to (pkx qky - pky qkx) + sx (pky qkz - pkz qky) + sy (pkz qkx - pkx qkz): the sx sy terms cancel. */
HZ_INLINE void edge_affine(const vf *pk, const vf *qk, float *e0, float *ex, float *ey, float *em)
{
    vf_store(e0, vf_sub(vf_mul(pk[0], qk[1]), vf_mul(pk[1], qk[0])));
    vf_store(ex, vf_sub(vf_mul(pk[1], qk[2]), vf_mul(pk[2], qk[1])));
    vf_store(ey, vf_sub(vf_mul(pk[2], qk[0]), vf_mul(pk[0], qk[2])));
    /* |sx|, |sy| <= 1 (kz is the dominant axis): the float test's operations and this evaluation each round off by
     * a few 2^-24 of M = (|pkx| + |pkz|)(|qky| + |qkz|) + (|pky| + |pkz|)(|qkx| + |qkz|); em = 2^-16 M */
    const vf pz = vf_abs(pk[2]), qz = vf_abs(qk[2]);
    const vf m = vf_add(vf_mul(vf_add(vf_abs(pk[0]), pz), vf_add(vf_abs(qk[1]), qz)),
                        vf_mul(vf_add(vf_abs(pk[1]), pz), vf_add(vf_abs(qk[0]), qz)));
    vf_store(em, vf_mul(m, vf_set1(1.0f / 65536.0f)));
}

static void tile_pre(const hz_bvh_block_t *b, const tgroup_t *g, tpre_t *p)
{
    const int ax[3] = { g->kx, g->ky, g->kz };
    vf v[3][3];
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            v[i][k] = vf_sub(vf_load(b->v[i][ax[k]]), vf_set1(g->org[ax[k]]));
    const vf e1x = vf_sub(v[1][0], v[0][0]), e1y = vf_sub(v[1][1], v[0][1]), e1z = vf_sub(v[1][2], v[0][2]);
    const vf e2x = vf_sub(v[2][0], v[0][0]), e2y = vf_sub(v[2][1], v[0][1]), e2z = vf_sub(v[2][2], v[0][2]);
    const vf nx = vf_sub(vf_mul(e1y, e2z), vf_mul(e1z, e2y));
    const vf ny = vf_sub(vf_mul(e1z, e2x), vf_mul(e1x, e2z));
    const vf nz = vf_sub(vf_mul(e1x, e2y), vf_mul(e1y, e2x));
    for (int k = 0; k < 3; k++) {
        vf_store(p->a[k], v[0][k]);
        vf_store(p->bb[k], v[1][k]);
        vf_store(p->c[k], v[2][k]);
    }
    vf_store(p->n[0], nx), vf_store(p->n[1], ny), vf_store(p->n[2], nz);
    vf_store(p->num, vf_add(vf_add(vf_mul(nx, v[0][0]), vf_mul(ny, v[0][1])), vf_mul(nz, v[0][2])));
    edge_affine(v[2], v[1], p->e0[0], p->ex[0], p->ey[0], p->em[0]); /* U = c x b */
    edge_affine(v[0], v[2], p->e0[1], p->ex[1], p->ey[1], p->em[1]); /* V = a x c */
    edge_affine(v[1], v[0], p->e0[2], p->ex[2], p->ey[2], p->em[2]); /* W = b x a */
}

/* Slots of the precomputed block that some lane of chunk ch may hit: over the chunk's shear box [sxlo, sxhi] x
 * [sylo, syhi] each edge function lies in an interval (widened by em); a slot with one edge surely positive and
 * another surely negative for every lane fails woop's sign test in every lane, so it is skipped. */
/* One edge's interval over the shear box: whether it is surely positive (*pos) / surely negative (*neg). */
HZ_INLINE void edge_signs(const tpre_t *p, int e, const tshear_t *sh, vm *pos, vm *neg)
{
    const vf ex = vf_load(p->ex[e]), ey = vf_load(p->ey[e]), e0 = vf_load(p->e0[e]), em = vf_load(p->em[e]);
    const vf x1 = vf_mul(sh->sxlo, ex), x2 = vf_mul(sh->sxhi, ex);
    const vf y1 = vf_mul(sh->sylo, ey), y2 = vf_mul(sh->syhi, ey);
    const vf lo = vf_sub(vf_add(vf_add(e0, vf_minn(x1, x2)), vf_minn(y1, y2)), em);
    const vf hi = vf_add(vf_add(vf_add(e0, vf_maxn(x1, x2)), vf_maxn(y1, y2)), em);
    *pos = vf_gt(lo, vf_set1(0.0f));
    *neg = vf_lt(hi, vf_set1(0.0f));
}

HZ_INLINE unsigned tile_cull(const tpre_t *p, const tshear_t *sh)
{
    vm p0, n0, p1, n1, p2, n2;
    edge_signs(p, 0, sh, &p0, &n0);
    edge_signs(p, 1, sh, &p1, &n1);
    edge_signs(p, 2, sh, &p2, &n2);
    return ~vm_bits(vm_and(vm_or(vm_or(p0, p1), p2), vm_or(vm_or(n0, n1), n2)));
}

/* One triangle (slot s) against the lanes lm of chunk ch, from the precomputed terms: woop's operations with the
 * ray-independent ones already done. */
HZ_INLINE unsigned tri_hit_pre(const tpre_t *p, unsigned s, const tchunk_t *ch, vf tfar, unsigned lm, vf *t_out,
                               vf *v_out, vf *w_out, vf *det_out)
{
    const vf akx = vf_set1(p->a[0][s]), aky = vf_set1(p->a[1][s]), akz = vf_set1(p->a[2][s]);
    const vf bkx = vf_set1(p->bb[0][s]), bky = vf_set1(p->bb[1][s]), bkz = vf_set1(p->bb[2][s]);
    const vf ckx = vf_set1(p->c[0][s]), cky = vf_set1(p->c[1][s]), ckz = vf_set1(p->c[2][s]);
    const vf sx = ch->sx, sy = ch->sy;
    const vf ax = vf_sub(akx, vf_mul(sx, akz)), ay = vf_sub(aky, vf_mul(sy, akz));
    const vf bx = vf_sub(bkx, vf_mul(sx, bkz)), by = vf_sub(bky, vf_mul(sy, bkz));
    const vf cx = vf_sub(ckx, vf_mul(sx, ckz)), cy = vf_sub(cky, vf_mul(sy, ckz));
    const vf U = vf_sub(vf_mul(cx, by), vf_mul(cy, bx));
    const vf V = vf_sub(vf_mul(ax, cy), vf_mul(ay, cx));
    const vf Wv = vf_sub(vf_mul(bx, ay), vf_mul(by, ax));
    const vf z = vf_set1(0.0f);
    const vm neg = vm_or(vm_or(vf_lt(U, z), vf_lt(V, z)), vf_lt(Wv, z));
    const vm pos = vm_or(vm_or(vf_gt(U, z), vf_gt(V, z)), vf_gt(Wv, z));
    const vf det = vf_add(vf_add(U, V), Wv);
    const unsigned m = vm_bits(vm_andn(vf_neu(det, z), vm_and(neg, pos))) & lm;
    if (!m)
        return 0;
    const vf den = vf_add(vf_add(vf_mul(vf_set1(p->n[0][s]), sx), vf_mul(vf_set1(p->n[1][s]), sy)),
                          vf_set1(p->n[2][s]));
    const vf t = vf_div(vf_mul(vf_set1(p->num[s]), ch->sz), den);
    const vm in =
        vm_and(vf_lt(vf_abs(t), vf_set1(__builtin_inff())), vm_and(vf_ge(t, ch->tnear), vf_le(t, tfar)));
    *t_out = t, *v_out = V, *w_out = Wv, *det_out = det;
    return m & vm_bits(in);
}

/* One triangle against the lanes lm of chunk ch, each lane from its own origin. */
HZ_INLINE unsigned tri_hit_lanes(const hz_bvh_block_t *b, unsigned s, const tgroup_t *g, const tchunk_t *ch,
                                 vf tfar, unsigned lm, vf *t_out, vf *v_out, vf *w_out, vf *det_out)
{
    const int kx = g->kx, ky = g->ky, kz = g->kz;
    return woop(vf_sub(vf_set1(b->v[0][kx][s]), ch->okx), vf_sub(vf_set1(b->v[0][ky][s]), ch->oky),
                vf_sub(vf_set1(b->v[0][kz][s]), ch->okz), vf_sub(vf_set1(b->v[1][kx][s]), ch->okx),
                vf_sub(vf_set1(b->v[1][ky][s]), ch->oky), vf_sub(vf_set1(b->v[1][kz][s]), ch->okz),
                vf_sub(vf_set1(b->v[2][kx][s]), ch->okx), vf_sub(vf_set1(b->v[2][ky][s]), ch->oky),
                vf_sub(vf_set1(b->v[2][kz][s]), ch->okz), ch->sx, ch->sy, ch->sz, ch->tnear, tfar, lm, t_out,
                v_out, w_out, det_out);
}

/* The lane's ray as the scalar kernels prepare it (any-hit arguments, single-ray continuations). */
static void tile_lane_ray(const tsrc_t *s, uint16_t li, hz_bvh_ray_t *r, uint32_t *id)
{
    const hz_bvh_rayw_t *p = src_packet(s, li / W);
    const unsigned l = li % W;
    hz_bvh_ray_prep(r, p->org_x[l], p->org_y[l], p->org_z[l], p->dir_x[l], p->dir_y[l], p->dir_z[l], p->tnear[l],
                    p->tfar[l]);
    *id = p->id[l];
}


/* Leaf (slots [slot, slot + cnt)) against the lanes `lanes` of chunk c: the best hits move in the vectors (held
 * in registers through the loop: the chunk is memory the compiler cannot tell from the block's). */
HZ_INLINE bool leaf_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const tsrc_t *src, tgroup_t *g, unsigned c,
                            unsigned lanes, uint32_t slot, unsigned sm, const tpre_t *pre, bool anyhit)
{
    tchunk_t *ch = &g->ch[c];
    const hz_bvh_block_t *b = &bvh->blocks[slot / W];
    vf tfar = ch->tfar, bv = ch->bv, bw = ch->bw, bdet = ch->bdet, bn0 = ch->bng[0], bn1 = ch->bng[1],
       bn2 = ch->bng[2];
    vi bprim = ch->bprim, bslot = ch->bslot;
    bool changed = false;
    for (; sm; sm &= sm - 1) {
        const unsigned s = (unsigned)__builtin_ctz(sm);
        vf t, V, Wv, det;
        unsigned mm = pre ? tri_hit_pre(pre, s, ch, tfar, lanes, &t, &V, &Wv, &det)
                          : tri_hit_lanes(b, s, g, ch, tfar, lanes, &t, &V, &Wv, &det);
        if (!mm)
            continue;
        const uint32_t pw = b->prim[s], prim = pw & HZ_BVH_PRIM_MASK, hs = (slot / W) * W + s;
        const vi vprim = vi_set1((int32_t)prim);
        /* t < best, or t == best and a lower triangle index (best starts at 0x7FFFFFFF) */
        unsigned bm = vm_bits(vm_or(vf_lt(t, tfar), vm_and(vf_eq(t, tfar), vi_gt(bprim, vprim)))) & mm;
        if (!bm)
            continue;
        if (anyhit && (pw & HZ_BVH_PRIM_ANYHIT) &&
            !(bm = lanes_anyhit(bvh, ctx, src, g->src[c], hs, bm, t, V, Wv, det)))
            continue;
        const vm better = vm_of(bm);
        tfar = vf_sel(better, t, tfar);
        bv = vf_sel(better, V, bv);
        bw = vf_sel(better, Wv, bw);
        bdet = vf_sel(better, det, bdet);
        bprim = vi_sel(better, vprim, bprim);
        bslot = vi_sel(better, vi_set1((int32_t)hs), bslot);
        /* the normal as hz_bvh_best_finish computes it, once per winning triangle (no gathers at the end) */
        float e1[3], e2[3];
        for (int q = 0; q < 3; q++) {
            e1[q] = b->v[1][q][s] - b->v[0][q][s];
            e2[q] = b->v[2][q][s] - b->v[0][q][s];
        }
        bn0 = vf_sel(better, vf_set1(e1[1] * e2[2] - e1[2] * e2[1]), bn0);
        bn1 = vf_sel(better, vf_set1(e1[2] * e2[0] - e1[0] * e2[2]), bn1);
        bn2 = vf_sel(better, vf_set1(e1[0] * e2[1] - e1[1] * e2[0]), bn2);
        changed = true;
    }
    if (changed) {
        ch->tfar = tfar, ch->bv = bv, ch->bw = bw, ch->bdet = bdet, ch->bprim = bprim, ch->bslot = bslot;
        ch->bng[0] = bn0, ch->bng[1] = bn1, ch->bng[2] = bn2;
        ch->cull = vf_mul(tfar, vf_set1(HZ_BVH_CULL));
        g->cmax[c] = vf_hmax(ch->cull); /* lanes without a ray hold -inf */
    }
    return changed;
}

HZ_INLINE float range_max(const tgroup_t *g, unsigned a, unsigned b)
{
    float m = g->cmax[a];
    for (unsigned c = a + 1; c <= b; c++)
        m = g->cmax[c] > m ? g->cmax[c] : m;
    return m;
}

/* Closest hits of a group. */
HZ_INLINE void closest_tile_core(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const tsrc_t *src, tgroup_t *g,
                                 hz_bvh_counters_t *k, const bool one)
{
    (void)k; /* counters exist only with HZ_FEATURE_STATS */
    uint32_t st_n[HZ_BVH_STACK + W];
    uint8_t st_a[HZ_BVH_STACK + W], st_b[HZ_BVH_STACK + W];
    float st_d[HZ_BVH_STACK + W];
    int sp = 0;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    tile_bounds(g, false);
    tpre_t pre;
    tshear_t gs; /* the whole group's shear bounds: leaves none of whose triangles any ray may hit are skipped */
    gs = g->ch[0].sh;
    for (uint32_t c = 1; c < g->nch; c++) {
        gs.sxlo = vf_minn(g->ch[c].sh.sxlo, gs.sxlo), gs.sxhi = vf_maxn(g->ch[c].sh.sxhi, gs.sxhi);
        gs.sylo = vf_minn(g->ch[c].sh.sylo, gs.sylo), gs.syhi = vf_maxn(g->ch[c].sh.syhi, gs.syhi);
    }
    uint32_t cur = 0;
    unsigned a = 0, bnd = one ? 0 : g->nch - 1;
    const hz_bvh_node_t *const nodes = bvh->nodes;
    const tplanes_t pl = { g->nx, g->ny, g->nz, g->fx, g->fy, g->fz };
    const tbounds_t gb = g->b;
    for (;;) {
        const hz_bvh_node_t *n = &nodes[cur];
        float lim = one ? g->cmax[0] : range_max(g, a, bnd);
        vf tmin;
        HZ_BVH_COUNT(k, nodes, 1);
        unsigned m = ia_node_hit(n, &gb, vf_set1(lim), &tmin);
        /* children's ranges: for a one-chunk range inner children keep it (their own nodes test the lanes) */
        unsigned first[W], last[W], l0[W], hit = 0;
        const unsigned leafw = vi_signs(vi_load(n->child)) & m;
        for (unsigned x = a == bnd ? leafw : m; x; x &= x - 1) {
            const unsigned j = (unsigned)__builtin_ctz(x);
            if (child_range(n, j, pl, g, a, bnd, &first[j], &last[j], &l0[j]))
                hit |= 1u << j;
        }
        if (a == bnd)
            for (unsigned x = m & ~leafw; x; x &= x - 1) {
                const unsigned j = (unsigned)__builtin_ctz(x);
                first[j] = last[j] = a;
                hit |= 1u << j;
            }
        float d[W] HZ_ALIGNED(32);
        vf_store(d, tmin);
        const unsigned leaves = hit & leafw;
        if (leaves) {
            unsigned ord[W];
            const unsigned nl = sort_by(leaves, d, ord);
            for (unsigned q = 0; q < nl; q++) {
                const unsigned j = ord[q];
                if (d[j] > lim)
                    break;
                const uint32_t cw = n->child[j], slot = hz_bvh_leaf_slot(cw), cnt = hz_bvh_leaf_count(cw);
                unsigned sm = slot_mask(slot, cnt);
                const bool use_pre = g->common;
                if (use_pre) {
                    tile_pre(&bvh->blocks[slot / W], g, &pre);
                    sm &= tile_cull(&pre, &gs);
                    if (!sm)
                        continue;
                }
                const bool per_chunk = use_pre && (sm & (sm - 1)) != 0 && last[j] > first[j];
                bool changed = false;
                for (unsigned c = first[j]; c <= last[j]; c++) {
                    const unsigned lanes = c == first[j] ? l0[j] : lanes_hit(n, j, pl, &g->ch[c]) & g->live[c];
                    if (!lanes)
                        continue;
                    const unsigned cm = per_chunk ? sm & tile_cull(&pre, &g->ch[c].sh) : sm;
                    HZ_BVH_COUNT(k, tris, (uint64_t)__builtin_popcount(cm) * (uint64_t)__builtin_popcount(lanes));
                    if (cm)
                        changed |= leaf_closest(bvh, ctx, src, g, c, lanes, slot, cm, use_pre ? &pre : NULL, anyhit);
                }
                if (changed)
                    lim = one ? g->cmax[0] : range_max(g, a, bnd);
            }
        }
        const unsigned inner = hit & ~leaves;
        if (inner) {
            unsigned ord[W];
            const unsigned ni = sort_by(inner, d, ord);
            for (unsigned q = ni; q-- > 1;) {
                const unsigned j = ord[q];
                st_n[sp] = n->child[j], st_a[sp] = (uint8_t)first[j], st_b[sp] = (uint8_t)last[j];
                st_d[sp] = d[j];
                sp++;
            }
            const unsigned j = ord[0];
            if (d[j] <= lim) {
                cur = n->child[j], a = first[j], bnd = last[j];
                continue;
            }
        }
        for (;;) {
            if (sp == 0)
                return;
            --sp;
            if (st_d[sp] <= (one ? g->cmax[0] : range_max(g, st_a[sp], st_b[sp]))) {
                cur = st_n[sp], a = st_a[sp], bnd = st_b[sp];
                break;
            }
        }
    }
}

static void tile_closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const tsrc_t *src, tgroup_t *g,
                         hz_bvh_counters_t *k)
{
    if (g->nch == 1) /* a packet: the same traversal with the ranges folded away */
        closest_tile_core(bvh, ctx, src, g, k, true);
    else
        closest_tile_core(bvh, ctx, src, g, k, false);
}

/* The hit attributes of every lane that hit (hz_bvh_best_finish's operations), stored into the call's packets. */
static void tile_write_hits(const tgroup_t *g, hz_bvh_rayhitw_t *rh, size_t stride)
{
    for (uint32_t c = 0; c < g->nch; c++) {
        const tchunk_t *ch = &g->ch[c];
        const vm hitm = vi_gt(ch->bslot, vi_set1(-1));
        const unsigned hb = vm_bits(hitm);
        if (!hb)
            continue;
        /* u = v * (1 / det) as hz_bvh_best_finish; the normal was taken with the hit */
        const vf rdet = vf_div(vf_set1(1.0f), ch->bdet);
        const vf u = vf_mul(ch->bv, rdet), vv = vf_mul(ch->bw, rdet);
        float out[6][W] HZ_ALIGNED(32), tf[W] HZ_ALIGNED(32);
        int32_t prim[W] HZ_ALIGNED(32);
        vf_store(out[0], ch->bng[0]);
        vf_store(out[1], ch->bng[1]);
        vf_store(out[2], ch->bng[2]);
        vf_store(out[3], u);
        vf_store(out[4], vv);
        vf_store(tf, ch->tfar);
        vi_store(prim, ch->bprim);
        if (g->direct) {
            hz_bvh_rayhitw_t *p = (hz_bvh_rayhitw_t *)(void *)((char *)rh + (size_t)c * stride);
            vf_store(p->ray.tfar, vf_sel(hitm, ch->tfar, vf_load(p->ray.tfar)));
            for (int q = 0; q < 5; q++) {
                float *dst = q == 0 ? p->hit.ng_x : q == 1 ? p->hit.ng_y : q == 2 ? p->hit.ng_z : q == 3 ? p->hit.u
                                                                                                      : p->hit.v;
                vf_store(dst, vf_sel(hitm, vf_load(out[q]), vf_load(dst)));
            }
            vi_store(p->hit.prim_id, vi_sel(hitm, ch->bprim, vi_load(p->hit.prim_id)));
            vi_store(p->hit.geom_id, vi_sel(hitm, vi_set1(0), vi_load(p->hit.geom_id)));
            vi_store(p->hit.inst_id[0], vi_sel(hitm, vi_set1(-1), vi_load(p->hit.inst_id[0])));
            continue;
        }
        for (unsigned x = hb; x; x &= x - 1) {
            const unsigned i = (unsigned)__builtin_ctz(x);
            const uint16_t li = g->src[c][i];
            hz_bvh_rayhitw_t *p = (hz_bvh_rayhitw_t *)(void *)((char *)rh + (size_t)(li / W) * stride);
            const unsigned l = li % W;
            p->ray.tfar[l] = tf[i];
            p->hit.ng_x[l] = out[0][i], p->hit.ng_y[l] = out[1][i], p->hit.ng_z[l] = out[2][i];
            p->hit.u[l] = out[3][i], p->hit.v[l] = out[4][i];
            p->hit.prim_id[l] = (uint32_t)prim[i];
            p->hit.geom_id[l] = 0;
            p->hit.inst_id[0][l] = HZ_ACCEL_INVALID_ID;
        }
    }
}

/* Occlusion of a group: returns nothing, clears live lanes as they are blocked (the caller reads the rest). */
HZ_INLINE void any_tile_core(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const tsrc_t *src, tgroup_t *g,
                             unsigned *blocked, hz_bvh_counters_t *k, const bool one)
{
    (void)k; /* counters exist only with HZ_FEATURE_STATS */
    uint32_t st_n[HZ_BVH_STACK + W];
    uint8_t st_a[HZ_BVH_STACK + W], st_b[HZ_BVH_STACK + W];
    unsigned st_l[HZ_BVH_STACK + W];
    int sp = 0;
    const bool anyhit = bvh->has_anyhit && ctx && ctx->anyhit;
    unsigned nlive = 0;
    for (uint32_t c = 0; c < g->nch; c++)
        nlive += (unsigned)__builtin_popcount(g->live[c]);
    tile_bounds(g, true);
    unsigned bounds_live = nlive;
    uint32_t cur = 0;
    unsigned a = 0, bnd = one ? 0 : g->nch - 1, cl = g->nch == 1 ? g->live[0] : 0; /* lanes of chunk a when a == bnd */
    const hz_bvh_node_t *const nodes = bvh->nodes;
    const tplanes_t pl = { g->nx, g->ny, g->nz, g->fx, g->fy, g->fz };
    unsigned single = ~0u; /* the lane prepared in r1 / s1 (chunk * W + lane) */
    hz_bvh_ray_t r1;
    sray_t s1;
    uint32_t id1 = 0;
    for (;;) {
        if (a == bnd && cl && !(cl & (cl - 1))) {
            /* one ray reaches this subtree: it goes on alone, with its own box tests (prepared once per lane) */
            const unsigned i = (unsigned)__builtin_ctz(cl);
            if (single != a * W + i) {
                tile_lane_ray(src, g->src[a][i], &r1, &id1);
                sray_init(&s1, &r1);
                single = a * W + i;
            }
            if (any_from(bvh, ctx, &r1, &s1, cur, id1, (int)(g->src[a][i] % W), k)) {
                blocked[a] |= cl;
                g->live[a] &= ~cl;
                g->ch[a].tfar = vf_sel(vm_of(cl), vf_set1(-__builtin_inff()), g->ch[a].tfar);
                g->ch[a].cull = vf_sel(vm_of(cl), vf_set1(-__builtin_inff()), g->ch[a].cull);
                nlive--;
            }
        } else {
            const hz_bvh_node_t *n = &nodes[cur];
            vf tmin;
            HZ_BVH_COUNT(k, nodes, 1);
            const unsigned m = ia_node_hit(n, &g->b, vf_set1(g->ia_tmax), &tmin);
            for (unsigned x = m; x; x &= x - 1) {
                const unsigned j = (unsigned)__builtin_ctz(x);
                unsigned first, last, l0;
                if (!child_range(n, j, pl, g, a, bnd, &first, &last, &l0))
                    continue;
                const uint32_t cw = n->child[j];
                if (!hz_bvh_is_leaf(cw)) {
                    st_n[sp] = cw, st_a[sp] = (uint8_t)first, st_b[sp] = (uint8_t)last;
                    st_l[sp] = first == last ? l0 : 0;
                    sp++;
                    continue;
                }
                const uint32_t slot = hz_bvh_leaf_slot(cw), cnt = hz_bvh_leaf_count(cw);
                const hz_bvh_block_t *b = &bvh->blocks[slot / W];
                for (unsigned c = first; c <= last; c++) {
                    unsigned lanes = c == first ? l0 : lanes_hit(n, j, pl, &g->ch[c]) & g->live[c];
                    if (!lanes)
                        continue;
                    HZ_BVH_COUNT(k, tris, (uint64_t)cnt * (uint64_t)__builtin_popcount(lanes));
                    tchunk_t *ch = &g->ch[c];
                    unsigned done = 0;
                    for (unsigned s = slot % W; s < slot % W + cnt && lanes; s++) {
                        vf t, V, Wv, det;
                        unsigned mm = tri_hit_lanes(b, s, g, ch, ch->tfar, lanes, &t, &V, &Wv, &det);
                        if (!mm)
                            continue;
                        if (anyhit && (b->prim[s] & HZ_BVH_PRIM_ANYHIT))
                            mm = lanes_anyhit(bvh, ctx, src, g->src[c], (slot / W) * W + s, mm, t, V, Wv, det);
                        done |= mm;
                        lanes &= ~mm;
                    }
                    if (done) {
                        blocked[c] |= done;
                        g->live[c] &= ~done;
                        ch->tfar = vf_sel(vm_of(done), vf_set1(-__builtin_inff()), ch->tfar);
                        ch->cull = vf_sel(vm_of(done), vf_set1(-__builtin_inff()), ch->cull);
                        nlive -= (unsigned)__builtin_popcount(done);
                    }
                }
                if (!nlive)
                    return;
            }
        }
        if (!nlive)
            return;
        if (!one && nlive * 2u <= bounds_live && nlive > 1) { /* (a packet's bounds: not worth their cost) */
            tile_bounds(g, true);
            bounds_live = nlive;
        }
        for (;;) {
            if (sp == 0)
                return;
            --sp;
            a = st_a[sp], bnd = st_b[sp];
            cl = st_l[sp] & g->live[a];
            if (a == bnd && !cl)
                continue; /* its one chunk's lanes are all blocked now */
            cur = st_n[sp];
            break;
        }
    }
}

static void tile_any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, const tsrc_t *src, tgroup_t *g, unsigned *blocked,
                     hz_bvh_counters_t *k)
{
    if (g->nch == 1)
        any_tile_core(bvh, ctx, src, g, blocked, k, true);
    else
        any_tile_core(bvh, ctx, src, g, blocked, k, false);
}

/* ---- entry points: packets of KW rays, one or many ---- */

/* Lane indices of the call sorted by key (stable), and the groups' boundaries. */
typedef struct tplan {
    uint16_t lanes[TILE_RAYS];
    uint16_t start[33], count[33];
    uint8_t keys[33];
    unsigned ngroups;
    uint16_t singles[TILE_RAYS];
    unsigned nsingle;
} tplan_t;

static void tile_plan(const int32_t *key, uint32_t nl, tplan_t *p)
{
    uint16_t cnt[32];
    hz_memset(cnt, 0, sizeof cnt);
    p->nsingle = 0;
    for (uint32_t i = 0; i < nl; i++) {
        if (key[i] == KEY_SINGLE)
            p->singles[p->nsingle++] = (uint16_t)i;
        else if (key[i] != KEY_NONE)
            cnt[key[i]]++;
    }
    uint16_t at[32];
    unsigned pos = 0;
    p->ngroups = 0;
    for (unsigned q = 0; q < 32; q++) {
        at[q] = (uint16_t)pos;
        if (!cnt[q])
            continue;
        if (cnt[q] < TILE_MIN_GROUP) { /* too few rays share these directions: single rays */
            for (uint32_t i = 0; i < nl; i++)
                if (key[i] == (int32_t)q)
                    p->singles[p->nsingle++] = (uint16_t)i;
            cnt[q] = 0;
            continue;
        }
        p->keys[p->ngroups] = (uint8_t)q;
        p->start[p->ngroups] = (uint16_t)pos;
        p->count[p->ngroups] = cnt[q];
        p->ngroups++;
        pos += cnt[q];
    }
    for (uint32_t i = 0; i < nl; i++)
        if (key[i] >= 0 && key[i] < 32 && cnt[key[i]])
            p->lanes[at[key[i]]++] = (uint16_t)i;
}

/* One slice of at most TILE_RAYS rays. */
static void tile_intersect(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_rayhitw_t *rh,
                           size_t stride, uint32_t n, hz_bvh_counters_t *k)
{
    const tsrc_t src = { &rh->ray, stride, n };
    int32_t key[TILE_RAYS];
    unsigned act[TILE_CHUNKS], nact = 0;
    const unsigned one = tile_keys(&src, valid, key, act);
    tgroup_t g;
    for (uint32_t p = 0; p < n; p++)
        nact += (unsigned)__builtin_popcount(act[p]);
    if (one != KEY_NONE && nact >= 2) {
        tile_load_direct(&g, &src, act, one);
        tile_closest(bvh, ctx, &src, &g, k);
        tile_write_hits(&g, rh, stride);
        return;
    }
    tplan_t plan;
    tile_plan(key, n * W, &plan);
    for (unsigned q = 0; q < plan.ngroups; q++) {
        tile_load(&g, &src, plan.lanes + plan.start[q], plan.count[q], plan.keys[q]);
        tile_closest(bvh, ctx, &src, &g, k);
        tile_write_hits(&g, rh, stride);
    }
    for (unsigned q = 0; q < plan.nsingle; q++) {
        const uint16_t li = plan.singles[q];
        hz_bvh_ray_t r;
        uint32_t id;
        tile_lane_ray(&src, li, &r, &id);
        hz_bvh_best_t best;
        hz_bvh_best_init(&best);
        sray_t s;
        sray_init(&s, &r);
        closest_from(bvh, ctx, &r, &s, 0, &best, id, (int)(li % W), k);
        if (best.slot == HZ_ACCEL_INVALID_ID)
            continue;
        hz_bvh_rayhitw_t *p = (hz_bvh_rayhitw_t *)(void *)((char *)rh + (size_t)(li / W) * stride);
        const unsigned l = li % W;
        float ng[3];
        hz_bvh_best_finish(bvh, &best, ng, &p->hit.u[l], &p->hit.v[l]);
        p->ray.tfar[l] = r.tfar;
        p->hit.ng_x[l] = ng[0], p->hit.ng_y[l] = ng[1], p->hit.ng_z[l] = ng[2];
        p->hit.prim_id[l] = best.prim;
        p->hit.geom_id[l] = 0;
        p->hit.inst_id[0][l] = HZ_ACCEL_INVALID_ID;
    }
}

static void tile_occluded(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_rayw_t *ray,
                          size_t stride, uint32_t n, hz_bvh_counters_t *k)
{
    const tsrc_t src = { ray, stride, n };
    int32_t key[TILE_RAYS];
    unsigned act[TILE_CHUNKS], nact = 0, blocked[TILE_CHUNKS];
    const unsigned one = tile_keys(&src, valid, key, act);
    tgroup_t g;
    for (uint32_t p = 0; p < n; p++)
        nact += (unsigned)__builtin_popcount(act[p]);
    if (one != KEY_NONE && nact >= 2) {
        tile_load_direct(&g, &src, act, one);
        hz_memset(blocked, 0, n * sizeof blocked[0]);
        tile_any(bvh, ctx, &src, &g, blocked, k);
        for (uint32_t c = 0; c < n; c++)
            if (blocked[c]) {
                hz_bvh_rayw_t *p = (hz_bvh_rayw_t *)(void *)((char *)ray + (size_t)c * stride);
                vf_store(p->tfar, vf_sel(vm_of(blocked[c]), vf_set1(-__builtin_inff()), vf_load(p->tfar)));
            }
        return;
    }
    tplan_t plan;
    tile_plan(key, n * W, &plan);
    for (unsigned q = 0; q < plan.ngroups; q++) {
        tile_load(&g, &src, plan.lanes + plan.start[q], plan.count[q], plan.keys[q]);
        hz_memset(blocked, 0, g.nch * sizeof blocked[0]);
        tile_any(bvh, ctx, &src, &g, blocked, k);
        for (uint32_t c = 0; c < g.nch; c++)
            for (unsigned x = blocked[c]; x; x &= x - 1) {
                const uint16_t li = g.src[c][__builtin_ctz(x)];
                hz_bvh_rayw_t *p = (hz_bvh_rayw_t *)(void *)((char *)ray + (size_t)(li / W) * stride);
                p->tfar[li % W] = -__builtin_inff();
            }
    }
    for (unsigned q = 0; q < plan.nsingle; q++) {
        const uint16_t li = plan.singles[q];
        hz_bvh_ray_t r;
        uint32_t id;
        tile_lane_ray(&src, li, &r, &id);
        sray_t s;
        sray_init(&s, &r);
        if (any_from(bvh, ctx, &r, &s, 0, id, (int)(li % W), k)) {
            hz_bvh_rayw_t *p = (hz_bvh_rayw_t *)(void *)((char *)ray + (size_t)(li / W) * stride);
            p->tfar[li % W] = -__builtin_inff();
        }
    }
}

/* Single rays, lane by lane, from packets. */
static void lanes_closest(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_rayhitw_t *rh,
                          hz_bvh_counters_t *k)
{
    for (unsigned l = 0; l < W; l++) {
        if (!valid[l])
            continue;
        hz_bvh_ray_t r;
        if (!hz_bvh_ray_prep(&r, rh->ray.org_x[l], rh->ray.org_y[l], rh->ray.org_z[l], rh->ray.dir_x[l],
                             rh->ray.dir_y[l], rh->ray.dir_z[l], rh->ray.tnear[l], rh->ray.tfar[l]))
            continue;
        hz_bvh_best_t best;
        hz_bvh_best_init(&best);
        sray_t s;
        sray_init(&s, &r);
        closest_from(bvh, ctx, &r, &s, 0, &best, rh->ray.id[l], (int)l, k);
        if (best.slot == HZ_ACCEL_INVALID_ID)
            continue;
        float ng[3];
        hz_bvh_best_finish(bvh, &best, ng, &rh->hit.u[l], &rh->hit.v[l]);
        rh->ray.tfar[l] = r.tfar;
        rh->hit.ng_x[l] = ng[0], rh->hit.ng_y[l] = ng[1], rh->hit.ng_z[l] = ng[2];
        rh->hit.prim_id[l] = best.prim;
        rh->hit.geom_id[l] = 0;
        rh->hit.inst_id[0][l] = HZ_ACCEL_INVALID_ID;
    }
}

static void lanes_any(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_rayw_t *ray,
                      hz_bvh_counters_t *k)
{
    for (unsigned l = 0; l < W; l++) {
        hz_bvh_ray_t r;
        if (!valid[l] || !hz_bvh_ray_prep(&r, ray->org_x[l], ray->org_y[l], ray->org_z[l], ray->dir_x[l],
                                          ray->dir_y[l], ray->dir_z[l], ray->tnear[l], ray->tfar[l]))
            continue;
        sray_t s;
        sray_init(&s, &r);
        if (any_from(bvh, ctx, &r, &s, 0, ray->id[l], (int)l, k))
            ray->tfar[l] = -__builtin_inff();
    }
}

void hz_bvh_simd_intersect_tile(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx,
                                hz_bvh_rayhitw_t *rh, uint32_t n, hz_accel_kernel_t kernel)
{
    hz_bvh_counters_t k = { 0, 0 };
    frustum_t f;
    if (kernel == HZ_ACCEL_KERNEL_SIMD_PACKET && n == 1 && frustum_init(&f, valid, &rh->ray)) {
        frustum_closest(bvh, ctx, &f, rh, &k);
    } else if (kernel == HZ_ACCEL_KERNEL_SIMD_PACKET) {
        for (uint32_t p = 0; p < n; p += TILE_CHUNKS)
            tile_intersect(valid + (size_t)p * W, bvh, ctx, rh + p, sizeof *rh,
                           n - p < TILE_CHUNKS ? n - p : TILE_CHUNKS, &k);
    } else {
        for (uint32_t p = 0; p < n; p++)
            lanes_closest(valid + (size_t)p * W, bvh, ctx, rh + p, &k);
    }
    hz_bvh_counters_flush(ctx, &k);
}

void hz_bvh_simd_occluded_tile(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_rayw_t *ray,
                               uint32_t n, hz_accel_kernel_t kernel)
{
    hz_bvh_counters_t k = { 0, 0 };
    frustum_t f;
    if (kernel == HZ_ACCEL_KERNEL_SIMD_PACKET && n == 1 && frustum_init(&f, valid, ray)) {
        const unsigned hit = frustum_any(bvh, ctx, &f, ray, &k);
        if (hit)
            vf_store(ray->tfar, vf_sel(vm_of(hit), vf_set1(-__builtin_inff()), vf_load(ray->tfar)));
    } else if (kernel == HZ_ACCEL_KERNEL_SIMD_PACKET) {
        for (uint32_t p = 0; p < n; p += TILE_CHUNKS)
            tile_occluded(valid + (size_t)p * W, bvh, ctx, ray + p, sizeof *ray,
                          n - p < TILE_CHUNKS ? n - p : TILE_CHUNKS, &k);
    } else {
        for (uint32_t p = 0; p < n; p++)
            lanes_any(valid + (size_t)p * W, bvh, ctx, ray + p, &k);
    }
    hz_bvh_counters_flush(ctx, &k);
}

bool hz_bvh_simd_intersect_motion(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx,
                                  hz_bvh_rayhitw_t *rh)
{
    frustum_t f;
    if (!bvh->time_keys || !bvh->key_boxes || !frustum_init(&f, valid, &rh->ray))
        return false;
    mtimes_t mt;
    mtimes_init(&mt, bvh, &rh->ray, f.active);
    hz_bvh_counters_t k = { 0, 0 };
    mfr_closest(bvh, ctx, &f, &mt, rh, &k);
    hz_bvh_counters_flush(ctx, &k);
    return true;
}

bool hz_bvh_simd_occluded_motion(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_rayw_t *ray)
{
    frustum_t f;
    if (!bvh->time_keys || !bvh->key_boxes || !frustum_init(&f, valid, ray))
        return false;
    mtimes_t mt;
    mtimes_init(&mt, bvh, ray, f.active);
    hz_bvh_counters_t k = { 0, 0 };
    const unsigned hit = mfr_any(bvh, ctx, &f, &mt, ray, &k);
    if (hit)
        vf_store(ray->tfar, vf_sel(vm_of(hit), vf_set1(-__builtin_inff()), vf_load(ray->tfar)));
    hz_bvh_counters_flush(ctx, &k);
    return true;
}

void hz_bvh_simd_intersectw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_rayhitw_t *rh,
                            hz_accel_kernel_t kernel)
{
    hz_bvh_simd_intersect_tile(valid, bvh, ctx, rh, 1, kernel);
}

void hz_bvh_simd_occludedw(const int32_t *valid, const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_bvh_rayw_t *ray,
                           hz_accel_kernel_t kernel)
{
    hz_bvh_simd_occluded_tile(valid, bvh, ctx, ray, 1, kernel);
}

#undef W
#endif /* HZ_ACCEL_TRAV_KERNEL_H */
