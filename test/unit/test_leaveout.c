/* Leave out what a scene does not need (DESIGN.md principle 5), asserted on real baked scenes: for static opaque
 * scenes (Conference, the dragon) no render mode's plan has a mirror G-buffer, reflected motion, any-hit,
 * transparency stage or animation state, and only the camera path costs motion vectors; under a still camera
 * (dragon-res4-still: one camera key) there are none at all, the renderer really holds no such arrays, and a
 * rendered frame traces no secondary rays.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "hz/tdense.h"
#include "render_fixture.h"

static size_t aligned(size_t bytes)
{
    return hz_align_up(bytes, 64) + 64; /* the renderer's per-array rounding (hz_render_plan) */
}

static void check_static_opaque(const char *file, bool camera_path)
{
    char path[512];
    if (!rfix_scene_path(file, path, sizeof path))
        fail_msg("HZ_SCENES_DIR is not set (make test sets it)");
    hz_pools_t *pools = hz_pools_get();
    assert_non_null(pools);
    hz_arena_mark_t mark = hz_arena_mark(&pools->scene);
    hz_scene_t scene;
    hz_error_t err;
    if (hz_scenefile_open(path, pools, &scene, &err) != HZ_OK)
        fail_msg("%s: %s", file, err.msg);
    assert_true(((scene.features & HZ_FEAT_CAMERA_PATH) != 0) == camera_path);
    assert_int_equal(scene.features & (HZ_FEAT_MOTION | HZ_FEAT_MIRROR | HZ_FEAT_BLEND | HZ_FEAT_CUTOUT), 0);
    assert_int_equal(scene.plan.arena_bytes, 0); /* no animation state */
    assert_null(scene.prev_pos);
    const uint32_t w = 320, h = 180;
    for (int m = 0; m < HZ_MODE_COUNT; m++) {
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = w, o.height = h, o.mode = (hz_render_mode_t)m;
        hz_render_plan_t p;
        assert_int_equal(hz_render_plan(&scene, &o, &p, &err), HZ_OK);
        assert_int_equal(p.gbuffer2_bytes, 0);
        assert_false(p.anyhit);
        assert_false(p.transparency);
        /* Motion vectors only for the camera: the primary ones, no reflected ones. */
        assert_int_equal(p.mv_bytes, camera_path ? aligned((size_t)w * h * 8) : 0);
        /* TAA and tdense read only object ids and flags of the G-buffer: no depth, normal or shadow counts. */
        const size_t px = (size_t)w * h;
        if (m == HZ_MODE_TAA || m == HZ_MODE_TDENSE)
            assert_int_equal(p.gbuffer_bytes, aligned(px * 2) + aligned(px));
        else
            assert_int_equal(p.gbuffer_bytes, aligned(px * 4) + aligned(px * 2) + aligned(px * 12) + 2 * aligned(px));
        assert_int_equal(p.display_bytes + p.gbuffer_bytes + p.gbuffer2_bytes + p.mv_bytes + p.state_bytes,
                         p.frame_bytes);
    }
    hz_arena_reset(&pools->scene, mark);
}

static void test_conference(void **state)
{
    (void)state;
    check_static_opaque("conference.hzb", true);
}

static void test_dragon(void **state)
{
    (void)state;
    check_static_opaque("dragon.hzb", true);
}

/* Under a still camera: nothing for motion anywhere, in the plan and in the renderer's arrays. */
static void test_still_dragon(void **state)
{
    (void)state;
    check_static_opaque("dragon-res4-still.hzb", false);
    char path[512];
    rfix_scene_path("dragon-res4-still.hzb", path, sizeof path);
    rfix_t f;
    hz_error_t err;
    if (rfix_open(&f, path, HZ_ACCEL_NATIVE, &err) != HZ_OK)
        fail_msg("open: %s", err.msg);
    for (int m = 0; m < HZ_MODE_COUNT; m++) {
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = 96, o.height = 64, o.mode = (hz_render_mode_t)m;
        hz_render_plan_t p;
        assert_int_equal(hz_render_plan(&f.scene, &o, &p, &err), HZ_OK);
        assert_int_equal(p.mv_bytes, 0);
        size_t before = f.frame_mark; /* rfix_renderer gives the previous renderer back first */
        if (rfix_renderer(&f, &o, 2, &err) != HZ_OK)
            fail_msg("renderer: %s", err.msg);
        if (f.pools->frame.used - before > p.frame_bytes)
            fail_msg("mode %s: the renderer took %zu bytes, the plan says %zu", hz_render_mode_name(o.mode),
                     f.pools->frame.used - before, p.frame_bytes);
        const hz_gbuffer_t *gb = hz_render_gbuffer(f.r);
        const bool attrs = m == HZ_MODE_FULL || m == HZ_MODE_ADAPTIVE;
        assert_true(hz_render_mode_keeps_surface(o.mode) == attrs);
        assert_true((gb->depth != NULL) == attrs && (gb->normal != NULL) == attrs && (gb->shadow != NULL) == attrs);
        assert_non_null(gb->object);
        assert_non_null(gb->flags);
        assert_null(gb->mv);
        assert_null(gb->mv_reflect);
        assert_null(gb->object2);
        assert_null(gb->normal2);
        assert_null(gb->shadow2);
        assert_null(gb->flags2);
        if (m == HZ_MODE_TDENSE)
            assert_null(hz_render_tdense(f.r)->mv);
        for (uint32_t i = 0; i < 4; i++)
            if (rfix_frame(&f, i, (float)i / 60.0f, &err) != HZ_OK)
                fail_msg("frame: %s", err.msg);
        hz_render_stats_t total;
        hz_render_frame_stats(f.r, NULL, &total);
        assert_true(total.primary_rays > 0 && total.shadow_rays > 0);
        assert_int_equal(total.secondary_rays, 0); /* no reflections, no continuation rays */
        /* Something was drawn: the dragon covers part of the view. */
        const hz_gbuffer_t *g = hz_render_gbuffer(f.r);
        size_t hit = 0;
        for (size_t i = 0; i < 96u * 64u; i++)
            hit += (g->flags[i] & HZ_GB_HIT) != 0;
        assert_true(hit > 100);
    }
    /* A still scene saves tdense exactly its motion array: 2 half floats per pixel (as every array, counted
     * with its worst alignment padding). */
    assert_int_equal(hz_tdense_plan(96, 64, true, NULL) - hz_tdense_plan(96, 64, false, NULL),
                     aligned(96u * 64u * 4u));
    rfix_close(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_conference),
        cmocka_unit_test(test_dragon),
        cmocka_unit_test(test_still_dragon),
    };
    return HZ_RUN(tests);
}
