/*
 * errtime through the renderer (et_render.h) on the baked CornellBox-Mirror at a small size: full-frame error
 * falls monotonically 1 -> 4 -> 9 -> 16 spp (PSNR and SSIM up, mean FLIP down) while the work grows. The work is
 * asserted as rays per frame from the renderer's stats (at least width * height * spp primary rays, strictly
 * rising), not as time: the house rules forbid timed assertions, so the driver's median times are printed only.
 * Also: TAA runs and traces one primary ray per pixel; the scene's cache key (content hash and renderer
 * fingerprint) is the same for every thread count and differs between scenes; the pools are given back by close
 * and by a failed open; a missing scene file is refused with its path; the tables are well formed; the adaptive
 * operating-point search brackets its answer.
 *
 * Needs the baked scenes ($HZ_SCENES_DIR, exported by make; `make scenes`); skipped with a message without them.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "errtime.h"
#include "et_flip.h"
#include "et_methods.h"
#include "et_render.h"
#include "et_search.h"
#include "fileio.h"
#include "pools.h"

/* Frames per sequence; under qemu half of them (each is a reference at many samples per pixel plus every
 * method's render of it, all emulated): the same paths and orderings, from the same seeds. */
#define ET_FRAMES HZ_EMULATED_LESS(8, 4)
#define ET_BLUR_FRAMES HZ_EMULATED_LESS(4, 2)

static char cache[64];
static uint8_t mem[96 << 20] HZ_ALIGNED(64);
static hz_arena_t arena;

static int setup(void **state)
{
    (void)state;
    strcpy(cache, "/tmp/hz-et-render-XXXXXX");
    hz_arena_init(&arena, "errtime", mem, sizeof mem);
    return mkdtemp(cache) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", cache);
    return system(cmd) == 0 ? 0 : -1;
}

static const char *scene_dir(void)
{
    const char *d = getenv("HZ_SCENES_DIR");
    if (!d || !*d) {
        print_message("HZ_SCENES_DIR is not set (make exports it; `make scenes` bakes the scenes)\n");
        return NULL;
    }
    return d;
}

/* Sum of the pools' used bytes: what open must give back. */
static size_t pools_used(void)
{
    hz_pools_t *p = hz_pools_get();
    size_t n = hz_arena_mark(&p->scene) + hz_arena_mark(&p->accel) + hz_arena_mark(&p->frame);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        n += hz_arena_mark(&p->thread[t]);
    return n;
}

static void test_tables_are_well_formed(void **state)
{
    (void)state;
    for (size_t i = 0; i < HZ_ET_RENDER_METHOD_COUNT; i++) {
        const hz_et_method_t *m = &hz_et_render_methods[i];
        assert_non_null(m->name);
        assert_non_null(m->knob);
        assert_non_null(m->begin);
        assert_non_null(m->render);
        assert_non_null(m->params);
    }
    for (size_t i = 0; i < hz_et_scene_count; i++) {
        const hz_et_scene_t *s = &hz_et_scenes[i];
        assert_non_null(s->open);
        assert_non_null(s->reference);
        assert_true(s->method_count > 0);
        assert_true(hz_et_scene_find(s->name) == s);
        if (s->width) /* report defaults: SSIM's window fits, and at least one display-integration window */
            assert_true(s->width >= 11 && s->height >= 11 && s->frames >= s->warmup + hz_et_window(240));
    }
    assert_null(hz_et_scene_find("no-such-scene"));
    const hz_et_scene_t *c = hz_et_scene_find("CornellBox-Mirror");
    assert_non_null(c);
    assert_true(c->reference == &hz_et_render_reference);
    assert_true(hz_et_render_reference.value == 256.0);
}

