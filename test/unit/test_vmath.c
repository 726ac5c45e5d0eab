/* vec3/mat4 and the libm-free scalar functions: accuracy against the C library, exactness where promised,
 * stability on degenerate and extreme inputs, and a golden sweep that holds x86-64 and AArch64 to the same
 * bits. */
#include "hz_test.h"

#include <math.h>
#include <string.h>

#include "hz/hash.h"
#include "hz/vmath.h"

/* Produced by this test on x86-64 (see test_golden_bits). */
#define HZ_VMATH_GOLDEN 0x2e2f783eu

static int32_t ulp_distance(float a, float b)
{
    int32_t ia, ib;
    memcpy(&ia, &a, 4);
    memcpy(&ib, &b, 4);
    if (ia < 0) ia = INT32_MIN - ia;
    if (ib < 0) ib = INT32_MIN - ib;
    int64_t d = (int64_t)ia - ib;
    return (int32_t)(d < 0 ? -d : d);
}

static void test_sincos_accuracy(void **state)
{
    (void)state;
    hz_rng_t r;
    hz_rng_seed(&r, 11, 0);
    int32_t worst = 0;
    for (int i = 0; i < 400000; i++) {
        float x = (hz_u32_to_unit(hz_rng_u32(&r)) * 2.0f - 1.0f) * (i < 200000 ? 8.0f : 1e5f);
        float s, c;
        hz_sincosf(x, &s, &c);
        /* Reference in double, rounded once: the correctly rounded float result (nearly always). */
        float rs = (float)sin((double)x), rc = (float)cos((double)x);
        int32_t d = ulp_distance(s, rs);
        int32_t e = ulp_distance(c, rc);
        if (d > worst) worst = d;
        if (e > worst) worst = e;
    }
    assert_true(worst <= 2);
    assert_true(hz_sinf(0.0f) == 0.0f);
    assert_true(hz_cosf(0.0f) == 1.0f);
    assert_true(fabsf(hz_tanf(HZ_PI / 4) - 1.0f) < 1e-6f);
    assert_true(isnan(hz_sinf(INFINITY)));
    assert_true(isnan(hz_cosf(NAN)));
}

/* Found by the .hzb fuzzer: an oscillating object whose frequency and phase put -2.3e36 into hz_sinf (a float of
 * that size is legal in a scene). The quadrant's conversion to long overflowed (UBSan: outside the range of
 * long); sin and cos of any finite float must come back finite and on the unit circle. */
static void test_sincos_of_fuzzed_oscillation_phase(void **state)
{
    (void)state;
    static const float xs[] = { -2.32591e36f, 2.32591e36f, 4.6116860e18f, 9.3e18f, -1.7e38f, 3.4028235e38f };
    for (size_t i = 0; i < sizeof xs / sizeof xs[0]; i++) {
        float s, c;
        hz_sincosf(xs[i], &s, &c);
        assert_true(hz_isfinitef(s) && hz_isfinitef(c));
        assert_true(hz_absf(s * s + c * c - 1.0f) < 1e-5f);
        assert_true(hz_sinf(xs[i]) == s && hz_cosf(xs[i]) == c);
    }
}

