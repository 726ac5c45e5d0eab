/*
 * The accel interface's shared parts and the native backend's operations: argument checks, memory bounds,
 * kernel dispatch (packets fall back to lane-by-lane loops where a board has no SIMD form), hit attributes,
 * any-hit calls and the ray-origin offset.
 */
#include "bvh.h"
#include "instance.h"

#include "hz/scene.h"

void hz_accel_config_default(hz_accel_config_t *cfg)
{
    cfg->leaf_max = HZ_BVH_W;
    cfg->spatial_splits = true;
    cfg->split_alpha = 1e-5f;
    cfg->split_budget = 0.25f;
    cfg->robust = false;
    cfg->quality = 1;
    cfg->progress = 0;
    cfg->progress_user = 0;
    cfg->blur = HZ_ACCEL_BLUR_MSBVH;
    cfg->rebuild_sah_growth = 0.30f;
    cfg->rigid = HZ_ACCEL_RIGID_INSTANCE;
    cfg->segments = HZ_ACCEL_SEGMENTS_PER_NODE;
    cfg->run = 0;
    cfg->run_user = 0;
    cfg->run_threads = 0;
}

static bool str_eq(const char *a, const char *b)
{
    while (*a && *a == *b)
        a++, b++;
    return *a == *b;
}

/* The enums' words: their names, and the index of a word among them (-1: none of them). */
static const char *word_of(const char *const *names, int n, int v)
{
    return v >= 0 && v < n ? names[v] : "unknown";
}

static int word_index(const char *s, const char *const *names, int n)
{
    for (int i = 0; s && i < n; i++)
        if (str_eq(s, names[i]))
            return i;
    return -1;
}

static const char *const blur_names[HZ_ACCEL_BLUR_COUNT] = { "msbvh", "interp", "swept" };
static const char *const rigid_names[HZ_ACCEL_RIGID_COUNT] = { "instance", "refit" };
static const char *const segments_names[HZ_ACCEL_SEGMENTS_COUNT] = { "per-node", "every-key" };

const char *hz_accel_blur_name(hz_accel_blur_t b)
{
    return word_of(blur_names, HZ_ACCEL_BLUR_COUNT, (int)b);
}

bool hz_accel_blur_parse(const char *s, hz_accel_blur_t *out)
{
    const int i = word_index(s, blur_names, HZ_ACCEL_BLUR_COUNT);
    if (i >= 0)
        *out = (hz_accel_blur_t)i;
    return i >= 0;
}

const char *hz_accel_rigid_name(hz_accel_rigid_t r)
{
    return word_of(rigid_names, HZ_ACCEL_RIGID_COUNT, (int)r);
}

bool hz_accel_rigid_parse(const char *s, hz_accel_rigid_t *out)
{
    const int i = word_index(s, rigid_names, HZ_ACCEL_RIGID_COUNT);
    if (i >= 0)
        *out = (hz_accel_rigid_t)i;
    return i >= 0;
}

const char *hz_accel_segments_name(hz_accel_segments_t g)
{
    return word_of(segments_names, HZ_ACCEL_SEGMENTS_COUNT, (int)g);
}

bool hz_accel_segments_parse(const char *s, hz_accel_segments_t *out)
{
    const int i = word_index(s, segments_names, HZ_ACCEL_SEGMENTS_COUNT);
    if (i >= 0)
        *out = (hz_accel_segments_t)i;
    return i >= 0;
}

hz_status_t hz_accel_plan_check(uint32_t tri_count, const hz_accel_config_t *cfg, const hz_arena_t *arena,
                                hz_error_t *err)
{
    hz_accel_geom_t g;
    hz_accel_geom_init(&g);
    g.tri_count = tri_count;
    return hz_accel_plan_check_geom(&g, cfg, arena, err);
}

hz_status_t hz_accel_plan_check_geom(const hz_accel_geom_t *g, const hz_accel_config_t *cfg, const hz_arena_t *arena,
                                     hz_error_t *err)
{
    const uint32_t tri_count = g->tri_count;
    hz_accel_bytes_t b = hz_accel_bytes_bound_geom(g, cfg);
    size_t avail = hz_arena_available(arena, 64);
    if (b.peak <= avail)
        return HZ_OK;
    return hz_error_set(err, HZ_E_NO_MEMORY,
                        "accel: %u triangles need up to %zu bytes to build (%zu kept), arena '%s' has %zu", tri_count,
                        b.peak, b.kept, arena && arena->name ? arena->name : "?", avail);
}

hz_status_t hz_accel_geom_from_scene(hz_accel_geom_t *g, const hz_scene_t *s, hz_arena_t *arena, hz_error_t *err)
{
    hz_accel_geom_init(g);
    g->pos = s->pos;
    g->vertex_count = s->vertex_count;
    g->tri = s->tri;
    g->tri_count = s->triangle_count;
    g->tri_flags = 0;
    bool any = false;
    for (uint32_t m = 0; m < s->material_count && !any; m++)
        any = s->materials[m].alpha_mode != HZ_ALPHA_OPAQUE;
    if (!any)
        return HZ_OK;
    uint8_t *f = hz_arena_alloc(arena, s->triangle_count ? s->triangle_count : 1u, 16);
    if (!f) {
        hz_arena_error(arena, err);
        hz_error_prefix(err, "accel: any-hit flags");
        return HZ_E_NO_MEMORY;
    }
    for (uint32_t t = 0; t < s->triangle_count; t++) {
        uint32_t m = hz_scene_tri_material(s, t);
        f[t] = m < s->material_count && s->materials[m].alpha_mode != HZ_ALPHA_OPAQUE ? HZ_ACCEL_TRI_ANYHIT : 0;
    }
    g->tri_flags = f;
    return HZ_OK;
}

