/* The accel benchmark of hzbench (see bench_accel.h). */
#include "bench_accel.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli.h"
#include "bench_fit.h"
#include "bench_util.h"
#include "clock.h"
#include "fileio.h"
#include "hz/accel.h"
#include "hz/hash.h"
#include "hz/hz.h"
#include "hz/scene.h"
#include "pools.h"
#include "scenefile.h"
#include "threads.h"
#if defined(HZ_HAVE_EMBREE)
#include "embree_accel.h"
#endif

#define CHUNK 2048u         /* rays per work item */
#define SCALAR_STRIDE 8u    /* the scalar reference runs every 8th item: same rays everywhere, an 8th of the time */
#define MAX_ROUNDS 15

typedef enum { K_PRIMARY, K_SHADOW, K_DIFFUSE, K_COUNT } kind_t;
/* Native methods, then Embree's at two devices: its default ISA (or --embree-config) and isa=avx2 (the native
 * kernels' ISA), each with rtcIntersect1 and rtcIntersect8 without and with RTC_INTERSECT_CONTEXT_FLAG_COHERENT. */
typedef enum {
    M_SCALAR, M_SINGLE, M_AUTO8, M_TILE, M_TILE_L,
    M_E1, M_E8, M_E8C, M_A1, M_A8, M_A8C,
    M_COUNT
} method_t;
#define M_FIRST_EMBREE M_E1

static const char *kind_name[K_COUNT] = { "primary", "shadow", "diffuse" };
static const char *method_name[M_COUNT] = { "scalar", "simd-1", "simd-8", "tile-64", "tile-256",
                                            "embree-1", "embree-8", "embree-8c", "avx2-1", "avx2-8", "avx2-8c" };
static const char *method_csv[M_COUNT] = { "native scalar", "native simd single", "native simd packet (auto)",
                                           "native tile of 8 packets (auto)", "native tile of 32 packets (auto)",
                                           "embree rtcIntersect1", "embree rtcIntersect8",
                                           "embree rtcIntersect8 coherent", "embree isa=avx2 rtcIntersect1",
                                           "embree isa=avx2 rtcIntersect8", "embree isa=avx2 rtcIntersect8 coherent" };
/* Tile calls: 8 packets (an 8x8-pixel tile of primary rays) or 32 (16x16 pixels: four 8x8 quadrants in turn). */
#define TILE_SMALL 8u
#define TILE_LARGE 32u

typedef struct rayset {
    hz_rayhit_t *aos;
    hz_rayhit8_t *soa;
    uint32_t n, packets;
} rayset_t;

typedef struct job {
    hz_accel_stats_t *stats; /* HZ_BENCH_STATS: counters of the one-thread run */
    const hz_accel_t *accel;
    method_t m;
    kind_t k;
    const rayset_t *rs;
    uint32_t stride;  /* run items with item % stride == 0 */
    uint32_t *hits;   /* per item */
    uint32_t *sum;    /* per item: a checksum of the triangles hit */
} job_t;

static void run_item(void *user, uint32_t item, int thread)
{
    const job_t *j = user;
    if (item % j->stride)
        return;
    const rayset_t *rs = j->rs;
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    ctx.stats = thread == 0 ? j->stats : NULL;
    /* native: the coherence hint as a renderer gives it (camera and shadow rays coherent, bounces not); Embree:
     * the flag as the method says */
    ctx.flags = j->m >= M_FIRST_EMBREE ? (j->m == M_E8C || j->m == M_A8C ? HZ_ACCEL_COHERENT : 0u)
                                       : (j->k == K_DIFFUSE ? 0u : HZ_ACCEL_COHERENT);
    ctx.kernel = j->m == M_SCALAR ? HZ_ACCEL_KERNEL_SCALAR
                 : j->m == M_SINGLE ? HZ_ACCEL_KERNEL_SIMD_SINGLE
                                    : HZ_ACCEL_KERNEL_AUTO;
    uint32_t lo = item * CHUNK, hi = lo + CHUNK < rs->n ? lo + CHUNK : rs->n, hits = 0, sum = 0;
    const bool single = j->m == M_SCALAR || j->m == M_SINGLE || j->m == M_E1 || j->m == M_A1;
    if (single) {
        for (uint32_t i = lo; i < hi; i++) {
            if (j->k == K_SHADOW) {
                hz_ray_t r = rs->aos[i].ray;
                hz_accel_occluded1(j->accel, &ctx, &r);
                hits += r.tfar < 0.0f;
            } else {
                hz_rayhit_t rh = rs->aos[i];
                hz_accel_intersect1(j->accel, &ctx, &rh);
                if (rh.hit.geom_id == 0)
                    hits++, sum += hz_hash32(rh.hit.prim_id);
            }
        }
    } else if (j->m == M_TILE || j->m == M_TILE_L) {
        const uint32_t tp = j->m == M_TILE ? TILE_SMALL : TILE_LARGE;
        for (uint32_t p = lo / 8; p < (hi + 7) / 8; p += tp) {
            const uint32_t np = (hi + 7) / 8 - p < tp ? (hi + 7) / 8 - p : tp;
            int32_t valid[8 * TILE_LARGE];
            for (uint32_t l = 0; l < 8 * np; l++)
                valid[l] = p * 8 + l < hi ? -1 : 0;
            if (j->k == K_SHADOW) {
                hz_ray8_t r[TILE_LARGE];
                for (uint32_t q = 0; q < np; q++)
                    r[q] = rs->soa[p + q].ray;
                hz_accel_occluded8n(valid, j->accel, &ctx, r, np);
                for (uint32_t l = 0; l < 8 * np; l++)
                    hits += valid[l] && r[l / 8].tfar[l % 8] < 0.0f;
            } else {
                hz_rayhit8_t rh[TILE_LARGE];
                memcpy(rh, &rs->soa[p], np * sizeof rh[0]);
                hz_accel_intersect8n(valid, j->accel, &ctx, rh, np);
                for (uint32_t l = 0; l < 8 * np; l++)
                    if (valid[l] && rh[l / 8].hit.geom_id[l % 8] == 0)
                        hits++, sum += hz_hash32(rh[l / 8].hit.prim_id[l % 8]);
            }
        }
    } else {
        for (uint32_t p = lo / 8; p < (hi + 7) / 8; p++) {
            int32_t valid[8];
            for (uint32_t l = 0; l < 8; l++)
                valid[l] = p * 8 + l < hi ? -1 : 0;
            if (j->k == K_SHADOW) {
                hz_ray8_t r = rs->soa[p].ray;
                hz_accel_occluded8(valid, j->accel, &ctx, &r);
                for (int l = 0; l < 8; l++)
                    hits += valid[l] && r.tfar[l] < 0.0f;
            } else {
                hz_rayhit8_t rh = rs->soa[p];
                hz_accel_intersect8(valid, j->accel, &ctx, &rh);
                for (int l = 0; l < 8; l++)
                    if (valid[l] && rh.hit.geom_id[l] == 0)
                        hits++, sum += hz_hash32(rh.hit.prim_id[l]);
            }
        }
    }
    j->hits[item] = hits;
    j->sum[item] = sum;
}

