/* TAA earns its keep: on a moving-camera Sponza sequence its frames are closer to the 256-spp reference frames
 * at the same instants than plain 1-spp frames are (issue 5). Host builds only: the 256-spp reference takes
 * seconds natively and minutes under emulation.
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_taa_beats_one_spp_on_sponza),
    };
    return HZ_RUN(tests);
}
