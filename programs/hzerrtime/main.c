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
#include "et_stability.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: hzerrtime [options]\n"
            "\n"
            "Renders a reference sequence (cached), runs every method of a scene on the same frames, and writes\n"
            "error (mean FLIP, PSNR, SSIM, display-integrated FLIP/PSNR) against ms per displayed frame.\n"
            "\n"
            "  --scene A,B        scenes (default synthetic; --list shows them); one CSV and Markdown table\n"
            "                     for all, one chart per scene. An item ending in .hzb is any baked scene file\n"
            "                     (its camera path and lights) run with the renderer's standard methods\n"
            "                     (full-frame 1/4/9/16 spp, TAA, adaptive) against 256 spp\n"
            "  --size WxH         frame size (default: the scene's, else 96x64)\n"
            "  --frames N         displayed frames (default: the scene's, else 48)\n"
            "  --warmup N         leading frames neither timed nor scored (default: the scene's, else 8)\n"
            "  --refresh HZ       display refresh rate (default the board's, %d Hz)\n"
            "  --methods A,B      only these methods (names as in --list)\n"
            "  --shutter S        motion-blur scenes (*-blur): shutter open for S in (0, 1] of each frame\n"
            "                     interval (default 1)\n"
            "  --skip A,B         all but these methods\n"
            "  --ppd X            FLIP observer, pixels per degree (default 67.02)\n"
            "  --cache DIR        reference cache (default build/errtime-cache)\n"
            "  --out DIR          report directory (default build/errtime): errtime.csv, errtime.md, <scene>.svg\n"
            "  --video DIR        also write each method's displayed frames (and the reference) as Y4M videos\n"
            "  --scenes DIR       baked scenes (.hzb) for the rendered scenes (default $HZ_SCENES_DIR, else\n"
            "                     build/scenes; `make scenes` bakes them)\n"
            "  --threads N        render threads (default: one per online CPU)\n"
            "  --arena-mib N      working memory (default 1024; touched only as needed)\n"
            "  --list             scenes and their methods\n"
            "\n"
            "exit status: 0 ok, 2 bad command line, 64+N a failure with hz status code N\n",
            HZ_DISPLAY_HZ);
}

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

int main(int argc, char **argv)
{
    hz_cli_prog = "hzerrtime";
    const char *scene_names = "synthetic", *methods = NULL, *cache = "build/errtime-cache", *out = "build/errtime";
    const char *skip = NULL, *video = NULL, *scene_dir = getenv("HZ_SCENES_DIR");
    bool size_given = false, frames_given = false, warmup_given = false, refresh_given = false;
    long threads = 0;
    int w = 96, h = 64;
    long frames = 48, warmup = 8, refresh = HZ_DISPLAY_HZ, arena_mib = 1024;
    float ppd = HZ_FLIP_DEFAULT_PPD;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        bool takes = strcmp(a, "--list") && strcmp(a, "-h") && strcmp(a, "--help");
        if (takes && !v) {
            hz_cli_error("%s needs a value (try --help)", a);
            return HZ_EXIT_USAGE;
        }
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--list")) {
            return list();
        } else if (!strcmp(a, "--scene")) {
            scene_names = v;
        } else if (!strcmp(a, "--size")) {
            if (!hz_cli_parse_size(a, v, 11, (int)HZ_IMAGE_MAX_DIM, &w, &h))
                return HZ_EXIT_USAGE;
            size_given = true;
        } else if (!strcmp(a, "--frames")) {
            if (!hz_cli_parse_long(a, v, 1, 1000000, &frames))
                return HZ_EXIT_USAGE;
            frames_given = true;
        } else if (!strcmp(a, "--warmup")) {
            if (!hz_cli_parse_long(a, v, 0, 1000000, &warmup))
                return HZ_EXIT_USAGE;
            warmup_given = true;
        } else if (!strcmp(a, "--threads")) {
            if (!hz_cli_parse_long(a, v, 1, HZ_MAX_THREADS, &threads))
                return HZ_EXIT_USAGE;
        } else if (!strcmp(a, "--scenes")) {
            scene_dir = v;
        } else if (!strcmp(a, "--refresh")) {
            if (!hz_cli_parse_long(a, v, 1, 960, &refresh))
                return HZ_EXIT_USAGE;
            refresh_given = true;
        } else if (!strcmp(a, "--arena-mib")) {
            if (!hz_cli_parse_long(a, v, 1, 1 << 20, &arena_mib))
                return HZ_EXIT_USAGE;
        } else if (!strcmp(a, "--ppd")) {
            char *end;
            double d = strtod(v, &end);
            if (end == v || *end || !(d > 0.0 && d <= 1000.0)) {
                hz_cli_error("--ppd: '%s' is not a number in (0, 1000]", v);
                return HZ_EXIT_USAGE;
            }
            ppd = (float)d;
        } else if (!strcmp(a, "--shutter")) {
            char *end;
            double d = strtod(v, &end);
            if (end == v || *end || !(d > 0.0 && d <= 1.0)) {
                hz_cli_error("--shutter: '%s' is not a fraction in (0, 1]", v);
                return HZ_EXIT_USAGE;
            }
            hz_et_render_set_shutter((float)d);
        } else if (!strcmp(a, "--methods")) {
            methods = v;
        } else if (!strcmp(a, "--skip")) {
            skip = v;
        } else if (!strcmp(a, "--cache")) {
            cache = v;
        } else if (!strcmp(a, "--out")) {
            out = v;
        } else if (!strcmp(a, "--video")) {
            video = v;
        } else {
            hz_cli_error("unknown option '%s' (try --help)", a);
            return HZ_EXIT_USAGE;
        }
        i++;
    }
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
    hz_et_method_t *chosen = calloc(total ? total : 1, sizeof *chosen);
    hz_et_row_t *rows = calloc(total ? total : 1, sizeof *rows);
    if (!chosen || !rows) {
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
    printf("\nwrote %s/errtime.csv, %s/errtime.md and %zu chart%s (", out, out, nscenes, nscenes == 1 ? "" : "s");
    for (size_t k = 0; k < nscenes; k++)
        printf("%s%s.svg", k ? ", " : "", scenes[k]->name);
    printf(") in %s\n", out);
    free(mem);
    free(chosen);
    free(rows);
    return 0;
}
