/* Stage blur: motion blur (seed 002: pose keys, the MSBVH / interpolated / swept motion BVHs traversed at each
 * lane's ray.time, --shutter renders) and the 64-bit scene clock, at the edges: equal key times, a half turn in
 * one segment, vertices collapsing to a point, triangles flipping through zero area, the loop's end, scene times
 * of 1e6 s and 2^62 ns, ray times at and just outside [0, 1]. Oracles: brute force over every triangle at the
 * ray's time (port/linux/motion_check.c, the code behind `hzrt accel --motion-check`), the analytic oscillation
 * at the wrapped time computed here in integers and double, the keys themselves at the ends of the interval, the
 * loader's and the key builder's documented refusals, and the unblurred renderer (shutter 0). */
#include <stdlib.h>

#include "hz/hash.h"
#include "hz/meshgen.h"
#include "motion_check.h"
#include "stab_util.h"

#define W 32
#define H 24

/* The motion BVHs checked: each kind with per-node motion segments (the default), the MSBVH also with every key. */
#define N_BVHS 4
static const hz_accel_blur_t blurs[N_BVHS] = { HZ_ACCEL_BLUR_MSBVH, HZ_ACCEL_BLUR_MSBVH, HZ_ACCEL_BLUR_INTERP,
                                               HZ_ACCEL_BLUR_SWEPT };
static const hz_accel_segments_t segments[N_BVHS] = { HZ_ACCEL_SEGMENTS_PER_NODE, HZ_ACCEL_SEGMENTS_EVERY_KEY,
                                                      HZ_ACCEL_SEGMENTS_PER_NODE, HZ_ACCEL_SEGMENTS_PER_NODE };

/* Builds every motion BVH over g and checks n random rays against brute force at each ray's time: 0 misses and
 * 0 mismatches (single rays, occlusion, 8-wide packets), at least a quarter of the rays hitting. */
static void mcheck_all(stab_result_t *r, const hz_accel_geom_t *g, uint64_t n, uint32_t seed)
{
    hz_pools_t *p = hz_pools_get();
    uint64_t hits = 0;
    for (int b = 0; b < N_BVHS; b++) {
        hz_arena_mark_t m = hz_arena_mark(&p->accel);
        hz_accel_config_t cfg;
        hz_accel_config_default(&cfg);
        cfg.blur = blurs[b];
        cfg.segments = segments[b];
        hz_accel_t *a = NULL;
        hz_error_t err;
        STAB_OK(r, hz_accel_build_native(&a, g, &cfg, &p->accel, &err), &err);
        hz_mcheck_counts_t c;
        memset(&c, 0, sizeof c);
        hz_mcheck_run(a, g, n, seed + (uint32_t)b, false, NULL, &c);
        STAB_CHECK(r, c.misses == 0 && c.mismatches == 0,
                   "%s BVH (%s segments), %u keys: %llu misses, %llu mismatches of %llu rays",
                   hz_accel_blur_name(blurs[b]), hz_accel_segments_name(segments[b]), g->time_keys,
                   (unsigned long long)c.misses,
                   (unsigned long long)c.mismatches, (unsigned long long)c.rays);
        STAB_CHECK(r, c.hits * 4 >= c.rays, "%s BVH: only %llu of %llu rays hit: the case tests nothing",
                   hz_accel_blur_name(blurs[b]), (unsigned long long)c.hits, (unsigned long long)c.rays);
        hits += c.hits;
        hz_accel_release(a);
        hz_arena_reset(&p->accel, m);
    }
    r->status = HZ_OK;
    stab_note(r, "%u keys: %llu rays x %d BVHs against brute force: 0 misses; 0 mismatches (%llu hits)", g->time_keys,
              (unsigned long long)n, N_BVHS, (unsigned long long)hits);
}

/* A small room: floor and wall (object 0), a coarse sphere (object 1: 120 triangles sharing vertices), a light.
 * Brute force over every triangle per ray is what the checks cost (qemu: keep it small). */
static void small_room(su_scene_t *b)
{
    su_begin(b);
    uint32_t grey = su_material(b, 0.7f, 0.7f, 0.7f), red = su_material(b, 0.8f, 0.2f, 0.1f);
    const float f0[3] = { -5, 0, -5 }, f1[3] = { 5, 0, -5 }, f2[3] = { 5, 0, 5 }, f3[3] = { -5, 0, 5 };
    su_quad(b, f3, f2, f1, f0, grey);
    const float w0[3] = { -5, 0, -5 }, w1[3] = { 5, 0, -5 }, w2[3] = { 5, 5, -5 }, w3[3] = { -5, 5, -5 };
    su_quad(b, w0, w1, w2, w3, grey);
    su_object(b);
    hz_mesh_t m;
    hz_arena_mark_t mk = hz_arena_mark(&hz_pools_get()->frame);
    if (hz_meshgen_sphere(&m, &hz_pools_get()->frame, 6, 10, 1.0f, NULL) == HZ_OK) {
        const float off[3] = { 0, 1.2f, 0 };
        su_mesh(b, m.pos, m.vertex_count, m.tri, m.tri_count, red, 1.0f, off);
        su_object(b);
    }
    hz_arena_reset(&hz_pools_get()->frame, mk);
    su_light(b, 1, 4, 3, 20.0f);
}

