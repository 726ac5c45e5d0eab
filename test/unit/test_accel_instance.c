/*
 * Rigid instances in the native accel (seed 002 section 3.2): a view whose moving objects carry object-space
 * positions and a matrix per key. Checked:
 *  - every kernel and packet form (single rays, 4 and 8 wide with holes, tiles of packets with the coherent
 *    hint, occlusion in each) against brute force over all triangles at the ray's time, bit for bit, with a
 *    static and with a moving rest, a mirrored and scaled instance among them, and again after a refit with new
 *    matrices;
 *  - independently of the shared transform code: rays aimed at points of the world-space triangles (the keys the
 *    renderer shades, each vertex moved by the key matrix in the test) hit them at the aimed distance;
 *  - the any-hit callback gets the view's triangle index and the side of the world-space triangle (a mirrored
 *    instance flips it);
 *  - the REFIT choice ignores the instances; rays are counted once; bad instance views are refused.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "accel_fixture.h"

#define MEM_BYTES (96u << 20)
static uint8_t mem[MEM_BYTES] HZ_ALIGNED(64);
static hz_arena_t arena;

#if defined(HZ_SIMD_NEON)
#define N_RAYS 2000u
#else
#define N_RAYS 12000u
#endif
#define K 5u

static hz_rayhit_t rays_in[N_RAYS], rays_ref[N_RAYS], rays_out[N_RAYS];
static uint8_t occ_out[N_RAYS];

static int setup(void **state)
{
    (void)state;
    hz_arena_init(&arena, "test", mem, sizeof mem);
    return 0;
}

/* ---- the scene: soup (rest), sphere (instance 0), soup (rest), cube sphere (instance 1, mirrored) ---- */
typedef struct world {
    float *obj;      /* object-space positions (the rest: their static positions) */
    float *keys[K];  /* world positions at each key */
    uint32_t *tri;
    uint32_t vertex_count, tri_count;
    uint8_t *flags;
    hz_accel_instance_t inst[2];
    uint32_t vfirst[2], vcount[2]; /* the instances' vertices */
    float xf[2][K][12];
    hz_accel_geom_t g;
} world_t;

static world_t W;

static void append(world_t *w, const hz_mesh_t *m, float scale, hz_vec3_t off)
{
    for (uint32_t v = 0; v < m->vertex_count; v++)
        for (int c = 0; c < 4; c++)
            w->obj[4u * (w->vertex_count + v) + (uint32_t)c] =
                c == 3 ? 0.0f : m->pos[4u * v + (uint32_t)c] * scale + (c == 0 ? off.x : c == 1 ? off.y : off.z);
    for (uint32_t t = 0; t < 3u * m->tri_count; t++)
        w->tri[3u * w->tri_count + t] = m->tri[t] + w->vertex_count;
    w->vertex_count += m->vertex_count;
    w->tri_count += m->tri_count;
}

