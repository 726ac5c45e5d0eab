/* Upscaling of RGB24 frames (see hz/rgb8.h). */
#include "hz/rgb8.h"

#include "hz/base.h"

/* Source coordinate of destination pixel d (of dn) in Q8 with pixel centres aligned, clamped to [0, sn - 1]:
 * (d + 0.5) sn / dn - 0.5. */
static void source_q8(uint32_t d, uint32_t dn, uint32_t sn, uint32_t *i0, uint32_t *i1, uint32_t *f)
{
    int64_t q = ((int64_t)(2 * (int64_t)d + 1) * (int64_t)sn * 128) / (int64_t)dn - 128;
    if (q < 0)
        q = 0;
    int64_t lim = (int64_t)(sn - 1) << 8;
    if (q > lim)
        q = lim;
    *i0 = (uint32_t)(q >> 8);
    *f = (uint32_t)(q & 255);
    *i1 = *i0 + 1 < sn ? *i0 + 1 : *i0;
}

size_t hz_rgb8_upscale_scratch(uint32_t dw)
{
    /* per column: two source offsets and a weight; two horizontally resampled rows in Q8 */
    return (size_t)dw * (2 * sizeof(uint32_t) + sizeof(uint16_t)) + 2 * (size_t)dw * 3 * sizeof(uint16_t) + 16;
}

/* Source row y resampled to dw pixels, Q8 (a (256 - f) + b f). */
static void resample_row(const uint8_t *restrict row, uint32_t dw, const uint32_t *restrict o0,
                         const uint32_t *restrict o1, const uint16_t *restrict fx, uint16_t *restrict out)
{
    for (uint32_t x = 0; x < dw; x++) {
        const uint8_t *a = row + o0[x], *b = row + o1[x];
        uint32_t f = fx[x], g = 256 - f;
        out[3 * x] = (uint16_t)(a[0] * g + b[0] * f);
        out[3 * x + 1] = (uint16_t)(a[1] * g + b[1] * f);
        out[3 * x + 2] = (uint16_t)(a[2] * g + b[2] * f);
    }
}

/* out = (t (256 - f) + b f + 2^15) >> 16, n values (restrict: the vector unit may take them in blocks) */
static void blend_rows(const uint16_t *restrict t, const uint16_t *restrict b, uint32_t f, uint8_t *restrict out,
                       uint32_t n)
{
    const uint32_t g = 256 - f;
    for (uint32_t i = 0; i < n; i++)
        out[i] = (uint8_t)(((uint32_t)t[i] * g + (uint32_t)b[i] * f + 32768u) >> 16);
}

void hz_rgb8_upscale(const uint8_t *src, uint32_t sw, uint32_t sh, size_t sstride, uint8_t *dst, uint32_t dw,
                     uint32_t dh, size_t dstride, bool nearest, void *scratch)
{
    if (sw == dw && sh == dh) {
        for (uint32_t y = 0; y < dh; y++)
            hz_memcpy(dst + y * dstride, src + y * sstride, (size_t)dw * 3);
        return;
    }
    if (nearest && dw % sw == 0 && dh % sh == 0) {
        const uint32_t kx = dw / sw, ky = dh / sh;
        for (uint32_t y = 0; y < sh; y++) {
            uint8_t *row = dst + (size_t)y * ky * dstride;
            const uint8_t *s = src + y * sstride;
            for (uint32_t x = 0; x < sw; x++)
                for (uint32_t i = 0; i < kx; i++)
                    hz_memcpy(row + ((size_t)x * kx + i) * 3, s + (size_t)x * 3, 3);
            for (uint32_t j = 1; j < ky; j++)
                hz_memcpy(row + j * dstride, row, (size_t)dw * 3);
        }
        return;
    }
    /* Separable: each source row resampled across once (the two an output row needs, reused while they stay the
     * same), then the rows blended down; the same arithmetic as blending the four pixels at once. */
    uint8_t *sp = (uint8_t *)scratch;
    sp += (16 - ((uintptr_t)sp & 15)) & 15;
    uint32_t *o0 = (uint32_t *)(void *)sp, *o1 = o0 + dw;
    uint16_t *rows = (uint16_t *)(void *)(o1 + dw), *fx = rows + 2 * (size_t)dw * 3;
    for (uint32_t x = 0; x < dw; x++) {
        uint32_t x0, x1, f;
        source_q8(x, dw, sw, &x0, &x1, &f);
        o0[x] = x0 * 3, o1[x] = x1 * 3, fx[x] = (uint16_t)f;
    }
    uint16_t *row[2] = { rows, rows + (size_t)dw * 3 };
    uint32_t have[2] = { UINT32_MAX, UINT32_MAX };
    for (uint32_t y = 0; y < dh; y++) {
        uint32_t y0, y1, fy;
        source_q8(y, dh, sh, &y0, &y1, &fy);
        if (have[0] != y0) {
            if (have[1] == y0) { /* moving down: the lower row becomes the upper */
                uint16_t *tmp = row[0];
                row[0] = row[1], row[1] = tmp;
                have[0] = have[1], have[1] = UINT32_MAX;
            } else {
                resample_row(src + y0 * sstride, dw, o0, o1, fx, row[0]);
                have[0] = y0;
            }
        }
        if (have[1] != y1) {
            resample_row(src + y1 * sstride, dw, o0, o1, fx, row[1]);
            have[1] = y1;
        }
        blend_rows(row[0], row[1], fy, dst + y * dstride, dw * 3);
    }
}
