/* MSE/PSNR, SSIM and frame averaging (see et_metrics.h). */
#include "et_metrics.h"

#include <math.h>

static hz_status_t same_size(const hz_image_t *a, const hz_image_t *b, const char *what, hz_error_t *err)
{
    if (a->width != b->width || a->height != b->height)
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s: image sizes differ (%ux%u vs %ux%u)", what,
                            (unsigned)a->width, (unsigned)a->height, (unsigned)b->width, (unsigned)b->height);
    return HZ_OK;
}

static double clamp01(float v)
{
    return v > 0.0f ? (v < 1.0f ? (double)v : 1.0) : 0.0; /* NaN -> 0 */
}

hz_status_t hz_mse(const hz_image_t *ref, const hz_image_t *test, hz_mse_t *out, hz_error_t *err)
{
    hz_status_t s = same_size(ref, test, "mse", err);
    if (s != HZ_OK)
        return s;
    size_t n = hz_image_pixels(ref) * 3;
    /* Integer sum for the codes: exact, and order-independent. */
    uint64_t code_sq = 0;
    double lin_sq = 0.0;
    for (size_t i = 0; i < n; i++) {
        int d = (int)hz_srgb8_encode(ref->rgb[i]) - (int)hz_srgb8_encode(test->rgb[i]);
        code_sq += (uint64_t)(d * d);
        double e = clamp01(ref->rgb[i]) - clamp01(test->rgb[i]);
        lin_sq += e * e;
    }
    out->srgb8 = (double)code_sq / (double)n;
    out->linear = lin_sq / (double)n;
    return HZ_OK;
}

double hz_psnr(double mse, double peak)
{
    if (!(mse > 0.0))
        return mse == 0.0 ? INFINITY : NAN;
    return 10.0 * log10(peak * peak / mse);
}

size_t hz_ssim_scratch_bytes(uint32_t width, uint32_t height)
{
    (void)height;
    /* Two luma rows, and 5 statistics x 11 rows of horizontally filtered values, plus alignment. */
    return (2 * (size_t)width + 5 * HZ_SSIM_WINDOW * (size_t)width) * sizeof(double) + 256;
}

static void luma_row(const hz_image_t *img, uint32_t y, double *out)
{
    const float *p = hz_image_at(img, 0, y);
    for (uint32_t x = 0; x < img->width; x++, p += 3)
        out[x] = 0.2126 * hz_srgb8_encode(p[0]) + 0.7152 * hz_srgb8_encode(p[1]) + 0.0722 * hz_srgb8_encode(p[2]);
}

hz_status_t hz_ssim(const hz_image_t *ref, const hz_image_t *test, hz_arena_t *scratch, double *ssim,
                    hz_error_t *err)
{
    hz_status_t s = same_size(ref, test, "ssim", err);
    if (s != HZ_OK)
        return s;
    const uint32_t W = HZ_SSIM_WINDOW, R = W / 2;
    uint32_t w = ref->width, h = ref->height;
    if (w < W || h < W)
        return hz_error_set(err, HZ_E_INVALID_ARG, "ssim: image %ux%u is smaller than the %ux%u window",
                            (unsigned)w, (unsigned)h, (unsigned)W, (unsigned)W);
    hz_arena_mark_t mark = hz_arena_mark(scratch);
    uint32_t ow = w - W + 1, oh = h - W + 1;
    double *la = hz_arena_alloc_array(scratch, w, sizeof(double), 64);
    double *lb = hz_arena_alloc_array(scratch, w, sizeof(double), 64);
    double *ring = hz_arena_alloc_array(scratch, (size_t)5 * W * ow, sizeof(double), 64);
    if (!la || !lb || !ring) {
        hz_arena_error(scratch, err);
        hz_error_prefix(err, "ssim scratch");
        hz_arena_reset(scratch, mark);
        return HZ_E_NO_MEMORY;
    }
    double g[HZ_SSIM_WINDOW], gsum = 0.0;
    for (uint32_t k = 0; k < W; k++) {
        double d = (double)k - R;
        g[k] = exp(-d * d / (2.0 * 1.5 * 1.5));
        gsum += g[k];
    }
    for (uint32_t k = 0; k < W; k++)
        g[k] /= gsum;
    const double L = 255.0, C1 = (0.01 * L) * (0.01 * L), C2 = (0.03 * L) * (0.03 * L);
    double total = 0.0;
    for (uint32_t y = 0; y < h; y++) {
        /* Horizontal 'valid' filtering of a, b, a^2, b^2, ab for row y into ring slot y % W. */
        luma_row(ref, y, la);
        luma_row(test, y, lb);
        double *slot = ring + (size_t)5 * ow * (y % W);
        double *ma = slot, *mb = slot + ow, *maa = slot + 2 * ow, *mbb = slot + 3 * ow, *mab = slot + 4 * ow;
        for (uint32_t x = 0; x < ow; x++) {
            double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
            for (uint32_t k = 0; k < W; k++) {
                double a = la[x + k], b = lb[x + k], gk = g[k];
                sa += gk * a;
                sb += gk * b;
                saa += gk * a * a;
                sbb += gk * b * b;
                sab += gk * a * b;
            }
            ma[x] = sa;
            mb[x] = sb;
            maa[x] = saa;
            mbb[x] = sbb;
            mab[x] = sab;
        }
        if (y + 1 < W)
            continue;
        /* Vertical filtering over rows y-W+1 .. y: one output row. */
        uint32_t top = y + 1 - W;
        for (uint32_t x = 0; x < ow; x++) {
            double mu_a = 0, mu_b = 0, e_aa = 0, e_bb = 0, e_ab = 0;
            for (uint32_t k = 0; k < W; k++) {
                const double *sl = ring + (size_t)5 * ow * ((top + k) % W);
                double gk = g[k];
                mu_a += gk * sl[x];
                mu_b += gk * sl[ow + x];
                e_aa += gk * sl[2 * ow + x];
                e_bb += gk * sl[3 * ow + x];
                e_ab += gk * sl[4 * ow + x];
            }
            double va = e_aa - mu_a * mu_a, vb = e_bb - mu_b * mu_b, cov = e_ab - mu_a * mu_b;
            total += ((2.0 * mu_a * mu_b + C1) * (2.0 * cov + C2)) /
                     ((mu_a * mu_a + mu_b * mu_b + C1) * (va + vb + C2));
        }
    }
    *ssim = total / ((double)ow * oh);
    hz_arena_reset(scratch, mark);
    return HZ_OK;
}

hz_status_t hz_image_mean(hz_image_t *out, const hz_image_t *const *frames, unsigned k, hz_error_t *err)
{
    if (k == 0)
        return hz_error_set(err, HZ_E_INVALID_ARG, "image mean of no frames");
    for (unsigned i = 0; i < k; i++) {
        hz_status_t s = same_size(out, frames[i], "image mean", err);
        if (s != HZ_OK)
            return s;
    }
    size_t n = hz_image_pixels(out) * 3;
    float inv = 1.0f / (float)k;
    for (size_t i = 0; i < n; i++) {
        float sum = 0.0f;
        for (unsigned j = 0; j < k; j++)
            sum += frames[j]->rgb[i];
        out->rgb[i] = sum * inv;
    }
    return HZ_OK;
}
