/* Image files: PNG, PPM, PFM readers and writers, and the streaming Y4M writer (see imageio.h). */
#include "imageio.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#if HZ_HAVE_PNG
#include <png.h>
#endif

/* ---------------------------------------------------------------------------------------------------------
 * Shared input helpers */

/* Opens a regular file for reading. FIFOs, devices and directories are refused; the open itself does not
 * block (O_NONBLOCK), so a FIFO without a writer cannot hang the reader. */
static FILE *open_input(const char *path, hz_status_t *s, hz_error_t *err)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        *s = hz_error_set(err, HZ_E_IO, "%s: %s", path, strerror(errno));
        return NULL;
    }
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        *s = hz_error_set(err, HZ_E_IO, "%s: not a regular file", path);
        return NULL;
    }
    int flags = fcntl(fd, F_GETFL);
    FILE *f = flags < 0 || fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) < 0 ? NULL : fdopen(fd, "rb");
    if (!f) {
        int e = errno;
        close(fd);
        *s = hz_error_set(err, HZ_E_IO, "%s: %s", path, strerror(e));
        return NULL;
    }
    *s = HZ_OK;
    return f;
}

/* Allocates the image, then gives back the arena to just after it on every later failure. */
typedef struct reader {
    const char *path;
    const char *kind; /* "PPM", "PFM", "PNG" */
    FILE *f;
    hz_arena_t *arena;
    hz_arena_mark_t entry;
    hz_image_t *img;
    hz_error_t *err;
} reader_t;

