/* The built-in analytic errtime scene and its methods (see et_synthetic.h). */
#include "et_synthetic.h"

#include <math.h>

#include "hz/hash.h"
#include "hz/tdense.h"

/* What a frame's time fixes: the checkerboard's rotation and the disc's position (no trig per sample). */
typedef struct synth_frame {
    float cx, cy, square, ca, sa, disc_x, disc_r;
    float dca, dsa, disc_dx; /* motion since the previous frame: rotation by (angle - previous angle), disc step */
} synth_frame_t;

static void frame_setup(synth_frame_t *f, float t, uint32_t width, uint32_t height)
{
    f->cx = 0.5f * (float)width;
    f->cy = 0.5f * (float)height;
    f->square = (float)height / 7.0f;
    f->ca = cosf(0.3f * t); /* the checkerboard turns at 0.3 rad/s around the centre */
    f->sa = sinf(0.3f * t);
    f->disc_x = f->cx + 0.3f * (float)width * sinf(3.14159265f * t); /* left and right every two seconds */
    f->disc_r = 0.22f * (float)height;
    f->dca = f->dsa = f->disc_dx = 0.0f;
}

/* frame_setup plus the motion from time t_prev to t, for methods that need motion vectors. */
static void frame_setup_motion(synth_frame_t *f, float t, float t_prev, uint32_t width, uint32_t height)
{
    frame_setup(f, t, width, height);
    f->dca = cosf(0.3f * (t - t_prev));
    f->dsa = sinf(0.3f * (t - t_prev));
    f->disc_dx = f->disc_x - (f->cx + 0.3f * (float)width * sinf(3.14159265f * t_prev));
}

/* Screen motion (previous minus current position, pixels, as the renderer's G-buffer has it) of what is seen
 * at (x, y): the disc's step inside it, else the board's rotation: a board point now at p was at
 * c + R(a - a_prev)(p - c). */
static void motion(const synth_frame_t *f, float x, float y, float mv[2])
{
    float dx = x - f->disc_x, dy = y - f->cy;
    if (dx * dx + dy * dy < f->disc_r * f->disc_r) {
        mv[0] = -f->disc_dx;
        mv[1] = 0.0f;
        return;
    }
    float px = x - f->cx, py = y - f->cy;
    mv[0] = (px * f->dca - py * f->dsa) - px;
    mv[1] = (px * f->dsa + py * f->dca) - py;
}

static void shade(const synth_frame_t *f, float x, float y, float rgb[3])
{
    float u = ((x - f->cx) * f->ca - (y - f->cy) * f->sa) / f->square;
    float v = ((x - f->cx) * f->sa + (y - f->cy) * f->ca) / f->square;
    bool odd = ((int)floorf(u) + (int)floorf(v)) & 1;
    rgb[0] = odd ? 0.80f : 0.04f;
    rgb[1] = odd ? 0.72f : 0.09f;
    rgb[2] = odd ? 0.55f : 0.20f;
    float dx = x - f->disc_x, dy = y - f->cy;
    if (dx * dx + dy * dy < f->disc_r * f->disc_r) {
        rgb[0] = 0.90f;
        rgb[1] = 0.25f;
        rgb[2] = 0.08f;
    }
}

void hz_synth_shade(float x, float y, float t, uint32_t width, uint32_t height, float rgb[3])
{
    synth_frame_t f;
    frame_setup(&f, t, width, height);
    shade(&f, x, y, rgb);
}

typedef struct synth_params {
    uint32_t spp;   /* supersample */
    float alpha;    /* accumulate; 0 for supersample */
    uint32_t salt;  /* jitter stream: the reference uses its own */
} synth_params_t;

typedef struct synth_state {
    const synth_params_t *p;
    const hz_et_sequence_t *seq;
    bool has_history;
} synth_state_t;

