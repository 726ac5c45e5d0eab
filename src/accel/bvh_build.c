/*
 * Native BVH build: a binary SBVH (binned SAH object splits, an exact sweep for nodes of at most SWEEP_N
 * references, plus spatial splits with reference unsplitting, Stich, Friedrich, Dietrich 2009) built on a
 * reference stack in scratch memory, then collapsed into wide nodes (greedy: open the largest child until the
 * node has HZ_BVH_W children) whose leaves are packed next-fit into triangle blocks. Scratch and result come from
 * one arena; the result is moved down over the scratch at the end so only the structure stays. Refit lives here
 * too: it shares the box helpers.
 *
 * Everything has a fixed operation order, so a build is bit-identical on every ISA: boxes of the binning loops
 * are four-lane vectors (box4.h) whose operations round exactly as the scalar C they stand for (the scalar twin,
 * HZ_BOX4_SCALAR, builds the same bytes: test_accel_build_twin).
 *
 * Top levels and tasks (every build of more than task_limit() references, pool or not): the top levels split
 * on the calling thread, binning large nodes in chunks run as items of cfg->run; subtrees of at most
 * task_limit() references (a rule on the reference count only) become tasks with their own ranges at the high
 * ends of the scratch arrays (what a subtree can use at most: n + budget references and leaf slots, twice that
 * in nodes), built with the serial code as items of cfg->run, or in turn without one: the same tree for every
 * thread count. Below the top levels a subtree's unused budget goes on to its sibling as before; at the top
 * levels it cannot (a task's is known only once it ran), so top-level children get their proportional shares
 * and a task may spend TASK_BUDGET_SCALE times its share. If the tasks then went over the budget together, the
 * ones that overspent are built again with their shares plus what the others left (build_top, plan_rerun): the
 * decision depends on the first pass's trees only, so the tree is still the same for every thread count.
 */
#include "bvh.h"
#include "box4.h"
#include "instance.h"

#define OBJ_BINS 32
#define SPATIAL_BINS 32     /* at most; smaller nodes use fewer (spatial_bins) */
#define DEPTH_FORCE_MEDIAN 48 /* from here on, halve by index: 2^27 refs need 27 more levels < MAX_DEPTH */
#define COST_NODE 1.0f        /* SAH: cost of a binary node relative to one test of a block of triangles */
#define COST_TRI 1.0f
#ifndef SAH_BLOCK
#define SAH_BLOCK 4u          /* SAH counts triangles in blocks of 4 (leaves test them together) */
#endif

/* Triangle count as the SAH sees it: whole blocks. */
HZ_INLINE float sah_count(uint32_t n)
{
    return (float)((n + SAH_BLOCK - 1u) / SAH_BLOCK);
}

typedef struct box {
    float lo[3], hi[3];
} box_t;

typedef struct ref {
    box_t b;
    uint32_t prim;
    uint32_t pad;
} ref_t;

/* Binary node in scratch: inner: a = left, n = right; leaf: a = first leaf_prims index, n = LEAF | count. */
typedef struct bnode {
    box_t b;
    uint32_t a, n;
} bnode_t;

#define BLEAF 0x80000000u

/* A bin's box in four lanes (box4.h; lane 3 is never looked at). */
typedef struct HZ_ALIGNED(16) bbox4 {
    float lo[4], hi[4];
} bbox4_t;

typedef struct obj_bin {
    bbox4_t b;
    uint32_t n, pad_[3];
} obj_bin_t;

typedef struct sp_bin {
    bbox4_t b;
    uint32_t enter, exit, pad_[2];
} sp_bin_t;

#define PAR_CHUNK 8192u      /* references per binning item of a large node */
#define PAR_MAX_CHUNKS 32u
#define PAR_TASK_MIN 4096u   /* subtrees smaller than this are never worth a task of their own */
#define PAR_MAX_TASKS 256u
#define PAR_MAX_TOP 512u     /* top-level nodes recorded for the SAH sum; more are built in place */
/* A task may spend up to this many times its share of the budget: build_node hands a subtree's unused budget
 * on to its sibling, which a task cannot, and its proportional splits of a small share starve deep nodes
 * (Conference's SAH cost 1% worse with plain shares, 0.1% better with 4x; the build's total stays capped). */
#define TASK_BUDGET_SCALE 4u

typedef struct sp_frame sp_frame_t;
typedef struct par par_t;

typedef struct build {
    const hz_accel_geom_t *g;
    ref_t *refs;
    uint32_t ref_cap, top;
    bnode_t *nodes;
    uint32_t node_cap, node_count;
    uint32_t *leaf_prims;
    uint32_t leaf_cap, leaf_count;
    uint32_t dup_left; /* duplicates the current node's share of the budget still allows */
    uint32_t leaf_max;
    bool spatial;
    float min_overlap; /* alpha * root area */
    uint32_t spatial_splits;
    uint32_t budget_stops; /* spatial split searches skipped and duplicates refused for lack of budget */
    obj_bin_t obins[3][OBJ_BINS];
    sp_bin_t sbins[3][SPATIAL_BINS];
    bool failed;
    par_t *par;   /* chunked binning on the pool (the top levels of a parallel build), else NULL */
    /* progress (hz_accel_config_t): references placed in leaves against the first ones' count */
    void (*progress)(void *user, float done);
    void *progress_user;
    uint32_t progress_next, progress_step, progress_total;
} build_t;


/* ---- boxes: written out per axis (no loops, no arrays indexed by a variable) so the compiler keeps boxes of
 * the hot loops in registers; struct copies of boxes just built from scalar stores stall on store forwarding. */
HZ_INLINE void box_empty(box_t *b)
{
    const float inf = __builtin_inff();
    b->lo[0] = inf, b->lo[1] = inf, b->lo[2] = inf;
    b->hi[0] = -inf, b->hi[1] = -inf, b->hi[2] = -inf;
}

HZ_INLINE void box_grow_pt(box_t *b, float x, float y, float z)
{
    b->lo[0] = hz_minf(b->lo[0], x), b->hi[0] = hz_maxf(b->hi[0], x);
    b->lo[1] = hz_minf(b->lo[1], y), b->hi[1] = hz_maxf(b->hi[1], y);
    b->lo[2] = hz_minf(b->lo[2], z), b->hi[2] = hz_maxf(b->hi[2], z);
}

HZ_INLINE void box_grow(box_t *b, const box_t *o)
{
    b->lo[0] = hz_minf(b->lo[0], o->lo[0]), b->hi[0] = hz_maxf(b->hi[0], o->hi[0]);
    b->lo[1] = hz_minf(b->lo[1], o->lo[1]), b->hi[1] = hz_maxf(b->hi[1], o->hi[1]);
    b->lo[2] = hz_minf(b->lo[2], o->lo[2]), b->hi[2] = hz_maxf(b->hi[2], o->hi[2]);
}

HZ_INLINE bool box_valid(const box_t *b)
{
    return b->lo[0] <= b->hi[0] && b->lo[1] <= b->hi[1] && b->lo[2] <= b->hi[2];
}

HZ_INLINE float box_area(const box_t *b)
{
    if (!box_valid(b))
        return 0.0f;
    float dx = b->hi[0] - b->lo[0], dy = b->hi[1] - b->lo[1], dz = b->hi[2] - b->lo[2];
    return 2.0f * (dx * dy + dy * dz + dz * dx);
}

/* a = a intersected with b */
HZ_INLINE void box_clip(box_t *a, const box_t *b)
{
    a->lo[0] = hz_maxf(a->lo[0], b->lo[0]), a->hi[0] = hz_minf(a->hi[0], b->hi[0]);
    a->lo[1] = hz_maxf(a->lo[1], b->lo[1]), a->hi[1] = hz_minf(a->hi[1], b->hi[1]);
    a->lo[2] = hz_maxf(a->lo[2], b->lo[2]), a->hi[2] = hz_minf(a->hi[2], b->hi[2]);
}

HZ_INLINE box_t box_and(const box_t *a, const box_t *b)
{
    box_t r = *a;
    box_clip(&r, b);
    return r;
}

static const float *vtx(const hz_accel_geom_t *g, uint32_t i)
{
    return g->pos + 4u * (size_t)i;
}

/* The triangle's box; with `sweep`, the union of its boxes at all of g's time keys (the swept motion BVH). */
static bool tri_box(const hz_accel_geom_t *g, uint32_t t, box_t *b, bool sweep)
{
    box_empty(b);
    const uint32_t nk = sweep ? g->time_keys : 1u;
    for (uint32_t key = 0; key < nk; key++) {
        const float *pos = sweep ? g->pos_keys[key] : g->pos;
        for (int k = 0; k < 3; k++) {
            const float *p = pos + 4u * (size_t)g->tri[3u * (size_t)t + (uint32_t)k];
            if (!(hz_absf(p[0]) <= HZ_ACCEL_MAX_COORD && hz_absf(p[1]) <= HZ_ACCEL_MAX_COORD &&
                  hz_absf(p[2]) <= HZ_ACCEL_MAX_COORD)) /* also false for NaN */
                return false;
            box_grow_pt(b, p[0], p[1], p[2]);
        }
    }
    return true;
}

/* ---- spatial split of one reference: the triangle clipped to each side of `pos` on `axis`, conservatively
 * (intersection points may round inwards: the other axes are padded by a few ulps of the coordinates), then
 * cut to the reference's box. ---- */
static void split_ref(const build_t *bd, const ref_t *r, int axis, float pos, ref_t *l, ref_t *rr)
{
    box_t lb, rb;
    box_empty(&lb);
    box_empty(&rb);
    const uint32_t *t = bd->g->tri + 3u * (size_t)r->prim;
    const float *v[3] = { vtx(bd->g, t[0]), vtx(bd->g, t[1]), vtx(bd->g, t[2]) };
    for (int i = 0; i < 3; i++) {
        const float *a = v[i], *b = v[i == 2 ? 0 : i + 1];
        float pa = a[axis], pb = b[axis];
        if (pa <= pos)
            box_grow_pt(&lb, a[0], a[1], a[2]);
        if (pa >= pos)
            box_grow_pt(&rb, a[0], a[1], a[2]);
        if ((pa < pos && pos < pb) || (pb < pos && pos < pa)) {
            float s = (pos - pa) / (pb - pa);
            s = hz_clampf(s, 0.0f, 1.0f);
            float x[3];
            for (int k = 0; k < 3; k++)
                x[k] = a[k] + (b[k] - a[k]) * s;
            x[axis] = pos;
            box_grow_pt(&lb, x[0], x[1], x[2]);
            box_grow_pt(&rb, x[0], x[1], x[2]);
        }
    }
    for (int k = 0; k < 3; k++) {
        if (k == axis)
            continue;
        float pad = (hz_absf(r->b.lo[k]) + hz_absf(r->b.hi[k])) * (1.0f / 1048576.0f); /* 2^-20 */
        lb.lo[k] -= pad, lb.hi[k] += pad;
        rb.lo[k] -= pad, rb.hi[k] += pad;
    }
    lb.hi[axis] = pos;
    rb.lo[axis] = pos;
    l->b = box_and(&lb, &r->b);
    rr->b = box_and(&rb, &r->b);
    l->prim = rr->prim = r->prim;
    l->pad = rr->pad = 0;
}

