/*
 * The option tables (renderopts.h, showopts.h) through the commands' entry points, walked entry by entry:
 *  - every option that changes the image is recorded in summary.json: two runs that differ only in it record
 *    different settings (and two runs that do not differ record the same);
 *  - every option is in its commands' --help, with its limits;
 *  - every option given where it does nothing (another mode, another source, sink or frames) is refused with
 *    status 2.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hz/status.h"
#include "latency.h"
#include "render_cmd.h"
#include "renderopts.h"
#include "showopts.h"

static char dir[64];

typedef struct args {
    const char *v[64];
    int n;
} args_t;

static void add(args_t *a, const char *s)
{
    assert_true(a->n < 63);
    a->v[a->n++] = s;
    a->v[a->n] = NULL;
}

/* Adds the space-separated words of s (kept in `store`, which must outlive the run). */
static void add_words(args_t *a, char *store, size_t cap, const char *s)
{
    if (!s)
        return;
    snprintf(store, cap, "%s", s);
    for (char *w = strtok(store, " "); w; w = strtok(NULL, " "))
        add(a, w);
}

static int run(int (*cmd)(int, char **), const args_t *a)
{
    fflush(stdout);
    return cmd(a->n, (char **)a->v);
}

/* Runs with stdout into a file; returns the status and the output (malloc'd). */
static int run_captured(int (*cmd)(int, char **), const args_t *a, char **text)
{
    char path[96];
    snprintf(path, sizeof path, "%s/stdout.txt", dir);
    fflush(stdout);
    int saved = dup(1);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    dup2(fileno(f), 1);
    int rc = run(cmd, a);
    fflush(stdout);
    dup2(saved, 1);
    close(saved);
    fclose(f);
    f = fopen(path, "r");
    assert_non_null(f);
    static char buf[1 << 18];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = 0;
    fclose(f);
    *text = strdup(buf);
    return rc;
}

/* summary.json's "settings" object as text (malloc'd). */
static char *settings_of(const char *out)
{
    char path[160];
    snprintf(path, sizeof path, "%s/summary.json", out);
    FILE *f = fopen(path, "r");
    if (!f)
        fail_msg("%s: no summary.json", out);
    static char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = 0;
    fclose(f);
    char *s = strstr(buf, "\"settings\": {");
    assert_non_null(s);
    char *e = strchr(s, '}'); /* no nested objects in it (lists are [..]) */
    assert_non_null(e);
    return strndup(s, (size_t)(e - s + 1));
}

static const char *mode_for(const hz_opt_t *t)
{
    if (!t->modes || (t->modes & (1u << HZ_MODE_TDENSE)))
        return NULL; /* the default mode */
    for (int m = 0; m < HZ_MODE_COUNT; m++)
        if (t->modes & (1u << m))
            return hz_render_mode_name((hz_render_mode_t)m);
    return NULL;
}

/* A run of `hzrt render builtin` with the base options, t's mode and needs, and (with_opt) t itself. */
static int render_with(const hz_opt_t *t, bool with_opt, const char *out)
{
    args_t a = { { 0 }, 0 };
    char needs[256];
    add(&a, "render");
    add(&a, "builtin");
    add(&a, "--size");
    add(&a, "32x18");
    add(&a, "--frames");
    add(&a, "2");
    add(&a, "--threads");
    add(&a, "1"); /* the settings do not depend on it; one thread is the cheapest run under qemu */
    add(&a, "--quiet");
    add(&a, "--out");
    add(&a, out);
    const char *mode = mode_for(t);
    if (mode) {
        add(&a, "--mode");
        add(&a, mode);
    }
    add_words(&a, needs, sizeof needs, t->needs);
    if (with_opt) {
        add(&a, t->name);
        if (t->arg)
            add(&a, t->sample);
    }
    return run(hz_cmd_render, &a);
}

/* The run without the option depends only on the mode and the needs the option brings: one run per such pair
 * serves every option that shares it (under qemu each run costs a scene build and two frames). */
typedef struct baseline {
    const char *mode, *needs;
    int rc;
    char *settings;
} baseline_t;
static baseline_t baselines[64];
static size_t baseline_count;

static bool same_text(const char *a, const char *b)
{
    return a == b || (a && b && !strcmp(a, b));
}

static const baseline_t *baseline_for(const hz_opt_t *t)
{
    const char *mode = mode_for(t);
    for (size_t i = 0; i < baseline_count; i++)
        if (same_text(baselines[i].mode, mode) && same_text(baselines[i].needs, t->needs))
            return &baselines[i];
    assert_true(baseline_count < HZ_ARRAY_LEN(baselines));
    baseline_t *b = &baselines[baseline_count];
    char out[128];
    snprintf(out, sizeof out, "%s/base%zu", dir, baseline_count);
    b->mode = mode, b->needs = t->needs;
    b->rc = render_with(t, false, out);
    b->settings = (b->rc == 0 || b->rc == 3) ? settings_of(out) : NULL;
    baseline_count++;
    return b;
}

