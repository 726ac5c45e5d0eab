/* `hzrt render` and `hzrt show`: a scene through the one frame loop (show.h), to files by default or to a display
 * locked to its v-sync. See `hzrt render --help`. */
#include "render_cmd.h"

#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "hz/hz.h"
#include "latency.h"
#include "renderopts.h"
#include "show.h"
#include "showopts.h"

static void usage(FILE *f, const char *cmd)
{
    if (!strcmp(cmd, "show"))
        fprintf(f,
                "usage: hzrt show [SCENE|builtin] [options]\n"
                "\n"
                "The board's default: its scene (%s) in its mode (%s) on its display (--sink display: %s), locked\n"
                "to its v-sync source (%s), with the frame-budget governor keeping every frame within the refresh\n"
                "period, for 10 s (--seconds, --frames), and the latency report (frames.csv with each frame's quality\n"
                "level, edges.csv, report.json, histogram.svg, summary.json) in out/show. It takes every option of\n"
                "hzrt render.\n",
                HZ_DISPLAY_SCENE, hz_render_mode_name(HZ_DISPLAY_MODE), HZ_DISPLAY_SINK,
                HZ_VSYNC_SOURCE == HZ_VSYNC_GPIO ? "GPIO" : HZ_VSYNC_SOURCE == HZ_VSYNC_FBDEV ? "fbdev" : "simulated");
    else
        fprintf(f,
                "usage: hzrt render SCENE|builtin [options]\n"
                "\n"
                "Renders SCENE (a .hzb file from hzbake, or the built-in scene) in any mode, through the one frame\n"
                "loop that also drives displays. By default every frame goes to files at a simulated refresh rate\n"
                "(--source offline: frame n shows scene time start + n / hz, however long it takes):\n"
                "  frames.y4m    the sequence (when more than one frame; plays in mpv/ffplay, converts with ffmpeg)\n"
                "  last.png      the last frame, 8-bit sRGB (last.ppm in builds without libpng)\n"
                "  last.pfm      the last frame, linear float (with --pfm)\n"
                "  summary.json  what the run did, every setting that changes the image, how fast (also printed)\n"
                "An offline run renders one complete image by default: 4 frames in tdense mode (each traces one pixel\n"
                "of every 2x2 tile), 1 in the others. Interrupted (Ctrl-C), it finishes the frame in progress and\n"
                "keeps the frames so far, with summary.json marked \"interrupted\"; a second Ctrl-C quits at once.\n"
                "With a display (--sink drm|fbdev|v4l2|display, --source gpio|drm|fbdev|v4l2|sim|vcd:F|csv:F) the frames\n"
                "are paced to its v-sync, the frame-budget governor keeps each frame within the refresh period, and the\n"
                "latency report is written as by `hzrt latency` (frames.csv, edges.csv, report.json, histogram.svg).\n"
                "A scene without lights gets a default light (the summary says so).\n");
    fputs("\noptions (an option that does nothing with the run's source, sink or frames is refused):\n"
          "  -h, --help            this text\n",
          f);
    hz_sopts_usage(f, !strcmp(cmd, "show") ? HZ_OC_SHOW : HZ_OC_RENDER);
    fputs("\n"
          "exit status: 0 ok, 2 bad command line (also an output that is an input or another output), 3 no lock\n"
          "or a run too short to judge one (a display run: files written), 64+N failure with hz status N (66:\n"
          "the scene or the frame does not fit the board's arenas, 68/70: malformed or corrupt scene, 72: the\n"
          "scene or an option needs a feature this build leaves out (doc/features.md), 73: a file that cannot\n"
          "be read or written, e.g. an --out that is not writable); killed by a signal, it removes\n"
          "its temporary files, and on SIGINT, SIGTERM or SIGHUP first keeps the frames it finished\n\n",
          f);
    hz_ropts_usage(f);
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
            usage(stdout, cmd);
            return 0;
        }
        int used = hz_opts_take(&c, display ? HZ_OC_SHOW : HZ_OC_RENDER, &ro, argc, argv, &i);
        if (used < 0)
            return -used;
        if (used)
            continue;
        if (a[0] == '-') {
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
    int rc = hz_show_from_ropts(&c, &ro, scene);
    if (rc)
        return rc;
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
