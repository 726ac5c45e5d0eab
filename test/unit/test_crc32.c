/* CRC-32 against the standard check value and zlib's crc32 on the same data (chaining included). */
#include "hz_test.h"

#include <string.h>

#include "hz/crc32.h"

static void test_check_value(void **state)
{
    (void)state;
    assert_int_equal(hz_crc32(0, "123456789", 9), 0xcbf43926u);
    assert_int_equal(hz_crc32(0, "", 0), 0u);
    assert_int_equal(hz_crc32(0, "a", 1), 0xe8b7be43u);
    /* "The quick brown fox jumps over the lazy dog": a widely published CRC-32 vector. */
    const char *fox = "The quick brown fox jumps over the lazy dog";
    assert_int_equal(hz_crc32(0, fox, strlen(fox)), 0x414fa339u);
}

static void test_chaining(void **state)
{
    (void)state;
    uint8_t buf[1000];
    for (int i = 0; i < 1000; i++)
        buf[i] = (uint8_t)(i * 7 + 3);
    uint32_t whole = hz_crc32(0, buf, sizeof buf);
    for (size_t cut = 0; cut <= sizeof buf; cut += 37)
        assert_int_equal(hz_crc32(hz_crc32(0, buf, cut), buf + cut, sizeof buf - cut), whole);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_check_value),
        cmocka_unit_test(test_chaining),
    };
    return HZ_RUN(tests);
}
