/* Stage geometry: the accel (BVH build and every traversal kernel) on degenerate, extreme-scale and
 * pathological meshes. Oracles: a ray from inside a closed mesh must hit it (0 leaks); a double-precision
 * Moller-Trumbore over every triangle for t (where the decision is not a near-tie); the scalar kernel for the
 * SIMD kernels and packets (bit-identical by contract). */
#include <stdlib.h>
#include <unistd.h>

#include "hz/hash.h"
#include "hz/meshgen.h"
#include "scenefile.h"
#include "stab_util.h"

static void sphere_case(stab_result_t *r, float radius, hz_vec3_t offset, uint32_t n, double t_bound)
{
    hz_error_t err;
    hz_mesh_t m;
    STAB_OK(r, hz_meshgen_cube_sphere(&m, &hz_pools_get()->scene, r->full ? 24 : 8, 1.0f, true, &err), &err);
    hz_meshgen_transform(&m, radius, offset);
    double c[3] = { offset.x, offset.y, offset.z };
    hz_rayhit_t *rays = su_inside_rays(n, c, 0.5 * radius, 11);
    su_check_mesh(r, m.pos, m.vertex_count, m.tri, m.tri_count, rays, n, true, m.tri_count, t_bound);
    free(rays);
}

static void c_unit_sphere(stab_result_t *r)
{
    sphere_case(r, 1.0f, hz_v3(0, 0, 0), r->full ? 100000 : 1500, 1e-4);
}

static void c_scale_1e_6(stab_result_t *r)
{
    sphere_case(r, 1e-6f, hz_v3(0, 0, 0), r->full ? 20000 : 1200, 1e-4);
}

static void c_scale_1e6(stab_result_t *r)
{
    sphere_case(r, 1e6f, hz_v3(0, 0, 0), r->full ? 20000 : 1200, 1e-4);
}

/* A unit sphere a million units from the origin: coordinates keep ~0.06 of resolution, shared vertices stay
 * shared, so the mesh stays closed. */
static void c_far_from_origin(stab_result_t *r)
{
    sphere_case(r, 1.0f, hz_v3(1e6f, -1e6f, 1e6f), r->full ? 20000 : 1200, 1e-2);
}

/* Coordinates of 6e10, just inside the accel's range (HZ_ACCEL_MAX_COORD = 2^36): products of three
 * coordinate differences reach 1e33 and must stay finite. */
static void c_scale_6e10(stab_result_t *r)
{
    sphere_case(r, 6e10f, hz_v3(0, 0, 0), r->full ? 20000 : 1200, 1e-4);
}

/* Near the top of the float range (3e38 = FLT_MAX / 1.1), beyond the accel's range: the build keeps every
 * such triangle out (counted), every ray misses, nothing non-finite comes out; a scene file with such
 * positions is refused naming the section and the element. */
static void c_near_float_max(stab_result_t *r)
{
    hz_error_t err;
    hz_mesh_t m;
    STAB_OK(r, hz_meshgen_cube_sphere(&m, &hz_pools_get()->scene, 6, 1.0f, true, &err), &err);
    hz_meshgen_transform(&m, 3e38f, hz_v3(0, 0, 0));
    hz_accel_t *a;
    STAB_OK(r, su_accel(&a, m.pos, m.vertex_count, m.tri, m.tri_count, &err), &err);
    STAB_CHECK(r, a->info.tri_skipped == m.tri_count, "%u of %u out-of-range triangles kept", 
               m.tri_count - a->info.tri_skipped, m.tri_count);
    double c[3] = { 0, 0, 0 };
    hz_rayhit_t *rays = su_inside_rays(2000, c, 1e10, 5);
    hz_rayhit_t *out = malloc(sizeof *out * 2000);
    su_check_kernels(r, a, rays, 2000, out);
    STAB_BAIL(r);
    for (uint32_t i = 0; i < 2000; i++)
        STAB_CHECK(r, out[i].hit.geom_id == HZ_ACCEL_INVALID_ID, "ray %u hit an out-of-range triangle", i);
    const float cost = a->info.sah_cost;
    stab_count_nonfinite(r, &cost, 1);
    stab_note(r, "accel: %u of %u triangles kept out; 2000 rays miss", a->info.tri_skipped, m.tri_count);
    su_scene_t b;
    su_begin(&b);
    uint32_t mat = su_material(&b, 1, 1, 1);
    uint32_t v0 = su_vertex(&b, 0, 0, 0), v1 = su_vertex(&b, 1, 0, 0), v2 = su_vertex(&b, 0, 3e38f, 0);
    su_tri(&b, v0, v1, v2, mat);
    su_object(&b);
    hz_scene_t sc;
    hz_status_t s = su_load(&b, &sc, &err);
    STAB_REFUSED(r, s, HZ_E_RANGE, &err, "positions");
    STAB_CHECK(r, strstr(err.msg, "element 2") != NULL, "message '%s' does not name the vertex", err.msg);
    free(rays), free(out);
}

