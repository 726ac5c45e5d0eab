/* Options from tables: values, a program's command line, help (see opttab.h). */
#include "opttab.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

const hz_opt_t *hz_opt_find(const hz_opt_t *t, size_t n, const char *name)
{
    for (size_t k = 0; k < n; k++)
        if (!strcmp(name, t[k].name) || (t[k].alias && !strcmp(name, t[k].alias)))
            return &t[k];
    return NULL;
}

/* 1000 as "1000", 0.5 as "0.5", 1e9 as "1000000000": limits as people write them. */
static const char *num_str(char *buf, size_t cap, double v)
{
    if (v == floor(v) && fabs(v) < 1e15)
        snprintf(buf, cap, "%.0f", v);
    else
        snprintf(buf, cap, "%g", v);
    return buf;
}

static void words_list(char *buf, size_t cap, const char *const *words)
{
    size_t n = 0;
    buf[0] = 0;
    for (int k = 0; words[k] && n < cap; k++)
        n += (size_t)snprintf(buf + n, cap - n, "%s%s", k ? (words[k + 1] ? ", " : " or ") : "", words[k]);
}

bool hz_opt_value(const hz_opt_t *o, const char *cmd_name, const char *v, hz_opt_val_t *out)
{
    memset(out, 0, sizeof *out);
    out->s = v;
    /* "render: --spp" in hzrt's commands, "--frames" in a program of its own */
    char cmd[64];
    snprintf(cmd, sizeof cmd, "%s%s%s", cmd_name ? cmd_name : "", cmd_name ? ": " : "", o->name);
    char lo[32], hi[32];
    num_str(lo, sizeof lo, o->lo);
    num_str(hi, sizeof hi, o->hi);
    switch (o->kind) {
    case HZ_OPT_FLAG:
        return true;
    case HZ_OPT_INT: {
        char *end = NULL;
        errno = 0;
        long n = strtol(v, &end, 10);
        if (!*v || *end || errno) {
            hz_cli_error("%s: '%s' is not an integer in [%s, %s]", cmd, v, lo, hi);
            return false;
        }
        if (n < (long)o->lo || n > (long)o->hi) {
            hz_cli_error("%s: %ld is outside [%s, %s]", cmd, n, lo, hi);
            return false;
        }
        out->n = n;
        return true;
    }
    case HZ_OPT_REAL: {
        char *end = NULL;
        errno = 0;
        double x = strtod(v, &end);
        if (!*v || *end || errno || !isfinite(x) || (o->lo_open ? !(x > o->lo) : !(x >= o->lo)) || !(x <= o->hi)) {
            hz_cli_error("%s: '%s' is not %s in %c%s, %s]", cmd, v, o->noun ? o->noun : "a number",
                         o->lo_open ? '(' : '[', lo, hi);
            return false;
        }
        out->x = x;
        return true;
    }
    case HZ_OPT_SIZE:
        return hz_cli_parse_size(cmd, v, (int)o->lo, (int)o->hi, &out->w, &out->h);
    case HZ_OPT_WORD:
        for (int k = 0; o->words[k]; k++)
            if (!strcmp(o->words[k], v)) {
                out->w = k;
                return true;
            }
        {
            char list[256];
            words_list(list, sizeof list, o->words);
            hz_cli_error("%s: '%s' is not %s", cmd, v, list);
        }
        return false;
    case HZ_OPT_TEXT:
        if (!*v) {
            hz_cli_error("%s: empty value (%s)", cmd, o->arg);
            return false;
        }
        return true;
    }
    return false;
}

/* ---- a program's command line ---- */

