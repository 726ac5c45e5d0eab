/* Temporal anti-aliasing resolve: this frame's jittered sample blended into the reprojected history after the
 * history is constrained to the neighbourhood's colour distribution (variance clipping, Salvi 2016; clip as in
 * Karis, "High Quality Temporal Supersampling", 2014). Works in YCoCg, where the box is tighter, on linear
 * radiance: Karis' reversible tone map (c / (1 + max c)) would tame flicker next to lights but biases the blend
 * away from the linear average the references are, and measured 0.2 dB worse against them on Sponza. */
#include "taa_internal.h"

#include "hz/dither.h"

/* Where the pixel's camera path took a stochastic transparency decision (seed 004, Sec. 3.2 and 3.3): the
 * variance box comes from a 7x7 neighbourhood (the dither's cells are 3x3 and 5x5: a 3x3 window sees one
 * threshold of each and clamps the accumulated coverage away), and the frame's sample is the mean over the
 * dither's cell around the pixel (3x3 for STD, 5x5 for DTAA; only the cell's dithered pixels, so that a small
 * particle is not spread over the background around it) before it enters the history wherever the camera
 * or the pixel's surface moved (a still pixel keeps its own sample: it walks the whole threshold cycle in place
 * and stays sharp; textured panels seen still lose 5 dB to the cell mean's blur). The dither is a
 * screen-space pattern of period 3 (5): the exponential average weighs the frames of a pixel's 9-frame threshold
 * cycle unequally (0.9^8 = 0.43 from newest to oldest), so per-pixel blending alone leaves that period in the
 * image, and the seed's remedy for a moving camera (motion vectors snapped to the cell so the history continues
 * the same threshold sequence) reads the history up to 1.5 pixels off the surface every frame. The box over one
 * cell holds every threshold once: its response is zero at the pattern's period and harmonics, so no phase
 * reaches the history, which is then read at the true motion. Measured on sponza-smoke, taa std, 320x180,
 * 48 frames from 2 s against exact: 34.7 dB with snapping, 39.4 dB with the cell mean, and the period-3
 * component of the smoke at exact's level (doc/transparency.md). */
/* (HZ_TAA_DITHER_RADIUS, taa_internal.h.) The box is widened there by HZ_TAA_DITHER_GAMMA (1.5): the dither's own
 * spread is signal the history must average, not a change to follow (make report: std within 1 dB of exact on
 * builtin-transp and sponza-smoke with it, 1.0 and 0.3 dB behind without). */
#include "hz/pack.h"


static void to_rgb(const float *y, float *o)
{
    o[0] = y[0] + y[1] - y[2];
    o[1] = y[0] + y[2];
    o[2] = y[0] - y[1] - y[2];
}

/* This frame's sample at pixel (x, y), clamped to the image's edge, as YCoCg. */
static void sample_at(const hz_taa_t *t, int32_t x, int32_t y, float q[3])
{
    const int32_t w = (int32_t)t->out.width, h = (int32_t)t->out.height;
    x = x < 0 ? 0 : x >= w ? w - 1 : x;
    y = y < 0 ? 0 : y >= h ? h - 1 : y;
    const size_t p = (size_t)y * (size_t)w + (size_t)x;
    for (int k = 0; k < 3; k++)
        q[k] = t->cur[k][p];
}

/* The history (half-float RGB, w x h) is an image of the output's size. */
typedef struct history {
    const uint16_t *rgb;
    int32_t width, height;
} history_t;

/* History pixel (x, y), clamped to the edge, as float RGB. */
static void hist_at(const history_t *h, int32_t x, int32_t y, float out[3])
{
    x = x < 0 ? 0 : x >= h->width ? h->width - 1 : x;
    y = y < 0 ? 0 : y >= h->height ? h->height - 1 : y;
    hz_half_unpack3(out, h->rgb + 3 * ((size_t)y * (size_t)h->width + (size_t)x));
}

