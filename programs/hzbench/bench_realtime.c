/* hzbench's real-time group (see bench_realtime.h). */
#include "bench_realtime.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accel_backend.h"
#include "bench_common.h"
#include "bench_fit.h"
#include "clock.h"
#include "hz/render.h"
#include "render_run.h"
#include "threads.h"

/* ---- the recording wrapper ---- */

/* One traced packet as the renderer gave it, widened to 8 lanes (lanes off in `valid` bits). */
enum { R_OX, R_OY, R_OZ, R_DX, R_DY, R_DZ, R_TN, R_TF, R_TM, R_FIELDS };
typedef struct rec_packet {
    float f[R_FIELDS][8];
    uint8_t valid, occluded, coherent;
} rec_packet_t;

#define REC_MAX_PACKETS (1u << 18) /* 256k packets, 2M rays: a 640x360 TAA frame traces about 100k packets */

static struct {
    const hz_accel_t *real;
    int64_t accel_ns;      /* summed over threads (atomic) */
    int timing;            /* the wrapper reads the clock around each call (parts passes only) */
    int recording;
    rec_packet_t *packets; /* REC_MAX_PACKETS, allocated by the group */
    uint32_t count;        /* atomic */
    uint32_t dropped;      /* atomic: packets beyond REC_MAX_PACKETS */
} g_rec;

static void record(const int32_t *valid, int lanes, const float *ox, const float *oy, const float *oz,
                   const float *dx, const float *dy, const float *dz, const float *tn, const float *tf,
                   const float *tm, bool occluded, const hz_accel_ctx_t *ctx)
{
    uint32_t k = __atomic_fetch_add(&g_rec.count, 1u, __ATOMIC_RELAXED);
    if (k >= REC_MAX_PACKETS) {
        __atomic_fetch_add(&g_rec.dropped, 1u, __ATOMIC_RELAXED);
        return;
    }
    rec_packet_t *p = &g_rec.packets[k];
    memset(p, 0, sizeof *p);
    const float *src[R_FIELDS] = { ox, oy, oz, dx, dy, dz, tn, tf, tm };
    for (int i = 0; i < lanes; i++) {
        if (!valid || valid[i])
            p->valid |= (uint8_t)(1u << i);
        for (int f = 0; f < R_FIELDS; f++)
            p->f[f][i] = src[f][i];
    }
    p->occluded = occluded;
    p->coherent = ctx && (ctx->flags & HZ_ACCEL_COHERENT);
}

#define REC_RAY(r, v, lanes, occ)                                                                                \
    do {                                                                                                           \
        if (g_rec.recording)                                                                                       \
            record(v, lanes, (r)->org_x, (r)->org_y, (r)->org_z, (r)->dir_x, (r)->dir_y, (r)->dir_z, (r)->tnear,   \
                   (r)->tfar, (r)->time, occ, c);                                              \
    } while (0)

#define TIMED(call)                                                                                                \
    do {                                                                                                           \
        if (!g_rec.timing) {                                                                                       \
            call;                                                                                                  \
            break;                                                                                                 \
        }                                                                                                          \
        int64_t t0_ = hz_clock_ns();                                                                               \
        call;                                                                                                      \
        __atomic_fetch_add(&g_rec.accel_ns, hz_clock_ns() - t0_, __ATOMIC_RELAXED);                                \
    } while (0)

