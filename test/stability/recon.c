/* Stage reconstruction: the temporally dense compositor (hz/tdense.h, driven directly with synthetic samples)
 * and TAA / tdense inside the renderer. Oracles: a constant input must come out unchanged (zero-variance boxes),
 * a reset mid-sequence must give exactly what a fresh instance gives, and non-finite or huge inputs must not
 * make the output non-finite once finite samples come again (or ever, for huge finite values). */
#include <stdlib.h>

#include "hz/pack.h"
#include "hz/tdense.h"
#include "stab_util.h"

#define TW 24
#define TH 18

typedef void (*sample_fn)(uint32_t frame, uint32_t x, uint32_t y, float rgb[3], float mv[2]);

static hz_status_t td_open(hz_tdense_t *td, hz_error_t *err)
{
    hz_tdense_config_t c = hz_tdense_config_default(TW, TH);
    return hz_tdense_init(td, &c, &hz_pools_get()->frame, err);
}

/* One frame of the compositor; `frame` is the caller's clock (what the samples depend on). */
static void td_frame(hz_tdense_t *td, uint32_t frame, sample_fn f)
{
    hz_tdense_begin_frame(td, false);
    for (uint32_t ty = 0; ty < td->tiles_y; ty++)
        for (uint32_t tx = 0; tx < td->tiles_x; tx++) {
            uint32_t px, py;
            float j[2], rgb[3], mv[2];
            int msaa;
            if (!hz_tdense_tile_sample(td, tx, ty, &px, &py, j, &msaa))
                continue;
            f(frame, px, py, rgb, mv);
            hz_tdense_put(td, tx, ty, rgb, mv, NULL);
        }
    hz_tdense_resolve_rows(td, 0, td->tiles_y);
    hz_tdense_end_frame(td);
}

static uint32_t count_nonfinite(const hz_image_t *img)
{
    uint32_t c = 0;
    for (size_t i = 0; i < 3 * hz_image_pixels(img); i++)
        c += !isfinite(img->rgb[i]);
    return c;
}

static void s_const_static(uint32_t f, uint32_t x, uint32_t y, float rgb[3], float mv[2])
{
    (void)f, (void)x, (void)y;
    rgb[0] = 0.25f, rgb[1] = 0.5f, rgb[2] = 0.75f, mv[0] = mv[1] = 0.0f;
}

static void s_const_moving(uint32_t f, uint32_t x, uint32_t y, float rgb[3], float mv[2])
{
    s_const_static(f, x, y, rgb, mv);
    mv[0] = 1.37f, mv[1] = -0.61f;
}

/* A constant colour, static and moving: every box has zero variance; after the first full cycle every pixel
 * shows exactly that colour. */
static void c_tdense_zero_variance(stab_result_t *r)
{
    hz_error_t err;
    for (int moving = 0; moving < 2; moving++) {
        hz_tdense_t td;
        STAB_OK(r, td_open(&td, &err), &err);
        for (uint32_t f = 0; f < 24; f++) {
            td_frame(&td, f, moving ? s_const_moving : s_const_static);
            const hz_image_t *o = hz_tdense_output(&td);
            stab_count_nonfinite(r, o->rgb, 3 * hz_image_pixels(o));
            if (f < 4)
                continue;
            for (size_t i = 0; i < hz_image_pixels(o); i++)
                for (int c = 0; c < 3; c++)
                    stab_error(r, fabs(o->rgb[3 * i + (size_t)c] - 0.25 * (c + 1)));
        }
    }
    stab_note(r, "constant input static and moving: max deviation %.3g", r->max_error);
    STAB_CHECK(r, r->max_error == 0.0, "a zero-variance box changed a constant by %g", r->max_error);
}

static float g_bad = NAN;
static uint32_t g_bad_frame = 6;
static int g_moving = 0;

/* A smooth gradient; at frame g_bad_frame one sample (near the centre) is g_bad. */
static void s_spike(uint32_t f, uint32_t x, uint32_t y, float rgb[3], float mv[2])
{
    rgb[0] = 0.1f + 0.02f * (float)x, rgb[1] = 0.2f + 0.01f * (float)y, rgb[2] = 0.5f;
    mv[0] = g_moving ? 0.8f : 0.0f, mv[1] = 0.0f;
    if (f == g_bad_frame && x / 2 == TW / 4 && y / 2 == TH / 4)
        rgb[0] = rgb[1] = rgb[2] = g_bad;
}

