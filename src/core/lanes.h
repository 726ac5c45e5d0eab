/*
 * lanes.h — a small kit of float and int32 SIMD lanes (8 on AVX2, 4 on NEON) for code that must give
 * bit-identical results to its scalar twin (the reconstruction passes).
 *
 * Contract:
 *  - Only for translation units built on an AVX2 or NEON board (HZ_BOARD_SIMD_AVX2 / _NEON); including it
 *    elsewhere is an error. HZ_LANES is the lane count.
 *  - Every operation rounds exactly as the scalar C it stands for under -ffp-contract=off: add, sub, mul, div
 *    and sqrt are IEEE single precision (correctly rounded), conversions truncate like a C cast. Nothing here
 *    uses an estimate (rcp, rsqrt) or a fused multiply-add.
 *  - Comparisons give masks (all ones / all zeros per lane); hz_lf_sel(mask, a, b) is `mask ? a : b`, so a
 *    scalar `a > b ? a : b` is hz_lf_sel(hz_lf_gt(a, b), a, b), NaN behaviour included; hz_lf_max_first(a, b)
 *    is the same expression in one instruction where the ISA's max has exactly that behaviour (x86's returns
 *    its second operand on NaN and equality), else the select. hz_lf_keep(m, v) is `m ? v : +0.0f`.
 *  - Gathers read one element per lane at base[index]; the caller keeps every index in bounds (inactive lanes
 *    included: select a safe index for them first).
 *  - Does not: touch memory other than through the explicit loads, stores and gathers (hz_lanes_prefetch is a
 *    hint that reads nothing and never faults); assume alignment.
 */
#ifndef HZ_LANES_H
#define HZ_LANES_H

#include <stdint.h>

#include "hz/base.h"

#if defined(HZ_BOARD_SIMD_AVX2)
#include <immintrin.h>

#define HZ_LANES 8
typedef __m256 hz_lf_t;  /* float lanes */
typedef __m256i hz_li_t; /* int32 lanes, also masks */

HZ_INLINE hz_lf_t hz_lf_set(float v) { return _mm256_set1_ps(v); }
HZ_INLINE hz_li_t hz_li_set(int32_t v) { return _mm256_set1_epi32(v); }
HZ_INLINE hz_li_t hz_li_iota(void) { return _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7); }
HZ_INLINE hz_lf_t hz_lf_load(const float *p) { return _mm256_loadu_ps(p); }
HZ_INLINE void hz_lf_store(float *p, hz_lf_t v) { _mm256_storeu_ps(p, v); }
/* Lanes 0 .. HZ_LANES / 2 - 1 to lo, the others to hi. */
HZ_INLINE void hz_lf_store_halves(float *lo, float *hi, hz_lf_t v)
{
    _mm_storeu_ps(lo, _mm256_castps256_ps128(v));
    _mm_storeu_ps(hi, _mm256_extractf128_ps(v, 1));
}
HZ_INLINE hz_li_t hz_li_load(const void *p) { return _mm256_loadu_si256((const __m256i *)p); }
HZ_INLINE void hz_li_store(void *p, hz_li_t v) { _mm256_storeu_si256((__m256i *)p, v); }
/* HZ_LANES bytes, zero-extended. */
HZ_INLINE hz_li_t hz_li_load_u8(const uint8_t *p) { return _mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)p)); }
/* The low byte of every lane to HZ_LANES bytes at p (values are 0..255). */
HZ_INLINE void hz_li_store_u8(uint8_t *p, hz_li_t v)
{
    __m128i w = _mm_packus_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    _mm_storel_epi64((__m128i *)p, _mm_packus_epi16(w, w));
}

