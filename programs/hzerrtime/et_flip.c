/*
 * LDR-FLIP (see et_flip.h). Single precision throughout, like the paper's reference, so that the mean agrees with
 * NVIDIA's tool to float rounding; planar images and separable filters whose inner loops run over x, so the
 * compiler vectorises them.
 */
#include "et_flip.h"

#include <math.h>
#include <stdbool.h>

#define FLIP_PI 3.14159265358979f

/* Paper constants. */
static const float qc = 0.7f, pc = 0.4f, pt = 0.95f, gw = 0.082f, qf = 0.5f;

/* Contrast sensitivity (spatial form): a1, b1, a2, b2 per YCxCz channel. */
static const float csf_a1[3] = { 1.0f, 1.0f, 34.1f }, csf_b1[3] = { 0.0047f, 0.0053f, 0.04f };
static const float csf_a2[3] = { 0.0f, 0.0f, 13.5f }, csf_b2[3] = { 1.0e-5f, 1.0e-5f, 0.025f };

/* sRGB primaries -> XYZ (exact rational form of the IEC 61966-2-1 matrix). */
static const double rgb2xyz_d[3][3] = {
    { 10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0 },
    { 2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0 },
    { 1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0 },
};

typedef struct colour_space {
    float m[3][3];    /* linear RGB -> XYZ */
    float minv[3][3]; /* XYZ -> linear RGB */
    float white[3];   /* XYZ of RGB (1, 1, 1) */
    float inv_white[3];
} colour_space_t;

static void colour_space_init(colour_space_t *cs)
{
    double inv[3][3];
    const double(*a)[3] = rgb2xyz_d;
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            /* Cofactor of a[j][i] (transposed adjugate). */
            int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            inv[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
        }
    for (int i = 0; i < 3; i++) {
        double w = a[i][0] + a[i][1] + a[i][2];
        cs->white[i] = (float)w;
        cs->inv_white[i] = (float)(1.0 / w);
        for (int j = 0; j < 3; j++) {
            cs->m[i][j] = (float)a[i][j];
            cs->minv[i][j] = (float)inv[i][j];
        }
    }
}

static void mat3(const float m[3][3], const float v[3], float out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
}

static void xyz_to_ycxcz(const colour_space_t *cs, const float xyz[3], float out[3])
{
    float x = xyz[0] * cs->inv_white[0], y = xyz[1] * cs->inv_white[1], z = xyz[2] * cs->inv_white[2];
    out[0] = 116.0f * y - 16.0f;
    out[1] = 500.0f * (x - y);
    out[2] = 200.0f * (y - z);
}

static void ycxcz_to_xyz(const colour_space_t *cs, const float ycc[3], float out[3])
{
    float y = (ycc[0] + 16.0f) / 116.0f;
    float x = y + ycc[1] / 500.0f, z = y - ycc[2] / 200.0f;
    out[0] = x * cs->white[0];
    out[1] = y * cs->white[1];
    out[2] = z * cs->white[2];
}

/* CIELAB with the Hunt adjustment (chroma scaled by L / 100). */
static void xyz_to_hunt_lab(const colour_space_t *cs, const float xyz[3], float out[3])
{
    const float delta = 6.0f / 29.0f, delta3 = delta * delta * delta;
    const float factor = 1.0f / (3.0f * delta * delta), term = 4.0f / 29.0f;
    float f[3];
    for (int i = 0; i < 3; i++) {
        float t = xyz[i] * cs->inv_white[i];
        f[i] = t > delta3 ? powf(t, 1.0f / 3.0f) : factor * t + term;
    }
    float L = 116.0f * f[1] - 16.0f;
    out[0] = L;
    out[1] = 0.01f * L * (500.0f * (f[0] - f[1]));
    out[2] = 0.01f * L * (200.0f * (f[1] - f[2]));
}

static float hyab(const float a[3], const float b[3])
{
    float da = a[1] - b[1], db = a[2] - b[2];
    return fabsf(a[0] - b[0]) + sqrtf(da * da + db * db);
}

static float clamp01(float v)
{
    return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; /* NaN -> 0 */
}

/* ---- kernels ---- */

static int spatial_radius(float ppd)
{
    float bmax = 0.0f;
    for (int c = 0; c < 3; c++) {
        bmax = fmaxf(bmax, csf_b1[c]);
        bmax = fmaxf(bmax, csf_b2[c]);
    }
    return (int)ceilf(3.0f * sqrtf(bmax / (2.0f * FLIP_PI * FLIP_PI)) * ppd);
}

static int feature_radius(float ppd)
{
    return (int)ceilf(3.0f * (0.5f * gw * ppd));
}

