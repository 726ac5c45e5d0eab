/* `hzrt accel` (see accel_cmd.h). */
#include "accel_cmd.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "clock.h"
#include "hz/accel.h"
#include "hz/meshgen.h"
#include "hz/posekeys.h"
#include "hz/scene.h"
#include "motion_check.h"
#include "pools.h"
#include "phase.h"
#include "scenefile.h"
#include "threads.h"
#if defined(HZ_HAVE_EMBREE)
#include "embree_accel.h"
#endif

/* ---- --motion-check: the motion BVH against brute force over the triangles at each ray's time ---- */
typedef struct mcheck {
    uint64_t n;
    hz_meshgen_motion_kind_t kind;
    bool kind_set;
    uint32_t keys;
    bool keys_set;
    float turns;
    uint32_t seed;
    float time, interval; /* scenes that move: the keys span [time - interval / 2, time + interval / 2] s */
} mcheck_t;

/* Runs the check on a built motion accel; prints the one result line; returns the exit status. */
static int motion_check(const hz_accel_t *a, const hz_accel_geom_t *g, const mcheck_t *mc)
{
    int64_t t0 = hz_clock_ns();
    hz_accel_stats_t st;
    memset(&st, 0, sizeof st);
    hz_mcheck_counts_t c;
    memset(&c, 0, sizeof c);
    hz_mcheck_run(a, g, mc->n, mc->seed, true, &st, &c);
    fprintf(stderr, "motion-check: %llu of the rays hit (brute force), %.1f s\n", (unsigned long long)c.hits,
            (double)(hz_clock_ns() - t0) * 1e-9);
    if (HZ_FEATURE_STATS && st.rays)
        fprintf(stderr, "motion-check: per ray %.1f nodes traversed (max %u), %.1f triangles intersected (max %u)\n",
                (double)st.nodes / (double)st.rays, st.ray_nodes_max, (double)st.tris / (double)st.rays,
                st.ray_tris_max);
    printf("motion-check: %llu rays, %llu misses, %llu mismatches\n", (unsigned long long)mc->n,
           (unsigned long long)c.misses, (unsigned long long)c.mismatches);
    return c.misses || c.mismatches ? 1 : 0;
}

static void usage(FILE *f)
{
    fprintf(f, "usage: hzrt accel SCENE [--embree [--embree-config S]] [--no-spatial] [--leaf N] [--budget F]\n"
               "       hzrt accel SCENE --motion-check N [--blur-bvh msbvh|interp|swept] [--rigid instance|refit]\n"
               "                  [--motion-segments per-node|every-key] [--motion KIND] [--keys K] [--turns F]\n"
               "                  [--time T] [--interval S] [--seed S]\n"
               "\n"
               "Builds the acceleration structure of SCENE (.hzb file or `builtin`) in the board's accel arena and\n"
               "prints build time, bytes per triangle and the tree's shape. The memory plan is checked first:\n"
               "a scene whose worst-case build does not fit the arena is refused with both byte counts.\n"
               "  --embree           Embree instead of the native BVH (host boards built with Embree)\n"
               "  --no-spatial       binned SAH only, no spatial splits\n"
               "  --leaf N           triangles per leaf, 1..%d (default %d)\n"
               "  --budget F         spatial-split replication budget, fraction of the triangles (default 0.25, at most 4)\n"
               "  --threads N        native build on a pool of N threads (default 1; 0: one per CPU); the tree is\n"
               "                     the same for every N\n"
               "Motion blur (native backend):\n"
               "  --motion-check N   build the motion BVH, shoot N random rays at random times and compare each with\n"
               "                     brute force over all triangles at that time (single rays, occlusion and 8-wide\n"
               "                     packets); prints 'motion-check: N rays, K misses, M mismatches' and exits 1\n"
               "                     when K or M is not 0\n"
               "  --blur-bvh B       msbvh (default), interp (interpolated BVH) or swept (static BVH, swept boxes)\n"
               "  --rigid R          instance (default): objects that move rigidly keep a BVH in object space and rays\n"
               "                     move into it at their time; refit: their triangles move with the keys like any\n"
               "                     other motion (the BVH is refitted every frame)\n"
               "  --motion-segments S  per-node (default): each node keeps as few motion segments as its content's\n"
               "                     motion needs (1, 2, 4 or 8); every-key: every node a box set at every key\n"
               "  --motion KIND      procedural time keys from the scene's positions instead of its animation: sway,\n"
               "                     rotate, cross (vertices cross split planes), collapse (to a point), rot180 (one\n"
               "                     segment). Default: the scene's animation if it moves, else sway\n"
               "  --time T, --interval S  scenes that move: keys over [T - S/2, T + S/2] s (default 1, 1/30)\n"
               "  --keys K           time keys, 2, 3, 5 or 9 (default: the scene's choice, else 2; rot180 needs 2)\n"
               "  --turns F          rotate: turns over the interval (default 0.25)\n"
               "  --seed S           ray seed (default 1)\n"
               "\n"
               "exit status: 0 ok, 2 bad command line, 64+N failure with hz status N (66: the build does not fit\n"
               "the accel arena, 68/70: malformed or corrupt scene, 72: no Embree in this build, 73: unreadable file)\n",
            HZ_BVH_WIDTH, HZ_BVH_WIDTH);
}

