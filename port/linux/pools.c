/* The board's arenas (see pools.h): static buffers, or with HZ_POOLS_RESERVE one reservation of address space. */
#define _DEFAULT_SOURCE 1 /* MAP_ANONYMOUS, MAP_NORESERVE; before any header */
#include "pools.h"

#include "hz/base.h"

#if HZ_POOLS_RESERVE
#include <sys/mman.h>
#endif

/* Every arena's bytes together: what a reservation asks for. */
#define ARENAS_BYTES ((size_t)HZ_ARENA_SCENE_BYTES + HZ_ARENA_ACCEL_BYTES + HZ_ARENA_FRAME_BYTES + \
                      (size_t)HZ_MAX_THREADS * HZ_ARENA_THREAD_BYTES)

#if HZ_POOLS_RESERVE
/* One private anonymous mapping for all arenas, without commitment (MAP_NORESERVE): the kernel's default
 * (heuristic) overcommit refuses a writable private mapping, a .bss included, larger than the machine's RAM and
 * swap, so host arenas sized for the largest bench scenes would stop the program from starting on a smaller
 * machine. Pages are zero until written and cost RAM only once touched, as untouched .bss does. */
static uint8_t *reserved;

static uint8_t *reserve(void)
{
    if (!reserved) {
        void *p = mmap(NULL, ARENAS_BYTES, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
        if (p != MAP_FAILED)
            reserved = p; /* page-aligned, so every arena below starts 64-byte aligned (the sizes are MiB) */
    }
    return reserved;
}
#else
/* 64-byte alignment: cache lines, and the widest SIMD load (AVX-512 would need it; AVX2 needs 32). */
static uint8_t scene_buf[HZ_ARENA_SCENE_BYTES] HZ_ALIGNED(64);
static uint8_t accel_buf[HZ_ARENA_ACCEL_BYTES] HZ_ALIGNED(64);
static uint8_t frame_buf[HZ_ARENA_FRAME_BYTES] HZ_ALIGNED(64);
static uint8_t thread_buf[HZ_MAX_THREADS][HZ_ARENA_THREAD_BYTES] HZ_ALIGNED(64);
#endif

static hz_pools_t pools;
static int pools_ready;

hz_status_t hz_pools_init(hz_pools_t *p)
{
#if HZ_POOLS_RESERVE
    uint8_t *scene_buf = reserve();
    if (!scene_buf)
        return HZ_E_NO_MEMORY;
    uint8_t *accel_buf = scene_buf + HZ_ARENA_SCENE_BYTES, *frame_buf = accel_buf + HZ_ARENA_ACCEL_BYTES;
    uint8_t *threads = frame_buf + HZ_ARENA_FRAME_BYTES;
#else
    uint8_t *threads = &thread_buf[0][0];
#endif
    hz_status_t s = hz_arena_init(&p->scene, "scene", scene_buf, HZ_ARENA_SCENE_BYTES);
    if (s == HZ_OK)
        s = hz_arena_init(&p->accel, "accel", accel_buf, HZ_ARENA_ACCEL_BYTES);
    if (s == HZ_OK)
        s = hz_arena_init(&p->frame, "frame", frame_buf, HZ_ARENA_FRAME_BYTES);
    for (int i = 0; s == HZ_OK && i < HZ_MAX_THREADS; i++)
        s = hz_arena_init(&p->thread[i], "thread", threads + (size_t)i * HZ_ARENA_THREAD_BYTES,
                          HZ_ARENA_THREAD_BYTES);
    return s;
}

hz_status_t hz_pools_error(hz_error_t *err, const char *who)
{
    const unsigned long long mib = (unsigned long long)(ARENAS_BYTES >> 20);
#if HZ_POOLS_RESERVE
    return hz_error_set(err, HZ_E_NO_MEMORY,
                        "%s: could not reserve %llu MiB of address space for the board's arenas (a limit on virtual "
                        "memory, such as ulimit -v?)", who, mib);
#else
    return hz_error_set(err, HZ_E_INTERNAL, "%s: could not set up the board's static arenas (%llu MiB)", who, mib);
#endif
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
