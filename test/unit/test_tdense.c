/* Temporally dense reconstruction (src/recon/tdense.c) driven by an analytic "tracer": placement of the one
 * sample per tile, the static window converging to the 4-spp MSAA average, new dynamic samples stored
 * directly, old ones reprojected and clamped to the newest neighbours' box, no history leaking through,
 * reflected motion on mirrors, camera-motion resets, the once-per-cycle ordering choice, odd sizes, and
 * bit-identical output for any split of the resolve into row ranges. */
#include "hz_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hz/hash.h"
#include "hz/pack.h"
#include "hz/tdense.h"
#include "hz/vmath.h"
#include "../../src/recon/tdense_internal.h" /* hz_tdense_ghat */

static uint8_t arena_buf[8u << 20];

/* The analytic scene: a smooth background plus a bright disc of radius r moving at (vx, vy) px per frame,
 * and optionally a "mirror" rectangle that shows the disc's motion only through mv_reflect. */
typedef struct scene {
    float cx, cy, r, vx, vy;
    float bg_flat; /* 1: uniform background (exact box tests), 0: gradient */
    int mirror;    /* mirror covers x < mirror_x1 */
    float mirror_x1, rvx, rvy;
    float cam_vx;  /* camera motion: everything moves by this much */
} scene_t;

static void shade(const scene_t *s, float x, float y, uint32_t frame, float rgb[3], float mv[2], float rmv[2],
                  int *mirror)
{
    float t = (float)frame;
    float cx = s->cx + s->vx * t, cy = s->cy + s->vy * t;
    float dx = x - cx, dy = y - cy;
    int in = dx * dx + dy * dy < s->r * s->r;
    if (in) {
        rgb[0] = 1.0f;
        rgb[1] = 0.8f;
        rgb[2] = 0.1f;
        mv[0] = -(s->vx + s->cam_vx); /* previous minus current position */
        mv[1] = -s->vy;
    } else {
        float g = s->bg_flat ? 0.25f : 0.1f + 0.004f * x + 0.002f * y;
        rgb[0] = g;
        rgb[1] = 0.5f * g;
        rgb[2] = 0.3f;
        mv[0] = -s->cam_vx;
        mv[1] = 0.0f;
    }
    *mirror = s->mirror && x < s->mirror_x1;
    rmv[0] = s->rvx;
    rmv[1] = s->rvy;
}

/* What the last run_frame traced, per pixel (test images are at most 64x64). */
static float traced_rgb[64 * 64 * 3];
static uint8_t traced_now[64 * 64];
static int8_t traced_msaa[64 * 64];

/* One frame: sample every tile through the public placement API, put, resolve rows in the given chunks. */
static void run_frame(hz_tdense_t *td, const scene_t *s, bool camera_moved, uint32_t chunk)
{
    assert_true(td->cfg.width <= 64 && td->cfg.height <= 64);
    memset(traced_now, 0, sizeof traced_now);
    hz_tdense_begin_frame(td, camera_moved);
    for (uint32_t ty = 0; ty < td->tiles_y; ty++) {
        for (uint32_t tx = 0; tx < td->tiles_x; tx++) {
            uint32_t px, py;
            float j[2], rgb[3], mv[2], rmv[2];
            int msaa, mirror;
            if (!hz_tdense_tile_sample(td, tx, ty, &px, &py, j, &msaa))
                continue;
            assert_true(px / 2 == tx && py / 2 == ty);
            shade(s, (float)px + 0.5f + j[0], (float)py + 0.5f + j[1], td->frame, rgb, mv, rmv, &mirror);
            hz_tdense_put(td, tx, ty, rgb, mv, mirror ? rmv : NULL);
            size_t p = (size_t)py * td->cfg.width + px;
            memcpy(traced_rgb + 3 * p, rgb, sizeof rgb);
            traced_now[p] = 1;
            traced_msaa[p] = (int8_t)msaa;
        }
    }
    if (chunk == 0) {
        hz_tdense_resolve_rows(td, 0, td->tiles_y);
    } else {
        /* Back to front, in chunks: order and split must not matter. */
        uint32_t n = (td->tiles_y + chunk - 1) / chunk;
        for (uint32_t i = n; i-- > 0;)
            hz_tdense_resolve_rows(td, i * chunk, (i + 1) * chunk);
    }
    hz_tdense_end_frame(td);
}

static void make(hz_tdense_t *td, hz_arena_t *arena, uint32_t w, uint32_t h, hz_ghat_rule_t rule, bool reflect)
{
    hz_error_t err;
    assert_int_equal(hz_arena_init(arena, "test", arena_buf, sizeof arena_buf), HZ_OK);
    hz_tdense_config_t cfg = hz_tdense_config_default(w, h);
    cfg.rule = rule;
    cfg.reflect_mv = reflect;
    cfg.seed = 99;
    if (hz_tdense_init(td, &cfg, arena, &err) != HZ_OK)
        fail_msg("init: %s", err.msg);
    assert_true(arena->used <= hz_tdense_bytes(w, h));
}

