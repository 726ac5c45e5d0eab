/*
 * LDR-FLIP: identical images give 0; constant images give the closed-form colour term (computed here
 * independently, in double); symmetry, range, the observer distance; argument errors; and the mean against
 * NVIDIA's reference implementation on image pairs from real renders and on pairs made from real textures.
 *
 * Reference values: NVIDIA FLIP v1.6 (github.com/NVlabs/flip, commit 1eb247c), its C++ CPU tool built outside
 * this repository (never committed) with
 *     g++ -O2 -std=c++17 -I src/cpp src/cpp/tool/FLIP-tool.cpp -o flip
 * (default observer: 0.7 m from a 0.7 m wide 3840-pixel display, 67 ppd; -v 1 prints "Mean: x", -nerm skips
 * the error map).
 *
 * 1. Renders (test/golden/flip/, 160x90 8-bit sRGB PNGs written by `hzrt render`): 1, 4 and 16 spp and TAA
 *    against 256 spp on CornellBox-Mirror, Sponza, Lost Empire and the built-in scene. Made from the repository
 *    root after `make scenes all` with
 *        R=build/host-sim/bin/hzrt; D=test/golden/flip; S=build/scenes; T=$(mktemp -d)
 *        shot() { n=$1; s=$2; shift 2; f=$S/$s.hzb; [ $s = builtin ] && f=builtin
 *                 $R render $f --size 160x90 --no-y4m --quiet --out $T "$@" && cp $T/last.png $D/$n.png; }
 *        for s in CornellBox-Mirror sponza lost-empire builtin; do
 *            shot $s-1spp $s --spp 1; shot $s-256spp $s --spp 256; done
 *        shot lost-empire-16spp lost-empire --spp 16
 *        shot builtin-4spp builtin --spp 4
 *        for s in CornellBox-Mirror sponza; do   # TAA's frame 23 (t = 23/240 s) and 256 spp at that time
 *            shot $s-taa-f23 $s --mode taa --frames 24; shot $s-256spp-f23 $s --spp 256 --start 0.0958333333; done
 *    and the values below by
 *        ./flip -r $D/<ref>.png -t $D/<test>.png -v 1 -nerm
 *    for each pair of render_pairs[]. The PNGs are the test's input (not re-rendered), so the check holds
 *    whatever the renderer does later.
 * 2. Texture crops of two shared-scene textures (LushPine.png from pine.zip, lost_empire-RGB.png from
 *    lost-empire.zip; `make tests` unpacks them into build/scenes-src/) with integer distortions, so they are
 *    bit-identical on every platform. The values were produced by:
 *        build/host-sim/test/unit/test_flip --write-pairs /tmp/flip-pairs
 *        for p in pine-noise pine-noise-low pine-blur atlas-shift atlas-banding pine-fireflies atlas-tint; do
 *            ./flip -r /tmp/flip-pairs/$p-ref.png -t /tmp/flip-pairs/$p-test.png -v 1 -nerm
 *        done
 * The tool sums its error map in single precision, which moves its printed mean by up to ~2e-5 on these sizes;
 * summed in double, its map's mean matches ours to ~1e-7 and no pixel differs by more than 1e-5 (checked with
 * a local harness around FLIP.h, not part of this repository). The test therefore holds the texture pairs' means
 * to 1e-4 and the small rendered pairs' to 1e-5 (measured: at most 4.9e-7, the tool's printed rounding), 10 and
 * 100 times tighter than the 1e-3 the issue asks for.
 * Builds without libpng (the AArch64 cross build) cannot read the PNGs and skip the two NVIDIA checks; the FLIP
 * code is the same C the host build checks.
 */
#include "hz_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "et_flip.h"
#include "hz/hash.h"
#include "hz/image.h"
#include "imageio.h"

/* The unpacked scene zips (make exports HZ_SCENES_UNPACK; `make tests` unpacks the two used here). */
static const char *data_dir(void)
{
    const char *d = getenv("HZ_SCENES_UNPACK");
    return d && *d ? d : "build/scenes-src";
}

