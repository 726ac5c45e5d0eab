/* Runtime linear-blend skinning: joint matrices and the scalar blend (see hz/skin.h). The SIMD blends live in
 * skin_avx2.c / skin_neon.c; this file's scalar one is their twin and the fallback on scalar boards. */
#include "hz/skin.h"

#include "scene_internal.h"

/* J(t) * B as four float4 columns. B is 3x4 column-major with an implied bottom row 0 0 0 1. */
static void bind_matrix(const hz_hzb_skin_bind_t *b, const hz_mat4_t *j, float *out)
{
    for (int c = 0; c < 4; c++) {
        const float *bc = b->inv_bind + c * 3;
        for (int r = 0; r < 3; r++) {
            float v = j->m[0 * 4 + r] * bc[0] + j->m[1 * 4 + r] * bc[1] + j->m[2 * 4 + r] * bc[2];
            out[c * 4 + r] = c == 3 ? v + j->m[12 + r] : v;
        }
        out[c * 4 + 3] = 0.0f;
    }
}

void hz_skin_matrices(const hz_hzb_object_t *o, const hz_hzb_skin_bind_t *binds, const hz_hzb_joint_t *joints,
                      const hz_hzb_rigid_key_t *keys, float t, float *mats)
{
    for (uint32_t i = 0; i < o->key_count; i++) {
        const hz_hzb_skin_bind_t *b = &binds[o->key_first + i];
        const hz_hzb_joint_t *j = &joints[b->joint];
        hz_mat4_t m = hz_rigid_keys_matrix(keys + j->key_first, j->key_count, t);
        bind_matrix(b, &m, mats + (size_t)i * HZ_SKIN_MAT_FLOATS);
    }
}

void hz_skin_blend_scalar(const float *mats, const hz_hzb_skin_weight_t *w, const float *rest_pos,
                          const float *rest_nrm, uint32_t n, float *pos, float *nrm)
{
    const float scale = 1.0f / 65535.0f;
    for (uint32_t i = 0; i < n; i++) {
        float m[16] = { 0 };
        for (int k = 0; k < 4; k++) {
            float wk = (float)w[i].weight[k] * scale;
            const float *src = mats + (size_t)w[i].bind[k] * HZ_SKIN_MAT_FLOATS;
            for (int e = 0; e < 16; e++)
                m[e] += wk * src[e];
        }
        const float *p = rest_pos + (size_t)i * 4;
        float *dp = pos + (size_t)i * 4;
        for (int r = 0; r < 3; r++)
            dp[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
        dp[3] = 0.0f;
        if (!rest_nrm || !nrm)
            continue;
        const float *q = rest_nrm + (size_t)i * 4;
        float v[3];
        for (int r = 0; r < 3; r++)
            v[r] = m[r] * q[0] + m[4 + r] * q[1] + m[8 + r] * q[2];
        float len2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        float *dn = nrm + (size_t)i * 4;
        if (len2 > 0.0f) {
            float inv = 1.0f / hz_sqrtf(len2);
            dn[0] = v[0] * inv, dn[1] = v[1] * inv, dn[2] = v[2] * inv;
        } else {
            dn[0] = q[0], dn[1] = q[1], dn[2] = q[2];
        }
        dn[3] = 0.0f;
    }
}

#if !defined(HZ_BOARD_SIMD_AVX2) && !defined(HZ_BOARD_SIMD_NEON) /* the Makefile builds skin_<simd>.c then */
void hz_skin_blend(const float *mats, const hz_hzb_skin_weight_t *w, const float *rest_pos, const float *rest_nrm,
                   uint32_t n, float *pos, float *nrm)
{
    hz_skin_blend_scalar(mats, w, rest_pos, rest_nrm, n, pos, nrm);
}

const char *hz_skin_blend_path(void)
{
    return "scalar";
}
#endif

hz_vec3_t hz_skin_point(const hz_hzb_object_t *o, const hz_hzb_skin_bind_t *binds, uint32_t bind_count,
                        const hz_hzb_joint_t *joints, uint32_t joint_count, const hz_hzb_rigid_key_t *keys,
                        uint32_t key_count, const hz_hzb_skin_weight_t *w, hz_vec3_t p, float t)
{
    float acc[3] = { 0, 0, 0 };
    for (int k = 0; k < 4; k++) {
        uint64_t bi = (uint64_t)o->key_first + w->bind[k];
        if (!w->weight[k] || w->bind[k] >= o->key_count || bi >= bind_count)
            continue;
        const hz_hzb_skin_bind_t *b = &binds[bi];
        if (b->joint >= joint_count)
            continue;
        const hz_hzb_joint_t *j = &joints[b->joint];
        if (j->key_count == 0 || (uint64_t)j->key_first + j->key_count > key_count)
            continue;
        hz_mat4_t jm = hz_rigid_keys_matrix(keys + j->key_first, j->key_count, t);
        float m[16];
        bind_matrix(b, &jm, m);
        float wk = (float)w->weight[k] / 65535.0f;
        for (int r = 0; r < 3; r++)
            acc[r] += wk * (m[r] * p.x + m[4 + r] * p.y + m[8 + r] * p.z + m[12 + r]);
    }
    return hz_v3(acc[0], acc[1], acc[2]);
}

float hz_skin_last_key_time(const hz_hzb_object_t *o, const hz_hzb_skin_bind_t *binds, const hz_hzb_joint_t *joints,
                            const hz_hzb_rigid_key_t *keys)
{
    float last = 0.0f;
    for (uint32_t i = 0; i < o->key_count; i++) {
        const hz_hzb_joint_t *j = &joints[binds[o->key_first + i].joint];
        last = hz_maxf(last, keys[j->key_first + j->key_count - 1].time);
    }
    return last;
}
