/* `hzrt latency`: display-locked latency measurement and v-sync trace analysis (see latency.h). */
#include "latency.h"

#include <errno.h>
#include <sched.h>
#include <sys/mman.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "fileio.h"
#include "devices.h"
#include "drm_port.h"
#include "hz/frameloop.h"
#include "hz/hz.h"
#include "hz/pixconv.h"
#include "hz/vsync.h"
#include "pools.h"
#include "latency_report.h"
#include "hz/render.h"
#include "renderopts.h"
#include "scenesrc.h"
#include "show.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: hzrt latency [options]\n"
            "\n"
            "Runs the display-locked frame loop against a v-sync source and reports deadline misses, latency\n"
            "(scan-out edge - render start), slack, phase error, dropped and repeated frames, and the v-sync\n"
            "model (period, drift, jitter, missed and spurious edges); or, with --edges-only (the default for\n"
            "trace files), analyses the edges alone. Writes frames.csv, edges.csv, report.json and\n"
            "histogram.svg to --out.\n"
            "\n"
            "v-sync source (--source; default: the board's, %s):\n"
            "  sim                   simulated display: --hz, --jitter-us N, --drift-ppm N, --miss-pct X,\n"
            "                        --glitch-pct X, --seed N\n"
            "  gpio[:CHIP[:LINE]]    GPIO edge events via libgpiod (default chip '%s', line %d)\n"
            "  fbdev[:DEV]           FBIO_WAITFORVSYNC on a framebuffer (default %s)\n"
            "  v4l2                  dequeue timestamps of the V4L2 output sink (needs --sink v4l2:...)\n"
            "  drm                   the DRM sink's vblank events (drmCrtcQueueSequence) or page-flip events\n"
            "                        (needs --sink drm[:...])\n"
            "  vcd:FILE              replay a logic-analyser trace (sigrok/PulseView VCD); --signal NAME\n"
            "  csv:FILE              replay edge timestamps (t_ns[,level], or hzrt's edges.csv)\n"
            "  --edge rising|falling|any   v-sync polarity (any: every edge, e.g. a photodiode on the marker)\n"
            "  --active-low          (gpio) the line is active low\n"
            "  --gpio-one-edge       (gpio) request only the v-sync polarity's edges (default both: pulse widths)\n"
            "  --hz HZ               nominal refresh rate, may have decimals (default %d; 0: learn it)\n"
            "  --timeout-ms MS       give up after this long without an edge (default max(500, 10 periods))\n"
            "lock verdict (a run that fails it exits 3, \"no lock\", and reports no period):\n"
            "  --lock-min-run N      a locked stretch needs N accepted edges in a row, no relock (default %u)\n"
            "  --lock-max-relock-pct X    relocks at most X%% of the accepted edges (default %g)\n"
            "  --lock-max-spurious-pct X  spurious edges at most X%% of the v-sync edges (default %g)\n"
            "  --lock-max-missed-pct X    missed pulses at most X%% of the refreshes (default %g)\n"
            "  the period and ppm come from the locked stretches only; a rate more than %g%% off --hz is a warning\n"
            "display sink (--sink; default none):\n"
            "  none | files (frames.y4m and last.png in --out) | fbdev[:DEV] | v4l2:DEV[:rgb24|xrgb32|yuyv]\n"
            "  drm[:CARD[:CONNECTOR[:WxH[@HZ]]]]   DRM/KMS page flips (default: the first card with a connected\n"
            "                        display, its first connected connector, the preferred mode); --drm-buffers 2|3\n"
            "  display               the board's display: %s\n",
            HZ_VSYNC_SOURCE == HZ_VSYNC_GPIO ? "gpio" : HZ_VSYNC_SOURCE == HZ_VSYNC_FBDEV ? "fbdev" : "sim",
            HZ_VSYNC_GPIO_CHIP, HZ_VSYNC_GPIO_LINE, HZ_DISPLAY_DEVICE, HZ_DISPLAY_HZ, HZ_LOCK_MIN_RUN,
            HZ_LOCK_RELOCK_PPM / 1e4, HZ_LOCK_SPURIOUS_PPM / 1e4, HZ_LOCK_MISSED_PPM / 1e4, HZ_LOCK_FAR_PPM / 1e4,
            !strcmp(HZ_DISPLAY_SINK, "drm") ? "DRM, falling back to fbdev " HZ_DISPLAY_DEVICE " without a DRM card"
                                            : "fbdev " HZ_DISPLAY_DEVICE);
    /* in two parts: C99 promises string literals of 4095 characters, no more */
    fputs("frames:\n"
          "  --frames N | --seconds S    run length (default 10 s)\n"
          "  --size WxH            frame size (default: the sink's mode, else 320x180)\n"
          "  --render pattern|scene     what to draw: the test pattern, or a scene through the renderer in any\n"
          "                        mode with any render option (listed below)\n"
          "  --scene FILE|builtin  (scene) the scene: a baked .hzb or the built-in one (default builtin)\n"
          "  --render-scale N      (scene) render 1/N of the width and height (multiples of N), each pixel\n"
          "                        shown N x N\n"
          "  --budget on|off       (scene) the frame-budget governor: each frame at the best quality level that\n"
          "                        fits the display's period (render scale 3/4..1/4, fewer bounces, cheaper\n"
          "                        transparency and thresholds, a cheaper mode), with hysteresis; default on in\n"
          "                        real time, off with --virtual. frames.csv gives each frame's level\n"
          "  --level-error N       (scene, governor) after the run, each level the run used rendered for N\n"
          "                        frames against level 0: PSNR and FLIP in the report\n"
          "  --marker, --no-marker      frame-id marker in the top-left corner (default: on with a sink)\n"
          "  --virtual             simulated clock (sim, vcd, csv sources): no sleeping, render times from\n"
          "                        --render-model const:T | uniform:A:B | spikes:A:B:PCT | triangle:A:B:N |\n"
          "                        step:A:B:N and --wake T (oversleep up to T); T like 3ms, 800us, 0.5P\n"
          "pacing:\n"
          "  --percentile P (100: the max)  --window N (1024)  --guard T (P/16)  --latch T (0)  --lookahead K (1)\n"
          "  --edges-only          capture and classify edges, render nothing\n"
          "  --rt                  real-time: SCHED_FIFO priority 50 and locked memory (needs root or\n"
          "                        CAP_SYS_NICE + CAP_IPC_LOCK; refused permissions are reported, not fatal)\n"
          "output:\n"
          "  --out DIR             default out/latency\n"
          "  --quiet               no summary on stdout\n"
          "\n"
          "exit status: 0 ok, 2 bad command line, 3 no lock (files written), 64+N failure with hz status N\n"
          "(75: no v-sync, time-out)\n\n",
          f);
    hz_ropts_usage(f);
}

