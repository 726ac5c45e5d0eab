/*
 * `hzrt latency` end to end, through its entry point: bad command lines are usage errors (2), bad inputs
 * fail with their own status (64 + hz status) and a message, a good run writes its four files.
 */
#include "hz_test.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hz/status.h"
#include "hz_traces.h" /* the VCDs of test/traces as string arrays */
#include "latency.h"

static char dir[64];

/* "latency" and the NULL-terminated arguments into argv[32]; returns argc. */
static int build_argv(const char **argv, const char *a, va_list ap)
{
    int argc = 0;
    argv[argc++] = "latency";
    for (const char *s = a; s && argc < 31; s = va_arg(ap, const char *))
        argv[argc++] = s;
    argv[argc] = NULL;
    return argc;
}

static int run(const char *a, ...)
{
    const char *argv[32];
    va_list ap;
    va_start(ap, a);
    int argc = build_argv(argv, a, ap);
    va_end(ap);
    fflush(stdout);
    return hz_cmd_latency(argc, (char **)argv);
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static int exists(const char *name)
{
    char p[128];
    struct stat st;
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return stat(p, &st) == 0 && st.st_size > 0;
}

static void test_usage_errors(void **state)
{
    (void)state;
    assert_int_equal(run("--bogus", NULL), 2);
    assert_int_equal(run("--frames", "0", NULL), 2);
    assert_int_equal(run("--frames", NULL), 2);
    assert_int_equal(run("--hz", "abc", NULL), 2);
    assert_int_equal(run("--source", "carrier-pigeon", NULL), 2);
    assert_int_equal(run("--sink", "crt", NULL), 2);
    assert_int_equal(run("--edge", "sideways", NULL), 2);
    assert_int_equal(run("--frames", "10", "--seconds", "1", NULL), 2);
    assert_int_equal(run("--virtual", "--source", "gpio", NULL), 2);                 /* live device, sim clock */
    assert_int_equal(run("--virtual", "--frames", "10", NULL), 2);                   /* no render model */
    assert_int_equal(run("--render-model", "const:1ms", NULL), 2);                   /* only with --virtual */
    assert_int_equal(run("--virtual", "--render-model", "gaussian:1ms", NULL), 2);
    assert_int_equal(run("--virtual", "--render-model", "const:3 parsecs", NULL), 2);
    assert_int_equal(run("--scene", "builtin", NULL), 2);                              /* only with --render scene */
    assert_int_equal(run("--threads", "2", "--render", "scene", "--edges-only", NULL), 2); /* renders nothing */
    assert_int_equal(run("--threads", "0", "--render", "scene", NULL), 2);
    assert_int_equal(run("--mode", "full", NULL), 2); /* the test pattern has no mode */
    assert_int_equal(run("--spp", "4", "--render", "scene", NULL), 2); /* full mode's option in tdense */
    /* the governor: on/off only; it picks a scene's quality, in real time */
    assert_int_equal(run("--budget", "maybe", "--render", "scene", NULL), 2);
    assert_int_equal(run("--budget", "on", NULL), 2);
    assert_int_equal(run("--budget", "on", "--render", "scene", "--virtual", "--render-model", "const:1ms", NULL), 2);
    assert_int_equal(run("--level-error", "8", NULL), 2);
    assert_int_equal(run("--help", NULL), 0);
}

static void test_bad_inputs_have_their_own_status(void **state)
{
    (void)state;
    char vcd[96], csv[96];
    snprintf(vcd, sizeof vcd, "vcd:%s/bad.vcd", dir);
    snprintf(csv, sizeof csv, "csv:%s/bad.csv", dir);
    write_file(vcd + 4, "$timescale 7 ns $end\n");
    write_file(csv + 4, "100\n50\n");
    assert_int_equal(run("--source", vcd, "--quiet", "--out", dir, NULL), 64 + HZ_E_FORMAT);
    assert_int_equal(run("--source", csv, "--quiet", "--out", dir, NULL), 64 + HZ_E_FORMAT);
    assert_int_equal(run("--source", "vcd:/nonexistent/trace.vcd", NULL), 64 + HZ_E_IO);
    write_file(csv + 4, "# nothing but a comment\n");
    assert_int_equal(run("--source", csv, "--quiet", "--out", dir, NULL), 64 + HZ_E_FORMAT); /* no edges */
    assert_int_equal(run("--sink", "v4l2:/dev/video1:nv12", NULL), 64 + HZ_E_UNSUPPORTED);
    assert_int_equal(run("--render-scale", "0", NULL), 2);
    /* the simulated source: a board whose default is its GPIO line would stop at the missing chip first */
    assert_int_equal(run("--source", "sim", "--render", "scene", "--scene", "/nonexistent/scene.hzb", "--frames", "1",
                         "--quiet", "--out", dir, NULL),
                     64 + HZ_E_IO);
    /* DRM: a malformed mode is a usage error; a card that is not there a device error (72 where the build has
     * no DRM port); --source drm needs the DRM sink. */
    assert_int_equal(run("--sink", "drm:card0:Virtual-1:640x", "--frames", "1", NULL), 2);
    int rc = run("--sink", "drm:/dev/dri/card-hz-none", "--frames", "1", NULL);
    assert_true(rc == 64 + HZ_E_DEVICE || rc == 64 + HZ_E_UNSUPPORTED);
    assert_int_equal(run("--source", "drm", "--frames", "1", NULL), 2);
    assert_int_equal(run("--sink", "drm", "--drm-buffers", "4", NULL), 2);
    assert_false(exists("report.json")); /* nothing half-written by the failures */
}

static void test_good_runs_write_their_files(void **state)
{
    (void)state;
    assert_int_equal(run("--virtual", "--source", "sim", "--hz", "240", "--jitter-us", "50", "--miss-pct", "1",
                         "--render-model", "uniform:0.2P:0.7P", "--wake", "50us", "--frames", "600", "--size",
                         "96x54", "--marker", "--quiet", "--out", dir, NULL),
                     0);
    assert_true(exists("frames.csv") && exists("edges.csv") && exists("report.json") && exists("histogram.svg"));
    /* The edges it wrote are a trace: analyse them again. */
    char csv[96];
    snprintf(csv, sizeof csv, "csv:%s/edges.csv", dir);
    char again[96];
    snprintf(again, sizeof again, "%s/again", dir);
    assert_int_equal(run("--source", csv, "--hz", "240", "--quiet", "--out", again, NULL), 0);
    /* Eight frames are too few edges for the default lock verdict (32 in a row): "no lock" (3), files still
     * written; unless a shorter run is stated. */
    unlink(csv + 4);
    assert_int_equal(run("--virtual", "--source", "sim", "--hz", "60", "--render-model", "const:5ms", "--frames", "8",
                         "--quiet", "--out", dir, NULL),
                     HZ_EXIT_NOLOCK);
    assert_true(exists("edges.csv"));
    /* The built-in scene through the renderer, small and scaled up (once per process: the renderer's pool). */
    assert_int_equal(run("--virtual", "--source", "sim", "--hz", "60", "--render", "scene", "--render-scale", "4",
                         "--size", "64x36", "--render-model", "const:5ms", "--frames", "8", "--lock-min-run", "8",
                         "--quiet", "--out", dir, NULL),
                     0);
    /* A VCD trace, edges only. */
    char vcd[96];
    snprintf(vcd, sizeof vcd, "%s/ok.vcd", dir);
    FILE *f = fopen(vcd, "w");
    fprintf(f, "$timescale 1 ns $end $var wire 1 ! v $end $enddefinitions $end\n#0 0!\n");
    for (int i = 1; i <= 100; i++)
        fprintf(f, "#%d 1!\n#%d 0!\n", i * 8333333, i * 8333333 + 500000);
    fclose(f);
    char src[128];
    snprintf(src, sizeof src, "vcd:%s", vcd);
    assert_int_equal(run("--source", src, "--hz", "120", "--quiet", "--out", again, NULL), 0);
    /* The same 120 Hz trace taken for the default 240 Hz locks on every other slot: half the refreshes
     * "missed" is no lock, not a 240 Hz display. */
    assert_int_equal(run("--source", src, "--hz", "240", "--quiet", "--out", again, NULL), HZ_EXIT_NOLOCK);
}

static void write_lines(const char *path, const char *const *lines, size_t n)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    for (size_t i = 0; i < n; i++)
        fputs(lines[i], f);
    fclose(f);
}

