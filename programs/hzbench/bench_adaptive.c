/* hzbench's adaptive supersampling group (see bench_adaptive.h). */
#include "bench_adaptive.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "accel_backend.h"
#include "bench_common.h"
#include "bench_fit.h"
#include "clock.h"
#include "fileio.h"
#include "hz/image.h"
#include "hz/render.h"
#include "pools.h"
#include "render_run.h"
#include "scenefile.h"
#include "threads.h"

#define METHODS (1 + HZ_BENCH_ADAPTIVE_TAUS)
static const float taus[HZ_BENCH_ADAPTIVE_TAUS] = { 0.3f, 0.6f, 1.0f };

/* One frame with each pass timed: ns[0..2] the first three passes, returns the whole frame. */
static hz_status_t frame(hz_renderer_t *r, uint64_t index, float t, int64_t *total, int64_t ns[3], hz_error_t *err)
{
    int64_t a = hz_clock_ns();
    hz_status_t s = hz_render_begin_frame(r, index, t, err);
    if (s != HZ_OK)
        return s;
    for (uint32_t p = 0; p < hz_render_pass_count(r); p++) {
        int64_t b = hz_clock_ns();
        hz_render_run_pass(r, p);
        if (p < 3)
            ns[p] = hz_clock_ns() - b;
    }
    hz_render_end_frame(r);
    *total = hz_clock_ns() - a;
    return HZ_OK;
}

/* PSNR of the 8-bit sRGB codes (what the display shows) against the reference's. */
static double psnr_srgb8(const hz_image_t *ref, const hz_image_t *img)
{
    double se = 0;
    size_t n = hz_image_pixels(ref) * 3;
    for (size_t i = 0; i < n; i++) {
        double d = (double)hz_srgb8_encode(ref->rgb[i]) - (double)hz_srgb8_encode(img->rgb[i]);
        se += d * d;
    }
    return se == 0 ? INFINITY : 10.0 * log10(255.0 * 255.0 * (double)n / se);
}

static const char *const scenes[][2] = { { "conference", "conference.hzb" }, { "sponza", "sponza.hzb" },
                                         { "CornellBox-Mirror", "CornellBox-Mirror.hzb" },
                                         { "lost-empire", "lost-empire.hzb" } };

static void ref_opts(const hz_bench_adaptive_opts_t *o, hz_render_opts_t *ro)
{
    hz_render_opts_default(ro);
    ro->width = o->width, ro->height = o->height, ro->spp = o->ref_spp, ro->seed = 0x5eed;
}

static void opts_for(int m, const hz_bench_adaptive_opts_t *o, hz_render_opts_t *ro)
{
    hz_render_opts_default(ro);
    ro->width = o->width, ro->height = o->height;
    if (m == 0) {
        ro->mode = HZ_MODE_FULL, ro->spp = 9;
    } else {
        ro->mode = HZ_MODE_ADAPTIVE;
        ro->adaptive.tau[HZ_TAU_COL] = ro->adaptive.tau[HZ_TAU_PTE] = ro->adaptive.tau[HZ_TAU_STE] = taus[m - 1];
    }
}

