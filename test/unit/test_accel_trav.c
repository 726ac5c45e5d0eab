/*
 * Native traversal: every kernel (scalar reference, SIMD single ray, frustum packet, masked packet; packets of
 * 4 and 8 with holes in the valid mask) against the brute-force reference and against each other, bit for bit,
 * on procedural meshes: a tessellated sphere, a closed cube-sphere, a random soup with degenerate triangles, the
 * sphere scaled by 1e-6 and 1e6, and the sphere moved 3e4 of its radii away from the origin. Also occlusion,
 * shadow rays from surfaces to point lights (packets whose origins spread and whose lanes are blocked at
 * different places), any-hit callbacks, zero direction components, bad rays, statistics, secondary rays from
 * surfaces, and a golden digest that holds x86-64 and AArch64 to the same bits.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "accel_fixture.h"

#define MEM_BYTES (192u << 20)
static uint8_t mem[MEM_BYTES] HZ_ALIGNED(64);
static hz_arena_t arena;

/* N_RAYS rays are made per mesh; N_CHECK of them go through every kernel and form. Under qemu-user (NEON) every
 * traversal is emulated: fewer of them through the same meshes, kernels and forms (the camera rays and the
 * brute-force sample stay whole, and the golden digest takes its 40000 from the N_RAYS made). */
#if defined(HZ_SIMD_NEON)
#define N_RAYS 40000u
#define N_CHECK 20000u
#else
#define N_RAYS 100000u
#define N_CHECK N_RAYS
#endif
#define N_BRUTE 2000u   /* of which checked against brute force */
#define CAM_W 128u
#define CAM_H 128u
#if N_CHECK < CAM_W * CAM_H + N_BRUTE || N_RAYS < 40000u || N_CHECK > N_RAYS
#error "the camera rays, the random rays checked against brute force and the golden digest's must fit in N_RAYS"
#endif

static hz_rayhit_t rays_in[N_RAYS], rays_ref[N_RAYS], rays_out[N_RAYS];
static uint8_t occ_ref[N_RAYS], occ_out[N_RAYS];

typedef enum { M_SPHERE, M_CUBE, M_SOUP, M_TINY, M_HUGE, M_FAR, M_COUNT } mesh_kind_t;
static const char *mesh_name[M_COUNT] = { "sphere", "cube-sphere", "soup+degenerate", "sphere*1e-6",
                                          "sphere*1e6", "sphere+3e4" };

static void make_mesh(mesh_kind_t k, hz_mesh_t *m)
{
    hz_error_t err;
    hz_status_t s = HZ_OK;
    switch (k) {
    case M_SPHERE: s = hz_meshgen_sphere(m, &arena, 48, 96, 1.0f, &err); break;
    case M_CUBE: s = hz_meshgen_cube_sphere(m, &arena, 24, 1.0f, true, &err); break;
    case M_SOUP:
        s = hz_meshgen_soup(m, &arena, 6000, 1.0f, 0.3f, 99, &err);
        if (s == HZ_OK)
            s = hz_meshgen_append_degenerates(m, &arena, 300, 5, &err);
        break;
    case M_TINY:
        s = hz_meshgen_sphere(m, &arena, 48, 96, 1.0f, &err);
        hz_meshgen_transform(m, 1e-6f, hz_v3(3e-6f, -2e-6f, 1e-6f));
        break;
    case M_HUGE:
        s = hz_meshgen_sphere(m, &arena, 48, 96, 1.0f, &err);
        hz_meshgen_transform(m, 1e6f, hz_v3(3e6f, -2e6f, 1e6f));
        break;
    case M_FAR: /* far from the world's origin: slab distances cancel (p * rd - o * rd) */
        s = hz_meshgen_sphere(m, &arena, 48, 96, 1.0f, &err);
        hz_meshgen_transform(m, 1.0f, hz_v3(3e4f, -2e4f, 1e4f));
        break;
    default: break;
    }
    assert_int_equal(s, HZ_OK);
}

static int setup(void **state)
{
    (void)state;
    hz_arena_init(&arena, "test", mem, sizeof mem);
    return 0;
}

static void make_rays(const hz_mesh_t *m, uint64_t seed)
{
    fx_bounds_t b = fx_mesh_bounds(m);
    fx_random_rays(rays_in, N_RAYS, b, seed);
    /* the first CAM_W x CAM_H rays: a camera outside, in pixel order (coherent packets) */
    float ext = b.hi[0] - b.lo[0];
    float eye[3] = { b.lo[0] - 0.7f * ext, b.hi[1] + 0.4f * ext, b.hi[2] + 1.1f * ext };
    fx_camera_rays(rays_in, CAM_W, CAM_H, eye, b);
}