HZ_INLINE hz_lf_t hz_lf_add(hz_lf_t a, hz_lf_t b) { return _mm256_add_ps(a, b); }
HZ_INLINE hz_lf_t hz_lf_sub(hz_lf_t a, hz_lf_t b) { return _mm256_sub_ps(a, b); }
HZ_INLINE hz_lf_t hz_lf_mul(hz_lf_t a, hz_lf_t b) { return _mm256_mul_ps(a, b); }
HZ_INLINE hz_lf_t hz_lf_div(hz_lf_t a, hz_lf_t b) { return _mm256_div_ps(a, b); }
HZ_INLINE hz_lf_t hz_lf_sqrt(hz_lf_t a) { return _mm256_sqrt_ps(a); }
HZ_INLINE hz_li_t hz_lf_gt(hz_lf_t a, hz_lf_t b) { return _mm256_castps_si256(_mm256_cmp_ps(a, b, _CMP_GT_OQ)); }
HZ_INLINE hz_li_t hz_lf_lt(hz_lf_t a, hz_lf_t b) { return _mm256_castps_si256(_mm256_cmp_ps(a, b, _CMP_LT_OQ)); }
HZ_INLINE hz_li_t hz_lf_eq(hz_lf_t a, hz_lf_t b) { return _mm256_castps_si256(_mm256_cmp_ps(a, b, _CMP_EQ_OQ)); }
HZ_INLINE hz_lf_t hz_lf_sel(hz_li_t m, hz_lf_t a, hz_lf_t b) { return _mm256_blendv_ps(b, a, _mm256_castsi256_ps(m)); }
HZ_INLINE hz_lf_t hz_lf_from_li(hz_li_t a) { return _mm256_cvtepi32_ps(a); }
/* hz_floorf (vmath.h): IEEE floor, the same bits */
HZ_INLINE hz_lf_t hz_lf_floor(hz_lf_t x) { return _mm256_floor_ps(x); }
HZ_INLINE hz_li_t hz_li_from_lf(hz_lf_t a) { return _mm256_cvttps_epi32(a); } /* truncates */
HZ_INLINE hz_li_t hz_lf_bits(hz_lf_t a) { return _mm256_castps_si256(a); }
HZ_INLINE hz_lf_t hz_lf_from_bits(hz_li_t a) { return _mm256_castsi256_ps(a); }

HZ_INLINE hz_li_t hz_li_add(hz_li_t a, hz_li_t b) { return _mm256_add_epi32(a, b); }
HZ_INLINE hz_li_t hz_li_sub(hz_li_t a, hz_li_t b) { return _mm256_sub_epi32(a, b); }
HZ_INLINE hz_li_t hz_li_mul(hz_li_t a, hz_li_t b) { return _mm256_mullo_epi32(a, b); }
HZ_INLINE hz_li_t hz_li_and(hz_li_t a, hz_li_t b) { return _mm256_and_si256(a, b); }
HZ_INLINE hz_li_t hz_li_or(hz_li_t a, hz_li_t b) { return _mm256_or_si256(a, b); }
HZ_INLINE hz_li_t hz_li_andnot(hz_li_t a, hz_li_t b) { return _mm256_andnot_si256(b, a); } /* a & ~b */
HZ_INLINE hz_li_t hz_li_eq(hz_li_t a, hz_li_t b) { return _mm256_cmpeq_epi32(a, b); }
HZ_INLINE hz_li_t hz_li_gt(hz_li_t a, hz_li_t b) { return _mm256_cmpgt_epi32(a, b); } /* signed */
HZ_INLINE hz_li_t hz_li_sel(hz_li_t m, hz_li_t a, hz_li_t b) { return _mm256_blendv_epi8(b, a, m); }
HZ_INLINE hz_li_t hz_li_min(hz_li_t a, hz_li_t b) { return _mm256_min_epi32(a, b); }
HZ_INLINE hz_li_t hz_li_max(hz_li_t a, hz_li_t b) { return _mm256_max_epi32(a, b); }
/* a < b ? a : b and a > b ? a : b, exactly (MINPS/MAXPS return the second operand on NaN and on equality). */
HZ_INLINE hz_lf_t hz_lf_min_first(hz_lf_t a, hz_lf_t b) { return _mm256_min_ps(a, b); }
HZ_INLINE hz_lf_t hz_lf_max_first(hz_lf_t a, hz_lf_t b) { return _mm256_max_ps(a, b); }
HZ_INLINE hz_lf_t hz_lf_keep(hz_li_t m, hz_lf_t v) { return _mm256_and_ps(_mm256_castsi256_ps(m), v); }
#define hz_li_shl(a, n) _mm256_slli_epi32((a), (n))
#define hz_li_shr(a, n) _mm256_srli_epi32((a), (n)) /* logical */
/* Logical right shift of every lane by the same run-time count (0..31). */
HZ_INLINE hz_li_t hz_li_shr_by(hz_li_t a, int n) { return _mm256_srl_epi32(a, _mm_cvtsi32_si128(n)); }
/* Logical right shift of each lane by its own count; counts outside 0..31 (as unsigned) give 0. */
HZ_INLINE hz_li_t hz_li_shr_lanes(hz_li_t a, hz_li_t n) { return _mm256_srlv_epi32(a, n); }
HZ_INLINE int hz_li_any(hz_li_t m) { return !_mm256_testz_si256(m, m); }
/* Lane 0. */
HZ_INLINE int32_t hz_li_first(hz_li_t v) { return _mm256_cvtsi256_si32(v); }
/* Bit i set when lane i of the mask is set. */
HZ_INLINE unsigned hz_li_bits(hz_li_t m) { return (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(m)); }

