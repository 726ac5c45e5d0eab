/* The render options' table and parser (see renderopts.h). */
#include "renderopts.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "hz/config.h"
#include "hz/fixed.h"
#include "transp_opt.h"

#define MODE_BIT(m) (1u << (m))
#define ALL_MODES ((1u << HZ_MODE_COUNT) - 1u)

typedef enum kind { K_FLAG, K_INT, K_REAL, K_WORD, K_SPECIAL } kind_t;

typedef enum opt_id {
    O_MODE, O_SPP, O_MSAA4, O_ORDERING, O_NO_RMV, O_TD_GAMMA, O_TAA_GAMMA, O_TAA_CLIP, O_TAA_CR, O_BOUNCES,
    O_TRANSP, O_RR_SHADOWS, O_SHUTTER, O_BLUR_BVH, O_BACKEND, O_THREADS, O_START
} opt_id_t;

static const char *const mode_words[] = { "tdense", "full", "taa", "adaptive", NULL };
static const char *const backend_words[] = { "native", "embree", NULL };
static const char *const blur_words[] = { "msbvh", "interp", "swept", NULL };
static const char *const ordering_words[] = { "full", "dominant", "shear-up", "shear-down", "hourglass", "bowtie", NULL };

typedef struct opt {
    const char *name, *arg;   /* arg NULL: a flag */
    kind_t kind;
    double lo, hi;            /* K_INT, K_REAL: the closed range (lo_open: lo excluded) */
    int lo_open;
    const char *const *words; /* K_WORD */
    unsigned modes;           /* the modes it acts in */
    opt_id_t id;
    const char *help;
} opt_t;

static const opt_t table[] = {
    { "--mode", "M", K_WORD, 0, 0, 0, mode_words, ALL_MODES, O_MODE,
      "tdense (one sample per 2x2 tile per frame, temporally dense composite), full (N samples per pixel), taa (1 "
      "jittered sample + temporal resolve) or adaptive (selective and adaptive supersampling)" },
    { "--spp", "N", K_INT, 1, 1024, 0, NULL, MODE_BIT(HZ_MODE_FULL), O_SPP,
      "samples per pixel, a square (1, 4, 9, ...); default 1" },
    { "--msaa4", NULL, K_FLAG, 0, 0, 0, NULL, MODE_BIT(HZ_MODE_FULL), O_MSAA4,
      "4 spp at the fixed 4x MSAA positions (what tdense converges to)" },
    { "--ordering", "R", K_WORD, 0, 0, 0, ordering_words, MODE_BIT(HZ_MODE_TDENSE), O_ORDERING,
      "tile orderings: full (the paper's adaptive choice), dominant, shear-up, shear-down, hourglass or bowtie; "
      "default full" },
    { "--no-reflected-mv", NULL, K_FLAG, 0, 0, 0, NULL, MODE_BIT(HZ_MODE_TDENSE), O_NO_RMV,
      "mirrors use their own motion, not the reflected hit's" },
    { "--tdense-gamma", "G", K_REAL, 0, 16, 1, NULL, MODE_BIT(HZ_MODE_TDENSE), O_TD_GAMMA,
      "variance box width in standard deviations; default 1" },
    { "--taa-gamma", "G", K_REAL, 0, 16, 1, NULL, MODE_BIT(HZ_MODE_TAA), O_TAA_GAMMA,
      "variance box width in standard deviations; default 1" },
    { "--taa-clip", NULL, K_FLAG, 0, 0, 0, NULL, MODE_BIT(HZ_MODE_TAA), O_TAA_CLIP,
      "clip history towards the box centre (default: clamp per channel)" },
    { "--taa-catmull-rom", NULL, K_FLAG, 0, 0, 0, NULL, MODE_BIT(HZ_MODE_TAA), O_TAA_CR,
      "fetch history with Catmull-Rom (default: bilinear)" },
    { "--bounces", "N", K_INT, 0, 3, 0, NULL, ALL_MODES, O_BOUNCES, "mirror reflections per path; default 3" },
    { "--transparency", "T", K_SPECIAL, 0, 0, 0, NULL, ALL_MODES, O_TRANSP,
      "blended surfaces: exact (front-to-back compositing, deep shadow rays), rr (Russian roulette), std "
      "(spatio-temporal dither), dtaa, dtaa-star, or hybrid:X (exact while the visibility > X in [0, 1], then one "
      "std decision); default exact. The stochastic ones shade one fragment per pixel: use them with taa or "
      "tdense, or full with N spp (N steps of the dither)" },
    { "--rr-shadows", NULL, K_FLAG, 0, 0, 0, NULL, ALL_MODES, O_RR_SHADOWS,
      "stochastic transparency: the shaded fragment's shadow ray takes blended occluders by Russian roulette "
      "instead of the deep shadow ray's transmittance" },
    { "--shutter", "S", K_REAL, 0, 1, 0, NULL, MODE_BIT(HZ_MODE_FULL) | MODE_BIT(HZ_MODE_TAA) | MODE_BIT(HZ_MODE_TDENSE),
      O_SHUTTER, "motion blur: the shutter is open for S of each frame interval 1/hz, centred on the frame's "
      "time; default 0 (no blur; adaptive mode has none)" },
    { "--blur-bvh", "B", K_WORD, 0, 0, 0, blur_words, ALL_MODES, O_BLUR_BVH,
      "motion-blur BVH of the native backend: msbvh (seed 002), interp (interpolated BVH) or swept (static BVH over "
      "swept boxes); default msbvh; needs --shutter" },
    { "--backend", "B", K_WORD, 0, 0, 0, backend_words, ALL_MODES, O_BACKEND,
      "native or embree (host builds); default native" },
    { "--threads", "N", K_INT, 1, HZ_MAX_THREADS, 0, NULL, ALL_MODES, O_THREADS,
      "render threads; default: the machine's cores" },
    { "--start", "T", K_REAL, 0, 1e9, 0, NULL, ALL_MODES, O_START,
      "scene time of the first frame in seconds (kept to the nanosecond); default 0" },
};

