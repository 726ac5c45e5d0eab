/*
 * blur_setup.h — motion blur for the Linux port's commands, tools and tests: the pose keys a shutter needs and
 * the accel built over them (hz/posekeys.h, hz/render.h "Motion blur").
 *
 * Contract: hz_blur_build(scene, opts, backend, blur, pools, keys, accel, err) builds the scene's geometry view
 * (hz_accel_geom_from_scene, in pools->accel) and the accel. With opts->shutter > 0 on a moving scene it first
 * takes the pose keys hz_render_plan asks for from pools->scene (HZ_E_NO_MEMORY naming the arena when they do
 * not fit), poses them for a first interval, points the view at them and sets opts->keys = keys; the native
 * backend builds the motion BVH `blur` (msbvh, interp, swept), Embree its own motion blur. Otherwise (no
 * shutter, static scene) it builds exactly what hz_accel_backend_build builds and leaves opts->keys NULL.
 * The keys and accel live as long as the pools' marks they were taken above. hz_blur_build_cfg starts from
 * `base` (progress callback, build options) instead of hz_accel_config_default.
 */
#ifndef HZ_PORT_BLUR_SETUP_H
#define HZ_PORT_BLUR_SETUP_H

#include "hz/accel.h"
#include "hz/posekeys.h"
#include "hz/render.h"
#include "pools.h"

hz_status_t hz_blur_build(const hz_scene_t *scene, hz_render_opts_t *opts, hz_accel_backend_t backend,
                          hz_accel_blur_t blur, hz_pools_t *pools, hz_posekeys_t *keys, hz_accel_t **accel,
                          hz_error_t *err);
hz_status_t hz_blur_build_cfg(const hz_scene_t *scene, hz_render_opts_t *opts, hz_accel_backend_t backend,
                              hz_accel_blur_t blur, const hz_accel_config_t *base, hz_pools_t *pools,
                              hz_posekeys_t *keys, hz_accel_t **accel, hz_error_t *err);

#endif
