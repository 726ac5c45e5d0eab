/* The board configuration as the running code sees it: the static pools have the sizes board.h asks for, the
 * native accel runs the SIMD path the ISA selects, and the board's default mode fits its arenas at its display
 * size with the built-in scene and the real scenes baked for the tests (the fixed-memory promise). Each of these
 * fails when a board's numbers and the code drift apart (an arena too small for the frame state at the panel's
 * size, a pool built from other sizes, an ISA flag that does not reach the kernels). */
#include "hz_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hz/accel.h"
#include "hz/config.h"
#include "hz/render.h"
#include "pools.h"
#include "scenefile.h"

static void test_pools_have_the_board_sizes(void **state)
{
    (void)state;
    hz_pools_t *p = hz_pools_get();
    assert_non_null(p);
    assert_true(p->scene.cap == (size_t)HZ_ARENA_SCENE_BYTES);
    assert_true(p->accel.cap == (size_t)HZ_ARENA_ACCEL_BYTES);
    assert_true(p->frame.cap == (size_t)HZ_ARENA_FRAME_BYTES);
    for (int i = 0; i < HZ_MAX_THREADS; i++)
        assert_true(p->thread[i].cap == (size_t)HZ_ARENA_THREAD_BYTES);
    /* Distinct, non-overlapping buffers. */
    assert_true(p->scene.base != p->accel.base && p->accel.base != p->frame.base);
    if (HZ_MAX_THREADS > 1)
        assert_true((const uint8_t *)p->thread[1].base >= (const uint8_t *)p->thread[0].base + p->thread[0].cap);
}

static void test_native_accel_runs_the_isa_path(void **state)
{
    (void)state;
    hz_pools_t *p = hz_pools_get();
    hz_scene_t sc;
    hz_error_t err;
    hz_arena_mark_t ms = hz_arena_mark(&p->scene), ma = hz_arena_mark(&p->accel), mf = hz_arena_mark(&p->frame);
    assert_int_equal(hz_scenefile_open("builtin", p, &sc, &err), HZ_OK);
    hz_accel_geom_t g;
    assert_int_equal(hz_accel_geom_from_scene(&g, &sc, &p->accel, &err), HZ_OK);
    hz_accel_t *a = NULL;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &p->accel, &err), HZ_OK);
#if defined(HZ_SIMD_AVX2)
    assert_string_equal(a->info.backend, "native-avx2");
#elif defined(HZ_SIMD_NEON)
    assert_string_equal(a->info.backend, "native-neon");
#else
    assert_string_equal(a->info.backend, "native-scalar");
#endif
    hz_accel_release(a);
    hz_arena_reset(&p->frame, mf);
    hz_arena_reset(&p->accel, ma);
    hz_arena_reset(&p->scene, ms);
}

/* The scene loads into the scene arena, its worst-case native build fits the accel arena, and the renderer's
 * default mode (hz_render_opts_default: what the board's display loop, `hzrt latency --render scene`, runs) at
 * the display's size fits the frame and thread arenas. */
static void check_fits(const char *name)
{
    hz_pools_t *p = hz_pools_get();
    hz_scene_t sc;
    hz_error_t err;
    hz_arena_mark_t ms = hz_arena_mark(&p->scene), mf = hz_arena_mark(&p->frame);
    if (hz_scenefile_open(name, p, &sc, &err) != HZ_OK)
        fail_msg("%s does not load into board %s's scene arena: %s", name, HZ_BOARD_NAME, err.msg);
    hz_accel_bytes_t ab = hz_accel_bytes_bound(sc.triangle_count, NULL);
    if (ab.peak > p->accel.cap)
        fail_msg("%s: the native build may need %zu bytes, board %s's accel arena has %zu", name, ab.peak,
                 HZ_BOARD_NAME, p->accel.cap);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = HZ_DISPLAY_WIDTH, o.height = HZ_DISPLAY_HEIGHT;
    hz_render_plan_t rp;
    if (hz_render_plan(&sc, &o, &rp, &err) != HZ_OK)
        fail_msg("%s: no render plan: %s", name, err.msg);
    if (rp.frame_bytes > p->frame.cap || rp.thread_bytes > p->thread[0].cap)
        fail_msg("%s at %dx%d (mode %s): frame %zu / %zu bytes, thread %zu / %zu bytes on board %s", name,
                 HZ_DISPLAY_WIDTH, HZ_DISPLAY_HEIGHT, hz_render_mode_name(o.mode), rp.frame_bytes, p->frame.cap, rp.thread_bytes,
                 p->thread[0].cap, HZ_BOARD_NAME);
    print_message("%s: frame %.1f of %.0f MiB, thread %.2f of %.0f MiB, accel at most %.1f of %.0f MiB\n", name,
                  rp.frame_bytes / 1048576.0, p->frame.cap / 1048576.0, rp.thread_bytes / 1048576.0,
                  p->thread[0].cap / 1048576.0, ab.peak / 1048576.0, p->accel.cap / 1048576.0);
    hz_arena_reset(&p->frame, mf);
    hz_arena_reset(&p->scene, ms);
}

static void test_default_mode_fits_the_board(void **state)
{
    (void)state;
    check_fits("builtin");
    /* Real scenes, when the tests have them (make test bakes them first): a textured architectural scene and
     * a dense scan. */
    const char *dir = getenv("HZ_SCENES_DIR");
    if (!dir)
        return;
    static const char *const real[] = { "sponza.hzb", "dragon-res2.hzb" };
    for (size_t i = 0; i < sizeof real / sizeof real[0]; i++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, real[i]);
        check_fits(path);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pools_have_the_board_sizes),
        cmocka_unit_test(test_native_accel_runs_the_isa_path),
        cmocka_unit_test(test_default_mode_fits_the_board),
    };
    return HZ_RUN(tests);
}
