/*
 * Watertightness: rays aimed exactly at the vertices and at points on the shared edges of closed meshes never
 * pass through (10^6 rays per mesh on the host; the emulated AArch64 run takes 10^5). Meshes: a tessellated UV
 * sphere, a closed cube-sphere, both also scaled by 1e-6 and 1e6, and a cube whose lattice coordinates are exact
 * in float, hit by axis-parallel rays (two direction components exactly zero) through its grid lines and
 * vertices. A leak is a ray that finds no hit within a small window around the aimed-at point; rays come from
 * outside (the first hit is the aimed-at point: the meshes are convex) and from inside.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "accel_fixture.h"

#if defined(HZ_SIMD_NEON)
#define N_WATER 100000u
#else
#define N_WATER 1000000u
#endif
#define BATCH 8192u

static uint8_t mem[64u << 20] HZ_ALIGNED(64);
static hz_arena_t arena;
static hz_rayhit_t rays[BATCH], outs[BATCH];

static int setup(void **state)
{
    (void)state;
    hz_arena_init(&arena, "accel", mem, sizeof mem);
    return 0;
}

/* Shoots n rays at vertices and edge points of m; returns the leaks. Kernels and forms (single rays, packets,
 * tiles of 8 packets) rotate batch by batch, and packets of 8 consecutive rays share their origin, so the packet
 * kernel sees coherent packets. */
static uint32_t shoot(const hz_mesh_t *m, const hz_accel_t *a, uint32_t n, uint64_t seed)
{
    fx_bounds_t b = fx_mesh_bounds(m);
    float c[3], r = 0.0f;
    for (int k = 0; k < 3; k++) {
        c[k] = 0.5f * (b.lo[k] + b.hi[k]);
        r = fmaxf(r, b.hi[k] - b.lo[k]);
    }
    hz_rng_t rng;
    hz_rng_seed(&rng, seed, 1);
    uint32_t leaks = 0, batch = 0;
    float o[3] = { 0, 0, 0 };
    for (uint32_t done = 0; done < n; done += BATCH, batch++) {
        uint32_t cnt = n - done < BATCH ? n - done : BATCH;
        for (uint32_t i = 0; i < cnt; i++) {
            if (i % 8 == 0) {
                if (hz_rng_u32(&rng) % 4 == 0) { /* from inside, near the centre */
                    for (int k = 0; k < 3; k++)
                        o[k] = c[k] + (fx_unit(&rng) - 0.5f) * 0.2f * r;
                } else { /* from outside */
                    float z = 2.0f * fx_unit(&rng) - 1.0f, ph = 2.0f * HZ_PI * fx_unit(&rng), sp, cp;
                    float sr = hz_sqrtf(1.0f - z * z);
                    hz_sincosf(ph, &sp, &cp);
                    o[0] = c[0] + 2.0f * r * sr * cp, o[1] = c[1] + 2.0f * r * sr * sp, o[2] = c[2] + 2.0f * r * z;
                }
            }
            float p[3], d[3];
            for (;;) {
                uint32_t t = hz_rng_below(&rng, m->tri_count), e = hz_rng_below(&rng, 3);
                const float *va = m->pos + 4u * m->tri[3u * t + e], *vb = m->pos + 4u * m->tri[3u * t + (e + 1) % 3];
                if (hz_rng_u32(&rng) & 1) {
                    memcpy(p, va, sizeof p); /* a vertex, exactly */
                } else {
                    float s = fx_unit(&rng); /* a point on the edge, as close as floats get */
                    for (int k = 0; k < 3; k++)
                        p[k] = va[k] + (vb[k] - va[k]) * s;
                }
                /* Rays that only graze the convex surface at p may rightly miss it: keep those that cross it
                 * (more than ~12 degrees off the tangent plane; the normal of these round meshes is p - c). */
                float dd = 0.0f, nn = 0.0f, dn = 0.0f;
                for (int k = 0; k < 3; k++) {
                    d[k] = p[k] - o[k];
                    dd += d[k] * d[k], nn += (p[k] - c[k]) * (p[k] - c[k]), dn += d[k] * (p[k] - c[k]);
                }
                if (dn * dn > 0.04f * dd * nn)
                    break;
            }
            /* t = 1 at the aimed-at point: a hit must lie in [1 - 1e-3, 1 + 1e-3] */
            fx_set_ray(&rays[i], o, d, 0.999f, 1.001f, i);
        }
        hz_accel_kernel_t k = (hz_accel_kernel_t)(1 + batch % 4);
        if (batch % 3 == 1)
            fx_trace_packets(a, k, HZ_ACCEL_COHERENT, 8, false, rays, outs, cnt, NULL);
        else if (batch % 3 == 2) /* tiles of 8 packets: 8 origins, rays in many directions (groups, single rays) */
            fx_trace_tiles(a, k, HZ_ACCEL_COHERENT, 8, 8, false, rays, outs, NULL, cnt, NULL);
        else
            fx_trace1(a, k, rays, outs, cnt, NULL);
        for (uint32_t i = 0; i < cnt; i++) {
            if (outs[i].hit.geom_id == 0)
                continue;
            if (leaks++ < 5)
                print_message("leak: ray %u org (%.9g %.9g %.9g) dir (%.9g %.9g %.9g) kernel %s\n", done + i,
                              (double)rays[i].ray.org_x, (double)rays[i].ray.org_y, (double)rays[i].ray.org_z,
                              (double)rays[i].ray.dir_x, (double)rays[i].ray.dir_y, (double)rays[i].ray.dir_z,
                              hz_accel_kernel_name(k));
        }
    }
    return leaks;
}

