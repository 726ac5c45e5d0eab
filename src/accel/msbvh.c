/*
 * Motion-blur BVHs (seed 002, Grünschloß, Stich, Nawaz, Keller 2011) over geometry with K = 2, 3, 5 or 9 time
 * keys: the topology comes from bvh_build.c at the midpoint time (MSBVH: SBVH with spatial splits; interpolated
 * BVH: the same builder without them; swept: a binned-SAH BVH over the triangles' boxes united over all keys),
 * then this file adds the triangle copies at every key and the node boxes at every key.
 *
 * MSBVH leaf boxes (paper section 3.1): every reference of a triangle that spatial splits cut into several
 * references (marked in bvh->clipped, a byte per slot) is clipped (Sutherland-Hodgman) against its leaf's
 * midpoint box; the clipped polygon, its vertices as barycentrics, is carried to each key's vertices and its
 * bounds, widened by the margin of the accel.h contract, extend the leaf's box at that key. Boxes then
 * propagate up. Nothing of the polygon is stored: a refit (section 5) cuts each such triangle again, at the
 * previous keys, against the leaf's previous boxes at the first and the last key, and carries that polygon to
 * the new keys. The previous piece lay inside those boxes, so the new piece contains it and the pieces of a
 * triangle cover it at any new motion. References of unsplit triangles are whole triangles: their key boxes are
 * the vertices' exact bounds, as in the interpolated BVH (which, like the swept one, needs no margin: see
 * accel.h).
 *
 * Everything is scalar C with a fixed operation order: a build is bit-identical on every ISA.
 */
#include "bvh.h"

#define COST_NODE 1.0f
#define SAH_BLOCK 4u

typedef struct box {
    float lo[3], hi[3];
} box_t;

static void box_empty(box_t *b)
{
    for (int k = 0; k < 3; k++)
        b->lo[k] = __builtin_inff(), b->hi[k] = -__builtin_inff();
}

static void box_pt(box_t *b, const float *p)
{
    for (int k = 0; k < 3; k++)
        b->lo[k] = hz_minf(b->lo[k], p[k]), b->hi[k] = hz_maxf(b->hi[k], p[k]);
}

static void box_grow(box_t *b, const box_t *o)
{
    for (int k = 0; k < 3; k++)
        b->lo[k] = hz_minf(b->lo[k], o->lo[k]), b->hi[k] = hz_maxf(b->hi[k], o->hi[k]);
}

static bool box_is_empty(const box_t *b)
{
    return !(b->lo[0] <= b->hi[0] && b->lo[1] <= b->hi[1] && b->lo[2] <= b->hi[2]);
}

static float box_area(const box_t *b)
{
    if (box_is_empty(b))
        return 0.0f;
    float dx = b->hi[0] - b->lo[0], dy = b->hi[1] - b->lo[1], dz = b->hi[2] - b->lo[2];
    return 2.0f * (dx * dy + dy * dz + dz * dx);
}

/* The contract's margin for a triangle whose key box is t: 2^-14 of its largest extent plus 2^-18 of its
 * largest absolute coordinate (`extra`: further coordinates that take part, e.g. the clip box). */
static float margin(const box_t *t, float extra)
{
    float e = 0.0f, m = extra;
    for (int k = 0; k < 3; k++) {
        e = hz_maxf(e, t->hi[k] - t->lo[k]);
        m = hz_maxf(m, hz_maxf(hz_absf(t->lo[k]), hz_absf(t->hi[k])));
    }
    return e * (1.0f / 16384.0f) + m * (1.0f / 262144.0f);
}

static void box_node_get(const float *lo_x, uint32_t c, box_t *b)
{
    /* lo_x points at the first of the six arrays of an hz_bvh_node_t or hz_bvh_mbox_t */
    for (int k = 0; k < 3; k++) {
        b->lo[k] = lo_x[(2 * k) * HZ_BVH_W + (int)c];
        b->hi[k] = lo_x[(2 * k + 1) * HZ_BVH_W + (int)c];
    }
}

static void box_node_set(float *lo_x, uint32_t c, const box_t *b)
{
    for (int k = 0; k < 3; k++) {
        lo_x[(2 * k) * HZ_BVH_W + (int)c] = b->lo[k];
        lo_x[(2 * k + 1) * HZ_BVH_W + (int)c] = b->hi[k];
    }
}

/* ---- clipping ---- */
#define POLY_MAX 16 /* a triangle cut by two boxes (12 half-planes) has at most 15 vertices */

typedef struct pvert {
    float b[3]; /* barycentrics (weights of vertices 0, 1, 2) */
    float p[3]; /* position at the clip time */
} pvert_t;

