/*
 * Images and exact sRGB 8-bit conversion: the committed tables against libm (long double), the bucket table's
 * invariant (which proves the one-compare encode exact for every float), special values, and allocation.
 */
#include "hz_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "hz/hash.h"
#include "hz/image.h"

static long double eotf(long double v)
{
    return v <= 0.04045L ? v / 12.92L : powl((v + 0.055L) / 1.055L, 2.4L);
}

/* The display code of x by definition: round(255 * OETF(clamp(x))). Double suffices: the generator made sure
 * no float lies within 1e-15 (relative) of a threshold, far more than double's evaluation error; long double
 * would be software quad precision on AArch64, too slow under qemu for 10^5 samples. */
static int reference_code(float x)
{
    if (!(x > 0.0f))
        return 0;
    if (x >= 1.0f)
        return 255;
    double v = 255.0 * (x <= 0.0031308f ? 12.92 * x : 1.055 * pow((double)x, 1.0 / 2.4) - 0.055);
    return (int)floor(v + 0.5);
}

static void test_decode_table_matches_libm(void **state)
{
    (void)state;
    for (int b = 0; b < 256; b++) {
        float want = (float)eotf((long double)b / 255.0L);
        assert_int_equal(hz_srgb8_decode_bits[b], hz_float_bits(want));
        assert_true(hz_srgb8_decode((uint8_t)b) == want);
    }
    assert_true(hz_srgb8_decode(0) == 0.0f);
    assert_true(hz_srgb8_decode(255) == 1.0f);
}

static void test_thresholds_bracket_the_exact_values(void **state)
{
    (void)state;
    for (int k = 0; k < 255; k++) {
        long double t = eotf(((long double)k + 0.5L) / 255.0L);
        float f = hz_float_from_bits(hz_srgb8_threshold_bits[k]);
        float below = nextafterf(f, 0.0f);
        assert_true((long double)below < t);
        assert_true(t <= (long double)f);
        if (k > 0)
            assert_true(hz_srgb8_threshold_bits[k] > hz_srgb8_threshold_bits[k - 1]);
    }
    assert_int_equal(hz_srgb8_threshold_bits[255], 0x7F800000u);
}

/* Every float in a bucket starts at the bucket's code and crosses at most one threshold inside it, whose low bits
 * the entry holds: so the one-compare encode is exact for every float in [2^-13, 1), without testing all 10^8 of
 * them. */
static void test_bucket_table_invariant(void **state)
{
    (void)state;
    assert_int_equal(HZ_SRGB8_LUT_SIZE, 1664);
    assert_true(hz_float_from_bits(HZ_SRGB8_LUT_BASE) == 0x1p-13f);
    assert_true(hz_srgb8_threshold_bits[0] > HZ_SRGB8_LUT_BASE);
    assert_int_equal(hz_srgb8_lut[0], 0x1000000u);                      /* zero, never one higher */
    assert_int_equal(hz_srgb8_lut[HZ_SRGB8_LUT_SIZE + 1], 0x10000ffu); /* 255, never one higher */
    assert_true(hz_srgb8_threshold_bits[254] < 0x3F800000u);           /* so everything >= 1.0 is 255 */
    for (uint32_t i = 0; i < HZ_SRGB8_LUT_SIZE; i++) {
        uint32_t lo = HZ_SRGB8_LUT_BASE + (i << HZ_SRGB8_LUT_SHIFT);
        uint32_t hi = lo + (1u << HZ_SRGB8_LUT_SHIFT) - 1;
        uint32_t below = 0, inside = 0, split = 0x10000;
        for (int k = 0; k < 255; k++) {
            if (hz_srgb8_threshold_bits[k] <= lo) {
                below++;
            } else if (hz_srgb8_threshold_bits[k] <= hi) {
                inside++;
                split = hz_srgb8_threshold_bits[k] & 0xffff;
            }
        }
        assert_int_equal(hz_srgb8_lut[i + 1] & 0xff, below);
        assert_true(inside <= 1);
        assert_int_equal(hz_srgb8_lut[i + 1] >> 8, split);
        assert_true(split > 0); /* a threshold at the bucket's first float would belong to the code below */
    }
}