static uint8_t buf[64 << 20] /* the 2048x2048 atlas is 48 MiB as floats */ HZ_ALIGNED(64);
static hz_arena_t arena;

static int setup(void **state)
{
    (void)state;
    hz_arena_init(&arena, "test", buf, sizeof buf);
    return 0;
}

/* ---- the reference pairs ---- */

typedef enum { NOISE, NOISE_LOW, BLUR, SHIFT, BANDING, FIREFLIES, TINT } distortion_t;

typedef struct pair {
    const char *name, *source;
    uint32_t x0, y0, w, h;
    distortion_t how;
    double nvidia_mean; /* NVIDIA FLIP v1.6 "Mean:" (6 decimals) */
} pair_t;

static const pair_t pairs[] = {
    { "pine-noise", "pine/LushPine.png", 128, 128, 256, 256, NOISE, 0.076229 },
    { "pine-noise-low", "pine/LushPine.png", 96, 200, 200, 160, NOISE_LOW, 0.029737 },
    { "pine-blur", "pine/LushPine.png", 128, 128, 256, 256, BLUR, 0.163284 },
    { "atlas-shift", "lost-empire/lost_empire-RGB.png", 0, 384, 256, 256, SHIFT, 0.088186 },
    { "atlas-banding", "lost-empire/lost_empire-RGB.png", 512, 640, 256, 256, BANDING, 0.184115 },
    { "pine-fireflies", "pine/LushPine.png", 64, 0, 256, 192, FIREFLIES, 0.051951 },
    { "atlas-tint", "lost-empire/lost_empire-RGB.png", 1024, 1024, 192, 192, TINT, 0.225287 },
};

static uint8_t clamp8(int v)
{
    return (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
}

/* ref and test codes (w * h * 3 each) of a pair, from the unpacked texture; integer arithmetic only. */
static hz_status_t make_pair(const pair_t *p, uint8_t *ref, uint8_t *test, hz_error_t *err)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", data_dir(), p->source);
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t src;
    hz_status_t s = hz_image_read(path, &arena, &src, err);
    if (s != HZ_OK)
        return s;
    if (p->x0 + p->w > src.width || p->y0 + p->h > src.height) {
        hz_arena_reset(&arena, m);
        return hz_error_set(err, HZ_E_RANGE, "%s: crop outside the %ux%u image", path, src.width, src.height);
    }
    const uint32_t w = p->w, h = p->h;
    for (uint32_t y = 0; y < h; y++)
        hz_srgb8_encode_n(hz_image_at(&src, p->x0, p->y0 + y), ref + (size_t)y * w * 3, (size_t)w * 3);
    hz_arena_reset(&arena, m);
    hz_rng_t r;
    hz_rng_seed(&r, 2020, (uint64_t)p->how);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const uint8_t *a = ref + ((size_t)y * w + x) * 3;
            uint8_t *t = test + ((size_t)y * w + x) * 3;
            bool firefly = p->how == FIREFLIES && hz_rng_below(&r, 1000) < 5;
            for (int c = 0; c < 3; c++) {
                int v = a[c];
                switch (p->how) {
                case NOISE: /* sum of four uniforms: roughly Gaussian, sd ~10 codes, like 1-spp Monte Carlo noise */
                case NOISE_LOW: {
                    int n = 0, span = p->how == NOISE ? 17 : 5;
                    for (int k = 0; k < 4; k++)
                        n += (int)hz_rng_below(&r, (uint32_t)span);
                    v += n - 2 * (span - 1);
                    break;
                }
                case BLUR: { /* 3x3 box, edges clamped */
                    int sum = 0;
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            int xx = (int)x + dx, yy = (int)y + dy;
                            xx = xx < 0 ? 0 : xx >= (int)w ? (int)w - 1 : xx;
                            yy = yy < 0 ? 0 : yy >= (int)h ? (int)h - 1 : yy;
                            sum += ref[((size_t)yy * w + (size_t)xx) * 3 + c];
                        }
                    v = (sum + 4) / 9;
                    break;
                }
                case SHIFT: /* one pixel to the right */
                    v = ref[((size_t)y * w + (x ? x - 1 : 0)) * 3 + c];
                    break;
                case BANDING: /* 8 levels a channel */
                    v = (v / 32) * 32 + 16;
                    break;
                case FIREFLIES:
                    v = firefly ? 255 : v;
                    break;
                case TINT:
                    v += c == 0 ? 24 : c == 2 ? -12 : 0;
                    break;
                }
                t[c] = clamp8(v);
            }
        }
    return HZ_OK;
}