static void w_i1(const hz_accel_t *a, hz_accel_ctx_t *c, hz_rayhit_t *rh)
{
    (void)a;
    const hz_ray_t *r = &rh->ray;
    if (g_rec.recording)
        record(NULL, 1, &r->org_x, &r->org_y, &r->org_z, &r->dir_x, &r->dir_y, &r->dir_z, &r->tnear, &r->tfar,
               &r->time, false, c);
    TIMED(g_rec.real->ops->intersect1(g_rec.real, c, rh));
}
static void w_o1(const hz_accel_t *a, hz_accel_ctx_t *c, hz_ray_t *r)
{
    (void)a;
    if (g_rec.recording)
        record(NULL, 1, &r->org_x, &r->org_y, &r->org_z, &r->dir_x, &r->dir_y, &r->dir_z, &r->tnear, &r->tfar,
               &r->time, true, c);
    TIMED(g_rec.real->ops->occluded1(g_rec.real, c, r));
}
static void w_i4(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_rayhit4_t *rh)
{
    (void)a;
    REC_RAY(&rh->ray, v, 4, false);
    TIMED(g_rec.real->ops->intersect4(v, g_rec.real, c, rh));
}
static void w_o4(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_ray4_t *r)
{
    (void)a;
    REC_RAY(r, v, 4, true);
    TIMED(g_rec.real->ops->occluded4(v, g_rec.real, c, r));
}
static void w_i8(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_rayhit8_t *rh)
{
    (void)a;
    REC_RAY(&rh->ray, v, 8, false);
    TIMED(g_rec.real->ops->intersect8(v, g_rec.real, c, rh));
}
static void w_o8(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_ray8_t *r)
{
    (void)a;
    REC_RAY(r, v, 8, true);
    TIMED(g_rec.real->ops->occluded8(v, g_rec.real, c, r));
}
static hz_status_t w_refit(hz_accel_t *a, hz_error_t *err)
{
    (void)a;
    return g_rec.real->ops->refit((hz_accel_t *)g_rec.real, err);
}
/* Tiles: recorded packet by packet (the Embree replay traces them as 8-ray packets), timed as one call. */
static void w_i8n(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_rayhit8_t *rh, uint32_t n)
{
    (void)a;
    for (uint32_t p = 0; p < n; p++)
        REC_RAY(&rh[p].ray, v + 8u * p, 8, false);
    TIMED(hz_accel_intersect8n(v, g_rec.real, c, rh, n));
}
static void w_o8n(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_ray8_t *r, uint32_t n)
{
    (void)a;
    for (uint32_t p = 0; p < n; p++)
        REC_RAY(&r[p], v + 8u * p, 8, true);
    TIMED(hz_accel_occluded8n(v, g_rec.real, c, r, n));
}
static void w_i4n(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_rayhit4_t *rh, uint32_t n)
{
    (void)a;
    for (uint32_t p = 0; p < n; p++)
        REC_RAY(&rh[p].ray, v + 4u * p, 4, false);
    TIMED(hz_accel_intersect4n(v, g_rec.real, c, rh, n));
}
static void w_o4n(const int32_t *v, const hz_accel_t *a, hz_accel_ctx_t *c, hz_ray4_t *r, uint32_t n)
{
    (void)a;
    for (uint32_t p = 0; p < n; p++)
        REC_RAY(&r[p], v + 4u * p, 4, true);
    TIMED(hz_accel_occluded4n(v, g_rec.real, c, r, n));
}
static const hz_accel_ops_t wrap_ops = { w_i1, w_o1, w_i4, w_o4, w_i8, w_o8, w_refit, NULL, w_i8n, w_o8n, w_i4n, w_o4n };

/* ---- replay through Embree ---- */

#define REPLAY_CHUNK 64u /* packets per work item */

typedef struct replay {
    const hz_accel_t *accel;
    uint32_t count;
} replay_t;

static void replay_item(void *user, uint32_t item, int thread)
{
    (void)thread;
    const replay_t *rp = user;
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    uint32_t end = (item + 1u) * REPLAY_CHUNK < rp->count ? (item + 1u) * REPLAY_CHUNK : rp->count;
    for (uint32_t k = item * REPLAY_CHUNK; k < end; k++) {
        const rec_packet_t *p = &g_rec.packets[k];
        ctx.flags = p->coherent ? HZ_ACCEL_COHERENT : 0u;
        int32_t valid[8] HZ_ALIGNED(32);
        hz_rayhit8_t rh;
        memset(&rh, 0, sizeof rh);
        for (int i = 0; i < 8; i++) {
            valid[i] = (p->valid >> i) & 1u ? -1 : 0;
            rh.ray.org_x[i] = p->f[R_OX][i], rh.ray.org_y[i] = p->f[R_OY][i], rh.ray.org_z[i] = p->f[R_OZ][i];
            rh.ray.dir_x[i] = p->f[R_DX][i], rh.ray.dir_y[i] = p->f[R_DY][i], rh.ray.dir_z[i] = p->f[R_DZ][i];
            rh.ray.tnear[i] = p->f[R_TN][i], rh.ray.tfar[i] = p->f[R_TF][i], rh.ray.time[i] = p->f[R_TM][i];
            rh.ray.mask[i] = 0xffffffffu;
            rh.hit.geom_id[i] = rh.hit.prim_id[i] = HZ_ACCEL_INVALID_ID;
        }
        if (p->occluded)
            hz_accel_occluded8(valid, rp->accel, &ctx, &rh.ray);
        else
            hz_accel_intersect8(valid, rp->accel, &ctx, &rh);
    }
}