static void test_round_trip_and_thresholds(void **state)
{
    (void)state;
    for (int b = 0; b < 256; b++)
        assert_int_equal(hz_srgb8_encode(hz_srgb8_decode((uint8_t)b)), b);
    for (int k = 0; k < 255; k++) {
        float t = hz_float_from_bits(hz_srgb8_threshold_bits[k]);
        assert_int_equal(hz_srgb8_encode(t), k + 1);
        assert_int_equal(hz_srgb8_encode(nextafterf(t, 0.0f)), k);
        assert_int_equal(hz_srgb8_encode(nextafterf(t, 2.0f)), k + 1);
        assert_int_equal(reference_code(t), k + 1);
        assert_int_equal(reference_code(nextafterf(t, 0.0f)), k);
    }
}

static void test_random_floats_match_definition(void **state)
{
    (void)state;
    hz_rng_t r;
    hz_rng_seed(&r, 7, 11);
    for (int i = 0; i < 400000; i++) {
        /* Uniform in bit patterns over [2^-16, 2) hits every exponent; uniform in value covers the bright end. */
        uint32_t bits = 0x37800000u + hz_rng_below(&r, 0x40000000u - 0x37800000u);
        float x = (i & 1) ? hz_float_from_bits(bits) : (float)hz_rng_u32(&r) * 0x1p-32f;
        assert_int_equal(hz_srgb8_encode(x), reference_code(x));
    }
}

static void test_special_values_stay_in_range(void **state)
{
    (void)state;
    assert_int_equal(hz_srgb8_encode(NAN), 0);
    assert_int_equal(hz_srgb8_encode(-NAN), 0);
    assert_int_equal(hz_srgb8_encode(hz_float_from_bits(0x7FC12345u)), 0); /* NaN with payload */
    assert_int_equal(hz_srgb8_encode(hz_float_from_bits(0xFF800001u)), 0); /* negative signalling NaN */
    assert_int_equal(hz_srgb8_encode(INFINITY), 255);
    assert_int_equal(hz_srgb8_encode(-INFINITY), 0);
    assert_int_equal(hz_srgb8_encode(0.0f), 0);
    assert_int_equal(hz_srgb8_encode(-0.0f), 0);
    assert_int_equal(hz_srgb8_encode(hz_float_from_bits(1)), 0); /* smallest denormal */
    assert_int_equal(hz_srgb8_encode(-1.0f), 0);
    assert_int_equal(hz_srgb8_encode(1.0f), 255);
    assert_int_equal(hz_srgb8_encode(nextafterf(1.0f, 0.0f)), 255);
    assert_int_equal(hz_srgb8_encode(1e30f), 255);
    assert_int_equal(hz_srgb8_encode(FLT_MAX), 255);
    assert_int_equal(hz_srgb8_encode(0.5f), reference_code(0.5f));
    assert_int_equal(hz_srgb8_encode(0.5f), 188); /* sRGB mid-grey: 0.5 linear displays as 188 */
    assert_int_equal(hz_srgb8_encode(0.18f), 118);
}

/* The SIMD encoder (AVX2 boards) against its scalar twin: every threshold and its neighbours, special values,
 * random bit patterns (every exponent, both signs, NaN payloads), at every tail length. */
static void test_simd_encode_matches_scalar(void **state)
{
    (void)state;
    static float v[4096 + 7];
    static uint8_t a[4096 + 7], b[4096 + 7];
    size_t n = 0;
    for (int k = 0; k < 255; k++) {
        float t = hz_float_from_bits(hz_srgb8_threshold_bits[k]);
        v[n++] = t;
        v[n++] = nextafterf(t, 0.0f);
        v[n++] = nextafterf(t, 2.0f);
    }
    const float special[] = { 0.0f, -0.0f, NAN, -NAN, INFINITY, -INFINITY, 1.0f, nextafterf(1.0f, 0.0f),
                              0x1p-13f, nextafterf(0x1p-13f, 0.0f), FLT_MIN, -FLT_MIN, FLT_MAX, -FLT_MAX,
                              hz_float_from_bits(1), hz_float_from_bits(0x7FC12345u), hz_float_from_bits(0xFF800001u),
                              hz_float_from_bits(0x7F800001u), 0.5f, -0.5f, 2.0f };
    for (size_t i = 0; i < HZ_ARRAY_LEN(special); i++)
        v[n++] = special[i];
    hz_rng_t r;
    hz_rng_seed(&r, 3, 4);
    while (n < HZ_ARRAY_LEN(v))
        v[n++] = hz_float_from_bits(hz_rng_u32(&r));
    for (size_t len = 0; len <= 17; len++) { /* tails */
        memset(a, 0xAA, sizeof a);
        memset(b, 0xAA, sizeof b);
        hz_srgb8_encode_n(v + len, a, len);
        hz_srgb8_encode_n_scalar(v + len, b, len);
        assert_memory_equal(a, b, sizeof a);
    }
    for (size_t off = 0; off < 8; off++) {
        hz_srgb8_encode_n(v + off, a, HZ_ARRAY_LEN(v) - off);
        hz_srgb8_encode_n_scalar(v + off, b, HZ_ARRAY_LEN(v) - off);
        assert_memory_equal(a, b, HZ_ARRAY_LEN(v) - off);
    }
    hz_srgb8_encode_n(v, a, HZ_ARRAY_LEN(v));
    for (size_t i = 0; i < HZ_ARRAY_LEN(v); i++)
        assert_int_equal(a[i], hz_srgb8_encode(v[i]));
}

