/* Frame-id marker: draw and read (see hz/marker.h). */
#include "hz/marker.h"

uint8_t hz_marker_crc8(uint32_t id)
{
    uint8_t crc = 0;
    for (int byte = 3; byte >= 0; byte--) {
        crc ^= (uint8_t)(id >> (8 * byte));
        for (int b = 0; b < 8; b++)
            crc = (uint8_t)((crc & 0x80u) ? ((unsigned)crc << 1) ^ 0x07u : (unsigned)crc << 1);
    }
    return crc;
}

hz_status_t hz_marker_layout(int w, int h, hz_marker_layout_t *m, hz_error_t *err)
{
    for (int c = 8; c >= 1; c /= 2) {
        int f = 4 * c;
        if (f + c + HZ_MARKER_CELLS * c <= w && f <= h) {
            m->cell = c;
            m->flash = f;
            m->width = f + c + HZ_MARKER_CELLS * c;
            m->height = f;
            return HZ_OK;
        }
    }
    return hz_error_set(err, HZ_E_RANGE, "frame-id marker needs an image of at least %dx%d pixels, not %dx%d",
                        4 + 1 + HZ_MARKER_CELLS, 4, w, h);
}

/* Bit i of the code row (0..43). */
static int code_bit(uint32_t id, uint8_t crc, int i)
{
    if (i < 2)
        return i == 0;
    if (i < 34)
        return (int)((id >> (31 - (i - 2))) & 1u);
    if (i < 42)
        return (crc >> (7 - (i - 34))) & 1;
    return i == 43;
}

static void fill(uint8_t *rgb, size_t stride, int x0, int y0, int w, int h, uint8_t v)
{
    for (int y = y0; y < y0 + h; y++) {
        uint8_t *p = rgb + (size_t)y * stride + (size_t)x0 * 3;
        for (int x = 0; x < w * 3; x++)
            p[x] = v;
    }
}

void hz_marker_draw(uint8_t *rgb, size_t stride, const hz_marker_layout_t *m, uint32_t id)
{
    int c = m->cell, f = m->flash;
    fill(rgb, stride, 0, 0, f, f, (id & 1u) ? 0 : 255);
    /* The gap column and the rows under the code row are black so the code stands out from the picture. */
    fill(rgb, stride, f, 0, m->width - f, f, 0);
    uint8_t crc = hz_marker_crc8(id);
    for (int i = 0; i < HZ_MARKER_CELLS; i++)
        fill(rgb, stride, f + c + i * c, 0, c, c, code_bit(id, crc, i) ? 255 : 0);
}

hz_status_t hz_marker_read(const uint8_t *base, size_t pixel_stride, size_t row_stride,
                           const hz_marker_layout_t *m, uint32_t *id)
{
    int c = m->cell, f = m->flash;
    int bits[HZ_MARKER_CELLS];
    size_t y = (size_t)(c / 2);
    for (int i = 0; i < HZ_MARKER_CELLS; i++) {
        size_t x = (size_t)(f + c + i * c + c / 2);
        bits[i] = base[y * row_stride + x * pixel_stride] >= 128;
    }
    if (bits[0] != 1 || bits[1] != 0 || bits[42] != 0 || bits[43] != 1)
        return HZ_E_CORRUPT;
    uint32_t v = 0;
    for (int i = 2; i < 34; i++)
        v = (v << 1) | (uint32_t)bits[i];
    uint8_t crc = 0;
    for (int i = 34; i < 42; i++)
        crc = (uint8_t)((crc << 1) | bits[i]);
    if (crc != hz_marker_crc8(v))
        return HZ_E_CORRUPT;
    /* The flash square must agree with the id's parity (white on even ids). */
    size_t fc = (size_t)(f / 2);
    if ((base[fc * row_stride + fc * pixel_stride] >= 128) != !(v & 1u))
        return HZ_E_CORRUPT;
    *id = v;
    return HZ_OK;
}