/* Every image-changing option of both tables: the two runs record different settings. */
static void walk_image_options(const hz_opt_t *table, size_t n, int *walked)
{
    for (size_t k = 0; k < n; k++) {
        const hz_opt_t *t = &table[k];
        if (!(t->flags & HZ_OF_IMAGE) || (t->cmds && !(t->cmds & HZ_OC_RENDER)))
            continue;
        if ((t->where & HZ_OW_SINKS) && !(t->where & (HZ_OW_FILES | HZ_OW_NONE))) {
            print_message("  %-18s acts only with a device sink: not run here\n", t->name);
            continue;
        }
        if (t->arg && !t->sample)
            fail_msg("%s changes the image but its table entry has no sample value", t->name);
        char b_out[128];
        snprintf(b_out, sizeof b_out, "%s/b%zu", dir, k);
        const baseline_t *base = baseline_for(t);
        int ra = base->rc, rb = render_with(t, true, b_out);
        if (rb == 64 + HZ_E_UNSUPPORTED) {
            print_message("  %-18s %s: not in this build\n", t->name, t->sample);
            continue;
        }
        /* a simulated display's short run may end without a lock (3): its files are written all the same */
        if ((ra != 0 && ra != 3) || (rb != 0 && rb != 3))
            fail_msg("%s %s: runs exit %d and %d", t->name, t->sample ? t->sample : "", ra, rb);
        char *sb = settings_of(b_out);
        if (!strcmp(base->settings, sb))
            fail_msg("%s %s changes the image but summary.json records the same settings:\n%s", t->name,
                     t->sample ? t->sample : "", sb);
        free(sb);
        (*walked)++;
    }
}

static void test_every_image_option_is_recorded(void **state)
{
    (void)state;
    /* the control: the same options twice, the same settings */
    static const hz_opt_t plain = { .name = "--plain" };
    char a_out[128], b_out[128];
    snprintf(a_out, sizeof a_out, "%s/same-a", dir);
    snprintf(b_out, sizeof b_out, "%s/same-b", dir);
    assert_int_equal(render_with(&plain, false, a_out), 0);
    assert_int_equal(render_with(&plain, false, b_out), 0);
    char *sa = settings_of(a_out), *sb = settings_of(b_out);
    assert_string_equal(sa, sb);
    free(sa);
    free(sb);
    size_t nr, ns;
    const hz_opt_t *rt = hz_ropts_table(&nr), *st = hz_sopts_table(&ns);
    int walked = 0;
    walk_image_options(rt, nr, &walked);
    walk_image_options(st, ns, &walked);
    print_message("  %d image-changing options each recorded in summary.json (%zu runs without one)\n", walked,
                  baseline_count);
    for (size_t i = 0; i < baseline_count; i++)
        free(baselines[i].settings);
    baseline_count = 0;
    assert_true(walked >= 30);
}

static const char *num(char *buf, size_t cap, double v)
{
    if (v == (double)(long long)v)
        snprintf(buf, cap, "%lld", (long long)v);
    else
        snprintf(buf, cap, "%g", v);
    return buf;
}

/* Every option a command takes is in its help, with its limits, on its own lines. */
static void check_help(int (*cmd)(int, char **), const char *name, unsigned oc, const hz_opt_t *table, size_t n)
{
    args_t a = { { 0 }, 0 };
    add(&a, name);
    add(&a, "--help");
    char *help;
    assert_int_equal(run_captured(cmd, &a, &help), 0);
    for (size_t k = 0; k < n; k++) {
        const hz_opt_t *t = &table[k];
        if (t->cmds && !(t->cmds & oc))
            continue;
        char head[64];
        snprintf(head, sizeof head, "\n  %s ", t->name);
        const char *at = strstr(help, head);
        if (!at) {
            snprintf(head, sizeof head, "\n  %s\n", t->name);
            at = strstr(help, head);
        }
        if (!at)
            fail_msg("hzrt %s --help lacks %s", name, t->name);
        const char *next = strstr(at + 1, "\n  --");
        char lim[96] = "", lo[32], hi[32];
        num(lo, sizeof lo, t->lo);
        num(hi, sizeof hi, t->hi);
        if (t->kind == HZ_OPT_INT || t->kind == HZ_OPT_REAL)
            snprintf(lim, sizeof lim, "%c%s..%s]", t->lo_open ? '(' : '[', lo, hi);
        else if (t->kind == HZ_OPT_SIZE)
            snprintf(lim, sizeof lim, "[%s..%s a side]", lo, hi);
        if (lim[0]) {
            const char *l = strstr(at, lim);
            if (!l || (next && l > next))
                fail_msg("hzrt %s --help: %s lacks its limits %s", name, t->name, lim);
        }
    }
    free(help);
}