/* Denormal coordinates: a sphere of radius 1e-39 (every vertex subnormal) inside a unit sphere. Products
 * underflow, so the tiny triangles are degenerate and never hit; the unit sphere around them stays closed. */
static void c_denormals(stab_result_t *r)
{
    hz_error_t err;
    hz_mesh_t a, b;
    hz_arena_t *ar = &hz_pools_get()->scene;
    STAB_OK(r, hz_meshgen_cube_sphere(&a, ar, 8, 1.0f, true, &err), &err);
    STAB_OK(r, hz_meshgen_cube_sphere(&b, ar, 4, 1e-39f, true, &err), &err);
    uint32_t nv = a.vertex_count + b.vertex_count, nt = a.tri_count + b.tri_count;
    float *pos = malloc(sizeof(float) * 4 * nv);
    uint32_t *tri = malloc(sizeof(uint32_t) * 3 * nt);
    memcpy(pos, a.pos, sizeof(float) * 4 * a.vertex_count);
    memcpy(pos + 4 * a.vertex_count, b.pos, sizeof(float) * 4 * b.vertex_count);
    memcpy(tri, a.tri, sizeof(uint32_t) * 3 * a.tri_count);
    for (uint32_t i = 0; i < 3 * b.tri_count; i++)
        tri[3 * a.tri_count + i] = b.tri[i] + a.vertex_count;
    uint32_t sub = 0;
    for (uint32_t i = 0; i < 4 * b.vertex_count; i++)
        sub += b.pos[i] != 0.0f && fabsf(b.pos[i]) < 1.17549435e-38f;
    STAB_CHECK(r, sub > 0, "no subnormal coordinate in the input");
    double c[3] = { 0, 0, 0 };
    hz_rayhit_t *rays = su_inside_rays(600, c, 1e-39, 3);
    su_check_mesh(r, pos, nv, tri, nt, rays, 600, true, a.tri_count, 1e-4);
    stab_note(r, "%u subnormal coordinates", sub);
    free(rays), free(pos), free(tri);
}

/* 600 degenerate triangles (repeated index, three equal points, collinear points) scattered inside a closed
 * sphere: never hit, no leak, no NaN. */
static void c_zero_area(stab_result_t *r)
{
    hz_error_t err;
    hz_mesh_t m;
    STAB_OK(r, hz_meshgen_cube_sphere(&m, &hz_pools_get()->scene, 8, 1.0f, true, &err), &err);
    uint32_t good = m.tri_count;
    STAB_OK(r, hz_meshgen_append_degenerates(&m, &hz_pools_get()->scene, 600, 9, &err), &err);
    double c[3] = { 0, 0, 0 };
    hz_rayhit_t *rays = su_inside_rays(1200, c, 0.6, 21);
    su_check_mesh(r, m.pos, m.vertex_count, m.tri, m.tri_count, rays, 1200, true, good, 1e-4);
    free(rays);
}

/* A closed tube of radius R and length 10 (64 sides, capped): every side triangle is a needle of aspect ratio
 * 10 / (R * 2 pi / 64). Rays from inside hit it. */
