/* Linear RGB float images and exact sRGB 8-bit conversion (see hz/image.h). */
#include "hz/image.h"

#include "hz/config.h"

#if defined(HZ_SIMD_AVX2)
#include <immintrin.h>
#endif

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

void hz_srgb8_encode_n_scalar(const float *lin, uint8_t *codes, size_t n)
{
    for (size_t i = 0; i < n; i++)
        codes[i] = hz_srgb8_encode(lin[i]);
}

#if defined(HZ_SIMD_AVX2)
/* Eight values at a time: the same index selection as hz_srgb8_encode, in signed compares (negative floats are
 * negative integers), one gather, the same low-bits compare. */
static void encode_avx2(const float *lin, uint8_t *codes, size_t n)
{
    const __m256i base = _mm256_set1_epi32((int)HZ_SRGB8_LUT_BASE), one = _mm256_set1_epi32(1);
    const __m256i below_one = _mm256_set1_epi32(0x3F7FFFFF), inf = _mm256_set1_epi32(0x7F800000);
    const __m256i top = _mm256_set1_epi32((int)HZ_SRGB8_LUT_SIZE + 1), low16 = _mm256_set1_epi32(0xffff);
    const __m256i low8 = _mm256_set1_epi32(0xff);
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        __m256i b = _mm256_loadu_si256((const __m256i *)(const void *)(lin + i));
        __m256i idx = _mm256_add_epi32(_mm256_srli_epi32(_mm256_sub_epi32(b, base), HZ_SRGB8_LUT_SHIFT), one);
        __m256i below = _mm256_cmpgt_epi32(base, b); /* also every negative float */
        __m256i above = _mm256_cmpgt_epi32(b, below_one);
        __m256i nan = _mm256_cmpgt_epi32(b, inf);
        idx = _mm256_blendv_epi8(idx, top, above);
        idx = _mm256_andnot_si256(_mm256_or_si256(below, nan), idx);
        __m256i e = _mm256_i32gather_epi32((const int *)(const void *)hz_srgb8_lut, idx, 4);
        /* code = (e & 0xff) + (low >= split) = (e & 0xff) + 1 + (split > low ? -1 : 0) */
        __m256i split_gt = _mm256_cmpgt_epi32(_mm256_srli_epi32(e, 8), _mm256_and_si256(b, low16));
        __m256i code = _mm256_add_epi32(_mm256_add_epi32(_mm256_and_si256(e, low8), one), split_gt);
        __m256i w = _mm256_packus_epi32(code, code); /* per 128-bit lane: c0..c3 c0..c3 | c4..c7 c4..c7 */
        __m256i by = _mm256_packus_epi16(w, w);
        uint32_t lo = (uint32_t)_mm_cvtsi128_si32(_mm256_castsi256_si128(by));
        uint32_t hi = (uint32_t)_mm_cvtsi128_si32(_mm256_extracti128_si256(by, 1));
        hz_memcpy(codes + i, &lo, 4);
        hz_memcpy(codes + i + 4, &hi, 4);
    }
    hz_srgb8_encode_n_scalar(lin + i, codes + i, n - i);
}
#endif

void hz_srgb8_encode_n(const float *lin, uint8_t *codes, size_t n)
{
#if defined(HZ_SIMD_AVX2)
    encode_avx2(lin, codes, n);
#else
    hz_srgb8_encode_n_scalar(lin, codes, n);
#endif
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
    uint8_t codes[768]; /* chunks, so the SIMD encoder does the work */
    size_t n = hz_image_pixels(img) * 3;
    float *p = img->rgb;
    for (size_t done = 0; done < n; done += sizeof codes) {
        size_t k = n - done < sizeof codes ? n - done : sizeof codes;
        hz_srgb8_encode_n(p + done, codes, k);
        hz_srgb8_decode_n(codes, p + done, k);
    }
}