/* Key k of instance i: rotation about a tilted axis, a scale (mirrored in x for instance 1) and a translation. */
static void make_xform(float m[12], int i, uint32_t k, float phase)
{
    const float s = (float)k / (float)(K - 1u);
    const float ang = phase + (i ? -1.1f : 0.8f) * s;
    const float ax[3] = { 0.3f, 1.0f, i ? -0.4f : 0.2f };
    const float n = sqrtf(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
    const float x = ax[0] / n, y = ax[1] / n, z = ax[2] / n, c = cosf(ang), sn = sinf(ang), C = 1.0f - c;
    const float R[9] = { c + x * x * C,      x * y * C - z * sn, x * z * C + y * sn, y * x * C + z * sn, c + y * y * C,
                         y * z * C - x * sn, z * x * C - y * sn, z * y * C + x * sn, c + z * z * C };
    const float sc[3] = { i ? -1.5f : 1.0f, i ? 1.5f : 1.0f, i ? 1.5f : 1.0f };
    const float tr[3] = { (i ? -0.6f : 0.5f) + 0.3f * s, 0.1f * s, i ? 0.4f : -0.2f };
    for (int r = 0; r < 3; r++) {
        for (int c2 = 0; c2 < 3; c2++)
            m[4 * r + c2] = R[3 * r + c2] * sc[c2];
        m[4 * r + 3] = tr[r];
    }
}

/* World keys: the rest static, or swaying along x with the key (moving_rest); instance vertices moved by their
 * key matrices. Matrices with `phase`. */
static void pose(world_t *w, bool moving_rest, float phase)
{
    for (int i = 0; i < 2; i++)
        for (uint32_t k = 0; k < K; k++)
            make_xform(w->xf[i][k], i, k, phase);
    for (uint32_t k = 0; k < K; k++)
        for (uint32_t v = 0; v < w->vertex_count; v++) {
            const float *p = w->obj + 4u * v;
            float *q = w->keys[k] + 4u * v;
            int in = -1;
            for (int i = 0; i < 2; i++)
                if (v >= w->vfirst[i] && v < w->vfirst[i] + w->vcount[i])
                    in = i;
            if (in < 0) {
                const float dx = moving_rest ? 0.05f * (float)k * p[1] : 0.0f;
                q[0] = p[0] + dx, q[1] = p[1], q[2] = p[2], q[3] = 0.0f;
                continue;
            }
            const float *m = w->xf[in][k];
            for (int r = 0; r < 3; r++)
                q[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
            q[3] = 0.0f;
        }
}

static void make_world(world_t *w, bool moving_rest, bool anyhit)
{
    hz_error_t err;
    hz_mesh_t soup1, sphere, soup2, cube;
    assert_int_equal(hz_meshgen_soup(&soup1, &arena, 600, 1.5f, 0.15f, 3, &err), HZ_OK);
    assert_int_equal(hz_meshgen_sphere(&sphere, &arena, 16, 32, 0.4f, &err), HZ_OK);
    assert_int_equal(hz_meshgen_soup(&soup2, &arena, 300, 1.5f, 0.15f, 5, &err), HZ_OK);
    assert_int_equal(hz_meshgen_cube_sphere(&cube, &arena, 6, 0.3f, true, &err), HZ_OK);
    const uint32_t nv = soup1.vertex_count + sphere.vertex_count + soup2.vertex_count + cube.vertex_count;
    const uint32_t nt = soup1.tri_count + sphere.tri_count + soup2.tri_count + cube.tri_count;
    memset(w, 0, sizeof *w);
    w->obj = hz_arena_alloc(&arena, (size_t)nv * 16u, 64);
    for (uint32_t k = 0; k < K; k++)
        w->keys[k] = hz_arena_alloc(&arena, (size_t)nv * 16u, 64);
    w->tri = hz_arena_alloc(&arena, (size_t)nt * 12u, 16);
    w->flags = hz_arena_alloc(&arena, nt, 16);
    assert_non_null(w->flags);
    append(w, &soup1, 1.0f, hz_v3(0, 0, 0));
    w->inst[0].tri_first = w->tri_count, w->inst[0].tri_count = sphere.tri_count;
    w->vfirst[0] = w->vertex_count, w->vcount[0] = sphere.vertex_count;
    append(w, &sphere, 1.0f, hz_v3(0, 0, 0));
    append(w, &soup2, 1.0f, hz_v3(0.2f, 0.3f, 0));
    w->inst[1].tri_first = w->tri_count, w->inst[1].tri_count = cube.tri_count;
    w->vfirst[1] = w->vertex_count, w->vcount[1] = cube.vertex_count;
    append(w, &cube, 1.0f, hz_v3(0, 0, 0));
    for (uint32_t t = 0; t < nt; t++) /* every third triangle asks the any-hit callback */
        w->flags[t] = anyhit && t % 3u == 0u ? HZ_ACCEL_TRI_ANYHIT : 0u;
    for (int i = 0; i < 2; i++) {
        w->inst[i].obj_pos = w->obj;
        for (uint32_t k = 0; k < K; k++)
            w->inst[i].xform[k] = w->xf[i][k];
    }
    pose(w, moving_rest, 0.0f);
    hz_accel_geom_init(&w->g);
    w->g.pos = w->keys[K / 2u];
    w->g.vertex_count = nv;
    w->g.tri = w->tri;
    w->g.tri_count = nt;
    w->g.tri_flags = anyhit ? w->flags : NULL;
    w->g.time_keys = K;
    for (uint32_t k = 0; k < K; k++)
        w->g.pos_keys[k] = w->keys[k];
    w->g.instance_count = 2;
    w->g.instances = w->inst;
    w->g.static_rest = !moving_rest;
}

static float unit01(uint32_t *s)
{
    *s = hz_hash32(*s + 0x9e3779b9u);
    return (float)(*s >> 8) * (1.0f / 16777216.0f);
}

/* Random rays through the world box (every key), times random with every 8th on a key; every other ray aimed at
 * a point of a triangle at its time (3 in 4 of those at an instance's). */
static void make_rays(const world_t *w, uint32_t seed)
{
    fx_bounds_t b = { { INFINITY, INFINITY, INFINITY }, { -INFINITY, -INFINITY, -INFINITY } };
    for (uint32_t k = 0; k < K; k++)
        for (uint32_t v = 0; v < w->vertex_count; v++)
            for (int c = 0; c < 3; c++)
                b.lo[c] = fminf(b.lo[c], w->keys[k][4u * v + (uint32_t)c]),
                b.hi[c] = fmaxf(b.hi[c], w->keys[k][4u * v + (uint32_t)c]);
    fx_random_rays(rays_in, N_RAYS, b, seed);
    uint32_t st = seed * 7919u + 1u;
    for (uint32_t i = 0; i < N_RAYS; i++) {
        hz_rayhit_t *r = &rays_in[i];
        float time = unit01(&st);
        if (i % 8u == 3u)
            time = (float)(uint32_t)(unit01(&st) * (float)K) / (float)(K - 1u);
        r->ray.time = time;
        if (i % 2u)
            continue;
        const int in = (int)(unit01(&st) * 4.0f);
        uint32_t t = in < 2 ? w->inst[in].tri_first + (uint32_t)(unit01(&st) * (float)w->inst[in].tri_count)
                            : (uint32_t)(unit01(&st) * (float)w->tri_count);
        t = t < w->tri_count ? t : w->tri_count - 1u;
        float b1 = unit01(&st), b2 = unit01(&st);
        if (b1 + b2 > 1.0f)
            b1 = 1.0f - b1, b2 = 1.0f - b2;
        const hz_vec3_t p = hz_meshgen_tri_point(&w->g, t, time, b1, b2);
        r->ray.dir_x = p.x - r->ray.org_x, r->ray.dir_y = p.y - r->ray.org_y, r->ray.dir_z = p.z - r->ray.org_z;
        r->ray.tfar = INFINITY;
    }
}

static uint32_t count_diff(const char *what)
{
    uint32_t bad = 0;
    for (uint32_t i = 0; i < N_RAYS; i++)
        if (!fx_same(&rays_ref[i], &rays_out[i]) && bad++ < 4)
            print_message("%s: ray %u: expected prim %u t %.9g, got prim %u t %.9g\n", what, i,
                          rays_ref[i].hit.prim_id, (double)rays_ref[i].ray.tfar, rays_out[i].hit.prim_id,
                          (double)rays_out[i].ray.tfar);
    return bad;
}

/* Brute force into rays_ref; then every kernel and form must give exactly it. */
static void check_forms(const hz_accel_t *a, const world_t *w, const char *what)
{
    uint32_t hits = 0, inst_hits = 0;
    for (uint32_t i = 0; i < N_RAYS; i++) {
        rays_ref[i] = rays_in[i];
        hz_accel_brute_intersect1(&w->g, &rays_ref[i]);
        const uint32_t p = rays_ref[i].hit.prim_id;
        hits += rays_ref[i].hit.geom_id == 0;
        for (int k = 0; k < 2; k++)
            inst_hits += rays_ref[i].hit.geom_id == 0 && p >= w->inst[k].tri_first &&
                         p < w->inst[k].tri_first + w->inst[k].tri_count;
    }
    print_message("%s: %u of %u rays hit, %u an instance\n", what, hits, N_RAYS, inst_hits);
    assert_true(hits > N_RAYS / 4);
    assert_true(inst_hits > N_RAYS / 8); /* the instances are hit, not just the rest */
    char name[160];
    const hz_accel_kernel_t ks[] = { HZ_ACCEL_KERNEL_SCALAR, HZ_ACCEL_KERNEL_SIMD_SINGLE, HZ_ACCEL_KERNEL_SIMD_PACKET,
                                     HZ_ACCEL_KERNEL_AUTO };
    for (size_t q = 0; q < HZ_ARRAY_LEN(ks); q++) {
        if (!hz_accel_kernel_available(ks[q]))
            continue;
        snprintf(name, sizeof name, "%s %s single", what, hz_accel_kernel_name(ks[q]));
        fx_trace1(a, ks[q], rays_in, rays_out, N_RAYS, NULL);
        assert_int_equal(count_diff(name), 0);
        for (int pw = 4; pw <= 8; pw += 4) {
            snprintf(name, sizeof name, "%s %s packets of %d", what, hz_accel_kernel_name(ks[q]), pw);
            fx_trace_packets(a, ks[q], pw == 8 ? HZ_ACCEL_COHERENT : 0, pw, true, rays_in, rays_out, N_RAYS, NULL);
            for (uint32_t i = 6; i < N_RAYS; i += 7) {
                assert_true(fx_same(&rays_in[i], &rays_out[i])); /* holes untouched */
                rays_out[i] = rays_ref[i];
            }
            assert_int_equal(count_diff(name), 0);
            snprintf(name, sizeof name, "%s %s tiles of %d", what, hz_accel_kernel_name(ks[q]), pw);
            fx_trace_tiles(a, ks[q], HZ_ACCEL_COHERENT, pw, 40, true, rays_in, rays_out, NULL, N_RAYS, NULL);
            for (uint32_t i = 6; i < N_RAYS; i += 7)
                rays_out[i] = rays_ref[i];
            assert_int_equal(count_diff(name), 0);
            fx_occlusion(a, ks[q], HZ_ACCEL_COHERENT, pw, rays_in, occ_out, N_RAYS, NULL);
            uint32_t bad = 0;
            for (uint32_t i = 0; i < N_RAYS; i++)
                bad += occ_out[i] != (rays_ref[i].hit.geom_id == 0);
            fx_trace_tiles(a, ks[q], HZ_ACCEL_COHERENT, pw, 40, false, rays_in, NULL, occ_out, N_RAYS, NULL);
            for (uint32_t i = 0; i < N_RAYS; i++)
                bad += occ_out[i] != (rays_ref[i].hit.geom_id == 0);
            if (bad)
                print_message("%s occlusion: %u differ\n", name, bad);
            assert_int_equal(bad, 0);
        }
    }
}

static void test_instances_exact(void **state)
{
    (void)state;
    for (int moving = 0; moving < 2; moving++) {
        const hz_arena_mark_t m0 = hz_arena_mark(&arena);
        make_world(&W, moving != 0, false);
        hz_accel_t *a;
        hz_error_t err;
        hz_accel_config_t cfg;
        hz_accel_config_default(&cfg);
        const hz_accel_bytes_t bound = hz_accel_bytes_bound_geom(&W.g, &cfg);
        const size_t before = arena.used;
        assert_int_equal(hz_accel_build_native(&a, &W.g, &cfg, &arena, &err), HZ_OK);
        assert_true(arena.used - before <= bound.kept);
        assert_true(a->info.bytes_peak <= bound.peak);
        assert_int_equal(a->info.instances, 2);
        assert_int_equal(a->info.instance_tris, W.inst[0].tri_count + W.inst[1].tri_count);
        assert_int_equal(a->info.time_keys, K);
        make_rays(&W, 11u + (uint32_t)moving);
        check_forms(a, &W, moving ? "moving rest" : "static rest");
        /* new matrices (and rest keys): a refit reads them */
        pose(&W, moving != 0, 0.7f);
        assert_int_equal(hz_accel_refit(a, &err), HZ_OK);
        make_rays(&W, 21u + (uint32_t)moving);
        check_forms(a, &W, moving ? "moving rest, refitted" : "static rest, refitted");
        hz_arena_reset(&arena, m0);
    }
}

/* Rays aimed at points of the world-space triangles (each vertex moved by its key matrix here, lerped between
 * keys): they hit at the aimed distance, on the aimed triangle or one as close. Nothing of the accel's transform
 * code is used to make them. */
static void test_aimed_points(void **state)
{
    (void)state;
    const hz_arena_mark_t m0 = hz_arena_mark(&arena);
    make_world(&W, false, false);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &W.g, NULL, &arena, &err), HZ_OK);
    uint32_t st = 99u, aimed = 0, ok = 0, normals = 0;
    int32_t normals_ok = 0;
    for (uint32_t i = 0; i < N_RAYS / 2u; i++) {
        const int in = (int)(i & 1u);
        const uint32_t t = W.inst[in].tri_first + (uint32_t)(unit01(&st) * (float)W.inst[in].tri_count);
        const float time = unit01(&st), b1 = 0.1f + 0.4f * unit01(&st), b2 = 0.1f + 0.4f * unit01(&st);
        const hz_vec3_t p = hz_meshgen_tri_point(&W.g, t, time, b1, b2);
        /* from outside the scene, 3 units away */
        const float d[3] = { unit01(&st) - 0.5f, unit01(&st) - 0.5f, unit01(&st) - 0.5f };
        const float n = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const float o[3] = { p.x - 3.0f * d[0] / n, p.y - 3.0f * d[1] / n, p.z - 3.0f * d[2] / n };
        const float dir[3] = { d[0] / n, d[1] / n, d[2] / n };
        hz_rayhit_t rh;
        fx_set_ray(&rh, o, dir, 0.0f, INFINITY, i);
        rh.ray.time = time;
        hz_accel_intersect1(a, NULL, &rh);
        aimed++;
        /* the first hit is at 3 or before (something else in front); at 3 it must be found */
        if (rh.hit.geom_id == 0 && rh.ray.tfar <= 3.0f + 1e-4f)
            ok++;
        if (rh.hit.geom_id != 0 || rh.hit.prim_id != t)
            continue;
        const hz_vec3_t dv = hz_v3(dir[0], dir[1], dir[2]);
        /* the hit's geometric normal is the world triangle's (v1 - v0) x (v2 - v0), length and sign */
        hz_vec3_t q[3];
        for (int k = 0; k < 3; k++)
            q[k] = hz_meshgen_tri_point(&W.g, t, time, k == 1 ? 1.0f : 0.0f, k == 2 ? 1.0f : 0.0f);
        const hz_vec3_t ng = hz_v3_cross(hz_v3_sub(q[1], q[0]), hz_v3_sub(q[2], q[0]));
        const hz_vec3_t got = hz_v3(rh.hit.ng_x, rh.hit.ng_y, rh.hit.ng_z);
        if (fabsf(hz_v3_dot(ng, dv)) < 0.05f * hz_v3_len(ng))
            continue; /* grazing: a rounding of the plane moves the point far along it */
        normals++;
        const bool n_ok = hz_v3_dot(ng, got) > 0.0f && hz_v3_len(hz_v3_sub(ng, got)) <= 1e-3f * hz_v3_len(ng);
        /* and u, v the aimed point (at grazing angles u, v move fast: compare the points) */
        const hz_vec3_t at = hz_meshgen_tri_point(&W.g, t, time, rh.hit.u, rh.hit.v);
        const bool uv_ok = hz_v3_len(hz_v3_sub(at, p)) < 1e-4f;
        normals_ok += n_ok && uv_ok;
        if (!(n_ok && uv_ok))
            print_message("t %.9g: prim %u time %g: ng %g %g %g (expected %g %g %g), u %g v %g (aimed %g %g)\n",
                          (double)rh.ray.tfar, t,
                          (double)time, (double)got.x, (double)got.y, (double)got.z, (double)ng.x, (double)ng.y,
                          (double)ng.z, (double)rh.hit.u, (double)rh.hit.v, (double)b1, (double)b2);
    }
    assert_int_equal(ok, aimed);
    print_message("%u of %u aimed rays hit the aimed triangle first\n", normals, aimed);
    assert_true(normals > aimed / 4);
    assert_int_equal(normals_ok, (int32_t)normals);
    hz_arena_reset(&arena, m0);
}

