/* End-to-end tests of --mode adaptive (seed 003, hz/adaptive.h) on the built-in scene (mirrors, cut-outs,
 * blended surfaces, motion) and, where baked, CornellBox-Mirror: the two limits (no subpixel active = the 1-spp
 * image bit for bit; every subpixel active = the 16-spp image, since the 16 sample positions are the full mode's),
 * weights summing to 1, packets full, thread counts agreeing, option checks and the memory plan; on Sponza, the
 * presample's textures over the pixel footprint. */
#include "hz_test.h"

#include "render_fixture.h"
#include "hz/config.h"

/* hz_trace_batch's packet width (render_internal.h) */
#define HZ_RENDER_LANES_TEST (HZ_SIMD_LANES >= 8 ? 8 : 4)

enum { W = 32, H = 24 };

static void open_scene(rfix_t *f, const char *scene, hz_accel_backend_t b)
{
    hz_error_t err;
    if (rfix_open(f, scene, b, &err) != HZ_OK)
        fail_msg("open %s: %s", scene, err.msg);
}

static float *render_copy(rfix_t *f, const hz_render_opts_t *o, int threads, float t, hz_render_stats_t *last)
{
    hz_error_t err;
    if (rfix_renderer(f, o, threads, &err) != HZ_OK)
        fail_msg("renderer: %s", err.msg);
    if (rfix_frame(f, 0, t, &err) != HZ_OK)
        fail_msg("frame: %s", err.msg);
    hz_render_frame_stats(f->r, last, NULL);
    const hz_image_t *img = hz_render_output(f->r);
    size_t n = hz_image_pixels(img) * 3 * sizeof(float);
    float *c = malloc(n);
    assert_non_null(c);
    memcpy(c, img->rgb, n);
    return c;
}

static void all_tau(hz_render_opts_t *o, float t)
{
    for (int k = 0; k < HZ_TAU_COUNT; k++)
        o->adaptive.tau[k] = t;
}

static void test_weights_sum_to_one(void **state)
{
    (void)state;
    for (uint32_t n = 0; n <= 4; n++) {
        float c, s;
        hz_adaptive_weights(n, &c, &s);
        assert_true(fabsf(c + 4.0f * (float)n * s - 1.0f) < 1e-7f); /* centre + 4 samples per active subpixel */
        assert_true(fabsf(s - 1.0f / 16.0f) < 1e-9f);
    }
}

/* The full mode's 1-spp and 16-spp frames at time t (what adaptive equals with nothing and with everything
 * active); o is left at the default options of that size with spp 16. */
static void full_one_and_sixteen(rfix_t *f, hz_render_opts_t *o, uint32_t w, uint32_t h, float t, float **one,
                                 float **sixteen)
{
    hz_render_stats_t st;
    hz_render_opts_default(o);
    o->width = w, o->height = h;
    *one = render_copy(f, o, 2, t, &st);
    o->spp = 16;
    *sixteen = render_copy(f, o, 2, t, &st);
}

