/* Where hzrt's options act: applicability, refusal, help (see optwhere.h). */
#include "optwhere.h"

#include <string.h>

#include "cli.h"
#include "hz/render.h"

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

void hz_opt_usage(FILE *f, const hz_opt_t *t, size_t n, unsigned cmd, unsigned fixed)
{
    for (size_t k = 0; k < n; k++) {
        const hz_opt_t *o = &t[k];
        if (o->cmds && !(o->cmds & cmd))
            continue;
        if (o->section)
            fprintf(f, "%s:\n", o->section);
        char only[320] = "";
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
        hz_opt_print_entry(f, o, only, false, 24);
    }
}