/* History at continuous position (hx, hy) (pixel centres at +0.5), bilinear. */
static void fetch_bilinear(const history_t *h, float hx, float hy, float out[3])
{
    float fx = hx - 0.5f, fy = hy - 0.5f;
    float x0 = hz_floorf(fx), y0 = hz_floorf(fy);
    float ax = fx - x0, ay = fy - y0;
    int32_t ix = (int32_t)x0, iy = (int32_t)y0;
    float a[3], b[3], c[3], d[3];
    hist_at(h, ix, iy, a), hist_at(h, ix + 1, iy, b), hist_at(h, ix, iy + 1, c), hist_at(h, ix + 1, iy + 1, d);
    for (int k = 0; k < 3; k++) {
        float top = a[k] + (b[k] - a[k]) * ax, bot = c[k] + (d[k] - c[k]) * ax;
        out[k] = top + (bot - top) * ay;
    }
}

static void catmull_rom_weights(float t, float w[4])
{
    float t2 = t * t, t3 = t2 * t;
    w[0] = -0.5f * t3 + t2 - 0.5f * t;
    w[1] = 1.5f * t3 - 2.5f * t2 + 1.0f;
    w[2] = -1.5f * t3 + 2.0f * t2 + 0.5f * t;
    w[3] = 0.5f * t3 - 0.5f * t2;
}

/* History with the 16-tap Catmull-Rom filter: sharper than bilinear, can overshoot (the clip removes that). */
static void fetch_catmull_rom(const history_t *h, float hx, float hy, float out[3])
{
    float fx = hx - 0.5f, fy = hy - 0.5f;
    float x0 = hz_floorf(fx), y0 = hz_floorf(fy);
    float wx[4], wy[4];
    catmull_rom_weights(fx - x0, wx);
    catmull_rom_weights(fy - y0, wy);
    int32_t ix = (int32_t)x0 - 1, iy = (int32_t)y0 - 1;
    out[0] = out[1] = out[2] = 0.0f;
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            float p[3];
            hist_at(h, ix + i, iy + j, p);
            float w = wx[i] * wy[j];
            out[0] += w * p[0], out[1] += w * p[1], out[2] += w * p[2];
        }
}

/* Clips h towards the box centre c along the segment c -> h, so it lies within c +- e. */
static void clip_to_box(float h[3], const float c[3], const float e[3])
{
    float scale = 1.0f;
    for (int k = 0; k < 3; k++) {
        float d = h[k] - c[k];
        float ad = hz_absf(d);
        if (ad > e[k] && ad > 0.0f)
            scale = hz_minf(scale, e[k] / ad);
    }
    for (int k = 0; k < 3; k++)
        h[k] = c[k] + (h[k] - c[k]) * scale;
}

/* Disocclusion: the object now at the pixel was at none of the four previous-frame pixels the history sample
 * blends. Checking all four (not the nearest) keeps edges between two objects from resetting every frame,
 * which would leave them without anti-aliasing. */
static bool seen_before(const hz_render_frame_t *f, const hz_taa_t *t, float hx, float hy, uint16_t object)
{
    int32_t w = (int32_t)f->opts.width, h = (int32_t)f->opts.height;
    int32_t x0 = (int32_t)hz_floorf(hx - 0.5f), y0 = (int32_t)hz_floorf(hy - 0.5f);
    for (int32_t dy = 0; dy <= 1; dy++)
        for (int32_t dx = 0; dx <= 1; dx++) {
            int32_t x = x0 + dx, y = y0 + dy;
            x = x < 0 ? 0 : x >= w ? w - 1 : x;
            y = y < 0 ? 0 : y >= h ? h - 1 : y;
            if (t->prev_object[(size_t)y * (size_t)w + (size_t)x] == object)
                return true;
        }
    return false;
}

