/* The frame loop's run options: table, parser, applicability, settings (see showopts.h). */
#include "showopts.h"

#include <string.h>

#include "cli.h"
#include "hz/config.h"
#include "hz/frameloop.h"
#include "hz/pace.h"

#define STR2(x) #x
#define STR(x) STR2(x)

typedef enum opt_id {
    S_SOURCE, S_SINK, S_OUT, S_QUIET, S_NO_Y4M, S_PFM, S_RENDER, S_SCENE, S_EDGES_ONLY,
    S_HZ, S_JITTER, S_DRIFT, S_MISS, S_GLITCH, S_SEED,
    S_SIGNAL, S_EDGE, S_ACTIVE_LOW, S_ONE_EDGE, S_TIMEOUT, S_DRM_BUFFERS,
    S_LOCK_MIN_RUN, S_LOCK_RELOCK, S_LOCK_SPURIOUS, S_LOCK_MISSED,
    S_FRAMES, S_SECONDS, S_SIZE, S_RENDER_SCALE, S_BUDGET, S_LEVEL_ERROR, S_MARKER, S_NO_MARKER,
    S_VIRTUAL, S_RENDER_MODEL, S_WAKE,
    S_PERCENTILE, S_WINDOW, S_GUARD, S_LATCH, S_LOOKAHEAD, S_RT,
} opt_id_t;

static const char *const render_words[] = { "pattern", "scene", NULL };
static const char *const edge_words[] = { "rising", "falling", "any", NULL };
static const char *const onoff_words[] = { "on", "off", NULL };

#define PACED (HZ_OW_DISPLAY_SOURCES | HZ_OW_FRAMES)
#define LAT HZ_OC_LATENCY

