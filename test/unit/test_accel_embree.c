/*
 * The Embree backend against the native one (host boards with embree in BOARD_ACCEL): on procedural meshes,
 * 10^5 camera rays + 10^5 random rays per mesh agree on hit/miss for >= 99.99% of rays and, where both hit, on
 * the triangle or on t within 1e-5 relative; normals point the same way. Packets of 4 and 8 give Embree's single
 * ray answers; any-hit filters, occlusion, refit, error mapping and the memory monitor work through the same
 * interface.
 * hz-test: embree (needs the Embree backend)
 */
#include "hz_test.h"

#include "accel_fixture.h"
#include "accel_scenes.h"
#include "embree_accel.h"

#define N_RAYS 200000u /* per mesh: the first 10^5 from a camera, the rest random */
#define CAM 316u       /* 316 x 316 ~ 10^5 camera rays */

static uint8_t mem[192u << 20] HZ_ALIGNED(64);
static hz_arena_t arena;
static hz_rayhit_t in[N_RAYS], nat[N_RAYS], emb[N_RAYS];

static int setup(void **state)
{
    (void)state;
    hz_arena_init(&arena, "accel", mem, sizeof mem);
    return 0;
}

static void make_rays(const hz_mesh_t *m, uint64_t seed)
{
    fx_bounds_t b = fx_mesh_bounds(m);
    fx_random_rays(in, N_RAYS, b, seed);
    float ext = b.hi[0] - b.lo[0];
    float eye[3] = { b.lo[0] - 0.6f * ext, b.hi[1] + 0.5f * ext, b.hi[2] + 1.2f * ext };
    fx_camera_rays(in, CAM, CAM, eye, b);
}

typedef struct agreement {
    uint32_t rays, hitmiss, prim_or_t, normal;
} agreement_t;

static agreement_t compare(const hz_rayhit_t *a, const hz_rayhit_t *b, uint32_t n)
{
    agreement_t r = { n, 0, 0, 0 };
    for (uint32_t i = 0; i < n; i++) {
        bool ha = a[i].hit.geom_id == 0, hb = b[i].hit.geom_id == 0;
        if (ha != hb) {
            r.hitmiss++;
            continue;
        }
        if (!ha)
            continue;
        float ta = a[i].ray.tfar, tb = b[i].ray.tfar;
        if (a[i].hit.prim_id != b[i].hit.prim_id && fabsf(ta - tb) > 1e-5f * fmaxf(fabsf(ta), fabsf(tb))) {
            if (r.prim_or_t++ < 2) /* rays through edges: Embree's test is not watertight unless robust */
                print_message("  ray %u: native prim %u t %.9g (u %.3g v %.3g), embree prim %u t %.9g\n", i,
                              a[i].hit.prim_id, (double)ta, (double)a[i].hit.u, (double)a[i].hit.v, b[i].hit.prim_id,
                              (double)tb);
        }
        else if (a[i].hit.prim_id == b[i].hit.prim_id &&
                 a[i].hit.ng_x * b[i].hit.ng_x + a[i].hit.ng_y * b[i].hit.ng_y + a[i].hit.ng_z * b[i].hit.ng_z <= 0.0f)
            r.normal++;
    }
    return r;
}

static void assert_agree(const char *what, agreement_t r)
{
    uint32_t agree = r.rays - r.hitmiss - r.prim_or_t;
    print_message("%s: %u rays, hit/miss differ on %u, triangle and t on %u: %.4f%% agree; normals differ on %u\n",
                  what, r.rays, r.hitmiss, r.prim_or_t, 100.0 * agree / r.rays, r.normal);
    /* >= 99.99% agree on hit/miss, and on the triangle or t where both hit */
    assert_true((uint64_t)agree * 10000u >= (uint64_t)r.rays * 9999u);
    assert_int_equal(r.normal, 0);
}