static void check_brute(const hz_accel_geom_t *g, const char *what)
{
    uint32_t bad = 0;
    for (uint32_t i = 0; i < N_BRUTE; i++) {
        /* half camera rays, half random ones */
        uint32_t j = i < N_BRUTE / 2 ? i * (CAM_W * CAM_H / (N_BRUTE / 2)) : CAM_W * CAM_H + i;
        float t;
        uint32_t p = fx_brute(g, &rays_in[j], &t, NULL);
        bool ok = p == rays_ref[j].hit.prim_id &&
                  (p == HZ_ACCEL_INVALID_ID ? rays_ref[j].hit.geom_id == HZ_ACCEL_INVALID_ID
                                            : (rays_ref[j].ray.tfar == t && rays_ref[j].hit.geom_id == 0));
        if (!ok && bad++ < 5)
            print_message("%s: ray %u: brute prim %u t %.9g, accel prim %u t %.9g\n", what, j, p, (double)t,
                          rays_ref[j].hit.prim_id, (double)rays_ref[j].ray.tfar);
    }
    assert_int_equal(bad, 0);
}

static uint32_t count_diff(const char *what, const char *kname)
{
    uint32_t bad = 0;
    for (uint32_t i = 0; i < N_CHECK; i++)
        if (!fx_same(&rays_ref[i], &rays_out[i]) && bad++ < 3)
            print_message("%s %s: ray %u: prim %u/%u t %.9g/%.9g u %.9g/%.9g\n", what, kname, i,
                          rays_ref[i].hit.prim_id, rays_out[i].hit.prim_id, (double)rays_ref[i].ray.tfar,
                          (double)rays_out[i].ray.tfar, (double)rays_ref[i].hit.u, (double)rays_out[i].hit.u);
    return bad;
}