#define NEXT_ARG()                                                                                   \
    do {                                                                                             \
        if (*i + 1 >= argc) {                                                                        \
            hz_cli_error("%s: %s needs a value (try hzrt %s --help)", c->cmd, a, c->cmd);            \
            return -HZ_EXIT_USAGE;                                                                   \
        }                                                                                            \
        v = argv[++*i];                                                                              \
    } while (0)

static int parse_double(const char *opt, const char *s, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(s ? s : "", &end);
    if (!s || errno || end == s || *end || !(v >= lo && v <= hi)) {
        hz_cli_error("%s: '%s' is not a number in [%g, %g]", opt, s ? s : "", lo, hi);
        return 0;
    }
    *out = v;
    return 1;
}

int hz_latency_opt_take(hz_show_cfg_t *c, int argc, char **argv, int *i)
{
    const char *a = argv[*i], *v = NULL;
    long l;
    double d;
    if (!strcmp(a, "--source")) {
        NEXT_ARG();
        c->source = v;
    } else if (!strcmp(a, "--sink")) {
        NEXT_ARG();
        c->sink = v;
    } else if (!strcmp(a, "--out")) {
        NEXT_ARG();
        if (!*v) {
            hz_cli_error("%s: --out: missing folder", c->cmd);
            return -HZ_EXIT_USAGE;
        }
        c->out = v;
    } else if (!strcmp(a, "--signal")) {
        NEXT_ARG();
        c->signal = v;
    } else if (!strcmp(a, "--edge")) {
        NEXT_ARG();
        if (!strcmp(v, "rising"))
            c->edge_mode = HZ_EDGE_RISING;
        else if (!strcmp(v, "falling"))
            c->edge_mode = HZ_EDGE_FALLING;
        else if (!strcmp(v, "any"))
            c->edge_mode = HZ_EDGE_ANY;
        else {
            hz_cli_error("--edge: '%s' is not rising, falling or any", v);
            return -HZ_EXIT_USAGE;
        }
    } else if (!strcmp(a, "--active-low")) {
        c->active_low = 1;
    } else if (!strcmp(a, "--hz")) {
        NEXT_ARG();
        if (!parse_double(a, v, 0, 1000, &c->hz))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(a, "--jitter-us")) {
        NEXT_ARG();
        if (!parse_double(a, v, 0, 1e6, &c->jitter_us))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(a, "--drift-ppm")) {
        NEXT_ARG();
        if (!parse_double(a, v, -100000, 100000, &c->drift_ppm))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(a, "--miss-pct")) {
        NEXT_ARG();
        if (!parse_double(a, v, 0, 50, &c->miss_pct))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(a, "--glitch-pct")) {
        NEXT_ARG();
        if (!parse_double(a, v, 0, 100, &c->glitch_pct))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(a, "--seed")) {
        NEXT_ARG();
        if (!hz_cli_parse_long(a, v, 0, 2147483647L, &c->seed))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(a, "--frames")) {
        NEXT_ARG();
        if (!hz_cli_parse_long(a, v, 1, 100000000L, &l))
            return -HZ_EXIT_USAGE;
        c->frames = (uint64_t)l;
    } else if (!strcmp(a, "--seconds")) {
        NEXT_ARG();
        if (!parse_double(a, v, 0.001, 86400, &c->seconds))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(a, "--size")) {
        NEXT_ARG();
        if (!hz_cli_parse_size(a, v, 8, 8192, &c->w, &c->h))
            return -HZ_EXIT_USAGE;
        c->size_given = true;
    } else if (!strcmp(a, "--marker")) {
        c->marker = 1;
    } else if (!strcmp(a, "--no-marker")) {
        c->marker = 0;
    } else if (!strcmp(a, "--virtual")) {
        c->virt = 1;
    } else if (!strcmp(a, "--render-model")) {
        NEXT_ARG();
        c->model = v;
    } else if (!strcmp(a, "--wake")) {
        NEXT_ARG();
        c->wake = v;
    } else if (!strcmp(a, "--percentile")) {
        NEXT_ARG();
        if (!parse_double(a, v, 50, 100, &c->percentile))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(a, "--window")) {
        NEXT_ARG();
        if (!hz_cli_parse_long(a, v, 16, HZ_PACE_WINDOW_MAX, &c->window))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(a, "--guard")) {
        NEXT_ARG();
        c->guard = v;
    } else if (!strcmp(a, "--latch")) {
        NEXT_ARG();
        c->latch = v;
    } else if (!strcmp(a, "--lookahead")) {
        NEXT_ARG();
        if (!hz_cli_parse_long(a, v, 1, 16, &c->lookahead))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(a, "--timeout-ms")) {
        NEXT_ARG();
        if (!hz_cli_parse_long(a, v, 1, 3600000L, &c->timeout_ms))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(a, "--quiet")) {
        c->quiet = 1;
    } else if (!strcmp(a, "--rt")) {
        c->rt = 1;
    } else if (!strcmp(a, "--gpio-one-edge")) {
        c->one_edge = 1;
    } else if (!strcmp(a, "--lock-min-run")) {
        NEXT_ARG();
        if (!hz_cli_parse_long(a, v, 2, 1000000L, &l))
            return -HZ_EXIT_USAGE;
        c->lock.min_run = (uint32_t)l;
    } else if (!strcmp(a, "--lock-max-relock-pct") || !strcmp(a, "--lock-max-spurious-pct") ||
               !strcmp(a, "--lock-max-missed-pct")) {
        NEXT_ARG();
        if (!parse_double(a, v, 0, 100, &d))
            return -HZ_EXIT_USAGE;
        uint32_t ppm = d >= 100 ? HZ_LOCK_ANY : (uint32_t)(d * 1e4 + 0.5);
        if (ppm == 0)
            ppm = HZ_LOCK_NONE; /* 0 in the configuration means the default */
        if (strstr(a, "relock"))
            c->lock.max_relock_ppm = ppm;
        else if (strstr(a, "spurious"))
            c->lock.max_spurious_ppm = ppm;
        else
            c->lock.max_missed_ppm = ppm;
    } else if (!strcmp(a, "--drm-buffers")) {
        NEXT_ARG();
        if (!hz_cli_parse_long(a, v, 2, 3, &l))
            return -HZ_EXIT_USAGE;
        c->drm_buffers = (int)l;
    } else if (!strcmp(a, "--render-scale")) {
        NEXT_ARG();
        if (!hz_cli_parse_long(a, v, 1, 64, &l))
            return -HZ_EXIT_USAGE;
        c->render_scale = (int)l;
        c->render_scale_given = true;
    } else if (!strcmp(a, "--budget")) {
        NEXT_ARG();
        if (strcmp(v, "on") && strcmp(v, "off")) {
            hz_cli_error("%s: --budget: '%s' is not on or off", c->cmd, v);
            return -HZ_EXIT_USAGE;
        }
        c->budget = !strcmp(v, "on");
    } else if (!strcmp(a, "--level-error")) {
        NEXT_ARG();
        if (!hz_cli_parse_long(a, v, 1, 1000, &l))
            return -HZ_EXIT_USAGE;
        c->level_error_frames = (uint32_t)l;
    } else {
        return 0;
    }
    return 1;
}

