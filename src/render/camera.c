/* Pinhole camera: basis, ray directions and the matching projection for motion vectors. Ray generation and
 * projection use the same basis, so a point on a pixel's ray projects back to that pixel: static content
 * under a still camera gets motion vectors of exactly zero. */
#include "shade.h"
#include "render_internal.h"

void hz_view_setup(hz_view_t *v, const hz_camera_t *cam, uint32_t width, uint32_t height)
{
    float aspect = (float)width / (float)height;
    float th = hz_tanf(0.5f * cam->fov_y);
    hz_mat4_t cam_to_world = hz_mat4_look_at(cam->eye, cam->target, cam->up);
    v->eye = cam->eye;
    v->right = hz_v3_scale(hz_v3(cam_to_world.m[0], cam_to_world.m[1], cam_to_world.m[2]), th * aspect);
    v->up = hz_v3_scale(hz_v3(cam_to_world.m[4], cam_to_world.m[5], cam_to_world.m[6]), th);
    v->fwd = hz_v3(-cam_to_world.m[8], -cam_to_world.m[9], -cam_to_world.m[10]);
    v->width = width;
    v->height = height;
    v->spread = 2.0f * th / (float)height;
    v->proj_x = hz_v3_scale(v->right, 0.5f * (float)width / hz_v3_dot(v->right, v->right));
    v->proj_y = hz_v3_scale(v->up, 0.5f * (float)height / hz_v3_dot(v->up, v->up));
}

void hz_view_footprint(const hz_view_t *v, hz_shade_footprint_t *fp)
{
    const float sx = 2.0f / (float)v->width, sy = -2.0f / (float)v->height, ff = hz_v3_dot(v->fwd, v->fwd);
    fp->ex[0] = v->right.x * sx, fp->ex[1] = v->right.y * sx, fp->ex[2] = v->right.z * sx;
    fp->ey[0] = v->up.x * sy, fp->ey[1] = v->up.y * sy, fp->ey[2] = v->up.z * sy;
    fp->f[0] = v->fwd.x / ff, fp->f[1] = v->fwd.y / ff, fp->f[2] = v->fwd.z / ff;
}

bool hz_view_project(const hz_view_t *v, hz_vec3_t p, float *px, float *py)
{
    /* Straight from the basis, so it inverts hz_view_ray_dir: sx = dot(p - eye, right) / |right|^2 / depth;
     * the constant factors are folded into proj_x and proj_y at setup, leaving one division per point (this
     * runs twice for every primary hit). */
    hz_vec3_t q = hz_v3_sub(p, v->eye);
    float z = hz_v3_dot(q, v->fwd);
    if (!(z > 0.0f))
        return false;
    float iz = 1.0f / z;
    *px = hz_v3_dot(q, v->proj_x) * iz + 0.5f * (float)v->width;
    *py = 0.5f * (float)v->height - hz_v3_dot(q, v->proj_y) * iz;
    return hz_isfinitef(*px) && hz_isfinitef(*py);
}

void hz_view_point_motion(const hz_view_t *cur, const hz_view_t *prev, const hz_vec3_t *p, const hz_vec3_t *pp,
                          float out[2])
{
    float cx, cy, px, py;
    if (hz_view_project(cur, *p, &cx, &cy) && hz_view_project(prev, *pp, &px, &py)) {
        out[0] = px - cx;
        out[1] = py - cy;
    } else {
        out[0] = out[1] = HZ_VIEW_MV_FAR;
    }
}

#if !defined(HZ_BOARD_SIMD_AVX2) && !defined(HZ_BOARD_SIMD_NEON) /* else camera_lanes.c */
void hz_view_ray_dirs(const hz_view_t *v, const float *x, const float *y, float *dx, float *dy, float *dz)
{
    for (uint32_t i = 0; i < HZ_SHADE_LANES; i++) {
        const hz_vec3_t d = hz_view_ray_dir(v, x[i], y[i]);
        dx[i] = d.x, dy[i] = d.y, dz[i] = d.z;
    }
}

void hz_view_motion_lanes(const hz_view_t *cur, const hz_view_t *prev, const float *const p[3],
                          const float *const pp[3], float *mx, float *my)
{
    for (uint32_t i = 0; i < HZ_SHADE_LANES; i++) {
        float m[2];
        hz_vec3_t a = hz_v3(p[0][i], p[1][i], p[2][i]), b = hz_v3(pp[0][i], pp[1][i], pp[2][i]);
        hz_view_point_motion(cur, prev, &a, &b, m);
        mx[i] = m[0], my[i] = m[1];
    }
}
#endif
