/* Q16.16 fixed point and integer square root: exact against wide arithmetic, saturation at the edges. */
#include "hz_test.h"

#include "hz/fixed.h"
#include "hz/hash.h"

/* Reference: round(a * b / 2^16) with ties away from zero, in 128-bit-safe integer math. */
static int64_t ref_mul(int32_t a, int32_t b)
{
    int64_t p = (int64_t)a * b;
    int64_t m = p < 0 ? -p : p;
    int64_t q = (m + 32768) / 65536;
    return p < 0 ? -q : q;
}

static hz_q16_t sat(int64_t v)
{
    return v > INT32_MAX ? INT32_MAX : v < INT32_MIN ? INT32_MIN : (hz_q16_t)v;
}

static void test_mul_matches_reference(void **state)
{
    (void)state;
    hz_rng_t r;
    hz_rng_seed(&r, 3, 3);
    for (int i = 0; i < 200000; i++) {
        int32_t a = (int32_t)hz_rng_u32(&r) >> (hz_rng_u32(&r) & 31);
        int32_t b = (int32_t)hz_rng_u32(&r) >> (hz_rng_u32(&r) & 31);
        assert_int_equal(hz_q16_mul(a, b), sat(ref_mul(a, b)));
    }
    assert_int_equal(hz_q16_mul(HZ_Q16_ONE, HZ_Q16_ONE), HZ_Q16_ONE);
    assert_int_equal(hz_q16_mul(HZ_Q16_HALF, 3 * HZ_Q16_ONE), 3 * HZ_Q16_HALF);
    assert_int_equal(hz_q16_mul(-HZ_Q16_ONE, HZ_Q16_HALF), -HZ_Q16_HALF);
    /* Ties round away from zero: 1/2^16 * 1/2 = half an ulp. */
    assert_int_equal(hz_q16_mul(1, HZ_Q16_HALF), 1);
    assert_int_equal(hz_q16_mul(-1, HZ_Q16_HALF), -1);
    /* Saturation instead of wrap-around. */
    assert_int_equal(hz_q16_mul(HZ_Q16_MAX, HZ_Q16_MAX), HZ_Q16_MAX);
    assert_int_equal(hz_q16_mul(HZ_Q16_MIN, HZ_Q16_MAX), HZ_Q16_MIN);
    assert_int_equal(hz_q16_mul(HZ_Q16_MIN, HZ_Q16_MIN), HZ_Q16_MAX);
}

static void test_div(void **state)
{
    (void)state;
    assert_int_equal(hz_q16_div(HZ_Q16_ONE, 2 * HZ_Q16_ONE), HZ_Q16_HALF);
    assert_int_equal(hz_q16_div(-3 * HZ_Q16_ONE, 2 * HZ_Q16_ONE), -3 * HZ_Q16_HALF);
    assert_int_equal(hz_q16_div(HZ_Q16_ONE, 3 * HZ_Q16_ONE), 21845); /* 0.33333 rounds down */
    assert_int_equal(hz_q16_div(2 * HZ_Q16_ONE, 3 * HZ_Q16_ONE), 43691); /* 0.66667 rounds up */
    assert_int_equal(hz_q16_div(5, 0), HZ_Q16_MAX);
    assert_int_equal(hz_q16_div(-5, 0), HZ_Q16_MIN);
    assert_int_equal(hz_q16_div(0, 0), 0);
    assert_int_equal(hz_q16_div(HZ_Q16_MAX, 1), HZ_Q16_MAX);
    assert_int_equal(hz_q16_div(HZ_Q16_MIN, 1), HZ_Q16_MIN);
    assert_int_equal(hz_q16_div(HZ_Q16_MIN, -1), HZ_Q16_MAX);
    assert_int_equal(hz_q16_div(HZ_Q16_ONE, HZ_Q16_MIN), -2); /* 1 / -32768 = -2^-15 */
    /* Round trip: (a / b) * b stays within one ulp times |b| of a. */
    hz_rng_t r;
    hz_rng_seed(&r, 9, 9);
    for (int i = 0; i < 100000; i++) {
        int32_t a = (int32_t)(hz_rng_u32(&r) >> 8) - (1 << 23);
        int32_t b = (int32_t)(hz_rng_u32(&r) >> 12) + HZ_Q16_ONE;
        int64_t back = ((int64_t)hz_q16_div(a, b) * b) >> 16;
        int64_t d = back - a;
        assert_true(d >= -(b >> 16) - 2 && d <= (b >> 16) + 2);
    }
}

