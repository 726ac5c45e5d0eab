/* The Embree backend (see embree_accel.h). */
#include "embree_accel.h"

#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <embree3/rtcore.h>

/* ---- the hz ray layouts are Embree's ---- */
#define SAME(a, fa, b, fb) HZ_STATIC_ASSERT(offsetof(a, fa) == offsetof(b, fb), a##_##fa)
#define SAME_SIZE(a, b) HZ_STATIC_ASSERT(sizeof(a) == sizeof(b) && __alignof__(a) == __alignof__(b), size_##a)
SAME_SIZE(hz_ray_t, struct RTCRay);
SAME_SIZE(hz_hit_t, struct RTCHit);
SAME_SIZE(hz_rayhit_t, struct RTCRayHit);
SAME_SIZE(hz_ray4_t, struct RTCRay4);
SAME_SIZE(hz_hit4_t, struct RTCHit4);
SAME_SIZE(hz_rayhit4_t, struct RTCRayHit4);
SAME_SIZE(hz_ray8_t, struct RTCRay8);
SAME_SIZE(hz_hit8_t, struct RTCHit8);
SAME_SIZE(hz_rayhit8_t, struct RTCRayHit8);
SAME(hz_ray_t, org_x, struct RTCRay, org_x);
SAME(hz_ray_t, tnear, struct RTCRay, tnear);
SAME(hz_ray_t, dir_x, struct RTCRay, dir_x);
SAME(hz_ray_t, time, struct RTCRay, time);
SAME(hz_ray_t, tfar, struct RTCRay, tfar);
SAME(hz_ray_t, mask, struct RTCRay, mask);
SAME(hz_ray_t, id, struct RTCRay, id);
SAME(hz_ray_t, flags, struct RTCRay, flags);
SAME(hz_hit_t, ng_x, struct RTCHit, Ng_x);
SAME(hz_hit_t, u, struct RTCHit, u);
SAME(hz_hit_t, v, struct RTCHit, v);
SAME(hz_hit_t, prim_id, struct RTCHit, primID);
SAME(hz_hit_t, geom_id, struct RTCHit, geomID);
SAME(hz_hit_t, inst_id, struct RTCHit, instID);
SAME(hz_rayhit_t, hit, struct RTCRayHit, hit);
SAME(hz_ray8_t, tnear, struct RTCRay8, tnear);
SAME(hz_ray8_t, time, struct RTCRay8, time);
SAME(hz_ray8_t, tfar, struct RTCRay8, tfar);
SAME(hz_ray8_t, flags, struct RTCRay8, flags);
SAME(hz_hit8_t, u, struct RTCHit8, u);
SAME(hz_hit8_t, prim_id, struct RTCHit8, primID);
SAME(hz_hit8_t, inst_id, struct RTCHit8, instID);
SAME(hz_rayhit8_t, hit, struct RTCRayHit8, hit);
SAME(hz_ray4_t, tfar, struct RTCRay4, tfar);
SAME(hz_ray4_t, flags, struct RTCRay4, flags);
SAME(hz_hit4_t, prim_id, struct RTCHit4, primID);
SAME(hz_hit4_t, inst_id, struct RTCHit4, instID);
SAME(hz_rayhit4_t, hit, struct RTCRayHit4, hit);
HZ_STATIC_ASSERT(HZ_ACCEL_INVALID_ID == RTC_INVALID_GEOMETRY_ID, invalid_id);

typedef struct embree {
    RTCDevice device;
    RTCScene scene;
    RTCGeometry geom;
    const uint8_t *tri_flags;
    /* error callback */
    enum RTCError last_error;
    char last_msg[160];
    /* memory monitor (called from Embree's threads) */
    int64_t bytes, bytes_peak, limit;
    int refused;
    int refitting;      /* the geometry's build quality is REFIT (set at the first refit) */
} embree_t;

/* The intersect context Embree hands to filter functions, extended with ours (Embree's documented way). */
typedef struct ectx {
    struct RTCIntersectContext rtc;
    hz_accel_ctx_t *hz;
} ectx_t;

static void on_error(void *user, enum RTCError code, const char *str)
{
    embree_t *e = user;
    e->last_error = code;
    snprintf(e->last_msg, sizeof e->last_msg, "%s", str ? str : "");
}

