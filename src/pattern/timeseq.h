/*
 * timeseq.h — shutter times of pixel samples: a stratified sequence built on the integer hash (motion blur,
 * seed 002). Integer-only (src/pattern/, -mgeneral-regs-only): identical results on every ISA.
 *
 * Contract:
 *  - hz_timeseq_u32(pixel, index, count, seed) gives sample `index` (0 <= index < count, count >= 1) of the
 *    `count` shutter times of pixel `pixel` as a 32-bit fraction f of the shutter interval (time = f / 2^32,
 *    in [0, 1)). The count samples of one pixel are stratified: stratum s = hz_timeseq_stratum(pixel, index,
 *    count, seed) is a permutation of 0..count-1 over index (a different shuffle per pixel and seed, so time
 *    strata are not correlated with the spatial strata of the same index), and f lies in
 *    [ceil(s 2^32 / count), ceil((s + 1) 2^32 / count)): f = floor(s 2^32 / count) rounded up, plus a jitter
 *    that is the hash of (pixel, index, seed) scaled into the stratum's width.
 *    index >= count wraps (index mod count); count 0 is taken as 1.
 *  - The exact definition (tools/gen/timeseq_golden.py recomputes it independently for the golden test):
 *      bits  = smallest b >= 0 with 2^b >= count, mask = 2^b - 1
 *      key   = hz_hash2(pixel, seed ^ 0x7f4a7c15)
 *      shuffle(i): repeat { i = (i * 0x2c1b3c6d + key) & mask; i ^= i >> 3 (if bits > 3, else nothing);
 *                           i = (i ^ (key >> 16)) & mask } until i < count   (cycle walking: a bijection)
 *      lo    = ceil(s * 2^32 / count), hi = ceil((s + 1) * 2^32 / count)       (64-bit integers)
 *      f     = lo + ((hz_hash3(pixel, index, seed ^ 0x3c6ef372) * (hi - lo)) >> 32)
 */
#ifndef HZ_TIMESEQ_H
#define HZ_TIMESEQ_H

#include <stdint.h>

uint32_t hz_timeseq_stratum(uint32_t pixel, uint32_t index, uint32_t count, uint32_t seed);
uint32_t hz_timeseq_u32(uint32_t pixel, uint32_t index, uint32_t count, uint32_t seed);

#endif /* HZ_TIMESEQ_H */
