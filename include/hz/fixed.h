/*
 * hz/fixed.h — integer fixed-point helpers (Q16.16) and integer square root.
 *
 * Contract: integer-only (safe for src/pattern/, which compiles with -mgeneral-regs-only) and bit-exact on
 * every ISA. Q16.16 values are int32_t with 16 fraction bits. Arithmetic that can exceed the range saturates
 * to HZ_Q16_MAX / HZ_Q16_MIN instead of wrapping; division by zero saturates towards the sign of the
 * numerator (0 / 0 gives 0). Products and quotients round to nearest, ties away from zero.
 * Float conversions live in hz/vmath.h so this header stays integer-only.
 */
#ifndef HZ_FIXED_H
#define HZ_FIXED_H

#include <stdint.h>

#include "hz/base.h"

typedef int32_t hz_q16_t;

#define HZ_Q16_SHIFT 16
#define HZ_Q16_ONE ((hz_q16_t)1 << HZ_Q16_SHIFT)
#define HZ_Q16_HALF ((hz_q16_t)1 << (HZ_Q16_SHIFT - 1))
#define HZ_Q16_MAX ((hz_q16_t)INT32_MAX)
#define HZ_Q16_MIN ((hz_q16_t)INT32_MIN)

HZ_INLINE hz_q16_t hz_q16_sat64(int64_t v)
{
    return v > INT32_MAX ? HZ_Q16_MAX : v < INT32_MIN ? HZ_Q16_MIN : (hz_q16_t)v;
}

/* Integer to Q16.16, saturating for |i| >= 32768. */
HZ_INLINE hz_q16_t hz_q16_from_int(int32_t i)
{
    return hz_q16_sat64((int64_t)i * HZ_Q16_ONE);
}

/* Largest integer <= q (arithmetic shift of a negative value is implementation-defined in C99, so the
 * floor is computed without it). */
HZ_INLINE int32_t hz_q16_floor_int(hz_q16_t q)
{
    int64_t v = q;
    return (int32_t)(v >= 0 ? v / HZ_Q16_ONE : -((-v + HZ_Q16_ONE - 1) / HZ_Q16_ONE));
}

/* Fractional part in [0, 1): q - floor(q). */
HZ_INLINE hz_q16_t hz_q16_frac(hz_q16_t q)
{
    return (hz_q16_t)((uint32_t)q & (uint32_t)(HZ_Q16_ONE - 1));
}

HZ_INLINE hz_q16_t hz_q16_add(hz_q16_t a, hz_q16_t b)
{
    return hz_q16_sat64((int64_t)a + b);
}

HZ_INLINE hz_q16_t hz_q16_sub(hz_q16_t a, hz_q16_t b)
{
    return hz_q16_sat64((int64_t)a - b);
}

HZ_INLINE hz_q16_t hz_q16_abs(hz_q16_t a)
{
    return a == HZ_Q16_MIN ? HZ_Q16_MAX : (a < 0 ? -a : a);
}

hz_q16_t hz_q16_mul(hz_q16_t a, hz_q16_t b);
hz_q16_t hz_q16_div(hz_q16_t a, hz_q16_t b);

/* floor(sqrt(x)) for any 64-bit x, exact. */
uint32_t hz_isqrt_u64(uint64_t x);

/* Q16.16 square root of a non-negative Q16.16 value (negative input gives 0), rounded down. */
hz_q16_t hz_q16_sqrt(hz_q16_t a);

/* Count of leading zero bits; 32 for x == 0. */
HZ_INLINE int hz_clz32(uint32_t x)
{
    return x ? __builtin_clz(x) : 32;
}

#endif /* HZ_FIXED_H */
