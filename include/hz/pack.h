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
#include "hz/image.h" /* hz_float_bits, hz_float_from_bits */

#define HZ_RGB9E5_MAX 65408.0f /* (511 / 512) * 2^16 */
#define HZ_HALF_MAX 65504.0f

/* The per-pixel codecs are inline: the tdense and TAA resolves call them for every pixel (a profile of a
 * Sponza tdense run showed them as 11% of the samples while they were calls into pack.c). */

/* 2^e for -126 <= e <= 127 (a normal float). */
HZ_INLINE float hz_pack_pow2f(int e)
{
    return hz_float_from_bits((uint32_t)(e + 127) << 23);
}

/* Non-negative, finite, at most max: NaN and negatives to 0, +Inf and above to max. */
HZ_INLINE float hz_pack_clamp(float v, float max)
{
    if (!(v > 0.0f))
        return 0.0f;
    return v < max ? v : max;
}

HZ_INLINE uint32_t hz_rgb9e5_pack(const float rgb[3])
{
    float c[3];
    for (int k = 0; k < 3; k++)
        c[k] = hz_pack_clamp(rgb[k], HZ_RGB9E5_MAX);
    float m = c[0] > c[1] ? c[0] : c[1];
    m = m > c[2] ? m : c[2];
    if (m == 0.0f)
        return 0;
    int ex = (int)((hz_float_bits(m) >> 23) & 0xffu) - 127; /* floor(log2 m); float subnormals read as -127 */
    if (ex < -16)
        ex = -16;
    int es = ex + 16; /* shared exponent: the largest channel's mantissa lands in [256, 512) */
    float scale = hz_pack_pow2f(24 - es);
    if ((uint32_t)(m * scale + 0.5f) >= 512u) { /* rounding (to nearest, ties up) carried into the next power */
        es++;
        scale = hz_pack_pow2f(24 - es);
    }
    uint32_t code = (uint32_t)es << 27;
    for (int k = 0; k < 3; k++) {
        uint32_t q = (uint32_t)(c[k] * scale + 0.5f);
        code |= (q > 511u ? 511u : q) << (9 * k);
    }
    return code;
}

HZ_INLINE void hz_rgb9e5_unpack(uint32_t code, float rgb[3])
{
    float scale = hz_pack_pow2f((int)(code >> 27) - 24);
    for (int k = 0; k < 3; k++)
        rgb[k] = (float)((code >> (9 * k)) & 511u) * scale;
}

HZ_INLINE uint16_t hz_half_pack(float v)
{
    v = hz_pack_clamp(v, HZ_HALF_MAX);
    uint32_t u = hz_float_bits(v);
    int e = (int)(u >> 23) - 127;
    if (v == 0.0f || e < -25)
        return 0; /* below half the smallest subnormal (2^-24) */
    if (e < -14) {
        /* Subnormal half: multiples of 2^-24, rounded to nearest even. */
        float q = v * hz_pack_pow2f(24);
        uint32_t i = (uint32_t)q;
        float rem = q - (float)i;
        if (rem > 0.5f || (rem == 0.5f && (i & 1u)))
            i++;
        return (uint16_t)i; /* i == 1024 is the smallest normal's code, as it should be */
    }
    /* Normal: keep 10 of the 23 mantissa bits, round to nearest even on the 13 dropped. */
    uint32_t mant = u & 0x7fffffu, keep = mant >> 13, drop = mant & 0x1fffu;
    uint32_t h = ((uint32_t)(e + 15) << 10) | keep;
    /* up above the half-way point, and at it when keep is odd; may carry into the exponent: still the
     * correctly rounded value. Flags, not branches: the dropped bits of motion vectors are noise to a
     * predictor (a profile of the tdense put showed the branch as its largest cost). */
    h += (uint32_t)(drop > 0x1000u) | ((uint32_t)(drop == 0x1000u) & keep);
    return (uint16_t)(h > 0x7bffu ? 0x7bffu : h);
}

HZ_INLINE float hz_half_unpack(uint16_t h)
{
    uint32_t e = (h >> 10) & 0x1fu, m = h & 0x3ffu;
    float sign = (h & 0x8000u) ? -1.0f : 1.0f;
    if (e == 0)
        return sign * (float)m * hz_pack_pow2f(-24);
    if (e == 31)
        return m ? 0.0f : sign * HZ_HALF_MAX; /* not produced by hz_half_pack; read as finite anyway */
    return sign * hz_float_from_bits(((e + 112u) << 23) | (m << 13));
}
/* Three channels at once: dst[0..2] / src[0..2]. */
void hz_half_pack3(uint16_t dst[3], const float src[3]);
void hz_half_unpack3(float dst[3], const uint16_t src[3]);

HZ_INLINE uint16_t hz_half_pack_signed(float v)
{
    if (v < 0.0f) {
        uint16_t m = hz_half_pack(-v);
        return m ? (uint16_t)(0x8000u | m) : 0; /* never -0: zero motion has one code */
    }
    return hz_half_pack(v); /* NaN and -0 give 0 */
}

#endif /* HZ_PACK_H */
