/*
 * hz/marker.h — the frame-id marker: a small binary code in the top-left corner that a capture (camera,
 * HDMI grabber, V4L2 loopback) decodes to know which frame it is looking at, and a flash square for a
 * photodiode (one edge per frame).
 *
 * Layout (cell = C x C pixels, all black 0 or white 255 in every channel):
 *   x in [0, F): the flash square, F = 4C high and wide: white on even frame ids, black on odd ones.
 *   then, from x = F + C, a row of 44 cells C high: 1 0 | frame id, 32 bits, MSB first | CRC-8 of the four id
 *   bytes (polynomial 0x07, initial 0, MSB first) | 0 1.
 * hz_marker_layout picks the largest C in {8, 4, 2, 1} whose code fits the width (F + C + 44C <= w, F <= h).
 * Decoding samples each cell's centre through any 8-bit channel view (RGB24: green; XRGB32: byte 2; YUYV: Y;
 * RGB565 little-endian: the high byte), thresholds at 128 and checks the sync bits, the CRC and the flash
 * parity, so a torn, blended or missing marker is reported as HZ_E_CORRUPT instead of a wrong id.
 */
#ifndef HZ_MARKER_H
#define HZ_MARKER_H

#include <stddef.h>
#include <stdint.h>

#include "hz/status.h"

#define HZ_MARKER_CELLS 44

typedef struct hz_marker_layout {
    int cell;  /* C */
    int flash; /* F */
    int width, height; /* pixels the marker covers from (0, 0) */
} hz_marker_layout_t;

/* HZ_E_RANGE when even C = 1 does not fit. */
hz_status_t hz_marker_layout(int w, int h, hz_marker_layout_t *m, hz_error_t *err);

/* Draws the marker for `id` into an RGB24 image (3 bytes per pixel, `stride` bytes per row). */
void hz_marker_draw(uint8_t *rgb, size_t stride, const hz_marker_layout_t *m, uint32_t id);

/* Reads the id from a channel view: the sample of pixel (x, y) is base[y * row_stride + x * pixel_stride]. */
hz_status_t hz_marker_read(const uint8_t *base, size_t pixel_stride, size_t row_stride,
                           const hz_marker_layout_t *m, uint32_t *id);

uint8_t hz_marker_crc8(uint32_t id);

#endif /* HZ_MARKER_H */
