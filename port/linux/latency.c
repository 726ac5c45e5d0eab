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
#include "frameloop.h"
#include "hz/hz.h"
#include "hz/pixconv.h"
#include "hz/vsync.h"
#include "pools.h"
#include "latency_report.h"
#include "hz/render.h"
#include "scenesrc.h"

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
            "  none | fbdev[:DEV] | v4l2:DEV[:rgb24|xrgb32|yuyv]\n"
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
          "  --render pattern|scene     what to draw: the test pattern, or a scene through the renderer\n"
          "  --scene FILE|builtin  (scene) the scene: a baked .hzb or the built-in one (default builtin)\n"
          "  --threads N           (scene) render threads, 1..64 (default: the machine's cores)\n"
          "  --mode tdense|full    (scene) temporally dense (one sample per 2x2 tile per frame, the\n"
          "                        default) or full frames at 1 spp\n"
          "  --render-scale N      (scene) render 1/N of the width and height (multiples of N), each pixel\n"
          "                        shown N x N\n"
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
          "(75: no v-sync, time-out)\n",
          f);
}

/* "3ms", "800us", "250ns", "1.5ms", "2s", "0.5P" (of period_ns). */
static int parse_time(const char *opt, const char *s, int64_t period_ns, int64_t *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    double scale = 0;
    if (errno == 0 && end != s && v >= 0) {
        if (!strcmp(end, "ns"))
            scale = 1;
        else if (!strcmp(end, "us"))
            scale = 1e3;
        else if (!strcmp(end, "ms"))
            scale = 1e6;
        else if (!strcmp(end, "s"))
            scale = 1e9;
        else if (!strcmp(end, "P") && period_ns > 0)
            scale = (double)period_ns;
    }
    if (scale == 0 || v * scale > 1e15) {
        hz_cli_error("%s: '%s' is not a time like 3ms, 800us, 250ns or 0.5P (a fraction of the period)", opt, s);
        return 0;
    }
    *out = (int64_t)(v * scale + 0.5);
    return 1;
}

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

static int parse_model(const char *spec, int64_t period_ns, hz_rtm_cfg_t *m)
{
    char buf[128];
    snprintf(buf, sizeof buf, "%s", spec);
    char *parts[5] = { 0 };
    int n = 0;
    for (char *t = strtok(buf, ":"); t && n < 5; t = strtok(NULL, ":"))
        parts[n++] = t;
    memset(m, 0, sizeof *m);
    struct { const char *name; hz_rtm_kind_t kind; int args; } kinds[] = {
        { "const", HZ_RTM_CONST, 1 }, { "uniform", HZ_RTM_UNIFORM, 2 }, { "spikes", HZ_RTM_SPIKES, 3 },
        { "triangle", HZ_RTM_TRIANGLE, 3 }, { "step", HZ_RTM_STEP, 3 },
    };
    for (size_t k = 0; n > 0 && k < sizeof kinds / sizeof kinds[0]; k++) {
        if (strcmp(parts[0], kinds[k].name))
            continue;
        if (n - 1 != kinds[k].args)
            break;
        m->kind = kinds[k].kind;
        if (!parse_time("--render-model", parts[1], period_ns, &m->a_ns))
            return 0;
        if (kinds[k].args >= 2 && !parse_time("--render-model", parts[2], period_ns, &m->b_ns))
            return 0;
        if (kinds[k].args == 3) {
            double v;
            if (m->kind == HZ_RTM_SPIKES) {
                if (!parse_double("--render-model spike %", parts[3], 0, 100, &v))
                    return 0;
                m->rate_ppm = (uint32_t)(v * 1e4 + 0.5);
            } else {
                if (!parse_double("--render-model frames", parts[3], 1, 1e12, &v))
                    return 0;
                m->frames = (uint64_t)v;
            }
        }
        return 1;
    }
    hz_cli_error("--render-model: '%s' is not one of const:T, uniform:A:B, spikes:A:B:PCT, triangle:A:B:N, "
                 "step:A:B:N", spec);
    return 0;
}

