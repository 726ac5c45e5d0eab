/* Texture decoding and mip chains (see bake.h). Images are decoded to RGBA8 by stb_image (Debian libstb),
 * filtered in linear light: colour bytes are sRGB, so each 2x2 box average converts to linear, weights colour
 * by alpha (fully transparent texels must not darken their neighbours' colour: cutout foliage would get
 * black fringes), averages alpha as stored (it is linear), and converts back with exact rounding. Levels halve
 * with floor (min 1), the rule the loader checks; a texture larger than max_size keeps only the levels that fit. */
#include "bake.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image.h>

static float srgb_lin[256]; /* byte -> linear */
static float srgb_cut[256]; /* linear value where the encoded byte steps from k to k + 1 */
static int tables_ready;

static float decode(float c)
{
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

static void init_tables(void)
{
    if (tables_ready)
        return;
    for (int k = 0; k < 256; k++) {
        srgb_lin[k] = decode((float)k / 255.0f);
        srgb_cut[k] = decode(((float)k + 0.5f) / 255.0f);
    }
    tables_ready = 1;
}

/* round(255 * encode(x)) by binary search over the step points: exact and without pow per texel. */
static uint8_t encode_byte(float x)
{
    int lo = 0, hi = 255; /* answer in [lo, hi] */
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (x >= srgb_cut[mid])
            lo = mid + 1;
        else
            hi = mid;
    }
    return (uint8_t)lo;
}

static uint8_t unit_byte(float a)
{
    float v = a * 255.0f + 0.5f;
    return v <= 0.0f ? 0 : v >= 255.0f ? 255 : (uint8_t)v;
}

static int find_texture(const hz_bake_scene_t *s, const char *key, int alpha_from_luma)
{
    for (size_t i = 0; i < s->texs.len; i++) {
        const hz_bake_texture_t *t = HZ_BAKE_AT(s->texs, hz_bake_texture_t, i);
        if (t->alpha_from_luma == alpha_from_luma && !strcmp(t->path, key))
            return (int)i;
    }
    return -1;
}

/* Builds the chain from decoded RGBA8 pixels and appends it to the scene. */
static int add_levels(hz_bake_scene_t *s, const char *key, uint8_t *px, uint32_t w, uint32_t h, int alpha_from_luma,
                      uint32_t max_size)
{
    init_tables();
    size_t n = (size_t)w * h;
    if (alpha_from_luma) {
        int opaque = 1;
        for (size_t i = 0; i < n && opaque; i++)
            opaque = px[i * 4 + 3] == 255;
        if (opaque) /* a grey alpha map: its value is the alpha */
            for (size_t i = 0; i < n; i++)
                px[i * 4 + 3] = (uint8_t)((px[i * 4] + px[i * 4 + 1] + px[i * 4 + 2] + 1) / 3);
    }
    /* Level chain dimensions; skip the levels larger than max_size. */
    uint32_t lw = w, lh = h, first = 0, levels = 1;
    while (lw > 1 || lh > 1) {
        lw = lw > 1 ? lw / 2 : 1;
        lh = lh > 1 ? lh / 2 : 1;
        levels++;
    }
    lw = w, lh = h;
    while (max_size && (lw > max_size || lh > max_size)) {
        lw = lw > 1 ? lw / 2 : 1;
        lh = lh > 1 ? lh / 2 : 1;
        first++;
    }
    uint64_t total = 0;
    {
        uint32_t a = lw, b = lh;
        for (uint32_t l = first; l < levels; l++) {
            total += (uint64_t)a * b;
            a = a > 1 ? a / 2 : 1;
            b = b > 1 ? b / 2 : 1;
        }
    }
    if (total + s->texels.len > UINT32_MAX) {
        hz_bake_warn("%s: texture '%s' would take the scene past 2^32 texels; it is left out", s->model, key);
        return -1;
    }
    hz_bake_texture_t *t = hz_bake_vec_push(&s->texs, 1);
    snprintf(t->path, sizeof t->path, "%s", key);
    t->alpha_from_luma = alpha_from_luma;
    t->t.width = lw;
    t->t.height = lh;
    t->t.levels = levels - first;
    t->t.first_texel = (uint32_t)s->texels.len;
    t->t.texel_count = (uint32_t)total;
    hz_bake_set_name(t->t.name, hz_bake_basename(key));
    int index = (int)s->texs.len - 1;
    uint8_t *out = hz_bake_vec_push(&s->texels, (size_t)total);

    /* Linear float working copy: rgb linear, a. */
    float *cur = hz_bake_xmalloc(n * 4 * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++)
            cur[i * 4 + c] = srgb_lin[px[i * 4 + c]];
        cur[i * 4 + 3] = px[i * 4 + 3] / 255.0f;
    }
    uint32_t cw = w, ch = h;
    size_t at = 0;
    for (uint32_t l = 0; l < levels; l++) {
        if (l >= first) {
            size_t cn = (size_t)cw * ch;
            if (l == 0) {
                memcpy(out + at * 4, px, cn * 4); /* level 0 unchanged: no round trip through float */
            } else {
                for (size_t i = 0; i < cn; i++) {
                    for (int c = 0; c < 3; c++)
                        out[(at + i) * 4 + c] = encode_byte(cur[i * 4 + c]);
                    out[(at + i) * 4 + 3] = unit_byte(cur[i * 4 + 3]);
                }
            }
            if (l == first)
                for (size_t i = 0; i < cn; i++)
                    if (out[(at + i) * 4 + 3] != 255) {
                        t->t.flags |= 1u;
                        break;
                    }
            at += cn;
        }
        if (l + 1 == levels)
            break;
        uint32_t nw = cw > 1 ? cw / 2 : 1, nh = ch > 1 ? ch / 2 : 1;
        float *next = hz_bake_xmalloc((size_t)nw * nh * 4 * sizeof(float));
        for (uint32_t y = 0; y < nh; y++)
            for (uint32_t x = 0; x < nw; x++) {
                uint32_t x0 = cw > 1 ? 2 * x : 0, x1 = cw > 1 ? 2 * x + 1 : 0;
                uint32_t y0 = ch > 1 ? 2 * y : 0, y1 = ch > 1 ? 2 * y + 1 : 0;
                const float *q[4] = { cur + ((size_t)y0 * cw + x0) * 4, cur + ((size_t)y0 * cw + x1) * 4,
                                      cur + ((size_t)y1 * cw + x0) * 4, cur + ((size_t)y1 * cw + x1) * 4 };
                float asum = q[0][3] + q[1][3] + q[2][3] + q[3][3];
                float *d = next + ((size_t)y * nw + x) * 4;
                for (int c = 0; c < 3; c++) {
                    if (asum > 0.0f)
                        d[c] = (q[0][c] * q[0][3] + q[1][c] * q[1][3] + q[2][c] * q[2][3] + q[3][c] * q[3][3]) / asum;
                    else
                        d[c] = 0.25f * (q[0][c] + q[1][c] + q[2][c] + q[3][c]);
                }
                d[3] = 0.25f * asum;
            }
        free(cur);
        cur = next;
        cw = nw;
        ch = nh;
    }
    free(cur);
    return index;
}