static const hz_opt_t table[] = {
    { .section = "source, sink, output", .name = "--source", .arg = "V", .kind = HZ_OPT_TEXT, .id = S_SOURCE,
      .help = "where v-sync comes from: offline (every frame, back to back, frame n at scene time start + n / "
              "hz), sim (a simulated display), gpio[:CHIP[:LINE]] (GPIO edge events via libgpiod), fbdev[:DEV] "
              "(FBIO_WAITFORVSYNC), drm (the DRM sink's vblank or page-flip events; needs --sink drm), v4l2 (the "
              "V4L2 output's dequeue times; needs --sink v4l2:DEV), vcd:FILE (a sigrok/PulseView logic-analyser "
              "trace) or csv:FILE (t_ns[,level] lines, or hzrt's edges.csv); trace files are regular files. "
              "Default: render offline, latency and show the board's" },
    { .name = "--sink", .arg = "S", .kind = HZ_OPT_TEXT, .id = S_SINK,
      .help = "where frames go: files (frames.y4m and last.png in --out), none, display (the board's), "
              "drm[:CARD[:CONNECTOR[:WxH[@HZ]]]] (DRM/KMS page flips; default the first card with a connected "
              "display, its first connected connector, the preferred mode), fbdev[:DEV] or "
              "v4l2:DEV[:rgb24|xrgb32|yuyv]. Default: render files, latency none, show display" },
    { .name = "--out", .arg = "DIR", .kind = HZ_OPT_TEXT, .id = S_OUT,
      .help = "output folder, created with its parents (a run that fails removes the folders it created); every "
              "output is checked before the run: none may be an input or another output. Default: render out, "
              "latency out/latency, show out/show" },
    { .name = "--quiet", .kind = HZ_OPT_FLAG, .id = S_QUIET,
      .help = "no progress and no printed summary (every file is still written)" },
    { .name = "--no-y4m", .kind = HZ_OPT_FLAG, .where = HZ_OW_FILES, .id = S_NO_Y4M,
      .help = "do not write frames.y4m" },
    { .name = "--pfm", .kind = HZ_OPT_FLAG, .where = HZ_OW_SCENE, .id = S_PFM,
      .help = "also write last.pfm: the last frame, linear float, at its rendered size" },
    { .name = "--render", .arg = "pattern|scene", .kind = HZ_OPT_WORD, .words = render_words, .cmds = LAT, .id = S_RENDER,
      .help = "what to draw: the test pattern, or a scene through the renderer in any mode with any render "
              "option (listed below); default pattern" },
    { .name = "--scene", .arg = "FILE", .kind = HZ_OPT_TEXT, .cmds = LAT, .where = HZ_OW_SCENE, .id = S_SCENE,
      .help = "the scene: a baked .hzb or builtin; default builtin" },
    { .name = "--edges-only", .kind = HZ_OPT_FLAG, .cmds = LAT, .id = S_EDGES_ONLY,
      .help = "capture and classify edges, render nothing (the default for trace files without --render or "
              "--virtual)" },

    { .section = "the display's rate; a simulated display (--source sim)", .name = "--hz", .arg = "HZ",
      .kind = HZ_OPT_REAL, .lo = 0, .hi = 1000, .flags = HZ_OF_IMAGE, .id = S_HZ, .sample = "30",
      .help = "refresh rate, may have decimals: the simulated display's, the nominal rate of a real one, the "
              "frame rate of offline frames; 0 learns it from the edges (not offline or sim). Default " STR(
                  HZ_DISPLAY_HZ) },
    { .name = "--jitter-us", .arg = "N", .kind = HZ_OPT_REAL, .lo = 0, .hi = 1e6, .where = HZ_OW_SIM, .id = S_JITTER,
      .help = "edge jitter, microseconds; default 0" },
    { .name = "--drift-ppm", .arg = "N", .kind = HZ_OPT_REAL, .lo = -100000, .hi = 100000, .where = HZ_OW_SIM,
      .id = S_DRIFT, .help = "rate error against --hz, ppm; default 0" },
    { .name = "--miss-pct", .arg = "X", .kind = HZ_OPT_REAL, .lo = 0, .hi = 50, .where = HZ_OW_SIM, .id = S_MISS,
      .help = "missed pulses, percent; default 0" },
    { .name = "--glitch-pct", .arg = "X", .kind = HZ_OPT_REAL, .lo = 0, .hi = 100, .where = HZ_OW_SIM,
      .id = S_GLITCH, .help = "spurious extra edges, percent; default 0" },
    { .name = "--seed", .arg = "N", .kind = HZ_OPT_INT, .lo = 0, .hi = 2147483647, .id = S_SEED,
      .help = "seed of the simulated display and the render-time model; default 1" },

    { .section = "device and trace sources", .name = "--signal", .arg = "NAME", .kind = HZ_OPT_TEXT,
      .where = HZ_OW_VCD, .id = S_SIGNAL, .help = "the VCD signal that carries v-sync; default the first" },
    { .name = "--edge", .arg = "E", .kind = HZ_OPT_WORD, .words = edge_words,
      .where = HZ_OW_DISPLAY_SOURCES & ~HZ_OW_SIM, .id = S_EDGE,
      .help = "v-sync polarity: rising, falling or any (every edge, e.g. a photodiode on the marker); default "
              "the board's" },
    { .name = "--active-low", .kind = HZ_OPT_FLAG, .where = HZ_OW_GPIO, .id = S_ACTIVE_LOW,
      .help = "the line is active low" },
    { .name = "--gpio-one-edge", .kind = HZ_OPT_FLAG, .where = HZ_OW_GPIO, .id = S_ONE_EDGE,
      .help = "request only the v-sync polarity's edges (default both: pulse widths)" },
    { .name = "--timeout-ms", .arg = "MS", .kind = HZ_OPT_INT, .lo = 1, .hi = 3600000,
      .where = HZ_OW_DISPLAY_SOURCES, .id = S_TIMEOUT,
      .help = "give up after this long without an edge (a live source) or without a lock; default max(500, 10 "
              "periods)" },
    { .name = "--drm-buffers", .arg = "N", .kind = HZ_OPT_INT, .lo = 2, .hi = 3, .where = HZ_OW_DRM,
      .id = S_DRM_BUFFERS, .help = "DRM sink: double or triple buffering; default 2" },

    { .section = "lock verdict (a run that fails it, or is too short to judge it, exits 3 and reports no period)",
      .name = "--lock-min-run", .arg = "N", .kind = HZ_OPT_INT, .lo = 2, .hi = 1000000,
      .where = HZ_OW_DISPLAY_SOURCES, .id = S_LOCK_MIN_RUN,
      .help = "a locked stretch needs N accepted edges in a row without a relock; default 32" },
    { .name = "--lock-max-relock-pct", .arg = "X", .kind = HZ_OPT_REAL, .lo = 0, .hi = 100,
      .where = HZ_OW_DISPLAY_SOURCES, .id = S_LOCK_RELOCK,
      .help = "relocks at most X% of the accepted edges; default 1" },
    { .name = "--lock-max-spurious-pct", .arg = "X", .kind = HZ_OPT_REAL, .lo = 0, .hi = 100,
      .where = HZ_OW_DISPLAY_SOURCES, .id = S_LOCK_SPURIOUS,
      .help = "spurious edges at most X% of the v-sync edges; default 10" },
    { .name = "--lock-max-missed-pct", .arg = "X", .kind = HZ_OPT_REAL, .lo = 0, .hi = 100,
      .where = HZ_OW_DISPLAY_SOURCES, .id = S_LOCK_MISSED,
      .help = "missed pulses at most X% of the refreshes; default 10. The period comes from the locked stretches "
              "only; a rate more than 1% off --hz is a warning" },

    { .section = "frames", .name = "--frames", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = 100000000,
      .id = S_FRAMES,
      .help = "run length in frames, at most 100000 with --source offline; default: offline one complete image "
              "(4 frames in tdense mode, 1 in the others), else --seconds 10 (a trace: all of it)" },
    { .name = "--seconds", .arg = "S", .kind = HZ_OPT_REAL, .lo = 0.001, .hi = 86400,
      .where = HZ_OW_DISPLAY_SOURCES, .id = S_SECONDS, .help = "run length in seconds" },
    { .name = "--size", .arg = "WxH", .kind = HZ_OPT_SIZE, .lo = 8, .hi = 8192, .flags = HZ_OF_IMAGE, .id = S_SIZE,
      .sample = "48x27",
      .help = "frame size; default the sink's mode, else render and show the board's display (" STR(
                  HZ_DISPLAY_WIDTH) "x" STR(HZ_DISPLAY_HEIGHT) "), latency 320x180" },
    { .name = "--render-scale", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = 64, .where = HZ_OW_SCENE,
      .flags = HZ_OF_IMAGE, .id = S_RENDER_SCALE, .sample = "2",
      .help = "render 1/N of the width and height (both multiples of N), each pixel shown N x N; default 1" },
    { .name = "--budget", .arg = "on|off", .kind = HZ_OPT_WORD, .words = onoff_words, .where = HZ_OW_SCENE,
      .flags = HZ_OF_IMAGE, .id = S_BUDGET, .sample = "off", .needs = "--source sim --frames 8 --lock-min-run 8",
      .help = "the frame-budget governor: each frame at the best quality level that fits the display's period "
              "(render scale 3/4..1/8, fewer bounces, cheaper transparency and thresholds, a cheaper mode), with "
              "hysteresis; default on when a display or a simulated display in real time sets the pace, refused "
              "offline and with --virtual. frames.csv gives each frame's level" },
    { .name = "--level-error", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = 1000, .where = HZ_OW_SCENE,
      .id = S_LEVEL_ERROR,
      .help = "with the governor: after the run, each level the run used rendered for N frames against level 0: "
              "PSNR and FLIP in the report" },
    { .name = "--marker", .kind = HZ_OPT_FLAG, .where = HZ_OW_FRAMES, .flags = HZ_OF_IMAGE, .id = S_MARKER,
      .needs = "--size 64x36", .help = "draw the frame-id marker in the top-left corner (default: on with a device sink)" },
    { .name = "--no-marker", .kind = HZ_OPT_FLAG, .where = HZ_OW_FRAMES | HZ_OW_DEVICE_SINKS, .flags = HZ_OF_IMAGE,
      .id = S_NO_MARKER, .help = "no frame-id marker on a device sink" },

    { .section = "simulated clock", .name = "--virtual", .kind = HZ_OPT_FLAG, .id = S_VIRTUAL,
      .help = "a simulated clock (sim, vcd and csv sources): no sleeping, render times from --render-model" },
    { .name = "--render-model", .arg = "M", .kind = HZ_OPT_TEXT, .where = HZ_OW_VIRTUAL, .id = S_RENDER_MODEL,
      .help = "render times: const:T, uniform:A:B, spikes:A:B:PCT, triangle:A:B:N or step:A:B:N; T like 3ms, "
              "800us, 0.5P (of the period)" },
    { .name = "--wake", .arg = "T", .kind = HZ_OPT_TEXT, .where = HZ_OW_VIRTUAL, .id = S_WAKE,
      .help = "wake-ups oversleep up to T; default 0" },

    { .section = "pacing", .name = "--percentile", .arg = "P", .kind = HZ_OPT_REAL, .lo = 50, .hi = 100,
      .where = PACED, .id = S_PERCENTILE,
      .help = "plan each frame for this percentile of the recent costs; default 100 (the max)" },
    { .name = "--window", .arg = "N", .kind = HZ_OPT_INT, .lo = 16, .hi = HZ_PACE_WINDOW_MAX, .where = PACED,
      .id = S_WINDOW, .help = "recent costs kept; default 1024" },
    { .name = "--guard", .arg = "T", .kind = HZ_OPT_TEXT, .where = PACED, .id = S_GUARD,
      .help = "safety margin before the edge (a time like 1ms or 0.1P); default P/16" },
    { .name = "--latch", .arg = "T", .kind = HZ_OPT_TEXT, .where = PACED, .id = S_LATCH,
      .help = "the display latches a frame this long before its edge; default 0" },
    { .name = "--lookahead", .arg = "K", .kind = HZ_OPT_INT, .lo = 1, .hi = 16, .where = PACED, .id = S_LOOKAHEAD,
      .help = "frames in flight: a frame may take up to K periods; default 1" },
    { .name = "--rt", .kind = HZ_OPT_FLAG, .where = HZ_OW_DISPLAY_SOURCES | HZ_OW_REAL, .id = S_RT,
      .help = "real-time scheduling: SCHED_FIFO priority 50 and locked memory (needs root or CAP_SYS_NICE + "
              "CAP_IPC_LOCK; refused permissions are reported, not fatal)" },
};