hz_status_t hz_accel_geom_check(const hz_accel_geom_t *g, hz_error_t *err)
{
    if (!g)
        return hz_error_set(err, HZ_E_INVALID_ARG, "accel: no geometry");
    if (g->tri_count > HZ_ACCEL_MAX_TRIS)
        return hz_error_set(err, HZ_E_RANGE, "accel: %u triangles, at most %u supported", g->tri_count,
                            HZ_ACCEL_MAX_TRIS);
    if (g->vertex_count && !g->pos)
        return hz_error_set(err, HZ_E_INVALID_ARG, "accel: %u vertices but no position array", g->vertex_count);
    if (((uintptr_t)g->pos & 15u) != 0)
        return hz_error_set(err, HZ_E_INVALID_ARG, "accel: positions at %p are not 16-byte aligned",
                            (const void *)g->pos);
    if (g->time_keys > 1u) {
        const uint32_t k = g->time_keys;
        if (k != 2u && k != 3u && k != 5u && k != 9u)
            return hz_error_set(err, HZ_E_RANGE, "accel: %u time keys, supported: 0, 1, 2, 3, 5 or 9", k);
        for (uint32_t i = 0; i < k; i++) {
            if (g->vertex_count && !g->pos_keys[i])
                return hz_error_set(err, HZ_E_INVALID_ARG, "accel: time key %u of %u has no position array", i, k);
            if (((uintptr_t)g->pos_keys[i] & 15u) != 0)
                return hz_error_set(err, HZ_E_INVALID_ARG, "accel: time key %u positions at %p are not 16-byte aligned",
                                    i, (const void *)g->pos_keys[i]);
        }
    }
    if (g->tri_count && !g->tri)
        return hz_error_set(err, HZ_E_INVALID_ARG, "accel: %u triangles but no index array", g->tri_count);
    if (g->instance_count) {
        if (g->instance_count > HZ_ACCEL_MAX_INSTANCES || !g->instances)
            return hz_error_set(err, HZ_E_RANGE, "accel: %u rigid instances%s (at most %d)", g->instance_count,
                                g->instances ? "" : " but no array", HZ_ACCEL_MAX_INSTANCES);
        if (g->time_keys < 2u)
            return hz_error_set(err, HZ_E_INVALID_ARG, "accel: rigid instances need time keys (time_keys %u)",
                                g->time_keys);
        uint32_t end = 0;
        for (uint32_t i = 0; i < g->instance_count; i++) {
            const hz_accel_instance_t *in = &g->instances[i];
            if (in->tri_first < end || in->tri_count > g->tri_count || in->tri_first > g->tri_count - in->tri_count)
                return hz_error_set(err, HZ_E_RANGE,
                                    "accel: rigid instance %u: triangles %u + %u overlap the previous instance or "
                                    "pass the view's %u",
                                    i, in->tri_first, in->tri_count, g->tri_count);
            end = in->tri_first + in->tri_count;
            if ((g->vertex_count && !in->obj_pos) || ((uintptr_t)in->obj_pos & 15u) != 0)
                return hz_error_set(err, HZ_E_INVALID_ARG,
                                    "accel: rigid instance %u: object-space positions missing or not 16-byte aligned",
                                    i);
            for (uint32_t k = 0; k < g->time_keys; k++)
                if (!in->xform[k])
                    return hz_error_set(err, HZ_E_INVALID_ARG, "accel: rigid instance %u: no matrix at key %u", i,
                                        k);
        }
    }
    for (uint32_t t = 0; t < g->tri_count; t++)
        for (int k = 0; k < 3; k++)
            if (g->tri[3u * (size_t)t + (uint32_t)k] >= g->vertex_count)
                return hz_error_set(err, HZ_E_RANGE, "accel: triangle %u: vertex index %u >= vertex count %u", t,
                                    g->tri[3u * (size_t)t + (uint32_t)k], g->vertex_count);
    return HZ_OK;
}

