/* hz_view_still_motion_lanes (render_internal.h) in SIMD lanes (src/core/lanes.h): the motion vectors of a
 * packet's primary hits on geometry that does not move, which shade_packet needs for every hit of a tdense or
 * TAA frame. Each lane does hz_view_project's operations in its order (no FMA, correctly rounded division), so
 * the results are hz_view_point_motion's bits; test_shade compares the two. */
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

void hz_view_still_motion_lanes(const hz_view_t *cur, const hz_view_t *prev, const float *px, const float *py,
                                const float *pz, float *mx, float *my)
{
    hz_lf_t x = hz_lf_load(px), y = hz_lf_load(py), z = hz_lf_load(pz);
    proj_t c = project(cur, x, y, z), p = project(prev, x, y, z);
    hz_li_t ok = hz_li_and(c.ok, p.ok);
    const hz_lf_t far = hz_lf_set(HZ_VIEW_MV_FAR);
    hz_lf_store(mx, hz_lf_sel(ok, hz_lf_sub(p.x, c.x), far));
    hz_lf_store(my, hz_lf_sel(ok, hz_lf_sub(p.y, c.y), far));
}
