/* Stage rays: rays and cameras at the edges of their contracts. Rays through the accel (every kernel against
 * the scalar one, analytic or double-precision oracles); cameras through the whole renderer (every output
 * value finite, the renderer's own non-finite counter 0). */
#include <stdlib.h>

#include "hz/hash.h"
#include "hz/meshgen.h"
#include "stab_util.h"

/* Axis-parallel rays (two zero direction components) and rays with one zero component from inside a cube
 * (cube_sphere, not rounded): the faces are at +-1, so t is known exactly. */
static void c_zero_dir_components(stab_result_t *r)
{
    hz_error_t err;
    hz_mesh_t m;
    STAB_OK(r, hz_meshgen_cube_sphere(&m, &hz_pools_get()->scene, 7, 1.0f, false, &err), &err);
    uint32_t n = 3000;
    hz_rayhit_t *rays = malloc(sizeof *rays * n);
    hz_rng_t g;
    hz_rng_seed(&g, 31, 1);
    for (uint32_t i = 0; i < n; i++) {
        double o[3], d[3] = { 0, 0, 0 };
        for (int k = 0; k < 3; k++)
            o[k] = 1.8 * su_unit(&g) - 0.9;
        int ax = (int)(i % 3);
        d[ax] = i & 4 ? -1.0 : 1.0;
        if (i & 8) /* one zero component instead of two */
            d[(ax + 1) % 3] = 0.5 - su_unit(&g);
        su_ray(&rays[i], o[0], o[1], o[2], d[0], d[1], d[2]);
    }
    su_check_mesh(r, m.pos, m.vertex_count, m.tri, m.tri_count, rays, n, true, m.tri_count, 1e-5);
    free(rays);
}

/* Rays the contract rules out: zero direction, NaN or Inf in origin or direction, tnear > tfar, NaN tfar,
 * negative tnear: every kernel misses (no crash, no loop), occlusion too. */
static void c_invalid_rays(stab_result_t *r)
{
    hz_error_t err;
    hz_mesh_t m;
    STAB_OK(r, hz_meshgen_cube_sphere(&m, &hz_pools_get()->scene, 4, 1.0f, true, &err), &err);
    hz_accel_t *a;
    STAB_OK(r, su_accel(&a, m.pos, m.vertex_count, m.tri, m.tri_count, &err), &err);
    enum { N = 10 };
    hz_rayhit_t rays[N], out[N];
    su_ray(&rays[0], 0, 0, 0, 0, 0, 0);
    su_ray(&rays[1], 0, 0, 0, NAN, 0, 1);
    su_ray(&rays[2], 0, 0, 0, INFINITY, 0, 0);
    su_ray(&rays[3], NAN, 0, 0, 0, 0, 1);
    su_ray(&rays[4], 0, -INFINITY, 0, 0, 1, 0);
    su_ray(&rays[5], 0, 0, 0, 0, 0, 1), rays[5].ray.tnear = 2.0f, rays[5].ray.tfar = 1.0f;
    su_ray(&rays[6], 0, 0, 0, 0, 0, 1), rays[6].ray.tfar = NAN;
    su_ray(&rays[7], 0, 0, 0, 0, 0, 1), rays[7].ray.tnear = NAN;
    su_ray(&rays[8], 0, 0, 0, 0, 0, -0.0), rays[8].ray.dir_z = -0.0f;
    /* a subnormal direction: the hit's t (1e45) is beyond float, so it misses, never with a non-finite t */
    su_ray(&rays[9], 0, 0, 0, 1e-45, 0, 0);
    su_check_kernels(r, a, rays, N, out);
    STAB_BAIL(r);
    for (int i = 0; i < N; i++)
        STAB_CHECK(r, out[i].hit.geom_id == HZ_ACCEL_INVALID_ID, "invalid ray %d hit", i);
    /* a tiny but normal direction: t = 1e30 is representable, so it hits */
    hz_rayhit_t tiny, tout;
    su_ray(&tiny, 0, 0, 0, 0, 1e-30, 0);
    su_check_kernels(r, a, &tiny, 1, &tout);
    STAB_BAIL(r);
    STAB_CHECK(r, tout.hit.geom_id != HZ_ACCEL_INVALID_ID, "ray with a 1e-30 direction missed");
    stab_error(r, su_relerr(tout.ray.tfar * 1e-30, 1.0, 1.0));
    STAB_CHECK(r, r->max_error < 1e-2, "distance along a 1e-30 direction off by %g", r->max_error);
    stab_note(r, "10 invalid rays miss; a 1e-30 direction hits at t %g", (double)tout.ray.tfar);
}

