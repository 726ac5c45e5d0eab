/* TAA earns its keep: on a moving-camera Sponza sequence its frames are closer to the 256-spp reference frames
 * at the same instants than plain 1-spp frames are; and under a moving camera TAA with stochastic transparency
 * (std) leaves no 3-pixel dither grid. Host builds only: these sequences take seconds natively and minutes
 * under emulation, and their arithmetic is the same on AArch64 (test_render matches stored images there to
 * ~150 dB; the NEON TAA, dither and traversal kernels are held bit for bit to their scalar twins by cheaper
 * tests that do run under qemu).
 * hz-test: native (native boards only)
 */
#include "hz_test.h"

#include "render_fixture.h"

#define W 96
#define H 54
#define WARMUP 8
#define MEASURED 16
#define HZ 60.0f
#define T0 1.0f /* seconds into the path: the camera sweeps through the nave */

static float refs[MEASURED][W * H * 3];

static double mse(const float *a, const float *b)
{
    double s = 0;
    for (size_t i = 0; i < (size_t)W * H * 3; i++) {
        double x = a[i] < 0 ? 0 : a[i] > 1 ? 1 : a[i];
        double y = b[i] < 0 ? 0 : b[i] > 1 ? 1 : b[i];
        s += (x - y) * (x - y);
    }
    return s / ((double)W * H * 3);
}

/* Mean squared error of a mode's measured frames against the references. */
static double sequence_error(const char *scene, hz_render_mode_t mode, uint32_t spp, bool store_refs)
{
    rfix_t f;
    hz_error_t err;
    if (rfix_open(&f, scene, HZ_ACCEL_NATIVE, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.mode = mode, o.spp = spp;
    if (rfix_renderer(&f, &o, 2, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    double sum = 0;
    for (uint32_t i = 0; i < WARMUP + MEASURED; i++) {
        if (store_refs && i < WARMUP)
            continue; /* the reference has no history: only the measured instants are needed */
        if (rfix_frame(&f, i, T0 + (float)i / HZ, &err) != HZ_OK)
            fail_msg("%s", err.msg);
        if (i < WARMUP)
            continue;
        const float *img = hz_render_output(f.r)->rgb;
        if (store_refs)
            memcpy(refs[i - WARMUP], img, sizeof refs[0]);
        else
            sum += mse(img, refs[i - WARMUP]);
    }
    rfix_close(&f);
    return sum / MEASURED;
}

static void test_taa_beats_one_spp_on_sponza(void **state)
{
    (void)state;
    char path[4096];
    const char *scene = rfix_scene_path("sponza.hzb", path, sizeof path);
    assert_non_null(scene);
    sequence_error(scene, HZ_MODE_FULL, 256, true);
    double one = sequence_error(scene, HZ_MODE_FULL, 1, false);
    double taa = sequence_error(scene, HZ_MODE_TAA, 1, false);
    print_message("Sponza %dx%d, %d frames at %.0f Hz: MSE 1 spp %.6f (PSNR %.2f dB), TAA %.6f (PSNR %.2f dB)\n", W, H,
                  MEASURED, (double)HZ, one, 10 * log10(1 / one), taa, 10 * log10(1 / taa));
    assert_true(taa < one);
}

/* RMS amplitude of the 3-pixel-periodic part of the luminance over the pixels `mask` marks, relative to their
 * mean: the nine phase means (x mod 3, y mod 3) minus their average. It is the image's spectral power at the
 * eight frequencies of period 3 (k/3 cycles per pixel on each axis), which is all a regular 3x3 dither grid
 * can put there. */
static double period3(const float *rgb, uint32_t w, uint32_t h, const uint8_t *mask)
{
    double s[9] = { 0 }, n[9] = { 0 };
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            size_t p = (size_t)y * w + x;
            if (!mask[p])
                continue;
            double l = 0.2126 * rgb[p * 3] + 0.7152 * rgb[p * 3 + 1] + 0.0722 * rgb[p * 3 + 2];
            s[(y % 3) * 3 + x % 3] += l, n[(y % 3) * 3 + x % 3] += 1.0;
        }
    double m[9], mu = 0, v = 0;
    for (int k = 0; k < 9; k++) {
        assert_true(n[k] > 100);
        m[k] = s[k] / n[k], mu += m[k] / 9.0;
    }
    for (int k = 0; k < 9; k++)
        v += (m[k] - mu) * (m[k] - mu) / 9.0;
    return sqrt(v) / mu;
}

/* sponza-smoke with its camera moving through the cloud (TAA, 240 Hz frames from 2 s): std's last frame shows no
 * more of the dither's 3-pixel period than exact's does (measured over the pixels std dithered), and stays
 * close to it. With the history read on motion vectors snapped to the cell and the raw sample blended, std had
 * 2.0x exact's period-3 amplitude at 320x180 and a visible grid. */
static void test_no_grid_moving_camera(void **state)
{
    (void)state;
    enum { PW = 144, PH = 81, FRAMES = 36 };
    char path[4096];
    const char *scene = rfix_scene_path("sponza-smoke.hzb", path, sizeof path);
    assert_non_null(scene);
    float *last[2];
    uint8_t *mask = calloc((size_t)PW * PH, 1);
    assert_non_null(mask);
    rfix_t f;
    hz_error_t err;
    assert_int_equal(rfix_open(&f, scene, HZ_ACCEL_NATIVE, &err), HZ_OK); /* one scene and build, two renderers */
    for (int m = 0; m < 2; m++) {
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = PW, o.height = PH, o.mode = HZ_MODE_TAA, o.transparency = m ? HZ_TRANSP_STD : HZ_TRANSP_EXACT;
        assert_int_equal(rfix_renderer(&f, &o, 2, &err), HZ_OK);
        for (uint32_t i = 0; i < FRAMES; i++)
            assert_int_equal(rfix_frame(&f, i, 2.0f + (float)i / 240.0f, &err), HZ_OK);
        last[m] = malloc((size_t)PW * PH * 3 * sizeof(float));
        assert_non_null(last[m]);
        memcpy(last[m], hz_render_output(f.r)->rgb, (size_t)PW * PH * 3 * sizeof(float));
        if (m) {
            const hz_gbuffer_t *gb = hz_render_gbuffer(f.r);
            for (size_t p = 0; p < (size_t)PW * PH; p++)
                mask[p] = (gb->flags[p] & HZ_GB_DITHER) != 0;
        }
    }
    rfix_close(&f);
    double pe = period3(last[0], PW, PH, mask), ps = period3(last[1], PW, PH, mask);
    double se = 0;
    size_t n = 0;
    for (size_t p = 0; p < (size_t)PW * PH; p++)
        for (int c = 0; mask[p] && c < 3; c++) {
            double x = last[0][p * 3 + c] > 1 ? 1 : last[0][p * 3 + c], y = last[1][p * 3 + c] > 1 ? 1 : last[1][p * 3 + c];
            se += (x - y) * (x - y), n++;
        }
    double db = 10.0 * log10((double)n / se);
    print_message("period-3 amplitude over the dithered pixels: exact %.5f, std %.5f (%.2fx); std vs exact %.1f dB\n",
                  pe, ps, ps / pe, db);
    assert_true(ps < 1.3 * pe);
    assert_true(db > 33.0);
    free(last[0]), free(last[1]), free(mask);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_taa_beats_one_spp_on_sponza),
        cmocka_unit_test(test_no_grid_moving_camera),
    };
    return HZ_RUN(tests);
}