/* Keeps the part of polygon in[0..n) where d(v) <= 0, d given per vertex; returns the new count. */
static int clip_poly(const pvert_t *in, int n, const float *d, pvert_t *out)
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        int j = i + 1 == n ? 0 : i + 1;
        if (d[i] <= 0.0f)
            out[m++] = in[i];
        if ((d[i] < 0.0f && d[j] > 0.0f) || (d[i] > 0.0f && d[j] < 0.0f)) {
            float s = d[i] / (d[i] - d[j]);
            s = hz_clampf(s, 0.0f, 1.0f);
            pvert_t *v = &out[m++];
            for (int k = 0; k < 3; k++) {
                v->b[k] = in[i].b[k] + (in[j].b[k] - in[i].b[k]) * s;
                v->p[k] = in[i].p[k] + (in[j].p[k] - in[i].p[k]) * s;
            }
        }
    }
    return m;
}

/* Cuts polygon a[0..n) to lo[k] <= p[k] <= hi[k] for k = 0..2 (p: the vertices' positions); returns the new
 * count. */
static int clip_to_box(pvert_t *a, int n, const float *lo, const float *hi)
{
    pvert_t b[POLY_MAX];
    for (int plane = 0; plane < 6 && n > 0; plane++) {
        const int k = plane >> 1;
        const bool up = plane & 1;
        float d[POLY_MAX];
        for (int i = 0; i < n; i++) {
            d[i] = up ? a[i].p[k] - hi[k] : lo[k] - a[i].p[k];
        }
        n = clip_poly(a, n, d, b);
        for (int i = 0; i < n; i++)
            a[i] = b[i];
    }
    return n;
}

static void tri_poly(pvert_t *v, const float *const *tv)
{
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) {
            v[i].b[k] = i == k ? 1.0f : 0.0f;
            v[i].p[k] = tv[i][k];
        }
}

static const float *key_vtx(const hz_accel_geom_t *g, const float *pos, uint32_t prim, int i)
{
    return pos + 4u * (size_t)g->tri[3u * (size_t)prim + (uint32_t)i];
}

/* The margin of the contract for the triangle tv[] clipped against box cb: from the triangle's box, and cb's
 * coordinates where finite. */
static float clip_margin(const float *const *tv, const box_t *cb)
{
    box_t tb;
    box_empty(&tb);
    for (int i = 0; i < 3; i++)
        box_pt(&tb, tv[i]);
    float cm = 0.0f;
    for (int k = 0; k < 3; k++)
        cm = hz_maxf(cm, hz_maxf(hz_absf(cb->lo[k]), hz_absf(cb->hi[k])));
    return margin(&tb, hz_isfinitef(cm) ? cm : 0.0f);
}

/* A reference's piece of its triangle: the clipped polygon, its vertices as barycentrics. */
typedef struct poly {
    int n;
    pvert_t v[POLY_MAX];
} poly_t;

/* Cuts pl (its vertices' barycentrics) to box cb widened by the margin, at the triangle's positions tv[]; an
 * empty result (rounding at a touching plane, an empty or non-finite box) leaves pl as it was: conservative. */
static void poly_clip(poly_t *pl, const float *const *tv, const box_t *cb)
{
    const float mg = clip_margin(tv, cb);
    float lo[3], hi[3];
    for (int k = 0; k < 3; k++)
        lo[k] = cb->lo[k] - mg, hi[k] = cb->hi[k] + mg;
    pvert_t a[POLY_MAX];
    for (int i = 0; i < pl->n; i++) {
        a[i] = pl->v[i];
        for (int k = 0; k < 3; k++) /* the same transfer as the key boxes': v0 b0 + v1 b1 + v2 b2 */
            a[i].p[k] = a[i].b[0] * tv[0][k] + a[i].b[1] * tv[1][k] + a[i].b[2] * tv[2][k];
    }
    const int n = clip_to_box(a, pl->n, lo, hi);
    if (n < 3)
        return;
    pl->n = n;
    for (int i = 0; i < n; i++)
        pl->v[i] = a[i];
}

static void poly_whole(poly_t *pl)
{
    const float e0[3] = { 1, 0, 0 }, e1[3] = { 0, 1, 0 }, e2[3] = { 0, 0, 1 };
    const float *tv[3] = { e0, e1, e2 };
    pl->n = 3;
    tri_poly(pl->v, tv);
}

/* The build's piece (paper section 3.1.1): triangle prim at the midpoint positions `mid` clipped
 * (Sutherland-Hodgman) against its leaf's midpoint box cb widened by the margin. */
static void piece_at_build(const hz_accel_geom_t *g, const float *mid, uint32_t prim, const box_t *cb, poly_t *pl)
{
    const float *tv[3] = { key_vtx(g, mid, prim, 0), key_vtx(g, mid, prim, 1), key_vtx(g, mid, prim, 2) };
    poly_whole(pl);
    poly_clip(pl, tv, cb);
}

