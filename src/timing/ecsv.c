/* CSV of edge timestamps (see hz/traceio.h). */
#include "hz/traceio.h"

void hz_ecsv_init(hz_ecsv_t *p)
{
    hz_ecsv_t zero = { 0 };
    *p = zero;
    p->level_col = -1;
}

static int is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r';
}

/* Trims field [b, e) in place; returns its start and sets *len. */
static char *trim(char *b, char *e, size_t *len)
{
    while (b < e && is_space(*b))
        b++;
    while (e > b && is_space(e[-1]))
        e--;
    *len = (size_t)(e - b);
    return b;
}

static int field_is(const char *f, size_t n, const char *name)
{
    size_t i = 0;
    for (; i < n && name[i]; i++) {
        char c = f[i];
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if (c != name[i])
            return 0;
    }
    return i == n && !name[i];
}

/* Decimal with up to `frac` fraction digits, scaled by 10^frac to an integer; false if malformed or
 * negative or too large. */
static int parse_time(const char *f, size_t n, int frac, int64_t *out)
{
    uint64_t v = 0;
    size_t i = 0;
    int digits = 0, fd = -1;
    if (n == 0)
        return 0;
    for (; i < n; i++) {
        char c = f[i];
        if (c == '.' && frac > 0 && fd < 0) {
            fd = 0;
            continue;
        }
        if (c < '0' || c > '9')
            return 0;
        if (fd >= 0 && ++fd > frac)
            return 0;
        uint64_t d = (uint64_t)(c - '0');
        if (v > ((uint64_t)INT64_MAX - d) / 10) /* exact: INT64_MAX itself is a valid time */
            return 0;
        v = v * 10 + d;
        digits++;
    }
    if (!digits)
        return 0;
    for (int k = fd < 0 ? 0 : fd; k < frac; k++) {
        if (v > (uint64_t)INT64_MAX / 10)
            return 0;
        v *= 10;
    }
    *out = (int64_t)v;
    return 1;
}

#define MAX_FIELDS 32