static void test_static_matches_4spp_after_16_frames(void **state)
{
    (void)state;
    hz_arena_t arena;
    hz_tdense_t td;
    const uint32_t W = 34, H = 22;
    make(&td, &arena, W, H, HZ_GHAT_FULL, true);
    scene_t s = { 15.3f, 9.7f, 6.2f, 0, 0, 0, 0, 0, 0, 0, 0 };
    for (uint32_t f = 0; f < 16; f++) {
        /* Each frame traces exactly one pixel per tile, every pixel once per cycle, always jittered. */
        for (uint32_t ty = 0; ty < td.tiles_y; ty++)
            for (uint32_t tx = 0; tx < td.tiles_x; tx++) {
                uint32_t px, py;
                float j[2];
                int msaa;
                assert_true(hz_tdense_tile_sample(&td, tx, ty, &px, &py, j, &msaa));
                assert_int_equal(msaa, (int)hz_tdense_jitter_index(f));
                assert_true(j[0] == hz_msaa4_jitter16[msaa][0] / 16.0f && j[1] == hz_msaa4_jitter16[msaa][1] / 16.0f);
            }
        run_frame(&td, &s, false, 0);
        size_t full = 0;
        for (size_t p = 0; p < (size_t)W * H; p++)
            full += (td.flags[p] & HZ_TDENSE_SAMPLES) == HZ_TDENSE_SAMPLES;
        if (f < 12)
            assert_true(full == 0);
    }
    /* After 16 frames every pixel holds its four jittered samples, and the image is the 4-spp MSAA average of
     * the samples as the window stores them (RGB9E5, hz/pack.h), summed in MSAA order: bit for bit where the
     * last frame traced the pixel, and that average as the history keeps it (half floats) elsewhere. */
    const hz_image_t *out = hz_tdense_output(&td);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            size_t p = (size_t)y * W + x;
            assert_int_equal(td.flags[p] & (HZ_TDENSE_SAMPLES | HZ_TDENSE_DYNAMIC), HZ_TDENSE_SAMPLES);
            float sum[3] = { 0, 0, 0 };
            for (int j = 0; j < 4; j++) {
                float rgb[3], mv[2], rmv[2];
                int mirror;
                shade(&s, (float)x + 0.5f + hz_msaa4_jitter16[j][0] / 16.0f,
                      (float)y + 0.5f + hz_msaa4_jitter16[j][1] / 16.0f, 0, rgb, mv, rmv, &mirror);
                hz_rgb9e5_unpack(hz_rgb9e5_pack(rgb), rgb);
                for (int k = 0; k < 3; k++)
                    sum[k] += rgb[k];
            }
            const float *c = hz_image_at(out, x, y);
            float avg[3] = { sum[0] * 0.25f, sum[1] * 0.25f, sum[2] * 0.25f }, kept[3];
            for (int k = 0; k < 3; k++)
                kept[k] = hz_half_unpack(hz_half_pack(avg[k]));
            assert_true(memcmp(c, (td.flags[p] & HZ_TDENSE_KEPT) ? kept : avg, sizeof avg) == 0);
        }
    /* It stays there. */
    for (int f = 0; f < 5; f++)
        run_frame(&td, &s, false, 0);
    out = hz_tdense_output(&td);
    float c0[3], mv[2], rmv[2];
    int mirror;
    float sum[3] = { 0, 0, 0 };
    for (int j = 0; j < 4; j++) {
        shade(&s, 0.5f + hz_msaa4_jitter16[j][0] / 16.0f, 0.5f + hz_msaa4_jitter16[j][1] / 16.0f, 0, c0, mv, rmv,
              &mirror);
        hz_rgb9e5_unpack(hz_rgb9e5_pack(c0), c0);
        for (int k = 0; k < 3; k++)
            sum[k] += c0[k];
    }
    float avg[3] = { sum[0] * 0.25f, sum[1] * 0.25f, sum[2] * 0.25f }, kept[3];
    hz_rgb9e5_unpack(hz_rgb9e5_pack(avg), kept);
    assert_true(memcmp(hz_image_at(out, 0, 0), (td.flags[0] & HZ_TDENSE_KEPT) ? kept : avg, sizeof avg) == 0);
}

static void test_dynamic_new_direct_old_clamped(void **state)
{
    (void)state;
    hz_arena_t arena;
    hz_tdense_t td;
    const uint32_t W = 40, H = 24;
    make(&td, &arena, W, H, HZ_GHAT_FULL, true);
    scene_t s = { 6.0f, 11.0f, 5.0f, 0.7f, 0.2f, 0, 0, 0, 0, 0, 0 };
    for (uint32_t f = 0; f < 24; f++) {
        run_frame(&td, &s, false, 0);
        if (f < 4)
            continue;
        const hz_image_t *out = hz_tdense_output(&td);
        int checked_old = 0, checked_new = 0;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                size_t p = (size_t)y * W + x;
                if (!(td.flags[p] & HZ_TDENSE_DYNAMIC))
                    continue;
                const float *c = hz_image_at(out, x, y);
                if (traced_now[p]) {
                    /* Stored directly. */
                    for (int k = 0; k < 3; k++)
                        assert_true(c[k] == traced_rgb[3 * p + k]);
                    checked_new++;
                    continue;
                }
                /* Old: inside mean ± σ of the immediate neighbours that are in this subframe. */
                double sum[3] = { 0, 0, 0 }, sq[3] = { 0, 0, 0 };
                int n = 0;
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int qx = (int)x + dx, qy = (int)y + dy;
                        if ((!dx && !dy) || qx < 0 || qy < 0 || qx >= (int)W || qy >= (int)H)
                            continue;
                        size_t q = (size_t)qy * W + (size_t)qx;
                        if (!traced_now[q])
                            continue;
                        for (int k = 0; k < 3; k++) {
                            sum[k] += traced_rgb[3 * q + k];
                            sq[k] += (double)traced_rgb[3 * q + k] * traced_rgb[3 * q + k];
                        }
                        n++;
                    }
                assert_true(n >= 1); /* the pixel's own tile always contributes */
                for (int k = 0; k < 3; k++) {
                    double mu = sum[k] / n, sd = sqrt(fmax(0.0, sq[k] / n - mu * mu));
                    assert_true(c[k] >= mu - sd - 1e-5 && c[k] <= mu + sd + 1e-5);
                }
                checked_old++;
            }
        assert_true(checked_old > 0 && checked_new > 0);
    }
}