static hz_status_t bench_scene(const char *label, const char *path, const hz_bench_adaptive_opts_t *o,
                               hz_bench_adaptive_row_t *rows, hz_error_t *err)
{
    hz_bench_scene_t bs;
    hz_image_t ref = { o->width, o->height, NULL };
    hz_status_t s = hz_bench_scene_open(&bs, path, err);
    hz_pools_t *pools = bs.pools;
    /* The reference first, from the frame arena, given back before the methods' renderers. */
    if (s == HZ_OK) {
        ref.rgb = malloc(hz_image_pixels(&ref) * 3 * sizeof(float));
        if (!ref.rgb)
            s = hz_error_set(err, HZ_E_NO_MEMORY, "bench: no memory for the reference image");
    }
    if (s == HZ_OK) {
        hz_render_opts_t ro;
        ref_opts(o, &ro);
        hz_renderer_t *rr = NULL;
        s = hz_render_create(&rr, &bs.scene, bs.accel, &ro, &pools->frame, pools->thread, (uint32_t)o->threads, err);
        if (s == HZ_OK && o->progress)
            fprintf(stderr, "\r  adaptive %-18s reference %u spp", label, o->ref_spp);
        if (s == HZ_OK)
            s = hz_render_run_frame(rr, 0, o->t, err);
        if (s == HZ_OK)
            memcpy(ref.rgb, hz_render_output(rr)->rgb, hz_image_pixels(&ref) * 3 * sizeof(float));
        hz_bench_scene_reset_frames(&bs);
    }
    hz_renderer_t *r[METHODS] = { NULL };
    for (int m = 0; m < METHODS && s == HZ_OK; m++) {
        hz_render_opts_t ro;
        opts_for(m, o, &ro);
        s = hz_render_create(&r[m], &bs.scene, bs.accel, &ro, &pools->frame, pools->thread, (uint32_t)o->threads,
                             err);
    }
    double ms_m[METHODS][HZ_BENCH_ADAPTIVE_MAX_ROUNDS], parts[METHODS][3][HZ_BENCH_ADAPTIVE_MAX_ROUNDS];
    for (int round = 0; round < o->rounds && s == HZ_OK; round++) {
        for (int k = 0; k < METHODS && s == HZ_OK; k++) {
            int m = (round + k) % METHODS;
            int64_t sum = 0, psum[3] = { 0, 0, 0 };
            for (uint32_t i = 0; i < o->warm + o->frames && s == HZ_OK; i++) {
                int64_t total = 0, ns[3] = { 0, 0, 0 };
                s = frame(r[m], i, o->t, &total, ns, err);
                if (i >= o->warm) {
                    sum += total;
                    for (int q = 0; q < 3; q++)
                        psum[q] += ns[q];
                }
            }
            ms_m[m][round] = (double)sum / o->frames * 1e-6;
            for (int q = 0; q < 3; q++)
                parts[m][q][round] = (double)psum[q] / o->frames * 1e-6;
        }
        if (o->progress) {
            fprintf(stderr, "\r  adaptive %-18s round %d/%d      ", label, round + 1, o->rounds);
            fflush(stderr);
        }
    }
    if (o->progress)
        fprintf(stderr, "\r%70s\r", "");
    for (int m = 0; m < METHODS && s == HZ_OK; m++) {
        hz_bench_adaptive_row_t *row = &rows[m];
        memset(row, 0, sizeof *row);
        snprintf(row->scene, sizeof row->scene, "%s", label);
        snprintf(row->method, sizeof row->method, "%s", m ? "adaptive" : "full-9spp");
        row->tau = m ? (double)taus[m - 1] : NAN;
        row->ms = hz_bench_median(ms_m[m], o->rounds);
        for (int q = 0; q < 3; q++)
            row->pass_ms[q] = hz_bench_median(parts[m][q], o->rounds);
        hz_render_stats_t last;
        hz_render_frame_stats(r[m], &last, NULL);
        double px = (double)o->width * o->height;
        row->rays_per_pixel = (double)last.primary_rays / px;
        row->lanes_per_packet = m && last.extra_packets ? (double)last.extra_rays / (double)last.extra_packets : NAN;
        row->psnr_srgb8_db = psnr_srgb8(&ref, hz_render_output(r[m]));
    }
    free(ref.rgb);
    hz_bench_scene_close(&bs);
    return s;
}

static const char *field(char *buf, size_t size, const char *fmt, double v)
{
    if (isnan(v))
        buf[0] = '\0';
    else
        snprintf(buf, size, fmt, v);
    return buf;
}

static hz_status_t write_csv(const char *path, const hz_bench_adaptive_row_t *rows, int n, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    fprintf(out.f, "scene,method,tau,ms,presample_ms,test_ms,extra_ms,rays_per_pixel,lanes_per_packet,psnr_srgb8_db\n");
    for (int k = 0; k < n; k++) {
        const hz_bench_adaptive_row_t *r = &rows[k];
        bool full = isnan(r->tau);
        char b[4][32];
        fprintf(out.f, "%s,%s,%s,%.3f,%.3f,%s,%s,%.4f,%s,%.3f\n", r->scene, r->method, field(b[0], 32, "%.2f", r->tau),
                r->ms, r->pass_ms[0], field(b[1], 32, "%.3f", full ? NAN : r->pass_ms[1]),
                field(b[2], 32, "%.3f", full ? NAN : r->pass_ms[2]), r->rays_per_pixel,
                field(b[3], 32, "%.3f", r->lanes_per_packet), r->psnr_srgb8_db);
    }
    return hz_out_commit(&out, err);
}

int hz_bench_adaptive(const hz_bench_adaptive_opts_t *o, hz_bench_adaptive_row_t *rows, int max_rows,
                      hz_error_t *err)
{
    int n = 0;
    if (hz_threads_start(o->threads, err) != HZ_OK)
        return -1;
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0] && n + METHODS <= max_rows; i++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", o->scenes_dir ? o->scenes_dir : ".", scenes[i][1]);
        if (access(path, R_OK) != 0) {
            printf("adaptive %-18s skipped: %s missing (make scenes)\n", scenes[i][0], path);
            continue;
        }
        if (bench_scene(scenes[i][0], path, o, &rows[n], err) != HZ_OK) {
            hz_threads_stop();
            return -1;
        }
        n += METHODS;
    }
    hz_threads_stop();
    if (o->csv_path && write_csv(o->csv_path, rows, n, err) != HZ_OK)
        return -1;
    return n;
}

static void fit_scene(hz_bench_fit_scene_t *fs, const void *ctx)
{
    const hz_bench_adaptive_opts_t *o = ctx;
    hz_render_opts_t ro[METHODS];
    hz_bench_fit_accel(fs, NULL, 0, "native BVH");
    ref_opts(o, &ro[0]);
    hz_bench_fit_render(fs, ro, 1, "reference");
    for (int m = 0; m < METHODS; m++)
        opts_for(m, o, &ro[m]);
    hz_bench_fit_render(fs, ro, METHODS, "9 spp + adaptive at each tau");
}

void hz_bench_adaptive_fit(const hz_bench_adaptive_opts_t *o, hz_bench_fit_t *fit)
{
    hz_bench_fit_scenes(fit, "adaptive", scenes, sizeof scenes / sizeof scenes[0], fit_scene, o);
}
