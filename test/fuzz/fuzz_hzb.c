/*
 * libFuzzer target for the .hzb loader (`make fuzz`; `make test` runs a bounded number of inputs).
 *
 * Each input is copied into a 64-byte aligned buffer (the loader requires it) and validated as is; then its
 * header and section CRCs are recomputed ("resealed") and it is loaded, so that mutations reach the content
 * checks instead of stopping at the CRCs. The loader must answer every input with HZ_OK or a status plus a
 * message; an accepted scene must pass fuzz_scene.h's checks. Any violation aborts, which libFuzzer records as a
 * crash.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_scene.h"
#include "hz/crc32.h"

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

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > MAX_IMAGE)
        return 0;
    memcpy(image, data, size);
    hz_scene_plan_t plan;
    hz_error_t err;
    hz_error_clear(&err);
    fuzz_check_error(hz_scene_plan(image, size, &plan, &err), &err);
    reseal(image, size);
    (void)fuzz_load_scene(image, size, state, sizeof state);
    return 0;
}
