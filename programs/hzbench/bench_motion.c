/* The motion-blur benchmark of hzbench (see bench_motion.h). */
#include "bench_motion.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli.h"
#include "clock.h"
#include "fileio.h"
#include "hz/accel.h"
#include "hz/hash.h"
#include "hz/hz.h"
#include "hz/meshgen.h"
#include "hz/posekeys.h"
#include "hz/scene.h"
#include "pools.h"
#include "scenefile.h"
#include "bench_fit.h"
#include "bench_util.h"
#if defined(HZ_HAVE_EMBREE)
#include "embree_accel.h"
#endif

#define MAX_ROUNDS 9
enum { B_MSBVH, B_INTERP, B_SWEPT, B_EMBREE, B_COUNT };
static const char *const bvh_name[B_COUNT] = { "msbvh", "interp", "swept", "embree-mb" };

typedef struct row {
    bool ran;
    hz_accel_info_t info;
    double build_ms[MAX_ROUNDS], refit_ms[MAX_ROUNDS], render_ms[MAX_ROUNDS];
    int n;
    hz_accel_stats_t st;
    bool have_stats;
    double bytes_per_tri;
    uint64_t rays; /* primary + shadow rays of one frame */
    double agree;  /* Embree: fraction of primary rays with the MSBVH's triangle */
} row_t;

static double thread_cpu_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static double median(const double *v, int n)
{
    double s[MAX_ROUNDS];
    memcpy(s, v, (size_t)n * sizeof(double));
    return hz_bench_median(s, n);
}

/* ---- the frame: primary packets (4x2-pixel tiles), each pixel at its own time ---- */
typedef struct frame {
    hz_rayhit8_t *prim;
    uint32_t packets, pixels;
    hz_vec3_t light;
    float scale;
    uint32_t *hit_prim; /* per pixel: the primary hit of the reference BVH, then of the one measured */
    uint8_t *shadowed;
} frame_t;

static bool make_frame(frame_t *fr, const hz_scene_t *sc, uint32_t w, uint32_t h)
{
    fr->pixels = w * h;
    fr->packets = (fr->pixels + 7u) / 8u;
    void *a = NULL;
    if (posix_memalign(&a, 64, (size_t)fr->packets * sizeof(hz_rayhit8_t)) != 0)
        return false;
    fr->prim = a;
    fr->hit_prim = malloc((size_t)fr->pixels * sizeof(uint32_t) * 2u);
    fr->shadowed = malloc((size_t)fr->pixels * 2u);
    if (!fr->hit_prim || !fr->shadowed)
        return false;
    memset(fr->prim, 0, (size_t)fr->packets * sizeof(hz_rayhit8_t));
    const float aspect = (float)w / (float)h;
    uint32_t n = 0;
    for (uint32_t ty = 0; ty < h; ty += 2)
        for (uint32_t tx = 0; tx < w; tx += 4)
            for (uint32_t y = ty; y < ty + 2 && y < h; y++)
                for (uint32_t x = tx; x < tx + 4 && x < w; x++, n++) {
                    const float time = hz_u32_to_unit(hz_hash2(y * w + x, 0x6d6f74u));
                    /* the camera at the pixel's time (normalised time -> the interval's seconds is the renderer's
                     * business; both scenes' cameras stand still) */
                    hz_camera_t cam = hz_scene_camera(sc, 1.0f);
                    hz_vec3_t f = hz_v3_normalize(hz_v3_sub(cam.target, cam.eye));
                    hz_vec3_t r = hz_v3_normalize(hz_v3_cross(f, cam.up));
                    hz_vec3_t u = hz_v3_cross(r, f);
                    const float th = hz_tanf(0.5f * cam.fov_y);
                    float sx = ((float)x + 0.5f) / (float)w * 2.0f - 1.0f, sy = 1.0f - ((float)y + 0.5f) / (float)h * 2.0f;
                    hz_vec3_t d = hz_v3_add(f, hz_v3_add(hz_v3_scale(r, sx * th * aspect), hz_v3_scale(u, sy * th)));
                    hz_rayhit8_t *P = &fr->prim[n / 8u];
                    const uint32_t l = n % 8u;
                    P->ray.org_x[l] = cam.eye.x, P->ray.org_y[l] = cam.eye.y, P->ray.org_z[l] = cam.eye.z;
                    P->ray.dir_x[l] = d.x, P->ray.dir_y[l] = d.y, P->ray.dir_z[l] = d.z;
                    P->ray.tnear[l] = 0.0f, P->ray.tfar[l] = INFINITY, P->ray.time[l] = time;
                    P->ray.mask[l] = 0xFFFFFFFFu, P->ray.id[l] = y * w + x;
                    P->hit.geom_id[l] = P->hit.prim_id[l] = P->hit.inst_id[0][l] = HZ_ACCEL_INVALID_ID;
                }
    for (; n % 8u; n++) { /* the last packet's spare lanes repeat its first ray */
        hz_rayhit8_t *P = &fr->prim[n / 8u];
        const uint32_t l = n % 8u;
        P->ray.org_x[l] = P->ray.org_x[0], P->ray.org_y[l] = P->ray.org_y[0], P->ray.org_z[l] = P->ray.org_z[0];
        P->ray.dir_x[l] = P->ray.dir_x[0], P->ray.dir_y[l] = P->ray.dir_y[0], P->ray.dir_z[l] = P->ray.dir_z[0];
        P->ray.tfar[l] = INFINITY, P->ray.mask[l] = 0xFFFFFFFFu;
        P->hit.geom_id[l] = P->hit.prim_id[l] = HZ_ACCEL_INVALID_ID;
    }
    const float *bmin = sc->header->bounds_min, *bmax = sc->header->bounds_max;
    fr->scale = 0.0f;
    for (int k = 0; k < 3; k++)
        fr->scale = fmaxf(fr->scale, fmaxf(fabsf(bmin[k]), fabsf(bmax[k])));
    fr->light = sc->light_count ? hz_v3(sc->lights[0].position[0], sc->lights[0].position[1], sc->lights[0].position[2])
                                : hz_v3(0.5f * (bmin[0] + bmax[0]), bmin[1] + 0.9f * (bmax[1] - bmin[1]),
                                        0.5f * (bmin[2] + bmax[2]));
    return true;
}