/* One pixel (the reference the SIMD tile resolve in taa_lanes.c reproduces bit for bit). */
void hz_taa_resolve_pixel(hz_taa_t *t, const hz_render_frame_t *f, uint32_t x, uint32_t y)
{
    const history_t prev_h = { t->hist[t->hist_index], (int32_t)f->opts.width, (int32_t)f->opts.height };
    const history_t *prev = &prev_h;
    uint16_t *next = t->hist[t->hist_index ^ 1u];
    const hz_gbuffer_t *gb = &f->gb;
    uint32_t w = f->opts.width, h = f->opts.height;
    float gamma = f->opts.taa_gamma, alpha = f->opts.taa_alpha;
    size_t px = (size_t)y * w + x;
    float c[3], sum[3] = { 0, 0, 0 }, sum2[3] = { 0, 0, 0 };
    bool dither = f->dither && (gb->flags[px] & HZ_GB_DITHER);
    const int rad = dither ? HZ_TAA_DITHER_RADIUS : 1;
    if (dither)
        gamma *= HZ_TAA_DITHER_GAMMA;
    const float count = dither ? (float)((2 * HZ_TAA_DITHER_RADIUS + 1) * (2 * HZ_TAA_DITHER_RADIUS + 1)) : 9.0f;
    sample_at(t, (int32_t)x, (int32_t)y, c);
    const int cell = dither ? hz_taa_cell_radius(f) : 0;
    /* A still view keeps the pixel's own sample: it walks the full threshold cycle in place and stays sharp. */
    const bool moving = f->camera_moved || (gb->mv && (gb->mv[px * 2] != 0.0f || gb->mv[px * 2 + 1] != 0.0f));
    if (cell > 0 && moving) {
        float cs[3] = { 0, 0, 0 };
        int n = 0;
        for (int dy = -cell; dy <= cell; dy++)
            for (int dx = -cell; dx <= cell; dx++) {
                int32_t qx = (int32_t)x + dx, qy = (int32_t)y + dy;
                qx = qx < 0 ? 0 : qx >= (int32_t)w ? (int32_t)w - 1 : qx;
                qy = qy < 0 ? 0 : qy >= (int32_t)h ? (int32_t)h - 1 : qy;
                if (!(gb->flags[(size_t)qy * w + (size_t)qx] & HZ_GB_DITHER))
                    continue;
                float q[3];
                sample_at(t, qx, qy, q);
                for (int k = 0; k < 3; k++)
                    cs[k] += q[k];
                n++;
            }
        const float inv = 1.0f / (float)n;
        for (int k = 0; k < 3; k++)
            c[k] = cs[k] * inv;
    }
    for (int dy = -rad; dy <= rad; dy++)
        for (int dx = -rad; dx <= rad; dx++) {
            float q[3];
            sample_at(t, (int32_t)x + dx, (int32_t)y + dy, q);
            for (int k = 0; k < 3; k++)
                sum[k] += q[k], sum2[k] += q[k] * q[k];
        }
    float mean[3], ext[3];
    for (int k = 0; k < 3; k++) {
        mean[k] = sum[k] / count;
        float var = sum2[k] / count - mean[k] * mean[k];
        ext[k] = gamma * hz_sqrtf(var > 0.0f ? var : 0.0f);
    }
    float res[3];
    bool reset = !t->hist_valid;
    float hx = (float)x + 0.5f, hy = (float)y + 0.5f;
    if (!reset && gb->mv) {
        hx += gb->mv[px * 2];
        hy += gb->mv[px * 2 + 1];
    }
    /* Off-screen or disoccluded (another object was there): start over from this frame's sample. */
    if (!reset && !(hx >= 0.0f && hy >= 0.0f && hx < (float)w && hy < (float)h))
        reset = true;
    /* A dithered pixel shows a different fragment from frame to frame: its object changes by design. */
    if (!reset && !dither && !seen_before(f, t, hx, hy, gb->object[px]))
        reset = true;
    if (reset) {
        res[0] = c[0], res[1] = c[1], res[2] = c[2];
    } else {
        float hist_rgb[3], hy3[3];
        if (f->opts.taa_catmull_rom)
            fetch_catmull_rom(prev, hx, hy, hist_rgb);
        else
            fetch_bilinear(prev, hx, hy, hist_rgb);
        hz_taa_to_ycocg(hist_rgb, hy3);
        if (f->opts.taa_clip) {
            clip_to_box(hy3, mean, ext);
        } else {
            for (int k = 0; k < 3; k++)
                hy3[k] = hz_clampf(hy3[k], mean[k] - ext[k], mean[k] + ext[k]);
        }
        for (int k = 0; k < 3; k++)
            res[k] = hy3[k] + alpha * (c[k] - hy3[k]);
    }
    float rgb[3];
    to_rgb(res, rgb);
    for (int k = 0; k < 3; k++) {
        float v = hz_isfinitef(rgb[k]) && rgb[k] > 0.0f ? rgb[k] : 0.0f;
        t->out.rgb[px * 3 + k] = v;
    }
    hz_half_pack3(next + px * 3, t->out.rgb + px * 3);
}

