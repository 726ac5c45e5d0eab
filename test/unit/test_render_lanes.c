/* The SIMD reconstruction passes (tdense and TAA resolves in lanes) against their scalar twins
 * (hz_render_opts_t.scalar_recon) inside the real renderer: the same scenes, modes and frames give the same
 * bits in every displayed frame. Sizes leave partial tiles and partial groups of lanes at the right and bottom
 * edges; the camera and objects move; dithered-transparency TAA runs (std, dtaa, rr) take the 7x7 box and the
 * dither cell's mean in lanes.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "render_fixture.h"

#define W 75
#define H 45
#define FRAMES 10

static float frames[FRAMES][W * H * 3];

typedef struct run {
    const char *scene; /* file in $HZ_SCENES_DIR, or "builtin" */
    hz_render_mode_t mode;
    hz_transp_t transparency;
} run_t;

/* Renders FRAMES frames from t = 0.5 s at 60 Hz; with check, compares each with the stored one. */
static void render(const run_t *run, bool scalar, bool check)
{
    rfix_t f;
    hz_error_t err;
    if (rfix_open_named(&f, run->scene, &err) != HZ_OK)
        fail_msg("%s: %s", run->scene, err.msg);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.mode = run->mode, o.transparency = run->transparency;
    o.scalar_recon = scalar;
    if (rfix_renderer(&f, &o, 2, &err) != HZ_OK)
        fail_msg("%s: %s", run->scene, err.msg);
    size_t dither = 0;
    for (uint32_t i = 0; i < FRAMES; i++) {
        if (rfix_frame(&f, i, 0.5f + (float)i / 60.0f, &err) != HZ_OK)
            fail_msg("%s frame %u: %s", run->scene, i, err.msg);
        const hz_image_t *img = hz_render_output(f.r);
        const hz_gbuffer_t *gb = hz_render_gbuffer(f.r);
        for (size_t p = 0; gb->flags && p < (size_t)W * H; p++)
            dither += (gb->flags[p] & HZ_GB_DITHER) != 0;
        if (!check) {
            memcpy(frames[i], img->rgb, sizeof frames[i]);
            continue;
        }
        for (size_t k = 0; k < (size_t)W * H * 3; k++) {
            uint32_t a, b;
            memcpy(&a, &frames[i][k], 4);
            memcpy(&b, &img->rgb[k], 4);
            if (a != b)
                fail_msg("%s %s frame %u pixel (%zu, %zu) channel %zu: lanes %08x, scalar %08x", run->scene,
                         hz_render_mode_name(run->mode), i, k / 3 % W, k / 3 / W, k % 3, a, b);
        }
    }
    if (run->transparency != HZ_TRANSP_EXACT && check)
        assert_true(dither > 0); /* the dithered pixels' path was taken */
    rfix_close(&f);
}

static void test_lanes_match_scalar_in_the_renderer(void **state)
{
    (void)state;
    static const run_t runs[] = {
        { "builtin", HZ_MODE_TDENSE, HZ_TRANSP_EXACT },
        { "builtin", HZ_MODE_TAA, HZ_TRANSP_EXACT },
        { "CesiumMan-small.hzb", HZ_MODE_TAA, HZ_TRANSP_EXACT },
        { "CesiumMan-small.hzb", HZ_MODE_TDENSE, HZ_TRANSP_EXACT },
        { "AlphaBlendModeTest-small.hzb", HZ_MODE_TAA, HZ_TRANSP_STD },
        /* the built-in scene's moving particles: the cell mean over 3x3 (std), 5x5 (dtaa) and none (rr) */
        { "builtin", HZ_MODE_TAA, HZ_TRANSP_STD },
        { "builtin", HZ_MODE_TAA, HZ_TRANSP_DTAA },
        { "builtin", HZ_MODE_TAA, HZ_TRANSP_RR },
    };
    for (size_t i = 0; i < HZ_ARRAY_LEN(runs); i++) {
        render(&runs[i], false, false);
        render(&runs[i], true, true);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lanes_match_scalar_in_the_renderer),
    };
    return HZ_RUN(tests);
}
