/*
 * hzbake's command line against a careless or hostile user: the output is never one of the inputs (the model,
 * the sidecar, a .mtl or texture the import reads, also through a hard link): the bake is refused and the input
 * stays byte for byte as it was; sidecar sections that would silently do nothing are refused; a missing .mtl is
 * a warning; a truncated glb is a malformed file; a non-finite vertex is named as the model gives it; names from a
 * file go to the terminal with their control bytes shown; counts of one are singular.
 */
#include "hz_test.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char tmpdir[64];

typedef struct run {
    int status;
    char out[8192];
} run_t;

/* hzbake (HZ_BAKE) with args (NULL-terminated; names relative to tmpdir), run in tmpdir. */
static void bake(run_t *r, const char *const *args)
{
    const char *exe = getenv("HZ_BAKE");
    if (!exe || !*exe)
        fail_msg("HZ_BAKE is not set (run through `make test-host`)");
    char log[128];
    snprintf(log, sizeof log, "%s/log", tmpdir);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        if (chdir(tmpdir) != 0)
            _exit(127);
        int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(fd, 1);
        dup2(fd, 2);
        const char *argv[16];
        int n = 0;
        argv[n++] = exe;
        for (; args[n - 1] && n < 15; n++)
            argv[n] = args[n - 1];
        argv[n] = NULL;
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    int st;
    waitpid(pid, &st, 0);
    r->status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    FILE *f = fopen(log, "rb");
    assert_non_null(f);
    size_t n = fread(r->out, 1, sizeof r->out - 1, f);
    r->out[n] = 0;
    fclose(f);
}

static void put(const char *name, const void *data, size_t size)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    fclose(f);
}

static void put_text(const char *name, const char *text)
{
    put(name, text, strlen(text));
}

/* The file is exactly `want`. */
static void assert_file_is(const char *name, const void *want, size_t size)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    char *got = malloc(size + 16);
    size_t n = fread(got, 1, size + 16, f);
    fclose(f);
    if (n != size || memcmp(got, want, size))
        fail_msg("%s changed: %zu bytes, starting '%.4s' (want %zu bytes, '%.4s')", name, n, got, size,
                 (const char *)want);
    free(got);
}

static void expect(const run_t *r, int status, const char *says)
{
    if (r->status != status || (says && !strstr(r->out, says)))
        fail_msg("exit %d (want %d), output lacks '%s':\n%s", r->status, status, says ? says : "", r->out);
}

static const char obj[] = "mtllib box.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl red\n"
                          "f 1/1 2/2 3/3\n";
static const char mtl[] = "newmtl red\nKd 1 0 0\nmap_Kd tex.png\n";
/* a 1x1 PNG */
static const unsigned char png[] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00, 0x00,
    0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00, 0x00, 0x90, 0x77, 0x53, 0xde, 0x00, 0x00, 0x00, 0x0c, 0x49,
    0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0xf8, 0xcf, 0xc0, 0x00, 0x00, 0x03, 0x01, 0x01, 0x00, 0xc9, 0xfe, 0x92, 0xef,
    0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
};