static bool on_memory(void *user, ssize_t bytes, bool post)
{
    embree_t *e = user;
    (void)post;
    int64_t now = __atomic_add_fetch(&e->bytes, (int64_t)bytes, __ATOMIC_RELAXED);
    if (bytes > 0 && e->limit > 0 && now > e->limit) {
        __atomic_sub_fetch(&e->bytes, (int64_t)bytes, __ATOMIC_RELAXED);
        __atomic_store_n(&e->refused, 1, __ATOMIC_RELAXED);
        return false;
    }
    int64_t peak = __atomic_load_n(&e->bytes_peak, __ATOMIC_RELAXED);
    while (now > peak && !__atomic_compare_exchange_n(&e->bytes_peak, &peak, now, true, __ATOMIC_RELAXED,
                                                      __ATOMIC_RELAXED)) {
    }
    return true;
}

static hz_status_t status_of(enum RTCError c)
{
    switch (c) {
    case RTC_ERROR_NONE: return HZ_OK;
    case RTC_ERROR_OUT_OF_MEMORY:
    case RTC_ERROR_CANCELLED: return HZ_E_NO_MEMORY;
    case RTC_ERROR_INVALID_ARGUMENT: return HZ_E_INVALID_ARG;
    case RTC_ERROR_UNSUPPORTED_CPU: return HZ_E_UNSUPPORTED;
    default: return HZ_E_INTERNAL;
    }
}

static hz_status_t check(embree_t *e, const char *what, hz_error_t *err)
{
    enum RTCError c = e->last_error;
    if (c == RTC_ERROR_NONE && e->device)
        c = rtcGetDeviceError(e->device);
    if (c == RTC_ERROR_NONE)
        return HZ_OK;
    if (e->refused)
        return hz_error_set(err, HZ_E_NO_MEMORY, "embree %s: needs more than the %lld bytes the accel arena has free",
                            what, (long long)e->limit);
    return hz_error_set(err, status_of(c), "embree %s: error %d: %s", what, (int)c, e->last_msg);
}

/* Any-hit: lanes on flagged triangles ask the callback; a refusal clears the lane's valid flag. For filters
 * Embree has put the candidate's distance in the ray's tfar. */
static void filter(const struct RTCFilterFunctionNArguments *args)
{
    const embree_t *e = args->geometryUserPtr;
    const ectx_t *c = (const ectx_t *)(const void *)args->context;
    const unsigned n = args->N;
    const float *ray = (const float *)(const void *)args->ray, *hit = (const float *)(const void *)args->hit;
    const unsigned *rayu = (const unsigned *)(const void *)args->ray, *hitu = (const unsigned *)(const void *)args->hit;
    if (!c->hz || !c->hz->anyhit)
        return;
    for (unsigned i = 0; i < n; i++) {
        if (args->valid[i] != -1)
            continue;
        unsigned prim = hitu[5 * n + i]; /* RTCHitN: Ng xyz, u, v, primID, geomID, instID */
        if (!(e->tri_flags[prim] & HZ_ACCEL_TRI_ANYHIT))
            continue;
        /* RTCRayN: org xyz, tnear, dir xyz, time, tfar, mask, id, flags */
        /* Embree's unnormalised Ng is e2 x e1 with e1 = v0 - v1, e2 = v2 - v0: (v1 - v0) x (v2 - v0), ours. */
        float dn = ray[4 * n + i] * hit[i] + ray[5 * n + i] * hit[n + i] + ray[6 * n + i] * hit[2 * n + i];
        if (!c->hz->anyhit(c->hz->user, prim, hit[3 * n + i], hit[4 * n + i], ray[8 * n + i], rayu[10 * n + i],
                           (int)i, dn > 0.0f))
            args->valid[i] = 0;
    }
}

static void ctx_init(ectx_t *c, hz_accel_ctx_t *hz)
{
    rtcInitIntersectContext(&c->rtc);
    c->hz = hz;
    if (hz && (hz->flags & HZ_ACCEL_COHERENT))
        c->rtc.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
}

static void e_intersect1(const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit_t *rh)
{
    ectx_t c;
    ctx_init(&c, ctx);
    rtcIntersect1(((const embree_t *)a->impl)->scene, &c.rtc, (struct RTCRayHit *)(void *)rh);
}

static void e_occluded1(const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray_t *r)
{
    ectx_t c;
    ctx_init(&c, ctx);
    rtcOccluded1(((const embree_t *)a->impl)->scene, &c.rtc, (struct RTCRay *)(void *)r);
}

static void e_intersect4(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit4_t *rh)
{
    ectx_t c;
    ctx_init(&c, ctx);
    rtcIntersect4((const int *)valid, ((const embree_t *)a->impl)->scene, &c.rtc, (struct RTCRayHit4 *)(void *)rh);
}

static void e_occluded4(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray4_t *r)
{
    ectx_t c;
    ctx_init(&c, ctx);
    rtcOccluded4((const int *)valid, ((const embree_t *)a->impl)->scene, &c.rtc, (struct RTCRay4 *)(void *)r);
}

