/*
 * accel_scenes.h — baked scenes for the accel tests: `make test` bakes ../shared/scenes first and exports
 * HZ_SCENES_DIR. Without that variable (a test binary run by hand) the scene tests skip and say so; with it, a
 * missing scene fails. Header-only; include after accel_fixture.h, link the port library.
 */
#ifndef HZ_TEST_ACCEL_SCENES_H
#define HZ_TEST_ACCEL_SCENES_H

#include <stdlib.h>

#include "hz/scene.h"
#include "pools.h"
#include "scenefile.h"

/* Loads <HZ_SCENES_DIR>/<name>.hzb into the process pools (reset first). false: no HZ_SCENES_DIR (skip). */
static __attribute__((unused)) bool fx_scene_load(const char *name, hz_scene_t *sc, hz_accel_geom_t *g)
{
    const char *dir = getenv("HZ_SCENES_DIR");
    if (!dir || !*dir) {
        print_message("HZ_SCENES_DIR is not set (run through `make test`): scene %s skipped\n", name);
        return false;
    }
    hz_pools_t *p = hz_pools_get();
    assert_non_null(p);
    assert_int_equal(hz_pools_init(p), HZ_OK);
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.hzb", dir, name);
    hz_error_t err;
    hz_status_t s = hz_scenefile_open(path, p, sc, &err);
    if (s != HZ_OK)
        print_message("%s\n", err.msg);
    assert_int_equal(s, HZ_OK);
    assert_int_equal(hz_accel_geom_from_scene(g, sc, &p->scene, &err), HZ_OK);
    return true;
}

/* n0 camera rays (the scene's camera, sqrt(n0) x sqrt(n0) pixels) then random rays through the bounds. */
static __attribute__((unused)) void fx_scene_rays(const hz_scene_t *sc, hz_rayhit_t *out, uint32_t n0, uint32_t n,
                                                  uint64_t seed)
{
    fx_bounds_t b;
    for (int k = 0; k < 3; k++)
        b.lo[k] = sc->header->bounds_min[k], b.hi[k] = sc->header->bounds_max[k];
    fx_random_rays(out, n, b, seed);
    hz_camera_t cam = hz_scene_camera(sc, 0.0f);
    hz_vec3_t f = hz_v3_normalize(hz_v3_sub(cam.target, cam.eye));
    hz_vec3_t r = hz_v3_normalize(hz_v3_cross(f, cam.up)), u = hz_v3_cross(r, f);
    const float th = hz_tanf(0.5f * cam.fov_y);
    uint32_t side = 1;
    while ((side + 1) * (side + 1) <= n0)
        side++;
    for (uint32_t y = 0; y < side; y++)
        for (uint32_t x = 0; x < side; x++) {
            float sx = (((float)x + 0.5f) / (float)side * 2.0f - 1.0f) * th;
            float sy = (1.0f - ((float)y + 0.5f) / (float)side * 2.0f) * th;
            hz_vec3_t d = hz_v3_add(f, hz_v3_add(hz_v3_scale(r, sx), hz_v3_scale(u, sy)));
            float o[3] = { cam.eye.x, cam.eye.y, cam.eye.z }, dd[3] = { d.x, d.y, d.z };
            fx_set_ray(&out[y * side + x], o, dd, 0.0f, INFINITY, y * side + x);
        }
}

#endif
