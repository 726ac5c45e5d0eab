/* CRC-32 against published check values, chaining, and a bitwise reference (the polynomial, one bit at a time)
 * at every length up to 300 bytes and every alignment, which checks each entry the sliced tables use. */
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

/* The definition itself: one bit per step, no table. */
static uint32_t crc32_bitwise(uint32_t crc, const uint8_t *p, size_t n)
{
    crc = ~crc;
    for (size_t i = 0; i < n; i++) {
        crc ^= p[i];
        for (int k = 0; k < 8; k++)
            crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

static void test_bitwise_reference(void **state)
{
    (void)state;
    static uint8_t buf[4096 + 8];
    uint32_t x = 0x12345678u;
    for (size_t i = 0; i < sizeof buf; i++) {
        x = x * 1664525u + 1013904223u;
        buf[i] = (uint8_t)(x >> 24);
    }
    for (size_t align = 0; align < 8; align++)
        for (size_t n = 0; n <= 300; n++)
            assert_int_equal(hz_crc32(0x5a5a5a5au, buf + align, n), crc32_bitwise(0x5a5a5a5au, buf + align, n));
    assert_int_equal(hz_crc32(0, buf + 3, 4096), crc32_bitwise(0, buf + 3, 4096));
    /* every byte value in every lane of a step reaches every table */
    static uint8_t ramp[256 * 8];
    for (size_t i = 0; i < sizeof ramp; i++)
        ramp[i] = (uint8_t)(i / 8 + i % 8 * 37);
    assert_int_equal(hz_crc32(0, ramp, sizeof ramp), crc32_bitwise(0, ramp, sizeof ramp));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_check_value),
        cmocka_unit_test(test_chaining),
        cmocka_unit_test(test_bitwise_reference),
    };
    return HZ_RUN(tests);
}
