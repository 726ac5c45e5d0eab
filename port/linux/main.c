/* hzrt — the Linux entry point: dispatches subcommands (see `hzrt --help`). */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "hz/hz.h"
#include "latency.h"
#include "pools.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: hzrt <command> [options]\n"
            "\n"
            "commands:\n"
            "  board        print this build's board settings: display, arenas, features, v-sync source\n"
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
            printf("usage: hzrt board\n\nPrints the board this binary was built for and its static memory.\n");
            return 0;
        }
        hz_cli_error("board: unknown option '%s' (try hzrt board --help)", argv[i]);
        return HZ_EXIT_USAGE;
    }
    hz_pools_t *p = hz_pools_get();
    if (!p) {
        hz_cli_error("board: could not set up the static arenas");
        return hz_status_exit_code(HZ_E_INTERNAL);
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
        printf(" (chip %s, line %d%s)", HZ_VSYNC_GPIO_CHIP, HZ_VSYNC_GPIO_LINE,
               HZ_VSYNC_GPIO_ACTIVE_LOW ? ", active low" : "");
    printf("\n");
    printf("features   textures=%d mirrors=%d transparency=%d motion=%d stats=%d\n", HZ_FEATURE_TEXTURES,
           HZ_FEATURE_MIRRORS, HZ_FEATURE_TRANSPARENCY, HZ_FEATURE_MOTION, HZ_FEATURE_STATS);
    printf("arenas     scene %zu MiB, accel %zu MiB, frame %zu MiB, %d x thread %zu MiB\n", p->scene.cap >> 20,
           p->accel.cap >> 20, p->frame.cap >> 20, HZ_MAX_THREADS, p->thread[0].cap >> 20);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return HZ_EXIT_USAGE;
    }
    const char *cmd = argv[1];
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
    if (!strcmp(cmd, "latency"))
        return hz_cmd_latency(argc - 1, argv + 1);
    hz_cli_error("unknown command '%s' (try hzrt --help)", cmd);
    return HZ_EXIT_USAGE;
}