/* The small room as a geometry view with procedural keys of `kind`. */
static void room_keys(stab_result_t *r, hz_scene_t *sc, hz_accel_geom_t *g, hz_meshgen_motion_kind_t kind,
                      uint32_t keys)
{
    su_scene_t b;
    small_room(&b);
    const float eye[3] = { 0, 1, 5 }, target[3] = { 0, 1, 0 };
    su_camera(&b, 0, eye, target, 1.0f);
    hz_pools_t *p = hz_pools_get();
    hz_error_t err;
    STAB_OK(r, su_load(&b, sc, &err), &err);
    STAB_OK(r, hz_accel_geom_from_scene(g, sc, &p->accel, &err), &err);
    hz_status_t s = hz_meshgen_motion(g, g->pos, kind, keys, hz_v3(0, 1.2f, 0), 2.0f, 0.25f, &p->scene);
    STAB_CHECK(r, s == HZ_OK, "meshgen motion %s: %s", hz_meshgen_motion_name(kind), hz_status_str(s));
}

static hz_render_opts_t blur_opts(hz_render_mode_t mode, float shutter)
{
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.mode = mode, o.shutter = shutter, o.frame_hz = 60;
    if (mode == HZ_MODE_FULL)
        o.spp = 4;
    return o;
}

/* Renders `frames` frames from t0 (seconds, step dt) with shutter 1 in full (4 spp), TAA, tdense and adaptive over every
 * motion BVH: every output finite, the pose keys in use (opts.keys set, K >= 2). Returns K. */
static uint32_t render_blurred(stab_result_t *r, const su_scene_t *b, hz_time_ns_t t0, hz_time_ns_t dt,
                               uint32_t frames)
{
    static const hz_render_mode_t modes[4] = { HZ_MODE_FULL, HZ_MODE_TAA, HZ_MODE_TDENSE, HZ_MODE_ADAPTIVE };
    uint32_t k = 0;
    for (int m = 0; m < 4; m++)
        for (int bl = 0; bl < HZ_ACCEL_BLUR_COUNT; bl++) {
            if (m != 1 && bl != 0)
                continue; /* every BVH once (TAA), every mode once (MSBVH) */
            hz_render_opts_t o = blur_opts(modes[m], 1.0f);
            su_render_t s;
            hz_error_t err;
            hz_status_t st = su_render_open_blur(&s, b, &o, (hz_accel_blur_t)bl, &err);
            if (st != HZ_OK) {
                stab_failf(r, __FILE__, __LINE__, "open (%s, %s): %s (%s)", hz_render_mode_name(modes[m]),
                           hz_accel_blur_name((hz_accel_blur_t)bl), hz_status_str(st), err.msg);
                return 0;
            }
            if (!s.opts.keys || s.opts.keys->count < 2) {
                stab_failf(r, __FILE__, __LINE__, "a moving scene under shutter 1 got no pose keys");
                return 0;
            }
            k = s.opts.keys->count;
            for (uint32_t f = 0; f < frames; f++) {
                st = su_render_frame_ns(&s, f, t0 + dt * (hz_time_ns_t)f, &err);
                if (st != HZ_OK) {
                    stab_failf(r, __FILE__, __LINE__, "frame %u: %s (%s)", f, hz_status_str(st), err.msg);
                    return 0;
                }
                su_render_check(r, &s);
                if (r->fail[0])
                    return 0;
            }
            su_render_close(&s);
        }
    return k;
}

/* The quad of su_wall_and_quad (half-size 1.5) with `n` vertex keys at 60 keys/s, key f of vertex p from fn. */
typedef void (*key_fn)(uint32_t f, const float *p, float *k);

static bool quad_vertex_keys(su_scene_t *b, uint32_t n, key_fn fn)
{
    hz_hzb_object_t *o = su_wall_and_quad(b, 1.5f);
    uint32_t nv = o->vertex_count, first = o->first_vertex;
    o->motion = HZ_MOTION_VERTEX, o->key_first = 0, o->key_count = n, o->key_rate = 60.0f;
    b->vkeys = malloc(sizeof(float) * 4 * nv * n);
    if (!b->vkeys)
        return false;
    b->nvkeys = n * nv;
    for (uint32_t f = 0; f < n; f++)
        for (uint32_t v = 0; v < nv; v++) {
            float *k = b->vkeys + 4 * (size_t)(f * nv + v);
            fn(f, b->pos + 4 * (size_t)(first + v), k);
            k[3] = 0;
        }
    return true;
}

/* Flattened to a line (key 1), then mirrored: winding flipped (key 2). */
static void key_flip(uint32_t f, const float *p, float *k)
{
    k[0] = p[0], k[1] = f == 1 ? 0.0f : f == 2 ? -p[1] : p[1], k[2] = p[2];
}

