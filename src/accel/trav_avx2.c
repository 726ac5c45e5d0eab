/*
 * AVX2 traversal: the lane operations of trav_kernel.h on 8-lane registers (nodes of 8 children, blocks of 8
 * triangles), then the kernels themselves (one source for every ISA, see there). Multiplies and adds stay
 * separate instructions (the build's -ffp-contract=off, no FMA intrinsics): the scalar reference's roundings.
 */
#include <immintrin.h>

#include "bvh.h"

#define KW 8
typedef __m256 vf;
typedef __m256 vm;
typedef __m256i vi;

HZ_INLINE vf vf_set1(float x) { return _mm256_set1_ps(x); }
HZ_INLINE vf vf_load(const float *p) { return _mm256_load_ps(p); }
HZ_INLINE void vf_store(float *p, vf v) { _mm256_store_ps(p, v); }
HZ_INLINE vf vf_add(vf a, vf b) { return _mm256_add_ps(a, b); }
HZ_INLINE vf vf_sub(vf a, vf b) { return _mm256_sub_ps(a, b); }
HZ_INLINE vf vf_mul(vf a, vf b) { return _mm256_mul_ps(a, b); }
HZ_INLINE vf vf_fmadd(vf a, vf b, vf c) { return _mm256_fmadd_ps(a, b, c); }
HZ_INLINE vf vf_div(vf a, vf b) { return _mm256_div_ps(a, b); }
HZ_INLINE vf vf_abs(vf a) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), a); }
/* max/min return their second operand when either is NaN: with only `a` NaN-prone, a NaN a drops out */
HZ_INLINE vf vf_maxn(vf a, vf b) { return _mm256_max_ps(a, b); }
HZ_INLINE vf vf_minn(vf a, vf b) { return _mm256_min_ps(a, b); }
HZ_INLINE vm vf_lt(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
HZ_INLINE vm vf_le(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
HZ_INLINE vm vf_gt(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
HZ_INLINE vm vf_ge(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
HZ_INLINE vm vf_eq(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
HZ_INLINE vm vf_neu(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_NEQ_UQ); }
HZ_INLINE vf vf_sel(vm m, vf a, vf b) { return _mm256_blendv_ps(b, a, m); }
HZ_INLINE float vf_lane0(vf v) { return _mm256_cvtss_f32(v); }
HZ_INLINE float vf_hmin(vf v)
{
    __m128 m = _mm_min_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_min_ss(m, _mm_shuffle_ps(m, m, 1)));
}
HZ_INLINE float vf_hmax(vf v)
{
    __m128 m = _mm_max_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_max_ss(m, _mm_shuffle_ps(m, m, 1)));
}

/* Horizontal minima of 8 vectors at once: out[i] is the minimum of v[i]'s lanes. */
HZ_INLINE void vf_hmins(const vf *v, float *out)
{
    const __m256 a01 = _mm256_min_ps(_mm256_unpacklo_ps(v[0], v[1]), _mm256_unpackhi_ps(v[0], v[1]));
    const __m256 a23 = _mm256_min_ps(_mm256_unpacklo_ps(v[2], v[3]), _mm256_unpackhi_ps(v[2], v[3]));
    const __m256 a45 = _mm256_min_ps(_mm256_unpacklo_ps(v[4], v[5]), _mm256_unpackhi_ps(v[4], v[5]));
    const __m256 a67 = _mm256_min_ps(_mm256_unpacklo_ps(v[6], v[7]), _mm256_unpackhi_ps(v[6], v[7]));
    /* per 128-bit half: a01 = [v0 v1 v0 v1] partial minima; combine pairs into [v0 v1 v2 v3] */
    const __m256 b03 = _mm256_min_ps(_mm256_shuffle_ps(a01, a23, 0x44), _mm256_shuffle_ps(a01, a23, 0xEE));
    const __m256 b47 = _mm256_min_ps(_mm256_shuffle_ps(a45, a67, 0x44), _mm256_shuffle_ps(a45, a67, 0xEE));
    _mm256_storeu_ps(out, _mm256_min_ps(_mm256_permute2f128_ps(b03, b47, 0x20), _mm256_permute2f128_ps(b03, b47, 0x31)));
}

HZ_INLINE vm vm_and(vm a, vm b) { return _mm256_and_ps(a, b); }
HZ_INLINE vm vm_or(vm a, vm b) { return _mm256_or_ps(a, b); }
HZ_INLINE vm vm_andn(vm a, vm b) { return _mm256_andnot_ps(b, a); } /* a & ~b */
HZ_INLINE unsigned vm_bits(vm m) { return (unsigned)_mm256_movemask_ps(m); }
HZ_INLINE vm vm_of(unsigned bits)
{
    const __m256i b = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32((int)bits), b), b));
}

