/*
 * scene_internal.h — helpers shared inside src/scene/ (writer, loader, animation, built-in scene).
 *
 * Contract: pure functions of their arguments, no allocation. Times are seconds.
 */
#ifndef HZ_SCENE_INTERNAL_H
#define HZ_SCENE_INTERNAL_H

#include "hz/fmt.h"
#include "hz/hzb.h"
#include "hz/scene.h"
#include "hz/vmath.h"

/* Feature bits derivable from the content (everything but HZ_FEAT_INSTANCING). */
uint32_t hz_hzb_content_features(const hz_hzb_material_t *materials, uint32_t material_count,
                                 const hz_hzb_object_t *objects, uint32_t object_count, uint32_t camera_key_count,
                                 int has_normals);

/* t wrapped into [0, period) when period > 0; t unchanged otherwise. */
float hz_scene_wrap_time(float t, float period);

/* Transform of a RIGID, SPIN or OSCILLATE object at time t (already wrapped by the scene duration); returns 0
 * (and the identity) for other kinds. `keys` is the scene's rigid-key array. */
int hz_object_matrix(const hz_hzb_object_t *o, const hz_hzb_rigid_key_t *keys, float t, hz_mat4_t *m);

/* Vertex-key frames and blend weight of a VERTEX object at time t: frames f0, f1 in [0, key_count), weight of
 * f1 in [0, 1). */
void hz_object_vertex_frames(const hz_hzb_object_t *o, float t, uint32_t *f0, uint32_t *f1, float *w);

/* Poses every animated object at time t into pos/nrm (no prev update): the loader uses it for t = 0. */
void hz_scene_pose_ns(hz_scene_t *s, hz_time_ns_t t);
void hz_scene_pose(hz_scene_t *s, float t);

/* Transform of n >= 1 rigid keys at time t (clamped outside their range; see hz/hzb.h): rigid objects and
 * skinning joints. */
hz_mat4_t hz_rigid_keys_matrix(const hz_hzb_rigid_key_t *k, uint32_t n, float t);

/* Rotation matrix of a unit quaternion (x, y, z, w). */
hz_mat4_t hz_quat_matrix(const float q[4]);

#endif
