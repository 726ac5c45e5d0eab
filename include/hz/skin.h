/*
 * hz/skin.h — runtime linear-blend skinning of HZ_MOTION_SKIN objects (the model is in hz/hzb.h).
 *
 * Contract:
 *  - hz_skin_matrices() evaluates the skinning matrix J(t) * B of each of object o's binds at time t (seconds,
 *    already inside the scene's loop) into mats: HZ_SKIN_MAT_FLOATS floats per bind, four float4 columns
 *    (x, y, z, translation), each with w = 0. mats must hold o->key_count matrices, 32-byte aligned. The
 *    arrays are the validated scene's (the loader checked every index), so nothing is range-checked here.
 *  - hz_skin_blend() writes the skinned positions (and, when rest_nrm and nrm are non-NULL, unit normals) of n
 *    vertices: pos[i] = sum_k w_k M_k rest_pos[i], nrm[i] = normalise(sum_k w_k M_k rest_nrm[i]) (a zero
 *    result keeps the rest normal), w = weight / 65535, M_k = mats[bind k]. float4 per vertex, w = 0 written.
 *    It uses the board's SIMD (AVX2 + FMA, NEON) where it was built with it; hz_skin_blend_scalar() is its
 *    scalar twin and gives the same values within float rounding (FMA and summation order differ).
 *    Both read and write only the n vertices given and allocate nothing.
 *  - hz_skin_point() is the slow, bounds-checked single-vertex form for tools and the writer's bounds (no
 *    scratch memory): point p of a vertex with weights w at time t; an out-of-range index contributes nothing.
 *  - hz_skin_last_key_time() is the latest last-key time over o's joints (the pose holds after it).
 */
#ifndef HZ_SKIN_H
#define HZ_SKIN_H

#include <stdint.h>

#include "hz/hzb.h"
#include "hz/vmath.h"

#define HZ_SKIN_MAT_FLOATS 16u
#define HZ_SKIN_MAT_BYTES (HZ_SKIN_MAT_FLOATS * 4u)

void hz_skin_matrices(const hz_hzb_object_t *o, const hz_hzb_skin_bind_t *binds, const hz_hzb_joint_t *joints,
                      const hz_hzb_rigid_key_t *keys, float t, float *mats);
void hz_skin_blend(const float *mats, const hz_hzb_skin_weight_t *w, const float *rest_pos, const float *rest_nrm,
                   uint32_t n, float *pos, float *nrm);
void hz_skin_blend_scalar(const float *mats, const hz_hzb_skin_weight_t *w, const float *rest_pos,
                          const float *rest_nrm, uint32_t n, float *pos, float *nrm);
/* Name of the path hz_skin_blend takes ("avx2", "neon" or "scalar"). */
const char *hz_skin_blend_path(void);

hz_vec3_t hz_skin_point(const hz_hzb_object_t *o, const hz_hzb_skin_bind_t *binds, uint32_t bind_count,
                        const hz_hzb_joint_t *joints, uint32_t joint_count, const hz_hzb_rigid_key_t *keys,
                        uint32_t key_count, const hz_hzb_skin_weight_t *w, hz_vec3_t p, float t);
float hz_skin_last_key_time(const hz_hzb_object_t *o, const hz_hzb_skin_bind_t *binds, const hz_hzb_joint_t *joints,
                            const hz_hzb_rigid_key_t *keys);

#endif /* HZ_SKIN_H */
