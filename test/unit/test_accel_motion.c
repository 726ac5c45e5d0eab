/*
 * Motion blur in the native accel (seed 002): the MSBVH, the interpolated BVH and the swept BVH over procedural
 * meshes with procedural time keys (swaying, rotation over several keys, vertices crossing split planes,
 * triangles collapsing to a point, a 180-degree rotation in one segment), rays at random times:
 *  - the scalar kernel against brute force over every triangle at the ray's time (hz_accel_brute_intersect1):
 *    same triangle, same t, u, v, ng bits: a lost hit would mean a box that does not bound its triangles;
 *  - every SIMD kernel and packet form (4 and 8 wide, holes, coherent hint) against scalar, bit for bit, and
 *    occlusion in every form;
 *  - a moving triangle against its analytic hit; time clamping; static geometry ignoring time;
 *  - refit after the keys are rewritten in place (still exact), rebuild when the SAH cost grows past the
 *    configured fraction (and not when the fraction is large), the memory bound, and bad motion views.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "accel_fixture.h"

#define MEM_BYTES (160u << 20)
static uint8_t mem[MEM_BYTES] HZ_ALIGNED(64);
static hz_arena_t arena;

/* Under qemu-user (NEON) every traversal is emulated: fewer rays through the same 30 builds and every kernel
 * form (the host runs the same checks with 7.5x the rays). */
#if defined(HZ_SIMD_NEON)
#define N_RAYS 1600u
#define N_BRUTE 100u
#define N_COVER 8000u
#else
#define N_RAYS 12000u
#define N_BRUTE 800u
#define N_COVER 50000u
#endif

static hz_rayhit_t rays_in[N_RAYS], rays_ref[N_RAYS], rays_out[N_RAYS], rays_coh[N_RAYS], rays_coh_ref[N_RAYS];
static uint8_t occ_out[N_RAYS];

static int setup(void **state)
{
    (void)state;
    hz_arena_init(&arena, "test", mem, sizeof mem);
    return 0;
}

static float unit01(uint32_t *s)
{
    *s = hz_hash32(*s + 0x9e3779b9u);
    return (float)(*s >> 8) * (1.0f / 16777216.0f);
}

/* Random rays through the bounds of all keys, half of them aimed at a triangle at the ray's time; times random
 * with every 8th exactly on a key and a few outside [0, 1] and NaN (clamped). */
static void make_rays(const hz_accel_geom_t *g, uint32_t seed)
{
    fx_bounds_t b = { { INFINITY, INFINITY, INFINITY }, { -INFINITY, -INFINITY, -INFINITY } };
    for (uint32_t k = 0; k < g->time_keys; k++)
        for (uint32_t v = 0; v < g->vertex_count; v++)
            for (int c = 0; c < 3; c++) {
                float x = g->pos_keys[k][4u * v + (uint32_t)c];
                if (isfinite(x))
                    b.lo[c] = fminf(b.lo[c], x), b.hi[c] = fmaxf(b.hi[c], x);
            }
    fx_random_rays(rays_in, N_RAYS, b, seed);
    uint32_t st = seed * 7919u + 1u;
    for (uint32_t i = 0; i < N_RAYS; i++) {
        hz_rayhit_t *r = &rays_in[i];
        float time = unit01(&st);
        if (i % 8u == 3u)
            time = (float)(uint32_t)(unit01(&st) * (float)g->time_keys) / (float)(g->time_keys - 1u);
        if (i % 97u == 5u)
            time = i % 2u ? -0.5f : 1.5f;
        if (i % 211u == 7u)
            time = NAN;
        r->ray.time = time;
        if (i % 2u == 0u) {
            uint32_t t = (uint32_t)(unit01(&st) * (float)g->tri_count) % g->tri_count;
            float b1 = unit01(&st), b2 = unit01(&st);
            if (b1 + b2 > 1.0f)
                b1 = 1.0f - b1, b2 = 1.0f - b2;
            const hz_vec3_t p = hz_meshgen_tri_point(g, t, time, b1, b2);
            const float d[3] = { p.x - r->ray.org_x, p.y - r->ray.org_y, p.z - r->ray.org_z };
            if (isfinite(d[0]) && isfinite(d[1]) && isfinite(d[2]) && (d[0] != 0.0f || d[1] != 0.0f || d[2] != 0.0f))
                r->ray.dir_x = d[0], r->ray.dir_y = d[1], r->ray.dir_z = d[2];
        }
    }
}

static uint32_t count_diff(const char *what)
{
    uint32_t bad = 0;
    for (uint32_t i = 0; i < N_RAYS; i++)
        if (!fx_same(&rays_ref[i], &rays_out[i]) && bad++ < 3)
            print_message("%s: ray %u (time %g): prim %u/%u t %.9g/%.9g\n", what, i, (double)rays_in[i].ray.time,
                          rays_ref[i].hit.prim_id, rays_out[i].hit.prim_id, (double)rays_ref[i].ray.tfar,
                          (double)rays_out[i].ray.tfar);
    return bad;
}

static void check_brute(const hz_accel_geom_t *g, const char *what)
{
    uint32_t bad = 0, hits = 0;
    for (uint32_t i = 0; i < N_BRUTE; i++) {
        uint32_t j = i * (N_RAYS / N_BRUTE);
        hz_rayhit_t b = rays_in[j];
        hz_accel_brute_intersect1(g, &b);
        hits += b.hit.geom_id == 0;
        if (!fx_same(&b, &rays_ref[j]) && bad++ < 5)
            print_message("%s: ray %u time %g: brute prim %u t %.9g, accel prim %u t %.9g\n", what, j,
                          (double)rays_in[j].ray.time, b.hit.prim_id, (double)b.ray.tfar, rays_ref[j].hit.prim_id,
                          (double)rays_ref[j].ray.tfar);
    }
    assert_int_equal(bad, 0);
    assert_true(hits > N_BRUTE / 10); /* the rays do hit */
}