static void check_mesh(mesh_kind_t mk)
{
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    make_mesh(mk, &m);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    make_rays(&m, 1000u + (uint64_t)mk);

    /* the reference: scalar single rays, checked against brute force */
    fx_trace1(a, HZ_ACCEL_KERNEL_SCALAR, rays_in, rays_ref, N_CHECK, NULL);
    check_brute(&g, mesh_name[mk]);
    uint32_t hits = 0;
    for (uint32_t i = 0; i < N_CHECK; i++)
        hits += rays_ref[i].hit.geom_id == 0;
    assert_true(hits > N_CHECK / 20); /* the ray sets do exercise hits */

    /* every SIMD kernel: single rays, packets of the native width (coherent hint on, holes in the valid mask:
     * lanes switched off stay untouched) and of the other width; AUTO with both hints */
    const hz_accel_kernel_t ks[] = { HZ_ACCEL_KERNEL_SIMD_SINGLE, HZ_ACCEL_KERNEL_SIMD_PACKET,
                                     HZ_ACCEL_KERNEL_SIMD_MASKED };
    const int native = HZ_BVH_W, other = HZ_BVH_W == 8 ? 4 : 8;
    for (size_t q = 0; q < HZ_ARRAY_LEN(ks); q++) {
        const char *kn = hz_accel_kernel_name(ks[q]);
        assert_true(hz_accel_kernel_available(ks[q]) == (HZ_SIMD_LANES > 1));
        fx_trace1(a, ks[q], rays_in, rays_out, N_CHECK, NULL);
        assert_int_equal(count_diff(mesh_name[mk], kn), 0);
        fx_trace_packets(a, ks[q], HZ_ACCEL_COHERENT, native, true, rays_in, rays_out, N_CHECK, NULL);
        for (uint32_t i = 6; i < N_CHECK; i += 7) {
            assert_true(fx_same(&rays_in[i], &rays_out[i]));
            rays_out[i] = rays_ref[i];
        }
        assert_int_equal(count_diff(mesh_name[mk], kn), 0);
        fx_trace_packets(a, ks[q], 0, other, false, rays_in, rays_out, N_CHECK, NULL);
        assert_int_equal(count_diff(mesh_name[mk], kn), 0);
    }
    for (int coh = 0; coh < 2; coh++) {
        fx_trace_packets(a, HZ_ACCEL_KERNEL_AUTO, coh ? HZ_ACCEL_COHERENT : 0, native, false, rays_in, rays_out,
                         N_CHECK, NULL);
        assert_int_equal(count_diff(mesh_name[mk], "auto"), 0);
    }
    /* tiles: calls of 8 packets (a coherent camera tile for the first rays, mixed directions for the random
     * ones: several groups and single rays in one call), of 32 and 64 packets (more than one slice of 256 rays
     * for 64 x 8), an odd count, both widths, with and without holes; lanes switched off stay untouched */
#if defined(HZ_SIMD_NEON) /* emulated: the forms that differ for the kernel (the other width is a copy) */
    const int tiles[][3] = { { 4, 8, 1 }, { 4, 64, 0 }, { 8, 5, 1 } };
#else
    const int tiles[][3] = { { 8, 8, 1 }, { 4, 8, 0 }, { 8, 32, 1 }, { 4, 64, 0 }, { 8, 64, 0 }, { 8, 5, 1 } };
#endif
    for (size_t q = 0; q < HZ_ARRAY_LEN(tiles); q++) {
        const bool holes = tiles[q][2] != 0;
        fx_trace_tiles(a, HZ_ACCEL_KERNEL_AUTO, HZ_ACCEL_COHERENT, tiles[q][0], tiles[q][1], holes, rays_in,
                       rays_out, NULL, N_CHECK, NULL);
        for (uint32_t i = 6; holes && i < N_CHECK; i += 7) {
            assert_true(fx_same(&rays_in[i], &rays_out[i]));
            rays_out[i] = rays_ref[i];
        }
        if (count_diff(mesh_name[mk], "tile"))
            print_message("tile width %d x %d packets\n", tiles[q][0], tiles[q][1]);
        assert_int_equal(count_diff(mesh_name[mk], "tile"), 0);
        fx_trace_tiles(a, HZ_ACCEL_KERNEL_AUTO, HZ_ACCEL_COHERENT, tiles[q][0], tiles[q][1], false, rays_in, NULL,
                       occ_out, N_CHECK, NULL);
        uint32_t bad = 0;
        for (uint32_t i = 0; i < N_CHECK; i++)
            bad += occ_out[i] != (rays_ref[i].hit.geom_id == 0);
        assert_int_equal(bad, 0);
    }

    /* occlusion: occluded exactly when a closest hit exists, in every form */
    for (uint32_t i = 0; i < N_CHECK; i++)
        occ_ref[i] = rays_ref[i].hit.geom_id == 0;
    struct {
        hz_accel_kernel_t k;
        int width;
    } occ[] = { { HZ_ACCEL_KERNEL_SCALAR, 0 },      { HZ_ACCEL_KERNEL_SIMD_SINGLE, 0 },
                { HZ_ACCEL_KERNEL_SIMD_PACKET, native }, { HZ_ACCEL_KERNEL_SIMD_MASKED, native },
                { HZ_ACCEL_KERNEL_AUTO, other } };
    for (size_t q = 0; q < HZ_ARRAY_LEN(occ); q++) {
        fx_occlusion(a, occ[q].k, HZ_ACCEL_COHERENT, occ[q].width, rays_in, occ_out, N_CHECK, NULL);
        uint32_t bad = 0;
        for (uint32_t i = 0; i < N_CHECK; i++)
            bad += occ_out[i] != occ_ref[i];
        if (bad)
            print_message("%s occlusion %s width %d: %u differ\n", mesh_name[mk], hz_accel_kernel_name(occ[q].k),
                          occ[q].width, bad);
        assert_int_equal(bad, 0);
    }
    hz_arena_reset(&arena, m0);
}

/* ---- any-hit ---- */
static bool accept_rule(uint32_t prim)
{
    return (hz_hash32(prim * 2654435761u + 17u) & 3u) != 0; /* three in four candidates count */
}

static uint64_t anyhit_calls;
/* The side the callback is told against the geometric one, dot((v1 - v0) x (v2 - v0), dir) > 0 for the back
 * (rays_in[ray_id] of side_mesh); grazing hits (|cos| < 1e-3) may go either way. */
