/*
 * One frame loop for files and displays (show.h), through the commands' entry points: every render mode with
 * options that change the image runs on the display path (a simulated display, and a recorded edge trace) into
 * every sink that needs no device, and writes its report with each frame's quality level; with the governor off a
 * display run renders exactly the frames the offline files run renders (byte for byte in frames.y4m); usage
 * errors of the combination are refused before anything is written.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "latency.h"
#include "render_cmd.h"

static char dir[64];

static int run_cmd(int (*cmd)(int, char **), const char *name, const char *a, va_list ap)
{
    const char *argv[48];
    int argc = 0;
    argv[argc++] = name;
    for (const char *s = a; s && argc < 47; s = va_arg(ap, const char *))
        argv[argc++] = s;
    argv[argc] = NULL;
    fflush(stdout);
    return cmd(argc, (char **)argv);
}

static int render(const char *a, ...)
{
    va_list ap;
    va_start(ap, a);
    int rc = run_cmd(hz_cmd_render, "render", a, ap);
    va_end(ap);
    return rc;
}

static int latency(const char *a, ...)
{
    va_list ap;
    va_start(ap, a);
    int rc = run_cmd(hz_cmd_latency, "latency", a, ap);
    va_end(ap);
    return rc;
}

static long file_size(const char *sub, const char *name)
{
    char p[160];
    struct stat st;
    snprintf(p, sizeof p, "%s/%s/%s", dir, sub, name);
    return stat(p, &st) == 0 ? (long)st.st_size : -1;
}

static char *slurp(const char *sub, const char *name, size_t *n)
{
    char p[160];
    snprintf(p, sizeof p, "%s/%s/%s", dir, sub, name);
    FILE *f = fopen(p, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)len + 1);
    assert_non_null(buf);
    *n = fread(buf, 1, (size_t)len, f);
    buf[*n] = 0;
    fclose(f);
    return buf;
}

static char *out(const char *sub)
{
    static char p[160];
    snprintf(p, sizeof p, "%s/%s", dir, sub);
    return p;
}

/* Every mode, each with an option of its own, on a simulated display (virtual clock) into the null sink and into
 * files; the report's frames.csv has a level column (all 0: the governor is off with a simulated clock). */
/* The frame size of the display-path runs: a quarter of the pixels under qemu (the same paths; 40 frames each, so
 * the lock is judged as natively). */
#define SIZE_W HZ_EMULATED_LESS(48, 24)
#define SIZE_H HZ_EMULATED_LESS(32, 16)
#define SIZE HZ_EMULATED_LESS("48x32", "24x16")
/* Each mode into both sinks; under qemu into one, alternating (full and tdense to none, TAA and adaptive to
 * files): the sink takes the same 8-bit frames from every mode, and adaptive's 40 frames cost half the case. */
#define SINKS_PER_MODE HZ_EMULATED_LESS(2, 1)

static void test_every_mode_on_the_display_path(void **state)
{
    (void)state;
    static const char *const modes[][4] = {
        { "full", "--spp", "4", "--bounces" },
        { "taa", "--transparency", "std", "--rr-shadows" },
        { "tdense", "--shutter", "0.5", "--no-reflected-mv" },
        { "adaptive", "--tau", "0.3", "--normal-angle" },
    };
    static const char *const last[] = { "1", NULL, NULL, "20" };
    for (int m = 0; m < 4; m++) {
        for (int k = 0; k < SINKS_PER_MODE; k++) {
            const int files = SINKS_PER_MODE == 2 ? k : m % 2;
            char sub[32];
            snprintf(sub, sizeof sub, "%s-%d", modes[m][0], files);
            int rc = latency("--virtual", "--source", "sim", "--hz", "120", "--render-model", "const:2ms", "--render",
                             "scene", "--mode", modes[m][0], modes[m][1], modes[m][2], modes[m][3],
                             last[m] ? last[m] : "--quiet", "--sink", files ? "files" : "none", "--size", SIZE,
                             "--frames", "40", "--threads", "2", "--quiet", "--out", out(sub), NULL);
            if (rc)
                fail_msg("%s: exit %d", sub, rc);
            assert_true(file_size(sub, "report.json") > 0 && file_size(sub, "summary.json") > 0);
            size_t n;
            char *csv = slurp(sub, "frames.csv", &n);
            assert_non_null(csv);
            assert_non_null(strstr(csv, ",status,level\n"));
            /* 40 rows, each ending in level 0 */
            int rows = 0;
            for (char *line = strchr(csv, '\n'); line && line[1]; line = strchr(line + 1, '\n')) {
                char *end = strchr(line + 1, '\n');
                assert_non_null(end);
                assert_true(end[-1] == '0' && end[-2] == ',');
                rows++;
            }
            assert_int_equal(rows, 40);
            free(csv);
            if (files)
                assert_true(file_size(sub, "frames.y4m") > SIZE_W * SIZE_H * 40 &&
                            (file_size(sub, "last.png") > 0 || file_size(sub, "last.ppm") > 0)); /* no libpng: PPM */
            else
                assert_int_equal(file_size(sub, "frames.y4m"), -1);
        }
    }
}