static void free_frame(frame_t *fr)
{
    free(fr->prim);
    free(fr->hit_prim);
    free(fr->shadowed);
}

/* One frame: primary packets, then shadow packets from their hits at the same times. Records hits in slot
 * `which` (0: the reference) when record; returns the rays traced. */
static uint64_t render(const hz_accel_t *a, frame_t *fr, hz_accel_stats_t *st, bool record, int which)
{
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    ctx.flags = HZ_ACCEL_COHERENT;
    ctx.stats = st;
    static const int32_t all[8] = { -1, -1, -1, -1, -1, -1, -1, -1 };
    uint64_t rays = 0;
    for (uint32_t p = 0; p < fr->packets; p++) {
        hz_rayhit8_t P = fr->prim[p];
        hz_accel_intersect8(all, a, &ctx, &P);
        hz_ray8_t S;
        int32_t valid[8];
        memset(&S, 0, sizeof S);
        for (uint32_t l = 0; l < 8; l++) {
            valid[l] = 0;
            const uint32_t px = p * 8u + l;
            if (px >= fr->pixels)
                continue;
            rays++;
            if (record)
                fr->hit_prim[(size_t)which * fr->pixels + px] = P.hit.geom_id[l] == 0 ? P.hit.prim_id[l] : HZ_ACCEL_INVALID_ID;
            if (P.hit.geom_id[l] != 0)
                continue;
            hz_vec3_t o = hz_v3(P.ray.org_x[l], P.ray.org_y[l], P.ray.org_z[l]);
            hz_vec3_t d = hz_v3(P.ray.dir_x[l], P.ray.dir_y[l], P.ray.dir_z[l]);
            hz_vec3_t hp = hz_v3_add(o, hz_v3_scale(d, P.ray.tfar[l]));
            hz_vec3_t n = hz_v3(P.hit.ng_x[l], P.hit.ng_y[l], P.hit.ng_z[l]);
            if (hz_v3_dot(n, d) > 0.0f)
                n = hz_v3_neg(n);
            hz_vec3_t org = hz_accel_offset_origin(hp, n, fr->scale);
            hz_vec3_t tl = hz_v3_sub(fr->light, org);
            S.org_x[l] = org.x, S.org_y[l] = org.y, S.org_z[l] = org.z;
            S.dir_x[l] = tl.x, S.dir_y[l] = tl.y, S.dir_z[l] = tl.z;
            S.tnear[l] = 0.0f, S.tfar[l] = 1.0f, S.time[l] = P.ray.time[l], S.mask[l] = 0xFFFFFFFFu;
            valid[l] = -1;
            rays++;
        }
        hz_accel_occluded8(valid, a, &ctx, &S);
        if (record)
            for (uint32_t l = 0; l < 8 && p * 8u + l < fr->pixels; l++)
                fr->shadowed[(size_t)which * fr->pixels + p * 8u + l] = valid[l] && S.tfar[l] < 0.0f;
    }
    return rays;
}