/* Any-hit through instances: the view's triangle index, and the side of the world triangle at the ray's time. */
typedef struct ah {
    const world_t *w;
    uint32_t calls, checked, wrong_side, wrong_prim;
} ah_t;

static bool anyhit_cb(void *user, uint32_t prim, float u, float v, float t, uint32_t ray_id, int lane, unsigned back)
{
    (void)u, (void)v, (void)t, (void)lane;
    ah_t *h = user;
    h->calls++;
    if (prim >= h->w->tri_count || !(h->w->flags[prim] & HZ_ACCEL_TRI_ANYHIT)) {
        h->wrong_prim++;
        return true;
    }
    const hz_ray_t *r = &rays_in[ray_id].ray;
    hz_vec3_t p[3];
    for (int k = 0; k < 3; k++)
        p[k] = hz_meshgen_tri_point(&h->w->g, prim, r->time, k == 1 ? 1.0f : 0.0f, k == 2 ? 1.0f : 0.0f);
    const hz_vec3_t e1 = hz_v3_sub(p[1], p[0]), e2 = hz_v3_sub(p[2], p[0]), ng = hz_v3_cross(e1, e2);
    const hz_vec3_t d = hz_v3(r->dir_x, r->dir_y, r->dir_z);
    const float dn = hz_v3_dot(d, ng);
    if (fabsf(dn) > 1e-3f * hz_v3_len(d) * hz_v3_len(ng)) { /* not grazing: the side is clear */
        h->checked++;
        h->wrong_side += back != (dn > 0.0f);
    }
    return (prim + ray_id) % 2u == 0u; /* accept some */
}