static void test_no_history_after_object_passes(void **state)
{
    (void)state;
    /* A disc crosses a flat background quickly. Behind it, every pixel whose 3x3 neighbourhood shows only
     * background shows exactly the background: new samples are stored, old pixels are clamped to a box of
     * identical neighbours (σ = 0). An exponential history would keep a trail. */
    hz_arena_t arena;
    hz_tdense_t td;
    const uint32_t W = 48, H = 16;
    make(&td, &arena, W, H, HZ_GHAT_FULL, true);
    scene_t s = { 4.0f, 8.0f, 4.0f, 1.5f, 0.0f, 1, 0, 0, 0, 0, 0 };
    for (uint32_t f = 0; f < 20; f++)
        run_frame(&td, &s, false, 0);
    const hz_image_t *out = hz_tdense_output(&td);
    float disc_x = s.cx + s.vx * 19.0f;
    int checked = 0;
    /* The background exactly: as a traced sample, as the half-float history keeps it, or as the average of a
     * static pixel's window of identical RGB9E5 samples (which the history then keeps exactly). */
    float bg[3] = { 0.25f, 0.125f, 0.3f }, kept[3], win[3];
    for (int k = 0; k < 3; k++)
        kept[k] = hz_half_unpack(hz_half_pack(bg[k]));
    hz_rgb9e5_unpack(hz_rgb9e5_pack(bg), win);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < (uint32_t)(disc_x - s.r - 3.0f); x++) {
            const float *c = hz_image_at(out, x, y);
            if (!(memcmp(c, bg, sizeof bg) == 0 || memcmp(c, kept, sizeof kept) == 0 || memcmp(c, win, sizeof win) == 0))
                fail_msg("pixel (%u, %u): %.9g %.9g %.9g, background %.9g %.9g %.9g", x, y, c[0], c[1], c[2], bg[0], bg[1], bg[2]);
            checked++;
        }
    assert_true(checked > 200);
}

static void test_reprojection_follows_motion(void **state)
{
    (void)state;
    /* A linear ramp sliding right by 0.7 px per frame (motion vectors -0.7: previous minus current). Bilinear
     * resampling reproduces a linear function, so an old pixel reprojected from the right place is exact; from
     * p - m instead of p + m it would be 0.014 off, well inside its neighbours' box (so the clamp cannot hide
     * it). */
    hz_arena_t arena;
    hz_tdense_t td;
    const uint32_t W = 40, H = 10;
    const float v = 0.7f, slope = 0.01f;
    make(&td, &arena, W, H, HZ_GHAT_FULL, true);
    for (uint32_t f = 0; f < 12; f++) {
        hz_tdense_begin_frame(&td, false);
        for (uint32_t ty = 0; ty < td.tiles_y; ty++)
            for (uint32_t tx = 0; tx < td.tiles_x; tx++) {
                uint32_t px, py;
                float j[2];
                int msaa;
                assert_true(hz_tdense_tile_sample(&td, tx, ty, &px, &py, j, &msaa));
                float x = (float)px + 0.5f + j[0], c = 0.2f + slope * (x - v * (float)f);
                const float rgb[3] = { c, c, c }, mv[2] = { -v, 0.0f };
                hz_tdense_put(&td, tx, ty, rgb, mv, NULL);
            }
        hz_tdense_resolve_rows(&td, 0, td.tiles_y);
        hz_tdense_end_frame(&td);
        /* Frame 0 is approximate (no history, and traced jittered before anything is known to move), and new
         * content enters at the left edge, where the source p + m lies outside and is clamped: both errors
         * travel along with the motion and fade by the bilinear weights. From frame 8 on, and 12 px from the
         * edge, they are below 5e-5 with float history; the half-float history adds at most half a step of
         * its rounding at the value (2^-11 of its power of two), well inside the 2^-8 allowed here (0.002 at
         * 0.3, 4 times less than the 0.014 of a reprojection from the wrong side). */
        if (f < 8)
            continue;
        const hz_image_t *out = hz_tdense_output(&td);
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 12; x < W - 2; x++) {
                float want = 0.2f + slope * ((float)x + 0.5f - v * (float)f);
                if (fabsf(hz_image_at(out, x, y)[0] - want) > ldexpf(1.0f, ilogbf(want) - 8))
                    fail_msg("frame %u pixel (%u, %u): %.6f, want %.6f", f, x, y, hz_image_at(out, x, y)[0], want);
            }
    }
}

static void test_mirror_motion_switch(void **state)
{
    (void)state;
    /* A static mirror (left half) reflecting something that moves: with reflected motion the mirror pixels are
     * dynamic and never averaged; with the switch off they look static and fill their windows. */
    for (int reflect = 0; reflect < 2; reflect++) {
        hz_arena_t arena;
        hz_tdense_t td;
        const uint32_t W = 24, H = 12;
        make(&td, &arena, W, H, HZ_GHAT_FULL, reflect != 0);
        scene_t s = { -100.0f, -100.0f, 1.0f, 0, 0, 0, 1, 10.0f, 0.6f, 0.0f, 0 };
        for (uint32_t f = 0; f < 16; f++)
            run_frame(&td, &s, false, 0);
        for (uint32_t y = 0; y < H; y++) {
            for (uint32_t x = 0; x < 8; x++) { /* well inside the mirror */
                unsigned fl = td.flags[(size_t)y * W + x];
                if (reflect)
                    assert_int_equal(fl & (HZ_TDENSE_DYNAMIC | HZ_TDENSE_SAMPLES), HZ_TDENSE_DYNAMIC);
                else
                    assert_int_equal(fl & (HZ_TDENSE_DYNAMIC | HZ_TDENSE_SAMPLES), HZ_TDENSE_SAMPLES);
            }
            for (uint32_t x = 12; x < W; x++) /* outside: static either way */
                assert_int_equal(td.flags[(size_t)y * W + x] & (HZ_TDENSE_DYNAMIC | HZ_TDENSE_SAMPLES),
                                 HZ_TDENSE_SAMPLES);
        }
    }
}