void hz_taa_resolve_tile_scalar(hz_taa_t *t, const hz_render_frame_t *f, uint32_t tile)
{
    uint32_t w = f->opts.width, h = f->opts.height;
    uint32_t x0 = (tile % f->tiles_x) * HZ_RENDER_TILE, y0 = (tile / f->tiles_x) * HZ_RENDER_TILE;
    for (uint32_t y = y0; y < y0 + HZ_RENDER_TILE && y < h; y++)
        for (uint32_t x = x0; x < x0 + HZ_RENDER_TILE && x < w; x++)
            hz_taa_resolve_pixel(t, f, x, y);
}

void hz_taa_store_samples_scalar(hz_taa_t *t, hz_batch_t *b)
{
    for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++)
        if (b->pixel[slot] != UINT32_MAX)
            hz_taa_store_slot(t, b, slot);
}

static void resolve_tiles_scalar(hz_taa_t *t, const hz_render_frame_t *f, uint32_t first, uint32_t count)
{
    for (uint32_t i = 0; i < count; i++)
        hz_taa_resolve_tile_scalar(t, f, first + i);
}

#if !defined(HZ_BOARD_SIMD_AVX2) && !defined(HZ_BOARD_SIMD_NEON) /* the Makefile builds taa_lanes.c then */
void hz_taa_resolve_tiles(hz_taa_t *t, const hz_render_frame_t *f, uint32_t first, uint32_t count)
{
    resolve_tiles_scalar(t, f, first, count);
}

void hz_taa_store_samples(hz_taa_t *t, hz_batch_t *b)
{
    hz_taa_store_samples_scalar(t, b);
}
#endif

/* ---- the mode (mode.h) ---- */

static void taa_layout(void *state, const hz_render_frame_t *f, hz_memplan_t *p)
{
    hz_taa_t *t = state;
    const size_t px = (size_t)f->opts.width * f->opts.height;
    t->out.width = f->opts.width;
    t->out.height = f->opts.height;
    hz_memplan_part(p, HZ_PART_DISPLAY);
    t->out.rgb = hz_memplan_array(p, px, 12);
    hz_memplan_part(p, HZ_PART_STATE);
    for (int k = 0; k < 3; k++)
        t->cur[k] = hz_memplan_array(p, px, sizeof(float));
    t->hist[0] = hz_memplan_array(p, px, 6);
    t->hist[1] = hz_memplan_array(p, px, 6);
    t->prev_object = hz_memplan_array(p, px, 2);
}

static hz_status_t taa_init(void *state, const hz_render_frame_t *f, hz_error_t *err)
{
    hz_taa_t *t = state;
    (void)err;
    hz_memset(t->out.rgb, 0, (size_t)f->opts.width * f->opts.height * 12);
    return HZ_OK;
}

static float halton(uint32_t i, uint32_t base)
{
    float f = 1.0f, v = 0.0f;
    while (i > 0) {
        f /= (float)base;
        v += f * (float)(i % base);
        i /= base;
    }
    return v;
}

