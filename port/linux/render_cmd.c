/* `hzrt render`: loads a scene, builds the accel, renders a sequence on the static thread pool and writes the
 * file sinks (Y4M video, PNG/PFM of the last frame) and a summary (stdout + JSON). See `hzrt render --help`. */
#include "render_cmd.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "accel_backend.h"
#include "adaptive_cli.h"
#include "blur_setup.h"
#include "cli.h"
#include "clock.h"
#include "fileio.h"
#include "hz/render.h"
#include "imageio.h"
#include "modeplan.h"
#include "pools.h"
#include "phase.h"
#include "render_run.h"
#include "scenefile.h"
#include "summary.h"
#include "threads.h"
#include "transp_opt.h"

#define MAX_FRAMES 100000

typedef struct args {
    const char *scene;
    const char *out_dir;
    hz_render_opts_t opts;
    uint32_t hz;
    uint32_t frames;
    int threads;
    hz_time_ns_t start;
    hz_accel_backend_t backend;
    hz_accel_blur_t blur;
    const char *blur_arg; /* --blur-bvh as given (NULL: default) */
    bool write_y4m, write_png, write_pfm, quiet;
    hz_adaptive_cli_t adaptive;
    const char *given[64]; /* the options on the command line, for the mode table below */
    int given_n;
} args_t;

/* Options that act only in some modes. Given in another mode they would do nothing, so they are refused (and a
 * summary never reports them). A mode-specific option joins by adding its row. */
#define IN_MODE(m) (1u << (m))
typedef struct mode_opt {
    const char *name;
    unsigned modes; /* IN_MODE(...) bits of the modes it acts in */
    const char *what;
} mode_opt_t;
static const mode_opt_t mode_opts[] = {
    { "--spp", IN_MODE(HZ_MODE_FULL), "samples per pixel of full mode (tdense traces one sample per 2x2 tile "
                                      "per frame, taa one jittered sample per pixel)" },
    { "--msaa4", IN_MODE(HZ_MODE_FULL), "the 4x MSAA positions of full mode" },
    { "--ordering", IN_MODE(HZ_MODE_TDENSE), "the tile orderings of tdense mode" },
    { "--no-reflected-mv", IN_MODE(HZ_MODE_TDENSE), "the mirrors' motion in tdense mode" },
    { "--tdense-gamma", IN_MODE(HZ_MODE_TDENSE), "the variance box of tdense mode" },
    { "--taa-gamma", IN_MODE(HZ_MODE_TAA), "the variance box of taa mode" },
    { "--taa-clip", IN_MODE(HZ_MODE_TAA), "the history constraint of taa mode" },
    { "--taa-catmull-rom", IN_MODE(HZ_MODE_TAA), "the history filter of taa mode" },
};

static bool check_mode_opts(const args_t *a)
{
    for (int g = 0; g < a->given_n; g++)
        for (size_t k = 0; k < sizeof mode_opts / sizeof mode_opts[0]; k++)
            if (!strcmp(a->given[g], mode_opts[k].name) && !(mode_opts[k].modes & IN_MODE(a->opts.mode))) {
                hz_cli_error("render: %s does nothing in %s mode: it sets %s", mode_opts[k].name,
                             hz_render_mode_name(a->opts.mode), mode_opts[k].what);
                return false;
            }
    return true;
}

