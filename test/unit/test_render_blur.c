/* Motion-blurred rendering (hz/render.h "Motion blur"): shutter 0 is the unblurred renderer byte for byte; a
 * blurred frame converges to the average of instantaneous frames over the shutter (the oracle: 16 unblurred
 * renders at times spread over the shutter); the motion BVHs and Embree give the same image; shadow and mirror
 * rays carry the time of the camera ray they come from; tdense refits once per cycle with cycle keys. The
 * convergence to the shutter average runs on native boards only (HZ_NATIVE_ONLY). Adaptive supersampling
 * under a shutter has the blurred full mode's 1-spp and 16-spp images as its limits.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "blur_setup.h"
#include "render_fixture.h"

#define W 64
#define H 36
#define HZ_RATE 4u     /* a slow display: lots of motion inside one shutter */
#define T0 1.0f

static float img_a[W * H * 3], img_b[W * H * 3], img_c[W * H * 3];
static hz_posekeys_t keys;

/* Opens `scene` and builds the accel for opts (keys when opts->shutter > 0). */
static hz_status_t bopen(rfix_t *f, const char *scene, hz_accel_backend_t backend, hz_accel_blur_t blur,
                         hz_render_opts_t *o, hz_error_t *err)
{
    hz_status_t s = rfix_open_scene(f, scene, err);
    return s == HZ_OK ? hz_blur_build(&f->scene, o, backend, blur, f->pools, &keys, &f->accel, err) : s;
}

static void opts_for(hz_render_opts_t *o, float shutter, uint32_t spp)
{
    hz_render_opts_default(o);
    o->width = W, o->height = H;
    o->mode = HZ_MODE_FULL;
    o->spp = spp;
    o->shutter = shutter;
    o->frame_hz = HZ_RATE;
}

/* One full-mode frame of `scene` at time t into out. */
static void render_one(const char *scene, hz_accel_backend_t backend, hz_accel_blur_t blur, float shutter,
                       uint32_t spp, float t, uint32_t seed, float *out)
{
    rfix_t f;
    hz_error_t err;
    hz_render_opts_t o;
    opts_for(&o, shutter, spp);
    o.seed = seed;
    hz_status_t s = bopen(&f, scene, backend, blur, &o, &err);
    if (s == HZ_OK)
        s = rfix_renderer(&f, &o, 2, &err);
    if (s == HZ_OK)
        s = rfix_frame(&f, 0, t, &err);
    if (s != HZ_OK)
        print_error("%s: %s\n", scene, err.msg);
    assert_int_equal(s, HZ_OK);
    memcpy(out, hz_render_output(f.r)->rgb, sizeof img_a);
    rfix_close(&f);
}

static double psnr(const float *a, const float *b)
{
    hz_image_t x = { W, H, (float *)a }, y = { W, H, (float *)b };
    return rfix_psnr(&x, &y);
}

static void test_shutter_zero_is_the_unblurred_renderer(void **state)
{
    (void)state;
    /* shutter 0 through the blur set-up: no keys, a static accel, the same bytes as the plain fixture. */
    rfix_t f;
    hz_error_t err;
    hz_render_opts_t o;
    opts_for(&o, 0.0f, 4);
    assert_int_equal(bopen(&f, "builtin", HZ_ACCEL_NATIVE, HZ_ACCEL_BLUR_MSBVH, &o, &err), HZ_OK);
    assert_null(o.keys);
    assert_true(f.accel->geom.time_keys <= 1);
    assert_int_equal(rfix_renderer(&f, &o, 2, &err), HZ_OK);
    assert_int_equal(rfix_frame(&f, 0, T0, &err), HZ_OK);
    memcpy(img_a, hz_render_output(f.r)->rgb, sizeof img_a);
    rfix_close(&f);
    assert_int_equal(rfix_open(&f, "builtin", HZ_ACCEL_NATIVE, &err), HZ_OK);
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.spp = 4;
    assert_int_equal(rfix_renderer(&f, &o, 2, &err), HZ_OK);
    assert_int_equal(rfix_frame(&f, 0, T0, &err), HZ_OK);
    assert_memory_equal(img_a, hz_render_output(f.r)->rgb, sizeof img_a);
    rfix_close(&f);
}

/* The oracle: the mean of 16 unblurred 16-spp frames at the midpoints of 16 equal parts of the shutter. */
static void shutter_average(const char *scene, float shutter, float *out)
{
    static float acc[W * H * 3];
    memset(out, 0, sizeof img_a);
    for (int i = 0; i < 16; i++) {
        float dt = ((float)i + 0.5f) / 16.0f * shutter / (float)HZ_RATE - 0.5f * shutter / (float)HZ_RATE;
        render_one(scene, HZ_ACCEL_NATIVE, HZ_ACCEL_BLUR_MSBVH, 0.0f, 16, T0 + dt, 100u + (uint32_t)i, acc);
        for (size_t k = 0; k < W * H * 3; k++)
            out[k] += acc[k] / 16.0f;
    }
}

