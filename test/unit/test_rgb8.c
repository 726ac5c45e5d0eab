/* hz_rgb8_upscale (hz/rgb8.h) against the contract's formula computed directly per destination pixel (the four
 * source pixels weighted at once, in doubles for the positions): every byte equal on random frames of many sizes
 * and ratios, equal sizes copied, whole-number ratios with `nearest` replicated as blocks, strides honoured. */
#include "hz_test.h"

#include <stdlib.h>
#include <string.h>

#include "hz/hash.h"
#include "hz/rgb8.h"

static void coord(uint32_t d, uint32_t dn, uint32_t sn, uint32_t *i0, uint32_t *i1, uint32_t *f)
{
    /* the header's mapping: (d + 0.5) sn / dn - 0.5 in Q8, truncated towards -inf, clamped */
    long long num = (2LL * d + 1) * (long long)sn * 128;
    long long q = num / (long long)dn - 128;
    if (q < 0)
        q = 0;
    if (q > ((long long)sn - 1) * 256)
        q = ((long long)sn - 1) * 256;
    *i0 = (uint32_t)(q / 256), *f = (uint32_t)(q % 256);
    *i1 = *i0 + 1 < sn ? *i0 + 1 : *i0;
}

static uint8_t oracle(const uint8_t *src, size_t ss, uint32_t sw, uint32_t sh, uint32_t dw, uint32_t dh, uint32_t x,
                      uint32_t y, int c)
{
    uint32_t x0, x1, fx, y0, y1, fy;
    coord(x, dw, sw, &x0, &x1, &fx);
    coord(y, dh, sh, &y0, &y1, &fy);
    uint32_t a = src[y0 * ss + x0 * 3 + c], b = src[y0 * ss + x1 * 3 + c], d = src[y1 * ss + x0 * 3 + c],
             e = src[y1 * ss + x1 * 3 + c];
    uint32_t v = (a * (256 - fx) + b * fx) * (256 - fy) + (d * (256 - fx) + e * fx) * fy;
    return (uint8_t)((v + 32768) >> 16);
}

static void test_bilinear_matches_formula(void **state)
{
    (void)state;
    static const uint32_t sizes[][4] = { { 80, 45, 640, 360 }, { 107, 60, 640, 360 }, { 480, 270, 640, 360 },
                                         { 1, 1, 7, 5 }, { 3, 2, 3, 9 }, { 16, 16, 17, 16 }, { 33, 17, 200, 101 },
                                         { 160, 90, 640, 360 } };
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        uint32_t sw = sizes[k][0], sh = sizes[k][1], dw = sizes[k][2], dh = sizes[k][3];
        size_t ss = (size_t)sw * 3 + 5, ds = (size_t)dw * 3 + 7;
        uint8_t *src = malloc(ss * sh), *dst = malloc(ds * dh);
        void *scratch = malloc(hz_rgb8_upscale_scratch(dw) + 3);
        assert_non_null(src);
        assert_non_null(dst);
        for (size_t i = 0; i < ss * sh; i++)
            src[i] = (uint8_t)hz_hash32((uint32_t)(i * 7919 + k));
        memset(dst, 0xEE, ds * dh);
        hz_rgb8_upscale(src, sw, sh, ss, dst, dw, dh, ds, false, (uint8_t *)scratch + 3); /* misaligned scratch */
        for (uint32_t y = 0; y < dh; y++) {
            for (uint32_t x = 0; x < dw; x++)
                for (int c = 0; c < 3; c++)
                    if (dst[y * ds + x * 3 + c] != oracle(src, ss, sw, sh, dw, dh, x, y, c))
                        fail_msg("%ux%u -> %ux%u: pixel (%u, %u) channel %d is %u, the formula %u", sw, sh, dw, dh, x,
                                 y, c, dst[y * ds + x * 3 + c], oracle(src, ss, sw, sh, dw, dh, x, y, c));
            for (size_t pad = (size_t)dw * 3; pad < ds; pad++)
                assert_int_equal(dst[y * ds + pad], 0xEE); /* the stride's padding untouched */
        }
        free(src);
        free(dst);
        free(scratch);
    }
}

static void test_copy_and_blocks(void **state)
{
    (void)state;
    uint8_t src[4 * 3 * 3], dst[12 * 3 * 6];
    for (size_t i = 0; i < sizeof src; i++)
        src[i] = (uint8_t)(i * 13 + 1);
    hz_rgb8_upscale(src, 4, 3, 12, dst, 4, 3, 12, false, NULL);
    assert_memory_equal(src, dst, sizeof src);
    hz_rgb8_upscale(src, 4, 3, 12, dst, 12, 6, 36, true, NULL); /* 3 x 2 blocks */
    for (uint32_t y = 0; y < 6; y++)
        for (uint32_t x = 0; x < 12; x++)
            assert_memory_equal(dst + y * 36 + x * 3, src + (y / 2) * 12 + (x / 3) * 3, 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bilinear_matches_formula),
        cmocka_unit_test(test_copy_and_blocks),
    };
    return HZ_RUN(tests);
}
