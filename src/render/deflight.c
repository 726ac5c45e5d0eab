/* The default key light of a scene without lights (see src/render/deflight.h). */
#include "deflight.h"

#include "hz/base.h"
#include "hz/vmath.h"

void hz_deflight_place(const hz_scene_t *scene, hz_light_t *out)
{
    hz_memset(out, 0, sizeof *out);
    hz_camera_t cam = hz_scene_camera(scene, 0.0f);
    hz_vec3_t f = hz_v3_sub(cam.target, cam.eye);
    float d = hz_v3_len(f);
    hz_vec3_t p = cam.eye;
    if (d > 0.0f && d < 3.0e38f) {
        f = hz_v3_scale(f, 1.0f / d);
        hz_vec3_t right = hz_v3_cross(f, cam.up);
        float rl = hz_v3_len(right);
        right = rl > 0.0f ? hz_v3_scale(right, 1.0f / rl) : hz_v3(1.0f, 0.0f, 0.0f);
        hz_vec3_t up = hz_v3_cross(right, f);
        p = hz_v3_add(p, hz_v3_add(hz_v3_scale(up, 0.3f * d), hz_v3_scale(right, -0.2f * d)));
    }
    if (!(p.x == p.x && p.y == p.y && p.z == p.z))
        p = hz_v3(0.0f, 0.0f, 0.0f);
    out->position[0] = p.x, out->position[1] = p.y, out->position[2] = p.z;
    out->color[0] = out->color[1] = out->color[2] = 0.8f * HZ_PI;
    out->falloff = HZ_FALLOFF_NONE;
}
