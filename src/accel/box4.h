/*
 * src/accel/box4.h — four float lanes for the BVH builder's boxes (x, y, z and a lane that is never looked at),
 * internal to src/accel: SSE on AVX2 boards, NEON on NEON boards, plain C elsewhere (the scalar twin; a build
 * with HZ_BOX4_SCALAR defined uses it on every board, which test_accel_build_twin compares against).
 *
 * Contract
 *  - Every operation rounds exactly as the scalar C it stands for under -ffp-contract=off, lane by lane:
 *    f4_min(a, b) is `a < b ? a : b` and f4_max(a, b) is `a > b ? a : b` (hz_minf / hz_maxf: the second
 *    operand on NaN and on equal values, so -0 / +0 come out as the scalar fold gives them), add, sub, mul are
 *    IEEE single precision, i4_from_f4 truncates like a C cast for values that fit an int32. So the builder
 *    makes bit-identical trees on every board.
 *  - f4_put(v, k, x) is v with lane k set to x; f4_rot1(v) is (v1, v2, v3, v0); f4_yzx(v) is (v1, v2, v0, v3).
 *  - Does not: assume alignment, touch memory other than through the explicit loads and stores.
 */
#ifndef HZ_ACCEL_BOX4_H
#define HZ_ACCEL_BOX4_H

#include "hz/base.h"
#include "hz/config.h"

#if defined(HZ_SIMD_AVX2) && !defined(HZ_BOX4_SCALAR)
#include <immintrin.h>
typedef __m128 f4_t;
typedef __m128i i4_t;
HZ_INLINE f4_t f4_load(const float *p) { return _mm_loadu_ps(p); }
HZ_INLINE void f4_store(float *p, f4_t v) { _mm_storeu_ps(p, v); }
HZ_INLINE f4_t f4_set1(float x) { return _mm_set1_ps(x); }
HZ_INLINE f4_t f4_set(float x, float y, float z, float w) { return _mm_setr_ps(x, y, z, w); }
HZ_INLINE f4_t f4_add(f4_t a, f4_t b) { return _mm_add_ps(a, b); }
HZ_INLINE f4_t f4_sub(f4_t a, f4_t b) { return _mm_sub_ps(a, b); }
HZ_INLINE f4_t f4_mul(f4_t a, f4_t b) { return _mm_mul_ps(a, b); }
HZ_INLINE f4_t f4_min(f4_t a, f4_t b) { return _mm_min_ps(a, b); } /* a < b ? a : b */
HZ_INLINE f4_t f4_max(f4_t a, f4_t b) { return _mm_max_ps(a, b); } /* a > b ? a : b */
/* lanes 0..2 (bit k for lane k) of a < b, a <= b, a == b */
HZ_INLINE unsigned f4_lt3(f4_t a, f4_t b) { return (unsigned)_mm_movemask_ps(_mm_cmplt_ps(a, b)) & 7u; }
HZ_INLINE unsigned f4_le3(f4_t a, f4_t b) { return (unsigned)_mm_movemask_ps(_mm_cmple_ps(a, b)) & 7u; }
HZ_INLINE unsigned f4_eq3(f4_t a, f4_t b) { return (unsigned)_mm_movemask_ps(_mm_cmpeq_ps(a, b)) & 7u; }
HZ_INLINE i4_t i4_from_f4(f4_t a) { return _mm_cvttps_epi32(a); }
HZ_INLINE i4_t i4_clamp(i4_t a, int lo, int hi)
{
    return _mm_min_epi32(_mm_max_epi32(a, _mm_set1_epi32(lo)), _mm_set1_epi32(hi));
}
HZ_INLINE void i4_store(int32_t *p, i4_t v) { _mm_storeu_si128((__m128i *)(void *)p, v); }
/* (v1, v2, v3, v0) */
HZ_INLINE f4_t f4_rot1(f4_t v) { return _mm_shuffle_ps(v, v, _MM_SHUFFLE(0, 3, 2, 1)); }
/* (v1, v2, v0, v3) */
HZ_INLINE f4_t f4_yzx(f4_t v) { return _mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 0, 2, 1)); }
/* v with lane k (0..3) replaced by x */
HZ_INLINE f4_t f4_put(f4_t v, int k, float x)
{
    static const int32_t m[4][4] HZ_ALIGNED(16) = { { -1, 0, 0, 0 }, { 0, -1, 0, 0 }, { 0, 0, -1, 0 }, { 0, 0, 0, -1 } };
    return _mm_blendv_ps(v, _mm_set1_ps(x), _mm_load_ps((const float *)(const void *)m[k]));
}
#elif defined(HZ_SIMD_NEON) && !defined(HZ_BOX4_SCALAR)
#include <arm_neon.h>
typedef float32x4_t f4_t;
typedef int32x4_t i4_t;
HZ_INLINE f4_t f4_load(const float *p) { return vld1q_f32(p); }
HZ_INLINE void f4_store(float *p, f4_t v) { vst1q_f32(p, v); }
HZ_INLINE f4_t f4_set1(float x) { return vdupq_n_f32(x); }
HZ_INLINE f4_t f4_set(float x, float y, float z, float w)
{
    const float v[4] = { x, y, z, w };
    return vld1q_f32(v);
}
HZ_INLINE f4_t f4_add(f4_t a, f4_t b) { return vaddq_f32(a, b); }
HZ_INLINE f4_t f4_sub(f4_t a, f4_t b) { return vsubq_f32(a, b); }
HZ_INLINE f4_t f4_mul(f4_t a, f4_t b) { return vmulq_f32(a, b); }
/* not vminq / vmaxq: those order -0 below +0 and pass NaN through; the scalar fold's semantics instead */
HZ_INLINE f4_t f4_min(f4_t a, f4_t b) { return vbslq_f32(vcltq_f32(a, b), a, b); }
HZ_INLINE f4_t f4_max(f4_t a, f4_t b) { return vbslq_f32(vcgtq_f32(a, b), a, b); }
HZ_INLINE unsigned f4_bits3(uint32x4_t m)
{
    static const uint32_t w[4] = { 1u, 2u, 4u, 0u };
    return vaddvq_u32(vandq_u32(m, vld1q_u32(w)));
}
HZ_INLINE unsigned f4_lt3(f4_t a, f4_t b) { return f4_bits3(vcltq_f32(a, b)); }
HZ_INLINE unsigned f4_le3(f4_t a, f4_t b) { return f4_bits3(vcleq_f32(a, b)); }
HZ_INLINE unsigned f4_eq3(f4_t a, f4_t b) { return f4_bits3(vceqq_f32(a, b)); }
HZ_INLINE i4_t i4_from_f4(f4_t a) { return vcvtq_s32_f32(a); }
HZ_INLINE i4_t i4_clamp(i4_t a, int lo, int hi) { return vminq_s32(vmaxq_s32(a, vdupq_n_s32(lo)), vdupq_n_s32(hi)); }
HZ_INLINE void i4_store(int32_t *p, i4_t v) { vst1q_s32(p, v); }
HZ_INLINE f4_t f4_rot1(f4_t v) { return vextq_f32(v, v, 1); }
HZ_INLINE f4_t f4_yzx(f4_t v) { return vcopyq_laneq_f32(vextq_f32(v, v, 1), 2, v, 0); }
HZ_INLINE f4_t f4_put(f4_t v, int k, float x)
{
    static const uint32_t m[4][4] = { { ~0u, 0, 0, 0 }, { 0, ~0u, 0, 0 }, { 0, 0, ~0u, 0 }, { 0, 0, 0, ~0u } };
    return vbslq_f32(vld1q_u32(m[k]), vdupq_n_f32(x), v);
}
#else
typedef struct f4 {
    float v[4];
} f4_t;
typedef struct i4 {
    int32_t v[4];
} i4_t;
HZ_INLINE f4_t f4_load(const float *p)
{
    f4_t r;
    for (int c = 0; c < 4; c++)
        r.v[c] = p[c];
    return r;
}
HZ_INLINE void f4_store(float *p, f4_t v)
{
    for (int c = 0; c < 4; c++)
        p[c] = v.v[c];
}
HZ_INLINE f4_t f4_set1(float x)
{
    f4_t r = { { x, x, x, x } };
    return r;
}
HZ_INLINE f4_t f4_set(float x, float y, float z, float w)
{
    f4_t r = { { x, y, z, w } };
    return r;
}
#define HZ_F4_BINOP(name, expr)                                                                                       \
    HZ_INLINE f4_t name(f4_t a, f4_t b)                                                                               \
    {                                                                                                                 \
        f4_t r;                                                                                                       \
        for (int c = 0; c < 4; c++)                                                                                   \
            r.v[c] = (expr);                                                                                          \
        return r;                                                                                                     \
    }