/* Every kernel and packet form against the scalar reference (rays_ref). */
static void check_kernels(const hz_accel_t *a, const char *what)
{
    const hz_accel_kernel_t ks[] = { HZ_ACCEL_KERNEL_SIMD_SINGLE, HZ_ACCEL_KERNEL_SIMD_PACKET,
                                     HZ_ACCEL_KERNEL_SIMD_MASKED, HZ_ACCEL_KERNEL_AUTO };
    char name[160];
    for (size_t q = 0; q < HZ_ARRAY_LEN(ks); q++) {
        snprintf(name, sizeof name, "%s %s", what, hz_accel_kernel_name(ks[q]));
        fx_trace1(a, ks[q], rays_in, rays_out, N_RAYS, NULL);
        assert_int_equal(count_diff(name), 0);
        for (int w = 4; w <= 8; w += 4) {
            fx_trace_packets(a, ks[q], w == 8 ? HZ_ACCEL_COHERENT : 0, w, true, rays_in, rays_out, N_RAYS, NULL);
            for (uint32_t i = 6; i < N_RAYS; i += 7) {
                assert_true(fx_same(&rays_in[i], &rays_out[i]));
                rays_out[i] = rays_ref[i];
            }
            assert_int_equal(count_diff(name), 0);
        }
    }
    const struct {
        hz_accel_kernel_t k;
        int width;
    } occ[] = { { HZ_ACCEL_KERNEL_SCALAR, 0 }, { HZ_ACCEL_KERNEL_SIMD_SINGLE, 0 }, { HZ_ACCEL_KERNEL_SIMD_PACKET, 8 },
                { HZ_ACCEL_KERNEL_SIMD_MASKED, 4 }, { HZ_ACCEL_KERNEL_AUTO, 8 } };
    for (size_t q = 0; q < HZ_ARRAY_LEN(occ); q++) {
        fx_occlusion(a, occ[q].k, HZ_ACCEL_COHERENT, occ[q].width, rays_in, occ_out, N_RAYS, NULL);
        uint32_t bad = 0;
        for (uint32_t i = 0; i < N_RAYS; i++)
            bad += occ_out[i] != (rays_ref[i].hit.geom_id == 0);
        if (bad)
            print_message("%s occlusion %s/%d: %u differ\n", what, hz_accel_kernel_name(occ[q].k), occ[q].width, bad);
        assert_int_equal(bad, 0);
    }
}

/* Coherent packets (the kernels' width) at each lane's own time: the lanes of a packet start at its first ray's
 * origin and point within 2% of its direction (the signs kept: a frustum packet), each at the time of its own
 * ray of rays_in (random, on keys, outside [0, 1], NaN: the lanes sit in different segments). The motion packet
 * kernels (closest and occlusion, asked for by name) against the scalar reference; where the tree has key boxes
 * they must visit fewer nodes than the same packets through the single-ray kernel, which shows that they ran. */
static void check_motion_packets(const hz_accel_t *a, const char *what)
{
    uint32_t st = 4242u;
    for (uint32_t i = 0; i < N_RAYS; i++) {
        const hz_rayhit_t *lead = &rays_in[i - i % 8u];
        hz_rayhit_t *r = &rays_coh[i];
        *r = rays_in[i];
        r->ray.org_x = lead->ray.org_x, r->ray.org_y = lead->ray.org_y, r->ray.org_z = lead->ray.org_z;
        r->ray.dir_x = lead->ray.dir_x * (1.0f + 0.04f * (unit01(&st) - 0.5f));
        r->ray.dir_y = lead->ray.dir_y * (1.0f + 0.04f * (unit01(&st) - 0.5f));
        r->ray.dir_z = lead->ray.dir_z * (1.0f + 0.04f * (unit01(&st) - 0.5f));
    }
    fx_trace1(a, HZ_ACCEL_KERNEL_SCALAR, rays_coh, rays_coh_ref, N_RAYS, NULL);
    hz_accel_stats_t s1, s8;
    memset(&s1, 0, sizeof s1), memset(&s8, 0, sizeof s8);
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    ctx.stats = &s1;
    fx_trace_packets(a, HZ_ACCEL_KERNEL_SIMD_SINGLE, HZ_ACCEL_COHERENT, HZ_BVH_WIDTH, true, rays_coh, rays_out, N_RAYS,
                     &ctx);
    ctx.stats = &s8;
    fx_trace_packets(a, HZ_ACCEL_KERNEL_SIMD_PACKET, HZ_ACCEL_COHERENT, HZ_BVH_WIDTH, true, rays_coh, rays_out, N_RAYS,
                     &ctx);
    uint32_t bad = 0, hits = 0;
    for (uint32_t i = 0; i < N_RAYS; i++) {
        const hz_rayhit_t *want = i % 7u == 6u ? &rays_coh[i] : &rays_coh_ref[i];
        hits += want->hit.geom_id == 0;
        if (!fx_same(want, &rays_out[i]) && bad++ < 3)
            print_message("%s motion packet: ray %u (time %g): prim %u/%u t %.9g/%.9g\n", what, i,
                          (double)rays_coh[i].ray.time, want->hit.prim_id, rays_out[i].hit.prim_id,
                          (double)want->ray.tfar, (double)rays_out[i].ray.tfar);
    }
    assert_int_equal(bad, 0);
    assert_true(hits > N_RAYS / 20);
#if HZ_FEATURE_STATS
    if (a->info.blur != HZ_ACCEL_BLUR_SWEPT && hz_accel_kernel_available(HZ_ACCEL_KERNEL_SIMD_PACKET)) {
        if (!(s8.nodes < s1.nodes))
            print_message("%s motion packet: %llu nodes against %llu single\n", what, (unsigned long long)s8.nodes,
                          (unsigned long long)s1.nodes);
        assert_true(s8.nodes < s1.nodes);
    }
#endif
    fx_occlusion(a, HZ_ACCEL_KERNEL_SIMD_PACKET, HZ_ACCEL_COHERENT, HZ_BVH_WIDTH, rays_coh, occ_out, N_RAYS, NULL);
    bad = 0;
    for (uint32_t i = 0; i < N_RAYS; i++)
        bad += occ_out[i] != (rays_coh_ref[i].hit.geom_id == 0);
    if (bad)
        print_message("%s motion packet occlusion: %u differ\n", what, bad);
    assert_int_equal(bad, 0);
}

