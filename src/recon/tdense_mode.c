/* The temporally dense mode (seed 001): each frame traces the pixel its 2x2 tile's ordering names and the
 * compositor (tdense.c, hz/tdense.h) resolves the displayed frame from it. */
#include "../render/mode.h"
#include "tdense_internal.h"

/* The compositor's plan parts are the renderer's. */
typedef char parts_agree[(int)HZ_TDENSE_PART_STATE == (int)HZ_PART_STATE &&
                         (int)HZ_TDENSE_PART_DISPLAY == (int)HZ_PART_DISPLAY ? 1 : -1];

static hz_tdense_config_t config_of(const hz_render_frame_t *f)
{
    hz_tdense_config_t tc = hz_tdense_config_default(f->opts.width, f->opts.height);
    tc.rule = f->opts.tdense_rule;
    tc.seed = f->opts.seed;
    tc.reflect_mv = f->opts.tdense_reflect_mv;
    tc.gamma = f->opts.tdense_gamma;
    tc.motion = f->need_mv;
    return tc;
}

static void td_layout(void *state, const hz_render_frame_t *f, hz_memplan_t *p)
{
    hz_tdense_config_t tc = config_of(f);
    hz_tdense_layout(state, &tc, p);
}

static hz_status_t td_init(void *state, const hz_render_frame_t *f, hz_error_t *err)
{
    hz_tdense_config_t tc = config_of(f);
    hz_status_t s = hz_tdense_check(&tc, err);
    if (s == HZ_OK)
        hz_tdense_reset(state);
    return s;
}

static uint32_t td_key_frames(const hz_render_opts_t *o)
{
    return o->tdense_cycle_keys ? 4u : 1u; /* one key interval and refit per 4-subframe cycle */
}

static uint32_t td_key_phase(const void *state)
{
    return ((const hz_tdense_t *)state)->frame % 4u;
}

static void td_begin(void *state, const hz_render_frame_t *f)
{
    hz_tdense_begin_frame(state, f->camera_moved); /* any camera change restarts every static window (3.2.2) */
}

/* A trace item is an area of SPAN x SPAN tdense tiles (16x16 pixels): its SPAN^2 = HZ_TILE_PIXELS camera rays
 * fill one batch, so the traversal's tile test, the batch's set-up and the packets it fills serve four times the
 * rays that an 8x8-pixel render tile (16 tdense tiles) would give it. */
enum { SPAN = HZ_RENDER_TILE };
typedef char span_fills_batch[SPAN * SPAN == HZ_TILE_PIXELS ? 1 : -1];

static uint32_t areas_x(const hz_tdense_t *td)
{
    return (td->tiles_x + SPAN - 1u) / SPAN;
}

static uint32_t areas_y(const hz_tdense_t *td)
{
    return (td->tiles_y + SPAN - 1u) / SPAN;
}

static uint32_t td_items(const void *state, const hz_render_frame_t *f, uint32_t pass)
{
    (void)f;
    /* the resolve works on whole rows (its 3x3 neighbourhoods span tiles): one item per row of areas */
    return pass == 1 ? areas_y(state) : areas_x(state) * areas_y(state);
}

static void td_trace_grid(const void *state, const hz_render_frame_t *f, uint32_t *rows, uint32_t *row_items)
{
    (void)f;
    *rows = areas_y(state), *row_items = areas_x(state);
}

/* The item traces one pixel of each of its tdense tiles, the one the tile's ordering names for this subframe
 * (jittered where static). Slots go packet by packet over blocks of 4x2 tdense tiles (2x2 with 4 lanes), as
 * hz_tile_slots lays out pixels, and the chosen pixels are packed to the front so packets stay full; the other
 * slots stay empty (UINT32_MAX), which hz_render_trace skips. */
