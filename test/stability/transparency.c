/* Stage transparency: today's exact front-to-back compositing of blended (BLEND) surfaces, along camera rays and
 * along shadow rays, at the alpha extremes and with hundreds of layers. References: the same scene without the
 * layer or with an opaque one (alpha 0, 1e-30, 1 - 1e-7, 1), the documented compositing rule evaluated in double
 * precision (stacks), and the analytic transmittance (1 - a)^N of shadow rays. */
#include <stdlib.h>

#include "stab_util.h"

#define W 32
#define H 24

/* Renders one full-mode frame (1 spp, pixel centres) into out (W * H * 3). */
static void render_full(stab_result_t *r, const su_scene_t *b, float min_vis, float *out, uint64_t *layer_cap)
{
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.min_visibility = min_vis;
    su_render_t s;
    hz_error_t err;
    STAB_OK(r, su_render_open(&s, b, &o, &err), &err);
    STAB_OK(r, su_render_frame(&s, 0, 0.0f, &err), &err);
    su_render_check(r, &s);
    memcpy(out, hz_render_output(s.r)->rgb, sizeof(float) * W * H * 3);
    if (layer_cap)
        *layer_cap = s.layer_cap;
    su_render_close(&s);
}

static double max_rel_diff(const float *a, const float *b, size_t n)
{
    double e = 0;
    for (size_t i = 0; i < n; i++)
        e = fmax(e, fabs((double)a[i] - b[i]) / fmax(fabs((double)b[i]), 1e-3));
    return e;
}

/* A blended layer of alpha `alpha` against the reference scene (no layer, or an opaque one). */
static void alpha_case(stab_result_t *r, float alpha, int ref_mode, double bound)
{
    static float img[W * H * 3], ref[W * H * 3];
    su_scene_t b;
    su_wall_layer(&b, HZ_ALPHA_BLEND, alpha);
    render_full(r, &b, 0.001f, img, NULL);
    STAB_BAIL(r);
    su_wall_layer(&b, ref_mode, 1.0f);
    render_full(r, &b, 0.001f, ref, NULL);
    STAB_BAIL(r);
    stab_error(r, max_rel_diff(img, ref, W * H * 3));
    stab_note(r, "alpha %.9g against %s: max relative difference %.3g", (double)alpha,
              ref_mode < 0 ? "no layer" : "an opaque layer", r->max_error);
    STAB_CHECK(r, r->max_error <= bound, "differs by %g > %g", r->max_error, bound);
}

/* Through a clear layer the wall is reached by a continuation ray from an offset origin, not the camera: its
 * hit point, and so the lighting, differs by float rounding (1e-5 seen), hence 1e-4. */
static void c_alpha_0(stab_result_t *r) { alpha_case(r, 0.0f, -1, 1e-4); }
static void c_alpha_1e_30(stab_result_t *r) { alpha_case(r, 1e-30f, -1, 1e-4); }
static void c_alpha_1m1e_7(stab_result_t *r) { alpha_case(r, 1.0f - 1e-7f, HZ_ALPHA_OPAQUE, 1e-5); }
static void c_alpha_1(stab_result_t *r) { alpha_case(r, 1.0f, HZ_ALPHA_OPAQUE, 1e-6); }

/* n parallel blended layers of alpha a (ambient light only, black background) in front of the camera: every
 * pixel's value is the compositing rule of hz/render.h in double precision: layer i adds a (1 - a)^i c, the
 * path stops when the visibility left drops below min_vis or after HZ_RENDER_MAX_LAYERS layers (counted). */