/* The keys a scene moves with over the interval: its own animation's (K from the interval, capped for scenes
 * over 1M triangles), or for a scene that does not move a procedural sway (furball) or rotation (others) of 2
 * keys; taken from `arena`, the view g pointed at them, `motion` says which. */
static hz_status_t scene_keys(const hz_bench_motion_opts_t *o, const char *name, const hz_scene_t *sc,
                              hz_accel_geom_t *g, hz_posekeys_t *keys, uint32_t *K_out, char *motion, size_t motion_size,
                              hz_arena_t *arena, hz_error_t *err)
{
    uint32_t K = hz_posekeys_count(sc, o->interval);
    if (K >= 2u) {
        if (g->tri_count > 1000000u && K > o->max_keys) {
            snprintf(motion, motion_size, "its animation over %.4f s, %u keys (the scene asks for %u; capped for memory)",
                     (double)o->interval, o->max_keys, K);
            K = o->max_keys;
        } else {
            snprintf(motion, motion_size, "its animation over %.4f s, %u keys", (double)o->interval, K);
        }
        hz_status_t s = hz_posekeys_init(keys, sc, K, arena, err);
        if (s != HZ_OK)
            return s;
        hz_posekeys_eval(keys, sc, 1.0f, -0.5f * o->interval, 0.5f * o->interval);
        hz_posekeys_geom(keys, g);
    } else {
        const float *lo = sc->header->bounds_min, *hi = sc->header->bounds_max;
        float size = fmaxf(hi[0] - lo[0], fmaxf(hi[1] - lo[1], hi[2] - lo[2]));
        hz_vec3_t c = hz_v3(0.5f * (lo[0] + hi[0]), 0.5f * (lo[1] + hi[1]), 0.5f * (lo[2] + hi[2]));
        const bool fur = strstr(name, "furball") != NULL;
        if (hz_meshgen_motion(g, g->pos, fur ? HZ_MESHGEN_SWAY : HZ_MESHGEN_ROTATE, 2, c, size, 1.0f / 48.0f,
                              arena) != HZ_OK)
            return hz_error_set(err, HZ_E_NO_MEMORY, "bench: %s: no memory for procedural keys in arena '%s'", name,
                                arena->name ? arena->name : "?");
        K = 2;
        snprintf(motion, motion_size, "no animation: procedural %s, 2 keys", fur ? "sway" : "rotation (7.5 deg)");
    }
    *K_out = K;
    return HZ_OK;
}