static double thread_cpu_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

/* Mrays/s of one method on one set, with one thread (CPU time) or all (wall time). */
static double measure(job_t *j, uint32_t items, bool all_threads)
{
    uint32_t rays = 0;
    for (uint32_t it = 0; it < items; it += j->stride) {
        uint32_t lo = it * CHUNK;
        rays += (lo + CHUNK < j->rs->n ? CHUNK : j->rs->n - lo);
    }
    double s;
    if (all_threads) {
        int64_t t0 = hz_clock_ns();
        hz_threads_run(run_item, j, items);
        s = (double)(hz_clock_ns() - t0) * 1e-9;
    } else {
        double t0 = thread_cpu_s();
        for (uint32_t it = 0; it < items; it++)
            run_item(j, it, 0);
        s = thread_cpu_s() - t0;
    }
    return s > 0.0 ? (double)rays / s * 1e-6 : 0.0;
}

/* ---- ray sets ---- */
static void set_ray(hz_rayhit_t *rh, hz_vec3_t o, hz_vec3_t d, float tfar, uint32_t id)
{
    memset(rh, 0, sizeof *rh);
    rh->ray.org_x = o.x, rh->ray.org_y = o.y, rh->ray.org_z = o.z;
    rh->ray.dir_x = d.x, rh->ray.dir_y = d.y, rh->ray.dir_z = d.z;
    rh->ray.tfar = tfar;
    rh->ray.mask = 0xFFFFFFFFu;
    rh->ray.id = id;
    rh->hit.geom_id = rh->hit.prim_id = rh->hit.inst_id[0] = HZ_ACCEL_INVALID_ID;
}

static void pack(rayset_t *rs)
{
    rs->packets = (rs->n + 7) / 8;
    for (uint32_t p = 0; p < rs->packets; p++) {
        hz_rayhit8_t *P = &rs->soa[p];
        memset(P, 0, sizeof *P);
        for (uint32_t l = 0; l < 8; l++) {
            const hz_rayhit_t *r = &rs->aos[p * 8 + l < rs->n ? p * 8 + l : rs->n - 1];
            P->ray.org_x[l] = r->ray.org_x, P->ray.org_y[l] = r->ray.org_y, P->ray.org_z[l] = r->ray.org_z;
            P->ray.tnear[l] = r->ray.tnear, P->ray.dir_x[l] = r->ray.dir_x, P->ray.dir_y[l] = r->ray.dir_y;
            P->ray.dir_z[l] = r->ray.dir_z, P->ray.time[l] = r->ray.time, P->ray.tfar[l] = r->ray.tfar;
            P->ray.mask[l] = r->ray.mask, P->ray.id[l] = r->ray.id, P->ray.flags[l] = r->ray.flags;
            P->hit.geom_id[l] = P->hit.prim_id[l] = P->hit.inst_id[0][l] = HZ_ACCEL_INVALID_ID;
        }
    }
}

static bool alloc_set(rayset_t *rs, uint32_t cap)
{
    void *a = NULL, *b = NULL;
    if (posix_memalign(&a, 64, (size_t)cap * sizeof(hz_rayhit_t)) != 0 ||
        posix_memalign(&b, 64, ((size_t)cap / 8 + 1) * sizeof(hz_rayhit8_t)) != 0) {
        free(a);
        return false;
    }
    rs->aos = a;
    rs->soa = b;
    rs->n = 0;
    return true;
}

static void free_set(rayset_t *rs)
{
    free(rs->aos);
    free(rs->soa);
}

/* Primary rays in 16x16-pixel tiles of four 8x8-pixel quadrants of eight 4x2-pixel packets each (a packet: 4x2
 * pixels; tile calls: a quadrant or the whole tile), then shadow and diffuse rays from their hits, in that
 * order. */