/* Equal as bits: a zero's sign counts. */
static int same_bits(float a, float b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static void test_floor(void **state)
{
    (void)state;
    const float cases[] = { 0.0f, -0.0f, 0.5f, -0.5f, 1.0f, -1.0f, 1.5f, -1.5f, 2.999999f, -2.999999f,
                            8388607.5f, -8388607.5f, 8388608.0f, 1e30f, -1e30f, 1e-30f, -1e-30f };
    for (size_t i = 0; i < HZ_ARRAY_LEN(cases); i++) {
        assert_true(same_bits(hz_floorf(cases[i]), floorf(cases[i])));
        assert_true(same_bits(hz_floorf_soft(cases[i]), floorf(cases[i])));
    }
    assert_true(isinf(hz_floorf(INFINITY)) && isinf(hz_floorf(-INFINITY)));
    assert_true(isinf(hz_floorf_soft(INFINITY)) && isinf(hz_floorf_soft(-INFINITY)));
    assert_true(isnan(hz_floorf(NAN)) && isnan(hz_floorf_soft(NAN)));
    hz_rng_t r;
    hz_rng_seed(&r, 12, 0);
    for (int i = 0; i < 100000; i++) {
        uint32_t bits = hz_rng_u32(&r);
        float f;
        memcpy(&f, &bits, 4);
        if (isnan(f))
            continue;
        assert_true(same_bits(hz_floorf(f), floorf(f)));
        assert_true(same_bits(hz_floorf_soft(f), floorf(f)));
    }
}

static void test_q16_from_float(void **state)
{
    (void)state;
    assert_int_equal(hz_q16_from_float(1.0f), HZ_Q16_ONE);
    assert_int_equal(hz_q16_from_float(-0.5f), -HZ_Q16_HALF);
    assert_int_equal(hz_q16_from_float(1.0f / 131072.0f), 1);   /* half an ulp: away from zero */
    assert_int_equal(hz_q16_from_float(-1.0f / 131072.0f), -1);
    assert_int_equal(hz_q16_from_float(1e9f), HZ_Q16_MAX);
    assert_int_equal(hz_q16_from_float(-1e9f), HZ_Q16_MIN);
    assert_int_equal(hz_q16_from_float(INFINITY), HZ_Q16_MAX);
    assert_int_equal(hz_q16_from_float(NAN), 0);
    assert_true(hz_q16_to_float(HZ_Q16_HALF) == 0.5f);
}

static void test_vec3(void **state)
{
    (void)state;
    hz_vec3_t a = hz_v3(1, 2, 3), b = hz_v3(-4, 5, 0.5f);
    hz_vec3_t c = hz_v3_cross(a, b);
    assert_true(hz_v3_dot(c, a) == 0.0f && hz_v3_dot(c, b) == 0.0f);
    hz_vec3_t n = hz_v3_normalize(a);
    assert_true(fabsf(hz_v3_len(n) - 1.0f) < 1e-6f);
    /* Degenerate and extreme inputs never give NaN. */
    hz_vec3_t z = hz_v3_normalize(hz_v3(0, 0, 0));
    assert_true(z.x == 0 && z.y == 0 && z.z == 0);
    z = hz_v3_normalize(hz_v3(NAN, 1, 1));
    assert_true(z.x == 0 && z.y == 0 && z.z == 0);
    hz_vec3_t big = hz_v3_normalize(hz_v3(3e38f, 3e38f, 0)); /* the squared length overflows */
    assert_true(fabsf(big.x - 0.70710678f) < 1e-6f && fabsf(big.y - 0.70710678f) < 1e-6f);
    hz_vec3_t tiny = hz_v3_normalize(hz_v3(1e-30f, 0, 0)); /* the squared length underflows to 0 */
    assert_true(fabsf(tiny.x - 1.0f) < 1e-6f);
    hz_vec3_t sub = hz_v3_normalize(hz_v3(1e-44f, 0, 0)); /* subnormal */
    assert_true(hz_isfinitef(sub.x));
}

static void assert_identity(const hz_mat4_t *m, float tol)
{
    for (int i = 0; i < 16; i++) {
        float expect = (i % 5 == 0) ? 1.0f : 0.0f;
        assert_true(fabsf(m->m[i] - expect) <= tol);
    }
}

static void test_mat4_inverse(void **state)
{
    (void)state;
    hz_rng_t r;
    hz_rng_seed(&r, 13, 0);
    for (int i = 0; i < 1000; i++) {
        hz_mat4_t rot = hz_mat4_rotate(hz_v3(hz_u32_to_unit(hz_rng_u32(&r)) - 0.5f, 1.0f, 0.3f),
                                       hz_u32_to_unit(hz_rng_u32(&r)) * 6.0f);
        hz_mat4_t sc = hz_mat4_scale(hz_v3(0.5f + hz_u32_to_unit(hz_rng_u32(&r)), 2.0f, 0.25f));
        hz_mat4_t tr = hz_mat4_translate(hz_v3(10.0f * hz_u32_to_unit(hz_rng_u32(&r)), -3.0f, 7.0f));
        hz_mat4_t rs = hz_mat4_mul(&rot, &sc);
        hz_mat4_t m = hz_mat4_mul(&tr, &rs);
        hz_mat4_t inv;
        assert_int_equal(hz_mat4_inverse(&m, &inv), HZ_OK);
        hz_mat4_t id = hz_mat4_mul(&m, &inv);
        assert_identity(&id, 2e-5f);
    }
    /* Singular and non-finite matrices are reported, not inverted. */
    hz_mat4_t s = hz_mat4_scale(hz_v3(1, 0, 1));
    hz_mat4_t out;
    assert_int_equal(hz_mat4_inverse(&s, &out), HZ_E_RANGE);
    hz_mat4_t nearly = hz_mat4_identity();
    nearly.m[1] = 1e-9f; /* column 0 = (1, 1e-9, 0, 0) */
    nearly.m[4] = 1.0f;  /* column 1 = (1, 2e-9, 0, 0): dependent on column 0 within float precision */
    nearly.m[5] = 2e-9f;
    assert_int_equal(hz_mat4_inverse(&nearly, &out), HZ_E_RANGE);
    hz_mat4_t nan = hz_mat4_identity();
    nan.m[7] = NAN;
    assert_int_equal(hz_mat4_inverse(&nan, &out), HZ_E_RANGE);
    /* Tiny and huge uniform scales are regular matrices (scenes scaled by 1e-6 and 1e6). */
    for (float k = 1e-6f; k <= 1e6f; k *= 1e3f) {
        hz_mat4_t m = hz_mat4_scale(hz_v3(k, k, k));
        m.m[12] = 3.0f * k;
        assert_int_equal(hz_mat4_inverse(&m, &out), HZ_OK);
        hz_mat4_t id = hz_mat4_mul(&m, &out);
        assert_identity(&id, 1e-5f);
    }
}

static void test_transforms(void **state)
{
    (void)state;
    hz_mat4_t r = hz_mat4_rotate(hz_v3(0, 0, 1), HZ_PI / 2);
    hz_vec3_t p = hz_mat4_mul_point(&r, hz_v3(1, 0, 0));
    assert_true(fabsf(p.x) < 1e-6f && fabsf(p.y - 1.0f) < 1e-6f); /* right-handed: x -> y */
    hz_mat4_t t = hz_mat4_translate(hz_v3(1, 2, 3));
    hz_vec3_t d = hz_mat4_mul_dir(&t, hz_v3(1, 0, 0));
    assert_true(d.x == 1 && d.y == 0 && d.z == 0); /* directions ignore translation */
    hz_mat4_t zero_axis = hz_mat4_rotate(hz_v3(0, 0, 0), 1.0f);
    assert_identity(&zero_axis, 0.0f);
    /* look_at: the camera's -z points at the target; a vertical view with up = +y stays finite. */
    hz_mat4_t cam = hz_mat4_look_at(hz_v3(0, 0, 5), hz_v3(0, 0, 0), hz_v3(0, 1, 0));
    hz_vec3_t fwd = hz_mat4_mul_dir(&cam, hz_v3(0, 0, -1));
    assert_true(fabsf(fwd.z + 1.0f) < 1e-6f);
    hz_mat4_t down = hz_mat4_look_at(hz_v3(0, 5, 0), hz_v3(0, 0, 0), hz_v3(0, 1, 0));
    for (int i = 0; i < 16; i++)
        assert_true(hz_isfinitef(down.m[i]));
    hz_vec3_t dfwd = hz_mat4_mul_dir(&down, hz_v3(0, 0, -1));
    assert_true(fabsf(dfwd.y + 1.0f) < 1e-6f);
    /* Projection: a point on the near plane maps to ndc z = -1, on the far plane to +1. */
    hz_mat4_t proj = hz_mat4_perspective(HZ_PI / 3, 16.0f / 9.0f, 0.1f, 100.0f);
    hz_vec3_t ndc;
    float w = hz_mat4_mul_point_h(&proj, hz_v3(0, 0, -0.1f), &ndc);
    assert_true(w > 0 && fabsf(ndc.z + 1.0f) < 1e-5f);
    hz_mat4_mul_point_h(&proj, hz_v3(0, 0, -100.0f), &ndc);
    assert_true(fabsf(ndc.z - 1.0f) < 1e-4f);
}

static void test_golden_bits(void **state)
{
    (void)state;
    /* Same bits on every ISA (-ffp-contract=off, no libm): hash the results of a sweep. The value was
     * produced on x86-64; the AArch64 run (qemu) must reproduce it. */
    uint32_t h = 0;
    for (int i = -5000; i < 5000; i++) {
        float x = (float)i * 0.01234f;
        float s, c;
        hz_sincosf(x, &s, &c);
        uint32_t bs, bc, bf;
        float f = hz_floorf(x * 3.3f);
        memcpy(&bs, &s, 4);
        memcpy(&bc, &c, 4);
        memcpy(&bf, &f, 4);
        h = hz_hash_combine(h, bs);
        h = hz_hash_combine(h, bc);
        h = hz_hash_combine(h, bf);
    }
    hz_mat4_t m = hz_mat4_look_at(hz_v3(1, 2, 3), hz_v3(-1, 0.5f, 2), hz_v3(0, 1, 0));
    hz_mat4_t inv;
    hz_mat4_inverse(&m, &inv);
    for (int i = 0; i < 16; i++) {
        uint32_t b;
        memcpy(&b, &inv.m[i], 4);
        h = hz_hash_combine(h, b);
    }
    print_message("vmath golden hash: 0x%08x\n", h);
    assert_int_equal(h, HZ_VMATH_GOLDEN);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sincos_accuracy),
        cmocka_unit_test(test_sincos_of_fuzzed_oscillation_phase),
        cmocka_unit_test(test_floor),
        cmocka_unit_test(test_q16_from_float),
        cmocka_unit_test(test_vec3),
        cmocka_unit_test(test_mat4_inverse),
        cmocka_unit_test(test_transforms),
        cmocka_unit_test(test_golden_bits),
    };
    return HZ_RUN(tests);
}
