/* Q16.16 arithmetic and integer square root (see hz/fixed.h). Integer-only: built with -mgeneral-regs-only. */
#include "hz/fixed.h"

/* Round |num| / den to nearest, ties away from zero, then restore the sign; den > 0. */
static int64_t div_round(int64_t num, uint64_t den)
{
    uint64_t mag = num < 0 ? 0u - (uint64_t)num : (uint64_t)num;
    uint64_t q = (mag + den / 2u) / den;
    /* Callers keep |num| below 2^62, so q fits in int64_t. */
    return num < 0 ? -(int64_t)q : (int64_t)q;
}

hz_q16_t hz_q16_mul(hz_q16_t a, hz_q16_t b)
{
    return hz_q16_sat64(div_round((int64_t)a * b, (uint64_t)HZ_Q16_ONE));
}

hz_q16_t hz_q16_div(hz_q16_t a, hz_q16_t b)
{
    if (b == 0)
        return a > 0 ? HZ_Q16_MAX : a < 0 ? HZ_Q16_MIN : 0;
    int64_t num = (int64_t)a * HZ_Q16_ONE; /* |num| <= 2^47: no overflow */
    int64_t b64 = b;
    if (b64 < 0) {
        num = -num;
        b64 = -b64; /* exact in 64 bits, also for INT32_MIN */
    }
    return hz_q16_sat64(div_round(num, (uint64_t)b64));
}

uint32_t hz_isqrt_u64(uint64_t x)
{
    /* Digit-by-digit (base 4) method: exact for every 64-bit input, no division. */
    uint64_t res = 0;
    uint64_t bit = (uint64_t)1 << 62;
    while (bit > x)
        bit >>= 2;
    while (bit) {
        if (x >= res + bit) {
            x -= res + bit;
            res = (res >> 1) + bit;
        } else {
            res >>= 1;
        }
        bit >>= 2;
    }
    return (uint32_t)res;
}

hz_q16_t hz_q16_sqrt(hz_q16_t a)
{
    if (a <= 0)
        return 0;
    /* sqrt(a / 2^16) * 2^16 = sqrt(a * 2^16); a * 2^16 < 2^47 so the root fits in 24 bits. */
    return (hz_q16_t)hz_isqrt_u64((uint64_t)a << 16);
}