static void check_backend_converges(hz_accel_backend_t backend, hz_accel_blur_t blur, const char *name)
{
    shutter_average("builtin", 1.0f, img_a);
    render_one("builtin", backend, blur, 1.0f, 64, T0, 0, img_b);
    render_one("builtin", HZ_ACCEL_NATIVE, HZ_ACCEL_BLUR_MSBVH, 0.0f, 64, T0, 0, img_c); /* no blur */
    double blurred = psnr(img_b, img_a), sharp = psnr(img_c, img_a);
    print_message("%s: 64 spp blurred vs shutter average %.2f dB, unblurred vs it %.2f dB\n", name, blurred, sharp);
    /* The blurred frame is the shutter average up to sampling noise; the unblurred one is visibly not. */
    assert_true(blurred >= 42.0);
    assert_true(blurred >= sharp + 4.0);
}

static void test_blur_converges_to_the_shutter_average(void **state)
{
    (void)state;
    /* 17 renders of 64 spp, about two minutes under qemu; the motion kernels' NEON paths meet the same rays in
     * test_bvhs_agree and test_accel_motion */
    HZ_NATIVE_ONLY("the shutter-average oracle is the same arithmetic on every ISA");
#if HZ_HAVE_EMBREE
    check_backend_converges(HZ_ACCEL_EMBREE, HZ_ACCEL_BLUR_MSBVH, "embree");
#endif
    check_backend_converges(HZ_ACCEL_NATIVE, HZ_ACCEL_BLUR_MSBVH, "msbvh");
}

/* Adaptive supersampling under a shutter (each extra sample at its own time, the stratum of its 4x4 cell): its
 * two limits are the blurred full mode's images, as without blur. Every threshold 1: the presample alone, the
 * blurred 1-spp image bit for bit; every threshold 0: the 16 extra samples take the full mode's 16 positions and
 * times, so the blurred 16-spp image up to the order of the float sums. And the blur shows: the tau-0 image is
 * far from the unblurred 16-spp one. */
static void adaptive_blurred(float shutter, uint32_t spp, hz_render_mode_t mode, float tau, float *out,
                             hz_render_stats_t *st)
{
    rfix_t f;
    hz_error_t err;
    hz_render_opts_t o;
    opts_for(&o, shutter, spp);
    o.mode = mode;
    for (int k = 0; k < HZ_TAU_COUNT; k++)
        o.adaptive.tau[k] = tau;
    hz_status_t s = bopen(&f, "builtin", HZ_ACCEL_NATIVE, HZ_ACCEL_BLUR_MSBVH, &o, &err);
    if (s == HZ_OK)
        s = rfix_renderer(&f, &o, 2, &err);
    if (s == HZ_OK)
        s = rfix_frame(&f, 0, T0, &err);
    if (s != HZ_OK)
        print_error("builtin %s shutter %g: %s\n", hz_render_mode_name(mode), (double)shutter, err.msg);
    assert_int_equal(s, HZ_OK);
    hz_render_frame_stats(f.r, st, NULL);
    memcpy(out, hz_render_output(f.r)->rgb, sizeof img_a);
    rfix_close(&f);
}

static void test_adaptive_blur_limits(void **state)
{
    (void)state;
    static float one[W * H * 3], sixteen[W * H * 3], sharp[W * H * 3];
    hz_render_stats_t st;
    adaptive_blurred(1.0f, 1, HZ_MODE_FULL, 0.6f, one, &st);
    adaptive_blurred(1.0f, 16, HZ_MODE_FULL, 0.6f, sixteen, &st);
    adaptive_blurred(0.0f, 16, HZ_MODE_FULL, 0.6f, sharp, &st);
    adaptive_blurred(1.0f, 1, HZ_MODE_ADAPTIVE, 1.0f, img_a, &st);
    assert_int_equal(st.extra_rays, 0);
    assert_memory_equal(img_a, one, sizeof img_a);
    adaptive_blurred(1.0f, 1, HZ_MODE_ADAPTIVE, 0.0f, img_b, &st);
    assert_int_equal(st.extra_rays, 16 * W * H);
    double worst = 0;
    for (size_t i = 0; i < (size_t)W * H * 3; i++) {
        double d = fabs((double)img_b[i] - sixteen[i]) / (fabs((double)sixteen[i]) + 1e-3);
        worst = d > worst ? d : worst;
    }
    double to_sharp = psnr(img_b, sharp), to_blurred = psnr(img_b, sixteen);
    print_message("adaptive tau 0 under shutter 1: worst relative difference to blurred 16 spp %.2g; %.2f dB from "
                  "it, %.2f dB from the unblurred 16 spp\n", worst, to_blurred, to_sharp);
    assert_true(worst < 1e-4);
    assert_true(to_sharp < 40.0); /* the built-in scene's object moves: blur is visible at this rate */
    /* the default thresholds: between the limits, extra rays where neighbours differ */
    adaptive_blurred(1.0f, 1, HZ_MODE_ADAPTIVE, 0.06f, img_c, &st);
    assert_true(st.extra_rays > 0 && st.extra_rays < 16 * W * H);
    assert_int_equal(st.nonfinite, 0);
    print_message("adaptive tau 0.06 under shutter 1: %.2f dB from blurred 16 spp (1 spp: %.2f dB), %llu extra "
                  "rays\n", psnr(img_c, sixteen), psnr(one, sixteen), (unsigned long long)st.extra_rays);
    assert_true(psnr(img_c, sixteen) > psnr(one, sixteen));
}