static int default_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > HZ_MAX_THREADS ? HZ_MAX_THREADS : (int)n;
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: hzrt render SCENE|builtin [options]\n"
            "\n"
            "Renders SCENE (a .hzb file from tools/bake, or the built-in scene) for a number of display frames\n"
            "at a simulated refresh rate and writes the results to the output folder:\n"
            "  frames.y4m    the sequence (when more than one frame; plays in mpv/ffplay, converts with ffmpeg)\n"
            "  last.png      the last frame, 8-bit sRGB\n"
            "  last.pfm      the last frame, linear float (with --pfm)\n"
            "  summary.json  what the run did and how fast (also printed)\n"
            "\n"
            "options:\n"
            "  --mode M          tdense (one sample per 2x2 tile per frame, temporally dense composite), full (N\n"
            "                    samples per pixel), taa (1 jittered sample + temporal resolve) or adaptive\n"
            "                    (selective and adaptive supersampling, see below); default tdense\n"
            "                    (a tdense frame holds a quarter of fresh samples: run 4 frames or more; a still\n"
            "                    view reaches the 4x MSAA average after 16)\n"
            "  --spp N           samples per pixel in full mode: 1, 4, 9, ... 1024 (squares); default 1\n"
            "  --msaa4           full mode, 4 spp at the fixed 4x MSAA positions (what tdense converges to)\n"
            "  --ordering R      tdense tile orderings: full (the paper's adaptive choice), dominant, shear-up,\n"
            "                    shear-down, hourglass or bowtie; default full\n"
            "  --no-reflected-mv tdense: mirrors use their own motion, not the reflected hit's\n"
            "  --tdense-gamma G  tdense variance box width in standard deviations; default 1\n"
            "  --size WxH        image size; default the board's display (%dx%d)\n"
            "  --hz N            simulated display refresh: frame n shows scene time start + n / N; default %d\n"
            "  --frames N        display frames to render; default 1\n"
            "  --start T         scene time of the first frame in seconds (0..1e9, kept to the nanosecond); default 0\n"
            "  --threads N       render threads (1..%d); default: the machine's cores\n"
            "  --backend B       native or embree (host builds); default native\n"
            "  --bounces N       mirror reflections per path, 0..3; default 3\n"
            "  --shutter S       motion blur: the shutter is open for S (0..1) of each frame interval 1/hz,\n"
            "                    centred on the frame's time; default 0 (no blur)\n"
            "  --blur-bvh B      motion-blur BVH of the native backend: msbvh (seed 002), interp (interpolated\n"
            "                    BVH) or swept (static BVH over swept boxes); default msbvh; needs --shutter\n"
            "  --taa-gamma G     TAA variance box width in standard deviations; default 1\n"
            "  --taa-clip        clip history towards the box centre (default: clamp per channel)\n"
            "  --taa-catmull-rom fetch history with Catmull-Rom (default: bilinear)\n"
            "  --transparency T  blended surfaces: exact (front-to-back compositing, deep shadow rays), rr\n"
            "                    (Russian roulette), std (spatio-temporal dither), dtaa, dtaa-star, or hybrid:X\n"
            "                    (exact while the visibility > X in [0, 1], then one std decision); default exact.\n"
            "                    The stochastic ones shade one fragment per pixel: use them with --mode taa or\n"
            "                    tdense, or full with N spp (N steps of the dither)\n"
            "  --rr-shadows      stochastic transparency: the shaded fragment's shadow ray takes blended occluders\n"
            "                    by Russian roulette (one binary ray) instead of the deep shadow ray's transmittance\n"
            "  --out DIR         output folder (created); default out\n"
            "  --no-y4m          do not write the video\n"
            "  --pfm             also write last.pfm\n"
            "  --quiet           no progress bar and no printed summary (the JSON is still written)\n"
            "  -h, --help        this text\n"
            "\n"
            "Options of one mode (--spp, --msaa4: full; --ordering, --no-reflected-mv, --tdense-gamma: tdense;\n"
            "--taa-*: taa) are refused in the others, where they would do nothing. A scene without lights gets a\n"
            "default light (the summary says so).\n"
            "\n"
            "exit status: 0 ok, 2 bad command line, 64+N failure with hz status N (66: the scene or the frame\n"
            "does not fit the board's arenas, 68/70: malformed or corrupt scene, 73: a file that cannot be read or\n"
            "written, e.g. an --out that is not writable; killed by a signal, it removes its temporary files)\n",
            HZ_DISPLAY_WIDTH, HZ_DISPLAY_HEIGHT, HZ_DISPLAY_HZ, HZ_MAX_THREADS);
    hz_adaptive_cli_usage(f);
}