static void test_camera_motion_restarts_windows(void **state)
{
    (void)state;
    hz_arena_t arena;
    hz_tdense_t td;
    const uint32_t W = 20, H = 14;
    make(&td, &arena, W, H, HZ_GHAT_FULL, true);
    scene_t s = { 8.0f, 7.0f, 3.0f, 0, 0, 0, 0, 0, 0, 0, 0 };
    for (int f = 0; f < 16; f++)
        run_frame(&td, &s, false, 0);
    /* The camera moves for one frame without changing the motion vectors (a pure rotation of a sky, say): still
     * every window restarts and no ray is jittered in that frame. */
    run_frame(&td, &s, true, 0);
    for (size_t p = 0; p < (size_t)W * H; p++) {
        assert_int_equal(td.flags[p] & (HZ_TDENSE_SAMPLES | HZ_TDENSE_DYNAMIC), HZ_TDENSE_DYNAMIC);
        if (traced_now[p])
            assert_int_equal(traced_msaa[p], -1);
    }
    /* Static again. The tracer learns that a pixel is static from the frame it was resolved in, so the first
     * frame after the move still traces at the centre (one frame of latency, as in the paper); from then on
     * every trace is jittered and the windows are full again 16 frames later. */
    run_frame(&td, &s, false, 0);
    for (size_t p = 0; p < (size_t)W * H; p++)
        if (traced_now[p])
            assert_int_equal(traced_msaa[p], -1);
    for (int f = 0; f < 16; f++) {
        run_frame(&td, &s, false, 0);
        for (size_t p = 0; p < (size_t)W * H; p++)
            if (traced_now[p])
                assert_true(traced_msaa[p] >= 0);
    }
    for (size_t p = 0; p < (size_t)W * H; p++)
        assert_int_equal(td.flags[p] & (HZ_TDENSE_SAMPLES | HZ_TDENSE_DYNAMIC), HZ_TDENSE_SAMPLES);
}

static unsigned count_order(const hz_tdense_t *td, unsigned order)
{
    unsigned n = 0;
    for (size_t t = 0; t < (size_t)td->tiles_x * td->tiles_y; t++)
        n += td->orders[t] == order;
    return n;
}

static void test_orderings_follow_ghat_once_per_cycle(void **state)
{
    (void)state;
    const uint32_t W = 16, H = 12;
    const size_t tiles = (size_t)(W / 2) * (H / 2);
    struct {
        float cam_vx, vy;
        hz_ghat_rule_t rule;
        unsigned expect;
    } cases[] = {
        { 0.5f, 0, HZ_GHAT_FULL, HZ_TILEORDER_HOURGLASS },   /* horizontal, lf 0.5 */
        { 1.1f, 0, HZ_GHAT_FULL, HZ_TILEORDER_BOWTIE },      /* horizontal, lf 0.1 */
        { 0.5f, 0, HZ_GHAT_BOWTIE, HZ_TILEORDER_BOWTIE },    /* forced */
        { 1.1f, 0, HZ_GHAT_HOURGLASS, HZ_TILEORDER_HOURGLASS },
    };
    for (size_t c = 0; c < HZ_ARRAY_LEN(cases); c++) {
        hz_arena_t arena;
        hz_tdense_t td;
        make(&td, &arena, W, H, cases[c].rule, true);
        scene_t s = { -50, -50, 1, 0, 0, 0, 0, 0, 0, 0, 0 };
        s.cam_vx = cases[c].cam_vx;
        uint8_t at_start[64];
        for (uint32_t f = 0; f < 12; f++) {
            if (hz_tdense_cycle_start(td.frame))
                memcpy(at_start, td.orders, tiles);
            else
                assert_memory_equal(at_start, td.orders, tiles); /* no change inside a cycle */
            run_frame(&td, &s, false, 0);
        }
        assert_int_equal(count_order(&td, cases[c].expect), tiles);
    }
    /* Vertical motion of 0.1 px: Eq. 5 gives hourglass (through the motion of the object, camera static). */
    hz_arena_t arena;
    hz_tdense_t td;
    make(&td, &arena, W, H, HZ_GHAT_FULL, true);
    scene_t s = { 8, 6, 100, 0, 0.1f, 0, 0, 0, 0, 0, 0 }; /* a disc covering everything */
    for (uint32_t f = 0; f < 8; f++)
        run_frame(&td, &s, false, 0);
    assert_int_equal(count_order(&td, HZ_TILEORDER_HOURGLASS), tiles);
}

static void test_split_and_order_invariance(void **state)
{
    (void)state;
    /* Diagonal motion (random band included) over a gradient: resolving in one piece or in chunks of 1, 2 or
     * 3 tile rows in reverse order gives the same bytes every frame. */
    static hz_tdense_t td[4];
    static hz_arena_t arenas[4];
    static uint8_t bufs[4][2u << 20];
    const uint32_t W = 30, H = 26;
    for (int i = 0; i < 4; i++) {
        hz_error_t err;
        assert_int_equal(hz_arena_init(&arenas[i], "split", bufs[i], sizeof bufs[i]), HZ_OK);
        hz_tdense_config_t cfg = hz_tdense_config_default(W, H);
        assert_int_equal(hz_tdense_init(&td[i], &cfg, &arenas[i], &err), HZ_OK);
    }
    scene_t s = { 10.0f, 9.0f, 6.0f, 0.53f, 0.55f, 0, 1, 6.0f, 0.3f, -0.2f, 0 };
    for (uint32_t f = 0; f < 20; f++) {
        for (uint32_t i = 0; i < 4; i++)
            run_frame(&td[i], &s, f == 9, i);
        for (int i = 1; i < 4; i++) {
            assert_memory_equal(hz_tdense_output(&td[0])->rgb, hz_tdense_output(&td[i])->rgb,
                                (size_t)W * H * 3 * sizeof(float));
            assert_memory_equal(td[0].flags, td[i].flags, (size_t)W * H);
            assert_memory_equal(td[0].orders, td[i].orders, (size_t)td[0].tiles_x * td[0].tiles_y);
        }
    }
}

static void test_odd_sizes(void **state)
{
    (void)state;
    /* Partial tiles at the right and bottom: named pixels outside the image are skipped, every pixel inside is
     * traced once per cycle, and a static scene still converges. */
    const uint32_t sizes[][2] = { { 7, 5 }, { 1, 1 }, { 1, 6 }, { 9, 2 } };
    for (size_t i = 0; i < HZ_ARRAY_LEN(sizes); i++) {
        hz_arena_t arena;
        hz_tdense_t td;
        uint32_t W = sizes[i][0], H = sizes[i][1];
        make(&td, &arena, W, H, HZ_GHAT_FULL, true);
        scene_t s = { 3.0f, 2.0f, 2.0f, 0, 0, 0, 0, 0, 0, 0, 0 };
        static unsigned traced[16 * 16];
        memset(traced, 0, sizeof traced);
        for (uint32_t f = 0; f < 16; f++) {
            for (uint32_t ty = 0; ty < td.tiles_y; ty++)
                for (uint32_t tx = 0; tx < td.tiles_x; tx++) {
                    uint32_t px, py;
                    float j[2];
                    int msaa;
                    if (hz_tdense_tile_sample(&td, tx, ty, &px, &py, j, &msaa)) {
                        assert_true(px < W && py < H);
                        traced[py * W + px]++;
                    }
                }
            run_frame(&td, &s, false, 0);
        }
        for (size_t p = 0; p < (size_t)W * H; p++) {
            assert_int_equal(traced[p], 4);
            assert_int_equal(td.flags[p] & HZ_TDENSE_SAMPLES, HZ_TDENSE_SAMPLES);
        }
    }
}

