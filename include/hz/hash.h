/*
 * hz/hash.h — integer hashes and a seeded random number generator, bit-exact on every ISA.
 *
 * Contract: integer-only (usable from src/pattern/), no global state, identical results on x86-64 and
 * AArch64 (tests compare against golden values on both).
 *  - hz_hash32: the MurmurHash3 32-bit finaliser ("fmix32", Appleby): a bijection on uint32 with full
 *    avalanche. hz_hash32(0) == 0, so mix in a seed or use hz_hash_combine for coordinates.
 *  - hz_hash_pcg: the PCG-based hash of Jarzynski and Olano (JCGT 2020), good for per-pixel noise.
 *  - hz_hash2/hz_hash3: hashes of 2 or 3 integers (pixel x, y, frame ...) built from the two above.
 *  - hz_rng_t: PCG32 (O'Neill, "PCG XSH RR 64/32"): 64-bit state, selectable stream, period 2^64.
 *    hz_rng_seed(r, 42, 54) reproduces the reference pcg32-demo sequence (0xa15c02b7, 0x7b47f409, ...).
 *  - hz_rng_below(r, n): uniform in [0, n) without modulo bias (Lemire's multiply-and-reject); n == 0 gives 0.
 */
#ifndef HZ_HASH_H
#define HZ_HASH_H

#include <stdint.h>

#include "hz/base.h"

HZ_INLINE uint32_t hz_hash32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x85ebca6bu;
    x ^= x >> 13;
    x *= 0xc2b2ae35u;
    x ^= x >> 16;
    return x;
}

HZ_INLINE uint32_t hz_hash_pcg(uint32_t v)
{
    uint32_t state = v * 747796405u + 2891336453u;
    uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/* Order-dependent combination (boost-style mixing through the finaliser). */
HZ_INLINE uint32_t hz_hash_combine(uint32_t seed, uint32_t v)
{
    return hz_hash32(seed ^ (hz_hash_pcg(v) + 0x9e3779b9u + (seed << 6) + (seed >> 2)));
}

HZ_INLINE uint32_t hz_hash2(uint32_t a, uint32_t b)
{
    return hz_hash_combine(hz_hash_pcg(a), b);
}

HZ_INLINE uint32_t hz_hash3(uint32_t a, uint32_t b, uint32_t c)
{
    return hz_hash_combine(hz_hash_combine(hz_hash_pcg(a), b), c);
}

typedef struct hz_rng {
    uint64_t state;
    uint64_t inc; /* stream selector, always odd */
} hz_rng_t;

void hz_rng_seed(hz_rng_t *r, uint64_t seed, uint64_t stream);

HZ_INLINE uint32_t hz_rng_u32(hz_rng_t *r)
{
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ull + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((0u - rot) & 31u));
}

uint32_t hz_rng_below(hz_rng_t *r, uint32_t n);

#endif /* HZ_HASH_H */