/* Planes of a node's spatial bins, computed once per node (spatial_pos for i = 0..nbins) with the per-axis
 * bin scale: the binning of every reference reads them instead of recomputing them. */
struct sp_frame {
    float planes[3][SPATIAL_BINS + 1];
    float inv[3];
    bool ok[3]; /* the node has extent on the axis */
    int nbins;
    const box_t *nb;
};

/* ---- four-lane boxes (box4.h): a reference's corners, bins ---- */
/* (lo x, lo y, lo z, hi x) and (hi x, hi y, hi z, lo z): whole loads, every lane a coordinate of the box */
HZ_INLINE f4_t ref_lo(const ref_t *r)
{
    return f4_load(&r->b.lo[0]);
}

HZ_INLINE f4_t ref_hi(const ref_t *r)
{
    return f4_rot1(f4_load(&r->b.lo[2]));
}

HZ_INLINE void b4_empty(bbox4_t *b)
{
    const float inf = __builtin_inff();
    f4_store(b->lo, f4_set1(inf));
    f4_store(b->hi, f4_set1(-inf));
}

/* b grows by [lo, hi], in box_grow's operand order */
HZ_INLINE void b4_grow(bbox4_t *b, f4_t lo, f4_t hi)
{
    f4_store(b->lo, f4_min(f4_load(b->lo), lo));
    f4_store(b->hi, f4_max(f4_load(b->hi), hi));
}

HZ_INLINE void b4_grow_b4(bbox4_t *b, const bbox4_t *o)
{
    b4_grow(b, f4_load(o->lo), f4_load(o->hi));
}

HZ_INLINE box_t b4_box(const bbox4_t *b)
{
    box_t r;
    r.lo[0] = b->lo[0], r.lo[1] = b->lo[1], r.lo[2] = b->lo[2];
    r.hi[0] = b->hi[0], r.hi[1] = b->hi[1], r.hi[2] = b->hi[2];
    return r;
}

/* box_area of a four-lane box: the same products and sums in the same order ((dx dy + dy dz) + dz dx) */
HZ_INLINE float b4_area(f4_t lo, f4_t hi)
{
    if (f4_le3(lo, hi) != 7u)
        return 0.0f;
    const f4_t d = f4_sub(hi, lo);
    float p[4];
    f4_store(p, f4_mul(d, f4_yzx(d))); /* dx dy, dy dz, dz dx */
    return 2.0f * (p[0] + p[1] + p[2]);
}

/* a + (b - a) * s, lane by lane */
HZ_INLINE f4_t f4_lerp(f4_t a, f4_t b, float s)
{
    return f4_add(a, f4_mul(f4_sub(b, a), f4_set1(s)));
}

/* Cross-section of the sorted triangle (lo, mid, hi along axis, with those coordinates alo, amid, ahi) at plane x:
 * grows (clo, chi). */
HZ_INLINE void cross_section4(f4_t lo, f4_t mid, f4_t hi, float alo, float amid, float ahi, int axis, float x, f4_t *clo,
                              f4_t *chi)
{
    if (!(alo < x && x < ahi))
        return;
    const bool below = x < amid;
    const f4_t e0 = below ? lo : mid, e1 = below ? mid : hi;
    const float a0 = below ? alo : amid, a1 = below ? amid : ahi;
    float s = hz_clampf((x - alo) / (ahi - alo), 0.0f, 1.0f);
    float t = a1 > a0 ? hz_clampf((x - a0) / (a1 - a0), 0.0f, 1.0f) : 0.0f;
    const f4_t p = f4_put(f4_lerp(lo, hi, s), axis, x), q = f4_put(f4_lerp(e0, e1, t), axis, x);
    *clo = f4_min(*clo, p), *chi = f4_max(*chi, p);
    *clo = f4_min(*clo, q), *chi = f4_max(*chi, q);
}

/* Bins one reference for the spatial split search on `axis`: the triangle's part inside each bin [b0, b1]
 * (clipped like split_ref, but walking the planes once: the triangle's cross-section at a plane is a segment
 * whose ends lie on edge lo-hi and on lo-mid or mid-hi of its vertices sorted along the axis). This loop runs for
 * every reference and bin it spans. rl, rh: the reference's box (ref_lo, ref_hi); v: its triangle's vertices.
 * Inlined with a constant axis (sp_bin_axis): the axis tests fold away. */
HZ_INLINE void chop_into_bins(const float *const *vp, const ref_t *r, f4_t rl, f4_t rh, int axis, const sp_frame_t *fr,
                              int b0, int b1, sp_bin_t *bins)
{
    const float *p0 = vp[0], *p1 = vp[1], *p2 = vp[2], *pt;
    if (p0[axis] > p1[axis]) /* sort the three vertices along the axis */
        pt = p0, p0 = p1, p1 = pt;
    if (p1[axis] > p2[axis])
        pt = p1, p1 = p2, p2 = pt;
    if (p0[axis] > p1[axis])
        pt = p0, p0 = p1, p1 = pt;
    const f4_t v0 = f4_load(p0), v1 = f4_load(p1), v2 = f4_load(p2);
    const float a0 = p0[axis], a1 = p1[axis], a2 = p2[axis];
    const float *planes = fr->planes[axis];
    float pd[3];
    for (int c = 0; c < 3; c++)
        pd[c] = c == axis ? 0.0f : (hz_absf(r->b.lo[c]) + hz_absf(r->b.hi[c])) * (1.0f / 1048576.0f);
    const f4_t pad = f4_set(pd[0], pd[1], pd[2], 0.0f);
    const float inf = __builtin_inff();
    const f4_t pinf = f4_set1(inf), ninf = f4_set1(-inf);
    f4_t clo = pinf, chi = ninf; /* cross-section at the piece's lower plane */
    for (int j = b0; j <= b1; j++) {
        const float x0 = j == b0 ? -inf : planes[j];
        const float x1 = j == b1 ? inf : planes[j + 1];
        f4_t plo = clo, phi = chi;
        clo = pinf, chi = ninf;
        if (j < b1)
            cross_section4(v0, v1, v2, a0, a1, a2, axis, x1, &clo, &chi);
        plo = f4_min(plo, clo), phi = f4_max(phi, chi);
        if (a0 >= x0 && a0 <= x1)
            plo = f4_min(plo, v0), phi = f4_max(phi, v0);
        if (a1 >= x0 && a1 <= x1)
            plo = f4_min(plo, v1), phi = f4_max(phi, v1);
        if (a2 >= x0 && a2 <= x1)
            plo = f4_min(plo, v2), phi = f4_max(phi, v2);
        /* pad (off the split axis), cut to the reference's box and to the bin's slab (-inf / +inf off the axis:
         * max(v, -inf) and min(v, inf) are v) */
        plo = f4_max(f4_max(f4_sub(plo, pad), rl), f4_put(ninf, axis, x0));
        phi = f4_min(f4_min(f4_add(phi, pad), rh), f4_put(pinf, axis, x1));
        if (f4_le3(plo, phi) == 7u)
            b4_grow(&bins[j].b, plo, phi);
    }
}

/* ---- split search ---- */
typedef struct split {
    float cost; /* SAH of the children, area-weighted (sum of area * count) */
    int axis;
    int bin;    /* object: last bin on the left; spatial: last bin on the left */
    float pos;  /* spatial: plane */
    box_t lb, rb;
    uint32_t nl, nr;
} split_t;

static float centroid(const ref_t *r, int k)
{
    return (r->b.lo[k] + r->b.hi[k]) * 0.5f;
}

static int obj_bin_of(float c, float lo, float scale)
{
    int i = (int)((c - lo) * scale);
    return i < 0 ? 0 : (i >= OBJ_BINS ? OBJ_BINS - 1 : i);
}

/* ---- chunked binning: items of par_run bin disjoint ranges of a node's references into their own bins;
 * merging them in chunk order gives the serial result bit for bit (boxes are folds of hz_minf / hz_maxf, which
 * keep the last of equal values in either grouping, and counts are integers). ---- */
typedef enum par_kind { PAR_OBJECT, PAR_SPATIAL, PAR_BOUNDS } par_kind_t;

struct par {
    const hz_accel_config_t *cfg; /* run, run_user */
    obj_bin_t (*obins)[3][OBJ_BINS];
    sp_bin_t (*sbins)[3][SPATIAL_BINS];
    box_t (*boxes)[2];
    /* the current job */
    const build_t *bd;
    par_kind_t kind;
    uint32_t base, n, chunks;
    const box_t *cb;
    const float *scale;
    const sp_frame_t *fr;
};

static void obj_clear(obj_bin_t bins[3][OBJ_BINS])
{
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < OBJ_BINS; i++) {
            b4_empty(&bins[k][i].b);
            bins[k][i].n = 0;
        }
}

static void sp_clear(sp_bin_t bins[3][SPATIAL_BINS], int nbins)
{
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < nbins; i++) {
            b4_empty(&bins[k][i].b);
            bins[k][i].enter = bins[k][i].exit = 0;
        }
}

/* Object bins of refs [i0, i1) on every axis (one pass: each reference is read once; an axis with scale 0 puts
 * everything into bin 0 and is not looked at). The centroid and the bin index as centroid() and obj_bin_of, in
 * four lanes. */
static void obj_bin_range(const ref_t *refs, uint32_t i0, uint32_t i1, const box_t *cb, const float *scale,
                          obj_bin_t bins[3][OBJ_BINS])
{
    const f4_t lo = f4_set(cb->lo[0], cb->lo[1], cb->lo[2], 0.0f);
    const f4_t sc = f4_set(scale[0], scale[1], scale[2], 0.0f), half = f4_set1(0.5f);
    for (uint32_t i = i0; i < i1; i++) {
        const ref_t *r = &refs[i];
        const f4_t rl = ref_lo(r), rh = ref_hi(r);
        int32_t bi[4];
        i4_store(bi, i4_clamp(i4_from_f4(f4_mul(f4_sub(f4_mul(f4_add(rl, rh), half), lo), sc)), 0, OBJ_BINS - 1));
        obj_bin_t *b0 = &bins[0][bi[0]], *b1 = &bins[1][bi[1]], *b2 = &bins[2][bi[2]];
        b4_grow(&b0->b, rl, rh);
        b0->n++;
        b4_grow(&b1->b, rl, rh);
        b1->n++;
        b4_grow(&b2->b, rl, rh);
        b2->n++;
    }
}