HZ_INLINE hz_li_t hz_li_gather(const int32_t *base, hz_li_t idx) { return _mm256_i32gather_epi32((const int *)base, idx, 4); }
HZ_INLINE hz_lf_t hz_lf_gather(const float *base, hz_li_t idx) { return _mm256_i32gather_ps(base, idx, 4); }
/* The 4 bytes at base + off (byte offsets), as little-endian words. */
HZ_INLINE hz_li_t hz_li_gather_bytes32(const void *base, hz_li_t off) { return _mm256_i32gather_epi32((const int *)base, off, 1); }
/* HZ_LANES uint16, zero-extended. */
HZ_INLINE hz_li_t hz_li_load_u16(const uint16_t *p) { return _mm256_cvtepu16_epi32(_mm_loadu_si128((const __m128i *)(const void *)p)); }
/* base[idx] as unsigned bytes; reads 4 bytes from base + idx, so base needs 3 readable bytes past the last. */
HZ_INLINE hz_li_t hz_li_gather_u8(const uint8_t *base, hz_li_t idx)
{
    return _mm256_and_si256(_mm256_i32gather_epi32((const int *)(const void *)base, idx, 1), _mm256_set1_epi32(0xff));
}

/* Lane i gets lane idx[i] of v (0 <= idx < HZ_LANES). */
HZ_INLINE hz_lf_t hz_lf_perm(hz_lf_t v, hz_li_t idx) { return _mm256_permutevar8x32_ps(v, idx); }
HZ_INLINE hz_li_t hz_li_perm(hz_li_t v, hz_li_t idx) { return _mm256_permutevar8x32_epi32(v, idx); }

/* Interleaved store of HZ_LANES (r, g, b) triples: dst[3 i + k] = lane i of channel k. */
HZ_INLINE void hz_lf_store3(float *dst, hz_lf_t r, hz_lf_t g, hz_lf_t b)
{
    const __m256 rp0 = _mm256_permutevar8x32_ps(r, _mm256_setr_epi32(0, 0, 0, 1, 1, 1, 2, 2));
    const __m256 gp0 = _mm256_permutevar8x32_ps(g, _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 2));
    const __m256 bp0 = _mm256_permutevar8x32_ps(b, _mm256_setr_epi32(0, 0, 0, 0, 0, 1, 1, 1));
    const __m256 rp1 = _mm256_permutevar8x32_ps(r, _mm256_setr_epi32(2, 3, 3, 3, 4, 4, 4, 5));
    const __m256 gp1 = _mm256_permutevar8x32_ps(g, _mm256_setr_epi32(2, 2, 3, 3, 3, 4, 4, 4));
    const __m256 bp1 = _mm256_permutevar8x32_ps(b, _mm256_setr_epi32(2, 2, 2, 3, 3, 3, 4, 4));
    const __m256 rp2 = _mm256_permutevar8x32_ps(r, _mm256_setr_epi32(5, 5, 6, 6, 6, 7, 7, 7));
    const __m256 gp2 = _mm256_permutevar8x32_ps(g, _mm256_setr_epi32(5, 5, 5, 6, 6, 6, 7, 7));
    const __m256 bp2 = _mm256_permutevar8x32_ps(b, _mm256_setr_epi32(4, 5, 5, 5, 6, 6, 6, 7));
    /* lane j of output vector v holds element 8 v + j: channel (8 v + j) % 3 */
    _mm256_storeu_ps(dst, _mm256_blend_ps(_mm256_blend_ps(rp0, gp0, 0x92), bp0, 0x24));
    _mm256_storeu_ps(dst + 8, _mm256_blend_ps(_mm256_blend_ps(rp1, gp1, 0x24), bp1, 0x49));
    _mm256_storeu_ps(dst + 16, _mm256_blend_ps(_mm256_blend_ps(rp2, gp2, 0x49), bp2, 0x92));
}