/* ---- one scene ---- */
static int bench_scene(const hz_bench_motion_opts_t *o, const char *name, FILE *csv, row_t *rows)
{
    hz_pools_t *P = hz_pools_get();
    hz_error_t err;
    hz_scene_t sc;
    hz_accel_geom_t g;
    int rc = hz_bench_open_named(o->scenes_dir, name, P, &sc, &g);
    if (rc)
        return rc;
    hz_posekeys_t keys;
    char motion[160];
    uint32_t K = 0;
    if (scene_keys(o, name, &sc, &g, &keys, &K, motion, sizeof motion, &P->scene, &err) != HZ_OK)
        return hz_cli_report(&err);
    printf("\n%s: %u triangles, %s; %ux%u pixels, one primary + one shadow ray each\n", name, g.tri_count, motion,
           o->width, o->height);
    fflush(stdout);
    frame_t fr;
    if (!make_frame(&fr, &sc, o->width, o->height)) {
        hz_cli_error("bench: out of memory for the frame's rays");
        return hz_status_exit_code(HZ_E_NO_MEMORY);
    }
    const int rounds = g.tri_count > 1000000u ? 1 : o->rounds;
    const hz_arena_mark_t m0 = hz_arena_mark(&P->accel);
    int bad = 0;
    for (int b = 0; b < B_COUNT; b++) {
        memset(&rows[b], 0, sizeof rows[b]);
#if !defined(HZ_HAVE_EMBREE)
        if (b == B_EMBREE)
            printf("  embree-mb: not built in (board without Embree)\n");
#endif
    }
    for (int r = 0; r < rounds; r++)
        for (int b = 0; b < B_COUNT; b++) {
            row_t *rw = &rows[b];
            hz_arena_reset(&P->accel, m0);
            hz_accel_t *a = NULL;
            hz_accel_config_t cfg;
            hz_accel_config_default(&cfg);
            cfg.blur = b == B_INTERP ? HZ_ACCEL_BLUR_INTERP : b == B_SWEPT ? HZ_ACCEL_BLUR_SWEPT : HZ_ACCEL_BLUR_MSBVH;
            int64_t t0 = hz_clock_ns();
            hz_status_t s;
            if (b == B_EMBREE) {
#if defined(HZ_HAVE_EMBREE)
                s = hz_accel_build_embree(&a, &g, &cfg, "threads=1", &P->accel, &err);
#else
                continue;
#endif
            } else {
                s = hz_accel_build_native(&a, &g, &cfg, &P->accel, &err);
            }
            if (s != HZ_OK) {
                free_frame(&fr);
                hz_error_prefix(&err, bvh_name[b]);
                return hz_cli_report(&err);
            }
            rw->build_ms[r] = (double)(hz_clock_ns() - t0) * 1e-6;
            t0 = hz_clock_ns();
            hz_posekeys_t *kp = K >= 2u && hz_posekeys_count(&sc, o->interval) >= 2u ? &keys : NULL;
            if (kp) /* the same interval again: the keys are rewritten, the refit re-reads them */
                hz_posekeys_eval(kp, &sc, 1.0f, -0.5f * o->interval, 0.5f * o->interval);
            if (hz_accel_refit(a, &err) != HZ_OK) {
                hz_accel_release(a);
                free_frame(&fr);
                return hz_cli_report(&err);
            }
            rw->refit_ms[r] = (double)(hz_clock_ns() - t0) * 1e-6;
            rw->info = a->info;
            rw->bytes_per_tri = g.tri_count ? (double)a->info.bytes / g.tri_count : 0.0;
            if (r == 0) { /* hits (compared) and per-ray statistics, untimed */
                hz_accel_stats_t st;
                memset(&st, 0, sizeof st);
                render(a, &fr, b == B_EMBREE ? NULL : &st, true, b == B_MSBVH ? 0 : 1);
                rw->st = st;
                rw->have_stats = b != B_EMBREE && HZ_FEATURE_STATS;
                if (b != B_MSBVH) {
                    uint64_t same = 0, diff = 0;
                    for (uint32_t i = 0; i < fr.pixels; i++) {
                        bool eq = fr.hit_prim[i] == fr.hit_prim[fr.pixels + i] &&
                                  fr.shadowed[i] == fr.shadowed[fr.pixels + i];
                        same += eq, diff += !eq;
                    }
                    rw->agree = (double)same / (double)(same + diff);
                    if (b != B_EMBREE && diff) {
                        hz_cli_error("bench: %s: %s differs from msbvh on %llu pixels", name, bvh_name[b],
                                     (unsigned long long)diff);
                        bad++;
                    }
                }
            }
            double c0 = thread_cpu_s();
            rw->rays = render(a, &fr, NULL, false, 0);
            rw->render_ms[r] = (thread_cpu_s() - c0) * 1e3;
            rw->n = r + 1;
            rw->ran = true;
            hz_accel_release(a);
        }
    hz_arena_reset(&P->accel, m0);
    free_frame(&fr);
    /* table: percentages of the interpolated BVH (the paper's baseline), Mrays/s against Embree */
    const row_t *ip = &rows[B_INTERP], *em = &rows[B_EMBREE];
    const double ip_isect = ip->st.rays ? (double)ip->st.tris / ip->st.rays : 0.0;
    const double ip_trav = ip->st.rays ? (double)ip->st.nodes / ip->st.rays : 0.0;
    const double ip_ms = ip->ran ? median(ip->render_ms, ip->n) : 0.0;
    const double em_mr = em->ran ? (double)em->rays / (median(em->render_ms, em->n) * 1e3) : 0.0;
    printf("%-10s %9s %8s %7s %7s %15s %15s %15s %15s %9s %9s %8s %9s %s\n", "bvh", "refs", "nodes", "splits",
           "sah", "isect max/avg", "(% interp)", "trav max/avg", "(% interp)", "render ms", "build ms", "refit ms",
           "bytes/tri", "Mrays/s (x embree-mb)");
    for (int b = 0; b < B_COUNT; b++) {
        const row_t *rw = &rows[b];
        if (!rw->ran)
            continue;
        const double rms = median(rw->render_ms, rw->n), bms = median(rw->build_ms, rw->n);
        const double fms = median(rw->refit_ms, rw->n), mr = (double)rw->rays / (rms * 1e3);
        const double ia = rw->st.rays ? (double)rw->st.tris / rw->st.rays : 0.0;
        const double ta = rw->st.rays ? (double)rw->st.nodes / rw->st.rays : 0.0;
        char c_refs[16] = "", c_nodes[16] = "", c_splits[16] = "", c_sah[16] = "", c_imax[16] = "", c_iavg[16] = "",
             c_tmax[16] = "", c_tavg[16] = "";
        if (b != B_EMBREE) {
            snprintf(c_refs, sizeof c_refs, "%u", rw->info.ref_count);
            snprintf(c_nodes, sizeof c_nodes, "%u", rw->info.node_count);
            snprintf(c_splits, sizeof c_splits, "%u", rw->info.spatial_splits);
            snprintf(c_sah, sizeof c_sah, "%.2f", (double)rw->info.sah_cost);
        }
        if (rw->have_stats) {
            snprintf(c_imax, sizeof c_imax, "%u", rw->st.ray_tris_max);
            snprintf(c_iavg, sizeof c_iavg, "%.2f", ia);
            snprintf(c_tmax, sizeof c_tmax, "%u", rw->st.ray_nodes_max);
            snprintf(c_tavg, sizeof c_tavg, "%.2f", ta);
        }
        char pi[32] = "", pt[32] = "", xe[32] = "";
        if (rw->have_stats && ip->have_stats && ip_isect > 0.0 && ip->st.ray_tris_max && ip->st.ray_nodes_max) {
            snprintf(pi, sizeof pi, "%.0f%% / %.0f%%", 100.0 * rw->st.ray_tris_max / ip->st.ray_tris_max,
                     100.0 * ia / ip_isect);
            snprintf(pt, sizeof pt, "%.0f%% / %.0f%%", 100.0 * rw->st.ray_nodes_max / ip->st.ray_nodes_max,
                     100.0 * ta / ip_trav);
        }
        if (em_mr > 0.0)
            snprintf(xe, sizeof xe, " (%.2fx)", mr / em_mr);
        char iv[40], tv[40];
        snprintf(iv, sizeof iv, "%s / %s", c_imax, c_iavg);
        snprintf(tv, sizeof tv, "%s / %s", c_tmax, c_tavg);
        printf("%-10s %9s %8s %7s %7s %15s %15s %15s %15s %9.1f %9.0f %8.1f %9.1f %.2f%s", bvh_name[b], c_refs,
               c_nodes, c_splits, c_sah, rw->have_stats ? iv : "", pi, rw->have_stats ? tv : "", pt, rms, bms, fms,
               rw->bytes_per_tri, mr, xe);
        if (ip_ms > 0.0 && b != B_INTERP)
            printf("  render %.2fx interp", rms / ip_ms);
        if (b == B_EMBREE)
            printf("  same hits as msbvh: %.3f%% of pixels", 100.0 * rw->agree);
        printf("\n");
        if (csv)
            fprintf(csv, "%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%.3f,%.1f,%.3f,%.1f,%.3f\n", name, bvh_name[b], c_refs,
                    c_nodes, c_splits, c_sah, c_imax, c_iavg, c_tmax, c_tavg, rms, bms, fms, rw->bytes_per_tri, mr);
    }
    fflush(stdout);
    return bad ? hz_status_exit_code(HZ_E_INTERNAL) : 0;
}

