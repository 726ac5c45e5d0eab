/* hz_render_reconfigure (hz/render.h): a renderer switched to another size or mode renders, from then on, bit for
 * bit what a renderer created for that configuration renders as its first frames (the oracle is a fresh
 * renderer); a switch that does not fit the reservation is refused and changes nothing; a change that keeps the
 * layout keeps the history; the shutter cannot change.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "render_fixture.h"

#define NCFG 5

static hz_render_opts_t config(int k)
{
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    static const struct { hz_render_mode_t mode; uint32_t w, h, spp; } c[NCFG] = {
        { HZ_MODE_TDENSE, 96, 54, 1 }, { HZ_MODE_TAA, 72, 40, 1 }, { HZ_MODE_FULL, 48, 27, 4 },
        { HZ_MODE_ADAPTIVE, 64, 36, 1 }, { HZ_MODE_TDENSE, 41, 23, 1 },
    };
    o.mode = c[k].mode, o.width = c[k].w, o.height = c[k].h, o.spp = c[k].spp;
    return o;
}

static bool same_image(const hz_image_t *a, const hz_image_t *b)
{
    return a->width == b->width && a->height == b->height &&
           !memcmp(a->rgb, b->rgb, (size_t)a->width * a->height * 3 * sizeof(float));
}

/* A second copy of the scene and its accel: a renderer animates its scene, so two renderers compared frame by
 * frame each need their own. */
typedef struct twin_scene {
    hz_scene_t scene;
    hz_accel_t *accel;
} twin_scene_t;

static void twin_open(rfix_t *f, twin_scene_t *t)
{
    hz_error_t err;
    hz_accel_geom_t g;
    if (hz_scenefile_open("builtin", f->pools, &t->scene, &err) != HZ_OK ||
        hz_accel_geom_from_scene(&g, &t->scene, &f->pools->accel, &err) != HZ_OK ||
        hz_accel_backend_build(HZ_ACCEL_NATIVE, &t->accel, &g, &f->pools->accel, &err) != HZ_OK)
        fail_msg("twin scene: %s", err.msg);
}

/* Frame k of a run: index and scene time. */
static hz_status_t frame(hz_renderer_t *r, uint64_t k, hz_error_t *err)
{
    return hz_render_run_frame(r, k, (float)k / 60.0f, err);
}

static void test_switch_matches_fresh(void **state)
{
    (void)state;
    rfix_t f;
    hz_error_t err;
    if (rfix_open_named(&f, "builtin", &err) != HZ_OK)
        fail_msg("open: %s", err.msg);
    assert_int_equal(hz_threads_start(2, &err), HZ_OK);
    twin_scene_t tw;
    twin_open(&f, &tw);
    size_t reserve = 0;
    for (int k = 0; k < NCFG; k++) {
        hz_render_opts_t o = config(k);
        hz_render_plan_t p;
        assert_int_equal(hz_render_plan(&f.scene, &o, &p, &err), HZ_OK);
        reserve = p.region_bytes > reserve ? p.region_bytes : reserve;
    }
    hz_render_opts_t o0 = config(0);
    o0.reserve_bytes = reserve;
    hz_renderer_t *a;
    if (hz_render_create(&a, &f.scene, f.accel, &o0, &f.pools->frame, f.pools->thread, 2, &err) != HZ_OK)
        fail_msg("create: %s", err.msg);
    uint64_t idx = 0;
    for (int k = 0; k < NCFG; k++) {
        hz_render_opts_t o = config(k);
        if (k > 0 && hz_render_reconfigure(a, &o, &err) != HZ_OK)
            fail_msg("reconfigure to %s %ux%u: %s", hz_render_mode_name(o.mode), o.width, o.height, err.msg);
        /* the oracle: a renderer made for this configuration, rendering the same frames from its first */
        hz_arena_mark_t fm = hz_arena_mark(&f.pools->frame), tm[2];
        for (int t = 0; t < 2; t++)
            tm[t] = hz_arena_mark(&f.pools->thread[t]);
        hz_renderer_t *b;
        if (hz_render_create(&b, &tw.scene, tw.accel, &o, &f.pools->frame, f.pools->thread, 2, &err) != HZ_OK)
            fail_msg("fresh %d: %s", k, err.msg);
        for (int n = 0; n < 5; n++, idx++) {
            assert_int_equal(frame(a, idx, &err), HZ_OK);
            assert_int_equal(frame(b, idx, &err), HZ_OK);
            assert_int_equal(hz_render_output(a)->width, o.width);
            if (!same_image(hz_render_output(a), hz_render_output(b)))
                fail_msg("config %d (%s %ux%u), frame %d after the switch differs from a fresh renderer's", k,
                         hz_render_mode_name(o.mode), o.width, o.height, n);
        }
        hz_arena_reset(&f.pools->frame, fm);
        for (int t = 0; t < 2; t++)
            hz_arena_reset(&f.pools->thread[t], tm[t]);
    }
    hz_accel_release(tw.accel);
    rfix_close(&f);
}

