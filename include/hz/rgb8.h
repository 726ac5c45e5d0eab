/*
 * hz/rgb8.h — resampling of 8-bit RGB frames (RGB24, rows of `stride` bytes): how a frame rendered at a lower
 * scale is shown on the display's full mode.
 *
 * Contract (integer-only, freestanding):
 *  - hz_rgb8_upscale fills every pixel of dst (dw x dh) from src (sw x sh, 1 <= sw <= dw, 1 <= sh <= dh),
 *    bilinearly, with pixel centres aligned ((x + 0.5) dw / sw maps onto itself) and edges clamped. Weights are
 *    Q8 per axis; the result is rounded to nearest. Equal sizes copy the pixels exactly. An integer ratio and
 *    `nearest` replicate each source pixel as a block (what a panel's own scaler does), no blending.
 *  - The bilinear case resamples each source row across once and blends rows down (the same integer result as
 *    weighting the four pixels at once), in scratch memory the caller gives: nothing is allocated.
 *  - The same inputs give the same bytes on every ISA.
 */
#ifndef HZ_RGB8_H
#define HZ_RGB8_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* scratch: hz_rgb8_upscale_scratch(dw) bytes (any alignment), used by the bilinear case. */
size_t hz_rgb8_upscale_scratch(uint32_t dw);
void hz_rgb8_upscale(const uint8_t *src, uint32_t sw, uint32_t sh, size_t sstride, uint8_t *dst, uint32_t dw,
                     uint32_t dh, size_t dstride, bool nearest, void *scratch);

#endif
