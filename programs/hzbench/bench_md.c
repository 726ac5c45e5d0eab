/* hzbench's Markdown tables from its CSVs (see bench_md.h). */
#include "bench_md.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

typedef struct csv {
    char *text;     /* the file, fields unquoted in place and NUL-terminated */
    char ***rows;   /* rows[0] is the header */
    size_t nrows, ncols;
} csv_t;

static void csv_free(csv_t *c)
{
    for (size_t i = 0; i < c->nrows; i++)
        free(c->rows[i]);
    free(c->rows);
    free(c->text);
    memset(c, 0, sizeof *c);
}

static char *read_all(const char *path, hz_error_t *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        hz_error_set(err, HZ_E_IO, "%s: %s", path, strerror(errno));
        return NULL;
    }
    size_t size = 0, cap = 4096;
    char *buf = malloc(cap);
    for (size_t n; buf && (n = fread(buf + size, 1, cap - size - 1, f)) > 0;) {
        size += n;
        if (cap - size - 1 == 0) {
            char *b = realloc(buf, cap * 2);
            if (!b)
                free(buf);
            buf = b, cap *= 2;
        }
    }
    int bad = ferror(f);
    fclose(f);
    if (!buf || bad) {
        free(buf);
        hz_error_set(err, buf ? HZ_E_IO : HZ_E_NO_MEMORY, "%s: %s", path, buf ? "read error" : "no memory");
        return NULL;
    }
    buf[size] = '\0';
    return buf;
}

/* Splits the text into rows of fields in place: quotes removed, "" made ", fields NUL-terminated. */
static hz_status_t parse(csv_t *c, const char *path, hz_error_t *err)
{
    char *r = c->text, *w = c->text;
    size_t cap_rows = 0;
    while (*r) {
        if (*r == '\n' || (*r == '\r' && r[1] == '\n')) { /* a blank line */
            r += *r == '\r' ? 2 : 1;
            continue;
        }
        size_t cap = 8, n = 0;
        char **fields = malloc(cap * sizeof *fields);
        if (!fields)
            return hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory", path);
        for (;;) {
            if (n == cap) {
                char **g = realloc(fields, 2 * cap * sizeof *fields);
                if (!g) {
                    free(fields);
                    return hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory", path);
                }
                fields = g, cap *= 2;
            }
            fields[n++] = w;
            if (*r == '"') {
                for (r++; *r && !(*r == '"' && r[1] != '"'); r++) {
                    if (*r == '"')
                        r++;
                    *w++ = *r;
                }
                if (*r == '"')
                    r++;
            }
            while (*r && *r != ',' && *r != '\n' && *r != '\r')
                *w++ = *r++;
            char end = *r;
            *w++ = '\0';
            if (end == ',') {
                r++;
                continue;
            }
            r += end == '\r' ? (r[1] == '\n' ? 2 : 1) : end == '\n' ? 1 : 0;
            break;
        }
        if (c->nrows == 0)
            c->ncols = n;
        else if (n > c->ncols) {
            free(fields);
            return hz_error_set(err, HZ_E_FORMAT, "%s: row %zu has %zu fields, the header %zu", path, c->nrows + 1, n,
                                c->ncols);
        }
        if (n < c->ncols) { /* a short row: the missing fields are empty */
            char **g = cap < c->ncols ? realloc(fields, c->ncols * sizeof *fields) : fields;
            if (!g) {
                free(fields);
                return hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory", path);
            }
            fields = g;
            for (; n < c->ncols; n++)
                fields[n] = w - 1; /* the NUL that ends the row's last field */
        }
        if (c->nrows == cap_rows) {
            size_t nc = cap_rows ? 2 * cap_rows : 64;
            char ***g = realloc(c->rows, nc * sizeof *g);
            if (!g) {
                free(fields);
                return hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory", path);
            }
            c->rows = g, cap_rows = nc;
        }
        c->rows[c->nrows++] = fields;
    }
    if (c->nrows == 0)
        return hz_error_set(err, HZ_E_FORMAT, "%s: empty (no header line)", path);
    return HZ_OK;
}

static int column(const csv_t *c, const char *name)
{
    for (size_t k = 0; k < c->ncols; k++)
        if (!strcmp(c->rows[0][k], name))
            return (int)k;
    return -1;
}

static bool is_number(const char *s)
{
    if (!strcmp(s, "nan") || !strcmp(s, "inf") || !strcmp(s, "-inf"))
        return true;
    char *end;
    errno = 0;
    strtod(s, &end);
    return end != s && *end == '\0';
}

void hz_bench_md_cell(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '|')
            fputc('\\', f);
        fputc(*s, f);
    }
}

/* One Markdown table: head[ncols], cells[nrows][ncols] (NULL = empty). */
static void table(FILE *f, const char *const *head, const char *const *cells, size_t nrows, size_t ncols)
{
    fputs("|", f);
    for (size_t k = 0; k < ncols; k++) {
        fputc(' ', f);
        hz_bench_md_cell(f, head[k]);
        fputs(" |", f);
    }
    fputs("\n|", f);
    for (size_t k = 0; k < ncols; k++) {
        bool num = false, other = false;
        for (size_t i = 0; i < nrows; i++) {
            const char *s = cells[i * ncols + k];
            if (s && *s)
                *(is_number(s) ? &num : &other) = true;
        }
        fputs(num && !other ? "---:|" : "---|", f);
    }
    fputc('\n', f);
    for (size_t i = 0; i < nrows; i++) {
        fputs("|", f);
        for (size_t k = 0; k < ncols; k++) {
            fputc(' ', f);
            if (cells[i * ncols + k])
                hz_bench_md_cell(f, cells[i * ncols + k]);
            fputs(" |", f);
        }
        fputc('\n', f);
    }
}