static void test_bad_motion_and_first_frame(void **state)
{
    (void)state;
    hz_arena_t arena;
    hz_tdense_t td;
    make(&td, &arena, 8, 8, HZ_GHAT_FULL, true);
    /* Frame 0: untraced pixels show the mean of their new neighbours, not black. */
    hz_tdense_begin_frame(&td, false);
    const float grey[3] = { 0.5f, 0.5f, 0.5f };
    const float nan_mv[2] = { NAN, INFINITY }, zero[2] = { 0, 0 };
    for (uint32_t ty = 0; ty < 4; ty++)
        for (uint32_t tx = 0; tx < 4; tx++)
            hz_tdense_put(&td, tx, ty, grey, (tx == 2 && ty == 2) ? nan_mv : zero, NULL);
    hz_tdense_resolve_rows(&td, 0, 4);
    const hz_image_t *out = hz_tdense_output(&td);
    for (size_t i = 0; i < 64 * 3; i++)
        assert_true(out->rgb[i] == 0.5f);
    /* NaN became 0, +Inf the clamp: finite either way. */
    uint32_t px, py;
    float j[2];
    int msaa;
    hz_tdense_tile_sample(&td, 2, 2, &px, &py, j, &msaa);
    assert_true(hz_half_unpack(td.mv[2 * (py * 8 + px)]) == 0.0f);
    assert_true(hz_half_unpack(td.mv[2 * (py * 8 + px) + 1]) == HZ_TDENSE_MAX_MOTION);
    hz_tdense_end_frame(&td);
    /* Huge motion reprojects from the clamped edge without reading outside the image. */
    for (int f = 0; f < 4; f++)
        run_frame(&td, &(scene_t){ -50, 4, 1, 0, 0, 0, 0, 0, 0, 0, 1e9f }, false, 0);
    out = hz_tdense_output(&td);
    for (size_t i = 0; i < 64 * 3; i++)
        assert_true(isfinite(out->rgb[i]));
}

static void test_init_errors(void **state)
{
    (void)state;
    static uint8_t small[4096];
    hz_arena_t arena;
    hz_tdense_t td;
    hz_error_t err;
    assert_int_equal(hz_arena_init(&arena, "small", small, sizeof small), HZ_OK);
    hz_tdense_config_t cfg = hz_tdense_config_default(64, 64);
    assert_int_equal(hz_tdense_init(&td, &cfg, &arena, &err), HZ_E_NO_MEMORY);
    assert_non_null(strstr(err.msg, "small"));
    assert_int_equal(arena.used, 0);
    cfg = hz_tdense_config_default(0, 4);
    assert_int_not_equal(hz_tdense_init(&td, &cfg, &arena, &err), HZ_OK);
    cfg = hz_tdense_config_default(4, 4);
    cfg.gamma = NAN;
    assert_int_equal(hz_tdense_init(&td, &cfg, &arena, &err), HZ_E_INVALID_ARG);
    cfg.gamma = 1.0f;
    cfg.rule = HZ_GHAT_RULE_COUNT;
    assert_int_equal(hz_tdense_init(&td, &cfg, &arena, &err), HZ_E_INVALID_ARG);
    assert_int_equal(hz_tdense_bytes(0, 3), 0);
    /* Exactly hz_tdense_bytes is enough, wherever the arena's buffer starts. */
    static uint8_t exact[1u << 16];
    for (size_t misalign = 0; misalign < 64; misalign += 7) {
        size_t n = hz_tdense_bytes(13, 9);
        assert_true(n + misalign <= sizeof exact);
        assert_int_equal(hz_arena_init(&arena, "exact", exact + misalign, n), HZ_OK);
        cfg = hz_tdense_config_default(13, 9);
        if (hz_tdense_init(&td, &cfg, &arena, &err) != HZ_OK)
            fail_msg("misalign %zu: %s", misalign, err.msg);
    }
    assert_true(hz_tdense_bytes(4, 4) > 0 && hz_tdense_bytes(4, 4) <= sizeof small);
}

/* A colour for the SIMD-vs-scalar test: mostly ordinary radiance, sometimes what a broken tracer gives. */
static float odd_value(hz_rng_t *rng)
{
    uint32_t k = hz_rng_below(rng, 40);
    switch (k) {
    case 0: return NAN;
    case 1: return INFINITY;
    case 2: return -INFINITY;
    case 3: return -0.5f;
    case 4: return 1.0e6f; /* above RGB9E5's range */
    case 5: return 1.0e-30f; /* below it */
    case 6: return 0.0f;
    case 7: return -0.0f;
    default: return (float)hz_rng_below(rng, 1u << 20) * (4.0f / (float)(1u << 20));
    }
}

/* Motion for the same test: zero in patches (static pixels, so windows fill), tiny, ordinary, beyond the image,
 * and non-finite (sanitised by put). */
static float odd_motion(hz_rng_t *rng, uint32_t px, uint32_t py, uint32_t frame)
{
    if (((px / 6 + py / 5 + frame / 7) & 3u) != 0)
        return 0.0f;
    uint32_t k = hz_rng_below(rng, 30);
    switch (k) {
    case 0: return NAN;
    case 1: return INFINITY;
    case 2: return 1.0e-3f;
    case 3: return -300.0f;
    case 4: return 70000.0f;
    default: return ((float)hz_rng_below(rng, 4096) - 2048.0f) * (1.0f / 256.0f);
    }
}

