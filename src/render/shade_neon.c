/* NEON packet surfaces (src/render/shade.h; scalar twin in shade_packet.c): the kernel of shade_kernel.h on 4 lanes.
 * AArch64 has no gather: the "gathers" load lane by lane; the arithmetic is one vector instruction per scalar
 * operation of the twin (vmulq/vaddq, never vfmaq; vdivq and vsqrtq are correctly rounded). */
#include <arm_neon.h>

#include "shade.h"

typedef float32x4_t vf;
typedef int32x4_t vi;
typedef uint32x4_t vm;

static inline vf vf_load(const float *p) { return vld1q_f32(p); }
static inline void vf_store(float *p, vf x) { vst1q_f32(p, x); }
static inline vf vf_set1(float x) { return vdupq_n_f32(x); }
static inline vf vf_add(vf a, vf b) { return vaddq_f32(a, b); }
static inline vf vf_sub(vf a, vf b) { return vsubq_f32(a, b); }
static inline vf vf_mul(vf a, vf b) { return vmulq_f32(a, b); }
static inline vf vf_div(vf a, vf b) { return vdivq_f32(a, b); }
static inline vf vf_sqrt(vf a) { return vsqrtq_f32(a); }
static inline vf vf_abs(vf a) { return vabsq_f32(a); }
static inline vm vf_gt(vf a, vf b) { return vcgtq_f32(a, b); }
static inline vm vf_lt(vf a, vf b) { return vcltq_f32(a, b); }
static inline vf vf_sel(vm m, vf a, vf b) { return vbslq_f32(m, a, b); }
static inline vm vm_and(vm a, vm b) { return vandq_u32(a, b); }
static inline uint32_t vm_bits(vm m)
{
    const uint32x4_t bit = { 1u, 2u, 4u, 8u };
    return vaddvq_u32(vandq_u32(m, bit));
}
static inline vi vi_load(const int32_t *p) { return vld1q_s32(p); }
static inline void vi_store(int32_t *p, vi x) { vst1q_s32(p, x); }
static inline vi vi_set1(int32_t x) { return vdupq_n_s32(x); }
static inline vi vi_add(vi a, vi b) { return vaddq_s32(a, b); }
static inline vi vi_sub(vi a, vi b) { return vsubq_s32(a, b); }
static inline vi vi_mul(vi a, vi b) { return vmulq_s32(a, b); }
static inline vi vi_and(vi a, vi b) { return vandq_s32(a, b); }
static inline vi vi_or(vi a, vi b) { return vorrq_s32(a, b); }
#define vi_srl(x, n) vreinterpretq_s32_u32(vshrq_n_u32(vreinterpretq_u32_s32(x), (n)))
static inline vm vi_lt(vi a, vi b) { return vcltq_s32(a, b); }
static inline vi vi_sel(vm m, vi a, vi b) { return vbslq_s32(m, a, b); }
static inline vf vf_from_vi(vi a) { return vcvtq_f32_s32(a); }
static inline vi vi_trunc(vf a) { return vcvtq_s32_f32(a); }
static inline vf vf_floor(vf a) { return vrndmq_f32(a); }
static inline vi vf_as_vi(vf a) { return vreinterpretq_s32_f32(a); }
static inline vf vi_as_vf(vi a) { return vreinterpretq_f32_s32(a); }
static inline vf vf_gather(const float *base, vi idx)
{
    int32_t ix[4];
    vst1q_s32(ix, idx);
    float r[4] = { base[ix[0]], base[ix[1]], base[ix[2]], base[ix[3]] };
    return vld1q_f32(r);
}
static inline vi vi_gather(const int32_t *base, vi idx)
{
    int32_t ix[4], r[4];
    vst1q_s32(ix, idx);
    for (int i = 0; i < 4; i++)
        hz_memcpy(&r[i], (const char *)base + (size_t)(uint32_t)ix[i] * 4, 4); /* texels need not be aligned */
    return vld1q_s32(r);
}

#include "shade_kernel.h"

const char *hz_shade_path(void)
{
    return "neon";
}
