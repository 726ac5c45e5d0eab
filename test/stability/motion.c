/* Stage motion: animation (rigid keys, vertex keys, spin, oscillation), the camera path and the motion vectors
 * the renderer derives from them, at the edges: huge motion, teleports, degenerate keys, collapsing and
 * flipping triangles, the loop's end. Oracles: analytic positions (rotation, periodicity), the loader's
 * documented refusals, and finiteness of every output. */
#include <stdlib.h>

#include "hz/meshgen.h"
#include "stab_util.h"

/* Renders `frames` frames at times t0 + i dt in TAA and tdense; returns the largest |mv| seen. */
static void render_modes(stab_result_t *r, const su_scene_t *b, float t0, float dt, uint32_t frames, double *max_mv)
{
    static const hz_render_mode_t modes[3] = { HZ_MODE_FULL, HZ_MODE_TAA, HZ_MODE_TDENSE };
    *max_mv = 0;
    for (int m = 0; m < 3; m++) {
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = 48, o.height = 32, o.mode = modes[m];
        su_render_t s;
        hz_error_t err;
        STAB_OK(r, su_render_open(&s, b, &o, &err), &err);
        for (uint32_t f = 0; f < frames; f++) {
            STAB_OK(r, su_render_frame(&s, f, t0 + dt * (float)f, &err), &err);
            su_render_check(r, &s);
            STAB_BAIL(r);
            const hz_gbuffer_t *gb = hz_render_gbuffer(s.r);
            for (size_t i = 0; gb->mv && i < 48 * 32; i++)
                if (isfinite(gb->mv[2 * i]))
                    *max_mv = fmax(*max_mv, hypot(gb->mv[2 * i], gb->mv[2 * i + 1]));
        }
        su_render_close(&s);
    }
}

/* A quad of half-size 1e8 filling the view slides sideways at 4.8e7 units/s: at 240 Hz that is about 1e6
 * pixels per frame for every pixel. */
static void c_mv_1e6px(stab_result_t *r)
{
    su_scene_t b;
    hz_hzb_object_t *o = su_wall_and_quad(&b, 1e8f);
    o->motion = HZ_MOTION_OSCILLATE;
    o->params[0] = 1e7f, o->params[3] = 0.76f;
    double mv;
    render_modes(r, &b, 0.0f, 1.0f / 240.0f, 6, &mv);
    STAB_BAIL(r);
    stab_note(r, "largest |mv| %.3g px; full/TAA/tdense outputs finite", mv);
    STAB_CHECK(r, mv >= 1e5, "the case did not produce huge motion (%g px)", mv);
}

/* The camera jumps 1e4 units between two frames (keys 1 ms apart) and back: TAA and tdense history is
 * discarded or clamped, outputs stay finite. */
static void c_camera_teleport(stab_result_t *r)
{
    su_scene_t b;
    su_wall_and_quad(&b, 1.0f);
    b.ncam = 0;
    const float e0[3] = { 0, 0, 6 }, e1[3] = { 1e4f, 0, 6 }, t0[3] = { 0, 0, 0 }, t1[3] = { 1e4f, 0, 0 };
    su_camera(&b, 0.0f, e0, t0, 1.0f);
    su_camera(&b, 0.010f, e0, t0, 1.0f);
    su_camera(&b, 0.011f, e1, t1, 1.0f);
    su_camera(&b, 0.030f, e1, t1, 1.0f);
    su_camera(&b, 0.031f, e0, t0, 1.0f);
    double mv;
    render_modes(r, &b, 0.0f, 0.005f, 10, &mv);
    STAB_BAIL(r);
    stab_note(r, "teleports of 1e4 units; largest |mv| %.3g px", mv);
}

/* Two rigid keys with equal times: refused naming the object and the key. */
static void c_rigid_equal_times(stab_result_t *r)
{
    su_scene_t b;
    hz_hzb_object_t *o = su_wall_and_quad(&b, 1.0f);
    o->motion = HZ_MOTION_RIGID, o->key_first = 0, o->key_count = 2;
    for (int i = 0; i < 2; i++) {
        memset(&b.rkey[i], 0, sizeof b.rkey[i]);
        b.rkey[i].time = 0.5f, b.rkey[i].rotation[3] = 1;
        b.rkey[i].scale[0] = b.rkey[i].scale[1] = b.rkey[i].scale[2] = 1;
    }
    b.rkey[1].translation[0] = 1;
    b.nrkey = 2;
    hz_scene_t sc;
    hz_error_t err;
    hz_status_t s = su_load(&b, &sc, &err);
    STAB_REFUSED(r, s, HZ_E_RANGE, &err, "object 1: rigid key times do not increase at key 1");
}

