/*
 * terminator.h — where a shadow ray from a smooth-shaded triangle starts looking for occluders.
 *
 * A triangle of a dense scan is a flat facet of a curved surface; its shading normal (interpolated from the
 * vertex normals) says how the smooth surface faces a light, but a shadow ray leaving the flat facet runs into
 * the neighbouring facets that the curvature lifts above its plane (the shadow terminator problem). On the
 * Stanford dragon (res2, 640x480) such a neighbour, sharing a vertex with the shaded triangle and hit within
 * 0.03 to 0.08 of its longest edge, was what darkened 8 of the 17 isolated dark pixels left once the baker's
 * vertex normals were right. Those occluders are the triangle's own curvature, not geometry in front of it.
 *
 * Contract: hz_terminator_skip(scene, prim, ng) returns the distance along a shadow ray from a point of
 * triangle prim (unit geometric normal ng, either orientation) inside which occluders are ignored: half the
 * triangle's longest edge times sin of the largest angle between ng and its vertex normals (the height the
 * surface those normals describe can rise over the facet's span), capped at a quarter of the longest edge. It is
 * 0 for flat-shaded triangles (no normals, or all vertex normals within 0.8 degrees of ng), so architecture and other flat
 * geometry keep their contact shadows exactly; finite and >= 0 for any input.
 */
#ifndef HZ_TERMINATOR_H
#define HZ_TERMINATOR_H

#include "hz/scene.h"
#include "hz/vmath.h"

float hz_terminator_skip(const hz_scene_t *scene, uint32_t prim, hz_vec3_t ng);

#endif