/* tnear == tfar: the hit at exactly that t counts (both ends inclusive); one ulp beyond it does not. */
static void c_tnear_equals_tfar(stab_result_t *r)
{
    float pos[12] = { -1, -1, 0, 0, 1, -1, 0, 0, 0, 1, 0, 0 };
    uint32_t tri[3] = { 0, 1, 2 };
    hz_error_t err;
    hz_accel_t *a;
    STAB_OK(r, su_accel(&a, pos, 3, tri, 1, &err), &err);
    hz_rayhit_t rays[4], out[4];
    for (int i = 0; i < 4; i++)
        su_ray(&rays[i], 0.1, 0.1, 1.0, 0, 0, -1);
    rays[0].ray.tnear = rays[0].ray.tfar = 1.0f;                          /* exactly at the plane */
    rays[1].ray.tnear = rays[1].ray.tfar = nextafterf(1.0f, 2.0f);        /* just behind */
    rays[2].ray.tnear = rays[2].ray.tfar = nextafterf(1.0f, 0.0f);        /* just before */
    rays[3].ray.tnear = 0.0f, rays[3].ray.tfar = 1.0f;                    /* tfar exactly at the plane */
    su_check_kernels(r, a, rays, 4, out);
    STAB_BAIL(r);
    STAB_CHECK(r, out[0].hit.geom_id != HZ_ACCEL_INVALID_ID && out[0].ray.tfar == 1.0f, "t = tnear = tfar missed");
    STAB_CHECK(r, out[1].hit.geom_id == HZ_ACCEL_INVALID_ID, "hit outside [tnear, tfar] (behind)");
    STAB_CHECK(r, out[2].hit.geom_id == HZ_ACCEL_INVALID_ID, "hit outside [tnear, tfar] (before)");
    STAB_CHECK(r, out[3].hit.geom_id != HZ_ACCEL_INVALID_ID, "hit at t = tfar missed");
    stab_note(r, "inclusive at both ends; one ulp outside misses");
}

/* Secondary rays from surfaces: points where random rays hit a sphere of radius s (1e-6, 1, 1e6), moved off
 * the surface with hz_accel_offset_origin, start rays into the outer hemisphere: none may hit the sphere
 * again (self-intersection); rays into the inner hemisphere must hit the far side (not the near one). */
static void offset_case(stab_result_t *r, float s)
{
    hz_error_t err;
    hz_mesh_t m;
    STAB_OK(r, hz_meshgen_sphere(&m, &hz_pools_get()->scene, 24, 48, s, &err), &err);
    hz_accel_t *a;
    STAB_OK(r, su_accel(&a, m.pos, m.vertex_count, m.tri, m.tri_count, &err), &err);
    hz_rng_t g;
    hz_rng_seed(&g, 77, 2);
    uint32_t n = 2000, self = 0, through = 0, far_ok = 0;
    for (uint32_t i = 0; i < n; i++) {
        double d[3];
        su_random_dir(&g, i, d);
        hz_rayhit_t p;
        su_ray(&p, 0, 0, 0, d[0], d[1], d[2]);
        hz_accel_intersect1(a, NULL, &p);
        STAB_CHECK(r, p.hit.geom_id != HZ_ACCEL_INVALID_ID, "primary ray %u leaked", i);
        hz_vec3_t hp = hz_v3(p.ray.tfar * p.ray.dir_x, p.ray.tfar * p.ray.dir_y, p.ray.tfar * p.ray.dir_z);
        hz_vec3_t ng = hz_v3(p.hit.ng_x, p.hit.ng_y, p.hit.ng_z);
        if (hz_v3_dot(ng, hp) < 0)
            ng = hz_v3_neg(ng); /* outward */
        for (int side = 0; side < 2; side++) {
            hz_vec3_t nn = side ? hz_v3_neg(ng) : ng;
            hz_vec3_t o = hz_accel_offset_origin(hp, nn, s);
            double e[3];
            su_random_dir(&g, i + 1, e);
            hz_vec3_t dir = hz_v3((float)e[0], (float)e[1], (float)e[2]);
            if (hz_v3_dot(dir, nn) <= 0)
                dir = hz_v3_neg(dir);
            if (hz_v3_dot(dir, nn) < 1e-3f * hz_v3_len(nn))
                continue;
            hz_rayhit_t q;
            su_ray(&q, o.x, o.y, o.z, dir.x, dir.y, dir.z);
            const float of[3] = { o.x, o.y, o.z };
            stab_count_nonfinite(r, of, 3);
            hz_accel_intersect1(a, NULL, &q);
            bool hit = q.hit.geom_id != HZ_ACCEL_INVALID_ID;
            if (getenv("HZSTAB_DEBUG") && hit)
                fprintf(stderr, "side %d hit t %g prim %u (from %u) dot %g\n", side, (double)q.ray.tfar,
                        q.hit.prim_id, p.hit.prim_id, (double)(hz_v3_dot(dir, nn) / hz_v3_len(nn)));
            if (!side)
                self += hit; /* outward from a convex surface: nothing to hit */
            else if (!hit)
                through++;
            else if (q.hit.prim_id == p.hit.prim_id)
                self++; /* inward: the surface it left is behind it */
            else
                far_ok++;
        }
    }
    stab_note(r, "radius %g: %u self-hits; %u inward rays lost; %u reached the far side", (double)s, self, through,
              far_ok);
    STAB_CHECK(r, self == 0, "%u secondary rays hit the surface they left", self);
    STAB_CHECK(r, through == 0, "%u inward secondary rays escaped the sphere", through);
}