static void test_full_frame_error_falls_as_rays_grow(void **state)
{
    (void)state;
    const char *dir = scene_dir();
    if (!dir)
        skip();
    const hz_et_scene_t *sc = hz_et_scene_find("CornellBox-Mirror");
    hz_et_env_t env = { dir, 2 };
    hz_et_sequence_t seq = { sc->name, 0, NULL, NULL, 40, 24, ET_FRAMES, 0, 240, NULL };
    hz_error_t err;
    size_t used = pools_used();
    if (sc->open(sc, &env, &seq, &arena, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    /* The full-frame rows of the scene's table, in table order. */
    hz_et_method_t m[4];
    size_t n = 0;
    for (size_t i = 0; i < sc->method_count && n < 4; i++)
        if (!strcmp(sc->methods[i].name, "full-frame"))
            m[n++] = sc->methods[i];
    assert_int_equal(n, 4);
    hz_et_config_t cfg = { cache, HZ_FLIP_DEFAULT_PPD, &arena, NULL, false, NULL };
    hz_et_row_t rows[4];
    hz_arena_mark_t mark = hz_arena_mark(&arena);
    hz_status_t s = hz_et_run(&seq, sc->reference, m, n, &cfg, rows, &err);
    sc->close();
    if (s != HZ_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(hz_arena_mark(&arena), mark);
    assert_int_equal(pools_used(), used);
    const double spp[4] = { 1, 4, 9, 16 };
    for (size_t i = 0; i < 4; i++) {
        const hz_et_row_t *r = &rows[i];
        print_message("full-frame %2g spp: FLIP %.4f  PSNR %.2f dB  SSIM %.4f  %.0f rays/frame  %.3f ms (not "
                      "asserted)\n", r->value, r->flip, r->psnr_srgb8, r->ssim, r->rays_per_frame, r->ms_median);
        assert_true(r->value == spp[i]);
        assert_int_equal(r->measured, ET_FRAMES);
        assert_true(r->rays_per_frame >= 40.0 * 24.0 * spp[i]); /* the primary rays alone */
        assert_true(r->flip > 0.0 && r->flip < 1.0 && isfinite(r->psnr_srgb8));
        if (i > 0) {
            assert_true(r->flip < rows[i - 1].flip);
            assert_true(r->psnr_srgb8 > rows[i - 1].psnr_srgb8);
            assert_true(r->ssim > rows[i - 1].ssim);
            assert_true(r->rays_per_frame > rows[i - 1].rays_per_frame);
        }
    }
}

/* Motion blur rows: every accel kind renders the same images at equal spp (same rays at the same times), error
 * falls with spp, and each run gives its pose keys and accel back. */
static void test_blur_rows_agree_and_give_back(void **state)
{
    (void)state;
    const hz_et_scene_t *sc = hz_et_scene_find("builtin-blur");
    assert_non_null(sc);
    assert_true(sc->reference == &hz_et_blur_reference);
    hz_et_env_t env = { scene_dir(), 2 };
    hz_et_sequence_t seq = { sc->name, 0, NULL, NULL, 32, 18, ET_BLUR_FRAMES, 0, 30, NULL };
    hz_error_t err;
    size_t used = pools_used();
    if (sc->open(sc, &env, &seq, &arena, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    assert_non_null(strstr(seq.settings, "shutter 1"));
    hz_et_config_t cfg = { cache, HZ_FLIP_DEFAULT_PPD, &arena, NULL, false, NULL };
    hz_et_row_t rows[HZ_ET_BLUR_METHOD_COUNT];
    /* Under qemu the reference takes 64 spp, still 4x the most a method takes (its 256 were most of the run):
     * the rows are compared with each other, each against the same reference. */
    hz_et_method_t ref = *sc->reference;
    hz_et_render_params_t ref_params = *(const hz_et_render_params_t *)ref.params;
    ref_params.spp = HZ_EMULATED_LESS(ref_params.spp, 64u);
    ref.value = ref_params.spp, ref.params = &ref_params;
    hz_status_t s = hz_et_run(&seq, &ref, sc->methods, sc->method_count, &cfg, rows, &err);
    sc->close();
    if (s != HZ_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(pools_used(), used);
    for (size_t i = 0; i < sc->method_count; i++) {
        const hz_et_row_t *r = &rows[i];
        print_message("%-7s %2g spp: PSNR %.2f dB (msbvh at this spp: %.2f dB)\n", sc->methods[i].name, r->value,
                      r->psnr_srgb8, rows[i % 3].psnr_srgb8);
        if (i % 3)
            assert_true(r->psnr_srgb8 > rows[i - 1].psnr_srgb8);
        assert_true(fabs(r->psnr_srgb8 - rows[i % 3].psnr_srgb8) < 0.5);
    }
}

/* The CornellBox-Mirror methods `pick` keeps, in table order, run at 40x24 into rows; returns how many. */
static size_t run_cornell(const char *dir, bool (*pick)(const hz_et_method_t *), hz_et_row_t *rows)
{
    const hz_et_scene_t *sc = hz_et_scene_find("CornellBox-Mirror");
    hz_et_env_t env = { dir, 2 };
    hz_et_sequence_t seq = { sc->name, 0, NULL, NULL, 40, 24, ET_FRAMES, 0, 240, NULL };
    hz_error_t err;
    if (sc->open(sc, &env, &seq, &arena, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    hz_et_method_t m[HZ_ET_RENDER_METHOD_COUNT];
    size_t n = 0;
    for (size_t i = 0; i < sc->method_count; i++)
        if (pick(&sc->methods[i]))
            m[n++] = sc->methods[i];
    hz_et_config_t cfg = { cache, HZ_FLIP_DEFAULT_PPD, &arena, NULL, false, NULL };
    hz_status_t s = hz_et_run(&seq, sc->reference, m, n, &cfg, rows, &err);
    sc->close();
    if (s != HZ_OK)
        fail_msg("%s", err.msg);
    return n;
}

static bool taa_or_1spp(const hz_et_method_t *m)
{
    return !strncmp(m->name, "taa", 3) || (m->value == 1.0 && !strcmp(m->name, "full-frame"));
}

static void test_taa_runs_one_ray_per_pixel(void **state)
{
    (void)state;
    const char *dir = scene_dir();
    if (!dir)
        skip();
    hz_et_row_t rows[HZ_ET_RENDER_METHOD_COUNT];
    size_t n = run_cornell(dir, taa_or_1spp, rows);
    assert_true(n >= 2);
    for (size_t i = 0; i < n; i++) {
        const hz_et_row_t *r = &rows[i];
        print_message("%-16s FLIP %.4f  PSNR %.2f dB  DI FLIP %.4f  %.0f rays/frame\n", r->method, r->flip,
                      r->psnr_srgb8, r->di_flip, r->rays_per_frame);
        assert_true(r->flip > 0.0 && r->flip < 1.0);
        assert_true(r->rays_per_frame >= 40.0 * 24.0);
        /* One camera ray per pixel, as full-frame 1 spp: shadow and mirror rays may differ, by less than 2x. */
        assert_true(r->rays_per_frame < 2.0 * rows[0].rays_per_frame);
    }
}

static void test_cache_key_is_content_and_renderer(void **state)
{
    (void)state;
    const char *dir = scene_dir();
    if (!dir)
        skip();
    hz_error_t err;
    char settings[2][256];
    uint64_t hash[3];
    const hz_et_scene_t *sc = hz_et_scene_find("CornellBox-Mirror");
    for (int k = 0; k < 2; k++) { /* 1 and 3 threads: the renderer's images, hence the key, are the same */
        hz_et_env_t env = { dir, k ? 3u : 1u };
        hz_et_sequence_t seq = { sc->name, 0, NULL, NULL, 40, 24, ET_FRAMES, 0, 240, NULL };
        if (sc->open(sc, &env, &seq, &arena, &err) != HZ_OK)
            fail_msg("%s", err.msg);
        snprintf(settings[k], sizeof settings[k], "%s", seq.settings);
        hash[k] = seq.scene_hash;
        assert_non_null(strstr(seq.settings, "probe "));
        assert_non_null(seq.scene_data);
        sc->close();
    }
    assert_string_equal(settings[0], settings[1]);
    assert_true(hash[0] == hash[1]);
    const hz_et_scene_t *other = hz_et_scene_find("builtin");
    hz_et_env_t env = { dir, 2 };
    hz_et_sequence_t seq = { other->name, 0, NULL, NULL, 40, 24, ET_FRAMES, 0, 240, NULL };
    if (other->open(other, &env, &seq, &arena, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    hash[2] = seq.scene_hash;
    assert_true(hash[2] != hash[0]);
    assert_string_not_equal(seq.settings, settings[0]); /* another scene renders another probe */
    /* One scene at a time: a second open is refused and leaves the first one open. */
    hz_et_sequence_t again = seq;
    assert_int_equal(sc->open(sc, &env, &again, &arena, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "already open"));
    other->close();
    other->close(); /* closing twice is harmless */
}

static void test_missing_scene_is_refused_and_pools_given_back(void **state)
{
    (void)state;
    hz_error_t err;
    size_t used = pools_used();
    hz_et_env_t env = { "/nonexistent-hz-scenes", 2 };
    const hz_et_scene_t *sc = hz_et_scene_find("sponza");
    hz_et_sequence_t seq = { sc->name, 0, NULL, NULL, 40, 24, ET_FRAMES, 0, 240, NULL };
    assert_int_equal(sc->open(sc, &env, &seq, &arena, &err), HZ_E_IO);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "/nonexistent-hz-scenes/sponza.hzb"));
    assert_non_null(strstr(err.msg, "make scenes"));
    assert_int_equal(pools_used(), used);
    /* Nothing is left open: the synthetic scene's methods need none, a rendered scene opens again. */
    const char *dir = scene_dir();
    if (!dir)
        return;
    env.scene_dir = dir;
    const hz_et_scene_t *c = hz_et_scene_find("CornellBox-Mirror");
    if (c->open(c, &env, &seq, &arena, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    c->close();
    assert_int_equal(pools_used(), used);
}

/* Adaptive supersampling (seed 003) through errtime: camera rays per pixel reported (9 for 9 spp), fewer extra rays
 * as tau_alpha grows, and the strictest setting beating 1 spp. Also a scene given as a file path. */
static void test_adaptive_rows_and_scene_file(void **state)
{
    (void)state;
    const char *dir = scene_dir();
    if (!dir)
        skip();
    char path[4096];
    snprintf(path, sizeof path, "%s/CornellBox-Mirror.hzb", dir);
    hz_et_scene_t file;
    char name[64];
    hz_et_scene_from_file(path, name, sizeof name, &file);
    assert_string_equal(file.name, "CornellBox-Mirror");
    assert_true(file.methods == hz_et_render_methods && file.reference == &hz_et_render_reference);
    assert_int_equal(file.width, 0);
    assert_true(hz_et_scene_is_file("a/b.hzb", 7) && !hz_et_scene_is_file("sponza", 6));
    hz_et_env_t env = { "/nonexistent", 2 }; /* a path does not go through the scene folder */
    hz_et_sequence_t seq = { file.name, 0, NULL, NULL, 40, 24, ET_FRAMES, 0, 240, NULL };
    hz_error_t err;
    if (file.open(&file, &env, &seq, &arena, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    hz_et_method_t m[HZ_ET_RENDER_METHOD_COUNT];
    size_t n = 0;
    for (size_t i = 0; i < file.method_count; i++)
        if (!strcmp(file.methods[i].name, "adaptive") ||
            (!strcmp(file.methods[i].name, "full-frame") && (file.methods[i].value == 1 || file.methods[i].value == 9)))
            m[n++] = file.methods[i];
    assert_int_equal(n, 6);
    hz_et_config_t cfg = { cache, HZ_FLIP_DEFAULT_PPD, &arena, NULL, false, NULL };
    hz_et_row_t rows[HZ_ET_RENDER_METHOD_COUNT];
    hz_status_t s = hz_et_run(&seq, file.reference, m, n, &cfg, rows, &err);
    file.close();
    if (s != HZ_OK)
        fail_msg("%s", err.msg);
    assert_true(rows[0].camera_rays_per_pixel == 1.0);
    assert_true(rows[1].camera_rays_per_pixel == 9.0);
    double prev = 1e9;
    for (size_t i = 2; i < n; i++) {
        const hz_et_row_t *r = &rows[i];
        print_message("adaptive tau %.1f: %.3f camera rays/px (%.1f%% of 9 spp), PSNR %.2f dB\n", r->value,
                      r->camera_rays_per_pixel, 100.0 * r->camera_rays_per_pixel / 9.0, r->psnr_srgb8);
        assert_true(r->camera_rays_per_pixel >= 1.0 && r->camera_rays_per_pixel <= 17.0);
        assert_true(r->camera_rays_per_pixel <= prev); /* larger thresholds never add samples */
        prev = r->camera_rays_per_pixel;
    }
    assert_true(rows[2].camera_rays_per_pixel > 1.0);
    assert_true(rows[2].psnr_srgb8 > rows[0].psnr_srgb8);
}

/* Seed 003's Fig. 7 pair on CornellBox-Mirror, which has no textures: with the geometry attributes on, a subpixel's
 * threshold is the smallest disagreeing attribute's (0.05 or 0.06, Table 2) or else tau_col, never more than
 * tau_col, which is the colour-only family's threshold everywhere; Mitchell's test is monotone in its threshold, so
 * at every tau_col "multiple" activates every subpixel "colour only" does (as many camera rays or more), and in each
 * family a larger tau_col never adds rays. The Markdown pairs the two by tau_col, one line each. */
static bool fig7_family(const hz_et_method_t *m)
{
    return !strcmp(m->name, "adaptive-colour-only") || !strcmp(m->name, "adaptive-multiple");
}

static void test_fig7_colour_only_and_multiple(void **state)
{
    (void)state;
    const char *dir = scene_dir();
    if (!dir)
        skip();
    hz_et_row_t rows[HZ_ET_RENDER_METHOD_COUNT];
    size_t n = run_cornell(dir, fig7_family, rows);
    assert_int_equal(n, 8);
    for (size_t i = 0; i < 4; i++) {
        const hz_et_row_t *c = &rows[i], *mm = &rows[4 + i];
        print_message("tau-col %.1f: colour only %.3f rays/px %.2f dB, multiple %.3f rays/px %.2f dB\n", c->value,
                      c->camera_rays_per_pixel, c->psnr_srgb8, mm->camera_rays_per_pixel, mm->psnr_srgb8);
        assert_string_equal(c->knob, "tau-col");
        assert_true(c->value == mm->value);
        assert_true(c->camera_rays_per_pixel >= 1.0 && mm->camera_rays_per_pixel <= 17.0);
        assert_true(mm->camera_rays_per_pixel >= c->camera_rays_per_pixel);
        if (i) {
            assert_true(c->camera_rays_per_pixel <= rows[i - 1].camera_rays_per_pixel);
            assert_true(mm->camera_rays_per_pixel <= rows[4 + i - 1].camera_rays_per_pixel);
        }
    }
    assert_true(rows[0].camera_rays_per_pixel > 1.0); /* the strictest colour threshold finds the box's edges */
    /* ... and at the loosest the attributes find edges the colour misses (white box faces on white walls meet at a
     * normal discontinuity with little contrast): the two families are not the same method. */
    assert_true(rows[7].camera_rays_per_pixel > rows[3].camera_rays_per_pixel);
    FILE *f = tmpfile();
    assert_non_null(f);
    hz_et_print_markdown(f, rows, n);
    rewind(f);
    char line[1024];
    int fig7 = 0, paired = 0;
    while (fgets(line, sizeof line, f)) {
        fig7 += strstr(line, "Fig. 7") != NULL;
        paired += !strncmp(line, "| 0.", 4) && !strstr(line, "adaptive") && !strstr(line, " - ");
    }
    fclose(f);
    assert_int_equal(fig7, 1);
    assert_int_equal(paired, 4);
    /* Without one family the pairing table is left out. */
    f = tmpfile();
    assert_non_null(f);
    hz_et_print_markdown(f, rows, 4);
    rewind(f);
    fig7 = 0;
    while (fgets(line, sizeof line, f))
        fig7 += strstr(line, "Fig. 7") != NULL;
    fclose(f);
    assert_int_equal(fig7, 0);
}

/* The operating-point search (et_search.h) on CornellBox-Mirror, with the target PSNR set by hand so that each
 * branch runs: a target every threshold reaches (tau 1, one probe), one none reaches (tau 1 and the smallest,
 * reached false) and one between the two (the bisection). Whatever the PSNR does between probes, the answer is
 * the largest probed tau that reached: every probe that reached lies at or below it, every one that failed above
 * it, and the bisection narrows the bracket to (1 / HZ_ET_SEARCH_TAU_MIN)^(2^-steps). The CSV has a line per
 * search. */
static void test_adaptive_search_brackets(void **state)
{
    (void)state;
    const char *dir = scene_dir();
    if (!dir)
        skip();
    const hz_et_scene_t *sc = hz_et_scene_find("CornellBox-Mirror");
    assert_non_null(sc);
    hz_et_env_t env = { dir, 2 };
    hz_et_sequence_t seq = { sc->name, 0, NULL, NULL, 40, 24, ET_FRAMES, 0, 240, NULL };
    hz_error_t err;
    if (sc->open(sc, &env, &seq, &arena, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    const hz_et_method_t *fam = NULL;
    for (size_t i = 0; i < sc->method_count && !fam; i++)
        if (!strcmp(sc->methods[i].name, "adaptive"))
            fam = &sc->methods[i];
    assert_non_null(fam);
    hz_et_config_t cfg = { cache, HZ_FLIP_DEFAULT_PPD, &arena, NULL, false, NULL };
    hz_et_row_t r9, r16, rows[3 * HZ_ET_SEARCH_PROBES];
    memset(&r9, 0, sizeof r9);
    snprintf(r9.scene, sizeof r9.scene, "%s", sc->name);
    r9.ms_median = 1.0;
    r16 = r9;
    hz_et_search_t res[3];
    size_t n = 0;
    /* everything reaches */
    r9.psnr_srgb8 = -1e9;
    hz_status_t s = hz_et_adaptive_search(&seq, sc->reference, fam, &r9, &r16, &cfg, rows, 3 * HZ_ET_SEARCH_PROBES,
                                          &n, &res[0], &err);
    if (s != HZ_OK) {
        sc->close();
        fail_msg("%s", err.msg);
    }
    assert_int_equal(n, 1);
    assert_true(res[0].reached && res[0].tau == 1.0 && res[0].probes == 1);
    assert_string_equal(rows[0].method, "adaptive-search");
    assert_string_equal(rows[0].knob, "tau");
    const double psnr_hi_tau = rows[0].psnr_srgb8;
    /* nothing reaches */
    r9.psnr_srgb8 = 1e9;
    s = hz_et_adaptive_search(&seq, sc->reference, fam, &r9, &r16, &cfg, rows, 3 * HZ_ET_SEARCH_PROBES, &n, &res[1],
                              &err);
    if (s != HZ_OK) {
        sc->close();
        fail_msg("%s", err.msg);
    }
    assert_int_equal(n, 3);
    assert_true(!res[1].reached && res[1].probes == 2);
    assert_true(res[1].tau == (double)(float)HZ_ET_SEARCH_TAU_MIN);
    const double psnr_lo_tau = rows[2].psnr_srgb8;
    print_message("adaptive: PSNR %.2f dB at tau 1, %.2f dB at tau %g\n", psnr_hi_tau, psnr_lo_tau,
                  HZ_ET_SEARCH_TAU_MIN);
    assert_true(psnr_lo_tau > psnr_hi_tau); /* the smallest threshold takes more samples here */
    /* in between: the bisection */
    r9.psnr_srgb8 = 0.5 * (psnr_lo_tau + psnr_hi_tau);
    const size_t first = n;
    s = hz_et_adaptive_search(&seq, sc->reference, fam, &r9, &r16, &cfg, rows, 3 * HZ_ET_SEARCH_PROBES, &n, &res[2],
                              &err);
    sc->close();
    if (s != HZ_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(n - first, HZ_ET_SEARCH_PROBES);
    assert_true(res[2].reached && res[2].probes == HZ_ET_SEARCH_PROBES);
    double above = 1.0;
    for (size_t i = first; i < n; i++) {
        print_message("  probe tau %.4f: PSNR %.2f dB (target %.2f)\n", rows[i].value, rows[i].psnr_srgb8,
                      r9.psnr_srgb8);
        if (rows[i].psnr_srgb8 >= r9.psnr_srgb8) {
            assert_true(rows[i].value <= res[2].tau);
        } else {
            assert_true(rows[i].value > res[2].tau);
            above = fmin(above, rows[i].value);
        }
    }
    assert_true(res[2].psnr >= r9.psnr_srgb8);
    assert_true(above / res[2].tau <= 1.001 * pow(1.0 / HZ_ET_SEARCH_TAU_MIN, 1.0 / (1 << HZ_ET_SEARCH_STEPS)));
    char path[128], text[4096];
    snprintf(path, sizeof path, "%s/search.csv", cache);
    if (hz_et_write_search_csv(path, res, 3, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    size_t bytes = 0;
    assert_int_equal(hz_file_read(path, text, sizeof text - 1, &bytes, &err), HZ_OK);
    text[bytes] = '\0';
    assert_true(!strncmp(text, HZ_ET_SEARCH_CSV_HEADER "\n", strlen(HZ_ET_SEARCH_CSV_HEADER) + 1));
    size_t lines = 0;
    for (size_t i = 0; i < bytes; i++)
        lines += text[i] == '\n';
    assert_int_equal(lines, 4);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tables_are_well_formed),
        cmocka_unit_test(test_full_frame_error_falls_as_rays_grow),
        cmocka_unit_test(test_taa_runs_one_ray_per_pixel),
        cmocka_unit_test(test_blur_rows_agree_and_give_back),
        cmocka_unit_test(test_cache_key_is_content_and_renderer),
        cmocka_unit_test(test_missing_scene_is_refused_and_pools_given_back),
        cmocka_unit_test(test_adaptive_rows_and_scene_file),
        cmocka_unit_test(test_adaptive_search_brackets),
        cmocka_unit_test(test_fig7_colour_only_and_multiple),
    };
    return HZ_RUN_GROUP(tests, setup, teardown);
}
