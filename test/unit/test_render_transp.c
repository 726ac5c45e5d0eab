/* Stochastic transparency in the renderer (seed 004; src/render/transp.c, hz/dither.h): the stage is left out
 * for scenes without blended surfaces (identical images, memory and ray counts to exact, no opacity mask);
 * hybrid:0 is exact and hybrid:1 is std by definition; the opacity mask marks dithered pixels only; every
 * stochastic method's temporal average converges to the exact composite (the dither strata of STD and DTAA
 * cover alpha exactly over their periods, so their averages get much closer than Russian roulette's); std + TAA
 * on a still view approaches exact + TAA; stochastic rays trace fewer continuation rays.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "render_fixture.h"
#include "../../src/render/render_internal.h" /* hz_transp_maps */

#define W 64
#define H 48

typedef struct run {
    float *rgb;            /* W * H * 3: the mean over the frames */
    uint8_t flags_or;      /* G-buffer flags of every pixel of the last frame, or'ed */
    uint8_t *dithered;     /* W * H: the pixel had HZ_GB_DITHER in some frame */
    hz_render_stats_t total;
    size_t frame_bytes;
} run_t;

static bool g_rr_shadows; /* render() with opts.rr_shadows */
static bool g_no_bounds;  /* render() without the materials' opacity bounds (every layer's opacity taken) */

/* Renders `frames` frames of a still view (scene time t, frame index 0..frames-1) with a renderer made on the
 * open fixture f, and averages them. */
static void render_on(rfix_t *f, hz_render_mode_t mode, uint32_t spp, hz_transp_t t, float x, uint32_t frames,
                      float time, run_t *out)
{
    hz_error_t err;
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.mode = mode, o.spp = spp, o.transparency = t, o.hybrid_x = x;
    o.rr_shadows = g_rr_shadows;
    hz_render_plan_t plan;
    assert_int_equal(hz_render_plan(&f->scene, &o, &plan, &err), HZ_OK);
    out->frame_bytes = plan.frame_bytes;
    assert_int_equal(rfix_renderer(f, &o, 2, &err), HZ_OK);
    if (g_no_bounds)
        f->r->blend_bound = NULL;
    out->rgb = calloc((size_t)W * H * 3, sizeof(float));
    out->dithered = calloc((size_t)W * H, 1);
    assert_non_null(out->rgb);
    assert_non_null(out->dithered);
    const hz_gbuffer_t *gb = hz_render_gbuffer(f->r);
    for (uint32_t i = 0; i < frames; i++) {
        assert_int_equal(rfix_frame(f, i, time, &err), HZ_OK);
        const hz_image_t *img = hz_render_output(f->r);
        for (size_t k = 0; k < (size_t)W * H * 3; k++)
            out->rgb[k] += img->rgb[k] / (float)frames;
        for (size_t p = 0; p < (size_t)W * H; p++)
            out->dithered[p] |= (gb->flags[p] & HZ_GB_DITHER) != 0;
    }
    out->flags_or = 0;
    for (size_t p = 0; p < (size_t)W * H; p++)
        out->flags_or |= gb->flags[p];
    hz_render_frame_stats(f->r, NULL, &out->total);
}

/* render_on with a fixture of its own. */
static void render(const char *scene, hz_render_mode_t mode, uint32_t spp, hz_transp_t t, float x, uint32_t frames,
                   float time, run_t *out)
{
    rfix_t f;
    hz_error_t err;
    assert_int_equal(rfix_open(&f, scene, HZ_ACCEL_NATIVE, &err), HZ_OK);
    render_on(&f, mode, spp, t, x, frames, time, out);
    rfix_close(&f);
}