static void c_origins_on_surface_1(stab_result_t *r) { offset_case(r, 1.0f); }
static void c_origins_on_surface_1e_6(stab_result_t *r) { offset_case(r, 1e-6f); }
static void c_origins_on_surface_1e6(stab_result_t *r) { offset_case(r, 1e6f); }

/* Grazing rays over a 200 x 200 quad at z = 0, starting 1e-2 above it with slopes from 1e-2 down to 1e-6:
 * hit iff the analytic crossing point lies on the quad (decided away from its border), t to 1e-4. */
static void c_grazing(stab_result_t *r)
{
    float pos[16] = { -100, -100, 0, 0, 100, -100, 0, 0, 100, 100, 0, 0, -100, 100, 0, 0 };
    uint32_t tri[6] = { 0, 1, 2, 0, 2, 3 };
    hz_error_t err;
    hz_accel_t *a;
    STAB_OK(r, su_accel(&a, pos, 4, tri, 2, &err), &err);
    uint32_t n = 2048, hits = 0, decided = 0;
    hz_rayhit_t *rays = malloc(sizeof *rays * n), *out = malloc(sizeof *out * n);
    for (uint32_t i = 0; i < n; i++) {
        double slope = pow(10.0, -2.0 - 4.0 * (i % 64) / 63.0), phi = 6.283185307179586 * (i / 64) / 32.0;
        su_ray(&rays[i], -50.0 + (double)(i % 7), -50.0 + (double)(i % 11), 1e-2, cos(phi), sin(phi), -slope);
    }
    su_check_kernels(r, a, rays, n, out);
    STAB_BAIL(r);
    for (uint32_t i = 0; i < n; i++) {
        double dz = rays[i].ray.dir_z, t = -rays[i].ray.org_z / dz;
        double x = rays[i].ray.org_x + t * rays[i].ray.dir_x, y = rays[i].ray.org_y + t * rays[i].ray.dir_y;
        bool in = fabs(x) < 100 && fabs(y) < 100, hit = out[i].hit.geom_id != HZ_ACCEL_INVALID_ID;
        hits += hit;
        if (fabs(fabs(x) - 100) < 1e-2 * t || fabs(fabs(y) - 100) < 1e-2 * t)
            continue;
        decided++;
        STAB_CHECK(r, hit == in, "grazing ray %u (slope %g): hit %d, analytic %d", i, -dz, hit, in);
        if (hit)
            stab_error(r, su_relerr(out[i].ray.tfar, t, 1e-300));
    }
    stab_note(r, "%u rays; slopes 1e-2..1e-6; %u decided; %u hit", n, decided, hits);
    STAB_CHECK(r, hits > 0 && r->max_error <= 1e-4, "t error %g (%u hits)", r->max_error, hits);
    free(rays), free(out);
}

/* ---- cameras, through the renderer ---- */

static void render_seq(stab_result_t *r, const su_scene_t *b, uint32_t w, uint32_t h, hz_render_mode_t mode,
                       uint32_t spp, uint32_t frames, double *hit_frac)
{
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = w, o.height = h, o.mode = mode, o.spp = spp;
    su_render_t s;
    hz_error_t err;
    STAB_OK(r, su_render_open(&s, b, &o, &err), &err);
    for (uint32_t f = 0; f < frames; f++)
        STAB_OK(r, su_render_frame(&s, f, (float)f / 60.0f, &err), &err);
    su_render_check(r, &s);
    const hz_gbuffer_t *gb = hz_render_gbuffer(s.r);
    size_t hits = 0, n = (size_t)w * h;
    for (size_t i = 0; i < n; i++)
        hits += gb->object[i] != HZ_GB_NO_OBJECT;
    if (hit_frac)
        *hit_frac = (double)hits / (double)n;
    su_render_close(&s);
}

