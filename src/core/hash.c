/* PCG32 seeding and unbiased bounded draws (see hz/hash.h). Integer-only: built with -mgeneral-regs-only. */
#include "hz/hash.h"

void hz_rng_seed(hz_rng_t *r, uint64_t seed, uint64_t stream)
{
    /* The reference pcg32_srandom_r sequence, so published test vectors apply. */
    r->state = 0u;
    r->inc = (stream << 1u) | 1u;
    (void)hz_rng_u32(r);
    r->state += seed;
    (void)hz_rng_u32(r);
}

uint32_t hz_rng_below(hz_rng_t *r, uint32_t n)
{
    if (n == 0)
        return 0;
    uint64_t m = (uint64_t)hz_rng_u32(r) * n;
    uint32_t low = (uint32_t)m;
    if (low < n) {
        uint32_t threshold = (0u - n) % n; /* 2^32 mod n */
        while (low < threshold) {
            m = (uint64_t)hz_rng_u32(r) * n;
            low = (uint32_t)m;
        }
    }
    return (uint32_t)(m >> 32);
}
