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

#define METHODS HZ_BENCH_ADAPTIVE_METHODS
#define FOCUS (METHODS - 1) /* the last method: tau 1 with the focus objects */
static const float taus[HZ_BENCH_ADAPTIVE_TAUS] = { 0.3f, 0.6f, 1.0f };

/* The focus set: what the viewer looks at, taken as the objects that fill at least a fifth of the frame's central
 * ninth in the reference (the fixation region; seed 003 focused on the fairy at the centre of its view), or
 * the one that fills most of it. Returns the count; 0 when the central ninth shows only background. */
static uint32_t pick_focus(const hz_gbuffer_t *gb, uint16_t focus[HZ_AMASK_MAX_FOCUS])
{
    static uint32_t count[65536];
    memset(count, 0, sizeof count);
    uint32_t x0 = gb->width / 3, x1 = gb->width - gb->width / 3, y0 = gb->height / 3,
             y1 = gb->height - gb->height / 3, n = 0, best = 0;
    if (!gb->object)
        return 0;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = x0; x < x1; x++)
            count[gb->object[(size_t)y * gb->width + x]]++;
    uint64_t area = (uint64_t)(x1 - x0) * (y1 - y0);
    for (uint32_t o = 0; o < HZ_GB_NO_OBJECT; o++) {
        if (count[o] > count[best])
            best = o;
        if (count[o] && (uint64_t)count[o] * 5 >= area && n < HZ_AMASK_MAX_FOCUS)
            focus[n++] = (uint16_t)o;
    }
    if (n == 0 && count[best])
        focus[n++] = (uint16_t)best;
    return n;
}

static bool in_focus(uint16_t object, const uint16_t *focus, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++)
        if (focus[i] == object)
            return true;
    return false;
}

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

/* PSNR of the 8-bit sRGB codes (what the display shows) against the reference's, over the pixels `mask` keeps
 * (every pixel when mask is NULL); NaN when it keeps none. */
static double psnr_srgb8(const hz_image_t *ref, const hz_image_t *img, const uint8_t *mask)
{
    double se = 0;
    size_t n = 0, px = hz_image_pixels(ref);
    for (size_t p = 0; p < px; p++) {
        if (mask && !mask[p])
            continue;
        for (size_t c = 3 * p; c < 3 * p + 3; c++) {
            double d = (double)hz_srgb8_encode(ref->rgb[c]) - (double)hz_srgb8_encode(img->rgb[c]);
            se += d * d;
        }
        n += 3;
    }
    if (n == 0)
        return NAN;
    return se == 0 ? INFINITY : 10.0 * log10(255.0 * 255.0 * (double)n / se);
}

static const char *const scenes[][2] = { { "conference", "conference.hzb" }, { "sponza", "sponza.hzb" },
                                         { "CornellBox-Mirror", "CornellBox-Mirror.hzb" },
                                         { "lost-empire", "lost-empire.hzb" } };
HZ_STATIC_ASSERT(sizeof scenes / sizeof scenes[0] == HZ_BENCH_ADAPTIVE_SCENES, adaptive_scenes);

static void ref_opts(const hz_bench_adaptive_opts_t *o, hz_render_opts_t *ro)
{
    hz_render_opts_default(ro);
    ro->width = o->width, ro->height = o->height, ro->spp = o->ref_spp, ro->seed = 0x5eed;
}

static void opts_for(int m, const hz_bench_adaptive_opts_t *o, const uint16_t *focus, uint32_t nfocus,
                     hz_render_opts_t *ro)
{
    hz_render_opts_default(ro);
    ro->width = o->width, ro->height = o->height;
    if (m == 0) {
        ro->mode = HZ_MODE_FULL, ro->spp = 9;
    } else {
        float tau = m == FOCUS ? 1.0f : taus[m - 1];
        ro->mode = HZ_MODE_ADAPTIVE;
        ro->adaptive.tau[HZ_TAU_COL] = ro->adaptive.tau[HZ_TAU_PTE] = ro->adaptive.tau[HZ_TAU_STE] = tau;
        if (m == FOCUS) {
            ro->adaptive.focus_count = nfocus;
            memcpy(ro->adaptive.focus, focus, nfocus * sizeof *focus);
        }
    }
}

