/*
 * The static worker pool: every item runs exactly once, every thread index is in range and used, results
 * indexed by item do not depend on the thread count, runs can follow each other back to back, the pool
 * restarts, nothing allocates during runs, and a run without a pool (or with one thread) stays on the caller.
 */
#define _GNU_SOURCE
#include "hz_test.h"

#include <dlfcn.h>
#include <stdlib.h>
#include <string.h>

#include "hz/hash.h"
#include "threads.h"

#define ITEMS 10000u

static uint32_t hits[ITEMS];
static uint32_t result[ITEMS];
static int thread_of[ITEMS];

/* malloc interposition: counts calls while armed (the pool must not allocate after start) */
static volatile int armed;
static volatile unsigned long armed_allocs;
static void *(*real_malloc)(size_t);
void *malloc(size_t n)
{
    if (armed)
        __atomic_add_fetch(&armed_allocs, 1, __ATOMIC_RELAXED);
    if (!real_malloc)
        *(void **)&real_malloc = dlsym(RTLD_NEXT, "malloc");
    return real_malloc(n);
}

static void work(void *user, uint32_t item, int thread)
{
    (void)user;
    __atomic_add_fetch(&hits[item], 1u, __ATOMIC_RELAXED);
    thread_of[item] = thread;
    uint32_t h = item;
    for (int i = 0; i < 200; i++) /* some work, so items spread over the threads */
        h = hz_hash32(h + (uint32_t)i);
    result[item] = h;
}

static void run_and_check(int n, uint32_t *expect)
{
    memset(hits, 0, sizeof hits);
    memset(result, 0, sizeof result);
    hz_threads_run(work, NULL, ITEMS);
    int used[HZ_MAX_THREADS] = { 0 };
    for (uint32_t i = 0; i < ITEMS; i++) {
        assert_int_equal(hits[i], 1);
        assert_true(thread_of[i] >= 0 && thread_of[i] < n);
        used[thread_of[i]] = 1;
    }
    if (n == 1)
        assert_true(used[0]);
    if (expect)
        assert_memory_equal(result, expect, sizeof result);
}

static void test_items_once_and_deterministic(void **state)
{
    (void)state;
    static uint32_t ref[ITEMS];
    /* no pool: everything on the caller */
    assert_int_equal(hz_threads_count(), 1);
    run_and_check(1, NULL);
    memcpy(ref, result, sizeof ref);
    const int counts[] = { 1, 2, 3, HZ_MAX_THREADS };
    for (size_t c = 0; c < HZ_ARRAY_LEN(counts); c++) {
        hz_error_t err;
        assert_int_equal(hz_threads_start(counts[c], &err), HZ_OK);
        int n = hz_threads_count();
        assert_int_equal(n, counts[c]);
        hz_error_t err2;
        assert_int_equal(hz_threads_start(2, &err2), HZ_E_INVALID_ARG); /* already running */
        armed_allocs = 0;
        armed = 1;
        for (int rep = 0; rep < 20; rep++)
            run_and_check(n, ref);
        hz_threads_run(work, NULL, 0);
        armed = 0;
        assert_int_equal(armed_allocs, 0);
        hz_threads_stop();
        assert_int_equal(hz_threads_count(), 1);
    }
}

static void test_default_count(void **state)
{
    (void)state;
    hz_error_t err;
    assert_int_equal(hz_threads_start(0, &err), HZ_OK);
    assert_true(hz_threads_count() >= 1 && hz_threads_count() <= HZ_MAX_THREADS);
    run_and_check(hz_threads_count(), NULL);
    hz_threads_stop();
    assert_int_equal(hz_threads_start(100000, &err), HZ_OK); /* clamped */
    assert_int_equal(hz_threads_count(), HZ_MAX_THREADS);
    hz_threads_stop();
}

/* Many tiny runs back to back: the hand-over between runs must not lose or repeat a run. */
static uint32_t tiny_count;
static void tiny(void *user, uint32_t item, int thread)
{
    (void)user, (void)item, (void)thread;
    __atomic_add_fetch(&tiny_count, 1u, __ATOMIC_RELAXED);
}

static void test_back_to_back(void **state)
{
    (void)state;
    hz_error_t err;
    assert_int_equal(hz_threads_start(4, &err), HZ_OK);
    tiny_count = 0;
    for (int i = 0; i < 500; i++)
        hz_threads_run(tiny, NULL, 1u + (uint32_t)(i % 5));
    uint32_t expect = 0;
    for (int i = 0; i < 500; i++)
        expect += 1u + (uint32_t)(i % 5);
    assert_int_equal(tiny_count, expect);
    hz_threads_stop();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_items_once_and_deterministic),
        cmocka_unit_test(test_default_count),
        cmocka_unit_test(test_back_to_back),
    };
    return HZ_RUN(tests);
}