static void with_defaults(hz_bench_motion_opts_t *o)
{
    static const char *const defaults[] = { "furball-sway", "sponza-rotated" };
    hz_bench_scene_list(&o->scenes_dir, o->scenes, &o->scene_count, defaults, (int)HZ_ARRAY_LEN(defaults));
    if (o->rounds <= 0)
        o->rounds = 3;
    if (o->rounds > MAX_ROUNDS)
        o->rounds = MAX_ROUNDS;
    if (!o->width || !o->height)
        o->width = o->height = 512;
    if (!(o->interval > 0.0f))
        o->interval = 1.0f / 24.0f;
    if (o->max_keys != 2u && o->max_keys != 3u && o->max_keys != 5u && o->max_keys != 9u)
        o->max_keys = 2u;
}

int hz_bench_motion(const hz_bench_motion_opts_t *opts)
{
    hz_bench_motion_opts_t o = *opts;
    with_defaults(&o);
    printf("\nmotion blur (seed 002): native motion BVHs vs Embree motion blur (one thread, 8-ray packets; "
           "%% of the interpolated BVH as in the paper's Table 1)\n");
    hz_out_t out;
    FILE *csv = NULL;
    hz_error_t err;
    if (o.csv_path) {
        if (hz_out_open(&out, o.csv_path, &err) != HZ_OK)
            return hz_cli_report(&err);
        csv = out.f;
        fprintf(csv, "scene,bvh,refs,nodes,spatial_splits,sah,isect_max,isect_avg,trav_max,trav_avg,render_ms,build_ms,"
                     "refit_ms,bytes_per_tri,mrays_per_s\n");
    }
    int status = 0;
    for (int i = 0; i < o.scene_count && status == 0; i++) {
        row_t rows[B_COUNT];
        status = bench_scene(&o, o.scenes[i], csv, rows);
    }
    printf("(seed 002, Table 1, MSBVH against the interpolated BVH: hairball 32%% / 43%% intersections max/avg, 85%% "
           "render time; Rotated Sponza 41%% / 47%%, 72%%)\n");
    if (csv) {
        if (status != 0) {
            hz_out_abort(&out);
        } else {
            if (hz_out_commit(&out, &err) != HZ_OK)
                return hz_cli_report(&err);
            printf("wrote %s\n", o.csv_path);
        }
    }
    return status;
}