/* ---- shared kernel helpers ---- */
void hz_bvh_best_finish(const hz_bvh_t *bvh, const hz_bvh_best_t *best, float *ng, float *u, float *v)
{
    const hz_bvh_block_t *b = &bvh->blocks[best->slot / HZ_BVH_W];
    unsigned s = best->slot % HZ_BVH_W;
    const float rdet = 1.0f / best->det;
    *u = best->v * rdet;
    *v = best->w * rdet;
    float e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = b->v[1][k][s] - b->v[0][k][s];
        e2[k] = b->v[2][k][s] - b->v[0][k][s];
    }
    ng[0] = e1[1] * e2[2] - e1[2] * e2[1];
    ng[1] = e1[2] * e2[0] - e1[0] * e2[2];
    ng[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

void hz_bvh_best_finish_at(const hz_bvh_t *bvh, const hz_bvh_best_t *best, const hz_bvh_ray_t *r, float *ng,
                           float *u, float *v)
{
    if (!bvh->time_keys) {
        hz_bvh_best_finish(bvh, best, ng, u, v);
        return;
    }
    /* the triangle at the ray's time, in a one-block tree of its own */
    hz_bvh_block_t tmp;
    hz_bvh_t one = *bvh;
    hz_bvh_best_t b1 = *best;
    one.blocks = (hz_bvh_block_t *)hz_bvh_block_at(bvh, best->slot / HZ_BVH_W, r, &tmp);
    b1.slot = best->slot % HZ_BVH_W;
    hz_bvh_best_finish(&one, &b1, ng, u, v);
}

bool hz_bvh_anyhit(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, uint32_t slot, float t, float V, float W, float det,
                   uint32_t ray_id, int lane)
{
    const float rdet = 1.0f / det; /* the same values the closest hit would report (hz_bvh_best_finish) */
    const float u = V * rdet, v = W * rdet;
    /* The sheared frame keeps the triangle's winding (ray_prep swaps x and y where dir[kz] < 0), so the
     * determinant's sign is the side: negative where the ray runs along (v1 - v0) x (v2 - v0). */
    const unsigned back = det < 0.0f;
#if HZ_FEATURE_STATS
    if (ctx->stats)
        ctx->stats->anyhit_calls++;
#endif
    uint32_t prim = bvh->blocks[slot / HZ_BVH_W].prim[slot % HZ_BVH_W] & HZ_BVH_PRIM_MASK;
    return ctx->anyhit(ctx->user, prim, u, v, t, ray_id, lane, back);
}

bool hz_accel_kernel_available(hz_accel_kernel_t kernel)
{
    switch (kernel) {
    case HZ_ACCEL_KERNEL_AUTO:
    case HZ_ACCEL_KERNEL_SCALAR: return true;
#if defined(HZ_BVH_HAS_SIMD)
    case HZ_ACCEL_KERNEL_SIMD_SINGLE:
    case HZ_ACCEL_KERNEL_SIMD_PACKET:
    case HZ_ACCEL_KERNEL_SIMD_MASKED: return true;
#endif
    default: return false;
    }
}

const char *hz_accel_kernel_name(hz_accel_kernel_t kernel)
{
    switch (kernel) {
    case HZ_ACCEL_KERNEL_AUTO: return "auto";
    case HZ_ACCEL_KERNEL_SCALAR: return "scalar";
    case HZ_ACCEL_KERNEL_SIMD_SINGLE: return "simd-single";
    case HZ_ACCEL_KERNEL_SIMD_PACKET: return "simd-packet";
    case HZ_ACCEL_KERNEL_SIMD_MASKED: return "simd-masked";
    default: return "unknown";
    }
}

/* ---- native operations ---- */
static hz_accel_kernel_t kernel_of(const hz_accel_ctx_t *ctx)
{
    hz_accel_kernel_t k = ctx ? ctx->kernel : HZ_ACCEL_KERNEL_AUTO;
    return hz_accel_kernel_available(k) ? k : HZ_ACCEL_KERNEL_SCALAR;
}

static void count_rays(hz_accel_ctx_t *ctx, uint32_t n)
{
#if HZ_FEATURE_STATS
    if (ctx && ctx->stats)
        ctx->stats->rays += n;
#else
    (void)ctx;
    (void)n;
#endif
}

static void closest(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_accel_kernel_t k, hz_bvh_ray_t *r,
                    hz_bvh_best_t *best, uint32_t id, int lane)
{
    hz_bvh_best_init(best);
#if defined(HZ_BVH_HAS_SIMD)
    if (k != HZ_ACCEL_KERNEL_SCALAR) {
        hz_bvh_simd_closest(bvh, ctx, r, best, id, lane);
        return;
    }
#endif
    (void)k;
    hz_bvh_scalar_closest(bvh, ctx, r, best, id, lane);
}

static bool any(const hz_bvh_t *bvh, hz_accel_ctx_t *ctx, hz_accel_kernel_t k, const hz_bvh_ray_t *r, uint32_t id,
                int lane)
{
#if defined(HZ_BVH_HAS_SIMD)
    if (k != HZ_ACCEL_KERNEL_SCALAR)
        return hz_bvh_simd_any(bvh, ctx, r, id, lane);
#endif
    (void)k;
    return hz_bvh_scalar_any(bvh, ctx, r, id, lane);
}

/* The ray's motion segment (static trees: none). */
HZ_INLINE void ray_time(hz_bvh_ray_t *r, const hz_bvh_t *bvh, float time)
{
    if (bvh->time_keys) {
        hz_accel_time_segment(time, bvh->time_keys, &r->seg, &r->f);
        if (bvh->mref)
            hz_bvh_ray_levels(r, time, bvh->key_level);
    }
}

static void native_intersect1(const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit_t *rh)
{
    const hz_bvh_t *bvh = a->impl;
    hz_bvh_ray_t r;
    count_rays(ctx, 1);
    if (!hz_bvh_ray_prep(&r, rh->ray.org_x, rh->ray.org_y, rh->ray.org_z, rh->ray.dir_x, rh->ray.dir_y,
                         rh->ray.dir_z, rh->ray.tnear, rh->ray.tfar))
        return;
    ray_time(&r, bvh, rh->ray.time);
    hz_bvh_best_t best;
    closest(bvh, ctx, kernel_of(ctx), &r, &best, rh->ray.id, 0);
    if (best.slot == HZ_ACCEL_INVALID_ID)
        return;
    float ng[3];
    hz_bvh_best_finish_at(bvh, &best, &r, ng, &rh->hit.u, &rh->hit.v);
    rh->ray.tfar = r.tfar;
    rh->hit.ng_x = ng[0], rh->hit.ng_y = ng[1], rh->hit.ng_z = ng[2];
    rh->hit.prim_id = best.prim;
    rh->hit.geom_id = 0;
    rh->hit.inst_id[0] = HZ_ACCEL_INVALID_ID;
}

static void native_occluded1(const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray_t *ray)
{
    hz_bvh_ray_t r;
    count_rays(ctx, 1);
    if (!hz_bvh_ray_prep(&r, ray->org_x, ray->org_y, ray->org_z, ray->dir_x, ray->dir_y, ray->dir_z, ray->tnear,
                         ray->tfar))
        return;
    ray_time(&r, a->impl, ray->time);
    if (any(a->impl, ctx, kernel_of(ctx), &r, ray->id, 0))
        ray->tfar = -__builtin_inff();
}

/* Packets of n lanes seen as arrays: the ray is 12 arrays of n words (org xyz, tnear, dir xyz, time, tfar, mask,
 * id, flags), the hit 8 (ng xyz, u, v, prim, geom, inst). */
enum { R_OX, R_OY, R_OZ, R_TNEAR, R_DX, R_DY, R_DZ, R_TIME, R_TFAR, R_MASK, R_ID, R_FLAGS };
enum { H_NGX, H_NGY, H_NGZ, H_U, H_V, H_PRIM, H_GEOM, H_INST };

static bool lane_prep(hz_bvh_ray_t *r, const hz_bvh_t *bvh, const float *ray, int n, int i)
{
    bool ok = hz_bvh_ray_prep(r, ray[R_OX * n + i], ray[R_OY * n + i], ray[R_OZ * n + i], ray[R_DX * n + i],
                              ray[R_DY * n + i], ray[R_DZ * n + i], ray[R_TNEAR * n + i], ray[R_TFAR * n + i]);
    ray_time(r, bvh, ray[R_TIME * n + i]);
    return ok;
}

static void loop_intersect(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, float *ray, float *hit,
                           int n, hz_accel_kernel_t k)
{
    const hz_bvh_t *bvh = a->impl;
    uint32_t *ray_u = (uint32_t *)(void *)ray, *hit_u = (uint32_t *)(void *)hit;
    for (int i = 0; i < n; i++) {
        if (!valid[i])
            continue;
        hz_bvh_ray_t r;
        count_rays(ctx, 1);
        if (!lane_prep(&r, bvh, ray, n, i))
            continue;
        hz_bvh_best_t best;
        closest(bvh, ctx, k, &r, &best, ray_u[R_ID * n + i], i);
        if (best.slot == HZ_ACCEL_INVALID_ID)
            continue;
        float ng[3];
        hz_bvh_best_finish_at(bvh, &best, &r, ng, &hit[H_U * n + i], &hit[H_V * n + i]);
        ray[R_TFAR * n + i] = r.tfar;
        hit[H_NGX * n + i] = ng[0], hit[H_NGY * n + i] = ng[1], hit[H_NGZ * n + i] = ng[2];
        hit_u[H_PRIM * n + i] = best.prim;
        hit_u[H_GEOM * n + i] = 0;
        hit_u[H_INST * n + i] = HZ_ACCEL_INVALID_ID;
    }
}

static void loop_occluded(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, float *ray, int n,
                          hz_accel_kernel_t k)
{
    const uint32_t *ray_u = (const uint32_t *)(const void *)ray;
    for (int i = 0; i < n; i++) {
        if (!valid[i])
            continue;
        hz_bvh_ray_t r;
        count_rays(ctx, 1);
        if (!lane_prep(&r, a->impl, ray, n, i))
            continue;
        if (any(a->impl, ctx, k, &r, ray_u[R_ID * n + i], i))
            ray[R_TFAR * n + i] = -__builtin_inff();
    }
}

/* n packets of w lanes (4 or 8): the first packet's ray at `ray`, its hits at `hit` (NULL: occlusion), `stride`
 * bytes from one packet to the next. */
typedef struct packets {
    const int32_t *valid;
    char *ray, *hit;
    size_t stride;
    int w;
    uint32_t n;
} packets_t;

static void loop_packets(const packets_t *q, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_accel_kernel_t k)
{
    for (uint32_t p = 0; p < q->n; p++) {
        const int32_t *v = q->valid + (size_t)p * (size_t)q->w;
        float *ray = (float *)(void *)(q->ray + (size_t)p * q->stride);
        if (q->hit)
            loop_intersect(v, a, ctx, ray, (float *)(void *)(q->hit + (size_t)p * q->stride), q->w, k);
        else
            loop_occluded(v, a, ctx, ray, q->w, k);
    }
}

#if defined(HZ_BVH_HAS_SIMD)
/* The packet kernel AUTO picks: the packet (tile) traversal for coherent rays; for incoherent rays, single rays
 * against wide nodes (the faster form in `make bench` on every shared scene). */
static hz_accel_kernel_t packet_kernel(const hz_accel_ctx_t *ctx, hz_accel_kernel_t k)
{
    if (k == HZ_ACCEL_KERNEL_AUTO)
        return ctx && (ctx->flags & HZ_ACCEL_COHERENT) ? HZ_ACCEL_KERNEL_SIMD_PACKET : HZ_ACCEL_KERNEL_SIMD_SINGLE;
    return k == HZ_ACCEL_KERNEL_SIMD_MASKED ? HZ_ACCEL_KERNEL_SIMD_SINGLE : k;
}

static int count_valid(const int32_t *valid, size_t n)
{
    int c = 0;
    for (size_t i = 0; i < n; i++)
        c += valid[i] != 0;
    return c;
}

#define SLICE_RAYS 256u
#define SLICE_PACKETS (SLICE_RAYS / HZ_BVH_W)

/* Word f (ray: 12 words per lane, hit: 8) of lane L of the call's packets. */
HZ_INLINE float *lane_word(const packets_t *q, char *base, int f, uint32_t L)
{
    return (float *)(void *)(base + (size_t)(L / (uint32_t)q->w) * q->stride) + f * q->w + (int)(L % (uint32_t)q->w);
}

/* Packets through the SIMD kernels: packets of the kernels' width go in place, others are repacked to that width
 * (a plain copy of the SoA words) a slice at a time. */
static void simd_query(const packets_t *q, const hz_accel_t *a, hz_accel_ctx_t *ctx)
{
    const hz_bvh_t *bvh = a->impl;
    hz_accel_kernel_t k = packet_kernel(ctx, kernel_of(ctx));
    /* Motion: lanes may sit at different times (and key pairs). Asked for by name (not by AUTO), packets of the
     * kernels' width go through the motion packet kernels where their lanes form a frustum packet, other lanes
     * through the single-ray kernel at each lane's own time. AUTO keeps single rays: on thin moving geometry
     * (the hairball, the swaying furball) the lanes of a primary packet part within a few nodes and the packet
     * kernels were slower there than single rays (doc/accel.md). */
    if (bvh->time_keys && kernel_of(ctx) == HZ_ACCEL_KERNEL_SIMD_PACKET && q->w == HZ_BVH_W &&
        q->stride == (q->hit ? sizeof(hz_bvh_rayhitw_t) : sizeof(hz_bvh_rayw_t))) {
        for (uint32_t p = 0; p < q->n; p++) {
            const int32_t *v = q->valid + (size_t)p * HZ_BVH_W;
            char *ray = q->ray + (size_t)p * q->stride;
            const bool done = q->hit ? hz_bvh_simd_intersect_motion(v, bvh, ctx, (hz_bvh_rayhitw_t *)(void *)ray)
                                     : hz_bvh_simd_occluded_motion(v, bvh, ctx, (hz_bvh_rayw_t *)(void *)ray);
            if (done)
                count_rays(ctx, (uint32_t)count_valid(v, HZ_BVH_W));
            else if (q->hit)
                loop_intersect(v, a, ctx, (float *)(void *)ray, (float *)(void *)(q->hit + (size_t)p * q->stride),
                               q->w, HZ_ACCEL_KERNEL_SIMD_SINGLE);
            else
                loop_occluded(v, a, ctx, (float *)(void *)ray, q->w, HZ_ACCEL_KERNEL_SIMD_SINGLE);
        }
        return;
    }
    if (bvh->time_keys && k != HZ_ACCEL_KERNEL_SCALAR)
        k = HZ_ACCEL_KERNEL_SIMD_SINGLE;
    if (k == HZ_ACCEL_KERNEL_SIMD_SINGLE || k == HZ_ACCEL_KERNEL_SCALAR) {
        loop_packets(q, a, ctx, k);
        return;
    }
    count_rays(ctx, (uint32_t)count_valid(q->valid, (size_t)q->n * (size_t)q->w));
    if (q->w == HZ_BVH_W && q->stride == (q->hit ? sizeof(hz_bvh_rayhitw_t) : sizeof(hz_bvh_rayw_t))) {
        if (q->hit)
            hz_bvh_simd_intersect_tile(q->valid, bvh, ctx, (hz_bvh_rayhitw_t *)(void *)q->ray, q->n, k);
        else
            hz_bvh_simd_occluded_tile(q->valid, bvh, ctx, (hz_bvh_rayw_t *)(void *)q->ray, q->n, k);
        return;
    }
    const uint32_t total = q->n * (uint32_t)q->w;
    for (uint32_t base = 0; base < total; base += SLICE_RAYS) {
        static const int nray = 12, nhit = 8;
        hz_bvh_rayhitw_t buf[SLICE_PACKETS];
        int32_t v[SLICE_RAYS];
        const uint32_t cnt = total - base < SLICE_RAYS ? total - base : SLICE_RAYS;
        const uint32_t np = (cnt + HZ_BVH_W - 1u) / HZ_BVH_W;
        hz_memset(buf, 0, np * sizeof buf[0]);
        for (uint32_t i = 0; i < np * HZ_BVH_W; i++) {
            const uint32_t L = base + i;
            float *rw = (float *)(void *)&buf[i / HZ_BVH_W].ray + i % HZ_BVH_W;
            float *hw = (float *)(void *)&buf[i / HZ_BVH_W].hit + i % HZ_BVH_W;
            v[i] = i < cnt ? q->valid[L] : 0;
            if (i >= cnt)
                continue;
            for (int f = 0; f < nray; f++)
                rw[f * HZ_BVH_W] = *lane_word(q, q->ray, f, L);
            for (int f = 0; q->hit && f < nhit; f++)
                hw[f * HZ_BVH_W] = *lane_word(q, q->hit, f, L);
        }
        if (q->hit) {
            hz_bvh_simd_intersect_tile(v, bvh, ctx, buf, np, k);
        } else {
            /* occlusion takes bare ray packets */
            hz_bvh_rayw_t rays[SLICE_PACKETS];
            for (uint32_t p = 0; p < np; p++)
                rays[p] = buf[p].ray;
            hz_bvh_simd_occluded_tile(v, bvh, ctx, rays, np, k);
            for (uint32_t p = 0; p < np; p++)
                buf[p].ray = rays[p];
        }
        for (uint32_t i = 0; i < cnt; i++) {
            const uint32_t L = base + i;
            const float *rw = (const float *)(const void *)&buf[i / HZ_BVH_W].ray + i % HZ_BVH_W;
            const float *hw = (const float *)(const void *)&buf[i / HZ_BVH_W].hit + i % HZ_BVH_W;
            *lane_word(q, q->ray, 8, L) = rw[8 * HZ_BVH_W]; /* tfar: the only ray word a query writes */
            for (int f = 0; q->hit && f < nhit; f++)
                *lane_word(q, q->hit, f, L) = hw[f * HZ_BVH_W];
        }
    }
}
#define PACKET_QUERY simd_query
#else
static void scalar_query(const packets_t *q, const hz_accel_t *a, hz_accel_ctx_t *ctx)
{
    loop_packets(q, a, ctx, HZ_ACCEL_KERNEL_SCALAR);
}
#define PACKET_QUERY scalar_query
#endif

static void native_intersect4(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit4_t *rh)
{
    const packets_t q = { valid, (char *)(void *)&rh->ray, (char *)(void *)&rh->hit, sizeof *rh, 4, 1 };
    PACKET_QUERY(&q, a, ctx);
}

static void native_occluded4(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray4_t *r)
{
    const packets_t q = { valid, (char *)(void *)r, NULL, sizeof *r, 4, 1 };
    PACKET_QUERY(&q, a, ctx);
}

static void native_intersect8(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit8_t *rh)
{
    const packets_t q = { valid, (char *)(void *)&rh->ray, (char *)(void *)&rh->hit, sizeof *rh, 8, 1 };
    PACKET_QUERY(&q, a, ctx);
}

static void native_occluded8(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray8_t *r)
{
    const packets_t q = { valid, (char *)(void *)r, NULL, sizeof *r, 8, 1 };
    PACKET_QUERY(&q, a, ctx);
}

static void native_intersect8n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit8_t *rh,
                               uint32_t n)
{
    const packets_t q = { valid, (char *)(void *)&rh->ray, (char *)(void *)&rh->hit, sizeof *rh, 8, n };
    PACKET_QUERY(&q, a, ctx);
}