/* Every vertex on one point (key 1). */
static void key_collapse(uint32_t f, const float *p, float *k)
{
    k[0] = f ? 0.25f : p[0], k[1] = f ? -0.5f : p[1], k[2] = f ? 0.5f : p[2];
}

/* ---- equal key times ---- */

/* Rigid keys with equal times under shutter 1: the loader refuses them before any key or BVH is built; pose keys
 * of a count other than 2, 3, 5, 9 are refused; a zero-length interval (every key at one time) is a valid,
 * motionless key set that every motion BVH traverses exactly. */
static void c_blur_equal_key_times(stab_result_t *r)
{
    su_scene_t b;
    hz_hzb_object_t *o = su_wall_and_quad(&b, 1.0f);
    o->motion = HZ_MOTION_RIGID, o->key_first = 0, o->key_count = 2;
    for (int i = 0; i < 2; i++) {
        memset(&b.rkey[i], 0, sizeof b.rkey[i]);
        b.rkey[i].time = 0.25f, b.rkey[i].rotation[3] = 1;
        b.rkey[i].scale[0] = b.rkey[i].scale[1] = b.rkey[i].scale[2] = 1;
    }
    b.rkey[1].translation[0] = 1;
    b.nrkey = 2;
    hz_render_opts_t opt = blur_opts(HZ_MODE_TAA, 1.0f);
    su_render_t s;
    hz_error_t err;
    hz_status_t st = su_render_open_blur(&s, &b, &opt, HZ_ACCEL_BLUR_MSBVH, &err);
    STAB_REFUSED(r, st, HZ_E_RANGE, &err, "object 1: rigid key times do not increase at key 1");
    int status = r->status;
    /* distinct times: pose keys of an unsupported count are refused */
    b.rkey[1].time = 0.5f;
    hz_scene_t sc;
    STAB_OK(r, su_load(&b, &sc, &err), &err);
    hz_posekeys_t keys;
    st = hz_posekeys_init(&keys, &sc, 4, &hz_pools_get()->scene, &err);
    STAB_REFUSED(r, st, HZ_E_INVALID_ARG, &err, "4 time keys (must be 2, 3, 5 or 9)");
    /* every key at one time: lo == hi */
    STAB_OK(r, hz_posekeys_init(&keys, &sc, 3, &hz_pools_get()->scene, &err), &err);
    hz_posekeys_eval(&keys, &sc, 0.4f, 0.0f, 0.0f);
    for (uint32_t k = 1; k < 3; k++)
        STAB_CHECK(r, memcmp(keys.pos[0], keys.pos[k], sizeof(float) * 4 * keys.vertex_count) == 0,
                   "keys at equal times differ (key %u)", k);
    hz_accel_geom_t g;
    STAB_OK(r, hz_accel_geom_from_scene(&g, &sc, &hz_pools_get()->accel, &err), &err);
    hz_posekeys_geom(&keys, &g);
    mcheck_all(r, &g, 800, 11);
    r->status = status;
}

/* ---- one-segment extremes through the motion BVHs ---- */

/* ROT180 (K = 2): every vertex passes through the axis in one segment, triangles flatten and flip. Then a rigid
 * half turn inside one shutter rendered blurred. */
static void c_blur_rotation_180(stab_result_t *r)
{
    hz_scene_t sc;
    hz_accel_geom_t g;
    room_keys(r, &sc, &g, HZ_MESHGEN_ROT180, 2);
    STAB_BAIL(r);
    mcheck_all(r, &g, r->full ? 40000 : 1200, 21);
    STAB_BAIL(r);
    su_scene_t b;
    hz_hzb_object_t *o = su_wall_and_quad(&b, 1.5f);
    o->motion = HZ_MOTION_RIGID, o->key_first = 0, o->key_count = 2;
    for (int i = 0; i < 2; i++) {
        memset(&b.rkey[i], 0, sizeof b.rkey[i]);
        b.rkey[i].time = (float)i / 60.0f; /* the half turn takes one frame interval: shutter 1 at 60 Hz */
        b.rkey[i].scale[0] = b.rkey[i].scale[1] = b.rkey[i].scale[2] = 1;
    }
    b.rkey[0].rotation[3] = 1, b.rkey[1].rotation[2] = 1; /* about z: the quad turns in the image plane */
    b.nrkey = 2;
    uint32_t k = render_blurred(r, &b, HZ_NS_PER_S / 120, HZ_NS_PER_S / 240, 4);
    STAB_BAIL(r);
    stab_note(r, "half turn in one rigid segment under shutter 1: %u pose keys; finite", k);
}

/* Vertex keys over [0, 1] of n triangles of their own: key 1 moves each triangle's first vertex to v1 + v2 - v0
 * (through the opposite edge's midpoint at t = 0.5: zero area, then flipped winding). */
