/*
 * hz/builtin.h — the built-in scene: procedural, compiled into every binary, no files needed. It is what
 * `make run` renders and it uses every feature the format has: a room with textured walls and floor, a mirror,
 * an alpha-tested cutout panel, a spinning box and an oscillating sphere, a waving flag with per-vertex keys,
 * a field of transparent particles (instances of one mesh, expanded), two point lights and a looping camera
 * path (8 s).
 *
 * Contract: hz_builtin_scene_image() builds the scene's .hzb image in `image_arena` (64-byte aligned, about
 * 1.6 MB; only the image stays allocated there) using `scratch` for temporary arrays (released before
 * returning). The image is identical on every ISA and every run. Load it with hz_scene_load like a file.
 */
#ifndef HZ_BUILTIN_H
#define HZ_BUILTIN_H

#include <stddef.h>

#include "hz/arena.h"
#include "hz/status.h"

hz_status_t hz_builtin_scene_image(hz_arena_t *image_arena, hz_arena_t *scratch, const void **image, size_t *size,
                                   hz_error_t *err);

#endif
