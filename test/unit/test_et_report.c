/*
 * errtime reports: the Pareto front on hand-made points (ties, NaN, other scenes), the exact CSV text, the
 * Markdown table, the SVG's structure (series, points, labels, front, escaping), write errors, and the
 * progress bar.
 */
#define _GNU_SOURCE /* memmem */
#include "hz_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hz/base.h"
#include "et_progress.h"
#include "et_report.h"

static char dir[64];

static int setup(void **state)
{
    (void)state;
    strcpy(dir, "/tmp/hz-report-XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static const char *path_of(const char *name)
{
    static char buf[2][256];
    static int k;
    k ^= 1;
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
    return buf[k];
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    assert_int_equal(fread(s, 1, (size_t)n, f), (size_t)n);
    s[n] = '\0';
    fclose(f);
    return s;
}

static size_t count(const char *hay, const char *needle)
{
    size_t n = 0;
    for (const char *p = hay; (p = strstr(p, needle)) != NULL; p += strlen(needle))
        n++;
    return n;
}

static hz_et_row_t row(const char *scene, const char *method, double value, double ms, double flip, double psnr)
{
    hz_et_row_t r;
    memset(&r, 0, sizeof r);
    snprintf(r.scene, sizeof r.scene, "%s", scene);
    snprintf(r.method, sizeof r.method, "%s", method);
    snprintf(r.knob, sizeof r.knob, "spp");
    r.value = value;
    r.width = 64;
    r.height = 48;
    r.frames = 20;
    r.measured = 16;
    r.refresh_hz = 240;
    r.di_k = 4;
    r.ms_median = ms;
    r.ms_p99 = ms * 1.5;
    r.rays_per_frame = 64 * 48 * value;
    r.flip = flip;
    r.psnr_srgb8 = psnr;
    r.psnr_linear = psnr + 1;
    r.ssim = 0.9;
    r.di_flip = flip / 2;
    r.di_psnr_srgb8 = psnr + 3;
    r.camera_rays_per_pixel = value;
    return r;
}

static void test_pareto_front(void **state)
{
    (void)state;
    hz_et_row_t r[] = {
        row("s", "a", 1, 1.0, 0.50, 20), /* fastest: on both fronts */
        row("s", "a", 2, 2.0, 0.30, 25),
        row("s", "b", 3, 3.0, 0.35, 30), /* slower and worse FLIP than [1]; best PSNR so far */
        row("s", "b", 4, 4.0, 0.10, 24), /* best FLIP; PSNR beaten by [2] which is faster */
        row("s", "c", 2, 2.0, 0.30, 25), /* a tie with [1]: both stay */
        row("s", "d", 1, 0.5, NAN, NAN), /* no error figures: never on a front, dominates nothing */
        row("t", "a", 1, 0.1, 0.01, 60), /* another scene: compared only with its own */
        row("t", "a", 2, 9.0, 0.02, 50),
    };
    hz_et_pareto(r, HZ_ARRAY_LEN(r));
    const bool flip[] = { true, true, false, true, true, false, true, false };
    const bool psnr[] = { true, true, true, false, true, false, true, false };
    for (size_t i = 0; i < HZ_ARRAY_LEN(r); i++) {
        if (r[i].pareto_flip != flip[i] || r[i].pareto_psnr != psnr[i])
            fail_msg("row %zu: pareto flip %d psnr %d, want %d %d", i, r[i].pareto_flip, r[i].pareto_psnr, flip[i],
                     psnr[i]);
    }
}

static void test_csv_text(void **state)
{
    (void)state;
    hz_et_row_t r[2] = { row("cornell", "full-frame", 4, 3.25, 0.125, 28.5),
                         row("cornell", "taa, 8 frames", 1, 1.5, 0.0, INFINITY) };
    r[1].psnr_linear = INFINITY;
    r[1].di_psnr_srgb8 = INFINITY;
    r[1].camera_rays_per_pixel = NAN; /* a method that does not say */
    hz_et_pareto(r, 2);
    hz_error_t err;
    assert_int_equal(hz_et_write_csv(path_of("a.csv"), r, 2, &err), HZ_OK);
    char *s = slurp(path_of("a.csv"));
    const char *want =
        HZ_ET_CSV_HEADER "\n"
        "cornell,full-frame,spp,4,64,48,20,16,240,3.2500,4.8750,12288,28.5000,29.5000,0.900000,0.125000,4,0.062500,"
        "31.5000,0,0,4.0000,0.4444\n"
        "cornell,\"taa, 8 frames\",spp,1,64,48,20,16,240,1.5000,2.2500,3072,inf,inf,0.900000,0.000000,4,0.000000,"
        "inf,1,1,nan,nan\n";
    assert_string_equal(s, want);
    free(s);
}

static void test_markdown_table(void **state)
{
    (void)state;
    hz_et_row_t r[3] = { row("cornell", "full|frame", 4, 3.25, 0.125, 28.5), row("sponza", "full-frame", 1, 9, 0.2, 20),
                         row("cornell", "taa", 1, 1.5, 0.05, INFINITY) };
    hz_et_pareto(r, 3);
    hz_error_t err;
    assert_int_equal(hz_et_write_markdown(path_of("a.md"), r, 3, &err), HZ_OK);
    char *s = slurp(path_of("a.md"));
    assert_int_equal(count(s, "### "), 2);
    assert_non_null(
        strstr(s, "### cornell — 64x48, 20 frames at 240 Hz (4 warm-up), display-integrated over k = 4\n"));
    assert_int_equal(count(s, "| method | setting | ms/frame |"), 2);
    assert_non_null(strstr(s, "| full\\|frame | spp=4 | 3.250 | 4.875 | 0.012 | 0.1250 | 28.50 | 29.50 | 0.9000 | "
                              "0.0625 | 31.50 | 4.00 | 44.4% |  |\n"));
    assert_non_null(strstr(s, "| taa | spp=1 | 1.500 | 2.250 | 0.003 | 0.0500 | inf | inf | 0.9000 | 0.0250 | inf | "
                              "1.00 | 11.1% | FLIP, PSNR |\n"));
    /* the cornell rows sit under the cornell heading, before sponza's */
    assert_true(strstr(s, "| taa |") < strstr(s, "### sponza"));
    free(s);
}

static void test_svg_structure(void **state)
{
    (void)state;
    hz_et_row_t r[] = {
        row("cornell", "full-frame", 16, 8.0, 0.03, 36), row("cornell", "full-frame", 1, 0.6, 0.2, 22),
        row("cornell", "full-frame", 4, 2.1, 0.09, 29), row("cornell", "a<b&c\"", 1, 0.9, 0.1, INFINITY),
        row("cornell", "a<b&c\"", 2, 1.2, NAN, NAN), row("other", "x", 1, 1, 0.5, 10),
    };
    hz_et_pareto(r, HZ_ARRAY_LEN(r));
    size_t fronts = 0;
    for (size_t i = 0; i < 5; i++)
        fronts += r[i].pareto_flip + r[i].pareto_psnr;
    hz_error_t err;
    assert_int_equal(hz_et_write_svg(path_of("c.svg"), r, HZ_ARRAY_LEN(r), "cornell", &err), HZ_OK);
    char *s = slurp(path_of("c.svg"));
    assert_true(!strncmp(s, "<?xml", 5));
    assert_int_equal(count(s, "<svg "), 1);
    assert_int_equal(count(s, "</svg>"), 1);
    assert_int_equal(count(s, "<g "), count(s, "</g>"));
    assert_int_equal(count(s, "class=\"panel\""), 2);
    assert_int_equal(count(s, "class=\"series\""), 4);     /* 2 methods x 2 panels */
    assert_int_equal(count(s, "class=\"point\""), 2 * 4);  /* the NaN row is not drawn */
    assert_int_equal(count(s, "class=\"knob\""), 2 * 4);
    assert_int_equal(count(s, "class=\"pareto\""), fronts);
    assert_int_equal(count(s, "class=\"front\""), 2);
    assert_null(strstr(s, "other"));                      /* the other scene's rows are left out */
    assert_non_null(strstr(s, "a&lt;b&amp;c&quot; (spp)"));
    assert_null(strstr(s, "a<b"));
    for (const char *p = s; (p = strchr(p, '&')) != NULL; p++)
        assert_true(!strncmp(p, "&amp;", 5) || !strncmp(p, "&lt;", 4) || !strncmp(p, "&gt;", 4) ||
                    !strncmp(p, "&quot;", 6));
    assert_non_null(strstr(s, ">inf</text>"));                /* infinite PSNR marked at the top */
    /* knob labels of a series come in knob order: 1, 4, 16 although the rows are 16, 1, 4 */
    const char *l1 = strstr(s, "class=\"knob\"");
    const char *p1 = strstr(l1, ">1<"), *p4 = strstr(l1, ">4<"), *p16 = strstr(l1, ">16<");
    assert_true(p1 && p4 && p16 && p1 < p4 && p4 < p16);
    /* log axis ticks: 0.1 to 10 ms covers 0.6 .. 8 ms */
    assert_non_null(strstr(s, ">0.1</text>"));
    assert_non_null(strstr(s, ">10</text>"));
    free(s);
    assert_int_equal(hz_et_write_svg(path_of("d.svg"), r, HZ_ARRAY_LEN(r), "nope", &err), HZ_E_INVALID_ARG);
}

static void test_write_errors(void **state)
{
    (void)state;
    hz_et_row_t r = row("s", "m", 1, 1, 0.1, 20);
    hz_error_t err;
    const char *bad = path_of("missing/dir/x.csv");
    assert_int_equal(hz_et_write_csv(bad, &r, 1, &err), HZ_E_IO);
    assert_non_null(strstr(err.msg, bad));
    assert_int_equal(hz_et_write_markdown(path_of("missing/x.md"), &r, 1, &err), HZ_E_IO);
    assert_int_equal(hz_et_write_svg(path_of("missing/x.svg"), &r, 1, "s", &err), HZ_E_IO);
}

static void test_progress_bar(void **state)
{
    (void)state;
    FILE *f = tmpfile();
    assert_non_null(f);
    hz_progress_t p;
    hz_progress_begin(&p, f, true, 50);
    hz_progress_label(&p, "full-frame spp=4");
    for (int i = 0; i < 60; i++)
        hz_progress_step(&p, 1); /* overshoot is clamped */
    hz_progress_end(&p);
    long n = ftell(f);
    assert_true(n > 0);
    char *s = calloc(1, (size_t)n + 1);
    rewind(f);
    assert_int_equal(fread(s, 1, (size_t)n, f), (size_t)n);
    assert_non_null(strstr(s, "full-frame spp=4"));
    assert_non_null(strstr(s, "  0%"));
    assert_non_null(strstr(s, "100%  50/50"));
    assert_non_null(strstr(s, "[##############################]"));
    assert_int_equal(s[n - 1], '\n');
    assert_true(count(s, "\r") <= 103); /* redrawn only when the percentage changes */
    free(s);
    fclose(f);

    f = tmpfile();
    hz_progress_begin(&p, f, false, 10); /* not a terminal: nothing at all */
    hz_progress_label(&p, "x");
    hz_progress_step(&p, 5);
    hz_progress_end(&p);
    assert_int_equal(ftell(f), 0);
    fclose(f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pareto_front),  cmocka_unit_test(test_csv_text),
        cmocka_unit_test(test_markdown_table), cmocka_unit_test(test_svg_structure),
        cmocka_unit_test(test_write_errors),  cmocka_unit_test(test_progress_bar),
    };
    return HZ_RUN_GROUP(tests, setup, teardown);
}