/* Interleaved store of HZ_LANES triples of 16-bit codes (each lane 0..65535): dst[3 i + k] = lane i of k. */
HZ_INLINE void hz_li_store3_u16(uint16_t *dst, hz_li_t a, hz_li_t b, hz_li_t c)
{
    float t[24];
    hz_lf_store3(t, _mm256_castsi256_ps(a), _mm256_castsi256_ps(b), _mm256_castsi256_ps(c));
    const __m256i v0 = _mm256_loadu_si256((const __m256i *)(const void *)t);
    const __m256i v1 = _mm256_loadu_si256((const __m256i *)(const void *)(t + 8));
    const __m256i v2 = _mm256_loadu_si256((const __m256i *)(const void *)(t + 16));
    /* packus works per 128-bit half: [v0 lo, v1 lo, v0 hi, v1 hi] -> reorder the 64-bit quarters */
    const __m256i p01 = _mm256_permute4x64_epi64(_mm256_packus_epi32(v0, v1), 0xd8);
    const __m128i p2 = _mm_packus_epi32(_mm256_castsi256_si128(v2), _mm256_extracti128_si256(v2, 1));
    _mm256_storeu_si256((__m256i *)(void *)dst, p01);
    _mm_storeu_si128((__m128i *)(void *)(dst + 16), p2);
}

/* Deinterleaving load of HZ_LANES (r, g, b) triples: lane i of *r, *g, *b = src[3 i], src[3 i + 1], src[3 i + 2]
 * (hz_lf_store3's inverse: each channel blended from the three vectors, then put in lane order). */
HZ_INLINE void hz_lf_deinterleave3(__m256 v0, __m256 v1, __m256 v2, hz_lf_t *r, hz_lf_t *g, hz_lf_t *b)
{
    /* element 3 i + k lies in vector (3 i + k) / 8 at position (3 i + k) % 8 */
    const __m256 tr = _mm256_blend_ps(_mm256_blend_ps(v0, v1, 0x92), v2, 0x24);
    const __m256 tg = _mm256_blend_ps(_mm256_blend_ps(v0, v1, 0x24), v2, 0x49);
    const __m256 tb = _mm256_blend_ps(_mm256_blend_ps(v0, v1, 0x49), v2, 0x92);
    *r = _mm256_permutevar8x32_ps(tr, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    *g = _mm256_permutevar8x32_ps(tg, _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
    *b = _mm256_permutevar8x32_ps(tb, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
}
HZ_INLINE void hz_lf_load3(const float *src, hz_lf_t *r, hz_lf_t *g, hz_lf_t *b)
{
    hz_lf_deinterleave3(_mm256_loadu_ps(src), _mm256_loadu_ps(src + 8), _mm256_loadu_ps(src + 16), r, g, b);
}

/* Deinterleaving load of HZ_LANES pairs: lane i of *a, *b = src[2 i], src[2 i + 1]. */
/* Deinterleaving load of HZ_LANES groups of four words: lane i of v[j] = src[4 i + j]; hz_li_store4 is its
 * inverse. Two 4x4 transposes per 128-bit half, then the lanes in order. */
HZ_INLINE void hz_li_load4(const void *src, hz_li_t v[4])
{
    const __m256i *p = (const __m256i *)src;
    const __m256i a = _mm256_loadu_si256(p), b = _mm256_loadu_si256(p + 1);
    const __m256i c = _mm256_loadu_si256(p + 2), d = _mm256_loadu_si256(p + 3);
    const __m256i t0 = _mm256_unpacklo_epi32(a, b), t1 = _mm256_unpackhi_epi32(a, b);
    const __m256i t2 = _mm256_unpacklo_epi32(c, d), t3 = _mm256_unpackhi_epi32(c, d);
    const __m256i order = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
    v[0] = _mm256_permutevar8x32_epi32(_mm256_unpacklo_epi64(t0, t2), order);
    v[1] = _mm256_permutevar8x32_epi32(_mm256_unpackhi_epi64(t0, t2), order);
    v[2] = _mm256_permutevar8x32_epi32(_mm256_unpacklo_epi64(t1, t3), order);
    v[3] = _mm256_permutevar8x32_epi32(_mm256_unpackhi_epi64(t1, t3), order);
}
HZ_INLINE void hz_li_store4(void *dst, const hz_li_t v[4])
{
    const __m256i order = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
    const __m256i u0 = _mm256_permutevar8x32_epi32(v[0], order), u1 = _mm256_permutevar8x32_epi32(v[1], order);
    const __m256i u2 = _mm256_permutevar8x32_epi32(v[2], order), u3 = _mm256_permutevar8x32_epi32(v[3], order);
    const __m256i x0 = _mm256_unpacklo_epi32(u0, u1), x1 = _mm256_unpackhi_epi32(u0, u1);
    const __m256i x2 = _mm256_unpacklo_epi32(u2, u3), x3 = _mm256_unpackhi_epi32(u2, u3);
    __m256i *p = (__m256i *)dst;
    _mm256_storeu_si256(p, _mm256_unpacklo_epi64(x0, x2));
    _mm256_storeu_si256(p + 1, _mm256_unpackhi_epi64(x0, x2));
    _mm256_storeu_si256(p + 2, _mm256_unpacklo_epi64(x1, x3));
    _mm256_storeu_si256(p + 3, _mm256_unpackhi_epi64(x1, x3));
}

HZ_INLINE void hz_lf_load2(const float *src, hz_lf_t *a, hz_lf_t *b)
{
    const __m256 v0 = _mm256_loadu_ps(src), v1 = _mm256_loadu_ps(src + 8);
    /* per 128-bit half: [a0 a1 a4 a5 | a2 a3 a6 a7], then the 64-bit quarters in order */
    *a = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(v0, v1, 0x88)), 0xd8));
    *b = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(v0, v1, 0xdd)), 0xd8));
}