static void needle_tube(stab_result_t *r, float R)
{
    const uint32_t S = 64;
    const float L = 10.0f;
    float *pos = malloc(sizeof(float) * 4 * (2 * S + 2));
    uint32_t *tri = malloc(sizeof(uint32_t) * 3 * 4 * S), nt = 0;
    for (uint32_t i = 0; i < S; i++)
        for (uint32_t e = 0; e < 2; e++) {
            float *p = pos + 4 * (e * S + i);
            double a = 6.283185307179586 * i / S;
            p[0] = (float)(R * cos(a)), p[1] = (float)(R * sin(a)), p[2] = e ? L : 0.0f, p[3] = 0;
        }
    float *c0 = pos + 4 * 2 * S, *c1 = pos + 4 * (2 * S + 1);
    c0[0] = c0[1] = c0[2] = c0[3] = 0;
    c1[0] = c1[1] = c1[3] = 0, c1[2] = L;
    for (uint32_t i = 0; i < S; i++) {
        uint32_t j = (i + 1) % S;
        uint32_t t[4][3] = { { i, j, S + j }, { i, S + j, S + i }, { 2 * S, j, i }, { 2 * S + 1, S + i, S + j } };
        memcpy(tri + 3 * nt, t, sizeof t);
        nt += 4;
    }
    uint32_t n = r->full ? 20000 : 1500;
    hz_rayhit_t *rays = malloc(sizeof *rays * n);
    hz_rng_t g;
    hz_rng_seed(&g, 4, 4);
    for (uint32_t i = 0; i < n; i++) {
        double d[3], rr = 0.5 * R * sqrt(su_unit(&g)), a = 6.283185307179586 * su_unit(&g);
        su_random_dir(&g, i, d);
        su_ray(&rays[i], rr * cos(a), rr * sin(a), 0.05 + 9.9 * su_unit(&g), d[0], d[1], d[2]);
    }
    su_check_mesh(r, pos, 2 * S + 2, tri, nt, rays, n, true, nt, 1e-3);
    stab_note(r, "side triangles of aspect %.0f", 10.0 / (R * 6.283185307179586 / S));
    free(rays), free(pos), free(tri);
}

static void c_needles(stab_result_t *r)
{
    needle_tube(r, getenv("HZSTAB_R") ? (float)atof(getenv("HZSTAB_R")) : 1e-3f);
}

/* Two coplanar grids of quads, the second shifted by half a cell, over the same plane z = 0: rays straight
 * down anywhere over the overlap hit at t = 1 exactly as the oracle computes it, and kernels agree on the tie
 * rule. */
static void c_coplanar_overlap(stab_result_t *r)
{
    const uint32_t N = 16;
    float *pos = malloc(sizeof(float) * 4 * 2 * (N + 1) * (N + 1));
    uint32_t *tri = malloc(sizeof(uint32_t) * 3 * 2 * 2 * N * N), nv = 0, nt = 0;
    for (uint32_t gi = 0; gi < 2; gi++) {
        uint32_t base = nv;
        for (uint32_t y = 0; y <= N; y++)
            for (uint32_t x = 0; x <= N; x++, nv++) {
                float *p = pos + 4 * nv;
                p[0] = (float)x / N + 0.5f * gi / N, p[1] = (float)y / N + 0.5f * gi / N, p[2] = 0, p[3] = 0;
            }
        for (uint32_t y = 0; y < N; y++)
            for (uint32_t x = 0; x < N; x++) {
                uint32_t a = base + y * (N + 1) + x, b = a + 1, c = a + N + 1, d = c + 1;
                uint32_t t[2][3] = { { a, b, d }, { a, d, c } };
                memcpy(tri + 3 * nt, t, sizeof t);
                nt += 2;
            }
    }
    uint32_t n = r->full ? 16384 : 1024, leaks = 0;
    hz_rayhit_t *rays = malloc(sizeof *rays * n);
    hz_rng_t g;
    hz_rng_seed(&g, 8, 8);
    for (uint32_t i = 0; i < n; i++) {
        double x = 0.5 / N + (1 - 0.5 / N) * su_unit(&g), y = 0.5 / N + (1 - 0.5 / N) * su_unit(&g);
        su_ray(&rays[i], x, y, 1.0, 0, 0, -1);
    }
    hz_error_t err;
    hz_accel_t *a;
    STAB_OK(r, su_accel(&a, pos, nv, tri, nt, &err), &err);
    r->status = HZ_OK;
    hz_rayhit_t *out = malloc(sizeof *out * n);
    su_check_kernels(r, a, rays, n, out);
    STAB_BAIL(r);
    for (uint32_t i = 0; i < n; i++) {
        if (out[i].hit.geom_id == HZ_ACCEL_INVALID_ID) {
            leaks++;
            continue;
        }
        stab_error(r, fabs(out[i].ray.tfar - 1.0));
    }
    stab_note(r, "%u rays over two overlapping coplanar grids; %u leaks", n, leaks);
    STAB_CHECK(r, leaks == 0, "%u rays fell through two coplanar layers", leaks);
    STAB_CHECK(r, r->max_error <= 1e-6, "t error %g", r->max_error);
    free(rays), free(out), free(pos), free(tri);
}

