/*
 * show.h — one run of the frame loop (hz/frameloop.h) from a command line: what `hzrt render`, `hzrt latency` and
 * `hzrt show` do. The frames (a scene through the renderer in any mode, or the test pattern), the sink (files,
 * none, DRM/KMS, fbdev, V4L2 or the board's display) and the v-sync source (offline, a simulated display, GPIO,
 * fbdev, DRM, V4L2 or a recorded trace) combine freely.
 *
 * Contract:
 *  - hz_show_run() checks the combination first (a usage error names the options and exits 2 before anything is
 *    opened or written), prepares --out (refused now if it cannot be written), opens the sink (its mode sets the
 *    frame size), the source and the frames, runs the loop and writes what the run asks for:
 *      files sink: frames.y4m (more than one frame) and last.png (last.ppm without libpng), the frames as shown;
 *      a scene: summary.json (settings, frame times, rays, memory) and, when asked, last.pfm (the last frame,
 *        linear float, at its level's size) and the adaptive mask map;
 *      a display source (anything but offline): the latency report (frames.csv, edges.csv, report.json,
 *        histogram.svg), with each frame's quality level and, with the governor, the share of time at each
 *        level and, when level_error_frames > 0, each level's error against level 0 (PSNR and FLIP of the
 *        frames as shown, after that many frames).
 *  - Offline: a simulated display with no jitter on a simulated clock and zero render time: every frame is
 *    rendered, in order, for the refresh after the one before (scene time start + n / hz exactly), as fast as
 *    the machine renders; nothing is paced, so the governor is off.
 *  - The governor (cfg->budget) is on by default when a display or a simulated display in real time sets the
 *    pace; --budget off keeps level 0, and then a scene renders exactly the frames it renders offline.
 *  - Returns the exit status: 0, HZ_EXIT_USAGE (2), HZ_EXIT_NOLOCK (3: files written, no lock), or 64 + the hz
 *    status of a failure.
 */
#ifndef HZ_PORT_SHOW_H
#define HZ_PORT_SHOW_H

#include <stdbool.h>
#include <stdint.h>

#include "adaptive_cli.h"
#include "hz/lockv.h"
#include "scenesrc.h"

enum { HZ_SHOW_PATTERN = 0, HZ_SHOW_SCENE = 1, HZ_SHOW_EDGES = 2 };
#define HZ_SHOW_MAX_OFFLINE_FRAMES 100000

typedef struct hz_show_cfg {
    const char *cmd;               /* "render", "latency", "show": names the command in messages */
    int what;                      /* HZ_SHOW_* */
    hz_scenesrc_cfg_t scene;       /* HZ_SHOW_SCENE: scene, level-0 render options, backend, threads, start */
    int render_scale;              /* scene: render 1/N of the frame's width and height, shown as N x N blocks */
    bool render_scale_given;
    const hz_adaptive_cli_t *adaptive; /* scene: focus names to resolve, --adaptive-map (NULL: none) */
    const struct hz_ropts *ropts;  /* scene: the render options as given (summary.json's settings) */
    /* where */
    const char *sink;              /* files | none | display | drm[:...] | fbdev[:DEV] | v4l2:DEV[:FMT] */
    int drm_buffers;
    const char *out;               /* the output folder */
    bool video, png, pfm;          /* files: frames.y4m, last.png; any sink: last.pfm */
    int w, h;                      /* the frame size where the sink has no mode of its own (a scene renders at
                                      w / render_scale x h / render_scale) */
    bool size_given;               /* w, h came from --size: a sink whose mode differs refuses it */
    /* when */
    const char *source;            /* offline | sim | gpio[:CHIP[:LINE]] | fbdev[:DEV] | drm | v4l2 | vcd:F | csv:F */
    double hz;                     /* nominal refresh (0: learn it) */
    double jitter_us, drift_ppm, miss_pct, glitch_pct;
    long seed;
    const char *signal;
    int edge_mode, active_low, one_edge;
    long timeout_ms;
    int virt;
    const char *model, *wake;
    double percentile;
    long window, lookahead;
    const char *guard, *latch;
    hz_lockv_cfg_t lock;
    uint64_t frames;               /* run length: frames, or */
    double seconds;                /* seconds (0 and frames 0: 10 s; a trace: all of it) */
    int marker;                    /* frame-id marker: 1, 0, -1 (on with a display sink) */
    int budget;                    /* governor: 1, 0, -1 (on when a display or real-time simulation paces) */
    uint32_t level_error_frames;   /* 0: no level-error measurement */
    int rt, quiet;
    /* the command line (showopts.h): the options given, for the applicability check; latency's --render,
     * --scene, --edges-only */
    const struct hz_opt *given[64];
    int given_n;
    const char *render_what, *scene_path;
    bool edges_only;
} hz_show_cfg_t;

/* Defaults of every command: the test pattern, sink none, source the board's, 10 s, 320x180 frames, marker
 * and budget by default, render scale 1, files' video and last.png on. */
void hz_show_defaults(hz_show_cfg_t *c);
int hz_show_run(hz_show_cfg_t *c);
/* Set (the option parsers' fuzz target): hz_show_run returns 0 once the command line is checked, before --out
 * is made or anything is opened, rendered or written. */
extern bool hz_show_check_only;

#endif
