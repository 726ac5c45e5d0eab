/*
 * errtime's driver end to end on the built-in analytic scene: error falls and rays grow with spp, the eye's
 * integration over k frames lowers the error of noise, a method identical to the reference scores FLIP 0,
 * PSNR inf, SSIM 1; the reference cache is built once, reused, keyed by the settings, refused when tampered
 * with, and never left half-written; render failures name the method and frame; timing statistics.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "errtime.h"
#include "et_flip.h"
#include "et_synthetic.h"

static char cache[64];
static uint8_t mem[64 << 20] HZ_ALIGNED(64);
static hz_arena_t arena;

static int setup(void **state)
{
    (void)state;
    strcpy(cache, "/tmp/hz-errtime-XXXXXX");
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

static hz_et_sequence_t sequence(const char *settings)
{
    hz_et_sequence_t s = { "synthetic", 1, "fixed", settings, 32, 24, 16, 4, 240, NULL };
    return s;
}

static hz_et_config_t config(void)
{
    hz_et_config_t c = { cache, HZ_FLIP_DEFAULT_PPD, &arena, NULL, false, NULL };
    return c;
}

/* The reference, counting its renders, failing at frame fail_at (if >= 0). */
static int reference_renders;
static int fail_at = -1;

static hz_status_t counting_render(void *state, uint32_t frame, hz_image_t *out, uint64_t *rays, hz_error_t *err)
{
    if ((int)frame == fail_at)
        return hz_error_set(err, HZ_E_DEVICE, "simulated failure");
    reference_renders++;
    return hz_synth_reference.render(state, frame, out, rays, err);
}

static hz_et_method_t counted_reference(void)
{
    hz_et_method_t m = hz_synth_reference;
    m.render = counting_render;
    return m;
}

static size_t entries(const char *suffix)
{
    DIR *d = opendir(cache);
    assert_non_null(d);
    size_t n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (e->d_name[0] != '.' && strstr(e->d_name, suffix))
            n++;
    closedir(d);
    return n;
}