/* SCHED_FIFO and locked memory for on-target measurement runs; what was granted goes into the report. */
static void hz_rt_setup(char *out, size_t cap)
{
    struct sched_param sp;
    memset(&sp, 0, sizeof sp);
    sp.sched_priority = 50;
    int fifo = sched_setscheduler(0, SCHED_FIFO, &sp) == 0;
    int e1 = errno;
    /* MCL_ONFAULT: pages are locked as they are first touched, so the board's large static arenas are not all
     * made resident up front; what the loop uses stays in RAM from its first frame on. */
#ifdef MCL_ONFAULT
    int locked = mlockall(MCL_CURRENT | MCL_FUTURE | MCL_ONFAULT) == 0;
#else
    int locked = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
#endif
    int e2 = errno;
    snprintf(out, cap, "%s, %s",
             fifo ? "SCHED_FIFO 50" : (e1 == EPERM ? "SCHED_FIFO refused (EPERM)" : "SCHED_FIFO failed"),
             locked ? "memory locked" : (e2 == EPERM || e2 == ENOMEM ? "mlockall refused" : "mlockall failed"));
    if (!fifo || !locked)
        hz_cli_error("warning: --rt: %s", out);
}

typedef struct opts {
    const char *source, *sink, *out, *render, *signal, *model;
    int edge_mode, active_low, marker, virt, edges_only, quiet;
    double hz;
    int hz_given;
    double jitter_us, drift_ppm, miss_pct, glitch_pct;
    long seed;
    uint64_t frames;
    double seconds;
    int w, h;
    double percentile;
    long window, lookahead, timeout_ms;
    const char *guard, *latch, *wake;
    int rt, one_edge;
    long render_scale;
    const char *scene; /* NULL: builtin */
    long threads;      /* 0: the machine's cores */
    const char *mode;  /* NULL: tdense */
    hz_lockv_cfg_t lock;
    long drm_buffers;
} opts_t;

#define NEXT_ARG()                                                                                   \
    do {                                                                                             \
        if (i + 1 >= argc) {                                                                         \
            hz_cli_error("latency: %s needs a value (try hzrt latency --help)", a);                  \
            return 0;                                                                                \
        }                                                                                            \
        v = argv[++i];                                                                               \
    } while (0)

