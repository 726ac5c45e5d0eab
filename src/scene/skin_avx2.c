/* AVX2 + FMA linear-blend skinning (see hz/skin.h; scalar twin in skin.c). One vertex per step: a skinning
 * matrix is two 256-bit registers (columns x|y and z|translation), so blending four of them is eight FMAs, and
 * the transform is two more plus a fold of the halves. */
#include "hz/skin.h"

#include <immintrin.h>

#include "scene_internal.h"

void hz_skin_blend(const float *mats, const hz_hzb_skin_weight_t *w, const float *rest_pos, const float *rest_nrm,
                   uint32_t n, float *pos, float *nrm)
{
    const __m256 scale = _mm256_set1_ps(1.0f / 65535.0f);
    const int normals = rest_nrm && nrm;
    for (uint32_t i = 0; i < n; i++) {
        __m256 xy = _mm256_setzero_ps(), zt = _mm256_setzero_ps();
        for (int k = 0; k < 4; k++) {
            __m256 wk = _mm256_mul_ps(_mm256_set1_ps((float)w[i].weight[k]), scale);
            const float *m = mats + (size_t)w[i].bind[k] * HZ_SKIN_MAT_FLOATS;
            xy = _mm256_fmadd_ps(wk, _mm256_loadu_ps(m), xy);
            zt = _mm256_fmadd_ps(wk, _mm256_loadu_ps(m + 8), zt);
        }
        const float *p = rest_pos + (size_t)i * 4;
        __m256 pxy = _mm256_setr_m128(_mm_set1_ps(p[0]), _mm_set1_ps(p[1]));
        __m256 pz1 = _mm256_setr_m128(_mm_set1_ps(p[2]), _mm_set1_ps(1.0f));
        __m256 r = _mm256_fmadd_ps(zt, pz1, _mm256_mul_ps(xy, pxy));
        __m128 q = _mm_add_ps(_mm256_castps256_ps128(r), _mm256_extractf128_ps(r, 1));
        q = _mm_blend_ps(q, _mm_setzero_ps(), 8); /* w = 0 */
        _mm_storeu_ps(pos + (size_t)i * 4, q);
        if (!normals)
            continue;
        const float *nn = rest_nrm + (size_t)i * 4;
        __m256 nxy = _mm256_setr_m128(_mm_set1_ps(nn[0]), _mm_set1_ps(nn[1]));
        __m256 nz0 = _mm256_setr_m128(_mm_set1_ps(nn[2]), _mm_setzero_ps());
        __m256 rn = _mm256_fmadd_ps(zt, nz0, _mm256_mul_ps(xy, nxy));
        __m128 v = _mm_add_ps(_mm256_castps256_ps128(rn), _mm256_extractf128_ps(rn, 1));
        v = _mm_blend_ps(v, _mm_setzero_ps(), 8);
        __m128 len2 = _mm_dp_ps(v, v, 0x7f);
        float l2 = _mm_cvtss_f32(len2);
        if (l2 > 0.0f)
            v = _mm_div_ps(v, _mm_sqrt_ps(len2));
        else
            v = _mm_setr_ps(nn[0], nn[1], nn[2], 0.0f);
        _mm_storeu_ps(nrm + (size_t)i * 4, v);
    }
}

const char *hz_skin_blend_path(void)
{
    return "avx2";
}