/* The refit's piece (section 5): the triangle as the previous keys had it (block slot s of kb0 and kb1, the
 * first and last key) clipped against the leaf's boxes at those keys, b0 and b1. The previous piece lay inside
 * both boxes at both keys, so the new one contains it, and the pieces of a triangle still cover it whatever
 * the new keys are. Clipping at both ends of the shutter instead of the paper's closing time alone keeps a
 * refit over unchanged keys close to the build's boxes. */
static void piece_at_refit(const hz_bvh_block_t *kb0, const hz_bvh_block_t *kb1, uint32_t s, const box_t *b0,
                           const box_t *b1, poly_t *pl)
{
    poly_whole(pl);
    const hz_bvh_block_t *kb[2] = { kb0, kb1 };
    const box_t *bb[2] = { b0, b1 };
    for (int e = 0; e < 2; e++) {
        float p[3][3];
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 3; k++)
                p[v][k] = kb[e]->v[v][k][s];
        const float *tv[3] = { p[0], p[1], p[2] };
        poly_clip(pl, tv, bb[e]);
    }
}

/* ---- fitting boxes at the keys ---- */
typedef struct fit {
    const hz_accel_geom_t *g;
    hz_bvh_t *bvh;
    uint32_t keys;
    const float *mid; /* build: the midpoint positions the topology was built on; refit: NULL */
} fit_t;

/* Boxes of block slot `slot` at every key (empty for a slot that never hits); pl: its piece, or NULL for the
 * whole triangle. */
static void slot_boxes(const fit_t *ft, uint32_t slot, const poly_t *pl, box_t *kb)
{
    const hz_bvh_t *bvh = ft->bvh;
    const uint32_t blk = slot / HZ_BVH_W, s = slot % HZ_BVH_W;
    bool point = true; /* the same point at every key: never hit, adds nothing */
    for (uint32_t key = 0; key < ft->keys && point; key++) {
        const hz_bvh_block_t *bl = &bvh->kblocks[key][blk];
        for (int k = 0; k < 3; k++)
            point = point && bl->v[0][k][s] == bl->v[1][k][s] && bl->v[0][k][s] == bl->v[2][k][s] &&
                    bl->v[0][k][s] == bvh->kblocks[0][blk].v[0][k][s];
    }
    for (uint32_t key = 0; key < ft->keys; key++) {
        box_empty(&kb[key]);
        if (point)
            continue;
        const hz_bvh_block_t *bl = &bvh->kblocks[key][blk];
        for (int v = 0; v < 3; v++) {
            const float p[3] = { bl->v[v][0][s], bl->v[v][1][s], bl->v[v][2][s] };
            box_pt(&kb[key], p);
        }
    }
    if (point || !pl)
        return;
    for (uint32_t key = 0; key < ft->keys; key++) {
        const hz_bvh_block_t *bl = &bvh->kblocks[key][blk];
        const box_t tb = kb[key];
        const float mg = margin(&tb, 0.0f);
        box_t pb;
        box_empty(&pb);
        for (int i = 0; i < pl->n; i++) {
            float p[3];
            for (int k = 0; k < 3; k++) /* barycentric transfer to this key */
                p[k] = pl->v[i].b[0] * bl->v[0][k][s] + pl->v[i].b[1] * bl->v[1][k][s] +
                       pl->v[i].b[2] * bl->v[2][k][s];
            box_pt(&pb, p);
        }
        for (int k = 0; k < 3; k++) {
            kb[key].lo[k] = hz_maxf(pb.lo[k] - mg, tb.lo[k] - mg);
            kb[key].hi[k] = hz_minf(pb.hi[k] + mg, tb.hi[k] + mg);
        }
    }
}

/* Triangle copies of block slot (b, s) at every key; a triangle with a non-finite coordinate at some key is
 * zeroed at all keys. */
static void fill_slot(const fit_t *ft, uint32_t b, uint32_t s)
{
    hz_bvh_t *bvh = ft->bvh;
    const uint32_t pw = bvh->kblocks[0][b].prim[s];
    if (pw == HZ_BVH_PRIM_PAD) {
        for (uint32_t key = 1; key < ft->keys; key++)
            bvh->kblocks[key][b].prim[s] = HZ_BVH_PRIM_PAD;
        return;
    }
    bool ok = true;
    for (uint32_t key = 0; key < ft->keys; key++)
        ok = hz_bvh_fill_slot(&bvh->kblocks[key][b], s, ft->g, ft->g->pos_keys[key], pw & HZ_BVH_PRIM_MASK) && ok;
    if (!ok)
        for (uint32_t key = 0; key < ft->keys; key++)
            for (int v = 0; v < 3; v++)
                for (int k = 0; k < 3; k++)
                    bvh->kblocks[key][b].v[v][k][s] = 0.0f;
}

/* ---- node boxes at the keys, every key or per-node segments ---- */
#define SEG_AREA_SLACK (1.0 / 32.0)  /* a coarser level may add this much to the children's key-box areas */
#define SEG_MARGIN (1.0 / 131072.0)  /* 2^-17 of the node's largest coordinate (hz/accel.h, "Motion segments") */

