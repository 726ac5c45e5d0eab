/* The render options' table, parser and settings (see renderopts.h). */
#include "renderopts.h"

#include <string.h>

#include "accel_backend.h"
#include "cli.h"
#include "hz/config.h"
#include "hz/fixed.h"
#include "phase.h"
#include "transp_opt.h"

#define M(m) (1u << (m))
#define FULL M(HZ_MODE_FULL)
#define TAA M(HZ_MODE_TAA)
#define TDENSE M(HZ_MODE_TDENSE)
#define ADAPTIVE M(HZ_MODE_ADAPTIVE)
#define IMG HZ_OF_IMAGE

typedef enum opt_id {
    O_MODE, O_SPP, O_MSAA4, O_ORDERING, O_NO_RMV, O_TD_GAMMA, O_TAA_GAMMA, O_TAA_CLIP, O_TAA_CR, O_BOUNCES,
    O_TRANSP, O_RR_SHADOWS, O_SHUTTER, O_BLUR_BVH, O_RIGID, O_SEGMENTS, O_BACKEND, O_THREADS, O_START, O_TAU, O_NORMAL_ANGLE, O_FOCUS,
    O_MAP, O_BILINEAR, O_FOOTPRINT,
    O_TAU_K /* + hz_tau_t: the nine thresholds */
} opt_id_t;

static const char *const mode_words[] = { "tdense", "full", "taa", "adaptive", NULL };
static const hz_render_mode_t mode_of_word[] = { HZ_MODE_TDENSE, HZ_MODE_FULL, HZ_MODE_TAA, HZ_MODE_ADAPTIVE };
static const char *const backend_words[] = { "native", "embree", NULL };
static const char *const blur_words[] = { "msbvh", "interp", "swept", NULL };
static const char *const rigid_words[] = { "instance", "refit", NULL };
static const char *const segments_words[] = { "per-node", "every-key", NULL };
static const char *const ordering_words[] = { "full", "dominant", "shear-up", "shear-down", "hourglass", "bowtie", NULL };

#define TAU(key, k, def, what)                                                                                   \
    { .name = "--tau-" key, .arg = "T", .kind = HZ_OPT_REAL, .lo = 0, .hi = 1, .modes = ADAPTIVE, .flags = IMG,   \
      .id = O_TAU_K + (k), .sample = "0.3", .noun = "a threshold", .help = what "; default " def }

