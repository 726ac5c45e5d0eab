/* hz_fmt: the message formatter of the freestanding core, against the C library's snprintf. */
#include "hz_test.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

#include "hz/fmt.h"

#define SAME_AS_LIBC(fmtstr, ...)                                                                           \
    do {                                                                                                    \
        char a[128], b[128];                                                                                \
        size_t na = hz_fmt(a, sizeof a, fmtstr, __VA_ARGS__);                                               \
        int nb = snprintf(b, sizeof b, fmtstr, __VA_ARGS__);                                                \
        assert_string_equal(a, b);                                                                          \
        assert_int_equal(na, (size_t)nb);                                                                   \
    } while (0)

static void test_matches_libc(void **state)
{
    (void)state;
    SAME_AS_LIBC("%d|%i|%u", 0, -17, 42u);
    SAME_AS_LIBC("%d %d", INT_MIN, INT_MAX);
    SAME_AS_LIBC("%ld %lu", LONG_MIN, ULONG_MAX);
    SAME_AS_LIBC("%lld %llu", LLONG_MIN, ULLONG_MAX);
    SAME_AS_LIBC("%zu bytes", (size_t)123456789);
    SAME_AS_LIBC("%x %X %08x", 0xdeadbeefu, 0xabcu, 0x1fu);
    SAME_AS_LIBC("[%5d] [%05d] [%5d] [%05d]", 42, 42, -42, -42);
    SAME_AS_LIBC("%s/%s %c%%", "a", "", 'z');
    SAME_AS_LIBC("%s", "no conversions at all");
}

static void test_truncates_and_counts(void **state)
{
    (void)state;
    char small[8];
    memset(small, 'X', sizeof small);
    size_t n = hz_fmt(small, sizeof small, "abcdefghij%d", 12345);
    assert_int_equal(n, 15);
    assert_string_equal(small, "abcdefg"); /* 7 characters + NUL, never more */
    char one[1] = { 'X' };
    assert_int_equal(hz_fmt(one, 1, "hello"), 5);
    assert_int_equal(one[0], '\0');
    assert_int_equal(hz_fmt(NULL, 0, "%d", 1234), 4); /* size 0: only counts */
}

static void test_null_and_bad_formats(void **state)
{
    (void)state;
    char b[64];
    hz_fmt(b, sizeof b, "%s", (const char *)NULL);
    assert_string_equal(b, "(null)");
    /* An unknown conversion stops argument processing: the rest is literal. */
    hz_fmt(b, sizeof b, "a=%d %q %s", 5, "never read");
    assert_string_equal(b, "a=5 %q %s");
    hz_fmt(b, sizeof b, "trailing %");
    assert_string_equal(b, "trailing %");
    hz_fmt(b, sizeof b, NULL);
    assert_string_equal(b, "(null format)");
}

static void test_pointer(void **state)
{
    (void)state;
    char b[64];
    hz_fmt(b, sizeof b, "%p", (void *)(uintptr_t)0x1234abcd);
    assert_string_equal(b, "0x1234abcd");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_matches_libc),
        cmocka_unit_test(test_truncates_and_counts),
        cmocka_unit_test(test_null_and_bad_formats),
        cmocka_unit_test(test_pointer),
    };
    return HZ_RUN(tests);
}
