/* hzerrtime — error against run time for every method errtime knows (see errtime.h, et_methods.h, README). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "errtime.h"
#include "fileio.h"
#include "et_flip.h"
#include "hz/config.h"
#include "et_methods.h"
#include "et_search.h"
#include "et_stability.h"
#include "opttab.h"

#define STR_(x) #x
#define STR(x) STR_(x)

/* The command line (opttab.h): the help is printed from this table. */
enum { E_SCENE, E_SIZE, E_FRAMES, E_WARMUP, E_REFRESH, E_METHODS, E_SHUTTER, E_SKIP, E_PPD, E_CACHE, E_OUT, E_VIDEO,
       E_SCENES, E_THREADS, E_ARENA, E_SEARCH, E_LIST };

static const hz_opt_t options[] = {
    { .name = "--scene", .arg = "A,B", .kind = HZ_OPT_TEXT, .id = E_SCENE,
      .help = "scenes (default synthetic; --list shows them); one CSV and Markdown table for all, one chart per "
              "scene. An item ending in .hzb is any baked scene file (its camera path and lights) run with the "
              "renderer's standard methods (full-frame 1/4/9/16 spp, TAA, adaptive) against 256 spp" },
    { .name = "--size", .arg = "WxH", .kind = HZ_OPT_SIZE, .lo = 11, .hi = HZ_IMAGE_MAX_DIM, .id = E_SIZE,
      .help = "frame size (default: the scene's, else 96x64)" },
    { .name = "--frames", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = 1000000, .id = E_FRAMES,
      .help = "displayed frames (default: the scene's, else 48)" },
    { .name = "--warmup", .arg = "N", .kind = HZ_OPT_INT, .lo = 0, .hi = 1000000, .id = E_WARMUP,
      .help = "leading frames neither timed nor scored (default: the scene's, else 8)" },
    { .name = "--refresh", .arg = "HZ", .kind = HZ_OPT_INT, .lo = 1, .hi = 960, .id = E_REFRESH,
      .help = "display refresh rate (default the board's, " STR(HZ_DISPLAY_HZ) " Hz)" },
    { .name = "--methods", .arg = "A,B", .kind = HZ_OPT_TEXT, .id = E_METHODS,
      .help = "only these methods (names as in --list)" },
    { .name = "--shutter", .arg = "S", .kind = HZ_OPT_REAL, .lo = 0, .hi = 1, .lo_open = true, .noun = "a fraction",
      .id = E_SHUTTER, .help = "motion-blur scenes (*-blur): shutter open for S of each frame interval (default 1)" },
    { .name = "--skip", .arg = "A,B", .kind = HZ_OPT_TEXT, .id = E_SKIP, .help = "all but these methods" },
    { .name = "--ppd", .arg = "X", .kind = HZ_OPT_REAL, .lo = 0, .hi = 1000, .lo_open = true, .id = E_PPD,
      .help = "FLIP observer, pixels per degree (default 67.02)" },
    { .name = "--cache", .arg = "DIR", .kind = HZ_OPT_TEXT, .id = E_CACHE,
      .help = "reference cache (default build/errtime-cache)" },
    { .name = "--out", .arg = "DIR", .kind = HZ_OPT_TEXT, .id = E_OUT,
      .help = "report directory (default build/errtime): errtime.csv, errtime.md, <scene>.svg" },
    { .name = "--video", .arg = "DIR", .kind = HZ_OPT_TEXT, .id = E_VIDEO,
      .help = "also write each method's displayed frames (and the reference) as Y4M videos" },
    { .name = "--scenes", .arg = "DIR", .kind = HZ_OPT_TEXT, .id = E_SCENES,
      .help = "baked scenes (.hzb) for the rendered scenes (default $HZ_SCENES_DIR, else build/scenes; `make "
              "scenes` bakes them)" },
    { .name = "--threads", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = HZ_MAX_THREADS, .id = E_THREADS,
      .help = "render threads (default: one per online CPU)" },
    { .name = "--arena-mib", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = 1 << 20, .id = E_ARENA,
      .help = "working memory (default 1024; touched only as needed)" },
    { .name = "--adaptive-search", .kind = HZ_OPT_FLAG, .id = E_SEARCH,
      .help = "also find, per scene and adaptive method (adaptive, adaptive-bilinear, adaptive-footprint: those "
              "--methods/--skip leave), the largest tau whose PSNR reaches full-frame 9 spp's, by bisection (up to "
              STR(HZ_ET_SEARCH_PROBES)
              " runs each, rows <method>-search); adaptive-search.csv and .md next to errtime.csv" },
    { .name = "--list", .kind = HZ_OPT_FLAG, .id = E_LIST, .help = "scenes and their methods" },
    { .name = "--help", .alias = "-h", .kind = HZ_OPT_FLAG, .id = HZ_OPT_ID_HELP, .help = "this text" },
};