static void make_rays(const hz_scene_t *sc, const hz_accel_t *a, uint32_t w, uint32_t h, rayset_t sets[K_COUNT],
                      hz_vec3_t *light_out)
{
    hz_camera_t cam = hz_scene_camera(sc, 0.0f);
    hz_vec3_t f = hz_v3_normalize(hz_v3_sub(cam.target, cam.eye));
    hz_vec3_t r = hz_v3_normalize(hz_v3_cross(f, cam.up));
    hz_vec3_t u = hz_v3_cross(r, f);
    const float th = hz_tanf(0.5f * cam.fov_y), aspect = (float)w / (float)h;
    rayset_t *pr = &sets[K_PRIMARY];
    for (uint32_t Ty = 0; Ty < h; Ty += 16)
        for (uint32_t Tx = 0; Tx < w; Tx += 16)
            for (uint32_t q = 0; q < 32; q++) /* quadrant q / 8, packet q % 8 of it: 2 across, 4 down */
            for (uint32_t ty = Ty + (q / 16) * 8 + (q % 8 / 2) * 2, tx = Tx + (q / 8 % 2) * 8 + (q % 2) * 4, y = ty;
                 y < ty + 2 && y < h; y++)
                for (uint32_t x = tx; x < tx + 4 && x < w; x++) {
                    float sx = ((float)x + 0.5f) / (float)w * 2.0f - 1.0f, sy = 1.0f - ((float)y + 0.5f) / (float)h * 2.0f;
                    hz_vec3_t d = hz_v3_add(f, hz_v3_add(hz_v3_scale(r, sx * th * aspect), hz_v3_scale(u, sy * th)));
                    set_ray(&pr->aos[pr->n++], cam.eye, d, INFINITY, y * w + x);
                }
    pack(pr);
    const float *bmin = sc->header->bounds_min, *bmax = sc->header->bounds_max;
    float scale = 0.0f;
    for (int k = 0; k < 3; k++)
        scale = fmaxf(scale, fmaxf(fabsf(bmin[k]), fabsf(bmax[k])));
    hz_vec3_t light = sc->light_count
                          ? hz_v3(sc->lights[0].position[0], sc->lights[0].position[1], sc->lights[0].position[2])
                          : hz_v3(0.5f * (bmin[0] + bmax[0]), bmin[1] + 0.9f * (bmax[1] - bmin[1]),
                                  0.5f * (bmin[2] + bmax[2]));
    *light_out = light;
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    ctx.flags = HZ_ACCEL_COHERENT;
    static const int32_t all[8] = { -1, -1, -1, -1, -1, -1, -1, -1 };
    for (uint32_t p = 0; p < pr->packets; p++) {
        hz_rayhit8_t P = pr->soa[p];
        hz_accel_intersect8(all, a, &ctx, &P);
        for (uint32_t l = 0; l < 8 && p * 8 + l < pr->n; l++) {
            if (P.hit.geom_id[l] != 0)
                continue;
            hz_vec3_t o = hz_v3(P.ray.org_x[l], P.ray.org_y[l], P.ray.org_z[l]);
            hz_vec3_t d = hz_v3(P.ray.dir_x[l], P.ray.dir_y[l], P.ray.dir_z[l]);
            hz_vec3_t hp = hz_v3_add(o, hz_v3_scale(d, P.ray.tfar[l]));
            hz_vec3_t n = hz_v3_normalize(hz_v3(P.hit.ng_x[l], P.hit.ng_y[l], P.hit.ng_z[l]));
            if (hz_v3_dot(n, d) > 0.0f)
                n = hz_v3_neg(n);
            hz_vec3_t org = hz_accel_offset_origin(hp, n, scale);
            uint32_t id = P.ray.id[l];
            hz_vec3_t tl = hz_v3_sub(light, org);
            if (hz_v3_dot(tl, n) > 0.0f) /* lit side only, as a renderer would */
                set_ray(&sets[K_SHADOW].aos[sets[K_SHADOW].n++], org, tl, 1.0f, id);
            /* cosine-weighted direction about n */
            float u1 = hz_u32_to_unit(hz_hash2(id, 1)), u2 = hz_u32_to_unit(hz_hash2(id, 2)), sp, cp;
            float rr = hz_sqrtf(u1);
            hz_sincosf(2.0f * HZ_PI * u2, &sp, &cp);
            hz_vec3_t t1 = hz_absf(n.x) > 0.5f ? hz_v3(0, 1, 0) : hz_v3(1, 0, 0);
            hz_vec3_t b1 = hz_v3_normalize(hz_v3_cross(n, t1)), b2 = hz_v3_cross(n, b1);
            hz_vec3_t dd = hz_v3_add(hz_v3_add(hz_v3_scale(b1, rr * cp), hz_v3_scale(b2, rr * sp)),
                                     hz_v3_scale(n, hz_sqrtf(hz_maxf(0.0f, 1.0f - u1))));
            set_ray(&sets[K_DIFFUSE].aos[sets[K_DIFFUSE].n++], org, dd, INFINITY, id);
        }
    }
    pack(&sets[K_SHADOW]);
    pack(&sets[K_DIFFUSE]);
}

