/*
 * hz/meshgen.h — procedural triangle meshes for tests, benchmarks and scene-less runs.
 *
 * Contract: every generator takes its arrays from the arena given (positions as float4, 16-byte aligned;
 * u32 indices; optional u8 flags left NULL), fills an hz_mesh_t and returns HZ_OK, or HZ_E_NO_MEMORY (arena
 * refusal, arena unchanged) / HZ_E_INVALID_ARG (a parameter out of its documented range). Results are
 * deterministic (seeded integer RNG), identical on every ISA.
 *  - sphere: UV sphere of `stacks` x `slices` (stacks >= 2, slices >= 3), one vertex per pole: closed,
 *    every edge shared by exactly two triangles, consistently wound (outward normals).
 *  - cube_sphere: each face of a cube divided n x n (n >= 1), lattice points shared across faces (closed),
 *    pushed out to radius r when `round` (else the cube of half-size r).
 *  - soup: `count` independent random triangles (no shared vertices) with vertices inside a cube of
 *    half-size `extent`, edge lengths up to `size`.
 *  - append_degenerates: adds `count` degenerate triangles (repeated index, three equal points, collinear
 *    points) at random places inside the mesh bounds (new arrays from the arena, old ones copied).
 *  - transform: p = p * scale + offset for every vertex.
 *  - to_geom: the hz_accel_geom_t view of a mesh.
 *  - motion: K = 2, 3, 5 or 9 time keys for positions pos[vertex_count] (float4), one new array per key from
 *    the arena, for motion-blur tests and `hzrt accel --motion-check` until scenes bring their own animation.
 *    `size` scales the motion (the geometry's extent is a good value); kinds:
 *      SWAY      smooth per-vertex deformation (strands swaying: a sine of the vertex's position and time),
 *      ROTATE    rigid rotation about the vertical axis through `center` by `turns` x 360 degrees over [0, 1],
 *      CROSS     every other vertex moves by +-size/2 along x: vertices cross one another and split planes,
 *      COLLAPSE  every vertex moves to `center` at time 1 (triangles shrink to a point),
 *      ROT180    K = 2: the last key is the first rotated by 180 degrees about the vertical axis (the linear
 *                motion passes every vertex through the axis: triangles flatten and flip within one segment).
 *    The view g gets time_keys = K, pos_keys = the arrays, pos = the middle key (or key 0 for K = 2).
 */
#ifndef HZ_MESHGEN_H
#define HZ_MESHGEN_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/accel.h"
#include "hz/arena.h"
#include "hz/status.h"

typedef struct hz_mesh {
    float *pos;
    uint32_t vertex_count;
    uint32_t *tri;
    uint32_t tri_count;
    uint8_t *tri_flags;
} hz_mesh_t;

hz_status_t hz_meshgen_sphere(hz_mesh_t *m, hz_arena_t *a, uint32_t stacks, uint32_t slices, float radius,
                              hz_error_t *err);
hz_status_t hz_meshgen_cube_sphere(hz_mesh_t *m, hz_arena_t *a, uint32_t n, float radius, bool round,
                                   hz_error_t *err);
hz_status_t hz_meshgen_soup(hz_mesh_t *m, hz_arena_t *a, uint32_t count, float extent, float size, uint64_t seed,
                            hz_error_t *err);
hz_status_t hz_meshgen_append_degenerates(hz_mesh_t *m, hz_arena_t *a, uint32_t count, uint64_t seed,
                                          hz_error_t *err);
void hz_meshgen_transform(hz_mesh_t *m, float scale, hz_vec3_t offset);

typedef enum hz_meshgen_motion_kind {
    HZ_MESHGEN_SWAY = 0,
    HZ_MESHGEN_ROTATE,
    HZ_MESHGEN_CROSS,
    HZ_MESHGEN_COLLAPSE,
    HZ_MESHGEN_ROT180,
    HZ_MESHGEN_MOTION_COUNT
} hz_meshgen_motion_kind_t;

const char *hz_meshgen_motion_name(hz_meshgen_motion_kind_t k); /* "sway", "rotate", "cross", ... */
bool hz_meshgen_motion_parse(const char *s, hz_meshgen_motion_kind_t *out);
hz_status_t hz_meshgen_motion(hz_accel_geom_t *g, const float *pos, hz_meshgen_motion_kind_t kind, uint32_t keys,
                              hz_vec3_t center, float size, float turns, hz_arena_t *a);
/* The point with barycentrics (1 - b1 - b2, b1, b2) of triangle t of g at normalised time `time` (the keys'
 * lerp, as the accel sees it; static views: pos): for rays aimed at moving triangles. */
hz_vec3_t hz_meshgen_tri_point(const hz_accel_geom_t *g, uint32_t t, float time, float b1, float b2);
hz_accel_geom_t hz_meshgen_geom(const hz_mesh_t *m);

#endif /* HZ_MESHGEN_H */