typedef struct motion_case {
    hz_meshgen_motion_kind_t kind;
    uint32_t keys;
    float turns;
} motion_case_t;

static const motion_case_t cases[] = {
    { HZ_MESHGEN_SWAY, 2, 0.0f },     { HZ_MESHGEN_ROTATE, 5, 0.5f }, { HZ_MESHGEN_CROSS, 3, 0.0f },
    { HZ_MESHGEN_COLLAPSE, 9, 0.0f }, { HZ_MESHGEN_ROT180, 2, 0.0f },
};

static void make_mesh(int which, hz_mesh_t *m)
{
    hz_error_t err;
    if (which == 0) {
        assert_int_equal(hz_meshgen_sphere(m, &arena, 24, 48, 1.0f, &err), HZ_OK);
    } else {
        /* long thin triangles invite spatial splits (the MSBVH's clipped pieces) */
        assert_int_equal(hz_meshgen_soup(m, &arena, 3000, 1.0f, 0.9f, 7, &err), HZ_OK);
        assert_int_equal(hz_meshgen_append_degenerates(m, &arena, 100, 3, &err), HZ_OK);
    }
}

static void run_case(int mesh, const motion_case_t *mc, hz_accel_blur_t blur)
{
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    make_mesh(mesh, &m);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    assert_int_equal(hz_meshgen_motion(&g, m.pos, mc->kind, mc->keys, hz_v3(0.1f, 0.0f, -0.05f), 2.0f, mc->turns,
                                       &arena),
                     HZ_OK);
    hz_accel_config_t cfg;
    hz_accel_config_default(&cfg);
    cfg.blur = blur;
    hz_accel_t *a;
    hz_error_t err;
    const hz_accel_bytes_t bound = hz_accel_bytes_bound_geom(&g, &cfg);
    const size_t before = arena.used;
    assert_int_equal(hz_accel_build_native(&a, &g, &cfg, &arena, &err), HZ_OK);
    assert_true(arena.used - before <= bound.kept);
    assert_true(a->info.bytes_peak <= bound.peak);
    assert_int_equal(a->info.time_keys, mc->keys);
    assert_int_equal(a->info.blur, blur);
    if (blur != HZ_ACCEL_BLUR_MSBVH)
        assert_int_equal(a->info.spatial_splits, 0);
    char what[96];
    snprintf(what, sizeof what, "%s/%s/K=%u/%s", mesh ? "soup" : "sphere", hz_meshgen_motion_name(mc->kind), mc->keys,
             hz_accel_blur_name(blur));
    make_rays(&g, 100u + (uint32_t)mesh * 10u + (uint32_t)mc->kind);
    fx_trace1(a, HZ_ACCEL_KERNEL_SCALAR, rays_in, rays_ref, N_RAYS, NULL);
    check_brute(&g, what);
    check_kernels(a, what);
    check_motion_packets(a, what);
    hz_arena_reset(&arena, m0);
}

static void test_motion_cases(void **state)
{
    (void)state;
    for (int mesh = 0; mesh < 2; mesh++)
        for (size_t c = 0; c < HZ_ARRAY_LEN(cases); c++)
            for (int b = 0; b < HZ_ACCEL_BLUR_COUNT; b++)
                run_case(mesh, &cases[c], (hz_accel_blur_t)b);
}

/* Per-node motion segments (seed 002 section 6.3): a node keeps 2^m + 1 of the K = 9 keys, as few as its
 * content's motion needs. Content that moves linearly (every vertex along a straight line to one point: boxes
 * shrink linearly) gives every node one segment; a half turn over the interval (22.5 degrees per key segment)
 * leaves the boxes far from linear, so most nodes keep more; every-key keeps all 9. Per-node and every-key trees
 * return the same hits bit for bit (boxes only decide what is visited), also after a refit over a different
 * motion, which keeps the levels; per-node against brute force and every kernel is test_motion_cases (the
 * default). */