/* Whether the comma-separated list `only` names kind:method. */
static bool only_has(const char *only, const char *kind, const char *method)
{
    char want[64];
    const int n = snprintf(want, sizeof want, "%s:%s", kind, method);
    for (const char *p = only; (p = strstr(p, want)) != NULL; p += n)
        if ((p == only || p[-1] == ',') && (p[n] == '\0' || p[n] == ','))
            return true;
    return false;
}

/* ---- one scene ---- */
typedef struct result {
    double mr[2][MAX_ROUNDS]; /* [threads: 1, all][round] */
    double med[2], lo[2], hi[2];
    bool ran;
} result_t;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static void stats(double *v, int n, double *med, double *lo, double *hi)
{
    double s[MAX_ROUNDS];
    memcpy(s, v, (size_t)n * sizeof(double));
    qsort(s, (size_t)n, sizeof(double), cmp_double);
    *med = n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
    *lo = s[0];
    *hi = s[n - 1];
}

static double best_of(const result_t *r, int t, const method_t *ms, int nm)
{
    double b = 0.0;
    for (int i = 0; i < nm; i++)
        if (r[ms[i]].ran && r[ms[i]].med[t] > b)
            b = r[ms[i]].med[t];
    return b;
}

typedef struct summary {
    char name[64];
    uint32_t tris;
    double ratio[K_COUNT][2];     /* best native SIMD / Embree's best at isa=avx2 (the goal's) */
    double ratio_any[K_COUNT][2]; /* best native SIMD / Embree's best at any ISA */
    /* build time native / Embree medium at 1 thread, native / Embree high at the pool's count, and the native
     * binned SAH build (no spatial splits: what Embree's medium build is) / Embree medium at 1 thread */
    double build[3];
} summary_t;

/* One native build of g with cfg (NULL: defaults) in the accel arena reset to m0; *secs its time. */
static hz_status_t timed_native_build(hz_accel_t **a, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                                      hz_arena_t *arena, hz_arena_mark_t m0, double *secs, hz_error_t *err)
{
    hz_arena_reset(arena, m0);
    const int64_t t0 = hz_clock_ns();
    const hz_status_t s = hz_accel_build_native(a, g, cfg, arena, err);
    *secs = (double)(hz_clock_ns() - t0) * 1e-9;
    return s;
}