/* 1024 copies of one triangle (65536 with FULL=1): one leaf cannot hold them, the builder must still terminate (no split can
 * separate them); every ray through the triangle reports copy 0 (equal t: lowest index), every other misses. */
static void c_identical_leaf(stab_result_t *r)
{
    const uint32_t N = r->full ? 65536 : 1024;
    float pos[12] = { 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0 };
    uint32_t *tri = malloc(sizeof(uint32_t) * 3 * N);
    for (uint32_t i = 0; i < N; i++)
        tri[3 * i] = 0, tri[3 * i + 1] = 1, tri[3 * i + 2] = 2;
    hz_error_t err;
    hz_accel_t *a;
    STAB_OK(r, su_accel(&a, pos, 3, tri, N, &err), &err);
    r->status = HZ_OK;
    uint32_t n = 512, inside = 0;
    hz_rayhit_t *rays = malloc(sizeof *rays * n), *out = malloc(sizeof *out * n);
    for (uint32_t i = 0; i < n; i++) {
        double x = -0.25 + 1.5 * ((i % 32) + 0.5) / 32, y = -0.25 + 1.5 * ((i / 32) + 0.5) / 16;
        su_ray(&rays[i], x, y, -2.0, 0, 0, 1);
    }
    su_check_kernels(r, a, rays, n, out);
    STAB_BAIL(r);
    for (uint32_t i = 0; i < n; i++) {
        double x = rays[i].ray.org_x, y = rays[i].ray.org_y;
        bool in = x > 0 && y > 0 && x + y < 1;
        bool hit = out[i].hit.geom_id != HZ_ACCEL_INVALID_ID;
        inside += in;
        STAB_CHECK(r, hit == in, "ray %u at (%g, %g): hit %d, want %d", i, x, y, hit, in);
        STAB_CHECK(r, !hit || out[i].hit.prim_id == 0, "ray %u hit copy %u, not copy 0", i, out[i].hit.prim_id);
        if (hit)
            stab_error(r, fabs(out[i].ray.tfar - 2.0) / 2.0);
    }
    stab_note(r, "%u copies in %u leaves / depth %u; %u rays inside hit copy 0", N, a->info.leaf_count,
              a->info.depth, inside);
    free(tri), free(rays), free(out);
}

/* Rays aimed exactly at the vertices and edge midpoints of a closed cube sphere, from its centre and from an
 * off-centre point: the watertight test must not let one through a shared edge or vertex. */
static void c_watertight_edges(stab_result_t *r)
{
    hz_error_t err;
    hz_mesh_t m;
    STAB_OK(r, hz_meshgen_cube_sphere(&m, &hz_pools_get()->scene, r->full ? 12 : 5, 1.0f, true, &err), &err);
    uint32_t n = 2 * (m.vertex_count + 3 * m.tri_count), k = 0;
    hz_rayhit_t *rays = malloc(sizeof *rays * n);
    const double org[2][3] = { { 0, 0, 0 }, { 0.1234, -0.0567, 0.0891 } };
    for (int o = 0; o < 2; o++) {
        for (uint32_t v = 0; v < m.vertex_count; v++) {
            const float *p = m.pos + 4 * v;
            su_ray(&rays[k++], org[o][0], org[o][1], org[o][2], p[0] - org[o][0], p[1] - org[o][1],
                   p[2] - org[o][2]);
        }
        for (uint32_t t = 0; t < m.tri_count; t++)
            for (int e = 0; e < 3; e++) {
                const float *p = m.pos + 4 * m.tri[3 * t + (uint32_t)e], *q = m.pos + 4 * m.tri[3 * t + (uint32_t)(e + 1) % 3];
                double mid[3] = { 0.5 * ((double)p[0] + q[0]), 0.5 * ((double)p[1] + q[1]), 0.5 * ((double)p[2] + q[2]) };
                su_ray(&rays[k++], org[o][0], org[o][1], org[o][2], mid[0] - org[o][0], mid[1] - org[o][1],
                       mid[2] - org[o][2]);
            }
    }
    su_check_mesh(r, m.pos, m.vertex_count, m.tri, m.tri_count, rays, k, true, m.tri_count, 1e-4);
    free(rays);
}

/* One triangle: a grid of rays over and around it; every ray the oracle decides clearly (barycentric margin
 * over 1e-6) agrees on hit or miss and on t. */
