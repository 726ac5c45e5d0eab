/*
 * embree_accel.h — the Embree 3 backend of hz/accel.h (host builds whose board lists embree in BOARD_ACCEL;
 * the Makefile then defines HZ_HAVE_EMBREE=1 and links -lembree3).
 *
 * Contract:
 *  - hz_accel_build_embree builds the same geometry view as the native backend, with Embree's own BVH: a
 *    device (config string `device_config`, e.g. "isa=avx2"; NULL or "" for Embree's defaults), one scene with
 *    one triangle geometry sharing the view's arrays (float4 stride, so no copy), cfg->quality as build quality
 *    and cfg->robust as RTC_SCENE_FLAG_ROBUST. The hz_accel_t lives in `arena`; Embree allocates its own memory,
 *    which a memory monitor counts (info.bytes / info.bytes_peak) and refuses beyond the arena's free bytes at
 *    build time: the build then fails with HZ_E_NO_MEMORY naming both counts. Embree errors reach the caller
 *    as hz status codes with Embree's message (out of memory -> HZ_E_NO_MEMORY, invalid argument ->
 *    HZ_E_INVALID_ARG, unsupported CPU -> HZ_E_UNSUPPORTED, others HZ_E_INTERNAL).
 *  - Queries pass the hz rays to rtcIntersect1/4/8 and rtcOccluded1/4/8 as they are (identical layouts,
 *    checked at compile time); HZ_ACCEL_COHERENT maps to RTC_INTERSECT_CONTEXT_FLAG_COHERENT. Any-hit
 *    triangles go through Embree filter functions (installed only when some triangle is flagged), which call
 *    ctx->anyhit with the lane index of the filter's packet. ctx->kernel and ctx->stats are ignored.
 *  - Motion blur: a view with time_keys K >= 2 becomes a triangle geometry with K time steps
 *    (rtcSetGeometryTimeStepCount), key k's array shared as vertex buffer k, over Embree's default time range
 *    [0, 1]; rays pass their normalised ray.time through. Embree's own motion BVH (cfg->blur is ignored).
 *  - Refit tells Embree the vertices (every key) changed and commits the scene again (Embree rebuilds, with its
 *    own allocations: the memory monitor counts them against the arena's free bytes).
 *  - hz_accel_release frees the scene and device (call it before resetting the arena).
 */
#ifndef HZ_PORT_EMBREE_ACCEL_H
#define HZ_PORT_EMBREE_ACCEL_H

#include "hz/accel.h"

hz_status_t hz_accel_build_embree(hz_accel_t **out, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                                  const char *device_config, hz_arena_t *arena, hz_error_t *err);

#endif
