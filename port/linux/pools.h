/*
 * pools.h — the board's fixed memory: one arena per role, zero-initialised, sized by board.h (HZ_ARENA_*_BYTES):
 * static buffers, or where the board sets HZ_POOLS_RESERVE (host builds) one reservation of address space made
 * on first use. This is the only memory the renderer uses after start-up.
 *
 * Contract: hz_pools_init() sets every arena up over its buffer and may be called again to start over (all
 * arenas empty, high-water marks cleared). hz_pools_get() returns the process-wide pools (initialised on first
 * use; call it from the main thread before workers start), or NULL when they cannot be had (a reservation refused,
 * e.g. under a virtual-memory limit); hz_pools_error() then says why, prefixed with `who`, and returns the status
 * (HZ_E_NO_MEMORY for a refused reservation). Thread arenas: thread[i] for worker i < HZ_MAX_THREADS.
 */
#ifndef HZ_PORT_POOLS_H
#define HZ_PORT_POOLS_H

#include "hz/arena.h"
#include "hz/config.h"

typedef struct hz_pools {
    hz_arena_t scene;
    hz_arena_t accel;
    hz_arena_t frame;
    hz_arena_t thread[HZ_MAX_THREADS];
} hz_pools_t;

hz_status_t hz_pools_init(hz_pools_t *p);
hz_pools_t *hz_pools_get(void);
hz_status_t hz_pools_error(hz_error_t *err, const char *who);

#endif