static int parse(int argc, char **argv, args_t *a)
{
    memset(a, 0, sizeof *a);
    hz_render_opts_default(&a->opts);
    a->opts.mode = HZ_MODE_TDENSE;
    a->opts.width = HZ_DISPLAY_WIDTH;
    a->opts.height = HZ_DISPLAY_HEIGHT;
    a->hz = HZ_DISPLAY_HZ;
    a->frames = 1;
    a->threads = default_threads();
    a->out_dir = "out";
    a->backend = HZ_ACCEL_NATIVE;
    a->write_y4m = true;
    a->write_png = true;
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        long n;
        if (o[0] == '-' && a->given_n < (int)(sizeof a->given / sizeof a->given[0]))
            a->given[a->given_n++] = o;
        int used = hz_adaptive_cli_option(o, v, &a->opts.adaptive, &a->adaptive);
        if (used < 0)
            return -used;
        if (used > 0) {
            i += used - 1;
            continue;
        }
        if (!strcmp(o, "-h") || !strcmp(o, "--help")) {
            usage(stdout);
            return -1;
        } else if (!strcmp(o, "--mode")) {
            if (v && !strcmp(v, "full"))
                a->opts.mode = HZ_MODE_FULL;
            else if (v && !strcmp(v, "taa"))
                a->opts.mode = HZ_MODE_TAA;
            else if (v && !strcmp(v, "tdense"))
                a->opts.mode = HZ_MODE_TDENSE;
            else if (v && !strcmp(v, "adaptive"))
                a->opts.mode = HZ_MODE_ADAPTIVE;
            else {
                hz_cli_error("render: --mode: '%s' is not tdense, full, taa or adaptive", v ? v : "");
                return HZ_EXIT_USAGE;
            }
            i++;
        } else if (!strcmp(o, "--msaa4")) {
            a->opts.msaa4 = true;
        } else if (!strcmp(o, "--ordering")) {
            int rule = -1;
            for (int k = 0; v && k < HZ_GHAT_RULE_COUNT; k++)
                if (!strcmp(v, hz_ghat_rule_name((hz_ghat_rule_t)k)))
                    rule = k;
            if (rule < 0) {
                hz_cli_error("render: --ordering: '%s' is not full, dominant, shear-up, shear-down, hourglass or "
                             "bowtie", v ? v : "");
                return HZ_EXIT_USAGE;
            }
            a->opts.tdense_rule = (hz_ghat_rule_t)rule, i++;
        } else if (!strcmp(o, "--no-reflected-mv")) {
            a->opts.tdense_reflect_mv = false;
        } else if (!strcmp(o, "--tdense-gamma")) {
            char *end = NULL;
            double g = v ? strtod(v, &end) : 0.0;
            if (!v || !*v || *end || !(g > 0.0 && g <= 16.0)) {
                hz_cli_error("render: --tdense-gamma: '%s' is not a number in (0, 16]", v ? v : "");
                return HZ_EXIT_USAGE;
            }
            a->opts.tdense_gamma = (float)g, i++;
        } else if (!strcmp(o, "--spp")) {
            if (!hz_cli_parse_long(o, v, 1, 1024, &n))
                return HZ_EXIT_USAGE;
            a->opts.spp = (uint32_t)n, i++;
        } else if (!strcmp(o, "--size")) {
            int w, h;
            if (!hz_cli_parse_size(o, v, 8, 8192, &w, &h))
                return HZ_EXIT_USAGE;
            a->opts.width = (uint32_t)w, a->opts.height = (uint32_t)h, i++;
        } else if (!strcmp(o, "--hz")) {
            if (!hz_cli_parse_long(o, v, 1, 1000, &n))
                return HZ_EXIT_USAGE;
            a->hz = (uint32_t)n, i++;
        } else if (!strcmp(o, "--frames")) {
            if (!hz_cli_parse_long(o, v, 1, MAX_FRAMES, &n))
                return HZ_EXIT_USAGE;
            a->frames = (uint32_t)n, i++;
        } else if (!strcmp(o, "--threads")) {
            if (!hz_cli_parse_long(o, v, 1, HZ_MAX_THREADS, &n))
                return HZ_EXIT_USAGE;
            a->threads = (int)n, i++;
        } else if (!strcmp(o, "--bounces")) {
            if (!hz_cli_parse_long(o, v, 0, 3, &n))
                return HZ_EXIT_USAGE;
            a->opts.max_bounces = (uint32_t)n, i++;
        } else if (!strcmp(o, "--start")) {
            char *end = NULL;
            double t = v ? strtod(v, &end) : 0.0;
            if (!v || !*v || *end || !isfinite(t) || t < 0.0 || t > 1e9) {
                hz_cli_error("render: --start: '%s' is not a time in seconds in [0, 1e9]", v ? v : "");
                return HZ_EXIT_USAGE;
            }
            a->start = hz_time_from_s(t), i++;
        } else if (!strcmp(o, "--taa-gamma")) {
            char *end = NULL;
            double g = v ? strtod(v, &end) : 0.0;
            if (!v || !*v || *end || !(g > 0.0 && g <= 16.0)) {
                hz_cli_error("render: --taa-gamma: '%s' is not a number in (0, 16]", v ? v : "");
                return HZ_EXIT_USAGE;
            }
            a->opts.taa_gamma = (float)g, i++;
        } else if (!strcmp(o, "--transparency")) {
            if (!hz_transp_parse(v, &a->opts.transparency, &a->opts.hybrid_x)) {
                hz_cli_error("render: --transparency: '%s' is not exact, rr, std, dtaa, dtaa-star or hybrid:X "
                             "with X in [0, 1]", v ? v : "");
                return HZ_EXIT_USAGE;
            }
            i++;
        } else if (!strcmp(o, "--rr-shadows")) {
            a->opts.rr_shadows = true;
        } else if (!strcmp(o, "--taa-clip")) {
            a->opts.taa_clip = true;
        } else if (!strcmp(o, "--taa-catmull-rom")) {
            a->opts.taa_catmull_rom = true;
        } else if (!strcmp(o, "--backend")) {
            if (v && !strcmp(v, "native"))
                a->backend = HZ_ACCEL_NATIVE;
            else if (v && !strcmp(v, "embree"))
                a->backend = HZ_ACCEL_EMBREE;
            else {
                hz_cli_error("render: --backend: '%s' is not native or embree", v ? v : "");
                return HZ_EXIT_USAGE;
            }
            i++;
        } else if (!strcmp(o, "--shutter")) {
            char *end = NULL;
            double sh = v ? strtod(v, &end) : 0.0;
            if (!v || !*v || *end || !(sh >= 0.0 && sh <= 1.0)) {
                hz_cli_error("render: --shutter: '%s' is not a fraction in [0, 1]", v ? v : "");
                return HZ_EXIT_USAGE;
            }
            a->opts.shutter = (float)sh, i++;
        } else if (!strcmp(o, "--blur-bvh")) {
            if (!v || !hz_accel_blur_parse(v, &a->blur)) {
                hz_cli_error("render: --blur-bvh: '%s' is not msbvh, interp or swept", v ? v : "");
                return HZ_EXIT_USAGE;
            }
            a->blur_arg = v, i++;
        } else if (!strcmp(o, "--out")) {
            if (!v || !*v) {
                hz_cli_error("render: --out: missing folder");
                return HZ_EXIT_USAGE;
            }
            a->out_dir = v, i++;
        } else if (!strcmp(o, "--no-y4m")) {
            a->write_y4m = false;
        } else if (!strcmp(o, "--pfm")) {
            a->write_pfm = true;
        } else if (!strcmp(o, "--quiet")) {
            a->quiet = true;
        } else if (o[0] == '-') {
            hz_cli_error("render: unknown option '%s' (try hzrt render --help)", o);
            return HZ_EXIT_USAGE;
        } else if (!a->scene) {
            a->scene = o;
        } else {
            hz_cli_error("render: more than one scene given ('%s', '%s')", a->scene, o);
            return HZ_EXIT_USAGE;
        }
    }
    if (!a->scene) {
        hz_cli_error("render: which scene? (a .hzb file or `builtin`; try hzrt render --help)");
        return HZ_EXIT_USAGE;
    }
    if (a->blur_arg && !(a->opts.shutter > 0.0f)) {
        hz_cli_error("render: --blur-bvh %s does nothing without motion blur (give --shutter S > 0)", a->blur_arg);
        return HZ_EXIT_USAGE;
    }
    if (a->blur_arg && a->backend == HZ_ACCEL_EMBREE) {
        hz_cli_error("render: --blur-bvh picks the native backend's BVH; Embree builds its own motion blur "
                     "(drop --blur-bvh or use --backend native)");
        return HZ_EXIT_USAGE;
    }
    a->opts.frame_hz = a->hz;
    if (hz_adaptive_cli_check(&a->adaptive, a->opts.mode) || !check_mode_opts(a))
        return HZ_EXIT_USAGE;
    hz_error_t err;
    if (hz_render_opts_check(&a->opts, &err) != HZ_OK) {
        hz_cli_error("render: %s", err.msg);
        return HZ_EXIT_USAGE;
    }
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double percentile(const double *sorted, uint32_t n, double p)
{
    if (n == 0)
        return 0.0;
    double idx = p * (n - 1);
    uint32_t lo = (uint32_t)idx;
    uint32_t hi = lo + 1 < n ? lo + 1 : lo;
    return sorted[lo] + (sorted[hi] - sorted[lo]) * (idx - lo);
}

