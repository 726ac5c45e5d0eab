/* Upscaling of RGB24 frames (see hz/rgb8.h). */
#include "hz/rgb8.h"

#include "hz/base.h"

/* Source coordinate of destination pixel d (of dn) in Q8 with pixel centres aligned, clamped to [0, sn - 1]. */
static void source_q8(uint32_t d, uint32_t dn, uint32_t sn, uint32_t *i0, uint32_t *i1, uint32_t *f)
{
    /* (d + 0.5) * sn / dn - 0.5, in Q8: ((2d + 1) * sn * 128) / dn - 128 */
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

void hz_rgb8_upscale(const uint8_t *src, uint32_t sw, uint32_t sh, size_t sstride, uint8_t *dst, uint32_t dw,
                     uint32_t dh, size_t dstride, bool nearest)
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
    for (uint32_t y = 0; y < dh; y++) {
        uint32_t y0, y1, fy;
        source_q8(y, dh, sh, &y0, &y1, &fy);
        const uint8_t *r0 = src + y0 * sstride, *r1 = src + y1 * sstride;
        uint8_t *out = dst + y * dstride;
        for (uint32_t x = 0; x < dw; x++) {
            uint32_t x0, x1, fx;
            source_q8(x, dw, sw, &x0, &x1, &fx);
            for (uint32_t c = 0; c < 3; c++) {
                uint32_t a = r0[x0 * 3 + c], b = r0[x1 * 3 + c], d = r1[x0 * 3 + c], e = r1[x1 * 3 + c];
                uint32_t top = a * (256 - fx) + b * fx, bot = d * (256 - fx) + e * fx; /* Q8 */
                uint32_t v = top * (256 - fy) + bot * fy;                            /* Q16 */
                out[x * 3 + c] = (uint8_t)((v + 32768) >> 16);
            }
        }
    }
}
