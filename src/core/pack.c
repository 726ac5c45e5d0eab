/* Compact frame-state formats (see hz/pack.h): the half-float packer and the three-channel helpers; the
 * per-pixel codecs of the resolves are inline in the header. Exponents are read from and written into float
 * bits, so the only float operations are exact power-of-two scalings and one rounding per value. */
#include "hz/pack.h"


uint16_t hz_half_pack(float v)
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
    if (drop > 0x1000u || (drop == 0x1000u && (keep & 1u)))
        h++; /* may carry into the exponent: still the correctly rounded value */
    return (uint16_t)(h > 0x7bffu ? 0x7bffu : h);
}

void hz_half_pack3(uint16_t dst[3], const float src[3])
{
    dst[0] = hz_half_pack(src[0]);
    dst[1] = hz_half_pack(src[1]);
    dst[2] = hz_half_pack(src[2]);
}

void hz_half_unpack3(float dst[3], const uint16_t src[3])
{
    dst[0] = hz_half_unpack(src[0]);
    dst[1] = hz_half_unpack(src[1]);
    dst[2] = hz_half_unpack(src[2]);
}

uint16_t hz_half_pack_signed(float v)
{
    if (v < 0.0f) {
        uint16_t m = hz_half_pack(-v);
        return m ? (uint16_t)(0x8000u | m) : 0; /* never -0: zero motion has one code */
    }
    return hz_half_pack(v); /* NaN and -0 give 0 */
}