int hz_opt_parse(const hz_opt_prog_t *p, int argc, char **argv, hz_opt_take_fn take, void *ctx, const char **ops,
                 int *nops)
{
    *nops = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (a[0] != '-' || !a[1]) {
            if (*nops >= p->max_operands) {
                hz_cli_error("unexpected argument '%s' (try %s --help)", a, p->name);
                return HZ_EXIT_USAGE;
            }
            ops[(*nops)++] = a;
            continue;
        }
        const hz_opt_t *o = hz_opt_find(p->table, p->n, a);
        if (!o) {
            hz_cli_error("unknown option '%s' (try %s --help)", a, p->name);
            return HZ_EXIT_USAGE;
        }
        if (o->id == HZ_OPT_ID_HELP) {
            hz_opt_help(stdout, p);
            return HZ_OPT_DONE;
        }
        const char *v = NULL;
        if (o->arg) {
            if (i + 1 >= argc) {
                hz_cli_error("%s needs a value %s (try %s --help)", a, o->arg, p->name);
                return HZ_EXIT_USAGE;
            }
            v = argv[++i];
        }
        hz_opt_val_t x;
        if (!hz_opt_value(o, NULL, v, &x))
            return HZ_EXIT_USAGE;
        int rc = take(ctx, o, &x);
        if (rc)
            return rc;
    }
    return 0;
}

/* ---- help ---- */

#define HELP_COL 24 /* hzrt's commands */
#define HELP_COL_MAX 34
#define HELP_WIDTH 116

void hz_opt_print_entry(FILE *f, const hz_opt_t *o, const char *note, bool wide, int col0)
{
    char head[64], lim[96] = "", lo[32], hi[32];
    snprintf(head, sizeof head, "%s%s%s%s%s", o->alias ? o->alias : wide ? "    " : "", o->alias ? ", " : "",
             o->name, o->arg ? " " : "", o->arg ? o->arg : "");
    num_str(lo, sizeof lo, o->lo);
    num_str(hi, sizeof hi, o->hi);
    if (o->kind == HZ_OPT_INT || o->kind == HZ_OPT_REAL)
        snprintf(lim, sizeof lim, " %c%s..%s]", o->lo_open ? '(' : '[', lo, hi);
    else if (o->kind == HZ_OPT_SIZE)
        snprintf(lim, sizeof lim, " [%s..%s a side]", lo, hi);
    char text[2048];
    snprintf(text, sizeof text, "%s%s%s%s%s", o->help, lim, note && note[0] ? " (only " : "", note ? note : "",
             note && note[0] ? ")" : "");
    /* wrapped under the option */
    int col = col0;
    if ((int)strlen(head) + 2 < col0 - 1)
        fprintf(f, "  %-*s", col0 - 2, head);
    else
        fprintf(f, "  %s\n%*s", head, col0, "");
    int first = 1;
    for (char *word = strtok(text, " "); word; word = strtok(NULL, " ")) {
        int len = (int)strlen(word);
        if (!first && col + 1 + len > HELP_WIDTH) {
            fprintf(f, "\n%*s", col0, "");
            col = col0;
            first = 1;
        }
        fprintf(f, "%s%s", first ? "" : " ", word);
        col += len + !first;
        first = 0;
    }
    fputc('\n', f);
}

void hz_opt_help(FILE *f, const hz_opt_prog_t *p)
{
    bool wide = false;
    for (size_t k = 0; k < p->n; k++)
        wide |= p->table[k].alias != NULL;
    /* the help column after the longest option (up to HELP_COL_MAX; longer ones get a line of their own) */
    int col = HELP_COL;
    for (size_t k = 0; k < p->n; k++) {
        const hz_opt_t *o = &p->table[k];
        int len = 2 + (wide ? 4 : 0) + (int)strlen(o->name) + (o->arg ? 1 + (int)strlen(o->arg) : 0) + 3;
        if (len > col)
            col = len < HELP_COL_MAX ? len : HELP_COL_MAX;
    }
    fputs(p->synopsis, f);
    for (size_t k = 0; k < p->n; k++) {
        if (p->table[k].section)
            fprintf(f, "%s:\n", p->table[k].section);
        hz_opt_print_entry(f, &p->table[k], NULL, wide, col);
    }
    if (p->epilogue)
        fputs(p->epilogue, f);
}