static void test_anyhit_side(void **state)
{
    (void)state;
    const hz_arena_mark_t m0 = hz_arena_mark(&arena);
    make_world(&W, false, true);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &W.g, NULL, &arena, &err), HZ_OK);
    make_rays(&W, 5u);
    for (uint32_t i = 0; i < N_RAYS; i++)
        rays_in[i].ray.id = i;
    ah_t h = { &W, 0, 0, 0, 0 };
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    ctx.anyhit = anyhit_cb, ctx.user = &h;
    fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, rays_in, rays_out, N_RAYS, &ctx);
    fx_trace_packets(a, HZ_ACCEL_KERNEL_AUTO, HZ_ACCEL_COHERENT, 8, false, rays_in, rays_out, N_RAYS, &ctx);
    fx_trace_tiles(a, HZ_ACCEL_KERNEL_AUTO, HZ_ACCEL_COHERENT, 8, 16, false, rays_in, rays_out, NULL, N_RAYS, &ctx);
    assert_true(h.calls > N_RAYS / 4);
    assert_true(h.checked > h.calls / 2);
    assert_int_equal(h.wrong_prim, 0);
    assert_int_equal(h.wrong_side, 0);
    hz_arena_reset(&arena, m0);
}

static void test_refit_choice_and_stats(void **state)
{
    (void)state;
    const hz_arena_mark_t m0 = hz_arena_mark(&arena);
    make_world(&W, true, false);
    hz_accel_t *a;
    hz_error_t err;
    hz_accel_config_t cfg;
    hz_accel_config_default(&cfg);
    cfg.rigid = HZ_ACCEL_RIGID_REFIT;
    assert_int_equal(hz_accel_build_native(&a, &W.g, &cfg, &arena, &err), HZ_OK);
    assert_int_equal(a->info.instances, 0);
    assert_int_equal(a->info.ref_count >= W.g.tri_count, true);
    /* against brute force over the keys: the view without its instances */
    hz_accel_geom_t plain = W.g;
    plain.instance_count = 0, plain.instances = NULL;
    make_rays(&W, 7u);
    uint32_t bad = 0;
    for (uint32_t i = 0; i < N_RAYS; i += 3) {
        hz_rayhit_t b = rays_in[i], r = rays_in[i];
        hz_accel_brute_intersect1(&plain, &b);
        hz_accel_intersect1(a, NULL, &r);
        bad += !fx_same(&b, &r);
    }
    assert_int_equal(bad, 0);
    /* with instances, a query counts each ray once (HZ_FEATURE_STATS boards) */
    hz_accel_t *ai;
    assert_int_equal(hz_accel_build_native(&ai, &W.g, NULL, &arena, &err), HZ_OK);
    hz_accel_stats_t st;
    memset(&st, 0, sizeof st);
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    ctx.stats = &st;
    fx_trace1(ai, HZ_ACCEL_KERNEL_AUTO, rays_in, rays_out, 1000, &ctx);
    fx_trace_tiles(ai, HZ_ACCEL_KERNEL_AUTO, HZ_ACCEL_COHERENT, 8, 4, false, rays_in, rays_out, NULL, 1000, &ctx);
    if (HZ_FEATURE_STATS) {
        assert_int_equal(st.rays, 2000);
        assert_true(st.tris > 0 && st.nodes > 0);
    }
    hz_arena_reset(&arena, m0);
}

