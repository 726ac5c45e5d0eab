/*
 * hz/vmath.h — small float math for the core: vec3, mat4 and the scalar functions the core needs without libm.
 *
 * Contract:
 *  - No libm: sqrt maps to the hardware instruction (builds use -fno-math-errno); sin/cos/tan/floor are
 *    implemented here from + - * / only, so results are bit-identical on x86-64 and AArch64 (the build uses
 *    -ffp-contract=off, so no FMA is fused implicitly). hz_sinf/hz_cosf are accurate to 2 ulp of float for
 *    |x| <= 1e5; beyond that, range reduction loses precision (angles there are meaningless anyway).
 *  - hz_vec3_t is three floats (12 bytes, no padding). hz_v3_normalize of a zero or non-finite vector returns
 *    the zero vector rather than NaN.
 *  - hz_mat4_t is column-major: m[col * 4 + row]; points are column vectors, so hz_mat4_mul(a, b) applies b
 *    first. hz_mat4_inverse reports a singular (or non-finite) matrix instead of returning garbage.
 *  - Float <-> Q16.16 conversions round to nearest and saturate; NaN converts to 0.
 */
#ifndef HZ_VMATH_H
#define HZ_VMATH_H

#include <float.h>
#include <stdint.h>

#include "hz/base.h"
#include "hz/fixed.h"
#include "hz/status.h"

#define HZ_PI 3.14159265358979323846f

/* ---- scalar ---- */
HZ_INLINE float hz_sqrtf(float x) { return __builtin_sqrtf(x); }
HZ_INLINE float hz_absf(float x) { return __builtin_fabsf(x); }
HZ_INLINE float hz_minf(float a, float b) { return a < b ? a : b; } /* returns b if either is NaN */
HZ_INLINE float hz_maxf(float a, float b) { return a > b ? a : b; } /* returns b if either is NaN */
HZ_INLINE float hz_clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }
HZ_INLINE int hz_isfinitef(float x) { return __builtin_isfinite(x); }
HZ_INLINE int hz_isnanf(float x) { return x != x; }

/* IEEE floor without the ISA's instruction: |x| >= 2^23 is integral, a zero keeps its sign, NaN and infinities
 * come back unchanged, else truncate and step down. */
HZ_INLINE float hz_floorf_soft(float x)
{
    if (!(hz_absf(x) < 8388608.0f) || x == 0.0f)
        return x;
    float t = (float)(int32_t)x; /* truncation toward zero */
    return t - (float)(t > x);   /* no branch: its sign is the data's, a coin toss for texture lookups */
}
/* IEEE floor, one instruction where the ISA has one (SSE4.1, AArch64): texture lookups and any-hit alpha tests
 * call it four times a sample. The lanes' floors (lanes.h, the shading kernel) give the same bits. */
HZ_INLINE float hz_floorf(float x)
{
#if defined(__SSE4_1__) || defined(__aarch64__)
    return __builtin_floorf(x);
#else
    return hz_floorf_soft(x);
#endif
}
float hz_sinf(float x);
float hz_cosf(float x);
float hz_tanf(float x);
/* sin and cos of one angle with one range reduction. */
void hz_sincosf(float x, float *s, float *c);

/* Top 24 bits of u as a float in [0, 1): exact, never 1.0. */
HZ_INLINE float hz_u32_to_unit(uint32_t u) { return (float)(u >> 8) * (1.0f / 16777216.0f); }

/* Inline: the tdense resolve converts two per tile in the last frame of every cycle. */
HZ_INLINE hz_q16_t hz_q16_from_float(float f)
{
    if (hz_isnanf(f))
        return 0;
    double v = (double)f * 65536.0;
    if (v >= 2147483647.0)
        return HZ_Q16_MAX;
    if (v <= -2147483648.0)
        return HZ_Q16_MIN;
    /* Round half away from zero, matching hz_q16_mul. */
    double r = v >= 0 ? v + 0.5 : v - 0.5;
    return (hz_q16_t)(int64_t)r; /* conversion truncates toward zero */
}
HZ_INLINE float hz_q16_to_float(hz_q16_t q) { return (float)q * (1.0f / 65536.0f); }

/* ---- vec3 ---- */
typedef struct hz_vec3 {
    float x, y, z;
} hz_vec3_t;

