/*
 * Rigid instances (seed 002 section 3.2): objects that move rigidly keep a static BVH in object space, built
 * once; a ray meets one at its own time through the instance's matrix, each element interpolated between the
 * frame's keys. The other triangles keep the motion BVH (see instance.h).
 */
#include "instance.h"

#include "bvh.h"

/* Packets seen as arrays of w words per field (hz_rayhit_t is the case w = 1): the ray's 12 fields, then the
 * hit's 8 (the layouts of hz/accel.h). */
enum { R_OX, R_OY, R_OZ, R_TNEAR, R_DX, R_DY, R_DZ, R_TIME, R_TFAR, R_MASK, R_ID, R_FLAGS, R_FIELDS };
enum { H_NGX = R_FIELDS, H_NGY, H_NGZ, H_U, H_V, H_PRIM, H_GEOM, H_INST, RH_FIELDS };

/* Rays an instance pass moves into object space at once: 8 packets of 8, 16 of 4 or 64 single rays. */
#define CHUNK_RAYS 64

/* The trees; the instances' triangle ranges and matrices stay in the view (a->geom.instances). */
typedef struct comp {
    hz_accel_t *rest; /* the triangles outside instances; NULL when there are none */
    uint32_t n;
    hz_accel_t *blas[HZ_ACCEL_MAX_INSTANCES]; /* static, object space */
} comp_t;

bool hz_inst_used(const hz_accel_geom_t *g, const hz_accel_config_t *cfg)
{
    return g && g->instance_count && g->time_keys >= 2u && (!cfg || cfg->rigid == HZ_ACCEL_RIGID_INSTANCE);
}

/* ---- the transform ---- */
bool hz_inst_xform(const hz_accel_instance_t *in, uint32_t keys, float time, hz_inst_xf_t *xf)
{
    uint32_t s;
    float f, m[12];
    hz_accel_time_segment(time, keys, &s, &f);
    const float *a = in->xform[s], *b = in->xform[s + 1u];
    for (int i = 0; i < 12; i++)
        m[i] = hz_accel_lerp_key(a[i], b[i], f);
    const float a0 = m[0], a1 = m[1], a2 = m[2], a3 = m[4], a4 = m[5], a5 = m[6], a6 = m[8], a7 = m[9], a8 = m[10];
    float *j = xf->adj;
    j[0] = a4 * a8 - a5 * a7, j[1] = a2 * a7 - a1 * a8, j[2] = a1 * a5 - a2 * a4;
    j[3] = a5 * a6 - a3 * a8, j[4] = a0 * a8 - a2 * a6, j[5] = a2 * a3 - a0 * a5;
    j[6] = a3 * a7 - a4 * a6, j[7] = a1 * a6 - a0 * a7, j[8] = a0 * a4 - a1 * a3;
    xf->det = a0 * j[0] + a1 * j[3] + a2 * j[6];
    xf->b[0] = m[3], xf->b[1] = m[7], xf->b[2] = m[11];
    if (!(hz_absf(xf->det) > 0.0f) || !hz_isfinitef(xf->det))
        return false;
    const float r = 1.0f / xf->det;
    bool ok = hz_isfinitef(r);
    for (int i = 0; i < 9; i++) {
        xf->inv[i] = j[i] * r;
        ok = ok && hz_isfinitef(xf->inv[i]);
    }
    return ok && hz_isfinitef(xf->b[0]) && hz_isfinitef(xf->b[1]) && hz_isfinitef(xf->b[2]);
}

bool hz_inst_ray_in(const hz_inst_xf_t *xf, const float org[3], const float dir[3], float oo[3], float od[3])
{
    const float *v = xf->inv;
    const float p0 = org[0] - xf->b[0], p1 = org[1] - xf->b[1], p2 = org[2] - xf->b[2];
    bool ok = true;
    for (int r = 0; r < 3; r++) {
        oo[r] = v[3 * r] * p0 + v[3 * r + 1] * p1 + v[3 * r + 2] * p2;
        od[r] = v[3 * r] * dir[0] + v[3 * r + 1] * dir[1] + v[3 * r + 2] * dir[2];
        ok = ok && hz_isfinitef(oo[r]) && hz_isfinitef(od[r]);
    }
    return ok && (od[0] != 0.0f || od[1] != 0.0f || od[2] != 0.0f);
}