static void test_end_to_end_synthetic(void **state)
{
    (void)state;
    hz_et_sequence_t seq = sequence("e2e");
    hz_et_config_t cfg = config();
    hz_et_method_t ref = counted_reference();
    hz_et_method_t methods[5] = { hz_synth_methods[0], hz_synth_methods[1], hz_synth_methods[2], hz_synth_methods[3],
                                  hz_synth_methods[4] };
    hz_et_row_t rows[5];
    hz_error_t err;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    reference_renders = 0;
    if (hz_et_run(&seq, &ref, methods, 5, &cfg, rows, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(reference_renders, 16);
    assert_int_equal(hz_arena_mark(&arena), m);
    const double spp[4] = { 1, 4, 9, 16 };
    for (int i = 0; i < 5; i++) {
        const hz_et_row_t *r = &rows[i];
        print_message("%-12s %s=%-4g flip %.4f psnr %.2f ssim %.4f di_flip %.4f di_psnr %.2f ms %.3f\n", r->method,
                      r->knob, r->value, r->flip, r->psnr_srgb8, r->ssim, r->di_flip, r->di_psnr_srgb8, r->ms_median);
        assert_string_equal(r->scene, "synthetic");
        assert_int_equal(r->width, 32);
        assert_int_equal(r->frames, 16);
        assert_int_equal(r->measured, 12);
        assert_int_equal(r->refresh_hz, 240);
        assert_int_equal(r->di_k, 4);
        assert_true(r->ms_median > 0.0 && r->ms_p99 >= r->ms_median);
        assert_true(r->flip > 0.0 && r->flip < 1.0 && isfinite(r->psnr_srgb8) && r->ssim < 1.0);
        if (i < 4) {
            assert_string_equal(r->method, "supersample");
            assert_true(r->value == spp[i]);
            assert_true(r->rays_per_frame == 32.0 * 24.0 * spp[i]);
            /* The eye averages 4 frames of independent noise: the integrated error is lower. */
            assert_true(r->di_flip < r->flip);
            assert_true(r->di_psnr_srgb8 > r->psnr_srgb8);
        }
        if (i > 0 && i < 4) {
            assert_true(r->flip < rows[i - 1].flip);
            assert_true(r->psnr_srgb8 > rows[i - 1].psnr_srgb8);
            assert_true(r->psnr_linear > rows[i - 1].psnr_linear);
            assert_true(r->ssim > rows[i - 1].ssim);
        }
    }
    assert_string_equal(rows[4].method, "accumulate");
    assert_true(rows[4].rays_per_frame == 32.0 * 24.0);
    /* Exactly one cache entry, complete, no temporary left over. */
    assert_int_equal(entries("synthetic-"), 1);
    assert_int_equal(entries(".tmp-"), 0);
}

static void test_cache_is_reused_and_keyed(void **state)
{
    (void)state;
    hz_et_sequence_t seq = sequence("reuse");
    hz_et_config_t cfg = config();
    hz_et_method_t ref = counted_reference();
    hz_et_row_t row;
    hz_error_t err;
    size_t before = entries("synthetic-");
    reference_renders = 0;
    assert_int_equal(hz_et_run(&seq, &ref, &hz_synth_methods[0], 1, &cfg, &row, &err), HZ_OK);
    assert_int_equal(reference_renders, 16);
    double flip = row.flip;
    reference_renders = 0;
    bool rendered = true;
    assert_int_equal(hz_et_reference(&seq, &ref, &cfg, &rendered, &err), HZ_OK);
    assert_false(rendered);
    assert_int_equal(hz_et_run(&seq, &ref, &hz_synth_methods[0], 1, &cfg, &row, &err), HZ_OK);
    assert_int_equal(reference_renders, 0);
    assert_true(row.flip == flip); /* deterministic */
    assert_int_equal(entries("synthetic-"), before + 1);
    /* Anything in the key makes a new entry: settings, size, frames, refresh, the reference's knob. */
    char d1[4096], d2[4096], k1[2048], k2[2048];
    assert_int_equal(hz_et_cache_entry(&seq, &ref, cache, d1, sizeof d1, k1, sizeof k1, &err), HZ_OK);
    hz_et_sequence_t other = seq;
    other.refresh_hz = 120;
    assert_int_equal(hz_et_cache_entry(&other, &ref, cache, d2, sizeof d2, k2, sizeof k2, &err), HZ_OK);
    assert_string_not_equal(d1, d2);
    hz_et_method_t ref2 = ref;
    ref2.value = 64;
    assert_int_equal(hz_et_cache_entry(&seq, &ref2, cache, d2, sizeof d2, k2, sizeof k2, &err), HZ_OK);
    assert_string_not_equal(d1, d2);
    other = seq;
    other.scene_hash = 2;
    assert_int_equal(hz_et_cache_entry(&other, &ref, cache, d2, sizeof d2, k2, sizeof k2, &err), HZ_OK);
    assert_string_not_equal(d1, d2);
    assert_non_null(strstr(k1, "settings reuse\n"));
    assert_non_null(strstr(k1, "reference supersample spp=256\n"));
    other = seq;
    other.scene = "../../etc/x y"; /* the directory name stays inside the cache */
    assert_int_equal(hz_et_cache_entry(&other, &ref, cache, d2, sizeof d2, k2, sizeof k2, &err), HZ_OK);
    assert_non_null(strstr(d2, "/_._.._etc_x_y-")); /* no "/" survives */
}

static void test_identical_method_scores_perfectly(void **state)
{
    (void)state;
    hz_et_sequence_t seq = sequence("identical");
    hz_et_config_t cfg = config();
    hz_et_row_t row;
    hz_error_t err;
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, &hz_synth_reference, 1, &cfg, &row, &err), HZ_OK);
    assert_true(row.flip == 0.0);
    assert_true(isinf(row.psnr_srgb8) && row.psnr_srgb8 > 0);
    assert_true(isinf(row.psnr_linear) && row.psnr_linear > 0);
    assert_float_equal(row.ssim, 1.0, 1e-12);
    assert_true(row.di_flip == 0.0);
    assert_true(isinf(row.di_psnr_srgb8));
    assert_true(row.pareto_flip && row.pareto_psnr);
    char path[128];
    snprintf(path, sizeof path, "%s/identical.csv", cache);
    assert_int_equal(hz_et_write_csv(path, &row, 1, &err), HZ_OK);
    FILE *f = fopen(path, "r");
    char line[512];
    assert_non_null(fgets(line, sizeof line, f));
    assert_non_null(fgets(line, sizeof line, f));
    fclose(f);
    assert_non_null(strstr(line, ",inf,inf,1.000000,0.000000,4,0.000000,inf,1,1"));
}