static void fit_scene(hz_bench_fit_scene_t *fs, const void *ctx)
{
    const hz_bench_motion_opts_t *o = ctx;
    hz_arena_t *scene_arena = &fs->bs.pools->scene;
    hz_accel_geom_t g;
    hz_posekeys_t keys;
    hz_error_t err;
    uint32_t K = 0;
    char motion[160];
    size_t before = hz_arena_available(scene_arena, 64);
    if (hz_accel_geom_from_scene(&g, &fs->bs.scene, scene_arena, &err) != HZ_OK ||
        scene_keys(o, fs->label, &fs->bs.scene, &g, &keys, &K, motion, sizeof motion, scene_arena, &err) != HZ_OK) {
        hz_bench_fit_fail(fs, "pose keys DO NOT FIT", err.msg); /* the arena's own refusal says what they asked */
        return;
    }
    hz_bench_fit_line(fs, "pose keys", "scene", before - hz_arena_available(scene_arena, 64), before);
    static const hz_accel_blur_t kinds[] = { HZ_ACCEL_BLUR_MSBVH, HZ_ACCEL_BLUR_INTERP, HZ_ACCEL_BLUR_SWEPT };
    static const char *const what[] = { "native msbvh", "native interp", "native swept" };
    for (int b = 0; b < 3; b++) {
        hz_accel_config_t cfg;
        hz_accel_config_default(&cfg);
        cfg.blur = kinds[b];
        hz_bench_fit_accel(fs, &cfg, K, what[b]);
    }
}

void hz_bench_motion_fit(const hz_bench_motion_opts_t *opts, hz_bench_fit_t *fit)
{
    hz_bench_motion_opts_t o = *opts;
    with_defaults(&o);
    hz_bench_fit_named(fit, "motion", o.scenes, o.scene_count, fit_scene, &o);
}