static const hz_opt_prog_t program = {
    .name = "hzerrtime",
    .table = options,
    .n = sizeof options / sizeof options[0],
    .synopsis = "usage: hzerrtime [options]\n"
                "\n"
                "Renders a reference sequence (cached), runs every method of a scene on the same frames, and writes\n"
                "error (mean FLIP, PSNR, SSIM, display-integrated FLIP/PSNR) against ms per displayed frame.\n"
                "\n",
    .epilogue = "\n"
                "exit status: 0 ok, 2 bad command line (an unknown option, a missing value, a value outside its\n"
                "limits), 64+N a failure with hz status code N\n",
};

static bool wanted(const char *list, const char *name)
{
    if (!list)
        return true;
    size_t n = strlen(name);
    for (const char *p = list; *p;) {
        const char *e = strchr(p, ',');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        if (len == n && !strncmp(p, name, n))
            return true;
        if (!e)
            break;
        p = e + 1;
    }
    return false;
}

static int list(void)
{
    for (size_t i = 0; i < hz_et_scene_count; i++) {
        const hz_et_scene_t *s = &hz_et_scenes[i];
        printf("%s: %s\n", s->name, s->about);
        if (s->width)
            printf("  default: %ux%u, %u frames (%u warm-up)\n", (unsigned)s->width, (unsigned)s->height,
                   (unsigned)s->frames, (unsigned)s->warmup);
        printf("  reference: %s %s=%g\n", s->reference->name, s->reference->knob, s->reference->value);
        for (size_t j = 0; j < s->method_count; j++)
            printf("  %-14s %s=%g\n", s->methods[j].name, s->methods[j].knob, s->methods[j].value);
    }
    return 0;
}

typedef struct args {
    const char *scene_names, *methods, *cache, *out, *skip, *video, *scene_dir;
    bool size_given, frames_given, warmup_given, refresh_given, search;
    long threads, frames, warmup, refresh, arena_mib;
    int w, h;
    float ppd;
} args_t;

static int take(void *ctx, const hz_opt_t *o, const hz_opt_val_t *v)
{
    args_t *a = ctx;
    switch (o->id) {
    case E_SCENE: a->scene_names = v->s; break;
    case E_SIZE: a->w = v->w, a->h = v->h, a->size_given = true; break;
    case E_FRAMES: a->frames = v->n, a->frames_given = true; break;
    case E_WARMUP: a->warmup = v->n, a->warmup_given = true; break;
    case E_REFRESH: a->refresh = v->n, a->refresh_given = true; break;
    case E_METHODS: a->methods = v->s; break;
    case E_SHUTTER: hz_et_render_set_shutter((float)v->x); break;
    case E_SKIP: a->skip = v->s; break;
    case E_PPD: a->ppd = (float)v->x; break;
    case E_CACHE: a->cache = v->s; break;
    case E_OUT: a->out = v->s; break;
    case E_VIDEO: a->video = v->s; break;
    case E_SCENES: a->scene_dir = v->s; break;
    case E_THREADS: a->threads = v->n; break;
    case E_ARENA: a->arena_mib = v->n; break;
    case E_SEARCH: a->search = true; break;
    case E_LIST: list(); return HZ_OPT_DONE;
    }
    return 0;
}

/* The adaptive methods --adaptive-search knows. */
enum { FAMILIES = 3 };
static const char *const families[FAMILIES] = { "adaptive", "adaptive-bilinear", "adaptive-footprint" };

/* The scene's method `name` (at knob value v; v < 0: any), or NULL. */
static const hz_et_method_t *method_of(const hz_et_scene_t *scene, const char *name, double v)
{
    for (size_t j = 0; j < scene->method_count; j++)
        if (!strcmp(scene->methods[j].name, name) && (v < 0.0 || scene->methods[j].value == v))
            return &scene->methods[j];
    return NULL;
}

/* Adaptive family f of the scene, if it has one and --methods/--skip leave it, else NULL. */
static const hz_et_method_t *family_of(const hz_et_scene_t *scene, int f, const char *methods, const char *skip)
{
    if (!wanted(methods, families[f]) || (skip && wanted(skip, families[f])))
        return NULL;
    return method_of(scene, families[f], -1.0);
}

