/* hzrt — the Linux entry point: dispatches subcommands (see `hzrt --help`). */
#include <stdio.h>
#include <string.h>

#include "accel_cmd.h"
#include "cli.h"
#include "fileio.h"
#include "hz/hz.h"
#include "latency.h"
#include "modeplan.h"
#include "hz/render.h"
#include "hz/skin.h"
#include "pools.h"
#include "render_cmd.h"
#include "scenefile.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: hzrt <command> [options]\n"
            "\n"
            "commands:\n"
            "  show         the board's default: its scene on its display in its default mode, locked to its\n"
            "               v-sync, with the frame-budget governor and the latency report\n"
            "  render SCENE render a scene (.hzb file or `builtin`) in any mode: to files (video, last frame,\n"
            "               summary), or to a display locked to its v-sync (--sink, --source)\n"
            "  info SCENE   validate a scene (.hzb file or `builtin`) and print its header, counts, features\n"
            "               and memory plan\n"
            "  board        print this build's board settings: display, arenas, features, v-sync source\n"
            "  accel SCENE  build a scene's acceleration structure: memory plan, build time, bytes per triangle\n"
            "  latency      display-locked latency: v-sync capture, frame pacing, report (CSV, JSON, SVG)\n"
            "\n"
            "options:\n"
            "  -h, --help   this text (also `hzrt <command> --help`)\n"
            "  --version    version and board\n"
            "\n"
            "exit status: 0 ok, 2 bad command line, 64+N a failure with hz status code N\n");
}

static const char *vsync_name(int source)
{
    switch (source) {
    case HZ_VSYNC_SIM: return "simulated";
    case HZ_VSYNC_GPIO: return "gpio";
    case HZ_VSYNC_FBDEV: return "fbdev";
    default: return "unknown";
    }
}

static int cmd_board(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            printf("usage: hzrt board\n\nPrints the board this binary was built for and its fixed memory.\n\n"
                   "exit status: 0 ok, 2 bad command line, %s\n",
                   HZ_POOLS_RESERVE ? "66 the arenas' address space could not be reserved"
                                    : "76 the static arenas could not be set up");
            return 0;
        }
        hz_cli_error("board: unknown option '%s' (try hzrt board --help)", argv[i]);
        return HZ_EXIT_USAGE;
    }
    hz_pools_t *p = hz_pools_get();
    if (!p) {
        hz_error_t err;
        hz_pools_error(&err, "board");
        return hz_cli_report(&err);
    }
    printf("board      %s\n", HZ_BOARD_NAME);
    printf("display    %dx%d @ %d Hz on %s\n", HZ_DISPLAY_WIDTH, HZ_DISPLAY_HEIGHT, HZ_DISPLAY_HZ,
           HZ_DISPLAY_DEVICE);
    printf("simd       %s, %d lanes\n",
#if defined(HZ_SIMD_AVX2)
           "avx2",
#elif defined(HZ_SIMD_NEON)
           "neon",
#else
           "scalar",
#endif
           HZ_SIMD_LANES);
    printf("vsync      %s", vsync_name(HZ_VSYNC_SOURCE));
    if (HZ_VSYNC_SOURCE == HZ_VSYNC_GPIO)
        printf(" (chip %s, line %d, %s edges%s)", HZ_VSYNC_GPIO_CHIP, HZ_VSYNC_GPIO_LINE,
               HZ_VSYNC_GPIO_EDGE == 0 ? "rising" : HZ_VSYNC_GPIO_EDGE == 1 ? "falling" : "all",
               HZ_VSYNC_GPIO_ACTIVE_LOW ? ", active low" : "");
    printf("\n");
    printf("features   textures=%d mirrors=%d transparency=%d motion=%d stats=%d\n", HZ_FEATURE_TEXTURES,
           HZ_FEATURE_MIRRORS, HZ_FEATURE_TRANSPARENCY, HZ_FEATURE_MOTION, HZ_FEATURE_STATS);
    printf("arenas     scene %zu MiB, accel %zu MiB, frame %zu MiB, %d x thread %zu MiB (%s)\n", p->scene.cap >> 20,
           p->accel.cap >> 20, p->frame.cap >> 20, HZ_MAX_THREADS, p->thread[0].cap >> 20,
           HZ_POOLS_RESERVE ? "reserved address space: RAM only where touched" : "static");
    return 0;
}