/* Reads a whole small file into buf (NUL-terminated). */
static void slurp(const char *path, char *buf, size_t cap)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    size_t n = fread(buf, 1, cap - 1, f);
    buf[n] = '\0';
    fclose(f);
}

/* Runs with stdout into a file; returns the status and leaves the output in buf. */
static int run_captured(char *buf, size_t cap, const char *a, ...)
{
    const char *argv[32];
    va_list ap;
    va_start(ap, a);
    int argc = build_argv(argv, a, ap);
    va_end(ap);
    char path[96];
    snprintf(path, sizeof path, "%s/stdout.txt", dir);
    fflush(stdout);
    int saved = dup(1);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    dup2(fileno(f), 1);
    int rc = hz_cmd_latency(argc, (char **)argv);
    fflush(stdout);
    dup2(saved, 1);
    close(saved);
    fclose(f);
    slurp(path, buf, cap);
    return rc;
}

static void test_sigrok_demo_is_no_lock(void **state)
{
    (void)state;
    /* sigrok-cli's demo patterns (test/traces/README.md): eight channels parse; none is a v-sync, so every one
     * is "no lock" with status 3 and no period, never the nominal rate echoed. */
    char vcd[96], src[128], out[96];
    static char text[65536];
    snprintf(vcd, sizeof vcd, "%s/sigrok-demo-200k.vcd", dir);
    write_lines(vcd, hz_trace_sigrok_demo_200k_vcd,
                sizeof hz_trace_sigrok_demo_200k_vcd / sizeof hz_trace_sigrok_demo_200k_vcd[0]);
    snprintf(src, sizeof src, "vcd:%s", vcd);
    snprintf(out, sizeof out, "%s/demo", dir);
    assert_int_equal(run_captured(text, sizeof text, "--source", src, "--signal", "D0", "--out", out, NULL),
                     HZ_EXIT_NOLOCK);
    assert_non_null(strstr(text, "no lock"));
    assert_null(strstr(text, "period"));
    assert_null(strstr(text, "240.0000 Hz"));
    char path[128];
    snprintf(path, sizeof path, "%s/report.json", out);
    slurp(path, text, sizeof text);
    assert_non_null(strstr(text, "\"locked\": false"));
    assert_non_null(strstr(text, "\"verdict\": \"no lock\""));
    /* edges.csv keeps the trace's own times: D0's first edge is the 1->0 at #5 (5 us). */
    snprintf(path, sizeof path, "%s/edges.csv", out);
    slurp(path, text, sizeof text);
    assert_non_null(strstr(text, "t_ns,level,class,slot,residual_ns,missed_before,reason,frame_id,loop_ns\n5000,0,"));
    snprintf(vcd, sizeof vcd, "%s/sigrok-demo-1k.vcd", dir);
    write_lines(vcd, hz_trace_sigrok_demo_1k_vcd,
                sizeof hz_trace_sigrok_demo_1k_vcd / sizeof hz_trace_sigrok_demo_1k_vcd[0]);
    snprintf(src, sizeof src, "vcd:%s", vcd);
    const char *ch[] = { "D0", "D1", "D2", "D3", "D4", "D5", "D6" };
    for (int c = 0; c < 7; c++) {
        int rc = run_captured(text, sizeof text, "--source", src, "--signal", ch[c], "--out", out, NULL);
        if (rc != HZ_EXIT_NOLOCK || strstr(text, "period"))
            fail_msg("1 kHz demo, %s: status %d, output:\n%s", ch[c], rc, text);
    }
    /* D7 never changes: a trace without edges is a format error, as before. */
    assert_int_equal(run("--source", src, "--signal", "D7", "--quiet", "--out", out, NULL), 64 + HZ_E_FORMAT);
}

