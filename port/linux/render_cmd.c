/* `hzrt render` and `hzrt show`: a scene through the one frame loop (show.h), to files by default or to a display
 * locked to its v-sync. See `hzrt render --help`. */
#include "render_cmd.h"

#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "hz/hz.h"
#include "latency.h"
#include "phase.h"
#include "renderopts.h"
#include "show.h"

#define MAX_FRAMES 100000

static void usage_show(FILE *f)
{
    fprintf(f,
            "usage: hzrt show [SCENE] [options]\n"
            "\n"
            "The board's default command: shows %s (or SCENE) in %s mode on the board's display (%s)\n"
            "locked to its v-sync (%s), with the frame-budget governor keeping every frame within the refresh\n"
            "period, for 10 s (--seconds, --frames), and writes the latency report (frames.csv with each frame's\n"
            "quality level, edges.csv, report.json, histogram.svg) and summary.json to out/show. It is\n"
            "`hzrt render` with these defaults: every option of `hzrt render --help` applies.\n\n",
            HZ_DISPLAY_SCENE, hz_render_mode_name(HZ_DISPLAY_MODE), HZ_DISPLAY_SINK,
            HZ_VSYNC_SOURCE == HZ_VSYNC_GPIO ? "GPIO" : HZ_VSYNC_SOURCE == HZ_VSYNC_FBDEV ? "fbdev" : "simulated");
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: hzrt render SCENE|builtin [options]\n"
            "\n"
            "Renders SCENE (a .hzb file from tools/bake, or the built-in scene) in any mode, through the one frame\n"
            "loop that also drives displays. By default every frame goes to files at a simulated refresh rate\n"
            "(--source offline: frame n shows scene time start + n / hz, however long it takes):\n"
            "  frames.y4m    the sequence (when more than one frame; plays in mpv/ffplay, converts with ffmpeg)\n"
            "  last.png      the last frame, 8-bit sRGB\n"
            "  last.pfm      the last frame, linear float (with --pfm)\n"
            "  summary.json  what the run did and how fast (also printed)\n"
            "With a display (--sink drm|fbdev|v4l2|display, --source gpio|drm|fbdev|v4l2|sim|vcd:F|csv:F) the frames\n"
            "are paced to its v-sync, the frame-budget governor keeps each frame within the refresh period, and the\n"
            "latency report is written as by `hzrt latency` (frames.csv, edges.csv, report.json, histogram.svg).\n"
            "\n"
            "options:\n"
            "  --size WxH        frame size [8..8192 a side]; default the board's display (%dx%d)\n"
            "  --hz N            refresh rate of the (simulated) display [1..1000]; default %d\n"
            "  --frames N        frames to render [1..%d]; default 1 offline, else --seconds 10\n"
            "  --out DIR         output folder (created); default out\n"
            "  --no-y4m          files sink: do not write the video\n"
            "  --pfm             also write last.pfm\n"
            "  --quiet           no progress and no printed summary (the files are still written)\n"
            "  --sink S          files (default), none, display, drm[:CARD[:CONNECTOR[:WxH[@HZ]]]], fbdev[:DEV],\n"
            "                    v4l2:DEV[:FMT]\n"
            "  --source V        offline (default), sim, gpio[:CHIP[:LINE]], fbdev[:DEV], drm, v4l2, vcd:FILE,\n"
            "                    csv:FILE (see hzrt latency --help for the source, pacing and lock options, which\n"
            "                    render takes as well)\n"
            "  --budget on|off   the frame-budget governor (default: on when a display or a real-time simulated\n"
            "                    display paces the frames; refused offline and with --virtual)\n"
            "  --render-scale N  render 1/N of the width and height [1..64], each pixel shown N x N\n"
            "  -h, --help        this text\n"
            "\n"
            "Options of one mode (--spp, --msaa4: full; --ordering, --no-reflected-mv, --tdense-gamma: tdense;\n"
            "--taa-*: taa; --tau*, --focus-objects, --normal-angle, --adaptive-map: adaptive) are refused in the\n"
            "others, where they would do nothing. A scene without lights gets a default light (the summary says so).\n"
            "\n"
            "exit status: 0 ok, 2 bad command line, 3 no lock (a display run: files written), 64+N failure with hz\n"
            "status N (66: the scene or the frame does not fit the board's arenas, 68/70: malformed or corrupt\n"
            "scene, 73: a file that cannot be read or written, e.g. an --out that is not writable; killed by a\n"
            "signal, it removes its temporary files)\n\n",
            HZ_DISPLAY_WIDTH, HZ_DISPLAY_HEIGHT, HZ_DISPLAY_HZ, MAX_FRAMES);
    hz_ropts_usage(f);
}