static void test_segments_per_node(void **state)
{
    (void)state;
    static const struct {
        hz_meshgen_motion_kind_t kind;
        float turns;
    } kinds[] = { { HZ_MESHGEN_COLLAPSE, 0.0f }, { HZ_MESHGEN_ROTATE, 0.5f }, { HZ_MESHGEN_SWAY, 0.0f } };
    for (int mesh = 0; mesh < 2; mesh++)
        for (size_t c = 0; c < HZ_ARRAY_LEN(kinds); c++)
            for (int b = 0; b < HZ_ACCEL_BLUR_SWEPT; b++) { /* swept keeps no key boxes */
                hz_arena_mark_t m0 = hz_arena_mark(&arena);
                hz_mesh_t m;
                make_mesh(mesh, &m);
                hz_accel_geom_t g = hz_meshgen_geom(&m);
                assert_int_equal(hz_meshgen_motion(&g, m.pos, kinds[c].kind, 9, hz_v3(0.1f, 0.0f, -0.05f), 2.0f,
                                                   kinds[c].turns, &arena),
                                 HZ_OK);
                hz_accel_config_t cfg;
                hz_accel_config_default(&cfg);
                assert_int_equal(cfg.segments, HZ_ACCEL_SEGMENTS_PER_NODE);
                cfg.blur = (hz_accel_blur_t)b;
                hz_accel_t *per, *every;
                hz_error_t err;
                const hz_accel_bytes_t bound = hz_accel_bytes_bound_geom(&g, &cfg);
                size_t before = arena.used;
                assert_int_equal(hz_accel_build_native(&per, &g, &cfg, &arena, &err), HZ_OK);
                const size_t per_bytes = arena.used - before;
                assert_true(per_bytes <= bound.kept);
                assert_true(per->info.bytes_peak <= bound.peak);
                cfg.segments = HZ_ACCEL_SEGMENTS_EVERY_KEY;
                before = arena.used;
                assert_int_equal(hz_accel_build_native(&every, &g, &cfg, &arena, &err), HZ_OK);
                const size_t every_bytes = arena.used - before;
                const uint64_t n = per->info.node_count;
                char what[96];
                snprintf(what, sizeof what, "%s/%s/%s", mesh ? "soup" : "sphere", hz_meshgen_motion_name(kinds[c].kind),
                         hz_accel_blur_name(cfg.blur));
                print_message("%s: %llu nodes, per-node %llu key sets (%.2f per node, SAH %.3f, %zu bytes), every key "
                              "%llu (SAH %.3f, %zu bytes)\n",
                              what, (unsigned long long)n, (unsigned long long)per->info.key_sets,
                              (double)per->info.key_sets / (double)n, (double)per->info.sah_cost, per_bytes,
                              (unsigned long long)every->info.key_sets, (double)every->info.sah_cost, every_bytes);
                assert_int_equal(every->info.node_count, n);
                assert_int_equal(every->info.key_sets, 9u * n);
                assert_true(per->info.key_sets >= 2u * n && per->info.key_sets <= 9u * n);
                /* what per-node adds: a word per node (mref) */
                assert_true(per_bytes <= every_bytes + n * sizeof(uint32_t) + 64u);
                if (kinds[c].kind == HZ_MESHGEN_COLLAPSE) {
                    assert_int_equal(per->info.key_sets, 2u * n);
                    assert_true(per_bytes + 7u * n * 6u * HZ_BVH_WIDTH * sizeof(float) <= every_bytes + n * sizeof(uint32_t) + 64u);
                }
                if (kinds[c].kind == HZ_MESHGEN_ROTATE)
                    assert_true(per->info.key_sets > 4u * n);
                /* the levels are paid for in box area: at most 1/32 more per node over its content, which its
                 * children's levels may have grown, so at most (1 + 1/32)^levels in the tree's SAH */
                assert_true(per->info.sah_cost <= every->info.sah_cost * powf(1.0f + 1.0f / 32.0f,
                                                                              (float)per->info.depth + 1.0f));
                make_rays(&g, 300u + (uint32_t)c * 10u + (uint32_t)mesh);
                fx_trace1(every, HZ_ACCEL_KERNEL_SCALAR, rays_in, rays_ref, N_RAYS, NULL);
                fx_trace1(per, HZ_ACCEL_KERNEL_SCALAR, rays_in, rays_out, N_RAYS, NULL);
                assert_int_equal(count_diff(what), 0);
                fx_trace1(per, HZ_ACCEL_KERNEL_SIMD_SINGLE, rays_in, rays_out, N_RAYS, NULL);
                assert_int_equal(count_diff(what), 0);
                /* a refit over another motion keeps the levels and stays exact */
                hz_accel_geom_t h = hz_meshgen_geom(&m);
                assert_int_equal(hz_meshgen_motion(&h, m.pos, HZ_MESHGEN_ROTATE, 9, hz_v3(0.3f, 0.0f, 0.2f), 2.0f,
                                                   0.3f, &arena),
                                 HZ_OK);
                for (uint32_t k = 0; k < 9u; k++)
                    memcpy((void *)(uintptr_t)g.pos_keys[k], h.pos_keys[k], 4u * sizeof(float) * m.vertex_count);
                const uint64_t sets = per->info.key_sets;
                per->info.sah_built = 1e30f; /* refit only: a rebuild would choose new levels */
                assert_int_equal(hz_accel_refit(per, &err), HZ_OK);
                assert_int_equal(per->info.key_sets, sets);
                assert_int_equal(per->info.rebuilds, 0);
                make_rays(&g, 400u + (uint32_t)c * 10u + (uint32_t)mesh);
                fx_trace1(per, HZ_ACCEL_KERNEL_SCALAR, rays_in, rays_ref, N_RAYS, NULL);
                check_brute(&g, what);
                fx_trace1(per, HZ_ACCEL_KERNEL_SIMD_SINGLE, rays_in, rays_out, N_RAYS, NULL);
                assert_int_equal(count_diff(what), 0);
                hz_arena_reset(&arena, m0);
            }
}

/* The soup of long slivers the MSBVH tests share (spatial splits happen in it), swaying over K keys. */
static hz_accel_geom_t sliver_soup(hz_mesh_t *m, uint32_t K)
{
    hz_error_t err;
    assert_int_equal(hz_meshgen_soup(m, &arena, 6000, 1.0f, 0.25f, 11, &err), HZ_OK);
    hz_accel_geom_t g = hz_meshgen_geom(m);
    assert_int_equal(hz_meshgen_motion(&g, m->pos, HZ_MESHGEN_SWAY, K, hz_v3(0, 0, 0), 2.0f, 0.0f, &arena), HZ_OK);
    return g;
}

/* A soup of long triangles gets spatial splits in the MSBVH (more references), none in the interpolated BVH;
 * which is cheaper is a property of the scene (make bench reports it on the furball and Sponza). */