static void test_tampered_cache_is_refused(void **state)
{
    (void)state;
    hz_et_sequence_t seq = sequence("tamper");
    hz_et_config_t cfg = config();
    hz_et_row_t row;
    hz_error_t err;
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, &hz_synth_methods[1], 1, &cfg, &row, &err), HZ_OK);
    char dir[4096], key[2048], p[4200];
    assert_int_equal(hz_et_cache_entry(&seq, &hz_synth_reference, cache, dir, sizeof dir, key, sizeof key, &err),
                     HZ_OK);
    /* A frame cut short: the PFM reader names it when the run reaches it. */
    snprintf(p, sizeof p, "%s/ref-00007.pfm", dir);
    assert_int_equal(truncate(p, 100), 0);
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, &hz_synth_methods[1], 1, &cfg, &row, &err), HZ_E_FORMAT);
    assert_non_null(strstr(err.msg, "ref-00007.pfm"));
    assert_non_null(strstr(err.msg, "truncated"));
    /* A missing frame: refused before anything runs. */
    assert_int_equal(unlink(p), 0);
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, &hz_synth_methods[1], 1, &cfg, &row, &err), HZ_E_CORRUPT);
    assert_non_null(strstr(err.msg, "ref-00007.pfm is missing"));
    /* A key that does not match. */
    snprintf(p, sizeof p, "%s/key.txt", dir);
    FILE *f = fopen(p, "a");
    fputs("extra\n", f);
    fclose(f);
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, &hz_synth_methods[1], 1, &cfg, &row, &err), HZ_E_CORRUPT);
    assert_non_null(strstr(err.msg, "does not match"));
    assert_non_null(strstr(err.msg, dir));
}

static void test_failed_reference_leaves_nothing(void **state)
{
    (void)state;
    hz_et_sequence_t seq = sequence("fails");
    hz_et_config_t cfg = config();
    hz_et_method_t ref = counted_reference();
    hz_et_row_t row;
    hz_error_t err;
    size_t before = entries("synthetic-");
    hz_arena_mark_t m = hz_arena_mark(&arena);
    fail_at = 5;
    hz_status_t s = hz_et_run(&seq, &ref, &hz_synth_methods[0], 1, &cfg, &row, &err);
    fail_at = -1;
    assert_int_equal(s, HZ_E_DEVICE);
    assert_non_null(strstr(err.msg, "supersample spp=256, frame 5"));
    assert_non_null(strstr(err.msg, "simulated failure"));
    assert_int_equal(entries("synthetic-"), before);
    assert_int_equal(entries(".tmp-"), 0);
    assert_int_equal(hz_arena_mark(&arena), m);
}

static hz_status_t failing_method(void *state, uint32_t frame, hz_image_t *out, uint64_t *rays, hz_error_t *err)
{
    if (frame == 9)
        return hz_error_set(err, HZ_E_NO_MEMORY, "arena 'thread0': needs 10 bytes, has 2 bytes");
    return hz_synth_methods[0].render(state, frame, out, rays, err);
}

static void test_failed_method_is_named(void **state)
{
    (void)state;
    hz_et_sequence_t seq = sequence("e2e");
    hz_et_config_t cfg = config();
    hz_et_method_t ms[2] = { hz_synth_methods[1], hz_synth_methods[0] };
    ms[1].name = "broken";
    ms[1].render = failing_method;
    hz_et_row_t rows[2];
    hz_error_t err;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, ms, 2, &cfg, rows, &err), HZ_E_NO_MEMORY);
    assert_non_null(strstr(err.msg, "broken spp=1, frame 9: render: arena 'thread0'"));
    assert_int_equal(hz_arena_mark(&arena), m);
    /* Too little memory for the run: refused with the arena's numbers, arena restored. */
    static uint8_t small[64 << 10];
    hz_arena_t tiny;
    hz_arena_init(&tiny, "tiny", small, sizeof small);
    cfg.arena = &tiny;
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, ms, 1, &cfg, rows, &err), HZ_E_NO_MEMORY);
    assert_non_null(strstr(err.msg, "arena 'tiny'"));
    assert_int_equal(hz_arena_mark(&tiny), 0);
    assert_true(hz_et_arena_bytes(&seq, cfg.ppd) < sizeof mem);
    /* hz_et_arena_bytes is enough: the driver's part plus the method's own state (a few bytes here). */
    hz_arena_t exact;
    hz_arena_init(&exact, "exact", mem + sizeof mem / 2, hz_et_arena_bytes(&seq, cfg.ppd) + 256);
    cfg.arena = &exact;
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, ms, 1, &cfg, rows, &err), HZ_OK);
    assert_int_equal(hz_arena_mark(&exact), 0);
    assert_true(exact.high_water > hz_et_arena_bytes(&seq, cfg.ppd) / 2); /* and not wildly more than needed */
}

