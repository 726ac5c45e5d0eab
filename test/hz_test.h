/*
 * hz_test.h — what every cmocka test includes first (cmocka needs stdarg/stddef/setjmp before cmocka.h).
 * Also small helpers shared by tests.
 */
#ifndef HZ_TEST_H
#define HZ_TEST_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

/* HZ_TEST_FILTER=PATTERN (cmocka's wildcards * and ?) runs only the matching cases of a test (every test's main
 * runs its cases through HZ_RUN or HZ_RUN_GROUP). */
static inline void hz_test_filter(void)
{
    const char *f = getenv("HZ_TEST_FILTER");
    if (f && *f)
        cmocka_set_test_filter(f);
}

#define HZ_RUN_GROUP(tests, setup, teardown) (hz_test_filter(), cmocka_run_group_tests(tests, setup, teardown))
#define HZ_RUN(tests) HZ_RUN_GROUP(tests, NULL, NULL)

/* HZ_NATIVE_ONLY(why): the case runs where the tests run natively and is skipped, with the reason printed and
 * counted as a skip in the summary, where they run under emulation (HZ_TEST_EMULATED: a board with a test
 * launcher, i.e. qemu). Only for cases whose arithmetic is the same on every ISA and that cost minutes under
 * qemu: a NEON kernel they go through must be held to its scalar twin by a cheaper case that does run there.
 * A whole file that qualifies says "hz-test: native" instead. */
#if defined(HZ_TEST_EMULATED)
#define HZ_NATIVE_ONLY(why)                                                                                    \
    do {                                                                                                       \
        print_message("  native boards only (%s)\n", why);                                                     \
        skip();                                                                                                \
    } while (0)
#else
#define HZ_NATIVE_ONLY(why) ((void)0)
#endif

/* HZ_EMULATED_LESS(native, emulated): a work size (frames, pixels) that is `native` where the tests run natively
 * and the smaller `emulated` under qemu, for cases that check the same paths with less of the same work. */
#if defined(HZ_TEST_EMULATED)
#define HZ_EMULATED_LESS(native, emulated) (emulated)
#else
#define HZ_EMULATED_LESS(native, emulated) (native)
#endif

#endif
