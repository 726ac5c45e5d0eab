/*
 * hzb_reseal.h — for tests that patch .hzb images: recompute every section's CRC-32 and the header's, so a patched
 * value gets past the CRC checks and reaches the loader's deeper validation. Header-only (a static function).
 * Sections whose table entry points outside the image are left as they are (the loader refuses those anyway).
 */
#ifndef HZ_TEST_HZB_RESEAL_H
#define HZ_TEST_HZB_RESEAL_H

#include <stddef.h>
#include <string.h>

#include "hz/crc32.h"
#include "hz/hzb.h"

static void reseal(uint8_t *img, size_t size)
{
    hz_hzb_header_t h;
    memcpy(&h, img, sizeof h);
    for (uint32_t i = 0; i < h.section_count && i < HZ_SEC_ID_MAX; i++) {
        hz_hzb_section_t e;
        memcpy(&e, img + sizeof h + i * sizeof e, sizeof e);
        if (e.offset <= size && e.size <= size - e.offset) {
            e.crc32 = hz_crc32(0, img + e.offset, (size_t)e.size);
            memcpy(img + sizeof h + i * sizeof e, &e, sizeof e);
        }
    }
    h.header_crc = hz_crc32(0, &h, offsetof(hz_hzb_header_t, header_crc));
    memcpy(img, &h, sizeof h);
}

#endif
