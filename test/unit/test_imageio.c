#define _GNU_SOURCE /* memmem */
/*
 * Image files: round trips (PPM, PFM bit-exact, PNG), every header variant the readers promise, bad files with
 * their distinct codes and messages naming the file, truncation at every length and random corruption (no
 * crash: ASan under SAN=1), the arena left as it was on failure, and the Y4M writer's exact bytes.
 */
#include "hz_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hz/hash.h"
#include "hz/image.h"
#include "imageio.h"

#if HZ_HAVE_PNG
#include <png.h>
#endif

static char dir[64];
static uint8_t arena_buf[8 << 20] HZ_ALIGNED(64);
static hz_arena_t arena;

static int setup(void **state)
{
    (void)state;
    strcpy(dir, "/tmp/hz-imageio-XXXXXX");
    if (!mkdtemp(dir))
        return -1;
    hz_arena_init(&arena, "test", arena_buf, sizeof arena_buf);
    return 0;
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
    static char buf[4][256];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
    return buf[k];
}

static void put_file(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
}

static uint8_t *get_file(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *p = malloc((size_t)len + 1);
    assert_int_equal(fread(p, 1, (size_t)len, f), (size_t)len);
    fclose(f);
    *n = (size_t)len;
    return p;
}

static hz_image_t make_image(uint32_t w, uint32_t h, uint32_t seed)
{
    hz_image_t img;
    hz_error_t err;
    assert_int_equal(hz_image_alloc(&img, &arena, w, h, &err), HZ_OK);
    hz_rng_t r;
    hz_rng_seed(&r, seed, 3);
    for (size_t i = 0; i < hz_image_pixels(&img) * 3; i++)
        img.rgb[i] = (float)hz_rng_u32(&r) * 0x1p-32f * 1.2f - 0.1f;
    return img;
}