/* A recorded edge trace (CSV, 120 Hz) as the v-sync source on its own clock, every mode. */
static void test_every_mode_on_a_recorded_trace(void **state)
{
    (void)state;
    char csv[160], src[176];
    snprintf(csv, sizeof csv, "%s/edges.csv", dir);
    FILE *f = fopen(csv, "w");
    assert_non_null(f);
    for (int i = 0; i < 400; i++)
        fprintf(f, "%lld,1\n", 1000000000LL + (long long)i * 8333333LL);
    fclose(f);
    snprintf(src, sizeof src, "csv:%s", csv);
    static const char *const modes[] = { "full", "taa", "tdense", "adaptive" };
    for (int m = 0; m < 4; m++) {
        char sub[32];
        snprintf(sub, sizeof sub, "trace-%s", modes[m]);
        int rc = latency("--virtual", "--source", src, "--hz", "120", "--render-model", "const:3ms", "--render", "scene",
                         "--mode", modes[m], "--size", HZ_EMULATED_LESS("40x24", "20x12"), "--frames", "60", "--threads", "2", "--quiet", "--out",
                         out(sub), NULL);
        if (rc)
            fail_msg("%s: exit %d", sub, rc);
        assert_true(file_size(sub, "frames.csv") > 0 && file_size(sub, "summary.json") > 0);
    }
}

/* The files run (offline) and a simulated display's run with the governor off render the same frames: scene
 * time comes from the display's refresh count, exactly. Also with a recorded trace replayed on its own clock. */
static void test_display_run_renders_the_offline_frames(void **state)
{
    (void)state;
    assert_int_equal(render("builtin", "--mode", "taa", "--size", "64x36", "--frames", "12", "--hz", "120",
                            "--start", "0.25", "--threads", "2", "--quiet", "--out", out("offline"), NULL),
                     0);
    assert_int_equal(render("builtin", "--mode", "taa", "--size", "64x36", "--frames", "12", "--hz", "120",
                            "--start", "0.25", "--threads", "2", "--source", "sim", "--virtual", "--render-model",
                            "const:3ms", "--budget", "off", "--lock-min-run", "8", "--quiet", "--out", out("display"), NULL),
                     0);
    size_t na, nb;
    char *a = slurp("offline", "frames.y4m", &na), *b = slurp("display", "frames.y4m", &nb);
    assert_non_null(a);
    assert_non_null(b);
    assert_int_equal(na, nb);
    assert_memory_equal(a, b, na);
    free(a);
    free(b);
    assert_true(file_size("display", "report.json") > 0);
    assert_int_equal(file_size("offline", "report.json"), -1); /* offline: no display, no latency report */
}

static void test_usage_errors(void **state)
{
    (void)state;
    assert_int_equal(render("builtin", "--budget", "on", "--out", out("u"), NULL), 2); /* offline sets no pace */
    assert_int_equal(render("builtin", "--source", "offline", "--seconds", "2", "--out", out("u"), NULL), 2);
    assert_int_equal(render("builtin", "--sink", "none", "--source", "sim", "--no-y4m", "--out", out("u"), NULL), 2);
    assert_int_equal(render("builtin", "--source", "offline", "--virtual", "--out", out("u"), NULL), 2);
    assert_int_equal(render("builtin", "--sink", "files:/tmp/x", "--out", out("u"), NULL), 2);
    assert_int_equal(render("builtin", "--level-error", "0", "--out", out("u"), NULL), 2);
    assert_int_equal(file_size("u", "summary.json"), -1);
}

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/hz-show-XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_mode_on_the_display_path),
        cmocka_unit_test(test_every_mode_on_a_recorded_trace),
        cmocka_unit_test(test_display_run_renders_the_offline_frames),
        cmocka_unit_test(test_usage_errors),
    };
    return HZ_RUN_GROUP(tests, setup, teardown);
}