static void test_msbvh_splits(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    hz_error_t err;
    hz_accel_geom_t g = sliver_soup(&m, 2);
    hz_accel_config_t cfg;
    hz_accel_config_default(&cfg);
    hz_accel_t *ms, *ip;
    assert_int_equal(hz_accel_build_native(&ms, &g, &cfg, &arena, &err), HZ_OK);
    cfg.blur = HZ_ACCEL_BLUR_INTERP;
    assert_int_equal(hz_accel_build_native(&ip, &g, &cfg, &arena, &err), HZ_OK);
    print_message("soup: msbvh %u refs %u splits sah %.2f, interp %u refs sah %.2f\n", ms->info.ref_count,
                  ms->info.spatial_splits, (double)ms->info.sah_cost, ip->info.ref_count, (double)ip->info.sah_cost);
    assert_true(ms->info.spatial_splits > 0);
    assert_true(ms->info.ref_count > ip->info.ref_count);
    assert_int_equal(ip->info.spatial_splits, 0);
    hz_arena_reset(&arena, m0);
}

/* The replication budget: a small one stops splits (and says so), the largest lets the overlap threshold alone
 * decide on these slivers; the references stay within each budget and the memory within its bound; at every
 * budget that pays for more than a few splits the MSBVH's SAH is no worse than the interpolated BVH's (seed
 * 002's claim). */
static void test_msbvh_budget(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    hz_error_t err;
    hz_accel_geom_t g = sliver_soup(&m, 2);
    hz_accel_config_t icfg;
    hz_accel_config_default(&icfg);
    icfg.blur = HZ_ACCEL_BLUR_INTERP;
    hz_accel_t *ip;
    const hz_arena_mark_t mi = hz_arena_mark(&arena);
    assert_int_equal(hz_accel_build_native(&ip, &g, &icfg, &arena, &err), HZ_OK);
    const float interp_sah = ip->info.sah_cost;
    hz_arena_reset(&arena, mi);
    static const float budgets[] = { 0.002f, 0.01f, 0.05f, 0.25f, HZ_ACCEL_SPLIT_BUDGET_MAX, 100.0f };
    for (size_t i = 0; i < HZ_ARRAY_LEN(budgets); i++) {
        hz_arena_mark_t m1 = hz_arena_mark(&arena);
        hz_accel_config_t cfg;
        hz_accel_config_default(&cfg);
        cfg.split_budget = budgets[i];
        const hz_accel_bytes_t bound = hz_accel_bytes_bound_geom(&g, &cfg);
        const size_t before = arena.used;
        hz_accel_t *a;
        assert_int_equal(hz_accel_build_native(&a, &g, &cfg, &arena, &err), HZ_OK);
        print_message("budget %g: %u refs, %u splits, %u stops, sah %.2f (interp %.2f)\n", (double)budgets[i],
                      a->info.ref_count, a->info.spatial_splits, a->info.budget_stops, (double)a->info.sah_cost,
                      (double)interp_sah);
        if (budgets[i] >= 0.01f) /* 0.002 pays for 3 splits here: greedy top-down, 44.35 against 44.34 */
            assert_true(a->info.sah_cost <= interp_sah);
        assert_true(arena.used - before <= bound.kept);
        assert_true(a->info.bytes_peak <= bound.peak);
        const float b = budgets[i] < HZ_ACCEL_SPLIT_BUDGET_MAX ? budgets[i] : HZ_ACCEL_SPLIT_BUDGET_MAX;
        assert_true((double)a->info.ref_count <= 6000.0 * (1.0 + (double)b) + 1.0);
        if (i == 0)
            assert_true(a->info.budget_stops > 0);
        else if (budgets[i] >= HZ_ACCEL_SPLIT_BUDGET_MAX)
            assert_int_equal(a->info.budget_stops, 0);
        hz_arena_reset(&arena, m1);
    }
    hz_arena_reset(&arena, m0);
}

/* Coverage, the oracle a clipped piece must pass: rays aimed at random points of random triangles at random
 * times (keys included), each from a random point of the bounds; every one must hit at or before its target
 * (direction = target - origin, so the target is t = 1), or else agree with brute force. A piece that leaves
 * part of its triangle outside every leaf lets such rays through. Returns the count that did neither. */
static uint32_t check_cover(const hz_accel_t *a, const hz_accel_geom_t *g, uint32_t seed, uint32_t n,
                            const char *what)
{
    uint32_t st = seed * 2654435761u + 7u, bad = 0, tried = 0;
    make_rays(g, seed);
    for (uint32_t i = 0; i < n; i++) {
        hz_rayhit_t r = rays_in[i % N_RAYS];
        float time = unit01(&st);
        if (i % 4u == 1u)
            time = (float)(uint32_t)(unit01(&st) * (float)g->time_keys) / (float)(g->time_keys - 1u);
        const uint32_t t = (uint32_t)(unit01(&st) * (float)g->tri_count) % g->tri_count;
        float b1 = 0.02f + 0.96f * unit01(&st), b2 = 0.02f + 0.96f * unit01(&st);
        if (b1 + b2 > 0.98f)
            b1 = 0.98f - b1 * 0.96f, b2 = 0.98f - b2 * 0.96f;
        if (b1 < 0.01f || b2 < 0.01f || b1 + b2 > 0.99f)
            continue;
        const hz_vec3_t p = hz_meshgen_tri_point(g, t, time, b1, b2);
        r.ray.time = time;
        r.ray.dir_x = p.x - r.ray.org_x, r.ray.dir_y = p.y - r.ray.org_y, r.ray.dir_z = p.z - r.ray.org_z;
        r.ray.tnear = 0.0f, r.ray.tfar = INFINITY;
        if (!isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z))
            continue;
        tried++;
        hz_rayhit_t out;
        fx_trace1(a, HZ_ACCEL_KERNEL_SCALAR, &r, &out, 1, NULL);
        if (out.hit.geom_id == 0 && out.ray.tfar <= 1.0001f)
            continue;
        /* a grazing ray can pass its target in floats: brute force over the triangles decides */
        hz_rayhit_t b = r;
        hz_accel_brute_intersect1(g, &b);
        if (!fx_same(&b, &out) && bad++ < 3)
            print_message("%s: ray at triangle %u (time %g): accel prim %u t %.9g, brute force prim %u t %.9g\n",
                          what, t, (double)time, out.hit.prim_id, (double)out.ray.tfar, b.hit.prim_id,
                          (double)b.ray.tfar);
    }
    assert_true(tried > n / 2);
    return bad;
}