/* Each lane one to the right, lane 0 from p's last: [p7, c0 .. c6]. */
HZ_INLINE hz_lf_t hz_lf_shift_in_left(hz_lf_t p, hz_lf_t c)
{
    __m256i t = _mm256_permute2x128_si256(_mm256_castps_si256(p), _mm256_castps_si256(c), 0x21);
    return _mm256_castsi256_ps(_mm256_alignr_epi8(_mm256_castps_si256(c), t, 12));
}
/* Each lane one to the left, the last from n's first: [c1 .. c7, n0]. */
HZ_INLINE hz_lf_t hz_lf_shift_in_right(hz_lf_t c, hz_lf_t n)
{
    __m256i t = _mm256_permute2x128_si256(_mm256_castps_si256(c), _mm256_castps_si256(n), 0x21);
    return _mm256_castsi256_ps(_mm256_alignr_epi8(t, _mm256_castps_si256(c), 4));
}
/* A hint that the cache line holding p will be read soon (never faults, any address). */
HZ_INLINE void hz_lanes_prefetch(const void *p) { _mm_prefetch((const char *)p, _MM_HINT_T0); }

#elif defined(HZ_BOARD_SIMD_NEON)
#include <arm_neon.h>

#define HZ_LANES 4
typedef float32x4_t hz_lf_t;
typedef int32x4_t hz_li_t;

HZ_INLINE hz_lf_t hz_lf_set(float v) { return vdupq_n_f32(v); }
HZ_INLINE hz_li_t hz_li_set(int32_t v) { return vdupq_n_s32(v); }
HZ_INLINE hz_li_t hz_li_iota(void)
{
    static const int32_t k[4] = { 0, 1, 2, 3 };
    return vld1q_s32(k);
}
HZ_INLINE hz_lf_t hz_lf_load(const float *p) { return vld1q_f32(p); }
HZ_INLINE void hz_lf_store(float *p, hz_lf_t v) { vst1q_f32(p, v); }
HZ_INLINE void hz_lf_store_halves(float *lo, float *hi, hz_lf_t v)
{
    vst1_f32(lo, vget_low_f32(v));
    vst1_f32(hi, vget_high_f32(v));
}
HZ_INLINE hz_li_t hz_li_load(const void *p) { return vld1q_s32((const int32_t *)p); }
HZ_INLINE void hz_li_store(void *p, hz_li_t v) { vst1q_s32((int32_t *)p, v); }
HZ_INLINE hz_li_t hz_li_load_u8(const uint8_t *p)
{
    uint32_t w = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    uint8x8_t b = vreinterpret_u8_u32(vdup_n_u32(w));
    return vreinterpretq_s32_u32(vmovl_u16(vget_low_u16(vmovl_u8(b))));
}
HZ_INLINE void hz_li_store_u8(uint8_t *p, hz_li_t v)
{
    p[0] = (uint8_t)vgetq_lane_s32(v, 0);
    p[1] = (uint8_t)vgetq_lane_s32(v, 1);
    p[2] = (uint8_t)vgetq_lane_s32(v, 2);
    p[3] = (uint8_t)vgetq_lane_s32(v, 3);
}