static void native_occluded8n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray8_t *r,
                              uint32_t n)
{
    const packets_t q = { valid, (char *)(void *)r, NULL, sizeof *r, 8, n };
    PACKET_QUERY(&q, a, ctx);
}

static void native_intersect4n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit4_t *rh,
                               uint32_t n)
{
    const packets_t q = { valid, (char *)(void *)&rh->ray, (char *)(void *)&rh->hit, sizeof *rh, 4, n };
    PACKET_QUERY(&q, a, ctx);
}

static void native_occluded4n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray4_t *r,
                              uint32_t n)
{
    const packets_t q = { valid, (char *)(void *)r, NULL, sizeof *r, 4, n };
    PACKET_QUERY(&q, a, ctx);
}

/* The native backend's data: the tree first (a->impl points at it, the kernels read it as an hz_bvh_t), then
 * what a motion refit needs to rebuild in place. */
typedef struct native {
    hz_bvh_t bvh;
    hz_arena_t *arena;
    hz_accel_config_t cfg;
    size_t start, end; /* arena offsets of the tree's arrays */
} native_t;

static void info_from_tree(hz_accel_info_t *in, const hz_bvh_t *bvh, const hz_bvh_build_out_t *bo)
{
    in->tri_skipped = bo->tri_skipped;
    in->ref_count = bo->ref_count;
    in->spatial_splits = bo->spatial_splits;
    in->budget_stops = bo->budget_stops;
    in->tasks_rebuilt = bo->tasks_rebuilt;
    in->node_count = bvh->node_count;
    in->leaf_count = bvh->leaf_count;
    in->block_count = bvh->block_count;
    in->depth = bvh->depth;
    in->sah_cost = bo->sah_cost;
    in->sah_built = bo->sah_cost;
    in->time_keys = bvh->time_keys;
    in->blur = bvh->blur;
    in->key_sets = bvh->key_boxes ? bvh->key_sets : 0u;
}