void hz_ropts_defaults(hz_ropts_t *r, const char *cmd, hz_render_mode_t mode)
{
    memset(r, 0, sizeof *r);
    hz_render_opts_default(&r->opts);
    r->opts.mode = mode;
    r->backend = HZ_ACCEL_NATIVE;
    r->cmd = cmd;
}

static int word_index(const char *const *words, const char *v)
{
    for (int k = 0; v && words[k]; k++)
        if (!strcmp(words[k], v))
            return k;
    return -1;
}

static void words_list(char *buf, size_t cap, const char *const *words)
{
    size_t n = 0;
    buf[0] = 0;
    for (int k = 0; words[k] && n < cap; k++)
        n += (size_t)snprintf(buf + n, cap - n, "%s%s", k ? (words[k + 1] ? ", " : " or ") : "", words[k]);
}

int hz_ropts_take(hz_ropts_t *r, int argc, char **argv, int i)
{
    const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    int used = hz_adaptive_cli_option(o, v, &r->opts.adaptive, &r->adaptive);
    if (used < 0)
        return used;
    if (used > 0) {
        if (r->given_n < (int)(sizeof r->given / sizeof r->given[0]))
            r->given[r->given_n++] = o;
        return used;
    }
    const opt_t *t = NULL;
    for (size_t k = 0; k < sizeof table / sizeof table[0] && !t; k++)
        if (!strcmp(o, table[k].name))
            t = &table[k];
    if (!t)
        return 0;
    if (r->given_n < (int)(sizeof r->given / sizeof r->given[0]))
        r->given[r->given_n++] = o;
    if (t->arg && !v) {
        hz_cli_error("%s: %s needs a value %s (try hzrt %s --help)", r->cmd, o, t->arg, r->cmd);
        return -HZ_EXIT_USAGE;
    }
    long n = 0;
    double x = 0;
    int w = -1;
    char list[160];
    switch (t->kind) {
    case K_INT:
        if (!hz_cli_parse_long(o, v, (long)t->lo, (long)t->hi, &n))
            return -HZ_EXIT_USAGE;
        break;
    case K_REAL: {
        char *end = NULL;
        errno = 0;
        x = strtod(v, &end);
        bool ok = *v && !*end && !errno && isfinite(x) && (t->lo_open ? x > t->lo : x >= t->lo) && x <= t->hi;
        if (!ok) {
            hz_cli_error("%s: %s: '%s' is not a number in %c%g, %g]", r->cmd, o, v, t->lo_open ? '(' : '[', t->lo,
                         t->hi);
            return -HZ_EXIT_USAGE;
        }
        break;
    }
    case K_WORD:
        w = word_index(t->words, v);
        if (w < 0) {
            words_list(list, sizeof list, t->words);
            hz_cli_error("%s: %s: '%s' is not %s", r->cmd, o, v, list);
            return -HZ_EXIT_USAGE;
        }
        break;
    default:
        break;
    }
    hz_render_opts_t *ro = &r->opts;
    switch (t->id) {
    case O_MODE:
        ro->mode = w == 0 ? HZ_MODE_TDENSE : w == 1 ? HZ_MODE_FULL : w == 2 ? HZ_MODE_TAA : HZ_MODE_ADAPTIVE;
        break;
    case O_SPP:
        if ((long)hz_isqrt_u64((uint64_t)n) * (long)hz_isqrt_u64((uint64_t)n) != n) {
            hz_cli_error("%s: --spp: %ld is not a square (1, 4, 9, 16, ... 1024)", r->cmd, n);
            return -HZ_EXIT_USAGE;
        }
        ro->spp = (uint32_t)n;
        break;
    case O_MSAA4: ro->msaa4 = true; break;
    case O_ORDERING:
        for (int k = 0; k < HZ_GHAT_RULE_COUNT; k++)
            if (!strcmp(v, hz_ghat_rule_name((hz_ghat_rule_t)k)))
                ro->tdense_rule = (hz_ghat_rule_t)k;
        break;
    case O_NO_RMV: ro->tdense_reflect_mv = false; break;
    case O_TD_GAMMA: ro->tdense_gamma = (float)x; break;
    case O_TAA_GAMMA: ro->taa_gamma = (float)x; break;
    case O_TAA_CLIP: ro->taa_clip = true; break;
    case O_TAA_CR: ro->taa_catmull_rom = true; break;
    case O_BOUNCES: ro->max_bounces = (uint32_t)n; break;
    case O_TRANSP:
        if (!hz_transp_parse(v, &ro->transparency, &ro->hybrid_x)) {
            hz_cli_error("%s: --transparency: '%s' is not exact, rr, std, dtaa, dtaa-star or hybrid:X with X in [0, 1]",
                         r->cmd, v);
            return -HZ_EXIT_USAGE;
        }
        break;
    case O_RR_SHADOWS: ro->rr_shadows = true; break;
    case O_SHUTTER: ro->shutter = (float)x; break;
    case O_BLUR_BVH:
        hz_accel_blur_parse(v, &r->blur);
        r->blur_arg = v;
        break;
    case O_BACKEND: r->backend = w == 0 ? HZ_ACCEL_NATIVE : HZ_ACCEL_EMBREE; break;
    case O_THREADS: r->threads = (int)n; break;
    case O_START: r->start = hz_time_from_s(x); break;
    }
    return t->arg ? 2 : 1;
}

