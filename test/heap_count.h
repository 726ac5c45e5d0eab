/*
 * heap_count.h — a process-wide heap interposer for the tests that prove frames allocate nothing
 * (test_zero_alloc, test_soak). Include it in exactly one file of a test binary, after _GNU_SOURCE and the
 * system headers it needs (dlfcn.h, execinfo.h, string.h).
 *
 * It interposes malloc/calloc/realloc/free and the aligned variants, forwards them to the next definition (libc's,
 * or the sanitizer's under SAN=1) and counts the calls made while `armed` (armed_calls). With `recording` set, the
 * first STACKS armed calls keep a backtrace (stacks[], stack_depth[]) to say where they came from.
 */
#ifndef HZ_TEST_HEAP_COUNT_H
#define HZ_TEST_HEAP_COUNT_H

#include "hz/base.h"

static volatile int armed;
static volatile unsigned long armed_calls;

static void *(*real_malloc)(size_t);
static void *(*real_calloc)(size_t, size_t);
static void *(*real_realloc)(void *, size_t);
static void (*real_free)(void *);
static int (*real_posix_memalign)(void **, size_t, size_t);
static void *(*real_aligned_alloc)(size_t, size_t);

/* dlsym itself may allocate (calloc) before the real functions are known: serve that from here. */
static unsigned char boot_buf[4096] HZ_ALIGNED(16);
static size_t boot_used;
static int resolving;

static void *boot_alloc(size_t n)
{
    n = (n + 15) & ~(size_t)15;
    if (boot_used + n > sizeof boot_buf)
        return NULL;
    void *p = boot_buf + boot_used;
    boot_used += n;
    return p;
}

static int from_boot(void *p)
{
    return (unsigned char *)p >= boot_buf && (unsigned char *)p < boot_buf + sizeof boot_buf;
}

static void resolve(void)
{
    if (real_malloc || resolving)
        return;
    resolving = 1;
    /* The object-to-function pointer conversion goes through void ** (POSIX's own idiom for dlsym). */
    *(void **)&real_calloc = dlsym(RTLD_NEXT, "calloc");
    *(void **)&real_realloc = dlsym(RTLD_NEXT, "realloc");
    *(void **)&real_free = dlsym(RTLD_NEXT, "free");
    *(void **)&real_posix_memalign = dlsym(RTLD_NEXT, "posix_memalign");
    *(void **)&real_aligned_alloc = dlsym(RTLD_NEXT, "aligned_alloc");
    *(void **)&real_malloc = dlsym(RTLD_NEXT, "malloc");
    resolving = 0;
}

/* Where the armed calls came from (the first few), for the Embree check; backtrace() is warmed up unarmed. */
#define STACKS 256
#define DEPTH 12
static void *stacks[STACKS][DEPTH];
static int stack_depth[STACKS];
static volatile int recording, in_backtrace;

static void count(void)
{
    if (armed) {
        if (recording && !in_backtrace && armed_calls < STACKS) {
            in_backtrace = 1;
            stack_depth[armed_calls] = backtrace(stacks[armed_calls], DEPTH);
            in_backtrace = 0;
        }
        armed_calls++;
    }
}

#ifdef HZ_HAVE_EMBREE
/* Whether recorded call i has a frame in a shared object whose path contains `lib`. */
__attribute__((unused)) static int stack_has(unsigned long i, const char *lib)
{
    for (int k = 0; k < stack_depth[i]; k++) {
        Dl_info d;
        if (dladdr(stacks[i][k], &d) && d.dli_fname && strstr(d.dli_fname, lib))
            return 1;
    }
    return 0;
}
#endif

void *malloc(size_t n)
{
    count();
    resolve();
    return real_malloc ? real_malloc(n) : boot_alloc(n);
}

void *calloc(size_t n, size_t m)
{
    count();
    resolve();
    if (!real_calloc) {
        if (m && n > (size_t)-1 / m)
            return NULL;
        return boot_alloc(n * m); /* static storage is already zero */
    }
    return real_calloc(n, m);
}

void *realloc(void *p, size_t n)
{
    count();
    resolve();
    if (from_boot(p)) {
        void *q = malloc(n);
        if (q)
            memcpy(q, p, n < 64 ? n : 64);
        return q;
    }
    return real_realloc(p, n);
}

void free(void *p)
{
    count();
    if (!p || from_boot(p))
        return;
    resolve();
    real_free(p);
}

int posix_memalign(void **out, size_t align, size_t n)
{
    count();
    resolve();
    return real_posix_memalign(out, align, n);
}

void *aligned_alloc(size_t align, size_t n)
{
    count();
    resolve();
    return real_aligned_alloc(align, n);
}

#endif