static hz_status_t fail(reader_t *r, hz_status_t code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static hz_status_t fail(reader_t *r, hz_status_t code, const char *fmt, ...)
{
    char msg[200];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return hz_error_set(r->err, code, "%s: %s: %s", r->path, r->kind, msg);
}

static hz_status_t finish(reader_t *r, hz_status_t s)
{
    if (r->f)
        fclose(r->f);
    r->f = NULL;
    if (s != HZ_OK) {
        hz_arena_reset(r->arena, r->entry);
        r->img->width = r->img->height = 0;
        r->img->rgb = NULL;
    }
    return s;
}

static hz_status_t check_dims(reader_t *r, uint64_t w, uint64_t h)
{
    if (w == 0 || h == 0 || w > HZ_IMAGE_MAX_DIM || h > HZ_IMAGE_MAX_DIM)
        return fail(r, HZ_E_RANGE, "absurd image size %llux%llu (each side must be 1..%u)", (unsigned long long)w,
                    (unsigned long long)h, HZ_IMAGE_MAX_DIM);
    return HZ_OK;
}

static hz_status_t alloc_image(reader_t *r, uint32_t w, uint32_t h)
{
    hz_error_t e;
    if (hz_image_alloc(r->img, r->arena, w, h, &e) != HZ_OK)
        return hz_error_set(r->err, e.code, "%s: %s", r->path, e.msg);
    return HZ_OK;
}

static void *alloc_temp(reader_t *r, size_t count, size_t size, hz_status_t *s)
{
    void *p = hz_arena_alloc_array(r->arena, count, size, 16);
    if (!p) {
        hz_error_t e;
        hz_arena_error(r->arena, &e);
        *s = hz_error_set(r->err, e.code, "%s: %s (temporary rows)", r->path, e.msg);
    }
    return p;
}

static hz_status_t read_exact(reader_t *r, void *buf, size_t n, size_t done_before, size_t total)
{
    size_t got = fread(buf, 1, n, r->f);
    if (got == n)
        return HZ_OK;
    if (ferror(r->f))
        return hz_error_set(r->err, HZ_E_IO, "%s: read error: %s", r->path, strerror(errno));
    return fail(r, HZ_E_FORMAT, "truncated: pixel data ends after %zu of %zu bytes", done_before + got, total);
}

/* sRGB-decoded value of every sample value 0..maxval (maxval 255 uses the exact 8-bit table). */
static float *decode_table(reader_t *r, uint32_t maxval, hz_status_t *s)
{
    float *t = alloc_temp(r, (size_t)maxval + 1, sizeof(float), s);
    if (!t)
        return NULL;
    for (uint32_t v = 0; v <= maxval; v++) {
        if (maxval == 255) {
            t[v] = hz_srgb8_decode((uint8_t)v);
        } else {
            double c = (double)v / maxval;
            t[v] = (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
        }
    }
    return t;
}

/* ---------------------------------------------------------------------------------------------------------
 * PPM (P6 colour, P5 grey), binary Netpbm */

static bool is_space(int c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/* Next header token's first character, skipping whitespace and (for PNM) '#' comments to the end of line. */
static int next_token_char(FILE *f, bool comments)
{
    int c;
    for (;;) {
        c = getc(f);
        if (comments && c == '#') {
            while ((c = getc(f)) != EOF && c != '\n' && c != '\r')
                ;
            if (c == EOF)
                return EOF;
            continue;
        }
        if (!is_space(c))
            return c;
    }
}

/* A decimal header field; values above `cap` saturate at cap + 1 (the caller says why that is wrong). *term gets
 * the character that ended the number (which must be whitespace). */
static hz_status_t read_header_uint(reader_t *r, const char *what, bool comments, uint64_t cap, uint64_t *out,
                                    int *term)
{
    int c = next_token_char(r->f, comments);
    if (c == EOF)
        return fail(r, HZ_E_FORMAT, "truncated: the header ends before the %s", what);
    if (c < '0' || c > '9')
        return fail(r, HZ_E_FORMAT, "bad header: expected the %s (a decimal number), found '%c'", what,
                    c >= 32 && c < 127 ? c : '?');
    uint64_t v = 0;
    int digits = 0;
    while (c >= '0' && c <= '9') {
        if (v <= cap)
            v = v * 10 + (uint64_t)(c - '0');
        if (++digits > 40)
            return fail(r, HZ_E_FORMAT, "bad header: the %s has too many digits", what);
        c = getc(r->f);
    }
    if (c == EOF)
        return fail(r, HZ_E_FORMAT, "truncated: the header ends after the %s", what);
    if (!is_space(c) && !(comments && c == '#'))
        return fail(r, HZ_E_FORMAT, "bad header: the %s is followed by '%c', not whitespace", what,
                    c >= 32 && c < 127 ? c : '?');
    if (c == '#')
        ungetc(c, r->f);
    *out = v > cap ? cap + 1 : v;
    *term = c;
    return HZ_OK;
}

static hz_status_t read_magic(reader_t *r, char m[2])
{
    int a = getc(r->f), b = a == EOF ? EOF : getc(r->f);
    if (a == EOF || b == EOF)
        return fail(r, HZ_E_FORMAT, "truncated: the file is %s", a == EOF ? "empty" : "1 byte long");
    m[0] = (char)a;
    m[1] = (char)b;
    return HZ_OK;
}

hz_status_t hz_ppm_read(const char *path, hz_arena_t *arena, hz_image_t *img, hz_error_t *err)
{
    reader_t r = { path, "PPM", NULL, arena, hz_arena_mark(arena), img, err };
    img->width = img->height = 0;
    img->rgb = NULL;
    hz_status_t s;
    r.f = open_input(path, &s, err);
    if (!r.f)
        return s;
    char m[2];
    if ((s = read_magic(&r, m)) != HZ_OK)
        return finish(&r, s);
    if (m[0] != 'P' || !(m[1] == '6' || m[1] == '5')) {
        if (m[0] == 'P' && (m[1] == '3' || m[1] == '2' || m[1] == '1'))
            return finish(&r, fail(&r, HZ_E_UNSUPPORTED, "ASCII Netpbm (P%c) is not supported; use binary P6", m[1]));
        if (m[0] == 'P' && (m[1] == '4' || m[1] == '7'))
            return finish(&r, fail(&r, HZ_E_UNSUPPORTED, "Netpbm P%c (%s) is not supported; use P6", m[1],
                                   m[1] == '4' ? "bitmap" : "PAM"));
        return finish(&r, fail(&r, HZ_E_FORMAT, "not a PPM file (wrong magic: expected \"P6\" or \"P5\")"));
    }
    uint32_t channels = m[1] == '6' ? 3 : 1;
    uint64_t w, h, maxval;
    int term;
    if ((s = read_header_uint(&r, "width", true, HZ_IMAGE_MAX_DIM, &w, &term)) != HZ_OK ||
        (s = read_header_uint(&r, "height", true, HZ_IMAGE_MAX_DIM, &h, &term)) != HZ_OK)
        return finish(&r, s);
    if ((s = check_dims(&r, w, h)) != HZ_OK)
        return finish(&r, s);
    if ((s = read_header_uint(&r, "maxval", true, 65535, &maxval, &term)) != HZ_OK)
        return finish(&r, s);
    if (maxval == 0 || maxval > 65535)
        return finish(&r, fail(&r, HZ_E_FORMAT, "bad header: maxval must be 1..65535"));
    if (term == '#')
        return finish(&r, fail(&r, HZ_E_FORMAT, "bad header: a comment directly after maxval (the single "
                                                "whitespace byte before the pixels is missing)"));
    /* Exactly one whitespace byte (term) separates maxval from the pixels: nothing more to skip. */
    size_t bps = maxval > 255 ? 2 : 1;
    size_t row_bytes = (size_t)w * channels * bps, total = row_bytes * (size_t)h;
    if ((s = alloc_image(&r, (uint32_t)w, (uint32_t)h)) != HZ_OK)
        return finish(&r, s);
    hz_arena_mark_t after_image = hz_arena_mark(arena);
    uint8_t *row = alloc_temp(&r, row_bytes, 1, &s);
    float *table = row ? decode_table(&r, (uint32_t)maxval, &s) : NULL;
    if (!table)
        return finish(&r, s);
    for (uint32_t y = 0; y < h; y++) {
        if ((s = read_exact(&r, row, row_bytes, row_bytes * y, total)) != HZ_OK)
            return finish(&r, s);
        float *dst = hz_image_at(img, 0, y);
        for (uint32_t x = 0; x < w; x++) {
            for (uint32_t c = 0; c < 3; c++) {
                size_t i = (size_t)x * channels + (channels == 3 ? c : 0);
                uint32_t v = bps == 1 ? row[i] : (uint32_t)row[2 * i] << 8 | row[2 * i + 1];
                if (v > maxval)
                    return finish(&r, fail(&r, HZ_E_FORMAT, "sample %u at (%u, %u) exceeds maxval %u",
                                           (unsigned)v, (unsigned)x, (unsigned)y, (unsigned)maxval));
                dst[3 * x + c] = table[v];
            }
        }
    }
    hz_arena_reset(arena, after_image);
    return finish(&r, HZ_OK);
}

/* Rows of 8-bit sRGB codes, from a linear float image (encoded row by row into tmp) or from RGB24 as given. */
typedef struct rows8 {
    const hz_image_t *img;
    const uint8_t *rgb;
    size_t stride;
    uint8_t *tmp;
} rows8_t;

static const uint8_t *row8(const rows8_t *r, uint32_t y, size_t row_bytes)
{
    if (!r->img)
        return r->rgb + (size_t)y * r->stride;
    hz_srgb8_encode_n(hz_image_at(r->img, 0, y), r->tmp, row_bytes);
    return r->tmp;
}

static hz_status_t ppm_write_rows(const char *path, uint32_t w, uint32_t h, rows8_t *r, hz_error_t *err)
{
    size_t row_bytes = (size_t)w * 3;
    uint8_t *row = malloc(row_bytes ? row_bytes : 1);
    if (!row)
        return hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory for a %zu-byte row", path, row_bytes);
    r->tmp = row;
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK) {
        free(row);
        return s;
    }
    fprintf(out.f, "P6\n%u %u\n255\n", (unsigned)w, (unsigned)h);
    for (uint32_t y = 0; y < h; y++) {
        if (fwrite(row8(r, y, row_bytes), 1, row_bytes, out.f) != row_bytes) {
            int e = errno;
            hz_out_abort(&out);
            free(row);
            return hz_error_set(err, HZ_E_IO, "%s: write failed: %s", path, strerror(e));
        }
    }
    free(row);
    return hz_out_commit(&out, err);
}

hz_status_t hz_ppm_write(const char *path, const hz_image_t *img, hz_error_t *err)
{
    rows8_t r = { img, NULL, 0, NULL };
    return ppm_write_rows(path, img->width, img->height, &r, err);
}

hz_status_t hz_ppm_write_rgb8(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h, size_t stride,
                              hz_error_t *err)
{
    rows8_t r = { NULL, rgb, stride, NULL };
    return ppm_write_rows(path, w, h, &r, err);
}

/* ---------------------------------------------------------------------------------------------------------
 * PFM: "PF" (RGB) or "Pf" (grey), "W H", scale (negative: little-endian), one whitespace byte, float rows from
 * the bottom row up. */

static bool host_is_little_endian(void)
{
    const uint16_t one = 1;
    return *(const uint8_t *)&one == 1;
}

hz_status_t hz_pfm_read(const char *path, hz_arena_t *arena, hz_image_t *img, hz_error_t *err)
{
    reader_t r = { path, "PFM", NULL, arena, hz_arena_mark(arena), img, err };
    img->width = img->height = 0;
    img->rgb = NULL;
    hz_status_t s;
    r.f = open_input(path, &s, err);
    if (!r.f)
        return s;
    char m[2];
    if ((s = read_magic(&r, m)) != HZ_OK)
        return finish(&r, s);
    if (m[0] != 'P' || (m[1] != 'F' && m[1] != 'f'))
        return finish(&r, fail(&r, HZ_E_FORMAT, "not a PFM file (wrong magic: expected \"PF\" or \"Pf\")"));
    uint32_t channels = m[1] == 'F' ? 3 : 1;
    int c = getc(r.f);
    if (!is_space(c))
        return finish(&r, fail(&r, HZ_E_FORMAT, "bad header: no whitespace after the magic"));
    uint64_t w, h;
    int term;
    if ((s = read_header_uint(&r, "width", false, HZ_IMAGE_MAX_DIM, &w, &term)) != HZ_OK ||
        (s = read_header_uint(&r, "height", false, HZ_IMAGE_MAX_DIM, &h, &term)) != HZ_OK)
        return finish(&r, s);
    if ((s = check_dims(&r, w, h)) != HZ_OK)
        return finish(&r, s);
    char tok[64];
    size_t n = 0;
    c = next_token_char(r.f, false);
    while (c != EOF && !is_space(c) && n < sizeof tok - 1) {
        tok[n++] = (char)c;
        c = getc(r.f);
    }
    tok[n] = '\0';
    if (c == EOF)
        return finish(&r, fail(&r, HZ_E_FORMAT, "truncated: the header ends %s",
                               n ? "after the scale" : "before the scale"));
    if (!is_space(c))
        return finish(&r, fail(&r, HZ_E_FORMAT, "bad header: the scale is longer than %zu characters", sizeof tok - 1));
    char *end;
    errno = 0;
    double scale = strtod(tok, &end);
    if (end == tok || *end != '\0' || errno == ERANGE || !isfinite(scale) || scale == 0.0)
        return finish(&r, fail(&r, HZ_E_FORMAT, "bad header: scale \"%s\" is not a finite non-zero number", tok));
    bool little = scale < 0.0;
    size_t row_bytes = (size_t)w * channels * 4, total = row_bytes * (size_t)h;
    if ((s = alloc_image(&r, (uint32_t)w, (uint32_t)h)) != HZ_OK)
        return finish(&r, s);
    hz_arena_mark_t after_image = hz_arena_mark(arena);
    uint8_t *row = alloc_temp(&r, row_bytes, 1, &s);
    if (!row)
        return finish(&r, s);
    for (uint32_t i = 0; i < h; i++) {
        if ((s = read_exact(&r, row, row_bytes, row_bytes * i, total)) != HZ_OK)
            return finish(&r, s);
        float *dst = hz_image_at(img, 0, (uint32_t)h - 1 - i); /* first stored row is the bottom one */
        for (uint32_t x = 0; x < w; x++) {
            for (uint32_t ch = 0; ch < 3; ch++) {
                const uint8_t *b = row + 4 * ((size_t)x * channels + (channels == 3 ? ch : 0));
                uint32_t u = little
                                 ? (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24
                                 : (uint32_t)b[3] | (uint32_t)b[2] << 8 | (uint32_t)b[1] << 16 | (uint32_t)b[0] << 24;
                dst[3 * x + ch] = hz_float_from_bits(u);
            }
        }
    }
    hz_arena_reset(arena, after_image);
    return finish(&r, HZ_OK);
}

hz_status_t hz_pfm_write(const char *path, const hz_image_t *img, hz_error_t *err)
{
    size_t row_bytes = (size_t)img->width * 12;
    uint8_t *row = malloc(row_bytes ? row_bytes : 1);
    if (!row)
        return hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory for a %zu-byte row", path, row_bytes);
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK) {
        free(row);
        return s;
    }
    fprintf(out.f, "PF\n%u %u\n-1.0\n", (unsigned)img->width, (unsigned)img->height);
    bool little = host_is_little_endian();
    for (uint32_t i = 0; i < img->height; i++) {
        const float *src = hz_image_at(img, 0, img->height - 1 - i);
        if (little) {
            memcpy(row, src, row_bytes);
        } else {
            for (size_t k = 0; k < (size_t)img->width * 3; k++) {
                uint32_t u = hz_float_bits(src[k]);
                for (int b = 0; b < 4; b++)
                    row[4 * k + b] = (uint8_t)(u >> (8 * b));
            }
        }
        if (fwrite(row, 1, row_bytes, out.f) != row_bytes) {
            int e = errno;
            hz_out_abort(&out);
            free(row);
            return hz_error_set(err, HZ_E_IO, "%s: write failed: %s", path, strerror(e));
        }
    }
    free(row);
    return hz_out_commit(&out, err);
}

/* ---------------------------------------------------------------------------------------------------------
 * PNG (libpng) */

#if HZ_HAVE_PNG

bool hz_png_supported(void)
{
    return true;
}

/* libpng reports errors through a callback that must not return: it records the message and jumps back. Every
 * piece of state the jump must see lives in this struct (not in locals changed after setjmp). */
typedef struct png_ctx {
    jmp_buf jump;
    FILE *f;
    char msg[160];
    bool io_error;
    bool truncated;
} png_ctx_t;

static void png_on_error(png_structp png, png_const_charp msg)
{
    png_ctx_t *c = png_get_error_ptr(png);
    snprintf(c->msg, sizeof c->msg, "%s", msg ? msg : "unknown libpng error");
    longjmp(c->jump, 1);
}

static void png_on_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg; /* benign (e.g. an unknown ancillary chunk): the image is still read */
}

static void png_read_data(png_structp png, png_bytep data, size_t n)
{
    png_ctx_t *c = png_get_io_ptr(png);
    size_t got = fread(data, 1, n, c->f);
    if (got != n) {
        if (ferror(c->f)) {
            c->io_error = true;
            png_error(png, strerror(errno));
        }
        c->truncated = true;
        png_error(png, "truncated: the file ends early");
    }
}

static void png_write_data(png_structp png, png_bytep data, size_t n)
{
    png_ctx_t *c = png_get_io_ptr(png);
    if (fwrite(data, 1, n, c->f) != n) {
        c->io_error = true;
        png_error(png, strerror(errno));
    }
}

static void png_flush_data(png_structp png)
{
    (void)png; /* hz_out_commit flushes */
}

static hz_status_t png_status(const png_ctx_t *c)
{
    if (c->io_error)
        return HZ_E_IO;
    if (!c->truncated && strstr(c->msg, "CRC"))
        return HZ_E_CORRUPT;
    return HZ_E_FORMAT;
}

typedef struct png_read_state {
    reader_t r;
    png_ctx_t ctx;
    png_structp png;
    png_infop info;
    hz_status_t status; /* set before any longjmp-able call returns an error of ours */
} png_read_state_t;

static hz_status_t png_read_body(png_read_state_t *st)
{
    reader_t *r = &st->r;
    png_structp png = st->png;
    png_infop info = st->info;
    hz_status_t s;
    png_set_sig_bytes(png, 8);
    png_read_info(png, info);
    png_uint_32 w, h;
    int depth, color, interlace;
    png_get_IHDR(png, info, &w, &h, &depth, &color, &interlace, NULL, NULL);
    if ((s = check_dims(r, w, h)) != HZ_OK)
        return s;
    if (color == PNG_COLOR_TYPE_PALETTE)
        png_set_palette_to_rgb(png);
    if (color == PNG_COLOR_TYPE_GRAY && depth < 8)
        png_set_expand_gray_1_2_4_to_8(png);
    if (color == PNG_COLOR_TYPE_GRAY || color == PNG_COLOR_TYPE_GRAY_ALPHA)
        png_set_gray_to_rgb(png);
    if (color & PNG_COLOR_MASK_ALPHA)
        png_set_strip_alpha(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    size_t bps = depth == 16 ? 2 : 1;
    size_t row_bytes = (size_t)w * 3 * bps;
    if (png_get_rowbytes(png, info) != row_bytes || png_get_channels(png, info) != 3)
        return fail(r, HZ_E_INTERNAL, "unexpected row layout after expansion (%zu bytes, %d channels)",
                    (size_t)png_get_rowbytes(png, info), (int)png_get_channels(png, info));
    if ((s = alloc_image(r, w, h)) != HZ_OK)
        return s;
    uint8_t *pixels = alloc_temp(r, row_bytes, h, &s);
    png_bytep *rows = pixels ? alloc_temp(r, h, sizeof(png_bytep), &s) : NULL;
    float *table = rows && bps == 2 ? decode_table(r, 65535, &s) : NULL;
    if (!rows || (bps == 2 && !table))
        return s;
    for (uint32_t y = 0; y < h; y++)
        rows[y] = pixels + row_bytes * y;
    png_read_image(png, rows);
    png_read_end(png, NULL); /* checks the chunks after the image data (CRC, truncation) */
    for (uint32_t y = 0; y < h; y++) {
        const uint8_t *src = rows[y];
        float *dst = hz_image_at(st->r.img, 0, y);
        if (bps == 1)
            hz_srgb8_decode_n(src, dst, (size_t)w * 3);
        else
            for (size_t i = 0; i < (size_t)w * 3; i++)
                dst[i] = table[(uint32_t)src[2 * i] << 8 | src[2 * i + 1]];
    }
    return HZ_OK;
}

hz_status_t hz_png_read(const char *path, hz_arena_t *arena, hz_image_t *img, hz_error_t *err)
{
    png_read_state_t st;
    memset(&st, 0, sizeof st);
    reader_t r0 = { path, "PNG", NULL, arena, hz_arena_mark(arena), img, err };
    st.r = r0;
    img->width = img->height = 0;
    img->rgb = NULL;
    hz_status_t s;
    st.r.f = open_input(path, &s, err);
    if (!st.r.f)
        return s;
    uint8_t sig[8];
    size_t got = fread(sig, 1, sizeof sig, st.r.f);
    if (got == 0)
        return finish(&st.r, fail(&st.r, HZ_E_FORMAT, "truncated: the file is empty"));
    if (got < sizeof sig || png_sig_cmp(sig, 0, sizeof sig) != 0)
        return finish(&st.r, fail(&st.r, HZ_E_FORMAT, "not a PNG file (wrong magic)"));
    st.ctx.f = st.r.f;
    st.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &st.ctx, png_on_error, png_on_warning);
    st.info = st.png ? png_create_info_struct(st.png) : NULL;
    if (!st.info) {
        png_destroy_read_struct(st.png ? &st.png : NULL, NULL, NULL);
        return finish(&st.r, fail(&st.r, HZ_E_NO_MEMORY, "libpng could not allocate its state"));
    }
    png_set_read_fn(st.png, &st.ctx, png_read_data);
    /* Our own size check gives the clearer message; libpng's limit stays above it. */
    png_set_user_limits(st.png, HZ_IMAGE_MAX_DIM * 2, HZ_IMAGE_MAX_DIM * 2);
    if (setjmp(st.ctx.jump)) {
        png_destroy_read_struct(&st.png, &st.info, NULL);
        return finish(&st.r, fail(&st.r, png_status(&st.ctx), "%s", st.ctx.msg));
    }
    s = png_read_body(&st);
    png_destroy_read_struct(&st.png, &st.info, NULL);
    return finish(&st.r, s);
}

typedef struct png_write_state {
    png_ctx_t ctx;
    png_structp png;
    png_infop info;
    hz_out_t out;
    uint8_t *row;
} png_write_state_t;

static hz_status_t png_write_image8(const char *path, uint32_t w, uint32_t h, rows8_t *r, hz_error_t *err)
{
    png_write_state_t *st = calloc(1, sizeof *st);
    if (!st)
        return hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory for the PNG writer", path);
    size_t row_bytes = (size_t)w * 3;
    st->row = malloc(row_bytes ? row_bytes : 1);
    hz_status_t s = HZ_OK;
    if (!st->row) {
        s = hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory for a %zu-byte row", path, row_bytes);
        goto done;
    }
    if ((s = hz_out_open(&st->out, path, err)) != HZ_OK)
        goto done;
    st->ctx.f = st->out.f;
    st->png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &st->ctx, png_on_error, png_on_warning);
    st->info = st->png ? png_create_info_struct(st->png) : NULL;
    if (!st->info) {
        hz_out_abort(&st->out);
        s = hz_error_set(err, HZ_E_NO_MEMORY, "%s: libpng could not allocate its state", path);
        goto done;
    }
    if (setjmp(st->ctx.jump)) {
        hz_out_abort(&st->out);
        s = hz_error_set(err, st->ctx.io_error ? HZ_E_IO : HZ_E_INTERNAL, "%s: PNG: write failed: %s", path,
                         st->ctx.msg);
        goto done;
    }
    png_set_write_fn(st->png, &st->ctx, png_write_data, png_flush_data);
    png_set_IHDR(st->png, st->info, w, h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB_gAMA_and_cHRM(st->png, st->info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(st->png, st->info);
    r->tmp = st->row;
    for (uint32_t y = 0; y < h; y++)
        png_write_row(st->png, (png_bytep)(uintptr_t)row8(r, y, row_bytes));
    png_write_end(st->png, NULL);
    s = hz_out_commit(&st->out, err);
done:
    if (st->png)
        png_destroy_write_struct(&st->png, st->info ? &st->info : NULL);
    free(st->row);
    free(st);
    return s;
}

hz_status_t hz_png_write(const char *path, const hz_image_t *img, hz_error_t *err)
{
    rows8_t r = { img, NULL, 0, NULL };
    return png_write_image8(path, img->width, img->height, &r, err);
}

hz_status_t hz_png_write_rgb8(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h, size_t stride,
                              hz_error_t *err)
{
    rows8_t r = { NULL, rgb, stride, NULL };
    return png_write_image8(path, w, h, &r, err);
}

#else /* !HZ_HAVE_PNG */

bool hz_png_supported(void)
{
    return false;
}

hz_status_t hz_png_read(const char *path, hz_arena_t *arena, hz_image_t *img, hz_error_t *err)
{
    (void)arena;
    img->width = img->height = 0;
    img->rgb = NULL;
    return hz_error_set(err, HZ_E_UNSUPPORTED, "%s: PNG support is not built in (libpng was not found for this "
                        "target); use PPM or PFM", path);
}

hz_status_t hz_png_write(const char *path, const hz_image_t *img, hz_error_t *err)
{
    (void)img;
    return hz_error_set(err, HZ_E_UNSUPPORTED, "%s: PNG support is not built in (libpng was not found for this "
                        "target); use PPM or PFM", path);
}

hz_status_t hz_png_write_rgb8(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h, size_t stride,
                              hz_error_t *err)
{
    (void)rgb, (void)w, (void)h, (void)stride;
    return hz_error_set(err, HZ_E_UNSUPPORTED, "%s: PNG support is not built in (libpng was not found for this "
                        "target); use PPM or PFM", path);
}

#endif

/* ---------------------------------------------------------------------------------------------------------
 * By content / extension */

hz_status_t hz_image_read(const char *path, hz_arena_t *arena, hz_image_t *img, hz_error_t *err)
{
    img->width = img->height = 0;
    img->rgb = NULL;
    hz_status_t s;
    FILE *f = open_input(path, &s, err);
    if (!f)
        return s;
    uint8_t m[8] = { 0 };
    size_t got = fread(m, 1, sizeof m, f);
    fclose(f);
    static const uint8_t png_sig[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
    if (got == sizeof m && !memcmp(m, png_sig, sizeof m))
        return hz_png_read(path, arena, img, err);
    if (got >= 2 && m[0] == 'P' && (m[1] == 'F' || m[1] == 'f'))
        return hz_pfm_read(path, arena, img, err);
    if (got >= 2 && m[0] == 'P' && m[1] >= '1' && m[1] <= '7')
        return hz_ppm_read(path, arena, img, err);
    if (got == 0)
        return hz_error_set(err, HZ_E_FORMAT, "%s: the file is empty", path);
    return hz_error_set(err, HZ_E_FORMAT, "%s: unknown image format (expected PNG, PPM P6/P5 or PFM)", path);
}

static bool has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    if (n <= e)
        return false;
    for (size_t i = 0; i < e; i++) {
        char c = path[n - e + i];
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if (c != ext[i])
            return false;
    }
    return true;
}

hz_status_t hz_image_write(const char *path, const hz_image_t *img, hz_error_t *err)
{
    if (has_ext(path, ".png"))
        return hz_png_write(path, img, err);
    if (has_ext(path, ".ppm"))
        return hz_ppm_write(path, img, err);
    if (has_ext(path, ".pfm"))
        return hz_pfm_write(path, img, err);
    return hz_error_set(err, HZ_E_INVALID_ARG, "%s: unknown image extension (use .png, .ppm or .pfm)", path);
}

/* ---------------------------------------------------------------------------------------------------------
 * Y4M */

static void matrix_coeffs(hz_y4m_matrix_t m, float *kr, float *kb)
{
    if (m == HZ_Y4M_BT709) {
        *kr = 0.2126f;
        *kb = 0.0722f;
    } else {
        *kr = 0.299f;
        *kb = 0.114f;
    }
}

static uint8_t quantize(float v)
{
    if (!(v > 0.0f))
        return 0;
    if (v >= 255.0f)
        return 255;
    return (uint8_t)(v + 0.5f);
}

/* Y' and unscaled colour differences Pb, Pr (each in [-0.5, 0.5]) of sRGB codes. */
static void rgb_to_ypbpr(float kr, float kb, uint8_t r8, uint8_t g8, uint8_t b8, float *yp, float *pb, float *pr)
{
    float r = r8 * (1.0f / 255.0f), g = g8 * (1.0f / 255.0f), b = b8 * (1.0f / 255.0f);
    float y = kr * r + (1.0f - kr - kb) * g + kb * b;
    *yp = y;
    *pb = (b - y) / (2.0f * (1.0f - kb));
    *pr = (r - y) / (2.0f * (1.0f - kr));
}

static uint8_t luma_code(bool full, float y)
{
    return quantize(full ? 255.0f * y : 16.0f + 219.0f * y);
}

static uint8_t chroma_code(bool full, float c)
{
    return quantize(128.0f + (full ? 255.0f : 224.0f) * c);
}

void hz_y4m_rgb_to_ycbcr(const hz_y4m_opts_t *opts, uint8_t r, uint8_t g, uint8_t b, uint8_t ycc[3])
{
    float kr, kb, y, pb, pr;
    matrix_coeffs(opts->matrix, &kr, &kb);
    rgb_to_ypbpr(kr, kb, r, g, b, &y, &pb, &pr);
    ycc[0] = luma_code(opts->full_range, y);
    ycc[1] = chroma_code(opts->full_range, pb);
    ycc[2] = chroma_code(opts->full_range, pr);
}

hz_status_t hz_y4m_open(hz_y4m_t *y4m, const char *path, uint32_t width, uint32_t height, const hz_y4m_opts_t *opts,
                        hz_error_t *err)
{
    memset(y4m, 0, sizeof *y4m);
    hz_status_t s = hz_image_check_size(width, height, NULL, err);
    if (s != HZ_OK) {
        hz_error_prefix(err, path);
        return s;
    }
    if (!opts || opts->fps_num == 0 || opts->fps_den == 0 ||
        (opts->chroma != HZ_Y4M_C444 && opts->chroma != HZ_Y4M_C420JPEG) ||
        (opts->matrix != HZ_Y4M_BT601 && opts->matrix != HZ_Y4M_BT709))
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s: Y4M: bad options (frame rate must be a positive fraction, "
                            "chroma 444 or 420jpeg, matrix BT.601 or BT.709)", path);
    y4m->opts = *opts;
    y4m->width = width;
    y4m->height = height;
    bool sub = opts->chroma == HZ_Y4M_C420JPEG;
    y4m->cw = sub ? (width + 1) / 2 : width;
    y4m->ch = sub ? (height + 1) / 2 : height;
    size_t luma = (size_t)width * height, chroma = (size_t)y4m->cw * y4m->ch;
    y4m->y = malloc(luma + 2 * chroma);
    y4m->pb = malloc(2 * sizeof(float) * y4m->cw);
    y4m->row = malloc((size_t)width * 3);
    if (!y4m->y || !y4m->pb || !y4m->row) {
        free(y4m->y);
        free(y4m->pb);
        free(y4m->row);
        memset(y4m, 0, sizeof *y4m);
        return hz_error_set(err, HZ_E_NO_MEMORY, "%s: Y4M: no memory for %zu bytes of planes", path,
                            luma + 2 * chroma);
    }
    y4m->cb = y4m->y + luma;
    y4m->cr = y4m->cb + chroma;
    y4m->pr = y4m->pb + y4m->cw;
    if ((s = hz_out_open(&y4m->out, path, err)) != HZ_OK) {
        free(y4m->y);
        free(y4m->pb);
        free(y4m->row);
        memset(y4m, 0, sizeof *y4m);
        return s;
    }
    fprintf(y4m->out.f, "YUV4MPEG2 W%u H%u F%u:%u Ip A1:1 %s XCOLORRANGE=%s\n", (unsigned)width, (unsigned)height,
            (unsigned)opts->fps_num, (unsigned)opts->fps_den, sub ? "C420jpeg" : "C444",
            opts->full_range ? "FULL" : "LIMITED");
    return HZ_OK;
}

static hz_status_t y4m_write_rows(hz_y4m_t *y4m, uint32_t fw, uint32_t fh, rows8_t *r, hz_error_t *err)
{
    if (!y4m->out.f)
        return hz_error_set(err, HZ_E_INVALID_ARG, "Y4M stream is not open");
    if (fw != y4m->width || fh != y4m->height)
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s: Y4M: frame is %ux%u, the stream %ux%u", y4m->out.path,
                            (unsigned)fw, (unsigned)fh, (unsigned)y4m->width, (unsigned)y4m->height);
    r->tmp = y4m->row;
    float kr, kb;
    matrix_coeffs(y4m->opts.matrix, &kr, &kb);
    bool full = y4m->opts.full_range, sub = y4m->opts.chroma == HZ_Y4M_C420JPEG;
    uint32_t w = y4m->width, h = y4m->height;
    for (uint32_t y = 0; y < h; y++) {
        const uint8_t *src = row8(r, y, (size_t)w * 3);
        uint8_t *ly = y4m->y + (size_t)y * w;
        if (sub && y % 2 == 0)
            for (uint32_t i = 0; i < y4m->cw; i++)
                y4m->pb[i] = y4m->pr[i] = 0.0f;
        for (uint32_t x = 0; x < w; x++) {
            float yp, pb, pr;
            rgb_to_ypbpr(kr, kb, src[3 * x], src[3 * x + 1], src[3 * x + 2], &yp, &pb, &pr);
            ly[x] = luma_code(full, yp);
            if (!sub) {
                y4m->cb[(size_t)y * w + x] = chroma_code(full, pb);
                y4m->cr[(size_t)y * w + x] = chroma_code(full, pr);
            } else {
                y4m->pb[x / 2] += pb;
                y4m->pr[x / 2] += pr;
            }
        }
        if (sub && (y % 2 == 1 || y + 1 == h)) {
            /* Average over the pixels the block really has (odd sizes: 2 or 1 at the right/bottom edge). */
            uint32_t rows = y % 2 == 1 ? 2 : 1;
            for (uint32_t i = 0; i < y4m->cw; i++) {
                uint32_t cols = 2 * i + 1 < w ? 2 : 1;
                float inv = 1.0f / (float)(rows * cols);
                y4m->cb[(size_t)(y / 2) * y4m->cw + i] = chroma_code(full, y4m->pb[i] * inv);
                y4m->cr[(size_t)(y / 2) * y4m->cw + i] = chroma_code(full, y4m->pr[i] * inv);
            }
        }
    }
    size_t bytes = (size_t)w * h + 2 * (size_t)y4m->cw * y4m->ch;
    if (fputs("FRAME\n", y4m->out.f) == EOF || fwrite(y4m->y, 1, bytes, y4m->out.f) != bytes)
        return hz_error_set(err, HZ_E_IO, "%s: Y4M: write failed at frame %llu: %s", y4m->out.path,
                            (unsigned long long)y4m->frames, strerror(errno));
    y4m->frames++;
    return HZ_OK;
}

hz_status_t hz_y4m_write(hz_y4m_t *y4m, const hz_image_t *frame, hz_error_t *err)
{
    rows8_t r = { frame, NULL, 0, NULL };
    return y4m_write_rows(y4m, frame->width, frame->height, &r, err);
}

hz_status_t hz_y4m_write_rgb8(hz_y4m_t *y4m, const uint8_t *rgb, uint32_t w, uint32_t h, size_t stride,
                              hz_error_t *err)
{
    rows8_t r = { NULL, rgb, stride, NULL };
    return y4m_write_rows(y4m, w, h, &r, err);
}

static void y4m_free(hz_y4m_t *y4m)
{
    free(y4m->y);
    free(y4m->pb);
    free(y4m->row);
    y4m->row = NULL;
    y4m->y = y4m->cb = y4m->cr = NULL;
    y4m->pb = y4m->pr = NULL;
}

hz_status_t hz_y4m_close(hz_y4m_t *y4m, hz_error_t *err)
{
    y4m_free(y4m);
    if (!y4m->out.f)
        return hz_error_set(err, HZ_E_INVALID_ARG, "Y4M stream is not open");
    return hz_out_commit(&y4m->out, err);
}

void hz_y4m_abort(hz_y4m_t *y4m)
{
    y4m_free(y4m);
    hz_out_abort(&y4m->out);
}