static const hz_mesh_t *side_mesh;
static uint64_t side_seen[2], side_bad;
static bool anyhit_cb(void *user, uint32_t prim, float u, float v, float t, uint32_t ray_id, int lane, unsigned back)
{
    assert_ptr_equal(user, &anyhit_calls);
    assert_true(u >= 0.0f && v >= 0.0f && u + v <= 1.0001f && t >= 0.0f);
    assert_true(lane >= 0 && lane < 8);
    assert_true(back <= 1u);
    anyhit_calls++;
    if (side_mesh && ray_id < N_CHECK) {
        const uint32_t *tv = side_mesh->tri + (size_t)prim * 3;
        const float *a = side_mesh->pos + (size_t)tv[0] * 4, *b = side_mesh->pos + (size_t)tv[1] * 4,
                    *c = side_mesh->pos + (size_t)tv[2] * 4;
        double e1[3], e2[3], n[3], d[3] = { rays_in[ray_id].ray.dir_x, rays_in[ray_id].ray.dir_y,
                                             rays_in[ray_id].ray.dir_z };
        for (int k = 0; k < 3; k++)
            e1[k] = (double)b[k] - a[k], e2[k] = (double)c[k] - a[k];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double dn = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (fabs(dn) > 1e-3 * len) {
            side_seen[dn > 0.0]++;
            side_bad += (dn > 0.0) != (back != 0u);
        }
    }
    return accept_rule(prim);
}

static void test_anyhit(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    make_mesh(M_SOUP, &m);
    m.tri_flags = hz_arena_calloc(&arena, m.tri_count, 1, 16);
    assert_non_null(m.tri_flags);
    for (uint32_t t = 0; t < m.tri_count; t++)
        m.tri_flags[t] = (t % 2) ? HZ_ACCEL_TRI_ANYHIT : 0;
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    make_rays(&m, 77);
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    ctx.anyhit = anyhit_cb;
    ctx.user = &anyhit_calls;
    side_mesh = &m, side_seen[0] = side_seen[1] = side_bad = 0;
    fx_trace1(a, HZ_ACCEL_KERNEL_SCALAR, rays_in, rays_ref, N_CHECK, &ctx);
    assert_true(anyhit_calls > 1000);
    /* the side comes from the intersection test: it agrees with the geometric one, both sides occur */
    assert_int_equal(side_bad, 0);
    assert_true(side_seen[0] > 100 && side_seen[1] > 100);
    uint32_t bad = 0, rejected = 0;
    for (uint32_t i = 0; i < N_BRUTE; i++) {
        uint32_t j = CAM_W * CAM_H + i;
        float t, t0;
        uint32_t p = fx_brute(&g, &rays_in[j], &t, accept_rule);
        uint32_t p0 = fx_brute(&g, &rays_in[j], &t0, NULL);
        rejected += p != p0;
        bad += p != rays_ref[j].hit.prim_id || (p != HZ_ACCEL_INVALID_ID && t != rays_ref[j].ray.tfar);
    }
    assert_int_equal(bad, 0);
    assert_true(rejected > 10); /* the callback did change results */
    const hz_accel_kernel_t ks[] = { HZ_ACCEL_KERNEL_SIMD_SINGLE, HZ_ACCEL_KERNEL_SIMD_PACKET,
                                     HZ_ACCEL_KERNEL_SIMD_MASKED };
    for (size_t q = 0; q < HZ_ARRAY_LEN(ks); q++) {
        fx_trace1(a, ks[q], rays_in, rays_out, N_CHECK, &ctx);
        assert_int_equal(count_diff("anyhit", hz_accel_kernel_name(ks[q])), 0);
        fx_trace_packets(a, ks[q], HZ_ACCEL_COHERENT, HZ_BVH_W, false, rays_in, rays_out, N_CHECK, &ctx);
        assert_int_equal(count_diff("anyhit", hz_accel_kernel_name(ks[q])), 0);
        fx_trace_tiles(a, ks[q], HZ_ACCEL_COHERENT, HZ_BVH_W, 8, false, rays_in, rays_out, NULL, N_CHECK, &ctx);
        assert_int_equal(count_diff("anyhit tile", hz_accel_kernel_name(ks[q])), 0);
    }
    assert_int_equal(side_bad, 0); /* every kernel tells the same side */
    side_mesh = NULL;
    /* occlusion honours the callback too; without the callback flagged triangles are opaque */
    for (uint32_t i = 0; i < N_CHECK; i++)
        occ_ref[i] = rays_ref[i].hit.geom_id == 0;
    for (size_t q = 0; q < HZ_ARRAY_LEN(ks); q++) {
        fx_occlusion(a, ks[q], HZ_ACCEL_COHERENT, HZ_BVH_W, rays_in, occ_out, N_CHECK, &ctx);
        assert_memory_equal(occ_ref, occ_out, N_CHECK);
        fx_trace_tiles(a, ks[q], HZ_ACCEL_COHERENT, HZ_BVH_W, 8, false, rays_in, NULL, occ_out, N_CHECK, &ctx);
        assert_memory_equal(occ_ref, occ_out, N_CHECK);
    }
    fx_occlusion(a, HZ_ACCEL_KERNEL_SCALAR, 0, 0, rays_in, occ_out, N_CHECK, &ctx);
    assert_memory_equal(occ_ref, occ_out, N_CHECK);
    fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, rays_in, rays_out, N_CHECK, NULL);
    uint32_t more = 0;
    for (uint32_t i = 0; i < N_CHECK; i++)
        more += rays_out[i].hit.geom_id == 0 && rays_ref[i].hit.geom_id != 0;
    assert_true(more > 10);
    hz_arena_reset(&arena, m0);
}

