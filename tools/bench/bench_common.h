/*
 * bench_common.h — what hzbench's scene groups (tdense, adaptive) share: the median of their rounds, and a baked
 * scene opened into the board pools with its native accel.
 *
 * Contract: hz_bench_median sorts v[0..n) in place (n > 0) and returns the middle value (the mean of the two
 * middle ones for even n). hz_bench_scene_open loads `path` ("builtin" or a .hzb file) and builds the native
 * accel, remembering where the pools were; hz_bench_scene_close releases the accel and resets every pool
 * (scene, accel, frame, threads) to that point, also after a failed open. Header-only (static functions).
 */
#ifndef HZ_BENCH_COMMON_H
#define HZ_BENCH_COMMON_H

#include <stdlib.h>

#include "accel_backend.h"
#include "pools.h"
#include "scenefile.h"

static inline int hz_bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static inline double hz_bench_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, hz_bench_cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

typedef struct hz_bench_scene {
    hz_pools_t *pools;
    hz_scene_t scene;
    hz_accel_t *accel;
    hz_arena_mark_t ms, ma, mf, mt[HZ_MAX_THREADS];
} hz_bench_scene_t;

static inline hz_status_t hz_bench_scene_open(hz_bench_scene_t *b, const char *path, hz_error_t *err)
{
    hz_pools_t *pools = b->pools = hz_pools_get();
    b->accel = NULL;
    b->ms = hz_arena_mark(&pools->scene), b->ma = hz_arena_mark(&pools->accel), b->mf = hz_arena_mark(&pools->frame);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        b->mt[t] = hz_arena_mark(&pools->thread[t]);
    hz_accel_geom_t geom;
    hz_status_t s = hz_scenefile_open(path, pools, &b->scene, err);
    if (s == HZ_OK)
        s = hz_accel_geom_from_scene(&geom, &b->scene, &pools->accel, err);
    if (s == HZ_OK)
        s = hz_accel_backend_build(HZ_ACCEL_NATIVE, &b->accel, &geom, &pools->accel, err);
    return s;
}

/* Gives the frame and thread arenas back to where open left them (between renderers). */
static inline void hz_bench_scene_reset_frames(hz_bench_scene_t *b)
{
    hz_arena_reset(&b->pools->frame, b->mf);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        hz_arena_reset(&b->pools->thread[t], b->mt[t]);
}

static inline void hz_bench_scene_close(hz_bench_scene_t *b)
{
    if (b->accel)
        hz_accel_release(b->accel);
    hz_bench_scene_reset_frames(b);
    hz_arena_reset(&b->pools->accel, b->ma);
    hz_arena_reset(&b->pools->scene, b->ms);
}

#endif