static uint32_t node_level(const hz_bvh_t *bvh, uint32_t i)
{
    return bvh->mref ? bvh->mref[i] & 3u : bvh->key_level;
}

/* Node i's q-th box set (of its own keys). */
static float *node_set(const hz_bvh_t *bvh, uint32_t i, uint32_t q)
{
    const size_t o = bvh->mref ? (size_t)(bvh->mref[i] >> 2) : (size_t)i * bvh->time_keys;
    return bvh->mbox[o + q].lo_x;
}

/* Child c of node i's box at key `key` (0..K-1) as the node keeps it: one of its own keys, or the lerp of the two
 * around it with a dyadic weight (an empty box, +-FLT_MAX at both, stays exactly that). */
static void stored_box(const hz_bvh_t *bvh, uint32_t i, uint32_t c, uint32_t key, box_t *b)
{
    const uint32_t sh = bvh->key_level - node_level(bvh, i), q = key >> sh, r = key & ((1u << sh) - 1u);
    box_node_get(node_set(bvh, i, q), c, b);
    if (!r)
        return;
    box_t e;
    box_node_get(node_set(bvh, i, q + 1u), c, &e);
    const float f = (float)r / (float)(1u << sh);
    for (int k = 0; k < 3; k++) {
        b->lo[k] = hz_accel_lerp_key(b->lo[k], e.lo[k], f);
        b->hi[k] = hz_accel_lerp_key(b->hi[k], e.hi[k], f);
    }
}

static float to_float_sat(double x)
{
    return x < -(double)FLT_MAX ? -FLT_MAX : x > (double)FLT_MAX ? FLT_MAX : (float)x;
}

/* The bounds at level m of one child's boxes kb[0..K) (K = 2^M + 1): per segment of 2^(M - m) keys the line
 * through its end keys moved down (lo) or up (hi) until it passes below (above) every key inside, each coarse key
 * the lower (higher) of its two segments' ends, then `delta` further out; out[0..2^m]. In doubles: the floats
 * written err by far less than delta. */
static void coarse_fit(const box_t *kb, uint32_t m, uint32_t M, double delta, box_t *out)
{
    const uint32_t s = 1u << (M - m), n = 1u << m;
    double lo[HZ_ACCEL_MAX_TIME_KEYS][3], hi[HZ_ACCEL_MAX_TIME_KEYS][3];
    for (uint32_t q = 0; q <= n; q++)
        for (int k = 0; k < 3; k++)
            lo[q][k] = __builtin_inf(), hi[q][k] = -__builtin_inf();
    for (uint32_t c = 0; c < n; c++) {
        const uint32_t a = c * s, b = a + s;
        for (int k = 0; k < 3; k++) {
            const double la = kb[a].lo[k], lb = kb[b].lo[k], ha = kb[a].hi[k], hb = kb[b].hi[k];
            double vl = 0.0, vh = 0.0;
            for (uint32_t j = a + 1u; j < b; j++) {
                const double w = (double)(j - a) / (double)s;
                const double l = la + (lb - la) * w, h = ha + (hb - ha) * w;
                if (l - (double)kb[j].lo[k] > vl)
                    vl = l - (double)kb[j].lo[k];
                if ((double)kb[j].hi[k] - h > vh)
                    vh = (double)kb[j].hi[k] - h;
            }
            lo[c][k] = la - vl < lo[c][k] ? la - vl : lo[c][k];
            lo[c + 1u][k] = lb - vl < lo[c + 1u][k] ? lb - vl : lo[c + 1u][k];
            hi[c][k] = ha + vh > hi[c][k] ? ha + vh : hi[c][k];
            hi[c + 1u][k] = hb + vh > hi[c + 1u][k] ? hb + vh : hi[c + 1u][k];
        }
    }
    for (uint32_t q = 0; q <= n; q++)
        for (int k = 0; k < 3; k++) {
            out[q].lo[k] = to_float_sat(lo[q][k] - delta);
            out[q].hi[k] = to_float_sat(hi[q][k] + delta);
        }
}

/* Summed areas at every key of the level-m bounds out[0..2^m] (lerped in doubles). */
static double coarse_area(const box_t *out, uint32_t m, uint32_t M)
{
    const uint32_t s = 1u << (M - m), K = (1u << M) + 1u;
    double sum = 0.0;
    for (uint32_t j = 0; j < K; j++) {
        const uint32_t q = j / s < (1u << m) ? j / s : (1u << m) - 1u;
        const double w = (double)(j - q * s) / (double)s;
        double d[3];
        for (int k = 0; k < 3; k++)
            d[k] = (out[q].hi[k] + ((double)out[q + 1u].hi[k] - out[q].hi[k]) * w) -
                   (out[q].lo[k] + ((double)out[q + 1u].lo[k] - out[q].lo[k]) * w);
        sum += 2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
    }
    return sum;
}