/* The bin of x on axis k: the float index, settled against the planes, which it may miss by one. */
HZ_INLINE int spatial_settle(int i, float x, const sp_frame_t *fr, int k)
{
    const int nbins = fr->nbins;
    const float *planes = fr->planes[k];
    while (i > 0 && x < planes[i])
        i--;
    while (i < nbins - 1 && x >= planes[i + 1])
        i++;
    return i;
}

HZ_INLINE int spatial_bin_of(float x, const sp_frame_t *fr, int k)
{
    const int nbins = fr->nbins;
    int i = (int)((x - fr->nb->lo[k]) * fr->inv[k]);
    i = i < 0 ? 0 : (i >= nbins ? nbins - 1 : i);
    return spatial_settle(i, x, fr, k);
}

/* Whether bin box b already holds [lo, hi] on lanes 0..2 so that growing it by any box inside [lo, hi] changes no
 * bit: strictly, or at an equal bound that is not zero (equal non-zero floats are the same bits; the min / max
 * folds could swap -0 for +0). Then the grow is a no-op in any order and any chunking. */
HZ_INLINE bool holds4(const bbox4_t *b, f4_t lo, f4_t hi)
{
    const f4_t bl = f4_load(b->lo), bh = f4_load(b->hi), z = f4_set1(0.0f);
    const unsigned l = f4_lt3(bl, lo) | (f4_eq3(bl, lo) & ~f4_eq3(lo, z));
    const unsigned h = f4_lt3(hi, bh) | (f4_eq3(bh, hi) & ~f4_eq3(hi, z));
    return (l & h) == 7u;
}

/* Whether every bin b0..b1 already holds what chop_into_bins would add to it (each piece lies inside the
 * reference's box cut to the bin's slab): then the chop is skipped, bit for bit the same bins. Large nodes,
 * whose bins fill early, skip most chops of their straddling references. */
HZ_INLINE bool chop_is_noop(const ref_t *r, f4_t rl, f4_t rh, int axis, const sp_frame_t *fr, int b0, int b1,
                            const sp_bin_t *bins)
{
    const float *planes = fr->planes[axis];
    for (int j = b0; j <= b1; j++) {
        const float lo = j == b0 ? r->b.lo[axis] : hz_maxf(r->b.lo[axis], planes[j]);
        const float hi = j == b1 ? r->b.hi[axis] : hz_minf(r->b.hi[axis], planes[j + 1]);
        if (!holds4(&bins[j].b, f4_put(rl, axis, lo), f4_put(rh, axis, hi)))
            return false;
    }
    return true;
}

/* One reference on axis k (a constant at each call, so chop_into_bins is specialised per axis), bins b0, b1 from
 * the float indices; vp: its triangle's vertices, read on the first chop. */
HZ_INLINE void sp_bin_axis(const hz_accel_geom_t *g, const ref_t *r, f4_t rl, f4_t rh, int k, int b0, int b1,
                           const sp_frame_t *fr, sp_bin_t *bins, const float **vp)
{
    b0 = spatial_settle(b0, r->b.lo[k], fr, k);
    b1 = spatial_settle(b1, r->b.hi[k], fr, k);
    if (b1 <= b0) {
        b4_grow(&bins[b0].b, rl, rh);
        b1 = b0;
    } else if (!chop_is_noop(r, rl, rh, k, fr, b0, b1, bins)) {
        if (!vp[0]) {
            const uint32_t *t = g->tri + 3u * (size_t)r->prim;
            vp[0] = vtx(g, t[0]), vp[1] = vtx(g, t[1]), vp[2] = vtx(g, t[2]);
        }
        chop_into_bins(vp, r, rl, rh, k, fr, b0, b1, bins);
    }
    bins[b0].enter++;
    bins[b1].exit++;
}

static void sp_bin_range(const hz_accel_geom_t *g, const ref_t *refs, uint32_t i0, uint32_t i1, const sp_frame_t *fr,
                         sp_bin_t bins[3][SPATIAL_BINS])
{
    const f4_t lo = f4_set(fr->nb->lo[0], fr->nb->lo[1], fr->nb->lo[2], 0.0f);
    const f4_t inv = f4_set(fr->inv[0], fr->inv[1], fr->inv[2], 0.0f);
    const int last = fr->nbins - 1;
    for (uint32_t i = i0; i < i1; i++) {
        const ref_t *r = &refs[i];
        const f4_t rl = ref_lo(r), rh = ref_hi(r);
        int32_t b0[4], b1[4];
        i4_store(b0, i4_clamp(i4_from_f4(f4_mul(f4_sub(rl, lo), inv)), 0, last));
        i4_store(b1, i4_clamp(i4_from_f4(f4_mul(f4_sub(rh, lo), inv)), 0, last));
        const float *vp[3] = { NULL, NULL, NULL };
        if (fr->ok[0])
            sp_bin_axis(g, r, rl, rh, 0, b0[0], b1[0], fr, bins[0], vp);
        if (fr->ok[1])
            sp_bin_axis(g, r, rl, rh, 1, b0[1], b1[1], fr, bins[1], vp);
        if (fr->ok[2])
            sp_bin_axis(g, r, rl, rh, 2, b0[2], b1[2], fr, bins[2], vp);
    }
}

/* The node's box and its references' centroid box (box_grow / box_grow_pt of centroid(), in four lanes). */
static void bounds_range(const ref_t *refs, uint32_t i0, uint32_t i1, box_t *b, box_t *cb)
{
    const float inf = __builtin_inff();
    const f4_t half = f4_set1(0.5f);
    f4_t bl = f4_set1(inf), bh = f4_set1(-inf), cl = bl, ch = bh;
    for (uint32_t i = i0; i < i1; i++) {
        const ref_t *r = &refs[i];
        const f4_t rl = ref_lo(r), rh = ref_hi(r), c = f4_mul(f4_add(rl, rh), half);
        bl = f4_min(bl, rl), bh = f4_max(bh, rh);
        cl = f4_min(cl, c), ch = f4_max(ch, c);
    }
    bbox4_t x, y;
    f4_store(x.lo, bl), f4_store(x.hi, bh);
    f4_store(y.lo, cl), f4_store(y.hi, ch);
    *b = b4_box(&x);
    *cb = b4_box(&y);
}

static void par_item(void *ctx, uint32_t item)
{
    const par_t *p = ctx;
    const uint32_t i0 = p->base + (uint32_t)((uint64_t)p->n * item / p->chunks);
    const uint32_t i1 = p->base + (uint32_t)((uint64_t)p->n * (item + 1u) / p->chunks);
    if (p->kind == PAR_OBJECT) {
        obj_clear(p->obins[item]);
        obj_bin_range(p->bd->refs, i0, i1, p->cb, p->scale, p->obins[item]);
    } else if (p->kind == PAR_SPATIAL) {
        sp_clear(p->sbins[item], p->fr->nbins);
        sp_bin_range(p->bd->g, p->bd->refs, i0, i1, p->fr, p->sbins[item]);
    } else {
        bounds_range(p->bd->refs, i0, i1, &p->boxes[item][0], &p->boxes[item][1]);
    }
}

/* Chunks for a node of n references: 0 when it is binned in one piece. Depends on n only. */
static uint32_t par_chunks(const build_t *bd, uint32_t n)
{
    if (!bd->par || n < 2u * PAR_CHUNK)
        return 0;
    uint32_t c = n / PAR_CHUNK;
    return c > PAR_MAX_CHUNKS ? PAR_MAX_CHUNKS : c;
}

static void par_go(build_t *bd, par_kind_t kind, uint32_t base, uint32_t n, uint32_t chunks)
{
    par_t *p = bd->par;
    p->bd = bd;
    p->kind = kind;
    p->base = base;
    p->n = n;
    p->chunks = chunks;
    p->cfg->run(p->cfg->run_user, par_item, p, chunks);
}

/* Small nodes: every split in centroid order on every axis (an exact sweep), not bins. It finds every split
 * the bins could (a bin boundary is a prefix in centroid order) and costs less than clearing and sweeping 3 x
 * OBJ_BINS bins for a handful of references. Order: by centroid, ties by position, so it is deterministic. */
#define SWEEP_N 16u

static void sweep_order(const ref_t *refs, uint32_t n, int k, uint8_t *ord)
{
    float key[SWEEP_N];
    for (uint32_t i = 0; i < n; i++) {
        key[i] = centroid(&refs[i], k);
        ord[i] = (uint8_t)i;
    }
    for (uint32_t i = 1; i < n; i++) { /* insertion sort: stable, and n is small */
        const uint8_t o = ord[i];
        const float c = key[o];
        uint32_t j = i;
        while (j > 0 && key[ord[j - 1]] > c) {
            ord[j] = ord[j - 1];
            j--;
        }
        ord[j] = o;
    }
}

static void find_sweep_split(build_t *bd, uint32_t base, uint32_t n, const box_t *cb, split_t *best)
{
    const ref_t *refs = bd->refs + base;
    box_t rb[SWEEP_N];
    uint8_t ord[SWEEP_N];
    for (int k = 0; k < 3; k++) {
        if (!(cb->hi[k] - cb->lo[k] > 0.0f))
            continue;
        sweep_order(refs, n, k, ord);
        box_t acc;
        box_empty(&acc);
        for (uint32_t i = n - 1; i > 0; i--) {
            box_grow(&acc, &refs[ord[i]].b);
            rb[i] = acc;
        }
        box_t lacc;
        box_empty(&lacc);
        for (uint32_t i = 0; i + 1 < n; i++) {
            box_grow(&lacc, &refs[ord[i]].b);
            const uint32_t nl = i + 1, nr = n - nl;
            float c = box_area(&lacc) * sah_count(nl) + box_area(&rb[i + 1]) * sah_count(nr);
            if (c < best->cost) {
                best->cost = c;
                best->axis = k;
                best->bin = (int)i;
                best->lb = lacc;
                best->rb = rb[i + 1];
                best->nl = nl;
                best->nr = nr;
            }
        }
    }
}

/* The partition of find_sweep_split's result: the references in centroid order on its axis, cut after bin. */
static uint32_t partition_sweep(build_t *bd, uint32_t base, uint32_t n, const split_t *s)
{
    ref_t tmp[SWEEP_N];
    uint8_t ord[SWEEP_N];
    ref_t *refs = bd->refs + base;
    sweep_order(refs, n, s->axis, ord);
    for (uint32_t i = 0; i < n; i++)
        tmp[i] = refs[ord[i]];
    hz_memcpy(refs, tmp, (size_t)n * sizeof(ref_t));
    return (uint32_t)s->bin + 1u;
}

/* The SAH sweep over one axis's bins (object or spatial: the box first, then counts; both 48 bytes): nl[i] and
 * nr[i] are the left and right counts of the split after bin i. The boxes stay in four-lane registers: the
 * unions, areas and costs are box_grow's and box_area's, in their order, so the result is the scalar one.
 * Returns whether it improved on *best. */
