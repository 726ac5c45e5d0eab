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
hz_accel_geom_t hz_meshgen_geom(const hz_mesh_t *m);

#endif /* HZ_MESHGEN_H */