/* Builds a new motion tree above the current one and moves it down in its place; when the arena cannot hold
 * both for the moment (or something was allocated after the accel), the refitted tree stays. */
static void motion_rebuild(hz_accel_t *a, native_t *nt)
{
    hz_arena_t *ar = nt->arena;
    if (hz_arena_mark(ar) != nt->end)
        return;
    hz_bvh_t nb;
    hz_bvh_build_out_t bo;
    hz_error_t e;
    hz_memset(&nb, 0, sizeof nb);
    hz_memset(&bo, 0, sizeof bo);
    if (hz_bvh_motion_build(&nb, &a->geom, &nt->cfg, ar, &bo, &e) != HZ_OK)
        return;
    uint8_t *src = (uint8_t *)(void *)nb.nodes, *dst = ar->base + nt->start;
    const size_t bytes = (size_t)(ar->base + hz_arena_mark(ar) - src);
    hz_memmove(dst, src, bytes);
    hz_bvh_relocate(&nb, dst - src);
    hz_arena_reset(ar, nt->start + bytes);
    nt->end = nt->start + bytes;
    nt->bvh = nb;
    info_from_tree(&a->info, &nt->bvh, &bo);
    a->info.bytes = nt->end - nt->start + sizeof(hz_accel_t) + sizeof(native_t);
    a->info.rebuilds++;
}