static const hz_opt_t table[] = {
    { .name = "--mode", .arg = "M", .kind = HZ_OPT_WORD, .words = mode_words, .flags = IMG, .id = O_MODE,
      .sample = "full",
      .help = "tdense (one sample per 2x2 tile per frame, temporally dense composite: 4 frames make a complete "
              "image), full (N samples per pixel), taa (1 jittered sample + temporal resolve) or adaptive "
              "(selective and adaptive supersampling); default the board's, tdense" },
    { .name = "--spp", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = 1024, .modes = FULL, .flags = IMG, .id = O_SPP,
      .sample = "4", .help = "samples per pixel, a square (1, 4, 9, ...); default 1" },
    { .name = "--msaa4", .kind = HZ_OPT_FLAG, .modes = FULL, .flags = IMG, .id = O_MSAA4, .needs = "--spp 4",
      .help = "4 spp at the fixed 4x MSAA positions (what tdense converges to; needs --spp 4)" },
    { .name = "--ordering", .arg = "R", .kind = HZ_OPT_WORD, .words = ordering_words, .modes = TDENSE, .flags = IMG,
      .id = O_ORDERING, .sample = "bowtie",
      .help = "tile orderings: full (the paper's adaptive choice), dominant, shear-up, shear-down, hourglass or "
              "bowtie; default full" },
    { .name = "--no-reflected-mv", .kind = HZ_OPT_FLAG, .modes = TDENSE, .flags = IMG, .id = O_NO_RMV,
      .help = "mirrors use their own motion, not the reflected hit's" },
    { .name = "--tdense-gamma", .arg = "G", .kind = HZ_OPT_REAL, .lo = 0, .hi = 16, .lo_open = true, .modes = TDENSE,
      .flags = IMG, .id = O_TD_GAMMA, .sample = "2",
      .help = "variance box width in standard deviations; default 1" },
    { .name = "--taa-gamma", .arg = "G", .kind = HZ_OPT_REAL, .lo = 0, .hi = 16, .lo_open = true, .modes = TAA,
      .flags = IMG, .id = O_TAA_GAMMA, .sample = "2",
      .help = "variance box width in standard deviations; default 1" },
    { .name = "--taa-clip", .kind = HZ_OPT_FLAG, .modes = TAA, .flags = IMG, .id = O_TAA_CLIP,
      .help = "clip history towards the box centre (default: clamp per channel)" },
    { .name = "--taa-catmull-rom", .kind = HZ_OPT_FLAG, .modes = TAA, .flags = IMG, .id = O_TAA_CR,
      .help = "fetch history with Catmull-Rom (default: bilinear)" },
    { .name = "--bounces", .arg = "N", .kind = HZ_OPT_INT, .lo = 0, .hi = 3, .flags = IMG, .id = O_BOUNCES,
      .sample = "1", .help = "mirror reflections per path; default 3" },
    { .name = "--transparency", .arg = "T", .kind = HZ_OPT_TEXT, .flags = IMG, .id = O_TRANSP, .sample = "std",
      .help = "blended surfaces: exact (front-to-back compositing, deep shadow rays), rr (Russian roulette), std "
              "(spatio-temporal dither), dtaa, dtaa-star, or hybrid:X (exact while the visibility > X in [0, 1], "
              "then one std decision); default exact. The stochastic ones shade one fragment per pixel: use them "
              "with taa or tdense, or full with N spp (N steps of the dither)" },
    { .name = "--rr-shadows", .kind = HZ_OPT_FLAG, .flags = IMG, .id = O_RR_SHADOWS, .needs = "--transparency std",
      .help = "with a stochastic --transparency (rr, std, dtaa, dtaa-star, hybrid:X with X > 0): the shaded "
              "fragment's shadow ray takes blended occluders by Russian roulette instead of the deep shadow ray's "
              "transmittance" },
    { .name = "--shutter", .arg = "S", .kind = HZ_OPT_REAL, .lo = 0, .hi = 1,
      .modes = FULL | TAA | TDENSE | ADAPTIVE, .flags = IMG, .id = O_SHUTTER, .sample = "0.5",
      .help = "motion blur: the shutter is open for S of each frame interval 1/hz, centred on the frame's time; "
              "default 0 (no blur)" },
    { .name = "--blur-bvh", .arg = "B", .kind = HZ_OPT_WORD, .words = blur_words, .modes = FULL | TAA | TDENSE | ADAPTIVE,
      .flags = IMG, .id = O_BLUR_BVH, .sample = "interp", .needs = "--shutter 0.5",
      .help = "motion-blur BVH of the native backend: msbvh (seed 002), interp (interpolated BVH) or swept "
              "(static BVH over swept boxes); default msbvh; needs --shutter" },
    { .name = "--rigid", .arg = "R", .kind = HZ_OPT_WORD, .words = rigid_words, .modes = FULL | TAA | TDENSE | ADAPTIVE,
      .flags = IMG, .id = O_RIGID, .sample = "refit", .needs = "--shutter 0.5",
      .help = "motion blur, native backend: instance (default) keeps each group of objects that move rigidly in a "
              "BVH of its own in object space, built once, rays moved into it at their time (seed 002 section "
              "3.2); refit moves their vertices and refits the motion BVH every frame like other motion; needs "
              "--shutter" },
    { .name = "--motion-segments", .arg = "S", .kind = HZ_OPT_WORD, .words = segments_words,
      .modes = FULL | TAA | TDENSE | ADAPTIVE, .id = O_SEGMENTS, .sample = "every-key", .needs = "--shutter 0.5",
      .help = "motion blur, native backend: per-node (default) lets each node of the motion BVH keep as few motion "
              "segments as its content's motion needs (seed 002 section 6.3; less memory, the same image); "
              "every-key keeps a box set at every time key in every node; needs --shutter" },
    { .name = "--backend", .arg = "B", .kind = HZ_OPT_WORD, .words = backend_words, .flags = IMG, .id = O_BACKEND,
      .sample = "embree", .help = "native or embree (builds with Embree); default native" },
    { .name = "--threads", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = HZ_MAX_THREADS, .id = O_THREADS,
      .help = "render threads (the images do not depend on it); default: the machine's cores" },
    { .name = "--start", .arg = "T", .kind = HZ_OPT_REAL, .lo = 0, .hi = 1e9, .flags = IMG, .id = O_START,
      .sample = "0.5", .help = "scene time of the first frame in seconds (kept to the nanosecond); default 0" },
    /* adaptive (seed 003): presample, activity mask, 4 extra samples per active subpixel */
    { .name = "--tau", .arg = "T", .kind = HZ_OPT_REAL, .lo = 0, .hi = 1, .modes = ADAPTIVE, .flags = IMG,
      .id = O_TAU, .sample = "0.3", .noun = "a threshold",
      .help = "--tau-col, --tau-pte and --tau-ste together (the paper's tau_alpha). Thresholds: smaller = more "
              "samples, 1 switches an attribute off" },
    TAU("col", HZ_TAU_COL, "0.6", "colour contrast where no attribute disagrees"),
    TAU("poid", HZ_TAU_POID, "0.05", "primary hit object id"),
    TAU("psn", HZ_TAU_PSN, "0.06", "primary shading normal"),
    TAU("psc", HZ_TAU_PSC, "0.06", "primary shadow count"),
    TAU("pte", HZ_TAU_PTE, "0.6", "primary texture"),
    TAU("soid", HZ_TAU_SOID, "0.05", "mirror hit object id"),
    TAU("ssn", HZ_TAU_SSN, "0.06", "mirror hit shading normal"),
    TAU("ssc", HZ_TAU_SSC, "0.06", "mirror hit shadow count"),
    TAU("ste", HZ_TAU_STE, "0.6", "mirror hit texture"),
    { .name = "--normal-angle", .arg = "D", .kind = HZ_OPT_REAL, .lo = 0, .hi = 90, .modes = ADAPTIVE, .flags = IMG,
      .id = O_NORMAL_ANGLE, .sample = "30", .noun = "an angle", .help = "normals within D degrees agree; default 15" },
    { .name = "--focus-objects", .arg = "L", .kind = HZ_OPT_TEXT, .modes = ADAPTIVE, .flags = IMG, .id = O_FOCUS,
      .sample = "1",
      .help = "attributes count only where these objects are involved: ids or names, comma-separated (`hzrt info "
              "SCENE` lists them); a name takes every object of that name, and a shell pattern (*Wall) every "
              "object it matches; summary.json lists the ids taken; default every object" },
    { .name = "--adaptive-bilinear", .kind = HZ_OPT_FLAG, .modes = ADAPTIVE, .flags = IMG, .id = O_BILINEAR,
      .help = "in a pixel with active subpixels, each inactive one takes the presample's colours interpolated "
              "bilinearly at its own centre, not the pixel's centre colour (the paper's future work; costs 12 "
              "bytes a pixel)" },
    { .name = "--adaptive-footprint", .kind = HZ_OPT_FLAG, .modes = ADAPTIVE, .flags = IMG, .id = O_FOOTPRINT,
      .help = "the presample's textures are the mean over each pixel's footprint on the surface (2x2 taps on the "
              "ray cone's mip level), the filter supersampled pixels apply" },
    { .name = "--adaptive-map", .arg = "F", .kind = HZ_OPT_TEXT, .modes = ADAPTIVE, .flags = HZ_OF_OUTPUT, .id = O_MAP,
      .help = "write the last frame's active subpixels per pixel (black, red, green, blue, white for 0..4) to F "
              "(.png, .ppm or .pfm; its folder must exist; not one of the run's other files)" },
};

