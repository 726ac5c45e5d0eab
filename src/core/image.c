/* Linear RGB float images and exact sRGB 8-bit conversion (see hz/image.h). */
#include "hz/image.h"

hz_status_t hz_image_check_size(uint32_t width, uint32_t height, size_t *bytes, hz_error_t *err)
{
    if (width == 0 || height == 0)
        return hz_error_set(err, HZ_E_INVALID_ARG, "image size %ux%u: width and height must be at least 1",
                            (unsigned)width, (unsigned)height);
    if (width > HZ_IMAGE_MAX_DIM || height > HZ_IMAGE_MAX_DIM)
        return hz_error_set(err, HZ_E_RANGE, "image size %ux%u: larger than %ux%u", (unsigned)width,
                            (unsigned)height, HZ_IMAGE_MAX_DIM, HZ_IMAGE_MAX_DIM);
    /* At most 16384^2 * 12 bytes (3 GiB): fits size_t on 32-bit targets too, but keep the check honest. */
    size_t px = (size_t)width * height;
    if (px > (size_t)-1 / (3 * sizeof(float)))
        return hz_error_set(err, HZ_E_OVERFLOW, "image size %ux%u: byte count overflows", (unsigned)width,
                            (unsigned)height);
    if (bytes)
        *bytes = px * 3 * sizeof(float);
    return HZ_OK;
}

hz_status_t hz_image_alloc(hz_image_t *img, hz_arena_t *arena, uint32_t width, uint32_t height, hz_error_t *err)
{
    if (!img || !arena)
        return hz_error_set(err, HZ_E_INVALID_ARG, "hz_image_alloc: NULL image or arena");
    img->width = img->height = 0;
    img->rgb = 0;
    size_t bytes;
    hz_status_t s = hz_image_check_size(width, height, &bytes, err);
    if (s != HZ_OK)
        return s;
    float *p = hz_arena_alloc(arena, bytes, 64);
    if (!p) {
        hz_arena_error(arena, err);
        hz_error_prefix(err, "image");
        return err ? err->code : HZ_E_NO_MEMORY;
    }
    img->width = width;
    img->height = height;
    img->rgb = p;
    return HZ_OK;
}

void hz_image_fill(hz_image_t *img, float r, float g, float b)
{
    size_t n = hz_image_pixels(img);
    float *p = img->rgb;
    for (size_t i = 0; i < n; i++, p += 3) {
        p[0] = r;
        p[1] = g;
        p[2] = b;
    }
}

hz_status_t hz_image_copy(hz_image_t *dst, const hz_image_t *src, hz_error_t *err)
{
    if (dst->width != src->width || dst->height != src->height)
        return hz_error_set(err, HZ_E_INVALID_ARG, "image copy: sizes differ (%ux%u vs %ux%u)",
                            (unsigned)dst->width, (unsigned)dst->height, (unsigned)src->width,
                            (unsigned)src->height);
    hz_memcpy(dst->rgb, src->rgb, hz_image_pixels(src) * 3 * sizeof(float));
    return HZ_OK;
}

void hz_srgb8_encode_n(const float *lin, uint8_t *codes, size_t n)
{
    for (size_t i = 0; i < n; i++)
        codes[i] = hz_srgb8_encode(lin[i]);
}

void hz_srgb8_decode_n(const uint8_t *codes, float *lin, size_t n)
{
    for (size_t i = 0; i < n; i++)
        lin[i] = hz_srgb8_decode(codes[i]);
}

void hz_image_to_srgb8(const hz_image_t *img, uint8_t *codes)
{
    hz_srgb8_encode_n(img->rgb, codes, hz_image_pixels(img) * 3);
}

void hz_image_from_srgb8(hz_image_t *img, const uint8_t *codes)
{
    hz_srgb8_decode_n(codes, img->rgb, hz_image_pixels(img) * 3);
}

void hz_image_quantize_srgb8(hz_image_t *img)
{
    size_t n = hz_image_pixels(img) * 3;
    float *p = img->rgb;
    for (size_t i = 0; i < n; i++)
        p[i] = hz_srgb8_decode(hz_srgb8_encode(p[i]));
}
