/*
 * MSE/PSNR and SSIM: identical images (PSNR = inf, SSIM = 1), analytic cases with constant offsets to 1e-6,
 * PSNR of a structured image plus an offset, the ring-buffered SSIM against a direct brute-force evaluation,
 * argument errors, and the frame mean used by the display-integrated error.
 */
#include "hz_test.h"

#include <math.h>
#include <string.h>

#include "hz/hash.h"
#include "hz/image.h"
#include "et_metrics.h"

static uint8_t buf[16 << 20] HZ_ALIGNED(64);
static hz_arena_t arena;

static int setup(void **state)
{
    (void)state;
    hz_arena_init(&arena, "test", buf, sizeof buf);
    return 0;
}

static hz_image_t codes_image(uint32_t w, uint32_t h, const uint8_t *codes)
{
    hz_image_t img;
    hz_error_t err;
    assert_int_equal(hz_image_alloc(&img, &arena, w, h, &err), HZ_OK);
    hz_image_from_srgb8(&img, codes);
    return img;
}

static hz_image_t constant(uint32_t w, uint32_t h, uint8_t r, uint8_t g, uint8_t b)
{
    hz_image_t img;
    hz_error_t err;
    assert_int_equal(hz_image_alloc(&img, &arena, w, h, &err), HZ_OK);
    hz_image_fill(&img, hz_srgb8_decode(r), hz_srgb8_decode(g), hz_srgb8_decode(b));
    return img;
}

static hz_image_t random_codes(uint32_t w, uint32_t h, uint32_t seed, int lo, int hi)
{
    static uint8_t c[1 << 20];
    hz_rng_t r;
    hz_rng_seed(&r, seed, 5);
    for (size_t i = 0; i < (size_t)w * h * 3; i++)
        c[i] = (uint8_t)(lo + (int)hz_rng_below(&r, (uint32_t)(hi - lo + 1)));
    return codes_image(w, h, c);
}

static const double C1 = (0.01 * 255) * (0.01 * 255), C2 = (0.03 * 255) * (0.03 * 255);

