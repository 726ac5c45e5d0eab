/*
 * threads.h — the static worker pool: hzrt's only threads, shared by the renderer, accel builds and tools.
 *
 * Contract:
 *  - hz_threads_start(n, err) starts n - 1 workers (n total participants, the calling thread being thread 0);
 *    n = 0 means one per online CPU. n is clamped to [1, HZ_MAX_THREADS]. Thread creation is the pool's only
 *    allocation (the C library's thread stacks); nothing allocates after start returns.
 *    Starting a started pool is refused (HZ_E_INVALID_ARG); a failed start stops what it began.
 *  - hz_threads_run(fn, user, items) calls fn(user, item, thread) exactly once for every item in
 *    [0, items) and returns when all calls have returned. Items are handed out one at a time from an atomic
 *    counter, so which thread runs an item varies from run to run: fn must write its results by item (and may
 *    use per-thread scratch indexed by `thread`, e.g. hz_pools_get()->thread[thread]), so results do not
 *    depend on the thread count. `thread` is in [0, hz_threads_count()). The caller's thread takes items too.
 *    run is called from thread 0 only, never from inside fn. Without a started pool it runs everything on
 *    the calling thread (thread 0).
 *  - Workers wait on a condition variable between runs (after a short spin), so an idle pool costs no CPU.
 *  - hz_threads_stop() joins the workers; the pool can be started again.
 *  - hz_threads_convert(convert, ctx, src, ..., w, h) is hz_threads_run over a w x h frame's rows in bands of
 *    HZ_THREADS_BAND_ROWS: convert(ctx, ...) once for every band, with src and dst advanced to its first row and
 *    h its row count (strides in bytes). For conversions whose rows are independent (the sRGB encode, a
 *    display's pixel format), so their bytes do not depend on which thread converts which band; the same rule
 *    as run (thread 0 only, not from inside convert).
 *  - hz_threads_accel_hook(cfg) points an accel config's task hook (cfg->run, see hz/accel.h) at this pool, with
 *    run_threads = hz_threads_count(): a native build with it runs on every thread of the pool (call it after
 *    start; builds from thread 0 only).
 */
#ifndef HZ_PORT_THREADS_H
#define HZ_PORT_THREADS_H

#include <stddef.h>
#include <stdint.h>

#include "hz/config.h"
#include "hz/status.h"

typedef void (*hz_threads_fn)(void *user, uint32_t item, int thread);

/* One spin-wait step (the CPU's pause/yield hint), for loops that wait on another thread's atomic. */
static inline void hz_threads_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#elif defined(__aarch64__)
    __asm__ __volatile__("yield");
#endif
}

hz_status_t hz_threads_start(int n, hz_error_t *err);
void hz_threads_run(hz_threads_fn fn, void *user, uint32_t items);
int hz_threads_count(void);
void hz_threads_stop(void);

/* Rows per band: a few rows of a frame are tens of kilobytes, enough to outweigh handing a band out. */
#define HZ_THREADS_BAND_ROWS 16u
typedef void (*hz_threads_convert_fn)(const void *ctx, const uint8_t *src, size_t src_stride, uint8_t *dst,
                                      size_t dst_stride, int w, int h);
void hz_threads_convert(hz_threads_convert_fn convert, const void *ctx, const uint8_t *src, size_t src_stride,
                        uint8_t *dst, size_t dst_stride, int w, int h);

struct hz_accel_config;
void hz_threads_accel_hook(struct hz_accel_config *cfg);

#endif