static void test_lanes_match_scalar(void **state)
{
    (void)state;
    /* The board's SIMD resolve (hz_tdense_resolve_rows) against its scalar twin on the same random frames:
     * every output float, history code, flag, window slot and chosen ordering has the same bits, frame after
     * frame, across sizes that leave partial groups of lanes and partial tiles, camera cuts, resets, foreign
     * ordering bytes and the still-scene configuration without motion vectors. */
    static hz_tdense_t td[2];
    static hz_arena_t arenas[2];
    static uint8_t bufs[2][2u << 20];
    static const uint32_t sizes[][2] = { { 1, 1 }, { 3, 2 }, { 8, 8 }, { 9, 7 }, { 16, 3 }, { 17, 17 },
                                         { 37, 23 }, { 64, 9 }, { 131, 6 }, { 4, 40 }, { 48, 20 } };
    hz_rng_t rng;
    hz_rng_seed(&rng, 2026, 12);
    printf("# resolve path: %s\n", hz_tdense_resolve_path());
    for (size_t si = 0; si < HZ_ARRAY_LEN(sizes) * 2; si++) {
        const uint32_t W = sizes[si / 2][0], H = sizes[si / 2][1];
        const bool motion = (si & 1u) == 0;
        for (int i = 0; i < 2; i++) {
            hz_error_t err;
            assert_int_equal(hz_arena_init(&arenas[i], "lanes", bufs[i], sizeof bufs[i]), HZ_OK);
            hz_tdense_config_t cfg = hz_tdense_config_default(W, H);
            cfg.motion = motion;
            cfg.gamma = si % 3 == 0 ? 0.5f : 1.0f;
            if (hz_tdense_init(&td[i], &cfg, &arenas[i], &err) != HZ_OK)
                fail_msg("init %ux%u: %s", W, H, err.msg);
        }
        const size_t px = (size_t)W * H, tiles = (size_t)td[0].tiles_x * td[0].tiles_y;
        for (uint32_t f = 0; f < 48; f++) {
            bool cut = motion && (f % 17 == 16);
            if (f == 30)
                for (int i = 0; i < 2; i++)
                    hz_tdense_reset(&td[i]);
            if (f >= 20 && f < 24) {
                /* orderings the ĝ never writes (bytes 24..255) on a third of the tiles, the same in both: the
                 * lanes' shift lookup and its fallback must answer as the scalar % 24 does */
                for (size_t t = 0; t < tiles; t++) {
                    uint32_t v = hz_rng_u32(&rng);
                    if (v % 3u == 0)
                        td[0].orders[t] = td[1].orders[t] = (uint8_t)(24u + (v >> 8) % 232u);
                }
            }
            hz_rng_t frame_rng = rng; /* both instances trace the same frame */
            for (int i = 0; i < 2; i++) {
                hz_rng_t r = frame_rng;
                hz_tdense_begin_frame(&td[i], cut);
                for (uint32_t ty = 0; ty < td[i].tiles_y; ty++) {
                    for (uint32_t tx = 0; tx < td[i].tiles_x; tx++) {
                        uint32_t x, y;
                        float j[2], rgb[3], mv[2] = { 0.0f, 0.0f }, rmv[2];
                        int msaa;
                        if (!hz_tdense_tile_sample(&td[i], tx, ty, &x, &y, j, &msaa))
                            continue;
                        for (int k = 0; k < 3; k++)
                            rgb[k] = odd_value(&r);
                        if (motion) {
                            mv[0] = odd_motion(&r, x, y, f);
                            mv[1] = odd_motion(&r, x, y, f + 3);
                        }
                        rmv[0] = -mv[1];
                        rmv[1] = mv[0];
                        hz_tdense_put(&td[i], tx, ty, rgb, mv, hz_rng_below(&r, 5) == 0 ? rmv : NULL);
                    }
                }
                if (i == 0)
                    rng = r;
            }
            hz_tdense_resolve_rows(&td[0], 0, td[0].tiles_y);
            for (uint32_t ty = td[1].tiles_y; ty-- > 0;) /* the twin row by row, backwards */
                hz_tdense_resolve_rows_scalar(&td[1], ty, ty + 1);
            const uint16_t *h0 = td[0].hist[td[0].frame & 1u], *h1 = td[1].hist[td[1].frame & 1u];
            for (size_t p = 0; p < px * 3; p++) {
                uint32_t a, b;
                memcpy(&a, &hz_tdense_output(&td[0])->rgb[p], 4);
                memcpy(&b, &hz_tdense_output(&td[1])->rgb[p], 4);
                if (a != b)
                    fail_msg("%ux%u%s frame %u pixel %zu channel %zu: lanes %08x, scalar %08x", W, H,
                             motion ? "" : " (no motion)", f, p / 3, p % 3, a, b);
            }
            assert_memory_equal(h0, h1, 3 * px * sizeof(uint16_t));
            assert_memory_equal(td[0].flags, td[1].flags, px);
            assert_memory_equal(td[0].window, td[1].window, px * 4 * sizeof(uint32_t));
            assert_memory_equal(td[0].next_orders, td[1].next_orders, tiles);
            for (int i = 0; i < 2; i++)
                hz_tdense_end_frame(&td[i]);
            assert_memory_equal(td[0].orders, td[1].orders, tiles);
        }
    }
}

/* The put's motion codes by the board's conversion (hz_tdense_motion_code_lanes) against the scalar codec
 * (hz_tdense_motion_code: sanitise, then hz/pack.h's hz_half_pack_signed) on every class of float: NaNs of both
 * signs, infinities, +-0, the clamp at +-HZ_TDENSE_MAX_MOTION and just inside it, subnormal halves and the
 * ties of their rounding, the underflow edge at 2^-25, random bit patterns and random motions. Where the board
 * has no lanes the scalar codec is all there is; the test then checks it against hz_half_pack_signed. */