/* The row of `name` at knob value v among rows[first, count), or NULL. */
static const hz_et_row_t *row_of(const hz_et_row_t *rows, size_t first, size_t count, const char *name, double v)
{
    for (size_t j = first; j < count; j++)
        if (!strcmp(rows[j].method, name) && rows[j].value == v)
            return &rows[j];
    return NULL;
}

/* --adaptive-search on one open scene: full-frame 9 and 16 spp (run now if --methods left them out), then the
 * search of every adaptive family --methods/--skip leave; probe rows appended after the scene's rows. */
static hz_status_t search_scene(const hz_et_scene_t *scene, const hz_et_sequence_t *seq, const hz_et_config_t *cfg,
                                const char *methods, const char *skip, hz_et_row_t *rows, size_t first, size_t *count,
                                size_t capacity, hz_et_search_t *found, size_t *nfound, hz_error_t *err)
{
    static const double spp[2] = { 9.0, 16.0 };
    hz_status_t s = HZ_OK;
    for (int i = 0; i < 2 && s == HZ_OK; i++) {
        const hz_et_method_t *m = method_of(scene, "full-frame", spp[i]);
        if (!m || row_of(rows, first, *count, m->name, spp[i]))
            continue;
        if (*count >= capacity)
            return hz_error_set(err, HZ_E_RANGE, "adaptive search: no room for more rows");
        if ((s = hz_et_run(seq, scene->reference, m, 1, cfg, &rows[*count], err)) == HZ_OK)
            (*count)++;
    }
    const hz_et_row_t *r9 = row_of(rows, first, *count, "full-frame", 9.0);
    const hz_et_row_t *r16 = row_of(rows, first, *count, "full-frame", 16.0);
    for (int f = 0; f < FAMILIES && s == HZ_OK; f++) {
        const hz_et_method_t *fam = family_of(scene, f, methods, skip);
        if (!fam || !r9 || !r16)
            continue;
        s = hz_et_adaptive_search(seq, scene->reference, fam, r9, r16, cfg, rows, capacity, count, &found[*nfound],
                                  err);
        *nfound += s == HZ_OK;
    }
    hz_et_pareto(rows + first, *count - first);
    return s;
}