static hz_status_t line(hz_ecsv_t *p, hz_edge_fn edge, void *ctx, hz_error_t *err)
{
    p->line_no++;
    if (p->too_long)
        return hz_error_set(err, HZ_E_FORMAT, "line %llu: longer than %u characters",
                            (unsigned long long)p->line_no, (unsigned)HZ_ECSV_LINE_MAX);
    char *s = p->line, *end = p->line + p->len;
    /* A UTF-8 byte-order mark, as spreadsheets write one, is not part of the first line. */
    if (p->line_no == 1 && p->len >= 3 && (unsigned char)s[0] == 0xef && (unsigned char)s[1] == 0xbb &&
        (unsigned char)s[2] == 0xbf)
        s += 3;
    size_t n;
    char *all = trim(s, end, &n);
    if (n == 0 || all[0] == '#')
        return HZ_OK;
    char *fb[MAX_FIELDS];
    size_t fl[MAX_FIELDS];
    int nf = 0;
    char *b = s;
    for (char *c = s;; c++) {
        if (c == end || *c == ',') {
            if (nf < MAX_FIELDS) {
                fb[nf] = trim(b, c, &fl[nf]);
                nf++;
            }
            if (c == end)
                break;
            b = c + 1;
        }
    }
    if (!p->header_done) {
        p->header_done = 1;
        int named = 0;
        for (size_t i = 0; i < fl[0]; i++)
            if ((fb[0][i] >= 'a' && fb[0][i] <= 'z') || (fb[0][i] >= 'A' && fb[0][i] <= 'Z'))
                named = 1;
        if (named) {
            p->t_col = -1;
            for (int i = 0; i < nf; i++) {
                if (field_is(fb[i], fl[i], "t_ns") && p->t_col < 0) {
                    p->t_col = i;
                    p->t_unit_digits = 0;
                } else if (field_is(fb[i], fl[i], "t_us") && p->t_col < 0) {
                    p->t_col = i;
                    p->t_unit_digits = 3;
                } else if (field_is(fb[i], fl[i], "t_s") && p->t_col < 0) {
                    p->t_col = i;
                    p->t_unit_digits = 9;
                } else if (field_is(fb[i], fl[i], "level") && p->level_col < 0) {
                    p->level_col = i;
                }
            }
            if (p->t_col < 0)
                return hz_error_set(err, HZ_E_FORMAT, "line %llu: the header names no time column (t_ns, t_us or t_s)",
                                    (unsigned long long)p->line_no);
            return HZ_OK;
        }
        p->t_col = 0;
        p->level_col = nf >= 2 ? 1 : -1;
    }
    if (p->t_col >= nf || (p->level_col >= 0 && p->level_col >= nf))
        return hz_error_set(err, HZ_E_FORMAT, "line %llu: %d field%s, the %s column is missing",
                            (unsigned long long)p->line_no, nf, nf == 1 ? "" : "s",
                            p->t_col >= nf ? "time" : "level");
    int64_t t;
    if (!parse_time(fb[p->t_col], fl[p->t_col], p->t_unit_digits, &t)) {
        /* the field as given, bytes that do not print (or are not ASCII) as \xNN: an invisible one is the usual
         * culprit */
        static const char hex[] = "0123456789abcdef";
        char shown[64];
        size_t k = 0;
        for (size_t i = 0; i < fl[p->t_col] && k + 5 < sizeof shown; i++) {
            unsigned char c = (unsigned char)fb[p->t_col][i];
            if (c >= 0x20 && c < 0x7f) {
                shown[k++] = (char)c;
            } else {
                shown[k++] = '\\', shown[k++] = 'x', shown[k++] = hex[c >> 4], shown[k++] = hex[c & 15];
            }
        }
        shown[k] = '\0';
        return hz_error_set(err, HZ_E_FORMAT, "line %llu: time '%s' is not a non-negative number%s",
                            (unsigned long long)p->line_no, shown,
                            p->t_unit_digits ? " (with at most the unit's decimals) below 2^63 ns" : " of nanoseconds below 2^63");
    }
    int level = 1;
    if (p->level_col >= 0) {
        const char *f = fb[p->level_col];
        if (fl[p->level_col] != 1 || (f[0] != '0' && f[0] != '1'))
            return hz_error_set(err, HZ_E_FORMAT, "line %llu: level must be 0 or 1", (unsigned long long)p->line_no);
        level = f[0] - '0';
    }
    if (p->have_last && t < p->last_t)
        return hz_error_set(err, HZ_E_FORMAT, "line %llu: time %lld ns goes backwards (previous %lld ns)",
                            (unsigned long long)p->line_no, (long long)t, (long long)p->last_t);
    p->last_t = t;
    p->have_last = 1;
    p->rows++;
    return edge(ctx, t, level, err);
}

hz_status_t hz_ecsv_feed(hz_ecsv_t *p, const char *data, size_t n, hz_edge_fn edge, void *ctx, hz_error_t *err)
{
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)data[i];
        if (c == '\n') {
            hz_status_t s = line(p, edge, ctx, err);
            p->len = 0;
            p->too_long = 0;
            if (s != HZ_OK)
                return s;
            continue;
        }
        if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7f)
            return hz_error_set(err, HZ_E_FORMAT, "line %llu: byte 0x%02x is not CSV text",
                                (unsigned long long)p->line_no + 1, c);
        if (p->len < HZ_ECSV_LINE_MAX)
            p->line[p->len++] = (char)c;
        else
            p->too_long = 1;
    }
    return HZ_OK;
}

hz_status_t hz_ecsv_finish(hz_ecsv_t *p, hz_edge_fn edge, void *ctx, hz_error_t *err)
{
    if (p->len == 0 && !p->too_long)
        return HZ_OK;
    hz_status_t s = line(p, edge, ctx, err);
    p->len = 0;
    p->too_long = 0;
    return s;
}
