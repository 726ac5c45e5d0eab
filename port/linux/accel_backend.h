/*
 * accel_backend.h — picks the accel backend for the Linux port: the native BVH (every board) or Embree (boards
 * with `embree` in BOARD_ACCEL, i.e. host builds).
 *
 * Contract: hz_accel_backend_build builds from `geom` with the backend's defaults; asking for Embree on a
 * build without it is HZ_E_UNSUPPORTED naming the board. The caller releases the accel (hz_accel_release).
 */
#ifndef HZ_PORT_ACCEL_BACKEND_H
#define HZ_PORT_ACCEL_BACKEND_H

#include "hz/accel.h"

hz_status_t hz_accel_backend_build(hz_accel_backend_t backend, hz_accel_t **out, const hz_accel_geom_t *geom,
                                   hz_arena_t *arena, hz_error_t *err);
/* The same with a configuration for the native build (NULL: defaults; its progress callback is used). */
hz_status_t hz_accel_backend_build_cfg(hz_accel_backend_t backend, hz_accel_t **out, const hz_accel_geom_t *geom,
                                       const hz_accel_config_t *cfg, hz_arena_t *arena, hz_error_t *err);
const char *hz_accel_backend_name(hz_accel_backend_t backend);

#endif