/* ---- shadow rays: from the camera rays' hit points (offset off the surface) to point lights, tfar 1 with
 * unnormalised directions, in pixel order as a renderer sends them: packets whose origins spread and whose
 * lanes are blocked at different places (the frustum packet's lane masks, its drop-out and its single-lane
 * subtrees). Every kernel and width against the scalar reference, which is checked against brute force. ---- */
static hz_rayhit_t shadow_in[CAM_W * CAM_H];
static uint8_t shadow_ref[CAM_W * CAM_H], shadow_out[CAM_W * CAM_H];

static uint32_t make_shadow_rays(const hz_accel_t *a, const hz_mesh_t *m, const float light[3])
{
    fx_bounds_t b = fx_mesh_bounds(m);
    float scale = 0.0f;
    for (int k = 0; k < 3; k++)
        scale = fmaxf(scale, fmaxf(fabsf(b.lo[k]), fabsf(b.hi[k])));
    uint32_t n = 0;
    for (uint32_t i = 0; i < CAM_W * CAM_H; i++) {
        hz_rayhit_t h = rays_in[i];
        hz_accel_intersect1(a, NULL, &h);
        if (h.hit.geom_id != 0)
            continue;
        hz_vec3_t d = hz_v3(h.ray.dir_x, h.ray.dir_y, h.ray.dir_z);
        hz_vec3_t p = hz_v3(h.ray.org_x + h.ray.tfar * d.x, h.ray.org_y + h.ray.tfar * d.y,
                            h.ray.org_z + h.ray.tfar * d.z);
        hz_vec3_t nn = hz_v3_normalize(hz_v3(h.hit.ng_x, h.hit.ng_y, h.hit.ng_z));
        if (hz_v3_dot(nn, d) > 0.0f)
            nn = hz_v3_neg(nn);
        hz_vec3_t o = hz_accel_offset_origin(p, nn, scale);
        float of[3] = { o.x, o.y, o.z }, df[3] = { light[0] - o.x, light[1] - o.y, light[2] - o.z };
        fx_set_ray(&shadow_in[n], of, df, 0.0f, 1.0f, i);
        n++;
    }
    return n;
}