/* A NaN or Inf sample reaching the compositor (a broken tracer) shows, as documented, but does not stay: 16
 * frames after it, with finite samples only, every pixel is finite again. Also: how far it spread. */
static void spike_case(stab_result_t *r, float bad, int moving)
{
    hz_error_t err;
    hz_tdense_t td;
    STAB_OK(r, td_open(&td, &err), &err);
    g_bad = bad, g_moving = moving;
    uint32_t worst = 0, last_bad = 0;
    for (uint32_t f = 0; f < 40; f++) {
        td_frame(&td, f, s_spike);
        uint32_t n = count_nonfinite(hz_tdense_output(&td));
        if (n > worst)
            worst = n;
        if (n)
            last_bad = f;
    }
    stab_note(r, "%s %s: at most %u non-finite values; the last in frame %u (injected in %u)",
              isnan(bad) ? "NaN" : "Inf", moving ? "moving" : "static", worst, last_bad, g_bad_frame);
    STAB_CHECK(r, last_bad <= g_bad_frame + 16, "non-finite values persist until frame %u", last_bad);
    STAB_CHECK(r, worst <= 3 * 9, "one bad sample spread to %u values", worst);
    const hz_image_t *o = hz_tdense_output(&td);
    stab_count_nonfinite(r, o->rgb, 3 * hz_image_pixels(o));
}

static void c_tdense_nan_static(stab_result_t *r) { spike_case(r, NAN, 0); }
static void c_tdense_nan_moving(stab_result_t *r) { spike_case(r, NAN, 1); }
static void c_tdense_inf_static(stab_result_t *r) { spike_case(r, INFINITY, 0); }
static void c_tdense_inf_moving(stab_result_t *r) { spike_case(r, INFINITY, 1); }

static float g_mv;
static void s_huge_mv(uint32_t f, uint32_t x, uint32_t y, float rgb[3], float mv[2])
{
    s_spike(1000 + f, x, y, rgb, mv);
    mv[0] = (f % 2) ? g_mv : -g_mv, mv[1] = (f % 3) ? g_mv : 0.0f;
}

/* Motion vectors of 1e30, Inf, -Inf and NaN (sanitised to +-16384 px / 0) and the ĝ choice at those: the output
 * stays finite, the tile orderings valid. */
static void c_tdense_huge_motion(stab_result_t *r)
{
    const float mvs[] = { 1e30f, INFINITY, -INFINITY, NAN, 16384.5f, -1e-45f };
    hz_error_t err;
    for (size_t k = 0; k < sizeof mvs / sizeof mvs[0]; k++) {
        hz_tdense_t td;
        STAB_OK(r, td_open(&td, &err), &err);
        g_mv = mvs[k];
        for (uint32_t f = 0; f < 12; f++) {
            td_frame(&td, f, s_huge_mv);
            const hz_image_t *o = hz_tdense_output(&td);
            stab_count_nonfinite(r, o->rgb, 3 * hz_image_pixels(o));
            for (uint32_t ty = 0; ty < td.tiles_y; ty++)
                for (uint32_t tx = 0; tx < td.tiles_x; tx++)
                    STAB_CHECK(r, hz_tdense_tile_order(&td, tx, ty) < HZ_TILEORDER_COUNT, "bad tile ordering");
        }
        for (size_t i = 0; i < 2 * hz_image_pixels(&td.out); i++) {
            float m = hz_half_unpack(td.mv[i]); /* stored as half floats */
            STAB_CHECK(r, fabsf(m) <= HZ_TDENSE_MAX_MOTION, "stored motion %g beyond the clamp", (double)m);
        }
    }
    stab_note(r, "mv 1e30; +-Inf; NaN; 16384.5; -1e-45: finite; motion clamped to +-%g px",
              (double)HZ_TDENSE_MAX_MOTION);
}

