/*
 * `hzrt accel SCENE --motion-check N` through its entry point (host and, under qemu, AArch64): the motion BVHs
 * against brute force on small scenes with their own animation (BoxAnimated: 9 keys of rigid keys with
 * rotation; CesiumMan-small: skinning; the built-in scene's moving object) and with the procedural extreme
 * motions on the built-in scene (vertices crossing split planes, collapse to a point, 180 degrees in one
 * segment, rotation over 5 and 9 keys). Each run must print exactly "motion-check: N rays, 0 misses,
 * 0 mismatches" and exit 0; bad command lines exit 2.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "accel_cmd.h"
#include "pools.h"

/* The brute-force oracle (every triangle at the ray's time, scalar) is nine tenths of a run: under qemu fewer
 * rays go through the same builds and NEON kernels. */
#if defined(HZ_TEST_EMULATED)
#define RAYS "500"
#elif defined(HZ_SIMD_NEON)
#define RAYS "1500"
#else
#define RAYS "3000"
#endif

static char out_path[64];

/* Runs hz_cmd_accel with the arguments (NULL-terminated), stdout captured into `out`; returns the status. */
static int run(char *out, size_t cap, const char *a, ...)
{
    const char *argv[32];
    int argc = 0;
    argv[argc++] = "accel";
    va_list ap;
    va_start(ap, a);
    for (const char *s = a; s && argc < 31; s = va_arg(ap, const char *))
        argv[argc++] = s;
    va_end(ap);
    argv[argc] = NULL;
    assert_int_equal(hz_pools_init(hz_pools_get()), HZ_OK);
    fflush(stdout);
    int saved = dup(1);
    FILE *f = fopen(out_path, "w");
    assert_non_null(f);
    dup2(fileno(f), 1);
    int rc = hz_cmd_accel(argc, (char **)argv);
    fflush(stdout);
    dup2(saved, 1);
    close(saved);
    fclose(f);
    f = fopen(out_path, "r");
    assert_non_null(f);
    size_t n = fread(out, 1, cap - 1, f);
    out[n] = 0;
    fclose(f);
    return rc;
}

static const char *scene_path(const char *name, char *buf, size_t cap)
{
    const char *dir = getenv("HZ_SCENES_DIR");
    if (!dir || !*dir)
        return NULL;
    snprintf(buf, cap, "%s/%s.hzb", dir, name);
    return buf;
}

static void expect_clean(const char *out)
{
    if (!strstr(out, "motion-check: " RAYS " rays, 0 misses, 0 mismatches\n"))
        print_message("output: %s\n", out);
    assert_non_null(strstr(out, "motion-check: " RAYS " rays, 0 misses, 0 mismatches\n"));
}

static void test_procedural_extremes(void **state)
{
    (void)state;
    static const char *const blur[] = { "msbvh", "interp", "swept" };
    static const char *const motion[][2] = { { "cross", "3" }, { "collapse", "2" }, { "rot180", "2" },
                                             { "rotate", "5" }, { "sway", "9" } };
    char out[4096];
    for (size_t m = 0; m < HZ_ARRAY_LEN(motion); m++)
        for (size_t b = 0; b < HZ_ARRAY_LEN(blur); b++) {
            int rc = run(out, sizeof out, "builtin", "--motion-check", RAYS, "--blur-bvh", blur[b], "--motion",
                         motion[m][0], "--keys", motion[m][1], "--turns", "0.5", NULL);
            expect_clean(out);
            assert_int_equal(rc, 0);
        }
}

static void test_scene_animation(void **state)
{
    (void)state;
    char out[4096], path[4096];
    int rc = run(out, sizeof out, "builtin", "--motion-check", RAYS, NULL); /* its own moving object */
    expect_clean(out);
    assert_int_equal(rc, 0);
    static const char *const scenes[] = { "BoxAnimated", "CesiumMan-small" };
    static const char *const blur[] = { "msbvh", "interp", "swept" };
    for (size_t s = 0; s < HZ_ARRAY_LEN(scenes); s++) {
        if (!scene_path(scenes[s], path, sizeof path)) {
            print_message("HZ_SCENES_DIR is not set (run through `make test`): %s skipped\n", scenes[s]);
            continue;
        }
        for (size_t b = 0; b < HZ_ARRAY_LEN(blur); b++) {
            rc = run(out, sizeof out, path, "--motion-check", RAYS, "--blur-bvh", blur[b], "--interval", "0.25",
                     NULL);
            expect_clean(out);
            assert_int_equal(rc, 0);
        }
    }
}

static void test_bad_arguments(void **state)
{
    (void)state;
    char out[4096];
    assert_int_equal(run(out, sizeof out, "builtin", "--motion-check", "10", "--blur-bvh", "fast", NULL), 2);
    assert_int_equal(run(out, sizeof out, "builtin", "--motion-check", "10", "--keys", "4", NULL), 2);
    assert_int_equal(run(out, sizeof out, "builtin", "--motion-check", "10", "--motion", "rot180", "--keys", "3", NULL),
                     2);
    assert_int_equal(run(out, sizeof out, "builtin", "--blur-bvh", "interp", NULL), 2);
    assert_int_equal(run(out, sizeof out, "builtin", "--motion-check", "0", NULL), 2);
    assert_int_equal(run(out, sizeof out, "builtin", "--motion-check", "10", "--motion", "wobble", NULL), 2);
}

int main(void)
{
    snprintf(out_path, sizeof out_path, "/tmp/hz-motion-cli-%ld.txt", (long)getpid());
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_procedural_extremes),
        cmocka_unit_test(test_scene_animation),
    };
    int rc = HZ_RUN(tests);
    remove(out_path);
    return rc;
}
