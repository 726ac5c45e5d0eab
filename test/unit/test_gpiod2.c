/*
 * The libgpiod 2 path of port/linux/gpio.c, compiled against Debian 13's libgpiod-dev 2.x (fetched into the
 * build folder by tools/gpiod2/fetch.sh, never installed) and linked with its static library: the backend says
 * v2, and the library's own chip-open errors come back as the port's messages. (Edges on a real line: the VM's
 * test_vm_gpiod2, the GPIO part of test/vm/test_vm_devices.c built the same way.)
 * hz-test: manual (built by tools/gpiod2/gpiod2.mk)
 */
#include "hz_test.h"

#include <stdio.h>
#include <string.h>

#include "devices.h"

static void test_backend_is_v2(void **state)
{
    (void)state;
    const char *b = hz_gpio_backend();
    print_message("  backend: %s\n", b);
    assert_non_null(strstr(b, "libgpiod 2."));
    assert_non_null(strstr(b, "(v2 API)"));
}

static void expect_open_error(const char *chip, const char *needle)
{
    hz_vsource_t v;
    hz_error_t err;
    hz_gpio_cfg_t c = { chip, 0, 0, NULL, 0 };
    hz_status_t s = hz_gpio_vsource_open(&v, &c, &err);
    if (s != HZ_E_DEVICE || !strstr(err.msg, needle))
        fail_msg("chip '%s': status %d, message '%s', expected '%s'", chip, s, s ? err.msg : "", needle);
    hz_vsource_close(&v);
}

static void test_open_errors(void **state)
{
    (void)state;
    expect_open_error("/dev/gpiochip-hz-none", "GPIO chip '/dev/gpiochip-hz-none': no such chip");
    expect_open_error("gpiochip-hz-none", "no such chip");
    expect_open_error("no-such-label", "no such chip");
    /* A character device that is not a GPIO chip: libgpiod 2 checks sysfs and refuses it. */
    expect_open_error("/dev/null", "GPIO chip '/dev/null'");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_backend_is_v2),
        cmocka_unit_test(test_open_errors),
    };
    return HZ_RUN(tests);
}
