/*
 * wide.h — 128-bit intermediates for the timing module (internal to src/timing/).
 *
 * Contract: exact 64x64 -> 128-bit products and 128/64-bit quotients built from 64-bit operations only, so
 * the core needs no libgcc helper (__divti3 and friends) and gives the same bits on every ISA. Signed helpers
 * round half away from zero and saturate to [INT64_MIN + 1, INT64_MAX] instead of wrapping.
 */
#ifndef HZ_TIMING_WIDE_H
#define HZ_TIMING_WIDE_H

#include <stdint.h>

typedef struct hz_u128 {
    uint64_t hi, lo;
} hz_u128_t;

/* a * b exactly. */
hz_u128_t hz_u128_mul(uint64_t a, uint64_t b);

/* n + m (wraps past 2^128, which callers keep out of reach). */
hz_u128_t hz_u128_add(hz_u128_t n, hz_u128_t m);

/* floor(n / d) for d > 0, saturated to UINT64_MAX when the quotient needs more than 64 bits; *rem (may be
 * NULL) gets n mod d when the quotient fits. d == 0 gives UINT64_MAX. */
uint64_t hz_u128_div(hz_u128_t n, uint64_t d, uint64_t *rem);

/* floor(n / d) with the full 128-bit quotient (d > 0; d == 0 gives all ones). */
hz_u128_t hz_u128_div_full(hz_u128_t n, uint64_t d);

/* floor(sqrt(x)), exact for every 128-bit x. */
uint64_t hz_u128_isqrt(hz_u128_t x);

/* round(a * b / c), exact intermediate; c == 0 saturates towards the sign of a * b (0 when a * b == 0). */
int64_t hz_muldiv(int64_t a, int64_t b, int64_t c);

/* round(a * q / 65536): a count of slots times a Q16.16-nanosecond period, and the like. */
int64_t hz_mul_q16(int64_t a, int64_t q);

/* Integer magnitudes: |INT64_MIN| saturates to INT64_MAX. */
static inline uint64_t hz_abs64(int64_t v)
{
    return v < 0 ? (v == INT64_MIN ? (uint64_t)INT64_MAX + 1u : (uint64_t)(-v)) : (uint64_t)v;
}

#endif /* HZ_TIMING_WIDE_H */