HZ_STATIC_ASSERT(sizeof(obj_bin_t) == sizeof(sp_bin_t) && offsetof(sp_bin_t, b) == 0 && offsetof(obj_bin_t, b) == 0,
                 bins_share_the_sweep);
static bool sah_sweep(const bbox4_t *bins, int nbins, const uint32_t *nl, const uint32_t *nr, int axis,
                      split_t *best)
{
    const size_t stride = sizeof(obj_bin_t);
    bool found = false;
    const uint8_t *bp = (const uint8_t *)bins;
    bbox4_t rb[OBJ_BINS > SPATIAL_BINS ? OBJ_BINS : SPATIAL_BINS];
    float rarea[OBJ_BINS > SPATIAL_BINS ? OBJ_BINS : SPATIAL_BINS];
    const float inf = __builtin_inff();
    f4_t lo = f4_set1(inf), hi = f4_set1(-inf);
    for (int i = nbins - 1; i > 0; i--) {
        const bbox4_t *b = (const bbox4_t *)(const void *)(bp + (size_t)i * stride);
        lo = f4_min(lo, f4_load(b->lo)), hi = f4_max(hi, f4_load(b->hi));
        f4_store(rb[i].lo, lo), f4_store(rb[i].hi, hi);
        rarea[i] = b4_area(lo, hi);
    }
    lo = f4_set1(inf), hi = f4_set1(-inf);
    for (int i = 0; i < nbins - 1; i++) {
        const bbox4_t *b = (const bbox4_t *)(const void *)(bp + (size_t)i * stride);
        lo = f4_min(lo, f4_load(b->lo)), hi = f4_max(hi, f4_load(b->hi));
        if (nl[i] == 0 || nr[i] == 0)
            continue;
        float c = b4_area(lo, hi) * sah_count(nl[i]) + rarea[i + 1] * sah_count(nr[i]);
        if (c < best->cost) {
            best->cost = c;
            best->axis = axis;
            best->bin = i;
            bbox4_t l;
            f4_store(l.lo, lo), f4_store(l.hi, hi);
            best->lb = b4_box(&l);
            best->rb = b4_box(&rb[i + 1]);
            best->nl = nl[i];
            best->nr = nr[i];
            found = true;
        }
    }
    return found;
}

static void find_object_split(build_t *bd, uint32_t base, uint32_t n, const box_t *cb, split_t *best)
{
    best->cost = FLT_MAX;
    best->axis = -1;
    if (n <= SWEEP_N) {
        find_sweep_split(bd, base, n, cb, best);
        return;
    }
    float scale[3];
    for (int k = 0; k < 3; k++) {
        float ext = cb->hi[k] - cb->lo[k];
        scale[k] = ext > 0.0f ? (float)OBJ_BINS * 0.99999f / ext : 0.0f;
    }
    obj_clear(bd->obins);
    const uint32_t chunks = par_chunks(bd, n);
    if (chunks) {
        bd->par->cb = cb;
        bd->par->scale = scale;
        par_go(bd, PAR_OBJECT, base, n, chunks);
        for (uint32_t c = 0; c < chunks; c++)
            for (int k = 0; k < 3; k++)
                for (int i = 0; i < OBJ_BINS; i++) {
                    b4_grow_b4(&bd->obins[k][i].b, &bd->par->obins[c][k][i].b);
                    bd->obins[k][i].n += bd->par->obins[c][k][i].n;
                }
    } else {
        obj_bin_range(bd->refs, base, base + n, cb, scale, bd->obins);
    }
    for (int k = 0; k < 3; k++) {
        if (!(scale[k] > 0.0f))
            continue;
        const obj_bin_t *bins = bd->obins[k];
        uint32_t nl[OBJ_BINS], nr[OBJ_BINS], acc = 0;
        for (int i = 0; i < OBJ_BINS; i++) {
            acc += bins[i].n;
            nl[i] = acc, nr[i] = n - acc;
        }
        (void)sah_sweep(&bins[0].b, OBJ_BINS, nl, nr, k, best);
    }
}

HZ_INLINE float spatial_pos(const box_t *nb, int k, int i, int nbins)
{
    float ext = nb->hi[k] - nb->lo[k];
    return nb->lo[k] + ext * ((float)i * (1.0f / (float)nbins)); /* nbins is a power of two: exact */
}

/* Spatial bins for a node of n references: chopping costs (references x bins spanned), and fine planes pay
 * off only where many references share a node. */
static int spatial_bins(uint32_t n)
{
    return n >= 1024 ? SPATIAL_BINS : n >= 128 ? SPATIAL_BINS / 2 : SPATIAL_BINS / 4;
}


/* The best spatial split whose planes the budget can pay for: a plane that needs more than max_dup duplicates
 * (its straddling references) is not a candidate. Partitioning one anyway sent the straddlers it could not
 * duplicate whole to one side, children far wider than the search had costed: with a small budget the trees came
 * out worse than without spatial splits (the hairball's MSBVH at a budget of 0.1: SAH 272 against 258). Returns
 * the cost of the best plane at any number of duplicates. */
static float find_spatial_split(build_t *bd, uint32_t base, uint32_t n, const box_t *nb, uint32_t max_dup,
                                split_t *best)
{
    best->cost = FLT_MAX;
    best->axis = -1;
    sp_frame_t fr;
    fr.nbins = spatial_bins(n);
    fr.nb = nb;
    const int nbins = fr.nbins;
    for (int k = 0; k < 3; k++) {
        float ext = nb->hi[k] - nb->lo[k];
        fr.ok[k] = ext > 0.0f;
        fr.inv[k] = fr.ok[k] ? (float)nbins / ext : 0.0f;
        for (int i = 0; i <= nbins; i++)
            fr.planes[k][i] = fr.ok[k] ? spatial_pos(nb, k, i, nbins) : 0.0f;
    }
    sp_clear(bd->sbins, nbins);
    const uint32_t chunks = par_chunks(bd, n);
    if (chunks) {
        bd->par->fr = &fr;
        par_go(bd, PAR_SPATIAL, base, n, chunks);
        for (uint32_t c = 0; c < chunks; c++)
            for (int k = 0; k < 3; k++)
                for (int i = 0; i < nbins; i++) {
                    const sp_bin_t *s = &bd->par->sbins[c][k][i];
                    b4_grow_b4(&bd->sbins[k][i].b, &s->b);
                    bd->sbins[k][i].enter += s->enter;
                    bd->sbins[k][i].exit += s->exit;
                }
    } else {
        sp_bin_range(bd->g, bd->refs, base, base + n, &fr, bd->sbins);
    }
    split_t any; /* the best plane at any number of duplicates, on the axes where some plane is dear */
    any.cost = FLT_MAX;
    any.axis = -1;
    for (int k = 0; k < 3; k++) {
        if (!fr.ok[k])
            continue;
        const sp_bin_t *bins = bd->sbins[k];
        uint32_t nl[SPATIAL_BINS], nr[SPATIAL_BINS], l = 0, r = n;
        for (int i = 0; i < nbins; i++) {
            l += bins[i].enter, r -= bins[i].exit;
            nl[i] = l, nr[i] = r;
        }
        bool dear = false; /* a plane on this axis needs more duplicates than max_dup */
        for (int i = 0; i < nbins; i++)
            dear = dear || (uint64_t)nl[i] + nr[i] > (uint64_t)n + max_dup;
        if (dear) {
            sah_sweep(&bins[0].b, nbins, nl, nr, k, &any);
            for (int i = 0; i < nbins; i++)
                if ((uint64_t)nl[i] + nr[i] > (uint64_t)n + max_dup)
                    nl[i] = 0; /* sah_sweep skips a plane with an empty side */
        }
        if (sah_sweep(&bins[0].b, nbins, nl, nr, k, best))
            best->pos = fr.planes[k][best->bin + 1];
    }
    return any.cost < best->cost ? any.cost : best->cost; /* axes with no dear plane: best is their best */
}


/* ---- partitions: left refs end up below right refs; returns the left count ---- */
static void swap_ref(ref_t *a, ref_t *b)
{
    ref_t t = *a;
    *a = *b;
    *b = t;
}

static uint32_t partition_object(build_t *bd, uint32_t base, uint32_t n, const box_t *cb, const split_t *s)
{
    float ext = cb->hi[s->axis] - cb->lo[s->axis];
    float scale = (float)OBJ_BINS * 0.99999f / ext;
    uint32_t i = base, j = base + n;
    while (i < j) {
        if (obj_bin_of(centroid(&bd->refs[i], s->axis), cb->lo[s->axis], scale) <= s->bin)
            i++;
        else
            swap_ref(&bd->refs[i], &bd->refs[--j]);
    }
    return i - base;
}

/* Spatial partition with reference unsplitting (Stich et al. section 4.5): straddling references go whole to
 * one side when that is cheaper than duplicating them, and always once the duplicate budget is spent. The
 * right pieces of duplicated references are pushed on top of the stack. Returns the left count; the right
 * child's references are [base + left, top). */
static uint32_t partition_spatial(build_t *bd, uint32_t base, uint32_t n, const split_t *s, box_t *lbox,
                                  box_t *rbox)
{
    const int k = s->axis;
    uint32_t lend = base, rstart = base + n;
    box_t lb, rb;
    box_empty(&lb);
    box_empty(&rb);
    for (uint32_t i = base; i < rstart;) {
        ref_t *r = &bd->refs[i];
        if (r->b.hi[k] <= s->pos) {
            box_grow(&lb, &r->b);
            swap_ref(r, &bd->refs[lend++]);
            i++;
        } else if (r->b.lo[k] >= s->pos) {
            box_grow(&rb, &r->b);
            swap_ref(r, &bd->refs[--rstart]);
        } else {
            i++;
        }
    }
    /* [lend, rstart) straddle the plane */
    while (lend < rstart) {
        ref_t *r = &bd->refs[lend];
        uint32_t nl = lend - base, nr = bd->top - rstart;
        box_t lub = lb, rub = rb;
        box_grow(&lub, &r->b);
        box_grow(&rub, &r->b);
        float c_left = box_area(&lub) * sah_count(nl + 1) + box_area(&rb) * sah_count(nr);
        float c_right = box_area(&lb) * sah_count(nl) + box_area(&rub) * sah_count(nr + 1);
        ref_t lr, rr;
        float c_dup = FLT_MAX;
        box_t ldb = lb, rdb = rb;
        if (bd->dup_left == 0)
            bd->budget_stops++;
        if (bd->dup_left > 0 && bd->top < bd->ref_cap) {
            split_ref(bd, r, k, s->pos, &lr, &rr);
            if (box_valid(&lr.b) && box_valid(&rr.b)) {
                ldb = lb, rdb = rb;
                box_grow(&ldb, &lr.b);
                box_grow(&rdb, &rr.b);
                c_dup = box_area(&ldb) * sah_count(nl + 1) + box_area(&rdb) * sah_count(nr + 1);
            }
        }
        if (c_dup < c_left && c_dup < c_right) {
            *r = lr;
            bd->refs[bd->top++] = rr;
            bd->dup_left--;
            lb = ldb, rb = rdb;
            lend++;
        } else if (c_left <= c_right) {
            lb = lub;
            lend++;
        } else {
            rb = rub;
            swap_ref(r, &bd->refs[--rstart]);
        }
    }
    *lbox = lb;
    *rbox = rb;
    return lend - base;
}

