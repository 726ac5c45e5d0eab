/*
 * NEON traversal (AArch64): the lane operations of trav_kernel.h on 4-lane registers (nodes of 4 children,
 * blocks of 4 triangles), then the kernels themselves (one source for every ISA, see there). maxNum/minNum
 * drop a NaN operand on either side; the kernels pass the NaN-prone one first, as x86 needs (see bvh.h).
 */
#include <arm_neon.h>

#include "bvh.h"

#define KW 4
typedef float32x4_t vf;
typedef uint32x4_t vm;
typedef int32x4_t vi;

HZ_INLINE vf vf_set1(float x) { return vdupq_n_f32(x); }
HZ_INLINE vf vf_load(const float *p) { return vld1q_f32(p); }
HZ_INLINE void vf_store(float *p, vf v) { vst1q_f32(p, v); }
HZ_INLINE vf vf_add(vf a, vf b) { return vaddq_f32(a, b); }
HZ_INLINE vf vf_sub(vf a, vf b) { return vsubq_f32(a, b); }
HZ_INLINE vf vf_mul(vf a, vf b) { return vmulq_f32(a, b); }
HZ_INLINE vf vf_fmadd(vf a, vf b, vf c) { return vfmaq_f32(c, a, b); }
HZ_INLINE vf vf_div(vf a, vf b) { return vdivq_f32(a, b); }
HZ_INLINE vf vf_abs(vf a) { return vabsq_f32(a); }
HZ_INLINE vf vf_maxn(vf a, vf b) { return vmaxnmq_f32(a, b); }
HZ_INLINE vf vf_minn(vf a, vf b) { return vminnmq_f32(a, b); }
HZ_INLINE vm vf_lt(vf a, vf b) { return vcltq_f32(a, b); }
HZ_INLINE vm vf_le(vf a, vf b) { return vcleq_f32(a, b); }
HZ_INLINE vm vf_gt(vf a, vf b) { return vcgtq_f32(a, b); }
HZ_INLINE vm vf_ge(vf a, vf b) { return vcgeq_f32(a, b); }
HZ_INLINE vm vf_eq(vf a, vf b) { return vceqq_f32(a, b); }
HZ_INLINE vm vf_neu(vf a, vf b) { return vmvnq_u32(vceqq_f32(a, b)); }
HZ_INLINE vf vf_sel(vm m, vf a, vf b) { return vbslq_f32(m, a, b); }
HZ_INLINE float vf_lane0(vf v) { return vgetq_lane_f32(v, 0); }
HZ_INLINE float vf_hmin(vf v) { return vminvq_f32(v); }
HZ_INLINE float vf_hmax(vf v) { return vmaxvq_f32(v); }

/* Horizontal minima of 4 vectors at once: out[i] is the minimum of v[i]'s lanes. */
HZ_INLINE void vf_hmins(const vf *v, float *out)
{
    vst1q_f32(out, vpminq_f32(vpminq_f32(v[0], v[1]), vpminq_f32(v[2], v[3])));
}

HZ_INLINE vm vm_and(vm a, vm b) { return vandq_u32(a, b); }
HZ_INLINE vm vm_or(vm a, vm b) { return vorrq_u32(a, b); }
HZ_INLINE vm vm_andn(vm a, vm b) { return vbicq_u32(a, b); } /* a & ~b */
HZ_INLINE unsigned vm_bits(vm m)
{
    static const uint32_t bits[4] = { 1, 2, 4, 8 };
    return vaddvq_u32(vandq_u32(m, vld1q_u32(bits)));
}
HZ_INLINE vm vm_of(unsigned b)
{
    static const uint32_t bits[4] = { 1, 2, 4, 8 };
    return vtstq_u32(vdupq_n_u32(b), vld1q_u32(bits));
}

HZ_INLINE vi vi_set1(int32_t x) { return vdupq_n_s32(x); }
HZ_INLINE vi vi_load(const void *p) { return vld1q_s32((const int32_t *)p); }
HZ_INLINE void vi_store(void *p, vi v) { vst1q_s32((int32_t *)p, v); }
HZ_INLINE void vi_storeu(void *p, vi v) { vst1q_s32((int32_t *)p, v); }
HZ_INLINE vi vi_iota(void)
{
    static const int32_t k[4] = { 0, 1, 2, 3 };
    return vld1q_s32(k);
}
HZ_INLINE vi vi_and(vi a, vi b) { return vandq_s32(a, b); }
HZ_INLINE vi vi_or(vi a, vi b) { return vorrq_s32(a, b); }
HZ_INLINE vi vi_andn(vi a, vi b) { return vbicq_s32(a, b); } /* a & ~b */
HZ_INLINE vi vi_add(vi a, vi b) { return vaddq_s32(a, b); }
HZ_INLINE vi vi_sub(vi a, vi b) { return vsubq_s32(a, b); }
#define vi_shl(x, n) vshlq_n_s32((x), (n))
HZ_INLINE int32_t vi_lane0(vi v) { return vgetq_lane_s32(v, 0); }
HZ_INLINE vi vi_sel(vm m, vi a, vi b) { return vbslq_s32(m, a, b); }
HZ_INLINE vm vi_gt(vi a, vi b) { return vcgtq_s32(a, b); }
/* Lane i of the result: lane idx[i] (0..3) of v, as a byte table lookup. */
HZ_INLINE vm vi_eq(vi a, vi b) { return vceqq_s32(a, b); }
HZ_INLINE vi vm_as_vi(vm m) { return vreinterpretq_s32_u32(m); }
HZ_INLINE unsigned vi_signs(vi a) { return vm_bits(vreinterpretq_u32_s32(vshrq_n_s32(a, 31))); }
HZ_INLINE vi vi_perm(vi v, vi idx)
{
    const uint8x16_t bytes = vreinterpretq_u8_s32(vaddq_s32(vmulq_n_s32(idx, 0x04040404), vdupq_n_s32(0x03020100)));
    return vreinterpretq_s32_u8(vqtbl1q_u8(vreinterpretq_u8_s32(v), bytes));
}
HZ_INLINE vi vf_as_vi(vf a) { return vreinterpretq_s32_f32(a); }
HZ_INLINE vf vi_as_vf(vi a) { return vreinterpretq_f32_s32(a); }

/* Four keys ascending (unsigned): comparators (0,1)(2,3), (0,2)(1,3), (1,2). */
HZ_INLINE vi vi_sort(vi v)
{
    static const uint32_t lo01[4] = { ~0u, 0, ~0u, 0 }, lo02[4] = { ~0u, ~0u, 0, 0 };
    static const uint8_t swap12[16] = { 0, 1, 2, 3, 8, 9, 10, 11, 4, 5, 6, 7, 12, 13, 14, 15 };
    uint32x4_t u = vreinterpretq_u32_s32(v), p;
    p = vrev64q_u32(u);
    u = vbslq_u32(vld1q_u32(lo01), vminq_u32(u, p), vmaxq_u32(u, p));
    p = vextq_u32(u, u, 2);
    u = vbslq_u32(vld1q_u32(lo02), vminq_u32(u, p), vmaxq_u32(u, p));
    p = vreinterpretq_u32_u8(vqtbl1q_u8(vreinterpretq_u8_u32(u), vld1q_u8(swap12)));
    u = vbslq_u32(vld1q_u32(lo02), vminq_u32(u, p), vmaxq_u32(u, p));
    return vreinterpretq_s32_u32(u);
}

#include "trav_kernel.h"
