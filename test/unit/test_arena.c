/* Arena allocator: alignment, exhaustion, marks, high water, zero and huge sizes, count*size overflow. */
#include "hz_test.h"

#include <string.h>

#include "hz/arena.h"
#include "hz/config.h"

static uint8_t buf[4096] HZ_ALIGNED(64);

static void test_every_allocation_aligned(void **state)
{
    (void)state;
    hz_arena_t a;
    assert_int_equal(hz_arena_init(&a, "t", buf + 1, sizeof buf - 1), HZ_OK); /* misaligned base on purpose */
    size_t aligns[] = { 1, 2, 4, 8, 16, 32, 64, 128, 0 };
    for (int round = 0; round < 3; round++)
        for (size_t i = 0; i < HZ_ARRAY_LEN(aligns); i++) {
            size_t al = aligns[i] ? aligns[i] : HZ_ARENA_DEFAULT_ALIGN;
            uint8_t *p = hz_arena_alloc(&a, 3 + i, aligns[i]);
            assert_non_null(p);
            assert_int_equal((uintptr_t)p % al, 0);
            assert_true(p >= buf + 1 && p + 3 + i <= buf + sizeof buf);
            memset(p, 0x5a, 3 + i); /* must be writable and in bounds (ASan checks) */
        }
}

static void test_allocations_do_not_overlap(void **state)
{
    (void)state;
    hz_arena_t a;
    hz_arena_init(&a, "t", buf, sizeof buf);
    uint8_t *prev_end = buf;
    for (int i = 0; i < 50; i++) {
        size_t n = (size_t)(i * 7 % 23) + 1;
        uint8_t *p = hz_arena_alloc(&a, n, (size_t)1 << (i % 6));
        assert_non_null(p);
        assert_true(p >= prev_end);
        prev_end = p + n;
    }
    assert_true(a.used == (size_t)(prev_end - buf));
}

static void test_exhaustion_refuses_cleanly(void **state)
{
    (void)state;
    hz_arena_t a;
    hz_arena_init(&a, "scene", buf, 256);
    assert_non_null(hz_arena_alloc(&a, 200, 16));
    size_t used = a.used;
    assert_null(hz_arena_alloc(&a, 100, 16));
    assert_int_equal(a.used, used); /* nothing allocated: never a partial object */
    assert_int_equal(a.last_status, HZ_E_NO_MEMORY);
    assert_int_equal(a.last_needed, 100 + 8); /* 200 -> next 16-aligned offset is 208 */
    assert_int_equal(a.last_available, 56);
    hz_error_t err;
    assert_int_equal(hz_arena_error(&a, &err), HZ_E_NO_MEMORY);
    assert_string_equal(err.msg, "arena 'scene': needs 108 bytes, has 56 bytes");
    /* What is left is still usable. */
    assert_non_null(hz_arena_alloc(&a, 48, 16));
    assert_int_equal(a.used, 256);
    assert_null(hz_arena_alloc(&a, 1, 1));
}

static void test_exact_fit(void **state)
{
    (void)state;
    hz_arena_t a;
    hz_arena_init(&a, "t", buf, 128);
    assert_non_null(hz_arena_alloc(&a, 128, 64));
    assert_int_equal(hz_arena_available(&a, 1), 0);
}

static void test_reset_to_mark(void **state)
{
    (void)state;
    hz_arena_t a;
    hz_arena_init(&a, "t", buf, sizeof buf);
    uint8_t *keep = hz_arena_alloc(&a, 100, 16);
    memset(keep, 0x11, 100);
    hz_arena_mark_t m = hz_arena_mark(&a);
    uint8_t *tmp = hz_arena_alloc(&a, 1000, 16);
    assert_non_null(tmp);
    memset(tmp, 0x22, 1000);
    assert_int_equal(hz_arena_reset(&a, m), HZ_OK);
    assert_int_equal(a.used, m);
    /* The next allocation reuses the released space; the kept object is untouched. */
    uint8_t *again = hz_arena_alloc(&a, 1000, 16);
    assert_ptr_equal(again, tmp);
    for (int i = 0; i < 100; i++)
        assert_int_equal(keep[i], 0x11);
#if HZ_ARENA_POISON
    /* Released bytes are poisoned so a use-after-reset is visible. */
    assert_int_equal(again[0], 0xA5);
    assert_int_equal(again[999], 0xA5);
#endif
    /* A mark above the current level is refused and changes nothing. */
    hz_arena_reset(&a, m);
    assert_int_equal(hz_arena_reset(&a, m + 1), HZ_E_INVALID_ARG);
    assert_int_equal(a.used, m);
    assert_int_equal(hz_arena_reset(&a, 0), HZ_OK);
    assert_int_equal(a.used, 0);
}

static void test_high_water_mark(void **state)
{
    (void)state;
    hz_arena_t a;
    hz_arena_init(&a, "t", buf, sizeof buf);
    hz_arena_alloc(&a, 1000, 1);
    hz_arena_reset(&a, 0);
    hz_arena_alloc(&a, 300, 1);
    assert_int_equal(a.used, 300);
    assert_int_equal(a.high_water, 1000);
    hz_arena_alloc(&a, 1500, 1);
    assert_int_equal(a.high_water, 1800);
    hz_arena_alloc(&a, 99999, 1); /* refused: must not raise the high-water mark */
    assert_int_equal(a.high_water, 1800);
    hz_arena_init(&a, "t", buf, sizeof buf);
    assert_int_equal(a.high_water, 0);
}