static void test_bad_instances(void **state)
{
    (void)state;
    const hz_arena_mark_t m0 = hz_arena_mark(&arena);
    make_world(&W, false, false);
    hz_accel_t *a;
    hz_error_t err;
    hz_accel_instance_t two[2] = { W.inst[0], W.inst[1] };
    hz_accel_geom_t g = W.g;
    g.instances = two;
    two[1].tri_first = two[0].tri_first + 1u; /* overlaps */
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_E_RANGE);
    assert_non_null(strstr(err.msg, "rigid instance 1"));
    two[1] = W.inst[1];
    two[1].tri_count = W.g.tri_count; /* past the view */
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_E_RANGE);
    two[1] = W.inst[1];
    two[1].xform[K - 1u] = NULL;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "no matrix at key"));
    two[1] = W.inst[1];
    two[1].obj_pos = W.obj + 1; /* misaligned */
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_E_INVALID_ARG);
    two[1] = W.inst[1];
    g.instance_count = HZ_ACCEL_MAX_INSTANCES + 1u;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_E_RANGE);
    g.instance_count = 2;
    g.time_keys = 0;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "need time keys"));
    /* a singular matrix at every key: the instance is flat, rays pass it (never a crash or a hit) */
    g = W.g;
    two[0] = W.inst[0], two[1] = W.inst[1];
    g.instances = two;
    static float zero[12];
    for (uint32_t k = 0; k < K; k++)
        two[0].xform[k] = zero;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    make_rays(&W, 3u);
    for (uint32_t i = 0; i < N_RAYS; i += 5) {
        hz_rayhit_t r = rays_in[i];
        hz_accel_intersect1(a, NULL, &r);
        assert_false(r.hit.geom_id == 0 && r.hit.prim_id >= W.inst[0].tri_first &&
                     r.hit.prim_id < W.inst[0].tri_first + W.inst[0].tri_count);
    }
    hz_arena_reset(&arena, m0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_instances),         cmocka_unit_test(test_aimed_points),
        cmocka_unit_test(test_anyhit_side),           cmocka_unit_test(test_refit_choice_and_stats),
        cmocka_unit_test(test_instances_exact),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