/* Median ms of `rounds` replays of the recorded packets through an Embree accel over the scene's current pose;
 * NaN where this build has no Embree. */
static hz_status_t embree_replay(hz_bench_scene_t *bs, int rounds, double *ms, hz_error_t *err)
{
    *ms = NAN;
    hz_arena_mark_t mark = hz_arena_mark(&bs->pools->accel);
    hz_accel_geom_t geom;
    hz_accel_t *e = NULL;
    hz_status_t s = hz_accel_geom_from_scene(&geom, &bs->scene, &bs->pools->accel, err);
    if (s == HZ_OK)
        s = hz_accel_backend_build(HZ_ACCEL_EMBREE, &e, &geom, &bs->pools->accel, err);
    if (s == HZ_E_UNSUPPORTED) {
        hz_arena_reset(&bs->pools->accel, mark);
        return HZ_OK;
    }
    if (s == HZ_OK) {
        uint32_t n = g_rec.count < REC_MAX_PACKETS ? g_rec.count : REC_MAX_PACKETS;
        replay_t rp = { e, n };
        double t[HZ_BENCH_REALTIME_MAX_ROUNDS];
        hz_threads_run(replay_item, &rp, (n + REPLAY_CHUNK - 1u) / REPLAY_CHUNK); /* warm the caches once */
        for (int r = 0; r < rounds; r++) {
            int64_t t0 = hz_clock_ns();
            hz_threads_run(replay_item, &rp, (n + REPLAY_CHUNK - 1u) / REPLAY_CHUNK);
            t[r] = (double)(hz_clock_ns() - t0) * 1e-6;
        }
        *ms = hz_bench_median(t, rounds);
    }
    hz_accel_release(e);
    hz_arena_reset(&bs->pools->accel, mark);
    return s;
}

/* ---- one scene ---- */

typedef struct mode_acc {
    double frame_ms[HZ_BENCH_REALTIME_MAX_ROUNDS * HZ_BENCH_REALTIME_MAX_FRAMES];
    size_t nframes;
    double part[4][HZ_BENCH_REALTIME_MAX_ROUNDS]; /* begin, trace, shade, resolve: per-frame means per round */
} mode_acc_t;

/* One pass over a round's frames. Without `parts` the wrapper reads no clock: the frame times (and the
 * begin / trace-pass / resolve split, three clock reads per frame) are the renderer's own. With `parts` the
 * wrapper times every accel call, which costs the frame two clock reads and an atomic add per packet, so that
 * pass gives only the accel share of the trace pass (`trace_ns`, per-frame mean). */
static hz_status_t run_pass(hz_renderer_t *r, const hz_bench_realtime_opts_t *o, bool rec, bool parts,
                            mode_acc_t *acc, double sum[4], hz_error_t *err)
{
    hz_render_reset_history(r);
    hz_time_ns_t t0 = hz_time_from_s(o->start);
    g_rec.timing = parts;
    for (uint32_t i = 0; i < o->warm + o->frames; i++) {
        bool timed = i >= o->warm;
        if (rec && i + 1 == o->warm + o->frames)
            g_rec.count = 0, g_rec.dropped = 0, g_rec.recording = 1;
        int64_t ns[3];
        g_rec.accel_ns = 0;
        int64_t a = hz_clock_ns();
        hz_status_t s = hz_render_run_frame_parts_ns(r, i, hz_time_of_frame(t0, i, o->hz), ns, err);
        int64_t frame = hz_clock_ns() - a;
        g_rec.recording = 0;
        if (s != HZ_OK) {
            g_rec.timing = 0;
            return s;
        }
        if (!timed)
            continue;
        if (parts) {
            double trace = (double)g_rec.accel_ns / (double)o->threads;
            sum[1] += trace < (double)ns[1] ? trace : (double)ns[1];
            continue;
        }
        acc->frame_ms[acc->nframes++] = (double)frame * 1e-6;
        sum[0] += (double)ns[0], sum[2] += (double)ns[1], sum[3] += (double)ns[2];
    }
    g_rec.timing = 0;
    return HZ_OK;
}