static int parse_opts(int argc, char **argv, opts_t *o, int *help)
{
    memset(o, 0, sizeof *o);
    o->source = HZ_VSYNC_SOURCE == HZ_VSYNC_GPIO ? "gpio" : HZ_VSYNC_SOURCE == HZ_VSYNC_FBDEV ? "fbdev" : "sim";
    o->sink = "none";
    o->out = "out/latency";
    o->render = "pattern";
    o->signal = "";
    o->marker = -1;
    o->edge_mode = HZ_VSYNC_GPIO_EDGE; /* HZ_EDGE_RISING, _FALLING, _ANY: the board's default */
    o->hz = HZ_DISPLAY_HZ;
    o->seed = 1;
    o->render_scale = 1;
    o->percentile = 100;
    o->lookahead = 1;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = NULL;
        long l;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            *help = 1;
            return 1;
        } else if (!strcmp(a, "--source")) {
            NEXT_ARG();
            o->source = v;
        } else if (!strcmp(a, "--sink")) {
            NEXT_ARG();
            o->sink = v;
        } else if (!strcmp(a, "--out")) {
            NEXT_ARG();
            o->out = v;
        } else if (!strcmp(a, "--render")) {
            NEXT_ARG();
            if (strcmp(v, "pattern") && strcmp(v, "scene")) {
                hz_cli_error("--render: '%s' is not pattern or scene", v);
                return 0;
            }
            o->render = v;
        } else if (!strcmp(a, "--signal")) {
            NEXT_ARG();
            o->signal = v;
        } else if (!strcmp(a, "--edge")) {
            NEXT_ARG();
            if (!strcmp(v, "rising"))
                o->edge_mode = HZ_EDGE_RISING;
            else if (!strcmp(v, "falling"))
                o->edge_mode = HZ_EDGE_FALLING;
            else if (!strcmp(v, "any"))
                o->edge_mode = HZ_EDGE_ANY;
            else {
                hz_cli_error("--edge: '%s' is not rising, falling or any", v);
                return 0;
            }
        } else if (!strcmp(a, "--active-low")) {
            o->active_low = 1;
        } else if (!strcmp(a, "--hz")) {
            NEXT_ARG();
            if (!parse_double(a, v, 0, 1000, &o->hz))
                return 0;
            o->hz_given = 1;
        } else if (!strcmp(a, "--jitter-us")) {
            NEXT_ARG();
            if (!parse_double(a, v, 0, 1e6, &o->jitter_us))
                return 0;
        } else if (!strcmp(a, "--drift-ppm")) {
            NEXT_ARG();
            if (!parse_double(a, v, -100000, 100000, &o->drift_ppm))
                return 0;
        } else if (!strcmp(a, "--miss-pct")) {
            NEXT_ARG();
            if (!parse_double(a, v, 0, 50, &o->miss_pct))
                return 0;
        } else if (!strcmp(a, "--glitch-pct")) {
            NEXT_ARG();
            if (!parse_double(a, v, 0, 100, &o->glitch_pct))
                return 0;
        } else if (!strcmp(a, "--seed")) {
            NEXT_ARG();
            if (!hz_cli_parse_long(a, v, 0, 2147483647L, &o->seed))
                return 0;
        } else if (!strcmp(a, "--frames")) {
            NEXT_ARG();
            if (!hz_cli_parse_long(a, v, 1, 100000000L, &l))
                return 0;
            o->frames = (uint64_t)l;
        } else if (!strcmp(a, "--seconds")) {
            NEXT_ARG();
            if (!parse_double(a, v, 0.001, 86400, &o->seconds))
                return 0;
        } else if (!strcmp(a, "--size")) {
            NEXT_ARG();
            if (!hz_cli_parse_size(a, v, 16, 8192, &o->w, &o->h))
                return 0;
        } else if (!strcmp(a, "--marker")) {
            o->marker = 1;
        } else if (!strcmp(a, "--no-marker")) {
            o->marker = 0;
        } else if (!strcmp(a, "--virtual")) {
            o->virt = 1;
        } else if (!strcmp(a, "--render-model")) {
            NEXT_ARG();
            o->model = v;
        } else if (!strcmp(a, "--wake")) {
            NEXT_ARG();
            o->wake = v;
        } else if (!strcmp(a, "--percentile")) {
            NEXT_ARG();
            if (!parse_double(a, v, 50, 100, &o->percentile))
                return 0;
        } else if (!strcmp(a, "--window")) {
            NEXT_ARG();
            if (!hz_cli_parse_long(a, v, 16, HZ_PACE_WINDOW_MAX, &o->window))
                return 0;
        } else if (!strcmp(a, "--guard")) {
            NEXT_ARG();
            o->guard = v;
        } else if (!strcmp(a, "--latch")) {
            NEXT_ARG();
            o->latch = v;
        } else if (!strcmp(a, "--lookahead")) {
            NEXT_ARG();
            if (!hz_cli_parse_long(a, v, 1, 16, &o->lookahead))
                return 0;
        } else if (!strcmp(a, "--timeout-ms")) {
            NEXT_ARG();
            if (!hz_cli_parse_long(a, v, 1, 3600000L, &o->timeout_ms))
                return 0;
        } else if (!strcmp(a, "--edges-only")) {
            o->edges_only = 1;
        } else if (!strcmp(a, "--quiet")) {
            o->quiet = 1;
        } else if (!strcmp(a, "--rt")) {
            o->rt = 1;
        } else if (!strcmp(a, "--gpio-one-edge")) {
            o->one_edge = 1;
        } else if (!strcmp(a, "--lock-min-run")) {
            NEXT_ARG();
            if (!hz_cli_parse_long(a, v, 2, 1000000L, &l))
                return 0;
            o->lock.min_run = (uint32_t)l;
        } else if (!strcmp(a, "--lock-max-relock-pct") || !strcmp(a, "--lock-max-spurious-pct") ||
                   !strcmp(a, "--lock-max-missed-pct")) {
            double pct;
            NEXT_ARG();
            if (!parse_double(a, v, 0, 100, &pct))
                return 0;
            uint32_t ppm = pct >= 100 ? HZ_LOCK_ANY : (uint32_t)(pct * 1e4 + 0.5);
            if (ppm == 0)
                ppm = HZ_LOCK_NONE; /* 0 in the configuration means the default */
            if (strstr(a, "relock"))
                o->lock.max_relock_ppm = ppm;
            else if (strstr(a, "spurious"))
                o->lock.max_spurious_ppm = ppm;
            else
                o->lock.max_missed_ppm = ppm;
        } else if (!strcmp(a, "--drm-buffers")) {
            NEXT_ARG();
            if (!hz_cli_parse_long(a, v, 2, 3, &o->drm_buffers))
                return 0;
        } else if (!strcmp(a, "--scene")) {
            NEXT_ARG();
            o->scene = v;
        } else if (!strcmp(a, "--mode")) {
            NEXT_ARG();
            if (strcmp(v, "tdense") && strcmp(v, "full")) {
                hz_cli_error("--mode: '%s' is not tdense or full", v);
                return 0;
            }
            o->mode = v;
        } else if (!strcmp(a, "--threads")) {
            NEXT_ARG();
            if (!hz_cli_parse_long(a, v, 1, 64, &o->threads))
                return 0;
        } else if (!strcmp(a, "--render-scale")) {
            NEXT_ARG();
            if (!hz_cli_parse_long(a, v, 1, 64, &o->render_scale))
                return 0;
        } else {
            hz_cli_error("latency: unknown option '%s' (try hzrt latency --help)", a);
            return 0;
        }
    }
    return 1;
}

