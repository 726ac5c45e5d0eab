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
#define MAX_ROWS (HZ_BENCH_MOTION_MAX_BUDGETS + 5)
/* The secondary ray of a pixel: the kinds of frame each BVH renders. */
enum { S_SHADOW, S_AO, S_COUNT };
static const char *const secondary_name[S_COUNT] = { "shadow", "ao" };

typedef struct row {
    const char *name;      /* msbvh, instances, interp, swept, embree-mb */
    hz_accel_blur_t blur;
    bool embree;
    bool instances;        /* rigid objects as instances (seed 002 section 3.2); the others refit them */
    bool every_key;        /* nodes keep every key (the others: per-node motion segments) */
    float budget;          /* the MSBVH's split budget (the others: 0) */
    bool ran, skipped;     /* skipped: its memory bound does not fit the accel arena */
    hz_accel_info_t info;
    double build_ms[MAX_ROUNDS], refit_ms[MAX_ROUNDS], render_ms[S_COUNT][MAX_ROUNDS];
    int n;
    hz_accel_stats_t st[S_COUNT];
    bool have_stats;
    double bytes_per_tri;
    uint64_t rays[S_COUNT]; /* primary + secondary rays of one frame */
    double agree[S_COUNT];  /* Embree, instances: fraction of pixels with the first MSBVH's hits */
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
    float scale, ao_len;
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
    fr->hit_prim = malloc((size_t)fr->pixels * sizeof(uint32_t) * 2u * S_COUNT);
    fr->shadowed = malloc((size_t)fr->pixels * 2u * S_COUNT);
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
    fr->ao_len = 0.1f * sqrtf((bmax[0] - bmin[0]) * (bmax[0] - bmin[0]) + (bmax[1] - bmin[1]) * (bmax[1] - bmin[1]) +
                              (bmax[2] - bmin[2]) * (bmax[2] - bmin[2]));
    fr->light = sc->light_count ? hz_v3(sc->lights[0].position[0], sc->lights[0].position[1], sc->lights[0].position[2])
                                : hz_v3(0.5f * (bmin[0] + bmax[0]), bmin[1] + 0.9f * (bmax[1] - bmin[1]),
                                        0.5f * (bmin[2] + bmax[2]));
    return true;
}

/* A native BVH of cfg over g built and refitted in the accel arena (*out); *fits false, and nothing built, where
 * its memory bound does not fit there. 0, or the exit status of an error (said, named `what`). */
static int build_refitted(const hz_accel_geom_t *g, const hz_accel_config_t *cfg, hz_pools_t *P, const char *what,
                          hz_accel_t **out, bool *fits)
{
    hz_error_t err;
    *out = NULL;
    *fits = hz_accel_bytes_bound_geom(g, cfg).peak <= hz_arena_available(&P->accel, 64);
    if (!*fits)
        return 0;
    if (hz_accel_build_native(out, g, cfg, &P->accel, &err) == HZ_OK && hz_accel_refit(*out, &err) == HZ_OK)
        return 0;
    if (*out)
        hz_accel_release(*out);
    *out = NULL;
    hz_error_prefix(&err, what);
    return hz_cli_report(&err);
}

/* The largest of the group's split budgets (the MSBVH the leaf sizes and the sweep build). */
static float largest_budget(const hz_bench_motion_opts_t *o)
{
    float budget = o->budgets[0];
    for (int i = 1; i < o->budget_count; i++)
        budget = fmaxf(budget, o->budgets[i]);
    return budget;
}

/* make_frame at the group's size; 0, or the exit status of a frame that does not fit in memory (said). */
static int frame_of(frame_t *fr, const hz_scene_t *sc, const hz_bench_motion_opts_t *o)
{
    if (make_frame(fr, sc, o->width, o->height))
        return 0;
    hz_cli_error("bench: out of memory for the frame's rays");
    return hz_status_exit_code(HZ_E_NO_MEMORY);
}

static void free_frame(frame_t *fr)
{
    free(fr->prim);
    free(fr->hit_prim);
    free(fr->shadowed);
}

/* A cosine-distributed direction about n for pixel px (two hashes of it). */
static hz_vec3_t ao_dir(hz_vec3_t n, uint32_t px)
{
    const float u1 = hz_u32_to_unit(hz_hash2(px, 0x616f31u)), u2 = hz_u32_to_unit(hz_hash2(px, 0x616f32u));
    const float r = sqrtf(u1), phi = 6.28318531f * u2;
    const hz_vec3_t a = fabsf(n.x) > 0.5f ? hz_v3(0, 1, 0) : hz_v3(1, 0, 0);
    const hz_vec3_t t = hz_v3_normalize(hz_v3_cross(a, n)), b = hz_v3_cross(n, t);
    return hz_v3_add(hz_v3_add(hz_v3_scale(t, r * cosf(phi)), hz_v3_scale(b, r * sinf(phi))),
                     hz_v3_scale(n, sqrtf(fmaxf(0.0f, 1.0f - u1))));
}

/* One frame: primary packets, then secondary packets (kind: shadow or AO) from their hits at the same times.
 * Records hits in slot `which` (0: the reference) when record; returns the rays traced. */
static uint64_t render(const hz_accel_t *a, frame_t *fr, int kind, hz_accel_stats_t *st, bool record, int which)
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
                fr->hit_prim[((size_t)kind * 2u + (size_t)which) * fr->pixels + px] = P.hit.geom_id[l] == 0 ? P.hit.prim_id[l] : HZ_ACCEL_INVALID_ID;
            if (P.hit.geom_id[l] != 0)
                continue;
            hz_vec3_t o = hz_v3(P.ray.org_x[l], P.ray.org_y[l], P.ray.org_z[l]);
            hz_vec3_t d = hz_v3(P.ray.dir_x[l], P.ray.dir_y[l], P.ray.dir_z[l]);
            hz_vec3_t hp = hz_v3_add(o, hz_v3_scale(d, P.ray.tfar[l]));
            hz_vec3_t n = hz_v3(P.hit.ng_x[l], P.hit.ng_y[l], P.hit.ng_z[l]);
            if (hz_v3_dot(n, d) > 0.0f)
                n = hz_v3_neg(n);
            hz_vec3_t org = hz_accel_offset_origin(hp, n, fr->scale);
            hz_vec3_t tl = kind == S_SHADOW ? hz_v3_sub(fr->light, org) : ao_dir(hz_v3_normalize(n), px);
            S.org_x[l] = org.x, S.org_y[l] = org.y, S.org_z[l] = org.z;
            S.dir_x[l] = tl.x, S.dir_y[l] = tl.y, S.dir_z[l] = tl.z;
            S.tnear[l] = 0.0f, S.tfar[l] = kind == S_SHADOW ? 1.0f : fr->ao_len, S.time[l] = P.ray.time[l];
            S.mask[l] = 0xFFFFFFFFu;
            valid[l] = -1;
            rays++;
        }
        hz_accel_occluded8(valid, a, &ctx, &S);
        if (record)
            for (uint32_t l = 0; l < 8 && p * 8u + l < fr->pixels; l++)
                fr->shadowed[((size_t)kind * 2u + (size_t)which) * fr->pixels + p * 8u + l] =
                    valid[l] && S.tfar[l] < 0.0f;
    }
    return rays;
}

