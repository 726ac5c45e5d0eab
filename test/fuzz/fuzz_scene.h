/*
 * Shared by the fuzz targets that end in a scene image (fuzz_hzb.c, fuzz_import.c): what the runtime does with
 * an image it accepted must hold for every image. hz_scene_load() into an arena of `state`; an accepted scene has
 * every triangle, material and texture index in range and animates and evaluates its camera without a
 * sanitizer report. Returns the load status; a refusal must carry its status and a message. Violations abort.
 */
#ifndef HZ_FUZZ_SCENE_H
#define HZ_FUZZ_SCENE_H

#include <stdlib.h>

#include "hz/arena.h"
#include "hz/scene.h"

static void fuzz_check_error(hz_status_t s, const hz_error_t *err)
{
    if (s != HZ_OK && (err->code != s || err->msg[0] == '\0'))
        abort(); /* a refusal must say why */
}

static hz_status_t fuzz_load_scene(void *image, size_t size, void *state, size_t state_bytes)
{
    hz_arena_t arena;
    hz_arena_init(&arena, "scene", state, state_bytes);
    hz_scene_t s;
    hz_error_t err;
    hz_error_clear(&err);
    hz_status_t st = hz_scene_load(&s, image, size, &arena, &err);
    fuzz_check_error(st, &err);
    if (st != HZ_OK)
        return st;
    for (uint32_t t = 0; t < s.triangle_count; t++) {
        for (int c = 0; c < 3; c++)
            if (s.tri[(size_t)t * 3 + c] >= s.vertex_count)
                abort();
        if (hz_scene_tri_material(&s, t) >= s.material_count || hz_scene_tri_object(&s, t) >= s.object_count)
            abort();
    }
    for (uint32_t m = 0; m < s.material_count; m++)
        if (s.materials[m].base_texture >= (int32_t)s.texture_count ||
            s.materials[m].alpha_texture >= (int32_t)s.texture_count)
            abort();
    hz_scene_animate(&s, 0.37f);
    hz_scene_animate(&s, 1234.5f);
    (void)hz_scene_camera(&s, 0.25f);
    (void)hz_scene_camera(&s, 1e6f);
    return HZ_OK;
}

#endif /* HZ_FUZZ_SCENE_H */