/* After the command line: what the scene options need and what the frame size is. */
int hz_show_from_ropts(hz_show_cfg_t *c, hz_ropts_t *ro, const char *scene)
{
    int rc = hz_ropts_check(ro);
    if (rc)
        return rc;
    c->scene.scene = scene;
    c->scene.opts = ro->opts;
    c->scene.backend = ro->backend;
    c->scene.blur = ro->blur;
    c->scene.threads = ro->threads;
    c->scene.start = ro->start;
    c->adaptive = &ro->adaptive;
    return 0;
}

static hz_status_t prepare_scene(void *ctx, const hz_scene_t *scene, hz_render_opts_t *opts, hz_error_t *err)
{
    const hz_adaptive_cli_t *a = ctx;
    return hz_adaptive_cli_resolve(a, scene, &opts->adaptive, err);
}

int hz_cmd_latency(int argc, char **argv)
{
    static hz_show_cfg_t c;
    static hz_ropts_t ro;
    hz_show_defaults(&c);
    c.cmd = "latency";
    c.out = "out/latency";
    hz_ropts_defaults(&ro, "latency", HZ_MODE_TDENSE);
    const char *render = NULL, *scene = NULL;
    bool edges_only = false;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        }
        int used = hz_latency_opt_take(&c, argc, argv, &i);
        if (used < 0)
            return -used;
        if (used)
            continue;
        if (!strcmp(a, "--render") || !strcmp(a, "--scene")) {
            if (i + 1 >= argc) {
                hz_cli_error("latency: %s needs a value (try hzrt latency --help)", a);
                return HZ_EXIT_USAGE;
            }
            const char *v = argv[++i];
            if (!strcmp(a, "--scene")) {
                scene = v;
            } else if (strcmp(v, "pattern") && strcmp(v, "scene")) {
                hz_cli_error("--render: '%s' is not pattern or scene", v);
                return HZ_EXIT_USAGE;
            } else {
                render = v;
            }
            continue;
        }
        if (!strcmp(a, "--edges-only")) {
            edges_only = true;
            continue;
        }
        used = hz_ropts_take(&ro, argc, argv, i);
        if (used < 0)
            return -used;
        if (used) {
            i += used - 1;
            continue;
        }
        hz_cli_error("latency: unknown option '%s' (try hzrt latency --help)", a);
        return HZ_EXIT_USAGE;
    }
    char kind[16];
    snprintf(kind, sizeof kind, "%s", c.source);
    char *colon = strchr(kind, ':');
    if (colon)
        *colon = 0;
    const bool trace_file = !strcmp(kind, "vcd") || !strcmp(kind, "csv");
    /* A recorded trace is analysed edge by edge unless frames are asked for (--virtual, --render). */
    c.what = edges_only || (trace_file && !c.virt && !render) ? HZ_SHOW_EDGES
             : render && !strcmp(render, "scene")            ? HZ_SHOW_SCENE
                                                               : HZ_SHOW_PATTERN;
    const bool scene_opts = scene || ro.given_n || c.render_scale_given || c.level_error_frames;
    if (scene_opts && c.what != HZ_SHOW_SCENE) {
        const char *first = scene ? "--scene" : ro.given_n ? ro.given[0] : c.render_scale_given ? "--render-scale"
                                                                                               : "--level-error";
        hz_cli_error("latency: %s renders a scene: it needs --render scene%s", first,
                     c.what == HZ_SHOW_EDGES ? " (and frames, not --edges-only)" : "");
        return HZ_EXIT_USAGE;
    }
    if (render && edges_only) {
        hz_cli_error("latency: --render and --edges-only: capturing edges only renders nothing");
        return HZ_EXIT_USAGE;
    }
    if (c.what == HZ_SHOW_SCENE) {
        int rc = hz_show_from_ropts(&c, &ro, scene ? scene : "builtin");
        if (rc)
            return rc;
        c.scene.prepare = prepare_scene;
        c.scene.prepare_ctx = &ro.adaptive;
    }
    return hz_show_run(&c);
}