static void test_bvhs_agree(void **state)
{
    (void)state;
    /* Full mode, shutter 1, 64 spp (16 under qemu): the same rays at the same times, so the images agree up to
     * hit rounding. */
    const uint32_t spp = HZ_EMULATED_LESS(64u, 16u);
    render_one("builtin", HZ_ACCEL_NATIVE, HZ_ACCEL_BLUR_MSBVH, 1.0f, spp, T0, 0, img_a);
    render_one("builtin", HZ_ACCEL_NATIVE, HZ_ACCEL_BLUR_INTERP, 1.0f, spp, T0, 0, img_b);
    double pi = psnr(img_a, img_b);
    print_message("msbvh vs interp %.2f dB\n", pi);
    assert_true(pi >= 45.0);
    render_one("builtin", HZ_ACCEL_NATIVE, HZ_ACCEL_BLUR_SWEPT, 1.0f, spp, T0, 0, img_b);
    double ps = psnr(img_a, img_b);
    print_message("msbvh vs swept %.2f dB\n", ps);
    assert_true(ps >= 45.0);
#if HZ_HAVE_EMBREE
    render_one("builtin", HZ_ACCEL_EMBREE, HZ_ACCEL_BLUR_MSBVH, 1.0f, spp, T0, 0, img_b);
    double pe = psnr(img_a, img_b);
    print_message("msbvh vs embree %.2f dB\n", pe);
    assert_true(pe >= 45.0);
#endif
}

/* ---- time inheritance: an accel wrapper records every ray's time ---- */
#define REC_MAX (1u << 20)
static float rec_primary[REC_MAX], rec_other[REC_MAX];
static uint32_t n_primary, n_other, n_shadow;
static const hz_accel_t *real;

static void rec(const int32_t *valid, const float *time, int lanes, bool primary)
{
    for (int i = 0; i < lanes; i++) {
        if (!valid[i])
            continue;
        if (primary && n_primary < REC_MAX)
            rec_primary[n_primary++] = time[i];
        else if (!primary && n_other < REC_MAX)
            rec_other[n_other++] = time[i];
    }
}

static void w_i1(const hz_accel_t *a, hz_accel_ctx_t *c, hz_rayhit_t *rh)
{
    (void)a;
    rec((const int32_t[]){ -1 }, &rh->ray.time, 1, false);
    real->ops->intersect1(real, c, rh);
}
static void w_o1(const hz_accel_t *a, hz_accel_ctx_t *c, hz_ray_t *r)
{
    (void)a;
    rec((const int32_t[]){ -1 }, &r->time, 1, false);
    n_shadow++;
    real->ops->occluded1(real, c, r);
}
static void w_i4(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_rayhit4_t *rh)
{
    (void)a;
    rec(v, rh->ray.time, 4, false);
    real->ops->intersect4(v, real, c, rh);
}
static void w_o4(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_ray4_t *r)
{
    (void)a;
    rec(v, r->time, 4, false);
    n_shadow++;
    real->ops->occluded4(v, real, c, r);
}
static void w_i8(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_rayhit8_t *rh)
{
    (void)a;
    rec(v, rh->ray.time, 8, false);
    real->ops->intersect8(v, real, c, rh);
}
/* Camera rays come as a batch of packets (one tile), everything they spawn a packet at a time. */
static void w_i8n(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_rayhit8_t *rh, uint32_t n)
{
    (void)a;
    for (uint32_t p = 0; p < n; p++)
        rec(v + 8 * p, rh[p].ray.time, 8, true);
    hz_accel_intersect8n(v, real, c, rh, n);
}
static void w_i4n(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_rayhit4_t *rh, uint32_t n)
{
    (void)a;
    for (uint32_t p = 0; p < n; p++)
        rec(v + 4 * p, rh[p].ray.time, 4, true);
    hz_accel_intersect4n(v, real, c, rh, n);
}
static void w_o8(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_ray8_t *r)
{
    (void)a;
    rec(v, r->time, 8, false);
    n_shadow++;
    real->ops->occluded8(v, real, c, r);
}
static hz_status_t w_refit(hz_accel_t *a, hz_error_t *err)
{
    (void)a;
    return real->ops->refit((hz_accel_t *)real, err);
}
static const hz_accel_ops_t wrap_ops = { w_i1, w_o1, w_i4, w_o4, w_i8, w_o8, w_refit, NULL, w_i8n, NULL, w_i4n, NULL };

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

