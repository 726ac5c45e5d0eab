/* `hzrt accel` (see accel_cmd.h). */
#include "accel_cmd.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "clock.h"
#include "hz/accel.h"
#include "hz/scene.h"
#include "pools.h"
#include "phase.h"
#include "scenefile.h"
#if defined(HZ_HAVE_EMBREE)
#include "embree_accel.h"
#endif

static void usage(FILE *f)
{
    fprintf(f, "usage: hzrt accel SCENE [--embree [--embree-config S]] [--no-spatial] [--leaf N] [--budget F]\n"
               "\n"
               "Builds the acceleration structure of SCENE (.hzb file or `builtin`) in the board's accel arena and\n"
               "prints build time, bytes per triangle and the tree's shape. The memory plan is checked first:\n"
               "a scene whose worst-case build does not fit the arena is refused with both byte counts.\n"
               "  --embree           Embree instead of the native BVH (host boards built with Embree)\n"
               "  --no-spatial       binned SAH only, no spatial splits\n"
               "  --leaf N           triangles per leaf, 1..%d (default %d)\n"
               "  --budget F         spatial-split replication budget, fraction of the triangles (default 0.25)\n"
               "\n"
               "exit status: 0 ok, 2 bad command line, 64+N failure with hz status N (66: the build does not fit\n"
               "the accel arena, 68/70: malformed or corrupt scene, 72: no Embree in this build, 73: unreadable file)\n",
            HZ_BVH_WIDTH, HZ_BVH_WIDTH);
}

int hz_cmd_accel(int argc, char **argv)
{
    const char *scene_name = NULL, *embree_config = "";
    bool embree = false;
    hz_accel_config_t cfg;
    hz_accel_config_default(&cfg);
    for (int i = 1; i < argc; i++) {
        long v;
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(argv[i], "--embree")) {
            embree = true;
        } else if (!strcmp(argv[i], "--embree-config") && i + 1 < argc) {
            embree_config = argv[++i];
        } else if (!strcmp(argv[i], "--no-spatial")) {
            cfg.spatial_splits = false;
        } else if (!strcmp(argv[i], "--leaf") && i + 1 < argc) {
            if (!hz_cli_parse_long("--leaf", argv[++i], 1, HZ_BVH_WIDTH, &v))
                return HZ_EXIT_USAGE;
            cfg.leaf_max = (uint32_t)v;
        } else if (!strcmp(argv[i], "--budget") && i + 1 < argc) {
            char *end;
            double b = strtod(argv[++i], &end);
            if (*end || end == argv[i] || !(b >= 0.0 && b <= 1.0)) {
                hz_cli_error("accel: --budget: '%s' is not a number in [0, 1]", argv[i]);
                return HZ_EXIT_USAGE;
            }
            cfg.split_budget = (float)b;
        } else if (argv[i][0] == '-') {
            hz_cli_error("accel: unknown option '%s' (try hzrt accel --help)", argv[i]);
            return HZ_EXIT_USAGE;
        } else if (!scene_name) {
            scene_name = argv[i];
        } else {
            hz_cli_error("accel: one scene only ('%s' is extra)", argv[i]);
            return HZ_EXIT_USAGE;
        }
    }
    if (!scene_name) {
        usage(stderr);
        return HZ_EXIT_USAGE;
    }
#if !defined(HZ_HAVE_EMBREE)
    if (embree) {
        hz_cli_error("accel: --embree: this build (board %s) has no Embree backend", HZ_BOARD_NAME);
        return hz_status_exit_code(HZ_E_UNSUPPORTED);
    }
#endif
    hz_pools_t *p = hz_pools_get();
    hz_error_t err;
    hz_scene_t sc;
    if (!p) {
        hz_cli_error("accel: could not set up the static arenas");
        return hz_status_exit_code(HZ_E_INTERNAL);
    }
    if (hz_scenefile_open(scene_name, p, &sc, &err) != HZ_OK)
        return hz_cli_report(&err);
    hz_accel_geom_t g;
    if (hz_accel_geom_from_scene(&g, &sc, &p->scene, &err) != HZ_OK)
        return hz_cli_report(&err);
    hz_accel_bytes_t bound = hz_accel_bytes_bound(g.tri_count, &cfg);
    printf("scene      %s: %u triangles, %u vertices%s\n", scene_name, g.tri_count, g.vertex_count,
           g.tri_flags ? ", any-hit triangles (alpha)" : "");
    if (embree)
        printf("plan       Embree allocates its own memory (the native plan, %zu bytes at most, does not apply)\n",
               bound.peak);
    else
        printf("plan       native build needs at most %zu bytes (%zu kept) of arena '%s' (%zu free)\n", bound.peak,
               bound.kept, p->accel.name, hz_arena_available(&p->accel, 64));
    if (!embree && hz_accel_plan_check(g.tri_count, &cfg, &p->accel, &err) != HZ_OK)
        return hz_cli_report(&err);
    hz_accel_t *a = NULL;
    hz_phase_t prog;
    cfg.progress = hz_phase_accel, cfg.progress_user = &prog;
    hz_phase_begin(&prog, false, "%s build of %s (%u triangles)", embree ? "Embree" : "native", scene_name,
                      g.tri_count);
    int64_t t0 = hz_clock_ns();
    hz_status_t s;
#if defined(HZ_HAVE_EMBREE)
    if (embree)
        s = hz_accel_build_embree(&a, &g, &cfg, embree_config, &p->accel, &err);
    else
#endif
        s = hz_accel_build_native(&a, &g, &cfg, &p->accel, &err);
    double secs = (double)(hz_clock_ns() - t0) * 1e-9;
    hz_phase_end(&prog);
    (void)embree_config;
    if (s != HZ_OK)
        return hz_cli_report(&err);
    const hz_accel_info_t *in = &a->info;
    printf("backend    %s\n", in->backend);
    printf("build      %.3f s (%s)\n", secs, embree ? "Embree's threads" : "one thread");
    printf("memory     %zu bytes, %.1f per triangle (peak %zu during the build)\n", in->bytes,
           g.tri_count ? (double)in->bytes / g.tri_count : 0.0, in->bytes_peak);
    if (!embree) {
        printf("references %u (%u spatial splits), %u skipped triangles\n", in->ref_count, in->spatial_splits,
               in->tri_skipped);
        printf("tree       %u nodes of %d, %u leaves in %u blocks, depth %u, SAH cost %.2f\n", in->node_count,
               HZ_BVH_WIDTH, in->leaf_count, in->block_count, in->depth, (double)in->sah_cost);
    }
    hz_accel_release(a);
    return 0;
}