static void test_the_output_is_never_an_input(void **state)
{
    (void)state;
    static const char sidecar[] = "light = position 0 2 0 color 1 1 1\n";
    put_text("box.obj", obj);
    put_text("box.mtl", mtl);
    put("tex.png", png, sizeof png);
    put_text("box.hzs", sidecar);
    run_t r;
    /* the model itself, the same file through another name, the sidecar: refused before any work */
    bake(&r, (const char *const[]){ "-q", "box.obj", "box.obj", NULL });
    expect(&r, 2, "the output is the model");
    assert_file_is("box.obj", obj, strlen(obj));
    char a[256], b[256];
    snprintf(a, sizeof a, "%s/box.obj", tmpdir);
    snprintf(b, sizeof b, "%s/link.hzb", tmpdir);
    assert_int_equal(link(a, b), 0);
    bake(&r, (const char *const[]){ "-q", "box.obj", "link.hzb", NULL });
    expect(&r, 2, "the output is the model");
    assert_file_is("box.obj", obj, strlen(obj));
    bake(&r, (const char *const[]){ "-q", "-s", "box.hzs", "box.obj", "box.hzs", NULL });
    expect(&r, 2, "the output is the sidecar");
    assert_file_is("box.hzs", sidecar, strlen(sidecar));
    /* files the import reads: the .mtl (assimp opens it), the texture (the baker decodes it) */
    bake(&r, (const char *const[]){ "-q", "box.obj", "box.mtl", NULL });
    expect(&r, 65, "box.mtl, a file the model reads, is the output");
    assert_file_is("box.mtl", mtl, strlen(mtl));
    bake(&r, (const char *const[]){ "-q", "box.obj", "tex.png", NULL });
    expect(&r, 65, "tex.png, a file the model reads, is the output");
    assert_file_is("tex.png", png, sizeof png);
    /* and a good bake next to them still works, with counts of one in the singular */
    bake(&r, (const char *const[]){ "box.obj", "box.hzb", NULL });
    expect(&r, 0, "box.hzb: 1 triangle, 3 vertices, 1 object, ");
    expect(&r, 0, ", 1 texture, 1 light, 0 camera keys;");
}

static void test_sidecar_sections_that_do_nothing_are_refused(void **state)
{
    (void)state;
    put_text("two.obj", "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no b\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf 4 5 6\n");
    put_text("twice.hzs", "[object *]\nmotion = spin\naxis = 0 1 0\nspeed = 10\n\n"
                          "[object *]\nmotion = spin\naxis = 0 1 0\nspeed = 20\n");
    run_t r;
    bake(&r, (const char *const[]){ "-q", "-s", "twice.hzs", "two.obj", "x.hzb", NULL });
    expect(&r, 68, "twice.hzs:6: [object \"*\"] repeats the section of line 1");
    put_text("over.hzs", "[object a]\nmotion = spin\naxis = 0 1 0\nspeed = 10\n\n"
                         "[object *]\nmotion = spin\naxis = 0 1 0\nspeed = 20\n");
    bake(&r, (const char *const[]){ "-q", "-s", "over.hzs", "two.obj", "x.hzb", NULL });
    expect(&r, 68, "over.hzs:1: [object \"a\"] does nothing");
    /* a later section that narrows an earlier one is what sections are for */
    put_text("narrow.hzs", "[object *]\nmotion = spin\naxis = 0 1 0\nspeed = 10\n\n[object b]\nmotion = none\n");
    bake(&r, (const char *const[]){ "-q", "-s", "narrow.hzs", "two.obj", "x.hzb", NULL });
    expect(&r, 0, NULL);
    put_text("tube.hzs", "name = t\ntube_sides = 2\n");
    bake(&r, (const char *const[]){ "-q", "-s", "tube.hzs", "two.obj", "x.hzb", NULL });
    expect(&r, 71, "tube.hzs:2: tube_sides = 2");
}