static hz_status_t native_refit(hz_accel_t *a, hz_error_t *err)
{
    (void)err;
    native_t *nt = a->impl;
    if (!nt->bvh.time_keys) {
        hz_bvh_refit(&nt->bvh, &a->geom);
        return HZ_OK;
    }
    hz_bvh_motion_refit(&nt->bvh, &a->geom);
    a->info.refits++;
    a->info.sah_cost = hz_bvh_wide_sah(&nt->bvh);
    const float growth = nt->cfg.rebuild_sah_growth >= 0.0f ? nt->cfg.rebuild_sah_growth : 0.0f;
    if (a->info.sah_cost > a->info.sah_built * (1.0f + growth))
        motion_rebuild(a, nt);
    return HZ_OK;
}

static const hz_accel_ops_t native_ops = {
    native_intersect1,  native_occluded1,  native_intersect4,  native_occluded4,  native_intersect8,
    native_occluded8,   native_refit,      0,                  native_intersect8n, native_occluded8n,
    native_intersect4n, native_occluded4n,
};

hz_status_t hz_accel_build_native(hz_accel_t **out, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                                  hz_arena_t *arena, hz_error_t *err)
{
    if (!out || !arena)
        return hz_error_set(err, HZ_E_INVALID_ARG, "accel: no output or arena");
    *out = 0;
    hz_status_t s = hz_accel_geom_check(g, err);
    if (s != HZ_OK)
        return s;
    hz_accel_config_t d;
    if (!cfg) {
        hz_accel_config_default(&d);
        cfg = &d;
    }
    if (hz_inst_used(g, cfg))
        return hz_inst_build(out, g, cfg, arena, err);
    const hz_arena_mark_t m0 = hz_arena_mark(arena);
    hz_accel_t *a = hz_arena_alloc(arena, sizeof *a, 64);
    native_t *nt = hz_arena_alloc(arena, sizeof *nt, 64);
    if (!a || !nt) {
        hz_arena_error(arena, err);
        hz_arena_reset(arena, m0);
        return HZ_E_NO_MEMORY;
    }
    hz_memset(nt, 0, sizeof *nt);
    hz_bvh_t *bvh = &nt->bvh;
    const bool motion = g->time_keys >= 2u;
    hz_bvh_build_out_t bo;
    hz_memset(&bo, 0, sizeof bo);
    const hz_arena_mark_t m1 = hz_arena_mark(arena);
    s = motion ? hz_bvh_motion_build(bvh, g, cfg, arena, &bo, err) : hz_bvh_build(bvh, g, cfg, arena, &bo, err);
    if (s != HZ_OK) {
        hz_arena_reset(arena, m0);
        if (s == HZ_E_NO_MEMORY) {
            hz_accel_bytes_t b = hz_accel_bytes_bound_geom(g, cfg);
            char inner[HZ_ERROR_MSG_BYTES];
            hz_memcpy(inner, err ? err->msg : "", err ? sizeof inner : 1);
            hz_error_set(err, s, "accel: %u triangles (bound %zu bytes): %s", g->tri_count, b.peak, inner);
        }
        return s;
    }
    a->ops = &native_ops;
    a->backend = HZ_ACCEL_NATIVE;
    a->geom = *g;
    a->impl = bvh;
    hz_memset(&a->info, 0, sizeof a->info);
#if defined(HZ_SIMD_AVX2)
    a->info.backend = "native-avx2";
#elif defined(HZ_SIMD_NEON)
    a->info.backend = "native-neon";
#else
    a->info.backend = "native-scalar";
#endif
    a->info.tri_count = g->tri_count;
    info_from_tree(&a->info, bvh, &bo);
    a->info.bytes = hz_arena_mark(arena) - m0;
    a->info.bytes_peak = bo.bytes_peak + (m1 - m0);
    if (a->info.bytes_peak < a->info.bytes)
        a->info.bytes_peak = a->info.bytes;
    nt->arena = arena;
    nt->cfg = *cfg;
    /* the hooks and their user pointers are the caller's for this call only: refit's rebuilds run serially */
    nt->cfg.progress = 0, nt->cfg.progress_user = 0;
    nt->cfg.run = 0, nt->cfg.run_user = 0, nt->cfg.run_threads = 0;
    nt->start = (size_t)((const uint8_t *)(const void *)bvh->nodes - arena->base);
    nt->end = hz_arena_mark(arena);
    *out = a;
    return HZ_OK;
}