static void test_limits(void **state)
{
    (void)state;
    rfix_t f;
    open_scene(&f, "builtin", HZ_ACCEL_NATIVE);
    hz_render_opts_t o;
    hz_render_stats_t st;
    float *one, *sixteen;
    full_one_and_sixteen(&f, &o, W, H, 0.5f, &one, &sixteen);

    /* every threshold 1: nothing is active, the presample is the 1-spp image */
    o.mode = HZ_MODE_ADAPTIVE, o.spp = 1;
    all_tau(&o, 1.0f);
    float *none = render_copy(&f, &o, 2, 0.5f, &st);
    assert_int_equal(st.extra_rays, 0);
    assert_int_equal(st.active_subpixels, 0);
    assert_memory_equal(none, one, (size_t)W * H * 3 * sizeof(float));
    const uint8_t *mask = hz_render_adaptive_mask(f.r);
    assert_non_null(mask);
    for (size_t i = 0; i < (size_t)W * H; i++)
        assert_int_equal(mask[i], 0);

    /* every threshold 0: every subpixel active, 16 extra rays per pixel in full packets, the 16-spp image (up to
     * the order of the float sums) */
    all_tau(&o, 0.0f);
    float *all = render_copy(&f, &o, 2, 0.5f, &st);
    assert_int_equal(st.active_subpixels, 4 * W * H);
    assert_int_equal(st.extra_rays, 16 * W * H);
    assert_int_equal(st.primary_rays, 17 * W * H);
    assert_int_equal(st.extra_packets * HZ_RENDER_LANES_TEST, st.extra_rays);
    double worst = 0;
    for (size_t i = 0; i < (size_t)W * H * 3; i++) {
        double d = fabs((double)all[i] - sixteen[i]) / (fabs((double)sixteen[i]) + 1e-3);
        worst = d > worst ? d : worst;
    }
    assert_true(worst < 1e-4);
    assert_int_equal(st.nonfinite, 0);
    assert_int_equal(st.queue_full, 0);
    free(one), free(sixteen), free(none), free(all);
    rfix_close(&f);
}

static void test_defaults_threads_and_mask(void **state)
{
    (void)state;
    rfix_t f;
    open_scene(&f, "builtin", HZ_ACCEL_NATIVE);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W + 3, o.height = H + 5; /* partial tiles at the right and bottom edges */
    o.mode = HZ_MODE_ADAPTIVE;
    hz_render_stats_t s1, s2;
    float *a = render_copy(&f, &o, 1, 0.75f, &s1);
    size_t px = (size_t)o.width * o.height;
    uint8_t *m1 = malloc(px);
    memcpy(m1, hz_render_adaptive_mask(f.r), px);
    float *b = render_copy(&f, &o, 2, 0.75f, &s2);
    assert_memory_equal(a, b, px * 3 * sizeof(float));
    assert_memory_equal(m1, hz_render_adaptive_mask(f.r), px);
    assert_int_equal(s1.extra_rays, s2.extra_rays);
    /* the counters agree with the mask */
    uint64_t active = 0;
    for (size_t i = 0; i < px; i++)
        active += hz_amask_count(m1[i]);
    assert_int_equal(s1.active_subpixels, active);
    assert_int_equal(s1.extra_rays, 4 * active);
    assert_int_equal(s1.primary_rays, px + 4 * active);
    /* a real scene with edges: some subpixels, not all; packets nearly full (only a tile's last can be
     * partial) */
    assert_true(active > 0 && active < 4 * px);
    assert_true(s1.extra_packets > 0);
    assert_true(s1.extra_rays >= s1.extra_packets * (HZ_RENDER_LANES_TEST - 4));
    assert_int_equal(s1.nonfinite, 0);
    assert_int_equal(s1.queue_full, 0);
    /* pixels with no active subpixel are the presample's: compare with 1 spp */
    hz_render_opts_t f1 = o;
    f1.mode = HZ_MODE_FULL;
    hz_render_stats_t s0;
    float *one = render_copy(&f, &f1, 2, 0.75f, &s0);
    size_t same = 0;
    for (size_t i = 0; i < px; i++)
        if (m1[i] == 0) {
            assert_memory_equal(a + i * 3, one + i * 3, 3 * sizeof(float));
            same++;
        }
    assert_true(same > px / 4);
    free(a), free(b), free(m1), free(one);
    rfix_close(&f);
}

/* Bilinear colour for inactive subpixels (seed 003 section 6, opts.adaptive.bilinear), against an oracle built
 * here from the plain mode's output: a pixel with n active subpixels is centre x (4 - n)/4 + its extra samples /
 * 16 there; with bilinear each inactive subpixel q takes instead the 1-spp image interpolated (in double, edge
 * replicated) at its centre, x 1/4. Pixels with no active subpixel or all four keep their colours bit for bit;
 * the mask, the rays and the thread counts do not change; the option costs a copy of the presample. */
