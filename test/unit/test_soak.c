/*
 * Soak: the frame loop (hz/frameloop.h) renders the built-in scene for many frames per configuration — every
 * render mode, motion blur, every transparency method — on a simulated 240 Hz display with a simulated clock,
 * through the scene source the commands use (port/linux/scenesrc.c), into the null sink. After a warm-up:
 *  - no heap call at all (the process-wide interposer of heap_count.h);
 *  - the arenas' high-water marks do not move (nothing grows with the run's length beyond its records);
 *  - the scene clock keeps animating: the last frames differ from each other, and the scene time of the last
 *    frame is exactly start + n / hz (the source's clock counts refreshes);
 *  - the frame-time distribution of the first and the last 10^4 frames is printed (p50, p99), for `make soak`'s
 *    table; no timing is asserted.
 * HZ_SOAK_FRAMES sets the frames per configuration (default 1000: the shortened run of make test; make soak runs
 * 100000). Each configuration is one test, so a failure names it.
 * hz-test: native no-vm (native boards only; heavy under system emulation, runs under qemu-user)
 */
#define _GNU_SOURCE
#include "hz_test.h"

#include <dlfcn.h>
#include <execinfo.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "heap_count.h"
#include "hz/crc32.h"
#include "hz/frameloop.h"
#include "hz/hz.h"
#include "pools.h"
#include "scenesrc.h"
#include "vsource.h"

#define WARMUP 64u
#define W 32
#define H 18

static uint64_t frames_per_config(void)
{
    const char *e = getenv("HZ_SOAK_FRAMES");
    long long n = e ? atoll(e) : 1000;
    return n < WARMUP + 32 ? WARMUP + 32 : (uint64_t)n;
}

/* The loop's frame source, wrapped: counts frames, arms the heap counter after the warm-up and keeps a
 * checksum of each of the last frames. */
typedef struct wrap {
    hz_framesrc_t inner;
    uint64_t n, total;
    uint32_t crc[4];
    size_t hw_scene, hw_accel, hw_frame;
    size_t used_warm[4], used_end[4]; /* scene, accel, frame, thread 0 arenas in use */
} wrap_t;

static void arenas_used(size_t used[4])
{
    hz_pools_t *p = hz_pools_get();
    used[0] = p->scene.used, used[1] = p->accel.used, used[2] = p->frame.used, used[3] = p->thread[0].used;
}

static hz_status_t wrapped(void *ctx, const hz_frame_req_t *req, hz_rgb8_image_t *out, hz_error_t *err)
{
    wrap_t *w = ctx;
    hz_status_t s = w->inner.render(w->inner.ctx, req, out, err);
    w->n++;
    if (w->n == WARMUP) {
        hz_pools_t *p = hz_pools_get();
        w->hw_scene = p->scene.high_water, w->hw_accel = p->accel.high_water, w->hw_frame = p->frame.high_water;
        arenas_used(w->used_warm);
        armed_calls = 0;
        armed = 1;
    }
    if (w->n == w->total)
        arenas_used(w->used_end);
    if (w->n + 4 > w->total)
        w->crc[(w->n + 4 - w->total - 1) % 4] = hz_crc32(0, out->rgb, (size_t)out->h * out->stride);
    return s;
}

static double pct(double *v, uint32_t n, double p)
{
    if (!n)
        return 0.0;
    for (uint32_t i = 1; i < n; i++) /* insertion sort: n is 10^4 at most */
        for (uint32_t j = i; j > 0 && v[j - 1] > v[j]; j--) {
            double t = v[j];
            v[j] = v[j - 1], v[j - 1] = t;
        }
    return v[(uint32_t)(p * (n - 1) + 0.5)];
}