static void c_one_triangle(stab_result_t *r)
{
    float pos[12] = { -1, -1, 0, 0, 1, -1, 0, 0, 0, 1.5f, 0, 0 };
    uint32_t tri[3] = { 0, 1, 2 };
    hz_error_t err;
    hz_accel_t *a;
    STAB_OK(r, su_accel(&a, pos, 3, tri, 1, &err), &err);
    r->status = HZ_OK;
    const uint32_t G = 64, n = G * G;
    hz_rayhit_t *rays = malloc(sizeof *rays * n), *out = malloc(sizeof *out * n);
    for (uint32_t i = 0; i < n; i++)
        su_ray(&rays[i], -1.5 + 3.0 * (i % G + 0.5) / G, -1.5 + 3.2 * (i / G + 0.5) / G, 3.0, 0.01, -0.02, -1.0);
    su_check_kernels(r, a, rays, n, out);
    STAB_BAIL(r);
    uint32_t hits = 0;
    for (uint32_t i = 0; i < n; i++) {
        /* the oracle's signed margin: barycentrics of the ray's crossing of z = 0 */
        double t = 3.0, x = rays[i].ray.org_x + t * 0.01f, y = rays[i].ray.org_y + t * -0.02f;
        double s;
        double x0 = -1, y0 = -1, x1 = 1, y1 = -1, x2 = 0, y2 = 1.5;
        double den = (y1 - y2) * (x0 - x2) + (x2 - x1) * (y0 - y2);
        double b0 = ((y1 - y2) * (x - x2) + (x2 - x1) * (y - y2)) / den;
        double b1 = ((y2 - y0) * (x - x2) + (x0 - x2) * (y - y2)) / den;
        s = fmin(b0, fmin(b1, 1 - b0 - b1));
        bool hit = out[i].hit.geom_id != HZ_ACCEL_INVALID_ID;
        hits += hit;
        if (fabs(s) < 1e-6)
            continue;
        STAB_CHECK(r, hit == (s > 0), "ray %u: hit %d, oracle margin %g", i, hit, s);
        if (hit)
            stab_error(r, su_relerr(out[i].ray.tfar, 3.0, 1e-300));
    }
    stab_note(r, "%u rays; %u hits", n, hits);
    STAB_CHECK(r, r->max_error <= 1e-6, "t error %g", r->max_error);
    free(rays), free(out);
}

/* An accel over no triangles: builds, and every query misses. */
static void c_empty_accel(stab_result_t *r)
{
    float pos[4] = { 0, 0, 0, 0 };
    uint32_t tri[3] = { 0, 0, 0 };
    hz_error_t err;
    hz_accel_t *a;
    hz_status_t s = su_accel(&a, pos, 1, tri, 0, &err);
    r->status = s;
    STAB_CHECK(r, s == HZ_OK, "build of 0 triangles: %s", err.msg);
    hz_rayhit_t rays[64], out[64];
    hz_rng_t g;
    hz_rng_seed(&g, 1, 1);
    for (uint32_t i = 0; i < 64; i++) {
        double d[3];
        su_random_dir(&g, i, d);
        su_ray(&rays[i], 0, 0, 0, d[0], d[1], d[2]);
    }
    su_check_kernels(r, a, rays, 64, out);
    STAB_BAIL(r);
    for (uint32_t i = 0; i < 64; i++)
        STAB_CHECK(r, out[i].hit.geom_id == HZ_ACCEL_INVALID_ID, "ray %u hit an empty accel", i);
    stab_note(r, "64 rays, all miss");
}

/* A scene file without triangles: refused by the loader with HZ_E_FORMAT, the message naming the file. */
static void c_empty_scene_file(stab_result_t *r)
{
    su_scene_t b;
    su_begin(&b);
    su_material(&b, 1, 1, 1);
    su_vertex(&b, 0, 0, 0), su_vertex(&b, 1, 0, 0), su_vertex(&b, 0, 1, 0);
    su_object(&b);
    const void *img;
    size_t n;
    hz_error_t err;
    STAB_OK(r, su_image(&b, &img, &n, &err), &err);
    char path[64];
    snprintf(path, sizeof path, "/tmp/hzstab-empty-%d.hzb", (int)getpid());
    FILE *f = fopen(path, "wb");
    STAB_CHECK(r, f && fwrite(img, 1, n, f) == n, "cannot write %s", path);
    fclose(f);
    hz_scene_t sc;
    hz_status_t s = hz_scenefile_open(path, hz_pools_get(), &sc, &err);
    remove(path);
    STAB_REFUSED(r, s, HZ_E_FORMAT, &err, path);
    STAB_CHECK(r, strstr(err.msg, "no geometry") != NULL, "message '%s' does not give the reason", err.msg);
}

