/*
 * bench_scene.h — a baked scene and its native accel opened into the board pools for one benchmark group, and
 * the pools given back as they were afterwards (shared by the tdense and transparency groups).
 *
 * Contract: hz_bench_scene_open marks every pool, loads `path` ("builtin" or a .hzb file) and builds the native
 * BVH; on failure err is set and close must still be called. hz_bench_scene_load does the same without the
 * BVH (b->accel stays NULL). hz_bench_scene_close releases the accel and resets
 * the scene, accel, frame and thread arenas to the marks (renderers created from them in between are gone);
 * hz_bench_scene_reset_frames resets only the frame and thread arenas.
 */
#ifndef HZ_BENCH_SCENE_H
#define HZ_BENCH_SCENE_H

#include "hz/accel.h"
#include "hz/scene.h"
#include "pools.h"

typedef struct hz_bench_scene {
    hz_pools_t *pools;
    hz_arena_mark_t ms, ma, mf, mt[HZ_MAX_THREADS];
    hz_scene_t scene;
    hz_accel_t *accel;
} hz_bench_scene_t;

hz_status_t hz_bench_scene_open(hz_bench_scene_t *b, const char *path, hz_error_t *err);
hz_status_t hz_bench_scene_load(hz_bench_scene_t *b, const char *path, hz_error_t *err);
void hz_bench_scene_close(hz_bench_scene_t *b);
/* Gives the frame and thread arenas back to where open left them (between renderers). */
void hz_bench_scene_reset_frames(hz_bench_scene_t *b);

#endif
