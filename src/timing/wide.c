/* 128-bit products and quotients from 64-bit operations (see wide.h). */
#include "wide.h"

hz_u128_t hz_u128_mul(uint64_t a, uint64_t b)
{
    uint64_t a0 = a & 0xffffffffu, a1 = a >> 32, b0 = b & 0xffffffffu, b1 = b >> 32;
    uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    /* The middle column collects three 32-bit quantities: it cannot overflow 64 bits. */
    uint64_t mid = (p00 >> 32) + (p01 & 0xffffffffu) + (p10 & 0xffffffffu);
    hz_u128_t r;
    r.lo = (mid << 32) | (p00 & 0xffffffffu);
    r.hi = p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
    return r;
}

hz_u128_t hz_u128_add(hz_u128_t n, hz_u128_t m)
{
    hz_u128_t r;
    r.lo = n.lo + m.lo;
    r.hi = n.hi + m.hi + (r.lo < n.lo);
    return r;
}

uint64_t hz_u128_div(hz_u128_t n, uint64_t d, uint64_t *rem)
{
    if (d == 0 || n.hi >= d) {
        if (rem)
            *rem = 0;
        return UINT64_MAX;
    }
    /* Restoring division, one quotient bit per step. Since n.hi < d the quotient fits 64 bits and the
     * partial remainder starts as n.hi. A remainder that shifts out its top bit exceeds d for certain. */
    uint64_t r = n.hi, q = 0;
    for (int i = 63; i >= 0; i--) {
        uint64_t top = r >> 63;
        r = (r << 1) | ((n.lo >> i) & 1u);
        if (top || r >= d) {
            r -= d;
            q |= (uint64_t)1 << i;
        }
    }
    if (rem)
        *rem = r;
    return q;
}

hz_u128_t hz_u128_div_full(hz_u128_t n, uint64_t d)
{
    hz_u128_t q;
    if (d == 0) {
        q.hi = q.lo = UINT64_MAX;
        return q;
    }
    q.hi = n.hi / d;
    hz_u128_t low = { n.hi % d, n.lo };
    q.lo = hz_u128_div(low, d, 0);
    return q;
}

static int u128_le(hz_u128_t a, hz_u128_t b)
{
    return a.hi < b.hi || (a.hi == b.hi && a.lo <= b.lo);
}

uint64_t hz_u128_isqrt(hz_u128_t x)
{
    uint64_t r = 0;
    for (int b = 63; b >= 0; b--) {
        uint64_t c = r | ((uint64_t)1 << b);
        if (u128_le(hz_u128_mul(c, c), x))
            r = c;
    }
    return r;
}

static int64_t saturate(uint64_t mag, int neg)
{
    if (mag > (uint64_t)INT64_MAX)
        return neg ? -INT64_MAX : INT64_MAX;
    return neg ? -(int64_t)mag : (int64_t)mag;
}

int64_t hz_muldiv(int64_t a, int64_t b, int64_t c)
{
    int neg = (a < 0) ^ (b < 0) ^ (c < 0);
    uint64_t ua = hz_abs64(a), ub = hz_abs64(b), uc = hz_abs64(c);
    hz_u128_t p = hz_u128_mul(ua, ub);
    if (uc == 0) {
        if (p.hi == 0 && p.lo == 0)
            return 0;
        return saturate(UINT64_MAX, (a < 0) ^ (b < 0));
    }
    hz_u128_t half = { 0, uc >> 1 };
    p = hz_u128_add(p, half);
    return saturate(hz_u128_div(p, uc, 0), neg);
}

int64_t hz_mul_q16(int64_t a, int64_t q)
{
    int neg = (a < 0) ^ (q < 0);
    hz_u128_t p = hz_u128_mul(hz_abs64(a), hz_abs64(q));
    hz_u128_t half = { 0, 1u << 15 };
    p = hz_u128_add(p, half);
    if (p.hi >> 16)
        return saturate(UINT64_MAX, neg);
    return saturate((p.hi << 48) | (p.lo >> 16), neg);
}
