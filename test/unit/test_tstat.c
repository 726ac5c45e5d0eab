/* Timing statistics: 128-bit helpers, sort/select, nearest-rank percentiles, mean/SD, histogram. */
#include "hz_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/timing/wide.h"
#include "hz/hash.h"
#include "hz/tstat.h"

/* The reference: the compiler's own 128-bit type (test code only; the core must not need libgcc). */
__extension__ typedef unsigned __int128 ref_u128;

static void test_u128_mul_div(void **state)
{
    (void)state;
    hz_u128_t p = hz_u128_mul(UINT64_MAX, UINT64_MAX); /* (2^64-1)^2 = 2^128 - 2^65 + 1 */
    assert_true(p.hi == UINT64_MAX - 1 && p.lo == 1);
    hz_rng_t r;
    hz_rng_seed(&r, 7, 1);
    for (int i = 0; i < 20000; i++) {
        uint64_t a = ((uint64_t)hz_rng_u32(&r) << 32 | hz_rng_u32(&r)) >> (hz_rng_u32(&r) % 64);
        uint64_t b = ((uint64_t)hz_rng_u32(&r) << 32 | hz_rng_u32(&r)) >> (hz_rng_u32(&r) % 64);
        uint64_t d = ((uint64_t)hz_rng_u32(&r) << 32 | hz_rng_u32(&r)) >> (hz_rng_u32(&r) % 64);
        ref_u128 ref = (ref_u128)a * b;
        hz_u128_t m = hz_u128_mul(a, b);
        assert_true(m.hi == (uint64_t)(ref >> 64) && m.lo == (uint64_t)ref);
        if (d == 0)
            continue;
        uint64_t rem = 0;
        uint64_t q = hz_u128_div(m, d, &rem);
        if ((ref / d) >> 64)
            assert_true(q == UINT64_MAX);
        else
            assert_true(q == (uint64_t)(ref / d) && rem == (uint64_t)(ref % d));
    }
}

static void test_muldiv_rounds_and_saturates(void **state)
{
    (void)state;
    assert_int_equal(hz_muldiv(7, 1, 2), 4);   /* 3.5 -> 4 */
    assert_int_equal(hz_muldiv(-7, 1, 2), -4); /* half away from zero */
    assert_int_equal(hz_muldiv(10, 3, -4), -8); /* -7.5 -> -8 */
    assert_int_equal(hz_muldiv(INT64_MAX, INT64_MAX, 1), INT64_MAX);
    assert_int_equal(hz_muldiv(INT64_MIN, 2, 1), -INT64_MAX);
    assert_int_equal(hz_muldiv(5, 5, 0), INT64_MAX);
    assert_int_equal(hz_muldiv(0, 5, 0), 0);
    /* 1e9 * 65536 / 240 Hz: the Q16 period of 240 Hz. */
    assert_int_equal(hz_muldiv(1000000000, 65536, 240), 273066666667ll);
    assert_int_equal(hz_mul_q16(3, 65536 + 32768), 5);  /* 4.5 -> 5 */
    assert_int_equal(hz_mul_q16(-3, 65536 + 32768), -5);
    assert_int_equal(hz_mul_q16(INT64_MAX, INT64_MAX), INT64_MAX);
}

static int cmp64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return x < y ? -1 : x > y;
}

static void test_sort_and_select_match_qsort(void **state)
{
    (void)state;
    static int64_t a[3000], b[3000], c[3000];
    hz_rng_t r;
    hz_rng_seed(&r, 3, 9);
    for (int round = 0; round < 40; round++) {
        size_t n = 1 + hz_rng_below(&r, 3000);
        uint32_t range = round % 3 == 0 ? 5 : 0xffffffffu; /* many ties, or few */
        for (size_t i = 0; i < n; i++)
            a[i] = (int64_t)(range == 5 ? hz_rng_below(&r, 5) : hz_rng_u32(&r)) - 100;
        if (round == 7)
            for (size_t i = 0; i < n; i++)
                a[i] = (int64_t)i; /* sorted input */
        if (round == 8)
            for (size_t i = 0; i < n; i++)
                a[i] = -(int64_t)i;
        memcpy(b, a, n * sizeof *a);
        qsort(b, n, sizeof *b, cmp64);
        memcpy(c, a, n * sizeof *a);
        hz_sort_i64(c, n);
        assert_memory_equal(b, c, n * sizeof *a);
        size_t k = hz_rng_below(&r, (uint32_t)n);
        memcpy(c, a, n * sizeof *a);
        assert_true(hz_select_i64(c, n, k) == b[k]);
    }
}

