/* hzbench's motion-blur group (see bench_blur.h). */
#include "bench_blur.h"

#include <stdio.h>
#include <string.h>

#include "bench_fit.h"
#include "bench_util.h"
#include "blur_setup.h"
#include "clock.h"
#include "hz/render.h"
#include "pools.h"
#include "render_run.h"
#include "scenefile.h"

/* Mean displayed-frame time and its begin and trace parts over `frames` frames after `warm`, history reset
 * first (every round the same sequence); refits per timed frame. */
static hz_status_t run_frames(hz_renderer_t *r, const hz_bench_blur_opts_t *o, double out[4], hz_error_t *err)
{
    hz_render_reset_history(r);
    int64_t sum = 0, begin = 0, trace = 0;
    uint64_t refits = 0;
    for (uint32_t i = 0; i < o->warm + o->frames; i++) {
        int64_t a = hz_clock_ns(), ns[3];
        hz_status_t s = hz_render_run_frame_parts(r, i, o->start + (float)i / (float)o->hz, ns, err);
        if (s != HZ_OK)
            return s;
        if (i >= o->warm) {
            hz_render_stats_t last;
            hz_render_frame_stats(r, &last, NULL);
            sum += hz_clock_ns() - a, begin += ns[0], trace += ns[1], refits += last.refits;
        }
    }
    out[0] = (double)sum / o->frames * 1e-6;
    out[1] = (double)begin / o->frames * 1e-6;
    out[2] = (double)trace / o->frames * 1e-6;
    out[3] = (double)refits / o->frames;
    return HZ_OK;
}

static const char *const scenes[][2] = { { "builtin", NULL }, { "sponza-rotated", "sponza-rotated.hzb" },
                                         { "furball-sway", "furball-sway.hzb" } };

/* m 0: keys per cycle, 1: posed and refitted every subframe. */
static void opts_for(const hz_bench_blur_opts_t *o, int m, hz_render_opts_t *ro)
{
    hz_render_opts_default(ro);
    ro->width = o->width, ro->height = o->height;
    ro->mode = HZ_MODE_TDENSE;
    ro->shutter = o->shutter;
    ro->frame_hz = o->hz;
    ro->tdense_cycle_keys = m == 0;
}

static hz_status_t bench_scene(const char *label, const char *path, const hz_bench_blur_opts_t *o,
                               hz_bench_blur_row_t *row, hz_error_t *err)
{
    hz_pools_t *pools = hz_pools_get();
    hz_arena_mark_t ms = hz_arena_mark(&pools->scene), ma = hz_arena_mark(&pools->accel),
                    mf = hz_arena_mark(&pools->frame), mt[HZ_MAX_THREADS];
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        mt[t] = hz_arena_mark(&pools->thread[t]);
    hz_scene_t scene;
    hz_accel_t *accel = NULL;
    static hz_posekeys_t keys;
    hz_render_opts_t ro[2];
    for (int m = 0; m < 2; m++)
        opts_for(o, m, &ro[m]);
    hz_status_t s = hz_scenefile_open(path, pools, &scene, err);
    /* The keys for the cycle's interval (the longer one); the per-subframe renderer uses the same ones. */
    if (s == HZ_OK)
        s = hz_blur_build(&scene, &ro[0], HZ_ACCEL_NATIVE, o->blur, pools, &keys, &accel, err);
    ro[1].keys = ro[0].keys;
    hz_renderer_t *r[2] = { NULL, NULL };
    for (int m = 0; m < 2 && s == HZ_OK; m++)
        s = hz_render_create(&r[m], &scene, accel, &ro[m], &pools->frame, pools->thread, (uint32_t)o->threads, err);
    double fig[2][4][HZ_BENCH_BLUR_MAX_ROUNDS], ratio[HZ_BENCH_BLUR_MAX_ROUNDS];
    for (int round = 0; round < o->rounds && s == HZ_OK; round++) {
        for (int k = 0; k < 2 && s == HZ_OK; k++) {
            int m = (round + k) & 1;
            double f[4] = { 0, 0, 0, 0 };
            s = run_frames(r[m], o, f, err);
            for (int q = 0; q < 4; q++)
                fig[m][q][round] = f[q];
        }
        ratio[round] = fig[1][0][round] / fig[0][0][round];
        if (o->progress) {
            fprintf(stderr, "\r  blur %-14s round %d/%d", label, round + 1, o->rounds);
            fflush(stderr);
        }
    }
    if (o->progress)
        fprintf(stderr, "\r%60s\r", "");
    if (s == HZ_OK) {
        memset(row, 0, sizeof *row);
        snprintf(row->scene, sizeof row->scene, "%s", label);
        row->time_keys = ro[0].keys ? ro[0].keys->count : 0;
        for (int m = 0; m < 2; m++) {
            row->ms[m] = hz_bench_median(fig[m][0], o->rounds);
            row->begin_ms[m] = hz_bench_median(fig[m][1], o->rounds);
            row->trace_ms[m] = hz_bench_median(fig[m][2], o->rounds);
            row->refits[m] = hz_bench_median(fig[m][3], o->rounds);
        }
        row->ratio = hz_bench_median(ratio, o->rounds);
    }
    hz_accel_release(accel);
    hz_arena_reset(&pools->frame, mf);
    hz_arena_reset(&pools->accel, ma);
    hz_arena_reset(&pools->scene, ms);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        hz_arena_reset(&pools->thread[t], mt[t]);
    return s;
}

static hz_status_t scene_fn(const char *label, const char *path, void *ctx, int row, hz_error_t *err)
{
    const hz_bench_blur_opts_t *o = ((void **)ctx)[0];
    hz_bench_blur_row_t *rows = ((void **)ctx)[1];
    return bench_scene(label, path, o, &rows[row], err);
}

int hz_bench_blur(const hz_bench_blur_opts_t *o, hz_bench_blur_row_t *rows, int max_rows, hz_error_t *err)
{
    void *ctx[2] = { (void *)o, rows };
    return hz_bench_scenes("blur", scenes, sizeof scenes / sizeof scenes[0], o->scenes_dir, o->threads, scene_fn, ctx,
                           max_rows, err);
}

static void fit_scene(hz_bench_fit_scene_t *fs, const void *ctx)
{
    const hz_bench_blur_opts_t *o = ctx;
    hz_render_opts_t ro[2];
    for (int m = 0; m < 2; m++)
        opts_for(o, m, &ro[m]);
    uint32_t keys = hz_bench_fit_render(fs, ro, 2, "tdense per cycle + per subframe");
    hz_accel_config_t cfg;
    hz_accel_config_default(&cfg);
    cfg.blur = o->blur;
    hz_bench_fit_accel(fs, &cfg, HZ_FEATURE_MOTION ? keys : 0u, keys >= 2u ? "native motion BVH" : "native BVH");
}

void hz_bench_blur_fit(const hz_bench_blur_opts_t *o, hz_bench_fit_t *fit)
{
    hz_bench_fit_scenes(fit, "blur", scenes, sizeof scenes / sizeof scenes[0], fit_scene, o);
}