/* PSNR over the pixels `mask` marks (the dithered ones: elsewhere every method is exact). */
static double psnr_masked(const float *a, const float *b, const uint8_t *mask)
{
    double se = 0;
    size_t n = 0;
    for (size_t p = 0; p < (size_t)W * H; p++)
        if (mask[p])
            for (int c = 0; c < 3; c++) {
                double x = a[p * 3 + c] < 0 ? 0 : a[p * 3 + c] > 1 ? 1 : a[p * 3 + c];
                double y = b[p * 3 + c] < 0 ? 0 : b[p * 3 + c] > 1 ? 1 : b[p * 3 + c];
                se += (x - y) * (x - y), n++;
            }
    assert_true(n > 300); /* the panels cover a real part of the view */
    return se == 0 ? INFINITY : 10.0 * log10((double)n / se);
}

static void run_free(run_t *r)
{
    free(r->rgb);
    free(r->dithered);
}

static bool same(const run_t *a, const run_t *b)
{
    return !memcmp(a->rgb, b->rgb, (size_t)W * H * 3 * sizeof(float));
}

static const char *scene_path(const char *file, char *buf, size_t n)
{
    const char *p = rfix_scene_path(file, buf, n);
    if (!p)
        fail_msg("HZ_SCENES_DIR is not set (make test sets it)");
    return p;
}

/* CornellBox-Original blends nothing: every method is the exact renderer, with the same memory. */
static void test_left_out_without_blend(void **state)
{
    (void)state;
    char path[4096];
    const char *scene = scene_path("CornellBox-Original.hzb", path, sizeof path);
    static const hz_render_mode_t modes[2] = { HZ_MODE_FULL, HZ_MODE_TAA };
    for (int m = 0; m < 2; m++) {
        run_t ex;
        render(scene, modes[m], 1, HZ_TRANSP_EXACT, 0.0f, 3, 0.0f, &ex);
        for (int t = HZ_TRANSP_RR; t < HZ_TRANSP_COUNT; t++) {
            run_t r;
            render(scene, modes[m], 1, (hz_transp_t)t, 0.75f, 3, 0.0f, &r);
            assert_true(same(&ex, &r));
            assert_int_equal(r.frame_bytes, ex.frame_bytes);
            assert_int_equal(r.total.primary_rays + r.total.shadow_rays + r.total.secondary_rays,
                             ex.total.primary_rays + ex.total.shadow_rays + ex.total.secondary_rays);
            assert_false(r.flags_or & HZ_GB_DITHER);
            run_free(&r);
        }
        run_free(&ex);
    }
}

static void test_hybrid_ends_and_mask(void **state)
{
    (void)state;
    char path[4096];
    const char *scene = scene_path("AlphaBlendModeTest-small.hzb", path, sizeof path);
    run_t ex, h0, st, h1, h5;
    render(scene, HZ_MODE_TAA, 1, HZ_TRANSP_EXACT, 0.0f, 4, 0.0f, &ex);
    render(scene, HZ_MODE_TAA, 1, HZ_TRANSP_HYBRID, 0.0f, 4, 0.0f, &h0);
    render(scene, HZ_MODE_TAA, 1, HZ_TRANSP_STD, 0.0f, 4, 0.0f, &st);
    render(scene, HZ_MODE_TAA, 1, HZ_TRANSP_HYBRID, 1.0f, 4, 0.0f, &h1);
    render(scene, HZ_MODE_TAA, 1, HZ_TRANSP_HYBRID, 0.5f, 4, 0.0f, &h5);
    assert_true(same(&ex, &h0));
    assert_true(same(&st, &h1));
    assert_false(same(&ex, &st));
    /* The opacity mask: set where std dithered, never with exact. */
    assert_false(ex.flags_or & HZ_GB_DITHER);
    assert_true(st.flags_or & HZ_GB_DITHER);
    /* Continuations through the blended panels are what the stochastic method saves. */
    assert_true(st.total.secondary_rays < ex.total.secondary_rays);
    assert_true(h5.total.secondary_rays <= ex.total.secondary_rays);
    run_free(&ex), run_free(&h0), run_free(&st), run_free(&h1), run_free(&h5);
}