static void taa_begin(void *state, const hz_render_frame_t *f)
{
    hz_taa_t *t = state;
    /* Halton (2, 3), 16 phases, centred on the pixel. */
    uint32_t phase = (uint32_t)(f->frame % 16u) + 1u;
    t->jitter[0] = halton(phase, 2) - 0.5f;
    t->jitter[1] = halton(phase, 3) - 0.5f;
}

/* The resolve's work items and overlap units are runs of RUN tiles along a tile row (the last run of a row may
 * be shorter): long enough that prefetching the next tile pays, short enough that the frame's tail is short. */
#define RUN 8u

static uint32_t runs_per_row(const hz_render_frame_t *f)
{
    return (f->tiles_x + RUN - 1u) / RUN;
}

static uint32_t taa_items(const void *state, const hz_render_frame_t *f, uint32_t pass)
{
    (void)state;
    return pass == 0 ? f->tiles_x * f->tiles_y : runs_per_row(f) * f->tiles_y;
}

static void taa_resolve(hz_taa_t *t, const hz_render_frame_t *f, uint32_t run)
{
    const uint32_t rpr = runs_per_row(f), row = run / rpr, first = (run % rpr) * RUN;
    const uint32_t count = f->tiles_x - first < RUN ? f->tiles_x - first : RUN;
    (f->opts.scalar_recon ? resolve_tiles_scalar : hz_taa_resolve_tiles)(t, f, row * f->tiles_x + first, count);
}

static void taa_run(void *state, hz_render_frame_t *f, uint32_t pass, uint32_t item, hz_batch_t *b)
{
    hz_taa_t *t = state;
    if (pass == 0) {
        /* One jittered sample per pixel; with motion blur its time walks 16 frames. */
        hz_tile_sampling_t smp = { 1, t->jitter, false, (uint32_t)(f->frame % 16u), 16, false };
        hz_render_sample_tile(f, b, item, &smp);
        (f->opts.scalar_recon ? hz_taa_store_samples_scalar : hz_taa_store_samples)(t, b);
    } else {
        taa_resolve(t, f, item);
    }
}

/* Overlap: one run of tiles per unit; its 3x3 or 7x7 window stays within the tile rows next to it. */
static uint32_t taa_units(const void *state, const hz_render_frame_t *f)
{
    return taa_items(state, f, 1);
}

static void taa_needs(const void *state, const hz_render_frame_t *f, uint32_t unit, uint32_t *lo, uint32_t *hi)
{
    const uint32_t row = unit / runs_per_row(f);
    (void)state;
    *lo = row ? row - 1u : 0u;
    *hi = row + 1u;
}

static void taa_overlap_run(void *state, hz_render_frame_t *f, uint32_t unit)
{
    if (unit < taa_units(state, f))
        taa_resolve(state, f, unit);
}

static void taa_end(void *state, const hz_render_frame_t *f)
{
    hz_taa_t *t = state;
    t->hist_index ^= 1u; /* the history just written becomes the previous frame's */
    t->hist_valid = true;
    hz_memcpy(t->prev_object, f->gb.object, (size_t)f->opts.width * f->opts.height * 2);
}

static const hz_image_t *taa_output(const void *state)
{
    return &((const hz_taa_t *)state)->out;
}

static void taa_reset(void *state, const hz_render_frame_t *f)
{
    (void)f;
    ((hz_taa_t *)state)->hist_valid = false;
}

const hz_mode_ops_t hz_mode_taa = {
    .name = "taa",
    .state_bytes = sizeof(hz_taa_t),
    .layout = taa_layout,
    .init = taa_init,
    .begin_frame = taa_begin,
    .passes = 2,
    .pass_items = taa_items,
    .pass_run = taa_run,
    .overlap_units = taa_units,
    .overlap_needs = taa_needs,
    .overlap_run = taa_overlap_run,
    .end_frame = taa_end,
    .output = taa_output,
    .reset = taa_reset,
};