static float unit(uint32_t h)
{
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

static hz_status_t synth_begin(const hz_et_method_t *m, const hz_et_sequence_t *seq, hz_arena_t *arena, void **state,
                               hz_error_t *err)
{
    synth_state_t *st = hz_arena_alloc(arena, sizeof *st, 16);
    if (!st) {
        hz_arena_error(arena, err);
        return HZ_E_NO_MEMORY;
    }
    st->p = m->params;
    st->seq = seq;
    st->has_history = false;
    *state = st;
    return HZ_OK;
}

/* Box-filtered estimate of pixel (px, py) from n samples of stream `salt`. */
static void estimate(const synth_state_t *st, const synth_frame_t *f, uint32_t px, uint32_t py, uint32_t frame,
                     uint32_t n, float rgb[3])
{
    uint32_t side = (uint32_t)(sqrtf((float)n) + 0.5f);
    bool grid = side * side == n;
    float acc[3] = { 0, 0, 0 };
    for (uint32_t s = 0; s < n; s++) {
        uint32_t h = hz_hash3(px + (py << 16), frame * 7919u + st->p->salt, s);
        float jx = unit(h), jy = unit(hz_hash32(h ^ 0x9e3779b9u));
        float sx = grid ? ((float)(s % side) + jx) / (float)side : jx;
        float sy = grid ? ((float)(s / side) + jy) / (float)side : jy;
        float c[3];
        shade(f, (float)px + sx, (float)py + sy, c);
        acc[0] += c[0];
        acc[1] += c[1];
        acc[2] += c[2];
    }
    for (int c = 0; c < 3; c++)
        rgb[c] = acc[c] / (float)n;
}

static hz_status_t synth_render(void *state, uint32_t frame, hz_image_t *out, uint64_t *rays, hz_error_t *err)
{
    synth_state_t *st = state;
    (void)err;
    const synth_params_t *p = st->p;
    synth_frame_t f;
    frame_setup(&f, (float)frame / (float)st->seq->refresh_hz, out->width, out->height);
    for (uint32_t y = 0; y < out->height; y++)
        for (uint32_t x = 0; x < out->width; x++) {
            float c[3], *o = hz_image_at(out, x, y);
            if (p->alpha > 0.0f) {
                estimate(st, &f, x, y, frame, 1, c);
                float a = st->has_history ? p->alpha : 1.0f;
                for (int k = 0; k < 3; k++)
                    o[k] = a * c[k] + (1.0f - a) * o[k]; /* out keeps the history between calls */
            } else {
                estimate(st, &f, x, y, frame, p->spp, o);
            }
        }
    st->has_history = true;
    *rays = (uint64_t)out->width * out->height * (p->alpha > 0.0f ? 1u : p->spp);
    return HZ_OK;
}

/* Temporally dense (hz/tdense.h): one sample per 2x2 tile per frame at the pixel the tile's ordering names,
 * jittered to the 4x MSAA positions where static, composited by the reconstruction. */
typedef struct synth_tdense {
    const hz_et_sequence_t *seq;
    hz_tdense_t td;
} synth_tdense_t;

static hz_status_t tdense_begin(const hz_et_method_t *m, const hz_et_sequence_t *seq, hz_arena_t *arena,
                                void **state, hz_error_t *err)
{
    (void)m;
    synth_tdense_t *st = hz_arena_alloc(arena, sizeof *st, 16);
    if (!st) {
        hz_arena_error(arena, err);
        return HZ_E_NO_MEMORY;
    }
    st->seq = seq;
    hz_tdense_config_t cfg = hz_tdense_config_default(seq->width, seq->height);
    hz_status_t s = hz_tdense_init(&st->td, &cfg, arena, err);
    *state = st;
    return s;
}

static hz_status_t tdense_render(void *state, uint32_t frame, hz_image_t *out, uint64_t *rays, hz_error_t *err)
{
    synth_tdense_t *st = state;
    float hz = (float)st->seq->refresh_hz;
    synth_frame_t f;
    frame_setup_motion(&f, (float)frame / hz, (float)(frame ? frame - 1 : 0) / hz, out->width, out->height);
    hz_tdense_begin_frame(&st->td, false);
    uint64_t n = 0;
    for (uint32_t ty = 0; ty < st->td.tiles_y; ty++)
        for (uint32_t tx = 0; tx < st->td.tiles_x; tx++) {
            uint32_t px, py;
            float j[2], c[3], mv[2];
            int msaa;
            if (!hz_tdense_tile_sample(&st->td, tx, ty, &px, &py, j, &msaa))
                continue;
            float x = (float)px + 0.5f + j[0], y = (float)py + 0.5f + j[1];
            shade(&f, x, y, c);
            motion(&f, x, y, mv);
            hz_tdense_put(&st->td, tx, ty, c, mv, NULL);
            n++;
        }
    hz_tdense_resolve_rows(&st->td, 0, st->td.tiles_y);
    hz_tdense_end_frame(&st->td);
    *rays = n;
    return hz_image_copy(out, hz_tdense_output(&st->td), err);
}

static const synth_params_t ref_params = { 256, 0.0f, 0x5eed };
static const synth_params_t ss1 = { 1, 0.0f, 1 }, ss4 = { 4, 0.0f, 1 }, ss9 = { 9, 0.0f, 1 }, ss16 = { 16, 0.0f, 1 };
static const synth_params_t acc50 = { 1, 0.5f, 2 }, acc20 = { 1, 0.2f, 2 }, acc10 = { 1, 0.1f, 2 };

const hz_et_method_t hz_synth_reference = { "supersample", "spp", 256, synth_begin, synth_render, NULL, &ref_params,
                                            0, NULL };

const hz_et_method_t hz_synth_methods[HZ_SYNTH_METHOD_COUNT] = {

    { "supersample", "spp", 1, synth_begin, synth_render, NULL, &ss1, 0, NULL },
    { "supersample", "spp", 4, synth_begin, synth_render, NULL, &ss4, 0, NULL },
    { "supersample", "spp", 9, synth_begin, synth_render, NULL, &ss9, 0, NULL },
    { "supersample", "spp", 16, synth_begin, synth_render, NULL, &ss16, 0, NULL },
    { "accumulate", "alpha", 0.5, synth_begin, synth_render, NULL, &acc50, 0, NULL },
    { "accumulate", "alpha", 0.2, synth_begin, synth_render, NULL, &acc20, 0, NULL },
    { "accumulate", "alpha", 0.1, synth_begin, synth_render, NULL, &acc10, 0, NULL },
    { "supersample@60Hz", "spp", 1, synth_begin, synth_render, NULL, &ss1, 4, NULL },
    { "accumulate@60Hz", "alpha", 0.1, synth_begin, synth_render, NULL, &acc10, 4, NULL },
    { "tdense", "hz", 240, tdense_begin, tdense_render, NULL, NULL, 0, NULL },
};