static float eotf(double c)
{
    return (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
}

/* ---- PPM ---- */

static void test_ppm_round_trip(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t img = make_image(16, 17, 1);
    for (int b = 0; b < 256; b++)
        img.rgb[b] = hz_srgb8_decode((uint8_t)b); /* every code once */
    img.rgb[300] = NAN;
    img.rgb[301] = INFINITY;
    hz_error_t err;
    const char *p = path_of("a.ppm");
    assert_int_equal(hz_ppm_write(p, &img, &err), HZ_OK);
    size_t n;
    uint8_t *bytes = get_file(p, &n);
    assert_int_equal(n, strlen("P6\n16 17\n255\n") + 16 * 17 * 3);
    assert_memory_equal(bytes, "P6\n16 17\n255\n", 13);
    free(bytes);
    hz_image_t back;
    assert_int_equal(hz_ppm_read(p, &arena, &back, &err), HZ_OK);
    assert_int_equal(back.width, 16);
    assert_int_equal(back.height, 17);
    for (size_t i = 0; i < 16 * 17 * 3; i++)
        assert_true(back.rgb[i] == hz_srgb8_decode(hz_srgb8_encode(img.rgb[i])));
    assert_true(back.rgb[300] == 0.0f);
    assert_true(back.rgb[301] == 1.0f);
    hz_image_t by_content;
    assert_int_equal(hz_image_read(p, &arena, &by_content, &err), HZ_OK);
    assert_memory_equal(by_content.rgb, back.rgb, 16 * 17 * 3 * sizeof(float));
    hz_arena_reset(&arena, m);
}

static void test_ppm_variants(void **state)
{
    (void)state;
    hz_error_t err;
    hz_image_t img;
    /* Comments between fields, grey (P5), 16-bit big-endian samples. */
    const char p5[] = "P5\n# a comment\n2 # width\n1\n65535\n\xff\xff\x80\x00";
    put_file(path_of("g16.pgm"), p5, sizeof p5 - 1);
    assert_int_equal(hz_ppm_read(path_of("g16.pgm"), &arena, &img, &err), HZ_OK);
    assert_int_equal(img.width, 2);
    assert_int_equal(img.height, 1);
    for (int c = 0; c < 3; c++) {
        assert_true(img.rgb[c] == 1.0f);
        assert_float_equal(img.rgb[3 + c], eotf(32768.0 / 65535.0), 0.0);
    }
    /* maxval 100: a sample of 50 is 0.5. */
    const char p6[] = "P6 1 1 100\n\x32\x00\x64";
    put_file(path_of("m100.ppm"), p6, sizeof p6 - 1);
    assert_int_equal(hz_ppm_read(path_of("m100.ppm"), &arena, &img, &err), HZ_OK);
    assert_float_equal(img.rgb[0], eotf(0.5), 0.0);
    assert_true(img.rgb[1] == 0.0f);
    assert_true(img.rgb[2] == 1.0f);
    /* Trailing bytes after the pixels (a second image in a stream) are not an error. */
    const char two[] = "P6\n1 1\n255\n\x01\x02\x03P6\n1 1\n255\n\x04\x05\x06";
    put_file(path_of("two.ppm"), two, sizeof two - 1);
    assert_int_equal(hz_ppm_read(path_of("two.ppm"), &arena, &img, &err), HZ_OK);
    assert_true(img.rgb[2] == hz_srgb8_decode(3));
}

/* ---- PFM ---- */

static void test_pfm_round_trip_is_bit_exact(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t img = make_image(3, 2, 2);
    img.rgb[0] = NAN;
    img.rgb[1] = -INFINITY;
    img.rgb[2] = -0.0f;
    img.rgb[3] = 1e30f;
    img.rgb[4] = hz_float_from_bits(1); /* denormal */
    img.rgb[5] = -7.25f;
    hz_error_t err;
    const char *p = path_of("a.pfm");
    assert_int_equal(hz_pfm_write(p, &img, &err), HZ_OK);
    size_t n;
    uint8_t *bytes = get_file(p, &n);
    const char *hdr = "PF\n3 2\n-1.0\n";
    assert_int_equal(n, strlen(hdr) + 3 * 2 * 12);
    assert_memory_equal(bytes, hdr, strlen(hdr));
    /* The first stored row is the image's bottom row, little-endian. */
    uint32_t u = hz_float_bits(hz_image_at(&img, 0, 1)[0]);
    const uint8_t *d = bytes + strlen(hdr);
    assert_int_equal(d[0] | d[1] << 8 | d[2] << 16 | (uint32_t)d[3] << 24, u);
    free(bytes);
    hz_image_t back;
    assert_int_equal(hz_pfm_read(p, &arena, &back, &err), HZ_OK);
    assert_memory_equal(back.rgb, img.rgb, 3 * 2 * 3 * sizeof(float));
    hz_arena_reset(&arena, m);
}

static void test_pfm_big_endian_grey(void **state)
{
    (void)state;
    /* "Pf", positive scale = big-endian; rows bottom to top: stored 1.0 2.0 (bottom), 3.0 4.0 (top). */
    uint8_t f[64];
    size_t n = 0;
    const char *hdr = "Pf\n2 2\n1.0\n";
    memcpy(f, hdr, strlen(hdr));
    n = strlen(hdr);
    const float v[4] = { 1.0f, 2.0f, 3.0f, 4.0f };
    for (int i = 0; i < 4; i++) {
        uint32_t b = hz_float_bits(v[i]);
        f[n++] = (uint8_t)(b >> 24);
        f[n++] = (uint8_t)(b >> 16);
        f[n++] = (uint8_t)(b >> 8);
        f[n++] = (uint8_t)b;
    }
    put_file(path_of("be.pfm"), f, n);
    hz_image_t img;
    hz_error_t err;
    assert_int_equal(hz_image_read(path_of("be.pfm"), &arena, &img, &err), HZ_OK);
    for (int c = 0; c < 3; c++) {
        assert_true(hz_image_at(&img, 0, 0)[c] == 3.0f);
        assert_true(hz_image_at(&img, 1, 0)[c] == 4.0f);
        assert_true(hz_image_at(&img, 0, 1)[c] == 1.0f);
        assert_true(hz_image_at(&img, 1, 1)[c] == 2.0f);
    }
}

/* ---- bad files ---- */

typedef struct bad_case {
    const char *name;
    const char *data;
    size_t len;
    hz_status_t code;
    const char *says;
} bad_case_t;

#define BAD(name, lit, code, says) { name, lit, sizeof lit - 1, code, says }

static void test_bad_files_get_distinct_errors_naming_the_file(void **state)
{
    (void)state;
    static const bad_case_t cases[] = {
        BAD("empty.ppm", "", HZ_E_FORMAT, "empty"),
        BAD("one.ppm", "P", HZ_E_FORMAT, "unknown image format"),
        BAD("gif.ppm", "GIF89a\x01\x00\x01\x00", HZ_E_FORMAT, "unknown image format"),
        BAD("ascii.ppm", "P3\n1 1\n255\n0 0 0\n", HZ_E_UNSUPPORTED, "ASCII"),
        BAD("pam.ppm", "P7\nWIDTH 1\n", HZ_E_UNSUPPORTED, "PAM"),
        BAD("zero.ppm", "P6\n0 1\n255\n", HZ_E_RANGE, "absurd image size 0x1"),
        BAD("huge.ppm", "P6\n100000 100000\n255\n", HZ_E_RANGE, "absurd image size"),
        BAD("digits.ppm", "P6\n99999999999999999999999 1\n255\n", HZ_E_RANGE, "absurd"),
        BAD("many.ppm", "P6\n0000000000000000000000000000000000000000001 1\n255\n", HZ_E_FORMAT, "too many digits"),
        BAD("max0.ppm", "P6\n2 2\n0\n", HZ_E_FORMAT, "maxval"),
        BAD("max70k.ppm", "P6\n2 2\n70000\n", HZ_E_FORMAT, "maxval"),
        BAD("short.ppm", "P6\n2 2\n255\n\x01\x02\x03\x04\x05", HZ_E_FORMAT, "pixel data ends after 5 of 12 bytes"),
        BAD("hdr.ppm", "P6\n2 2", HZ_E_FORMAT, "truncated"),
        BAD("x.ppm", "P6\n2x2\n255\n", HZ_E_FORMAT, "followed by 'x'"),
        BAD("neg.ppm", "P6\n-2 2\n255\n", HZ_E_FORMAT, "expected the width"),
        BAD("cmt.ppm", "P6\n1 1\n255#c\n\x01\x02\x03", HZ_E_FORMAT, "comment directly after maxval"),
        BAD("over.ppm", "P6\n1 1\n100\n\x01\xc8\x01", HZ_E_FORMAT, "exceeds maxval"),
        BAD("scale0.pfm", "PF\n2 2\n0\n", HZ_E_FORMAT, "scale \"0\""),
        BAD("scaleabc.pfm", "PF\n2 2\nabc\n", HZ_E_FORMAT, "not a finite"),
        BAD("scalenan.pfm", "PF\n2 2\nnan\n", HZ_E_FORMAT, "not a finite"),
        BAD("scaleinf.pfm", "PF\n1 1\n1e999\n", HZ_E_FORMAT, "not a finite"),
        BAD("noscale.pfm", "PF\n2 2\n", HZ_E_FORMAT, "truncated"),
        BAD("short.pfm", "PF\n2 2\n-1.0\n0123456789", HZ_E_FORMAT, "pixel data ends after 10 of 48 bytes"),
        BAD("glued.pfm", "PF2 2\n-1\n", HZ_E_FORMAT, "no whitespace after the magic"),
        BAD("zero.pfm", "Pf\n0 2\n-1\n", HZ_E_RANGE, "absurd"),
        BAD("comment.pfm", "PF\n#c\n1 1\n-1\n", HZ_E_FORMAT, "expected the width"),
        BAD("png.png", "\x89PNG\r\n\x1a\n", HZ_E_FORMAT, "PNG"),
    };
    for (size_t i = 0; i < HZ_ARRAY_LEN(cases); i++) {
        const bad_case_t *c = &cases[i];
        const char *p = path_of(c->name);
        put_file(p, c->data, c->len);
        hz_arena_mark_t m = hz_arena_mark(&arena);
        hz_image_t img = { 7, 7, (float *)arena_buf };
        hz_error_t err;
        hz_status_t s = hz_image_read(p, &arena, &img, &err);
        if (!hz_png_supported() && strstr(c->name, ".png")) {
            assert_int_equal(s, HZ_E_UNSUPPORTED);
            continue;
        }
        if (s != c->code || !strstr(err.msg, c->says) || !strstr(err.msg, p))
            fail_msg("%s: got %d \"%s\", want %d containing \"%s\"", c->name, s, err.msg, c->code, c->says);
        assert_int_equal(hz_arena_mark(&arena), m); /* nothing kept */
        assert_null(img.rgb);
        assert_int_equal(img.width, 0);
    }
}

static void test_missing_directory_and_fifo_are_io_errors(void **state)
{
    (void)state;
    hz_image_t img;
    hz_error_t err;
    const char *p = path_of("does-not-exist.ppm");
    assert_int_equal(hz_ppm_read(p, &arena, &img, &err), HZ_E_IO);
    assert_non_null(strstr(err.msg, p));
    assert_non_null(strstr(err.msg, "No such file"));
    assert_int_equal(hz_pfm_read(dir, &arena, &img, &err), HZ_E_IO);
    assert_non_null(strstr(err.msg, "not a regular file"));
    const char *fifo = path_of("fifo.ppm");
    assert_int_equal(mkfifo(fifo, 0600), 0);
    /* No writer: a blocking open would wait forever. The reader must refuse at once. */
    assert_int_equal(hz_image_read(fifo, &arena, &img, &err), HZ_E_IO);
    assert_non_null(strstr(err.msg, "not a regular file"));
    assert_int_equal(hz_ppm_read("/dev/null", &arena, &img, &err), HZ_E_IO);
}

static void test_arena_too_small_and_restored(void **state)
{
    (void)state;
    static uint8_t small[4096] HZ_ALIGNED(64);
    hz_arena_t a;
    hz_arena_init(&a, "tiny", small, sizeof small);
    hz_image_t img = make_image(40, 40, 3);
    hz_error_t err;
    assert_int_equal(hz_pfm_write(path_of("big.pfm"), &img, &err), HZ_OK);
    hz_image_t back;
    assert_int_equal(hz_pfm_read(path_of("big.pfm"), &a, &back, &err), HZ_E_NO_MEMORY);
    assert_non_null(strstr(err.msg, "big.pfm"));
    assert_non_null(strstr(err.msg, "arena 'tiny': needs 19200"));
    assert_int_equal(hz_arena_mark(&a), 0);
    /* On success the arena holds the image and nothing else (temporary rows released). */
    hz_arena_mark_t m = hz_arena_mark(&arena);
    assert_int_equal(hz_pfm_read(path_of("big.pfm"), &arena, &back, &err), HZ_OK);
    assert_true(hz_arena_mark(&arena) - m <= 40 * 40 * 12 + 64);
    assert_true(hz_arena_mark(&arena) - m >= 40 * 40 * 12);
}

/* Every proper prefix of a valid file must be refused; random corruption must never crash. */
static void check_prefixes_and_corruption(const char *name)
{
    size_t n;
    uint8_t *full = get_file(path_of(name), &n);
    hz_image_t img;
    hz_error_t err;
    char cut[64];
    snprintf(cut, sizeof cut, "cut-%s", name);
    for (size_t len = 0; len < n; len++) {
        put_file(path_of(cut), full, len);
        hz_arena_mark_t m = hz_arena_mark(&arena);
        hz_status_t s = hz_image_read(path_of(cut), &arena, &img, &err);
        if (s == HZ_OK)
            fail_msg("%s: a %zu-byte prefix of %zu was accepted", name, len, n);
        assert_int_equal(hz_arena_mark(&arena), m);
    }
    hz_rng_t r;
    hz_rng_seed(&r, 99, n);
    uint8_t *bad = malloc(n);
    for (int trial = 0; trial < 300; trial++) {
        memcpy(bad, full, n);
        int flips = 1 + (int)hz_rng_below(&r, 4);
        for (int k = 0; k < flips; k++)
            bad[hz_rng_below(&r, (uint32_t)n)] ^= (uint8_t)(1u << hz_rng_below(&r, 8));
        put_file(path_of(cut), bad, n);
        hz_arena_mark_t m = hz_arena_mark(&arena);
        hz_status_t s = hz_image_read(path_of(cut), &arena, &img, &err);
        if (s != HZ_OK) {
            assert_true(strlen(err.msg) > 0);
            assert_int_equal(hz_arena_mark(&arena), m);
        } else {
            hz_arena_reset(&arena, m);
        }
    }
    free(bad);
    free(full);
}

static void test_truncation_and_corruption(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t img = make_image(5, 4, 4);
    hz_error_t err;
    assert_int_equal(hz_ppm_write(path_of("t.ppm"), &img, &err), HZ_OK);
    assert_int_equal(hz_pfm_write(path_of("t.pfm"), &img, &err), HZ_OK);
    check_prefixes_and_corruption("t.ppm");
    check_prefixes_and_corruption("t.pfm");
    if (hz_png_supported()) {
        assert_int_equal(hz_png_write(path_of("t.png"), &img, &err), HZ_OK);
        check_prefixes_and_corruption("t.png");
    }
    hz_arena_reset(&arena, m);
}

static void test_write_errors(void **state)
{
    (void)state;
    hz_image_t img = make_image(2, 2, 5);
    hz_error_t err;
    const char *p = path_of("no-such-dir/x.ppm");
    assert_int_equal(hz_image_write(p, &img, &err), HZ_E_IO);
    assert_non_null(strstr(err.msg, p));
    assert_int_equal(hz_image_write(path_of("x.tiff"), &img, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "x.tiff"));
    assert_int_equal(hz_image_write(path_of("UPPER.PFM"), &img, &err), HZ_OK);
    assert_int_equal(hz_image_write(path_of("lower.ppm"), &img, &err), HZ_OK);
}

/* ---- PNG ---- */

#if HZ_HAVE_PNG
static uint32_t crc32_of(const uint8_t *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1)));
    }
    return ~c;
}