HZ_F4_BINOP(f4_add, a.v[c] + b.v[c])
HZ_F4_BINOP(f4_sub, a.v[c] - b.v[c])
HZ_F4_BINOP(f4_mul, a.v[c] * b.v[c])
HZ_F4_BINOP(f4_min, a.v[c] < b.v[c] ? a.v[c] : b.v[c])
HZ_F4_BINOP(f4_max, a.v[c] > b.v[c] ? a.v[c] : b.v[c])
#undef HZ_F4_BINOP
HZ_INLINE unsigned f4_lt3(f4_t a, f4_t b)
{
    return (unsigned)(a.v[0] < b.v[0]) | (unsigned)(a.v[1] < b.v[1]) << 1 | (unsigned)(a.v[2] < b.v[2]) << 2;
}
HZ_INLINE unsigned f4_le3(f4_t a, f4_t b)
{
    return (unsigned)(a.v[0] <= b.v[0]) | (unsigned)(a.v[1] <= b.v[1]) << 1 | (unsigned)(a.v[2] <= b.v[2]) << 2;
}
HZ_INLINE unsigned f4_eq3(f4_t a, f4_t b)
{
    return (unsigned)(a.v[0] == b.v[0]) | (unsigned)(a.v[1] == b.v[1]) << 1 | (unsigned)(a.v[2] == b.v[2]) << 2;
}
HZ_INLINE i4_t i4_from_f4(f4_t a)
{
    i4_t r;
    for (int c = 0; c < 4; c++)
        r.v[c] = (int32_t)a.v[c];
    return r;
}
HZ_INLINE i4_t i4_clamp(i4_t a, int lo, int hi)
{
    for (int c = 0; c < 4; c++)
        a.v[c] = a.v[c] < lo ? lo : (a.v[c] > hi ? hi : a.v[c]);
    return a;
}
HZ_INLINE void i4_store(int32_t *p, i4_t v)
{
    for (int c = 0; c < 4; c++)
        p[c] = v.v[c];
}
HZ_INLINE f4_t f4_rot1(f4_t v)
{
    f4_t r = { { v.v[1], v.v[2], v.v[3], v.v[0] } };
    return r;
}
HZ_INLINE f4_t f4_yzx(f4_t v)
{
    f4_t r = { { v.v[1], v.v[2], v.v[0], v.v[3] } };
    return r;
}
HZ_INLINE f4_t f4_put(f4_t v, int k, float x)
{
    v.v[k] = x;
    return v;
}
#endif

#endif /* HZ_ACCEL_BOX4_H */
