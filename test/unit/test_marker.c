/* Frame-id marker, pixel conversion and the test pattern. */
#include "hz_test.h"

#include <stdlib.h>
#include <string.h>

#include "hz/framesrc.h"
#include "hz/marker.h"
#include "hz/pixconv.h"

#define W 320
#define H 96

static uint8_t rgb[W * H * 3], out[W * H * 4], rgb2[W * H * 3];

static void test_layout_fits(void **state)
{
    (void)state;
    hz_marker_layout_t m;
    hz_error_t err;
    assert_int_equal(hz_marker_layout(1280, 720, &m, &err), HZ_OK);
    assert_int_equal(m.cell, 8);
    assert_int_equal(m.flash, 32);
    assert_int_equal(m.width, 32 + 8 + 44 * 8);
    assert_int_equal(hz_marker_layout(320, 180, &m, &err), HZ_OK);
    assert_int_equal(m.cell, 4);
    assert_int_equal(hz_marker_layout(49, 4, &m, &err), HZ_OK);
    assert_int_equal(m.cell, 1);
    assert_int_equal(hz_marker_layout(48, 4, &m, &err), HZ_E_RANGE);
    assert_non_null(strstr(err.msg, "at least 49x4"));
}

static void test_marker_roundtrip_all_formats(void **state)
{
    (void)state;
    hz_marker_layout_t m;
    hz_error_t err;
    assert_int_equal(hz_marker_layout(W, H, &m, &err), HZ_OK);
    uint32_t ids[] = { 0, 1, 2, 0x7fffffffu, 0xffffffffu, 0xdeadbeefu, 12345 };
    hz_pix_fmt_t fmts[] = { HZ_PIX_RGB24, HZ_PIX_XRGB32, HZ_PIX_YUYV };
    for (size_t i = 0; i < sizeof ids / sizeof ids[0]; i++) {
        hz_testpattern_draw(rgb, W * 3, W, H, ids[i]);
        hz_marker_draw(rgb, W * 3, &m, ids[i]);
        for (size_t f = 0; f < 3; f++) {
            size_t stride = (size_t)W * hz_pix_bpp(fmts[f]);
            hz_pix_convert(fmts[f], rgb, W * 3, out, stride, W, H);
            size_t off, ps;
            hz_pix_marker_view(fmts[f], &off, &ps);
            uint32_t got = 0;
            assert_int_equal(hz_marker_read(out + off, ps, stride, &m, &got), HZ_OK);
            assert_true(got == ids[i]);
        }
    }
}

static void test_marker_damage_is_detected(void **state)
{
    (void)state;
    hz_marker_layout_t m;
    hz_error_t err;
    assert_int_equal(hz_marker_layout(W, H, &m, &err), HZ_OK);
    hz_testpattern_draw(rgb, W * 3, W, H, 77);
    uint32_t got;
    /* No marker at all: the pattern underneath does not decode. */
    assert_int_equal(hz_marker_read(rgb + 1, 3, W * 3, &m, &got), HZ_E_CORRUPT);
    hz_marker_draw(rgb, W * 3, &m, 77);
    /* Every single flipped code cell is caught (sync, id, CRC or flash parity). */
    for (int cell = 0; cell < HZ_MARKER_CELLS; cell++) {
        memcpy(rgb2, rgb, sizeof rgb);
        size_t at = (size_t)(m.cell / 2) * W * 3 + (size_t)(m.flash + m.cell + cell * m.cell + m.cell / 2) * 3 + 1;
        rgb2[at] = (uint8_t)(255 - rgb2[at]);
        assert_int_equal(hz_marker_read(rgb2 + 1, 3, W * 3, &m, &got), HZ_E_CORRUPT);
    }
    memcpy(rgb2, rgb, sizeof rgb);
    size_t fc = (size_t)(m.flash / 2) * W * 3 + (size_t)(m.flash / 2) * 3 + 1;
    rgb2[fc] = (uint8_t)(255 - rgb2[fc]);
    assert_int_equal(hz_marker_read(rgb2 + 1, 3, W * 3, &m, &got), HZ_E_CORRUPT);
    assert_int_equal(hz_marker_read(rgb + 1, 3, W * 3, &m, &got), HZ_OK);
    assert_int_equal(got, 77);
}