static int bench_scene(const hz_bench_accel_opts_t *o, const char *name, FILE *csv, summary_t *sum)
{
    hz_pools_t *P = hz_pools_get();
    hz_error_t err;
    hz_scene_t sc;
    hz_accel_geom_t g;
    int rc = hz_bench_open_named(o->scenes_dir, name, P, &sc, &g);
    if (rc)
        return rc;
    snprintf(sum->name, sizeof sum->name, "%s", name);
    sum->tris = g.tri_count;

    /* builds, interleaved: native on this thread and on the pool (the same tree), Embree's medium (its default,
     * binned SAH) and high (spatial splits) builds with threads=1 and threads=N (N = the pool's size), so each
     * pair is at the same thread count. Goals: native on one thread within 2x of Embree medium on one thread, and
     * native on N threads within 2x of Embree high on N threads. The native binned SAH build (spatial splits
     * off) on one thread is timed with them: Embree medium's like for like. */
    const int build_rounds = g.tri_count > 1000000 ? 1 : 3;
    const int nthr = hz_threads_count();
    double tn1[3], tnn[3], tb1[3], te[2][2][3]; /* te: [quality medium, high][threads 1, N][round] */
    float binned_sah = 0.0f;
    size_t native_bytes = 0, embree_bytes = 0;
    hz_accel_t *a = NULL;
    hz_arena_mark_t m0 = hz_arena_mark(&P->accel);
    hz_accel_config_t pcfg;
    hz_accel_config_default(&pcfg);
    hz_threads_accel_hook(&pcfg);
    hz_accel_config_t bcfg;
    hz_accel_config_default(&bcfg);
    bcfg.spatial_splits = false;
    for (int r = 0; r < build_rounds; r++) {
        /* first the binned build, so that the tree the rays below use is the last one built (the default) */
        if (timed_native_build(&a, &g, &bcfg, &P->accel, m0, &tb1[r], &err) != HZ_OK)
            return hz_cli_report(&err);
        binned_sah = a->info.sah_cost;
        if (timed_native_build(&a, &g, NULL, &P->accel, m0, &tn1[r], &err) != HZ_OK)
            return hz_cli_report(&err);
        const hz_accel_info_t one = a->info;
        if (timed_native_build(&a, &g, &pcfg, &P->accel, m0, &tnn[r], &err) != HZ_OK)
            return hz_cli_report(&err);
        if (one.ref_count != a->info.ref_count || one.node_count != a->info.node_count ||
            one.sah_cost != a->info.sah_cost) {
            hz_cli_error("bench: %s: the %d-thread native build differs from the 1-thread one", name, nthr);
            return hz_status_exit_code(HZ_E_INTERNAL);
        }
        native_bytes = a->info.bytes;
        for (int q = 0; q < 2; q++)
            for (int one_thr = 0; one_thr < 2; one_thr++) {
                te[q][one_thr ? 0 : 1][r] = 0.0;
#if defined(HZ_HAVE_EMBREE)
                hz_accel_t *e;
                hz_accel_config_t ecfg;
                hz_accel_config_default(&ecfg);
                ecfg.quality = q ? 2 : 1;
                hz_arena_mark_t m1 = hz_arena_mark(&P->accel);
                char cfgs[256];
                snprintf(cfgs, sizeof cfgs, "%s%sthreads=%d", o->embree_config, *o->embree_config ? "," : "",
                         one_thr ? 1 : nthr);
                const int64_t t0 = hz_clock_ns();
                if (hz_accel_build_embree(&e, &g, &ecfg, cfgs, &P->accel, &err) != HZ_OK)
                    return hz_cli_report(&err);
                te[q][one_thr ? 0 : 1][r] = (double)(hz_clock_ns() - t0) * 1e-9;
                if (!q)
                    embree_bytes = e->info.bytes;
                hz_accel_release(e);
                hz_arena_reset(&P->accel, m1);
#endif
            }
    }
    double bn1, bnn, bb1, be[2][2], dummy1, dummy2;
    stats(tn1, build_rounds, &bn1, &dummy1, &dummy2);
    stats(tb1, build_rounds, &bb1, &dummy1, &dummy2);
    stats(tnn, build_rounds, &bnn, &dummy1, &dummy2);
    for (int q = 0; q < 2; q++)
        for (int t = 0; t < 2; t++)
            stats(te[q][t], build_rounds, &be[q][t], &dummy1, &dummy2);
    sum->build[0] = be[0][0] > 0.0 ? bn1 / be[0][0] : 0.0; /* vs medium, 1 thread */
    sum->build[1] = be[1][1] > 0.0 ? bnn / be[1][1] : 0.0; /* vs high, N threads */
    sum->build[2] = be[0][0] > 0.0 ? bb1 / be[0][0] : 0.0; /* binned vs medium, 1 thread */
    hz_accel_t *e = NULL, *ea = NULL; /* Embree at its default ISA (or --embree-config), and at isa=avx2 */
#if defined(HZ_HAVE_EMBREE)
    if (hz_accel_build_embree(&e, &g, NULL, o->embree_config, &P->accel, &err) != HZ_OK ||
        hz_accel_build_embree(&ea, &g, NULL, "isa=avx2", &P->accel, &err) != HZ_OK)
        return hz_cli_report(&err);
#endif
    printf("\n%s: %u triangles, %u refs (%u spatial splits), SAH %.2f; bytes/triangle native %.1f, embree %.1f\n",
           name, g.tri_count, a->info.ref_count, a->info.spatial_splits, (double)a->info.sah_cost,
           (double)native_bytes / g.tri_count, (double)embree_bytes / g.tri_count);
    printf("build    1 thread: native %.3f s, embree medium %.3f s, high %.3f s; %d threads: native %.3f s, embree "
           "medium %.3f s, high %.3f s; native/medium 1 thread %.2f, native/high %d threads %.2f\n", bn1, be[0][0],
           be[1][0], nthr, bnn, be[0][1], be[1][1], sum->build[0], nthr, sum->build[1]);
    printf("build    native binned SAH (no spatial splits) 1 thread %.3f s, SAH %.2f; over embree medium 1 thread %.2f\n",
           bb1, (double)binned_sah, sum->build[2]);
    if (csv) {
        static const char *qn[2] = { "medium", "high" };
        fprintf(csv, "%s,%u,build,1,native,%.4f,,,s\n", name, g.tri_count, bn1);
        fprintf(csv, "%s,%u,build,%d,native,%.4f,,,s\n", name, g.tri_count, nthr, bnn);
        fprintf(csv, "%s,%u,build,1,native binned,%.4f,,,s\n", name, g.tri_count, bb1);
        for (int q = 0; q < 2; q++) {
            fprintf(csv, "%s,%u,build,1,embree %s,%.4f,,,s\n", name, g.tri_count, qn[q], be[q][0]);
            fprintf(csv, "%s,%u,build,%d,embree %s,%.4f,,,s\n", name, g.tri_count, nthr, qn[q], be[q][1]);
        }
        if (be[0][0] > 0.0 && be[1][1] > 0.0) {
            fprintf(csv, "%s,%u,build,1,ratio native/embree medium,%.3f,,,time ratio\n", name, g.tri_count,
                    sum->build[0]);
            fprintf(csv, "%s,%u,build,%d,ratio native/embree high,%.3f,,,time ratio\n", name, g.tri_count, nthr,
                    sum->build[1]);
            fprintf(csv, "%s,%u,build,1,ratio native binned/embree medium,%.3f,,,time ratio\n", name, g.tri_count,
                    sum->build[2]);
        }
        fprintf(csv, "%s,%u,memory,,native,%.2f,,,bytes/triangle\n", name, g.tri_count,
                (double)native_bytes / g.tri_count);
        fprintf(csv, "%s,%u,memory,,embree,%.2f,,,bytes/triangle\n", name, g.tri_count,
                (double)embree_bytes / g.tri_count);
    }

    rayset_t sets[K_COUNT];
    const uint32_t np = o->width * o->height;
    for (int k = 0; k < K_COUNT; k++)
        if (!alloc_set(&sets[k], np + 8)) {
            hz_cli_error("bench: out of memory for %u rays", np);
            return hz_status_exit_code(HZ_E_NO_MEMORY);
        }
    hz_vec3_t light;
    make_rays(&sc, a, o->width, o->height, sets, &light);

    /* agreement of native and Embree on 10^5 camera rays (every tenth primary ray) + 10^5 random rays */
    if (e) {
        const uint32_t na = 200000;
        hz_rng_t rng;
        hz_rng_seed(&rng, 77, 7);
        uint32_t hm = 0, pt = 0, both = 0;
        for (uint32_t i = 0; i < na; i++) {
            hz_rayhit_t x;
            if (i < na / 2) {
                x = sets[K_PRIMARY].aos[(uint64_t)i * sets[K_PRIMARY].n / (na / 2)];
            } else {
                hz_vec3_t o, d;
                float c[3];
                for (int k = 0; k < 3; k++)
                    c[k] = sc.header->bounds_min[k] + (sc.header->bounds_max[k] - sc.header->bounds_min[k]) *
                                                          hz_u32_to_unit(hz_rng_u32(&rng));
                o = hz_v3(c[0], c[1], c[2]);
                d = hz_v3(hz_u32_to_unit(hz_rng_u32(&rng)) - 0.5f, hz_u32_to_unit(hz_rng_u32(&rng)) - 0.5f,
                          hz_u32_to_unit(hz_rng_u32(&rng)) - 0.5f);
                set_ray(&x, o, d, INFINITY, i);
            }
            hz_rayhit_t y = x;
            hz_accel_intersect1(a, NULL, &x);
            hz_accel_intersect1(e, NULL, &y);
            bool hx = x.hit.geom_id == 0, hy = y.hit.geom_id == 0;
            if (hx != hy) {
                hm++;
            } else if (hx) {
                both++;
                if (x.hit.prim_id != y.hit.prim_id &&
                    fabsf(x.ray.tfar - y.ray.tfar) > 1e-5f * fmaxf(fabsf(x.ray.tfar), fabsf(y.ray.tfar)))
                    pt++;
            }
        }
        printf("agreement native/embree on %u camera + %u random rays: hit/miss %.4f%%, triangle or t (1e-5) on "
               "%.4f%% of %u common hits\n",
               na / 2, na / 2, 100.0 * (na - hm) / na, both ? 100.0 * (both - pt) / both : 100.0, both);
        if (csv) {
            fprintf(csv, "%s,%u,agreement,,hit/miss,%.5f,,,%%\n", name, g.tri_count, 100.0 * (na - hm) / na);
            fprintf(csv, "%s,%u,agreement,,triangle or t,%.5f,,,%%\n", name, g.tri_count,
                    both ? 100.0 * (both - pt) / both : 100.0);
        }
    }

    result_t res[K_COUNT][M_COUNT];
    memset(res, 0, sizeof res);
    uint32_t *hits[M_COUNT], *sums[M_COUNT];
    const uint32_t max_items = (np + CHUNK - 1) / CHUNK;
    for (int m = 0; m < M_COUNT; m++) {
        hits[m] = calloc(max_items, sizeof(uint32_t));
        sums[m] = calloc(max_items, sizeof(uint32_t));
    }
    int bad = 0;
    for (int r = 0; r < o->rounds; r++)
        for (int k = 0; k < K_COUNT; k++)
            for (int m = 0; m < M_COUNT; m++) {
                if (m >= M_FIRST_EMBREE && !e)
                    continue;
                const char *only = getenv("HZ_BENCH_ONLY"); /* profiling aid: "kind:method[,kind:method...]" */
                if (only && !only_has(only, kind_name[k], method_name[m]))
                    continue;
                hz_accel_stats_t st;
                memset(&st, 0, sizeof st);
                job_t j = { r == 0 && getenv("HZ_BENCH_STATS") ? &st : NULL, m >= M_A1 ? ea : m >= M_FIRST_EMBREE ? e : a, (method_t)m,
                            (kind_t)k, &sets[k], m == M_SCALAR ? SCALAR_STRIDE : 1, hits[m], sums[m] };
                const uint32_t items = (sets[k].n + CHUNK - 1) / CHUNK;
                for (int t = 0; t < 2; t++) {
                    res[k][m].mr[t][r] = measure(&j, items, t == 1);
                    j.stats = NULL;
                }
                if (st.rays)
                    printf("  stats %s %s: %.2f nodes, %.2f triangle tests per ray\n", kind_name[k], method_name[m],
                           (double)st.nodes / (double)st.rays, (double)st.tris / (double)st.rays);
                res[k][m].ran = true;
                if (r > 0 || m != M_FIRST_EMBREE || getenv("HZ_BENCH_ONLY"))
                    continue;
                /* first round, set done: every native method agrees exactly with SIMD single rays */
                for (int q = M_SCALAR; q < M_FIRST_EMBREE; q++)
                    for (uint32_t it = 0; it < items; it += q == M_SCALAR ? SCALAR_STRIDE : 1)
                        if (hits[q][it] != hits[M_SINGLE][it] || sums[q][it] != sums[M_SINGLE][it]) {
                            if (bad++ < 3) {
                                fprintf(stderr, "bench: %s %s: %s disagrees with simd-1 on rays %u..%u\n", name,
                                        kind_name[k], method_name[q], it * CHUNK, it * CHUNK + CHUNK - 1);
                                if (getenv("HZ_BENCH_DEBUG") && k == K_SHADOW && (q == M_TILE || q == M_TILE_L)) {
                                    /* the tile's occlusion lane by lane against single rays */
                                    const uint32_t tp = q == M_TILE ? TILE_SMALL : TILE_LARGE;
                                    for (uint32_t p = it * CHUNK / 8; p < (it + 1) * CHUNK / 8 && p < sets[k].packets;
                                         p += tp) {
                                        hz_ray8_t rr[TILE_LARGE];
                                        int32_t vv[8 * TILE_LARGE];
                                        const uint32_t np = sets[k].packets - p < tp ? sets[k].packets - p : tp;
                                        hz_accel_ctx_t c1;
                                        hz_accel_ctx_init(&c1);
                                        c1.flags = HZ_ACCEL_COHERENT;
                                        for (uint32_t l = 0; l < 8 * np; l++)
                                            vv[l] = p * 8 + l < sets[k].n ? -1 : 0;
                                        for (uint32_t q2 = 0; q2 < np; q2++)
                                            rr[q2] = sets[k].soa[p + q2].ray;
                                        hz_accel_occluded8n(vv, a, &c1, rr, np);
                                        for (uint32_t l = 0; l < 8 * np && p * 8 + l < sets[k].n; l++) {
                                            hz_ray_t r1 = sets[k].aos[p * 8 + l].ray;
                                            hz_accel_occluded1(a, NULL, &r1);
                                            if ((r1.tfar < 0.0f) != (rr[l / 8].tfar[l % 8] < 0.0f))
                                                fprintf(stderr, "  ray %u (packet %u lane %u of the tile at %u) org %a %a %a "
                                                        "dir %a %a %a tfar %a: single %d, tile %d\n", p * 8 + l,
                                                        l / 8, l % 8, p, r1.org_x, r1.org_y, r1.org_z, r1.dir_x,
                                                        r1.dir_y, r1.dir_z, sets[k].aos[p * 8 + l].ray.tfar,
                                                        r1.tfar < 0.0f, rr[l / 8].tfar[l % 8] < 0.0f);
                                        }
                                    }
                                }
                                if (getenv("HZ_BENCH_DEBUG"))
                                    for (uint32_t i = it * CHUNK; i < (it + 1) * CHUNK && i < sets[k].n; i++) {
                                        hz_rayhit_t x = sets[k].aos[i], y = sets[k].aos[i];
                                        hz_accel_ctx_t c1, c2;
                                        hz_accel_ctx_init(&c1), hz_accel_ctx_init(&c2);
                                        c1.kernel = HZ_ACCEL_KERNEL_SCALAR, c2.kernel = HZ_ACCEL_KERNEL_SIMD_SINGLE;
                                        hz_accel_intersect1(a, &c1, &x);
                                        hz_accel_intersect1(a, &c2, &y);
                                        if (memcmp(&x, &y, sizeof x))
                                            fprintf(stderr, "  ray %u org %a %a %a dir %a %a %a: scalar %u t %.9g, "
                                                    "simd %u t %.9g\n", i, x.ray.org_x, x.ray.org_y, x.ray.org_z,
                                                    x.ray.dir_x, x.ray.dir_y, x.ray.dir_z, x.hit.prim_id,
                                                    (double)x.ray.tfar, y.hit.prim_id, (double)y.ray.tfar);
                                    }
                            }
                        }
            }
    printf("%-8s %3s", "rays", "thr");
    for (int m = 0; m < M_COUNT; m++)
        printf(" %9s", method_name[m]);
    printf("  vs avx2  vs any  (Mrays/s, median of %d; %u primary, %u shadow, %u diffuse rays)\n", o->rounds,
           sets[K_PRIMARY].n, sets[K_SHADOW].n, sets[K_DIFFUSE].n);
    const method_t native_simd[] = { M_SINGLE, M_AUTO8, M_TILE, M_TILE_L };
    const method_t embree_avx2[] = { M_A1, M_A8, M_A8C }, embree_any[] = { M_E1, M_E8, M_E8C, M_A1, M_A8, M_A8C };
    for (int k = 0; k < K_COUNT; k++)
        for (int t = 0; t < 2; t++) {
            printf("%-8s %3d", kind_name[k], t ? hz_threads_count() : 1);
            for (int m = 0; m < M_COUNT; m++) {
                result_t *q = &res[k][m];
                if (!q->ran) {
                    printf(" %9s", "-");
                    continue;
                }
                stats(q->mr[t], o->rounds, &q->med[t], &q->lo[t], &q->hi[t]);
                printf(" %9.2f", q->med[t]);
                if (csv)
                    fprintf(csv, "%s,%u,%s,%d,%s,%.3f,%.3f,%.3f,Mrays/s\n", name, g.tri_count, kind_name[k],
                            t ? hz_threads_count() : 1, method_csv[m], q->med[t], q->lo[t], q->hi[t]);
            }
            /* the goal's ratio: best native SIMD over Embree's best at the native ISA; also over its best at all */
            const double nb = best_of(res[k], t, native_simd, (int)HZ_ARRAY_LEN(native_simd));
            const double ea2 = best_of(res[k], t, embree_avx2, (int)HZ_ARRAY_LEN(embree_avx2));
            const double eany = best_of(res[k], t, embree_any, (int)HZ_ARRAY_LEN(embree_any));
            sum->ratio[k][t] = ea2 > 0.0 ? nb / ea2 : 0.0;
            sum->ratio_any[k][t] = eany > 0.0 ? nb / eany : 0.0;
            printf("  %7.2f %7.2f\n", sum->ratio[k][t], sum->ratio_any[k][t]);
            if (csv && ea2 > 0.0) {
                fprintf(csv, "%s,%u,%s,%d,ratio native/embree avx2,%.3f,,,best native simd / best embree isa=avx2\n",
                        name, g.tri_count, kind_name[k], t ? hz_threads_count() : 1, sum->ratio[k][t]);
                fprintf(csv, "%s,%u,%s,%d,ratio native/embree any,%.3f,,,best native simd / best embree\n", name,
                        g.tri_count, kind_name[k], t ? hz_threads_count() : 1, sum->ratio_any[k][t]);
            }
        }
    (void)light;
    for (int m = 0; m < M_COUNT; m++) {
        free(hits[m]);
        free(sums[m]);
    }
    for (int k = 0; k < K_COUNT; k++)
        free_set(&sets[k]);
    hz_accel_release(ea);
    hz_accel_release(e);
    if (bad) {
        hz_cli_error("bench: %s: native kernels disagree (%d chunks)", name, bad);
        return hz_status_exit_code(HZ_E_INTERNAL);
    }
    return 0;
}