/* ky, kx: Y and Cx kernels (each sums to 1); kz1, kz2: the two Gaussians of Cz, scaled so that
 * kz1 (x) kz1 + kz2 (x) kz2 sums to 1 in 2D (each carries the square root of its 2D weight). */
static void spatial_kernels(float ppd, int r, float *ky, float *kx, float *kz1, float *kz2)
{
    const float pi2 = FLIP_PI * FLIP_PI, dx = 1.0f / ppd;
    float sy = 0.0f, sx = 0.0f, s1 = 0.0f, s2 = 0.0f;
    for (int i = 0; i <= 2 * r; i++) {
        float x = (float)(i - r) * dx, x2 = x * x;
        ky[i] = csf_a1[0] * sqrtf(FLIP_PI / csf_b1[0]) * expf(-pi2 * x2 / csf_b1[0]);
        kx[i] = csf_a1[1] * sqrtf(FLIP_PI / csf_b1[1]) * expf(-pi2 * x2 / csf_b1[1]);
        kz1[i] = sqrtf(csf_a1[2] * sqrtf(FLIP_PI / csf_b1[2])) * expf(-pi2 * x2 / csf_b1[2]);
        kz2[i] = sqrtf(csf_a2[2] * sqrtf(FLIP_PI / csf_b2[2])) * expf(-pi2 * x2 / csf_b2[2]);
        sy += ky[i];
        sx += kx[i];
        s1 += kz1[i];
        s2 += kz2[i];
    }
    float ny = 1.0f / sy, nx = 1.0f / sx, nz = 1.0f / sqrtf(s1 * s1 + s2 * s2);
    for (int i = 0; i <= 2 * r; i++) {
        ky[i] *= ny;
        kx[i] *= nx;
        kz1[i] *= nz;
        kz2[i] *= nz;
    }
}

/* Gaussian g, its first derivative dg and second derivative ddg (sd in pixels); g sums to 1, the positive and
 * the negative weights of dg and ddg each sum to +1 and -1. */
static void feature_kernels(float ppd, int r, float *g, float *dg, float *ddg)
{
    const float sd = 0.5f * gw * ppd;
    float gs = 0.0f, dpos = 0.0f, dneg = 0.0f, ddpos = 0.0f, ddneg = 0.0f;
    for (int i = 0; i <= 2 * r; i++) {
        float x = (float)(i - r);
        g[i] = expf(-(x * x) / (2.0f * sd * sd));
        dg[i] = -x * g[i];
        ddg[i] = (x * x / (sd * sd) - 1.0f) * g[i];
        gs += g[i];
        if (dg[i] > 0.0f)
            dpos += dg[i];
        else
            dneg -= dg[i];
        if (ddg[i] > 0.0f)
            ddpos += ddg[i];
        else
            ddneg -= ddg[i];
    }
    for (int i = 0; i <= 2 * r; i++) {
        g[i] /= gs;
        dg[i] /= dg[i] > 0.0f ? dpos : dneg;
        ddg[i] /= ddg[i] > 0.0f ? ddpos : ddneg;
    }
}

/* ---- separable filtering, edges clamped ---- */

/* dst = src convolved along x with k (2r + 1 taps); pad holds w + 2r floats. Each output sums its taps in
 * order from the leftmost, starting at 0. */
static void filter_x(const float *src, float *dst, uint32_t w, uint32_t h, const float *k, int r, float *pad)
{
    for (uint32_t y = 0; y < h; y++) {
        const float *s = src + (size_t)y * w;
        float *d = dst + (size_t)y * w;
        for (int i = 0; i < r; i++) {
            pad[i] = s[0];
            pad[(size_t)r + w + i] = s[w - 1];
        }
        for (uint32_t x = 0; x < w; x++)
            pad[(size_t)r + x] = s[x];
        for (uint32_t x = 0; x < w; x++)
            d[x] = 0.0f;
        for (int j = 0; j <= 2 * r; j++) {
            const float kj = k[j], *p = pad + j;
            for (uint32_t x = 0; x < w; x++)
                d[x] += kj * p[x];
        }
    }
}

/* One output row y of src convolved along y with k. */
static void filter_y_row(const float *src, float *row, uint32_t w, uint32_t h, uint32_t y, const float *k, int r)
{
    for (uint32_t x = 0; x < w; x++)
        row[x] = 0.0f;
    for (int j = 0; j <= 2 * r; j++) {
        long yy = (long)y + j - r;
        yy = yy < 0 ? 0 : yy >= (long)h ? (long)h - 1 : yy;
        const float kj = k[j], *s = src + (size_t)yy * w;
        for (uint32_t x = 0; x < w; x++)
            row[x] += kj * s[x];
    }
}

