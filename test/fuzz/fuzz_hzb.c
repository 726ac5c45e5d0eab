/*
 * libFuzzer target for the .hzb loader (`make fuzz`; `make test` runs a bounded number of inputs).
 *
 * Each input is copied into a 64-byte aligned buffer (the loader requires it) and validated as is; then its
 * header and section CRCs are recomputed ("resealed") and it is loaded, so that mutations reach the content
 * checks instead of stopping at the CRCs. The loader must answer every input with HZ_OK or a status plus a
 * message; an accepted scene must have every index in range and must animate and evaluate its camera without
 * a sanitizer report. Any violation aborts, which libFuzzer records as a crash.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hz/arena.h"
#include "hz/crc32.h"
#include "hz/scene.h"

#define MAX_IMAGE (8u << 20)

static uint8_t image[MAX_IMAGE] HZ_ALIGNED(64);
/* Animation state: 4 float4 arrays per vertex; an image of MAX_IMAGE bytes holds fewer than MAX_IMAGE / 16. */
static uint8_t state[4 * MAX_IMAGE + 4096] HZ_ALIGNED(64);

static void reseal(uint8_t *img, size_t size)
{
    hz_hzb_header_t h;
    if (size < sizeof h)
        return;
    memcpy(&h, img, sizeof h);
    for (uint32_t i = 0; i < h.section_count && i < HZ_SEC_ID_MAX; i++) {
        hz_hzb_section_t e;
        size_t at = sizeof h + (size_t)i * sizeof e;
        if (at + sizeof e > size)
            break;
        memcpy(&e, img + at, sizeof e);
        if (e.offset <= size && e.size <= size - e.offset) {
            e.crc32 = hz_crc32(0, img + e.offset, (size_t)e.size);
            memcpy(img + at, &e, sizeof e);
        }
    }
    h.header_crc = hz_crc32(0, &h, offsetof(hz_hzb_header_t, header_crc));
    memcpy(img, &h, sizeof h);
}

static void check_error(hz_status_t s, const hz_error_t *err)
{
    if (s != HZ_OK && (err->code != s || err->msg[0] == '\0'))
        abort(); /* a refusal must say why */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > MAX_IMAGE)
        return 0;
    memcpy(image, data, size);
    hz_scene_plan_t plan;
    hz_error_t err;
    hz_error_clear(&err);
    check_error(hz_scene_plan(image, size, &plan, &err), &err);

    reseal(image, size);
    hz_arena_t arena;
    hz_arena_init(&arena, "scene", state, sizeof state);
    hz_scene_t s;
    hz_error_clear(&err);
    hz_status_t st = hz_scene_load(&s, image, size, &arena, &err);
    check_error(st, &err);
    if (st != HZ_OK)
        return 0;
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
    return 0;
}