/* ---- brute force (the reference of tests and --motion-check) ---- */
static bool tri_finite(const hz_accel_geom_t *g, uint32_t t)
{
    const uint32_t nk = g->time_keys >= 2u ? g->time_keys : 1u;
    for (uint32_t key = 0; key < nk; key++) {
        const float *pos = g->time_keys >= 2u ? g->pos_keys[key] : g->pos;
        for (int v = 0; v < 3; v++) {
            const float *p = pos + 4u * (size_t)g->tri[3u * (size_t)t + (uint32_t)v];
            if (!hz_isfinitef(p[0]) || !hz_isfinitef(p[1]) || !hz_isfinitef(p[2]))
                return false;
        }
    }
    return true;
}

/* An instance's triangle in object space: the native build leaves out the same ones (its tri_box) */
static bool tri_finite_blk(const hz_bvh_block_t *b)
{
    for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++)
            if (!(hz_absf(b->v[v][k][0]) <= HZ_ACCEL_MAX_COORD))
                return false;
    return true;
}

void hz_accel_brute_intersect1(const hz_accel_geom_t *g, hz_rayhit_t *rh)
{
    hz_bvh_ray_t r;
    if (!hz_bvh_ray_prep(&r, rh->ray.org_x, rh->ray.org_y, rh->ray.org_z, rh->ray.dir_x, rh->ray.dir_y,
                         rh->ray.dir_z, rh->ray.tnear, rh->ray.tfar))
        return;
    const bool motion = g->time_keys >= 2u;
    uint32_t seg = 0;
    float f = 0.0f;
    if (motion)
        hz_accel_time_segment(rh->ray.time, g->time_keys, &seg, &f);
    /* Rigid instances (when the native build takes them: the default configuration's choice): their triangles
     * in object space against the ray moved there at its time, as the traversal does. */
    const bool inst = hz_inst_used(g, 0);
    /* with static_rest the other triangles are static geometry over pos (a lerp of equal keys may round) */
    const bool moving_rest = motion && !(inst && g->static_rest);
    hz_bvh_ray_t ri[HZ_ACCEL_MAX_INSTANCES];
    hz_inst_xf_t xf[HZ_ACCEL_MAX_INSTANCES];
    bool in_ok[HZ_ACCEL_MAX_INSTANCES];
    for (uint32_t i = 0; inst && i < g->instance_count; i++) {
        const float org[3] = { rh->ray.org_x, rh->ray.org_y, rh->ray.org_z };
        const float dir[3] = { rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z };
        float oo[3], od[3];
        in_ok[i] = hz_inst_xform(&g->instances[i], g->time_keys, rh->ray.time, &xf[i]) &&
                   hz_inst_ray_in(&xf[i], org, dir, oo, od) &&
                   hz_bvh_ray_prep(&ri[i], oo[0], oo[1], oo[2], od[0], od[1], od[2], rh->ray.tnear, rh->ray.tfar);
    }
    hz_bvh_block_t blk, hit_blk;
    hz_memset(&blk, 0, sizeof blk);
    uint32_t best_prim = HZ_ACCEL_INVALID_ID, best_inst = HZ_ACCEL_INVALID_ID, i = 0;
    float bv = 0.0f, bw = 0.0f, bdet = 1.0f;
    for (uint32_t t = 0; t < g->tri_count; t++) {
        while (inst && i < g->instance_count && t >= g->instances[i].tri_first + g->instances[i].tri_count)
            i++;
        const bool in = inst && i < g->instance_count && t >= g->instances[i].tri_first;
        if (in ? !in_ok[i] : !tri_finite(g, t))
            continue;
        for (int v = 0; v < 3; v++) {
            const size_t vi = 4u * (size_t)g->tri[3u * (size_t)t + (uint32_t)v];
            for (int k = 0; k < 3; k++)
                blk.v[v][k][0] = in           ? g->instances[i].obj_pos[vi + (size_t)k]
                                 : moving_rest ? hz_accel_lerp_key(g->pos_keys[seg][vi + (size_t)k],
                                                              g->pos_keys[seg + 1u][vi + (size_t)k], f)
                                          : g->pos[vi + (size_t)k];
        }
        if (in && !tri_finite_blk(&blk))
            continue;
        float tt, U, V, W, det;
        hz_bvh_ray_t *rr = in ? &ri[i] : &r;
        rr->tfar = r.tfar;
        if (!hz_bvh_tri_test(&blk, 0, rr, &tt, &U, &V, &W, &det))
            continue;
        if (!(tt >= r.tnear) || !hz_bvh_better(tt, t, r.tfar, best_prim))
            continue;
        r.tfar = tt;
        best_prim = t;
        best_inst = in ? i : HZ_ACCEL_INVALID_ID;
        bv = V, bw = W, bdet = det;
        hit_blk = blk;
    }
    if (best_prim == HZ_ACCEL_INVALID_ID)
        return;
    hz_bvh_t one;
    hz_memset(&one, 0, sizeof one);
    one.blocks = &hit_blk;
    hz_bvh_best_t b;
    b.slot = 0, b.prim = best_prim, b.v = bv, b.w = bw, b.det = bdet;
    float ng[3];
    hz_bvh_best_finish(&one, &b, ng, &rh->hit.u, &rh->hit.v);
    if (best_inst != HZ_ACCEL_INVALID_ID)
        hz_inst_normal_out(&xf[best_inst], ng);
    rh->ray.tfar = r.tfar;
    rh->hit.ng_x = ng[0], rh->hit.ng_y = ng[1], rh->hit.ng_z = ng[2];
    rh->hit.prim_id = best_prim;
    rh->hit.geom_id = 0;
    rh->hit.inst_id[0] = HZ_ACCEL_INVALID_ID;
}

/* ---- ray origin offset (Wächter and Binder 2019, constants scaled with the scene) ---- */
static float offset_component(float p, float n, float scale)
{
    const float origin = scale * (1.0f / 32.0f), float_scale = scale * (1.0f / 65536.0f), int_scale = 256.0f;
    if (hz_absf(p) < origin)
        return p + float_scale * n;
    int32_t of = (int32_t)(int_scale * n);
    int32_t bits;
    hz_memcpy(&bits, &p, sizeof bits);
    bits += p < 0.0f ? -of : of;
    float r;
    hz_memcpy(&r, &bits, sizeof r);
    return r;
}

hz_vec3_t hz_accel_offset_origin(hz_vec3_t p, hz_vec3_t n, float scale)
{
    if (!(scale > 0.0f) || !hz_isfinitef(scale))
        scale = 1.0f;
    n = hz_v3_normalize(n);
    return hz_v3(offset_component(p.x, n.x, scale), offset_component(p.y, n.y, scale),
                 offset_component(p.z, n.z, scale));
}