static double bilerp(const float *img, int w, int h, double x, double y, int c)
{
    double fx = x - 0.5, fy = y - 0.5;
    int ix = (int)floor(fx), iy = (int)floor(fy);
    double tx = fx - ix, ty = fy - iy, v[2][2];
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            int xx = ix + i < 0 ? 0 : ix + i >= w ? w - 1 : ix + i;
            int yy = iy + j < 0 ? 0 : iy + j >= h ? h - 1 : iy + j;
            v[j][i] = img[((size_t)yy * (size_t)w + (size_t)xx) * 3 + (size_t)c];
        }
    return (v[0][0] * (1 - tx) + v[0][1] * tx) * (1 - ty) + (v[1][0] * (1 - tx) + v[1][1] * tx) * ty;
}

static void test_bilinear_inactive_subpixels(void **state)
{
    (void)state;
    rfix_t f;
    open_scene(&f, "builtin", HZ_ACCEL_NATIVE);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W + 3, o.height = H + 5;
    const int w = (int)o.width, h = (int)o.height;
    const size_t px = (size_t)w * (size_t)h;
    hz_render_stats_t s0, s1, s2;
    float *one = render_copy(&f, &o, 2, 0.75f, &s0);
    o.mode = HZ_MODE_ADAPTIVE;
    hz_render_plan_t plain_plan, bil_plan;
    hz_error_t err;
    assert_int_equal(hz_render_plan(&f.scene, &o, &plain_plan, &err), HZ_OK);
    float *plain = render_copy(&f, &o, 2, 0.75f, &s1);
    uint8_t *mask = malloc(px);
    memcpy(mask, hz_render_adaptive_mask(f.r), px);
    o.adaptive.bilinear = 1;
    assert_int_equal(hz_render_plan(&f.scene, &o, &bil_plan, &err), HZ_OK);
    assert_true(bil_plan.frame_bytes >= plain_plan.frame_bytes + px * 12);
    float *bil = render_copy(&f, &o, 1, 0.75f, &s2);
    assert_memory_equal(mask, hz_render_adaptive_mask(f.r), px);
    assert_int_equal(s2.extra_rays, s1.extra_rays);
    float *bil2 = render_copy(&f, &o, 2, 0.75f, &s2);
    assert_memory_equal(bil, bil2, px * 3 * sizeof(float));
    size_t partial = 0;
    double worst = 0;
    for (size_t i = 0; i < px; i++) {
        uint32_t n = hz_amask_count(mask[i]);
        if (n == 0 || n == 4) {
            assert_memory_equal(bil + i * 3, plain + i * 3, 3 * sizeof(float));
            continue;
        }
        partial++;
        const int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
        for (int c = 0; c < 3; c++) {
            double want = plain[i * 3 + (size_t)c] - one[i * 3 + (size_t)c] * (4.0 - n) / 4.0;
            for (int q = 0; q < 4; q++)
                if (!(mask[i] & (1u << q)))
                    want += 0.25 * bilerp(one, w, h, x + 0.25 + 0.5 * (q & 1), y + 0.25 + 0.5 * (q >> 1), c);
            want = want > 0 ? want : 0;
            double d = fabs(bil[i * 3 + (size_t)c] - want) / (fabs(want) + 1e-3);
            worst = d > worst ? d : worst;
        }
    }
    print_message("bilinear: %zu partly active pixels of %zu, worst relative difference to the oracle %.2g\n", partial,
                  px, worst);
    assert_true(partial > px / 50);
    assert_true(worst < 1e-4);
    free(one), free(plain), free(mask), free(bil), free(bil2);
    rfix_close(&f);
}

/* Textures over the pixel (opts.adaptive.footprint): no subpixel active gives the filtered presample, which on
 * Sponza's textured walls lies closer to 64 spp (36 under qemu) than the 1-spp image does (the geometry of each
 * pixel's centre sample is the same in both, so the difference is the texture filter); every subpixel active
 * still gives the 16-spp image; one thread and two agree bit for bit. */
