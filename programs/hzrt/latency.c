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
#include "showopts.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: hzrt latency [options]\n"
            "\n"
            "Runs the display-locked frame loop against a v-sync source and reports deadline misses, latency\n"
            "(scan-out edge - render start), slack, phase error, dropped and repeated frames, and the v-sync\n"
            "model (period, drift, jitter, missed and spurious edges); or, with --edges-only (the default for\n"
            "trace files without --render or --virtual), analyses the edges alone. Writes frames.csv, edges.csv,\n"
            "report.json and histogram.svg to --out (and summary.json with --render scene).\n"
            "\n"
            "This board: v-sync source %s%s%s, display sink %s, %d Hz.\n"
            "An option that does nothing with the run's source, sink or frames is refused (each says below what\n"
            "it acts with).\n"
            "\n",
            HZ_VSYNC_SOURCE == HZ_VSYNC_GPIO ? "gpio" : HZ_VSYNC_SOURCE == HZ_VSYNC_FBDEV ? "fbdev" : "sim",
            HZ_VSYNC_SOURCE == HZ_VSYNC_GPIO ? " " : "", HZ_VSYNC_SOURCE == HZ_VSYNC_GPIO ? HZ_VSYNC_GPIO_CHIP : "",
            !strcmp(HZ_DISPLAY_SINK, "drm") ? "DRM (fbdev " HZ_DISPLAY_DEVICE " without a DRM card)"
            : !strcmp(HZ_DISPLAY_SINK, "none") ? "none (a simulated display shows nothing)"
                                               : "fbdev " HZ_DISPLAY_DEVICE,
            HZ_DISPLAY_HZ);
    hz_sopts_usage(f, HZ_OC_LATENCY);
    fputs("\n"
          "exit status: 0 ok, 2 bad command line, 3 no lock or a run too short to judge one (files written),\n"
          "64+N failure with hz status N (68 a malformed trace, 73 a file that cannot be read or written, 75 no\n"
          "v-sync: time-out)\n\n",
          f);
    hz_ropts_usage(f);
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
    c->scene.rigid = ro->rigid;
    c->scene.segments = ro->segments;
    c->scene.threads = ro->threads;
    c->scene.start = ro->start;
    c->scene.prepare = hz_ropts_prepare;
    c->scene.prepare_ctx = ro;
    c->adaptive = &ro->adaptive;
    c->ropts = ro;
    return 0;
}

int hz_cmd_latency(int argc, char **argv)
{
    static hz_show_cfg_t c;
    static hz_ropts_t ro;
    hz_show_defaults(&c);
    c.cmd = "latency";
    c.out = "out/latency";
    hz_ropts_defaults(&ro, "latency", HZ_MODE_TDENSE);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        }
        int used = hz_opts_take(&c, HZ_OC_LATENCY, &ro, argc, argv, &i);
        if (used < 0)
            return -used;
        if (used)
            continue;
        hz_cli_error("latency: unknown option '%s' (try hzrt latency --help)", a);
        return HZ_EXIT_USAGE;
    }
    char kind[16];
    snprintf(kind, sizeof kind, "%s", c.source);
    char *colon = strchr(kind, ':');
    if (colon)
        *colon = 0;
    const bool trace_file = !strcmp(kind, "vcd") || !strcmp(kind, "csv");
    const char *render = c.render_what;
    /* A recorded trace is analysed edge by edge unless frames are asked for (--virtual, --render). */
    c.what = c.edges_only || (trace_file && !c.virt && !render) ? HZ_SHOW_EDGES
             : render && !strcmp(render, "scene")              ? HZ_SHOW_SCENE
                                                                 : HZ_SHOW_PATTERN;
    if (render && c.edges_only) {
        hz_cli_error("latency: --render and --edges-only: capturing edges only renders nothing");
        return HZ_EXIT_USAGE;
    }
    if (ro.given_n && c.what != HZ_SHOW_SCENE) {
        hz_cli_error("latency: %s renders a scene: it needs --render scene%s", ro.given[0]->name,
                     c.what == HZ_SHOW_EDGES ? " (and frames, not --edges-only)" : "");
        return HZ_EXIT_USAGE;
    }
    if (c.what == HZ_SHOW_SCENE) {
        int rc = hz_show_from_ropts(&c, &ro, c.scene_path ? c.scene_path : "builtin");
        if (rc)
            return rc;
    }
    return hz_show_run(&c);
}
