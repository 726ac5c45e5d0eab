/*
 * hz/pack.h — compact storage formats for frame state (colour history, sample windows, motion vectors).
 *
 * Contract:
 *  - Every pack function accepts any float, NaN and infinities included, and produces a finite code: NaN and
 *    values below the format's range become 0 (colours are radiance, never negative), +Inf and values above
 *    the largest code become the largest code. Rounding is to nearest. Unpacking a code gives a finite value,
 *    and packing that value again gives the same code (storage can be read and rewritten without drift).
 *  - RGB9E5 (hz_rgb9e5_*): three 9-bit mantissas sharing one 5-bit exponent in 32 bits (the layout of
 *    OpenGL's EXT_texture_shared_exponent: r in bits 0-8, g 9-17, b 18-26, exponent 27-31, bias 15). Range
 *    [0, HZ_RGB9E5_MAX]; every channel has the absolute precision of the largest one (2^-9 of it).
 *  - Half (hz_half_*): IEEE 754 binary16, round to nearest even, subnormals kept, 11 significant bits.
 *    hz_half_pack: one non-negative value, range [0, HZ_HALF_MAX]; hz_half_pack_signed: either sign, range
 *    +-HZ_HALF_MAX (NaN and -0 give +0), for motion vectors: relative precision, so a motion of 10^-3 px
 *    stays non-zero (static and dynamic pixels are told apart exactly as in float) and 16384 px still fits.
 *  - Scalar C only, bit-identical on every ISA (float arithmetic limited to exact power-of-two scaling and one
 *    rounding per value).
 */
#ifndef HZ_PACK_H
#define HZ_PACK_H

#include <stdint.h>

#include "hz/base.h"

#define HZ_RGB9E5_MAX 65408.0f /* (511 / 512) * 2^16 */
#define HZ_HALF_MAX 65504.0f

uint32_t hz_rgb9e5_pack(const float rgb[3]);
void hz_rgb9e5_unpack(uint32_t code, float rgb[3]);

uint16_t hz_half_pack(float v);
float hz_half_unpack(uint16_t h);
/* Three channels at once: dst[0..2] / src[0..2]. */
void hz_half_pack3(uint16_t dst[3], const float src[3]);
void hz_half_unpack3(float dst[3], const uint16_t src[3]);

uint16_t hz_half_pack_signed(float v);

#endif /* HZ_PACK_H */
