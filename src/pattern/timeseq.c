/* Stratified shutter times (see src/pattern/timeseq.h). Integer-only: built with -mgeneral-regs-only. */
#include "timeseq.h"

#include "hz/hash.h"

uint32_t hz_timeseq_stratum(uint32_t pixel, uint32_t index, uint32_t count, uint32_t seed)
{
    if (count <= 1)
        return 0;
    index %= count;
    uint32_t bits = 0;
    while (bits < 32 && (1ull << bits) < count)
        bits++;
    const uint32_t mask = (uint32_t)((1ull << bits) - 1u), key = hz_hash2(pixel, seed ^ 0x7f4a7c15u);
    /* Each step is a bijection of [0, mask] (odd multiply and add mod 2^bits, xorshift, xor), so walking the
     * cycle until the value lands below count is a bijection of [0, count). At most mask + 1 steps. */
    uint32_t i = index;
    do {
        i = (i * 0x2c1b3c6du + key) & mask;
        if (bits > 3)
            i ^= i >> 3;
        i = (i ^ (key >> 16)) & mask;
    } while (i >= count);
    return i;
}

uint32_t hz_timeseq_u32(uint32_t pixel, uint32_t index, uint32_t count, uint32_t seed)
{
    if (count == 0)
        count = 1;
    index %= count;
    const uint64_t s = hz_timeseq_stratum(pixel, index, count, seed);
    const uint64_t lo = ((s << 32) + count - 1u) / count, hi = (((s + 1u) << 32) + count - 1u) / count;
    const uint64_t j = hz_hash3(pixel, index, seed ^ 0x3c6ef372u);
    return (uint32_t)(lo + ((j * (hi - lo)) >> 32));
}