/* ---- the metric ---- */

float hz_flip_ppd(float distance_m, float width_px, float width_m)
{
    return distance_m * (width_px / width_m) * (FLIP_PI / 180.0f);
}

#define PLANES 16
#define ROWS 8

size_t hz_flip_scratch_bytes(uint32_t width, uint32_t height, float ppd)
{
    int r = spatial_radius(ppd), rf = feature_radius(ppd);
    int rmax = r > rf ? r : rf;
    size_t plane = (size_t)width * height * sizeof(float);
    return PLANES * (plane + 64) + ROWS * ((size_t)width * sizeof(float) + 64) +
           ((size_t)width + 2 * (size_t)rmax) * sizeof(float) + 7 * (2 * (size_t)rmax + 1) * sizeof(float) + 1024;
}

static void to_ycxcz(const colour_space_t *cs, const hz_image_t *img, float *py, float *px, float *pz)
{
    size_t n = hz_image_pixels(img);
    for (size_t i = 0; i < n; i++) {
        float rgb[3] = { clamp01(img->rgb[3 * i]), clamp01(img->rgb[3 * i + 1]), clamp01(img->rgb[3 * i + 2]) };
        float xyz[3], ycc[3];
        mat3(cs->m, rgb, xyz);
        xyz_to_ycxcz(cs, xyz, ycc);
        py[i] = ycc[0];
        px[i] = ycc[1];
        pz[i] = ycc[2];
    }
}

/* Filtered YCxCz -> linear RGB (clamped) -> Hunt-adjusted Lab. */
static void filtered_to_lab(const colour_space_t *cs, float y, float cx, float cz, float lab[3])
{
    float ycc[3] = { y, cx, cz }, xyz[3], rgb[3];
    ycxcz_to_xyz(cs, ycc, xyz);
    mat3(cs->minv, xyz, rgb);
    for (int c = 0; c < 3; c++)
        rgb[c] = clamp01(rgb[c]);
    mat3(cs->m, rgb, xyz);
    xyz_to_hunt_lab(cs, xyz, lab);
}

/* The remapping's scale: the (qc-powered) distance between Hunt-adjusted green and blue, the largest in gamut. */
static float max_colour_distance(const colour_space_t *cs)
{
    const float green[3] = { 0.0f, 1.0f, 0.0f }, blue[3] = { 0.0f, 0.0f, 1.0f };
    float xyz[3], lg[3], lb[3];
    mat3(cs->m, green, xyz);
    xyz_to_hunt_lab(cs, xyz, lg);
    mat3(cs->m, blue, xyz);
    xyz_to_hunt_lab(cs, xyz, lb);
    return powf(hyab(lg, lb), qc);
}

