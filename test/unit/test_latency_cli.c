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
#include "latency.h"

static char dir[64];

static int run(const char *a, ...)
{
    const char *argv[32];
    int argc = 0;
    argv[argc++] = "latency";
    va_list ap;
    va_start(ap, a);
    for (const char *s = a; s && argc < 31; s = va_arg(ap, const char *))
        argv[argc++] = s;
    va_end(ap);
    argv[argc] = NULL;
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
    /* The built-in scene through the renderer, small and scaled up. */
    assert_int_equal(run("--virtual", "--source", "sim", "--hz", "60", "--render", "scene", "--render-scale", "4",
                         "--size", "64x36", "--render-model", "const:5ms", "--frames", "8", "--quiet", "--out", dir,
                         NULL),
                     0);
    /* The edges it wrote are a trace: analyse them again. */
    char csv[96];
    snprintf(csv, sizeof csv, "csv:%s/edges.csv", dir);
    char again[96];
    snprintf(again, sizeof again, "%s/again", dir);
    assert_int_equal(run("--source", csv, "--hz", "240", "--quiet", "--out", again, NULL), 0);
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
    assert_int_equal(run("--source", src, "--quiet", "--out", again, NULL), 0);
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
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