/* "kind:rest" -> kind and rest (rest "" when absent). */
static void split_spec(const char *spec, char *kind, size_t kcap, const char **rest)
{
    const char *colon = strchr(spec, ':');
    size_t n = colon ? (size_t)(colon - spec) : strlen(spec);
    if (n >= kcap)
        n = kcap - 1;
    memcpy(kind, spec, n);
    kind[n] = '\0';
    *rest = colon ? colon + 1 : "";
}

int hz_cmd_latency(int argc, char **argv)
{
    opts_t o;
    int help = 0;
    if (!parse_opts(argc, argv, &o, &help))
        return HZ_EXIT_USAGE;
    if (help) {
        usage(stdout);
        return 0;
    }
    hz_error_t err;
    hz_error_clear(&err);
    int64_t period = o.hz > 0 ? (int64_t)(1e9 / o.hz + 0.5) : 0;
    char kind[16];
    const char *rest;
    split_spec(o.source, kind, sizeof kind, &rest);
    int timeline = !strcmp(kind, "sim") || !strcmp(kind, "vcd") || !strcmp(kind, "csv");
    int trace_file = !strcmp(kind, "vcd") || !strcmp(kind, "csv");
    int edges_only = o.edges_only || (trace_file && !o.virt);
    if ((o.scene || o.threads || o.mode) && (strcmp(o.render, "scene") || edges_only)) {
        hz_cli_error("%s renders a scene: it needs --render scene (and frames, not --edges-only)",
                     o.scene ? "--scene" : o.threads ? "--threads" : "--mode");
        return HZ_EXIT_USAGE;
    }
    if (o.virt && !timeline) {
        hz_cli_error("--virtual needs a timeline source (sim, vcd or csv), not '%s'", o.source);
        return HZ_EXIT_USAGE;
    }
    if (o.virt && !edges_only && !o.model) {
        hz_cli_error("--virtual needs --render-model (e.g. uniform:0.2P:0.8P)");
        return HZ_EXIT_USAGE;
    }
    if (o.model && !o.virt) {
        hz_cli_error("--render-model only applies with --virtual (in real time render times are measured)");
        return HZ_EXIT_USAGE;
    }
    if (o.frames && o.seconds > 0) {
        hz_cli_error("give --frames or --seconds, not both");
        return HZ_EXIT_USAGE;
    }
    hz_rtm_cfg_t model;
    if (o.model) {
        if (!parse_model(o.model, period, &model))
            return HZ_EXIT_USAGE;
        model.seed = (uint64_t)o.seed;
        if (o.wake && !parse_time("--wake", o.wake, period, &model.wake_ns))
            return HZ_EXIT_USAGE;
    }
    hz_loop_cfg_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.frames_mode = !edges_only;
    cfg.nominal_period_ns = period;
    cfg.edge_mode = o.edge_mode;
    cfg.pace.percentile = (uint32_t)(o.percentile * 10 + 0.5);
    cfg.pace.window = (uint32_t)o.window;
    cfg.pace.lookahead = (uint32_t)o.lookahead;
    cfg.pace.guard_ns = -1;
    if (o.guard && !parse_time("--guard", o.guard, period, &cfg.pace.guard_ns))
        return HZ_EXIT_USAGE;
    if (o.latch && !parse_time("--latch", o.latch, period, &cfg.pace.latch_ns))
        return HZ_EXIT_USAGE;
    cfg.edge_timeout_ns = o.timeout_ms * 1000000LL;
    cfg.rtm = o.model ? &model : NULL;
    cfg.lock = o.lock;

    /* The report folder before the run: a folder that cannot be written is refused now, not after it. */
    char created[1024];
    if (hz_out_dir_prepare(o.out, created, sizeof created, &err) != HZ_OK)
        return hz_cli_report(&err);
    if (created[0] && !o.quiet)
        fprintf(stderr, "%s: latency: --out: created %s\n", hz_cli_prog, created);

    /* Real-time scheduling first: threads started later (the renderer's workers) inherit it. */
    char sched[128] = "";
    if (o.rt && !o.virt)
        hz_rt_setup(sched, sizeof sched);

    /* ---- open the sink first: its mode sets the frame size, and V4L2 output is also a source ---- */
    hz_sink_t sink;
    hz_vsource_t src;
    memset(&sink, 0, sizeof sink);
    memset(&src, 0, sizeof src);
    hz_status_t s = HZ_OK;
    int src_open = 0;
    char skind[16];
    const char *srest;
    split_spec(o.sink, skind, sizeof skind, &srest);
    int drm_fallback = 0;
    if (!strcmp(skind, "display") && !edges_only) {
        /* The board's display: DRM where the board says so, fbdev when no DRM card or display is there. */
        snprintf(skind, sizeof skind, "%s", HZ_DISPLAY_SINK);
        drm_fallback = !strcmp(skind, "drm");
        srest = "";
    }
    if (edges_only || !strcmp(skind, "none")) {
        hz_sink_null(&sink);
    } else if (!strcmp(skind, "drm")) {
        hz_drm_cfg_t dc;
        char spec[256];
        s = *hz_devices_missing("drm") ? hz_error_set(&err, HZ_E_UNSUPPORTED, "--sink drm: %s", hz_devices_missing("drm"))
                                       : hz_drm_parse_spec(srest, &dc, spec, sizeof spec, &err);
        if (s == HZ_E_INVALID_ARG) {
            hz_cli_error("%s", err.msg);
            return HZ_EXIT_USAGE;
        }
        if (s == HZ_OK) {
            dc.buffers = (int)o.drm_buffers;
            s = hz_drm_sink_open(&sink, !strcmp(kind, "drm") ? &src : NULL, &dc, &err);
            src_open = s == HZ_OK && !strcmp(kind, "drm");
        }
        if (s != HZ_OK && drm_fallback && strcmp(kind, "drm")) {
            hz_cli_error("note: %s; using fbdev %s", err.msg, HZ_DISPLAY_DEVICE);
            hz_error_clear(&err);
            s = hz_fbdev_sink_open(&sink, HZ_DISPLAY_DEVICE, NULL, &err);
        }
    } else if (!strcmp(skind, "fbdev")) {
        s = hz_fbdev_sink_open(&sink, *srest ? srest : HZ_DISPLAY_DEVICE, NULL, &err);
    } else if (!strcmp(skind, "v4l2")) {
        char dev[256];
        snprintf(dev, sizeof dev, "%s", srest);
        char *fmt_s = strchr(dev, ':');
        hz_pix_fmt_t fmt = HZ_PIX_RGB24;
        if (fmt_s) {
            *fmt_s++ = '\0';
            s = hz_pix_parse(fmt_s, &fmt, &err);
        }
        if (s == HZ_OK && !*dev) {
            hz_cli_error("--sink v4l2:DEV needs the output device, e.g. v4l2:/dev/video1");
            return HZ_EXIT_USAGE;
        }
        if (s == HZ_OK) {
            s = hz_v4l2_out_open(&sink, !strcmp(kind, "v4l2") ? &src : NULL, dev, fmt, o.w, o.h, NULL, &err);
            src_open = s == HZ_OK && !strcmp(kind, "v4l2");
        }
    } else {
        hz_cli_error("--sink: '%s' is not none, display, drm[:CARD[:CONNECTOR[:WxH[@HZ]]]], fbdev[:DEV] or "
                     "v4l2:DEV[:FORMAT]", o.sink);
        return HZ_EXIT_USAGE;
    }
    if (s != HZ_OK)
        return hz_cli_report(&err);

    /* ---- the v-sync source ---- */
    if (!strcmp(kind, "sim")) {
        hz_vsynth_cfg_t g;
        memset(&g, 0, sizeof g);
        g.period_q16 = hz_vsync_period_q16_from_mhz((uint64_t)((o.hz > 0 ? o.hz : HZ_DISPLAY_HZ) * 1000 + 0.5));
        g.jitter_ns = (int64_t)(o.jitter_us * 1000);
        g.drift_ppb_start = g.drift_ppb_end = (int32_t)(o.drift_ppm * 1000);
        g.miss_ppm = (uint32_t)(o.miss_pct * 1e4);
        g.glitch_ppm = (uint32_t)(o.glitch_pct * 1e4);
        g.seed = (uint64_t)o.seed;
        s = hz_vsource_sim(&src, &g, &err);
    } else if (!strcmp(kind, "vcd") || !strcmp(kind, "csv")) {
        if (!*rest) {
            hz_cli_error("--source %s:FILE needs a file", kind);
            hz_sink_close(&sink);
            return HZ_EXIT_USAGE;
        }
        s = !strcmp(kind, "vcd") ? hz_vsource_vcd(&src, rest, o.signal, &err) : hz_vsource_csv(&src, rest, &err);
    } else if (!strcmp(kind, "gpio")) {
        if (*hz_devices_missing("gpio")) {
            hz_error_set(&err, HZ_E_UNSUPPORTED, "--source gpio: %s", hz_devices_missing("gpio"));
            s = err.code;
        } else {
            char chip[128];
            snprintf(chip, sizeof chip, "%s", *rest ? rest : HZ_VSYNC_GPIO_CHIP);
            long line = HZ_VSYNC_GPIO_LINE;
            char *c = strchr(chip, ':');
            if (c) {
                *c++ = '\0';
                if (!hz_cli_parse_long("--source gpio:CHIP:LINE", c, 0, 1023, &line)) {
                    hz_sink_close(&sink);
                    return HZ_EXIT_USAGE;
                }
            }
            if (!*chip || line < 0) {
                hz_cli_error("--source gpio: this board names no v-sync GPIO; give gpio:CHIP:LINE");
                hz_sink_close(&sink);
                return HZ_EXIT_USAGE;
            }
            hz_gpio_cfg_t gc = { chip, (int)line, o.active_low || HZ_VSYNC_GPIO_ACTIVE_LOW, NULL, 0 };
            if (o.one_edge)
                gc.one_edge = o.edge_mode == HZ_EDGE_FALLING ? -1 : 1;
            s = hz_gpio_vsource_open(&src, &gc, &err);
        }
    } else if (!strcmp(kind, "fbdev")) {
        s = hz_fbdev_vsource_open(&src, *rest ? rest : HZ_DISPLAY_DEVICE, NULL, &err);
    } else if (!strcmp(kind, "drm")) {
        if (!src_open) {
            hz_cli_error("--source drm takes the vblank or page-flip events of the DRM sink: add --sink drm[:...]");
            hz_sink_close(&sink);
            return HZ_EXIT_USAGE;
        }
    } else if (!strcmp(kind, "v4l2")) {
        if (!src_open) {
            hz_cli_error("--source v4l2 takes the dequeue timestamps of a V4L2 output: add --sink v4l2:DEV");
            hz_sink_close(&sink);
            return HZ_EXIT_USAGE;
        }
    } else {
        hz_cli_error("--source: '%s' is not sim, gpio[:CHIP[:LINE]], fbdev[:DEV], v4l2, drm, vcd:FILE or csv:FILE",
                     o.source);
        hz_sink_close(&sink);
        return HZ_EXIT_USAGE;
    }
    if (s != HZ_OK) {
        hz_sink_close(&sink);
        return hz_cli_report(&err);
    }

    /* ---- frames ---- */
    hz_framesrc_t frames = hz_framesrc_testpattern();
    cfg.w = sink.w ? sink.w : (o.w ? o.w : 320);
    cfg.h = sink.h ? sink.h : (o.h ? o.h : 180);
    if (sink.w && o.w && (o.w != sink.w || o.h != sink.h)) {
        hz_error_set(&err, HZ_E_UNSUPPORTED, "%s: the display mode is %dx%d, --size asked for %dx%d", sink.name,
                     sink.w, sink.h, o.w, o.h);
        s = err.code;
    }
    if (s == HZ_OK && cfg.frames_mode && !strcmp(o.render, "scene"))
        s = hz_scene_framesrc(&frames, o.scene ? o.scene : "builtin", cfg.w, cfg.h, (int)o.render_scale,
                              (int)o.threads, o.mode && !strcmp(o.mode, "full") ? HZ_MODE_FULL : HZ_MODE_TDENSE,
                              &err);
    cfg.marker = o.marker < 0 ? strcmp(skind, "none") != 0 : o.marker;
    /* ---- run length and record capacity ---- */
    double hz_cap = o.hz > 0 ? o.hz : 1000;
    double seconds = o.seconds > 0 ? o.seconds : (o.frames ? 0 : 10);
    cfg.frames = o.frames;
    cfg.duration_ns = (int64_t)(seconds * 1e9);
    if (edges_only && trace_file && o.seconds <= 0)
        cfg.duration_ns = 0; /* the whole trace */
    cfg.max_frames = o.frames ? o.frames : (size_t)(seconds * hz_cap * 1.1) + 64;
    hz_pools_t *pools = hz_pools_get();
    if (!pools) {
        hz_error_set(&err, HZ_E_INTERNAL, "could not set up the static arenas");
        s = err.code;
    }
    if (s == HZ_OK) {
        if (edges_only && trace_file && cfg.duration_ns == 0) {
            /* A trace of unknown length: as many edges as the frame arena holds. */
            size_t per = sizeof(hz_edge_rec_t) + sizeof(uint32_t) + sizeof(int64_t);
            size_t avail = hz_arena_available(&pools->frame, 64);
            cfg.max_frames = 0;
            cfg.max_edges = avail > 1024 ? (avail - 1024) / per : 1;
        } else {
            double refreshes = o.frames ? (double)o.frames * 4 : seconds * hz_cap;
            cfg.max_edges = (size_t)(refreshes * 2.5) + 256;
        }
        if (!cfg.frames_mode)
            cfg.max_frames = 0;
    }
    hz_loop_result_t res;
    memset(&res, 0, sizeof res);
    hz_timebase_t tb;
    if (o.virt || (edges_only && !src.live))
        hz_tb_init_virtual(&tb, 0);
    else
        hz_tb_init_real(&tb);
    hz_arena_mark_t mark = pools ? hz_arena_mark(&pools->frame) : 0;
    if (s == HZ_OK)
        s = hz_loop_run(&cfg, &tb, &src, &sink, &frames, &pools->frame, &res, &err);
    hz_vsource_close(&src);
    hz_sink_close(&sink);
    if (s != HZ_OK) {
        if (pools)
            hz_arena_reset(&pools->frame, mark);
        return hz_cli_report(&err);
    }
    /* Recorded traces keep their own times in edges.csv; the simulated display has no clock but the loop's. */
    if (!trace_file)
        res.trace_offset_ns = 0;
    char clock[160];
    if (o.virt && cfg.frames_mode)
        snprintf(clock, sizeof clock, "simulated clock, render-time model %s%s%s", o.model,
                 o.wake ? ", wake-up up to " : "", o.wake ? o.wake : "");
    else if (tb.virtual_time)
        snprintf(clock, sizeof clock, "trace time (analysed as fast as it reads)");
    else
        snprintf(clock, sizeof clock, "real time (CLOCK_MONOTONIC)%s%s", sched[0] ? ", " : "", sched);
    hz_report_info_t info = { src.name, sink.name, frames.name, clock, cfg.w, cfg.h, cfg.marker };
    static hz_report_t rep;
    hz_report_compute(&rep, &cfg, &info, &res);
    if (!o.quiet)
        hz_report_print(stdout, &rep);
    s = hz_report_write(o.out, &rep, &err);
    hz_arena_reset(&pools->frame, mark);
    if (s != HZ_OK)
        return hz_cli_report(&err);
    if (!o.quiet)
        printf("wrote     %s/{%sedges.csv,report.json,histogram.svg}\n", o.out, cfg.frames_mode ? "frames.csv," : "");
    if (res.lock.verdict != HZ_LOCK_OK) {
        char why[256];
        hz_cli_error("%s: no lock: %s", src.name, hz_report_lock_reasons(why, sizeof why, &res.lock));
        return HZ_EXIT_NOLOCK;
    }
    if (res.lock.far && o.quiet)
        hz_cli_error("warning: %s: the measured rate %.4f Hz is far from --hz %g", src.name,
                     1e9 * 65536.0 / (double)res.lock.period_q16, o.hz);
    return 0;
}