static void check_shadows(mesh_kind_t mk, bool with_anyhit)
{
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    make_mesh(mk, &m);
    if (with_anyhit) {
        m.tri_flags = hz_arena_calloc(&arena, m.tri_count, 1, 16);
        assert_non_null(m.tri_flags);
        for (uint32_t t = 0; t < m.tri_count; t++)
            m.tri_flags[t] = (t % 2) ? HZ_ACCEL_TRI_ANYHIT : 0;
    }
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    make_rays(&m, 31u + (uint64_t)mk);
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    ctx.anyhit = with_anyhit ? anyhit_cb : NULL;
    ctx.user = &anyhit_calls;
    fx_bounds_t b = fx_mesh_bounds(&m);
    float c[3], e[3];
    for (int k = 0; k < 3; k++)
        c[k] = 0.5f * (b.lo[k] + b.hi[k]), e[k] = b.hi[k] - b.lo[k];
    /* above the mesh, beside it, and just off a corner of its bounds (grazing rays) */
    const float lights[3][3] = { { c[0] + 0.2f * e[0], b.hi[1] + 1.5f * e[1], c[2] - 0.3f * e[2] },
                                 { b.lo[0] - 0.8f * e[0], c[1], c[2] + 0.1f * e[2] },
                                 { b.hi[0] + 0.05f * e[0], c[1] + 0.3f * e[1], b.hi[2] + 0.05f * e[2] } };
    for (int l = 0; l < 3; l++) {
        const uint32_t n = make_shadow_rays(a, &m, lights[l]);
        assert_true(n > 1000);
        fx_occlusion(a, HZ_ACCEL_KERNEL_SCALAR, 0, 0, shadow_in, shadow_ref, n, &ctx);
        uint32_t blocked = 0, bad = 0;
        for (uint32_t i = 0; i < n; i++)
            blocked += shadow_ref[i];
        for (uint32_t i = 0; i < n; i += 7) {
            float t;
            bad += (fx_brute(&g, &shadow_in[i], &t, with_anyhit ? accept_rule : NULL) != HZ_ACCEL_INVALID_ID) !=
                   shadow_ref[i];
        }
        print_message("%s%s light %d: %u shadow rays, %u blocked\n", mesh_name[mk], with_anyhit ? " (any-hit)" : "",
                      l, n, blocked);
        assert_int_equal(bad, 0);
        struct {
            hz_accel_kernel_t k;
            int width;
        } occ[] = { { HZ_ACCEL_KERNEL_SIMD_SINGLE, 0 }, { HZ_ACCEL_KERNEL_SIMD_PACKET, 8 },
                    { HZ_ACCEL_KERNEL_SIMD_PACKET, 4 }, { HZ_ACCEL_KERNEL_SIMD_MASKED, 8 },
                    { HZ_ACCEL_KERNEL_AUTO, 8 },        { HZ_ACCEL_KERNEL_AUTO, 4 } };
        for (size_t q = 0; q < HZ_ARRAY_LEN(occ); q++) {
            fx_occlusion(a, occ[q].k, HZ_ACCEL_COHERENT, occ[q].width, shadow_in, shadow_out, n, &ctx);
            uint32_t diff = 0;
            for (uint32_t i = 0; i < n; i++)
                diff += shadow_out[i] != shadow_ref[i];
            if (diff)
                print_message("%s shadows %s width %d: %u differ\n", mesh_name[mk], hz_accel_kernel_name(occ[q].k),
                              occ[q].width, diff);
            assert_int_equal(diff, 0);
        }
        /* tiles of shadow rays (8 and 32 packets, both widths): groups bounded from the light's end */
        const int tiles[][2] = { { 8, 8 }, { 4, 8 }, { 8, 32 }, { 4, 16 } };
        for (size_t q = 0; q < HZ_ARRAY_LEN(tiles); q++) {
            fx_trace_tiles(a, HZ_ACCEL_KERNEL_AUTO, HZ_ACCEL_COHERENT, tiles[q][0], tiles[q][1], false, shadow_in, NULL,
                           shadow_out, n, &ctx);
            uint32_t diff = 0;
            for (uint32_t i = 0; i < n; i++)
                diff += shadow_out[i] != shadow_ref[i];
            if (diff)
                print_message("%s shadows tile %d x %d: %u differ\n", mesh_name[mk], tiles[q][0], tiles[q][1], diff);
            assert_int_equal(diff, 0);
        }
    }
    hz_arena_reset(&arena, m0);
}

static void test_shadow_rays(void **state)
{
    (void)state;
    check_shadows(M_SPHERE, false);
    check_shadows(M_CUBE, false);
    check_shadows(M_SOUP, false);
    check_shadows(M_SOUP, true);
    check_shadows(M_HUGE, false);
}

/* ---- rays outside the contract miss and change nothing ---- */
static void test_bad_rays(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    make_mesh(M_SPHERE, &m);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    const float nan = NAN, inf = INFINITY;
    const float bad[][8] = {
        /* org xyz, dir xyz, tnear, tfar */
        { nan, 0, -3, 0, 0, 1, 0, inf },  { 0, 0, -3, nan, 0, 1, 0, inf }, { 0, 0, -3, 0, 0, 0, 0, inf },
        { inf, 0, -3, 0, 0, 1, 0, inf },  { 0, 0, -3, 0, inf, 1, 0, inf }, { 0, 0, -3, 0, 0, 1, 5, 1 },
        { 0, 0, -3, 0, 0, 1, nan, inf },  { 0, 0, -3, 0, 0, 1, 0, nan },   { 0, 0, -3, 0, 0, -0.0f, 0, inf },
    };
    for (size_t i = 0; i < HZ_ARRAY_LEN(bad); i++) {
        hz_rayhit_t in;
        fx_set_ray(&in, bad[i], bad[i] + 3, bad[i][6], bad[i][7], (uint32_t)i);
        for (int k = HZ_ACCEL_KERNEL_AUTO; k < HZ_ACCEL_KERNEL_COUNT; k++) {
            hz_rayhit_t out;
            fx_trace1(a, (hz_accel_kernel_t)k, &in, &out, 1, NULL);
            assert_true(fx_same(&in, &out));
            fx_trace_packets(a, (hz_accel_kernel_t)k, HZ_ACCEL_COHERENT, 8, false, &in, &out, 1, NULL);
            assert_true(fx_same(&in, &out));
            uint8_t occ = 1;
            fx_occlusion(a, (hz_accel_kernel_t)k, 0, 4, &in, &occ, 1, NULL);
            assert_int_equal(occ, 0);
        }
    }
    hz_arena_reset(&arena, m0);
}

