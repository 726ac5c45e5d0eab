/*
 * The static worker pool: every item runs exactly once, every thread index is in range and used, results
 * indexed by item do not depend on the thread count, runs can follow each other back to back, the pool
 * restarts, nothing allocates during runs, and a run without a pool (or with one thread) stays on the caller.
 */
#define _GNU_SOURCE
#include "hz_test.h"

#include <dlfcn.h>
#include <pthread.h>
#include <signal.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "hz/hash.h"
#include "threads.h"

#define ITEMS 10000u

static uint32_t hits[ITEMS];
static uint32_t result[ITEMS];
static int thread_of[ITEMS];

/* malloc interposition: counts calls while armed (the pool must not allocate after start). dlsym may itself
 * allocate while the real malloc is looked up: those requests come from a static buffer. */
static volatile int armed;
static volatile unsigned long armed_allocs;
static void *(*real_malloc)(size_t);
static unsigned char boot[4096] HZ_ALIGNED(16);
static size_t boot_used;
static int resolving;

void *malloc(size_t n)
{
    if (armed)
        __atomic_add_fetch(&armed_allocs, 1, __ATOMIC_RELAXED);
    if (!real_malloc && !resolving) {
        resolving = 1;
        *(void **)&real_malloc = dlsym(RTLD_NEXT, "malloc");
        resolving = 0;
    }
    if (!real_malloc) {
        n = (n + 15) & ~(size_t)15;
        if (boot_used + n > sizeof boot)
            return NULL;
        boot_used += n;
        return boot + boot_used - n;
    }
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

/* Whether this process can start and join a thread: qemu-aarch64 user-mode emulation of dynamically linked
 * binaries hangs in pthread_create on this project's CI machines, so the probe runs in a child with a timer. */
static void *probe_thread(void *arg)
{
    return arg;
}

static bool threads_work(void)
{
    pid_t pid = fork();
    if (pid == 0) {
        pthread_t t;
        if (pthread_create(&t, NULL, probe_thread, NULL) != 0 || pthread_join(t, NULL) != 0)
            _exit(1);
        _exit(0);
    }
    if (pid < 0)
        return false;
    int st = 0;
    for (int i = 0; i < 50; i++) { /* up to 5 s */
        if (waitpid(pid, &st, WNOHANG) == pid)
            return WIFEXITED(st) && WEXITSTATUS(st) == 0;
        usleep(100000);
    }
    kill(pid, SIGKILL);
    waitpid(pid, &st, 0);
    return false;
}

static bool can_thread;

static int setup(void **state)
{
    (void)state;
    can_thread = threads_work();
    if (!can_thread)
        print_message("threads cannot start here (emulated?): only the caller-only paths are tested\n");
    return 0;
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
    for (size_t c = 0; c < (can_thread ? HZ_ARRAY_LEN(counts) : 1); c++) {
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
    if (!can_thread)
        skip();
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
    if (!can_thread)
        skip();
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
    return HZ_RUN_GROUP(tests, setup, NULL);
}