static double luma(int r, int g, int b)
{
    return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

static void test_identical_images(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t a = random_codes(40, 30, 1, 0, 255);
    hz_mse_t mse;
    hz_error_t err;
    assert_int_equal(hz_mse(&a, &a, &mse, &err), HZ_OK);
    assert_true(mse.srgb8 == 0.0 && mse.linear == 0.0);
    assert_true(isinf(hz_psnr(mse.srgb8, 255.0)) && hz_psnr(mse.srgb8, 255.0) > 0);
    assert_true(isinf(hz_psnr(mse.linear, 1.0)) && hz_psnr(mse.linear, 1.0) > 0);
    double s;
    hz_arena_mark_t before = hz_arena_mark(&arena);
    assert_int_equal(hz_ssim(&a, &a, &arena, &s, &err), HZ_OK);
    assert_float_equal(s, 1.0, 1e-12);
    assert_int_equal(hz_arena_mark(&arena), before); /* scratch released */
    hz_arena_reset(&arena, m);
}

static void test_constant_offsets_are_analytic(void **state)
{
    (void)state;
    static const struct {
        uint8_t a[3], b[3];
    } cases[] = {
        { { 100, 100, 100 }, { 110, 110, 110 } },
        { { 0, 0, 0 }, { 255, 255, 255 } },
        { { 30, 200, 90 }, { 30, 190, 90 } },
        { { 250, 5, 128 }, { 240, 25, 120 } },
        { { 17, 17, 17 }, { 18, 17, 17 } },
    };
    for (size_t k = 0; k < HZ_ARRAY_LEN(cases); k++) {
        hz_arena_mark_t m = hz_arena_mark(&arena);
        const uint8_t *ca = cases[k].a, *cb = cases[k].b;
        hz_image_t a = constant(23, 17, ca[0], ca[1], ca[2]), b = constant(23, 17, cb[0], cb[1], cb[2]);
        double sq = 0, lsq = 0;
        for (int c = 0; c < 3; c++) {
            sq += (double)(ca[c] - cb[c]) * (ca[c] - cb[c]);
            double d = (double)hz_srgb8_decode(ca[c]) - (double)hz_srgb8_decode(cb[c]);
            lsq += d * d;
        }
        double want_psnr = 10.0 * log10(255.0 * 255.0 / (sq / 3.0));
        double want_lin = 10.0 * log10(1.0 / (lsq / 3.0));
        double ya = luma(ca[0], ca[1], ca[2]), yb = luma(cb[0], cb[1], cb[2]);
        double want_ssim = (2 * ya * yb + C1) / (ya * ya + yb * yb + C1);
        hz_mse_t mse;
        hz_error_t err;
        assert_int_equal(hz_mse(&a, &b, &mse, &err), HZ_OK);
        assert_float_equal(hz_psnr(mse.srgb8, 255.0), want_psnr, 1e-6);
        assert_float_equal(hz_psnr(mse.linear, 1.0), want_lin, 1e-6);
        double s;
        assert_int_equal(hz_ssim(&a, &b, &arena, &s, &err), HZ_OK);
        assert_float_equal(s, want_ssim, 1e-6);
        double s2;
        assert_int_equal(hz_ssim(&b, &a, &arena, &s2, &err), HZ_OK);
        assert_float_equal(s2, s, 1e-12);
        hz_arena_reset(&arena, m);
    }
    /* The headline case: a 10-code offset is 20 log10(25.5) = 28.1308 dB. */
    assert_float_equal(hz_psnr(100.0, 255.0), 28.130803608679103, 1e-9);
}

/* A structured image plus a uniform code offset d: PSNR = 20 log10(255 / d) whatever the content; SSIM's
 * structure term is exactly 1 (same variances and covariance), so only the luminance term lowers it. */
static void test_structured_image_plus_offset(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    static uint8_t ca[64 * 48 * 3], cb[64 * 48 * 3];
    hz_rng_t r;
    hz_rng_seed(&r, 9, 9);
    for (size_t i = 0; i < sizeof ca; i++) {
        ca[i] = (uint8_t)(40 + hz_rng_below(&r, 150));
        cb[i] = (uint8_t)(ca[i] + 7);
    }
    hz_image_t a = codes_image(64, 48, ca), b = codes_image(64, 48, cb);
    hz_mse_t mse;
    hz_error_t err;
    assert_int_equal(hz_mse(&a, &b, &mse, &err), HZ_OK);
    assert_float_equal(hz_psnr(mse.srgb8, 255.0), 20.0 * log10(255.0 / 7.0), 1e-9);
    double s;
    assert_int_equal(hz_ssim(&a, &b, &arena, &s, &err), HZ_OK);
    assert_true(s < 1.0 && s > 0.99); /* luminance term only: (2mu(mu+7)+C1)/(mu^2+(mu+7)^2+C1) ~ 0.9985 */
    hz_arena_reset(&arena, m);
}

/* Direct evaluation: every 11x11 window summed in 2D, no separability, no ring buffer. */
static double brute_ssim(const hz_image_t *a, const hz_image_t *b)
{
    double g[11], gs = 0;
    for (int k = 0; k < 11; k++) {
        g[k] = exp(-(k - 5.0) * (k - 5.0) / (2 * 1.5 * 1.5));
        gs += g[k];
    }
    double total = 0;
    int count = 0;
    for (uint32_t y = 0; y + 11 <= a->height; y++)
        for (uint32_t x = 0; x + 11 <= a->width; x++) {
            double ma = 0, mb = 0, eaa = 0, ebb = 0, eab = 0;
            for (int j = 0; j < 11; j++)
                for (int i = 0; i < 11; i++) {
                    const float *pa = hz_image_at(a, x + i, y + j), *pb = hz_image_at(b, x + i, y + j);
                    double la = luma(hz_srgb8_encode(pa[0]), hz_srgb8_encode(pa[1]), hz_srgb8_encode(pa[2]));
                    double lb = luma(hz_srgb8_encode(pb[0]), hz_srgb8_encode(pb[1]), hz_srgb8_encode(pb[2]));
                    double wgt = g[i] * g[j] / (gs * gs);
                    ma += wgt * la;
                    mb += wgt * lb;
                    eaa += wgt * la * la;
                    ebb += wgt * lb * lb;
                    eab += wgt * la * lb;
                }
            double va = eaa - ma * ma, vb = ebb - mb * mb, cov = eab - ma * mb;
            total += (2 * ma * mb + C1) * (2 * cov + C2) / ((ma * ma + mb * mb + C1) * (va + vb + C2));
            count++;
        }
    return total / count;
}

static void test_ssim_matches_direct_evaluation(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t a = random_codes(29, 23, 2, 0, 255), b = random_codes(29, 23, 3, 0, 255);
    /* b: a blend of a and noise, so the structure term is neither 0 nor 1. */
    for (size_t i = 0; i < hz_image_pixels(&b) * 3; i++)
        b.rgb[i] = 0.7f * a.rgb[i] + 0.3f * b.rgb[i];
    double s;
    hz_error_t err;
    assert_int_equal(hz_ssim(&a, &b, &arena, &s, &err), HZ_OK);
    assert_float_equal(s, brute_ssim(&a, &b), 1e-10);
    assert_true(s > 0.1 && s < 0.99);
    /* Exactly the window size: one window. */
    hz_image_t c = random_codes(11, 11, 4, 0, 255), d = random_codes(11, 11, 5, 0, 255);
    assert_int_equal(hz_ssim(&c, &d, &arena, &s, &err), HZ_OK);
    assert_float_equal(s, brute_ssim(&c, &d), 1e-10);
    hz_arena_reset(&arena, m);
}

static void test_more_noise_scores_worse(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t ref = random_codes(48, 48, 6, 60, 200), t = random_codes(48, 48, 6, 60, 200);
    double last_psnr = INFINITY, last_ssim = 1.0;
    hz_rng_t r;
    for (int amp = 2; amp <= 32; amp *= 2) {
        hz_rng_seed(&r, 77, 1);
        for (size_t i = 0; i < hz_image_pixels(&ref) * 3; i++) {
            int c = hz_srgb8_encode(ref.rgb[i]) + (int)hz_rng_below(&r, (uint32_t)(2 * amp + 1)) - amp;
            t.rgb[i] = hz_srgb8_decode((uint8_t)(c < 0 ? 0 : c > 255 ? 255 : c));
        }
        hz_mse_t mse;
        double s;
        hz_error_t err;
        assert_int_equal(hz_mse(&ref, &t, &mse, &err), HZ_OK);
        assert_int_equal(hz_ssim(&ref, &t, &arena, &s, &err), HZ_OK);
        double p = hz_psnr(mse.srgb8, 255.0);
        assert_true(p < last_psnr);
        assert_true(s < last_ssim);
        last_psnr = p;
        last_ssim = s;
    }
    hz_arena_reset(&arena, m);
}

static void test_out_of_range_values_are_clamped(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t a = constant(12, 12, 255, 0, 0), b = constant(12, 12, 255, 0, 0);
    hz_image_fill(&b, 7.0f, NAN, -3.0f); /* displays as (255, 0, 0) */
    hz_mse_t mse;
    double s;
    hz_error_t err;
    assert_int_equal(hz_mse(&a, &b, &mse, &err), HZ_OK);
    assert_true(mse.srgb8 == 0.0 && mse.linear == 0.0);
    assert_int_equal(hz_ssim(&a, &b, &arena, &s, &err), HZ_OK);
    assert_float_equal(s, 1.0, 1e-12);
    hz_arena_reset(&arena, m);
}

static void test_argument_errors(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t a = constant(12, 12, 1, 2, 3), b = constant(12, 13, 1, 2, 3), c = constant(10, 40, 1, 2, 3);
    hz_mse_t mse;
    double s;
    hz_error_t err;
    assert_int_equal(hz_mse(&a, &b, &mse, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "12x12 vs 12x13"));
    assert_int_equal(hz_ssim(&a, &b, &arena, &s, &err), HZ_E_INVALID_ARG);
    assert_int_equal(hz_ssim(&c, &c, &arena, &s, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "smaller than the 11x11 window"));
    static uint8_t tiny[256];
    hz_arena_t t;
    hz_arena_init(&t, "tiny", tiny, sizeof tiny);
    assert_int_equal(hz_ssim(&a, &a, &t, &s, &err), HZ_E_NO_MEMORY);
    assert_non_null(strstr(err.msg, "ssim scratch"));
    assert_int_equal(hz_arena_mark(&t), 0);
    assert_true(hz_ssim_scratch_bytes(1920, 1080) < (1u << 20));
    hz_arena_reset(&arena, m);
}

static void test_image_mean(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t f[4], out;
    hz_error_t err;
    for (int i = 0; i < 4; i++) {
        assert_int_equal(hz_image_alloc(&f[i], &arena, 3, 2, &err), HZ_OK);
        hz_image_fill(&f[i], (float)i, 1.0f, (float)(i * i));
    }
    assert_int_equal(hz_image_alloc(&out, &arena, 3, 2, &err), HZ_OK);
    const hz_image_t *fp[4] = { &f[0], &f[1], &f[2], &f[3] };
    assert_int_equal(hz_image_mean(&out, fp, 4, &err), HZ_OK);
    for (size_t p = 0; p < 6; p++) {
        assert_true(out.rgb[3 * p] == 1.5f);
        assert_true(out.rgb[3 * p + 1] == 1.0f);
        assert_true(out.rgb[3 * p + 2] == 3.5f);
    }
    assert_int_equal(hz_image_mean(&out, fp, 0, &err), HZ_E_INVALID_ARG);
    hz_image_t other;
    assert_int_equal(hz_image_alloc(&other, &arena, 2, 3, &err), HZ_OK);
    const hz_image_t *bad[2] = { &f[0], &other };
    assert_int_equal(hz_image_mean(&out, bad, 2, &err), HZ_E_INVALID_ARG);
    hz_arena_reset(&arena, m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_identical_images),
        cmocka_unit_test(test_constant_offsets_are_analytic),
        cmocka_unit_test(test_structured_image_plus_offset),
        cmocka_unit_test(test_ssim_matches_direct_evaluation),
        cmocka_unit_test(test_more_noise_scores_worse),
        cmocka_unit_test(test_out_of_range_values_are_clamped),
        cmocka_unit_test(test_argument_errors),
        cmocka_unit_test(test_image_mean),
    };
    return HZ_RUN_GROUP(tests, setup, NULL);
}