static void scene_list(hz_bench_accel_opts_t *o)
{
    static const char *const defaults[] = { "conference", "sponza", "lost-empire", "furball",
                                            "dragon-res4", "dragon-res3", "dragon-res2", "dragon" };
    hz_bench_scene_list(&o->scenes_dir, o->scenes, &o->scene_count, defaults, (int)HZ_ARRAY_LEN(defaults));
}

int hz_bench_accel(const hz_bench_accel_opts_t *opts)
{
    hz_bench_accel_opts_t o = *opts;
    scene_list(&o);
    if (o.rounds <= 0)
        o.rounds = 5;
    if (o.rounds > MAX_ROUNDS)
        o.rounds = MAX_ROUNDS;
    if (!o.width || !o.height)
        o.width = o.height = 1024;
    if (!o.embree_config)
        o.embree_config = "";
    /* Every scene is there before anything is measured: a missing one is named, not found half-way. */
    int missing = 0;
    for (int i = 0; i < o.scene_count; i++)
        missing += !hz_bench_scene_present(o.scenes_dir, o.scenes[i], "");
    if (missing) {
        hz_cli_error("bench: %d of %d scenes missing (`make bench` bakes them; by hand: `make scenes`, or pick "
                     "others with --scene NAME)", missing, o.scene_count);
        return hz_status_exit_code(HZ_E_IO);
    }
    hz_error_t err;
    if (hz_threads_start(o.threads, &err) != HZ_OK)
        return hz_cli_report(&err);
    printf("\naccel: native (%s) vs embree%s%s, %d threads; %ux%u primary rays\n",
#if defined(HZ_SIMD_AVX2)
           "avx2, 8-wide",
#elif defined(HZ_SIMD_NEON)
           "neon, 4-wide",
#else
           "scalar",
#endif
#if defined(HZ_HAVE_EMBREE)
           *o.embree_config ? " with device config " : "", o.embree_config,
#else
           " (not built in)", "",
#endif
           hz_threads_count(), o.width, o.height);
    hz_out_t out;
    FILE *csv = NULL;
    if (o.csv_path) {
        if (hz_out_open(&out, o.csv_path, &err) != HZ_OK)
            return hz_cli_report(&err);
        csv = out.f;
        fprintf(csv, "scene,triangles,what,threads,method,value,min,max,unit\n");
    }
    summary_t sums[HZ_BENCH_MAX_SCENES];
    int status = 0, done = 0;
    for (int i = 0; i < o.scene_count && status == 0; i++) {
        status = bench_scene(&o, o.scenes[i], csv, &sums[i]);
        if (status == 0)
            done++;
    }
    for (int table = 0; done && table < 2; table++) {
        if (!table)
            printf("\nnative/embree at equal ISA (best native SIMD over Embree's best with isa=avx2, Mrays/s; goals "
                   "primary >= 1.5, shadow >= 1.2, diffuse >= 1.0)\nbuild: time, native on 1 thread over Embree "
                   "medium on 1 thread, native on %d over Embree high (spatial splits) on %d; goal <= 2; binned-1: the\n"
                   "native binned SAH build (no spatial splits) on 1 thread over Embree medium on 1 thread\n",
                   hz_threads_count(), hz_threads_count());
        else
            printf("\nnative/embree at any ISA (Embree's best at its default ISA or isa=avx2)\n");
        printf("%-14s %9s", "scene", "tris");
        for (int k = 0; k < K_COUNT; k++)
            printf(" %9s-1 %9s-%d", kind_name[k], kind_name[k], hz_threads_count());
        if (!table)
            printf(" %9s-1 %9s-%d %8s-1", "build", "build", hz_threads_count(), "binned");
        printf("\n");
        for (int i = 0; i < done; i++) {
            printf("%-14s %9u", sums[i].name, sums[i].tris);
            for (int k = 0; k < K_COUNT; k++)
                for (int t = 0; t < 2; t++)
                    printf(" %11.2f", table ? sums[i].ratio_any[k][t] : sums[i].ratio[k][t]);
            if (!table)
                printf(" %11.2f %11.2f %10.2f", sums[i].build[0], sums[i].build[1], sums[i].build[2]);
            printf("\n");
        }
    }
    hz_threads_stop();
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
    (void)ctx;
    hz_bench_fit_accel(fs, NULL, 0, "native BVH");
}

void hz_bench_accel_fit(const hz_bench_accel_opts_t *opts, hz_bench_fit_t *fit)
{
    hz_bench_accel_opts_t o = *opts;
    scene_list(&o);
    hz_bench_fit_named(fit, "accel", o.scenes, o.scene_count, fit_scene, NULL);
}