#define TABLE_N (sizeof table / sizeof table[0])

/* The options given, each entry once: the list holds the whole table, so however many options a command line
 * repeats, every one is checked for where it acts (a full list once let the options after the 64th through). */
typedef char given_holds_table[sizeof((hz_show_cfg_t *)0)->given / sizeof((hz_show_cfg_t *)0)->given[0] >= TABLE_N ? 1 : -1];
static void note_given(const hz_opt_t **given, int *n, const hz_opt_t *t)
{
    for (int g = 0; g < *n; g++)
        if (given[g] == t)
            return;
    given[(*n)++] = t;
}

const hz_opt_t *hz_sopts_table(size_t *n)
{
    *n = TABLE_N;
    return table;
}

int hz_sopts_take(hz_show_cfg_t *c, unsigned cmd, int argc, char **argv, int *i)
{
    const char *a = argv[*i];
    const hz_opt_t *t = hz_opt_find(table, TABLE_N, a);
    if (!t || (t->cmds && !(t->cmds & cmd)))
        return 0;
    const char *v = NULL;
    if (t->arg) {
        if (*i + 1 >= argc) {
            hz_cli_error("%s: %s needs a value %s (try hzrt %s --help)", c->cmd, a, t->arg, c->cmd);
            return -HZ_EXIT_USAGE;
        }
        v = argv[++*i];
    }
    hz_opt_val_t x;
    if (!hz_opt_value(t, c->cmd, v, &x))
        return -HZ_EXIT_USAGE;
    note_given(c->given, &c->given_n, t);
    switch ((opt_id_t)t->id) {
    case S_SOURCE: c->source = v; break;
    case S_SINK: c->sink = v; break;
    case S_OUT: c->out = v; break;
    case S_QUIET: c->quiet = 1; break;
    case S_NO_Y4M: c->video = false; break;
    case S_PFM: c->pfm = true; break;
    case S_RENDER: c->render_what = v; break;
    case S_SCENE: c->scene_path = v; break;
    case S_EDGES_ONLY: c->edges_only = true; break;
    case S_HZ: c->hz = x.x; break;
    case S_JITTER: c->jitter_us = x.x; break;
    case S_DRIFT: c->drift_ppm = x.x; break;
    case S_MISS: c->miss_pct = x.x; break;
    case S_GLITCH: c->glitch_pct = x.x; break;
    case S_SEED: c->seed = x.n; break;
    case S_SIGNAL: c->signal = v; break;
    case S_EDGE: c->edge_mode = x.w == 0 ? HZ_EDGE_RISING : x.w == 1 ? HZ_EDGE_FALLING : HZ_EDGE_ANY; break;
    case S_ACTIVE_LOW: c->active_low = 1; break;
    case S_ONE_EDGE: c->one_edge = 1; break;
    case S_TIMEOUT: c->timeout_ms = x.n; break;
    case S_DRM_BUFFERS: c->drm_buffers = (int)x.n; break;
    case S_LOCK_MIN_RUN: c->lock.min_run = (uint32_t)x.n; break;
    case S_LOCK_RELOCK:
    case S_LOCK_SPURIOUS:
    case S_LOCK_MISSED: {
        uint32_t ppm = x.x >= 100 ? HZ_LOCK_ANY : (uint32_t)(x.x * 1e4 + 0.5);
        if (ppm == 0)
            ppm = HZ_LOCK_NONE; /* 0 in the configuration means the default */
        if (t->id == S_LOCK_RELOCK)
            c->lock.max_relock_ppm = ppm;
        else if (t->id == S_LOCK_SPURIOUS)
            c->lock.max_spurious_ppm = ppm;
        else
            c->lock.max_missed_ppm = ppm;
        break;
    }
    case S_FRAMES: c->frames = (uint64_t)x.n; break;
    case S_SECONDS: c->seconds = x.x; break;
    case S_SIZE:
        c->w = x.w, c->h = x.h;
        c->size_given = true;
        break;
    case S_RENDER_SCALE:
        c->render_scale = (int)x.n;
        c->render_scale_given = true;
        break;
    case S_BUDGET: c->budget = x.w == 0; break;
    case S_LEVEL_ERROR: c->level_error_frames = (uint32_t)x.n; break;
    case S_MARKER: c->marker = 1; break;
    case S_NO_MARKER: c->marker = 0; break;
    case S_VIRTUAL: c->virt = 1; break;
    case S_RENDER_MODEL: c->model = v; break;
    case S_WAKE: c->wake = v; break;
    case S_PERCENTILE: c->percentile = x.x; break;
    case S_WINDOW: c->window = x.n; break;
    case S_GUARD: c->guard = v; break;
    case S_LATCH: c->latch = v; break;
    case S_LOOKAHEAD: c->lookahead = x.n; break;
    case S_RT: c->rt = 1; break;
    }
    return 1;
}