static void be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

/* Writes a PNG of any colour type with libpng directly (the reader must take what other tools write). */
static void write_png_variant(const char *path, uint32_t w, uint32_t h, int depth, int color, int interlace,
                              const uint8_t *rows, size_t row_bytes, const png_color *palette, int npal)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    assert_int_equal(setjmp(png_jmpbuf(png)), 0);
    png_init_io(png, f);
    png_set_IHDR(png, info, w, h, depth, color, interlace, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (palette)
        png_set_PLTE(png, info, palette, npal);
    png_write_info(png, info);
    int passes = png_set_interlace_handling(png);
    for (int pass = 0; pass < passes; pass++)
        for (uint32_t y = 0; y < h; y++)
            png_write_row(png, rows + y * row_bytes);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(f);
}
#endif

static void test_png_round_trip_and_variants(void **state)
{
    (void)state;
    hz_error_t err;
    hz_image_t img = make_image(7, 5, 6), back;
    if (!hz_png_supported()) {
        assert_int_equal(hz_png_write(path_of("x.png"), &img, &err), HZ_E_UNSUPPORTED);
        assert_non_null(strstr(err.msg, "not built in"));
        put_file(path_of("y.png"), "\x89PNG\r\n\x1a\n", 8);
        assert_int_equal(hz_png_read(path_of("y.png"), &arena, &back, &err), HZ_E_UNSUPPORTED);
        return;
    }
#if HZ_HAVE_PNG
    const char *p = path_of("rt.png");
    assert_int_equal(hz_png_write(p, &img, &err), HZ_OK);
    assert_int_equal(hz_png_read(p, &arena, &back, &err), HZ_OK);
    assert_int_equal(back.width, 7);
    assert_int_equal(back.height, 5);
    for (size_t i = 0; i < 7 * 5 * 3; i++)
        assert_true(back.rgb[i] == hz_srgb8_decode(hz_srgb8_encode(img.rgb[i])));
    size_t n;
    uint8_t *bytes = get_file(p, &n);
    assert_non_null(memmem(bytes, n, "sRGB", 4));
    free(bytes);

    /* Grey 8-bit, interlaced: value v everywhere -> (v, v, v). */
    uint8_t g[3 * 4];
    for (int i = 0; i < 12; i++)
        g[i] = (uint8_t)(i * 20);
    write_png_variant(path_of("g8i.png"), 3, 4, 8, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_ADAM7, g, 3, NULL, 0);
    assert_int_equal(hz_png_read(path_of("g8i.png"), &arena, &back, &err), HZ_OK);
    for (uint32_t y = 0; y < 4; y++)
        for (uint32_t x = 0; x < 3; x++)
            for (int c = 0; c < 3; c++)
                assert_true(hz_image_at(&back, x, y)[c] == hz_srgb8_decode(g[y * 3 + x]));
    /* Grey 1-bit. */
    uint8_t bits[2] = { 0xA0, 0x40 }; /* row 0: 1 0 1, row 1: 0 1 0 */
    write_png_variant(path_of("g1.png"), 3, 2, 1, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, bits, 1, NULL, 0);
    assert_int_equal(hz_png_read(path_of("g1.png"), &arena, &back, &err), HZ_OK);
    assert_true(hz_image_at(&back, 0, 0)[1] == 1.0f && hz_image_at(&back, 1, 0)[1] == 0.0f);
    assert_true(hz_image_at(&back, 1, 1)[2] == 1.0f && hz_image_at(&back, 2, 1)[0] == 0.0f);
    /* Palette, 4-bit. */
    png_color pal[3] = { { 255, 0, 0 }, { 0, 128, 0 }, { 10, 20, 30 } };
    uint8_t idx[2] = { 0x01, 0x20 }; /* row 0: 0 1, row 1: 2 0 */
    write_png_variant(path_of("p4.png"), 2, 2, 4, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE, idx, 1, pal, 3);
    assert_int_equal(hz_png_read(path_of("p4.png"), &arena, &back, &err), HZ_OK);
    assert_true(hz_image_at(&back, 0, 0)[0] == 1.0f && hz_image_at(&back, 0, 0)[1] == 0.0f);
    assert_true(hz_image_at(&back, 1, 0)[1] == hz_srgb8_decode(128));
    assert_true(hz_image_at(&back, 0, 1)[2] == hz_srgb8_decode(30));
    /* RGBA 8-bit: alpha dropped. */
    uint8_t rgba[8] = { 1, 2, 3, 0, 250, 251, 252, 128 };
    write_png_variant(path_of("rgba.png"), 2, 1, 8, PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE, rgba, 8, NULL, 0);
    assert_int_equal(hz_png_read(path_of("rgba.png"), &arena, &back, &err), HZ_OK);
    assert_true(back.rgb[0] == hz_srgb8_decode(1) && back.rgb[5] == hz_srgb8_decode(252));
    /* RGB 16-bit and grey+alpha 16-bit. */
    uint8_t rgb16[6] = { 0xff, 0xff, 0x80, 0x00, 0x00, 0x00 };
    write_png_variant(path_of("rgb16.png"), 1, 1, 16, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, rgb16, 6, NULL, 0);
    assert_int_equal(hz_png_read(path_of("rgb16.png"), &arena, &back, &err), HZ_OK);
    assert_true(back.rgb[0] == 1.0f && back.rgb[2] == 0.0f);
    assert_float_equal(back.rgb[1], eotf(32768.0 / 65535.0), 0.0);
    uint8_t ga16[4] = { 0x12, 0x34, 0x00, 0x00 };
    write_png_variant(path_of("ga16.png"), 1, 1, 16, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_INTERLACE_NONE, ga16, 4, NULL, 0);
    assert_int_equal(hz_png_read(path_of("ga16.png"), &arena, &back, &err), HZ_OK);
    assert_float_equal(back.rgb[2], eotf(0x1234 / 65535.0), 0.0);
#endif
}