/* Over the reservation: refused with both counts, and the renderer goes on exactly as one never asked. */
static void test_refused_changes_nothing(void **state)
{
    (void)state;
    rfix_t f;
    hz_error_t err;
    if (rfix_open_named(&f, "builtin", &err) != HZ_OK)
        fail_msg("open: %s", err.msg);
    assert_int_equal(hz_threads_start(2, &err), HZ_OK);
    hz_render_opts_t o = config(1), big = o;
    big.width *= 2;
    twin_scene_t tw;
    twin_open(&f, &tw);
    hz_renderer_t *a, *b;
    if (hz_render_create(&a, &f.scene, f.accel, &o, &f.pools->frame, f.pools->thread, 2, &err) != HZ_OK ||
        hz_render_create(&b, &tw.scene, tw.accel, &o, &f.pools->frame, f.pools->thread, 2, &err) != HZ_OK)
        fail_msg("create: %s", err.msg);
    for (uint64_t k = 0; k < 6; k++) {
        if (k == 3) {
            assert_int_equal(hz_render_reconfigure(a, &big, &err), HZ_E_NO_MEMORY);
            assert_non_null(strstr(err.msg, "needs"));
            hz_render_opts_t blur = o;
            blur.shutter = 0.5f;
            assert_int_equal(hz_render_reconfigure(a, &blur, &err), HZ_E_INVALID_ARG);
            hz_render_opts_t bad = o;
            bad.max_bounces = 7;
            assert_int_equal(hz_render_reconfigure(a, &bad, &err), HZ_E_INVALID_ARG);
        }
        assert_int_equal(frame(a, k, &err), HZ_OK);
        assert_int_equal(frame(b, k, &err), HZ_OK);
        assert_true(same_image(hz_render_output(a), hz_render_output(b)));
    }
    hz_accel_release(tw.accel);
    rfix_close(&f);
}

/* A change that keeps the layout keeps the TAA history: the scalar twins and the barrier give the same frames,
 * so switching to them mid-run must give the frames of a run that never switched; a run reset at that frame
 * (what a relayout does) gives other frames, so the check can tell. */
static void test_history_kept(void **state)
{
    (void)state;
    rfix_t f;
    hz_error_t err;
    if (rfix_open_named(&f, "builtin", &err) != HZ_OK)
        fail_msg("open: %s", err.msg);
    assert_int_equal(hz_threads_start(2, &err), HZ_OK);
    hz_render_opts_t o = config(1), twin = o;
    twin.scalar_recon = true, twin.serial_passes = true;
    twin_scene_t tb, tc;
    twin_open(&f, &tb);
    twin_open(&f, &tc);
    hz_renderer_t *a, *b, *c;
    if (hz_render_create(&a, &f.scene, f.accel, &o, &f.pools->frame, f.pools->thread, 2, &err) != HZ_OK ||
        hz_render_create(&b, &tb.scene, tb.accel, &o, &f.pools->frame, f.pools->thread, 2, &err) != HZ_OK ||
        hz_render_create(&c, &tc.scene, tc.accel, &o, &f.pools->frame, f.pools->thread, 2, &err) != HZ_OK)
        fail_msg("create: %s", err.msg);
    bool reset_differs = false;
    for (uint64_t k = 0; k < 8; k++) {
        if (k == 4) {
            assert_int_equal(hz_render_reconfigure(a, &twin, &err), HZ_OK);
            hz_render_reset_history(c);
        }
        assert_int_equal(frame(a, k, &err), HZ_OK);
        assert_int_equal(frame(b, k, &err), HZ_OK);
        assert_int_equal(frame(c, k, &err), HZ_OK);
        assert_true(same_image(hz_render_output(a), hz_render_output(b)));
        reset_differs = reset_differs || !same_image(hz_render_output(b), hz_render_output(c));
    }
    assert_true(reset_differs);
    hz_accel_release(tc.accel);
    hz_accel_release(tb.accel);
    rfix_close(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_switch_matches_fresh),
        cmocka_unit_test(test_refused_changes_nothing),
        cmocka_unit_test(test_history_kept),
    };
    return HZ_RUN(tests);
}