static void bounds_of(build_t *bd, uint32_t base, uint32_t n, box_t *b, box_t *cb)
{
    const uint32_t chunks = par_chunks(bd, n);
    if (!chunks) {
        bounds_range(bd->refs, base, base + n, b, cb);
        return;
    }
    par_go(bd, PAR_BOUNDS, base, n, chunks);
    box_empty(b);
    box_empty(cb);
    for (uint32_t c = 0; c < chunks; c++) {
        box_grow(b, &bd->par->boxes[c][0]);
        box_grow(cb, &bd->par->boxes[c][1]);
    }
}

static uint32_t new_node(build_t *bd)
{
    if (bd->node_count >= bd->node_cap) {
        bd->failed = true;
        return 0;
    }
    return bd->node_count++;
}

static float make_leaf(build_t *bd, uint32_t idx, uint32_t n, float area)
{
    bnode_t *nd = &bd->nodes[idx];
    uint32_t base = bd->top - n;
    if (bd->leaf_count + n > bd->leaf_cap) {
        bd->failed = true;
        return 0.0f;
    }
    nd->a = bd->leaf_count;
    nd->n = BLEAF | n;
    for (uint32_t i = 0; i < n; i++)
        bd->leaf_prims[bd->leaf_count++] = bd->refs[base + i].prim;
    bd->top = base;
    if (bd->progress && bd->leaf_count >= bd->progress_next) {
        /* Splits add references as it goes, so the fraction is capped; the collapse into wide nodes after it
         * takes about a fifth of the time (the dragon, the furball). */
        float f = (float)bd->leaf_count / (float)bd->progress_total;
        bd->progress(bd->progress_user, 0.8f * (f < 1.0f ? f : 1.0f));
        bd->progress_next = bd->leaf_count + bd->progress_step;
    }
    return COST_TRI * sah_count(n) * area;
}

/* Builds the node for the n references on top of the stack (bounds b); pops them. `budget` is the subtree's
 * share of the replication budget: what a split does not use is shared between the children in proportion to
 * their references, so the first subtrees built cannot spend it all (which left the rest of Sponza without
 * any). Returns the SAH cost (unnormalised: area-weighted). */
/* What split_node decided for an inner node. */
typedef struct node_split {
    uint32_t li, ri, nl, nr;
    box_t lb, rb;
    uint32_t left_over; /* the budget after the node's own duplicates */
} node_split_t;

/* Decides node idx for the n references on top of the stack (bounds b) with the subtree's share `budget` of the
 * replication budget: a leaf (true, *leaf_cost set, the references popped), or a split (false): children
 * allocated, references partitioned (the right child's on top). */
static bool split_node(build_t *bd, uint32_t idx, uint32_t n, const box_t *b, uint32_t depth, uint32_t budget,
                       node_split_t *sp, float *leaf_cost)
{
    bnode_t *nd = &bd->nodes[idx];
    nd->b = *b;
    const float area = box_area(b);
    const uint32_t base = bd->top - n;
    *leaf_cost = 0.0f;
    if (bd->failed)
        return true;
    /* A leaf of at most SAH_BLOCK references costs one block test (COST_TRI), no more than the node a split
     * would add (COST_NODE): it wins against any split below, so no split is searched for. */
    if (n <= 1 || (n <= bd->leaf_max && (depth + 1 >= HZ_BVH_MAX_DEPTH || n <= SAH_BLOCK))) {
        *leaf_cost = make_leaf(bd, idx, n, area);
        return true;
    }

    box_t nb, cb;
    bounds_of(bd, base, n, &nb, &cb);
    split_t os, ss;
    hz_memset(&os, 0, sizeof os);
    hz_memset(&ss, 0, sizeof ss);
    ss.cost = FLT_MAX;
    ss.axis = -1;
    bool median = depth >= DEPTH_FORCE_MEDIAN;
    if (!median) {
        find_object_split(bd, base, n, &cb, &os);
        if (bd->spatial) {
            box_t ov = box_and(&os.lb, &os.rb);
            /* Children that only touch (axis-aligned architecture: blocks side by side) overlap in a flat box
             * whose area passes α, but no spatial split can remove such an overlap. Skipping the search there
             * builds Lost Empire 3.7x faster (0 spatial splits either way) and Sponza 1.3x (807 instead of
             * 1,036 splits, the same Mrays/s in make bench). */
            const bool thick = ov.lo[0] < ov.hi[0] && ov.lo[1] < ov.hi[1] && ov.lo[2] < ov.hi[2];
            const bool want = os.axis < 0 || (thick && box_area(&ov) > bd->min_overlap);
            if (want && budget > 0) {
                /* a stop: the split the budget left out would have been taken */
                const float unbounded = find_spatial_split(bd, base, n, b, budget, &ss);
                if (unbounded < ss.cost && unbounded < os.cost)
                    bd->budget_stops++;
            } else if (want) {
                bd->budget_stops++;
            }
        }
    } else {
        os.axis = -1;
        os.cost = FLT_MAX;
    }
    float best = hz_minf(os.cost, ss.cost);
    float leaf_cost_here = COST_TRI * sah_count(n) * area;
    float split_cost = COST_NODE * area + COST_TRI * best;
    if (n <= bd->leaf_max && (leaf_cost_here <= split_cost || best == FLT_MAX)) {
        *leaf_cost = make_leaf(bd, idx, n, area);
        return true;
    }

    uint32_t nl;
    box_t lb, rb;
    bd->dup_left = budget;
    if (ss.axis >= 0 && ss.cost < os.cost) {
        nl = partition_spatial(bd, base, n, &ss, &lb, &rb);
        if (nl == 0 || nl == bd->top - base) {
            median = true; /* unsplitting emptied a side (possible only without duplicates) */
        } else {
            bd->spatial_splits++;
        }
    } else if (os.axis >= 0) {
        nl = n <= SWEEP_N ? partition_sweep(bd, base, n, &os) : partition_object(bd, base, n, &cb, &os);
        if (nl == 0 || nl == n) {
            median = true;
        } else {
            lb = os.lb;
            rb = os.rb;
        }
    } else {
        median = true;
    }
    if (median) {
        /* No usable split (coincident centroids, or too deep): halve by index. */
        nl = (bd->top - base) / 2;
        box_t dummy;
        bounds_of(bd, base, nl, &lb, &dummy);
        bounds_of(bd, base + nl, bd->top - base - nl, &rb, &dummy);
    }
    uint32_t nr = bd->top - base - nl;
    uint32_t li = new_node(bd), ri = new_node(bd);
    if (bd->failed)
        return true;
    nd = &bd->nodes[idx];
    nd->a = li;
    nd->n = ri;
    sp->li = li, sp->ri = ri, sp->nl = nl, sp->nr = nr;
    sp->lb = lb, sp->rb = rb;
    sp->left_over = bd->dup_left;
    return false;
}

/* Builds the node for the n references on top of the stack (bounds b); pops them. `budget` is the subtree's
 * share of the replication budget: what a split does not use is shared between the children in proportion to
 * their references, so the first subtrees built cannot spend it all (which left the rest of Sponza without
 * any). Returns the SAH cost (unnormalised: area-weighted). */
static float build_node(build_t *bd, uint32_t idx, uint32_t n, const box_t *b, uint32_t depth, uint32_t *budget_io)
{
    node_split_t sp;
    float c;
    if (split_node(bd, idx, n, b, depth, *budget_io, &sp, &c))
        return c;
    /* Right references are on top: build them first, which pops them. */
    c = COST_NODE * box_area(b);
    uint32_t rbud = (uint32_t)((uint64_t)sp.left_over * sp.nr / (sp.nl + sp.nr));
    const uint32_t keep = sp.left_over - rbud;
    c += build_node(bd, sp.ri, sp.nr, &sp.rb, depth + 1, &rbud);
    uint32_t lbud = keep + rbud; /* what the right subtree left unused goes on to the left one */
    c += build_node(bd, sp.li, sp.nl, &sp.lb, depth + 1, &lbud);
    *budget_io = lbud;
    return c;
}

/* ---- parallel build: top levels here, subtrees as tasks ---- */
typedef struct task {
    box_t b;
    uint32_t idx, n, depth, budget, share; /* budget: what it may spend; share: its plain share */
    uint32_t ref0, node0, node_end, leaf0, leaf_end; /* its ranges of the scratch arrays */
    float sah;
    uint32_t splits, stops, leaves;
    bool failed;
    bool rerun;       /* over budget in the first pass: built again with budget2 (build_top) */
    uint32_t budget2;
} task_t;

enum { TOP_NODE = 0, TOP_TASK = 1, TOP_DONE = 2 };

/* A top-level node and its children (0: right, 1: left): a top node, a task, or a subtree built in place. */
typedef struct top_node {
    float area;
    uint32_t kind[2], ref[2];
    float cost[2];
} top_node_t;

typedef struct top_ctx {
    build_t *bd;
    task_t *tasks;
    uint32_t task_count;
    top_node_t *tops;
    uint32_t top_count;
    uint32_t limit; /* subtrees of at most this many references become tasks */
    uint32_t list[PAR_MAX_TASKS]; /* the tasks a pass runs, in order */
    uint32_t list_count;
} top_ctx_t;

/* Subtrees of at most this many references are tasks: about 64 to 128 of them (from the reference count only). */
static uint32_t task_limit(uint32_t n)
{
    return n / 64u > PAR_TASK_MIN ? n / 64u : PAR_TASK_MIN;
}

static void top_node(top_ctx_t *tc, uint32_t idx, uint32_t n, const box_t *b, uint32_t depth, uint32_t budget,
                     uint32_t *kind, uint32_t *ref, float *cost);