static hz_image_t image_of(uint32_t w, uint32_t h, const uint8_t *codes)
{
    hz_image_t img;
    hz_error_t err;
    assert_int_equal(hz_image_alloc(&img, &arena, w, h, &err), HZ_OK);
    hz_image_from_srgb8(&img, codes);
    return img;
}

static int write_pairs(const char *dir)
{
    static uint8_t ref[256 * 256 * 3], test[256 * 256 * 3];
    hz_error_t err;
    if (hz_mkdirs(dir, &err) != HZ_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    for (size_t i = 0; i < HZ_ARRAY_LEN(pairs); i++) {
        const pair_t *p = &pairs[i];
        hz_arena_mark_t m = hz_arena_mark(&arena);
        if (make_pair(p, ref, test, &err) != HZ_OK) {
            fprintf(stderr, "%s\n", err.msg);
            return 1;
        }
        hz_image_t a, b;
        if (hz_image_alloc(&a, &arena, p->w, p->h, &err) != HZ_OK ||
            hz_image_alloc(&b, &arena, p->w, p->h, &err) != HZ_OK) {
            fprintf(stderr, "%s\n", err.msg);
            return 1;
        }
        hz_image_from_srgb8(&a, ref);
        hz_image_from_srgb8(&b, test);
        char pa[512], pb[512];
        snprintf(pa, sizeof pa, "%s/%s-ref.png", dir, p->name);
        snprintf(pb, sizeof pb, "%s/%s-test.png", dir, p->name);
        double mean = NAN;
        if (hz_png_write(pa, &a, &err) != HZ_OK || hz_png_write(pb, &b, &err) != HZ_OK ||
            hz_flip(&a, &b, HZ_FLIP_DEFAULT_PPD, &arena, NULL, &mean, &err) != HZ_OK) {
            fprintf(stderr, "%s\n", err.msg);
            return 1;
        }
        printf("%-16s %ux%u  hz mean FLIP %.6f\n", p->name, p->w, p->h, mean);
        hz_arena_reset(&arena, m);
    }
    return 0;
}

static void test_matches_nvidia_reference(void **state)
{
    (void)state;
    if (!hz_png_supported()) {
        print_message("no PNG support on this target: the texture crops cannot be read here "
                      "(the algorithm is the same C code the host build checks)\n");
        skip();
    }
    static uint8_t ref[256 * 256 * 3], test[256 * 256 * 3];
    double worst = 0.0;
    for (size_t i = 0; i < HZ_ARRAY_LEN(pairs); i++) {
        const pair_t *p = &pairs[i];
        hz_arena_mark_t m = hz_arena_mark(&arena);
        hz_error_t err;
        if (make_pair(p, ref, test, &err) != HZ_OK)
            fail_msg("%s", err.msg);
        hz_image_t a = image_of(p->w, p->h, ref), b = image_of(p->w, p->h, test);
        double mean;
        assert_int_equal(hz_flip(&a, &b, HZ_FLIP_DEFAULT_PPD, &arena, NULL, &mean, &err), HZ_OK);
        double diff = fabs(mean - p->nvidia_mean);
        print_message("%-16s hz %.6f  nvidia %.6f  diff %.1e\n", p->name, mean, p->nvidia_mean, diff);
        if (diff > worst)
            worst = diff;
        if (diff > 1e-4)
            fail_msg("%s: mean FLIP %.6f, NVIDIA's %.6f", p->name, mean, p->nvidia_mean);
        hz_arena_reset(&arena, m);
    }
    print_message("largest difference %.1e over %zu pairs\n", worst, HZ_ARRAY_LEN(pairs));
}

/* ---- pairs from real renders ---- */

typedef struct render_pair {
    const char *ref, *test; /* test/golden/flip/<name>.png */
    double nvidia_mean;     /* NVIDIA FLIP v1.6 "Mean:" (6 decimals) */
} render_pair_t;

static const render_pair_t render_pairs[] = {
    { "CornellBox-Mirror-256spp", "CornellBox-Mirror-1spp", 0.056385 },
    { "sponza-256spp", "sponza-1spp", 0.030545 },
    { "lost-empire-256spp", "lost-empire-1spp", 0.030358 },
    { "builtin-256spp", "builtin-1spp", 0.028919 },
    { "CornellBox-Mirror-256spp-f23", "CornellBox-Mirror-taa-f23", 0.067314 },
    { "sponza-256spp-f23", "sponza-taa-f23", 0.039940 },
    { "lost-empire-256spp", "lost-empire-16spp", 0.009258 },
    { "builtin-256spp", "builtin-4spp", 0.020267 },
};

static void golden_path(char *buf, size_t size, const char *name)
{
    const char *root = getenv("HZ_TEST_DIR");
    snprintf(buf, size, "%s/golden/flip/%s.png", root && *root ? root : "test", name);
}

static void test_matches_nvidia_on_renders(void **state)
{
    (void)state;
    if (!hz_png_supported()) {
        print_message("no PNG support on this target: the rendered pairs cannot be read here "
                      "(the algorithm is the same C code the host build checks)\n");
        skip();
    }
    double worst = 0.0;
    for (size_t i = 0; i < HZ_ARRAY_LEN(render_pairs); i++) {
        const render_pair_t *p = &render_pairs[i];
        hz_arena_mark_t m = hz_arena_mark(&arena);
        char pa[512], pb[512];
        golden_path(pa, sizeof pa, p->ref);
        golden_path(pb, sizeof pb, p->test);
        hz_image_t a, b;
        hz_error_t err;
        if (hz_image_read(pa, &arena, &a, &err) != HZ_OK || hz_image_read(pb, &arena, &b, &err) != HZ_OK)
            fail_msg("%s", err.msg);
        assert_int_equal(a.width, 160);
        assert_int_equal(a.height, 90);
        double mean;
        assert_int_equal(hz_flip(&a, &b, HZ_FLIP_DEFAULT_PPD, &arena, NULL, &mean, &err), HZ_OK);
        double diff = fabs(mean - p->nvidia_mean);
        print_message("%-26s hz %.6f  nvidia %.6f  diff %.1e\n", p->test, mean, p->nvidia_mean, diff);
        if (diff > worst)
            worst = diff;
        /* 14400 pixels: NVIDIA's float sum is good to ~1e-7 here, so the bound is the 6 printed decimals plus
         * margin for other compilers and ISAs. */
        if (diff > 1e-5)
            fail_msg("%s vs %s: mean FLIP %.6f, NVIDIA's %.6f", p->test, p->ref, mean, p->nvidia_mean);
        hz_arena_reset(&arena, m);
    }
    print_message("largest difference %.1e over %zu rendered pairs\n", worst, HZ_ARRAY_LEN(render_pairs));
}

/* ---- analytic and property tests ---- */

/* Independent double-precision colour term for constant images (filters of constant images are identities). */
static void hunt_lab(const double rgb[3], double out[3])
{
    static const double m[3][3] = {
        { 10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0 },
        { 2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0 },
        { 1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0 },
    };
    double f[3];
    for (int i = 0; i < 3; i++) {
        double white = m[i][0] + m[i][1] + m[i][2];
        double t = (m[i][0] * rgb[0] + m[i][1] * rgb[1] + m[i][2] * rgb[2]) / white;
        double d = 6.0 / 29.0;
        f[i] = t > d * d * d ? cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
    }
    double L = 116 * f[1] - 16;
    out[0] = L;
    out[1] = L / 100 * 500 * (f[0] - f[1]);
    out[2] = L / 100 * 200 * (f[1] - f[2]);
}

static double hyab(const double a[3], const double b[3])
{
    return fabs(a[0] - b[0]) + hypot(a[1] - b[1], a[2] - b[2]);
}

static double constant_flip(const double a[3], const double b[3])
{
    const double g[3] = { 0, 1, 0 }, bl[3] = { 0, 0, 1 };
    double la[3], lb[3], lg[3], lbl[3];
    hunt_lab(a, la);
    hunt_lab(b, lb);
    hunt_lab(g, lg);
    hunt_lab(bl, lbl);
    double cmax = pow(hyab(lg, lbl), 0.7), pcc = 0.4 * cmax;
    double d = pow(hyab(la, lb), 0.7);
    return d < pcc ? d * 0.95 / pcc : 0.95 + (d - pcc) / (cmax - pcc) * 0.05;
}

static hz_image_t filled(uint32_t w, uint32_t h, const double rgb[3])
{
    hz_image_t img;
    hz_error_t err;
    assert_int_equal(hz_image_alloc(&img, &arena, w, h, &err), HZ_OK);
    hz_image_fill(&img, (float)rgb[0], (float)rgb[1], (float)rgb[2]);
    return img;
}

static void test_identical_images_give_zero(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t a;
    hz_error_t err;
    assert_int_equal(hz_image_alloc(&a, &arena, 37, 29, &err), HZ_OK);
    hz_rng_t r;
    hz_rng_seed(&r, 1, 1);
    for (size_t i = 0; i < hz_image_pixels(&a) * 3; i++)
        a.rgb[i] = (float)hz_rng_u32(&r) * 0x1p-32f;
    static float map[37 * 29];
    double mean = -1;
    assert_int_equal(hz_flip(&a, &a, HZ_FLIP_DEFAULT_PPD, &arena, map, &mean, &err), HZ_OK);
    assert_true(mean == 0.0);
    for (size_t i = 0; i < 37 * 29; i++)
        assert_true(map[i] == 0.0f);
    hz_arena_reset(&arena, m);
}

static void test_constant_images_give_the_colour_term(void **state)
{
    (void)state;
    static const double cases[][2][3] = {
        { { 0, 0, 0 }, { 1, 1, 1 } },
        { { 0.2, 0.2, 0.2 }, { 0.25, 0.2, 0.2 } },
        { { 0.5, 0.1, 0.9 }, { 0.45, 0.12, 0.8 } },
        { { 0, 1, 0 }, { 0, 0, 1 } }, /* cmax itself: error 1 */
        { { 0.01, 0.01, 0.01 }, { 0.011, 0.01, 0.01 } },
    };
    for (size_t k = 0; k < HZ_ARRAY_LEN(cases); k++) {
        hz_arena_mark_t m = hz_arena_mark(&arena);
        hz_image_t a = filled(24, 20, cases[k][0]), b = filled(24, 20, cases[k][1]);
        double mean;
        hz_error_t err;
        assert_int_equal(hz_flip(&a, &b, HZ_FLIP_DEFAULT_PPD, &arena, NULL, &mean, &err), HZ_OK);
        double want = constant_flip(cases[k][0], cases[k][1]);
        print_message("constant case %zu: hz %.7f  closed form %.7f\n", k, mean, want);
        /* Single precision (like the reference) costs up to ~3e-5 here: the YCxCz round trip's rounding is
         * amplified by d^0.7 near small differences. The same code in double matches to 1e-7. */
        assert_float_equal(mean, want, 1e-4);
        hz_arena_reset(&arena, m);
    }
    double g[3] = { 0, 1, 0 }, b[3] = { 0, 0, 1 };
    assert_float_equal(constant_flip(g, b), 1.0, 1e-12);
}

static void test_symmetry_range_and_observer(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t a, b;
    hz_error_t err;
    assert_int_equal(hz_image_alloc(&a, &arena, 64, 48, &err), HZ_OK);
    assert_int_equal(hz_image_alloc(&b, &arena, 64, 48, &err), HZ_OK);
    hz_rng_t r;
    hz_rng_seed(&r, 3, 3);
    for (size_t i = 0; i < hz_image_pixels(&a) * 3; i++) {
        a.rgb[i] = (float)((i / 3) % 64 < 32) * 0.8f + 0.1f;       /* vertical bars */
        b.rgb[i] = a.rgb[i] + ((float)hz_rng_u32(&r) * 0x1p-32f - 0.5f) * 0.3f;
    }
    static float map_ab[64 * 48], map_ba[64 * 48];
    double ab, ba;
    assert_int_equal(hz_flip(&a, &b, HZ_FLIP_DEFAULT_PPD, &arena, map_ab, &ab, &err), HZ_OK);
    assert_int_equal(hz_flip(&b, &a, HZ_FLIP_DEFAULT_PPD, &arena, map_ba, &ba, &err), HZ_OK);
    assert_true(ab == ba);
    assert_memory_equal(map_ab, map_ba, sizeof map_ab);
    for (size_t i = 0; i < 64 * 48; i++)
        assert_true(map_ab[i] >= 0.0f && map_ab[i] <= 1.0f);
    assert_true(ab > 0.05 && ab < 0.9);
    /* Pixel noise is less visible from farther away (more pixels per degree). */
    double near, far;
    assert_int_equal(hz_flip(&a, &b, 20.0f, &arena, NULL, &near, &err), HZ_OK);
    assert_int_equal(hz_flip(&a, &b, 120.0f, &arena, NULL, &far, &err), HZ_OK);
    assert_true(near > ab && ab > far);
    assert_float_equal(HZ_FLIP_DEFAULT_PPD, 67.0206f, 1e-4);
    hz_arena_reset(&arena, m);
}

static void test_argument_errors(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    double z[3] = { 0.5, 0.5, 0.5 };
    hz_image_t a = filled(16, 16, z), b = filled(16, 15, z);
    double mean;
    hz_error_t err;
    assert_int_equal(hz_flip(&a, &b, HZ_FLIP_DEFAULT_PPD, &arena, NULL, &mean, &err), HZ_E_INVALID_ARG);
    assert_int_equal(hz_flip(&a, &a, 0.0f, &arena, NULL, &mean, &err), HZ_E_INVALID_ARG);
    assert_int_equal(hz_flip(&a, &a, NAN, &arena, NULL, &mean, &err), HZ_E_INVALID_ARG);
    static uint8_t small[1024];
    hz_arena_t t;
    hz_arena_init(&t, "tiny", small, sizeof small);
    assert_int_equal(hz_flip(&a, &a, HZ_FLIP_DEFAULT_PPD, &t, NULL, &mean, &err), HZ_E_NO_MEMORY);
    assert_non_null(strstr(err.msg, "flip scratch"));
    assert_int_equal(hz_arena_mark(&t), 0);
    /* The advertised scratch size is enough. */
    size_t need = hz_flip_scratch_bytes(16, 16, HZ_FLIP_DEFAULT_PPD);
    assert_true(need <= sizeof buf / 2);
    hz_arena_t exact;
    hz_arena_init(&exact, "exact", buf + sizeof buf / 2, need);
    assert_int_equal(hz_flip(&a, &a, HZ_FLIP_DEFAULT_PPD, &exact, NULL, &mean, &err), HZ_OK);
    /* A one-pixel image works (every filter tap clamps to it). */
    hz_image_t one = filled(1, 1, z), two = filled(1, 1, z);
    two.rgb[0] = 0.6f;
    assert_int_equal(hz_flip(&one, &two, HZ_FLIP_DEFAULT_PPD, &arena, NULL, &mean, &err), HZ_OK);
    assert_true(mean > 0.0 && mean < 1.0);
    hz_arena_reset(&arena, m);
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "--write-pairs")) {
        hz_arena_init(&arena, "pairs", buf, sizeof buf);
        return write_pairs(argv[2]);
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_identical_images_give_zero),
        cmocka_unit_test(test_constant_images_give_the_colour_term),
        cmocka_unit_test(test_symmetry_range_and_observer),
        cmocka_unit_test(test_argument_errors),
        cmocka_unit_test(test_matches_nvidia_reference),
        cmocka_unit_test(test_matches_nvidia_on_renders),
    };
    return HZ_RUN_GROUP(tests, setup, NULL);
}