static void room_with_camera(su_scene_t *b, const float eye[3], const float target[3], float fov)
{
    su_begin(b);
    su_room(b, 1.0f);
    su_camera(b, 0, eye, target, fov);
}

/* Inside a closed sphere of radius 3 with a sphere in the middle: every direction hits something. */
static hz_status_t enclosed(su_scene_t *b, const float eye[3], const float target[3], float fov, hz_error_t *err)
{
    hz_mesh_t m;
    hz_arena_mark_t mk = hz_arena_mark(&hz_pools_get()->frame);
    hz_status_t s = hz_meshgen_cube_sphere(&m, &hz_pools_get()->frame, 8, 1.0f, true, err);
    if (s != HZ_OK)
        return s;
    su_begin(b);
    const float off[3] = { 0, 0, 0 }, off2[3] = { 0.5f, 0, -1.5f };
    su_mesh(b, m.pos, m.vertex_count, m.tri, m.tri_count, su_material(b, 0.5f, 0.6f, 0.7f), 3.0f, off);
    su_object(b);
    su_mesh(b, m.pos, m.vertex_count, m.tri, m.tri_count, su_material(b, 0.9f, 0.2f, 0.2f), 0.4f, off2);
    su_object(b);
    hz_arena_reset(&hz_pools_get()->frame, mk);
    su_light(b, 0.5f, 1, 0.2f, 5);
    su_camera(b, 0, eye, target, fov);
    return HZ_OK;
}

static void fov_case(stab_result_t *r, float degrees)
{
    su_scene_t b;
    hz_error_t err;
    const float eye[3] = { 0.3f, -0.2f, 0.1f }, target[3] = { 0.5f, 0, -1.5f };
    STAB_OK(r, enclosed(&b, eye, target, degrees * 3.14159265f / 180.0f, &err), &err);
    double frac = 0;
    static const hz_render_mode_t modes[3] = { HZ_MODE_FULL, HZ_MODE_TAA, HZ_MODE_TDENSE };
    for (int m = 0; m < 3; m++) {
        render_seq(r, &b, 64, 36, modes[m], m ? 1 : 4, m ? 6 : 1, &frac);
        STAB_BAIL(r);
    }
    stab_note(r, "fov %g deg: %.0f%% of pixels hit; full 4 spp / TAA / tdense finite", (double)degrees, 100 * frac);
    STAB_CHECK(r, frac == 1.0, "%.2f%% of pixels saw out of a closed sphere", 100 * (1 - frac));
}

static void c_fov_1(stab_result_t *r) { fov_case(r, 1.0f); }
static void c_fov_179(stab_result_t *r) { fov_case(r, 179.0f); }

/* A field of view of 180 degrees (or 0) is refused by the loader naming the camera key. */
static void c_fov_180_refused(stab_result_t *r)
{
    su_scene_t b;
    const float eye[3] = { 0, 1.5f, 6 }, target[3] = { 0, 1.2f, 0 };
    room_with_camera(&b, eye, target, 3.14159265f);
    hz_scene_t sc;
    hz_error_t err;
    hz_status_t s = su_load(&b, &sc, &err);
    STAB_REFUSED(r, s, HZ_E_RANGE, &err, "camera key 0");
}

/* Eye equal to target: refused by the loader (HZ_E_RANGE) naming the key. */
static void c_eye_equals_target(stab_result_t *r)
{
    su_scene_t b;
    const float eye[3] = { 0, 1.5f, 6 };
    room_with_camera(&b, eye, eye, 1.0f);
    hz_scene_t sc;
    hz_error_t err;
    hz_status_t s = su_load(&b, &sc, &err);
    STAB_REFUSED(r, s, HZ_E_RANGE, &err, "camera key 0");
}

/* Up vector parallel to the view direction (looking straight down): the camera basis falls back to another
 * axis; every pixel finite. */
static void c_up_parallel_view(stab_result_t *r)
{
    su_scene_t b;
    const float eye[3] = { 0, 8, 0 }, target[3] = { 0, 0, 0 };
    room_with_camera(&b, eye, target, 1.0f);
    double frac = 0;
    render_seq(r, &b, 48, 48, HZ_MODE_FULL, 1, 1, &frac);
    STAB_BAIL(r);
    stab_note(r, "looking along up: %.0f%% hit", 100 * frac);
    STAB_CHECK(r, frac > 0.9, "only %.1f%% of pixels hit the floor below", 100 * frac);
}