static void cross_check(hz_mesh_t *m, const char *name, bool robust)
{
    hz_accel_geom_t g = hz_meshgen_geom(m);
    hz_accel_config_t cfg;
    hz_accel_config_default(&cfg);
    cfg.robust = robust;
    hz_accel_t *a, *e;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, &cfg, &arena, &err), HZ_OK);
    assert_int_equal(hz_accel_build_embree(&e, &g, &cfg, NULL, &arena, &err), HZ_OK);
    assert_true(e->info.bytes > 0 && e->info.bytes_peak >= e->info.bytes);
    make_rays(m, 55);
    fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, in, nat, N_RAYS, NULL);
    fx_trace1(e, HZ_ACCEL_KERNEL_AUTO, in, emb, N_RAYS, NULL);
    char what[96];
    snprintf(what, sizeof what, "%s%s: native vs embree rtcIntersect1", name, robust ? " (embree robust)" : "");
    assert_agree(what, compare(nat, emb, N_RAYS));
    /* Embree's packets and single rays agree with each other (both Embree) */
    static hz_rayhit_t pk[N_RAYS];
    for (int pw = 4; pw <= 8; pw += 4) {
        fx_trace_packets(e, HZ_ACCEL_KERNEL_AUTO, HZ_ACCEL_COHERENT, pw, false, in, pk, N_RAYS, NULL);
        snprintf(what, sizeof what, "%s: native vs embree rtcIntersect%d", name, pw);
        assert_agree(what, compare(nat, pk, N_RAYS));
    }
    /* occlusion */
    static uint8_t on[N_RAYS], oe[N_RAYS];
    fx_occlusion(a, HZ_ACCEL_KERNEL_AUTO, 0, 8, in, on, N_RAYS, NULL);
    fx_occlusion(e, HZ_ACCEL_KERNEL_AUTO, 0, 8, in, oe, N_RAYS, NULL);
    uint32_t diff = 0;
    for (uint32_t i = 0; i < N_RAYS; i++)
        diff += on[i] != oe[i];
    print_message("%s: occlusion differs on %u rays\n", name, diff);
    assert_true(diff * 10000u <= N_RAYS);
    hz_accel_release(e);
}

static void test_sphere(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    hz_error_t err;
    assert_int_equal(hz_meshgen_sphere(&m, &arena, 64, 128, 1.0f, &err), HZ_OK);
    cross_check(&m, "sphere", false);
    cross_check(&m, "sphere", true);
    hz_arena_reset(&arena, m0);
}

static void test_soup(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    hz_error_t err;
    assert_int_equal(hz_meshgen_soup(&m, &arena, 20000, 1.0f, 0.15f, 8, &err), HZ_OK);
    assert_int_equal(hz_meshgen_append_degenerates(&m, &arena, 500, 2, &err), HZ_OK);
    cross_check(&m, "soup", false);
    hz_arena_reset(&arena, m0);
}

static void test_scaled(void **state)
{
    (void)state;
    const float scales[] = { 1e-6f, 1e6f };
    for (int i = 0; i < 2; i++) {
        hz_arena_mark_t m0 = hz_arena_mark(&arena);
        hz_mesh_t m;
        hz_error_t err;
        assert_int_equal(hz_meshgen_cube_sphere(&m, &arena, 30, 1.0f, true, &err), HZ_OK);
        hz_meshgen_transform(&m, scales[i], hz_v3(scales[i], 0.0f, -scales[i]));
        cross_check(&m, i ? "cube-sphere x 1e6" : "cube-sphere x 1e-6", false);
        hz_arena_reset(&arena, m0);
    }
}

static bool accept_rule(uint32_t prim)
{
    return (hz_hash32(prim + 991u) % 3u) != 0;
}

/* The decision depends on the side too: both backends must tell the same one for the hits to agree. */
static bool side_rule(uint32_t prim, unsigned back)
{
    return accept_rule(back ? prim ^ 0x40000000u : prim);
}