int hz_sopts_check(const hz_show_cfg_t *c, unsigned run_where)
{
    for (int g = 0; g < c->given_n; g++)
        if (!hz_opt_acts(c->given[g], run_where))
            return hz_opt_refuse_idle(c->given[g], c->cmd, run_where);
    return 0;
}

void hz_sopts_usage(FILE *f, unsigned cmd)
{
    hz_opt_usage(f, table, TABLE_N, cmd, cmd & HZ_OC_LATENCY ? 0u : HZ_OW_WHAT); /* render and show: a scene */
}

static void member(FILE *f, bool *first, const char *key)
{
    fprintf(f, "%s\"%s\": ", *first ? "" : ", ", key);
    *first = false;
}

void hz_sopts_settings(FILE *f, const hz_show_cfg_t *c, bool *first)
{
    for (size_t k = 0; k < TABLE_N; k++) {
        const hz_opt_t *t = &table[k];
        if (!(t->flags & HZ_OF_IMAGE))
            continue;
        switch ((opt_id_t)t->id) {
        case S_HZ:
            member(f, first, "hz");
            fprintf(f, "%.6g", c->hz);
            break;
        case S_SIZE:
            member(f, first, "size");
            fprintf(f, "[%d, %d]", c->w, c->h);
            break;
        case S_RENDER_SCALE:
            member(f, first, "render_scale");
            fprintf(f, "%d", c->render_scale);
            break;
        case S_BUDGET:
            member(f, first, "governor");
            fputs(c->budget > 0 ? "true" : "false", f);
            break;
        case S_MARKER:
            member(f, first, "marker");
            fputs(c->marker > 0 ? "true" : "false", f);
            break;
        default: break; /* --no-marker: the same setting as --marker */
        }
    }
}

int hz_opts_take(hz_show_cfg_t *c, unsigned cmd, hz_ropts_t *r, int argc, char **argv, int *i)
{
    int used = hz_sopts_take(c, cmd, argc, argv, i);
    if (used)
        return used < 0 ? used : 1;
    used = hz_ropts_take(r, argc, argv, *i);
    if (used <= 0)
        return used;
    *i += used - 1;
    return 1;
}