static void test_png_bad_files(void **state)
{
    (void)state;
    if (!hz_png_supported())
        return; /* test_png_round_trip_and_variants checks the refusal */
#if HZ_HAVE_PNG
    hz_image_t img = make_image(6, 6, 7), back;
    hz_error_t err;
    const char *p = path_of("good.png");
    assert_int_equal(hz_png_write(p, &img, &err), HZ_OK);
    size_t n;
    uint8_t *bytes = get_file(p, &n);
    /* A flipped bit in IDAT's stored CRC (the data itself still inflates): a checksum mismatch. */
    uint8_t *idat = memmem(bytes, n, "IDAT", 4);
    assert_non_null(idat);
    uint32_t len = (uint32_t)idat[-4] << 24 | (uint32_t)idat[-3] << 16 | (uint32_t)idat[-2] << 8 | idat[-1];
    uint8_t *crc = idat + 4 + len;
    crc[1] ^= 0x10;
    put_file(path_of("crc.png"), bytes, n);
    assert_int_equal(hz_png_read(path_of("crc.png"), &arena, &back, &err), HZ_E_CORRUPT);
    assert_non_null(strstr(err.msg, "crc.png"));
    assert_non_null(strstr(err.msg, "CRC"));
    crc[1] ^= 0x10;
    /* IHDR claiming 20000 x 6, with a valid CRC: an absurd size, refused before any allocation. */
    uint8_t *ihdr = bytes + 12;
    assert_memory_equal(ihdr, "IHDR", 4);
    be32(ihdr + 4, 20000);
    be32(ihdr + 17, crc32_of(ihdr, 17));
    put_file(path_of("wide.png"), bytes, n);
    hz_arena_mark_t m = hz_arena_mark(&arena);
    assert_int_equal(hz_png_read(path_of("wide.png"), &arena, &back, &err), HZ_E_RANGE);
    assert_non_null(strstr(err.msg, "absurd image size 20000x6"));
    assert_int_equal(hz_arena_mark(&arena), m);
    /* Truncated in the middle of the image data (with the original header). */
    be32(ihdr + 4, 6);
    be32(ihdr + 17, crc32_of(ihdr, 17));
    put_file(path_of("half.png"), bytes, (size_t)(idat - bytes) + 10);
    assert_int_equal(hz_png_read(path_of("half.png"), &arena, &back, &err), HZ_E_FORMAT);
    assert_non_null(strstr(err.msg, "truncated"));
    free(bytes);
    put_file(path_of("notpng.png"), "\x89PNX\r\n\x1a\nxxxxxxxx", 16);
    assert_int_equal(hz_png_read(path_of("notpng.png"), &arena, &back, &err), HZ_E_FORMAT);
    assert_non_null(strstr(err.msg, "wrong magic"));
#endif
}