static void test_floor_and_frac(void **state)
{
    (void)state;
    assert_int_equal(hz_q16_floor_int(HZ_Q16_ONE + 1), 1);
    assert_int_equal(hz_q16_floor_int(-1), -1);
    assert_int_equal(hz_q16_floor_int(-HZ_Q16_ONE), -1);
    assert_int_equal(hz_q16_floor_int(-HZ_Q16_ONE - 1), -2);
    assert_int_equal(hz_q16_floor_int(HZ_Q16_MIN), -32768);
    assert_int_equal(hz_q16_floor_int(HZ_Q16_MAX), 32767);
    assert_int_equal(hz_q16_frac(-HZ_Q16_HALF / 2), 3 * HZ_Q16_ONE / 4); /* -0.25 -> 0.75 */
    assert_int_equal(hz_q16_frac(5 * HZ_Q16_ONE + 7), 7);
    for (int32_t q = -300000; q < 300000; q += 997)
        assert_int_equal((int64_t)hz_q16_floor_int(q) * HZ_Q16_ONE + hz_q16_frac(q), q);
    assert_int_equal(hz_q16_from_int(3), 3 * HZ_Q16_ONE);
    assert_int_equal(hz_q16_from_int(40000), HZ_Q16_MAX);
    assert_int_equal(hz_q16_from_int(-40000), HZ_Q16_MIN);
    assert_int_equal(hz_q16_abs(HZ_Q16_MIN), HZ_Q16_MAX);
    assert_int_equal(hz_q16_add(HZ_Q16_MAX, 1), HZ_Q16_MAX);
    assert_int_equal(hz_q16_sub(HZ_Q16_MIN, 1), HZ_Q16_MIN);
}

static void test_isqrt_exact(void **state)
{
    (void)state;
    assert_int_equal(hz_isqrt_u64(0), 0);
    assert_int_equal(hz_isqrt_u64(1), 1);
    assert_int_equal(hz_isqrt_u64(3), 1);
    assert_int_equal(hz_isqrt_u64(4), 2);
    assert_int_equal(hz_isqrt_u64(UINT64_MAX), 0xffffffffu);
    assert_int_equal(hz_isqrt_u64(0xfffffffe00000001ull), 0xffffffffu);     /* (2^32-1)^2 */
    assert_int_equal(hz_isqrt_u64(0xfffffffe00000000ull), 0xfffffffeu);     /* one below */
    hz_rng_t r;
    hz_rng_seed(&r, 5, 5);
    for (int i = 0; i < 200000; i++) {
        uint64_t x = ((uint64_t)hz_rng_u32(&r) << 32 | hz_rng_u32(&r)) >> (hz_rng_u32(&r) & 63);
        uint64_t s = hz_isqrt_u64(x);
        assert_true(s * s <= x);
        assert_true((s + 1) * (s + 1) > x || s == 0xffffffffu);
    }
    assert_int_equal(hz_q16_sqrt(4 * HZ_Q16_ONE), 2 * HZ_Q16_ONE);
    assert_int_equal(hz_q16_sqrt(HZ_Q16_ONE / 4), HZ_Q16_ONE / 2);
    assert_int_equal(hz_q16_sqrt(-5), 0);
    assert_int_equal(hz_q16_sqrt(2 * HZ_Q16_ONE), 92681); /* floor(sqrt(2) * 65536) */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mul_matches_reference),
        cmocka_unit_test(test_div),
        cmocka_unit_test(test_floor_and_frac),
        cmocka_unit_test(test_isqrt_exact),
    };
    return HZ_RUN(tests);
}