static void test_secondary_rays_inherit_time(void **state)
{
    (void)state;
    rfix_t f;
    hz_error_t err;
    hz_render_opts_t o;
    opts_for(&o, 1.0f, 1);
    assert_int_equal(bopen(&f, "builtin", HZ_ACCEL_NATIVE, HZ_ACCEL_BLUR_MSBVH, &o, &err), HZ_OK);
    assert_non_null(o.keys);
    hz_accel_t wrapped = *f.accel;
    wrapped.ops = &wrap_ops;
    real = f.accel;
    hz_threads_stop();
    assert_int_equal(hz_threads_start(1, &err), HZ_OK);
    assert_int_equal(hz_render_create(&f.r, &f.scene, &wrapped, &o, &f.pools->frame, f.pools->thread, 1, &err),
                     HZ_OK);
    n_primary = n_other = n_shadow = 0;
    assert_int_equal(rfix_frame(&f, 0, T0, &err), HZ_OK);
    rfix_close(&f);
    /* Camera rays: one per pixel, times spread over the whole shutter. */
    assert_int_equal(n_primary, W * H);
    qsort(rec_primary, n_primary, sizeof(float), cmp_float);
    assert_true(rec_primary[0] >= 0.0f && rec_primary[0] < 0.01f);
    assert_true(rec_primary[n_primary - 1] < 1.0f && rec_primary[n_primary - 1] > 0.99f);
    /* Shadow, mirror and continuation rays: many, each at the time of some camera ray. */
    assert_true(n_shadow > 0 && n_other > W * H);
    uint32_t distinct = 0;
    for (uint32_t i = 0; i < n_other; i++) {
        float *hit = bsearch(&rec_other[i], rec_primary, n_primary, sizeof(float), cmp_float);
        assert_non_null(hit);
        distinct += i == 0 || rec_other[i] != rec_other[i - 1];
    }
    assert_true(distinct > W * H / 4);
}

static void test_tdense_refits_once_per_cycle(void **state)
{
    (void)state;
    float out[2][W * H * 3];
    uint64_t refits[2];
    for (int cyc = 0; cyc < 2; cyc++) {
        rfix_t f;
        hz_error_t err;
        hz_render_opts_t o;
        opts_for(&o, 0.5f, 1);
        o.mode = HZ_MODE_TDENSE;
        o.frame_hz = 240;
        o.tdense_cycle_keys = cyc == 1;
        assert_int_equal(bopen(&f, "builtin", HZ_ACCEL_NATIVE, HZ_ACCEL_BLUR_MSBVH, &o, &err), HZ_OK);
        assert_int_equal(rfix_renderer(&f, &o, 2, &err), HZ_OK);
        for (uint32_t i = 0; i < 8; i++)
            assert_int_equal(rfix_frame(&f, i, T0 + (float)i / 240.0f, &err), HZ_OK);
        hz_render_stats_t total;
        hz_render_frame_stats(f.r, NULL, &total);
        refits[cyc] = total.refits;
        memcpy(out[cyc], hz_render_output(f.r)->rgb, sizeof out[cyc]);
        rfix_close(&f);
    }
    assert_int_equal(refits[0], 8);
    assert_int_equal(refits[1], 2);
    double p = psnr(out[0], out[1]);
    print_message("tdense, keys per subframe vs per cycle: %.2f dB\n", p);
    assert_true(p >= 40.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shutter_zero_is_the_unblurred_renderer),
        cmocka_unit_test(test_blur_converges_to_the_shutter_average),
        cmocka_unit_test(test_bvhs_agree),
        cmocka_unit_test(test_adaptive_blur_limits),
        cmocka_unit_test(test_secondary_rays_inherit_time),
        cmocka_unit_test(test_tdense_refits_once_per_cycle),
    };
    return HZ_RUN(tests);
}