/* Averages over the dither periods converge to the exact composite (full mode, 1 spp, still view). */
static void test_temporal_average_converges(void **state)
{
    (void)state;
    char path[4096];
    const char *scene = scene_path("AlphaBlendModeTest-small.hzb", path, sizeof path);
    run_t ex, one, st, rr, dt, ds, hy;
    render(scene, HZ_MODE_FULL, 1, HZ_TRANSP_EXACT, 0.0f, 1, 0.0f, &ex);
    render(scene, HZ_MODE_FULL, 1, HZ_TRANSP_STD, 0.0f, 1, 0.0f, &one);
    render(scene, HZ_MODE_FULL, 1, HZ_TRANSP_STD, 0.0f, 18, 0.0f, &st);
    render(scene, HZ_MODE_FULL, 1, HZ_TRANSP_RR, 0.0f, 18, 0.0f, &rr);
    render(scene, HZ_MODE_FULL, 1, HZ_TRANSP_DTAA, 0.0f, 10, 0.0f, &dt);
    render(scene, HZ_MODE_FULL, 1, HZ_TRANSP_DTAA_STAR, 0.0f, 10, 0.0f, &ds);
    render(scene, HZ_MODE_FULL, 1, HZ_TRANSP_HYBRID, 0.5f, 18, 0.0f, &hy);
    run_t rs;
    g_rr_shadows = true;
    render(scene, HZ_MODE_FULL, 1, HZ_TRANSP_STD, 0.0f, 18, 0.0f, &rs);
    g_rr_shadows = false;
    const uint8_t *m = st.dithered;
    double p1 = psnr_masked(ex.rgb, one.rgb, m), ps = psnr_masked(ex.rgb, st.rgb, m),
           pr = psnr_masked(ex.rgb, rr.rgb, m), pd = psnr_masked(ex.rgb, dt.rgb, m),
           pds = psnr_masked(ex.rgb, ds.rgb, m), ph = psnr_masked(ex.rgb, hy.rgb, m),
           prs = psnr_masked(ex.rgb, rs.rgb, m);
    print_message("PSNR vs exact: std 1 frame %.1f dB, std 18 %.1f, rr 18 %.1f, dtaa 10 %.1f, dtaa* 10 %.1f, "
                  "hybrid:0.5 18 %.1f, std + rr shadows 18 %.1f\n", p1, ps, pr, pd, pds, ph, prs);
    assert_true(ps > p1 + 10.0);
    assert_true(ps > 35.0);
    assert_true(pd > 35.0 && pds > 35.0);
    assert_true(pr > p1 + 5.0);
    assert_true(ps > pr + 3.0); /* stratified beats white noise at the same frame count */
    assert_true(ph > ps - 1.0);
    assert_true(prs > p1 + 5.0); /* roulette shadows converge too, more slowly */
    run_free(&rs);
    run_free(&ex), run_free(&one), run_free(&st), run_free(&rr), run_free(&dt), run_free(&ds), run_free(&hy);
}

/* Full mode with N spp walks N steps of the dither within the frame: std at 9 spp is close to exact at 9. */
static void test_full_spp_walks_the_dither(void **state)
{
    (void)state;
    char path[4096];
    const char *scene = scene_path("AlphaBlendModeTest-small.hzb", path, sizeof path);
    run_t ex, st1, st9;
    render(scene, HZ_MODE_FULL, 9, HZ_TRANSP_EXACT, 0.0f, 1, 0.0f, &ex);
    render(scene, HZ_MODE_FULL, 1, HZ_TRANSP_STD, 0.0f, 1, 0.0f, &st1);
    render(scene, HZ_MODE_FULL, 9, HZ_TRANSP_STD, 0.0f, 1, 0.0f, &st9);
    double p1 = psnr_masked(ex.rgb, st1.rgb, st9.dithered), p9 = psnr_masked(ex.rgb, st9.rgb, st9.dithered);
    print_message("PSNR vs exact 9 spp: std 1 spp %.1f dB, std 9 spp %.1f dB\n", p1, p9);
    assert_true(p9 > p1 + 8.0);
    run_free(&ex), run_free(&st1), run_free(&st9);
}

