/* RGB24 to display formats (see hz/pixconv.h). */
#include "hz/pixconv.h"

#include "hz/base.h"

static int same(const char *a, const char *b)
{
    while (*a && *a == *b) {
        a++;
        b++;
    }
    return *a == *b;
}

hz_status_t hz_pix_parse(const char *name, hz_pix_fmt_t *fmt, hz_error_t *err)
{
    if (same(name, "rgb24"))
        *fmt = HZ_PIX_RGB24;
    else if (same(name, "xrgb32"))
        *fmt = HZ_PIX_XRGB32;
    else if (same(name, "yuyv"))
        *fmt = HZ_PIX_YUYV;
    else
        return hz_error_set(err, HZ_E_UNSUPPORTED,
                            "pixel format '%s' is not supported (supported: rgb24, xrgb32, yuyv)", name);
    return HZ_OK;
}

const char *hz_pix_name(hz_pix_fmt_t fmt)
{
    switch (fmt) {
    case HZ_PIX_RGB24: return "rgb24";
    case HZ_PIX_XRGB32: return "xrgb32";
    case HZ_PIX_YUYV: return "yuyv";
    default: return "none";
    }
}

#define FOURCC(a, b, c, d) ((uint32_t)(a) | ((uint32_t)(b) << 8) | ((uint32_t)(c) << 16) | ((uint32_t)(d) << 24))

uint32_t hz_pix_fourcc(hz_pix_fmt_t fmt)
{
    switch (fmt) {
    case HZ_PIX_RGB24: return FOURCC('R', 'G', 'B', '3');
    case HZ_PIX_XRGB32: return FOURCC('B', 'X', '2', '4');
    case HZ_PIX_YUYV: return FOURCC('Y', 'U', 'Y', 'V');
    default: return 0;
    }
}

int hz_pix_bpp(hz_pix_fmt_t fmt)
{
    switch (fmt) {
    case HZ_PIX_RGB24: return 3;
    case HZ_PIX_XRGB32: return 4;
    case HZ_PIX_YUYV: return 2;
    default: return 0;
    }
}

hz_status_t hz_pix_check(hz_pix_fmt_t fmt, int w, int h, hz_error_t *err)
{
    if (hz_pix_bpp(fmt) == 0)
        return hz_error_set(err, HZ_E_UNSUPPORTED, "no pixel format chosen");
    if (w < 1 || h < 1 || w > 16384 || h > 16384)
        return hz_error_set(err, HZ_E_INVALID_ARG, "frame size %dx%d is outside [1, 16384]", w, h);
    if (fmt == HZ_PIX_YUYV && (w & 1))
        return hz_error_set(err, HZ_E_UNSUPPORTED, "yuyv needs an even width, not %d", w);
    return HZ_OK;
}

static uint8_t luma(int r, int g, int b)
{
    return (uint8_t)(((66 * r + 129 * g + 25 * b + 128) >> 8) + 16);
}

/* The sums are made non-negative before shifting (a right shift of a negative int is implementation-defined
 * in C99); +32768 is 128 << 8, the chroma offset. */
static uint8_t chroma_u(int r, int g, int b)
{
    return (uint8_t)((-38 * r - 74 * g + 112 * b + 128 + 32768) >> 8);
}

static uint8_t chroma_v(int r, int g, int b)
{
    return (uint8_t)((112 * r - 94 * g - 18 * b + 128 + 32768) >> 8);
}

void hz_pix_convert(hz_pix_fmt_t fmt, const uint8_t *rgb, size_t rgb_stride, uint8_t *dst, size_t dst_stride,
                    int w, int h)
{
    for (int y = 0; y < h; y++) {
        const uint8_t *s = rgb + (size_t)y * rgb_stride;
        uint8_t *d = dst + (size_t)y * dst_stride;
        switch (fmt) {
        case HZ_PIX_RGB24:
            for (int x = 0; x < 3 * w; x++)
                d[x] = s[x];
            break;
        case HZ_PIX_XRGB32:
            for (int x = 0; x < w; x++, s += 3, d += 4) {
                d[0] = 0;
                d[1] = s[0];
                d[2] = s[1];
                d[3] = s[2];
            }
            break;
        case HZ_PIX_YUYV:
            for (int x = 0; x + 1 < w; x += 2, s += 6, d += 4) {
                int r = (s[0] + s[3] + 1) >> 1, g = (s[1] + s[4] + 1) >> 1, b = (s[2] + s[5] + 1) >> 1;
                d[0] = luma(s[0], s[1], s[2]);
                d[1] = chroma_u(r, g, b);
                d[2] = luma(s[3], s[4], s[5]);
                d[3] = chroma_v(r, g, b);
            }
            break;
        default:
            return;
        }
    }
}