void hz_inst_normal_out(const hz_inst_xf_t *xf, float ng[3])
{
    /* the cofactor matrix det * A^-T is the adjugate's transpose: (A e1) x (A e2) = cof(A) (e1 x e2) */
    const float *j = xf->adj;
    const float x = ng[0], y = ng[1], z = ng[2];
    ng[0] = j[0] * x + j[3] * y + j[6] * z;
    ng[1] = j[1] * x + j[4] * y + j[7] * z;
    ng[2] = j[2] * x + j[5] * y + j[8] * z;
}

/* ---- queries ---- */
/* The caller's any-hit callback, reached through an instance: its triangle index and the world-space side. */
typedef struct tramp {
    hz_accel_anyhit_fn fn;
    void *user;
    uint32_t base;
    uint8_t flip[8]; /* by lane: the instance's matrix mirrors (det < 0), so the object-space side is the other */
} tramp_t;

static bool tramp_anyhit(void *user, uint32_t prim, float u, float v, float t, uint32_t ray_id, int lane,
                         unsigned back)
{
    const tramp_t *tr = user;
    return tr->fn(tr->user, prim + tr->base, u, v, t, ray_id, lane, back ^ tr->flip[(unsigned)lane & 7u]);
}

/* n packets of w lanes (w = 1: single rays) at `pk`, `hit`: with hit records (closest hit) or rays only. */
typedef struct batch {
    const int32_t *valid;
    float *pk;
    int w;
    uint32_t n;
    bool hit;
} batch_t;

HZ_INLINE size_t batch_stride(const batch_t *b)
{
    return (size_t)(b->hit ? RH_FIELDS : R_FIELDS) * (size_t)b->w;
}

HZ_INLINE float *word(const batch_t *b, uint32_t p, int f, int l)
{
    return b->pk + (size_t)p * batch_stride(b) + (size_t)f * (size_t)b->w + (size_t)l;
}

static void sub_query(const hz_accel_t *s, hz_accel_ctx_t *ctx, const batch_t *b)
{
    if (b->w == 1) {
        for (uint32_t p = 0; p < b->n; p++)
            if (b->valid[p]) {
                if (b->hit)
                    s->ops->intersect1(s, ctx, (hz_rayhit_t *)(void *)word(b, p, 0, 0));
                else
                    s->ops->occluded1(s, ctx, (hz_ray_t *)(void *)word(b, p, 0, 0));
            }
    } else if (b->w == 4) {
        if (b->hit)
            hz_accel_intersect4n(b->valid, s, ctx, (hz_rayhit4_t *)(void *)b->pk, b->n);
        else
            hz_accel_occluded4n(b->valid, s, ctx, (hz_ray4_t *)(void *)b->pk, b->n);
    } else {
        if (b->hit)
            hz_accel_intersect8n(b->valid, s, ctx, (hz_rayhit8_t *)(void *)b->pk, b->n);
        else
            hz_accel_occluded8n(b->valid, s, ctx, (hz_ray8_t *)(void *)b->pk, b->n);
    }
}

/* An instance pass's counts (its rays were counted by the first pass over them). */
static void stats_add(hz_accel_stats_t *to, const hz_accel_stats_t *from)
{
    if (!to)
        return;
    to->nodes += from->nodes;
    to->tris += from->tris;
    to->anyhit_calls += from->anyhit_calls;
    to->ray_nodes_max = to->ray_nodes_max > from->ray_nodes_max ? to->ray_nodes_max : from->ray_nodes_max;
    to->ray_tris_max = to->ray_tris_max > from->ray_tris_max ? to->ray_tris_max : from->ray_tris_max;
}

/* One instance over packets [p0, p0 + n) of b (at most CHUNK_RAYS rays): the active lanes move into object
 * space, go through the instance's BVH in one call (or packet by packet where their sides differ), and the
 * closer hits (or the occlusions) come back. */
