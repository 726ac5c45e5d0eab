/* The full-frame mode: every pixel, opts.spp stratified samples (or the 4x MSAA positions), averaged. */
#include "../render/mode.h"

typedef struct full_state {
    hz_image_t out;
} full_state_t;

static void full_layout(void *state, const hz_render_frame_t *f, hz_memplan_t *p)
{
    full_state_t *s = state;
    s->out.width = f->opts.width, s->out.height = f->opts.height;
    hz_memplan_part(p, HZ_PART_DISPLAY);
    s->out.rgb = hz_memplan_array(p, (size_t)f->opts.width * f->opts.height, 12);
}

static hz_status_t full_init(void *state, const hz_render_frame_t *f, hz_error_t *err)
{
    full_state_t *s = state;
    (void)err;
    hz_memset(s->out.rgb, 0, (size_t)f->opts.width * f->opts.height * 12);
    return HZ_OK;
}

static uint32_t full_items(const void *state, const hz_render_frame_t *f, uint32_t pass)
{
    (void)state, (void)pass;
    return f->tiles_x * f->tiles_y;
}

static void full_run(void *state, hz_render_frame_t *f, uint32_t pass, uint32_t item, hz_batch_t *b)
{
    full_state_t *s = state;
    hz_tile_sampling_t smp = { f->opts.spp, NULL, f->opts.msaa4, 0, 0, false };
    (void)pass;
    hz_render_trace_tile(f, b, item, &smp, &s->out);
}

static const hz_image_t *full_output(const void *state)
{
    return &((const full_state_t *)state)->out;
}

const hz_mode_ops_t hz_mode_full = {
    .name = "full",
    .flags = HZ_MODE_TAKES_MSAA4 | HZ_MODE_KEEPS_SURFACE,
    .state_bytes = sizeof(full_state_t),
    .layout = full_layout,
    .init = full_init,
    .passes = 1,
    .pass_items = full_items,
    .pass_run = full_run,
    .output = full_output,
};
