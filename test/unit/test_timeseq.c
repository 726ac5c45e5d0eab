/* Stratified shutter times (src/pattern/timeseq.h): every pixel's samples cover each stratum exactly once and lie inside
 * it, and golden values that x86-64 and AArch64 (under qemu) must both reproduce. The golden values come from an
 * independent Python model of the definition in src/pattern/timeseq.h: tools/gen/timeseq_golden.py. */
#include "hz_test.h"

#include <string.h>

#include "../../src/pattern/timeseq.h"

static void test_strata_are_a_permutation(void **state)
{
    (void)state;
    static unsigned char seen[1024];
    const uint32_t counts[] = { 1, 2, 3, 4, 9, 16, 25, 64, 100, 256, 1000, 1024 };
    for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++) {
        uint32_t n = counts[c];
        for (uint32_t pixel = 0; pixel < 50; pixel++) {
            memset(seen, 0, sizeof seen);
            for (uint32_t i = 0; i < n; i++) {
                uint32_t s = hz_timeseq_stratum(pixel * 7919u, i, n, 3);
                assert_true(s < n);
                assert_int_equal(seen[s], 0);
                seen[s] = 1;
                /* f lies in [ceil(s 2^32 / n), ceil((s + 1) 2^32 / n)) */
                uint64_t f = hz_timeseq_u32(pixel * 7919u, i, n, 3);
                uint64_t lo = (((uint64_t)s << 32) + n - 1) / n, hi = (((uint64_t)(s + 1) << 32) + n - 1) / n;
                assert_true(f >= lo && f < hi);
            }
        }
    }
}

static void test_shuffles_differ_between_pixels(void **state)
{
    (void)state;
    /* 16 samples: the first sample's stratum takes many values over pixels (not always the same stratum). */
    unsigned char seen[16] = { 0 };
    int distinct = 0;
    for (uint32_t p = 0; p < 256; p++) {
        uint32_t s = hz_timeseq_stratum(p, 0, 16, 0);
        distinct += !seen[s];
        seen[s] = 1;
    }
    assert_true(distinct >= 12);
    /* index wraps, count 0 is 1 */
    assert_int_equal(hz_timeseq_u32(5, 17, 16, 1), hz_timeseq_u32(5, 1, 16, 1));
    assert_int_equal(hz_timeseq_u32(5, 3, 0, 1), hz_timeseq_u32(5, 0, 1, 1));
}

static void test_golden_sweep(void **state)
{
    (void)state;
    assert_int_equal(hz_timeseq_u32(0, 0, 1, 0), 0x9ce269fcu);
    assert_int_equal(hz_timeseq_u32(12345, 3, 16, 7), 0x41223fe2u);
    const uint32_t counts[] = { 1, 2, 4, 9, 16, 64, 256, 1000 };
    uint32_t h = 0;
    for (uint32_t seed = 0; seed <= 7; seed += 7)
        for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++)
            for (uint32_t pixel = 0; pixel < 300; pixel++)
                for (uint32_t i = 0; i < (counts[c] <= 16 ? counts[c] : 16); i++)
                    h = h * 31u + hz_timeseq_u32(pixel * 2654435761u, i, counts[c], seed);
    assert_int_equal(h, 0x5219c31fu);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_strata_are_a_permutation),
        cmocka_unit_test(test_shuffles_differ_between_pixels),
        cmocka_unit_test(test_golden_sweep),
    };
    return HZ_RUN(tests);
}
