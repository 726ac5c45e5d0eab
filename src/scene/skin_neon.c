/* NEON linear-blend skinning (see hz/skin.h; scalar twin in skin.c). One vertex per step: a skinning matrix is
 * four float32x4 columns; blending four of them is sixteen FMAs, the transform four more. */
#include "hz/skin.h"

#include <arm_neon.h>

#include "scene_internal.h"

void hz_skin_blend(const float *mats, const hz_hzb_skin_weight_t *w, const float *rest_pos, const float *rest_nrm,
                   uint32_t n, float *pos, float *nrm)
{
    const float scale = 1.0f / 65535.0f;
    const int normals = rest_nrm && nrm;
    const float32x4_t wmask = vreinterpretq_f32_u32(vsetq_lane_u32(0, vdupq_n_u32(0xffffffffu), 3));
    for (uint32_t i = 0; i < n; i++) {
        float32x4_t c0 = vdupq_n_f32(0.0f), c1 = c0, c2 = c0, c3 = c0;
        for (int k = 0; k < 4; k++) {
            float32x4_t wk = vdupq_n_f32((float)w[i].weight[k] * scale);
            const float *m = mats + (size_t)w[i].bind[k] * HZ_SKIN_MAT_FLOATS;
            c0 = vfmaq_f32(c0, wk, vld1q_f32(m));
            c1 = vfmaq_f32(c1, wk, vld1q_f32(m + 4));
            c2 = vfmaq_f32(c2, wk, vld1q_f32(m + 8));
            c3 = vfmaq_f32(c3, wk, vld1q_f32(m + 12));
        }
        const float *p = rest_pos + (size_t)i * 4;
        float32x4_t r = vfmaq_n_f32(vfmaq_n_f32(vfmaq_n_f32(c3, c0, p[0]), c1, p[1]), c2, p[2]);
        r = vreinterpretq_f32_u32(vandq_u32(vreinterpretq_u32_f32(r), vreinterpretq_u32_f32(wmask)));
        vst1q_f32(pos + (size_t)i * 4, r);
        if (!normals)
            continue;
        const float *nn = rest_nrm + (size_t)i * 4;
        float32x4_t v = vfmaq_n_f32(vmulq_n_f32(c0, nn[0]), c1, nn[1]);
        v = vfmaq_n_f32(v, c2, nn[2]);
        v = vreinterpretq_f32_u32(vandq_u32(vreinterpretq_u32_f32(v), vreinterpretq_u32_f32(wmask)));
        float l2 = vaddvq_f32(vmulq_f32(v, v));
        if (l2 > 0.0f)
            v = vdivq_f32(v, vdupq_n_f32(hz_sqrtf(l2)));
        else
            v = (float32x4_t){ nn[0], nn[1], nn[2], 0.0f };
        vst1q_f32(nrm + (size_t)i * 4, v);
    }
}

const char *hz_skin_blend_path(void)
{
    return "neon";
}