static void test_footprint(void **state)
{
    (void)state;
    char path[512];
    if (!rfix_scene_path("sponza.hzb", path, sizeof path))
        fail_msg("HZ_SCENES_DIR is not set (make test sets it)");
    enum { FW = HZ_EMULATED_LESS(96, 48), FH = HZ_EMULATED_LESS(64, 32) }; /* under qemu a quarter of the pixels */
    const size_t n = (size_t)FW * FH * 3;
    rfix_t f;
    open_scene(&f, path, HZ_ACCEL_NATIVE);
    hz_render_opts_t o;
    hz_render_stats_t st;
    float *one, *sixteen;
    full_one_and_sixteen(&f, &o, FW, FH, 1.0f, &one, &sixteen);
    o.spp = HZ_EMULATED_LESS(64, 36);
    float *ref = render_copy(&f, &o, 2, 1.0f, &st);
    o.mode = HZ_MODE_ADAPTIVE, o.spp = 1;
    o.adaptive.footprint = 1;
    all_tau(&o, 1.0f);
    float *none = render_copy(&f, &o, 2, 1.0f, &st);
    float *none1 = render_copy(&f, &o, 1, 1.0f, &st);
    assert_int_equal(st.extra_rays, 0);
    assert_memory_equal(none, none1, n * sizeof(float));
    double e_one = 0, e_foot = 0;
    size_t changed = 0, closer = 0;
    for (size_t i = 0; i < n; i++) {
        double a = fabs((double)one[i] - ref[i]), b = fabs((double)none[i] - ref[i]);
        e_one += a, e_foot += b;
        changed += none[i] != one[i];
        closer += b < a;
    }
    print_message("footprint: %zu of %zu values changed, %zu closer to %u spp; absolute error %.4g (1 spp: %.4g)\n",
                  changed, n, closer, (unsigned)HZ_EMULATED_LESS(64, 36), e_foot, e_one);
    assert_true(changed > n / 2);  /* nearly every Sponza surface is textured */
    assert_true(closer > changed * 6 / 10);
    assert_true(e_foot < e_one); /* the centre samples' edges weigh the same in both */
    all_tau(&o, 0.0f);
    float *all = render_copy(&f, &o, 2, 1.0f, &st);
    assert_int_equal(st.active_subpixels, 4 * FW * FH);
    double worst = 0;
    for (size_t i = 0; i < n; i++) {
        double d = fabs((double)all[i] - sixteen[i]) / (fabs((double)sixteen[i]) + 1e-3);
        worst = d > worst ? d : worst;
    }
    assert_true(worst < 1e-4); /* the presample's weight is 0 */
    free(one), free(sixteen), free(ref), free(none), free(none1), free(all);
    rfix_close(&f);
}

static void test_mirror_scene(void **state)
{
    (void)state;
    char path[512];
    if (!rfix_scene_path("CornellBox-Mirror.hzb", path, sizeof path)) {
        skip();
        return;
    }
    rfix_t f;
    open_scene(&f, path, HZ_ACCEL_NATIVE);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.mode = HZ_MODE_ADAPTIVE;
    hz_render_stats_t st;
    float *def = render_copy(&f, &o, 2, 0.0f, &st);
    uint64_t base = st.extra_rays;
    /* the mirror hit's attributes are compared: object ids of reflected hits at 0 add samples */
    o.adaptive.tau[HZ_TAU_SOID] = 0.0f;
    float *more = render_copy(&f, &o, 2, 0.0f, &st);
    assert_true(st.extra_rays > base);
    /* no texture in the box: the footprint changes nothing */
    o.adaptive.footprint = 1;
    float *foot = render_copy(&f, &o, 2, 0.0f, &st);
    assert_memory_equal(foot, more, (size_t)W * H * 3 * sizeof(float));
    free(foot);
    o.adaptive.footprint = 0;
    hz_render_plan_t plan, full;
    hz_error_t err;
    assert_int_equal(hz_render_plan(&f.scene, &o, &plan, &err), HZ_OK);
    o.mode = HZ_MODE_FULL;
    assert_int_equal(hz_render_plan(&f.scene, &o, &full, &err), HZ_OK);
    assert_int_equal(plan.frame_bytes - full.frame_bytes, hz_adaptive_frame_bytes(W, H, 1));
    assert_int_equal(hz_adaptive_attr_bytes_per_pixel(1), 16); /* half the paper's 32 B/px */
    free(def), free(more);
    rfix_close(&f);
}