static void top_child(top_ctx_t *tc, uint32_t idx, uint32_t n, const box_t *b, uint32_t depth, uint32_t budget,
                      uint32_t *kind, uint32_t *ref, float *cost)
{
    build_t *bd = tc->bd;
    *cost = 0.0f;
    *ref = 0;
    if (n <= tc->limit) {
        /* A task's ranges hold what its subtree can use at most: n + budget references and leaf slots, twice
         * that in nodes; they are cut from the high ends of the arrays, which the top levels' caps then end at. */
        const uint64_t tb = (uint64_t)budget * TASK_BUDGET_SCALE;
        const uint64_t nr = (uint64_t)n + tb, nn = 2u * nr;
        if (tc->task_count < PAR_MAX_TASKS && bd->ref_cap - bd->top >= nr && bd->node_cap - bd->node_count >= nn &&
            bd->leaf_cap - bd->leaf_count >= nr) {
            task_t *t = &tc->tasks[tc->task_count];
            t->b = *b;
            t->idx = idx, t->n = n, t->depth = depth, t->budget = (uint32_t)tb, t->share = budget;
            bd->ref_cap -= (uint32_t)nr;
            t->ref0 = bd->ref_cap;
            hz_memcpy(&bd->refs[t->ref0], &bd->refs[bd->top - n], (size_t)n * sizeof(ref_t));
            bd->top -= n;
            bd->node_cap -= (uint32_t)nn;
            t->node0 = bd->node_cap, t->node_end = bd->node_cap + (uint32_t)nn;
            bd->leaf_cap -= (uint32_t)nr;
            t->leaf0 = bd->leaf_cap, t->leaf_end = bd->leaf_cap + (uint32_t)nr;
            bd->nodes[idx].b = *b;
            *kind = TOP_TASK;
            *ref = tc->task_count++;
            return;
        }
    }
    if (n <= tc->limit || tc->top_count >= PAR_MAX_TOP) {
        uint32_t bud = budget;
        *kind = TOP_DONE;
        *cost = build_node(bd, idx, n, b, depth, &bud);
        return;
    }
    top_node(tc, idx, n, b, depth, budget, kind, ref, cost);
}

/* build_node for the top levels, but the children get their shares of the budget as they are (build_node adds
 * the right subtree's unused budget to the left one's: unknown here, the right one may be a task). */
static void top_node(top_ctx_t *tc, uint32_t idx, uint32_t n, const box_t *b, uint32_t depth, uint32_t budget,
                     uint32_t *kind, uint32_t *ref, float *cost)
{
    build_t *bd = tc->bd;
    node_split_t sp;
    float c;
    if (split_node(bd, idx, n, b, depth, budget, &sp, &c)) {
        *kind = TOP_DONE;
        *cost = c;
        return;
    }
    const uint32_t ti = tc->top_count++;
    top_node_t *t = &tc->tops[ti];
    t->area = box_area(b);
    const uint32_t rbud = (uint32_t)((uint64_t)sp.left_over * sp.nr / (sp.nl + sp.nr));
    const uint32_t keep = sp.left_over - rbud;
    top_child(tc, sp.ri, sp.nr, &sp.rb, depth + 1, rbud, &t->kind[0], &t->ref[0], &t->cost[0]);
    t = &tc->tops[ti];
    top_child(tc, sp.li, sp.nl, &sp.lb, depth + 1, keep, &t->kind[1], &t->ref[1], &t->cost[1]);
    *kind = TOP_NODE;
    *ref = ti;
}

/* The SAH sum in the serial build's order: node, then right subtree, then left. */
static float top_cost(const top_ctx_t *tc, uint32_t kind, uint32_t ref, float cost)
{
    if (kind == TOP_DONE)
        return cost;
    if (kind == TOP_TASK)
        return tc->tasks[ref].sah;
    const top_node_t *t = &tc->tops[ref];
    float c = COST_NODE * t->area;
    c += top_cost(tc, t->kind[0], t->ref[0], t->cost[0]);
    c += top_cost(tc, t->kind[1], t->ref[1], t->cost[1]);
    return c;
}

static void task_item(void *ctx, uint32_t item)
{
    const top_ctx_t *tc = ctx;
    const build_t *bd = tc->bd;
    task_t *t = &tc->tasks[tc->list[item]];
    build_t b; /* on this thread's stack: the bins are per task */
    hz_memset(&b, 0, sizeof b);
    b.g = bd->g;
    b.refs = bd->refs + t->ref0;
    b.top = t->n;
    b.ref_cap = t->n + t->budget;
    b.nodes = bd->nodes;
    b.node_count = t->node0;
    b.node_cap = t->node_end;
    b.leaf_prims = bd->leaf_prims;
    b.leaf_count = t->leaf0;
    b.leaf_cap = t->leaf_end;
    b.leaf_max = bd->leaf_max;
    b.spatial = bd->spatial;
    b.min_overlap = bd->min_overlap;
    uint32_t bud = t->budget;
    t->sah = build_node(&b, t->idx, t->n, &t->b, t->depth, &bud);
    t->splits = b.spatial_splits;
    t->stops = b.budget_stops;
    t->leaves = b.leaf_count - t->leaf0;
    t->failed = b.failed;
}

typedef enum top_result { TOP_FAILED, TOP_BUILT, TOP_RERUN } top_result_t;

/* Which tasks of a first pass that went over the budget are built again, and with what: in task order (the
 * serial build's), a task keeps its tree if what it used fits beside the plain shares of the tasks after it;
 * the others get their shares plus, in proportion to them, what the kept ones left (capped at what their ranges
 * hold). The total then stays within the budget. Returns false if the shares themselves do not fit (the serial
 * build instead). */
static bool plan_rerun(top_ctx_t *tc, uint64_t avail)
{
    uint64_t rest = 0, acc = 0, rej_share = 0;
    for (uint32_t i = 0; i < tc->task_count; i++)
        rest += tc->tasks[i].share;
    if (rest > avail)
        return false;
    for (uint32_t i = 0; i < tc->task_count; i++) {
        task_t *t = &tc->tasks[i];
        const uint64_t used = t->leaves - t->n;
        rest -= t->share;
        t->rerun = acc + used + rest > avail;
        if (t->rerun) {
            acc += t->share;
            rej_share += t->share;
        } else {
            acc += used;
        }
    }
    const uint64_t slack = avail - acc;
    for (uint32_t i = 0; i < tc->task_count; i++) {
        task_t *t = &tc->tasks[i];
        if (!t->rerun)
            continue;
        uint64_t b = t->share + (rej_share ? slack * t->share / rej_share : 0u);
        t->budget2 = (uint32_t)(b < t->budget ? b : t->budget);
    }
    return true;
}

static void run_list(const hz_accel_config_t *cfg, top_ctx_t *tc, bool parallel)
{
    if (parallel && tc->list_count > 1u)
        cfg->run(cfg->run_user, task_item, tc, tc->list_count);
    else
        for (uint32_t i = 0; i < tc->list_count; i++) {
            task_item(tc, i);
            if (cfg->progress && i % 4u == 3u)
                cfg->progress(cfg->progress_user, 0.3f + 0.5f * (float)i / (float)tc->list_count);
        }
}

/* The build of the root (idx 0, every reference on the stack) through the top levels and tasks; the tasks run
 * on cfg->run when `parallel`, else here in turn: the same tree either way. First pass (rerun false): every task
 * with TASK_BUDGET_SCALE times its share; if the references then went over the budget (the furball, where it
 * binds everywhere), TOP_RERUN with a plan (plan_rerun), and the caller restores the references and calls again
 * with rerun true: the top levels are built again (the same), the kept tasks keep their trees and only the
 * others are built again, in parallel. TOP_FAILED if a range was too small or the plan does not hold. */
static top_result_t build_top(build_t *bd, const hz_accel_config_t *cfg, top_ctx_t *tc, const box_t *root,
                              uint32_t budget, bool parallel, bool rerun, float *sah)
{
    tc->bd = bd;
    const uint32_t first_count = tc->task_count;
    tc->task_count = 0;
    tc->top_count = 0;
    tc->limit = task_limit(bd->top);
    const uint32_t refs0 = bd->top;
    uint32_t kind, ref;
    float cost;
    top_node(tc, 0, bd->top, root, 0, budget, &kind, &ref, &cost);
    if (bd->failed || (rerun && tc->task_count != first_count))
        return TOP_FAILED;
    if (cfg->progress)
        cfg->progress(cfg->progress_user, 0.3f);
    const uint32_t top_leaves = bd->leaf_count;
    tc->list_count = 0;
    for (uint32_t i = 0; i < tc->task_count; i++)
        if (!rerun || tc->tasks[i].rerun) {
            if (rerun)
                tc->tasks[i].budget = tc->tasks[i].budget2;
            tc->list[tc->list_count++] = i;
        }
    run_list(cfg, tc, parallel);
    uint32_t splits = 0, stops = 0;
    uint64_t leaves = 0;
    for (uint32_t i = 0; i < tc->task_count; i++) {
        const task_t *t = &tc->tasks[i];
        if (t->failed)
            return TOP_FAILED;
        splits += t->splits;
        stops += t->stops;
        leaves += t->leaves;
    }
    const uint64_t used = top_leaves + leaves - refs0;
    if (used > budget) {
        if (rerun)
            return TOP_FAILED;
        /* what the tasks may use together: the budget less the top levels' own duplicates */
        uint64_t task_refs = 0;
        for (uint32_t i = 0; i < tc->task_count; i++)
            task_refs += tc->tasks[i].n;
        const uint64_t top_dups = top_leaves + task_refs - refs0;
        return top_dups <= budget && plan_rerun(tc, budget - top_dups) ? TOP_RERUN : TOP_FAILED;
    }
    bd->spatial_splits += splits;
    bd->budget_stops += stops;
    bd->leaf_count += (uint32_t)leaves;
    *sah = top_cost(tc, kind, ref, cost);
    if (cfg->progress)
        cfg->progress(cfg->progress_user, 0.8f);
    return TOP_BUILT;
}

/* ---- collapse into wide nodes ---- */
typedef struct collapse {
    const build_t *bd;
    const hz_accel_geom_t *g;
    hz_bvh_node_t *nodes; /* NULL in the counting pass */
    hz_bvh_block_t *blocks;
    uint32_t node_count, block_count, fill, leaf_count;
    uint32_t depth;
} collapse_t;

static void fill_block_slot(hz_bvh_block_t *bl, uint32_t s, const hz_accel_geom_t *g, uint32_t prim)
{
    (void)hz_bvh_fill_slot(bl, s, g, g->pos, prim);
}

bool hz_bvh_fill_slot(hz_bvh_block_t *bl, uint32_t s, const hz_accel_geom_t *g, const float *pos, uint32_t prim)
{
    const uint32_t *t = g->tri + 3u * (size_t)prim;
    bool ok = true;
    for (int v = 0; v < 3; v++) {
        const float *p = pos + 4u * (size_t)t[v];
        for (int k = 0; k < 3; k++) {
            bl->v[v][k][s] = p[k];
            ok = ok && hz_absf(p[k]) <= HZ_ACCEL_MAX_COORD;
        }
    }
    if (!ok) /* moved out of range (or to NaN) by the caller: the triangle disappears (degenerate) */
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 3; k++)
                bl->v[v][k][s] = 0.0f;
    uint32_t w = prim;
    if (g->tri_flags && (g->tri_flags[prim] & HZ_ACCEL_TRI_ANYHIT))
        w |= HZ_BVH_PRIM_ANYHIT;
    bl->prim[s] = w;
    return ok;
}