static void trace_tile(hz_tdense_t *td, hz_render_frame_t *f, uint32_t item, hz_batch_t *b)
{
    enum { PW = HZ_RENDER_LANES == 8 ? 4 : 2, PH = HZ_RENDER_LANES / PW };
    float jitter[HZ_TILE_PIXELS][2], times[HZ_TILE_PIXELS];
    uint32_t where[HZ_TILE_PIXELS]; /* the slot's tdense tile (index) */
    int8_t msaa_of[HZ_TILE_PIXELS];
    const uint32_t ax = areas_x(td);
    uint32_t tx0 = (item % ax) * SPAN, ty0 = (item / ax) * SPAN, n = 0;
    for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++)
        b->pixel[slot] = UINT32_MAX;
    for (uint32_t k = 0; k < SPAN * SPAN; k++) {
        uint32_t packet = k / HZ_RENDER_LANES, lane = k % HZ_RENDER_LANES;
        uint32_t tx = tx0 + (packet % (SPAN / PW)) * PW + lane % PW;
        uint32_t ty = ty0 + (packet / (SPAN / PW)) * PH + lane / PW, px, py;
        int msaa;
        if (tx >= td->tiles_x || ty >= td->tiles_y || !hz_tdense_sample_at(td, tx, ty, &px, &py, jitter[n], &msaa))
            continue;
        b->pixel[n] = py * f->opts.width + px;
        where[n] = ty * td->tiles_x + tx;
        msaa_of[n] = (int8_t)msaa;
        /* A pixel is traced once per cycle: its times are stratified over 4 cycles (the static window). */
        if (HZ_FEATURE_MOTION && f->blur)
            times[n] = hz_render_sample_time(f, b->pixel[n], (td->frame / 4u) % 4u, 4u);
        n++;
    }
    hz_memset(b->radiance, 0, sizeof b->radiance);
    b->dither_frame = (uint32_t)f->frame;
    hz_render_trace(f, b, (const float(*)[2])jitter, HZ_FEATURE_MOTION && f->blur ? times : NULL, true);
    const hz_gbuffer_t *gb = &f->gb;
    static const float still[2] = { 0.0f, 0.0f };
    for (uint32_t slot = 0; slot < n; slot++) {
        uint32_t px = b->pixel[slot];
        float c[3];
        hz_render_store(b, c, &b->radiance[slot * 3], 1.0f);
        const float *mv = gb->mv ? gb->mv + (size_t)px * 2 : still;
        const float *mvr = gb->mv_reflect && (gb->flags[px] & HZ_GB_MIRROR) ? gb->mv_reflect + (size_t)px * 2 : NULL;
        /* the placement the sampling found (no resolve touches these tiles' flags before their unit) */
        hz_tdense_put_sample(td, where[slot], px, msaa_of[slot], c, mv, mvr);
    }
}

/* The tdense tile rows [r0, r1) (pixel rows 2 r0 .. 2 r1 - 1). */
static void resolve_rows(hz_tdense_t *td, const hz_render_frame_t *f, uint32_t r0, uint32_t r1)
{
    (f->opts.scalar_recon ? hz_tdense_resolve_rows_scalar : hz_tdense_resolve_rows)(td, r0, r1);
}

static void td_run(void *state, hz_render_frame_t *f, uint32_t pass, uint32_t item, hz_batch_t *b)
{
    if (pass == 0)
        trace_tile(state, f, item, b);
    else
        resolve_rows(state, f, item * SPAN, (item + 1) * SPAN);
}

/* Overlap: one unit resolves the tdense tile rows of one trace row (SPAN of them, the barrier pass's items:
 * single tdense rows measured 3-5% slower frames at 2 threads, from the resolve's per-call setup and more
 * switching between tracing and resolving). */
static uint32_t td_units(const void *state, const hz_render_frame_t *f)
{
    (void)f;
    return areas_y(state);
}

static void td_needs(const void *state, const hz_render_frame_t *f, uint32_t unit, uint32_t *lo, uint32_t *hi)
{
    (void)state, (void)f;
    /* the unit's tdense rows and the rows above and below them lie in trace rows u - 1 .. u + 1 */
    *lo = unit ? unit - 1u : 0u;
    *hi = unit + 1u;
}

static void td_overlap_run(void *state, hz_render_frame_t *f, uint32_t unit)
{
    hz_tdense_t *td = state;
    if (unit * SPAN < td->tiles_y)
        resolve_rows(td, f, unit * SPAN, (unit + 1u) * SPAN);
}

static void td_end(void *state, const hz_render_frame_t *f)
{
    (void)f;
    hz_tdense_end_frame(state);
}

static const hz_image_t *td_output(const void *state)
{
    return hz_tdense_output(state);
}

static void td_reset(void *state, const hz_render_frame_t *f)
{
    (void)f;
    hz_tdense_reset(state);
}

const hz_mode_ops_t hz_mode_tdense = {
    .name = "tdense",
    .state_bytes = sizeof(hz_tdense_t),
    .layout = td_layout,
    .init = td_init,
    .key_frames = td_key_frames,
    .key_phase = td_key_phase,
    .begin_frame = td_begin,
    .passes = 2,
    .pass_items = td_items,
    .pass_run = td_run,
    .overlap_units = td_units,
    .trace_grid = td_trace_grid,
    .overlap_needs = td_needs,
    .overlap_run = td_overlap_run,
    .end_frame = td_end,
    .output = td_output,
    .reset = td_reset,
};

const struct hz_tdense *hz_render_tdense(const hz_renderer_t *r)
{
    return hz_render_mode_state(r, &hz_mode_tdense);
}