static void test_messages_say_what_is_wrong(void **state)
{
    (void)state;
    run_t r;
    /* a missing .mtl: a warning naming it, not silence */
    put_text("lost.obj", "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    bake(&r, (const char *const[]){ "-q", "lost.obj", "x.hzb", NULL });
    expect(&r, 0, "warning: lost.obj: names 'gone.mtl', which cannot be opened");
    /* a vertex the model gives as "inf 0 0" is named so, not after transforms as (inf -nan -nan) */
    put_text("inf.obj", "v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    bake(&r, (const char *const[]){ "-q", "inf.obj", "x.hzb", NULL });
    expect(&r, 71, "(inf 0 0)");
    assert_null(strstr(r.out, "nan"));
    /* a glb cut short is a malformed file (68), not an unsupported format */
    static const unsigned char glb[10] = { 'g', 'l', 'T', 'F', 2, 0, 0, 0, 0x40, 0x00 };
    put("cut.glb", glb, sizeof glb);
    bake(&r, (const char *const[]){ "-q", "cut.glb", "x.hzb", NULL });
    expect(&r, 68, "not a readable glTF file (truncated or corrupt");
    /* a scene name with control bytes: shown as \xNN by --info, never sent to the terminal */
    put_text("esc.hzs", "name = red\x1b[31mname\nlight = position 0 2 0 color 1 1 1\n");
    put_text("esc.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    bake(&r, (const char *const[]){ "-q", "-s", "esc.hzs", "esc.obj", "esc.hzb", NULL });
    expect(&r, 0, NULL);
    bake(&r, (const char *const[]){ "--info", "esc.hzb", NULL });
    expect(&r, 0, "scene        red\\x1b[31mname");
    assert_null(strchr(r.out, 0x1b));
    /* a FIFO as the sidecar is refused at once, not waited on (the alarm ends this test if it hangs) */
    char fifo[128];
    snprintf(fifo, sizeof fifo, "%s/fifo.hzs", tmpdir);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    alarm(60);
    bake(&r, (const char *const[]){ "-q", "-s", "fifo.hzs", "esc.obj", "x.hzb", NULL });
    alarm(0);
    expect(&r, 73, "fifo.hzs: not a regular file");
}

/* The command line is read from hzbake's option table: an unknown option, a missing value and a value outside
 * the entry's limits are each refused with status 2, naming the option and the reason, before any file is
 * touched; the help lists every option with its limits from the same table. */
static void test_bad_command_lines_are_refused_by_name(void **state)
{
    (void)state;
    run_t r;
    put("box.obj", obj, sizeof obj - 1);
    bake(&r, (const char *const[]){ "--fast", "box.obj", "a.hzb", NULL });
    expect(&r, 2, "unknown option '--fast' (try hzbake --help)");
    bake(&r, (const char *const[]){ "box.obj", "a.hzb", "-s", NULL });
    expect(&r, 2, "-s needs a value FILE");
    bake(&r, (const char *const[]){ "--info", NULL });
    expect(&r, 2, "--info needs a value FILE.hzb");
    bake(&r, (const char *const[]){ "--texture-max", "20000", "box.obj", "a.hzb", NULL });
    expect(&r, 2, "--texture-max: 20000 is outside [1, 16384]");
    bake(&r, (const char *const[]){ "--timeout", "0", "box.obj", "a.hzb", NULL });
    expect(&r, 2, "--timeout: 0 is outside [1, 86400]");
    bake(&r, (const char *const[]){ "--timeout", "10s", "box.obj", "a.hzb", NULL });
    expect(&r, 2, "--timeout: '10s' is not an integer in [1, 86400]");
    bake(&r, (const char *const[]){ "box.obj", "a.hzb", "b.hzb", NULL });
    expect(&r, 2, "unexpected argument 'b.hzb'");
    char out[128];
    struct stat st;
    snprintf(out, sizeof out, "%s/a.hzb", tmpdir);
    assert_int_not_equal(stat(out, &st), 0); /* nothing was baked */
    bake(&r, (const char *const[]){ "--help", NULL });
    expect(&r, 0, "  -s, --sidecar FILE");
    expect(&r, 0, "--texture-max N   largest stored texture level (overrides the sidecar; default 1024) [1..16384]");
    expect(&r, 0, "--timeout S");
    bake(&r, (const char *const[]){ "-h", NULL });
    expect(&r, 0, "usage: hzbake [options] MODEL OUT.hzb");
    /* a good line still bakes: the short forms are the table's aliases */
    bake(&r, (const char *const[]){ "-q", "--texture-max", "16", "box.obj", "a.hzb", NULL });
    expect(&r, 0, NULL);
    assert_int_equal(stat(out, &st), 0);
}

static int setup(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/hzbake-cli.XXXXXX");
    return mkdtemp(tmpdir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    return system(cmd) == 0 ? 0 : -1;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_output_is_never_an_input),
        cmocka_unit_test(test_sidecar_sections_that_do_nothing_are_refused),
        cmocka_unit_test(test_messages_say_what_is_wrong),
        cmocka_unit_test(test_bad_command_lines_are_refused_by_name),
    };
    return HZ_RUN_GROUP(tests, setup, teardown);
}