/* ---- Y4M ---- */

static void test_y4m_known_colours(void **state)
{
    (void)state;
    uint8_t ycc[3];
    hz_y4m_opts_t o601f = { HZ_Y4M_C444, HZ_Y4M_BT601, true, 60, 1 };
    hz_y4m_opts_t o709l = { HZ_Y4M_C444, HZ_Y4M_BT709, false, 60, 1 };
    hz_y4m_rgb_to_ycbcr(&o601f, 255, 255, 255, ycc);
    assert_int_equal(ycc[0], 255);
    assert_int_equal(ycc[1], 128);
    assert_int_equal(ycc[2], 128);
    hz_y4m_rgb_to_ycbcr(&o601f, 0, 0, 0, ycc);
    assert_int_equal(ycc[0], 0);
    assert_int_equal(ycc[1], 128);
    hz_y4m_rgb_to_ycbcr(&o601f, 255, 0, 0, ycc); /* JFIF red: 76, 85, 255 */
    assert_int_equal(ycc[0], 76);
    assert_int_equal(ycc[1], 85);
    assert_int_equal(ycc[2], 255);
    hz_y4m_rgb_to_ycbcr(&o709l, 255, 255, 255, ycc);
    assert_int_equal(ycc[0], 235);
    assert_int_equal(ycc[1], 128);
    assert_int_equal(ycc[2], 128);
    hz_y4m_rgb_to_ycbcr(&o709l, 0, 0, 0, ycc);
    assert_int_equal(ycc[0], 16);
    hz_y4m_rgb_to_ycbcr(&o709l, 255, 0, 0, ycc); /* BT.709 limited red: 63, 102, 240 */
    assert_int_equal(ycc[0], 63);
    assert_int_equal(ycc[1], 102);
    assert_int_equal(ycc[2], 240);
    hz_y4m_rgb_to_ycbcr(&o709l, 0, 0, 255, ycc); /* blue: 32, 240, 118 */
    assert_int_equal(ycc[0], 32);
    assert_int_equal(ycc[1], 240);
    assert_int_equal(ycc[2], 118);
}