static void inst_chunk(const hz_accel_t *a, const hz_accel_t *blas, const hz_accel_instance_t *gi,
                       hz_accel_ctx_t *ctx, const batch_t *b, uint32_t p0, uint32_t n)
{
    HZ_ALIGNED(32) float buf[CHUNK_RAYS * RH_FIELDS];
    HZ_ALIGNED(32) int32_t valid[CHUNK_RAYS];
    float adj[CHUNK_RAYS][9];
    uint8_t neg[CHUNK_RAYS];
    const int w = b->w;
    batch_t t = { valid, buf, w, n, b->hit };
    uint32_t active = 0, negs = 0;
    for (uint32_t p = 0; p < n; p++)
        for (int l = 0; l < w; l++) {
            const uint32_t L = p * (uint32_t)w + (uint32_t)l;
            for (int f = 0; f < R_FIELDS; f++)
                *word(&t, p, f, l) = *word(b, p0 + p, f, l);
            valid[L] = 0;
            if (!b->valid[(size_t)(p0 + p) * (size_t)w + (size_t)l] || !(*word(b, p0 + p, R_TFAR, l) >= 0.0f))
                continue; /* inactive, or already occluded (tfar = -inf) */
            hz_inst_xf_t xf;
            const float org[3] = { *word(b, p0 + p, R_OX, l), *word(b, p0 + p, R_OY, l), *word(b, p0 + p, R_OZ, l) };
            const float dir[3] = { *word(b, p0 + p, R_DX, l), *word(b, p0 + p, R_DY, l), *word(b, p0 + p, R_DZ, l) };
            float oo[3], od[3];
            if (!hz_inst_xform(gi, a->geom.time_keys, *word(b, p0 + p, R_TIME, l), &xf) ||
                !hz_inst_ray_in(&xf, org, dir, oo, od))
                continue;
            for (int c = 0; c < 3; c++)
                *word(&t, p, R_OX + c, l) = oo[c], *word(&t, p, R_DX + c, l) = od[c];
            if (b->hit)
                ((uint32_t *)(void *)word(&t, p, H_PRIM, l))[0] = HZ_ACCEL_INVALID_ID;
            for (int c = 0; c < 9; c++)
                adj[L][c] = xf.adj[c];
            neg[L] = xf.det < 0.0f;
            negs += neg[L];
            valid[L] = -1;
            active++;
        }
    if (!active)
        return;
    hz_accel_stats_t st;
    hz_memset(&st, 0, sizeof st);
    hz_accel_ctx_t c2 = *ctx;
    c2.stats = ctx->stats ? &st : 0;
    tramp_t tr;
    if (ctx->anyhit) {
        tr.fn = ctx->anyhit, tr.user = ctx->user, tr.base = gi->tri_first;
        c2.anyhit = tramp_anyhit, c2.user = &tr;
    }
    if (!ctx->anyhit || negs == 0 || negs == active) {
        for (int l = 0; l < 8; l++) /* one side for every lane: one call */
            tr.flip[l] = negs != 0;
        sub_query(blas, &c2, &t);
    } else {
        /* the callback tells lanes apart within a packet only: packet by packet (a single ray is a packet of 1) */
        for (uint32_t p = 0; p < n; p++) {
            batch_t one = { valid + p * (uint32_t)w, word(&t, p, 0, 0), w, 1, b->hit };
            for (int l = 0; l < w; l++)
                tr.flip[l] = neg[p * (uint32_t)w + (uint32_t)l];
            sub_query(blas, &c2, &one);
        }
    }
    stats_add(ctx->stats, &st);
    for (uint32_t p = 0; p < n; p++)
        for (int l = 0; l < w; l++) {
            const uint32_t L = p * (uint32_t)w + (uint32_t)l;
            if (!valid[L])
                continue;
            float *wt = word(b, p0 + p, R_TFAR, l);
            const float tt = *word(&t, p, R_TFAR, l);
            if (!b->hit) {
                if (tt < 0.0f)
                    *wt = tt; /* -inf: occluded */
                continue;
            }
            const uint32_t prim = ((const uint32_t *)(const void *)word(&t, p, H_PRIM, l))[0];
            if (prim == HZ_ACCEL_INVALID_ID)
                continue;
            uint32_t *wprim = (uint32_t *)(void *)word(b, p0 + p, H_PRIM, l);
            const uint32_t gp = prim + gi->tri_first;
            /* a hit of the other triangles (or of an earlier instance) at exactly this t: the lower index wins */
            if (!(*wprim == HZ_ACCEL_INVALID_ID || tt < *wt || (tt == *wt && gp < *wprim)))
                continue;
            hz_inst_xf_t xf;
            for (int c = 0; c < 9; c++)
                xf.adj[c] = adj[L][c];
            float ng[3] = { *word(&t, p, H_NGX, l), *word(&t, p, H_NGY, l), *word(&t, p, H_NGZ, l) };
            hz_inst_normal_out(&xf, ng);
            *wt = tt;
            *word(b, p0 + p, H_NGX, l) = ng[0], *word(b, p0 + p, H_NGY, l) = ng[1], *word(b, p0 + p, H_NGZ, l) = ng[2];
            *word(b, p0 + p, H_U, l) = *word(&t, p, H_U, l), *word(b, p0 + p, H_V, l) = *word(&t, p, H_V, l);
            *wprim = gp;
            ((uint32_t *)(void *)word(b, p0 + p, H_GEOM, l))[0] = 0;
            ((uint32_t *)(void *)word(b, p0 + p, H_INST, l))[0] = HZ_ACCEL_INVALID_ID;
        }
}