static void stack_case(stab_result_t *r, uint32_t n, float a, float min_vis, bool expect_cap)
{
    su_scene_t b;
    su_begin(&b);
    b.ambient[0] = b.ambient[1] = b.ambient[2] = 1.0f;
    const float albedo = 0.5f;
    uint32_t m = su_material_alpha(&b, albedo, albedo, albedo, a, HZ_ALPHA_BLEND);
    for (uint32_t i = 0; i < n; i++) {
        float z = -0.01f * (float)i;
        const float q0[3] = { -50, -50, z }, q1[3] = { 50, -50, z }, q2[3] = { 50, 50, z }, q3[3] = { -50, 50, z };
        su_quad(&b, q0, q1, q2, q3, m);
    }
    su_object(&b);
    /* dark and behind every surface (no shadow rays): without lights the scene would get the default key light */
    su_light(&b, 0, 0, -100, 0.0f);
    const float eye[3] = { 0, 0, 5 }, target[3] = { 0, 0, 0 };
    su_camera(&b, 0, eye, target, 0.3f);
    /* the rule, in double */
    double want = 0, vis = 1;
    uint32_t layers = 0;
    bool capped = false;
    for (uint32_t i = 0; i < n; i++) {
        want += vis * (double)a * albedo;
        layers++;
        double left = vis * (1.0 - (double)a);
        if (!(left >= (double)min_vis))
            break;
        if (i + 1 >= HZ_RENDER_MAX_LAYERS) {
            capped = true;
            break;
        }
        vis = left;
    }
    static float img[W * H * 3];
    uint64_t cap = 0;
    render_full(r, &b, min_vis, img, &cap);
    STAB_BAIL(r);
    for (size_t i = 0; i < W * H * 3; i++)
        stab_error(r, fabs(img[i] - want) / fmax(want, 1e-30));
    stab_note(r, "%u layers of alpha %g: %u composited%s; value %.6g (double rule %.6g); layer_cap %llu", n,
              (double)a, layers, capped ? " (capped)" : "", (double)img[0], want, (unsigned long long)cap);
    STAB_CHECK(r, r->max_error <= 1e-4, "composite off the rule by %g", r->max_error);
    STAB_CHECK(r, (cap > 0) == expect_cap && capped == expect_cap, "layer cap counted %llu, rule says %d",
               (unsigned long long)cap, capped);
}

static void c_stacked_1000(stab_result_t *r) { stack_case(r, 1000, 0.01f, 0.001f, true); }
static void c_stacked_1000_dense(stab_result_t *r) { stack_case(r, 1000, 0.5f, 0.001f, false); }
static void c_visibility_underflow(stab_result_t *r) { stack_case(r, 1000, 0.9f, 0.0f, true); }

/* Shadow rays through N blended layers between a wall and the light (the camera sees the wall directly): with
 * no ambient term every wall pixel is the unshadowed one times (1 - a)^N; below min_visibility, or past
 * HZ_RENDER_MAX_LAYERS layers with visibility left (counted in layer_cap), it is black. */
