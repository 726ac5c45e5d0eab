/* Integer hash and RNG: published test vectors and golden sweeps, so x86-64 and AArch64 are held to the
 * same bits. The golden values were computed by an independent Python implementation of the same
 * algorithms (MurmurHash3 fmix32, the Jarzynski-Olano PCG hash, PCG32 pcg32_srandom_r). */
#include "hz_test.h"

#include "hz/hash.h"

static void test_fmix32_vectors(void **state)
{
    (void)state;
    assert_int_equal(hz_hash32(0), 0x0u);
    assert_int_equal(hz_hash32(1), 0x514e28b7u);
    assert_int_equal(hz_hash32(2), 0x30f4c306u);
    assert_int_equal(hz_hash32(0xdeadbeefu), 0x0de5c6a9u);
    assert_int_equal(hz_hash32(0xffffffffu), 0x81f16f39u);
}

static void test_pcg_hash_vectors(void **state)
{
    (void)state;
    assert_int_equal(hz_hash_pcg(0), 0x07bb2fe2u);
    assert_int_equal(hz_hash_pcg(1), 0xa8beea3cu);
    assert_int_equal(hz_hash_pcg(2), 0x7a7ecc88u);
    assert_int_equal(hz_hash_pcg(0xdeadbeefu), 0x67299972u);
    assert_int_equal(hz_hash_pcg(0xffffffffu), 0xe62a4902u);
}

static void test_golden_sweeps(void **state)
{
    (void)state;
    uint32_t a = 0, b = 0, c = 0;
    for (uint32_t i = 0; i < (1u << 16); i++) {
        a = a * 31u + hz_hash32(i);
        b = b * 31u + hz_hash_pcg(i);
    }
    for (uint32_t y = 0; y < 64; y++)
        for (uint32_t x = 0; x < 64; x++)
            c = c * 31u + hz_hash3(x, y, 7);
    assert_int_equal(a, 0xa425c103u);
    assert_int_equal(b, 0x24b99effu);
    assert_int_equal(c, 0xa701e534u);
    /* Combination is order-dependent. */
    assert_int_equal(hz_hash2(3, 4), 0x71c90859u);
    assert_int_equal(hz_hash2(4, 3), 0x10b6d6edu);
}

static void test_pcg32_reference_sequence(void **state)
{
    (void)state;
    /* pcg32-demo's first round for seed 42, sequence 54. */
    const uint32_t expect[6] = { 0xa15c02b7u, 0x7b47f409u, 0xba1d3330u, 0x83d2f293u, 0xbfa4784bu, 0xcbed606eu };
    hz_rng_t r;
    hz_rng_seed(&r, 42u, 54u);
    for (int i = 0; i < 6; i++)
        assert_int_equal(hz_rng_u32(&r), expect[i]);
}

static void test_streams_differ(void **state)
{
    (void)state;
    hz_rng_t a, b;
    hz_rng_seed(&a, 7, 1);
    hz_rng_seed(&b, 7, 2);
    int same = 0;
    for (int i = 0; i < 64; i++)
        same += hz_rng_u32(&a) == hz_rng_u32(&b);
    assert_true(same < 2);
}

static void test_below_is_bounded_and_uniform(void **state)
{
    (void)state;
    hz_rng_t r;
    hz_rng_seed(&r, 1, 1);
    assert_int_equal(hz_rng_below(&r, 0), 0);
    assert_int_equal(hz_rng_below(&r, 1), 0);
    /* Chi-square over 6 buckets, 60000 draws: 5 degrees of freedom, 99.99% quantile is 25.7. */
    unsigned counts[6] = { 0 };
    for (int i = 0; i < 60000; i++) {
        uint32_t v = hz_rng_below(&r, 6);
        assert_true(v < 6);
        counts[v]++;
    }
    double chi2 = 0;
    for (int k = 0; k < 6; k++)
        chi2 += (counts[k] - 10000.0) * (counts[k] - 10000.0) / 10000.0;
    assert_true(chi2 < 25.7);
    /* A bound just above 2^31 is where modulo bias would be worst: half the values would be twice as likely.
     * Count how many land in the lower half of the range. */
    const uint32_t n = 0x80000001u;
    int low = 0;
    for (int i = 0; i < 20000; i++)
        low += hz_rng_below(&r, n) < n / 2;
    assert_true(low > 9500 && low < 10500); /* biased modulo would give ~13333 */
}

static void test_avalanche(void **state)
{
    (void)state;
    /* Flipping one input bit flips about half of the output bits, for every input bit. */
    for (int bit = 0; bit < 32; bit++) {
        long flips = 0;
        for (uint32_t x = 0; x < 4096; x++) {
            uint32_t v = x * 2654435761u;
            flips += __builtin_popcount(hz_hash32(v) ^ hz_hash32(v ^ (1u << bit)));
        }
        double mean = flips / 4096.0;
        assert_true(mean > 15.0 && mean < 17.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fmix32_vectors),
        cmocka_unit_test(test_pcg_hash_vectors),
        cmocka_unit_test(test_golden_sweeps),
        cmocka_unit_test(test_pcg32_reference_sequence),
        cmocka_unit_test(test_streams_differ),
        cmocka_unit_test(test_below_is_bounded_and_uniform),
        cmocka_unit_test(test_avalanche),
    };
    return HZ_RUN(tests);
}