/* Two camera keys with equal times: refused naming the key. */
static void c_camera_equal_times(stab_result_t *r)
{
    su_scene_t b;
    su_wall_and_quad(&b, 1.0f);
    const float eye[3] = { 1, 0, 6 }, target[3] = { 0, 0, 0 };
    su_camera(&b, 0.0f, eye, target, 1.0f);
    hz_scene_t sc;
    hz_error_t err;
    hz_status_t s = su_load(&b, &sc, &err);
    STAB_REFUSED(r, s, HZ_E_RANGE, &err, "camera key times do not increase at key 1");
}

/* Rigid keys from the identity to a half turn about y in one segment: halfway the object has turned a quarter
 * (normalised lerp = slerp at the midpoint), rigidly; a full turn (q and -q) takes the shorter arc: no motion. */
static void c_rotation_180(stab_result_t *r)
{
    su_scene_t b;
    hz_hzb_object_t *o = su_wall_and_quad(&b, 1.0f);
    o->motion = HZ_MOTION_RIGID, o->key_first = 0, o->key_count = 2;
    for (int i = 0; i < 2; i++) {
        memset(&b.rkey[i], 0, sizeof b.rkey[i]);
        b.rkey[i].time = (float)i;
        b.rkey[i].scale[0] = b.rkey[i].scale[1] = b.rkey[i].scale[2] = 1;
    }
    b.rkey[0].rotation[3] = 1, b.rkey[1].rotation[1] = 1; /* (0, 1, 0, 0): 180 degrees about y */
    b.nrkey = 2;
    hz_scene_t sc;
    hz_error_t err;
    STAB_OK(r, su_load(&b, &sc, &err), &err);
    const hz_hzb_object_t *ob = &sc.objects[1];
    for (int step = 0; step <= 8; step++) {
        float t = (float)step / 8.0f;
        hz_scene_animate(&sc, t);
        for (uint32_t v = ob->first_vertex; v < ob->first_vertex + ob->vertex_count; v++) {
            const float *p = sc.pos + 4 * (size_t)v, *q = sc.rest_pos + 4 * (size_t)v;
            stab_count_nonfinite(r, p, 3);
            /* rigid: distance from the axis and height preserved */
            stab_error(r, fabs(hypot(p[0], p[2]) - hypot(q[0], q[2])));
            stab_error(r, fabs((double)p[1] - q[1]));
            if (step == 4) { /* a quarter turn about y: (x, z) -> (z, -x) */
                stab_error(r, fabs((double)p[0] - q[2]));
                stab_error(r, fabs((double)p[2] + q[0]));
            }
            if (step == 8) {
                stab_error(r, fabs((double)p[0] + q[0]));
                stab_error(r, fabs((double)p[2] + q[2]));
            }
        }
    }
    STAB_CHECK(r, r->max_error <= 1e-5, "rotation off by %g", r->max_error);
    double e_half = r->max_error;
    /* q and -q: the same orientation; the shorter arc does not move */
    b.rkey[1].rotation[1] = 0, b.rkey[1].rotation[3] = -1;
    STAB_OK(r, su_load(&b, &sc, &err), &err);
    hz_scene_animate(&sc, 0.5f);
    for (uint32_t v = ob->first_vertex; v < ob->first_vertex + ob->vertex_count; v++)
        for (int k = 0; k < 3; k++)
            stab_error(r, fabs((double)sc.pos[4 * (size_t)v + (uint32_t)k] - sc.rest_pos[4 * (size_t)v + (uint32_t)k]));
    STAB_CHECK(r, r->max_error <= 1e-6, "q to -q moved by %g", r->max_error);
    stab_note(r, "half turn: quarter at the midpoint within %.2g; q to -q still", e_half);
}

/* Vertex keys that collapse a quad to one point (frame 1) and flip it over (frame 2): the accel refits to a
 * zero-area and a mirrored quad, the renderer's normals and motion stay finite; at the collapse the quad
 * shows nowhere. */