static bool anyhit_cb(void *user, uint32_t prim, float u, float v, float t, uint32_t ray_id, int lane, unsigned back)
{
    (void)user, (void)u, (void)v, (void)t, (void)ray_id, (void)lane;
    return side_rule(prim, back);
}

/* The geometric side: the ray runs along (v1 - v0) x (v2 - v0). */
static unsigned geom_back(const hz_mesh_t *m, uint32_t prim, const hz_rayhit_t *r)
{
    const uint32_t *tv = m->tri + (size_t)prim * 3;
    const float *a = m->pos + (size_t)tv[0] * 4, *b = m->pos + (size_t)tv[1] * 4, *c = m->pos + (size_t)tv[2] * 4;
    hz_vec3_t n = hz_v3_cross(hz_v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]), hz_v3(c[0] - a[0], c[1] - a[1], c[2] - a[2]));
    return hz_v3_dot(n, hz_v3(r->ray.dir_x, r->ray.dir_y, r->ray.dir_z)) > 0.0f;
}

static void test_anyhit_filters(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    hz_error_t err;
    assert_int_equal(hz_meshgen_soup(&m, &arena, 20000, 1.0f, 0.15f, 9, &err), HZ_OK);
    m.tri_flags = hz_arena_calloc(&arena, m.tri_count, 1, 16);
    assert_non_null(m.tri_flags);
    for (uint32_t t = 0; t < m.tri_count; t += 2)
        m.tri_flags[t] = HZ_ACCEL_TRI_ANYHIT;
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a, *e;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    assert_int_equal(hz_accel_build_embree(&e, &g, NULL, NULL, &arena, &err), HZ_OK);
    make_rays(&m, 66);
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    ctx.anyhit = anyhit_cb;
    fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, in, nat, N_RAYS, &ctx);
    fx_trace1(e, HZ_ACCEL_KERNEL_AUTO, in, emb, N_RAYS, &ctx);
    assert_agree("any-hit: native vs embree rtcIntersect1", compare(nat, emb, N_RAYS));
    fx_trace_packets(e, HZ_ACCEL_KERNEL_AUTO, 0, 8, false, in, emb, N_RAYS, &ctx);
    assert_agree("any-hit: native vs embree rtcIntersect8", compare(nat, emb, N_RAYS));
    uint32_t rejected = 0;
    for (uint32_t i = 0; i < N_RAYS; i++)
        rejected += nat[i].hit.geom_id == 0 && m.tri_flags[nat[i].hit.prim_id] &&
                    !side_rule(nat[i].hit.prim_id, geom_back(&m, nat[i].hit.prim_id, &in[i]));
    assert_int_equal(rejected, 0);
    static uint8_t on[N_RAYS], oe[N_RAYS];
    fx_occlusion(a, HZ_ACCEL_KERNEL_AUTO, 0, 8, in, on, N_RAYS, &ctx);
    fx_occlusion(e, HZ_ACCEL_KERNEL_AUTO, 0, 8, in, oe, N_RAYS, &ctx);
    uint32_t diff = 0;
    for (uint32_t i = 0; i < N_RAYS; i++)
        diff += on[i] != oe[i];
    assert_true(diff * 10000u <= N_RAYS);
    hz_accel_release(e);
    hz_arena_reset(&arena, m0);
}

static void test_refit(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    hz_error_t err;
    assert_int_equal(hz_meshgen_sphere(&m, &arena, 48, 96, 1.0f, &err), HZ_OK);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a, *e;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    assert_int_equal(hz_accel_build_embree(&e, &g, NULL, NULL, &arena, &err), HZ_OK);
    for (uint32_t i = 0; i < m.vertex_count; i++) { /* squash and shift */
        m.pos[4u * i + 1] *= 0.5f;
        m.pos[4u * i + 0] += 0.25f;
    }
    assert_int_equal(hz_accel_refit(a, &err), HZ_OK);
    assert_int_equal(hz_accel_refit(e, &err), HZ_OK);
    make_rays(&m, 7);
    fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, in, nat, N_RAYS, NULL);
    fx_trace1(e, HZ_ACCEL_KERNEL_AUTO, in, emb, N_RAYS, NULL);
    assert_agree("after refit", compare(nat, emb, N_RAYS));
    hz_accel_release(e);
    hz_arena_reset(&arena, m0);
}