static uint8_t arena_buf[1 << 16] HZ_ALIGNED(64);

static void test_alloc_sizes_and_refusals(void **state)
{
    (void)state;
    hz_arena_t a;
    hz_arena_init(&a, "frame", arena_buf + 4, sizeof arena_buf - 4);
    hz_image_t img;
    hz_error_t err;
    assert_int_equal(hz_image_alloc(&img, &a, 0, 4, &err), HZ_E_INVALID_ARG);
    assert_null(img.rgb);
    assert_int_equal(hz_image_alloc(&img, &a, HZ_IMAGE_MAX_DIM + 1, 1, &err), HZ_E_RANGE);
    assert_non_null(strstr(err.msg, "16385x1"));
    assert_int_equal(hz_arena_mark(&a), 0);
    assert_int_equal(hz_image_alloc(&img, &a, 100, 100, &err), HZ_E_NO_MEMORY);
    assert_non_null(strstr(err.msg, "image"));
    assert_non_null(strstr(err.msg, "arena 'frame': needs 1200")); /* 120000 + alignment padding */
    assert_int_equal(hz_image_alloc(&img, &a, 17, 9, &err), HZ_OK);
    assert_int_equal(img.width, 17);
    assert_int_equal(img.height, 9);
    assert_int_equal((uintptr_t)img.rgb % 64, 0);
    assert_int_equal(hz_image_pixels(&img), 153);
    hz_image_fill(&img, 0.25f, -1.0f, 2.0f);
    assert_true(hz_image_at(&img, 16, 8)[0] == 0.25f);
    assert_true(hz_image_at(&img, 16, 8)[2] == 2.0f);
    assert_true(hz_image_at(&img, 3, 4) == img.rgb + 3 * (4 * 17 + 3));

    hz_image_t other;
    assert_int_equal(hz_image_alloc(&other, &a, 9, 17, &err), HZ_OK);
    assert_int_equal(hz_image_copy(&other, &img, &err), HZ_E_INVALID_ARG);
    hz_image_t same;
    assert_int_equal(hz_image_alloc(&same, &a, 17, 9, &err), HZ_OK);
    hz_image_at(&img, 5, 5)[1] = NAN;
    assert_int_equal(hz_image_copy(&same, &img, &err), HZ_OK);
    assert_memory_equal(same.rgb, img.rgb, 153 * 3 * sizeof(float));

    uint8_t codes[153 * 3];
    hz_image_to_srgb8(&img, codes);
    assert_int_equal(codes[0], hz_srgb8_encode(0.25f));
    assert_int_equal(codes[1], 0);
    assert_int_equal(codes[2], 255);
    assert_int_equal(codes[3 * (5 * 17 + 5) + 1], 0); /* the NaN */
    hz_image_quantize_srgb8(&same);
    for (size_t i = 0; i < 153 * 3; i++)
        assert_true(same.rgb[i] == hz_srgb8_decode(codes[i]));
    hz_image_from_srgb8(&other, codes); /* sizes are equal in pixels: 9x17 */
    assert_memory_equal(other.rgb, same.rgb, 153 * 3 * sizeof(float));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_decode_table_matches_libm),
        cmocka_unit_test(test_thresholds_bracket_the_exact_values),
        cmocka_unit_test(test_bucket_table_invariant),
        cmocka_unit_test(test_round_trip_and_thresholds),
        cmocka_unit_test(test_random_floats_match_definition),
        cmocka_unit_test(test_special_values_stay_in_range),
        cmocka_unit_test(test_simd_encode_matches_scalar),
        cmocka_unit_test(test_alloc_sizes_and_refusals),
    };
    return HZ_RUN(tests);
}