static void vertex_key_case(stab_result_t *r, int flip)
{
    su_scene_t b;
    hz_hzb_object_t *o = su_wall_and_quad(&b, 1.5f);
    uint32_t nv = o->vertex_count, first = o->first_vertex;
    o->motion = HZ_MOTION_VERTEX, o->key_first = 0, o->key_count = 3, o->key_rate = 10.0f;
    b.vkeys = malloc(sizeof(float) * 4 * nv * 3);
    b.nvkeys = 3 * nv;
    for (uint32_t f = 0; f < 3; f++)
        for (uint32_t v = 0; v < nv; v++) {
            const float *p = b.pos + 4 * (size_t)(first + v);
            float *k = b.vkeys + 4 * (size_t)(f * nv + v);
            k[3] = 0;
            if (f == 0)
                k[0] = p[0], k[1] = p[1], k[2] = p[2];
            else if (f == 1 && !flip)
                k[0] = 0.25f, k[1] = -0.5f, k[2] = 0.5f; /* every vertex on one point */
            else if (f == 1)
                k[0] = p[0], k[1] = 0.0f, k[2] = p[2]; /* flattened to a line (zero area) */
            else
                k[0] = p[0], k[1] = -p[1], k[2] = p[2]; /* mirrored: winding flipped */
        }
    su_render_t s;
    hz_render_opts_t opt;
    hz_render_opts_default(&opt);
    opt.width = 48, opt.height = 32, opt.mode = HZ_MODE_TAA;
    hz_error_t err;
    STAB_OK(r, su_render_open(&s, &b, &opt, &err), &err);
    uint32_t seen_at_collapse = 0;
    for (uint32_t f = 0; f <= 30; f++) {
        float t = (float)f / 100.0f; /* frames 0, 1, 2 at t = 0, 0.1, 0.2 */
        STAB_OK(r, su_render_frame(&s, f, t, &err), &err);
        su_render_check(r, &s);
        STAB_BAIL(r);
        if (f == 10) {
            const hz_gbuffer_t *gb = hz_render_gbuffer(s.r);
            for (size_t i = 0; i < 48 * 32; i++)
                seen_at_collapse += gb->object[i] == 1;
        }
    }
    stab_note(r, "%s; quad pixels at the degenerate key %u", flip ? "flip through a line" : "collapse to a point",
              seen_at_collapse);
    STAB_CHECK(r, seen_at_collapse == 0, "a zero-area quad covers %u pixels", seen_at_collapse);
    su_render_close(&s);
    free(b.vkeys);
}

static void c_collapse_to_point(stab_result_t *r) { vertex_key_case(r, 0); }
static void c_triangle_flip(stab_result_t *r) { vertex_key_case(r, 1); }

/* The loop's end: with duration 2 s, animation at t = 2, 2 - ulp, 2 k (k up to 2^20) and the camera path at
 * the same times equal their wrapped times (oscillation with period 2: positions within 1e-4 of t = 0). */
static void c_loop_end(stab_result_t *r)
{
    su_scene_t b;
    hz_hzb_object_t *o = su_wall_and_quad(&b, 1.0f);
    o->motion = HZ_MOTION_OSCILLATE, o->params[0] = 1.0f, o->params[3] = 0.5f;
    b.duration = 2.0f;
    b.camera_flags = 1;
    b.ncam = 0;
    const float e0[3] = { 0, 0, 6 }, e1[3] = { 1, 0, 6 }, tg[3] = { 0, 0, 0 };
    su_camera(&b, 0.0f, e0, tg, 1.0f);
    su_camera(&b, 1.0f, e1, tg, 1.0f);
    hz_scene_t sc;
    hz_error_t err;
    STAB_OK(r, su_load(&b, &sc, &err), &err);
    const hz_hzb_object_t *ob = &sc.objects[1];
    hz_scene_animate(&sc, 0.0f);
    static float ref[4 * 8];
    memcpy(ref, sc.pos + 4 * (size_t)ob->first_vertex, sizeof(float) * 4 * ob->vertex_count);
    hz_camera_t c0 = hz_scene_camera(&sc, 0.0f);
    const float times[] = { 2.0f, nextafterf(2.0f, 0.0f), 4.0f, 2048.0f, 2097152.0f, 1e-30f };
    for (size_t i = 0; i < sizeof times / sizeof times[0]; i++) {
        hz_scene_animate(&sc, times[i]);
        for (uint32_t v = 0; v < ob->vertex_count; v++)
            for (int k = 0; k < 3; k++) {
                float p = sc.pos[4 * (size_t)(ob->first_vertex + v) + (uint32_t)k];
                stab_count_nonfinite(r, &p, 1);
                stab_error(r, fabs((double)p - ref[4 * v + (uint32_t)k]));
            }
        hz_camera_t c = hz_scene_camera(&sc, times[i]);
        const float cv[4] = { c.eye.x, c.eye.y, c.eye.z, c.fov_y };
        stab_count_nonfinite(r, cv, 4);
        stab_error(r, fabs((double)c.eye.x - c0.eye.x));
    }
    stab_note(r, "t = 2; 2 - ulp; 4; 2048; 2^21; 1e-30 against t = 0");
    STAB_CHECK(r, r->max_error <= 1e-4, "state at the loop's end differs from its start by %g", r->max_error);
}

