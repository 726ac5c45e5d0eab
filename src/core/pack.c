/* Compact frame-state formats (see hz/pack.h). Exponents are read from and written into float bits, so the
 * only float operations are exact power-of-two scalings and one rounding per value. */
#include "hz/pack.h"

#include "hz/image.h" /* hz_float_bits, hz_float_from_bits */

/* 2^e for -126 <= e <= 127 (a normal float). */
static float pow2f(int e)
{
    return hz_float_from_bits((uint32_t)(e + 127) << 23);
}

/* Non-negative, finite, at most max: NaN and negatives to 0, +Inf and above to max. */
static float clamp_range(float v, float max)
{
    if (!(v > 0.0f))
        return 0.0f;
    return v < max ? v : max;
}

/* Round to nearest (ties up) of a value in [0, 2^23). */
static uint32_t round_u(float v)
{
    return (uint32_t)(v + 0.5f);
}

uint32_t hz_rgb9e5_pack(const float rgb[3])
{
    float c[3];
    for (int k = 0; k < 3; k++)
        c[k] = clamp_range(rgb[k], HZ_RGB9E5_MAX);
    float m = c[0] > c[1] ? c[0] : c[1];
    m = m > c[2] ? m : c[2];
    if (m == 0.0f)
        return 0;
    int ex = (int)((hz_float_bits(m) >> 23) & 0xffu) - 127; /* floor(log2 m); float subnormals read as -127 */
    if (ex < -16)
        ex = -16;
    int es = ex + 16; /* shared exponent: the largest channel's mantissa lands in [256, 512) */
    float scale = pow2f(24 - es);
    if (round_u(m * scale) >= 512u) { /* rounding carried into the next power of two */
        es++;
        scale = pow2f(24 - es);
    }
    uint32_t code = (uint32_t)es << 27;
    for (int k = 0; k < 3; k++) {
        uint32_t q = round_u(c[k] * scale);
        code |= (q > 511u ? 511u : q) << (9 * k);
    }
    return code;
}

void hz_rgb9e5_unpack(uint32_t code, float rgb[3])
{
    float scale = pow2f((int)(code >> 27) - 24);
    for (int k = 0; k < 3; k++)
        rgb[k] = (float)((code >> (9 * k)) & 511u) * scale;
}

uint16_t hz_half_pack(float v)
{
    v = clamp_range(v, HZ_HALF_MAX);
    uint32_t u = hz_float_bits(v);
    int e = (int)(u >> 23) - 127;
    if (v == 0.0f || e < -25)
        return 0; /* below half the smallest subnormal (2^-24) */
    if (e < -14) {
        /* Subnormal half: multiples of 2^-24, rounded to nearest even. */
        float q = v * pow2f(24);
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

float hz_half_unpack(uint16_t h)
{
    uint32_t e = (h >> 10) & 0x1fu, m = h & 0x3ffu;
    float sign = (h & 0x8000u) ? -1.0f : 1.0f;
    if (e == 0)
        return sign * (float)m * pow2f(-24);
    if (e == 31)
        return m ? 0.0f : sign * HZ_HALF_MAX; /* not produced by hz_half_pack; read as finite anyway */
    return sign * hz_float_from_bits(((e + 112u) << 23) | (m << 13));
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