static void check(hz_mesh_t *m, const char *name, uint32_t n)
{
    hz_accel_geom_t g = hz_meshgen_geom(m);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    uint32_t leaks = shoot(m, a, n, 17);
    print_message("%s: %u triangles, %u rays at vertices and shared edges, %u leaks\n", name, m->tri_count, n,
                  leaks);
    assert_int_equal(leaks, 0);
}

static void test_sphere(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    hz_error_t err;
    assert_int_equal(hz_meshgen_sphere(&m, &arena, 64, 128, 1.0f, &err), HZ_OK);
    check(&m, "tessellated sphere", N_WATER);
    hz_arena_reset(&arena, m0);
}

static void test_cube_sphere(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    hz_error_t err;
    assert_int_equal(hz_meshgen_cube_sphere(&m, &arena, 40, 1.0f, true, &err), HZ_OK);
    check(&m, "cube-sphere", N_WATER);
    hz_arena_reset(&arena, m0);
}

static void test_scaled(void **state)
{
    (void)state;
    const float scales[] = { 1e-6f, 1e6f };
    for (size_t i = 0; i < HZ_ARRAY_LEN(scales); i++) {
        hz_arena_mark_t m0 = hz_arena_mark(&arena);
        hz_mesh_t m;
        hz_error_t err;
        assert_int_equal(hz_meshgen_sphere(&m, &arena, 32, 64, 1.0f, &err), HZ_OK);
        hz_meshgen_transform(&m, scales[i], hz_v3(0.5f * scales[i], -2.0f * scales[i], 0.0f));
        check(&m, i ? "sphere x 1e6" : "sphere x 1e-6", N_WATER / 5);
        hz_arena_reset(&arena, m0);
    }
}

/* A flat-faced cube, n = 16 cells per edge: every lattice coordinate (k / 8 - 1) is exact in float. Rays with
 * two zero direction components run along the axes through grid vertices and along grid lines (edges shared
 * by two triangles, or by a face diagonal), entering through one face and leaving through the opposite one. */
static void test_axis_parallel_exact(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    hz_error_t err;
    assert_int_equal(hz_meshgen_cube_sphere(&m, &arena, 16, 1.0f, false, &err), HZ_OK);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    hz_rng_t rng;
    hz_rng_seed(&rng, 3, 3);
    uint32_t leaks = 0, n = 0;
    for (int axis = 0; axis < 3; axis++)
        for (int sign = -1; sign <= 1; sign += 2)
            for (int i = 0; i <= 16; i++)
                for (int j = 0; j <= 16; j++) {
                    for (int variant = 0; variant < 3; variant++) {
                        float u = (float)i / 8.0f - 1.0f, w = (float)j / 8.0f - 1.0f;
                        if (variant == 1) { /* on a grid line: one coordinate on the lattice */
                            w = fx_unit(&rng) * 2.0f - 1.0f;
                        } else if (variant == 2) { /* on the diagonal two triangles of a cell share, exactly */
                            float sd = (float)hz_rng_below(&rng, 64) / 512.0f;
                            u += sd, w += sd;
                        }
                        if (u < -1.0f || u > 1.0f || w < -1.0f || w > 1.0f)
                            continue;
                        float o[3], d[3] = { 0, 0, 0 };
                        o[axis] = -2.0f * (float)sign;
                        o[(axis + 1) % 3] = u;
                        o[(axis + 2) % 3] = w;
                        d[axis] = (float)sign;
                        hz_rayhit_t in, out;
                        fx_set_ray(&in, o, d, 0.0f, INFINITY, 0);
                        for (int k = HZ_ACCEL_KERNEL_SCALAR; k < HZ_ACCEL_KERNEL_COUNT; k++) {
                            fx_trace1(a, (hz_accel_kernel_t)k, &in, &out, 1, NULL);
                            n++;
                            /* enters at distance 1 (the face at -sign) */
                            if (out.hit.geom_id != 0 || out.ray.tfar != 1.0f)
                                leaks++;
                            fx_trace_packets(a, (hz_accel_kernel_t)k, HZ_ACCEL_COHERENT, 8, false, &in, &out, 1, NULL);
                            n++;
                            if (out.hit.geom_id != 0 || out.ray.tfar != 1.0f)
                                leaks++;
                        }
                    }
                }
    print_message("cube: %u axis-parallel rays through lattice vertices, grid lines and cell diagonals, %u leaks\n",
                  n, leaks);
    assert_true(n > 10000);
    assert_int_equal(leaks, 0);
    hz_arena_reset(&arena, m0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_cube_sphere),
        cmocka_unit_test(test_scaled),
        cmocka_unit_test(test_axis_parallel_exact),
    };
    return HZ_RUN_GROUP(tests, setup, NULL);
}