static void c_blur_triangle_flip(stab_result_t *r)
{
    const uint32_t n = 200;
    float *k0 = malloc(sizeof(float) * 4 * 3 * n), *k1 = malloc(sizeof(float) * 4 * 3 * n);
    uint32_t *tri = malloc(sizeof(uint32_t) * 3 * n);
    STAB_CHECK(r, k0 && k1 && tri, "malloc");
    uint32_t st = 7;
    for (uint32_t t = 0; t < n; t++) {
        float c[3];
        for (int a = 0; a < 3; a++)
            st = hz_hash32(st), c[a] = (float)(st >> 8) * (4.0f / 16777216.0f) - 2.0f;
        for (uint32_t v = 0; v < 3; v++) {
            float *p = k0 + 4 * (3 * (size_t)t + v);
            for (int a = 0; a < 3; a++)
                st = hz_hash32(st), p[a] = c[a] + (float)(st >> 8) * (0.6f / 16777216.0f) - 0.3f;
            p[3] = 0;
            tri[3 * t + v] = 3 * t + v;
        }
        memcpy(k1 + 12 * (size_t)t, k0 + 12 * (size_t)t, sizeof(float) * 12);
        for (int a = 0; a < 3; a++)
            k1[12 * (size_t)t + (size_t)a] = k0[12 * (size_t)t + 4 + (size_t)a] + k0[12 * (size_t)t + 8 + (size_t)a] -
                                             k0[12 * (size_t)t + (size_t)a];
    }
    hz_accel_geom_t g = { .pos = k0, .vertex_count = 3 * n, .tri = tri, .tri_count = n };
    g.time_keys = 2, g.pos_keys[0] = k0, g.pos_keys[1] = k1;
    mcheck_all(r, &g, r->full ? 40000 : 1000, 31);
    STAB_BAIL(r);
    /* CROSS: shared vertices of the room cross one another and the split planes */
    hz_scene_t sc;
    room_keys(r, &sc, &g, HZ_MESHGEN_CROSS, 3);
    STAB_BAIL(r);
    mcheck_all(r, &g, r->full ? 20000 : 800, 33);
    STAB_BAIL(r);
    /* rendered: vertex keys flattening the quad to a line and mirroring it, under shutter 1 */
    su_scene_t b;
    STAB_CHECK(r, quad_vertex_keys(&b, 3, key_flip), "malloc");
    uint32_t k = render_blurred(r, &b, 0, HZ_NS_PER_S / 120, 4);
    STAB_BAIL(r);
    stab_note(r, "rendered flip through a line: %u pose keys; finite", k);
    free(b.vkeys), free(k0), free(k1), free(tri);
}

/* COLLAPSE: every vertex reaches one point at time 1 (K = 2, 5, 9); then vertex keys collapsing the quad to a
 * point rendered blurred. */
static void c_blur_collapse(stab_result_t *r)
{
    static const uint32_t ks[3] = { 2, 5, 9 };
    for (int i = 0; i < 3; i++) {
        hz_scene_t sc;
        hz_accel_geom_t g;
        hz_pools_t *p = hz_pools_get();
        hz_arena_mark_t m0 = hz_arena_mark(&p->scene), m1 = hz_arena_mark(&p->accel);
        room_keys(r, &sc, &g, HZ_MESHGEN_COLLAPSE, ks[i]);
        STAB_BAIL(r);
        mcheck_all(r, &g, r->full ? 20000 : 600, 41 + (uint32_t)i);
        STAB_BAIL(r);
        hz_arena_reset(&p->accel, m1), hz_arena_reset(&p->scene, m0);
    }
    su_scene_t b;
    STAB_CHECK(r, quad_vertex_keys(&b, 2, key_collapse), "malloc");
    uint32_t k = render_blurred(r, &b, 0, HZ_NS_PER_S / 240, 4);
    STAB_BAIL(r);
    stab_note(r, "rendered collapse to a point: %u pose keys; finite", k);
    free(b.vkeys);
}

/* ---- the clock: loop end, 1e6 s, 2^62 ns ---- */

/* The quad oscillating along x with amplitude 1 at `hz`: its analytic x at time t_ns + dt, with the time
 * wrapped into the period here, in integers (period_ns exact) and double. */
static double osc_x(double rest_x, double hz, int64_t period_ns, hz_time_ns_t t_ns, double dt)
{
    int64_t w = t_ns % period_ns;
    if (w < 0)
        w += period_ns;
    double t = (double)w * 1e-9 + dt;
    return rest_x + sin(2.0 * 3.14159265358979323846 * hz * t);
}

/* Pose keys at scene time T over a shutter of `interval` seconds against the analytic oscillation (within
 * 2e-4: float sines of offsets inside one period), then every motion BVH over those keys. */