/* A spin of 1e6 rad/s and a rigid key scaling the object to 0: finite everywhere. */
static void c_spin_and_zero_scale(stab_result_t *r)
{
    su_scene_t b;
    hz_hzb_object_t *o = su_wall_and_quad(&b, 1.0f);
    o->motion = HZ_MOTION_SPIN, o->params[4] = 1.0f, o->params[6] = 1e6f;
    double mv;
    render_modes(r, &b, 0.3f, 1.0f / 240.0f, 4, &mv);
    STAB_BAIL(r);
    o = &b.obj[1];
    o->motion = HZ_MOTION_RIGID, o->key_first = 0, o->key_count = 2;
    for (int i = 0; i < 2; i++) {
        memset(&b.rkey[i], 0, sizeof b.rkey[i]);
        b.rkey[i].time = (float)i * 0.05f, b.rkey[i].rotation[3] = 1;
        b.rkey[i].scale[0] = b.rkey[i].scale[1] = b.rkey[i].scale[2] = (float)(1 - i);
    }
    b.nrkey = 2;
    double mv2;
    render_modes(r, &b, 0.0f, 1.0f / 60.0f, 6, &mv2);
    STAB_BAIL(r);
    stab_note(r, "spin 1e6 rad/s: |mv| up to %.3g px; scale 1 -> 0: finite", mv);
}

/* A frame time that is not finite is refused by begin_frame, naming the time. */
static void c_time_nonfinite(stab_result_t *r)
{
    su_scene_t b;
    su_wall_and_quad(&b, 1.0f);
    su_render_t s;
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = 16, o.height = 16;
    hz_error_t err;
    STAB_OK(r, su_render_open(&s, &b, &o, &err), &err);
    hz_status_t st = su_render_frame(&s, 0, NAN, &err);
    STAB_REFUSED(r, st, HZ_E_INVALID_ARG, &err, "frame time");
    st = su_render_frame(&s, 0, INFINITY, &err);
    STAB_REFUSED(r, st, HZ_E_INVALID_ARG, &err, "frame time");
}

static const stab_case_t cases[] = {
    { "mv_1e6px", "object moving ~1e6 px per frame: full/TAA/tdense finite", c_mv_1e6px, 0 },
    { "camera_teleport", "camera jumps 1e4 units and back: TAA/tdense finite", c_camera_teleport, 0 },
    { "rigid_equal_times", "rigid keys with equal times: refused (range) naming object and key",
      c_rigid_equal_times, 0 },
    { "camera_equal_times", "camera keys with equal times: refused (range) naming the key", c_camera_equal_times,
      0 },
    { "rotation_180", "half turn in one segment: rigid; quarter at midpoint <= 1e-5; q to -q still",
      c_rotation_180, 0 },
    { "collapse_to_point", "vertex keys collapsing a quad to a point: finite; covers no pixel",
      c_collapse_to_point, 0 },
    { "triangle_flip", "vertex keys flipping a quad through zero area: finite; covers no pixel at the line",
      c_triangle_flip, 0 },
    { "loop_end", "t = duration; duration - ulp; 2^21 s: state equals t = 0 within 1e-4", c_loop_end, 0 },
    { "spin_and_zero_scale", "spin 1e6 rad/s; rigid scale to 0: finite", c_spin_and_zero_scale, 0 },
    { "time_nonfinite", "NaN/Inf frame time: refused (invalid argument) naming the time", c_time_nonfinite, 0 },
};
STAB_STAGE(motion, cases);