/* One round of one mode: the timed pass, then the parts pass (which records the packets of its last frame
 * when `rec`). shade = the timed pass's trace pass minus the parts pass's accel time. */
static hz_status_t run_round(hz_renderer_t *r, const hz_bench_realtime_opts_t *o, int round, bool rec,
                             mode_acc_t *acc, hz_error_t *err)
{
    double sum[4] = { 0, 0, 0, 0 };
    hz_status_t s = run_pass(r, o, false, false, acc, sum, err);
    if (s == HZ_OK)
        s = run_pass(r, o, rec, true, acc, sum, err);
    if (s != HZ_OK)
        return s;
    if (sum[1] > sum[2])
        sum[1] = sum[2];
    sum[2] -= sum[1];
    for (int k = 0; k < 4; k++)
        acc->part[k][round] = sum[k] / o->frames * 1e-6;
    return HZ_OK;
}

static const char *const scenes[][2] = { { "builtin", NULL }, { "sponza", "sponza.hzb" },
                                         { "conference", "conference.hzb" } };

/* m 0: tdense; 1: TAA, or tdense with the scalar shading twin. */
static void opts_for(const hz_bench_realtime_opts_t *o, int m, hz_render_opts_t *ro)
{
    hz_render_opts_default(ro);
    ro->width = o->width, ro->height = o->height;
    ro->mode = m == 1 && !o->compare_shading ? HZ_MODE_TAA : HZ_MODE_TDENSE;
    ro->scalar_shading = o->compare_shading && m == 1;
}

static hz_status_t bench_scene(const char *label, const char *path, const hz_bench_realtime_opts_t *o,
                               hz_bench_realtime_row_t *rows, hz_error_t *err)
{
    static mode_acc_t acc[2], twin[2], serial[2];
    hz_bench_scene_t bs;
    hz_status_t s = hz_bench_scene_open(&bs, path, err);
    hz_accel_t wrapped;
    hz_renderer_t *r[2] = { NULL, NULL };
    if (s == HZ_OK) {
        wrapped = *bs.accel;
        wrapped.ops = &wrap_ops;
        g_rec.real = bs.accel;
    }
    for (int m = 0; m < 2 && s == HZ_OK; m++) {
        hz_render_opts_t ro;
        opts_for(o, m, &ro);
        s = hz_render_create(&r[m], &bs.scene, &wrapped, &ro, &bs.pools->frame, bs.pools->thread,
                             (uint32_t)o->threads, err);
        acc[m].nframes = 0;
        twin[m].nframes = 0;
        serial[m].nframes = 0;
    }
    double embree_ms[2] = { NAN, NAN };
    hz_render_stats_t recorded[2];
    for (int round = 0; round < o->rounds && s == HZ_OK; round++) {
        for (int k = 0; k < 2 && s == HZ_OK; k++) {
            int m = (round + k) & 1;
            s = run_round(r[m], o, round, round == 0, &acc[m], err);
            if (s == HZ_OK) {
                double tmp[4] = { 0, 0, 0, 0 };
                hz_render_set_serial_passes(r[m], true);
                s = run_pass(r[m], o, false, false, &serial[m], tmp, err);
                hz_render_set_serial_passes(r[m], false);
            }
            if (s == HZ_OK && round == 0) {
                /* The recorded frame's pose is the scene's current one: replay against it now. */
                hz_render_frame_stats(r[m], &recorded[m], NULL);
                if (g_rec.dropped)
                    fprintf(stderr, "hzbench: realtime %s: %u packets beyond the recorder's %u left out\n", label,
                            g_rec.dropped, REC_MAX_PACKETS);
                s = embree_replay(&bs, o->rounds, &embree_ms[m], err);
                if (s == HZ_OK) {
                    double tw[4] = { 0, 0, 0, 0 };
                    hz_render_set_scalar_recon(r[m], true);
                    s = run_pass(r[m], o, false, false, &twin[m], tw, err);
                    hz_render_set_scalar_recon(r[m], false);
                    twin[m].part[3][0] = tw[3] / o->frames * 1e-6;
                }
            }
        }
        if (o->progress) {
            fprintf(stderr, "\r  realtime %-12s round %d/%d", label, round + 1, o->rounds);
            fflush(stderr);
        }
    }
    if (o->progress)
        fprintf(stderr, "\r%60s\r", "");
    for (int m = 0; m < 2 && s == HZ_OK; m++) {
        hz_bench_realtime_row_t *w = &rows[m];
        memset(w, 0, sizeof *w);
        snprintf(w->scene, sizeof w->scene, "%s", label);
        hz_render_opts_t ro;
        opts_for(o, m, &ro);
        w->mode = ro.scalar_shading ? "tdense-scalar" : hz_render_mode_name(ro.mode);
        w->threads = o->threads;
        w->p50_ms = hz_bench_quantile(acc[m].frame_ms, acc[m].nframes, 0.50);
        w->p99_ms = hz_bench_quantile(acc[m].frame_ms, acc[m].nframes, 0.99);
        w->begin_ms = hz_bench_median(acc[m].part[0], o->rounds);
        w->trace_ms = hz_bench_median(acc[m].part[1], o->rounds);
        w->shade_ms = hz_bench_median(acc[m].part[2], o->rounds);
        w->resolve_ms = hz_bench_median(acc[m].part[3], o->rounds);
        w->resolve_scalar_ms = twin[m].part[3][0];
        w->serial_p50_ms = hz_bench_quantile(serial[m].frame_ms, serial[m].nframes, 0.50);
        w->embree_trace_ms = embree_ms[m];
        w->overhead = w->p50_ms / embree_ms[m];
        w->primary = (double)recorded[m].primary_rays;
        w->shadow = (double)recorded[m].shadow_rays;
        w->secondary = (double)recorded[m].secondary_rays;
    }
    g_rec.real = NULL;
    hz_bench_scene_close(&bs);
    return s;
}