HZ_INLINE hz_lf_t hz_lf_add(hz_lf_t a, hz_lf_t b) { return vaddq_f32(a, b); }
HZ_INLINE hz_lf_t hz_lf_sub(hz_lf_t a, hz_lf_t b) { return vsubq_f32(a, b); }
HZ_INLINE hz_lf_t hz_lf_mul(hz_lf_t a, hz_lf_t b) { return vmulq_f32(a, b); }
HZ_INLINE hz_lf_t hz_lf_div(hz_lf_t a, hz_lf_t b) { return vdivq_f32(a, b); }
HZ_INLINE hz_lf_t hz_lf_sqrt(hz_lf_t a) { return vsqrtq_f32(a); }
HZ_INLINE hz_li_t hz_lf_gt(hz_lf_t a, hz_lf_t b) { return vreinterpretq_s32_u32(vcgtq_f32(a, b)); }
HZ_INLINE hz_li_t hz_lf_lt(hz_lf_t a, hz_lf_t b) { return vreinterpretq_s32_u32(vcltq_f32(a, b)); }
HZ_INLINE hz_li_t hz_lf_eq(hz_lf_t a, hz_lf_t b) { return vreinterpretq_s32_u32(vceqq_f32(a, b)); }
HZ_INLINE hz_lf_t hz_lf_sel(hz_li_t m, hz_lf_t a, hz_lf_t b) { return vbslq_f32(vreinterpretq_u32_s32(m), a, b); }
HZ_INLINE hz_lf_t hz_lf_from_li(hz_li_t a) { return vcvtq_f32_s32(a); }
/* hz_floorf (vmath.h): IEEE floor, the same bits */
HZ_INLINE hz_lf_t hz_lf_floor(hz_lf_t x) { return vrndmq_f32(x); }
HZ_INLINE hz_li_t hz_li_from_lf(hz_lf_t a) { return vcvtq_s32_f32(a); } /* truncates */
HZ_INLINE hz_li_t hz_lf_bits(hz_lf_t a) { return vreinterpretq_s32_f32(a); }
HZ_INLINE hz_lf_t hz_lf_from_bits(hz_li_t a) { return vreinterpretq_f32_s32(a); }

HZ_INLINE hz_li_t hz_li_add(hz_li_t a, hz_li_t b) { return vaddq_s32(a, b); }
HZ_INLINE hz_li_t hz_li_sub(hz_li_t a, hz_li_t b) { return vsubq_s32(a, b); }
HZ_INLINE hz_li_t hz_li_mul(hz_li_t a, hz_li_t b) { return vmulq_s32(a, b); }
HZ_INLINE hz_li_t hz_li_and(hz_li_t a, hz_li_t b) { return vandq_s32(a, b); }
HZ_INLINE hz_li_t hz_li_or(hz_li_t a, hz_li_t b) { return vorrq_s32(a, b); }
HZ_INLINE hz_li_t hz_li_andnot(hz_li_t a, hz_li_t b) { return vbicq_s32(a, b); } /* a & ~b */
HZ_INLINE hz_li_t hz_li_eq(hz_li_t a, hz_li_t b) { return vreinterpretq_s32_u32(vceqq_s32(a, b)); }
HZ_INLINE hz_li_t hz_li_gt(hz_li_t a, hz_li_t b) { return vreinterpretq_s32_u32(vcgtq_s32(a, b)); }
HZ_INLINE hz_li_t hz_li_sel(hz_li_t m, hz_li_t a, hz_li_t b) { return vbslq_s32(vreinterpretq_u32_s32(m), a, b); }
HZ_INLINE hz_li_t hz_li_min(hz_li_t a, hz_li_t b) { return vminq_s32(a, b); }
HZ_INLINE hz_li_t hz_li_max(hz_li_t a, hz_li_t b) { return vmaxq_s32(a, b); }
/* FMIN/FMAX return NaN when either input is NaN: the C expressions need the select. */
HZ_INLINE hz_lf_t hz_lf_min_first(hz_lf_t a, hz_lf_t b) { return vbslq_f32(vcltq_f32(a, b), a, b); }
HZ_INLINE hz_lf_t hz_lf_max_first(hz_lf_t a, hz_lf_t b) { return vbslq_f32(vcgtq_f32(a, b), a, b); }
HZ_INLINE hz_lf_t hz_lf_keep(hz_li_t m, hz_lf_t v)
{
    return vreinterpretq_f32_s32(vandq_s32(m, vreinterpretq_s32_f32(v)));
}
#define hz_li_shl(a, n) vshlq_n_s32((a), (n))
#define hz_li_shr(a, n) vreinterpretq_s32_u32(vshrq_n_u32(vreinterpretq_u32_s32(a), (n)))
HZ_INLINE hz_li_t hz_li_shr_by(hz_li_t a, int n)
{
    return vreinterpretq_s32_u32(vshlq_u32(vreinterpretq_u32_s32(a), vdupq_n_s32(-n)));
}
HZ_INLINE hz_li_t hz_li_shr_lanes(hz_li_t a, hz_li_t n)
{
    /* USHL by -n shifts right for n in 0..31 (left for negative n: masked off, as are counts >= 32) */
    uint32x4_t r = vshlq_u32(vreinterpretq_u32_s32(a), vnegq_s32(n));
    return vreinterpretq_s32_u32(vandq_u32(r, vcltq_u32(vreinterpretq_u32_s32(n), vdupq_n_u32(32))));
}
HZ_INLINE int hz_li_any(hz_li_t m) { return vmaxvq_u32(vreinterpretq_u32_s32(m)) != 0; }
HZ_INLINE int32_t hz_li_first(hz_li_t v) { return vgetq_lane_s32(v, 0); }
HZ_INLINE unsigned hz_li_bits(hz_li_t m)
{
    static const int32_t w[4] = { 1, 2, 4, 8 };
    return (unsigned)vaddvq_s32(vandq_s32(m, vld1q_s32(w)));
}