static long file_size(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fclose(f);
    return n;
}

static void test_videos_of_displayed_frames(void **state)
{
    (void)state;
    hz_et_sequence_t seq = sequence("e2e");
    hz_et_config_t cfg = config();
    char vdir[128], p[256];
    snprintf(vdir, sizeof vdir, "%s/videos", cache);
    cfg.video_dir = vdir;
    hz_et_method_t ms[2] = { hz_synth_methods[1], hz_synth_methods[5] };
    hz_et_row_t rows[2];
    hz_error_t err;
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, ms, 2, &cfg, rows, &err), HZ_OK);
    const char *hdr = "YUV4MPEG2 W32 H24 F240:1 Ip A1:1 C444 XCOLORRANGE=FULL\n";
    long want = (long)strlen(hdr) + 16 * (6 + 32 * 24 * 3);
    const char *names[3] = { "synthetic-supersample-spp4.y4m", "synthetic-accumulate-alpha0.2.y4m",
                             "synthetic-reference.y4m" };
    for (int i = 0; i < 3; i++) {
        snprintf(p, sizeof p, "%s/%s", vdir, names[i]);
        if (file_size(p) != want)
            fail_msg("%s: %ld bytes, want %ld", p, file_size(p), want);
    }
    FILE *f = fopen(p, "rb");
    char line[128];
    assert_non_null(fgets(line, sizeof line, f));
    fclose(f);
    assert_string_equal(line, hdr);
}

/* A held method: which frames it was asked to render. */
static uint32_t held_calls[64], held_count;

static hz_status_t recording_render(void *state, uint32_t frame, hz_image_t *out, uint64_t *rays, hz_error_t *err)
{
    if (held_count < 64)
        held_calls[held_count++] = frame;
    return hz_synth_methods[0].render(state, frame, out, rays, err);
}

static void test_held_method_renders_every_nth_frame(void **state)
{
    (void)state;
    /* supersample spp 1 at 60 Hz on a 240 Hz display: rendered at frames 0, 4, 8, 12 and shown 4 times each;
     * costs and rays are per displayed frame. */
    hz_et_sequence_t seq = sequence("e2e");
    hz_et_config_t cfg = config();
    hz_et_method_t ms[2] = { hz_synth_methods[0], hz_synth_methods[7] };
    assert_string_equal(ms[1].name, "supersample@60Hz");
    assert_int_equal(ms[1].hold, 4);
    ms[1].render = recording_render;
    held_count = 0;
    hz_et_row_t rows[2];
    hz_error_t err;
    if (hz_et_run(&seq, &hz_synth_reference, ms, 2, &cfg, rows, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(held_count, 4);
    for (uint32_t i = 0; i < held_count; i++)
        assert_int_equal(held_calls[i], 4 * i);
    assert_true(rows[1].rays_per_frame == 32.0 * 24.0 / 4.0);
    assert_true(rows[1].ms_median > 0.0);
    /* Showing stale frames costs accuracy against the moving reference. */
    assert_true(rows[1].flip > rows[0].flip);
    /* A hold longer than the measured frames is refused, naming the method. */
    ms[1].hold = 13;
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, ms, 2, &cfg, rows, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "supersample@60Hz"));
}