/* TAA on a still view accumulates std towards exact + TAA (7x7 window and no object-id resets where dithered). */
static void test_taa_accumulates(void **state)
{
    (void)state;
    char path[4096];
    const char *scene = scene_path("AlphaBlendModeTest-small.hzb", path, sizeof path);
    run_t ex, st, one;
    /* The last frame of each: averaging 1 frame = the frame itself. */
    rfix_t f;
    hz_error_t err;
    float *last[2];
    for (int m = 0; m < 2; m++) {
        assert_int_equal(rfix_open(&f, scene, HZ_ACCEL_NATIVE, &err), HZ_OK);
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = W, o.height = H, o.mode = HZ_MODE_TAA, o.transparency = m ? HZ_TRANSP_STD : HZ_TRANSP_EXACT;
        assert_int_equal(rfix_renderer(&f, &o, 2, &err), HZ_OK);
        for (uint32_t i = 0; i < 60; i++)
            assert_int_equal(rfix_frame(&f, i, 0.0f, &err), HZ_OK);
        last[m] = malloc((size_t)W * H * 3 * sizeof(float));
        memcpy(last[m], hz_render_output(f.r)->rgb, (size_t)W * H * 3 * sizeof(float));
        rfix_close(&f);
    }
    ex.rgb = last[0], st.rgb = last[1];
    render(scene, HZ_MODE_TAA, 1, HZ_TRANSP_STD, 0.0f, 1, 0.0f, &one);
    double p = psnr_masked(ex.rgb, st.rgb, one.dithered), p1 = psnr_masked(ex.rgb, one.rgb, one.dithered);
    print_message("PSNR vs exact + TAA after 60 frames: std + TAA %.1f dB (first frame %.1f dB)\n", p, p1);
    assert_true(p > p1 + 6.0);
    assert_true(p > 28.0);
    free(last[0]), free(last[1]);
    run_free(&one);
}

/* Dither maps per particle: each quad written with vertices of its own gets its own maps (both of its
 * triangles the same), a mesh sharing vertices keeps one, an object boundary starts a new group. */
static void test_maps_per_particle(void **state)
{
    (void)state;
    enum { QUADS = 40, STRIP = 12 };
    static uint32_t tri[(2 * QUADS + STRIP + 2) * 3], info[2 * QUADS + STRIP + 2], maps[2 * QUADS + STRIP + 2];
    uint32_t n = 0;
    for (uint32_t q = 0; q < QUADS; q++) { /* one object: particle quads, vertices 4q..4q+3 */
        const uint32_t v = 4 * q;
        const uint32_t t2[6] = { v, v + 1, v + 2, v + 2, v + 1, v + 3 }; /* the second triangle's lowest is v + 1 */
        for (int k = 0; k < 6; k++)
            tri[n * 3 + (uint32_t)k] = t2[k];
        info[n] = info[n + 1] = 5u << 16;
        n += 2;
    }
    const uint32_t s0 = n, base = 4 * QUADS;
    for (uint32_t i = 0; i < STRIP; i++) { /* one object: a strip, each triangle sharing two vertices */
        tri[n * 3] = base + i, tri[n * 3 + 1] = base + i + 1, tri[n * 3 + 2] = base + i + 2;
        info[n++] = 6u << 16;
    }
    /* the next object reuses the strip's last vertices: a new group all the same */
    tri[n * 3] = base + STRIP - 1, tri[n * 3 + 1] = base + STRIP, tri[n * 3 + 2] = base + STRIP + 1;
    info[n++] = 7u << 16;
    hz_scene_t sc;
    memset(&sc, 0, sizeof sc);
    sc.tri = tri, sc.tri_info = info, sc.triangle_count = n;
    hz_transp_maps(&sc, maps);
    uint32_t distinct_std = 0;
    for (uint32_t q = 0; q < QUADS; q++) {
        assert_int_equal(maps[2 * q], maps[2 * q + 1]);
        assert_true(HZ_TRANSP_MAPS_STD(maps[2 * q], 0) < HZ_DITHER_MAPS && HZ_TRANSP_MAPS_STD(maps[2 * q], 1) < HZ_DITHER_MAPS);
        assert_true(HZ_TRANSP_MAPS_PERM(maps[2 * q], 0) < HZ_DITHER_DTAA_PERMS &&
                    HZ_TRANSP_MAPS_PERM(maps[2 * q], 1) < HZ_DITHER_DTAA_PERMS);
        /* the maps are those of the group's key: the object's for its first group, else its first triangle's */
        const uint32_t key = q ? 0x10000u + 2 * q : 5u;
        assert_int_equal(HZ_TRANSP_MAPS_STD(maps[2 * q], 1), hz_dither_map_index(key, 1));
        assert_int_equal(HZ_TRANSP_MAPS_PERM(maps[2 * q], 0), hz_dither_dtaa_perm(key, 0));
        if (q && HZ_TRANSP_MAPS_STD(maps[2 * q], 0) != HZ_TRANSP_MAPS_STD(maps[2 * q - 2], 0))
            distinct_std++;
    }
    assert_true(distinct_std > QUADS * 9 / 10); /* neighbours differ but for the odd hash collision */
    for (uint32_t i = 1; i < STRIP; i++)
        assert_int_equal(maps[s0 + i], maps[s0]);
    assert_int_equal(HZ_TRANSP_MAPS_STD(maps[s0], 0), hz_dither_map_index(6, 0)); /* one group: the object's maps */
    assert_int_not_equal(maps[s0], maps[2 * QUADS - 1]);
    assert_int_not_equal(maps[n - 1], maps[s0]);
}