static void test_errors_and_memory(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    hz_error_t err;
    assert_int_equal(hz_meshgen_sphere(&m, &arena, 64, 128, 1.0f, &err), HZ_OK);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *e;
    /* a device config Embree rejects */
    assert_int_not_equal(hz_accel_build_embree(&e, &g, NULL, "threads=abc", &arena, &err), HZ_OK);
    assert_non_null(strstr(err.msg, "embree"));
    /* bad geometry: the shared check names the triangle */
    uint32_t saved = m.tri[5];
    m.tri[5] = m.vertex_count;
    assert_int_equal(hz_accel_build_embree(&e, &g, NULL, NULL, &arena, &err), HZ_E_RANGE);
    assert_non_null(strstr(err.msg, "triangle 1"));
    m.tri[5] = saved;
    /* the memory monitor refuses past the arena's free bytes */
    static uint8_t small[64u << 10] HZ_ALIGNED(64);
    hz_arena_t sa;
    hz_arena_init(&sa, "accel", small, sizeof small);
    assert_int_equal(hz_accel_build_embree(&e, &g, NULL, NULL, &sa, &err), HZ_E_NO_MEMORY);
    print_message("small arena: %s\n", err.msg);
    assert_non_null(strstr(err.msg, "bytes"));
    assert_int_equal(sa.used, 0);
    hz_arena_reset(&arena, m0);
}

/* The shared scenes (`make test` bakes them): 10^5 camera rays from the scene's camera + 10^5 random rays. */
static void check_scene(const char *name)
{
    hz_scene_t sc;
    hz_accel_geom_t g;
    if (!fx_scene_load(name, &sc, &g))
        skip();
    hz_pools_t *p = hz_pools_get();
    hz_accel_t *a, *e;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &p->accel, &err), HZ_OK);
    assert_int_equal(hz_accel_build_embree(&e, &g, NULL, NULL, &p->accel, &err), HZ_OK);
    fx_scene_rays(&sc, in, 100000, N_RAYS, 4242);
    fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, in, nat, N_RAYS, NULL);
    fx_trace1(e, HZ_ACCEL_KERNEL_AUTO, in, emb, N_RAYS, NULL);
    char what[96];
    snprintf(what, sizeof what, "%s: native vs embree rtcIntersect1", name);
    assert_agree(what, compare(nat, emb, N_RAYS));
    fx_trace_packets(e, HZ_ACCEL_KERNEL_AUTO, HZ_ACCEL_COHERENT, 8, false, in, emb, N_RAYS, NULL);
    snprintf(what, sizeof what, "%s: native vs embree rtcIntersect8", name);
    assert_agree(what, compare(nat, emb, N_RAYS));
    hz_accel_release(e);
}

static void test_scene_dragon(void **state)
{
    (void)state;
    check_scene("dragon-res4");
}

static void test_scene_cornell(void **state)
{
    (void)state;
    check_scene("CornellBox-Original");
}

static void test_scene_sponza(void **state)
{
    (void)state;
    check_scene("sponza");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_soup),
        cmocka_unit_test(test_scaled),
        cmocka_unit_test(test_anyhit_filters),
        cmocka_unit_test(test_refit),
        cmocka_unit_test(test_errors_and_memory),
        cmocka_unit_test(test_scene_dragon),
        cmocka_unit_test(test_scene_cornell),
        cmocka_unit_test(test_scene_sponza),
    };
    return HZ_RUN_GROUP(tests, setup, NULL);
}