/* Node i's child boxes at its keys from the children's boxes at every key, kb[c][0..K), under per-node segments:
 * a build picks the node's level (the lowest whose bounds add at most SEG_AREA_SLACK to the children's summed
 * key-box areas), a refit keeps it. A child empty at some keys only (no geometry makes one today) is taken at
 * those keys as the union of its other keys' boxes: larger, so still a bound, and linear where it is needed. */
static void set_segments(const fit_t *ft, uint32_t i, box_t (*kb)[HZ_ACCEL_MAX_TIME_KEYS])
{
    hz_bvh_t *bvh = ft->bvh;
    const uint32_t M = bvh->key_level, K = ft->keys;
    double big = 0.0, fine = 0.0;
    bool used[HZ_BVH_W];
    for (uint32_t c = 0; c < HZ_BVH_W; c++) {
        box_t u;
        box_empty(&u);
        for (uint32_t key = 0; key < K; key++)
            if (!box_is_empty(&kb[c][key]))
                box_grow(&u, &kb[c][key]);
        used[c] = !box_is_empty(&u);
        if (!used[c])
            continue;
        for (uint32_t key = 0; key < K; key++) {
            box_t *b = &kb[c][key];
            if (box_is_empty(b))
                *b = u;
            fine += box_area(b);
            for (int k = 0; k < 3; k++) {
                big = hz_absf(b->lo[k]) > big ? hz_absf(b->lo[k]) : big;
                big = hz_absf(b->hi[k]) > big ? hz_absf(b->hi[k]) : big;
            }
        }
    }
    const double delta = big * SEG_MARGIN;
    box_t out[HZ_BVH_W][HZ_ACCEL_MAX_TIME_KEYS];
    uint32_t m = node_level(bvh, i);
    bool fitted = false; /* out[] already holds level m's bounds */
    if (ft->mid) {
        for (m = 0; m < M; m++) {
            double area = 0.0;
            for (uint32_t c = 0; c < HZ_BVH_W; c++)
                if (used[c]) {
                    coarse_fit(kb[c], m, M, delta, out[c]);
                    area += coarse_area(out[c], m, M);
                }
            fitted = area <= fine * (1.0 + SEG_AREA_SLACK);
            if (fitted)
                break;
        }
        bvh->mref[i] = (bvh->mref[i] & ~3u) | m;
    }
    for (uint32_t c = 0; c < HZ_BVH_W; c++) {
        if (!used[c]) /* empty at every key: +-FLT_MAX, not +-inf, so that the lerp (0 * inf = NaN) stays empty */
            for (uint32_t q = 0; q <= (1u << m); q++)
                for (int k = 0; k < 3; k++)
                    out[c][q].lo[k] = FLT_MAX, out[c][q].hi[k] = -FLT_MAX;
        else if (!fitted)
            coarse_fit(kb[c], m, M, delta, out[c]);
        for (uint32_t q = 0; q <= (1u << m); q++)
            box_node_set(node_set(bvh, i, q), c, &out[c][q]);
    }
}

/* Boxes of leaf `cw` (child c of node i) at every key. A build has filled the slots already; a refit fills each
 * slot from g's keys after its piece has been cut from the previous keys and boxes. */
static void leaf_boxes(const fit_t *ft, uint32_t i, uint32_t c, uint32_t cw, box_t *kb)
{
    hz_bvh_t *bvh = ft->bvh;
    const uint32_t K = ft->keys;
    box_t cb0, cb1; /* what pieces are cut against: build, the midpoint box; refit, the first and last keys' */
    if (bvh->clipped && ft->mid) {
        box_node_get(bvh->nodes[i].lo_x, c, &cb0);
    } else if (bvh->clipped) {
        stored_box(bvh, i, c, 0, &cb0);
        stored_box(bvh, i, c, K - 1u, &cb1);
    }
    const uint32_t slot = hz_bvh_leaf_slot(cw), n = hz_bvh_leaf_count(cw);
    for (uint32_t sl = slot; sl < slot + n; sl++) {
        const uint32_t b = sl / HZ_BVH_W, s = sl % HZ_BVH_W;
        const bool cut = bvh->clipped && bvh->clipped[sl];
        poly_t pl;
        if (cut && ft->mid)
            piece_at_build(ft->g, ft->mid, bvh->kblocks[0][b].prim[s] & HZ_BVH_PRIM_MASK, &cb0, &pl);
        else if (cut)
            piece_at_refit(&bvh->kblocks[0][b], &bvh->kblocks[K - 1u][b], s, &cb0, &cb1, &pl);
        if (!ft->mid)
            fill_slot(ft, b, s);
        box_t sb[HZ_ACCEL_MAX_TIME_KEYS];
        slot_boxes(ft, sl, cut ? &pl : NULL, sb);
        for (uint32_t key = 0; key < K; key++)
            box_grow(&kb[key], &sb[key]);
    }
}