static void clear_block(hz_bvh_block_t *bl)
{
    hz_memset(bl, 0, sizeof *bl);
    for (int s = 0; s < HZ_BVH_W; s++)
        bl->prim[s] = HZ_BVH_PRIM_PAD;
}

static uint32_t place_leaf(collapse_t *c, const bnode_t *leaf)
{
    uint32_t n = leaf->n & ~BLEAF;
    if (c->block_count == 0 || c->fill + n > HZ_BVH_W) {
        if (c->blocks)
            clear_block(&c->blocks[c->block_count]);
        c->block_count++;
        c->fill = 0;
    }
    uint32_t b = c->block_count - 1, s0 = c->fill;
    if (c->blocks)
        for (uint32_t i = 0; i < n; i++)
            fill_block_slot(&c->blocks[b], s0 + i, c->g, c->bd->leaf_prims[leaf->a + i]);
    c->fill += n;
    c->leaf_count++;
    return hz_bvh_make_leaf(b * HZ_BVH_W + s0, n);
}

static void set_child_box(hz_bvh_node_t *w, int i, const box_t *b)
{
    w->lo_x[i] = b->lo[0], w->hi_x[i] = b->hi[0];
    w->lo_y[i] = b->lo[1], w->hi_y[i] = b->hi[1];
    w->lo_z[i] = b->lo[2], w->hi_z[i] = b->hi[2];
}

static uint32_t collapse_node(collapse_t *c, uint32_t bi, uint32_t depth)
{
    const bnode_t *bn = c->bd->nodes;
    uint32_t wi = c->node_count++;
    if (depth + 1 > c->depth)
        c->depth = depth + 1;
    uint32_t kids[HZ_BVH_W];
    float area[HZ_BVH_W]; /* of each kid, -1 for leaves (never opened): computed once, not per round */
    int nk = 0;
    if (bn[bi].n & BLEAF) {
        kids[nk++] = bi;
    } else {
        kids[nk++] = bn[bi].a;
        kids[nk++] = bn[bi].n;
    }
    for (int i = 0; i < nk; i++)
        area[i] = bn[kids[i]].n & BLEAF ? -1.0f : box_area(&bn[kids[i]].b);
    while (nk < HZ_BVH_W) {
        int pick = -1;
        float best = -1.0f;
        for (int i = 0; i < nk; i++)
            if (area[i] > best) {
                best = area[i];
                pick = i;
            }
        if (pick < 0)
            break;
        uint32_t open = kids[pick];
        kids[pick] = bn[open].a;
        kids[nk++] = bn[open].n;
        area[pick] = bn[kids[pick]].n & BLEAF ? -1.0f : box_area(&bn[kids[pick]].b);
        area[nk - 1] = bn[kids[nk - 1]].n & BLEAF ? -1.0f : box_area(&bn[kids[nk - 1]].b);
    }
    uint32_t words[HZ_BVH_W];
    for (int i = 0; i < nk; i++) /* leaves first, so a node's leaves sit side by side in the blocks */
        if (bn[kids[i]].n & BLEAF)
            words[i] = place_leaf(c, &bn[kids[i]]);
    for (int i = 0; i < nk; i++)
        if (!(bn[kids[i]].n & BLEAF))
            words[i] = collapse_node(c, kids[i], depth + 1);
    if (c->nodes) {
        hz_bvh_node_t *w = &c->nodes[wi];
        box_t e;
        box_empty(&e);
        for (int i = 0; i < HZ_BVH_W; i++) {
            set_child_box(w, i, i < nk ? &bn[kids[i]].b : &e);
            w->child[i] = i < nk ? words[i] : HZ_BVH_EMPTY;
            w->pad[i] = 0;
        }
    }
    return wi;
}

/* ---- bounds ---- */
static uint64_t refs_bound(uint32_t tri_count, const hz_accel_config_t *cfg)
{
    uint64_t n = tri_count ? tri_count : 1;
    if (cfg->spatial_splits && cfg->split_budget > 0.0f) {
        float b = cfg->split_budget > HZ_ACCEL_SPLIT_BUDGET_MAX ? HZ_ACCEL_SPLIT_BUDGET_MAX : cfg->split_budget;
        n += (uint64_t)((float)tri_count * b);
    }
    return n;
}

uint64_t hz_bvh_blocks_bound(uint64_t refs)
{
    /* next-fit: two consecutive blocks hold more than W slots together */
    return 2u * refs / HZ_BVH_W + 1u;
}

uint64_t hz_bvh_nodes_bound(uint64_t refs)
{
    /* With L <= refs leaves: a node with fewer than W children has only leaf children (and >= 2 of them but
     * for a leaf root), so full nodes <= (L - 1) / (W - 1) and the others <= (L + 1) / 2. */
    return refs / (HZ_BVH_W - 1) + (refs + 1) / 2 + 2;
}

/* The parallel build's bookkeeping (tasks, top nodes, chunk bins): only builds of more than PAR_TASK_MIN
 * references take that path. */
static uint64_t par_scratch_bytes(void)
{
    return PAR_MAX_TASKS * sizeof(task_t) + PAR_MAX_TOP * sizeof(top_node_t) + sizeof(par_t) +
           PAR_MAX_CHUNKS * (sizeof(obj_bin_t[3][OBJ_BINS]) + sizeof(sp_bin_t[3][SPATIAL_BINS]) + 2u * sizeof(box_t)) +
           5u * 64u;
}

/* References the scratch arrays hold: with tasks (more than PAR_TASK_MIN triangles) room for every task's
 * scaled budget. */
static uint64_t scratch_refs(uint32_t tri_count, uint64_t refs)
{
    return tri_count > PAR_TASK_MIN ? refs + (TASK_BUDGET_SCALE - 1u) * (refs - tri_count) : refs;
}

uint64_t hz_bvh_scratch_bound(uint32_t tri_count, uint64_t refs)
{
    const uint64_t cap = scratch_refs(tri_count, refs);
    return cap * sizeof(ref_t) + (2u * cap + 2u) * sizeof(bnode_t) + cap * sizeof(uint32_t) + sizeof(build_t) +
           4u * 64u + (tri_count > PAR_TASK_MIN ? par_scratch_bytes() : 0u);
}

static size_t sat_size(uint64_t x)
{
    return x > (uint64_t)SIZE_MAX ? SIZE_MAX : (size_t)x;
}

hz_accel_bytes_t hz_accel_bytes_bound(uint32_t tri_count, const hz_accel_config_t *cfg)
{
    hz_accel_config_t d;
    if (!cfg) {
        hz_accel_config_default(&d);
        cfg = &d;
    }
    uint64_t r = refs_bound(tri_count, cfg);
    uint64_t kept = sizeof(hz_accel_t) + sizeof(hz_bvh_t) + hz_bvh_nodes_bound(r) * sizeof(hz_bvh_node_t) +
                    hz_bvh_blocks_bound(r) * sizeof(hz_bvh_block_t) + 4u * 64u;
    hz_accel_bytes_t out;
    out.kept = sat_size(kept);
    out.peak = sat_size(kept + hz_bvh_scratch_bound(tri_count, r));
    return out;
}

hz_accel_bytes_t hz_accel_bytes_bound_geom(const hz_accel_geom_t *g, const hz_accel_config_t *cfg)
{
    hz_accel_config_t d;
    if (!cfg) {
        hz_accel_config_default(&d);
        cfg = &d;
    }
    if (hz_inst_used(g, cfg))
        return hz_inst_bytes_bound(g, cfg);
    if (!g || g->time_keys < 2u)
        return hz_accel_bytes_bound(g ? g->tri_count : 0u, cfg);
    hz_accel_config_t c2 = *cfg;
    if (cfg->blur != HZ_ACCEL_BLUR_MSBVH)
        c2.spatial_splits = false; /* the interpolated and swept BVHs have no spatial splits */
    hz_accel_bytes_t b = hz_accel_bytes_bound(g->tri_count, &c2);
    const uint64_t r = refs_bound(g->tri_count, &c2);
    const uint64_t extra = hz_bvh_motion_kept_bound(r, g->time_keys, cfg->blur, g->vertex_count);
    /* the build's peak adds the midpoint positions (K = 2) and one byte per triangle of reference counts */
    const uint64_t scratch = (g->time_keys == 2u ? ((uint64_t)g->vertex_count * 4u + 4u) * sizeof(float) + 64u : 0u) +
                             (uint64_t)g->tri_count + 64u;
    hz_accel_bytes_t out;
    out.kept = sat_size((uint64_t)b.kept + extra);
    out.peak = sat_size((uint64_t)b.peak + extra + scratch);
    return out;
}

/* ---- the build ---- */
/* References for every triangle in range, in triangle order, on an empty stack; returns the count skipped. */
static uint32_t init_refs(build_t *bd, bool sweep, box_t *root)
{
    const hz_accel_geom_t *g = bd->g;
    uint32_t skipped = 0;
    box_empty(root);
    for (uint32_t t = 0; t < g->tri_count; t++) {
        box_t b;
        if (g->tri_flags && (g->tri_flags[t] & HZ_ACCEL_TRI_LEFT_OUT))
            continue;
        if (!tri_box(g, t, &b, sweep)) {
            skipped++;
            continue;
        }
        ref_t *r = &bd->refs[bd->top++];
        r->b = b;
        r->prim = t;
        r->pad = 0;
        box_grow(root, &b);
    }
    return skipped;
}