static hz_status_t prepare_scene(void *ctx, const hz_scene_t *scene, hz_render_opts_t *opts, hz_error_t *err)
{
    const hz_ropts_t *ro = ctx;
    hz_status_t s = hz_adaptive_cli_resolve(&ro->adaptive, scene, &opts->adaptive, err);
    if (s == HZ_OK && opts->transparency != HZ_TRANSP_EXACT && !(scene->features & HZ_FEAT_BLEND) && !hz_phase_muted)
        fprintf(stderr, "%s: %s: --transparency %s: the scene has no blended surfaces; it renders as exact\n",
                hz_cli_prog, ro->cmd, hz_transp_name(opts->transparency));
    return s;
}

/* The commands' shared body: cmd "render" (files and offline by default) or "show" (the board's display). */
static int run(int argc, char **argv, const char *cmd, const char *default_scene, bool display)
{
    static hz_show_cfg_t c;
    static hz_ropts_t ro;
    hz_show_defaults(&c);
    c.cmd = cmd;
    c.what = HZ_SHOW_SCENE;
    c.w = HZ_DISPLAY_WIDTH, c.h = HZ_DISPLAY_HEIGHT;
    if (display) {
        c.sink = "display";
        c.out = "out/show";
        c.seconds = 0;
    } else {
        c.sink = "files";
        c.source = "offline";
    }
    hz_ropts_defaults(&ro, cmd, HZ_DISPLAY_MODE);
    const char *scene = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            if (display)
                usage_show(stdout);
            else
                usage(stdout);
            return 0;
        }
        int used = hz_latency_opt_take(&c, argc, argv, &i);
        if (used < 0)
            return -used;
        if (used) {
            if (!strcmp(a, "--frames") && c.frames > MAX_FRAMES && !strcmp(c.source, "offline")) {
                hz_cli_error("%s: --frames: %llu is more than %d offline frames", cmd, (unsigned long long)c.frames,
                             MAX_FRAMES);
                return HZ_EXIT_USAGE;
            }
            continue;
        }
        used = hz_ropts_take(&ro, argc, argv, i);
        if (used < 0)
            return -used;
        if (used) {
            i += used - 1;
            continue;
        }
        if (!strcmp(a, "--no-y4m")) {
            c.video = false;
        } else if (!strcmp(a, "--pfm")) {
            c.pfm = true;
        } else if (a[0] == '-') {
            hz_cli_error("%s: unknown option '%s' (try hzrt %s --help)", cmd, a, cmd);
            return HZ_EXIT_USAGE;
        } else if (!scene) {
            scene = a;
        } else {
            hz_cli_error("%s: more than one scene given ('%s', '%s')", cmd, scene, a);
            return HZ_EXIT_USAGE;
        }
    }
    if (!scene)
        scene = default_scene;
    if (!scene) {
        hz_cli_error("%s: which scene? (a .hzb file or `builtin`; try hzrt %s --help)", cmd, cmd);
        return HZ_EXIT_USAGE;
    }
    if (!c.frames && !c.seconds && !strcmp(c.source, "offline"))
        c.frames = 1;
    int rc = hz_show_from_ropts(&c, &ro, scene);
    if (rc)
        return rc;
    c.scene.prepare = prepare_scene;
    c.scene.prepare_ctx = &ro;
    hz_phase_muted = c.quiet;
    return hz_show_run(&c);
}

int hz_cmd_render(int argc, char **argv)
{
    return run(argc, argv, "render", NULL, false);
}

int hz_cmd_show(int argc, char **argv)
{
    return run(argc, argv, "show", HZ_DISPLAY_SCENE, true);
}