int hz_ropts_check(hz_ropts_t *r)
{
    for (int g = 0; g < r->given_n; g++)
        for (size_t k = 0; k < sizeof table / sizeof table[0]; k++)
            if (!strcmp(r->given[g], table[k].name) && !(table[k].modes & MODE_BIT(r->opts.mode))) {
                hz_cli_error("%s: %s does nothing in %s mode (it acts in %s%s%s%s)", r->cmd, table[k].name,
                             hz_render_mode_name(r->opts.mode),
                             table[k].modes & MODE_BIT(HZ_MODE_FULL) ? "full " : "",
                             table[k].modes & MODE_BIT(HZ_MODE_TAA) ? "taa " : "",
                             table[k].modes & MODE_BIT(HZ_MODE_TDENSE) ? "tdense " : "", "mode");
                return HZ_EXIT_USAGE;
            }
    if (hz_adaptive_cli_check(&r->adaptive, r->opts.mode))
        return HZ_EXIT_USAGE;
    if (r->blur_arg && !(r->opts.shutter > 0.0f)) {
        hz_cli_error("%s: --blur-bvh %s does nothing without motion blur (give --shutter S > 0)", r->cmd, r->blur_arg);
        return HZ_EXIT_USAGE;
    }
    if (r->blur_arg && r->backend == HZ_ACCEL_EMBREE) {
        hz_cli_error("%s: --blur-bvh picks the native backend's BVH; Embree builds its own motion blur (drop "
                     "--blur-bvh or use --backend native)", r->cmd);
        return HZ_EXIT_USAGE;
    }
    return 0;
}

void hz_ropts_usage(FILE *f)
{
    fputs("render options (every sink, every v-sync source):\n", f);
    for (size_t k = 0; k < sizeof table / sizeof table[0]; k++) {
        const opt_t *t = &table[k];
        char head[40], lim[96] = "";
        snprintf(head, sizeof head, "%s%s%s", t->name, t->arg ? " " : "", t->arg ? t->arg : "");
        if (t->kind == K_INT)
            snprintf(lim, sizeof lim, " [%g..%g]", t->lo, t->hi);
        else if (t->kind == K_REAL)
            snprintf(lim, sizeof lim, " [%s%g..%g]", t->lo_open ? ">" : "", t->lo, t->hi);
        char modes[48] = "";
        if (t->modes != ALL_MODES)
            snprintf(modes, sizeof modes, " (%s%s%s%s only)", t->modes & MODE_BIT(HZ_MODE_FULL) ? "full " : "",
                     t->modes & MODE_BIT(HZ_MODE_TAA) ? "taa " : "", t->modes & MODE_BIT(HZ_MODE_TDENSE) ? "tdense " : "",
                     "mode");
        /* wrapped at about 116 columns under the option */
        fprintf(f, "  %-19s", head);
        const char *s = t->help;
        int col = 21, first = 1;
        char text[1024];
        snprintf(text, sizeof text, "%s%s%s", s, lim, modes);
        for (char *word = strtok(text, " "); word; word = strtok(NULL, " ")) {
            int len = (int)strlen(word);
            if (!first && col + 1 + len > 116) {
                fprintf(f, "\n%21s", "");
                col = 21;
                first = 1;
            }
            fprintf(f, "%s%s", first ? "" : " ", word);
            col += len + !first;
            first = 0;
        }
        fputc('\n', f);
    }
    hz_adaptive_cli_usage(f);
}