#define TABLE_N (sizeof table / sizeof table[0])

/* The options given, each entry once: the list holds the whole table, so however many options a command line
 * repeats, every one is checked for where it acts (a full list once let the options after the 64th through). */
typedef char given_holds_table[sizeof((hz_ropts_t *)0)->given / sizeof((hz_ropts_t *)0)->given[0] >= TABLE_N ? 1 : -1];
static void note_given(const hz_opt_t **given, int *n, const hz_opt_t *t)
{
    for (int g = 0; g < *n; g++)
        if (given[g] == t)
            return;
    given[(*n)++] = t;
}

const hz_opt_t *hz_ropts_table(size_t *n)
{
    *n = TABLE_N;
    return table;
}

void hz_ropts_defaults(hz_ropts_t *r, const char *cmd, hz_render_mode_t mode)
{
    memset(r, 0, sizeof *r);
    hz_render_opts_default(&r->opts);
    r->opts.mode = mode;
    r->backend = HZ_ACCEL_NATIVE;
    r->cmd = cmd;
}

int hz_ropts_take(hz_ropts_t *r, int argc, char **argv, int i)
{
    const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    const hz_opt_t *t = hz_opt_find(table, TABLE_N, o);
    if (!t)
        return 0;
    note_given(r->given, &r->given_n, t);
    if (t->arg && !v) {
        hz_cli_error("%s: %s needs a value %s (try hzrt %s --help)", r->cmd, o, t->arg, r->cmd);
        return -HZ_EXIT_USAGE;
    }
    hz_opt_val_t x;
    if (!hz_opt_value(t, r->cmd, v, &x))
        return -HZ_EXIT_USAGE;
    hz_render_opts_t *ro = &r->opts;
    char why[160];
    switch ((int)t->id) {
    case O_MODE: ro->mode = mode_of_word[x.w]; break;
    case O_SPP:
        if ((long)hz_isqrt_u64((uint64_t)x.n) * (long)hz_isqrt_u64((uint64_t)x.n) != x.n) {
            hz_cli_error("%s: --spp: %ld is not a square (1, 4, 9, 16, ... 1024)", r->cmd, x.n);
            return -HZ_EXIT_USAGE;
        }
        ro->spp = (uint32_t)x.n;
        break;
    case O_MSAA4: ro->msaa4 = true; break;
    case O_ORDERING:
        for (int k = 0; k < HZ_GHAT_RULE_COUNT; k++)
            if (!strcmp(v, hz_ghat_rule_name((hz_ghat_rule_t)k)))
                ro->tdense_rule = (hz_ghat_rule_t)k;
        break;
    case O_NO_RMV: ro->tdense_reflect_mv = false; break;
    case O_TD_GAMMA: ro->tdense_gamma = (float)x.x; break;
    case O_TAA_GAMMA: ro->taa_gamma = (float)x.x; break;
    case O_TAA_CLIP: ro->taa_clip = true; break;
    case O_TAA_CR: ro->taa_catmull_rom = true; break;
    case O_BOUNCES: ro->max_bounces = (uint32_t)x.n; break;
    case O_TRANSP:
        if (!hz_transp_parse(v, &ro->transparency, &ro->hybrid_x)) {
            hz_cli_error("%s: --transparency: '%s' is not exact, rr, std, dtaa, dtaa-star or hybrid:X with X in [0, 1]",
                         r->cmd, v);
            return -HZ_EXIT_USAGE;
        }
        break;
    case O_RR_SHADOWS: ro->rr_shadows = true; break;
    case O_SHUTTER: ro->shutter = (float)x.x; break;
    case O_BLUR_BVH:
        hz_accel_blur_parse(v, &r->blur);
        r->blur_arg = v;
        break;
    case O_RIGID:
        hz_accel_rigid_parse(v, &r->rigid);
        r->rigid_arg = v;
        break;
    case O_SEGMENTS:
        hz_accel_segments_parse(v, &r->segments);
        r->segments_arg = v;
        break;
    case O_BACKEND: r->backend = x.w == 0 ? HZ_ACCEL_NATIVE : HZ_ACCEL_EMBREE; break;
    case O_THREADS: r->threads = (int)x.n; break;
    case O_START: r->start = hz_time_from_s(x.x); break;
    case O_TAU:
        /* the paper's tau_alpha */
        ro->adaptive.tau[HZ_TAU_COL] = ro->adaptive.tau[HZ_TAU_PTE] = ro->adaptive.tau[HZ_TAU_STE] = (float)x.x;
        break;
    case O_NORMAL_ANGLE: ro->adaptive.normal_angle_deg = (float)x.x; break;
    case O_BILINEAR: ro->adaptive.bilinear = 1; break;
    case O_FOOTPRINT: ro->adaptive.footprint = 1; break;
    case O_FOCUS:
        if (!hz_adaptive_cli_focus_ok(v, why, sizeof why)) {
            hz_cli_error("%s: --focus-objects: %s", r->cmd, why);
            return -HZ_EXIT_USAGE;
        }
        r->adaptive.focus = v;
        break;
    case O_MAP:
        if (!hz_adaptive_cli_map_ok(v, why, sizeof why)) {
            hz_cli_error("%s: --adaptive-map: %s", r->cmd, why);
            return -HZ_EXIT_USAGE;
        }
        r->adaptive.map_path = v;
        break;
    default:
        ro->adaptive.tau[t->id - O_TAU_K] = (float)x.x;
        break;
    }
    return t->arg ? 2 : 1;
}