static hz_status_t bench_scene(const char *label, const char *path, const hz_bench_adaptive_opts_t *o,
                               hz_bench_adaptive_row_t *rows, hz_error_t *err)
{
    hz_bench_scene_t bs;
    hz_image_t ref = { o->width, o->height, NULL };
    uint16_t focus[HZ_AMASK_MAX_FOCUS];
    uint32_t nfocus = 0;
    uint8_t *mask = NULL; /* pixels whose reference primary hit is a focus object */
    size_t in_mask = 0;
    hz_status_t s = hz_bench_scene_open(&bs, path, err);
    hz_pools_t *pools = bs.pools;
    memset(rows, 0, METHODS * sizeof *rows);
    /* The reference first, from the frame arena, given back before the methods' renderers. */
    if (s == HZ_OK) {
        ref.rgb = malloc(hz_image_pixels(&ref) * 3 * sizeof(float));
        mask = calloc(hz_image_pixels(&ref), 1);
        if (!ref.rgb || !mask)
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
        if (s == HZ_OK) {
            memcpy(ref.rgb, hz_render_output(rr)->rgb, hz_image_pixels(&ref) * 3 * sizeof(float));
            const hz_gbuffer_t *gb = hz_render_gbuffer(rr);
            nfocus = pick_focus(gb, focus);
            for (size_t p = 0; p < hz_image_pixels(&ref) && nfocus; p++)
                in_mask += mask[p] = in_focus(gb->object[p], focus, nfocus);
        }
        hz_bench_scene_reset_frames(&bs);
    }
    /* Nothing to focus on (the centre shows background): the focus method is left out. One renderer at a time,
     * made before its frames and given back after them (outside the timing): at the paper's 1024x1024 the five
     * do not fit the frame arena together. Each frame renders the same time, so the counts and the image are
     * the same every round: they are taken from the first. */
    int methods = nfocus ? METHODS : METHODS - 1;
    double ms_m[METHODS][HZ_BENCH_ADAPTIVE_MAX_ROUNDS], parts[METHODS][3][HZ_BENCH_ADAPTIVE_MAX_ROUNDS];
    for (int round = 0; round < o->rounds && s == HZ_OK; round++) {
        for (int k = 0; k < methods && s == HZ_OK; k++) {
            int m = (round + k) % methods;
            hz_render_opts_t ro;
            hz_renderer_t *r = NULL;
            opts_for(m, o, focus, nfocus, &ro);
            s = hz_render_create(&r, &bs.scene, bs.accel, &ro, &pools->frame, pools->thread, (uint32_t)o->threads,
                                 err);
            int64_t sum = 0, psum[3] = { 0, 0, 0 };
            for (uint32_t i = 0; i < o->warm + o->frames && s == HZ_OK; i++) {
                int64_t total = 0, ns[3] = { 0, 0, 0 };
                s = frame(r, i, o->t, &total, ns, err);
                if (i >= o->warm) {
                    sum += total;
                    for (int q = 0; q < 3; q++)
                        psum[q] += ns[q];
                }
            }
            ms_m[m][round] = (double)sum / o->frames * 1e-6;
            for (int q = 0; q < 3; q++)
                parts[m][q][round] = (double)psum[q] / o->frames * 1e-6;
            if (round == 0 && s == HZ_OK) {
                hz_bench_adaptive_row_t *row = &rows[m];
                hz_render_stats_t last;
                hz_render_frame_stats(r, &last, NULL);
                double px = (double)o->width * o->height;
                row->rays_per_pixel = (double)last.primary_rays / px;
                row->lanes_per_packet =
                    m && last.extra_packets ? (double)last.extra_rays / (double)last.extra_packets : NAN;
                row->psnr_srgb8_db = psnr_srgb8(&ref, hz_render_output(r), NULL);
                row->focus_psnr_srgb8_db = nfocus ? psnr_srgb8(&ref, hz_render_output(r), mask) : NAN;
            }
            hz_bench_scene_reset_frames(&bs);
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
        snprintf(row->scene, sizeof row->scene, "%s", label);
        snprintf(row->method, sizeof row->method, "%s", m == FOCUS ? "adaptive-focus" : m ? "adaptive" : "full-9spp");
        row->tau = m == FOCUS ? 1.0 : m ? (double)taus[m - 1] : NAN;
        row->focus_count = nfocus;
        memcpy(row->focus, focus, nfocus * sizeof *focus);
        row->focus_share = (double)in_mask / (double)hz_image_pixels(&ref);
        if (m >= methods) { /* left out: no focus objects */
            row->ms = row->rays_per_pixel = row->lanes_per_packet = row->psnr_srgb8_db = NAN;
            row->focus_psnr_srgb8_db = NAN;
            for (int q = 0; q < 3; q++)
                row->pass_ms[q] = NAN;
            continue;
        }
        row->ms = hz_bench_median(ms_m[m], o->rounds);
        for (int q = 0; q < 3; q++)
            row->pass_ms[q] = hz_bench_median(parts[m][q], o->rounds);
    }
    free(ref.rgb);
    free(mask);
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
    fprintf(out.f, "scene,method,tau,ms,presample_ms,test_ms,extra_ms,rays_per_pixel,lanes_per_packet,psnr_srgb8_db,"
                   "focus_objects,focus_share,focus_psnr_srgb8_db\n");
    for (int k = 0; k < n; k++) {
        const hz_bench_adaptive_row_t *r = &rows[k];
        bool full = isnan(r->tau);
        char b[10][32], objs[HZ_AMASK_MAX_FOCUS * 6 + 1] = "";
        for (uint32_t i = 0, at = 0; i < r->focus_count; i++)
            at += (uint32_t)snprintf(objs + at, sizeof objs - at, "%s%u", i ? " " : "", (unsigned)r->focus[i]);
        fprintf(out.f, "%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s\n", r->scene, r->method,
                field(b[0], 32, "%.2f", r->tau), field(b[4], 32, "%.3f", r->ms), field(b[5], 32, "%.3f", r->pass_ms[0]),
                field(b[1], 32, "%.3f", full ? NAN : r->pass_ms[1]), field(b[2], 32, "%.3f", full ? NAN : r->pass_ms[2]),
                field(b[6], 32, "%.4f", r->rays_per_pixel), field(b[3], 32, "%.3f", r->lanes_per_packet),
                field(b[7], 32, "%.3f", r->psnr_srgb8_db), objs, field(b[8], 32, "%.4f", r->focus_share),
                field(b[9], 32, "%.3f", r->focus_psnr_srgb8_db));
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
    uint16_t focus[1] = { 0 }; /* the focus list does not change what a renderer takes */
    hz_bench_fit_accel(fs, NULL, 0, "native BVH");
    ref_opts(o, &ro[0]);
    hz_bench_fit_render(fs, ro, 1, "reference");
    for (int m = 0; m < METHODS; m++) { /* one at a time, as the group makes them */
        char what[48];
        opts_for(m, o, focus, 1, &ro[m]);
        if (m == 0)
            snprintf(what, sizeof what, "9 spp");
        else
            snprintf(what, sizeof what, "adaptive tau %.1f%s", m == FOCUS ? 1.0 : (double)taus[m - 1],
                     m == FOCUS ? ", focused" : "");
        hz_bench_fit_render(fs, &ro[m], 1, what);
    }
}

void hz_bench_adaptive_fit(const hz_bench_adaptive_opts_t *o, hz_bench_fit_t *fit)
{
    hz_bench_fit_scenes(fit, "adaptive", scenes, sizeof scenes / sizeof scenes[0], fit_scene, o);
}
