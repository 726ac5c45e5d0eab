/* A scene for a benchmark group (see bench_scene.h). */
#include "bench_scene.h"

#include <string.h>

#include "accel_backend.h"
#include "scenefile.h"

hz_status_t hz_bench_scene_load(hz_bench_scene_t *b, const char *path, hz_error_t *err)
{
    memset(b, 0, sizeof *b);
    hz_pools_t *pools = b->pools = hz_pools_get();
    b->ms = hz_arena_mark(&pools->scene), b->ma = hz_arena_mark(&pools->accel), b->mf = hz_arena_mark(&pools->frame);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        b->mt[t] = hz_arena_mark(&pools->thread[t]);
    return hz_scenefile_open(path, pools, &b->scene, err);
}

hz_status_t hz_bench_scene_open(hz_bench_scene_t *b, const char *path, hz_error_t *err)
{
    hz_accel_geom_t geom;
    hz_status_t s = hz_bench_scene_load(b, path, err);
    if (s == HZ_OK)
        s = hz_accel_geom_from_scene(&geom, &b->scene, &b->pools->accel, err);
    if (s == HZ_OK)
        s = hz_accel_backend_build(HZ_ACCEL_NATIVE, &b->accel, &geom, &b->pools->accel, err);
    return s;
}

void hz_bench_scene_reset_frames(hz_bench_scene_t *b)
{
    hz_arena_reset(&b->pools->frame, b->mf);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        hz_arena_reset(&b->pools->thread[t], b->mt[t]);
}

void hz_bench_scene_close(hz_bench_scene_t *b)
{
    if (b->accel)
        hz_accel_release(b->accel);
    b->accel = NULL;
    hz_bench_scene_reset_frames(b);
    hz_arena_reset(&b->pools->accel, b->ma);
    hz_arena_reset(&b->pools->scene, b->ms);
}
