/*
 * hz/posekeys.h — the scene's pose at the K key times of a shutter interval (motion blur, seed 002): the key
 * arrays the accel's motion-blur BVH reads (hz_accel_geom_t.pos_keys) and the renderer interpolates for shading
 * at a ray's time. The scene itself is never changed (hz_scene_pose_at).
 *
 * Contract:
 *  - hz_posekeys_count(scene, interval_s) chooses K for an interval of interval_s seconds from the scene's
 *    motion: 1 when nothing moves (no keys needed), else K = n + 1 with n = 2^m segments (m = 0..3), the
 *    smallest power of two that keeps every object's motion within one segment nearly linear: rotation (spin,
 *    rigid keys) and phase (oscillate, sway) at most HZ_POSEKEYS_SEGMENT_RAD radians per segment, vertex keys
 *    (baked skinning) and rigid-key knots (rigid objects, and the joints of runtime-skinned objects: their
 *    fastest) at most one key interval per segment. Linear motion gives K = 2.
 *  - hz_posekeys_bytes(scene, K) is what hz_posekeys_init takes from its arena: K float4 position arrays of
 *    vertex_count entries and, when the scene has normals, K normal arrays (64-byte aligned each); 0 for K < 2.
 *  - hz_posekeys_init takes them (HZ_E_NO_MEMORY naming the arena and both byte counts, arena left as it was
 *    found) and fills every key with the scene's current pose, so vertices that never move are right in every
 *    key. K must be 2, 3, 5 or 9 (HZ_E_INVALID_ARG otherwise).
 *  - hz_posekeys_eval(keys, scene, t, lo, hi) poses key k at time t + lo + (hi - lo) k / (K - 1) (lo <= hi:
 *    small offsets in seconds around the frame time t), rewriting only animated objects' vertices, in place:
 *    an accel built over the keys sees the new interval after its refit. Nothing is allocated. The _ns variant
 *    takes t in nanoseconds (hz/scenetime.h), what the renderer's 64-bit clock gives.
 *  - Rigid instances (seed 002 section 3.2): hz_posekeys_init also groups the objects that move rigidly (rigid
 *    keys, spin, oscillate) into at most HZ_ACCEL_MAX_INSTANCES instances: consecutive objects (adjacent
 *    triangle ranges) with the same motion form one (all of rotated Sponza is one). Each instance's vertices
 *    in object space are the scene's rest positions, and eval writes its matrix at every key (the motion of its
 *    first object, as the pose itself uses it). A scene with more groups than that has none (its rigid objects
 *    are then moved vertex by vertex like the rest). static_rest: every moving object is in an instance.
 *  - hz_posekeys_geom points a geometry view at the keys (time_keys = K, pos_keys[k], pos = the middle key) and
 *    its instances (the accel's configuration decides whether it uses them).
 *  - hz_posekeys_lerp(keys, arrays, v, time) interpolates vertex v at normalised time `time` in [0, 1] (clamped;
 *    key k at k / (K - 1)) linearly inside its segment with the accel's own hz_accel_time_segment and
 *    hz_accel_lerp_key, so the triangle the renderer shades is the one the ray hit.
 */
#ifndef HZ_POSEKEYS_H
#define HZ_POSEKEYS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hz/accel.h"
#include "hz/arena.h"
#include "hz/scene.h"
#include "hz/scenetime.h"
#include "hz/status.h"
#include "hz/vmath.h"

#define HZ_POSEKEYS_MAX 9
#define HZ_POSEKEYS_SEGMENT_RAD 0.1f /* rotation / phase per segment: chord error below 0.13% of the radius */

typedef struct hz_posekeys {
    uint32_t count;                  /* K */
    uint32_t vertex_count;
    float *pos[HZ_POSEKEYS_MAX];     /* float4 per vertex, key k */
    float *nrm[HZ_POSEKEYS_MAX];     /* NULL without normals */
    hz_time_ns_t time;               /* the keys span [time + lo, time + hi] (time in ns, lo and hi in s) */
    float lo, hi;
    bool valid;                      /* eval has run */
    /* rigid instances */
    uint32_t instance_count;
    bool static_rest;
    hz_accel_instance_t inst[HZ_ACCEL_MAX_INSTANCES];
    uint32_t inst_object[HZ_ACCEL_MAX_INSTANCES]; /* its first object, whose motion is the instance's */
    float xform[HZ_ACCEL_MAX_INSTANCES][HZ_POSEKEYS_MAX][12];
} hz_posekeys_t; /* not to be copied: inst[].xform points into it */

uint32_t hz_posekeys_count(const hz_scene_t *scene, float interval_s);
size_t hz_posekeys_bytes(const hz_scene_t *scene, uint32_t count);
hz_status_t hz_posekeys_init(hz_posekeys_t *keys, const hz_scene_t *scene, uint32_t count, hz_arena_t *arena,
                             hz_error_t *err);
void hz_posekeys_eval(hz_posekeys_t *keys, const hz_scene_t *scene, float t, float lo, float hi);
void hz_posekeys_eval_ns(hz_posekeys_t *keys, const hz_scene_t *scene, hz_time_ns_t t, float lo, float hi);
void hz_posekeys_geom(const hz_posekeys_t *keys, hz_accel_geom_t *g);

HZ_INLINE hz_vec3_t hz_posekeys_lerp(const hz_posekeys_t *k, float *const *arrays, uint32_t v, float time)
{
    uint32_t s;
    float f;
    hz_accel_time_segment(time, k->count, &s, &f);
    const float *a = arrays[s] + (size_t)v * 4, *b = arrays[s + 1] + (size_t)v * 4;
    return hz_v3(hz_accel_lerp_key(a[0], b[0], f), hz_accel_lerp_key(a[1], b[1], f), hz_accel_lerp_key(a[2], b[2], f));
}

#endif /* HZ_POSEKEYS_H */