void hz_pix_marker_view(hz_pix_fmt_t fmt, size_t *offset, size_t *pixel_stride)
{
    switch (fmt) {
    case HZ_PIX_XRGB32: *offset = 2; *pixel_stride = 4; break;
    case HZ_PIX_YUYV: *offset = 0; *pixel_stride = 2; break;
    default: *offset = 1; *pixel_stride = 3; break;
    }
}

static int channel_ok(int off, int len, int bpp)
{
    return len >= 1 && len <= 8 && off >= 0 && off + len <= bpp;
}

static uint32_t mask(int off, int len)
{
    return ((1u << len) - 1u) << off;
}

hz_status_t hz_fb_layout_check(const hz_fb_layout_t *l, hz_error_t *err)
{
    if (l->bpp != 16 && l->bpp != 24 && l->bpp != 32)
        return hz_error_set(err, HZ_E_UNSUPPORTED,
                            "%d bits per pixel is not supported (16, 24 or 32 bpp true colour only)", l->bpp);
    if (!channel_ok(l->r_off, l->r_len, l->bpp) || !channel_ok(l->g_off, l->g_len, l->bpp) ||
        !channel_ok(l->b_off, l->b_len, l->bpp))
        return hz_error_set(err, HZ_E_UNSUPPORTED,
                            "pixel layout r%d@%d g%d@%d b%d@%d does not fit %d bpp with 1..8 bits per channel",
                            l->r_len, l->r_off, l->g_len, l->g_off, l->b_len, l->b_off, l->bpp);
    uint32_t r = mask(l->r_off, l->r_len), g = mask(l->g_off, l->g_len), b = mask(l->b_off, l->b_len);
    if ((r & g) || (r & b) || (g & b))
        return hz_error_set(err, HZ_E_UNSUPPORTED, "pixel layout r%d@%d g%d@%d b%d@%d has overlapping channels",
                            l->r_len, l->r_off, l->g_len, l->g_off, l->b_len, l->b_off);
    return HZ_OK;
}

uint32_t hz_fb_pixel(const hz_fb_layout_t *l, uint8_t r, uint8_t g, uint8_t b)
{
    return ((uint32_t)(r >> (8 - l->r_len)) << l->r_off) | ((uint32_t)(g >> (8 - l->g_len)) << l->g_off) |
           ((uint32_t)(b >> (8 - l->b_len)) << l->b_off);
}

/* One row at a constant byte count (the callers' 2, 3 or 4), so the compiler merges each pixel's byte stores;
 * the layout is a local copy, which those stores cannot alias, so its fields stay out of the loop. */
HZ_INLINE void pack_row(const hz_fb_layout_t *layout, const uint8_t *s, uint8_t *d, int w, int bytes)
{
    const hz_fb_layout_t l = *layout;
    for (int x = 0; x < w; x++, s += 3, d += bytes) {
        const uint32_t v = hz_fb_pixel(&l, s[0], s[1], s[2]);
        d[0] = (uint8_t)v;
        d[1] = (uint8_t)(v >> 8);
        if (bytes > 2)
            d[2] = (uint8_t)(v >> 16);
        if (bytes > 3)
            d[3] = (uint8_t)(v >> 24);
    }
}

void hz_fb_pack(const hz_fb_layout_t *l, const uint8_t *rgb, size_t rgb_stride, uint8_t *dst, size_t dst_stride,
                int w, int h)
{
    for (int y = 0; y < h; y++) {
        const uint8_t *s = rgb + (size_t)y * rgb_stride;
        uint8_t *d = dst + (size_t)y * dst_stride;
        if (l->bpp == 16)
            pack_row(l, s, d, w, 2);
        else if (l->bpp == 24)
            pack_row(l, s, d, w, 3);
        else
            pack_row(l, s, d, w, 4);
    }
}