/* Inverse of the documented conversion, for checking the stream. */
static void ycbcr_to_rgb(const hz_y4m_opts_t *o, const uint8_t ycc[3], double rgb[3])
{
    double kr = o->matrix == HZ_Y4M_BT709 ? 0.2126 : 0.299, kb = o->matrix == HZ_Y4M_BT709 ? 0.0722 : 0.114;
    double y = o->full_range ? ycc[0] / 255.0 : (ycc[0] - 16) / 219.0;
    double pb = (ycc[1] - 128) / (o->full_range ? 255.0 : 224.0);
    double pr = (ycc[2] - 128) / (o->full_range ? 255.0 : 224.0);
    double r = y + 2 * (1 - kr) * pr, b = y + 2 * (1 - kb) * pb;
    double g = (y - kr * r - kb * b) / (1 - kr - kb);
    rgb[0] = 255 * r;
    rgb[1] = 255 * g;
    rgb[2] = 255 * b;
}

static void check_y4m_stream(const hz_y4m_opts_t *o, uint32_t w, uint32_t h, double tol)
{
    hz_arena_mark_t m = hz_arena_mark(&arena);
    bool sub = o->chroma == HZ_Y4M_C420JPEG;
    /* Frames constant over each 2x2 block when subsampled, so chroma can be checked exactly. */
    hz_image_t f[3];
    for (int k = 0; k < 3; k++) {
        f[k] = make_image(w, h, 10 + k);
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                for (int c = 0; c < 3; c++)
                    hz_image_at(&f[k], x, y)[c] = sub ? hz_image_at(&f[k], x & ~1u, y & ~1u)[c]
                                                      : hz_image_at(&f[k], x, y)[c];
    }
    hz_image_at(&f[1], 0, 0)[0] = NAN;
    hz_image_at(&f[1], 0, 0)[1] = NAN;
    hz_image_at(&f[1], 0, 0)[2] = NAN;
    if (sub) {
        for (uint32_t y = 0; y < 2 && y < h; y++)
            for (uint32_t x = 0; x < 2 && x < w; x++)
                for (int c = 0; c < 3; c++)
                    hz_image_at(&f[1], x, y)[c] = 0.0f;
    }
    const char *p = path_of("v.y4m");
    hz_y4m_t v;
    hz_error_t err;
    assert_int_equal(hz_y4m_open(&v, p, w, h, o, &err), HZ_OK);
    for (int k = 0; k < 3; k++)
        assert_int_equal(hz_y4m_write(&v, &f[k], &err), HZ_OK);
    assert_int_equal(hz_y4m_close(&v, &err), HZ_OK);
    size_t n;
    uint8_t *bytes = get_file(p, &n);
    char hdr[128];
    snprintf(hdr, sizeof hdr, "YUV4MPEG2 W%u H%u F%u:%u Ip A1:1 %s XCOLORRANGE=%s\n", w, h, o->fps_num, o->fps_den,
             sub ? "C420jpeg" : "C444", o->full_range ? "FULL" : "LIMITED");
    size_t hl = strlen(hdr);
    assert_memory_equal(bytes, hdr, hl);
    uint32_t cw = sub ? (w + 1) / 2 : w, ch = sub ? (h + 1) / 2 : h;
    size_t frame = 6 + (size_t)w * h + 2 * (size_t)cw * ch;
    assert_int_equal(n, hl + 3 * frame);
    for (int k = 0; k < 3; k++) {
        const uint8_t *fr = bytes + hl + k * frame;
        assert_memory_equal(fr, "FRAME\n", 6);
        const uint8_t *Y = fr + 6, *Cb = Y + (size_t)w * h, *Cr = Cb + (size_t)cw * ch;
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                size_t ci = sub ? (size_t)(y / 2) * cw + x / 2 : (size_t)y * w + x;
                uint8_t ycc[3] = { Y[(size_t)y * w + x], Cb[ci], Cr[ci] };
                double rgb[3];
                ycbcr_to_rgb(o, ycc, rgb);
                for (int c = 0; c < 3; c++) {
                    double want = hz_srgb8_encode(hz_image_at(&f[k], x, y)[c]);
                    if (fabs(rgb[c] - want) > tol)
                        fail_msg("frame %d (%u,%u) channel %d: got %.2f want %.0f", k, x, y, c, rgb[c], want);
                }
            }
    }
    free(bytes);
    hz_arena_reset(&arena, m);
}