static bool kept(const csv_t *c, size_t row, int where, const hz_bench_md_spec_t *spec)
{
    if (where < 0)
        return true;
    bool in = false;
    for (const char *const *v = spec->in; v && *v; v++)
        if (!strcmp(c->rows[row][where], *v))
            in = true;
    return in != spec->not_in;
}

static hz_status_t render(FILE *f, const csv_t *c, const char *path, const hz_bench_md_spec_t *spec, hz_error_t *err)
{
    int where = -1;
    if (spec && spec->where && (where = column(c, spec->where)) < 0)
        return hz_error_set(err, HZ_E_FORMAT, "%s: no column '%s'", path, spec->where);
    size_t n = 0;
    for (size_t i = 1; i < c->nrows; i++)
        n += kept(c, i, where, spec);
    if (n == 0) {
        fprintf(f, "(no rows in %s)\n", path);
        return HZ_OK;
    }
    if (!spec || !spec->keys) {
        const char **cells = malloc(n * c->ncols * sizeof *cells);
        if (!cells)
            return hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory", path);
        size_t r = 0;
        for (size_t i = 1; i < c->nrows; i++)
            if (kept(c, i, where, spec))
                memcpy(&cells[r++ * c->ncols], c->rows[i], c->ncols * sizeof *cells);
        table(f, (const char *const *)c->rows[0], cells, n, c->ncols);
        free(cells);
        return HZ_OK;
    }
    /* Pivot: key columns, then one column per value of `across`. */
    size_t nkeys = 0;
    int kcol[16];
    for (; spec->keys[nkeys]; nkeys++) {
        if (nkeys == 16 || (kcol[nkeys] = column(c, spec->keys[nkeys])) < 0)
            return hz_error_set(err, HZ_E_FORMAT, "%s: no column '%s'", path, spec->keys[nkeys]);
    }
    int acol = column(c, spec->across), vcol = column(c, spec->value);
    if (acol < 0 || vcol < 0)
        return hz_error_set(err, HZ_E_FORMAT, "%s: no column '%s'", path, acol < 0 ? spec->across : spec->value);
    const char **across = malloc(n * sizeof *across);
    size_t *keyrow = malloc(n * sizeof *keyrow); /* the CSV row first showing each distinct key */
    size_t na = 0, nk = 0;
    if (!across || !keyrow) {
        free(across), free(keyrow);
        return hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory", path);
    }
    for (size_t i = 1; i < c->nrows; i++) {
        if (!kept(c, i, where, spec))
            continue;
        size_t a = 0;
        while (a < na && strcmp(across[a], c->rows[i][acol]))
            a++;
        if (a == na)
            across[na++] = c->rows[i][acol];
        size_t k = 0;
        for (; k < nk; k++) {
            size_t q = 0;
            while (q < nkeys && !strcmp(c->rows[keyrow[k]][kcol[q]], c->rows[i][kcol[q]]))
                q++;
            if (q == nkeys)
                break;
        }
        if (k == nk)
            keyrow[nk++] = i;
    }
    size_t ncols = nkeys + na;
    const char **head = malloc(ncols * sizeof *head), **cells = calloc(nk * ncols, sizeof *cells);
    if (!head || !cells) {
        free(across), free(keyrow), free(head), free(cells);
        return hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory", path);
    }
    for (size_t q = 0; q < nkeys; q++)
        head[q] = spec->keys[q];
    for (size_t a = 0; a < na; a++)
        head[nkeys + a] = across[a];
    for (size_t k = 0; k < nk; k++)
        for (size_t q = 0; q < nkeys; q++)
            cells[k * ncols + q] = c->rows[keyrow[k]][kcol[q]];
    for (size_t i = 1; i < c->nrows; i++) {
        if (!kept(c, i, where, spec))
            continue;
        for (size_t k = 0; k < nk; k++) {
            size_t q = 0;
            while (q < nkeys && !strcmp(c->rows[keyrow[k]][kcol[q]], c->rows[i][kcol[q]]))
                q++;
            if (q < nkeys)
                continue;
            for (size_t a = 0; a < na; a++)
                if (!strcmp(across[a], c->rows[i][acol]))
                    cells[k * ncols + nkeys + a] = c->rows[i][vcol];
            break;
        }
    }
    table(f, head, cells, nk, ncols);
    free(across), free(keyrow), free(head), free(cells);
    return HZ_OK;
}

hz_status_t hz_bench_md_csv(FILE *f, const char *path, const hz_bench_md_spec_t *spec, hz_error_t *err)
{
    csv_t c;
    memset(&c, 0, sizeof c);
    if (!(c.text = read_all(path, err)))
        return err ? err->code : HZ_E_IO;
    hz_status_t s = parse(&c, path, err);
    if (s == HZ_OK)
        s = render(f, &c, path, spec, err);
    csv_free(&c);
    return s;
}