/* The MSBVH's refit cuts each split triangle again at the previous keys against its leaf's previous boxes
 * (seed 002 section 5): over unchanged keys the pieces can only grow (the boxes contain the build's, the SAH
 * grows little), and over new motions, again and again, every ray still finds what brute force finds. */
static void test_msbvh_refit_reclip(void **state)
{
    (void)state;
    static const struct { hz_meshgen_motion_kind_t kind; float size; } moves[] = {
        { HZ_MESHGEN_CROSS, 1.5f }, { HZ_MESHGEN_ROTATE, 2.0f }, { HZ_MESHGEN_SWAY, 2.0f }, { HZ_MESHGEN_COLLAPSE, 1.0f },
    };
    for (uint32_t K = 2; K <= 5; K += 3) {
        hz_arena_mark_t m0 = hz_arena_mark(&arena);
        hz_mesh_t m;
        hz_error_t err;
        hz_accel_geom_t g = sliver_soup(&m, K);
        hz_accel_config_t cfg;
        hz_accel_config_default(&cfg);
        cfg.rebuild_sah_growth = 1e9f; /* refits only */
        hz_accel_t *a;
        assert_int_equal(hz_accel_build_native(&a, &g, &cfg, &arena, &err), HZ_OK);
        assert_true(a->info.spatial_splits > 0);
        assert_int_equal(check_cover(a, &g, 400u + K, N_COVER, "built"), 0);
        const float sah0 = a->info.sah_cost;
        assert_int_equal(hz_accel_refit(a, &err), HZ_OK);
        print_message("K=%u: sah built %.3f, refit over the same keys %.3f\n", K, (double)sah0, (double)a->info.sah_cost);
        assert_true(a->info.sah_cost >= sah0);
        assert_true(a->info.sah_cost <= sah0 * 1.05f);
        for (size_t i = 0; i < HZ_ARRAY_LEN(moves); i++) {
            hz_accel_geom_t mv = g;
            assert_int_equal(hz_meshgen_motion(&mv, m.pos, moves[i].kind, K, hz_v3(0.1f, 0, 0), moves[i].size, 0.5f,
                                               &arena),
                             HZ_OK);
            for (uint32_t k = 0; k < K; k++)
                memcpy((void *)(uintptr_t)g.pos_keys[k], mv.pos_keys[k], 4u * sizeof(float) * m.vertex_count);
            assert_int_equal(hz_accel_refit(a, &err), HZ_OK);
            assert_int_equal(a->info.rebuilds, 0);
            char what[64];
            snprintf(what, sizeof what, "K=%u refit %zu (%s)", K, i, hz_meshgen_motion_name(moves[i].kind));
            print_message("%s: sah %.2f\n", what, (double)a->info.sah_cost);
            assert_int_equal(check_cover(a, &g, 500u + (uint32_t)i, N_COVER, what), 0);
            make_rays(&g, 300u + (uint32_t)i);
            fx_trace1(a, HZ_ACCEL_KERNEL_SCALAR, rays_in, rays_ref, N_RAYS, NULL);
            check_brute(&g, what);
            fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, rays_in, rays_out, N_RAYS, NULL);
            assert_int_equal(count_diff(what), 0);
        }
        hz_arena_reset(&arena, m0);
    }
}

/* One triangle in the z = 2t plane (translating along z): a ray down the z axis at time t hits at 10 - 2t. */
static void test_analytic(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    static float k0[12] HZ_ALIGNED(16) = { -1, -1, 0, 0, 1, -1, 0, 0, 0, 1, 0, 0 };
    static float k1[12] HZ_ALIGNED(16) = { -1, -1, 2, 0, 1, -1, 2, 0, 0, 1, 2, 0 };
    static const uint32_t tri[3] = { 0, 1, 2 };
    hz_accel_geom_t g;
    hz_accel_geom_init(&g);
    g.pos = k0, g.vertex_count = 3, g.tri = tri, g.tri_count = 1;
    g.time_keys = 2, g.pos_keys[0] = k0, g.pos_keys[1] = k1;
    for (int b = 0; b < HZ_ACCEL_BLUR_COUNT; b++) {
        hz_accel_config_t cfg;
        hz_accel_config_default(&cfg);
        cfg.blur = (hz_accel_blur_t)b;
        hz_accel_t *a;
        hz_error_t err;
        assert_int_equal(hz_accel_build_native(&a, &g, &cfg, &arena, &err), HZ_OK);
        const float times[] = { 0.0f, 0.25f, 0.5f, 1.0f, -3.0f, 7.0f, NAN };
        const float expect[] = { 10.0f, 9.5f, 9.0f, 8.0f, 10.0f, 8.0f, 10.0f };
        for (size_t i = 0; i < HZ_ARRAY_LEN(times); i++) {
            hz_rayhit_t rh;
            const float o[3] = { 0.0f, 0.0f, 10.0f }, d[3] = { 0.0f, 0.0f, -1.0f };
            fx_set_ray(&rh, o, d, 0.0f, INFINITY, 1);
            rh.ray.time = times[i];
            hz_accel_intersect1(a, NULL, &rh);
            assert_int_equal(rh.hit.prim_id, 0);
            assert_float_equal(rh.ray.tfar, expect[i], 1e-6f);
            assert_float_equal(rh.hit.ng_z, 4.0f, 0.0f); /* (v1 - v0) x (v2 - v0) = (2,0,0) x (1,2,0) */
        }
        /* beside the triangle at time 1 but where it was at time 0: no hit */
        hz_rayhit_t rh;
        const float o[3] = { 0.0f, 0.0f, 1.0f }, d[3] = { 0.0f, 0.0f, -1.0f };
        fx_set_ray(&rh, o, d, 0.0f, 0.5f, 1);
        rh.ray.time = 1.0f;
        hz_accel_intersect1(a, NULL, &rh);
        assert_int_equal(rh.hit.geom_id, HZ_ACCEL_INVALID_ID);
    }
    hz_arena_reset(&arena, m0);
}

