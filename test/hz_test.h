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

#include <cmocka.h>

#define HZ_RUN(tests) cmocka_run_group_tests(tests, NULL, NULL)

#endif