static void test_yuyv_and_xrgb_values(void **state)
{
    (void)state;
    uint8_t px[6] = { 255, 255, 255, 0, 0, 0 }, d[8];
    hz_pix_convert(HZ_PIX_YUYV, px, 6, d, 4, 2, 1);
    assert_int_equal(d[0], 235); /* white Y */
    assert_int_equal(d[2], 16);  /* black Y */
    assert_int_equal(d[1], 128); /* grey average: no chroma */
    assert_int_equal(d[3], 128);
    uint8_t red[6] = { 255, 0, 0, 255, 0, 0 };
    hz_pix_convert(HZ_PIX_YUYV, red, 6, d, 4, 2, 1);
    assert_int_equal(d[0], 82);  /* BT.601: Y = 16 + 65.5 */
    assert_int_equal(d[1], 90);  /* U = 128 - 37.8 */
    assert_int_equal(d[3], 240); /* V = 128 + 112 */
    uint8_t c[3] = { 1, 2, 3 };
    hz_pix_convert(HZ_PIX_XRGB32, c, 3, d, 4, 1, 1);
    assert_int_equal(d[0], 0);
    assert_int_equal(d[1], 1);
    assert_int_equal(d[2], 2);
    assert_int_equal(d[3], 3);
    hz_error_t err;
    hz_pix_fmt_t f;
    assert_int_equal(hz_pix_parse("nv12", &f, &err), HZ_E_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "'nv12' is not supported (supported: rgb24, xrgb32, yuyv)"));
    assert_int_equal(hz_pix_parse("yuyv", &f, &err), HZ_OK);
    assert_int_equal(f, HZ_PIX_YUYV);
    assert_int_equal(hz_pix_fourcc(HZ_PIX_YUYV), 0x56595559u);
    assert_int_equal(hz_pix_check(HZ_PIX_YUYV, 641, 480, &err), HZ_E_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "even width"));
}

static void test_fb_layouts(void **state)
{
    (void)state;
    hz_error_t err;
    hz_fb_layout_t rgb565 = { 16, 11, 5, 5, 6, 0, 5 };
    hz_fb_layout_t xrgb8888 = { 32, 16, 8, 8, 8, 0, 8 };
    hz_fb_layout_t bgr888 = { 24, 0, 8, 8, 8, 16, 8 };
    assert_int_equal(hz_fb_layout_check(&rgb565, &err), HZ_OK);
    assert_int_equal(hz_fb_layout_check(&xrgb8888, &err), HZ_OK);
    assert_int_equal(hz_fb_layout_check(&bgr888, &err), HZ_OK);
    assert_int_equal(hz_fb_pixel(&rgb565, 255, 255, 255), 0xffff);
    assert_int_equal(hz_fb_pixel(&rgb565, 255, 0, 0), 0xf800);
    assert_int_equal(hz_fb_pixel(&rgb565, 0, 255, 0), 0x07e0);
    assert_int_equal(hz_fb_pixel(&xrgb8888, 1, 2, 3), 0x010203);
    uint8_t px[6] = { 0x12, 0x34, 0x56, 0xff, 0x00, 0x80 }, d[8] = { 0 };
    hz_fb_pack(&bgr888, px, 6, d, 6, 2, 1);
    uint8_t want[6] = { 0x12, 0x34, 0x56, 0xff, 0x00, 0x80 }; /* r at bit 0 = first byte */
    assert_memory_equal(d, want, 6);
    hz_fb_pack(&xrgb8888, px, 6, d, 8, 2, 1);
    uint8_t want32[8] = { 0x56, 0x34, 0x12, 0, 0x80, 0x00, 0xff, 0 };
    assert_memory_equal(d, want32, 8);
    hz_fb_pack(&rgb565, px, 6, d, 4, 2, 1);
    uint8_t want16[4] = { 0xaa, 0x11, 0x10, 0xf8 }; /* r 0x12>>3 = 2 @11, g 0x34>>2 = 13 @5, b 0x56>>3 = 10 */
    assert_memory_equal(d, want16, 4);
    hz_fb_layout_t pal8 = { 8, 0, 3, 3, 3, 6, 2 };
    assert_int_equal(hz_fb_layout_check(&pal8, &err), HZ_E_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "8 bits per pixel"));
    hz_fb_layout_t overlap = { 16, 0, 8, 4, 8, 12, 4 };
    assert_int_equal(hz_fb_layout_check(&overlap, &err), HZ_E_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "overlapping"));
    hz_fb_layout_t wide = { 32, 0, 10, 10, 10, 20, 10 };
    assert_int_equal(hz_fb_layout_check(&wide, &err), HZ_E_UNSUPPORTED);
}

static void test_pattern_moves_and_is_deterministic(void **state)
{
    (void)state;
    hz_testpattern_draw(rgb, W * 3, W, H, 10);
    hz_testpattern_draw(rgb2, W * 3, W, H, 10);
    assert_memory_equal(rgb, rgb2, sizeof rgb);
    hz_testpattern_draw(rgb2, W * 3, W, H, 11);
    size_t diff = 0;
    for (size_t i = 0; i < sizeof rgb; i++)
        diff += rgb[i] != rgb2[i];
    assert_true(diff > (size_t)W * H / 4); /* a new frame changes a good part of the picture */
    hz_framesrc_t src = hz_framesrc_testpattern();
    hz_rgb8_image_t img = { rgb2, W, H, W * 3 };
    hz_frame_req_t req = { 10, 0, 0, 0, 0 };
    hz_error_t err;
    assert_int_equal(src.render(src.ctx, &req, &img, &err), HZ_OK);
    assert_memory_equal(rgb, rgb2, sizeof rgb);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layout_fits),
        cmocka_unit_test(test_marker_roundtrip_all_formats),
        cmocka_unit_test(test_marker_damage_is_detected),
        cmocka_unit_test(test_yuyv_and_xrgb_values),
        cmocka_unit_test(test_fb_layouts),
        cmocka_unit_test(test_pattern_moves_and_is_deterministic),
    };
    return HZ_RUN(tests);
}
