/* The board configuration as the code sees it: settings present, SIMD selection consistent with the ISA. */
#include "hz_test.h"

#include <string.h>

#include "hz/config.h"

static void test_board_settings(void **state)
{
    (void)state;
    assert_true(strlen(HZ_BOARD_NAME) > 0);
    assert_true(HZ_DISPLAY_WIDTH >= 16 && HZ_DISPLAY_HEIGHT >= 16);
    assert_true(HZ_ARENA_SCENE_BYTES > 0 && HZ_ARENA_ACCEL_BYTES > 0 && HZ_ARENA_FRAME_BYTES > 0);
    assert_true(HZ_FEATURE_TEXTURES == 0 || HZ_FEATURE_TEXTURES == 1);
    assert_true(HZ_FEATURE_MOTION == 0 || HZ_FEATURE_MOTION == 1);
    if (HZ_VSYNC_SOURCE == HZ_VSYNC_GPIO) {
        assert_true(strlen(HZ_VSYNC_GPIO_CHIP) > 0);
        assert_true(HZ_VSYNC_GPIO_LINE >= 0);
    }
}

static void test_simd_matches_isa(void **state)
{
    (void)state;
#if defined(__aarch64__)
    assert_int_equal(HZ_SIMD_LANES, 4);
#elif defined(__AVX2__) && defined(__FMA__)
    assert_int_equal(HZ_SIMD_LANES, 8);
#else
    assert_int_equal(HZ_SIMD_LANES, 1);
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_board_settings),
        cmocka_unit_test(test_simd_matches_isa),
    };
    return HZ_RUN(tests);
}
