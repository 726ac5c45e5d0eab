/* Options from tables: values, applicability, help (see opttab.h). */
#include "opttab.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "hz/render.h"

const hz_opt_t *hz_opt_find(const hz_opt_t *t, size_t n, const char *name)
{
    for (size_t k = 0; k < n; k++)
        if (!strcmp(name, t[k].name))
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

bool hz_opt_value(const hz_opt_t *o, const char *cmd, const char *v, hz_opt_val_t *out)
{
    memset(out, 0, sizeof *out);
    out->s = v;
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
            hz_cli_error("%s: %s: '%s' is not an integer in [%s, %s]", cmd, o->name, v, lo, hi);
            return false;
        }
        if (n < (long)o->lo || n > (long)o->hi) {
            hz_cli_error("%s: %s: %ld is outside [%s, %s]", cmd, o->name, n, lo, hi);
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
            hz_cli_error("%s: %s: '%s' is not %s in %c%s, %s]", cmd, o->name, v, o->noun ? o->noun : "a number",
                         o->lo_open ? '(' : '[', lo, hi);
            return false;
        }
        out->x = x;
        return true;
    }
    case HZ_OPT_SIZE: {
        char opt[64];
        snprintf(opt, sizeof opt, "%s: %s", cmd, o->name);
        return hz_cli_parse_size(opt, v, (int)o->lo, (int)o->hi, &out->w, &out->h);
    }
    case HZ_OPT_WORD:
        for (int k = 0; o->words[k]; k++)
            if (!strcmp(o->words[k], v)) {
                out->w = k;
                return true;
            }
        {
            char list[256];
            words_list(list, sizeof list, o->words);
            hz_cli_error("%s: %s: '%s' is not %s", cmd, o->name, v, list);
        }
        return false;
    case HZ_OPT_TEXT:
        if (!*v) {
            hz_cli_error("%s: %s: empty value (%s)", cmd, o->name, o->arg);
            return false;
        }
        return true;
    }
    return false;
}

/* ---- applicability ---- */

typedef struct group {
    unsigned mask;
    const char *prefix; /* "with --source " */
    struct { unsigned bit; const char *name; } v[8];
} group_t;

static const group_t groups[] = {
    { HZ_OW_SOURCES, "with --source ",
      { { HZ_OW_OFFLINE, "offline" }, { HZ_OW_SIM, "sim" }, { HZ_OW_GPIO, "gpio" }, { HZ_OW_FBDEV_SRC, "fbdev" },
        { HZ_OW_DRM_SRC, "drm" }, { HZ_OW_V4L2_SRC, "v4l2" }, { HZ_OW_VCD, "vcd:FILE" }, { HZ_OW_CSV, "csv:FILE" } } },
    { HZ_OW_SINKS, "with --sink ",
      { { HZ_OW_FILES, "files" }, { HZ_OW_NONE, "none" }, { HZ_OW_DRM, "drm" }, { HZ_OW_FBDEV, "fbdev" },
        { HZ_OW_V4L2, "v4l2" } } },
    { HZ_OW_WHAT, "with ",
      { { HZ_OW_PATTERN, "the test pattern" }, { HZ_OW_SCENE, "a scene (--render scene)" },
        { HZ_OW_EDGES, "edges only (--edges-only)" } } },
    { HZ_OW_CLOCK, "",
      { { HZ_OW_REAL, "in real time" }, { HZ_OW_VIRTUAL, "with --virtual" } } },
};

/* The names of the bits of `bits` in group g: "--source sim or vcd:FILE". */
static const char *group_str(char *buf, size_t cap, const group_t *g, unsigned bits)
{
    if (g->mask == HZ_OW_SOURCES && bits == HZ_OW_DISPLAY_SOURCES) {
        snprintf(buf, cap, "with a display's v-sync (any --source but offline)");
        return buf;
    }
    if (g->mask == HZ_OW_WHAT && bits == HZ_OW_FRAMES) {
        snprintf(buf, cap, "with frames (not --edges-only)");
        return buf;
    }
    size_t n = (size_t)snprintf(buf, cap, "%s", g->prefix);
    int count = 0, total = 0;
    for (int k = 0; k < 8 && g->v[k].bit; k++)
        total += (bits & g->v[k].bit) != 0;
    for (int k = 0; k < 8 && g->v[k].bit && n < cap; k++)
        if (bits & g->v[k].bit) {
            count++;
            n += (size_t)snprintf(buf + n, cap - n, "%s%s", count == 1 ? "" : count == total ? " or " : ", ",
                                  g->v[k].name);
        }
    return buf;
}