hz_status_t hz_ropts_prepare(void *ctx, const hz_scene_t *scene, hz_render_opts_t *opts, hz_error_t *err)
{
    const hz_ropts_t *ro = ctx;
    hz_status_t s = hz_adaptive_cli_resolve(&ro->adaptive, scene, &opts->adaptive, err);
    if (s == HZ_OK && opts->transparency != HZ_TRANSP_EXACT && !(scene->features & HZ_FEAT_BLEND) && !hz_phase_muted)
        fprintf(stderr, "%s: %s: --transparency %s: the scene has no blended surfaces; it renders as exact\n",
                hz_cli_prog, ro->cmd, hz_transp_name(opts->transparency));
    return s;
}

/* A stochastic method that shades a fragment (hybrid:0 composites exactly). */
static bool stochastic(const hz_render_opts_t *o)
{
    return o->transparency != HZ_TRANSP_EXACT && !(o->transparency == HZ_TRANSP_HYBRID && !(o->hybrid_x > 0.0f));
}

int hz_ropts_check(hz_ropts_t *r)
{
    for (int g = 0; g < r->given_n; g++) {
        const hz_opt_t *t = r->given[g];
        if (t->modes == ADAPTIVE && r->opts.mode != HZ_MODE_ADAPTIVE) {
            hz_cli_error("%s: %s applies only to --mode adaptive (this run is --mode %s, where it does nothing)", r->cmd,
                         t->name, hz_render_mode_name(r->opts.mode));
            return HZ_EXIT_USAGE;
        }
        if (t->modes && !(t->modes & M(r->opts.mode))) {
            char modes[64];
            hz_cli_error("%s: %s does nothing in %s mode: it acts only in %s mode (--mode)", r->cmd, t->name,
                         hz_render_mode_name(r->opts.mode), hz_opt_modes_str(modes, sizeof modes, t->modes));
            return HZ_EXIT_USAGE;
        }
    }
    if (r->blur_arg && !(r->opts.shutter > 0.0f)) {
        hz_cli_error("%s: --blur-bvh %s does nothing without motion blur (give --shutter S > 0)", r->cmd, r->blur_arg);
        return HZ_EXIT_USAGE;
    }
    if (r->rigid_arg && !(r->opts.shutter > 0.0f)) {
        hz_cli_error("%s: --rigid %s does nothing without motion blur (give --shutter S > 0)", r->cmd, r->rigid_arg);
        return HZ_EXIT_USAGE;
    }
    if (r->segments_arg && !(r->opts.shutter > 0.0f)) {
        hz_cli_error("%s: --motion-segments %s does nothing without motion blur (give --shutter S > 0)", r->cmd,
                     r->segments_arg);
        return HZ_EXIT_USAGE;
    }
    if (r->segments_arg && r->backend == HZ_ACCEL_EMBREE) {
        hz_cli_error("%s: --motion-segments shapes the native backend's motion BVH; Embree builds its own motion "
                     "blur (drop --motion-segments or use --backend native)", r->cmd);
        return HZ_EXIT_USAGE;
    }
    if (r->rigid_arg && r->backend == HZ_ACCEL_EMBREE) {
        hz_cli_error("%s: --rigid picks what the native backend does with rigid motion; Embree builds its own "
                     "motion blur (drop --rigid or use --backend native)", r->cmd);
        return HZ_EXIT_USAGE;
    }
    if (r->blur_arg && r->backend == HZ_ACCEL_EMBREE) {
        hz_cli_error("%s: --blur-bvh picks the native backend's BVH; Embree builds its own motion blur (drop "
                     "--blur-bvh or use --backend native)", r->cmd);
        return HZ_EXIT_USAGE;
    }
    if (r->opts.rr_shadows && !stochastic(&r->opts)) {
        char t[32];
        hz_transp_format(t, sizeof t, r->opts.transparency, r->opts.hybrid_x);
        hz_cli_error("%s: --rr-shadows does nothing with --transparency %s: it changes the shadow rays of stochastic "
                     "fragments (--transparency rr, std, dtaa, dtaa-star or hybrid:X with X > 0)", r->cmd, t);
        return HZ_EXIT_USAGE;
    }
    return 0;
}