static void test_help_lists_every_option_with_its_limits(void **state)
{
    (void)state;
    size_t nr, ns;
    const hz_opt_t *rt = hz_ropts_table(&nr), *st = hz_sopts_table(&ns);
    check_help(hz_cmd_render, "render", HZ_OC_RENDER, rt, nr);
    check_help(hz_cmd_render, "render", HZ_OC_RENDER, st, ns);
    check_help(hz_cmd_latency, "latency", HZ_OC_LATENCY, rt, nr);
    check_help(hz_cmd_latency, "latency", HZ_OC_LATENCY, st, ns);
    check_help(hz_cmd_show, "show", HZ_OC_SHOW, st, ns);
}

/* A valid value for an entry (its sample, else one from its limits). */
static const char *value_for(const hz_opt_t *t, char *buf, size_t cap)
{
    if (t->sample)
        return t->sample;
    switch (t->kind) {
    case HZ_OPT_INT: return num(buf, cap, t->lo);
    case HZ_OPT_REAL: return num(buf, cap, t->hi);
    case HZ_OPT_SIZE: return "32x18";
    case HZ_OPT_WORD: return t->words[0];
    default: return "1ms";
    }
}

/* Every run option given where it does nothing is refused (2), before anything is written. */
static void test_idle_options_are_refused(void **state)
{
    (void)state;
    size_t ns;
    const hz_opt_t *st = hz_sopts_table(&ns);
    char out[128];
    snprintf(out, sizeof out, "%s/idle", dir);
    int refused = 0;
    for (int c = 0; c < 2; c++) {
        /* render's defaults: offline, files, a scene, no display clock; latency here: sim, none, the pattern */
        unsigned where = c == 0 ? HZ_OW_OFFLINE | HZ_OW_FILES | HZ_OW_SCENE | HZ_OW_VIRTUAL
                                : HZ_OW_SIM | HZ_OW_NONE | HZ_OW_PATTERN | HZ_OW_REAL;
        for (size_t k = 0; k < ns; k++) {
            const hz_opt_t *t = &st[k];
            if ((t->cmds && !(t->cmds & (c == 0 ? HZ_OC_RENDER : HZ_OC_LATENCY))) || hz_opt_acts(t, where))
                continue;
            args_t a = { { 0 }, 0 };
            char v[32];
            add(&a, c == 0 ? "render" : "latency");
            if (c == 0)
                add(&a, "builtin");
            else {
                add(&a, "--source");
                add(&a, "sim");
                add(&a, "--sink");
                add(&a, "none");
            }
            add(&a, "--frames");
            add(&a, "1");
            add(&a, "--quiet");
            add(&a, "--out");
            add(&a, out);
            add(&a, t->name);
            if (t->arg)
                add(&a, value_for(t, v, sizeof v));
            int rc = run(c == 0 ? hz_cmd_render : hz_cmd_latency, &a);
            if (rc != 2)
                fail_msg("%s %s does nothing there but exits %d", c == 0 ? "render" : "latency", t->name, rc);
            assert_int_equal(access(out, F_OK), -1); /* refused before anything was made */
            refused++;
        }
    }
    /* render options of one mode in another */
    size_t nr;
    const hz_opt_t *rt = hz_ropts_table(&nr);
    for (size_t k = 0; k < nr; k++) {
        const hz_opt_t *t = &rt[k];
        if (!t->modes)
            continue;
        int other = 0;
        while (t->modes & (1u << other))
            other++;
        args_t a = { { 0 }, 0 };
        char v[32];
        add(&a, "render");
        add(&a, "builtin");
        add(&a, "--mode");
        add(&a, hz_render_mode_name((hz_render_mode_t)other));
        add(&a, "--out");
        add(&a, out);
        add(&a, t->name);
        if (t->arg)
            add(&a, !strcmp(t->name, "--adaptive-map") ? "m.png" : value_for(t, v, sizeof v));
        int rc = run(hz_cmd_render, &a);
        if (rc != 2)
            fail_msg("render --mode %s %s does nothing there but exits %d", hz_render_mode_name((hz_render_mode_t)other),
                     t->name, rc);
        refused++;
    }
    print_message("  %d options refused where they do nothing\n", refused);
    assert_true(refused >= 20);
}

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/hz-options-XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_image_option_is_recorded),
        cmocka_unit_test(test_help_lists_every_option_with_its_limits),
        cmocka_unit_test(test_idle_options_are_refused),
    };
    return HZ_RUN_GROUP(tests, setup, teardown);
}
