/* The SIMD reconstruction passes (tdense and TAA resolves in lanes) against their scalar twins
 * (hz_render_opts_t.scalar_recon), and the packet shading (the kernels, camera hits shaded a packet at once,
 * shadow rays straight from the kernel's lanes) against its twin, the hit-by-hit path through the queues
 * (scalar_shading), inside the real renderer: the same scenes, modes and frames give the same bits in every
 * displayed frame. Sizes leave partial tiles and partial groups of lanes at the right and bottom
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
    bool rr_shadows;
} run_t;

enum { LANES, SCALAR_RECON, SCALAR_SHADING }; /* what render() runs */

/* Renders FRAMES frames from t = 0.5 s at 60 Hz; with check, compares each with the stored one. */
static void render(const run_t *run, int which, bool check)
{
    rfix_t f;
    hz_error_t err;
    if (rfix_open_named(&f, run->scene, &err) != HZ_OK)
        fail_msg("%s: %s", run->scene, err.msg);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.mode = run->mode, o.transparency = run->transparency;
    o.rr_shadows = run->rr_shadows;
    o.scalar_recon = which == SCALAR_RECON;
    o.scalar_shading = which == SCALAR_SHADING;
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
                fail_msg("%s %s frame %u pixel (%zu, %zu) channel %zu: lanes %08x, %s %08x", run->scene,
                         hz_render_mode_name(run->mode), i, k / 3 % W, k / 3 / W, k % 3, a,
                         which == SCALAR_RECON ? "scalar resolve" : "scalar shading", b);
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
        { "builtin", HZ_MODE_TDENSE, HZ_TRANSP_EXACT, false },
        { "builtin", HZ_MODE_TAA, HZ_TRANSP_EXACT, false },
        { "CesiumMan-small.hzb", HZ_MODE_TAA, HZ_TRANSP_EXACT, false },
        { "CesiumMan-small.hzb", HZ_MODE_TDENSE, HZ_TRANSP_EXACT, false },
        { "AlphaBlendModeTest-small.hzb", HZ_MODE_TAA, HZ_TRANSP_STD, false },
        /* the built-in scene's moving particles: the cell mean over 3x3 (std), 5x5 (dtaa) and none (rr) */
        { "builtin", HZ_MODE_TAA, HZ_TRANSP_STD, false },
        { "builtin", HZ_MODE_TAA, HZ_TRANSP_DTAA, false },
        { "builtin", HZ_MODE_TAA, HZ_TRANSP_RR, false },
    };
    for (size_t i = 0; i < HZ_ARRAY_LEN(runs); i++) {
        render(&runs[i], LANES, false);
        render(&runs[i], SCALAR_RECON, true);
    }
}

/* Every kind of hit the packet paths take or leave to the twin: mirrors and their reflected hits (builtin,
 * CornellBox-Mirror), blended layers and their continuation rays (exact), stochastic fragments with deep and
 * roulette shadow rays (std, rr_shadows), cutouts and textures, skinned motion, two lights and one, and the
 * modes that keep depth, normals and shadow counts (full). */
static void test_shading_matches_twin_in_the_renderer(void **state)
{
    (void)state;
    static const run_t runs[] = {
        { "builtin", HZ_MODE_TDENSE, HZ_TRANSP_EXACT, false },
        { "builtin", HZ_MODE_TAA, HZ_TRANSP_STD, false },
        { "builtin", HZ_MODE_TAA, HZ_TRANSP_STD, true },
        { "builtin", HZ_MODE_FULL, HZ_TRANSP_EXACT, false },
        { "CornellBox-Mirror.hzb", HZ_MODE_FULL, HZ_TRANSP_EXACT, false },
        { "CornellBox-Mirror.hzb", HZ_MODE_TAA, HZ_TRANSP_EXACT, false },
        { "CesiumMan-small.hzb", HZ_MODE_TDENSE, HZ_TRANSP_EXACT, false },
        { "AlphaBlendModeTest-small.hzb", HZ_MODE_TAA, HZ_TRANSP_EXACT, false },
        { "AlphaBlendModeTest-small.hzb", HZ_MODE_FULL, HZ_TRANSP_STD, false },
    };
    for (size_t i = 0; i < HZ_ARRAY_LEN(runs); i++) {
        render(&runs[i], LANES, false);
        render(&runs[i], SCALAR_SHADING, true);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lanes_match_scalar_in_the_renderer),
        cmocka_unit_test(test_shading_matches_twin_in_the_renderer),
    };
    return HZ_RUN(tests);
}