/* A material's opacity bound (hz_transp_bounds) against the opacity its hits really have: its alpha times its
 * alpha texture's level 0 read by hz_texture_alpha at 20,000 random coordinates (wrapped, far out, on texel
 * centres and edges), and close to the largest texel so that it rejects something; the material's own alpha
 * where a triangle's coordinates are not finite or no texture is usable; 1 where not blended or textures are
 * left out of the run. */
static void test_opacity_bounds(void **state)
{
    (void)state;
    enum { TW = 8, TH = 4 };
    static uint8_t texels[TW * TH * 4];
    uint32_t rng = 12345u;
    for (int i = 0; i < TW * TH; i++) {
        rng = rng * 1664525u + 1013904223u;
        texels[4 * i + 3] = (uint8_t)((rng >> 24) % 201u); /* alpha 0..200 */
    }
    texels[4 * 13 + 3] = 200; /* the largest, once at least */
    hz_texture_t tex;
    memset(&tex, 0, sizeof tex);
    tex.width = TW, tex.height = TH, tex.levels = 1, tex.flags = 1u, tex.first_texel = 0, tex.texel_count = TW * TH;
    hz_material_t mats[6];
    memset(mats, 0, sizeof mats);
    const float alpha[6] = { 0.37f, 0.3f, 0.6f, 0.5f, 0.8f, 2.0f };
    const int32_t atex[6] = { 0, -1, 7, 0, 0, 0 }; /* 2: no such texture */
    for (int i = 0; i < 6; i++)
        mats[i].alpha = alpha[i], mats[i].alpha_mode = HZ_ALPHA_BLEND, mats[i].alpha_texture = atex[i];
    mats[3].alpha_mode = HZ_ALPHA_OPAQUE;
    /* one triangle per material; material 4's has a vertex with an infinite coordinate */
    static const float uv[8] = { 0.1f, 0.2f, 0.9f, 0.3f, 0.4f, 0.8f, INFINITY, 0.5f };
    static const uint32_t tri[18] = { 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 3, 0, 1, 2 };
    static const uint32_t info[6] = { 0, 1, 2, 3, 4, 5 };
    hz_scene_t sc;
    memset(&sc, 0, sizeof sc);
    sc.materials = mats, sc.material_count = 6, sc.textures = &tex, sc.texture_count = 1, sc.texels = texels;
    sc.uv = uv, sc.tri = tri, sc.tri_info = info, sc.triangle_count = 6, sc.vertex_count = 4;
    uint32_t b[6];
    hz_transp_bounds(&sc, true, b);
    const uint32_t most = hz_transp_alpha_q16(0.37f * (200.0f / 255.0f));
    assert_true(b[0] >= most && b[0] <= most + 32u); /* tight: about 0.29, well under 1 */
    for (int i = 0; i < 20000; i++) {
        rng = rng * 1664525u + 1013904223u;
        float u = (float)(rng >> 8) * (1.0f / 16777216.0f) * 6.0f - 3.0f;
        rng = rng * 1664525u + 1013904223u;
        float v = (float)(rng >> 8) * (1.0f / 16777216.0f) * 6.0f - 3.0f;
        if (i % 4 == 1) /* texel centres and edges, where the mix takes one texel whole */
            u = floorf(u * TW) / TW + (i % 8 == 1 ? 0.5f / TW : 0.0f), v = floorf(v * TH) / TH;
        const uint32_t a = hz_transp_alpha_q16(mats[0].alpha * hz_texture_alpha(&sc, 0, u, v));
        assert_true(a <= b[0]);
    }
    assert_int_equal(b[1], hz_transp_alpha_q16(0.3f));           /* untextured: the material's alpha */
    assert_int_equal(b[2], hz_transp_alpha_q16(0.6f));           /* no such texture: alpha times 1 */
    assert_int_equal(b[3], HZ_DITHER_ONE);                       /* not blended */
    assert_int_equal(b[4], hz_transp_alpha_q16(0.8f));           /* a coordinate not finite: alpha times 1 */
    assert_int_equal(b[5], HZ_DITHER_ONE);                       /* opaque at its largest texel */
    hz_transp_bounds(&sc, false, b);                             /* textures left out: the material's alpha */
    assert_int_equal(b[0], hz_transp_alpha_q16(0.37f));
    assert_int_equal(b[4], hz_transp_alpha_q16(0.8f));
}