static void test_motion_code_lanes_matches_scalar(void **state)
{
    (void)state;
    static const float special[] = { 0.0f, -0.0f, INFINITY, -INFINITY, NAN, -NAN, 16384.0f, -16384.0f,
                                     16385.0f, -70000.0f, 16383.99f, 65504.0f, 0x1p-24f, -0x1p-24f, 0x1p-25f,
                                     -0x1p-25f, 0x1.8p-25f, 0x1p-26f, 0x1.8p-24f, -0x1.8p-24f, 0x1.4p-23f,
                                     0x1p-14f, 0x1.ffcp-15f, 1.0f + 0x1p-11f, 1.0f + 0x1.8p-10f, -1.0f - 0x1p-11f };
    const uint32_t n = HZ_EMULATED_LESS(2000000u, 200000u), ns = (uint32_t)HZ_ARRAY_LEN(special);
    hz_rng_t rng;
    hz_rng_seed(&rng, 12, 7);
    uint32_t checked = 0;
    for (uint32_t i = 0; i < n + ns * ns; i++) {
        float x, y;
        if (i < ns * ns) {
            x = special[i % ns], y = special[i / ns];
        } else if (i & 1u) {
            uint32_t a = hz_rng_u32(&rng), b = hz_rng_u32(&rng);
            memcpy(&x, &a, 4), memcpy(&y, &b, 4);
        } else {
            x = ((float)hz_rng_below(&rng, 1u << 20) - 524288.0f) * (1.0f / 1024.0f);
            y = ((float)hz_rng_below(&rng, 1u << 20) - 524288.0f) * (1.0f / 65536.0f);
        }
        const uint32_t want = hz_tdense_motion_code(x, y);
        const float cx = isnan(x) ? 0.0f : x < -HZ_TDENSE_MAX_MOTION ? -HZ_TDENSE_MAX_MOTION
                                           : x > HZ_TDENSE_MAX_MOTION ? HZ_TDENSE_MAX_MOTION : x;
        assert_int_equal(want & 0xffffu, hz_half_pack_signed(cx));
#ifdef HZ_TDENSE_LANES
        const uint32_t got = hz_tdense_motion_code_lanes(x, y);
        if (got != want)
            fail_msg("motion (%a, %a): lanes %08x, scalar %08x", (double)x, (double)y, got, want);
#endif
        checked++;
    }
    printf("# motion codes: %u pairs checked\n", checked);
}

/* The end of cycle's block motion in lanes (hz_tdense_block_motion_lanes) against a brute-force scan: per tile,
 * the first vector of the largest x^2 + y^2 over the 4x4 pixel block around it, clamped to the image, scanned
 * row by row. Motions drawn from a few vectors of equal length in different directions, so that most blocks tie;
 * widths whose groups lie inside the image and at both edges, heights of one tile row and more. */
static void test_block_motion_lanes_matches_scan(void **state)
{
    (void)state;
#ifdef HZ_TDENSE_LANES
    static const float vec[][2] = { { 3, 4 }, { 4, 3 }, { -3, 4 }, { 0, 5 }, { -5, 0 }, { 4, -3 }, { 0, 0 },
                                    { 1, 1 }, { -1, -1 }, { 0.5f, -0.25f }, { 6, 0 }, { 0, -6 }, { -0.0f, 0 } };
    static const uint32_t dims[][2] = { { 2 * HZ_TDENSE_LANES, 2 }, { 6 * HZ_TDENSE_LANES + 1, 7 },
                                        { 8 * HZ_TDENSE_LANES + 3, 12 }, { 4 * HZ_TDENSE_LANES + 2, 3 } };
    static uint32_t mv[(8 * HZ_TDENSE_LANES + 3) * 12];
    hz_rng_t rng;
    hz_rng_seed(&rng, 31, 5);
    uint32_t tiles = 0, ties = 0;
    for (int round = 0; round < 40; round++) {
        const uint32_t w = dims[round % 4][0], h = dims[round % 4][1];
        for (uint32_t i = 0; i < w * h; i++) {
            const float *v = vec[hz_rng_below(&rng, (uint32_t)HZ_ARRAY_LEN(vec))];
            mv[i] = (uint32_t)hz_half_pack_signed(v[0]) | (uint32_t)hz_half_pack_signed(v[1]) << 16;
        }
        hz_tdense_t td;
        memset(&td, 0, sizeof td);
        td.cfg.width = w, td.cfg.height = h;
        td.mv = (uint16_t *)mv;
        const uint32_t tiles_x = (w + 1) / 2, tiles_y = (h + 1) / 2;
        for (uint32_t ty = 0; ty < tiles_y; ty++)
            for (uint32_t tx0 = 0; tx0 + HZ_TDENSE_LANES <= tiles_x; tx0 += HZ_TDENSE_LANES) {
                float mx[HZ_TDENSE_LANES], my[HZ_TDENSE_LANES];
                hz_tdense_block_motion_lanes(&td, ty, tx0, mx, my);
                for (uint32_t k = 0; k < HZ_TDENSE_LANES; k++) {
                    const int tx = (int)(tx0 + k);
                    float bx = 0.0f, by = 0.0f, bl = 0.0f;
                    int equal = 0;
                    for (int y = 2 * (int)ty - 1; y <= 2 * (int)ty + 2; y++)
                        for (int x = 2 * tx - 1; x <= 2 * tx + 2; x++) {
                            if (x < 0 || y < 0 || x >= (int)w || y >= (int)h)
                                continue;
                            const uint32_t c = mv[(uint32_t)y * w + (uint32_t)x];
                            const float vx = hz_half_unpack((uint16_t)c), vy = hz_half_unpack((uint16_t)(c >> 16));
                            const float l2 = vx * vx + vy * vy;
                            equal += l2 == bl && l2 > 0.0f && (vx != bx || vy != by);
                            if (l2 > bl)
                                bx = vx, by = vy, bl = l2, equal = 0;
                        }
                    if (memcmp(&bx, &mx[k], sizeof bx) || memcmp(&by, &my[k], sizeof by))
                        fail_msg("%ux%u tile (%d, %u): lanes (%g, %g), scan (%g, %g)", w, h, tx, ty, (double)mx[k],
                                 (double)my[k], (double)bx, (double)by);
                    tiles++, ties += equal > 0;
                }
            }
    }
    printf("# block motion: %u tiles (%u with a tie the scan order decides)\n", tiles, ties);
    assert_true(ties > tiles / 4);
#else
    skip();
#endif
}