hz_status_t hz_bvh_build(hz_bvh_t *bvh, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                         hz_arena_t *arena, hz_bvh_build_out_t *out, hz_error_t *err)
{
    const hz_arena_mark_t m0 = hz_arena_mark(arena);
    const uint64_t rb = refs_bound(g->tri_count, cfg), cap = scratch_refs(g->tri_count, rb);
    build_t *bd = hz_arena_alloc(arena, sizeof(build_t), 64);
    ref_t *refs = hz_arena_alloc_array(arena, (size_t)cap, sizeof(ref_t), 64);
    bnode_t *nodes = hz_arena_alloc_array(arena, (size_t)(2u * cap + 2u), sizeof(bnode_t), 64);
    uint32_t *leaf_prims = hz_arena_alloc_array(arena, (size_t)cap, sizeof(uint32_t), 64);
    if (!bd || !refs || !nodes || !leaf_prims) {
        hz_arena_error(arena, err);
        hz_error_prefix(err, "accel build scratch");
        hz_arena_reset(arena, m0);
        return HZ_E_NO_MEMORY;
    }
    hz_memset(bd, 0, sizeof *bd);
    bd->g = g;
    bd->refs = refs;
    bd->ref_cap = (uint32_t)rb;
    bd->nodes = nodes;
    bd->node_cap = (uint32_t)(2u * rb);
    bd->leaf_prims = leaf_prims;
    bd->leaf_cap = (uint32_t)rb;
    bd->leaf_max = cfg->leaf_max < 1 ? 1 : (cfg->leaf_max > HZ_BVH_W ? HZ_BVH_W : cfg->leaf_max);
    bd->spatial = cfg->spatial_splits;
    const uint32_t budget = (uint32_t)(rb - g->tri_count);
    const bool sweep = g->time_keys >= 2u && cfg->blur == HZ_ACCEL_BLUR_SWEPT;

    box_t root;
    uint32_t skipped = init_refs(bd, sweep, &root);
    float alpha = cfg->split_alpha > 0.0f ? cfg->split_alpha : 0.0f;
    bd->min_overlap = alpha * box_area(&root);
    float sah = 0.0f;
    uint32_t root_idx = new_node(bd);
    bool done = false, par_held = false;
    uint32_t rebuilt = 0;
    hz_arena_mark_t par_mark = 0;
    if (bd->top == 0) {
        /* nothing to hit: one empty leaf */
        nodes[0].b = root;
        nodes[0].a = 0;
        nodes[0].n = BLEAF | 0u;
        done = true;
    } else if (bd->top > task_limit(bd->top)) {
        /* Top levels and tasks (also without a pool: the tree must not depend on it). Their bookkeeping sits
         * above the scratch arrays (hz_bvh_scratch_bound counts it). */
        const bool parallel = cfg->run && cfg->run_threads > 1u;
        const hz_arena_mark_t m1 = hz_arena_mark(arena);
        top_ctx_t tc;
        tc.task_count = 0;
        par_t *par = hz_arena_alloc(arena, sizeof(par_t), 64);
        tc.tasks = hz_arena_alloc_array(arena, PAR_MAX_TASKS, sizeof(task_t), 64);
        tc.tops = hz_arena_alloc_array(arena, PAR_MAX_TOP, sizeof(top_node_t), 64);
        if (par) {
            par->cfg = cfg;
            par->obins = hz_arena_alloc_array(arena, PAR_MAX_CHUNKS, sizeof(obj_bin_t[3][OBJ_BINS]), 64);
            par->sbins = hz_arena_alloc_array(arena, PAR_MAX_CHUNKS, sizeof(sp_bin_t[3][SPATIAL_BINS]), 64);
            par->boxes = hz_arena_alloc_array(arena, PAR_MAX_CHUNKS, 2u * sizeof(box_t), 64);
        }
        if (!par || !tc.tasks || !tc.tops || !par->obins || !par->sbins || !par->boxes) {
            hz_arena_error(arena, err);
            hz_error_prefix(err, "accel build scratch");
            hz_arena_reset(arena, m0);
            return HZ_E_NO_MEMORY;
        }
        /* If the tasks together went over the budget (a scene where it binds everywhere, like the furball), the
         * references are restored and the top levels built again with the overspending tasks on reduced
         * budgets; should even that fail (it cannot within the bounds), the serial build. */
        bd->ref_cap = (uint32_t)cap;
        bd->node_cap = (uint32_t)(2u * cap + 2u);
        bd->leaf_cap = (uint32_t)cap;
        bd->par = parallel ? par : NULL;
        top_result_t res = build_top(bd, cfg, &tc, &root, budget, parallel, false, &sah);
        for (int pass = 0; pass < 2 && res != TOP_BUILT; pass++) { /* again from the triangles */
            bd->top = 0;
            bd->node_count = 0;
            bd->leaf_count = 0;
            bd->spatial_splits = 0;
            bd->budget_stops = 0;
            bd->failed = false;
            if (res == TOP_RERUN) {
                bd->ref_cap = (uint32_t)cap;
                bd->node_cap = (uint32_t)(2u * cap + 2u);
                bd->leaf_cap = (uint32_t)cap;
            } else {
                bd->ref_cap = (uint32_t)rb;
                bd->node_cap = (uint32_t)(2u * rb);
                bd->leaf_cap = (uint32_t)rb;
            }
            (void)init_refs(bd, sweep, &root);
            (void)new_node(bd);
            if (res != TOP_RERUN)
                break;
            res = build_top(bd, cfg, &tc, &root, budget, parallel, true, &sah);
            rebuilt = tc.list_count;
        }
        done = res == TOP_BUILT;
        par_mark = m1;
        par_held = true;
    }
    if (!done) {
        uint32_t bud = budget;
        bd->progress = cfg->progress;
        bd->progress_user = cfg->progress_user;
        bd->progress_total = bd->top;
        bd->progress_step = bd->top / 256u + 1u;
        bd->progress_next = bd->progress_step;
        sah = build_node(bd, root_idx, bd->top, &root, 0, &bud);
    }
    bd->par = NULL;
    if (par_held)
        hz_arena_reset(arena, par_mark);
    if (bd->failed) {
        hz_arena_reset(arena, m0);
        return hz_error_set(err, HZ_E_INTERNAL, "accel build: scratch capacity exceeded (a bug: the bounds "
                                                "must hold)");
    }

    /* Counting pass, then the real one into arrays above the scratch. */
    collapse_t c;
    hz_memset(&c, 0, sizeof c);
    c.bd = bd;
    c.g = g;
    bool empty = (nodes[0].n & BLEAF) && (nodes[0].n & ~BLEAF) == 0;
    uint32_t wn = 1, wb = 0;
    if (!empty) {
        collapse_node(&c, 0, 0);
        wn = c.node_count;
        wb = c.block_count;
    }
    if (cfg->progress)
        cfg->progress(cfg->progress_user, 0.9f);
    hz_bvh_node_t *wnodes = hz_arena_alloc_array(arena, wn, sizeof(hz_bvh_node_t), 64);
    hz_bvh_block_t *wblocks = wb ? hz_arena_alloc_array(arena, wb, sizeof(hz_bvh_block_t), 64) : 0;
    out->bytes_peak = hz_arena_mark(arena) - m0;
    if (!wnodes || (wb && !wblocks)) {
        hz_arena_error(arena, err);
        hz_error_prefix(err, "accel build");
        hz_arena_reset(arena, m0);
        return HZ_E_NO_MEMORY;
    }
    hz_memset(&c, 0, sizeof c);
    c.bd = bd;
    c.g = g;
    c.nodes = wnodes;
    c.blocks = wblocks;
    if (empty) {
        box_t e;
        box_empty(&e);
        for (int i = 0; i < HZ_BVH_W; i++) {
            set_child_box(&wnodes[0], i, &e);
            wnodes[0].child[i] = HZ_BVH_EMPTY;
            wnodes[0].pad[i] = 0;
        }
        c.node_count = 1;
        c.depth = 1;
    } else {
        collapse_node(&c, 0, 0);
    }
    out->ref_count = bd->leaf_count;
    out->spatial_splits = bd->spatial_splits;
    out->budget_stops = bd->budget_stops;
    out->tasks_rebuilt = rebuilt;
    out->tri_skipped = skipped;
    float ra = box_area(&root);
    out->sah_cost = ra > 0.0f ? sah / ra : 0.0f;

    /* Move the result down over the scratch (memmove: the regions may overlap) and release the rest. */
    size_t node_bytes = (size_t)wn * sizeof(hz_bvh_node_t);
    size_t block_bytes = (size_t)wb * sizeof(hz_bvh_block_t);
    uint8_t *dst = (uint8_t *)hz_align_up((size_t)(arena->base + m0), 64);
    hz_memmove(dst, wnodes, node_bytes);
    hz_memmove(dst + node_bytes, wblocks ? (const void *)wblocks : (const void *)dst, block_bytes);
    size_t end = (size_t)(dst + node_bytes + block_bytes - arena->base);
    hz_arena_reset(arena, end);
    bvh->nodes = (hz_bvh_node_t *)(void *)dst;
    bvh->blocks = wb ? (hz_bvh_block_t *)(void *)(dst + node_bytes) : 0;
    bvh->node_count = wn;
    bvh->block_count = wb;
    bvh->leaf_count = c.leaf_count;
    bvh->depth = c.depth;
    bvh->has_anyhit = false;
    bvh->time_keys = 0; /* msbvh.c adds the motion arrays */
    bvh->key_boxes = false;
    bvh->blur = cfg->blur;
    bvh->mbox = 0;
    bvh->mref = 0;
    bvh->key_level = 0;
    bvh->key_sets = 0;
    bvh->clipped = 0;
    for (int k = 0; k < HZ_ACCEL_MAX_TIME_KEYS; k++)
        bvh->kblocks[k] = 0;
    if (g->tri_flags)
        for (uint32_t t = 0; t < g->tri_count && !bvh->has_anyhit; t++)
            bvh->has_anyhit = (g->tri_flags[t] & HZ_ACCEL_TRI_ANYHIT) != 0;
    if (cfg->progress)
        cfg->progress(cfg->progress_user, 1.0f);
    return HZ_OK;
}

/* ---- refit ---- */
void hz_bvh_refit(hz_bvh_t *bvh, const hz_accel_geom_t *g)
{
    for (uint32_t b = 0; b < bvh->block_count; b++) {
        hz_bvh_block_t *bl = &bvh->blocks[b];
        for (uint32_t s = 0; s < HZ_BVH_W; s++)
            if (bl->prim[s] != HZ_BVH_PRIM_PAD)
                fill_block_slot(bl, s, g, bl->prim[s] & HZ_BVH_PRIM_MASK);
    }
    for (uint32_t i = bvh->node_count; i-- > 0;) {
        hz_bvh_node_t *w = &bvh->nodes[i];
        for (int c = 0; c < HZ_BVH_W; c++) {
            uint32_t cw = w->child[c];
            box_t b;
            box_empty(&b);
            if (cw == HZ_BVH_EMPTY) {
                /* stays empty */
            } else if (hz_bvh_is_leaf(cw)) {
                uint32_t slot = hz_bvh_leaf_slot(cw), n = hz_bvh_leaf_count(cw);
                const hz_bvh_block_t *bl = &bvh->blocks[slot / HZ_BVH_W];
                for (uint32_t s = slot % HZ_BVH_W; s < slot % HZ_BVH_W + n; s++) {
                    bool point = true; /* all three vertices equal: never hit, adds nothing */
                    for (int k = 0; k < 3; k++)
                        point = point && bl->v[0][k][s] == bl->v[1][k][s] && bl->v[0][k][s] == bl->v[2][k][s];
                    if (!point)
                        for (int v = 0; v < 3; v++)
                            box_grow_pt(&b, bl->v[v][0][s], bl->v[v][1][s], bl->v[v][2][s]);
                }
            } else {
                const hz_bvh_node_t *k = &bvh->nodes[cw];
                for (int j = 0; j < HZ_BVH_W; j++) {
                    box_t kb = { { k->lo_x[j], k->lo_y[j], k->lo_z[j] }, { k->hi_x[j], k->hi_y[j], k->hi_z[j] } };
                    box_grow(&b, &kb);
                }
            }
            set_child_box(w, c, &b);
        }
    }
}