static void keys_at(stab_result_t *r, su_scene_t *b, hz_time_ns_t T, double hz, int64_t period_ns, float interval)
{
    hz_pools_t *p = hz_pools_get();
    hz_arena_mark_t m0 = hz_arena_mark(&p->scene), m1 = hz_arena_mark(&p->accel);
    hz_scene_t sc;
    hz_error_t err;
    STAB_OK(r, su_load(b, &sc, &err), &err);
    uint32_t K = hz_posekeys_count(&sc, interval);
    STAB_CHECK(r, K >= 2, "an oscillating quad needs pose keys (got %u)", K);
    hz_posekeys_t keys;
    STAB_OK(r, hz_posekeys_init(&keys, &sc, K, &p->scene, &err), &err);
    const float lo = -0.5f * interval, hi = 0.5f * interval;
    hz_posekeys_eval_ns(&keys, &sc, T, lo, hi);
    const hz_hzb_object_t *ob = &sc.objects[1];
    double e = 0, spread = 0;
    for (uint32_t k = 0; k < K; k++) {
        double dt = (double)lo + ((double)hi - lo) * k / (K - 1);
        for (uint32_t v = ob->first_vertex; v < ob->first_vertex + ob->vertex_count; v++) {
            const float *q = keys.pos[k] + 4 * (size_t)v;
            stab_count_nonfinite(r, q, 3);
            double want = osc_x(sc.rest_pos[4 * (size_t)v], hz, period_ns, T, dt);
            e = fmax(e, fabs(q[0] - want));
            e = fmax(e, fabs((double)q[1] - sc.rest_pos[4 * (size_t)v + 1]));
            spread = fmax(spread, fabs((double)q[0] - keys.pos[0][4 * (size_t)v]));
        }
    }
    stab_error(r, e);
    STAB_CHECK(r, e <= 2e-4, "pose keys at %lld ns off the analytic oscillation by %g", (long long)T, e);
    STAB_CHECK(r, spread > 1e-4, "pose keys at %lld ns do not move across the shutter (spread %g)", (long long)T,
               spread);
    hz_accel_geom_t g;
    STAB_OK(r, hz_accel_geom_from_scene(&g, &sc, &p->accel, &err), &err);
    hz_posekeys_geom(&keys, &g);
    mcheck_all(r, &g, 1000, (uint32_t)(T >> 20) ^ 51u);
    hz_arena_reset(&p->accel, m1), hz_arena_reset(&p->scene, m0);
}

static void osc_scene(su_scene_t *b, float hz, float duration)
{
    hz_hzb_object_t *o = su_wall_and_quad(b, 1.0f);
    o->motion = HZ_MOTION_OSCILLATE, o->params[0] = 1.0f, o->params[3] = hz;
    b->duration = duration;
}

/* The loop's end: a 2 s loop, the quad at 0.5 Hz; keys at t = 2 s (the shutter straddles the wrap), 2 s - 1 ns,
 * 2^20 loops, against the analytic oscillation; blurred renders across the wrap stay finite. */
static void c_blur_loop_end(stab_result_t *r)
{
    su_scene_t b;
    osc_scene(&b, 0.5f, 2.0f);
    const hz_time_ns_t ts[] = { 2 * HZ_NS_PER_S, 2 * HZ_NS_PER_S - 1, ((hz_time_ns_t)1 << 21) * HZ_NS_PER_S, 0 };
    for (size_t i = 0; i < sizeof ts / sizeof ts[0]; i++) {
        keys_at(r, &b, ts[i], 0.5, 2 * HZ_NS_PER_S, 1.0f / 60.0f);
        STAB_BAIL(r);
    }
    r->note[0] = 0;
    uint32_t k = render_blurred(r, &b, 2 * HZ_NS_PER_S - HZ_NS_PER_S / 60, HZ_NS_PER_S / 120, 4);
    STAB_BAIL(r);
    stab_note(r, "keys at 2 s; 2 s - 1 ns; 2^21 s; 0 within %.2g of the analytic oscillation; 3 BVHs exact; "
                 "renders across the wrap (%u keys) finite", r->max_error, k);
}

/* 1e6 s (+0.3 s) and 2^62 ns (+0.3 s) on the 64-bit clock, no scene loop (the quad's own 4 s period): keys match
 * the analytic oscillation, every BVH is exact, blurred renders there are finite. */
static void c_blur_time_1e6s(stab_result_t *r)
{
    su_scene_t b;
    osc_scene(&b, 0.25f, 0.0f);
    const hz_time_ns_t ts[] = { 1000000 * HZ_NS_PER_S + 300000000, ((hz_time_ns_t)1 << 62) + 300000000 };
    for (size_t i = 0; i < 2; i++) {
        keys_at(r, &b, ts[i], 0.25, 4 * HZ_NS_PER_S, 1.0f / 60.0f);
        STAB_BAIL(r);
    }
    r->note[0] = 0;
    uint32_t k = render_blurred(r, &b, ts[0], HZ_NS_PER_S / 60, 3);
    STAB_BAIL(r);
    k = render_blurred(r, &b, ts[1], HZ_NS_PER_S / 60, 3);
    STAB_BAIL(r);
    stab_note(r, "1e6 s and 2^62 ns: keys within %.2g of the analytic oscillation; 3 BVHs exact; blurred renders "
                 "(%u keys) finite", r->max_error, k);
}