HZ_INLINE hz_li_t hz_li_gather(const int32_t *base, hz_li_t idx)
{
    hz_li_t r = vdupq_n_s32(base[vgetq_lane_s32(idx, 0)]);
    r = vsetq_lane_s32(base[vgetq_lane_s32(idx, 1)], r, 1);
    r = vsetq_lane_s32(base[vgetq_lane_s32(idx, 2)], r, 2);
    return vsetq_lane_s32(base[vgetq_lane_s32(idx, 3)], r, 3);
}
HZ_INLINE hz_lf_t hz_lf_gather(const float *base, hz_li_t idx)
{
    hz_lf_t r = vdupq_n_f32(base[vgetq_lane_s32(idx, 0)]);
    r = vsetq_lane_f32(base[vgetq_lane_s32(idx, 1)], r, 1);
    r = vsetq_lane_f32(base[vgetq_lane_s32(idx, 2)], r, 2);
    return vsetq_lane_f32(base[vgetq_lane_s32(idx, 3)], r, 3);
}

HZ_INLINE int32_t hz_lanes_word_at(const uint8_t *p)
{
    uint32_t v;
    hz_memcpy(&v, p, 4);
    return (int32_t)v;
}
HZ_INLINE hz_li_t hz_li_gather_bytes32(const void *base, hz_li_t off)
{
    const uint8_t *b = (const uint8_t *)base;
    hz_li_t r = vdupq_n_s32(hz_lanes_word_at(b + vgetq_lane_s32(off, 0)));
    r = vsetq_lane_s32(hz_lanes_word_at(b + vgetq_lane_s32(off, 1)), r, 1);
    r = vsetq_lane_s32(hz_lanes_word_at(b + vgetq_lane_s32(off, 2)), r, 2);
    return vsetq_lane_s32(hz_lanes_word_at(b + vgetq_lane_s32(off, 3)), r, 3);
}
HZ_INLINE hz_li_t hz_li_load_u16(const uint16_t *p) { return vreinterpretq_s32_u32(vmovl_u16(vld1_u16(p))); }
HZ_INLINE hz_li_t hz_li_gather_u8(const uint8_t *base, hz_li_t idx)
{
    hz_li_t r = vdupq_n_s32(base[vgetq_lane_s32(idx, 0)]);
    r = vsetq_lane_s32(base[vgetq_lane_s32(idx, 1)], r, 1);
    r = vsetq_lane_s32(base[vgetq_lane_s32(idx, 2)], r, 2);
    return vsetq_lane_s32(base[vgetq_lane_s32(idx, 3)], r, 3);
}

/* Byte indices of a table lookup that moves whole lanes: 4 idx + (0, 1, 2, 3) in each lane. */
HZ_INLINE uint8x16_t hz_lanes_bytes(hz_li_t idx)
{
    return vreinterpretq_u8_s32(vaddq_s32(vmulq_n_s32(idx, 0x04040404), vdupq_n_s32(0x03020100)));
}
HZ_INLINE hz_lf_t hz_lf_perm(hz_lf_t v, hz_li_t idx)
{
    return vreinterpretq_f32_u8(vqtbl1q_u8(vreinterpretq_u8_f32(v), hz_lanes_bytes(idx)));
}
HZ_INLINE hz_li_t hz_li_perm(hz_li_t v, hz_li_t idx)
{
    return vreinterpretq_s32_u8(vqtbl1q_u8(vreinterpretq_u8_s32(v), hz_lanes_bytes(idx)));
}

