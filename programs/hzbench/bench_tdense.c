/* hzbench's temporally dense group (see bench_tdense.h). */
#include "bench_tdense.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "accel_backend.h"
#include "bench_common.h"
#include "bench_fit.h"
#include "clock.h"
#include "hz/render.h"
#include "pools.h"
#include "scenefile.h"
#include "render_run.h"
#include "threads.h"

/* Mean displayed-frame time (ms, begin_frame to end_frame) of `frames` frames from scene time t0 at `hz`, after
 * `warm` untimed frames, and its parts: part[0] begin_frame (animation, refit, camera), part[1] the trace pass,
 * part[2] the resolve pass (TAA or tdense composite). History restarts first, so every round sees the same
 * sequence. */
static hz_status_t run_frames(hz_renderer_t *r, uint32_t warm, uint32_t frames, float t0, uint32_t hz, double *ms,
                              double part[3], hz_error_t *err)
{
    hz_render_reset_history(r);
    int64_t sum = 0, parts[3] = { 0, 0, 0 };
    for (uint32_t i = 0; i < warm + frames; i++) {
        int64_t a = hz_clock_ns();
        int64_t ns[3];
        hz_status_t s = hz_render_run_frame_parts(r, i, t0 + (float)i / (float)hz, ns, err);
        if (s != HZ_OK)
            return s;
        if (i >= warm) {
            sum += hz_clock_ns() - a;
            for (int k = 0; k < 3; k++)
                parts[k] += ns[k];
        }
    }
    *ms = (double)sum / frames * 1e-6;
    for (int k = 0; k < 3; k++)
        part[k] = (double)parts[k] / frames * 1e-6;
    return HZ_OK;
}

static const char *const scenes[][2] = { { "builtin", NULL }, { "sponza", "sponza.hzb" },
                                         { "conference", "conference.hzb" } };

/* The renderer of mode m: 0 tdense, 1 TAA. */
static void opts_for(const hz_bench_tdense_opts_t *o, int m, hz_render_opts_t *ro)
{
    hz_render_opts_default(ro);
    ro->width = o->width, ro->height = o->height;
    ro->mode = m == 0 ? HZ_MODE_TDENSE : HZ_MODE_TAA;
}

/* One scene: both renderers from the same pools, rounds alternating which mode goes first. */
static hz_status_t bench_scene(const char *label, const char *path, const hz_bench_tdense_opts_t *o,
                               hz_bench_tdense_row_t *row, hz_error_t *err)
{
    hz_bench_scene_t bs;
    hz_status_t s = hz_bench_scene_open(&bs, path, err);
    hz_pools_t *pools = bs.pools;
    hz_renderer_t *r[2] = { NULL, NULL };
    for (int m = 0; m < 2 && s == HZ_OK; m++) {
        hz_render_opts_t ro;
        opts_for(o, m, &ro);
        s = hz_render_create(&r[m], &bs.scene, bs.accel, &ro, &pools->frame, pools->thread, (uint32_t)o->threads,
                             err);
    }
    double ms_mode[2][HZ_BENCH_TDENSE_MAX_ROUNDS], ratio[HZ_BENCH_TDENSE_MAX_ROUNDS];
    double parts[2][3][HZ_BENCH_TDENSE_MAX_ROUNDS];
    for (int round = 0; round < o->rounds && s == HZ_OK; round++) {
        for (int k = 0; k < 2 && s == HZ_OK; k++) {
            int m = (round + k) & 1;
            double part[3] = { 0, 0, 0 };
            s = run_frames(r[m], o->warm, o->frames, o->start, o->hz, &ms_mode[m][round], part, err);
            for (int q = 0; q < 3; q++)
                parts[m][q][round] = part[q];
        }
        ratio[round] = ms_mode[1][round] / ms_mode[0][round];
        if (o->progress) {
            fprintf(stderr, "\r  tdense %-12s round %d/%d", label, round + 1, o->rounds);
            fflush(stderr);
        }
    }
    if (o->progress)
        fprintf(stderr, "\r%60s\r", "");
    if (s == HZ_OK) {
        memset(row, 0, sizeof *row);
        snprintf(row->scene, sizeof row->scene, "%s", label);
        for (int m = 0; m < 2; m++)
            for (int q = 0; q < 3; q++)
                row->part_ms[m][q] = hz_bench_median(parts[m][q], o->rounds);
        row->tdense_ms = hz_bench_median(ms_mode[0], o->rounds);
        row->taa_ms = hz_bench_median(ms_mode[1], o->rounds);
        row->ratio = hz_bench_median(ratio, o->rounds);
        row->ratio_min = ratio[0], row->ratio_max = ratio[o->rounds - 1]; /* sorted by hz_bench_median() */
        hz_render_stats_t last;
        hz_render_frame_stats(r[0], &last, NULL);
        row->tdense_rays = (double)(last.primary_rays + last.shadow_rays + last.secondary_rays);
        hz_render_frame_stats(r[1], &last, NULL);
        row->taa_rays = (double)(last.primary_rays + last.shadow_rays + last.secondary_rays);
    }
    hz_bench_scene_close(&bs);
    return s;
}

static hz_status_t scene_fn(const char *label, const char *path, void *ctx, int row, hz_error_t *err)
{
    const hz_bench_tdense_opts_t *o = ((void **)ctx)[0];
    hz_bench_tdense_row_t *rows = ((void **)ctx)[1];
    return bench_scene(label, path, o, &rows[row], err);
}

int hz_bench_tdense(const hz_bench_tdense_opts_t *o, hz_bench_tdense_row_t *rows, int max_rows, hz_error_t *err)
{
    void *ctx[2] = { (void *)o, rows };
    return hz_bench_scenes("tdense", scenes, sizeof scenes / sizeof scenes[0], o->scenes_dir, o->threads, scene_fn,
                           ctx, max_rows, err);
}

static void fit_scene(hz_bench_fit_scene_t *fs, const void *ctx)
{
    hz_render_opts_t ro[2];
    for (int m = 0; m < 2; m++)
        opts_for(ctx, m, &ro[m]);
    hz_bench_fit_accel(fs, NULL, 0, "native BVH");
    hz_bench_fit_render(fs, ro, 2, "tdense + taa");
}

void hz_bench_tdense_fit(const hz_bench_tdense_opts_t *o, hz_bench_fit_t *fit)
{
    hz_bench_fit_scenes(fit, "tdense", scenes, sizeof scenes / sizeof scenes[0], fit_scene, o);
}
