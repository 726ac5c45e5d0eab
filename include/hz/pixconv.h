/*
 * hz/pixconv.h — converting rendered RGB24 frames to what display devices scan out.
 *
 * Contract (integer-only, freestanding, no allocation):
 *  - Sources are RGB24: 3 bytes per pixel R, G, B, `stride` bytes per row.
 *  - V4L2 formats: RGB24 ('RGB3': R G B), XRGB32 ('BX24': X R G B in memory, X written as 0), YUYV ('YUYV':
 *    Y0 U Y1 V per pixel pair, BT.601 limited range: Y 16..235, U/V 16..240; chroma from the pair's average;
 *    the width must be even). The arithmetic is exact integer arithmetic, identical on every ISA.
 *  - fbdev: any packed true-colour layout of 16, 24 or 32 bits per pixel described by bit offsets and lengths
 *    (1..8 bits per channel, inside the pixel, not overlapping, msb_right not supported), stored little-endian
 *    (fbdev pixels are in CPU order and both supported ISAs are little-endian). Channels take the top bits of
 *    the 8-bit value; unused bits are 0.
 */
#ifndef HZ_PIXCONV_H
#define HZ_PIXCONV_H

#include <stddef.h>
#include <stdint.h>

#include "hz/status.h"

typedef enum hz_pix_fmt { HZ_PIX_NONE = 0, HZ_PIX_RGB24, HZ_PIX_XRGB32, HZ_PIX_YUYV } hz_pix_fmt_t;

/* "rgb24", "xrgb32", "yuyv" (the names the command line uses); unknown names: HZ_E_UNSUPPORTED naming the
 * supported ones. */
hz_status_t hz_pix_parse(const char *name, hz_pix_fmt_t *fmt, hz_error_t *err);
const char *hz_pix_name(hz_pix_fmt_t fmt);
/* The V4L2 fourcc of the format (v4l2_fourcc byte order: first character in the low byte). */
uint32_t hz_pix_fourcc(hz_pix_fmt_t fmt);
/* Bytes per pixel on average (YUYV: 2); 0 for HZ_PIX_NONE. */
int hz_pix_bpp(hz_pix_fmt_t fmt);
/* HZ_E_UNSUPPORTED for an odd width in YUYV, HZ_E_INVALID_ARG for sizes out of range. */
hz_status_t hz_pix_check(hz_pix_fmt_t fmt, int w, int h, hz_error_t *err);
void hz_pix_convert(hz_pix_fmt_t fmt, const uint8_t *rgb, size_t rgb_stride, uint8_t *dst, size_t dst_stride,
                    int w, int h);
/* Where a marker reader finds an 8-bit brightness-like channel in this format: byte offset in a pixel and
 * bytes from one pixel to the next. */
void hz_pix_marker_view(hz_pix_fmt_t fmt, size_t *offset, size_t *pixel_stride);

typedef struct hz_fb_layout {
    int bpp;
    int r_off, r_len, g_off, g_len, b_off, b_len;
} hz_fb_layout_t;

/* HZ_E_UNSUPPORTED with the reason ("8 bits per pixel (palette) ...", "green overlaps red", ...). */
hz_status_t hz_fb_layout_check(const hz_fb_layout_t *l, hz_error_t *err);
void hz_fb_pack(const hz_fb_layout_t *l, const uint8_t *rgb, size_t rgb_stride, uint8_t *dst, size_t dst_stride,
                int w, int h);
/* The packed value of one colour (for tests and for clearing). */
uint32_t hz_fb_pixel(const hz_fb_layout_t *l, uint8_t r, uint8_t g, uint8_t b);

#endif /* HZ_PIXCONV_H */