static void test_zero_size(void **state)
{
    (void)state;
    hz_arena_t a;
    hz_arena_init(&a, "t", buf, sizeof buf);
    hz_arena_alloc(&a, 3, 1);
    size_t used = a.used;
    void *p = hz_arena_alloc(&a, 0, 64);
    assert_non_null(p);
    assert_int_equal((uintptr_t)p % 64, 0);
    assert_int_equal(a.used, used); /* consumes nothing */
    /* An arena without a buffer still answers zero-size requests with a non-NULL pointer... */
    hz_arena_t empty;
    assert_int_equal(hz_arena_init(&empty, "empty", NULL, 0), HZ_OK);
    assert_non_null(hz_arena_alloc(&empty, 0, 16));
    /* ...and refuses anything else with both counts. */
    assert_null(hz_arena_alloc(&empty, 1, 1));
    assert_int_equal(empty.last_needed, 1);
    assert_int_equal(empty.last_available, 0);
    /* calloc of zero elements is a zero-size request. */
    assert_non_null(hz_arena_calloc(&a, 0, 16, 16));
}

static void test_huge_sizes(void **state)
{
    (void)state;
    hz_arena_t a;
    hz_arena_init(&a, "t", buf, sizeof buf);
    hz_arena_alloc(&a, 1, 1); /* so that alignment padding is non-zero below */
    size_t used = a.used;
    assert_null(hz_arena_alloc(&a, SIZE_MAX, 16));
    assert_int_equal(a.last_status, HZ_E_NO_MEMORY);
    assert_int_equal(a.last_needed, SIZE_MAX); /* saturated, not wrapped to a small number */
    assert_null(hz_arena_alloc(&a, SIZE_MAX - 3, 16));
    assert_null(hz_arena_alloc(&a, sizeof buf, 1));
    assert_int_equal(a.used, used);
    /* A huge alignment cannot be met inside the buffer. */
    assert_null(hz_arena_alloc(&a, 1, (size_t)1 << 40));
    assert_int_equal(a.used, used);
}

static void test_bad_alignment(void **state)
{
    (void)state;
    hz_arena_t a;
    hz_arena_init(&a, "accel", buf, sizeof buf);
    assert_null(hz_arena_alloc(&a, 8, 3));
    assert_int_equal(a.last_status, HZ_E_INVALID_ARG);
    assert_null(hz_arena_alloc(&a, 8, 48));
    assert_int_equal(a.used, 0);
    hz_error_t err;
    assert_int_equal(hz_arena_error(&a, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "accel"));
}

static void test_count_times_size_overflow(void **state)
{
    (void)state;
    hz_arena_t a;
    hz_arena_init(&a, "frame", buf, sizeof buf);
    assert_null(hz_arena_alloc_array(&a, SIZE_MAX / 2 + 1, 2, 8));
    assert_int_equal(a.last_status, HZ_E_OVERFLOW);
    assert_null(hz_arena_alloc_array(&a, (size_t)1 << (sizeof(size_t) * 4), (size_t)1 << (sizeof(size_t) * 4), 8));
    assert_int_equal(a.last_status, HZ_E_OVERFLOW);
    assert_int_equal(a.used, 0);
    hz_error_t err;
    assert_int_equal(hz_arena_error(&a, &err), HZ_E_OVERFLOW);
    assert_non_null(strstr(err.msg, "overflow"));
    /* Large but representable products are plain refusals. */
    assert_null(hz_arena_alloc_array(&a, 1u << 20, 1u << 10, 8));
    assert_int_equal(a.last_status, HZ_E_NO_MEMORY);
    /* And normal arrays work, zero-filled by calloc. */
    uint32_t *v = hz_arena_calloc(&a, 100, sizeof(uint32_t), 4);
    assert_non_null(v);
    for (int i = 0; i < 100; i++)
        assert_int_equal(v[i], 0);
}

static void test_bad_init(void **state)
{
    (void)state;
    hz_arena_t a;
    assert_int_equal(hz_arena_init(&a, "t", NULL, 16), HZ_E_INVALID_ARG);
    assert_int_equal(hz_arena_init(NULL, "t", buf, 16), HZ_E_INVALID_ARG);
    assert_null(hz_arena_alloc(NULL, 1, 1));
    assert_int_equal(hz_arena_reset(NULL, 0), HZ_E_INVALID_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_allocation_aligned),
        cmocka_unit_test(test_allocations_do_not_overlap),
        cmocka_unit_test(test_exhaustion_refuses_cleanly),
        cmocka_unit_test(test_exact_fit),
        cmocka_unit_test(test_reset_to_mark),
        cmocka_unit_test(test_high_water_mark),
        cmocka_unit_test(test_zero_size),
        cmocka_unit_test(test_huge_sizes),
        cmocka_unit_test(test_bad_alignment),
        cmocka_unit_test(test_count_times_size_overflow),
        cmocka_unit_test(test_bad_init),
    };
    return HZ_RUN(tests);
}