/* Child boxes at every key, leaves from their slots, inner nodes from their children (reverse pre-order: a
 * child's boxes are final before its parent reads them), then stored at every key or at the node's segments.
 * Without key boxes (swept) the nodes' own boxes get the union over the keys. */
static void fit_boxes(const fit_t *ft)
{
    hz_bvh_t *bvh = ft->bvh;
    const uint32_t K = ft->keys;
    for (uint32_t i = bvh->node_count; i-- > 0;) {
        hz_bvh_node_t *w = &bvh->nodes[i];
        box_t kb[HZ_BVH_W][HZ_ACCEL_MAX_TIME_KEYS];
        for (uint32_t c = 0; c < HZ_BVH_W; c++) {
            const uint32_t cw = w->child[c];
            for (uint32_t key = 0; key < K; key++)
                box_empty(&kb[c][key]);
            if (cw == HZ_BVH_EMPTY) {
                /* stays empty */
            } else if (hz_bvh_is_leaf(cw)) {
                leaf_boxes(ft, i, c, cw, kb[c]);
            } else {
                for (uint32_t key = 0; key < K; key++)
                    for (uint32_t j = 0; j < HZ_BVH_W; j++) {
                        box_t b;
                        if (bvh->key_boxes)
                            stored_box(bvh, cw, j, key, &b);
                        else
                            box_node_get(bvh->nodes[cw].lo_x, j, &b);
                        box_grow(&kb[c][key], &b);
                    }
            }
        }
        if (bvh->key_boxes && bvh->mref)
            set_segments(ft, i, kb);
        for (uint32_t c = 0; c < HZ_BVH_W; c++) {
            box_t all;
            box_empty(&all);
            for (uint32_t key = 0; key < K; key++) {
                box_grow(&all, &kb[c][key]);
                if (bvh->key_boxes && !bvh->mref) {
                    /* empty: +-FLT_MAX, not +-inf, so that the lerp (0 * inf = NaN) stays an empty box */
                    box_t e = kb[c][key];
                    if (box_is_empty(&e))
                        for (int k = 0; k < 3; k++)
                            e.lo[k] = FLT_MAX, e.hi[k] = -FLT_MAX;
                    box_node_set(node_set(bvh, i, key), c, &e);
                }
            }
            box_node_set(w->lo_x, c, &all);
        }
    }
}

/* Triangle copies at every key (a build's; a refit fills each slot in leaf_boxes). */
static void fill_keys(const fit_t *ft)
{
    for (uint32_t b = 0; b < ft->bvh->block_count; b++)
        for (uint32_t s = 0; s < HZ_BVH_W; s++)
            fill_slot(ft, b, s);
}

/* ---- SAH of the wide tree ---- */
static float child_area(const hz_bvh_t *bvh, uint32_t node, uint32_t c)
{
    box_t b;
    if (!bvh->key_boxes) {
        box_node_get(bvh->nodes[node].lo_x, c, &b);
        return box_area(&b);
    }
    float sum = 0.0f;
    for (uint32_t key = 0; key < bvh->time_keys; key++) {
        stored_box(bvh, node, c, key, &b);
        sum += box_area(&b);
    }
    return sum / (float)bvh->time_keys;
}

float hz_bvh_wide_sah(const hz_bvh_t *bvh)
{
    /* root area: of the union of node 0's children, averaged over keys */
    float root = 0.0f;
    const uint32_t nk = bvh->key_boxes ? bvh->time_keys : 1u;
    for (uint32_t key = 0; key < nk; key++) {
        box_t r, b;
        box_empty(&r);
        for (uint32_t c = 0; c < HZ_BVH_W; c++) {
            if (bvh->key_boxes)
                stored_box(bvh, 0, c, key, &b);
            else
                box_node_get(bvh->nodes[0].lo_x, c, &b);
            box_grow(&r, &b);
        }
        root += box_area(&r);
    }
    root /= (float)nk;
    if (!(root > 0.0f))
        return 0.0f;
    double cost = (double)root * COST_NODE;
    for (uint32_t i = 0; i < bvh->node_count; i++)
        for (uint32_t c = 0; c < HZ_BVH_W; c++) {
            const uint32_t cw = bvh->nodes[i].child[c];
            if (cw == HZ_BVH_EMPTY)
                continue;
            const float a = child_area(bvh, i, c);
            if (hz_bvh_is_leaf(cw))
                cost += (double)a * (double)((hz_bvh_leaf_count(cw) + SAH_BLOCK - 1u) / SAH_BLOCK);
            else
                cost += (double)a * COST_NODE;
        }
    return (float)(cost / (double)root);
}