/* Unblurred frames at 1e6 s and 2^62 ns: the quad moves (frames 1 s apart differ) and each frame is the frame at
 * the time wrapped into the quad's period (computed here in integers), within 1e-5. */
static void c_clock_1e6s_2p62(stab_result_t *r)
{
    su_scene_t b;
    osc_scene(&b, 0.25f, 0.0f);
    static float img[3][W * H * 3];
    const hz_time_ns_t ts[] = { 1000000 * HZ_NS_PER_S + 300000000, ((hz_time_ns_t)1 << 62) + 300000000 };
    double e = 0;
    for (size_t i = 0; i < 2; i++) {
        const hz_time_ns_t at[3] = { ts[i], ts[i] + HZ_NS_PER_S, ts[i] % (4 * HZ_NS_PER_S) };
        for (int j = 0; j < 3; j++) {
            hz_render_opts_t o = blur_opts(HZ_MODE_FULL, 0.0f);
            su_render_t s;
            hz_error_t err;
            STAB_OK(r, su_render_open(&s, &b, &o, &err), &err);
            STAB_OK(r, su_render_frame_ns(&s, 0, at[j], &err), &err);
            su_render_check(r, &s);
            STAB_BAIL(r);
            memcpy(img[j], hz_render_output(s.r)->rgb, sizeof img[j]);
            su_render_close(&s);
        }
        size_t moved = 0;
        for (size_t v = 0; v < W * H * 3; v++) {
            moved += img[0][v] != img[1][v];
            e = fmax(e, fabs((double)img[0][v] - img[2][v]) / fmax(fabs((double)img[2][v]), 1e-3));
        }
        STAB_CHECK(r, moved > 30, "at %lld ns the quad does not move in 1 s (%zu values differ)", (long long)ts[i],
                   moved);
    }
    stab_error(r, e);
    STAB_CHECK(r, e <= 1e-5, "a frame at a huge time differs from the frame at its wrapped time by %g", e);
    stab_note(r, "1e6 s and 2^62 ns: frames 1 s apart differ; equal to the wrapped time within %.2g", e);
}

/* shutter 0 renders exactly what the renderer renders without the option (the port's blur build included), in
 * every mode, on a moving scene. */
static void c_blur_shutter0_identical(stab_result_t *r)
{
    su_scene_t b;
    osc_scene(&b, 0.5f, 0.0f);
    static const hz_render_mode_t modes[4] = { HZ_MODE_FULL, HZ_MODE_TAA, HZ_MODE_TDENSE, HZ_MODE_ADAPTIVE };
    for (int m = 0; m < 4; m++) {
        hz_render_opts_t o0;
        hz_render_opts_default(&o0);
        o0.width = W, o0.height = H, o0.mode = modes[m];
        hz_render_opts_t o1 = o0;
        o1.shutter = 0.0f, o1.frame_hz = 60;
        su_render_t a, c;
        hz_error_t err;
        STAB_OK(r, su_render_open(&a, &b, &o0, &err), &err);
        static float ref[W * H * 3];
        float *refs = malloc(sizeof ref * 6);
        STAB_CHECK(r, refs != NULL, "malloc");
        for (uint32_t f = 0; f < 6; f++) {
            STAB_OK(r, su_render_frame(&a, f, (float)f / 60.0f, &err), &err);
            su_render_check(r, &a);
            memcpy(refs + (size_t)f * W * H * 3, hz_render_output(a.r)->rgb, sizeof ref);
        }
        su_render_close(&a);
        STAB_BAIL(r);
        STAB_OK(r, su_render_open_blur(&c, &b, &o1, HZ_ACCEL_BLUR_MSBVH, &err), &err);
        STAB_CHECK(r, c.opts.keys == NULL, "shutter 0 took pose keys");
        for (uint32_t f = 0; f < 6; f++) {
            STAB_OK(r, su_render_frame(&c, f, (float)f / 60.0f, &err), &err);
            su_render_check(r, &c);
            STAB_CHECK(r, memcmp(hz_render_output(c.r)->rgb, refs + (size_t)f * W * H * 3, sizeof ref) == 0,
                       "%s frame %u: shutter 0 differs from no blur", hz_render_mode_name(modes[m]), f);
        }
        su_render_close(&c);
        free(refs);
    }
    stab_note(r, "full; TAA; tdense; adaptive: 6 frames each bit-identical");
}

/* Key interpolation at t = 0 and 1 is the end keys exactly; just outside [0, 1] (and NaN, +-Inf) it clamps to
 * them; rays at those times through every motion BVH hit exactly what rays at 0 and 1 hit. */