static void test_dist_nearest_rank(void **state)
{
    (void)state;
    int64_t v[1000];
    for (int i = 0; i < 1000; i++)
        v[i] = 1000 - i; /* 1..1000 reversed */
    hz_dist_t d;
    hz_dist_compute(v, 1000, &d);
    assert_int_equal(d.n, 1000);
    assert_int_equal(d.min, 1);
    assert_int_equal(d.max, 1000);
    assert_int_equal(d.p50, 500);  /* rank ceil(0.5 * 1000) = 500 */
    assert_int_equal(d.p90, 900);
    assert_int_equal(d.p99, 990);
    assert_int_equal(d.p999, 999);
    assert_int_equal(d.mean, 501); /* 500.5 rounds up */
    /* population SD of 1..1000 = sqrt((1000^2 - 1) / 12) = 288.67 */
    assert_int_equal(d.sd, 288);
    int64_t three[3] = { 10, 30, 20 };
    hz_dist_compute(three, 3, &d);
    assert_int_equal(d.p50, 20);
    assert_int_equal(d.p999, 30); /* rank ceil(2.997) = 3 */
    assert_int_equal(d.mean, 20);
    assert_int_equal(d.sd, 8); /* sqrt(200/3) = 8.16 */
    hz_dist_compute(three, 0, &d);
    assert_int_equal(d.n, 0);
}

static void test_dist_no_overflow(void **state)
{
    (void)state;
    /* Values near +-2^62: sums and squares overflow 64 bits, the 128-bit accumulators do not. */
    int64_t v[4] = { 4611686018427387904ll, -4611686018427387904ll, 4611686018427387904ll,
                     -4611686018427387904ll };
    hz_dist_t d;
    hz_dist_compute(v, 4, &d);
    assert_int_equal(d.mean, 0);
    assert_true(d.sd == 4611686018427387904ll);
}

static void test_dist_sd_matches_double(void **state)
{
    (void)state;
    static int64_t v[5000];
    hz_rng_t r;
    hz_rng_seed(&r, 11, 2);
    double s = 0, ss = 0;
    for (int i = 0; i < 5000; i++) {
        v[i] = 4000000 + (int64_t)hz_rng_below(&r, 100000);
        s += (double)v[i];
    }
    double mean = s / 5000;
    for (int i = 0; i < 5000; i++)
        ss += ((double)v[i] - mean) * ((double)v[i] - mean);
    hz_dist_t d;
    hz_dist_compute(v, 5000, &d);
    assert_true(llabs(d.mean - (int64_t)llround(mean)) <= 1);
    assert_true(fabs((double)d.sd - sqrt(ss / 5000)) <= 1.0);
}

static void test_histogram_counts_everything(void **state)
{
    (void)state;
    static hz_hist_t h;
    hz_error_t err;
    assert_int_equal(hz_hist_init(&h, 0, 0, 10, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "bin width"));
    assert_int_equal(hz_hist_init(&h, 0, 10, HZ_HIST_BINS_MAX + 1, &err), HZ_E_INVALID_ARG);
    assert_int_equal(hz_hist_init(&h, 100, 10, 5, &err), HZ_OK);
    int64_t vals[] = { 99, 100, 109, 110, 149, 150, INT64_MAX, INT64_MIN };
    for (size_t i = 0; i < sizeof vals / sizeof vals[0]; i++)
        hz_hist_add(&h, vals[i]);
    assert_int_equal(h.n, 8);
    assert_int_equal(h.below, 2);
    assert_int_equal(h.above, 2);
    assert_int_equal(h.count[0], 2);
    assert_int_equal(h.count[1], 1);
    assert_int_equal(h.count[4], 1);
    uint64_t sum = h.below + h.above;
    for (uint32_t i = 0; i < h.nbins; i++)
        sum += h.count[i];
    assert_int_equal(sum, h.n);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_u128_mul_div),
        cmocka_unit_test(test_muldiv_rounds_and_saturates),
        cmocka_unit_test(test_sort_and_select_match_qsort),
        cmocka_unit_test(test_dist_nearest_rank),
        cmocka_unit_test(test_dist_no_overflow),
        cmocka_unit_test(test_dist_sd_matches_double),
        cmocka_unit_test(test_histogram_counts_everything),
    };
    return HZ_RUN(tests);
}
