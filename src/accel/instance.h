/*
 * instance.h — the native backend's rigid instances (seed 002 section 3.2), inside src/accel.
 *
 * Contract:
 *  - hz_inst_used(g, cfg): whether a native build of view g with cfg takes the instance path (the view has
 *    instances, time keys, and cfg->rigid is HZ_ACCEL_RIGID_INSTANCE).
 *  - hz_inst_build builds it: one static native BVH per instance over its object-space positions (built once,
 *    never refitted), and one BVH of the other triangles (the motion BVH cfg->blur names over the keys, or a
 *    static one when g->static_rest), all in `arena`. Refit re-reads the instances' matrices and refits the
 *    other triangles' BVH when it moves. Queries: the other triangles first, then each instance with the ray
 *    moved into object space at the ray's own time (hz_inst_xform); the closest hit over all of them with the
 *    contract's tie rule (equal t: the lower triangle index), any-hit callbacks called with the view's triangle
 *    indices and the world-space side.
 *  - hz_inst_xform(inst, K, time, xf): the instance's matrix at `time` (each element interpolated between the
 *    keys of hz_accel_time_segment with hz_accel_lerp_key), its adjugate and determinant; false where the
 *    matrix is singular or not finite (the instance is then flat or broken at that time: rays pass it).
 *    hz_inst_ray_in maps a world ray into object space (same t along both); hz_inst_normal_out maps an
 *    object-space geometric normal (v1 - v0) x (v2 - v0) to the world triangle's (the cofactor matrix). The
 *    brute-force reference uses exactly these, so it tests the triangles the traversal tests.
 *  - hz_inst_bytes_bound: what hz_accel_bytes_bound_geom reports for such a view.
 */
#ifndef HZ_ACCEL_INSTANCE_H
#define HZ_ACCEL_INSTANCE_H

#include "hz/accel.h"

typedef struct hz_inst_xf {
    float adj[9]; /* adjugate of the 3x3 part A (row-major): A^-1 = adj / det */
    float inv[9]; /* adj * (1 / det) */
    float b[3];   /* translation */
    float det;
} hz_inst_xf_t;

bool hz_inst_used(const hz_accel_geom_t *g, const hz_accel_config_t *cfg);
hz_status_t hz_inst_build(hz_accel_t **out, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                          hz_arena_t *arena, hz_error_t *err);
hz_accel_bytes_t hz_inst_bytes_bound(const hz_accel_geom_t *g, const hz_accel_config_t *cfg);

bool hz_inst_xform(const hz_accel_instance_t *in, uint32_t keys, float time, hz_inst_xf_t *xf);
/* False when the object-space ray is not finite or has a zero direction (it then misses the instance). */
bool hz_inst_ray_in(const hz_inst_xf_t *xf, const float org[3], const float dir[3], float oorg[3], float odir[3]);
void hz_inst_normal_out(const hz_inst_xf_t *xf, float ng[3]);

#endif /* HZ_ACCEL_INSTANCE_H */