/* The opacity bounds change no image: each stochastic method on sponza-smoke (textured sprites whose opacity
 * never exceeds 0.40, so most layers are rejected by the bound alone) renders the same bits, with the same ray
 * counts, with and without them. */
static void test_opacity_bounds_same_images(void **state)
{
    (void)state;
    char path[512];
    const char *scene = scene_path("sponza-smoke.hzb", path, sizeof path);
    static const hz_transp_t methods[] = { HZ_TRANSP_STD, HZ_TRANSP_RR, HZ_TRANSP_DTAA_STAR, HZ_TRANSP_STD };
    rfix_t f;
    hz_error_t err;
    assert_int_equal(rfix_open(&f, scene, HZ_ACCEL_NATIVE, &err), HZ_OK); /* one accel for every renderer */
    for (size_t i = 0; i < sizeof methods / sizeof methods[0]; i++) {
        run_t with, without;
        g_rr_shadows = i == 3; /* the stochastic shadow rays too */
        render_on(&f, HZ_MODE_TAA, 1, methods[i], 0.0f, 2, 4.5f, &with);
        g_no_bounds = true;
        render_on(&f, HZ_MODE_TAA, 1, methods[i], 0.0f, 2, 4.5f, &without);
        g_no_bounds = false;
        g_rr_shadows = false;
        assert_true(same(&with, &without));
        assert_true(with.total.primary_rays == without.total.primary_rays &&
                    with.total.shadow_rays == without.total.shadow_rays &&
                    with.total.secondary_rays == without.total.secondary_rays);
        assert_true(memcmp(with.dithered, without.dithered, (size_t)W * H) == 0);
        assert_int_not_equal(with.flags_or & HZ_GB_DITHER, 0); /* the cloud is in view */
        run_free(&with);
        run_free(&without);
    }
    rfix_close(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_left_out_without_blend),
        cmocka_unit_test(test_hybrid_ends_and_mask),
        cmocka_unit_test(test_temporal_average_converges),
        cmocka_unit_test(test_full_spp_walks_the_dither),
        cmocka_unit_test(test_taa_accumulates),
        cmocka_unit_test(test_maps_per_particle),
        cmocka_unit_test(test_opacity_bounds),
        cmocka_unit_test(test_opacity_bounds_same_images),
    };
    return HZ_RUN(tests);
}