void hz_ropts_usage(FILE *f)
{
    fputs("render options (any sink, any v-sync source; an option of one mode is refused in the others):\n", f);
    hz_opt_usage(f, table, TABLE_N, 0, 0);
}

static void member(FILE *f, bool *first, const char *key)
{
    fprintf(f, "%s\"%s\": ", *first ? "" : ", ", key);
    *first = false;
}

void hz_ropts_settings(FILE *f, const hz_ropts_t *r, const hz_render_opts_t *o, bool *first)
{
    char key[40], text[64];
    for (size_t k = 0; k < TABLE_N; k++) {
        const hz_opt_t *t = &table[k];
        if (!(t->flags & HZ_OF_IMAGE) || (t->modes && !(t->modes & M(o->mode))))
            continue;
        /* the key: the option's name without dashes (the value is what it set, whatever its sense) */
        switch ((int)t->id) {
        case O_NO_RMV: snprintf(key, sizeof key, "reflected_mv"); break;
        case O_TAU: continue; /* recorded as the three thresholds it sets */
        default: {
            size_t n = 0;
            for (const char *c = t->name + 2; *c && n + 1 < sizeof key; c++)
                key[n++] = *c == '-' ? '_' : *c;
            key[n] = 0;
        }
        }
        member(f, first, key);
        switch ((int)t->id) {
        case O_MODE: fprintf(f, "\"%s\"", hz_render_mode_name(o->mode)); break;
        case O_SPP: fprintf(f, "%u", o->spp); break;
        case O_MSAA4: fputs(o->msaa4 ? "true" : "false", f); break;
        case O_ORDERING: fprintf(f, "\"%s\"", hz_ghat_rule_name(o->tdense_rule)); break;
        case O_NO_RMV: fputs(o->tdense_reflect_mv ? "true" : "false", f); break;
        case O_TD_GAMMA: fprintf(f, "%.6g", (double)o->tdense_gamma); break;
        case O_TAA_GAMMA: fprintf(f, "%.6g", (double)o->taa_gamma); break;
        case O_TAA_CLIP: fputs(o->taa_clip ? "true" : "false", f); break;
        case O_TAA_CR: fputs(o->taa_catmull_rom ? "true" : "false", f); break;
        case O_BOUNCES: fprintf(f, "%u", o->max_bounces); break;
        case O_TRANSP:
            hz_transp_format(text, sizeof text, o->transparency, o->hybrid_x);
            fprintf(f, "\"%s\"", text);
            break;
        case O_RR_SHADOWS: fputs(o->rr_shadows ? "true" : "false", f); break;
        case O_SHUTTER: fprintf(f, "%.6g", (double)o->shutter); break;
        case O_BLUR_BVH:
            fprintf(f, "\"%s\"", !(o->shutter > 0.0f)              ? "none"
                                 : r->backend == HZ_ACCEL_EMBREE ? "embree"
                                                                 : hz_accel_blur_name(r->blur));
            break;
        case O_RIGID:
            fprintf(f, "\"%s\"", !(o->shutter > 0.0f)              ? "none"
                                 : r->backend == HZ_ACCEL_EMBREE ? "embree"
                                                                 : hz_accel_rigid_name(r->rigid));
            break;
        case O_BACKEND: fprintf(f, "\"%s\"", r->backend == HZ_ACCEL_EMBREE ? "embree" : "native"); break;
        case O_START: fprintf(f, "%.9g", (double)r->start * 1e-9); break;
        case O_NORMAL_ANGLE: fprintf(f, "%.6g", (double)o->adaptive.normal_angle_deg); break;
        case O_BILINEAR: fputs(o->adaptive.bilinear ? "true" : "false", f); break;
        case O_FOOTPRINT: fputs(o->adaptive.footprint ? "true" : "false", f); break;
        case O_FOCUS:
            fputc('[', f);
            for (uint32_t i = 0; i < o->adaptive.focus_count; i++)
                fprintf(f, "%s%u", i ? ", " : "", o->adaptive.focus[i]);
            fputc(']', f);
            break;
        default:
            if (t->id >= O_TAU_K)
                fprintf(f, "%.6g", (double)o->adaptive.tau[t->id - O_TAU_K]);
            else
                fputs("null", f);
            break;
        }
    }
}