static void c_blur_time_edges(stab_result_t *r)
{
    hz_scene_t sc;
    hz_accel_geom_t g;
    room_keys(r, &sc, &g, HZ_MESHGEN_SWAY, 5);
    STAB_BAIL(r);
    hz_posekeys_t keys;
    memset(&keys, 0, sizeof keys);
    keys.count = g.time_keys, keys.vertex_count = g.vertex_count;
    for (uint32_t k = 0; k < g.time_keys; k++)
        keys.pos[k] = (float *)(uintptr_t)g.pos_keys[k];
    const float below[] = { 0.0f, -1e-7f, -0.0f, -1e-38f, -INFINITY, NAN, -1.0f };
    const float above[] = { 1.0f, 1.0000001f, 1.0f + 1e-6f, INFINITY, 2.0f };
    for (uint32_t v = 0; v < g.vertex_count; v++) {
        for (size_t i = 0; i < sizeof below / sizeof below[0]; i++) {
            hz_vec3_t p = hz_posekeys_lerp(&keys, keys.pos, v, below[i]);
            const float *q = g.pos_keys[0] + 4 * (size_t)v;
            STAB_CHECK(r, p.x == q[0] && p.y == q[1] && p.z == q[2], "lerp at t = %g is not key 0 (vertex %u)",
                       (double)below[i], v);
        }
        for (size_t i = 0; i < sizeof above / sizeof above[0]; i++) {
            hz_vec3_t p = hz_posekeys_lerp(&keys, keys.pos, v, above[i]);
            const float *q = g.pos_keys[g.time_keys - 1] + 4 * (size_t)v;
            STAB_CHECK(r, p.x == q[0] && p.y == q[1] && p.z == q[2], "lerp at t = %g is not the last key (vertex %u)",
                       (double)above[i], v);
        }
    }
    /* rays: random ones re-timed to the edge times; each against brute force and against the same ray at the
     * clamped time */
    hz_pools_t *p = hz_pools_get();
    float lo[3], hi[3];
    hz_mcheck_bounds(&g, lo, hi);
    uint64_t n = 0, same = 0;
    for (int b = 0; b < HZ_ACCEL_BLUR_COUNT; b++) {
        hz_accel_config_t cfg;
        hz_accel_config_default(&cfg);
        cfg.blur = (hz_accel_blur_t)b;
        hz_accel_t *a = NULL;
        hz_error_t err;
        hz_arena_mark_t m = hz_arena_mark(&p->accel);
        STAB_OK(r, hz_accel_build_native(&a, &g, &cfg, &p->accel, &err), &err);
        hz_mcheck_counts_t c;
        memset(&c, 0, sizeof c);
        hz_accel_ctx_t ctx;
        hz_accel_ctx_init(&ctx);
        for (uint64_t i = 0; i < (r->full ? 1024u : 64u); i++) {
            hz_rayhit_t rays[8], clamp[8];
            for (int l = 0; l < 8; l++) {
                hz_mcheck_ray(&g, lo, hi, 8 * i + (uint64_t)l, 61, &rays[l]);
                const bool up = l & 1;
                rays[l].ray.time = up ? above[1 + (size_t)l / 2 % 4] : below[1 + (size_t)l / 2 % 6];
                clamp[l] = rays[l];
                clamp[l].ray.time = up ? 1.0f : 0.0f;
                hz_rayhit_t x = rays[l], y = clamp[l];
                hz_accel_intersect1(a, &ctx, &x);
                hz_accel_intersect1(a, &ctx, &y);
                same += x.hit.prim_id == y.hit.prim_id && x.ray.tfar == y.ray.tfar && x.hit.u == y.hit.u &&
                        x.hit.v == y.hit.v;
                n++;
            }
            hz_mcheck_batch(a, &g, rays, 8, NULL, &c);
            hz_mcheck_batch(a, &g, clamp, 8, NULL, &c);
        }
        STAB_CHECK(r, c.misses == 0 && c.mismatches == 0, "%s BVH at edge times: %llu misses, %llu mismatches",
                   hz_accel_blur_name((hz_accel_blur_t)b), (unsigned long long)c.misses,
                   (unsigned long long)c.mismatches);
        hz_accel_release(a);
        hz_arena_reset(&p->accel, m);
    }
    STAB_CHECK(r, same == n, "%llu of %llu rays outside [0, 1] hit differently from their clamped time",
               (unsigned long long)(n - same), (unsigned long long)n);
    r->status = HZ_OK;
    stab_note(r, "lerp at 0; 1; -1e-7; 1 + 1e-7; +-Inf; NaN = end keys exactly; %llu edge-time rays x 3 BVHs = "
                 "brute force and the clamped time", (unsigned long long)n / 3);
}

/* Rigid instances (seed 002 section 3.2) at the edges: a half turn in one segment (the lerped matrix is singular
 * halfway: the quad is a line there, as its lerped vertices are), a quad 1e6 units out, one scaled to 1e-4 and a
 * mirrored one. Each against brute force at the ray's time (which moves each ray into the instance as the
 * traversal does), and the scene rendered blurred. */