/* ---- memory ---- */
uint64_t hz_bvh_motion_kept_bound(uint64_t refs, uint32_t keys, hz_accel_blur_t blur, uint32_t vertex_count)
{
    (void)vertex_count;
    if (keys < 2u)
        return 0;
    const uint64_t nodes = hz_bvh_nodes_bound(refs), blocks = hz_bvh_blocks_bound(refs);
    uint64_t b = (uint64_t)(keys - 1u) * blocks * sizeof(hz_bvh_block_t) + 8u * 64u;
    if (blur != HZ_ACCEL_BLUR_SWEPT)
        b += nodes * keys * sizeof(hz_bvh_mbox_t) + nodes * sizeof(uint32_t) + 16u; /* + per-node segments */
    if (blur == HZ_ACCEL_BLUR_MSBVH)
        b += blocks * HZ_BVH_W; /* a byte per slot: clipped or whole */
    return b;
}

void hz_bvh_relocate(hz_bvh_t *bvh, ptrdiff_t delta)
{
#define MOVE(p) ((p) = (p) ? (void *)((uint8_t *)(void *)(p) + delta) : (p))
    MOVE(bvh->nodes);
    MOVE(bvh->blocks);
    MOVE(bvh->mbox);
    MOVE(bvh->mref);
    MOVE(bvh->clipped);
    for (int k = 0; k < HZ_ACCEL_MAX_TIME_KEYS; k++)
        MOVE(bvh->kblocks[k]);
#undef MOVE
}

/* ---- build and refit ---- */
static bool keys_valid(uint32_t k)
{
    return k == 2u || k == 3u || k == 5u || k == 9u;
}

