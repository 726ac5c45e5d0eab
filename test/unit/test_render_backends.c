/* Native BVH against Embree through the whole renderer: on every shared scene (and the built-in one) the two
 * backends give images within PSNR >= 50 dB of each other (issue 5). Host builds only (Embree is not packaged
 * for arm64 here). Time t = 0.5 s so animated scenes are compared after refit (native) / rebuild (Embree).
 * hz-test: embree (needs the Embree backend)
 */
#include "hz_test.h"

#include "render_fixture.h"

static const char *const scenes[] = {
    "CornellBox-Original", "CornellBox-Mirror", "conference", "sponza", "lost-empire", "pine",
    "dragon-res4", "dragon-res3", "dragon-res2", "dragon", "furball", "BoxAnimated", "CesiumMan",
    "AlphaBlendModeTest", NULL,
};

static uint8_t copy_mem[320 * 180 * 12] HZ_ALIGNED(64);

static double compare(const char *scene)
{
    hz_image_t native = { 320, 180, (float *)copy_mem };
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = 320, o.height = 180;
    double psnr = 0;
    for (int b = 0; b < 2; b++) {
        rfix_t f;
        hz_error_t err;
        if (rfix_open(&f, scene, b ? HZ_ACCEL_EMBREE : HZ_ACCEL_NATIVE, &err) != HZ_OK)
            fail_msg("%s: %s", scene, err.msg);
        if (rfix_renderer(&f, &o, 2, &err) != HZ_OK || rfix_frame(&f, 0, 0.5f, &err) != HZ_OK)
            fail_msg("%s: %s", scene, err.msg);
        const hz_image_t *img = hz_render_output(f.r);
        if (b == 0)
            memcpy(native.rgb, img->rgb, sizeof copy_mem);
        else
            psnr = rfix_psnr(&native, img);
        rfix_close(&f);
    }
    return psnr;
}

static void test_backends_agree_on_every_scene(void **state)
{
    (void)state;
    char path[4096], file[256];
    double worst = compare("builtin");
    print_message("%-22s native vs embree: PSNR %.2f dB\n", "builtin", worst);
    assert_true(worst >= 50.0);
    for (int i = 0; scenes[i]; i++) {
        snprintf(file, sizeof file, "%s.hzb", scenes[i]);
        const char *scene = rfix_scene_path(file, path, sizeof path);
        assert_non_null(scene); /* make test exports HZ_SCENES_DIR */
        double p = compare(scene);
        print_message("%-22s native vs embree: PSNR %.2f dB\n", scenes[i], p);
        if (p < worst)
            worst = p;
        assert_true(p >= 50.0);
    }
    print_message("worst: %.2f dB\n", worst);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_backends_agree_on_every_scene),
    };
    return HZ_RUN(tests);
}