/* The resolve's ĝ (hz_tdense_ghat: double precision where certain, tdense_ghat.c) against the exact integer ĝ
 * (hz_tileorder_ghat, itself held to an independent oracle by test_tileorder) on every rule: random motions of a
 * few pixels and of every scale, motions built to land within a few units of the band edges (the angle at
 * π/4 ± π/40, the length's fraction at 1/4 and 3/4 of the shifted period), the axes, the diagonal and the Q16
 * extremes. The same decision everywhere; and the fast part decides nearly all ordinary motions itself. */
static hz_q16_t q16_of(double px)
{
    double v = px * 65536.0;
    v = v > 2147483647.0 ? 2147483647.0 : v < -2147483648.0 ? -2147483648.0 : v;
    return (hz_q16_t)llround(v);
}

static void test_ghat_fast_matches_exact(void **state)
{
    (void)state;
    const uint32_t n = HZ_EMULATED_LESS(400000u, 40000u);
    hz_rng_t rng;
    hz_rng_seed(&rng, 7, 29);
    const double pi = 3.14159265358979323846;
    uint32_t decided_ordinary = 0, ordinary = 0, undecided_edges = 0, edges = 0, differ = 0;
    for (int rule = 0; rule < HZ_GHAT_RULE_COUNT; rule++) {
        for (uint32_t i = 0; i < n; i++) {
            hz_q16_t mx, my;
            const uint32_t kind = i % 8u;
            const double phi = (double)hz_rng_u32(&rng) * (2.0 * pi / 4294967296.0);
            if (kind < 3) { /* a few pixels per frame */
                mx = (hz_q16_t)hz_rng_below(&rng, 1u << 19) - (1 << 18);
                my = (hz_q16_t)hz_rng_below(&rng, 1u << 19) - (1 << 18);
            } else if (kind < 5) { /* 2^-16 .. 2^15 px at any angle */
                const double len = ldexp(1.0 + (double)hz_rng_below(&rng, 1u << 20) / 1048576.0,
                                         (int)hz_rng_below(&rng, 31) - 16);
                mx = q16_of(len * cos(phi)), my = q16_of(len * sin(phi));
            } else if (kind < 7) { /* the length's fraction within a few units of a band edge */
                const double len = (double)hz_rng_below(&rng, 64) + 0.25 + 0.5 * (double)hz_rng_below(&rng, 2) +
                                   ((double)hz_rng_below(&rng, 64) - 32.0) / 65536.0;
                const double a = phi / 4.0;                          /* 0 .. π/2 */
                const double shift = a / pi * ((kind == 5) ? 1.0 : -1.0); /* u = |m| -+ α/π */
                mx = q16_of((len + shift) * cos(a)), my = q16_of((len + shift) * sin(a));
            } else { /* the angle within a few units of the random band's edges */
                const double edge = pi / 4.0 + ((hz_rng_below(&rng, 2) ? 1.0 : -1.0) * pi / 40.0);
                const double a = edge + ((double)hz_rng_below(&rng, 512) - 256.0) * (pi / 2.0) / 1073741824.0;
                const double len = 0.5 + (double)hz_rng_below(&rng, 1u << 16) / 256.0;
                mx = q16_of(len * cos(a)), my = q16_of(len * sin(a));
            }
            if (i % 97u == 0) { /* axes, diagonal, extremes */
                static const hz_q16_t odd[] = { 0, 1, -1, 65536, INT32_MAX, INT32_MIN, 12345, -98765 };
                mx = odd[hz_rng_below(&rng, 8)];
                my = hz_rng_below(&rng, 3) == 0 ? mx : odd[hz_rng_below(&rng, 8)];
            }
            const uint32_t tx = hz_rng_below(&rng, 4096), ty = hz_rng_below(&rng, 4096), key = hz_rng_u32(&rng);
            const hz_tilecycle_t want =
                hz_tileorder_ghat(mx, my, hz_tileorder_tile_random_keyed(tx, ty, key), (hz_ghat_rule_t)rule);
            const hz_tilecycle_t got = hz_tdense_ghat(mx, my, tx, ty, key, (hz_ghat_rule_t)rule);
            if (got != want && differ++ < 5)
                print_message("rule %s, motion (%d, %d): %d, exact %d\n", hz_ghat_rule_name((hz_ghat_rule_t)rule),
                              (int)mx, (int)my, (int)got, (int)want);
            const int certain = hz_tdense_ghat_certain(mx, my, (hz_ghat_rule_t)rule);
            if (rule == HZ_GHAT_FULL && kind < 5 && mx && my) {
                ordinary++;
                decided_ordinary += certain >= 0;
            }
            if (rule == HZ_GHAT_FULL && kind >= 5) {
                edges++;
                undecided_edges += certain < 0;
            }
        }
    }
    print_message("ghat: %u of %u ordinary motions decided in double precision, %u of %u built at the edges left "
                  "to the exact code, %u differences\n", decided_ordinary, ordinary, undecided_edges, edges, differ);
    assert_int_equal(differ, 0);
    assert_true(decided_ordinary > ordinary - ordinary / 100);
    assert_true(undecided_edges > edges / 10); /* the edge cases do reach the exact code */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_static_matches_4spp_after_16_frames),
        cmocka_unit_test(test_dynamic_new_direct_old_clamped),
        cmocka_unit_test(test_no_history_after_object_passes),
        cmocka_unit_test(test_reprojection_follows_motion),
        cmocka_unit_test(test_mirror_motion_switch),
        cmocka_unit_test(test_camera_motion_restarts_windows),
        cmocka_unit_test(test_orderings_follow_ghat_once_per_cycle),
        cmocka_unit_test(test_split_and_order_invariance),
        cmocka_unit_test(test_odd_sizes),
        cmocka_unit_test(test_bad_motion_and_first_frame),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_lanes_match_scalar),
        cmocka_unit_test(test_motion_code_lanes_matches_scalar),
        cmocka_unit_test(test_block_motion_lanes_matches_scan),
        cmocka_unit_test(test_ghat_fast_matches_exact),
    };
    return HZ_RUN(tests);
}