HZ_INLINE vi vi_set1(int32_t x) { return _mm256_set1_epi32(x); }
HZ_INLINE vi vi_load(const void *p) { return _mm256_load_si256((const __m256i *)p); }
HZ_INLINE void vi_store(void *p, vi v) { _mm256_store_si256((__m256i *)p, v); }
HZ_INLINE void vi_storeu(void *p, vi v) { _mm256_storeu_si256((__m256i *)p, v); }
HZ_INLINE vi vi_iota(void) { return _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7); }
HZ_INLINE vi vi_and(vi a, vi b) { return _mm256_and_si256(a, b); }
HZ_INLINE vi vi_or(vi a, vi b) { return _mm256_or_si256(a, b); }
HZ_INLINE vi vi_andn(vi a, vi b) { return _mm256_andnot_si256(b, a); } /* a & ~b */
HZ_INLINE vi vi_add(vi a, vi b) { return _mm256_add_epi32(a, b); }
HZ_INLINE vi vi_sub(vi a, vi b) { return _mm256_sub_epi32(a, b); }
#define vi_shl(x, n) _mm256_slli_epi32((x), (n))
HZ_INLINE int32_t vi_lane0(vi v) { return _mm256_cvtsi256_si32(v); }
HZ_INLINE vi vi_sel(vm m, vi a, vi b) { return _mm256_blendv_epi8(b, a, _mm256_castps_si256(m)); }
HZ_INLINE vm vi_gt(vi a, vi b) { return _mm256_castsi256_ps(_mm256_cmpgt_epi32(a, b)); }
HZ_INLINE vm vi_eq(vi a, vi b) { return _mm256_castsi256_ps(_mm256_cmpeq_epi32(a, b)); }
HZ_INLINE vi vm_as_vi(vm m) { return _mm256_castps_si256(m); }
HZ_INLINE unsigned vi_signs(vi a) { return (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(a)); }
HZ_INLINE vi vi_perm(vi v, vi idx) { return _mm256_permutevar8x32_epi32(v, idx); }
HZ_INLINE vi vf_as_vi(vf a) { return _mm256_castps_si256(a); }
HZ_INLINE vf vi_as_vf(vi a) { return _mm256_castsi256_ps(a); }

/* One compare-exchange stage of a bitonic network: lane i meets lane p[i]; lanes in `hi` take the larger key. */
#define SORT_STAGE(v, p0, p1, p2, p3, p4, p5, p6, p7, h0, h1, h2, h3, h4, h5, h6, h7)                              \
    do {                                                                                                           \
        const __m256i p_ = _mm256_permutevar8x32_epi32(v, _mm256_setr_epi32(p0, p1, p2, p3, p4, p5, p6, p7));       \
        v = _mm256_blendv_epi8(_mm256_min_epu32(v, p_), _mm256_max_epu32(v, p_),                                   \
                               _mm256_setr_epi32(h0, h1, h2, h3, h4, h5, h6, h7));                                 \
    } while (0)

/* Bitonic network, ascending (unsigned); stages (k, j) = (2,1) (4,2) (4,1) (8,4) (8,2) (8,1): a lane takes the
 * larger key when (lane & j) != 0 differs from (lane & k) != 0. */
HZ_INLINE vi vi_sort(vi v)
{
    SORT_STAGE(v, 1, 0, 3, 2, 5, 4, 7, 6, 0, -1, -1, 0, 0, -1, -1, 0);
    SORT_STAGE(v, 2, 3, 0, 1, 6, 7, 4, 5, 0, 0, -1, -1, -1, -1, 0, 0);
    SORT_STAGE(v, 1, 0, 3, 2, 5, 4, 7, 6, 0, -1, 0, -1, -1, 0, -1, 0);
    SORT_STAGE(v, 4, 5, 6, 7, 0, 1, 2, 3, 0, 0, 0, 0, -1, -1, -1, -1);
    SORT_STAGE(v, 2, 3, 0, 1, 6, 7, 4, 5, 0, 0, -1, -1, 0, 0, -1, -1);
    SORT_STAGE(v, 1, 0, 3, 2, 5, 4, 7, 6, 0, -1, 0, -1, 0, -1, 0, -1);
    return v;
}

#include "trav_kernel.h"