static void e_intersect8(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit8_t *rh)
{
    ectx_t c;
    ctx_init(&c, ctx);
    rtcIntersect8((const int *)valid, ((const embree_t *)a->impl)->scene, &c.rtc, (struct RTCRayHit8 *)(void *)rh);
}

static void e_occluded8(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray8_t *r)
{
    ectx_t c;
    ctx_init(&c, ctx);
    rtcOccluded8((const int *)valid, ((const embree_t *)a->impl)->scene, &c.rtc, (struct RTCRay8 *)(void *)r);
}

/* Tiles: packet by packet, one context for all (Embree 3's stream calls take no valid mask). */
static void e_intersect8n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit8_t *rh, uint32_t n)
{
    ectx_t c;
    ctx_init(&c, ctx);
    for (uint32_t p = 0; p < n; p++)
        rtcIntersect8((const int *)valid + 8u * p, ((const embree_t *)a->impl)->scene, &c.rtc,
                      (struct RTCRayHit8 *)(void *)(rh + p));
}

static void e_occluded8n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray8_t *r, uint32_t n)
{
    ectx_t c;
    ctx_init(&c, ctx);
    for (uint32_t p = 0; p < n; p++)
        rtcOccluded8((const int *)valid + 8u * p, ((const embree_t *)a->impl)->scene, &c.rtc,
                     (struct RTCRay8 *)(void *)(r + p));
}

static void e_intersect4n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit4_t *rh, uint32_t n)
{
    ectx_t c;
    ctx_init(&c, ctx);
    for (uint32_t p = 0; p < n; p++)
        rtcIntersect4((const int *)valid + 4u * p, ((const embree_t *)a->impl)->scene, &c.rtc,
                      (struct RTCRayHit4 *)(void *)(rh + p));
}

static void e_occluded4n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray4_t *r, uint32_t n)
{
    ectx_t c;
    ctx_init(&c, ctx);
    for (uint32_t p = 0; p < n; p++)
        rtcOccluded4((const int *)valid + 4u * p, ((const embree_t *)a->impl)->scene, &c.rtc,
                     (struct RTCRay4 *)(void *)(r + p));
}

static hz_status_t e_refit(hz_accel_t *a, hz_error_t *err)
{
    embree_t *e = a->impl;
    e->last_error = RTC_ERROR_NONE;
    if (!e->refitting) {
        /* An animated scene refits its BVH (topology from the build, boxes from the new vertices) as the native
         * backend does, instead of Embree's default full rebuild at every commit: that rebuild made ~53 heap
         * calls per frame (builder temporaries, TBB tasks); a refit commit makes 4 (test_zero_alloc). */
        rtcSetGeometryBuildQuality(e->geom, RTC_BUILD_QUALITY_REFIT);
        rtcSetSceneFlags(e->scene, rtcGetSceneFlags(e->scene) | RTC_SCENE_FLAG_DYNAMIC);
        e->refitting = 1;
    }
    /* Motion blur: every key moved (the renderer re-posed them for the new shutter interval). */
    uint32_t slots = a->geom.time_keys >= 2u ? a->geom.time_keys : 1u;
    for (uint32_t k = 0; k < slots && a->geom.tri_count; k++)
        rtcUpdateGeometryBuffer(e->geom, RTC_BUFFER_TYPE_VERTEX, k);
    rtcCommitGeometry(e->geom);
    rtcCommitScene(e->scene);
    hz_status_t s = check(e, "refit", err);
    a->info.bytes = (size_t)__atomic_load_n(&e->bytes, __ATOMIC_RELAXED);
    return s;
}

static void e_release(hz_accel_t *a)
{
    embree_t *e = a->impl;
    if (!e)
        return;
    if (e->geom)
        rtcReleaseGeometry(e->geom);
    if (e->scene)
        rtcReleaseScene(e->scene);
    if (e->device)
        rtcReleaseDevice(e->device);
    e->geom = NULL, e->scene = NULL, e->device = NULL;
}

static const hz_accel_ops_t embree_ops = {
    e_intersect1, e_occluded1,   e_intersect4, e_occluded4,   e_intersect8,  e_occluded8,
    e_refit,      e_release,     e_intersect8n, e_occluded8n, e_intersect4n, e_occluded4n,
};