/* Rays one slice of a call takes (the native tiles' own slice): the caller's triangle indices are set aside
 * for so many lanes. */
#define SLICE_RAYS 256

static void comp_query(const hz_accel_t *a, hz_accel_ctx_t *ctx, const batch_t *b)
{
    const comp_t *c = a->impl;
    hz_accel_ctx_t local;
    if (!ctx) {
        hz_accel_ctx_init(&local);
        ctx = &local;
    }
    const uint32_t slice = (uint32_t)(SLICE_RAYS / b->w), chunk = (uint32_t)(CHUNK_RAYS / b->w);
    for (uint32_t p0 = 0; p0 < b->n; p0 += slice) {
        const uint32_t np = b->n - p0 < slice ? b->n - p0 : slice;
        const batch_t s = { b->valid + (size_t)p0 * (size_t)b->w, word(b, p0, 0, 0), b->w, np, b->hit };
        /* The merge needs to know which lanes hold a hit (a hit at exactly the ray's tfar leaves tfar as it
         * was): the caller's triangle index is set aside and replaced by "none" meanwhile, and put back where
         * nothing was hit, so a miss leaves the record untouched. */
        uint32_t saved[SLICE_RAYS];
        for (uint32_t p = 0; s.hit && p < np; p++)
            for (int l = 0; l < s.w; l++)
                if (s.valid[p * (uint32_t)s.w + (uint32_t)l]) {
                    uint32_t *pr = (uint32_t *)(void *)word(&s, p, H_PRIM, l);
                    saved[p * (uint32_t)s.w + (uint32_t)l] = *pr;
                    *pr = HZ_ACCEL_INVALID_ID;
                }
        if (c->rest)
            sub_query(c->rest, ctx, &s);
        else if (ctx->stats)
            for (uint32_t i = 0; i < np * (uint32_t)s.w; i++)
                ctx->stats->rays += s.valid[i] != 0;
        for (uint32_t i = 0; i < c->n; i++)
            for (uint32_t p = 0; p < np; p += chunk)
                inst_chunk(a, c->blas[i], &a->geom.instances[i], ctx, &s, p, np - p < chunk ? np - p : chunk);
        for (uint32_t p = 0; s.hit && p < np; p++)
            for (int l = 0; l < s.w; l++) {
                uint32_t *pr = (uint32_t *)(void *)word(&s, p, H_PRIM, l);
                if (s.valid[p * (uint32_t)s.w + (uint32_t)l] && *pr == HZ_ACCEL_INVALID_ID)
                    *pr = saved[p * (uint32_t)s.w + (uint32_t)l];
            }
    }
}

static const int32_t one_valid[1] = { -1 };

static void comp_intersect1(const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit_t *rh)
{
    const batch_t b = { one_valid, (float *)(void *)rh, 1, 1, true };
    comp_query(a, ctx, &b);
}

static void comp_occluded1(const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray_t *r)
{
    const batch_t b = { one_valid, (float *)(void *)r, 1, 1, false };
    comp_query(a, ctx, &b);
}

static void comp_intersect4n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit4_t *rh,
                             uint32_t n)
{
    const batch_t b = { valid, (float *)(void *)rh, 4, n, true };
    comp_query(a, ctx, &b);
}

static void comp_occluded4n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray4_t *r,
                            uint32_t n)
{
    const batch_t b = { valid, (float *)(void *)r, 4, n, false };
    comp_query(a, ctx, &b);
}

static void comp_intersect8n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit8_t *rh,
                             uint32_t n)
{
    const batch_t b = { valid, (float *)(void *)rh, 8, n, true };
    comp_query(a, ctx, &b);
}

static void comp_occluded8n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray8_t *r,
                            uint32_t n)
{
    const batch_t b = { valid, (float *)(void *)r, 8, n, false };
    comp_query(a, ctx, &b);
}

static void comp_intersect4(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit4_t *rh)
{
    comp_intersect4n(valid, a, ctx, rh, 1);
}

