/* Status codes: names, distinct exit statuses, error messages and prefixes. */
#include "hz_test.h"

#include <string.h>

#include "hz/status.h"

static void test_every_code_has_a_name(void **state)
{
    (void)state;
    for (int s = 0; s < HZ_STATUS_COUNT; s++) {
        const char *n = hz_status_str((hz_status_t)s);
        assert_non_null(n);
        assert_true(strlen(n) > 1);
        assert_string_not_equal(n, "unknown status");
    }
    assert_string_equal(hz_status_str((hz_status_t)999), "unknown status");
    assert_string_equal(hz_status_str((hz_status_t)-1), "unknown status");
}

static void test_exit_codes_distinct(void **state)
{
    (void)state;
    assert_int_equal(hz_status_exit_code(HZ_OK), 0);
    for (int a = 1; a < HZ_STATUS_COUNT; a++) {
        int ea = hz_status_exit_code((hz_status_t)a);
        assert_true(ea > 2 && ea < 126); /* clear of usage (2) and the shell's own codes */
        for (int b = a + 1; b < HZ_STATUS_COUNT; b++)
            assert_int_not_equal(ea, hz_status_exit_code((hz_status_t)b));
    }
}

static void test_error_set_and_prefix(void **state)
{
    (void)state;
    hz_error_t err;
    hz_error_clear(&err);
    assert_int_equal(err.code, HZ_OK);
    assert_string_equal(err.msg, "");
    assert_int_equal(hz_error_set(&err, HZ_E_RANGE, "index %u >= count %u", 4711u, 4096u), HZ_E_RANGE);
    assert_int_equal(err.code, HZ_E_RANGE);
    assert_string_equal(err.msg, "index 4711 >= count 4096");
    hz_error_prefix(&err, "scene.hzb");
    assert_string_equal(err.msg, "scene.hzb: index 4711 >= count 4096");
    /* NULL error objects are allowed: the code still comes back. */
    assert_int_equal(hz_error_set(NULL, HZ_E_IO, "x"), HZ_E_IO);
}

static void test_long_messages_truncate(void **state)
{
    (void)state;
    hz_error_t err;
    char longname[600];
    memset(longname, 'n', sizeof longname - 1);
    longname[sizeof longname - 1] = '\0';
    hz_error_set(&err, HZ_E_FORMAT, "%s", longname);
    assert_int_equal(strlen(err.msg), HZ_ERROR_MSG_BYTES - 1);
    hz_error_prefix(&err, longname);
    assert_int_equal(strlen(err.msg), HZ_ERROR_MSG_BYTES - 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_code_has_a_name),
        cmocka_unit_test(test_exit_codes_distinct),
        cmocka_unit_test(test_error_set_and_prefix),
        cmocka_unit_test(test_long_messages_truncate),
    };
    return HZ_RUN(tests);
}