hz_status_t hz_flip(const hz_image_t *ref, const hz_image_t *test, float ppd, hz_arena_t *scratch, float *map,
                    double *mean, hz_error_t *err)
{
    if (ref->width != test->width || ref->height != test->height)
        return hz_error_set(err, HZ_E_INVALID_ARG, "flip: image sizes differ (%ux%u vs %ux%u)",
                            (unsigned)ref->width, (unsigned)ref->height, (unsigned)test->width,
                            (unsigned)test->height);
    if (!(ppd > 0.0f && ppd <= 1000.0f))
        return hz_error_set(err, HZ_E_INVALID_ARG, "flip: pixels per degree must be in (0, 1000]");
    const uint32_t w = ref->width, h = ref->height;
    const size_t n = (size_t)w * h;
    const int r = spatial_radius(ppd), rf = feature_radius(ppd), rmax = r > rf ? r : rf;
    hz_arena_mark_t mark = hz_arena_mark(scratch);
    float *pl[PLANES], *row[ROWS];
    float *pad = hz_arena_alloc_array(scratch, (size_t)w + 2 * (size_t)rmax, sizeof(float), 64);
    float *kern = hz_arena_alloc_array(scratch, 7 * (2 * (size_t)rmax + 1), sizeof(float), 64);
    bool ok = pad && kern;
    for (int i = 0; i < PLANES && ok; i++)
        ok = (pl[i] = hz_arena_alloc_array(scratch, n, sizeof(float), 64)) != NULL;
    for (int i = 0; i < ROWS && ok; i++)
        ok = (row[i] = hz_arena_alloc_array(scratch, w, sizeof(float), 64)) != NULL;
    if (!ok) {
        hz_arena_error(scratch, err);
        hz_error_prefix(err, "flip scratch");
        hz_arena_reset(scratch, mark);
        return HZ_E_NO_MEMORY;
    }
    colour_space_t cs;
    colour_space_init(&cs);
    const size_t kn = 2 * (size_t)rmax + 1;
    float *ky = kern, *kx = kern + kn, *kz1 = kern + 2 * kn, *kz2 = kern + 3 * kn;
    float *g = kern + 4 * kn, *dg = kern + 5 * kn, *ddg = kern + 6 * kn;
    spatial_kernels(ppd, r, ky, kx, kz1, kz2);
    feature_kernels(ppd, rf, g, dg, ddg);

    /* Planes: 0..2 reference Y Cx Cz, 3..5 test; 6..13 filtered (per image: Y, Cx, Cz1, Cz2); 14 temp;
     * 15 colour difference. */
    float *src[2][3] = { { pl[0], pl[1], pl[2] }, { pl[3], pl[4], pl[5] } };
    float *flt[2][4] = { { pl[6], pl[7], pl[8], pl[9] }, { pl[10], pl[11], pl[12], pl[13] } };
    float *tmp = pl[14], *cdiff = pl[15];
    const hz_image_t *imgs[2] = { ref, test };
    for (int m = 0; m < 2; m++) {
        to_ycxcz(&cs, imgs[m], src[m][0], src[m][1], src[m][2]);
        const float *k[4] = { ky, kx, kz1, kz2 };
        const int ch[4] = { 0, 1, 2, 2 };
        for (int c = 0; c < 4; c++) {
            filter_x(src[m][ch[c]], tmp, w, h, k[c], r, pad);
            for (uint32_t y = 0; y < h; y++)
                filter_y_row(tmp, flt[m][c] + (size_t)y * w, w, h, y, k[c], r);
        }
    }

    /* Colour difference. */
    const float cmax = max_colour_distance(&cs), pccmax = pc * cmax;
    for (size_t i = 0; i < n; i++) {
        float la[3], lt[3];
        filtered_to_lab(&cs, flt[0][0][i], flt[0][1][i], flt[0][2][i] + flt[0][3][i], la);
        filtered_to_lab(&cs, flt[1][0][i], flt[1][1][i], flt[1][2][i] + flt[1][3][i], lt);
        float d = powf(hyab(la, lt), qc);
        cdiff[i] = d < pccmax ? d * (pt / pccmax) : pt + ((d - pccmax) / (cmax - pccmax)) * (1.0f - pt);
    }

    /* Features on normalised luminance (Y / Yw = (Y_YCxCz + 16) / 116), in place of the Y planes; the filtered
     * planes are free again and take the x-pass results (per image: d/dx, d2/dx2, Gaussian). */
    const float inv116 = 1.0f / 116.0f, s16 = 16.0f / 116.0f;
    float *fx[2][3] = { { flt[0][0], flt[0][1], flt[0][2] }, { flt[1][0], flt[1][1], flt[1][2] } };
    for (int m = 0; m < 2; m++) {
        float *yn = src[m][0];
        for (size_t i = 0; i < n; i++)
            yn[i] = yn[i] * inv116 + s16;
        filter_x(yn, fx[m][0], w, h, dg, rf, pad);
        filter_x(yn, fx[m][1], w, h, ddg, rf, pad);
        filter_x(yn, fx[m][2], w, h, g, rf, pad);
    }
    const float inv_sqrt2 = 1.0f / sqrtf(2.0f);
    double sum = 0.0;
    for (uint32_t y = 0; y < h; y++) {
        /* rows: per image Dx, DDx, Dy, DDy */
        for (int m = 0; m < 2; m++) {
            filter_y_row(fx[m][0], row[4 * m + 0], w, h, y, g, rf);
            filter_y_row(fx[m][1], row[4 * m + 1], w, h, y, g, rf);
            filter_y_row(fx[m][2], row[4 * m + 2], w, h, y, dg, rf);
            filter_y_row(fx[m][2], row[4 * m + 3], w, h, y, ddg, rf);
        }
        for (uint32_t x = 0; x < w; x++) {
            float er = sqrtf(row[0][x] * row[0][x] + row[2][x] * row[2][x]);
            float et = sqrtf(row[4][x] * row[4][x] + row[6][x] * row[6][x]);
            float pr = sqrtf(row[1][x] * row[1][x] + row[3][x] * row[3][x]);
            float ptt = sqrtf(row[5][x] * row[5][x] + row[7][x] * row[7][x]);
            float fd = powf(inv_sqrt2 * fmaxf(fabsf(er - et), fabsf(pr - ptt)), qf);
            float e = powf(cdiff[(size_t)y * w + x], 1.0f - fd);
            if (map)
                map[(size_t)y * w + x] = e;
            sum += e;
        }
    }
    *mean = sum / (double)n;
    hz_arena_reset(scratch, mark);
    return HZ_OK;
}