int hz_cmd_accel(int argc, char **argv)
{
    const char *scene_name = NULL, *embree_config = "";
    bool embree = false, blur_set = false, rigid_set = false, segments_set = false, motion_opt = false;
    int threads = 1;
    hz_accel_config_t cfg;
    hz_accel_config_default(&cfg);
    mcheck_t mc = { 0, HZ_MESHGEN_SWAY, false, 2u, false, 0.25f, 1u, 1.0f, 1.0f / 30.0f };
    for (int i = 1; i < argc; i++) {
        long v;
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            if (!hz_cli_parse_long("--threads", argv[++i], 0, HZ_MAX_THREADS, &v))
                return HZ_EXIT_USAGE;
            threads = (int)v;
        } else if (!strcmp(argv[i], "--motion-check") && i + 1 < argc) {
            if (!hz_cli_parse_long("--motion-check", argv[++i], 1, 1000000000L, &v))
                return HZ_EXIT_USAGE;
            mc.n = (uint64_t)v;
        } else if (!strcmp(argv[i], "--blur-bvh") && i + 1 < argc) {
            if (!hz_accel_blur_parse(argv[++i], &cfg.blur)) {
                hz_cli_error("accel: --blur-bvh: '%s' is not msbvh, interp or swept", argv[i]);
                return HZ_EXIT_USAGE;
            }
            blur_set = true;
        } else if (!strcmp(argv[i], "--rigid") && i + 1 < argc) {
            if (!hz_accel_rigid_parse(argv[++i], &cfg.rigid)) {
                hz_cli_error("accel: --rigid: '%s' is not instance or refit", argv[i]);
                return HZ_EXIT_USAGE;
            }
            rigid_set = true;
        } else if (!strcmp(argv[i], "--motion-segments") && i + 1 < argc) {
            if (!hz_accel_segments_parse(argv[++i], &cfg.segments)) {
                hz_cli_error("accel: --motion-segments: '%s' is not per-node or every-key", argv[i]);
                return HZ_EXIT_USAGE;
            }
            segments_set = true;
        } else if (!strcmp(argv[i], "--motion") && i + 1 < argc) {
            if (!hz_meshgen_motion_parse(argv[++i], &mc.kind)) {
                hz_cli_error("accel: --motion: '%s' is not sway, rotate, cross, collapse or rot180", argv[i]);
                return HZ_EXIT_USAGE;
            }
            mc.kind_set = motion_opt = true;
        } else if (!strcmp(argv[i], "--keys") && i + 1 < argc) {
            if (!hz_cli_parse_long("--keys", argv[++i], 2, 9, &v) || (v != 2 && v != 3 && v != 5 && v != 9)) {
                hz_cli_error("accel: --keys: '%s' is not 2, 3, 5 or 9", argv[i]);
                return HZ_EXIT_USAGE;
            }
            mc.keys = (uint32_t)v;
            mc.keys_set = motion_opt = true;
        } else if (!strcmp(argv[i], "--turns") && i + 1 < argc) {
            char *end;
            double t = strtod(argv[++i], &end);
            if (*end || end == argv[i] || !(t >= -100.0 && t <= 100.0)) {
                hz_cli_error("accel: --turns: '%s' is not a number in [-100, 100]", argv[i]);
                return HZ_EXIT_USAGE;
            }
            mc.turns = (float)t;
            motion_opt = true;
        } else if ((!strcmp(argv[i], "--time") || !strcmp(argv[i], "--interval")) && i + 1 < argc) {
            const bool is_time = !strcmp(argv[i], "--time");
            char *end;
            double t = strtod(argv[++i], &end);
            if (*end || end == argv[i] || !(is_time ? (t >= 0.0 && t <= 1e6) : (t > 0.0 && t <= 10.0))) {
                hz_cli_error("accel: %s: '%s' is not a number in %s", is_time ? "--time" : "--interval", argv[i],
                             is_time ? "[0, 1e6] (seconds)" : "(0, 10] (seconds)");
                return HZ_EXIT_USAGE;
            }
            *(is_time ? &mc.time : &mc.interval) = (float)t;
            motion_opt = true;
        } else if (!strcmp(argv[i], "--seed") && i + 1 < argc) {
            if (!hz_cli_parse_long("--seed", argv[++i], 0, 0x7FFFFFFFL, &v))
                return HZ_EXIT_USAGE;
            mc.seed = (uint32_t)v;
            motion_opt = true;
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
            if (*end || end == argv[i] || !(b >= 0.0 && b <= HZ_ACCEL_SPLIT_BUDGET_MAX)) {
                hz_cli_error("accel: --budget: '%s' is not a number in [0, %g]", argv[i],
                             (double)HZ_ACCEL_SPLIT_BUDGET_MAX);
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
    if ((blur_set || rigid_set || segments_set || motion_opt) && !mc.n) {
        hz_cli_error("accel: --blur-bvh, --rigid, --motion-segments, --motion, --keys, --turns, --time, --interval and "
                     "--seed need --motion-check N");
        return HZ_EXIT_USAGE;
    }
    if (mc.n && embree) {
        hz_cli_error("accel: --motion-check checks the native motion BVH; it does not take --embree");
        return HZ_EXIT_USAGE;
    }
    if (mc.n && mc.kind == HZ_MESHGEN_ROT180 && mc.keys != 2u) {
        hz_cli_error("accel: --motion rot180 is one segment: it needs --keys 2");
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
        hz_pools_error(&err, "accel");
        return hz_cli_report(&err);
    }
    if (hz_scenefile_open(scene_name, p, &sc, &err) != HZ_OK)
        return hz_cli_report(&err);
    hz_accel_geom_t g;
    if (hz_accel_geom_from_scene(&g, &sc, &p->scene, &err) != HZ_OK)
        return hz_cli_report(&err);
    hz_posekeys_t keys;
    const uint32_t scene_k = mc.n && !mc.kind_set ? hz_posekeys_count(&sc, mc.interval) : 0u;
    if (mc.n && scene_k >= 2u) {
        /* the scene's own animation, posed at the keys of an interval around mc.time */
        const uint32_t k = mc.keys_set ? mc.keys : scene_k;
        if (hz_posekeys_init(&keys, &sc, k, &p->scene, &err) != HZ_OK)
            return hz_cli_report(&err);
        hz_posekeys_eval(&keys, &sc, mc.time, -0.5f * mc.interval, 0.5f * mc.interval);
        hz_posekeys_geom(&keys, &g);
        fprintf(stderr, "motion-check: %s, %u triangles, the scene's animation over [%g, %g] s, %u keys, %s BVH\n",
                scene_name, g.tri_count, (double)(mc.time - 0.5f * mc.interval),
                (double)(mc.time + 0.5f * mc.interval), k, hz_accel_blur_name(cfg.blur));
    } else if (mc.n) {
        if (!mc.kind_set)
            fprintf(stderr, "motion-check: %s does not move: procedural keys (--motion sway)\n", scene_name);
        /* procedural keys from the scene's positions (center: the middle of its box, size: its largest extent) */
        float lo[3] = { 1e30f, 1e30f, 1e30f }, hi[3] = { -1e30f, -1e30f, -1e30f };
        for (uint32_t v = 0; v < g.vertex_count; v++)
            for (int c = 0; c < 3; c++) {
                float x = g.pos[4u * (size_t)v + (size_t)c];
                if (x == x && x - x == 0.0f)
                    lo[c] = x < lo[c] ? x : lo[c], hi[c] = x > hi[c] ? x : hi[c];
            }
        float size = 0.0f;
        for (int c = 0; c < 3; c++)
            size = hi[c] - lo[c] > size ? hi[c] - lo[c] : size;
        hz_vec3_t center = hz_v3(0.5f * (lo[0] + hi[0]), 0.5f * (lo[1] + hi[1]), 0.5f * (lo[2] + hi[2]));
        hz_status_t ms = hz_meshgen_motion(&g, g.pos, mc.kind, mc.keys, center, size, mc.turns, &p->scene);
        if (ms != HZ_OK) {
            hz_error_set(&err, ms, "accel: --motion %s: no memory for %u keys of %u vertices in arena '%s'",
                         hz_meshgen_motion_name(mc.kind), mc.keys, g.vertex_count, p->scene.name);
            return hz_cli_report(&err);
        }
        fprintf(stderr, "motion-check: %s, %u triangles, motion %s, %u keys, %s BVH\n", scene_name, g.tri_count,
                hz_meshgen_motion_name(mc.kind), mc.keys, hz_accel_blur_name(cfg.blur));
    }
    if (mc.n) {
        if (cfg.rigid == HZ_ACCEL_RIGID_REFIT)
            g.instance_count = 0, g.instances = NULL; /* and so the brute force moves their vertices too */
        if (hz_accel_plan_check_geom(&g, &cfg, &p->accel, &err) != HZ_OK)
            return hz_cli_report(&err);
        hz_accel_t *ma = NULL;
        int64_t t0 = hz_clock_ns();
        if (hz_accel_build_native(&ma, &g, &cfg, &p->accel, &err) != HZ_OK)
            return hz_cli_report(&err);
        const hz_accel_info_t *in = &ma->info;
        char sah[48];
        if (in->instances && in->instance_tris == in->tri_count)
            snprintf(sah, sizeof sah, "no motion BVH");
        else
            snprintf(sah, sizeof sah, "SAH %.2f%s", (double)in->sah_cost, in->instances ? " outside instances" : "");
        fprintf(stderr, "motion-check: built in %.3f s: %u references (%u spatial splits, %u stopped by the budget), "
                        "%u nodes, %s, %.1f bytes per triangle\n", (double)(hz_clock_ns() - t0) * 1e-9,
                in->ref_count, in->spatial_splits, in->budget_stops, in->node_count, sah,
                g.tri_count ? (double)in->bytes / g.tri_count : 0.0);
        if (in->key_sets && in->node_count)
            fprintf(stderr, "motion-check: %s motion segments: %llu key box sets, %.2f per node (every key: %u)\n",
                    hz_accel_segments_name(cfg.segments), (unsigned long long)in->key_sets,
                    (double)in->key_sets / (double)in->node_count, in->time_keys);
        if (in->instances)
            fprintf(stderr, "motion-check: %u rigid instance%s holding %u of the triangles (object-space BVHs)\n",
                    in->instances, in->instances == 1 ? "" : "s", in->instance_tris);
        return motion_check(ma, &g, &mc);
    }
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
    if (threads != 1 && !embree) {
        if (hz_threads_start(threads, &err) != HZ_OK)
            return hz_cli_report(&err);
        hz_threads_accel_hook(&cfg);
    }
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
    const int used_threads = hz_threads_count();
    hz_threads_stop();
    (void)embree_config;
    if (s != HZ_OK)
        return hz_cli_report(&err);
    const hz_accel_info_t *in = &a->info;
    printf("backend    %s\n", in->backend);
    if (embree)
        printf("build      %.3f s (Embree's threads)\n", secs);
    else
        printf("build      %.3f s (%d thread%s)\n", secs, used_threads, used_threads == 1 ? "" : "s");
    printf("memory     %zu bytes, %.1f per triangle (peak %zu during the build)\n", in->bytes,
           g.tri_count ? (double)in->bytes / g.tri_count : 0.0, in->bytes_peak);
    if (!embree) {
        printf("references %u (%u spatial splits, %u stopped by the budget), %u skipped triangles\n", in->ref_count,
               in->spatial_splits, in->budget_stops, in->tri_skipped);
        printf("tree       %u nodes of %d, %u leaves in %u blocks, depth %u, SAH cost %.2f\n", in->node_count,
               HZ_BVH_WIDTH, in->leaf_count, in->block_count, in->depth, (double)in->sah_cost);
    }
    hz_accel_release(a);
    return 0;
}