/* Static geometry ignores ray.time: results with random times equal those at time 0, bit for bit. */
static void test_static_ignores_time(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    make_mesh(0, &m);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    assert_int_equal(a->info.time_keys, 0);
    fx_random_rays(rays_in, N_RAYS, fx_mesh_bounds(&m), 5);
    fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, rays_in, rays_ref, N_RAYS, NULL);
    uint32_t st = 3;
    for (uint32_t i = 0; i < N_RAYS; i++) {
        rays_in[i].ray.time = i % 5u ? unit01(&st) : NAN;
        rays_ref[i].ray.time = rays_in[i].ray.time;
    }
    fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, rays_in, rays_out, N_RAYS, NULL);
    assert_int_equal(count_diff("static"), 0);
    hz_arena_reset(&arena, m0);
}

/* Refit after rewriting the keys in place: still exact against brute force; a large motion grows the SAH
 * cost past 30% and rebuilds (also exact), a large threshold only refits. */
static void test_refit_rebuild(void **state)
{
    (void)state;
    for (int b = 0; b < HZ_ACCEL_BLUR_COUNT; b++)
        for (int lazy = 0; lazy < 2; lazy++) {
            hz_arena_mark_t m0 = hz_arena_mark(&arena);
            hz_mesh_t m;
            make_mesh(1, &m);
            hz_accel_geom_t g = hz_meshgen_geom(&m);
            assert_int_equal(hz_meshgen_motion(&g, m.pos, HZ_MESHGEN_SWAY, 3, hz_v3(0, 0, 0), 0.5f, 0.0f, &arena),
                             HZ_OK);
            hz_accel_geom_t big = g; /* the same vertices, a much larger motion, written over g's keys */
            assert_int_equal(hz_meshgen_motion(&big, m.pos, HZ_MESHGEN_CROSS, 3, hz_v3(0, 0, 0), 1.5f, 0.0f, &arena),
                             HZ_OK);
            hz_accel_config_t cfg;
            hz_accel_config_default(&cfg);
            cfg.blur = (hz_accel_blur_t)b;
            if (lazy)
                cfg.rebuild_sah_growth = 1000.0f;
            hz_accel_t *a;
            hz_error_t err;
            assert_int_equal(hz_accel_build_native(&a, &g, &cfg, &arena, &err), HZ_OK);
            const float sah0 = a->info.sah_cost;
            assert_true(a->info.sah_built == sah0);
            /* same keys: refit reproduces the build's boxes exactly */
            assert_int_equal(hz_accel_refit(a, &err), HZ_OK);
            assert_int_equal(a->info.refits, 1);
            assert_true(a->info.sah_cost == sah0);
            assert_int_equal(a->info.rebuilds, 0);
            for (uint32_t k = 0; k < 3; k++)
                memcpy((void *)(uintptr_t)g.pos_keys[k], big.pos_keys[k], 4u * sizeof(float) * m.vertex_count);
            assert_int_equal(hz_accel_refit(a, &err), HZ_OK);
            assert_int_equal(a->info.refits, 2);
            print_message("%s%s: sah built %.2f, after refit %.2f, rebuilds %u\n", hz_accel_blur_name(cfg.blur),
                          lazy ? " (lazy)" : "", (double)sah0, (double)a->info.sah_cost, a->info.rebuilds);
            assert_int_equal(a->info.rebuilds, lazy ? 0u : 1u);
            if (!lazy)
                assert_true(a->info.sah_built == a->info.sah_cost);
            make_rays(&g, 77u + (uint32_t)b);
            fx_trace1(a, HZ_ACCEL_KERNEL_SCALAR, rays_in, rays_ref, N_RAYS, NULL);
            check_brute(&g, "after refit");
            fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, rays_in, rays_out, N_RAYS, NULL);
            assert_int_equal(count_diff("after refit auto"), 0);
            hz_arena_reset(&arena, m0);
        }
}