static void comp_occluded4(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray4_t *r)
{
    comp_occluded4n(valid, a, ctx, r, 1);
}

static void comp_intersect8(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit8_t *rh)
{
    comp_intersect8n(valid, a, ctx, rh, 1);
}

static void comp_occluded8(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray8_t *r)
{
    comp_occluded8n(valid, a, ctx, r, 1);
}

/* ---- build and refit ---- */
static void info_sum(hz_accel_t *a)
{
    const comp_t *c = a->impl;
    hz_accel_info_t *in = &a->info;
    const hz_accel_info_t *r = c->rest ? &c->rest->info : NULL;
    in->tri_skipped = 0, in->ref_count = 0, in->spatial_splits = 0, in->budget_stops = 0, in->tasks_rebuilt = 0;
    in->node_count = 0, in->leaf_count = 0, in->block_count = 0, in->depth = 0;
    for (uint32_t i = 0; i <= c->n; i++) {
        const hz_accel_info_t *s = i < c->n ? &c->blas[i]->info : r;
        if (!s)
            continue;
        in->tri_skipped += s->tri_skipped, in->ref_count += s->ref_count, in->spatial_splits += s->spatial_splits;
        in->budget_stops += s->budget_stops, in->tasks_rebuilt += s->tasks_rebuilt;
        in->node_count += s->node_count, in->leaf_count += s->leaf_count, in->block_count += s->block_count;
        in->depth = in->depth > s->depth + 1u ? in->depth : s->depth + 1u; /* the instance list is a level */
    }
    in->sah_cost = r ? r->sah_cost : 0.0f;
    in->sah_built = r ? r->sah_built : 0.0f;
    in->rebuilds = r ? r->rebuilds : 0u;
    in->key_sets = r ? r->key_sets : 0u; /* the instances' trees are static */
}

static hz_status_t comp_refit(hz_accel_t *a, hz_error_t *err)
{
    comp_t *c = a->impl;
    hz_status_t s = HZ_OK;
    /* the instances' matrices are read by every query: nothing of theirs to refit */
    if (c->rest && c->rest->info.time_keys >= 2u)
        s = hz_accel_refit(c->rest, err);
    a->info.refits++;
    info_sum(a);
    return s;
}

static const hz_accel_ops_t comp_ops = {
    comp_intersect1,  comp_occluded1,  comp_intersect4,  comp_occluded4,  comp_intersect8,
    comp_occluded8,   comp_refit,      0,                comp_intersect8n, comp_occluded8n,
    comp_intersect4n, comp_occluded4n,
};

/* The caller's progress hook over several builds: build i reports in its share of [0, 1]. */
typedef struct progress_share {
    void (*fn)(void *user, float done);
    void *user;
    float lo, span;
} progress_share_t;

static void share_progress(void *user, float done)
{
    const progress_share_t *p = user;
    p->fn(p->user, p->lo + p->span * done);
}

static hz_status_t sub_build(hz_accel_t **out, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                             progress_share_t *share, uint32_t tris, uint32_t *done, uint32_t total,
                             hz_arena_t *arena, hz_error_t *err)
{
    hz_accel_config_t c = *cfg;
    if (cfg->progress) {
        share->lo = total ? (float)*done / (float)total : 0.0f;
        share->span = total ? (float)tris / (float)total : 1.0f;
        c.progress = share_progress, c.progress_user = share;
    }
    *done += tris;
    return hz_accel_build_native(out, g, &c, arena, err);
}

