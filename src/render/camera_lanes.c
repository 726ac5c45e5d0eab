/* The camera's per-ray work in SIMD lanes (src/core/lanes.h), for every camera packet of a frame:
 * hz_view_ray_dirs, the rays' directions, and hz_view_motion_lanes, the motion vectors of a packet's primary
 * hits (render_internal.h). Each lane does the scalar code's operations in its
 * order (no FMA, correctly rounded division and square root), so the results are hz_view_ray_dir's and
 * hz_view_point_motion's bits; test_shade compares them. */
#include "../core/lanes.h"
#include "shade.h"
#include "render_internal.h"

#if HZ_LANES != HZ_SHADE_LANES
#error "camera_lanes.c: a packet must be one group of lanes"
#endif

typedef struct proj {
    hz_lf_t x, y;
    hz_li_t ok;
} proj_t;

static proj_t project(const hz_view_t *v, hz_lf_t px, hz_lf_t py, hz_lf_t pz)
{
    hz_lf_t qx = hz_lf_sub(px, hz_lf_set(v->eye.x)), qy = hz_lf_sub(py, hz_lf_set(v->eye.y));
    hz_lf_t qz = hz_lf_sub(pz, hz_lf_set(v->eye.z));
    hz_lf_t z = hz_lf_add(hz_lf_add(hz_lf_mul(qx, hz_lf_set(v->fwd.x)), hz_lf_mul(qy, hz_lf_set(v->fwd.y))),
                          hz_lf_mul(qz, hz_lf_set(v->fwd.z)));
    hz_lf_t dx = hz_lf_add(hz_lf_add(hz_lf_mul(qx, hz_lf_set(v->proj_x.x)), hz_lf_mul(qy, hz_lf_set(v->proj_x.y))),
                           hz_lf_mul(qz, hz_lf_set(v->proj_x.z)));
    hz_lf_t dy = hz_lf_add(hz_lf_add(hz_lf_mul(qx, hz_lf_set(v->proj_y.x)), hz_lf_mul(qy, hz_lf_set(v->proj_y.y))),
                           hz_lf_mul(qz, hz_lf_set(v->proj_y.z)));
    hz_lf_t iz = hz_lf_div(hz_lf_set(1.0f), z);
    proj_t r;
    r.x = hz_lf_add(hz_lf_mul(dx, iz), hz_lf_set(0.5f * (float)v->width));
    r.y = hz_lf_sub(hz_lf_set(0.5f * (float)v->height), hz_lf_mul(dy, iz));
    r.ok = hz_li_and(hz_lf_gt(z, hz_lf_set(0.0f)), hz_li_and(hz_lf_finite(r.x), hz_lf_finite(r.y)));
    return r;
}

void hz_view_motion_lanes(const hz_view_t *cur, const hz_view_t *prev, const float *const p[3],
                          const float *const pp[3], float *mx, float *my)
{
    proj_t c = project(cur, hz_lf_load(p[0]), hz_lf_load(p[1]), hz_lf_load(p[2]));
    proj_t q = project(prev, hz_lf_load(pp[0]), hz_lf_load(pp[1]), hz_lf_load(pp[2]));
    hz_li_t ok = hz_li_and(c.ok, q.ok);
    const hz_lf_t far = hz_lf_set(HZ_VIEW_MV_FAR);
    hz_lf_store(mx, hz_lf_sel(ok, hz_lf_sub(q.x, c.x), far));
    hz_lf_store(my, hz_lf_sel(ok, hz_lf_sub(q.y, c.y), far));
}

void hz_view_ray_dirs(const hz_view_t *v, const float *x, const float *y, float *dx, float *dy, float *dz)
{
    const hz_lf_t one = hz_lf_set(1.0f), two = hz_lf_set(2.0f);
    const hz_lf_t sx = hz_lf_sub(hz_lf_div(hz_lf_mul(two, hz_lf_load(x)), hz_lf_set((float)v->width)), one);
    const hz_lf_t sy = hz_lf_sub(one, hz_lf_div(hz_lf_mul(two, hz_lf_load(y)), hz_lf_set((float)v->height)));
    hz_lf_t d[3];
    const float fwd[3] = { v->fwd.x, v->fwd.y, v->fwd.z }, right[3] = { v->right.x, v->right.y, v->right.z };
    const float up[3] = { v->up.x, v->up.y, v->up.z };
    for (int k = 0; k < 3; k++)
        d[k] = hz_lf_add(hz_lf_set(fwd[k]),
                         hz_lf_add(hz_lf_mul(hz_lf_set(right[k]), sx), hz_lf_mul(hz_lf_set(up[k]), sy)));
    const hz_lf_t l2 = hz_lf_add(hz_lf_add(hz_lf_mul(d[0], d[0]), hz_lf_mul(d[1], d[1])), hz_lf_mul(d[2], d[2]));
    const hz_lf_t inv = hz_lf_div(one, hz_lf_sqrt(l2));
    hz_lf_store(dx, hz_lf_mul(d[0], inv));
    hz_lf_store(dy, hz_lf_mul(d[1], inv));
    hz_lf_store(dz, hz_lf_mul(d[2], inv));
    /* hz_v3_normalize's other paths: a direction not finite, or a squared length not > 0 or not finite */
    const hz_li_t ok = hz_li_and(hz_li_and(hz_li_and(hz_lf_finite(d[0]), hz_lf_finite(d[1])), hz_lf_finite(d[2])),
                                 hz_li_and(hz_lf_gt(l2, hz_lf_set(0.0f)), hz_lf_finite(l2)));
    for (unsigned m = ~hz_li_bits(ok) & ((1u << HZ_LANES) - 1u); m; m &= m - 1u) {
        const unsigned i = (unsigned)__builtin_ctz(m);
        const hz_vec3_t r = hz_view_ray_dir(v, x[i], y[i]);
        dx[i] = r.x, dy[i] = r.y, dz[i] = r.z;
    }
}