static void test_bad_motion(void **state)
{
    (void)state;
    static float k0[16] HZ_ALIGNED(16);
    static const uint32_t tri[3] = { 0, 1, 2 };
    hz_accel_geom_t g;
    hz_accel_geom_init(&g);
    g.pos = k0, g.vertex_count = 3, g.tri = tri, g.tri_count = 1;
    g.time_keys = 4, g.pos_keys[0] = g.pos_keys[1] = g.pos_keys[2] = g.pos_keys[3] = k0;
    hz_accel_t *a;
    hz_error_t err;
    size_t used = arena.used;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_E_RANGE);
    assert_non_null(strstr(err.msg, "4 time keys"));
    g.time_keys = 3, g.pos_keys[2] = NULL;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "time key 2"));
    g.pos_keys[2] = k0 + 1;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "aligned"));
    assert_int_equal(arena.used, used);
    hz_accel_blur_t bl = HZ_ACCEL_BLUR_SWEPT;
    assert_false(hz_accel_blur_parse("fast", &bl));
    assert_int_equal(bl, HZ_ACCEL_BLUR_SWEPT);
    assert_true(hz_accel_blur_parse("interp", &bl));
    assert_int_equal(bl, HZ_ACCEL_BLUR_INTERP);
    assert_string_equal(hz_accel_blur_name(HZ_ACCEL_BLUR_MSBVH), "msbvh");
    hz_accel_segments_t sg = HZ_ACCEL_SEGMENTS_EVERY_KEY;
    assert_false(hz_accel_segments_parse("per-nod", &sg));
    assert_false(hz_accel_segments_parse(NULL, &sg));
    assert_int_equal(sg, HZ_ACCEL_SEGMENTS_EVERY_KEY);
    assert_true(hz_accel_segments_parse("per-node", &sg));
    assert_int_equal(sg, HZ_ACCEL_SEGMENTS_PER_NODE);
    assert_string_equal(hz_accel_segments_name(HZ_ACCEL_SEGMENTS_EVERY_KEY), "every-key");
    assert_string_equal(hz_accel_segments_name((hz_accel_segments_t)7), "unknown");
}

/* Empty geometry with keys builds and misses; a triangle with a non-finite coordinate at one key never hits
 * (at any time, also where its other keys are finite), as brute force says, in every BVH. */
static void test_motion_edge_geometry(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    static float k0[16] HZ_ALIGNED(16) = { -1, -1, 0, 0, 1, -1, 0, 0, 0, 1, 0, 0, 5, 5, 5, 0 };
    static float k1[16] HZ_ALIGNED(16) = { -1, -1, 1, 0, 1, -1, 1, 0, 0, 1, 1, 0, 5, 5, 5, 0 };
    k1[13] = NAN; /* vertex 3 at key 1 */
    static const uint32_t tri[6] = { 0, 1, 2, 0, 1, 3 };
    for (int b = 0; b < HZ_ACCEL_BLUR_COUNT; b++) {
        hz_accel_config_t cfg;
        hz_accel_config_default(&cfg);
        cfg.blur = (hz_accel_blur_t)b;
        hz_accel_geom_t g;
        hz_accel_geom_init(&g);
        g.time_keys = 2, g.pos_keys[0] = g.pos_keys[1] = k0, g.pos = k0; /* no vertices, no triangles */
        hz_accel_t *a;
        hz_error_t err;
        assert_int_equal(hz_accel_build_native(&a, &g, &cfg, &arena, &err), HZ_OK);
        hz_rayhit_t rh;
        const float o[3] = { 0.2f, -0.3f, 5.0f }, d[3] = { 0.0f, 0.0f, -1.0f };
        fx_set_ray(&rh, o, d, 0.0f, INFINITY, 1);
        rh.ray.time = 0.5f;
        hz_accel_intersect1(a, NULL, &rh);
        assert_int_equal(rh.hit.geom_id, HZ_ACCEL_INVALID_ID);
        g.pos = k0, g.vertex_count = 4, g.tri = tri, g.tri_count = 2, g.pos_keys[1] = k1;
        assert_int_equal(hz_accel_build_native(&a, &g, &cfg, &arena, &err), HZ_OK);
        for (int i = 0; i <= 8; i++) {
            hz_rayhit_t r1, r2;
            fx_set_ray(&r1, o, d, 0.0f, INFINITY, 1);
            r1.ray.time = (float)i / 8.0f;
            r2 = r1;
            hz_accel_intersect1(a, NULL, &r1);
            hz_accel_brute_intersect1(&g, &r2);
            assert_true(fx_same(&r1, &r2));
            assert_int_equal(r1.hit.prim_id, 0); /* triangle 1 (through the NaN vertex) never */
            assert_float_equal(r1.ray.tfar, 5.0f - (float)i / 8.0f, 1e-6f);
        }
    }
    hz_arena_reset(&arena, m0);
}

/* hz_accel_time_segment: exact segments and weights, clamping, NaN. */
static void test_time_segment(void **state)
{
    (void)state;
    uint32_t s;
    float f;
    hz_accel_time_segment(0.3f, 2, &s, &f);
    assert_int_equal(s, 0), assert_true(f == 0.3f);
    hz_accel_time_segment(1.0f, 9, &s, &f);
    assert_int_equal(s, 7), assert_true(f == 1.0f);
    hz_accel_time_segment(0.5f, 5, &s, &f);
    assert_int_equal(s, 2), assert_true(f == 0.0f);
    hz_accel_time_segment(0.6f, 3, &s, &f);
    assert_int_equal(s, 1), assert_true(f == 0.6f * 2.0f - 1.0f);
    hz_accel_time_segment(-1.0f, 3, &s, &f);
    assert_int_equal(s, 0), assert_true(f == 0.0f);
    hz_accel_time_segment(NAN, 3, &s, &f);
    assert_int_equal(s, 0), assert_true(f == 0.0f);
    hz_accel_time_segment(INFINITY, 3, &s, &f);
    assert_int_equal(s, 1), assert_true(f == 1.0f);
    assert_true(hz_accel_lerp_key(3.0f, 7.0f, 0.0f) == 3.0f && hz_accel_lerp_key(3.0f, 7.0f, 1.0f) == 7.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_time_segment),     cmocka_unit_test(test_analytic),
        cmocka_unit_test(test_static_ignores_time), cmocka_unit_test(test_bad_motion),
        cmocka_unit_test(test_motion_edge_geometry),
        cmocka_unit_test(test_msbvh_splits),     cmocka_unit_test(test_msbvh_refit_reclip),
        cmocka_unit_test(test_msbvh_budget),
        cmocka_unit_test(test_refit_rebuild),
        cmocka_unit_test(test_motion_cases),
        cmocka_unit_test(test_segments_per_node),
    };
    return HZ_RUN_GROUP(tests, setup, NULL);
}