/* ---- statistics are counted exactly when the board asks for them ---- */
static void test_stats(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    make_mesh(M_SPHERE, &m);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    make_rays(&m, 5);
    for (int k = HZ_ACCEL_KERNEL_AUTO; k < HZ_ACCEL_KERNEL_COUNT; k++) {
        hz_accel_stats_t st;
        memset(&st, 0, sizeof st);
        hz_accel_ctx_t ctx;
        hz_accel_ctx_init(&ctx);
        ctx.stats = &st;
        fx_trace_packets(a, (hz_accel_kernel_t)k, HZ_ACCEL_COHERENT, 8, false, rays_in + CAM_W * CAM_H / 2,
                         rays_out, 4096, &ctx);
#if HZ_FEATURE_STATS
        print_message("%s: %llu rays, %llu nodes, %llu triangle tests\n", hz_accel_kernel_name((hz_accel_kernel_t)k),
                      (unsigned long long)st.rays, (unsigned long long)st.nodes, (unsigned long long)st.tris);
        assert_int_equal(st.rays, 4096);
        assert_true(st.nodes >= 4096 / 8 && st.tris > 0);
#else
        assert_int_equal(st.rays + st.nodes + st.tris, 0);
#endif
    }
    hz_arena_reset(&arena, m0);
}

/* ---- secondary rays from hit points: with hz_accel_offset_origin no ray hits the surface it leaves, at any
 * scale. The UV sphere is convex, so a ray leaving a face outwards must miss everything, and one leaving it
 * inwards must reach the far side. ---- */
static void check_offsets(mesh_kind_t mk)
{
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    make_mesh(mk, &m);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    make_rays(&m, 9);
    fx_bounds_t b = fx_mesh_bounds(&m);
    const float diam = b.hi[0] - b.lo[0];
    float scale = 0.0f;
    for (int k = 0; k < 3; k++)
        scale = fmaxf(scale, fmaxf(fabsf(b.lo[k]), fabsf(b.hi[k])));
    hz_rng_t r;
    hz_rng_seed(&r, 4, 4);
    uint32_t tested = 0, self_out = 0, self_in = 0, raw_self = 0;
    for (uint32_t i = 0; i < CAM_W * CAM_H; i++) {
        hz_rayhit_t h = rays_in[i];
        hz_accel_intersect1(a, NULL, &h);
        if (h.hit.geom_id != 0)
            continue;
        hz_vec3_t p = hz_v3(h.ray.org_x + h.ray.tfar * h.ray.dir_x, h.ray.org_y + h.ray.tfar * h.ray.dir_y,
                            h.ray.org_z + h.ray.tfar * h.ray.dir_z);
        hz_vec3_t n = hz_v3_normalize(hz_v3(h.hit.ng_x, h.hit.ng_y, h.hit.ng_z));
        /* a direction within ~75 degrees of the normal */
        float j[3];
        for (int k = 0; k < 3; k++) /* one draw per statement: the order of arguments is unspecified */
            j[k] = (fx_unit(&r) - 0.5f) * 2.0f;
        hz_vec3_t d = hz_v3_normalize(hz_v3(n.x + j[0], n.y + j[1], n.z + j[2]));
        if (hz_v3_dot(d, n) < 0.26f)
            continue;
        tested++;
        for (int side = 0; side < 2; side++) {
            hz_vec3_t dn = side ? hz_v3_neg(d) : d, nn = side ? hz_v3_neg(n) : n;
            hz_vec3_t o = hz_accel_offset_origin(p, nn, scale);
            float of[3] = { o.x, o.y, o.z }, df[3] = { dn.x, dn.y, dn.z };
            hz_rayhit_t s;
            fx_set_ray(&s, of, df, 0.0f, INFINITY, i);
            hz_accel_intersect1(a, NULL, &s);
            if (side == 0)
                self_out += s.hit.geom_id == 0;
            else
                self_in += s.hit.geom_id != 0 || s.hit.prim_id == h.hit.prim_id || s.ray.tfar < 1e-3f * diam;
            /* the same rays from the unshifted point do hit themselves now and then */
            float pf[3] = { p.x, p.y, p.z };
            fx_set_ray(&s, pf, df, 0.0f, INFINITY, i);
            hz_accel_intersect1(a, NULL, &s);
            raw_self += s.hit.geom_id == 0 && s.ray.tfar < 1e-3f * diam;
        }
    }
    print_message("%s: %u secondary rays, self-hits with offset %u out / %u in, without %u\n", mesh_name[mk],
                  tested, self_out, self_in, raw_self);
    assert_true(tested > 1000);
    assert_int_equal(self_out, 0);
    assert_int_equal(self_in, 0);
    assert_true(raw_self > 0);
    hz_arena_reset(&arena, m0);
}

