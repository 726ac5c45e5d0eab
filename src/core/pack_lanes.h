/*
 * pack_lanes.h — hz/pack.h's codecs in SIMD lanes (lanes.h), each bit-identical to its scalar function for
 * every input: RGB9E5 pack and unpack, half unpack (hz_half_unpack, the e == 31 codes included) and half pack
 * (hz_half_pack: non-negative, round to nearest even, subnormals kept). The half codecs use the ISA's
 * conversion instructions where the board has them; the *_bits variants are the same codecs in plain lane
 * arithmetic (for boards without them, and for the tests that compare the two).
 *
 * Contract: as lanes.h (AVX2 and NEON boards only). Half codes travel in the low 16 bits of int32 lanes.
 */
#ifndef HZ_PACK_LANES_H
#define HZ_PACK_LANES_H

#include "hz/pack.h"
#include "lanes.h"

typedef struct hz_lrgb {
    hz_lf_t c[3];
} hz_lrgb_t;

/* The ISA's half <-> single conversions (x86-64-v3's F16C, AArch64's FCVT), where the board has them: exact for
 * every finite half, and round to nearest even from single (the rounding mode is fixed in the instruction on
 * x86 and the default FPCR's on AArch64), so on the codes and values below they give hz/pack.h's bits. */
#if defined(HZ_BOARD_SIMD_AVX2) && defined(__F16C__)
#define HZ_LANES_HW_HALF 1
HZ_INLINE hz_lf_t hz_lanes_half_hw_unpack(hz_li_t h)
{
    const __m128i p = _mm_packus_epi32(_mm256_castsi256_si128(h), _mm256_extracti128_si256(h, 1));
    return _mm256_cvtph_ps(p);
}
/* v finite, 0 <= v <= HZ_HALF_MAX */
HZ_INLINE hz_li_t hz_lanes_half_hw_pack(hz_lf_t v)
{
    return _mm256_cvtepu16_epi32(_mm256_cvtps_ph(v, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
}
#elif defined(HZ_BOARD_SIMD_NEON) && defined(__aarch64__)
#define HZ_LANES_HW_HALF 1
HZ_INLINE hz_lf_t hz_lanes_half_hw_unpack(hz_li_t h)
{
    return vcvt_f32_f16(vreinterpret_f16_u16(vmovn_u32(vreinterpretq_u32_s32(h))));
}
HZ_INLINE hz_li_t hz_lanes_half_hw_pack(hz_lf_t v)
{
    return vreinterpretq_s32_u32(vmovl_u16(vreinterpret_u16_f16(vcvt_f16_f32(v))));
}
#endif

/* HZ_LANES consecutive half codes at p (no exponent-31 code among them: see hz_lanes_half_load) into floats, and
 * HZ_LANES floats stored as hz_half_pack's codes at p, with the conversion instruction. */
#if defined(HZ_BOARD_SIMD_AVX2) && defined(__F16C__)
HZ_INLINE hz_lf_t hz_lanes_half_hw_load(const uint16_t *p)
{
    return _mm256_cvtph_ps(_mm_loadu_si128((const __m128i *)(const void *)p));
}
/* v finite, 0 <= v <= HZ_HALF_MAX */
HZ_INLINE void hz_lanes_half_hw_store(uint16_t *p, hz_lf_t v)
{
    _mm_storeu_si128((__m128i *)(void *)p, _mm256_cvtps_ph(v, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
}
#elif defined(HZ_BOARD_SIMD_NEON) && defined(__aarch64__)
HZ_INLINE hz_lf_t hz_lanes_half_hw_load(const uint16_t *p)
{
    return vcvt_f32_f16(vreinterpret_f16_u16(vld1_u16(p)));
}
HZ_INLINE void hz_lanes_half_hw_store(uint16_t *p, hz_lf_t v)
{
    vst1_u16(p, vreinterpret_u16_f16(vcvt_f16_f32(v)));
}
#endif

/* hz_half_unpack of the half codes in the low 16 bits of each lane, by the bit assembly below. */
HZ_INLINE hz_lf_t hz_lanes_half_unpack_bits(hz_li_t h)
{
    const hz_li_t e = hz_li_and(hz_li_shr(h, 10), hz_li_set(0x1f)), m = hz_li_and(h, hz_li_set(0x3ff));
    const hz_li_t sign = hz_li_shl(hz_li_and(h, hz_li_set(0x8000)), 16);
    /* normal: the exponent rebiased, the mantissa widened; exact, so it equals the scalar's bit assembly */
    hz_li_t normal = hz_li_or(hz_li_shl(hz_li_add(e, hz_li_set(112)), 23), hz_li_shl(m, 13));
    /* subnormal: sign * m * 2^-24 (both products exact, so the sign can be or-ed in afterwards) */
    hz_li_t sub = hz_lf_bits(hz_lf_mul(hz_lf_from_li(m), hz_lf_set(1.0f / 16777216.0f)));
    /* e == 31 (never packed): 0 for a NaN code, +-HZ_HALF_MAX for infinities */
    hz_li_t inf = hz_li_sel(hz_li_eq(m, hz_li_set(0)), hz_lf_bits(hz_lf_set(HZ_HALF_MAX)), hz_li_set(0));
    hz_li_t sign_inf = hz_li_sel(hz_li_eq(m, hz_li_set(0)), sign, hz_li_set(0));
    hz_li_t r = hz_li_sel(hz_li_eq(e, hz_li_set(0)), hz_li_or(sub, sign), hz_li_or(normal, sign));
    return hz_lf_from_bits(hz_li_sel(hz_li_eq(e, hz_li_set(31)), hz_li_or(inf, sign_inf), r));
}

/* hz_half_unpack of the half codes in the low 16 bits of each lane (the upper 16 bits must be zero). The
 * conversion instruction where there is one; codes with exponent 31 (infinities and NaNs, which hz_half_pack
 * never writes) are read as hz_half_unpack reads them. */
HZ_INLINE hz_lf_t hz_lanes_half_unpack(hz_li_t h)
{
#ifdef HZ_LANES_HW_HALF
    const hz_li_t top = hz_li_set(0x7c00);
    if (HZ_LIKELY(!hz_li_any(hz_li_eq(hz_li_and(h, top), top))))
        return hz_lanes_half_hw_unpack(h);
#endif
    return hz_lanes_half_unpack_bits(h);
}

#ifdef HZ_LANES_HW_HALF
/* HZ_LANES consecutive half RGB pixels at p (3 HZ_LANES codes) into *o, as hz_half_unpack reads them; false
 * (and *o untouched) when a code has exponent 31, which the instruction reads otherwise. */
HZ_INLINE int hz_lanes_half3_load(const uint16_t *p, hz_lrgb_t *o)
{
#if defined(HZ_BOARD_SIMD_AVX2)
    const __m128i a = _mm_loadu_si128((const __m128i *)(const void *)p);
    const __m128i b = _mm_loadu_si128((const __m128i *)(const void *)(p + 8));
    const __m128i c = _mm_loadu_si128((const __m128i *)(const void *)(p + 16));
    const __m128i top = _mm_set1_epi16(0x7c00);
    const __m128i e31 = _mm_or_si128(_mm_or_si128(_mm_cmpeq_epi16(_mm_and_si128(a, top), top),
                                                  _mm_cmpeq_epi16(_mm_and_si128(b, top), top)),
                                     _mm_cmpeq_epi16(_mm_and_si128(c, top), top));
    if (HZ_UNLIKELY(!_mm_testz_si128(e31, e31)))
        return 0;
    hz_lf_deinterleave3(_mm256_cvtph_ps(a), _mm256_cvtph_ps(b), _mm256_cvtph_ps(c), &o->c[0], &o->c[1], &o->c[2]);
#else
    const uint16x4x3_t v = vld3_u16(p);
    const uint16x4_t top = vdup_n_u16(0x7c00);
    const uint16x4_t e31 = vorr_u16(vorr_u16(vceq_u16(vand_u16(v.val[0], top), top),
                                             vceq_u16(vand_u16(v.val[1], top), top)),
                                    vceq_u16(vand_u16(v.val[2], top), top));
    if (HZ_UNLIKELY(vget_lane_u64(vreinterpret_u64_u16(e31), 0) != 0))
        return 0;
    HZ_UNROLL
    for (int k = 0; k < 3; k++)
        o->c[k] = vcvt_f32_f16(vreinterpret_f16_u16(v.val[k]));
#endif
    return 1;
}
#endif

HZ_INLINE hz_lrgb_t hz_lanes_rgb9e5_unpack(hz_li_t code)
{
    hz_lrgb_t o;
    hz_lf_t scale = hz_lf_from_bits(hz_li_shl(hz_li_add(hz_li_shr(code, 27), hz_li_set(127 - 24)), 23));
    o.c[0] = hz_lf_mul(hz_lf_from_li(hz_li_and(code, hz_li_set(511))), scale);
    o.c[1] = hz_lf_mul(hz_lf_from_li(hz_li_and(hz_li_shr(code, 9), hz_li_set(511))), scale);
    o.c[2] = hz_lf_mul(hz_lf_from_li(hz_li_and(hz_li_shr(code, 18), hz_li_set(511))), scale);
    return o;
}

/* hz_pack_clamp(v, max_value): v > 0 ? (v < max ? v : max) : 0 */
HZ_INLINE hz_lf_t hz_lanes_pack_clamp(hz_lf_t v, float max_value)
{
    return hz_lf_keep(hz_lf_gt(v, hz_lf_set(0.0f)), hz_lf_min_first(v, hz_lf_set(max_value)));
}

HZ_INLINE hz_lf_t hz_lanes_pow2(hz_li_t e) /* 2^e for normal e */
{
    return hz_lf_from_bits(hz_li_shl(hz_li_add(e, hz_li_set(127)), 23));
}

/* hz_rgb9e5_pack, lane by lane. The carry's smaller exponent halves the scale (a power of two within the
 * normal range: exact). */
HZ_INLINE hz_li_t hz_lanes_rgb9e5_pack(const hz_lrgb_t *in)
{
    hz_lf_t c[3];
    HZ_UNROLL
    for (int k = 0; k < 3; k++)
        c[k] = hz_lanes_pack_clamp(in->c[k], HZ_RGB9E5_MAX);
    const hz_lf_t m = hz_lf_max_first(hz_lf_max_first(c[0], c[1]), c[2]);
    hz_li_t ex = hz_li_sub(hz_li_and(hz_li_shr(hz_lf_bits(m), 23), hz_li_set(0xff)), hz_li_set(127));
    hz_li_t es = hz_li_add(hz_li_max(ex, hz_li_set(-16)), hz_li_set(16));
    hz_lf_t scale = hz_lanes_pow2(hz_li_sub(hz_li_set(24), es));
    hz_li_t top = hz_li_from_lf(hz_lf_add(hz_lf_mul(m, scale), hz_lf_set(0.5f)));
    hz_li_t carry = hz_li_gt(top, hz_li_set(511));
    es = hz_li_sub(es, carry); /* masks are -1 */
    scale = hz_lf_sel(carry, hz_lf_mul(scale, hz_lf_set(0.5f)), scale);
    hz_li_t code = hz_li_shl(es, 27);
    HZ_UNROLL
    for (int k = 0; k < 3; k++) {
        hz_li_t q = hz_li_min(hz_li_from_lf(hz_lf_add(hz_lf_mul(c[k], scale), hz_lf_set(0.5f))), hz_li_set(511));
        code = hz_li_or(code, k == 0 ? q : k == 1 ? hz_li_shl(q, 9) : hz_li_shl(q, 18));
    }
    return hz_li_andnot(code, hz_lf_eq(m, hz_lf_set(0.0f)));
}

/* hz_half_pack, lane by lane, by bit steps: round to nearest even. */
HZ_INLINE hz_li_t hz_lanes_half_pack_bits(hz_lf_t v)
{
    v = hz_lanes_pack_clamp(v, HZ_HALF_MAX);
    const hz_li_t u = hz_lf_bits(v), zero = hz_li_set(0);
    const hz_li_t e = hz_li_sub(hz_li_shr(u, 23), hz_li_set(127));
    /* subnormal half: multiples of 2^-24, rounded to nearest even */
    hz_lf_t q = hz_lf_mul(v, hz_lf_set(16777216.0f));
    hz_li_t i = hz_li_from_lf(q);
    hz_lf_t rem = hz_lf_sub(q, hz_lf_from_li(i));
    hz_li_t up = hz_li_or(hz_lf_gt(rem, hz_lf_set(0.5f)),
                          hz_li_and(hz_lf_eq(rem, hz_lf_set(0.5f)), hz_li_not(hz_li_eq(hz_li_and(i, hz_li_set(1)), zero))));
    hz_li_t sub = hz_li_sub(i, up);
    /* normal: 10 of the 23 mantissa bits, nearest even on the 13 dropped (a carry may reach the exponent) */
    hz_li_t mant = hz_li_and(u, hz_li_set(0x7fffff)), keep = hz_li_shr(mant, 13), drop = hz_li_and(mant, hz_li_set(0x1fff));
    hz_li_t h = hz_li_or(hz_li_shl(hz_li_add(e, hz_li_set(15)), 10), keep);
    hz_li_t hup = hz_li_or(hz_li_gt(drop, hz_li_set(0x1000)),
                           hz_li_and(hz_li_eq(drop, hz_li_set(0x1000)), hz_li_not(hz_li_eq(hz_li_and(keep, hz_li_set(1)), zero))));
    h = hz_li_min(hz_li_sub(h, hup), hz_li_set(0x7bff));
    hz_li_t r = hz_li_sel(hz_li_gt(hz_li_set(-14), e), sub, h);
    hz_li_t none = hz_li_or(hz_lf_eq(v, hz_lf_set(0.0f)), hz_li_gt(hz_li_set(-25), e));
    return hz_li_sel(none, zero, r);
}

/* hz_half_pack, lane by lane: clamped to [0, HZ_HALF_MAX] (NaN to 0), then the conversion instruction where
 * there is one, else hz_lanes_half_pack_bits. */
HZ_INLINE hz_li_t hz_lanes_half_pack(hz_lf_t v)
{
#ifdef HZ_LANES_HW_HALF
    return hz_lanes_half_hw_pack(hz_lanes_pack_clamp(v, HZ_HALF_MAX));
#else
    return hz_lanes_half_pack_bits(v);
#endif
}

/* Planes of half codes that only hz_half_pack wrote (so no code has exponent 31, which hz_half_unpack reads as
 * finite and the instruction does not): HZ_LANES consecutive codes at p read as hz_half_unpack reads them, the
 * codes at base[idx[i]] (base readable for one code past the largest index: whole words are gathered), and
 * HZ_LANES values stored as hz_half_pack's codes. */
HZ_INLINE hz_lf_t hz_lanes_half_load(const uint16_t *p)
{
#ifdef HZ_LANES_HW_HALF
    return hz_lanes_half_hw_load(p);
#else
    return hz_lanes_half_unpack_bits(hz_li_load_u16(p));
#endif
}

HZ_INLINE hz_lf_t hz_lanes_half_gather(const uint16_t *base, hz_li_t idx)
{
    const hz_li_t h = hz_li_and(hz_li_gather_bytes32(base, hz_li_add(idx, idx)), hz_li_set(0xffff));
#ifdef HZ_LANES_HW_HALF
    return hz_lanes_half_hw_unpack(h);
#else
    return hz_lanes_half_unpack_bits(h);
#endif
}

HZ_INLINE void hz_lanes_half_store(uint16_t *p, hz_lf_t v)
{
#ifdef HZ_LANES_HW_HALF
    hz_lanes_half_hw_store(p, hz_lanes_pack_clamp(v, HZ_HALF_MAX));
#else
    int32_t c[HZ_LANES];
    hz_li_store(c, hz_lanes_half_pack_bits(v));
    for (int i = 0; i < HZ_LANES; i++)
        p[i] = (uint16_t)c[i];
#endif
}

/* HZ_LANES RGB pixels stored as hz_half_pack's codes, interleaved: p[3 i + k] = the code of lane i of c[k]. On
 * AVX2 the three rows of codes are interleaved with byte shuffles, without widening them to words first. */
HZ_INLINE void hz_lanes_half3_store(uint16_t *p, const hz_lrgb_t *c)
{
#if defined(HZ_BOARD_SIMD_AVX2) && defined(__F16C__)
    const int rnd = _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC;
    const __m128i r = _mm256_cvtps_ph(hz_lanes_pack_clamp(c->c[0], HZ_HALF_MAX), rnd);
    const __m128i g = _mm256_cvtps_ph(hz_lanes_pack_clamp(c->c[1], HZ_HALF_MAX), rnd);
    const __m128i b = _mm256_cvtps_ph(hz_lanes_pack_clamp(c->c[2], HZ_HALF_MAX), rnd);
    /* output code j of 16-byte vector v is element 8 v + j: pixel (8 v + j) / 3, channel (8 v + j) % 3 */
#define Z -128
    const __m128i r0 = _mm_setr_epi8(0, 1, Z, Z, Z, Z, 2, 3, Z, Z, Z, Z, 4, 5, Z, Z);
    const __m128i g0 = _mm_setr_epi8(Z, Z, 0, 1, Z, Z, Z, Z, 2, 3, Z, Z, Z, Z, 4, 5);
    const __m128i b0 = _mm_setr_epi8(Z, Z, Z, Z, 0, 1, Z, Z, Z, Z, 2, 3, Z, Z, Z, Z);
    const __m128i r1 = _mm_setr_epi8(Z, Z, 6, 7, Z, Z, Z, Z, 8, 9, Z, Z, Z, Z, 10, 11);
    const __m128i g1 = _mm_setr_epi8(Z, Z, Z, Z, 6, 7, Z, Z, Z, Z, 8, 9, Z, Z, Z, Z);
    const __m128i b1 = _mm_setr_epi8(4, 5, Z, Z, Z, Z, 6, 7, Z, Z, Z, Z, 8, 9, Z, Z);
    const __m128i r2 = _mm_setr_epi8(Z, Z, Z, Z, 12, 13, Z, Z, Z, Z, 14, 15, Z, Z, Z, Z);
    const __m128i g2 = _mm_setr_epi8(10, 11, Z, Z, Z, Z, 12, 13, Z, Z, Z, Z, 14, 15, Z, Z);
    const __m128i b2 = _mm_setr_epi8(Z, Z, 10, 11, Z, Z, Z, Z, 12, 13, Z, Z, Z, Z, 14, 15);
#undef Z
    __m128i *d = (__m128i *)(void *)p;
    _mm_storeu_si128(d, _mm_or_si128(_mm_or_si128(_mm_shuffle_epi8(r, r0), _mm_shuffle_epi8(g, g0)),
                                     _mm_shuffle_epi8(b, b0)));
    _mm_storeu_si128(d + 1, _mm_or_si128(_mm_or_si128(_mm_shuffle_epi8(r, r1), _mm_shuffle_epi8(g, g1)),
                                         _mm_shuffle_epi8(b, b1)));
    _mm_storeu_si128(d + 2, _mm_or_si128(_mm_or_si128(_mm_shuffle_epi8(r, r2), _mm_shuffle_epi8(g, g2)),
                                         _mm_shuffle_epi8(b, b2)));
#else
    hz_li_store3_u16(p, hz_lanes_half_pack(c->c[0]), hz_lanes_half_pack(c->c[1]), hz_lanes_half_pack(c->c[2]));
#endif
}

#endif /* HZ_PACK_LANES_H */