static void test_lock_verdict_and_rate_warning(void **state)
{
    (void)state;
    /* A clean 240 Hz trace whose first edge is at 2,025,764 ns: locked, measured 240 Hz, times kept. */
    char vcd[96], src[128], out[96], path[128];
    static char text[65536];
    snprintf(vcd, sizeof vcd, "%s/clean.vcd", dir);
    FILE *f = fopen(vcd, "w");
    assert_non_null(f);
    fprintf(f, "$timescale 1 ns $end $var wire 1 ! v $end $enddefinitions $end\n#0 0!\n");
    for (int64_t i = 0; i < 200; i++)
        fprintf(f, "#%lld 1!\n#%lld 0!\n", (long long)(2025764 + i * 4166667), (long long)(2025764 + i * 4166667 + 1000));
    fclose(f);
    snprintf(src, sizeof src, "vcd:%s", vcd);
    snprintf(out, sizeof out, "%s/clean", dir);
    assert_int_equal(run_captured(text, sizeof text, "--source", src, "--hz", "240", "--out", out, NULL), 0);
    assert_non_null(strstr(text, "240.0000 Hz"));
    assert_null(strstr(text, "warning"));
    snprintf(path, sizeof path, "%s/edges.csv", out);
    slurp(path, text, sizeof text);
    assert_non_null(strstr(text, "frame_id,loop_ns\n2025764,1,vsync,0,"));
    assert_non_null(strstr(text, "\n2026764,0,other-edge,"));
    /* Against --hz 60: still the measured 240 Hz, with a plain warning and no ppm against 60 Hz. */
    assert_int_equal(run_captured(text, sizeof text, "--source", src, "--hz", "60", "--out", out, NULL), 0);
    assert_non_null(strstr(text, "240.0000 Hz"));
    assert_non_null(strstr(text, "warning"));
    assert_null(strstr(text, "ppm"));
    /* A stated minimum run longer than the trace: no lock. */
    assert_int_equal(run("--source", src, "--lock-min-run", "500", "--quiet", "--out", out, NULL), HZ_EXIT_NOLOCK);
    /* Bad limits are usage errors. */
    assert_int_equal(run("--source", src, "--lock-max-spurious-pct", "101", "--out", out, NULL), 2);
    assert_int_equal(run("--source", src, "--lock-min-run", "1", "--out", out, NULL), 2);
}

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/hz-latency-cli-XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

/* rm -r without a shell (the VM tier has none): the directory holds files and one level of subdirectories. */
static int remove_tree(const char *path, int depth)
{
    DIR *d = opendir(path);
    if (!d)
        return -1;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        char p[512];
        if ((size_t)snprintf(p, sizeof p, "%s/%s", path, e->d_name) >= sizeof p)
            continue;
        struct stat st;
        if (lstat(p, &st) == 0 && S_ISDIR(st.st_mode) && depth > 0)
            remove_tree(p, depth - 1);
        else
            unlink(p);
    }
    closedir(d);
    return rmdir(path);
}

static int teardown(void **state)
{
    (void)state;
    return remove_tree(dir, 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_usage_errors),
        cmocka_unit_test(test_bad_inputs_have_their_own_status),
        cmocka_unit_test(test_good_runs_write_their_files),
        cmocka_unit_test(test_sigrok_demo_is_no_lock),
        cmocka_unit_test(test_lock_verdict_and_rate_warning),
    };
    return HZ_RUN_GROUP(tests, setup, teardown);
}