/* Reset after 12 frames, then 12 more, against a fresh instance given the same 12: bit-identical. */
static void c_tdense_reset_mid_sequence(stab_result_t *r)
{
    hz_error_t err;
    hz_tdense_t a, b;
    STAB_OK(r, td_open(&a, &err), &err);
    STAB_OK(r, td_open(&b, &err), &err);
    g_moving = 1, g_bad_frame = 1000;
    for (uint32_t f = 0; f < 12; f++)
        td_frame(&a, f, s_spike);
    hz_tdense_reset(&a);
    for (uint32_t f = 12; f < 24; f++) {
        td_frame(&a, f, s_spike);
        td_frame(&b, f, s_spike);
        const hz_image_t *oa = hz_tdense_output(&a), *ob = hz_tdense_output(&b);
        STAB_CHECK(r, memcmp(oa->rgb, ob->rgb, sizeof(float) * 3 * hz_image_pixels(oa)) == 0,
                   "frame %u after the reset differs from a fresh compositor", f);
        stab_count_nonfinite(r, oa->rgb, 3 * hz_image_pixels(oa));
    }
    stab_note(r, "12 frames after a reset bit-identical to a fresh instance");
}

/* ---- inside the renderer ---- */

static void room(su_scene_t *b, float light_power)
{
    su_begin(b);
    su_room(b, 1.0f);
    b->light[0].color[0] = b->light[0].color[1] = b->light[0].color[2] = light_power;
    b->ncam = 0;
    const float e0[3] = { -1, 1.5f, 6 }, e1[3] = { 1, 1.8f, 5 }, t[3] = { 0, 1.2f, 0 };
    su_camera(b, 0.0f, e0, t, 0.9f);
    su_camera(b, 1.0f, e1, t, 0.9f);
}

/* TAA / tdense renderer reset after 8 frames, then 8 more, against a fresh renderer on the same frames. */
static void reset_case(stab_result_t *r, hz_render_mode_t mode)
{
    su_scene_t b;
    room(&b, 20.0f);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = 40, o.height = 24, o.mode = mode;
    su_render_t A, B;
    hz_error_t err;
    STAB_OK(r, su_render_open(&A, &b, &o, &err), &err);
    STAB_OK(r, su_render_open(&B, &b, &o, &err), &err);
    for (uint32_t f = 0; f < 8; f++)
        STAB_OK(r, su_render_frame(&A, f, (float)f / 30.0f, &err), &err);
    hz_render_reset_history(A.r);
    for (uint32_t f = 8; f < 16; f++) {
        STAB_OK(r, su_render_frame(&A, f, (float)f / 30.0f, &err), &err);
        STAB_OK(r, su_render_frame(&B, f, (float)f / 30.0f, &err), &err);
        su_render_check(r, &A);
        const hz_image_t *ia = hz_render_output(A.r), *ib = hz_render_output(B.r);
        STAB_CHECK(r, memcmp(ia->rgb, ib->rgb, sizeof(float) * 3 * hz_image_pixels(ia)) == 0,
                   "frame %u after the reset differs from a fresh renderer", f);
    }
    stab_note(r, "%s: 8 frames after a reset bit-identical to a fresh renderer", hz_render_mode_name(mode));
}

static void c_taa_reset_mid_sequence(stab_result_t *r) { reset_case(r, HZ_MODE_TAA); }
static void c_render_tdense_reset(stab_result_t *r) { reset_case(r, HZ_MODE_TDENSE); }

/* A wall of one colour under ambient light only: every neighbourhood has zero variance; TAA's output under a
 * moving camera equals the full-frame value. */
static void c_taa_zero_variance(stab_result_t *r)
{
    su_scene_t b;
    su_begin(&b);
    b.ambient[0] = b.ambient[1] = b.ambient[2] = 1.0f;
    uint32_t m = su_material(&b, 0.5f, 0.25f, 0.125f);
    const float w0[3] = { -50, -50, 0 }, w1[3] = { 50, -50, 0 }, w2[3] = { 50, 50, 0 }, w3[3] = { -50, 50, 0 };
    su_quad(&b, w0, w1, w2, w3, m);
    su_object(&b);
    /* dark and behind every surface (no shadow rays): without lights the scene would get the default key light */
    su_light(&b, 0, 0, -100, 0.0f);
    const float e0[3] = { 0, 0, 5 }, e1[3] = { 2, 1, 4 }, t0[3] = { 0, 0, 0 }, t1[3] = { 1, 0, 0 };
    su_camera(&b, 0, e0, t0, 0.8f);
    su_camera(&b, 1, e1, t1, 0.8f);
    static const hz_render_mode_t modes[2] = { HZ_MODE_TAA, HZ_MODE_TDENSE };
    for (int k = 0; k < 2; k++) {
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = 40, o.height = 24, o.mode = modes[k];
        su_render_t s;
        hz_error_t err;
        STAB_OK(r, su_render_open(&s, &b, &o, &err), &err);
        for (uint32_t f = 0; f < 12; f++) {
            STAB_OK(r, su_render_frame(&s, f, (float)f / 12.0f, &err), &err);
            su_render_check(r, &s);
            const hz_image_t *img = hz_render_output(s.r);
            for (size_t i = 0; f >= 4 && i < hz_image_pixels(img); i++)
                for (int c = 0; c < 3; c++)
                    stab_error(r, fabs(img->rgb[3 * i + (size_t)c] - 0.5 / (1 << c)) / (0.5 / (1 << c)));
        }
        su_render_close(&s);
    }
    stab_note(r, "flat colour under a moving camera: TAA and tdense within %.3g", r->max_error);
    STAB_CHECK(r, r->max_error <= 1e-6, "zero-variance history changed the colour by %g", r->max_error);
}

