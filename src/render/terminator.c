/* Shadow-ray start on smooth-shaded facets (see src/render/terminator.h). */
#include "terminator.h"

static hz_vec3_t vec4_at(const float *arr, uint32_t i)
{
    return hz_v3(arr[(size_t)i * 4], arr[(size_t)i * 4 + 1], arr[(size_t)i * 4 + 2]);
}

float hz_terminator_skip(const hz_scene_t *s, uint32_t prim, hz_vec3_t ng)
{
    if (!s->nrm)
        return 0.0f;
    const uint32_t *t = s->tri + (size_t)prim * 3;
    hz_vec3_t a = vec4_at(s->pos, t[0]), b = vec4_at(s->pos, t[1]), c = vec4_at(s->pos, t[2]);
    float e = hz_maxf(hz_v3_len(hz_v3_sub(b, a)), hz_maxf(hz_v3_len(hz_v3_sub(c, b)), hz_v3_len(hz_v3_sub(a, c))));
    /* The least |cos| between ng and a vertex normal: orientation does not matter (normals may face either
     * side of a facet whose winding disagrees with them). */
    float cmin = 1.0f;
    for (int i = 0; i < 3; i++) {
        hz_vec3_t n = vec4_at(s->nrm, t[i]);
        float len = hz_v3_len(n);
        if (!(len > 0.0f))
            continue;
        float cs = hz_absf(hz_v3_dot(n, ng)) / len;
        cmin = hz_minf(cmin, cs);
    }
    /* Normals within 0.8 degrees of ng are the facet's own, up to rounding: flat shading. */
    if (!(cmin < 0.9999f) || !(e > 0.0f) || !(e < 3.0e38f))
        return 0.0f;
    float sn = hz_sqrtf(1.0f - cmin * cmin);
    return hz_minf(0.5f * e * sn, 0.25f * e);
}
