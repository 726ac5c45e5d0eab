/* hzbench's transparency group (see bench_transp.h). */
#include "bench_transp.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench_fit.h"
#include "bench_scene.h"
#include "clock.h"
#include "hz/render.h"
#include "hz/scene.h"
#include "pools.h"
#include "render_run.h"
#include "threads.h"
#include "transp_opt.h"

const char *const hz_bench_transp_scenes[HZ_BENCH_TRANSP_SCENES][2] = { { "sponza-smoke", "sponza-smoke.hzb" },
                                                                        { "smoke-column", "smoke-column.hzb" } };

static const struct {
    hz_transp_t t;
    float x;
    bool rr_shadows;
} methods[HZ_BENCH_TRANSP_METHODS] = {
    { HZ_TRANSP_EXACT, 0.0f, false },   { HZ_TRANSP_RR, 0.0f, false },     { HZ_TRANSP_STD, 0.0f, false },
    { HZ_TRANSP_DTAA, 0.0f, false },    { HZ_TRANSP_HYBRID, 0.25f, false }, { HZ_TRANSP_HYBRID, 0.5f, false },
    { HZ_TRANSP_HYBRID, 0.75f, false }, { HZ_TRANSP_STD, 0.0f, true },
};

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Nearest-rank percentile of n sorted values. */
static double percentile(const double *sorted, uint32_t n, double p)
{
    uint32_t k = (uint32_t)(p * n + 0.999999);
    return sorted[k < 1 ? 0 : k > n ? n - 1 : k - 1];
}

/* ns per rejected layer of renderer r (see bench_transp.h); *share the share of candidates rejected. Every
 * blended triangle from both sides; -1 if a rejected candidate is kept when repeated (decisions after a frame
 * depend on nothing else). */
static double reject_cost(hz_renderer_t *r, const hz_scene_t *scene, double *share)
{
    enum { MAX_CAND = 1u << 16 };
    static uint32_t cand[MAX_CAND];
    static uint8_t side[MAX_CAND], keep[MAX_CAND];
    uint32_t n = 0;
    for (uint32_t t = 0; t < scene->triangle_count && n + 1 < MAX_CAND; t++)
        if (scene->materials[hz_scene_tri_material(scene, t)].alpha_mode == HZ_ALPHA_BLEND)
            for (uint8_t b = 0; b < 2; b++)
                cand[n] = t, side[n++] = b;
    *share = 0.0;
    if (n == 0)
        return 0.0;
    hz_render_dither_decide(r, cand, side, n, keep);
    uint32_t nr = 0;
    for (uint32_t i = 0; i < n; i++)
        if (!keep[i])
            cand[nr] = cand[i], side[nr++] = side[i];
    *share = (double)nr / n;
    if (nr == 0)
        return 0.0;
    double best = 0.0;
    for (int round = 0; round < 5; round++) {
        uint64_t calls = 0, kept = 0;
        int64_t a = hz_clock_ns(), b = a;
        while (b - a < 4000000) {
            kept += hz_render_dither_decide(r, cand, side, nr, NULL);
            calls += nr;
            b = hz_clock_ns();
        }
        if (kept != 0)
            return -1.0;
        double ns = (double)(b - a) / (double)calls;
        if (round == 0 || ns < best)
            best = ns;
    }
    return best;
}

static void opts_for(const hz_bench_transp_opts_t *o, int m, hz_render_opts_t *ro)
{
    hz_render_opts_default(ro);
    ro->width = o->width, ro->height = o->height;
    ro->mode = HZ_MODE_TAA;
    ro->transparency = methods[m].t, ro->hybrid_x = methods[m].x, ro->rr_shadows = methods[m].rr_shadows;
}

