/* Runtime skinning against the old per-vertex keys on real baked scenes: CesiumMan is baked both ways
 * (CesiumMan.hzb: joints + weights skinned at run time; CesiumMan-keys.hzb: `skinning = keys`, every vertex
 * sampled at 30 frames/s by the baker through assimp in double precision, an independent implementation of the
 * same skinning). The same motion: vertex positions agree at the sampled frames and between them, and rendered
 * frames agree within 45 dB PSNR at several times. The generated long model (tools/gen/skinned_gltf.c:
 * 48 joints, 61,440 triangles, 35 s) is small on disk and in the arena and animates all through its loop.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "render_fixture.h"

#define W 96
#define H 96

static float img_rt[W * H * 3], img_keys[W * H * 3];

static void open_or_fail(rfix_t *f, const char *file)
{
    char path[512];
    hz_error_t err;
    if (!rfix_scene_path(file, path, sizeof path))
        fail_msg("HZ_SCENES_DIR is not set (make test sets it)");
    if (rfix_open_scene(f, path, &err) != HZ_OK)
        fail_msg("%s: %s", file, err.msg);
}

/* Largest distance between the two scenes' vertices after animating both to t, relative to the bounds. */
static double max_rel_diff(hz_scene_t *a, hz_scene_t *b, float t)
{
    hz_scene_animate(a, t);
    hz_scene_animate(b, t);
    const float *lo = a->header->bounds_min, *hi = a->header->bounds_max;
    double diag = sqrt((double)(hi[0] - lo[0]) * (hi[0] - lo[0]) + (double)(hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (double)(hi[2] - lo[2]) * (hi[2] - lo[2]));
    double worst = 0;
    for (uint32_t v = 0; v < a->vertex_count; v++) {
        double d2 = 0;
        for (int c = 0; c < 3; c++) {
            double d = (double)a->pos[v * 4 + c] - b->pos[v * 4 + c];
            d2 += d * d;
        }
        worst = fmax(worst, sqrt(d2));
    }
    return worst / diag;
}

/* Largest coordinate change of any vertex from time t0 to t1. */
static double largest_move(hz_scene_t *s, float t0, float t1)
{
    hz_scene_animate(s, t0);
    hz_scene_animate(s, t1);
    double moved = 0;
    for (uint32_t v = 0; v < s->vertex_count; v++)
        for (int c = 0; c < 3; c++)
            moved = fmax(moved, fabs((double)s->pos[v * 4 + c] - s->prev_pos[v * 4 + c]));
    return moved;
}

static void test_cesiumman_positions_match_keys(void **state)
{
    (void)state;
    rfix_t f;
    open_or_fail(&f, "CesiumMan.hzb");
    char path[512];
    hz_scene_t keys;
    hz_error_t err;
    rfix_scene_path("CesiumMan-keys.hzb", path, sizeof path);
    if (hz_scenefile_open(path, f.pools, &keys, &err) != HZ_OK)
        fail_msg("CesiumMan-keys.hzb: %s", err.msg);
    assert_int_equal(f.scene.objects[0].motion, HZ_MOTION_SKIN);
    assert_int_equal(keys.objects[0].motion, HZ_MOTION_VERTEX);
    assert_int_equal(f.scene.vertex_count, keys.vertex_count);
    assert_true(f.scene.features & HZ_FEAT_SKINNING);
    /* At the baker's frames (k / 30 s) both are exact samples of the same skinning: only float rounding and
     * unorm16 weights differ. Between frames the keys interpolate positions linearly, the runtime interpolates
     * joints (nlerp): a small difference, far below the motion itself. */
    static const float frames[] = { 0.0f, 10.0f / 30.0f, 29.0f / 30.0f, 47.0f / 30.0f };
    for (size_t i = 0; i < HZ_ARRAY_LEN(frames); i++) {
        double d = max_rel_diff(&f.scene, &keys, frames[i]);
        print_message("t = %.4f s (a baked frame): max vertex difference %.2e of the bounds' diagonal\n",
                      (double)frames[i], d);
        assert_true(d < 1e-4);
    }
    static const float between[] = { 0.5f / 30.0f, 0.37f, 1.2345f, 1.9f };
    for (size_t i = 0; i < HZ_ARRAY_LEN(between); i++) {
        double d = max_rel_diff(&f.scene, &keys, between[i]);
        print_message("t = %.4f s (between frames): max vertex difference %.2e\n", (double)between[i], d);
        assert_true(d < 5e-4);
    }
    /* The motion is real: the walker moves by far more than that. */
    double moved = largest_move(&f.scene, 0.0f, 0.5f);
    print_message("largest vertex move from 0 s to 0.5 s: %.3f\n", moved);
    assert_true(moved > 0.05);
    rfix_close(&f);
}

static void render_at(const char *file, float t, float *out)
{
    rfix_t f;
    hz_error_t err;
    char path[512];
    if (!rfix_scene_path(file, path, sizeof path))
        fail_msg("HZ_SCENES_DIR is not set (make test sets it)");
    hz_status_t s = rfix_open(&f, path, HZ_ACCEL_NATIVE, &err);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.mode = HZ_MODE_FULL, o.spp = 1;
    if (s == HZ_OK)
        s = rfix_renderer(&f, &o, 2, &err);
    if (s == HZ_OK)
        s = rfix_frame(&f, 0, t, &err);
    if (s != HZ_OK)
        fail_msg("%s at %.3f s: %s", file, (double)t, err.msg);
    memcpy(out, hz_render_output(f.r)->rgb, sizeof img_rt);
    rfix_close(&f);
}

static double psnr(const float *a, const float *b)
{
    hz_image_t x = { W, H, (float *)a }, y = { W, H, (float *)b };
    return rfix_psnr(&x, &y);
}

static void test_cesiumman_renders_like_keys(void **state)
{
    (void)state;
    static const float times[] = { 0.25f, 0.9f, 1.55f };
    for (size_t i = 0; i < HZ_ARRAY_LEN(times); i++) {
        render_at("CesiumMan.hzb", times[i], img_rt);
        render_at("CesiumMan-keys.hzb", times[i], img_keys);
        double p = psnr(img_rt, img_keys);
        print_message("t = %.2f s: runtime skinning vs per-vertex keys %.1f dB\n", (double)times[i], p);
        assert_true(p >= 45.0);
    }
    /* The comparison can fail: the walker half a step apart is far below 45 dB. */
    render_at("CesiumMan.hzb", 0.25f, img_rt);
    render_at("CesiumMan-keys.hzb", 0.45f, img_keys);
    double p = psnr(img_rt, img_keys);
    print_message("0.25 s vs 0.45 s: %.1f dB\n", p);
    assert_true(p < 45.0);
}

static void test_long_model_is_small_and_moves(void **state)
{
    (void)state;
    rfix_t f;
    open_or_fail(&f, "tentacles.hzb");
    const hz_hzb_header_t *h = f.scene.header;
    print_message("tentacles: %u triangles, %u joints, %.1f s, %llu bytes on disk, %zu bytes of arena\n",
                  h->triangle_count, h->joint_count, (double)h->duration, (unsigned long long)h->file_bytes,
                  f.scene.plan.arena_bytes);
    assert_true(h->triangle_count >= 60000);
    assert_true(h->joint_count >= 40);
    assert_true(h->duration >= 30.0f);
    assert_int_equal(h->vertex_key_count, 0);
    assert_true(h->file_bytes < 20u << 20); /* the bound; per-vertex keys would take about 1 GB */
    assert_true(f.scene.plan.skin_bytes > 0 && f.scene.plan.skin_bytes <= 65536);
    /* Moving at the end of the loop as at its start: the joints' keys cover all 35 s. */
    static const float times[] = { 1.0f, 17.0f, 33.5f };
    for (size_t i = 0; i < HZ_ARRAY_LEN(times); i++) {
        double moved = largest_move(&f.scene, times[i], times[i] + 0.25f);
        print_message("t = %.1f s: largest move in 0.25 s %.3f\n", (double)times[i], moved);
        assert_true(moved > 0.01);
        for (uint32_t v = 0; v < f.scene.vertex_count; v++) {
            const float *n = f.scene.nrm + (size_t)v * 4;
            assert_true(fabs(sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]) - 1.0) < 1e-4);
        }
    }
    rfix_close(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cesiumman_positions_match_keys),
        cmocka_unit_test(test_cesiumman_renders_like_keys),
        cmocka_unit_test(test_long_model_is_small_and_moves),
    };
    return HZ_RUN(tests);
}
