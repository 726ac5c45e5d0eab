/* Static arenas sized by the board (see pools.h). */
#include "pools.h"

#include "hz/base.h"

/* 64-byte alignment: cache lines, and the widest SIMD load (AVX-512 would need it; AVX2 needs 32). */
static uint8_t scene_buf[HZ_ARENA_SCENE_BYTES] HZ_ALIGNED(64);
static uint8_t accel_buf[HZ_ARENA_ACCEL_BYTES] HZ_ALIGNED(64);
static uint8_t frame_buf[HZ_ARENA_FRAME_BYTES] HZ_ALIGNED(64);
static uint8_t thread_buf[HZ_MAX_THREADS][HZ_ARENA_THREAD_BYTES] HZ_ALIGNED(64);

static hz_pools_t pools;
static int pools_ready;

hz_status_t hz_pools_init(hz_pools_t *p)
{
    hz_status_t s = hz_arena_init(&p->scene, "scene", scene_buf, sizeof scene_buf);
    if (s == HZ_OK)
        s = hz_arena_init(&p->accel, "accel", accel_buf, sizeof accel_buf);
    if (s == HZ_OK)
        s = hz_arena_init(&p->frame, "frame", frame_buf, sizeof frame_buf);
    for (int i = 0; s == HZ_OK && i < HZ_MAX_THREADS; i++)
        s = hz_arena_init(&p->thread[i], "thread", thread_buf[i], sizeof thread_buf[i]);
    return s;
}

hz_pools_t *hz_pools_get(void)
{
    if (!pools_ready) {
        if (hz_pools_init(&pools) != HZ_OK)
            return NULL;
        pools_ready = 1;
    }
    return &pools;
}