hz_status_t hz_accel_build_embree(hz_accel_t **out, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                                  const char *device_config, hz_arena_t *arena, hz_error_t *err)
{
    if (!out || !arena)
        return hz_error_set(err, HZ_E_INVALID_ARG, "accel: no output or arena");
    *out = NULL;
    hz_status_t s = hz_accel_geom_check(g, err);
    if (s != HZ_OK)
        return s;
    hz_accel_config_t d;
    if (!cfg) {
        hz_accel_config_default(&d);
        cfg = &d;
    }
    const hz_arena_mark_t m0 = hz_arena_mark(arena);
    hz_accel_t *a = hz_arena_alloc(arena, sizeof *a, 64);
    embree_t *e = hz_arena_alloc(arena, sizeof *e, 64);
    if (!a || !e) {
        hz_arena_error(arena, err);
        hz_arena_reset(arena, m0);
        return HZ_E_NO_MEMORY;
    }
    memset(e, 0, sizeof *e);
    e->limit = (int64_t)hz_arena_available(arena, 64);
    e->tri_flags = g->tri_flags;
    a->ops = &embree_ops;
    a->backend = HZ_ACCEL_EMBREE;
    a->geom = *g;
    a->impl = e;
    memset(&a->info, 0, sizeof a->info);
    a->info.backend = "embree";
    a->info.tri_count = g->tri_count;

    e->device = rtcNewDevice(device_config && *device_config ? device_config : NULL);
    if (!e->device) {
        enum RTCError c = rtcGetDeviceError(NULL);
        hz_arena_reset(arena, m0);
        return hz_error_set(err, status_of(c) == HZ_OK ? HZ_E_INTERNAL : status_of(c),
                            "embree: cannot create a device with config '%s' (error %d)",
                            device_config ? device_config : "", (int)c);
    }
    rtcSetDeviceErrorFunction(e->device, on_error, e);
    rtcSetDeviceMemoryMonitorFunction(e->device, on_memory, e);
    e->scene = rtcNewScene(e->device);
    if (e->scene) {
        rtcSetSceneFlags(e->scene, cfg->robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
        rtcSetSceneBuildQuality(e->scene, cfg->quality <= 0   ? RTC_BUILD_QUALITY_LOW
                                          : cfg->quality == 1 ? RTC_BUILD_QUALITY_MEDIUM
                                                              : RTC_BUILD_QUALITY_HIGH);
        e->geom = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    }
    if (e->geom && g->tri_count && g->time_keys >= 2u) {
        /* Motion blur: one vertex buffer per time key, spread evenly over Embree's default time range [0, 1]
         * (ray.time is normalised the same way: hz/accel.h "Motion"); Embree interpolates linearly between them. */
        rtcSetGeometryTimeStepCount(e->geom, g->time_keys);
        for (uint32_t k = 0; k < g->time_keys; k++)
            rtcSetSharedGeometryBuffer(e->geom, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, g->pos_keys[k], 0,
                                       4 * sizeof(float), g->vertex_count);
        a->info.time_keys = g->time_keys;
    } else if (e->geom && g->tri_count) {
        rtcSetSharedGeometryBuffer(e->geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, g->pos, 0,
                                   4 * sizeof(float), g->vertex_count);
    }
    if (e->geom && g->tri_count) {
        rtcSetSharedGeometryBuffer(e->geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, g->tri, 0,
                                   3 * sizeof(uint32_t), g->tri_count);
        rtcSetGeometryBuildQuality(e->geom, cfg->quality <= 0   ? RTC_BUILD_QUALITY_LOW
                                            : cfg->quality == 1 ? RTC_BUILD_QUALITY_MEDIUM
                                                                : RTC_BUILD_QUALITY_HIGH);
        bool flagged = false;
        for (uint32_t t = 0; g->tri_flags && t < g->tri_count && !flagged; t++)
            flagged = (g->tri_flags[t] & HZ_ACCEL_TRI_ANYHIT) != 0;
        if (flagged) {
            rtcSetGeometryUserData(e->geom, e);
            rtcSetGeometryIntersectFilterFunction(e->geom, filter);
            rtcSetGeometryOccludedFilterFunction(e->geom, filter);
        }
        rtcCommitGeometry(e->geom);
        rtcAttachGeometryByID(e->scene, e->geom, 0);
    }
    if (e->scene)
        rtcCommitScene(e->scene);
    s = check(e, "build", err);
    if (s == HZ_OK && (!e->scene || !e->geom))
        s = hz_error_set(err, HZ_E_INTERNAL, "embree build: no scene or geometry");
    if (s != HZ_OK) {
        e_release(a);
        hz_arena_reset(arena, m0);
        return s;
    }
    a->info.bytes = (size_t)__atomic_load_n(&e->bytes, __ATOMIC_RELAXED);
    a->info.bytes_peak = (size_t)__atomic_load_n(&e->bytes_peak, __ATOMIC_RELAXED);
    *out = a;
    return HZ_OK;
}