static hz_status_t scene_fn(const char *label, const char *path, void *ctx, int row, hz_error_t *err)
{
    const hz_bench_realtime_opts_t *o = ((void **)ctx)[0];
    hz_bench_realtime_row_t *rows = ((void **)ctx)[1];
    return bench_scene(label, path, o, &rows[2 * row], err);
}

int hz_bench_realtime(const hz_bench_realtime_opts_t *o, hz_bench_realtime_row_t *rows, int max_rows,
                      hz_error_t *err)
{
    if (o->rounds < 1 || o->rounds > HZ_BENCH_REALTIME_MAX_ROUNDS || o->frames < 1 ||
        o->frames > HZ_BENCH_REALTIME_MAX_FRAMES || o->threads < 1) {
        hz_error_set(err, HZ_E_INVALID_ARG, "realtime: rounds 1..%d, frames 1..%d, threads >= 1",
                     HZ_BENCH_REALTIME_MAX_ROUNDS, HZ_BENCH_REALTIME_MAX_FRAMES);
        return -1;
    }
    g_rec.packets = malloc(sizeof(rec_packet_t) * REC_MAX_PACKETS);
    if (!g_rec.packets) {
        hz_error_set(err, HZ_E_NO_MEMORY, "realtime: no memory for the packet recorder");
        return -1;
    }
    void *ctx[2] = { (void *)o, rows };
    int n = hz_bench_scenes("realtime", scenes, sizeof scenes / sizeof scenes[0], o->scenes_dir, o->threads,
                            scene_fn, ctx, max_rows / 2, err);
    free(g_rec.packets);
    g_rec.packets = NULL;
    return n < 0 ? n : 2 * n;
}

static void fit_scene(hz_bench_fit_scene_t *fs, const void *ctx)
{
    hz_render_opts_t ro[2];
    for (int m = 0; m < 2; m++)
        opts_for(ctx, m, &ro[m]);
    hz_bench_fit_accel(fs, NULL, 0, "native BVH");
    hz_bench_fit_render(fs, ro, 2, ((const hz_bench_realtime_opts_t *)ctx)->compare_shading
                                       ? "tdense + its scalar shading twin" : "tdense + taa");
}

void hz_bench_realtime_fit(const hz_bench_realtime_opts_t *o, hz_bench_fit_t *fit)
{
    hz_bench_fit_scenes(fit, "realtime", scenes, sizeof scenes / sizeof scenes[0], fit_scene, o);
}