static void test_tdense_method(void **state)
{
    (void)state;
    /* Temporally dense on the synthetic scene: one ray per 2x2 tile per frame, a sane image. */
    hz_et_sequence_t seq = sequence("e2e");
    hz_et_config_t cfg = config();
    const hz_et_method_t *m = &hz_synth_methods[9];
    assert_string_equal(m->name, "tdense");
    hz_et_row_t row;
    hz_error_t err;
    hz_arena_mark_t mark = hz_arena_mark(&arena);
    if (hz_et_run(&seq, &hz_synth_reference, m, 1, &cfg, &row, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(hz_arena_mark(&arena), mark);
    assert_true(row.rays_per_frame == 32.0 * 24.0 / 4.0);
    print_message("tdense flip %.4f psnr %.2f ssim %.4f di_flip %.4f\n", row.flip, row.psnr_srgb8, row.ssim, row.di_flip);
    /* At 32x24 the checkerboard's squares are 3.4 px wide, so a quarter of the samples per frame shows; the eye's
     * integration over 4 frames is what recovers it (the technique's premise). */
    assert_true(row.flip > 0.0 && row.flip < 0.3 && row.ssim > 0.75 && row.psnr_srgb8 > 15.0);
    assert_true(row.di_flip < row.flip);
}

static void test_argument_errors(void **state)
{
    (void)state;
    hz_et_config_t cfg = config();
    hz_et_row_t row;
    hz_error_t err;
    hz_et_sequence_t seq = sequence("args");
    seq.frames = 7; /* 4 warm-up + 3 < k = 4 */
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, &hz_synth_methods[0], 1, &cfg, &row, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "7 frames with 4 of warm-up"));
    seq = sequence("args");
    seq.width = 10;
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, &hz_synth_methods[0], 1, &cfg, &row, &err), HZ_E_INVALID_ARG);
    seq = sequence("args");
    seq.refresh_hz = 0;
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, &hz_synth_methods[0], 1, &cfg, &row, &err), HZ_E_INVALID_ARG);
    seq = sequence("args");
    hz_et_method_t bad = hz_synth_methods[0];
    bad.render = NULL;
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, &bad, 1, &cfg, &row, &err), HZ_E_INVALID_ARG);
    hz_et_config_t nocache = cfg;
    nocache.cache_dir = NULL;
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, &hz_synth_methods[0], 1, &nocache, &row, &err),
                     HZ_E_INVALID_ARG);
    hz_et_config_t far = cfg;
    far.ppd = 5000.0f;
    assert_int_equal(hz_et_run(&seq, &hz_synth_reference, &hz_synth_methods[0], 1, &far, &row, &err),
                     HZ_E_INVALID_ARG);
    assert_int_equal(entries("args"), 0); /* refused before rendering anything */
}

static void test_window_and_time_stats(void **state)
{
    (void)state;
    assert_int_equal(hz_et_window(60), 1);
    assert_int_equal(hz_et_window(120), 2);
    assert_int_equal(hz_et_window(144), 2);
    assert_int_equal(hz_et_window(165), 3);
    assert_int_equal(hz_et_window(240), 4);
    assert_int_equal(hz_et_window(30), 1);
    assert_int_equal(hz_et_window(1), 1);
    int64_t a[5] = { 5000000, 1000000, 3000000, 2000000, 4000000 };
    double med, p99;
    hz_et_time_stats(a, 5, &med, &p99);
    assert_true(med == 3.0 && p99 == 5.0);
    int64_t b[4] = { 4000000, 1000000, 2000000, 3000000 };
    hz_et_time_stats(b, 4, &med, &p99);
    assert_true(med == 2.5 && p99 == 4.0);
    int64_t c[200];
    for (int i = 0; i < 200; i++)
        c[i] = (int64_t)(199 - i) * 1000000; /* 0 .. 199 ms */
    hz_et_time_stats(c, 200, &med, &p99);
    assert_true(med == 99.5);
    assert_true(p99 == 197.0); /* the 198th smallest of 200 */
    int64_t one = 7000000;
    hz_et_time_stats(&one, 1, &med, &p99);
    assert_true(med == 7.0 && p99 == 7.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_end_to_end_synthetic),
        cmocka_unit_test(test_cache_is_reused_and_keyed),
        cmocka_unit_test(test_identical_method_scores_perfectly),
        cmocka_unit_test(test_tampered_cache_is_refused),
        cmocka_unit_test(test_failed_reference_leaves_nothing),
        cmocka_unit_test(test_failed_method_is_named),
        cmocka_unit_test(test_videos_of_displayed_frames),
        cmocka_unit_test(test_held_method_renders_every_nth_frame),
        cmocka_unit_test(test_tdense_method),
        cmocka_unit_test(test_argument_errors),
        cmocka_unit_test(test_window_and_time_stats),
    };
    return HZ_RUN_GROUP(tests, setup, teardown);
}