/* The camera inside a closed sphere (with a light inside): every pixel hits it. */
static void c_camera_inside(stab_result_t *r)
{
    hz_error_t err;
    su_scene_t b;
    const float eye[3] = { 0.3f, -0.2f, 0.1f }, target[3] = { 1, 0, -1 };
    STAB_OK(r, enclosed(&b, eye, target, 2.0f, &err), &err);
    double frac = 0;
    render_seq(r, &b, 64, 48, HZ_MODE_FULL, 1, 1, &frac);
    STAB_BAIL(r);
    stab_note(r, "%.1f%% of pixels hit the enclosing sphere", 100 * frac);
    STAB_CHECK(r, frac == 1.0, "%.3f%% of pixels saw out of a closed sphere", 100 * (1 - frac));
}

static void size_case(stab_result_t *r, uint32_t w, uint32_t h)
{
    su_scene_t b;
    const float eye[3] = { 0, 1.5f, 6 }, target[3] = { 0, 1.2f, 0 };
    room_with_camera(&b, eye, target, 1.0f);
    static const hz_render_mode_t modes[3] = { HZ_MODE_FULL, HZ_MODE_TAA, HZ_MODE_TDENSE };
    for (int m = 0; m < 3; m++) {
        render_seq(r, &b, w, h, modes[m], 1, m ? 5 : 1, NULL);
        STAB_BAIL(r);
    }
    stab_note(r, "%ux%u in full / TAA / tdense: finite", w, h);
}

static void c_image_1x1(stab_result_t *r) { size_case(r, 1, 1); }
static void c_image_4096x16(stab_result_t *r) { size_case(r, 4096, 16); }
static void c_image_3x4097(stab_result_t *r) { size_case(r, 3, 4097); }

/* Sizes beyond the limits are refused by the option check, naming the option. */
static void c_image_size_refused(stab_result_t *r)
{
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    hz_error_t err;
    o.width = 0, o.height = 16;
    hz_status_t s = hz_render_opts_check(&o, &err);
    STAB_REFUSED(r, s, HZ_E_INVALID_ARG, &err, "0x16");
    o.width = HZ_IMAGE_MAX_DIM + 1;
    s = hz_render_opts_check(&o, &err);
    STAB_REFUSED(r, s, HZ_E_INVALID_ARG, &err, "16385x16");
}

static const stab_case_t cases[] = {
    { "zero_dir_components", "axis-parallel rays in a cube: 0 leaks; t vs oracle <= 1e-5", c_zero_dir_components,
      0 },
    { "invalid_rays", "zero/NaN/Inf direction or origin; bad [tnear tfar]: every kernel misses", c_invalid_rays, 0 },
    { "tnear_equals_tfar", "interval ends inclusive; one ulp outside misses", c_tnear_equals_tfar, 0 },
    { "origins_on_surface", "offset secondary origins (radius 1): 0 self-hits; inward rays reach far side",
      c_origins_on_surface_1, 0 },
    { "origins_on_surface_1e-6", "the same at radius 1e-6", c_origins_on_surface_1e_6, 0 },
    { "origins_on_surface_1e6", "the same at radius 1e6", c_origins_on_surface_1e6, 0 },
    { "grazing", "slopes 1e-2..1e-6 over a quad: hit/miss as analytic; t <= 1e-4", c_grazing, 0 },
    { "fov_1", "fov 1 degree in full/TAA/tdense (inside a sphere): finite; every pixel hits", c_fov_1, 0 },
    { "fov_179", "fov 179 degrees in full/TAA/tdense (inside a sphere): finite; every pixel hits", c_fov_179, 0 },
    { "fov_180_refused", "fov 180 degrees: refused (range) naming the camera key", c_fov_180_refused, 0 },
    { "eye_equals_target", "eye == target: refused (range) naming the camera key", c_eye_equals_target, 0 },
    { "up_parallel_view", "up parallel to the view: basis falls back; finite; floor seen", c_up_parallel_view, 0 },
    { "camera_inside", "camera inside a closed sphere: every pixel hits; finite", c_camera_inside, 0 },
    { "image_1x1", "1x1 image in full/TAA/tdense: finite", c_image_1x1, 0 },
    { "image_4096x16", "4096x16 image in full/TAA/tdense: finite", c_image_4096x16, 0 },
    { "image_3x4097", "3x4097 image (odd tiles) in full/TAA/tdense: finite", c_image_3x4097, 0 },
    { "image_size_refused", "width 0 and 16385: refused (invalid argument) naming the option",
      c_image_size_refused, 0 },
};
STAB_STAGE(rays, cases);