int hz_bench_transp(const hz_bench_transp_opts_t *o, hz_bench_transp_row_t rows[HZ_BENCH_TRANSP_METHODS],
                    hz_error_t *err)
{
    char path[4096];
    const char *const *entry = o->scene ? o->scene : hz_bench_transp_scenes[0];
    const char *name = entry[0];
    snprintf(path, sizeof path, "%s/%s", o->scenes_dir ? o->scenes_dir : ".", entry[1]);
    if (access(path, R_OK) != 0) {
        printf("transparency: skipped: %s missing (make scenes)\n", path);
        return 0;
    }
    uint32_t frames = o->frames < 1 ? 1 : o->frames > HZ_BENCH_TRANSP_MAX_FRAMES ? HZ_BENCH_TRANSP_MAX_FRAMES : o->frames;
    hz_bench_scene_t bs;
    hz_status_t s = hz_bench_scene_open(&bs, path, err);
    hz_pools_t *pools = bs.pools;
    bool threads = false;
    if (s == HZ_OK)
        threads = (s = hz_threads_start(o->threads, err)) == HZ_OK;
    const hz_scene_t *scene = &bs.scene;
    hz_renderer_t *r[HZ_BENCH_TRANSP_METHODS] = { NULL };
    for (int m = 0; m < HZ_BENCH_TRANSP_METHODS && s == HZ_OK; m++) {
        hz_render_opts_t ro;
        opts_for(o, m, &ro);
        s = hz_render_create(&r[m], &bs.scene, bs.accel, &ro, &pools->frame, pools->thread, (uint32_t)o->threads,
                             err);
    }
    static double best[HZ_BENCH_TRANSP_METHODS][HZ_BENCH_TRANSP_MAX_FRAMES];
    double rays[HZ_BENCH_TRANSP_METHODS] = { 0 };
    float duration = s == HZ_OK && scene->header->duration > 0.0f ? scene->header->duration : 1.0f;
    for (int round = 0; round < o->rounds && s == HZ_OK; round++) {
        for (uint32_t i = 0; i < frames && s == HZ_OK; i++) {
            float t = duration * (float)i / (float)frames;
            for (int k = 0; k < HZ_BENCH_TRANSP_METHODS && s == HZ_OK; k++) {
                int m = (int)((k + i + (uint32_t)round) % HZ_BENCH_TRANSP_METHODS);
                int64_t a = hz_clock_ns();
                s = hz_render_run_frame(r[m], i, t, err);
                double ms_frame = (double)(hz_clock_ns() - a) * 1e-6;
                if (round == 0 || ms_frame < best[m][i])
                    best[m][i] = ms_frame;
                if (round == 0) {
                    hz_render_stats_t last;
                    hz_render_frame_stats(r[m], &last, NULL);
                    rays[m] += (double)(last.primary_rays + last.shadow_rays + last.secondary_rays) / frames;
                }
            }
            if (o->progress) {
                fprintf(stderr, "\r  transparency %s round %d/%d frame %u/%u", name, round + 1, o->rounds, i + 1,
                        frames);
                fflush(stderr);
            }
        }
    }
    if (o->progress)
        fprintf(stderr, "\r%60s\r", "");
    int n = 0;
    if (s == HZ_OK) {
        for (int m = 0; m < HZ_BENCH_TRANSP_METHODS; m++) {
            hz_bench_transp_row_t *row = &rows[n++];
            memset(row, 0, sizeof *row);
            snprintf(row->scene, sizeof row->scene, "%s", name);
            hz_transp_format(row->method, sizeof row->method, methods[m].t, methods[m].x);
            if (methods[m].rr_shadows)
                strncat(row->method, "+rr-shadows", sizeof row->method - strlen(row->method) - 1);
            row->frames = frames;
            for (uint32_t i = 0; i < frames; i++)
                row->frame_ms[i] = best[m][i], row->t_s[i] = duration * (float)i / (float)frames;
            qsort(best[m], frames, sizeof(double), cmp_double);
            row->p50_ms = percentile(best[m], frames, 0.5);
            row->p99_ms = percentile(best[m], frames, 0.99);
            row->rays_per_frame = rays[m];
            row->reject_ns = methods[m].t == HZ_TRANSP_EXACT ? 0.0 : reject_cost(r[m], scene, &row->reject_share);
        }
    }
    hz_bench_scene_close(&bs);
    if (threads)
        hz_threads_stop();
    return s == HZ_OK ? n : -1;
}

hz_status_t hz_bench_transp_layers(const char *scene, hz_transp_t t, uint32_t width, uint32_t height, double *ns,
                                   double *share, hz_error_t *err)
{
    hz_bench_scene_t bs;
    hz_status_t s = hz_bench_scene_open(&bs, scene, err);
    bool threads = false;
    if (s == HZ_OK)
        threads = (s = hz_threads_start(1, err)) == HZ_OK;
    hz_renderer_t *r = NULL;
    if (s == HZ_OK) {
        hz_render_opts_t ro;
        hz_render_opts_default(&ro);
        ro.width = width, ro.height = height, ro.mode = HZ_MODE_TAA, ro.transparency = t;
        s = hz_render_create(&r, &bs.scene, bs.accel, &ro, &bs.pools->frame, bs.pools->thread, 1, err);
    }
    if (s == HZ_OK)
        s = hz_render_run_frame(r, 0, 0.0f, err);
    if (s == HZ_OK)
        *ns = reject_cost(r, &bs.scene, share);
    hz_bench_scene_close(&bs);
    if (threads)
        hz_threads_stop();
    return s;
}

static void fit_scene(hz_bench_fit_scene_t *fs, const void *ctx)
{
    hz_render_opts_t ro[HZ_BENCH_TRANSP_METHODS];
    for (int m = 0; m < HZ_BENCH_TRANSP_METHODS; m++)
        opts_for(ctx, m, &ro[m]);
    hz_bench_fit_accel(fs, NULL, 0, "native BVH");
    hz_bench_fit_render(fs, ro, HZ_BENCH_TRANSP_METHODS, "taa, every transparency method");
}

void hz_bench_transp_fit(const hz_bench_transp_opts_t *o, hz_bench_fit_t *fit)
{
    hz_bench_fit_scenes(fit, "transparency", hz_bench_transp_scenes, HZ_BENCH_TRANSP_SCENES, fit_scene, o);
}