static int decoded(hz_bake_scene_t *s, const char *key, uint8_t *px, int w, int h, int alpha_from_luma,
                   uint32_t max_size, const char *material)
{
    if (!px) {
        hz_bake_warn("%s: texture '%s' of material '%s' cannot be decoded (%s); the material uses its colour instead",
                     s->model, key, material, stbi_failure_reason());
        return -1;
    }
    if (w < 1 || h < 1 || w > 16384 || h > 16384) {
        hz_bake_warn("%s: texture '%s' is %dx%d, outside 1..16384; the material '%s' uses its colour instead", s->model,
                     key, w, h, material);
        stbi_image_free(px);
        return -1;
    }
    int index = add_levels(s, key, px, (uint32_t)w, (uint32_t)h, alpha_from_luma, max_size);
    stbi_image_free(px);
    if (index >= 0)
        hz_bake_progress("texture %s: %dx%d -> %ux%u, %u levels", hz_bake_basename(key), w, h,
                         HZ_BAKE_AT(s->texs, hz_bake_texture_t, index)->t.width,
                         HZ_BAKE_AT(s->texs, hz_bake_texture_t, index)->t.height,
                         HZ_BAKE_AT(s->texs, hz_bake_texture_t, index)->t.levels);
    return index;
}

int hz_bake_texture_get(hz_bake_scene_t *s, const char *path, int alpha_from_luma, uint32_t max_size,
                        const char *material)
{
    int found = find_texture(s, path, alpha_from_luma);
    if (found >= 0)
        return found;
    if (!hz_bake_file_exists(path)) {
        hz_bake_warn("%s: texture '%s' of material '%s' is missing; the material uses its colour instead", s->model,
                     path, material);
        return -1;
    }
    if (!hz_bake_input_ok(path))
        return -1; /* the output: the bake fails after the import (hz_bake_input_clash) */
    int w = 0, h = 0, comp = 0;
    hz_bake_phase("decoding textures (%s)", hz_bake_basename(path));
    uint8_t *px = stbi_load(path, &w, &h, &comp, 4);
    return decoded(s, path, px, w, h, alpha_from_luma, max_size, material);
}

int hz_bake_texture_from_memory(hz_bake_scene_t *s, const char *key, const uint8_t *data, size_t size,
                                int alpha_from_luma, uint32_t max_size, const char *material)
{
    int found = find_texture(s, key, alpha_from_luma);
    if (found >= 0)
        return found;
    if (size > (size_t)INT32_MAX) {
        hz_bake_warn("%s: embedded texture '%s' is too large; material '%s' uses its colour instead", s->model, key,
                     material);
        return -1;
    }
    int w = 0, h = 0, comp = 0;
    uint8_t *px = stbi_load_from_memory(data, (int)size, &w, &h, &comp, 4);
    return decoded(s, key, px, w, h, alpha_from_luma, max_size, material);
}