static void soak(const char *label, hz_render_mode_t mode, hz_transp_t transp, float shutter)
{
    const uint64_t total = frames_per_config();
    hz_error_t err;
    hz_scenesrc_cfg_t sc;
    hz_scenesrc_cfg_init(&sc, "builtin", mode, W, H, 1);
    sc.opts.transparency = transp;
    sc.opts.hybrid_x = 0.5f;
    sc.opts.shutter = shutter;
    sc.opts.frame_hz = 240;
    sc.threads = 2;
    sc.clock = HZ_SCENE_CLOCK_SLOTS;
    static wrap_t w;
    memset(&w, 0, sizeof w);
    w.total = total;
    if (hz_scenesrc_open(&sc, &w.inner, &err) != HZ_OK)
        fail_msg("%s: %s", label, err.msg);
    hz_framesrc_t fs = { w.inner.name, &w, wrapped, NULL };
    hz_vsynth_cfg_t g;
    memset(&g, 0, sizeof g);
    g.period_q16 = hz_vsync_period_q16_from_mhz(240000);
    hz_vsource_t src;
    hz_sink_t sink;
    assert_int_equal(hz_vsource_sim(&src, &g, &err), HZ_OK);
    hz_sink_null(&sink);
    hz_rtm_cfg_t m = { HZ_RTM_CONST, 1000000, 0, 0, 0, 0, 1 };
    hz_loop_cfg_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.frames_mode = 1;
    cfg.frames = total;
    cfg.nominal_period_ns = 4166667;
    cfg.pace.guard_ns = -1;
    cfg.w = W, cfg.h = H;
    cfg.rtm = &m;
    cfg.max_frames = (size_t)total;
    cfg.max_edges = (size_t)total * 3 + 256;
    hz_timebase_t tb;
    hz_tb_init_virtual(&tb, 0);
    hz_pools_t *pools = hz_pools_get();
    hz_arena_mark_t mark = hz_arena_mark(&pools->frame);
    static hz_loop_result_t res;
    hz_status_t s = hz_loop_run(&cfg, &tb, &src, &sink, &fs, &pools->frame, &res, &err);
    armed = 0;
    const unsigned long calls = armed_calls;
    const size_t hw_scene = pools->scene.high_water, hw_accel = pools->accel.high_water;
    const size_t hw_frame = pools->frame.high_water;
    hz_vsource_close(&src);
    hz_sink_close(&sink);
    if (s != HZ_OK) {
        hz_scenesrc_close();
        fail_msg("%s: %s", label, err.msg);
    }
    /* frame times of the first and last 10^4 frames (render only, wall clock) */
    const hz_scenesrc_stats_t *st = hz_scenesrc_stats();
    static double a[10000], b[10000];
    uint32_t k = st->timed < 20000 ? st->timed / 2 : 10000;
    memcpy(a, st->render_ms, k * sizeof(double));
    memcpy(b, st->render_ms + st->timed - k, k * sizeof(double));
    const double a50 = pct(a, k, 0.5), a99 = pct(a, k, 0.99), b50 = pct(b, k, 0.5), b99 = pct(b, k, 0.99);
    print_message("  soak %-14s %7llu frames: heap calls after %u frames %lu; high water scene %zu accel %zu frame %zu "
                  "(after warm-up %zu %zu %zu); render ms p50/p99 first %u %.3f/%.3f, last %u %.3f/%.3f\n",
                  label, (unsigned long long)res.n_frames, WARMUP, calls, hw_scene, hw_accel, hw_frame, w.hw_scene,
                  w.hw_accel, w.hw_frame, k, a50, a99, k, b50, b99);
    hz_arena_reset(&pools->frame, mark);
    hz_scenesrc_close();
    assert_int_equal(res.n_frames, total);
    assert_int_equal(calls, 0);
    assert_int_equal(hw_scene, w.hw_scene);
    assert_int_equal(hw_accel, w.hw_accel);
    assert_int_equal(hw_frame, w.hw_frame); /* the loop's records were taken before the warm-up ended */
    /* the high-water marks are the process's: the arenas' fill itself must not move either */
    for (int a = 0; a < 4; a++)
        if (w.used_end[a] != w.used_warm[a])
            fail_msg("%s: arena %d holds %zu bytes at the end, %zu after the warm-up", label, a, w.used_end[a],
                     w.used_warm[a]);
    /* still animating at the end: the last four frames all differ */
    for (int i = 0; i < 4; i++)
        for (int j = i + 1; j < 4; j++)
            if (w.crc[i] == w.crc[j])
                fail_msg("%s: frames %llu and %llu of the last four are the same: the scene stopped", label,
                         (unsigned long long)(total - 4 + (uint64_t)i), (unsigned long long)(total - 4 + (uint64_t)j));
}

static void test_full(void **state)
{
    (void)state;
    soak("full", HZ_MODE_FULL, HZ_TRANSP_EXACT, 0.0f);
}

static void test_taa(void **state)
{
    (void)state;
    soak("taa", HZ_MODE_TAA, HZ_TRANSP_EXACT, 0.0f);
}

static void test_tdense(void **state)
{
    (void)state;
    soak("tdense", HZ_MODE_TDENSE, HZ_TRANSP_EXACT, 0.0f);
}

static void test_adaptive(void **state)
{
    (void)state;
    soak("adaptive", HZ_MODE_ADAPTIVE, HZ_TRANSP_EXACT, 0.0f);
}

static void test_tdense_blur(void **state)
{
    (void)state;
    soak("tdense+blur", HZ_MODE_TDENSE, HZ_TRANSP_EXACT, 0.5f);
}

static void test_adaptive_blur(void **state)
{
    (void)state;
    soak("adaptive+blur", HZ_MODE_ADAPTIVE, HZ_TRANSP_EXACT, 0.5f);
}

static void test_taa_transparency(void **state)
{
    (void)state;
    static const hz_transp_t methods[] = { HZ_TRANSP_RR, HZ_TRANSP_STD, HZ_TRANSP_DTAA, HZ_TRANSP_DTAA_STAR,
                                           HZ_TRANSP_HYBRID };
    for (size_t i = 0; i < sizeof methods / sizeof methods[0]; i++) {
        char label[32];
        snprintf(label, sizeof label, "taa+%s", hz_transp_name(methods[i]));
        soak(label, HZ_MODE_TAA, methods[i], 0.0f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full),        cmocka_unit_test(test_taa),         cmocka_unit_test(test_tdense),
        cmocka_unit_test(test_adaptive),    cmocka_unit_test(test_tdense_blur), cmocka_unit_test(test_adaptive_blur),
        cmocka_unit_test(test_taa_transparency),
    };
    return HZ_RUN(tests);
}