#if HZ_HAVE_EMBREE
static void test_embree_backend(void **state)
{
    (void)state;
    float *img[2];
    hz_render_stats_t st[2];
    for (int b = 0; b < 2; b++) {
        rfix_t f;
        open_scene(&f, "builtin", b ? HZ_ACCEL_EMBREE : HZ_ACCEL_NATIVE);
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = W, o.height = H, o.mode = HZ_MODE_ADAPTIVE;
        img[b] = render_copy(&f, &o, 2, 0.25f, &st[b]);
        rfix_close(&f);
    }
    hz_image_t a = { W, H, img[0] }, e = { W, H, img[1] };
    assert_true(rfix_psnr(&a, &e) > 35.0); /* the backends' hits differ in the last bits only */
    assert_true(st[1].extra_rays > 0);
    free(img[0]), free(img[1]);
}
#endif

static void test_option_checks(void **state)
{
    (void)state;
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.mode = HZ_MODE_ADAPTIVE;
    hz_error_t err;
    assert_int_equal(hz_render_opts_check(&o, &err), HZ_OK);
    o.adaptive.tau[HZ_TAU_PSN] = 1.5f;
    assert_int_equal(hz_render_opts_check(&o, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "tau-psn"));
    o.adaptive.tau[HZ_TAU_PSN] = NAN;
    assert_int_equal(hz_render_opts_check(&o, &err), HZ_E_INVALID_ARG);
    o.adaptive.tau[HZ_TAU_PSN] = 0.06f;
    o.adaptive.focus_count = HZ_AMASK_MAX_FOCUS + 1;
    assert_int_equal(hz_render_opts_check(&o, &err), HZ_E_INVALID_ARG);
    /* the focus list is sorted and deduplicated for the mask */
    hz_adaptive_opts_t ao;
    hz_adaptive_opts_default(&ao);
    ao.focus_count = 4;
    ao.focus[0] = 9, ao.focus[1] = 2, ao.focus[2] = 9, ao.focus[3] = 5;
    hz_amask_config_t c;
    assert_int_equal(hz_adaptive_config(&ao, &c, &err), HZ_OK);
    assert_int_equal(c.focus_count, 3);
    assert_int_equal(c.focus[0], 2), assert_int_equal(c.focus[1], 5), assert_int_equal(c.focus[2], 9);
    /* the float defaults become the mask's Table 2 defaults */
    hz_amask_config_t d;
    hz_amask_config_default(&d);
    assert_memory_equal(c.tau, d.tau, sizeof c.tau);
    assert_int_equal(c.normal_cos, d.normal_cos);
    assert_string_equal(hz_render_mode_name(HZ_MODE_ADAPTIVE), "adaptive");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_weights_sum_to_one),
        cmocka_unit_test(test_limits),
        cmocka_unit_test(test_defaults_threads_and_mask),
        cmocka_unit_test(test_bilinear_inactive_subpixels),
        cmocka_unit_test(test_footprint),
        cmocka_unit_test(test_mirror_scene),
#if HZ_HAVE_EMBREE
        cmocka_unit_test(test_embree_backend),
#endif
        cmocka_unit_test(test_option_checks),
    };
    return HZ_RUN(tests);
}