static void test_y4m_streams_decode_back(void **state)
{
    (void)state;
    hz_y4m_opts_t o = { HZ_Y4M_C444, HZ_Y4M_BT601, true, 240, 1 };
    check_y4m_stream(&o, 5, 3, 1.5);
    o.matrix = HZ_Y4M_BT709;
    o.full_range = false;
    check_y4m_stream(&o, 4, 4, 2.0);
    o.chroma = HZ_Y4M_C420JPEG;
    check_y4m_stream(&o, 5, 3, 2.0); /* odd sizes: 3x2 chroma */
    o.full_range = true;
    o.fps_num = 120000;
    o.fps_den = 1001;
    check_y4m_stream(&o, 6, 4, 1.5);
}

static void test_y4m_420_averages_the_block(void **state)
{
    (void)state;
    hz_arena_mark_t m = hz_arena_mark(&arena);
    hz_image_t img;
    hz_error_t err;
    assert_int_equal(hz_image_alloc(&img, &arena, 3, 1, &err), HZ_OK);
    hz_image_fill(&img, 0.0f, 0.0f, 0.0f);
    img.rgb[0] = 1.0f; /* (0,0) red, (1,0) black: block 0 averages them; (2,0) alone in block 1 */
    img.rgb[8] = 1.0f; /* (2,0) blue */
    hz_y4m_opts_t o = { HZ_Y4M_C420JPEG, HZ_Y4M_BT601, true, 60, 1 };
    hz_y4m_t v;
    assert_int_equal(hz_y4m_open(&v, path_of("avg.y4m"), 3, 1, &o, &err), HZ_OK);
    assert_int_equal(hz_y4m_write(&v, &img, &err), HZ_OK);
    assert_int_equal(hz_y4m_close(&v, &err), HZ_OK);
    size_t n;
    uint8_t *bytes = get_file(path_of("avg.y4m"), &n);
    const uint8_t *fr = (const uint8_t *)memmem(bytes, n, "FRAME\n", 6) + 6;
    assert_int_equal(n, (size_t)(fr - bytes) + 3 + 2 + 2);
    /* Red: Pb = -0.299 / 1.772, Pr = 0.701 / 1.402 = 0.5; averaged with black (0, 0). */
    assert_int_equal(fr[3], (int)floor(128 + 255 * (-0.299 / 1.772) / 2 + 0.5));
    assert_int_equal(fr[5], (int)floor(128 + 255 * 0.25 + 0.5));
    /* Blue alone: Pb = 0.5 -> 255.5 clamps to 255; Pr = -0.114 / 1.402. */
    assert_int_equal(fr[4], 255);
    assert_int_equal(fr[6], (int)floor(128 + 255 * (-0.114 / 1.402) + 0.5));
    free(bytes);
    hz_arena_reset(&arena, m);
}

