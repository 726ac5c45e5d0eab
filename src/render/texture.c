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

static uint32_t wrap(int32_t i, uint32_t n)
{
    int32_t r = i % (int32_t)n;
    return (uint32_t)(r < 0 ? r + (int32_t)n : r);
}

/* Fetches texel (x, y) of level `level` with wrapping; writes linear rgb + alpha. */
static void fetch(const hz_scene_t *s, const hz_texture_t *t, const uint8_t *base, uint32_t w, uint32_t h,
                  int32_t x, int32_t y, float out[4])
{
    (void)s;
    (void)t;
    const uint8_t *p = base + ((size_t)wrap(y, h) * w + wrap(x, w)) * 4;
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
    for (uint32_t l = 0; l < level; l++) {
        first += (size_t)lw * lh;
        lw = lw > 1 ? lw / 2 : 1;
        lh = lh > 1 ? lh / 2 : 1;
    }
    *w = lw;
    *h = lh;
    return first;
}

uint32_t hz_texture_level_of(const hz_texture_t *t, float lod)
{
    float l = hz_isfinitef(lod) ? lod + 0.5f : 0.0f;
    return l <= 0.0f ? 0u : (uint32_t)hz_minf(l, (float)(t->levels - 1));
}

bool hz_texture_usable(const hz_scene_t *s, int32_t tex, float u, float v)
{
    return !(tex < 0 || (uint32_t)tex >= s->texture_count || !hz_isfinitef(u) || !hz_isfinitef(v));
}

static void bilinear(const hz_scene_t *s, const hz_texture_t *t, uint32_t level, float u, float v, float rgba[4])
{
    uint32_t w, h;
    const uint8_t *base = level_data(s, t, level, &w, &h);
    /* Texel centres at half-integers; keep coordinates small so float keeps its precision. */
    float fu = (u - hz_floorf(u)) * (float)w - 0.5f;
    float fv = (v - hz_floorf(v)) * (float)h - 0.5f;
    float x0f = hz_floorf(fu), y0f = hz_floorf(fv);
    float ax = fu - x0f, ay = fv - y0f;
    int32_t x0 = (int32_t)x0f, y0 = (int32_t)y0f;
    float a[4], b[4], c[4], d[4];
    fetch(s, t, base, w, h, x0, y0, a);
    fetch(s, t, base, w, h, x0 + 1, y0, b);
    fetch(s, t, base, w, h, x0, y0 + 1, c);
    fetch(s, t, base, w, h, x0 + 1, y0 + 1, d);
    for (int k = 0; k < 4; k++) {
        float top = a[k] + (b[k] - a[k]) * ax;
        float bot = c[k] + (d[k] - c[k]) * ax;
        rgba[k] = top + (bot - top) * ay;
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
    float rgba[4];
    hz_texture_sample(s, tex, u, v, 0.0f, rgba);
    return rgba[3];
}
