/* The static worker pool (see threads.h): pthreads, a generation counter to start runs, an atomic item
 * counter to share them out, and a count of finished workers to end them. */
#include "threads.h"

#include "hz/accel.h"

#include <pthread.h>
#include <string.h>
#include <unistd.h>

#define SPIN_ROUNDS 256 /* short: on a loaded or oversubscribed machine spinning steals the workers' time */

static pthread_t workers[HZ_MAX_THREADS];
static int thread_count = 1; /* participants, including the caller */
static int started;

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t wake = PTHREAD_COND_INITIALIZER;
static pthread_cond_t done = PTHREAD_COND_INITIALIZER;

/* The current run; written by thread 0 under `lock` before the generation changes. */
static hz_threads_fn run_fn;
static void *run_user;
static uint32_t run_items;
static uint32_t next_item;    /* atomic */
static unsigned generation;   /* atomic; odd values never used: just a counter */
static int workers_busy;      /* atomic: workers that have not finished the current run */
static int quitting;


static void take_items(int thread)
{
    for (;;) {
        uint32_t i = __atomic_fetch_add(&next_item, 1u, __ATOMIC_RELAXED);
        if (i >= run_items)
            break;
        run_fn(run_user, i, thread);
    }
}

static void *worker_main(void *arg)
{
    const int thread = (int)(intptr_t)arg;
    unsigned seen = 0;
    for (;;) {
        unsigned g = __atomic_load_n(&generation, __ATOMIC_ACQUIRE);
        for (int spin = 0; g == seen && spin < SPIN_ROUNDS; spin++) {
            hz_threads_relax();
            g = __atomic_load_n(&generation, __ATOMIC_ACQUIRE);
        }
        if (g == seen) {
            pthread_mutex_lock(&lock);
            while ((g = __atomic_load_n(&generation, __ATOMIC_ACQUIRE)) == seen && !quitting)
                pthread_cond_wait(&wake, &lock);
            pthread_mutex_unlock(&lock);
        }
        if (__atomic_load_n(&quitting, __ATOMIC_ACQUIRE))
            return NULL;
        seen = g;
        take_items(thread);
        if (__atomic_sub_fetch(&workers_busy, 1, __ATOMIC_ACQ_REL) == 0) {
            pthread_mutex_lock(&lock);
            pthread_cond_signal(&done);
            pthread_mutex_unlock(&lock);
        }
    }
}

hz_status_t hz_threads_start(int n, hz_error_t *err)
{
    if (started)
        return hz_error_set(err, HZ_E_INVALID_ARG, "threads: the pool is already running");
    if (n <= 0) {
        long c = sysconf(_SC_NPROCESSORS_ONLN);
        n = c > 0 ? (int)c : 1;
    }
    if (n > HZ_MAX_THREADS)
        n = HZ_MAX_THREADS;
    quitting = 0;
    generation = 0;
    for (int i = 1; i < n; i++) {
        int e = pthread_create(&workers[i], NULL, worker_main, (void *)(intptr_t)i);
        if (e != 0) {
            thread_count = i;
            started = 1;
            hz_threads_stop();
            return hz_error_set(err, HZ_E_DEVICE, "threads: cannot start worker %d of %d: %s", i, n - 1,
                                strerror(e));
        }
    }
    thread_count = n;
    started = 1;
    return HZ_OK;
}

void hz_threads_run(hz_threads_fn fn, void *user, uint32_t items)
{
    if (items == 0)
        return;
    if (!started || thread_count == 1) {
        for (uint32_t i = 0; i < items; i++)
            fn(user, i, 0);
        return;
    }
    pthread_mutex_lock(&lock);
    run_fn = fn;
    run_user = user;
    run_items = items;
    __atomic_store_n(&next_item, 0u, __ATOMIC_RELAXED);
    __atomic_store_n(&workers_busy, thread_count - 1, __ATOMIC_RELAXED);
    __atomic_add_fetch(&generation, 1u, __ATOMIC_RELEASE);
    pthread_cond_broadcast(&wake);
    pthread_mutex_unlock(&lock);
    take_items(0);
    for (int spin = 0; __atomic_load_n(&workers_busy, __ATOMIC_ACQUIRE) != 0 && spin < SPIN_ROUNDS; spin++)
        hz_threads_relax();
    if (__atomic_load_n(&workers_busy, __ATOMIC_ACQUIRE) != 0) {
        pthread_mutex_lock(&lock);
        while (__atomic_load_n(&workers_busy, __ATOMIC_ACQUIRE) != 0)
            pthread_cond_wait(&done, &lock);
        pthread_mutex_unlock(&lock);
    }
}

typedef struct convert_job {
    hz_threads_convert_fn convert;
    const void *ctx;
    const uint8_t *src;
    size_t src_stride;
    uint8_t *dst;
    size_t dst_stride;
    int w, h;
} convert_job_t;

static void convert_band(void *user, uint32_t item, int thread)
{
    (void)thread;
    const convert_job_t *j = user;
    const int y0 = (int)(item * HZ_THREADS_BAND_ROWS), rows = j->h - y0;
    j->convert(j->ctx, j->src + (size_t)y0 * j->src_stride, j->src_stride, j->dst + (size_t)y0 * j->dst_stride,
               j->dst_stride, j->w, rows < (int)HZ_THREADS_BAND_ROWS ? rows : (int)HZ_THREADS_BAND_ROWS);
}

void hz_threads_convert(hz_threads_convert_fn convert, const void *ctx, const uint8_t *src, size_t src_stride,
                        uint8_t *dst, size_t dst_stride, int w, int h)
{
    if (h <= 0)
        return;
    convert_job_t j = { convert, ctx, src, src_stride, dst, dst_stride, w, h };
    hz_threads_run(convert_band, &j, (uint32_t)h / HZ_THREADS_BAND_ROWS + ((uint32_t)h % HZ_THREADS_BAND_ROWS != 0));
}

int hz_threads_count(void)
{
    return started ? thread_count : 1;
}

void hz_threads_stop(void)
{
    if (!started)
        return;
    pthread_mutex_lock(&lock);
    __atomic_store_n(&quitting, 1, __ATOMIC_RELEASE);
    pthread_cond_broadcast(&wake);
    pthread_mutex_unlock(&lock);
    for (int i = 1; i < thread_count; i++)
        pthread_join(workers[i], NULL);
    started = 0;
    thread_count = 1;
    quitting = 0;
}

/* The accel's hook has no thread argument (a build's items carry their own scratch): adapt it to the pool's. */
typedef struct accel_run {
    void (*fn)(void *ctx, uint32_t item);
    void *ctx;
} accel_run_t;

static void accel_item(void *user, uint32_t item, int thread)
{
    const accel_run_t *r = user;
    (void)thread;
    r->fn(r->ctx, item);
}

static void accel_run(void *run_user, void (*fn)(void *ctx, uint32_t item), void *ctx, uint32_t items)
{
    accel_run_t r = { fn, ctx };
    (void)run_user;
    hz_threads_run(accel_item, &r, items);
}

void hz_threads_accel_hook(hz_accel_config_t *cfg)
{
    cfg->run = accel_run;
    cfg->run_user = 0;
    cfg->run_threads = (uint32_t)hz_threads_count();
}
