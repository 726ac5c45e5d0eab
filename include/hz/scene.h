/*
 * hz/scene.h — a loaded scene: validated .hzb data used in place, plus the little mutable state animation needs.
 *
 * Contract:
 *  - hz_scene_plan() validates a whole .hzb image in memory (see hz/hzb.h) without allocating or writing
 *    anything and reports the memory plan. Validation covers: magic, version, header CRC, file size, section
 *    table (ids, element sizes, offsets in bounds and aligned, no overlaps, sizes vs. counts computed without
 *    integer overflow), section CRCs, every index (triangle vertices, materials, objects, textures, keys) in
 *    range, object ranges consistent, no NaN/Inf in any float, unit-range material values, strictly increasing
 *    key times, and the feature mask against the content. It never reads outside [buf, buf + size) and runs in
 *    time linear in size. Errors name the section and the reason.
 *  - hz_scene_load() does the same validation, then refuses (HZ_E_NO_MEMORY, naming the arena and both byte
 *    counts) a scene whose mutable state does not fit `arena`, and otherwise sets up `scene`. The scene points
 *    into buf, which must stay alive and unchanged while the scene is used, and be 64-byte aligned (so float4
 *    arrays can be loaded with aligned SIMD loads). Only animated scenes take memory from the arena: current
 *    and previous positions and normals of the moving vertices' arrays, and for runtime skinning (hz/skin.h)
 *    one 64-byte matrix per joint of the largest skinned object; a static scene takes none.
 *  - hz_scene_animate_ns(scene, t) moves every animated object to scene time t (hz/scenetime.h: int64
 *    nanoseconds, exact for centuries): prev_pos/prev_nrm receive the old state, pos/nrm the new one. Static
 *    scenes ignore it. It allocates nothing. Motion is evaluated at t wrapped into the scene's loop (duration),
 *    or without one into each object's own period (one turn, one oscillation, the vertex-key range; rigid keys
 *    hold the last key), so float only ever holds an offset inside a period.
 *  - hz_scene_camera_ns(scene, t) evaluates the camera path at t (looped, or held at the last key), or a default
 *    camera framing the bounds.
 *  - hz_scene_pose_at_ns(scene, t, dt, pos, nrm) writes the pose at time t + dt (dt: a small offset in seconds,
 *    e.g. inside a shutter interval) of every animated object's vertices into pos (float4 per vertex, full-size
 *    array) and, when the scene has normals, nrm; other vertices are left as they are. It reads the scene, never
 *    changes it (skinning passes its joint matrices through the scene's scratch skin_mats, so calls on one
 *    scene must not run concurrently), and allocates nothing: motion blur evaluates the shutter's key times with it (hz/posekeys.h).
 *    hz_scene_pose_at takes t in float seconds.
 *  - hz_scene_object_matrix_at_ns(scene, i, t, dt, m) writes object i's rigid motion at t + dt (rigid keys,
 *    spin, oscillate: the map from its rest positions to the pose hz_scene_pose_at_ns writes) as 12 floats, 3
 *    rows of 4, row-major (world = A p + b, b in the last column); other objects get the identity.
 *  - hz_scene_animate / hz_scene_camera take float seconds: conveniences for short times (tests, tools), the
 *    same as the _ns functions at the nearest nanosecond.
 */
#ifndef HZ_SCENE_H
#define HZ_SCENE_H

#include <stddef.h>
#include <stdint.h>

#include "hz/arena.h"
#include "hz/hzb.h"
#include "hz/scenetime.h"
#include "hz/status.h"
#include "hz/vmath.h"

typedef hz_hzb_material_t hz_material_t;
typedef hz_hzb_texture_t hz_texture_t;
typedef hz_hzb_object_t hz_object_t;
typedef hz_hzb_light_t hz_light_t;

typedef struct hz_scene_plan {
    uint32_t features;          /* the validated feature mask */
    size_t file_bytes;          /* the image itself (resident: the scene is used in place) */
    size_t arena_bytes;         /* what hz_scene_load takes from its arena (0 for static scenes) */
    uint32_t animated_vertices; /* vertices rewritten by animation */
    size_t skin_bytes;          /* of arena_bytes: joint matrices for runtime skinning (largest object's binds) */
} hz_scene_plan_t;

typedef struct hz_scene {
    const hz_hzb_header_t *header;
    uint32_t features;
    uint32_t vertex_count, triangle_count, material_count, texture_count, object_count, light_count;
    uint32_t camera_key_count;

    float *pos;                 /* float4 per vertex, at the last animated time (== rest_pos if static) */
    float *nrm;                 /* float4 per vertex or NULL (no smooth normals) */
    float *prev_pos;            /* positions before the last hz_scene_animate, or NULL if nothing moves */
    float *prev_nrm;
    const float *rest_pos;      /* POSITIONS as baked */
    const float *rest_nrm;
    const float *uv;            /* float2 per vertex or NULL */
    const uint32_t *tri;        /* 3 per triangle */
    const uint32_t *tri_info;   /* material | object << 16 */
    const hz_material_t *materials;
    const hz_texture_t *textures;
    const uint8_t *texels;      /* RGBA8 */
    const hz_object_t *objects;
    const hz_hzb_rigid_key_t *rigid_keys;
    const float *vertex_keys;
    const float *vertex_key_normals;
    const hz_light_t *lights;
    const hz_hzb_camera_key_t *camera_keys;
    const hz_hzb_joint_t *joints;               /* runtime skinning (NULL when no object is HZ_MOTION_SKIN) */
    const hz_hzb_skin_bind_t *skin_binds;
    const hz_hzb_skin_weight_t *skin_weights;   /* per vertex */
    float *skin_mats;           /* scratch: one skinning matrix per bind of the largest SKIN object (arena) */

    float time;                 /* time of pos/nrm inside the scene's loop (seconds) */
    hz_time_ns_t time_ns;       /* time of pos/nrm */
    hz_scene_plan_t plan;
} hz_scene_t;

typedef struct hz_camera {
    hz_vec3_t eye, target, up;
    float fov_y;                /* radians */
} hz_camera_t;

hz_status_t hz_scene_plan(const void *buf, size_t size, hz_scene_plan_t *plan, hz_error_t *err);
hz_status_t hz_scene_load(hz_scene_t *scene, const void *buf, size_t size, hz_arena_t *arena, hz_error_t *err);
void hz_scene_animate_ns(hz_scene_t *scene, hz_time_ns_t t);
hz_camera_t hz_scene_camera_ns(const hz_scene_t *scene, hz_time_ns_t t);
void hz_scene_animate(hz_scene_t *scene, float t);
void hz_scene_pose_at_ns(const hz_scene_t *scene, hz_time_ns_t t, float dt, float *pos, float *nrm);
void hz_scene_pose_at(const hz_scene_t *scene, float t, float dt, float *pos, float *nrm);
void hz_scene_object_matrix_at_ns(const hz_scene_t *scene, uint32_t object, hz_time_ns_t t, float dt, float m[12]);
hz_camera_t hz_scene_camera(const hz_scene_t *scene, float t);

/* Material and object of a triangle. */
HZ_INLINE uint32_t hz_scene_tri_material(const hz_scene_t *s, uint32_t tri) { return s->tri_info[tri] & 0xffffu; }
HZ_INLINE uint32_t hz_scene_tri_object(const hz_scene_t *s, uint32_t tri) { return s->tri_info[tri] >> 16; }

/* Feature names for reports: writes "motion,blend,..." (or "none") into buf. */
void hz_scene_features_str(uint32_t features, char *buf, size_t size);

#endif /* HZ_SCENE_H */