static void shadow_case(stab_result_t *r, uint32_t n, float a)
{
    uint64_t cap = 0;
    static float lit[W * H * 3], img[W * H * 3];
    for (int pass = 0; pass < 2; pass++) {
        su_scene_t b;
        su_begin(&b);
        b.ambient[0] = b.ambient[1] = b.ambient[2] = 0.0f;
        uint32_t wall = su_material(&b, 0.8f, 0.8f, 0.8f);
        const float w0[3] = { -3, -3, 0 }, w1[3] = { 3, -3, 0 }, w2[3] = { 3, 3, 0 }, w3[3] = { -3, 3, 0 };
        su_quad(&b, w0, w1, w2, w3, wall);
        uint32_t m = su_material_alpha(&b, 0.3f, 0.3f, 0.3f, a, HZ_ALPHA_BLEND);
        /* out of view and of every light path, in both passes: the scene's bounds (which scale secondary-ray
         * offsets, and so move the shading point) are the same with and without the layers */
        const float f0[3] = { -20, -50, 0.01f }, f1[3] = { -20, 50, 0.01f }, f2[3] = { -20, 50, 10 },
                    f3[3] = { -20, -50, 10 };
        su_quad(&b, f0, f1, f2, f3, m);
        for (uint32_t i = 0; pass && i < n; i++) {
            float x = 2.0f + 0.005f * (float)i;
            const float q0[3] = { x, -50, 0.01f }, q1[3] = { x, 50, 0.01f }, q2[3] = { x, 50, 10 },
                        q3[3] = { x, -50, 10 };
            su_quad(&b, q0, q1, q2, q3, m);
        }
        su_object(&b);
        su_light(&b, 10, 0, 1, 400);
        const float eye[3] = { 0, 0, 5 }, target[3] = { 0, 0, 0 };
        su_camera(&b, 0, eye, target, 0.3f);
        render_full(r, &b, 0.001f, pass ? img : lit, pass ? &cap : NULL);
        STAB_BAIL(r);
    }
    double t = pow(1.0 - (double)a, (double)n);
    /* the layer a ray leaves the cap at still has visibility left: (1 - a)^HZ_RENDER_MAX_LAYERS >= 0.001 */
    const bool capped = n > HZ_RENDER_MAX_LAYERS && pow(1.0 - (double)a, HZ_RENDER_MAX_LAYERS) >= 0.001;
    bool blocked = t < 0.001 || capped;
    double want = blocked ? 0.0 : t;
    double e = 0;
    for (size_t i = 0; i < W * H * 3; i++) {
        STAB_CHECK(r, lit[i] > 0, "unshadowed wall pixel %zu is black", i / 3);
        e = fmax(e, fabs(img[i] / lit[i] - want) / fmax(want, 1e-30));
    }
    stab_error(r, blocked ? e * 1e-30 : e);
    stab_note(r, "%u layers of alpha %g: light ratio %.6g; (1 - a)^N %.6g%s; layer_cap %llu", n, (double)a,
              (double)(img[0] / lit[0]), t,
              capped ? " (past the layer cap: blocked)" : blocked ? " (below min_visibility: blocked)" : "",
              (unsigned long long)cap);
    STAB_CHECK(r, r->max_error <= 1e-4, "transmittance off by %g", r->max_error);
    STAB_CHECK(r, capped == (cap > 0), "layer_cap %llu where %s expected", (unsigned long long)cap,
               capped ? "a count was" : "none was");
}

static void c_shadow_20(stab_result_t *r) { shadow_case(r, 20, 0.1f); }
static void c_shadow_100(stab_result_t *r) { shadow_case(r, 100, 0.05f); }
static void c_shadow_200(stab_result_t *r) { shadow_case(r, 200, 0.02f); }
static void c_shadow_1000(stab_result_t *r) { shadow_case(r, 1000, 0.1f); }

static const stab_case_t cases[] = {
    { "alpha_0", "blended layer of alpha 0 = no layer (relative 1e-4)", c_alpha_0, 0 },
    { "alpha_1e-30", "alpha 1e-30 = no layer (relative 1e-4)", c_alpha_1e_30, 0 },
    { "alpha_1-1e-7", "alpha 1 - 1e-7 = opaque layer (relative 1e-5)", c_alpha_1m1e_7, 0 },
    { "alpha_1", "alpha 1 = opaque layer (relative 1e-6)", c_alpha_1, 0 },
    { "stacked_1000", "1000 layers of alpha 0.01: double-precision rule within 1e-4; cap counted",
      c_stacked_1000, 0 },
    { "stacked_1000_dense", "1000 layers of alpha 0.5: stops at min_visibility; rule within 1e-4",
      c_stacked_1000_dense, 0 },
    { "visibility_underflow", "alpha 0.9 with min_visibility 0: visibility underflows to 0; finite; rule",
      c_visibility_underflow, 0 },
    { "shadow_20_layers", "shadow ray through 20 layers: (1 - a)^N within 1e-4", c_shadow_20, 0 },
    { "shadow_100_layers", "shadow ray through 100 layers of alpha 0.05: (1 - a)^N within 1e-4", c_shadow_100, 0 },
    { "shadow_200_layers", "shadow ray through 200 layers of alpha 0.02: blocked past the layer cap, counted",
      c_shadow_200, 0 },
    { "shadow_1000_layers", "shadow ray through 1000 layers: blocked below min_visibility", c_shadow_1000, 0 },
};
STAB_STAGE(transparency, cases);
