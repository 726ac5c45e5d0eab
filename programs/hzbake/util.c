/* Baker utilities: arrays, messages, file and gzip input, paths (see bake.h). */
#include "bake.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>
#include <time.h>
#include <zlib.h>

#include "cli.h"

int hz_bake_verbose = 0;
int hz_bake_warnings = 0;

static void out_of_memory(size_t n)
{
    fprintf(stderr, "%s: out of memory (a request for %zu bytes failed)\n", hz_cli_prog, n);
    exit(hz_status_exit_code(HZ_E_NO_MEMORY));
}

void *hz_bake_xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (!p)
        out_of_memory(n);
    return p;
}

void *hz_bake_xcalloc(size_t n, size_t size)
{
    if (size && n > SIZE_MAX / size)
        out_of_memory(SIZE_MAX);
    void *p = calloc(n ? n : 1, size ? size : 1);
    if (!p)
        out_of_memory(n * size);
    return p;
}

char *hz_bake_xstrdup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = hz_bake_xmalloc(n);
    memcpy(d, s, n);
    return d;
}

void hz_bake_vec_init(hz_bake_vec_t *v, size_t elem)
{
    v->data = NULL;
    v->len = v->cap = 0;
    v->elem = elem;
}

void *hz_bake_vec_push(hz_bake_vec_t *v, size_t n)
{
    if (n > SIZE_MAX / v->elem - v->len)
        out_of_memory(SIZE_MAX);
    if (v->len + n > v->cap) {
        size_t cap = v->cap ? v->cap : 16;
        while (cap < v->len + n)
            cap = cap > SIZE_MAX / 2 / v->elem ? v->len + n : cap * 2;
        void *p = realloc(v->data, cap * v->elem);
        if (!p)
            out_of_memory(cap * v->elem);
        v->data = p;
        v->cap = cap;
    }
    void *at = (char *)v->data + v->len * v->elem;
    memset(at, 0, n * v->elem);
    v->len += n;
    return at;
}

void hz_bake_vec_free(hz_bake_vec_t *v)
{
    free(v->data);
    v->data = NULL;
    v->len = v->cap = 0;
}

void hz_bake_warn(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s: warning: ", hz_cli_prog);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    hz_bake_warnings++;
}

void hz_bake_progress(const char *fmt, ...)
{
    if (!hz_bake_verbose)
        return;
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s: ", hz_cli_prog);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

int hz_bake_phase_fd = -1;

void hz_bake_phase(const char *fmt, ...)
{
    if (hz_bake_phase_fd < 0)
        return;
    char line[256];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(line, sizeof line - 1, fmt, ap);
    va_end(ap);
    if (n < 0)
        return;
    if (n > (int)sizeof line - 2)
        n = (int)sizeof line - 2;
    for (int i = 0; i < n; i++)
        if (line[i] == '\n')
            line[i] = ' ';
    line[n++] = '\n';
    /* One short write: atomic on a pipe; a full pipe (the parent reads every 20 ms) just drops the line. */
    ssize_t w = write(hz_bake_phase_fd, line, (size_t)n);
    (void)w;
}

hz_status_t hz_bake_err(hz_error_t *err, hz_status_t code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        err->code = code;
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
    }
    return code;
}

const char *hz_bake_num(char *buf, size_t cap, double v)
{
    if (v != v)
        snprintf(buf, cap, "nan");
    else
        snprintf(buf, cap, "%g", v); /* inf and -inf as themselves */
    return buf;
}

double hz_bake_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static struct stat guard_st;
static int guard_set;
static char guard_out[4096], clash[4096];

void hz_bake_guard_output(const char *out)
{
    guard_set = stat(out, &guard_st) == 0;
    hz_bake_strcpy(guard_out, sizeof guard_out, out);
    clash[0] = 0;
}

int hz_bake_input_ok(const char *path)
{
    struct stat st;
    if (!guard_set || stat(path, &st) != 0 || st.st_dev != guard_st.st_dev || st.st_ino != guard_st.st_ino)
        return 1;
    if (!clash[0])
        hz_bake_strcpy(clash, sizeof clash, path);
    return 0;
}

const char *hz_bake_input_clash(void)
{
    return clash;
}

static hz_status_t clash_error(const char *path, hz_error_t *err)
{
    return hz_bake_err(err, HZ_E_INVALID_ARG, "%s is the output %s too: baking would replace one of its own inputs; "
                       "choose another output path", path, guard_out);
}

hz_status_t hz_bake_read_file(const char *path, uint8_t **data, size_t *size, hz_error_t *err)
{
    *data = NULL;
    *size = 0;
    if (!hz_bake_input_ok(path))
        return clash_error(path, err);
    /* O_NONBLOCK: a FIFO named as an input must not wait for a writer (it is refused below) */
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    if (fd < 0)
        return hz_bake_err(err, HZ_E_IO, "%s: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return hz_bake_err(err, HZ_E_IO, "%s: not a regular file", path);
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        close(fd);
        return hz_bake_err(err, HZ_E_IO, "%s: %s", path, strerror(errno));
    }
    size_t n = (size_t)st.st_size;
    uint8_t *buf = hz_bake_xmalloc(n + 1);
    size_t got = n ? fread(buf, 1, n, f) : 0;
    int bad = ferror(f);
    fclose(f);
    if (got != n || bad) {
        free(buf);
        return hz_bake_err(err, HZ_E_IO, "%s: read failed after %zu of %zu bytes", path, got, n);
    }
    buf[n] = 0;
    *data = buf;
    *size = n;
    return HZ_OK;
}