/* Vertices that are NaN or +-Inf: their triangles are kept out of the structure (counted), never hit, and the
 * closed unit sphere around them still holds every ray. */
static void c_nonfinite_vertices(stab_result_t *r)
{
    hz_error_t err;
    hz_mesh_t a;
    STAB_OK(r, hz_meshgen_cube_sphere(&a, &hz_pools_get()->scene, 8, 1.0f, true, &err), &err);
    uint32_t extra = 64, nv = a.vertex_count + 3 * extra, nt = a.tri_count + extra;
    float *pos = malloc(sizeof(float) * 4 * nv);
    uint32_t *tri = malloc(sizeof(uint32_t) * 3 * nt);
    memcpy(pos, a.pos, sizeof(float) * 4 * a.vertex_count);
    memcpy(tri, a.tri, sizeof(uint32_t) * 3 * a.tri_count);
    const float bad[4] = { NAN, INFINITY, -INFINITY, 1e30f * 1e30f };
    for (uint32_t i = 0; i < extra; i++)
        for (uint32_t v = 0; v < 3; v++) {
            float *p = pos + 4 * (a.vertex_count + 3 * i + v);
            p[0] = 0.3f * (float)v - 0.3f, p[1] = 0.01f * (float)i - 0.3f, p[2] = 0, p[3] = 0;
            if (v == i % 3)
                p[i / 3 % 3] = bad[i % 4];
            tri[3 * (a.tri_count + i) + v] = a.vertex_count + 3 * i + v;
        }
    double c[3] = { 0, 0, 0 };
    hz_rayhit_t *rays = su_inside_rays(1200, c, 0.6, 17);
    su_check_mesh(r, pos, nv, tri, nt, rays, 1200, true, a.tri_count, 1e-4);
    free(rays), free(pos), free(tri);
}

static const stab_case_t cases[] = {
    { "unit_sphere", "closed sphere: 0 leaks; t vs double oracle <= 1e-4; kernels bit-identical", c_unit_sphere, 0 },
    { "scale_1e-6", "sphere of radius 1e-6: 0 leaks; t vs oracle <= 1e-4", c_scale_1e_6, 0 },
    { "scale_1e6", "sphere of radius 1e6: 0 leaks; t vs oracle <= 1e-4", c_scale_1e6, 0 },
    { "scale_6e10", "sphere of radius 6e10 (edge of the accel's range): 0 leaks; t vs oracle", c_scale_6e10, 0 },
    { "far_from_origin", "unit sphere at 1e6 offset: 0 leaks; t vs oracle <= 1e-2", c_far_from_origin, 0 },
    { "near_float_max", "coordinates of 3e38: kept out of the accel (counted); misses; scene file refused (range)", c_near_float_max, 0 },
    { "denormals", "subnormal-coordinate mesh inside a sphere: never hit; 0 leaks", c_denormals, 0 },
    { "zero_area", "600 degenerate triangles in a sphere: never hit; 0 leaks", c_zero_area, 0 },
    { "needles", "closed tube of 1e5:1 needle triangles: 0 leaks; t vs oracle <= 1e-3", c_needles, 0 },
    { "coplanar_overlap", "two overlapping coplanar grids: 0 leaks; t exact to 1e-6; tie rule agrees",
      c_coplanar_overlap, 0 },
    { "identical_leaf", "1024 identical triangles: build ends; hits report copy 0; others miss", c_identical_leaf,
      0 },
    { "watertight_edges", "rays through every shared vertex and edge midpoint: 0 leaks", c_watertight_edges, 0 },
    { "one_triangle", "single triangle: hit/miss and t agree with the oracle off the edges", c_one_triangle, 0 },
    { "empty_accel", "accel over 0 triangles: builds; every kernel misses", c_empty_accel, 0 },
    { "empty_scene_file", "scene file with no triangles: refused (format) naming the file", c_empty_scene_file,
      0 },
    { "nonfinite_vertices", "NaN/Inf vertices: their triangles skipped; never hit; 0 leaks", c_nonfinite_vertices,
      0 },
};
STAB_STAGE(geometry, cases);