HZ_INLINE hz_vec3_t hz_v3(float x, float y, float z) { hz_vec3_t v = { x, y, z }; return v; }
HZ_INLINE hz_vec3_t hz_v3_add(hz_vec3_t a, hz_vec3_t b) { return hz_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
HZ_INLINE hz_vec3_t hz_v3_sub(hz_vec3_t a, hz_vec3_t b) { return hz_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
HZ_INLINE hz_vec3_t hz_v3_mul(hz_vec3_t a, hz_vec3_t b) { return hz_v3(a.x * b.x, a.y * b.y, a.z * b.z); }
HZ_INLINE hz_vec3_t hz_v3_scale(hz_vec3_t a, float s) { return hz_v3(a.x * s, a.y * s, a.z * s); }
HZ_INLINE hz_vec3_t hz_v3_neg(hz_vec3_t a) { return hz_v3(-a.x, -a.y, -a.z); }
HZ_INLINE float hz_v3_dot(hz_vec3_t a, hz_vec3_t b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
HZ_INLINE hz_vec3_t hz_v3_cross(hz_vec3_t a, hz_vec3_t b)
{
    return hz_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
HZ_INLINE float hz_v3_len(hz_vec3_t a) { return hz_sqrtf(hz_v3_dot(a, a)); }
HZ_INLINE hz_vec3_t hz_v3_min(hz_vec3_t a, hz_vec3_t b)
{
    return hz_v3(hz_minf(a.x, b.x), hz_minf(a.y, b.y), hz_minf(a.z, b.z));
}
HZ_INLINE hz_vec3_t hz_v3_max(hz_vec3_t a, hz_vec3_t b)
{
    return hz_v3(hz_maxf(a.x, b.x), hz_maxf(a.y, b.y), hz_maxf(a.z, b.z));
}
HZ_INLINE hz_vec3_t hz_v3_lerp(hz_vec3_t a, hz_vec3_t b, float t)
{
    return hz_v3(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t);
}
HZ_INLINE float hz_v3_get(hz_vec3_t a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }
/* hz_v3_normalize's path for a finite vector whose squared length overflows or underflows. */
hz_vec3_t hz_v3_normalize_rescaled(hz_vec3_t a);
/* Inline: a vector returned from a call passes through the stack in pieces, and copying it into a ray or a
 * packet stalled on store forwarding in the per-ray loops. */
HZ_INLINE hz_vec3_t hz_v3_normalize(hz_vec3_t a)
{
    if (!hz_isfinitef(a.x) || !hz_isfinitef(a.y) || !hz_isfinitef(a.z))
        return hz_v3(0.0f, 0.0f, 0.0f);
    const float l2 = hz_v3_dot(a, a);
    if (!(l2 > 0.0f) || !hz_isfinitef(l2))
        return hz_v3_normalize_rescaled(a);
    return hz_v3_scale(a, 1.0f / hz_sqrtf(l2));
}

/* ---- mat4 ---- */
typedef struct hz_mat4 {
    float m[16];
} hz_mat4_t;

hz_mat4_t hz_mat4_identity(void);
hz_mat4_t hz_mat4_mul(const hz_mat4_t *a, const hz_mat4_t *b);
hz_mat4_t hz_mat4_transpose(const hz_mat4_t *a);
hz_mat4_t hz_mat4_translate(hz_vec3_t t);
hz_mat4_t hz_mat4_scale(hz_vec3_t s);
/* Rotation by `radians` about `axis` (normalised here; a zero axis gives the identity), right-handed. */
hz_mat4_t hz_mat4_rotate(hz_vec3_t axis, float radians);
/* Camera-to-world matrix of a camera at eye looking at target (-z forward, +y up, right-handed). A degenerate
 * up (parallel to the view direction) is replaced by the closest axis that is not. */
hz_mat4_t hz_mat4_look_at(hz_vec3_t eye, hz_vec3_t target, hz_vec3_t up);
/* OpenGL-style projection (clip z in [-w, w]); fov_y in radians. */
hz_mat4_t hz_mat4_perspective(float fov_y, float aspect, float z_near, float z_far);
/* General inverse via cofactors in double precision; HZ_E_RANGE if singular or non-finite. */
hz_status_t hz_mat4_inverse(const hz_mat4_t *a, hz_mat4_t *out);

hz_vec3_t hz_mat4_mul_point(const hz_mat4_t *a, hz_vec3_t p);  /* affine: w = 1, no divide */
hz_vec3_t hz_mat4_mul_dir(const hz_mat4_t *a, hz_vec3_t d);    /* w = 0 */
/* Full projective transform; returns w (the caller decides what w <= 0 means). */
float hz_mat4_mul_point_h(const hz_mat4_t *a, hz_vec3_t p, hz_vec3_t *out_ndc);

#endif /* HZ_VMATH_H */