bool hz_opt_acts(const hz_opt_t *o, unsigned run)
{
    for (size_t k = 0; k < sizeof groups / sizeof groups[0]; k++) {
        unsigned m = o->where & groups[k].mask;
        if (m && !(m & run))
            return false;
    }
    return true;
}

int hz_opt_refuse_idle(const hz_opt_t *o, const char *cmd, unsigned run)
{
    for (size_t k = 0; k < sizeof groups / sizeof groups[0]; k++) {
        unsigned m = o->where & groups[k].mask;
        if (m && !(m & run)) {
            char here[160], there[256];
            hz_cli_error("%s: %s does nothing %s: it acts only %s", cmd, o->name,
                         group_str(here, sizeof here, &groups[k], run & groups[k].mask),
                         group_str(there, sizeof there, &groups[k], m));
            return HZ_EXIT_USAGE;
        }
    }
    return 0;
}

const char *hz_opt_modes_str(char *buf, size_t cap, unsigned modes)
{
    static const hz_render_mode_t order[] = { HZ_MODE_FULL, HZ_MODE_TAA, HZ_MODE_TDENSE, HZ_MODE_ADAPTIVE };
    size_t n = 0;
    int count = 0, total = 0;
    buf[0] = 0;
    for (size_t k = 0; k < 4; k++)
        total += (modes >> order[k]) & 1u;
    for (size_t k = 0; k < 4 && n < cap; k++)
        if ((modes >> order[k]) & 1u) {
            count++;
            n += (size_t)snprintf(buf + n, cap - n, "%s%s", count == 1 ? "" : count == total ? " or " : ", ",
                                  hz_render_mode_name(order[k]));
        }
    return buf;
}

/* ---- help ---- */

#define HELP_COL 24
#define HELP_WIDTH 116

void hz_opt_usage(FILE *f, const hz_opt_t *t, size_t n, unsigned cmd, unsigned fixed)
{
    for (size_t k = 0; k < n; k++) {
        const hz_opt_t *o = &t[k];
        if (o->cmds && !(o->cmds & cmd))
            continue;
        if (o->section)
            fprintf(f, "%s:\n", o->section);
        char head[48], lim[96] = "", lo[32], hi[32], only[320] = "";
        snprintf(head, sizeof head, "%s%s%s", o->name, o->arg ? " " : "", o->arg ? o->arg : "");
        num_str(lo, sizeof lo, o->lo);
        num_str(hi, sizeof hi, o->hi);
        if (o->kind == HZ_OPT_INT || o->kind == HZ_OPT_REAL)
            snprintf(lim, sizeof lim, " %c%s..%s]", o->lo_open ? '(' : '[', lo, hi);
        else if (o->kind == HZ_OPT_SIZE)
            snprintf(lim, sizeof lim, " [%s..%s a side]", lo, hi);
        size_t m = 0;
        if (o->modes && o->modes != (1u << HZ_MODE_COUNT) - 1u) {
            char modes[64];
            m += (size_t)snprintf(only, sizeof only, "in %s mode", hz_opt_modes_str(modes, sizeof modes, o->modes));
        }
        for (size_t g = 0; g < sizeof groups / sizeof groups[0] && m < sizeof only; g++) {
            unsigned bits = o->where & groups[g].mask;
            if (bits && !(groups[g].mask & fixed)) {
                char s[256];
                m += (size_t)snprintf(only + m, sizeof only - m, "%s%s", m ? "; " : "",
                                      group_str(s, sizeof s, &groups[g], bits));
            }
        }
        char text[2048];
        snprintf(text, sizeof text, "%s%s%s%s%s", o->help, lim, only[0] ? " (only " : "", only, only[0] ? ")" : "");
        /* wrapped under the option */
        int col;
        if ((int)strlen(head) + 2 < HELP_COL - 1) {
            fprintf(f, "  %-*s", HELP_COL - 2, head);
            col = HELP_COL;
        } else {
            fprintf(f, "  %s\n%*s", head, HELP_COL, "");
            col = HELP_COL;
        }
        int first = 1;
        for (char *word = strtok(text, " "); word; word = strtok(NULL, " ")) {
            int len = (int)strlen(word);
            if (!first && col + 1 + len > HELP_WIDTH) {
                fprintf(f, "\n%*s", HELP_COL, "");
                col = HELP_COL;
                first = 1;
            }
            fprintf(f, "%s%s", first ? "" : " ", word);
            col += len + !first;
            first = 0;
        }
        fputc('\n', f);
    }
}