HZ_INLINE void hz_lf_store3(float *dst, hz_lf_t r, hz_lf_t g, hz_lf_t b)
{
    float32x4x3_t v;
    v.val[0] = r, v.val[1] = g, v.val[2] = b;
    vst3q_f32(dst, v);
}

HZ_INLINE void hz_li_store3_u16(uint16_t *dst, hz_li_t a, hz_li_t b, hz_li_t c)
{
    uint16x4x3_t v;
    v.val[0] = vmovn_u32(vreinterpretq_u32_s32(a));
    v.val[1] = vmovn_u32(vreinterpretq_u32_s32(b));
    v.val[2] = vmovn_u32(vreinterpretq_u32_s32(c));
    vst3_u16(dst, v);
}

HZ_INLINE void hz_lf_load3(const float *src, hz_lf_t *r, hz_lf_t *g, hz_lf_t *b)
{
    float32x4x3_t v = vld3q_f32(src);
    *r = v.val[0], *g = v.val[1], *b = v.val[2];
}

/* Deinterleaving load of HZ_LANES groups of four words: lane i of v[j] = src[4 i + j]; hz_li_store4 is its
 * inverse. */
HZ_INLINE void hz_li_load4(const void *src, hz_li_t v[4])
{
    const int32x4x4_t t = vld4q_s32((const int32_t *)src);
    v[0] = t.val[0], v[1] = t.val[1], v[2] = t.val[2], v[3] = t.val[3];
}
HZ_INLINE void hz_li_store4(void *dst, const hz_li_t v[4])
{
    int32x4x4_t t;
    t.val[0] = v[0], t.val[1] = v[1], t.val[2] = v[2], t.val[3] = v[3];
    vst4q_s32((int32_t *)dst, t);
}

HZ_INLINE void hz_lf_load2(const float *src, hz_lf_t *a, hz_lf_t *b)
{
    float32x4x2_t v = vld2q_f32(src);
    *a = v.val[0], *b = v.val[1];
}

HZ_INLINE hz_lf_t hz_lf_shift_in_left(hz_lf_t p, hz_lf_t c) { return vextq_f32(p, c, 3); }
HZ_INLINE hz_lf_t hz_lf_shift_in_right(hz_lf_t c, hz_lf_t n) { return vextq_f32(c, n, 1); }
HZ_INLINE void hz_lanes_prefetch(const void *p) { __builtin_prefetch(p); }

#else
#error "lanes.h is for AVX2 and NEON boards only"
#endif

/* Derived operations, the same on both. */
HZ_INLINE hz_li_t hz_li_not(hz_li_t m) { return hz_li_eq(m, hz_li_set(0)); }
/* isfinite: the exponent is not all ones. */
HZ_INLINE hz_li_t hz_lf_finite(hz_lf_t a)
{
    hz_li_t e = hz_li_and(hz_lf_bits(a), hz_li_set(0x7f800000));
    return hz_li_not(hz_li_eq(e, hz_li_set(0x7f800000)));
}
/* |x| */
HZ_INLINE hz_lf_t hz_lf_abs(hz_lf_t x) { return hz_lf_from_bits(hz_li_and(hz_lf_bits(x), hz_li_set(0x7fffffff))); }
/* hz_clampf: x < lo ? lo : (x > hi ? hi : x) (NaN stays NaN). */
HZ_INLINE hz_lf_t hz_lf_clamp(hz_lf_t x, hz_lf_t lo, hz_lf_t hi)
{
    return hz_lf_sel(hz_lf_lt(x, lo), lo, hz_lf_sel(hz_lf_gt(x, hi), hi, x));
}
/* hz_lf_clamp where no lane has lo > hi (either may be NaN): t = (hi < x ? hi : x) is x or hi, and
 * lo > t ? lo : t then gives lo exactly when x < lo (t <= x then), x or hi otherwise (hi >= lo). */
HZ_INLINE hz_lf_t hz_lf_clamp_ordered(hz_lf_t x, hz_lf_t lo, hz_lf_t hi)
{
    return hz_lf_max_first(lo, hz_lf_min_first(hi, x));
}

#endif /* HZ_LANES_H */