static void test_offset_origin(void **state)
{
    (void)state;
    check_offsets(M_SPHERE);
    check_offsets(M_TINY);
    check_offsets(M_HUGE);
    /* the offset is a few ulps far from the origin and tiny near it */
    hz_vec3_t o = hz_accel_offset_origin(hz_v3(1e6f, 0.0f, -1e-9f), hz_v3(1, 0, -1), 1.0f);
    assert_true(o.x > 1e6f && o.x <= 1e6f + 1e6f * 256.0f / 8388608.0f); /* <= 256 ulps */
    assert_true(o.y == 0.0f);
    assert_true(o.z < -1e-9f && o.z > -1e-4f);
    hz_vec3_t q = hz_accel_offset_origin(hz_v3(1e-9f, 0.0f, 0.0f), hz_v3(1, 0, 0), 1e-6f);
    assert_true(q.x > 1e-9f && q.x < 1e-9f + 1e-10f);
    hz_vec3_t z = hz_accel_offset_origin(hz_v3(0.5f, 0.5f, 0.5f), hz_v3(0, 0, 1), -3.0f); /* scale 1 */
    assert_true(z.x == 0.5f && z.z > 0.5f);
}

/* ---- the same hits bit for bit on x86-64 and AArch64 (whose trees differ: 8- against 4-wide nodes): a digest
 * of t, u, v, the normal and the triangle of every ray, against the value this test printed on x86-64 ---- */
#define ACCEL_GOLDEN 0xfb91fa61u

static uint32_t digest(uint32_t h, const void *p, size_t n)
{
    const uint8_t *b = p;
    for (size_t i = 0; i < n; i++)
        h = hz_hash32(h ^ (b[i] + 0x9e3779b9u * (uint32_t)(i & 3)));
    return h;
}

static void test_golden(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    make_mesh(M_SOUP, &m);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    make_rays(&m, 2024);
    const uint32_t n = 40000; /* the same count on every board (N_RAYS holds at least as many) */
    fx_trace1(a, HZ_ACCEL_KERNEL_SCALAR, rays_in, rays_ref, n, NULL);
    uint32_t h = 1;
    for (uint32_t i = 0; i < n; i++) {
        h = digest(h, &rays_ref[i].ray.tfar, sizeof(float));
        h = digest(h, &rays_ref[i].hit, sizeof(hz_hit_t));
    }
    const hz_accel_info_t *in = &a->info;
    print_message("accel golden digest 0x%08x (refs %u, spatial splits %u, leaves %u)\n", h, in->ref_count,
                  in->spatial_splits, in->leaf_count);
    assert_int_equal(h, ACCEL_GOLDEN);
    hz_arena_reset(&arena, m0);
}

static void test_sphere(void **state) { (void)state; check_mesh(M_SPHERE); }
static void test_cube_sphere(void **state) { (void)state; check_mesh(M_CUBE); }
static void test_soup_degenerate(void **state) { (void)state; check_mesh(M_SOUP); }
static void test_scaled_tiny(void **state) { (void)state; check_mesh(M_TINY); }
static void test_scaled_huge(void **state) { (void)state; check_mesh(M_HUGE); }
static void test_far_offset(void **state) { (void)state; check_mesh(M_FAR); }

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_cube_sphere),
        cmocka_unit_test(test_soup_degenerate),
        cmocka_unit_test(test_scaled_tiny),
        cmocka_unit_test(test_scaled_huge),
        cmocka_unit_test(test_far_offset),
        cmocka_unit_test(test_anyhit),
        cmocka_unit_test(test_shadow_rays),
        cmocka_unit_test(test_bad_rays),
        cmocka_unit_test(test_stats),
        cmocka_unit_test(test_offset_origin),
        cmocka_unit_test(test_golden),
    };
    return HZ_RUN_GROUP(tests, setup, NULL);
}