/* Lights of 1e6 and 1e30 (radiance near the float range): TAA's variance (squares of 1e30) and tdense's boxes
 * must not overflow into NaN or Inf. */
static void bright_case(stab_result_t *r, float power)
{
    su_scene_t b;
    room(&b, power);
    static const hz_render_mode_t modes[3] = { HZ_MODE_FULL, HZ_MODE_TAA, HZ_MODE_TDENSE };
    double peak = 0;
    for (int k = 0; k < 3; k++) {
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = 32, o.height = 20, o.mode = modes[k], o.spp = k ? 1 : 4;
        su_render_t s;
        hz_error_t err;
        STAB_OK(r, su_render_open(&s, &b, &o, &err), &err);
        for (uint32_t f = 0; f < 8; f++) {
            STAB_OK(r, su_render_frame(&s, f, (float)f / 30.0f, &err), &err);
            su_render_check(r, &s);
            STAB_BAIL(r);
        }
        const hz_image_t *img = hz_render_output(s.r);
        for (size_t i = 0; i < 3 * hz_image_pixels(img); i++)
            peak = fmax(peak, img->rgb[i]);
        su_render_close(&s);
    }
    stab_note(r, "light %g: peak radiance %.3g; full/TAA/tdense finite", (double)power, peak);
    STAB_CHECK(r, peak > (double)power * 1e-3, "peak %g: the bright light did not show", peak);
}

static void c_radiance_1e6(stab_result_t *r) { bright_case(r, 1e6f); }
static void c_radiance_1e30(stab_result_t *r) { bright_case(r, 1e30f); }

static const stab_case_t cases[] = {
    { "tdense_zero_variance", "constant input (static and moving): output exactly the constant",
      c_tdense_zero_variance, 0 },
    { "tdense_nan_static", "NaN sample in a static region: gone within 16 frames; spreads <= 3x3",
      c_tdense_nan_static, 0 },
    { "tdense_nan_moving", "NaN sample in a moving region: gone within 16 frames; spreads <= 3x3",
      c_tdense_nan_moving, 0 },
    { "tdense_inf_static", "Inf sample in a static region: gone within 16 frames; spreads <= 3x3",
      c_tdense_inf_static, 0 },
    { "tdense_inf_moving", "Inf sample in a moving region: gone within 16 frames; spreads <= 3x3",
      c_tdense_inf_moving, 0 },
    { "tdense_huge_motion", "mv 1e30/Inf/NaN: finite output; motion clamped; orderings valid",
      c_tdense_huge_motion, 0 },
    { "tdense_reset_mid_sequence", "reset after 12 frames = fresh compositor (bit-identical)",
      c_tdense_reset_mid_sequence, 0 },
    { "taa_reset_mid_sequence", "renderer TAA reset mid-sequence = fresh renderer (bit-identical)",
      c_taa_reset_mid_sequence, 0 },
    { "render_tdense_reset", "renderer tdense reset mid-sequence = fresh renderer (bit-identical)",
      c_render_tdense_reset, 0 },
    { "taa_zero_variance", "flat colour; moving camera: TAA/tdense output = the colour (1e-6)", c_taa_zero_variance,
      0 },
    { "radiance_1e6", "light of 1e6: full/TAA/tdense finite", c_radiance_1e6, 0 },
    { "radiance_1e30", "light of 1e30 (squares overflow float): full/TAA/tdense finite", c_radiance_1e30, 0 },
};
STAB_STAGE(recon, cases);