static void c_blur_instances(stab_result_t *r)
{
    static const struct {
        const char *what;
        float q1[4], scale[3], t0[3], t1[3];
    } ex[] = {
        { "half turn", { 0, 0, 1, 0 }, { 1, 1, 1 }, { 0, 0, 0 }, { 0, 0, 0 } },
        { "1e6 out", { 0, 0, 0.3826834f, 0.9238795f }, { 1, 1, 1 }, { 1e6f, 0, 0 }, { 1e6f + 0.5f, 0, 0 } },
        { "scale 1e-4", { 0, 0, 0.7071068f, 0.7071068f }, { 1e-4f, 1e-4f, 1e-4f }, { 0, 0, 1 }, { 0, 0, 1 } },
        { "mirrored", { 0.3826834f, 0, 0, 0.9238795f }, { -1, 1, 1.5f }, { 0.2f, 0, 0 }, { -0.2f, 0.3f, 0 } },
    };
    const uint64_t n = r->full ? 20000 : 800;
    char done[160] = "";
    for (size_t e = 0; e < HZ_ARRAY_LEN(ex); e++) {
        su_scene_t b;
        hz_hzb_object_t *o = su_wall_and_quad(&b, 1.5f);
        o->motion = HZ_MOTION_RIGID, o->key_first = 0, o->key_count = 2;
        for (int i = 0; i < 2; i++) {
            memset(&b.rkey[i], 0, sizeof b.rkey[i]);
            b.rkey[i].time = (float)i / 60.0f;
            for (int c = 0; c < 3; c++)
                b.rkey[i].scale[c] = ex[e].scale[c], b.rkey[i].translation[c] = i ? ex[e].t1[c] : ex[e].t0[c];
        }
        b.rkey[0].rotation[3] = 1;
        memcpy(b.rkey[1].rotation, ex[e].q1, sizeof ex[e].q1);
        b.nrkey = 2;
        hz_scene_t sc;
        hz_error_t err;
        hz_posekeys_t keys;
        hz_accel_geom_t g;
        hz_pools_t *p = hz_pools_get();
        STAB_OK(r, su_load(&b, &sc, &err), &err);
        STAB_OK(r, hz_posekeys_init(&keys, &sc, 2, &p->scene, &err), &err);
        hz_posekeys_eval(&keys, &sc, 1.0f / 120.0f, -1.0f / 120.0f, 1.0f / 120.0f);
        STAB_OK(r, hz_accel_geom_from_scene(&g, &sc, &p->accel, &err), &err);
        hz_posekeys_geom(&keys, &g);
        STAB_CHECK(r, g.instance_count == 1 && g.static_rest, "%s: %u instances (static rest %d), expected 1",
                   ex[e].what, g.instance_count, (int)g.static_rest);
        mcheck_all(r, &g, n, 40u + (uint32_t)e);
        STAB_BAIL(r);
        if (e == HZ_ARRAY_LEN(ex) - 1u) {
            render_blurred(r, &b, HZ_NS_PER_S / 120, HZ_NS_PER_S / 240, 3);
            STAB_BAIL(r);
        }
        snprintf(done + strlen(done), sizeof done - strlen(done), "%s%s", e ? ", " : "", ex[e].what);
    }
    r->status = HZ_OK;
    stab_note(r, "one rigid instance each (%s): %llu rays x 3 BVHs against brute force, 0 misses, 0 mismatches; "
                 "blurred render finite", done, (unsigned long long)n);
}

static const stab_case_t cases[] = {
    { "blur_equal_key_times", "shutter 1 with equal rigid key times: refused (range); 4 keys refused; lo == hi "
                              "keys traversed exactly", c_blur_equal_key_times, 0 },
    { "blur_rotation_180", "half turn in one segment: 3 motion BVHs = brute force at the ray's time; blurred "
                           "render finite", c_blur_rotation_180, 0 },
    { "blur_triangle_flip", "triangles flipping through zero area and crossing vertices: BVHs = brute force; "
                            "blurred render finite", c_blur_triangle_flip, 0 },
    { "blur_collapse", "vertices collapsing to a point (2/5/9 keys): BVHs = brute force; blurred render finite",
      c_blur_collapse, 0 },
    { "blur_loop_end", "keys at the loop's end = analytic oscillation (2e-4); BVHs exact; renders across the wrap",
      c_blur_loop_end, 0 },
    { "blur_time_1e6s", "keys at 1e6 s and 2^62 ns = analytic (2e-4); BVHs exact; blurred renders finite",
      c_blur_time_1e6s, 0 },
    { "clock_1e6s_2p62", "frames at 1e6 s and 2^62 ns animate and equal the wrapped time (1e-5)",
      c_clock_1e6s_2p62, 0 },
    { "blur_shutter0_identical", "shutter 0 bit-identical to no blur: full/TAA/tdense/adaptive",
      c_blur_shutter0_identical, 0 },
    { "blur_instances", "rigid instances: half turn in a segment, 1e6 out, scale 1e-4, mirrored = brute force; "
                        "blurred render finite", c_blur_instances, 0 },
    { "blur_time_edges", "key lerp at 0/1 and just outside (NaN/Inf) = end keys; edge-time rays = brute force",
      c_blur_time_edges, 0 },
};
STAB_STAGE(blur, cases);