hz_status_t hz_bvh_motion_build(hz_bvh_t *bvh, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                                hz_arena_t *arena, hz_bvh_build_out_t *out, hz_error_t *err)
{
    const uint32_t K = g->time_keys;
    if (!keys_valid(K))
        return hz_error_set(err, HZ_E_RANGE, "accel: %u time keys, supported: 2, 3, 5 or 9", K);
    if ((unsigned)cfg->blur >= HZ_ACCEL_BLUR_COUNT)
        return hz_error_set(err, HZ_E_INVALID_ARG, "accel: unknown motion BVH %d", (int)cfg->blur);
    const hz_arena_mark_t m0 = hz_arena_mark(arena);
    /* topology at time 0.5: key (K - 1) / 2 for odd K, the lerp of keys 0 and 1 for K = 2 */
    const float *mid = g->pos_keys[(K - 1u) / 2u];
    if (K == 2u) {
        float *m = hz_arena_alloc_array(arena, (size_t)g->vertex_count * 4u + 4u, sizeof(float), 64);
        if (!m) {
            hz_arena_error(arena, err);
            hz_error_prefix(err, "accel: motion midpoint positions");
            return HZ_E_NO_MEMORY;
        }
        for (size_t i = 0; i < (size_t)g->vertex_count * 4u; i++)
            m[i] = hz_accel_lerp_key(g->pos_keys[0][i], g->pos_keys[1][i], 0.5f);
        mid = m;
    }
    const size_t mid_bytes = hz_arena_mark(arena) - m0;
    hz_accel_geom_t gm = *g;
    gm.pos = mid;
    hz_accel_config_t c2 = *cfg;
    if (cfg->blur != HZ_ACCEL_BLUR_MSBVH)
        c2.spatial_splits = false;
    hz_status_t s = hz_bvh_build(bvh, &gm, &c2, arena, out, err);
    if (s != HZ_OK) {
        hz_arena_reset(arena, m0);
        return s;
    }
    out->bytes_peak += mid_bytes;
    const uint32_t alias = K & 1u ? (K - 1u) / 2u : 0u; /* the key whose copies live in bvh->blocks */
    bvh->time_keys = K;
    bvh->blur = cfg->blur;
    bvh->key_boxes = cfg->blur != HZ_ACCEL_BLUR_SWEPT;
    const size_t nb = bvh->block_count ? bvh->block_count : 1u;
    bool ok = true;
    for (uint32_t k = 0; k < K; k++) {
        if (k == alias) {
            bvh->kblocks[k] = bvh->blocks;
            continue;
        }
        bvh->kblocks[k] = hz_arena_alloc_array(arena, nb, sizeof(hz_bvh_block_t), 64);
        ok = ok && bvh->kblocks[k];
    }
    if (!bvh->blocks) { /* empty geometry: one padding block per key keeps the kernels' reads valid */
        for (uint32_t k = 0; k < K && ok; k++)
            if (!bvh->kblocks[k]) {
                bvh->kblocks[k] = hz_arena_alloc_array(arena, 1, sizeof(hz_bvh_block_t), 64);
                ok = bvh->kblocks[k] != 0;
            }
    }
    /* per-node segments: with K >= 3, and offsets that fit mref's 30 bits */
    const bool per_node = bvh->key_boxes && K >= 3u && cfg->segments == HZ_ACCEL_SEGMENTS_PER_NODE &&
                          (uint64_t)bvh->node_count * K < (1u << 30);
    bvh->key_level = K == 9u ? 3u : K == 5u ? 2u : K == 3u ? 1u : 0u;
    if (ok && per_node) {
        bvh->mref = hz_arena_alloc_array(arena, bvh->node_count ? bvh->node_count : 1u, sizeof(uint32_t), 16);
        ok = bvh->mref != 0;
    }
    if (ok && cfg->blur == HZ_ACCEL_BLUR_MSBVH && bvh->block_count) {
        bvh->clipped = hz_arena_alloc_array(arena, (size_t)bvh->block_count * HZ_BVH_W, 1, 16);
        ok = bvh->clipped != 0;
    }
    if (ok && bvh->key_boxes) { /* last: per-node segments give its tail back */
        bvh->mbox = hz_arena_alloc_array(arena, (size_t)bvh->node_count * K, sizeof(hz_bvh_mbox_t), 64);
        ok = bvh->mbox != 0;
    }
    const hz_arena_mark_t m2 = hz_arena_mark(arena);
    uint8_t *refs = ok && bvh->clipped ? hz_arena_calloc(arena, g->tri_count ? g->tri_count : 1u, 1, 16) : 0;
    if (!ok || (bvh->clipped && !refs)) {
        hz_arena_error(arena, err);
        hz_error_prefix(err, "accel: motion boxes");
        hz_arena_reset(arena, m0);
        return HZ_E_NO_MEMORY;
    }
    for (uint32_t k = 0; k < K; k++)
        if (k != alias || !bvh->blocks)
            for (size_t b = 0; b < nb; b++) {
                hz_memset(&bvh->kblocks[k][b], 0, sizeof(hz_bvh_block_t));
                for (int i = 0; i < HZ_BVH_W; i++)
                    bvh->kblocks[k][b].prim[i] = bvh->blocks ? bvh->blocks[b].prim[i] : HZ_BVH_PRIM_PAD;
            }
    if (bvh->clipped) {
        /* clipped: the references of triangles that spatial splits put in several leaves */
        const uint32_t nslots = bvh->block_count * HZ_BVH_W;
        for (uint32_t sl = 0; sl < nslots; sl++) {
            const uint32_t pw = bvh->blocks[sl / HZ_BVH_W].prim[sl % HZ_BVH_W];
            if (pw != HZ_BVH_PRIM_PAD && refs[pw & HZ_BVH_PRIM_MASK] < 2u)
                refs[pw & HZ_BVH_PRIM_MASK]++;
        }
        for (uint32_t sl = 0; sl < nslots; sl++) {
            const uint32_t pw = bvh->blocks[sl / HZ_BVH_W].prim[sl % HZ_BVH_W];
            bvh->clipped[sl] = pw != HZ_BVH_PRIM_PAD && refs[pw & HZ_BVH_PRIM_MASK] >= 2u;
        }
    }
    if (hz_arena_mark(arena) - m0 > out->bytes_peak)
        out->bytes_peak = hz_arena_mark(arena) - m0;
    hz_arena_reset(arena, m2); /* the reference counts */
    fit_t ft = { g, bvh, K, mid };
    fill_keys(&ft);
    if (bvh->mref)
        for (uint32_t i = 0; i < bvh->node_count; i++)
            bvh->mref[i] = (i * K) << 2 | bvh->key_level;
    fit_boxes(&ft);
    bvh->key_sets = bvh->key_boxes ? (uint64_t)bvh->node_count * K : 0u;
    if (bvh->mref) {
        /* each node's sets moved down next to the previous node's (offsets only shrink: in order, in place) */
        uint64_t o = 0;
        for (uint32_t i = 0; i < bvh->node_count; i++) {
            const uint32_t m = bvh->mref[i] & 3u, n = (1u << m) + 1u;
            hz_memmove(&bvh->mbox[o], &bvh->mbox[(size_t)i * K], n * sizeof(hz_bvh_mbox_t));
            bvh->mref[i] = (uint32_t)o << 2 | m;
            o += n;
        }
        bvh->key_sets = o;
        hz_arena_reset(arena, (size_t)((uint8_t *)(void *)(bvh->mbox + o) - arena->base));
    }
    /* K = 2: move the structure down over the midpoint positions */
    if (K == 2u) {
        uint8_t *src = (uint8_t *)(void *)bvh->nodes;
        uint8_t *dst = (uint8_t *)hz_align_up((size_t)(arena->base + m0), 64);
        const size_t end = hz_arena_mark(arena);
        const size_t bytes = (size_t)(arena->base + end - src);
        hz_memmove(dst, src, bytes);
        hz_bvh_relocate(bvh, dst - src);
        hz_arena_reset(arena, (size_t)(dst + bytes - arena->base));
    }
    out->sah_cost = hz_bvh_wide_sah(bvh);
    return HZ_OK;
}

void hz_bvh_motion_refit(hz_bvh_t *bvh, const hz_accel_geom_t *g)
{
    fit_t ft = { g, bvh, bvh->time_keys, NULL };
    fit_boxes(&ft);
}