int main(int argc, char **argv)
{
    hz_cli_prog = "hzerrtime";
    args_t a = { "synthetic", NULL, "build/errtime-cache", "build/errtime", NULL, NULL, getenv("HZ_SCENES_DIR"),
                 false, false, false, false, false, 0, 48, 8, HZ_DISPLAY_HZ, 1024, 96, 64, HZ_FLIP_DEFAULT_PPD };
    int nops = 0;
    int rc = hz_opt_parse(&program, argc, argv, take, &a, NULL, &nops);
    if (rc)
        return rc == HZ_OPT_DONE ? 0 : rc;
    const char *scene_names = a.scene_names, *methods = a.methods, *cache = a.cache, *out = a.out, *skip = a.skip;
    const char *video = a.video, *scene_dir = a.scene_dir;
    bool size_given = a.size_given, frames_given = a.frames_given, warmup_given = a.warmup_given;
    bool refresh_given = a.refresh_given;
    long threads = a.threads, frames = a.frames, warmup = a.warmup, refresh = a.refresh, arena_mib = a.arena_mib;
    int w = a.w, h = a.h;
    float ppd = a.ppd;
    /* The scenes asked for, validated before anything runs. */
    const hz_et_scene_t *scenes[64];
    static hz_et_scene_t files[64];
    static char file_names[64][64], file_paths[64][4096];
    size_t nscenes = 0, total = 0, nfiles = 0;
    for (size_t i = 0; i < hz_et_scene_count; i++)
        if (wanted(scene_names, hz_et_scenes[i].name)) {
            if (nscenes == 64) {
                hz_cli_error("--scene: more than 64 scenes");
                return HZ_EXIT_USAGE;
            }
            scenes[nscenes++] = &hz_et_scenes[i];
            total += hz_et_scenes[i].method_count;
        }
    for (const char *p = scene_names; *p;) { /* every listed name must exist */
        const char *e = strchr(p, ',');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        if (hz_et_scene_is_file(p, len)) { /* a baked scene file: its own entry */
            if (nscenes == 64 || len >= sizeof file_paths[0] - 2) {
                hz_cli_error("--scene: more than 64 scenes, or a path longer than 4 KiB");
                return HZ_EXIT_USAGE;
            }
            /* a bare file name is relative to the working directory, like any path */
            snprintf(file_paths[nfiles], sizeof file_paths[0], "%s%.*s", memchr(p, '/', len) ? "" : "./", (int)len,
                     p);
            if (access(file_paths[nfiles], R_OK) != 0) {
                hz_cli_error("--scene: cannot read '%s': %s", file_paths[nfiles], strerror(errno));
                return HZ_EXIT_USAGE;
            }
            hz_et_scene_from_file(file_paths[nfiles], file_names[nfiles], sizeof file_names[0], &files[nfiles]);
            scenes[nscenes++] = &files[nfiles];
            total += files[nfiles].method_count;
            nfiles++;
            if (!e)
                break;
            p = e + 1;
            continue;
        }
        bool known = false;
        for (size_t i = 0; i < hz_et_scene_count; i++)
            known |= strlen(hz_et_scenes[i].name) == len && !strncmp(hz_et_scenes[i].name, p, len);
        if (!known) {
            hz_cli_error("--scene: unknown scene '%.*s' (try --list)", (int)len, p);
            return HZ_EXIT_USAGE;
        }
        if (!e)
            break;
        p = e + 1;
    }
    /* --adaptive-search: per scene, the adaptive families to search and full-frame 9 and 16 spp to compare with */
    size_t capacity = total;
    if (a.search) {
        for (size_t k = 0; k < nscenes; k++) {
            const hz_et_scene_t *sc = scenes[k];
            bool fam = false;
            for (int f = 0; f < FAMILIES; f++)
                fam |= family_of(sc, f, methods, skip) != NULL;
            if (!fam || !method_of(sc, "full-frame", 9.0) || !method_of(sc, "full-frame", 16.0)) {
                hz_cli_error("--adaptive-search: scene %s has %s", sc->name,
                             !fam ? "no adaptive method to search (adaptive, adaptive-bilinear or adaptive-footprint, "
                                    "left by --methods/--skip)"
                                  : "no full-frame 9 and 16 spp to compare with");
                return HZ_EXIT_USAGE;
            }
        }
        capacity += nscenes * (2 + FAMILIES * HZ_ET_SEARCH_PROBES);
    }
    hz_et_search_t *found = calloc(nscenes * FAMILIES + 1, sizeof *found);
    size_t nfound = 0;
    /* chosen[] and rows[] share their index: a scene's methods follow the previous scene's rows, probes included */
    hz_et_method_t *chosen = calloc(capacity ? capacity : 1, sizeof *chosen);
    hz_et_row_t *rows = calloc(capacity ? capacity : 1, sizeof *rows);
    if (!chosen || !rows || !found) {
        hz_cli_error("no memory for %zu methods", total);
        return hz_status_exit_code(HZ_E_NO_MEMORY);
    }
    size_t count = 0;
    hz_et_stab_row_t *stab = NULL; /* still-view stability of the scenes that ask for it */
    size_t nstab = 0;

    hz_et_env_t env = { scene_dir && *scene_dir ? scene_dir : "build/scenes", (uint32_t)threads };
    hz_arena_t arena;
    hz_error_t err;
    void *mem = NULL;
    size_t bytes = 0;
    for (size_t k = 0; k < nscenes; k++) {
        const hz_et_scene_t *scene = scenes[k];
        size_t first = count;
        for (size_t j = 0; j < scene->method_count; j++)
            if (wanted(methods, scene->methods[j].name) && !(skip && wanted(skip, scene->methods[j].name)))
                chosen[count++] = scene->methods[j];
        if (count == first) {
            hz_cli_error("--methods/--skip: no method of scene %s is left (try --list)", scene->name);
            return HZ_EXIT_USAGE;
        }
        /* The scene's own size and length unless the command line gave them. */
        uint32_t sw = size_given || !scene->width ? (uint32_t)w : scene->width;
        uint32_t sh = size_given || !scene->height ? (uint32_t)h : scene->height;
        uint32_t sf = frames_given || !scene->frames ? (uint32_t)frames : scene->frames;
        uint32_t swu = warmup_given || !scene->warmup ? (uint32_t)warmup : scene->warmup;
        uint32_t sr = refresh_given || !scene->refresh_hz ? (uint32_t)refresh : scene->refresh_hz;
        hz_et_sequence_t seq = { scene->name, 0, NULL, NULL, sw, sh, sf, swu, sr, NULL };
        size_t need = (size_t)arena_mib << 20;
        if (need < hz_et_arena_bytes(&seq, ppd) + (64u << 20))
            need = hz_et_arena_bytes(&seq, ppd) + (64u << 20);
        if (need > bytes) { /* grows for a larger scene; pages are touched only as used */
            free(mem);
            mem = malloc(need);
            bytes = need;
            if (!mem) {
                hz_error_set(&err, HZ_E_NO_MEMORY, "cannot allocate %zu MiB of working memory", need >> 20);
                return hz_cli_report(&err);
            }
        }
        hz_arena_init(&arena, "errtime", mem, bytes);
        if (scene->open(scene, &env, &seq, &arena, &err) != HZ_OK)
            return hz_cli_report(&err);
        hz_et_config_t cfg = { cache, ppd, &arena, stderr, hz_cli_stderr_is_tty(), video };
        hz_status_t s = hz_et_run(&seq, scene->reference, chosen + first, count - first, &cfg, rows + first, &err);
        for (size_t j = first; j < count && s == HZ_OK && scene->still_frames; j++) {
            hz_et_stab_row_t *sr = realloc(stab, (nstab + 1) * sizeof *stab);
            if (!sr) {
                hz_error_set(&err, HZ_E_NO_MEMORY, "no memory for the stability rows");
                return hz_cli_report(&err);
            }
            stab = sr;
            s = hz_et_stability(&seq, &chosen[j], scene->still_frames, &arena, &stab[nstab], &err);
            nstab += s == HZ_OK;
        }
        if (a.search && s == HZ_OK)
            s = search_scene(scene, &seq, &cfg, methods, skip, rows, first, &count, capacity, found, &nfound, &err);
        if (scene->close)
            scene->close();
        if (s != HZ_OK)
            return hz_cli_report(&err);
    }

    char path[4200];
    if (hz_mkdirs(out, &err) != HZ_OK)
        return hz_cli_report(&err);
    snprintf(path, sizeof path, "%s/errtime.csv", out);
    if (hz_et_write_csv(path, rows, count, &err) != HZ_OK)
        return hz_cli_report(&err);
    snprintf(path, sizeof path, "%s/errtime.md", out);
    if (hz_et_write_markdown(path, rows, count, &err) != HZ_OK)
        return hz_cli_report(&err);
    for (size_t k = 0; k < nscenes; k++) {
        snprintf(path, sizeof path, "%s/%s.svg", out, scenes[k]->name);
        if (hz_et_write_svg(path, rows, count, scenes[k]->name, &err) != HZ_OK)
            return hz_cli_report(&err);
    }
    hz_et_print_markdown(stdout, rows, count);
    if (nstab) {
        snprintf(path, sizeof path, "%s/transparency-stability.csv", out);
        if (hz_et_write_stability_csv(path, stab, nstab, &err) != HZ_OK)
            return hz_cli_report(&err);
        printf("\nstill-view stability: mean |frame-to-frame change|, 8-bit sRGB codes (%s)\n", path);
        printf("| scene | method | knob | change |\n|---|---|---:|---:|\n");
        for (size_t k = 0; k < nstab; k++)
            printf("| %s | %s | %s %g | %.3f |\n", stab[k].scene, stab[k].method, stab[k].knob, stab[k].value,
                   stab[k].mean_abs_change);
    }
    free(stab);
    if (a.search) {
        snprintf(path, sizeof path, "%s/adaptive-search.csv", out);
        if (hz_et_write_search_csv(path, found, nfound, &err) != HZ_OK)
            return hz_cli_report(&err);
        snprintf(path, sizeof path, "%s/adaptive-search.md", out);
        if (hz_et_write_search_markdown(path, found, nfound, &err) != HZ_OK)
            return hz_cli_report(&err);
        printf("\n");
        hz_et_print_search(stdout, found, nfound);
        printf("\nwrote %s/adaptive-search.csv and %s/adaptive-search.md\n", out, out);
    }
    free(found);
    printf("\nwrote %s/errtime.csv, %s/errtime.md and %zu chart%s (", out, out, nscenes, nscenes == 1 ? "" : "s");
    for (size_t k = 0; k < nscenes; k++)
        printf("%s%s.svg", k ? ", " : "", scenes[k]->name);
    printf(") in %s\n", out);
    free(mem);
    free(chosen);
    free(rows);
    return 0;
}