static void progress(uint32_t done, uint32_t total, double ms)
{
    const int width = 30;
    int fill = (int)((double)done / total * width);
    fprintf(stderr, "\r[%.*s%*s] %u/%u frames  %.2f ms/frame ", fill, "==============================",
            width - fill, "", done, total, ms);
    if (done == total)
        fputc('\n', stderr);
    fflush(stderr);
}

static double frame_ms[MAX_FRAMES];
static double sorted_ms[MAX_FRAMES];

int hz_cmd_render(int argc, char **argv)
{
    args_t a;
    int rc = parse(argc, argv, &a);
    if (rc)
        return rc < 0 ? 0 : rc;
    hz_phase_muted = a.quiet;
    hz_error_t err;
    hz_pools_t *pools = hz_pools_get();
    if (!pools) {
        hz_cli_error("render: could not set up the static arenas");
        return hz_status_exit_code(HZ_E_INTERNAL);
    }
    char created[1024];
    if (hz_out_dir_prepare(a.out_dir, created, sizeof created, &err) != HZ_OK)
        return hz_cli_report(&err);
    if (created[0] && !a.quiet)
        fprintf(stderr, "%s: render: --out: created %s\n", hz_cli_prog, created);

    hz_scene_t scene;
    if (hz_scenefile_open(a.scene, pools, &scene, &err) != HZ_OK)
        return hz_cli_report(&err);
    if (hz_adaptive_cli_resolve(&a.adaptive, &scene, &a.opts.adaptive, &err) != HZ_OK)
        return hz_cli_report(&err);
    if (a.opts.transparency != HZ_TRANSP_EXACT && !(scene.features & HZ_FEAT_BLEND) && !a.quiet)
        fprintf(stderr, "%s: render: --transparency %s: %s has no blended surfaces; it renders as exact\n",
                hz_cli_prog, hz_transp_name(a.opts.transparency), a.scene);
    /* Refuse up front, before the accel build, with the numbers `hzrt info` prints. */
    hz_render_plan_t plan;
    char why[256];
    if (!hz_modeplan_check(&scene, pools, &a.opts, a.threads, &plan, why, sizeof why)) {
        hz_cli_error("render: a %ux%u %s render of %s does not fit board %s: %s (hzrt info %s shows every mode)",
                     a.opts.width, a.opts.height, hz_render_mode_name(a.opts.mode), a.scene, HZ_BOARD_NAME, why,
                     a.scene);
        return hz_status_exit_code(HZ_E_NO_MEMORY);
    }
    /* The pool starts before the build: a native build runs its binning and subtrees on it (the same tree for
     * any thread count). */
    if (hz_threads_start(a.threads, &err) != HZ_OK)
        return hz_cli_report(&err);
    int64_t t0 = hz_clock_ns();
    hz_accel_t *accel = NULL;
    static hz_posekeys_t keys; /* motion blur: the scene's pose across the shutter (opts.keys) */
    hz_phase_t prog;
    hz_accel_config_t acfg;
    hz_accel_config_default(&acfg);
    acfg.progress = hz_phase_accel, acfg.progress_user = &prog;
    if (a.backend == HZ_ACCEL_NATIVE)
        hz_threads_accel_hook(&acfg);
    hz_phase_begin(&prog, a.quiet, "%s build of %s (%u triangles)", hz_accel_backend_name(a.backend), a.scene,
                   scene.triangle_count);
    hz_status_t bs = hz_blur_build_cfg(&scene, &a.opts, a.backend, a.blur, &acfg, pools, &keys, &accel, &err);
    hz_phase_end(&prog);
    if (bs != HZ_OK) {
        hz_threads_stop();
        return hz_cli_report(&err);
    }
    double build_ms = (hz_clock_ns() - t0) * 1e-6;

    hz_renderer_t *r = NULL;
    if (hz_render_create(&r, &scene, accel, &a.opts, &pools->frame, pools->thread, (uint32_t)a.threads, &err) !=
        HZ_OK) {
        hz_threads_stop();
        hz_accel_release(accel);
        return hz_cli_report(&err);
    }

    char path[4096];
    hz_y4m_t y4m;
    bool y4m_open = false;
    if (a.write_y4m && a.frames > 1) {
        hz_y4m_opts_t yo = { HZ_Y4M_C420JPEG, HZ_Y4M_BT709, true, a.hz, 1 };
        snprintf(path, sizeof path, "%s/frames.y4m", a.out_dir);
        if (hz_y4m_open(&y4m, path, a.opts.width, a.opts.height, &yo, &err) != HZ_OK) {
            rc = hz_cli_report(&err);
            goto done;
        }
        y4m_open = true;
    }

    bool show = !a.quiet && hz_cli_stderr_is_tty() && a.frames > 1;
    int64_t run0 = hz_clock_ns(), last_progress = run0;
    for (uint32_t f = 0; f < a.frames; f++) {
        hz_time_ns_t t = hz_time_of_frame(a.start, f, a.hz);
        int64_t f0 = hz_clock_ns();
        /* A single frame has no frame counter to show: its own progress, should it take long. */
        if (a.frames == 1)
            hz_phase_begin(&prog, a.quiet, "rendering %s (%ux%u, mode %s)", a.scene, a.opts.width,
                              a.opts.height, hz_render_mode_name(a.opts.mode));
        hz_status_t fs = hz_render_run_frame_progress_ns(r, f, t, a.frames == 1 ? &prog : NULL, &err);
        if (a.frames == 1)
            hz_phase_end(&prog);
        if (fs != HZ_OK) {
            rc = hz_cli_report(&err);
            goto done;
        }
        frame_ms[f] = (hz_clock_ns() - f0) * 1e-6;
        if (y4m_open && hz_y4m_write(&y4m, hz_render_output(r), &err) != HZ_OK) {
            rc = hz_cli_report(&err);
            goto done;
        }
        int64_t now = hz_clock_ns();
        if (show && (now - last_progress > 100000000 || f + 1 == a.frames)) {
            progress(f + 1, a.frames, frame_ms[f]);
            last_progress = now;
        }
    }
    double run_s = (hz_clock_ns() - run0) * 1e-9;
    if (y4m_open) {
        y4m_open = false;
        if (hz_y4m_close(&y4m, &err) != HZ_OK) {
            rc = hz_cli_report(&err);
            goto done;
        }
    }
    if (a.write_png) {
        /* Builds without libpng (cross builds) write the same 8-bit sRGB pixels as PPM. */
        bool png = hz_png_supported();
        snprintf(path, sizeof path, "%s/last.%s", a.out_dir, png ? "png" : "ppm");
        hz_status_t ws = png ? hz_png_write(path, hz_render_output(r), &err)
                             : hz_ppm_write(path, hz_render_output(r), &err);
        if (ws != HZ_OK) {
            rc = hz_cli_report(&err);
            goto done;
        }
    }
    if (a.adaptive.map_path && hz_adaptive_map_write(a.adaptive.map_path, r, a.opts.width, a.opts.height, &err) != HZ_OK) {
        rc = hz_cli_report(&err);
        goto done;
    }
    if (a.write_pfm) {
        snprintf(path, sizeof path, "%s/last.pfm", a.out_dir);
        if (hz_pfm_write(path, hz_render_output(r), &err) != HZ_OK) {
            rc = hz_cli_report(&err);
            goto done;
        }
    }

    /* Summary: the first frame is excluded from the frame-time statistics when there are several (it pays
     * for page faults and cold caches), and said so. */
    uint32_t skip = a.frames > 1 ? 1u : 0u, n = a.frames - skip;
    memcpy(sorted_ms, frame_ms + skip, n * sizeof(double));
    qsort(sorted_ms, n, sizeof(double), cmp_double);
    double sum = 0;
    for (uint32_t i = 0; i < n; i++)
        sum += sorted_ms[i];
    hz_render_stats_t total;
    hz_render_frame_stats(r, NULL, &total);
    uint64_t rays = total.primary_rays + total.shadow_rays + total.secondary_rays;
    double render_s = 0;
    for (uint32_t i = 0; i < a.frames; i++)
        render_s += frame_ms[i] * 1e-3;
    char feats[160];
    hz_scene_features_str(scene.features, feats, sizeof feats);
    char note[256];
    const hz_light_t *dl = hz_render_default_light(r);
    if (dl)
        snprintf(note, sizeof note, "the scene has no lights: lit by a default key light at (%.4g %.4g %.4g) "
                 "(a sidecar 'light = ...' line replaces it)", (double)dl->position[0], (double)dl->position[1],
                 (double)dl->position[2]);
    hz_summary_t sm = {
        .note = dl ? note : NULL,
        .scene = a.scene, .mode = hz_render_mode_name(a.opts.mode),
        .spp = (double)total.primary_rays / ((double)a.opts.width * a.opts.height * a.frames),
        .start = (double)a.start * 1e-9, .width = a.opts.width, .height = a.opts.height, .hz = a.hz,
        .frames = a.frames, .threads = a.threads,
        .backend = accel->info.backend, .build_ms = build_ms, .ms_p50 = percentile(sorted_ms, n, 0.5),
        .ms_p99 = percentile(sorted_ms, n, 0.99), .ms_mean = n ? sum / n : 0, .ms_max = n ? sorted_ms[n - 1] : 0,
        .frames_timed = n, .rays = rays, .rays_per_frame = (double)rays / a.frames,
        .mrays_per_s = render_s > 0 ? rays / render_s * 1e-6 : 0, .run_s = run_s, .features = feats,
        .stats = total, .pools = pools,
    };
    hz_summary_adaptive_t ads;
    if (a.opts.mode == HZ_MODE_ADAPTIVE) {
        hz_adaptive_summary(&total, a.frames, a.opts.width, a.opts.height, hz_render_gbuffer(r)->object2 != NULL, &ads);
        sm.adaptive = &ads;
    }
    snprintf(path, sizeof path, "%s/summary.json", a.out_dir);
    if (hz_summary_write_json(&sm, path, &err) != HZ_OK) {
        rc = hz_cli_report(&err);
        goto done;
    }
    if (!a.quiet)
        hz_summary_print(&sm, stdout);
    if (!a.quiet && a.opts.shutter > 0.0f)
        printf("motion blur  shutter %.3g of each 1/%u s frame, %s, %u time keys, %u refits, %u rebuilds\n",
               (double)a.opts.shutter, a.hz,
               accel->info.time_keys < 2 ? "static accel (nothing moves: camera blur only)"
               : a.backend == HZ_ACCEL_EMBREE ? "Embree motion blur" : hz_accel_blur_name(accel->info.blur),
               accel->info.time_keys, accel->info.refits, accel->info.rebuilds);
    rc = 0;
done:
    if (y4m_open)
        hz_y4m_abort(&y4m);
    hz_threads_stop();
    hz_accel_release(accel);
    return rc;
}