/* The keys a scene moves with over the interval: its own animation's (K from the interval), or for a scene that
 * does not move a procedural sway (furball) or rotation (others) of 2 keys; taken from `arena`, the view g
 * pointed at them, `motion` says which. */
static hz_status_t scene_keys(const hz_bench_motion_opts_t *o, const char *name, const hz_scene_t *sc,
                              hz_accel_geom_t *g, hz_posekeys_t *keys, uint32_t *K_out, char *motion, size_t motion_size,
                              hz_arena_t *arena, hz_error_t *err)
{
    uint32_t K = hz_posekeys_count(sc, o->interval);
    if (K >= 2u) {
        snprintf(motion, motion_size, "its animation over %.4f s, %u keys", (double)o->interval, K);
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
/* The rows of a scene: the MSBVH at each budget, rigid instances (when the scene has some: its other triangles in
 * the MSBVH at the default budget), the interpolated and swept BVHs, Embree's motion blur. */
static int make_rows(const hz_bench_motion_opts_t *o, const hz_accel_geom_t *g, row_t *rows)
{
    int n = 0;
    hz_accel_config_t d;
    hz_accel_config_default(&d);
    for (int i = 0; i < o->budget_count; i++)
        rows[n++] = (row_t){ .name = "msbvh", .blur = HZ_ACCEL_BLUR_MSBVH, .budget = o->budgets[i] };
    if (o->budget_count && g->time_keys > 2u) /* K = 2: one segment, nothing to compare */
        rows[n++] = (row_t){ .name = "msbvh-every-key", .blur = HZ_ACCEL_BLUR_MSBVH,
                             .budget = o->budgets[o->budget_count - 1], .every_key = true };
    if (g->instance_count)
        rows[n++] = (row_t){ .name = "instances", .blur = HZ_ACCEL_BLUR_MSBVH, .budget = d.split_budget,
                             .instances = true };
    rows[n++] = (row_t){ .name = "interp", .blur = HZ_ACCEL_BLUR_INTERP };
    rows[n++] = (row_t){ .name = "swept", .blur = HZ_ACCEL_BLUR_SWEPT };
    rows[n++] = (row_t){ .name = "embree-mb", .embree = true };
    return n;
}

static bool is_msbvh(const row_t *rw)
{
    return !rw->embree && !rw->instances && rw->blur == HZ_ACCEL_BLUR_MSBVH;
}

static void row_config(const row_t *rw, uint32_t leaf_max, hz_accel_config_t *cfg)
{
    hz_accel_config_default(cfg);
    if (leaf_max)
        cfg->leaf_max = leaf_max;
    cfg->blur = rw->blur;
    cfg->rigid = rw->instances ? HZ_ACCEL_RIGID_INSTANCE : HZ_ACCEL_RIGID_REFIT;
    cfg->segments = rw->every_key ? HZ_ACCEL_SEGMENTS_EVERY_KEY : HZ_ACCEL_SEGMENTS_PER_NODE;
    if (is_msbvh(rw))
        cfg->split_budget = rw->budget;
}

static void row_label(const row_t *rw, char *buf, size_t size)
{
    if (is_msbvh(rw))
        snprintf(buf, size, "%s %g", rw->name, (double)rw->budget);
    else
        snprintf(buf, size, "%s", rw->name);
}

static void print_table(const char *name, int kind, const row_t *rows, int nrows, int ip_row, int em_row, FILE *csv)
{
    const row_t *ip = &rows[ip_row], *em = &rows[em_row];
    const hz_accel_stats_t *ips = &ip->st[kind];
    const double ip_isect = ips->rays ? (double)ips->tris / ips->rays : 0.0;
    const double ip_trav = ips->rays ? (double)ips->nodes / ips->rays : 0.0;
    const double ip_ms = ip->ran ? median(ip->render_ms[kind], ip->n) : 0.0;
    const double em_mr = em->ran ? (double)em->rays[kind] / (median(em->render_ms[kind], em->n) * 1e3) : 0.0;
    printf("primary + %s:\n", kind == S_SHADOW ? "shadow ray" : "ambient-occlusion ray");
    printf("%-20s %9s %8s %7s %6s %7s %15s %15s %15s %15s %9s %9s %8s %9s %s\n", "bvh, budget", "refs", "nodes",
           "splits", "stops", "sah", "isect max/avg", "(% interp)", "trav max/avg", "(% interp)", "render ms",
           "build ms", "refit ms", "bytes/tri", "Mrays/s (x embree-mb)");
    for (int b = 0; b < nrows; b++) {
        const row_t *rw = &rows[b];
        char label[32];
        row_label(rw, label, sizeof label);
        if (rw->skipped) {
            printf("%-20s does not fit the accel arena: not built\n", label);
            continue;
        }
        if (!rw->ran)
            continue;
        const hz_accel_stats_t *st = &rw->st[kind];
        const double rms = median(rw->render_ms[kind], rw->n), bms = median(rw->build_ms, rw->n);
        const double fms = median(rw->refit_ms, rw->n), mr = (double)rw->rays[kind] / (rms * 1e3);
        const double ia = st->rays ? (double)st->tris / st->rays : 0.0;
        const double ta = st->rays ? (double)st->nodes / st->rays : 0.0;
        char c_refs[16] = "", c_nodes[16] = "", c_splits[16] = "", c_stops[16] = "", c_sah[16] = "", c_imax[16] = "",
             c_iavg[16] = "", c_tmax[16] = "", c_tavg[16] = "", c_budget[16] = "";
        if (!rw->embree) {
            snprintf(c_refs, sizeof c_refs, "%u", rw->info.ref_count);
            snprintf(c_nodes, sizeof c_nodes, "%u", rw->info.node_count);
            snprintf(c_splits, sizeof c_splits, "%u", rw->info.spatial_splits);
            /* instances: the SAH of the triangles outside them only (object-space trees do not compare) */
            if (!rw->instances || rw->info.instance_tris < rw->info.tri_count)
                snprintf(c_sah, sizeof c_sah, "%.2f", (double)rw->info.sah_cost);
        }
        if (is_msbvh(rw)) {
            snprintf(c_stops, sizeof c_stops, "%u", rw->info.budget_stops);
            snprintf(c_budget, sizeof c_budget, "%g", (double)rw->budget);
        }
        if (rw->have_stats) {
            snprintf(c_imax, sizeof c_imax, "%u", st->ray_tris_max);
            snprintf(c_iavg, sizeof c_iavg, "%.2f", ia);
            snprintf(c_tmax, sizeof c_tmax, "%u", st->ray_nodes_max);
            snprintf(c_tavg, sizeof c_tavg, "%.2f", ta);
        }
        char pi[32] = "", pt[32] = "", xe[32] = "";
        if (rw->have_stats && ip->have_stats && ip_isect > 0.0 && ips->ray_tris_max && ips->ray_nodes_max) {
            snprintf(pi, sizeof pi, "%.0f%% / %.0f%%", 100.0 * st->ray_tris_max / ips->ray_tris_max,
                     100.0 * ia / ip_isect);
            snprintf(pt, sizeof pt, "%.0f%% / %.0f%%", 100.0 * st->ray_nodes_max / ips->ray_nodes_max,
                     100.0 * ta / ip_trav);
        }
        if (em_mr > 0.0)
            snprintf(xe, sizeof xe, " (%.2fx)", mr / em_mr);
        char iv[40], tv[40];
        snprintf(iv, sizeof iv, "%s / %s", c_imax, c_iavg);
        snprintf(tv, sizeof tv, "%s / %s", c_tmax, c_tavg);
        printf("%-20s %9s %8s %7s %6s %7s %15s %15s %15s %15s %9.1f %9.0f %8.1f %9.1f %.2f%s", label, c_refs, c_nodes,
               c_splits, c_stops, c_sah, rw->have_stats ? iv : "", pi, rw->have_stats ? tv : "", pt, rms, bms, fms,
               rw->bytes_per_tri, mr, xe);
        if (ip_ms > 0.0 && b != ip_row)
            printf("  render %.2fx interp", rms / ip_ms);
        if (rw->embree || rw->instances)
            printf("  same hits as msbvh: %.3f%% of pixels", 100.0 * rw->agree[kind]);
        printf("\n");
        if (csv)
            fprintf(csv, "%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%.3f,%.1f,%.3f,%.1f,%.3f,%s,%s,%s\n", name, rw->name, c_refs,
                    c_nodes, c_splits, c_sah, c_imax, c_iavg, c_tmax, c_tavg, rms, bms, fms, rw->bytes_per_tri, mr,
                    secondary_name[kind], c_budget, c_stops);
    }
}

/* Seed 002's Fig. 5: the MSBVH's SAH cost over an animation, refitted every frame (never rebuilt) against built
 * anew every frame, SAH_FRAMES frames at 24 Hz from t = 1 s, each frame's keys over `interval`. */
#define SAH_FRAMES 12
static int sah_over_animation(const hz_bench_motion_opts_t *o, const char *name, const hz_scene_t *sc,
                              hz_accel_geom_t *g, hz_posekeys_t *kp, hz_pools_t *P, FILE *csv)
{
    hz_error_t err;
    const hz_arena_mark_t m0 = hz_arena_mark(&P->accel);
    hz_accel_config_t cfg;
    hz_accel_config_default(&cfg);
    cfg.rebuild_sah_growth = 1e30f; /* refits only */
    cfg.rigid = HZ_ACCEL_RIGID_REFIT;  /* the MSBVH over every moving triangle */
    hz_accel_t *kept = NULL;
    printf("SAH cost over the animation (the paper's Fig. 5), msbvh at budget %g: refitted every frame / built anew\n",
           (double)cfg.split_budget);
    for (int f = 0; f < SAH_FRAMES; f++) {
        const float t = 1.0f + (float)f / 24.0f;
        hz_posekeys_eval(kp, sc, t, -0.5f * o->interval, 0.5f * o->interval);
        if (!kept) {
            if (hz_accel_build_native(&kept, g, &cfg, &P->accel, &err) != HZ_OK)
                return hz_cli_report(&err);
        } else if (hz_accel_refit(kept, &err) != HZ_OK) {
            hz_arena_reset(&P->accel, m0);
            return hz_cli_report(&err);
        }
        const hz_arena_mark_t m1 = hz_arena_mark(&P->accel);
        hz_accel_t *fresh = NULL;
        if (hz_accel_build_native(&fresh, g, &cfg, &P->accel, &err) != HZ_OK) {
            hz_arena_reset(&P->accel, m0);
            return hz_cli_report(&err);
        }
        const float refit = kept->info.sah_cost, built = fresh->info.sah_cost;
        hz_accel_release(fresh);
        hz_arena_reset(&P->accel, m1);
        printf("  t %.4f s  refit %8.2f  rebuilt %8.2f  (%.3fx)\n", (double)t, (double)refit, (double)built,
               built > 0.0f ? (double)(refit / built) : 0.0);
        if (csv)
            fprintf(csv, "%s,%d,%.6f,%.4f,%.4f\n", name, f, (double)t, (double)refit, (double)built);
    }
    hz_accel_release(kept);
    hz_arena_reset(&P->accel, m0);
    return 0;
}

static int bench_scene(const hz_bench_motion_opts_t *o, const char *name, FILE *csv, FILE *sah_csv)
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
    printf("\n%s: %u triangles, %s; %ux%u pixels, one primary + one secondary ray each\n", name, g.tri_count,
           motion, o->width, o->height);
    fflush(stdout);
    frame_t fr;
    if ((rc = frame_of(&fr, &sc, o)) != 0)
        return rc;
    const int rounds = g.tri_count > 1000000u ? 1 : o->rounds;
    const hz_arena_mark_t m0 = hz_arena_mark(&P->accel);
    int bad = 0;
    row_t rows[MAX_ROWS];
    const int nrows = make_rows(o, &g, rows);
    const int ip_row = nrows - 3, em_row = nrows - 1;
    int ref_row = -1; /* the first MSBVH built: the others' hits are compared with its */
#if !defined(HZ_HAVE_EMBREE)
    printf("  embree-mb: not built in (board without Embree)\n");
#endif
    for (int r = 0; r < rounds; r++)
        for (int b = 0; b < nrows; b++) {
            row_t *rw = &rows[b];
            hz_arena_reset(&P->accel, m0);
            hz_accel_t *a = NULL;
            hz_accel_config_t cfg;
            row_config(rw, o->leaf_max, &cfg);
            int64_t t0 = hz_clock_ns();
            hz_status_t s;
            if (rw->embree) {
#if defined(HZ_HAVE_EMBREE)
                s = hz_accel_build_embree(&a, &g, &cfg, "threads=1", &P->accel, &err);
#else
                continue;
#endif
            } else {
                if (rw->skipped || hz_accel_bytes_bound_geom(&g, &cfg).peak > hz_arena_available(&P->accel, 64)) {
                    rw->skipped = true;
                    continue;
                }
                s = hz_accel_build_native(&a, &g, &cfg, &P->accel, &err);
            }
            if (s != HZ_OK) {
                free_frame(&fr);
                hz_error_prefix(&err, rw->name);
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
            if (ref_row < 0 && !rw->embree)
                ref_row = b;
            for (int kind = 0; kind < S_COUNT; kind++) {
                const bool ref = b == ref_row;
                if (r == 0) { /* hits (compared) and per-ray statistics, untimed */
                    hz_accel_stats_t st;
                    memset(&st, 0, sizeof st);
                    render(a, &fr, kind, rw->embree ? NULL : &st, true, ref ? 0 : 1);
                    rw->st[kind] = st;
                    rw->have_stats = !rw->embree && HZ_FEATURE_STATS;
                    if (!ref) {
                        uint64_t same = 0, diff = 0;
                        for (uint32_t i = 0; i < fr.pixels; i++) {
                            const size_t j = (size_t)kind * 2u * fr.pixels;
                            bool eq = fr.hit_prim[j + i] == fr.hit_prim[j + fr.pixels + i] &&
                                      fr.shadowed[j + i] == fr.shadowed[j + fr.pixels + i];
                            same += eq, diff += !eq;
                        }
                        rw->agree[kind] = (double)same / (double)(same + diff);
                        /* the instances' hits are computed in object space: they may round apart */
                        if (!rw->embree && !rw->instances && diff) {
                            char label[32];
                            row_label(rw, label, sizeof label);
                            hz_cli_error("bench: %s: %s (%s rays) differs from the first msbvh on %llu pixels", name,
                                         label, secondary_name[kind], (unsigned long long)diff);
                            bad++;
                        }
                    }
                }
                double c0 = thread_cpu_s();
                rw->rays[kind] = render(a, &fr, kind, NULL, false, 0);
                rw->render_ms[kind][r] = (thread_cpu_s() - c0) * 1e3;
            }
            rw->n = r + 1;
            rw->ran = true;
            hz_accel_release(a);
        }
    hz_arena_reset(&P->accel, m0);
    free_frame(&fr);
    /* tables: percentages of the interpolated BVH (the paper's baseline), Mrays/s against Embree */
    for (int kind = 0; kind < S_COUNT; kind++)
        print_table(name, kind, rows, nrows, ip_row, em_row, csv);
    if (K >= 2u && hz_posekeys_count(&sc, o->interval) >= 2u && g.tri_count <= 1000000u && !bad) {
        const int st = sah_over_animation(o, name, &sc, &g, &keys, P, sah_csv);
        if (st)
            return st;
    } else if (!bad) {
        printf("SAH cost over the animation: not measured (%s)\n",
               g.tri_count > 1000000u ? "over a million triangles: a build per frame takes too long"
                                      : "the scene has no animation of its own");
    }
    fflush(stdout);
    return bad ? hz_status_exit_code(HZ_E_INTERNAL) : 0;
}

/* ---- the motion-size sweep ---- */
#define SWEEP_STEPS 7
static const float sweep_factor[SWEEP_STEPS] = { 0.125f, 0.25f, 0.5f, 1.0f, 2.0f, 4.0f, 8.0f };

static int cmp_float(const void *a, const void *b)
{
    const float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* How far triangles move over the keys against their size: per triangle, the longest path of its three vertices
 * (the sum of the straight moves from key to key) over its mean edge length at the middle key. Median and mean
 * over the triangles with a non-zero size; false when none has one or there is no memory for the median. */
static bool motion_over_size(const hz_accel_geom_t *g, double *median_out, double *mean_out)
{
    float *ratio = malloc((size_t)g->tri_count * sizeof(float) + 1u);
    if (!ratio)
        return false;
    uint32_t n = 0;
    double sum = 0.0;
    const float *mid = g->pos_keys[(g->time_keys - 1u) / 2u]; /* the key g->pos is (hz_posekeys_geom) */
    for (uint32_t t = 0; t < g->tri_count; t++) {
        const uint32_t *v = g->tri + 3u * (size_t)t;
        double path = 0.0, edge = 0.0;
        for (int i = 0; i < 3; i++) {
            const float *a = mid + 4u * (size_t)v[i], *b = mid + 4u * (size_t)v[(i + 1) % 3];
            edge += sqrt((double)(a[0] - b[0]) * (a[0] - b[0]) + (double)(a[1] - b[1]) * (a[1] - b[1]) +
                         (double)(a[2] - b[2]) * (a[2] - b[2])) / 3.0;
            double len = 0.0;
            for (uint32_t k = 0; k + 1u < g->time_keys; k++) {
                const float *p = g->pos_keys[k] + 4u * (size_t)v[i], *q = g->pos_keys[k + 1u] + 4u * (size_t)v[i];
                len += sqrt((double)(q[0] - p[0]) * (q[0] - p[0]) + (double)(q[1] - p[1]) * (q[1] - p[1]) +
                            (double)(q[2] - p[2]) * (q[2] - p[2]));
            }
            path = fmax(path, len);
        }
        if (edge > 0.0 && isfinite(path / edge)) {
            ratio[n++] = (float)(path / edge);
            sum += path / edge;
        }
    }
    if (n)
        qsort(ratio, n, sizeof(float), cmp_float);
    *median_out = n ? ratio[n / 2u] : 0.0;
    *mean_out = n ? sum / n : 0.0;
    free(ratio);
    return n > 0;
}

/* The scene's shutter interval scaled by each sweep factor: keys posed anew, the msbvh at the largest budget, the
 * interpolated and the swept BVH built and refitted, one frame of each secondary kind counted (untimed). */
static int motion_sweep(const hz_bench_motion_opts_t *o, const char *name, FILE *csv)
{
    hz_pools_t *P = hz_pools_get();
    hz_error_t err;
    hz_scene_t sc;
    hz_accel_geom_t g0;
    int rc = hz_bench_open_named(o->scenes_dir, name, P, &sc, &g0);
    if (rc)
        return rc;
    if (hz_posekeys_count(&sc, o->interval) < 2u) {
        printf("\nmotion-size sweep: %s has no animation of its own: not swept\n", name);
        return 0;
    }
    if (!HZ_FEATURE_STATS) {
        printf("\nmotion-size sweep: not measured (board %s counts no intersections)\n", HZ_BOARD_NAME);
        return 0;
    }
    const float budget = largest_budget(o);
    printf("\nmotion-size sweep on %s: the shutter interval scaled (%ux%u pixels, one primary + one secondary ray "
           "each; intersections per ray averaged, %% of the interpolated BVH; msbvh at budget %g)\n", name, o->width,
           o->height, (double)budget);
    printf("%10s %5s %18s %18s %18s %18s %9s %9s %9s\n", "interval s", "keys", "motion/size median", "mean",
           "msbvh ao / shadow", "swept ao / shadow", "sah msbvh", "interp", "refs x");
    frame_t fr;
    if ((rc = frame_of(&fr, &sc, o)) != 0)
        return rc;
    const hz_arena_mark_t s0 = hz_arena_mark(&P->scene), a0 = hz_arena_mark(&P->accel);
    static const hz_accel_blur_t kinds[3] = { HZ_ACCEL_BLUR_MSBVH, HZ_ACCEL_BLUR_INTERP, HZ_ACCEL_BLUR_SWEPT };
    static const char *const kname[3] = { "msbvh", "interp", "swept" };
    int status = 0;
    bool stopped = false; /* a BVH does not fit: the longer intervals would not either */
    for (int f = 0; f < SWEEP_STEPS && !status && !stopped; f++) {
        hz_bench_motion_opts_t fo = *o;
        fo.interval = fminf(10.0f, o->interval * sweep_factor[f]);
        if (f > 0 && fo.interval == fminf(10.0f, o->interval * sweep_factor[f - 1]))
            break; /* capped at 10 s: the same interval again */
        hz_arena_reset(&P->scene, s0);
        hz_accel_geom_t g = g0;
        hz_posekeys_t keys;
        uint32_t K = 0;
        char motion[160];
        if (scene_keys(&fo, name, &sc, &g, &keys, &K, motion, sizeof motion, &P->scene, &err) != HZ_OK) {
            status = hz_cli_report(&err);
            break;
        }
        double med = 0.0, mean = 0.0;
        char c_med[24] = "", c_mean[24] = "", t_med[24] = "-", t_mean[24] = "-"; /* CSV, table */
        if (motion_over_size(&g, &med, &mean)) {
            snprintf(c_med, sizeof c_med, "%.4f", med);
            snprintf(c_mean, sizeof c_mean, "%.4f", mean);
            snprintf(t_med, sizeof t_med, "%.3f", med);
            snprintf(t_mean, sizeof t_mean, "%.3f", mean);
        } else {
            hz_cli_error("bench: %s: motion over size not measured at %.4f s (no triangle with a size, or no memory "
                         "for the median)", name, (double)fo.interval);
        }
        double isect[3][S_COUNT], imax[3][S_COUNT];
        hz_accel_info_t info[3];
        for (int b = 0; b < 3 && !status && !stopped; b++) {
            hz_arena_reset(&P->accel, a0);
            hz_accel_config_t cfg;
            const row_t rw = { .name = kname[b], .blur = kinds[b], .budget = budget };
            row_config(&rw, o->leaf_max, &cfg);
            hz_accel_t *a = NULL;
            bool fits;
            if ((status = build_refitted(&g, &cfg, P, kname[b], &a, &fits)) != 0)
                break;
            if (!fits) {
                printf("%10.4f %5u %s does not fit the accel arena: sweep stopped\n", (double)fo.interval, K, kname[b]);
                stopped = true;
                break;
            }
            info[b] = a->info;
            for (int kind = 0; kind < S_COUNT; kind++) {
                hz_accel_stats_t st;
                memset(&st, 0, sizeof st);
                render(a, &fr, kind, &st, false, 0);
                isect[b][kind] = st.rays ? (double)st.tris / st.rays : 0.0;
                imax[b][kind] = st.ray_tris_max;
            }
            hz_accel_release(a);
        }
        if (status || stopped)
            break;
        char m[3][40];
        for (int b = 0; b < 3; b += 2)
            snprintf(m[b], sizeof m[b], "%.0f%% / %.0f%%", 100.0 * isect[b][S_AO] / isect[1][S_AO],
                     100.0 * isect[b][S_SHADOW] / isect[1][S_SHADOW]);
        printf("%10.4f %5u %18s %18s %18s %18s %9.2f %9.2f %8.2fx\n", (double)fo.interval, K, t_med, t_mean, m[0],
               m[2], (double)info[0].sah_cost, (double)info[1].sah_cost,
               (double)info[0].ref_count / (double)info[1].ref_count);
        for (int b = 0; csv && b < 3; b++)
            for (int kind = 0; kind < S_COUNT; kind++)
                fprintf(csv, "%s,%.6f,%u,%s,%s,%s,%s,%.3f,%.0f,%.1f,%.3f,%u\n", name, (double)fo.interval, K, c_med,
                        c_mean, kname[b], secondary_name[kind], isect[b][kind], imax[b][kind],
                        100.0 * isect[b][kind] / isect[1][kind], (double)info[b].sah_cost, info[b].ref_count);
    }
    hz_arena_reset(&P->accel, a0);
    hz_arena_reset(&P->scene, s0);
    free_frame(&fr);
    fflush(stdout);
    return status;
}

/* ---- leaf sizes ---- */
/* Seed 002's trees were binary with about 3.8 triangles per leaf (its hairball BVH: 182,450 nodes for 348,000
 * triangles), ours are 8 wide with up to 8 per leaf; intersections per ray count the triangles of every leaf
 * entered, so they depend on the leaf size as much as on the boxes. Per leaf size, the MSBVH at budget 1 and at
 * the largest budget (one row where that is 1 or less) and the interpolated BVH, alive together, rendered
 * interleaved. */
#define LEAF_SIZES 3
#define LEAF_BVHS 3

/* The rows of one leaf size (interp last); returns their number: 2, or 3 where the largest budget exceeds 1. */
static int leaf_rows(const hz_bench_motion_opts_t *o, row_t *rows)
{
    const float budget = largest_budget(o);
    int n = 0;
    if (budget > 1.0f)
        rows[n++] = (row_t){ .name = "msbvh", .blur = HZ_ACCEL_BLUR_MSBVH, .budget = 1.0f };
    rows[n++] = (row_t){ .name = "msbvh", .blur = HZ_ACCEL_BLUR_MSBVH, .budget = budget };
    rows[n++] = (row_t){ .name = "interp", .blur = HZ_ACCEL_BLUR_INTERP };
    return n;
}

static void leaf_sizes_of(uint32_t *sizes)
{
    hz_accel_config_t d;
    hz_accel_config_default(&d);
    sizes[0] = 2u, sizes[1] = 4u, sizes[2] = d.leaf_max;
}

static int leaf_pass(const hz_bench_motion_opts_t *o, const char *name, FILE *csv)
{
    hz_pools_t *P = hz_pools_get();
    hz_error_t err;
    hz_scene_t sc;
    hz_accel_geom_t g;
    int rc = hz_bench_open_named(o->scenes_dir, name, P, &sc, &g);
    if (rc)
        return rc;
    if (!HZ_FEATURE_STATS) {
        printf("\nleaf sizes: not measured (board %s counts no intersections)\n", HZ_BOARD_NAME);
        return 0;
    }
    hz_posekeys_t keys;
    char motion[160];
    uint32_t K = 0;
    if (scene_keys(o, name, &sc, &g, &keys, &K, motion, sizeof motion, &P->scene, &err) != HZ_OK)
        return hz_cli_report(&err);
    frame_t fr;
    if ((rc = frame_of(&fr, &sc, o)) != 0)
        return rc;
    uint32_t sizes[LEAF_SIZES];
    leaf_sizes_of(sizes);
    printf("\nleaf sizes on %s (%s; %ux%u pixels, one primary + one secondary ray each; the seed's hairball tree held "
           "about 3.8 triangles per leaf, ours up to %u; %% and x of the interpolated BVH with the same leaves, "
           "rendered interleaved with it; render ms: thread CPU, median of %d rounds)\n", name, motion, o->width,
           o->height, sizes[LEAF_SIZES - 1], o->rounds);
    printf("%5s %-12s %9s %8s %9s %17s %17s %15s %19s %12s\n", "leaf", "bvh, budget", "refs", "nodes", "bytes/tri",
           "isect shadow/ao", "(% interp)", "trav shadow/ao", "render ms shadow/ao", "(x interp)");
    const hz_arena_mark_t m0 = hz_arena_mark(&P->accel);
    int status = 0, bad = 0;
    bool have_ref = false; /* the first BVH's hits, which every other must return */
    double ip_default[S_COUNT] = { 0.0, 0.0 };
    for (int li = 0; li < LEAF_SIZES && !status; li++) {
        row_t rows[LEAF_BVHS];
        const int nb = leaf_rows(o, rows);
        hz_accel_t *acc[LEAF_BVHS] = { NULL, NULL, NULL };
        hz_arena_reset(&P->accel, m0);
        for (int b = 0; b < nb && !status; b++) {
            hz_accel_config_t cfg;
            row_config(&rows[b], sizes[li], &cfg);
            bool fits;
            if ((status = build_refitted(&g, &cfg, P, rows[b].name, &acc[b], &fits)) != 0)
                break;
            if (!fits) {
                rows[b].skipped = true;
                continue;
            }
            rows[b].info = acc[b]->info;
            rows[b].bytes_per_tri = g.tri_count ? (double)acc[b]->info.bytes / g.tri_count : 0.0;
            for (int kind = 0; kind < S_COUNT; kind++) {
                hz_accel_stats_t st;
                memset(&st, 0, sizeof st);
                render(acc[b], &fr, kind, &st, true, have_ref ? 1 : 0);
                rows[b].st[kind] = st;
                if (!have_ref)
                    continue;
                uint64_t diff = 0;
                const size_t j = (size_t)kind * 2u * fr.pixels;
                for (uint32_t i = 0; i < fr.pixels; i++)
                    diff += fr.hit_prim[j + i] != fr.hit_prim[j + fr.pixels + i] ||
                            fr.shadowed[j + i] != fr.shadowed[j + fr.pixels + i];
                if (diff) {
                    hz_cli_error("bench: %s: %s %g with leaves of %u (%s rays) differs from the first msbvh on %llu "
                                 "pixels", name, rows[b].name, (double)rows[b].budget, sizes[li],
                                 secondary_name[kind], (unsigned long long)diff);
                    bad++;
                }
            }
            have_ref = true;
            rows[b].have_stats = true;
        }
        for (int r = 0; r < o->rounds && !status; r++)
            for (int b = 0; b < nb; b++)
                for (int kind = 0; acc[b] && kind < S_COUNT; kind++) {
                    double c0 = thread_cpu_s();
                    rows[b].rays[kind] = render(acc[b], &fr, kind, NULL, false, 0);
                    rows[b].render_ms[kind][r] = (thread_cpu_s() - c0) * 1e3;
                    rows[b].n = r + 1;
                    rows[b].ran = true;
                }
        for (int b = nb; b-- > 0;)
            if (acc[b])
                hz_accel_release(acc[b]);
        if (status)
            break;
        const row_t *ip = &rows[nb - 1];
        double ip_isect[S_COUNT], ip_ms[S_COUNT];
        for (int kind = 0; kind < S_COUNT; kind++) {
            ip_isect[kind] = ip->ran && ip->st[kind].rays ? (double)ip->st[kind].tris / ip->st[kind].rays : 0.0;
            ip_ms[kind] = ip->ran ? median(ip->render_ms[kind], ip->n) : 0.0;
            if (li == LEAF_SIZES - 1)
                ip_default[kind] = ip_ms[kind];
        }
        for (int b = 0; b < nb; b++) {
            const row_t *rw = &rows[b];
            char label[32];
            row_label(rw, label, sizeof label);
            if (rw->skipped) {
                printf("%5u %-12s does not fit the accel arena: not built\n", sizes[li], label);
                continue;
            }
            if (!rw->ran)
                continue;
            double ia[S_COUNT], ta[S_COUNT], ms[S_COUNT], pct[S_COUNT], x[S_COUNT];
            for (int kind = 0; kind < S_COUNT; kind++) {
                const hz_accel_stats_t *st = &rw->st[kind];
                ia[kind] = st->rays ? (double)st->tris / st->rays : 0.0;
                ta[kind] = st->rays ? (double)st->nodes / st->rays : 0.0;
                ms[kind] = median(rw->render_ms[kind], rw->n);
                pct[kind] = ip_isect[kind] > 0.0 ? 100.0 * ia[kind] / ip_isect[kind] : 0.0;
                x[kind] = ip_ms[kind] > 0.0 ? ms[kind] / ip_ms[kind] : 0.0;
            }
            printf("%5u %-12s %9u %8u %9.1f %8.2f / %6.2f %7.0f%% / %5.0f%% %6.2f / %6.2f %9.1f / %7.1f %5.2fx / "
                   "%4.2fx\n", sizes[li], label, rw->info.ref_count, rw->info.node_count, rw->bytes_per_tri,
                   ia[S_SHADOW], ia[S_AO], pct[S_SHADOW], pct[S_AO], ta[S_SHADOW], ta[S_AO], ms[S_SHADOW], ms[S_AO],
                   x[S_SHADOW], x[S_AO]);
            for (int kind = 0; csv && kind < S_COUNT; kind++) {
                char c_budget[16] = "";
                if (is_msbvh(rw))
                    snprintf(c_budget, sizeof c_budget, "%g", (double)rw->budget);
                fprintf(csv, "%s,%u,%s,%s,%s,%u,%u,%.1f,%.3f,%u,%.1f,%.3f,%.3f,%.3f\n", name, sizes[li], rw->name,
                        c_budget, secondary_name[kind], rw->info.ref_count, rw->info.node_count, rw->bytes_per_tri,
                        ia[kind], rw->st[kind].ray_tris_max, pct[kind], ta[kind], ms[kind], x[kind]);
            }
        }
    }
    if (!status && ip_default[S_SHADOW] > 0.0)
        printf("(the interpolated BVH with leaves of %u renders in %.1f / %.1f ms: the render-time goal's baseline)\n",
               sizes[LEAF_SIZES - 1], ip_default[S_SHADOW], ip_default[S_AO]);
    hz_arena_reset(&P->accel, m0);
    free_frame(&fr);
    fflush(stdout);
    if (status)
        return status;
    return bad ? hz_status_exit_code(HZ_E_INTERNAL) : 0;
}

static void with_defaults(hz_bench_motion_opts_t *o)
{
    static const char *const defaults[] = { "hairball", "sponza-rotated", "furball-sway", "tentacles" };
    hz_bench_scene_list(&o->scenes_dir, o->scenes, &o->scene_count, defaults, (int)HZ_ARRAY_LEN(defaults));
    if (!o->sweep_scene)
        for (int i = 0; i < o->scene_count; i++)
            if (!strcmp(o->scenes[i], "hairball"))
                o->sweep_scene = "hairball";
    if (o->sweep_scene && !strcmp(o->sweep_scene, "none"))
        o->sweep_scene = NULL;
    if (o->rounds <= 0)
        o->rounds = 3;
    if (o->rounds > MAX_ROUNDS)
        o->rounds = MAX_ROUNDS;
    if (!o->width || !o->height)
        o->width = o->height = 512;
    if (!(o->interval > 0.0f))
        o->interval = 1.0f / 24.0f;
    if (o->budget_count <= 0) {
        static const float budgets[] = { 0.25f, 0.5f, 1.0f, HZ_ACCEL_SPLIT_BUDGET_MAX };
        o->budget_count = (int)HZ_ARRAY_LEN(budgets);
        for (int i = 0; i < o->budget_count; i++)
            o->budgets[i] = budgets[i];
    }
}

int hz_bench_motion(const hz_bench_motion_opts_t *opts, bool *swept)
{
    *swept = false;
    hz_bench_motion_opts_t o = *opts;
    with_defaults(&o);
    /* Every scene is there before anything is measured: a missing one is named, not found half-way. */
    int missing = 0;
    for (int i = 0; i < o.scene_count; i++)
        missing += !hz_bench_scene_present(o.scenes_dir, o.scenes[i], "");
    if (o.sweep_scene)
        missing += !hz_bench_scene_present(o.scenes_dir, o.sweep_scene, "--motion-sweep: ");
    if (missing) {
        hz_cli_error("bench: motion: %d scene%s missing (`make bench` bakes them; by hand: `make scenes`)", missing,
                     missing > 1 ? "s" : "");
        return hz_status_exit_code(HZ_E_IO);
    }
    printf("\nmotion blur (seed 002): native motion BVHs vs Embree motion blur (one thread, 8-ray packets; "
           "%% of the interpolated BVH as in the paper's Table 1)\n");
    if (o.leaf_max)
        printf("native leaves of at most %u triangles\n", o.leaf_max);
    enum { MAIN, SAH, SWEEP, LEAF, NOUT };
    static const char *const suffix[NOUT] = { NULL, "sah", "sweep", "leaf" };
    static const char *const header[NOUT] = {
        "scene,bvh,refs,nodes,spatial_splits,sah,isect_max,isect_avg,trav_max,trav_avg,render_ms,build_ms,refit_ms,"
        "bytes_per_tri,mrays_per_s,secondary,split_budget,budget_stops\n",
        "scene,frame,time_s,sah_refit,sah_rebuilt\n",
        "scene,interval_s,keys,motion_over_size_median,motion_over_size_mean,bvh,secondary,isect_avg,isect_max,"
        "isect_avg_pct_interp,sah,refs\n",
        "scene,leaf_max,bvh,split_budget,secondary,refs,nodes,bytes_per_tri,isect_avg,isect_max,isect_avg_pct_interp,"
        "trav_avg,render_ms,render_vs_interp\n"
    };
    hz_out_t out[NOUT];
    FILE *f[NOUT] = { NULL, NULL, NULL, NULL };
    char path[NOUT][4096];
    hz_error_t err;
    const int nout = o.sweep_scene ? NOUT : SWEEP;
    for (int i = 0; o.csv_path && i < nout; i++) {
        if (i == MAIN)
            snprintf(path[i], sizeof path[i], "%s", o.csv_path);
        else
            hz_bench_csv_beside(o.csv_path, suffix[i], path[i], sizeof path[i]);
        if (hz_out_open(&out[i], path[i], &err) != HZ_OK) {
            while (i-- > 0)
                hz_out_abort(&out[i]);
            return hz_cli_report(&err);
        }
        f[i] = out[i].f;
        fputs(header[i], f[i]);
    }
    int status = 0;
    for (int i = 0; i < o.scene_count && status == 0; i++) {
        status = bench_scene(&o, o.scenes[i], f[MAIN], f[SAH]);
    }
    printf("(seed 002, Table 1, one primary + one ambient-occlusion ray, MSBVH against the interpolated BVH: hairball "
           "2.50x references, 32%% / 43%% intersections max/avg, 85%% render time; Rotated Sponza 1.85x, 41%% / 47%%, "
           "72%%. A budget's stops column: splits the budget stopped, 0 = as without a budget)\n");
    if (status == 0 && o.sweep_scene)
        status = leaf_pass(&o, o.sweep_scene, f[LEAF]);
    if (status == 0 && o.sweep_scene)
        status = motion_sweep(&o, o.sweep_scene, f[SWEEP]);
    if (o.csv_path) {
        for (int i = 0; i < nout; i++) {
            if (status != 0) {
                hz_out_abort(&out[i]);
            } else if (hz_out_commit(&out[i], &err) != HZ_OK) {
                status = hz_cli_report(&err);
            }
        }
        if (status == 0 && nout > SWEEP)
            printf("wrote %s, %s, %s and %s\n", path[MAIN], path[SAH], path[LEAF], path[SWEEP]);
        else if (status == 0)
            printf("wrote %s and %s\n", path[MAIN], path[SAH]);
        *swept = status == 0 && nout > SWEEP;
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
    /* the native rows the table builds, each as it configures them (the MSBVH's bound grows with the budget) */
    row_t rows[MAX_ROWS];
    const int nrows = make_rows(o, &g, rows);
    for (int b = 0; b < nrows; b++) {
        if (rows[b].embree)
            continue;
        hz_accel_config_t cfg;
        char label[32], what[48];
        row_config(&rows[b], o->leaf_max, &cfg);
        row_label(&rows[b], label, sizeof label);
        snprintf(what, sizeof what, "native %s", label);
        hz_bench_fit_accel(fs, &cfg, K, what);
    }
}

/* The leaf pass keeps the BVHs of a leaf size alive together: their bounds summed, per leaf size. */
static void fit_leaf(hz_bench_fit_scene_t *fs, const void *ctx)
{
    const hz_bench_motion_opts_t *o = ctx;
    hz_arena_t *scene_arena = &fs->bs.pools->scene;
    hz_accel_geom_t g;
    hz_posekeys_t keys;
    hz_error_t err;
    uint32_t K = 0;
    char motion[160];
    if (hz_accel_geom_from_scene(&g, &fs->bs.scene, scene_arena, &err) != HZ_OK ||
        scene_keys(o, fs->label, &fs->bs.scene, &g, &keys, &K, motion, sizeof motion, scene_arena, &err) != HZ_OK) {
        hz_bench_fit_fail(fs, "pose keys DO NOT FIT", err.msg);
        return;
    }
    uint32_t sizes[LEAF_SIZES];
    leaf_sizes_of(sizes);
    for (int li = 0; li < LEAF_SIZES; li++) {
        row_t rows[LEAF_BVHS];
        const int nb = leaf_rows(o, rows);
        size_t need = 0;
        for (int b = 0; b < nb; b++) {
            hz_accel_config_t cfg;
            row_config(&rows[b], sizes[li], &cfg);
            need += hz_accel_bytes_bound_geom(&g, &cfg).peak;
        }
        char what[64];
        snprintf(what, sizeof what, "native msbvh x%d + interp, leaves of %u, %u keys", nb - 1, sizes[li], K);
        hz_bench_fit_line(fs, what, "accel", need, hz_arena_available(&fs->bs.pools->accel, 64));
    }
}

void hz_bench_motion_fit(const hz_bench_motion_opts_t *opts, hz_bench_fit_t *fit)
{
    hz_bench_motion_opts_t o = *opts;
    with_defaults(&o);
    hz_bench_fit_named(fit, "motion", o.scenes, o.scene_count, fit_scene, &o);
    if (o.sweep_scene)
        hz_bench_fit_named(fit, "motion-leaf", &o.sweep_scene, 1, fit_leaf, &o);
    if (o.sweep_scene) { /* the sweep's longest interval: the most keys */
        o.interval = fminf(10.0f, o.interval * sweep_factor[SWEEP_STEPS - 1]);
        hz_bench_fit_named(fit, "motion-sweep", &o.sweep_scene, 1, fit_scene, &o);
    }
}
