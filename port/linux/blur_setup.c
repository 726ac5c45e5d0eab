/* Pose keys and the accel over them (see blur_setup.h). */
#include "blur_setup.h"

#include "accel_backend.h"
#include "hz/config.h"
#if HZ_HAVE_EMBREE
#include "embree_accel.h"
#endif

hz_status_t hz_blur_build(const hz_scene_t *scene, hz_render_opts_t *opts, hz_accel_backend_t backend,
                          hz_accel_blur_t blur, hz_pools_t *pools, hz_posekeys_t *keys, hz_accel_t **accel,
                          hz_error_t *err)
{
    hz_accel_config_t cfg;
    hz_accel_config_default(&cfg);
    return hz_blur_build_cfg(scene, opts, backend, blur, &cfg, pools, keys, accel, err);
}

hz_status_t hz_blur_build_cfg(const hz_scene_t *scene, hz_render_opts_t *opts, hz_accel_backend_t backend,
                              hz_accel_blur_t blur, const hz_accel_config_t *base, hz_pools_t *pools,
                              hz_posekeys_t *keys, hz_accel_t **accel, hz_error_t *err)
{
    hz_accel_geom_t geom;
    opts->keys = NULL;
    hz_status_t s = hz_accel_geom_from_scene(&geom, scene, &pools->accel, err);
    if (s != HZ_OK)
        return s;
    hz_render_plan_t plan;
    if (opts->shutter > 0.0f && (s = hz_render_plan(scene, opts, &plan, err)) != HZ_OK)
        return s;
    if (!HZ_FEATURE_MOTION || opts->shutter <= 0.0f || plan.time_keys < 2) /* no keys: a build without motion */
        return hz_accel_backend_build_cfg(backend, accel, &geom, base, &pools->accel, err);
    if ((s = hz_posekeys_init(keys, scene, plan.time_keys, &pools->scene, err)) != HZ_OK)
        return s;
    /* A first interval (frame 0's shutter) so the build sees real motion; every frame re-poses and refits. */
    float half = 0.5f * opts->shutter / (float)opts->frame_hz;
    hz_posekeys_eval_ns(keys, scene, scene->time_ns, -half, half);
    hz_posekeys_geom(keys, &geom);
    hz_accel_config_t cfg = *base;
    cfg.blur = blur;
    if (backend == HZ_ACCEL_NATIVE)
        s = hz_accel_build_native(accel, &geom, &cfg, &pools->accel, err);
    else
#if HZ_HAVE_EMBREE
        s = hz_accel_build_embree(accel, &geom, &cfg, NULL, &pools->accel, err);
#else
        s = hz_accel_backend_build_cfg(backend, accel, &geom, &cfg, &pools->accel, err);
#endif
    if (s == HZ_OK)
        opts->keys = keys;
    return s;
}
