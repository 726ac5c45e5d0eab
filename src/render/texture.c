/* Texture sampling: bilinear filtering with wrap-around addressing on the mip level a ray cone selects
 * (Akenine-Moeller et al., "Texture Level of Detail Strategies for Real-Time Ray Tracing", 2019). Texels are
 * sRGB colour + linear alpha; colour is decoded to linear light before filtering. */
#include "hz/image.h"
#include "render_internal.h"

float hz_log2_approx(float x)
{
    /* Exponent plus a quadratic fit of log2 on the mantissa [1, 2): error below 0.005, plenty for a mip
     * level. Non-positive and non-finite inputs give a large negative level (finest mip). */
    if (!(x > 0.0f) || !hz_isfinitef(x))
        return -126.0f;
    uint32_t bits = hz_float_bits(x);
    int32_t e = (int32_t)((bits >> 23) & 0xffu) - 127;
    float m = hz_float_from_bits((bits & 0x007fffffu) | 0x3f800000u);
    return (float)e + (-0.34484843f * m + 2.02466578f) * m - 1.67487759f;
}

/* i wrapped into [0, n). Bilinear's corners lie in [-1, n], where it needs no division. */
HZ_INLINE uint32_t wrap(int32_t i, uint32_t n)
{
    if ((uint32_t)i < n)
        return (uint32_t)i;
    if (i < 0 && i >= -(int32_t)n)
        return (uint32_t)(i + (int32_t)n);
    if (i >= (int32_t)n && i - (int32_t)n < (int32_t)n)
        return (uint32_t)(i - (int32_t)n);
    int32_t r = i % (int32_t)n;
    return (uint32_t)(r < 0 ? r + (int32_t)n : r);
}

/* The four texels bilinear filtering at (u, v) reads on a w x h level (byte offsets of its corners x0y0, x1y0,
 * x0y1, x1y1, wrapped) and its weights ax, ay. */
typedef struct corners {
    size_t at[4];
    float ax, ay;
} corners_t;

HZ_INLINE void corners_of(uint32_t w, uint32_t h, float u, float v, corners_t *c)
{
    /* Texel centres at half-integers; keep coordinates small so float keeps its precision. */
    float fu = (u - hz_floorf(u)) * (float)w - 0.5f;
    float fv = (v - hz_floorf(v)) * (float)h - 0.5f;
    float x0f = hz_floorf(fu), y0f = hz_floorf(fv);
    c->ax = fu - x0f, c->ay = fv - y0f;
    int32_t x0 = (int32_t)x0f, y0 = (int32_t)y0f;
    size_t xa = wrap(x0, w), xb = wrap(x0 + 1, w), ya = wrap(y0, h) * (size_t)w, yb = wrap(y0 + 1, h) * (size_t)w;
    c->at[0] = (ya + xa) * 4, c->at[1] = (ya + xb) * 4, c->at[2] = (yb + xa) * 4, c->at[3] = (yb + xb) * 4;
}

/* Texel p as linear rgb + alpha. */
static void fetch(const uint8_t *p, float out[4])
{
    out[0] = hz_srgb8_decode(p[0]);
    out[1] = hz_srgb8_decode(p[1]);
    out[2] = hz_srgb8_decode(p[2]);
    out[3] = (float)p[3] * (1.0f / 255.0f);
}

/* Level `level` of texture t: its texels and size. */
static const uint8_t *level_data(const hz_scene_t *s, const hz_texture_t *t, uint32_t level, uint32_t *w,
                                 uint32_t *h)
{
    return s->texels + hz_texture_level_first(t, level, w, h) * 4;
}

size_t hz_texture_level_first(const hz_texture_t *t, uint32_t level, uint32_t *w, uint32_t *h)
{
    size_t first = t->first_texel;
    uint32_t lw = t->width, lh = t->height;
    for (uint32_t l = 0; l < level; l++)
        hz_texture_level_next(&first, &lw, &lh);
    *w = lw;
    *h = lh;
    return first;
}

static void bilinear(const hz_scene_t *s, const hz_texture_t *t, uint32_t level, float u, float v, float rgba[4])
{
    uint32_t w, h;
    const uint8_t *base = level_data(s, t, level, &w, &h);
    corners_t c;
    corners_of(w, h, u, v, &c);
    float a[4], b[4], cc[4], d[4];
    fetch(base + c.at[0], a);
    fetch(base + c.at[1], b);
    fetch(base + c.at[2], cc);
    fetch(base + c.at[3], d);
    for (int k = 0; k < 4; k++) {
        float top = a[k] + (b[k] - a[k]) * c.ax;
        float bot = cc[k] + (d[k] - cc[k]) * c.ax;
        rgba[k] = top + (bot - top) * c.ay;
    }
}

void hz_texture_sample(const hz_scene_t *s, int32_t tex, float u, float v, float lod, float rgba[4])
{
    if (!hz_texture_usable(s, tex, u, v)) {
        rgba[0] = rgba[1] = rgba[2] = rgba[3] = 1.0f;
        return;
    }
    const hz_texture_t *t = &s->textures[tex];
    bilinear(s, t, hz_texture_level_of(t, lod), u, v, rgba);
}

float hz_texture_alpha(const hz_scene_t *s, int32_t tex, float u, float v)
{
    /* hz_texture_sample at lod 0 (level 0), alpha only: the any-hit test of every cut-out and blended layer. The
     * same operations on the alpha channel, without decoding colour. */
    if (!hz_texture_usable(s, tex, u, v))
        return 1.0f;
    const hz_texture_t *t = &s->textures[tex];
    uint32_t w, h;
    const uint8_t *base = level_data(s, t, 0, &w, &h);
    corners_t c;
    corners_of(w, h, u, v, &c);
    const float k = 1.0f / 255.0f;
    float a = (float)base[c.at[0] + 3] * k, b = (float)base[c.at[1] + 3] * k;
    float cc = (float)base[c.at[2] + 3] * k, d = (float)base[c.at[3] + 3] * k;
    float top = a + (b - a) * c.ax;
    float bot = cc + (d - cc) * c.ax;
    return top + (bot - top) * c.ay;
}