static void test_y4m_errors(void **state)
{
    (void)state;
    hz_y4m_opts_t o = { HZ_Y4M_C444, HZ_Y4M_BT709, true, 60, 1 };
    hz_y4m_t v;
    hz_error_t err;
    const char *bad = path_of("nodir/v.y4m");
    assert_int_equal(hz_y4m_open(&v, bad, 4, 4, &o, &err), HZ_E_IO);
    assert_non_null(strstr(err.msg, bad));
    hz_y4m_opts_t z = o;
    z.fps_den = 0;
    assert_int_equal(hz_y4m_open(&v, path_of("z.y4m"), 4, 4, &z, &err), HZ_E_INVALID_ARG);
    assert_int_equal(hz_y4m_open(&v, path_of("z.y4m"), 0, 4, &o, &err), HZ_E_INVALID_ARG);
    const char *p = path_of("aborted.y4m");
    assert_int_equal(hz_y4m_open(&v, p, 4, 4, &o, &err), HZ_OK);
    hz_image_t wrong = make_image(4, 3, 1);
    assert_int_equal(hz_y4m_write(&v, &wrong, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "4x3"));
    hz_y4m_abort(&v);
    assert_int_equal(access(p, F_OK), -1); /* nothing left behind */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ppm_round_trip),
        cmocka_unit_test(test_ppm_variants),
        cmocka_unit_test(test_pfm_round_trip_is_bit_exact),
        cmocka_unit_test(test_pfm_big_endian_grey),
        cmocka_unit_test(test_bad_files_get_distinct_errors_naming_the_file),
        cmocka_unit_test(test_missing_directory_and_fifo_are_io_errors),
        cmocka_unit_test(test_arena_too_small_and_restored),
        cmocka_unit_test(test_truncation_and_corruption),
        cmocka_unit_test(test_write_errors),
        cmocka_unit_test(test_png_round_trip_and_variants),
        cmocka_unit_test(test_png_bad_files),
        cmocka_unit_test(test_y4m_known_colours),
        cmocka_unit_test(test_y4m_streams_decode_back),
        cmocka_unit_test(test_y4m_420_averages_the_block),
        cmocka_unit_test(test_y4m_errors),
    };
    return HZ_RUN_GROUP(tests, setup, teardown);
}