#define PL(n) ((n) == 1 ? "" : "s")

static void print_mib(const char *what, size_t bytes)
{
    printf("  %-22s %12zu bytes (%.1f MiB)\n", what, bytes, bytes / 1048576.0);
}

static int cmd_info(int argc, char **argv)
{
    const char *name = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            printf("usage: hzrt info SCENE\n\n"
                   "Validates SCENE (a .hzb file from hzbake, or `builtin`) exactly as a render would load it,\n"
                   "then prints its header, counts, feature mask and memory plan against this board's arenas.\n\n"
                   "exit status: 0 ok, 2 bad command line, 64+N failure with hz status N: 66 does not load into the\n"
                   "scene arena, 68 malformed, 69 unsupported version, 70 corrupt (a checksum fails), 73 missing or\n"
                   "unreadable file (a scene that loads but whose render would not fit exits 0: see the verdict)\n");
            return 0;
        }
        if (argv[i][0] == '-' || name) {
            hz_cli_error("info: unexpected argument '%s' (try hzrt info --help)", argv[i]);
            return HZ_EXIT_USAGE;
        }
        name = argv[i];
    }
    if (!name) {
        hz_cli_error("info: which scene? (a .hzb file or `builtin`)");
        return HZ_EXIT_USAGE;
    }
    hz_pools_t *pools = hz_pools_get();
    hz_scene_t scene;
    hz_error_t err;
    if (!pools) {
        hz_pools_error(&err, "info");
        return hz_cli_report(&err);
    }
    if (hz_scenefile_open(name, pools, &scene, &err) != HZ_OK)
        return hz_cli_report(&err);
    const hz_hzb_header_t *h = scene.header;
    char feats[160];
    hz_scene_features_str(scene.features, feats, sizeof feats);
    char shown[4 * HZ_HZB_NAME_BYTES + 1]; /* names come from the file: control bytes as \xNN, not to the terminal */
    printf("scene        %s (%s)\n", h->name[0] ? hz_cli_printable(shown, sizeof shown, (const char *)h->name,
                                                                   HZ_HZB_NAME_BYTES)
                                               : "(unnamed)", name);
    printf("format       .hzb version %u, %llu bytes, %u sections\n", h->version,
           (unsigned long long)h->file_bytes, h->section_count);
    printf("features     %s\n", feats);
    printf("geometry     %u triangle%s, %u vert%s, %u object%s\n", h->triangle_count, PL(h->triangle_count),
           h->vertex_count, h->vertex_count == 1 ? "ex" : "ices", h->object_count, PL(h->object_count));
    printf("materials    %u material%s, %u texture%s (%u texel%s)\n", h->material_count, PL(h->material_count),
           h->texture_count, PL(h->texture_count), h->texel_count, PL(h->texel_count));
    printf("lights       %u\n", h->light_count);
    printf("animation    %u camera keys, %u rigid keys, %u vertex keys, loop %.3g s\n", h->camera_key_count,
           h->rigid_key_count, h->vertex_key_count, (double)h->duration);
    if (h->joint_count)
        printf("skinning     %u joints, %u binds, skinned at run time (%s)\n", h->joint_count, h->skin_bind_count,
               hz_skin_blend_path());
    printf("bounds       (%.4g %.4g %.4g) .. (%.4g %.4g %.4g)\n", (double)h->bounds_min[0],
           (double)h->bounds_min[1], (double)h->bounds_min[2], (double)h->bounds_max[0],
           (double)h->bounds_max[1], (double)h->bounds_max[2]);
    for (uint32_t i = 0; i < scene.object_count; i++) {
        static const char *const kinds[] = { "static", "rigid keys", "vertex keys", "spin", "oscillate", "sway",
                                             "skinned" };
        const hz_object_t *o = &scene.objects[i];
        printf("  object %-3u %-24s %8u tris %8u verts  %s\n", i,
               hz_cli_printable(shown, sizeof shown, (const char *)o->name, HZ_HZB_NAME_BYTES), o->triangle_count,
               o->vertex_count, kinds[o->motion]);
    }
    /* The whole plan against this board's arenas: what a render at the display's size needs. */
    printf("memory plan (board %s, render at the display's %dx%d)\n", HZ_BOARD_NAME, HZ_DISPLAY_WIDTH,
           HZ_DISPLAY_HEIGHT);
    print_mib("scene image", scene.plan.file_bytes);
    print_mib("animation state", scene.plan.arena_bytes);
    if (scene.plan.skin_bytes)
        print_mib("of it joint matrices", scene.plan.skin_bytes);
    print_mib("scene arena used", pools->scene.used);
    print_mib("scene arena size", pools->scene.cap);
    hz_accel_config_t acfg;
    hz_accel_config_default(&acfg);
    hz_accel_bytes_t ab = hz_accel_bytes_bound(scene.triangle_count, &acfg);
    print_mib("accel build, at most", ab.peak);
    print_mib("accel kept, at most", ab.kept);
    print_mib("accel arena size", pools->accel.cap);
    print_mib("frame arena size", pools->frame.cap);
    print_mib("thread arena size", pools->thread[0].cap);
    /* Every render mode's plan at the display's size; the verdict is for hzrt render's default mode. */
    int fits = ab.peak <= pools->accel.cap;
    fits = hz_modeplan_print(stdout, &scene, pools, HZ_DISPLAY_WIDTH, HZ_DISPLAY_HEIGHT) && fits;
    printf("verdict      %s: default mode %s at %dx%d%s\n", fits ? "fits this board" : "does NOT fit this board",
           hz_render_mode_name(HZ_MODEPLAN_DEFAULT_MODE), HZ_DISPLAY_WIDTH, HZ_DISPLAY_HEIGHT,
           fits ? "" : " (see the sizes above)");
    /* Motion blur is an option (--shutter), not the default: its pose keys are shown, not counted. */
    hz_render_opts_t ro;
    hz_render_opts_default(&ro);
    ro.width = HZ_DISPLAY_WIDTH, ro.height = HZ_DISPLAY_HEIGHT;
    ro.shutter = 1.0f, ro.mode = HZ_MODE_TDENSE;
    hz_render_plan_t rp;
    if (hz_render_plan(&scene, &ro, &rp, &err) == HZ_OK && rp.time_keys)
        printf("  pose keys, --shutter 1 %12zu bytes (%.1f MiB, %u time keys, scene arena; not counted)\n",
               rp.keys_bytes, rp.keys_bytes / 1048576.0, rp.time_keys);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return HZ_EXIT_USAGE;
    }
    const char *cmd = argv[1];
    hz_out_remove_on_signals(); /* an interrupted run leaves no temporary files */
    if (!strcmp(cmd, "-h") || !strcmp(cmd, "--help") || !strcmp(cmd, "help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(cmd, "--version")) {
        printf("hzrt %s (board %s)\n", HZ_VERSION_STRING, HZ_BOARD_NAME);
        return 0;
    }
    if (!strcmp(cmd, "board"))
        return cmd_board(argc - 1, argv + 1);
    if (!strcmp(cmd, "render"))
        return hz_cmd_render(argc - 1, argv + 1);
    if (!strcmp(cmd, "show"))
        return hz_cmd_show(argc - 1, argv + 1);
    if (!strcmp(cmd, "accel"))
        return hz_cmd_accel(argc - 1, argv + 1);
    if (!strcmp(cmd, "info"))
        return cmd_info(argc - 1, argv + 1);
    if (!strcmp(cmd, "latency"))
        return hz_cmd_latency(argc - 1, argv + 1);
    hz_cli_error("unknown command '%s' (try hzrt --help)", cmd);
    return HZ_EXIT_USAGE;
}
