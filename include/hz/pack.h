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
 *  - Half (hz_half_*): IEEE 754 binary16 of one non-negative value, round to nearest even, subnormals kept.
 *    Range [0, HZ_HALF_MAX]; 11 significant bits per channel.
 *  - MV16 (hz_mv16_*): signed 16-bit fixed point with HZ_MV16_FRAC_BITS fraction bits (1/32 pixel), range
 *    +-HZ_MV16_MAX pixels, for motion vectors; symmetric (the code -32768 is never produced).
 *  - Scalar C only, bit-identical on every ISA (float arithmetic limited to exact power-of-two scaling and one
 *    rounding per value).
 */
#ifndef HZ_PACK_H
#define HZ_PACK_H

#include <stdint.h>

#include "hz/base.h"

#define HZ_RGB9E5_MAX 65408.0f /* (511 / 512) * 2^16 */
#define HZ_HALF_MAX 65504.0f
#define HZ_MV16_FRAC_BITS 5
#define HZ_MV16_MAX (32767.0f / 32.0f)

uint32_t hz_rgb9e5_pack(const float rgb[3]);
void hz_rgb9e5_unpack(uint32_t code, float rgb[3]);

uint16_t hz_half_pack(float v);
float hz_half_unpack(uint16_t h);
/* Three channels at once: dst[0..2] / src[0..2]. */
void hz_half_pack3(uint16_t dst[3], const float src[3]);
void hz_half_unpack3(float dst[3], const uint16_t src[3]);

int16_t hz_mv16_pack(float pixels);
HZ_INLINE float hz_mv16_unpack(int16_t q)
{
    return (float)q * (1.0f / 32.0f);
}

#endif /* HZ_PACK_H */