hz_status_t hz_bake_read_gzip(const char *path, uint8_t **data, size_t *size, hz_error_t *err)
{
    *data = NULL;
    *size = 0;
    if (!hz_bake_file_exists(path))
        return hz_bake_err(err, HZ_E_IO, "%s: %s", path, strerror(ENOENT));
    if (!hz_bake_input_ok(path))
        return clash_error(path, err);
    gzFile g = gzopen(path, "rb");
    if (!g)
        return hz_bake_err(err, HZ_E_IO, "%s: %s", path, strerror(errno ? errno : ENOMEM));
    gzbuffer(g, 1 << 17);
    hz_bake_vec_t buf;
    hz_bake_vec_init(&buf, 1);
    for (;;) {
        size_t at = buf.len;
        hz_bake_vec_push(&buf, 1 << 20);
        int r = gzread(g, (char *)buf.data + at, 1 << 20);
        if (r < 0) {
            int code;
            const char *msg = gzerror(g, &code);
            hz_status_t s = hz_bake_err(err, code == Z_ERRNO ? HZ_E_IO : HZ_E_FORMAT, "%s: corrupt gzip stream: %s",
                                        path, code == Z_ERRNO ? strerror(errno) : msg);
            gzclose(g);
            hz_bake_vec_free(&buf);
            return s;
        }
        buf.len = at + (size_t)r;
        if (r < (1 << 20))
            break;
    }
    /* gzread reports a stream that ends early (truncated file) only through gzerror. */
    int code;
    const char *msg = gzerror(g, &code);
    if (code != Z_OK && code != Z_STREAM_END) {
        hz_status_t s = hz_bake_err(err, HZ_E_FORMAT, "%s: truncated or corrupt gzip stream: %s", path, msg);
        gzclose(g);
        hz_bake_vec_free(&buf);
        return s;
    }
    if (gzclose(g) != Z_OK) {
        hz_bake_vec_free(&buf);
        return hz_bake_err(err, HZ_E_FORMAT, "%s: truncated or corrupt gzip stream", path);
    }
    *(uint8_t *)hz_bake_vec_push(&buf, 1) = 0; /* NUL for text formats, not counted */
    *data = buf.data;
    *size = buf.len - 1;
    return HZ_OK;
}

int hz_bake_file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

int hz_bake_ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    if (m > n)
        return 0;
    for (size_t i = 0; i < m; i++)
        if (tolower((unsigned char)s[n - m + i]) != tolower((unsigned char)suffix[i]))
            return 0;
    return 1;
}

void hz_bake_dirname(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (!slash) {
        snprintf(out, size, ".");
        return;
    }
    size_t n = (size_t)(slash - path);
    if (n == 0)
        n = 1; /* "/file" */
    snprintf(out, size, "%.*s", (int)n, path);
}

const char *hz_bake_basename(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

static int ieq(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b))
            return 0;
    return *a == *b;
}

int hz_bake_resolve(const char *dir, const char *ref, char *out, size_t size)
{
    char rel[4096];
    snprintf(rel, sizeof rel, "%s", ref);
    for (char *p = rel; *p; p++)
        if (*p == '\\')
            *p = '/';
    /* Some exporters write "./name" or surround names with spaces. */
    char *r = rel;
    while (*r == ' ')
        r++;
    size_t n = strlen(r);
    while (n && (r[n - 1] == ' ' || r[n - 1] == '\r'))
        r[--n] = 0;
    if (!*r)
        return 0;
    if (r[0] == '/')
        snprintf(out, size, "%s", r);
    else if ((size_t)snprintf(out, size, "%s/%s", dir, r) >= size)
        return 0;
    if (hz_bake_file_exists(out))
        return 1;
    /* Case-insensitive match of the last component in its directory. */
    char parent[4096];
    hz_bake_dirname(out, parent, sizeof parent);
    const char *base = hz_bake_basename(out);
    char want[1024];
    snprintf(want, sizeof want, "%s", base);
    DIR *d = opendir(parent);
    if (!d)
        return 0;
    struct dirent *e;
    int found = 0;
    while ((e = readdir(d)) != NULL) {
        if (ieq(e->d_name, want)) {
            if ((size_t)snprintf(out, size, "%s/%s", parent, e->d_name) < size && hz_bake_file_exists(out))
                found = 1;
            break;
        }
    }
    closedir(d);
    return found;
}

void hz_bake_strcpy(char *dst, size_t size, const char *src)
{
    if (!size)
        return;
    size_t n = strlen(src);
    if (n >= size)
        n = size - 1;
    memcpy(dst, src, n);
    dst[n] = 0;
}

void hz_bake_set_name(uint8_t dst[HZ_HZB_NAME_BYTES], const char *name)
{
    memset(dst, 0, HZ_HZB_NAME_BYTES);
    size_t n = strlen(name);
    if (n > HZ_HZB_NAME_BYTES - 1) {
        n = HZ_HZB_NAME_BYTES - 1;
        while (n > 0 && ((unsigned char)name[n] & 0xc0) == 0x80)
            n--; /* do not cut a UTF-8 sequence */
    }
    memcpy(dst, name, n);
}