hz_status_t hz_inst_build(hz_accel_t **out, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                          hz_arena_t *arena, hz_error_t *err)
{
    const hz_arena_mark_t m0 = hz_arena_mark(arena);
    hz_accel_t *a = hz_arena_alloc(arena, sizeof *a, 64);
    comp_t *c = hz_arena_alloc(arena, sizeof *c, 64);
    uint8_t *flags = hz_arena_alloc(arena, g->tri_count ? g->tri_count : 1u, 16);
    if (!a || !c || !flags) {
        hz_arena_error(arena, err);
        hz_error_prefix(err, "accel: rigid instances");
        hz_arena_reset(arena, m0);
        return HZ_E_NO_MEMORY;
    }
    hz_memset(c, 0, sizeof *c);
    for (uint32_t t = 0; t < g->tri_count; t++)
        flags[t] = g->tri_flags ? g->tri_flags[t] : 0u;
    uint32_t held = 0;
    for (uint32_t i = 0; i < g->instance_count; i++) {
        const hz_accel_instance_t *gi = &g->instances[i];
        for (uint32_t t = gi->tri_first; t < gi->tri_first + gi->tri_count; t++)
            flags[t] |= HZ_ACCEL_TRI_LEFT_OUT;
        held += gi->tri_count;
    }
    progress_share_t share = { cfg->progress, cfg->progress_user, 0.0f, 1.0f };
    uint32_t done = 0;
    hz_status_t s = HZ_OK;
    /* the instances first: the other triangles' motion BVH rebuilds in place on refit only when it is the last
     * thing in the arena */
    for (uint32_t i = 0; i < g->instance_count && s == HZ_OK; i++) {
        const hz_accel_instance_t *gi = &g->instances[i];
        hz_accel_geom_t v;
        hz_accel_geom_init(&v);
        v.pos = gi->obj_pos;
        v.vertex_count = g->vertex_count;
        v.tri = g->tri + 3u * (size_t)gi->tri_first;
        v.tri_count = gi->tri_count;
        v.tri_flags = g->tri_flags ? g->tri_flags + gi->tri_first : 0;
        s = sub_build(&c->blas[i], &v, cfg, &share, gi->tri_count, &done, g->tri_count, arena, err);
        c->n = i + 1u;
    }
    if (s == HZ_OK && held < g->tri_count) {
        hz_accel_geom_t r = *g;
        r.instance_count = 0, r.instances = 0, r.static_rest = false;
        r.tri_flags = flags;
        if (g->static_rest) {
            r.time_keys = 0;
            for (int k = 0; k < HZ_ACCEL_MAX_TIME_KEYS; k++)
                r.pos_keys[k] = 0;
        }
        s = sub_build(&c->rest, &r, cfg, &share, g->tri_count - held, &done, g->tri_count, arena, err);
    }
    if (s != HZ_OK) {
        hz_error_prefix(err, "accel: rigid instances");
        hz_arena_reset(arena, m0);
        return s;
    }
    a->ops = &comp_ops;
    a->backend = HZ_ACCEL_NATIVE;
    a->geom = *g;
    a->impl = c;
    hz_memset(&a->info, 0, sizeof a->info);
    a->info.backend = c->n ? c->blas[0]->info.backend : c->rest->info.backend;
    a->info.tri_count = g->tri_count;
    a->info.time_keys = g->time_keys;
    a->info.blur = cfg->blur;
    a->info.instances = c->n;
    a->info.instance_tris = held;
    info_sum(a);
    a->info.bytes = hz_arena_mark(arena) - m0;
    size_t peak = 0;
    for (uint32_t i = 0; i <= c->n; i++) {
        const hz_accel_t *sub = i < c->n ? c->blas[i] : c->rest;
        if (sub && sub->info.bytes_peak > peak)
            peak = sub->info.bytes_peak;
    }
    a->info.bytes_peak = a->info.bytes + peak;
    if (cfg->progress)
        cfg->progress(cfg->progress_user, 1.0f);
    *out = a;
    return HZ_OK;
}

hz_accel_bytes_t hz_inst_bytes_bound(const hz_accel_geom_t *g, const hz_accel_config_t *cfg)
{
    hz_accel_geom_t r = *g;
    r.instance_count = 0, r.instances = 0;
    if (g->static_rest)
        r.time_keys = 0;
    /* the other triangles' bound as if they were all of them: an upper bound, and it keeps this simple */
    hz_accel_bytes_t rest = hz_accel_bytes_bound_geom(&r, cfg), out;
    uint64_t kept = (uint64_t)rest.kept, peak_extra = (uint64_t)rest.peak - (uint64_t)rest.kept;
    for (uint32_t i = 0; i < g->instance_count; i++) {
        const hz_accel_bytes_t b = hz_accel_bytes_bound(g->instances[i].tri_count, cfg);
        kept += (uint64_t)b.kept;
        if ((uint64_t)b.peak - (uint64_t)b.kept > peak_extra)
            peak_extra = (uint64_t)b.peak - (uint64_t)b.kept;
    }
    kept += sizeof(hz_accel_t) + sizeof(comp_t) + (uint64_t)g->tri_count + 3u * 64u;
    const uint64_t peak = kept + peak_extra, lim = (uint64_t)(size_t)-1;
    out.kept = kept > lim ? (size_t)-1 : (size_t)kept;
    out.peak = peak > lim ? (size_t)-1 : (size_t)peak;
    return out;
}
