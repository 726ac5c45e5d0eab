/*
 * The BVH builder's four-lane boxes (src/accel/box4.h: SSE on AVX2 boards, NEON on NEON boards) against their
 * scalar twin: this file compiles the builder a second time with HZ_BOX4_SCALAR (plain C lanes, the scalar
 * order of operations) under other names, builds the same geometry with both and wants the same bytes: nodes,
 * triangle blocks and the build's figures (SAH cost, references, spatial splits). Geometry that exercises every
 * part: spatial splits (slivers, large overlapping triangles), flat and axis-aligned triangles (cube), -0 / +0
 * and degenerate triangles (soup), and a large soup binned in chunks on a run hook that runs items in reverse
 * order (the chunk merges).
 *
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "accel_fixture.h"

/* The second builder: the library's builder with scalar lanes, every external name renamed. */
#define HZ_BOX4_SCALAR 1
#define hz_bvh_build hz_bvh_build_twin
#define hz_bvh_refit hz_bvh_refit_twin
#define hz_bvh_fill_slot hz_bvh_fill_slot_twin
#define hz_accel_bytes_bound hz_accel_bytes_bound_twin
#define hz_accel_bytes_bound_geom hz_accel_bytes_bound_geom_twin
#define hz_bvh_blocks_bound hz_bvh_blocks_bound_twin
#define hz_bvh_nodes_bound hz_bvh_nodes_bound_twin
#define hz_bvh_scratch_bound hz_bvh_scratch_bound_twin
hz_status_t hz_bvh_build(hz_bvh_t *bvh, const hz_accel_geom_t *g, const hz_accel_config_t *cfg, hz_arena_t *arena,
                         hz_bvh_build_out_t *out, hz_error_t *err);
void hz_bvh_refit(hz_bvh_t *bvh, const hz_accel_geom_t *g);
bool hz_bvh_fill_slot(hz_bvh_block_t *bl, uint32_t s, const hz_accel_geom_t *g, const float *pos, uint32_t prim);
hz_accel_bytes_t hz_accel_bytes_bound(uint32_t tri_count, const hz_accel_config_t *cfg);
hz_accel_bytes_t hz_accel_bytes_bound_geom(const hz_accel_geom_t *g, const hz_accel_config_t *cfg);
uint64_t hz_bvh_blocks_bound(uint64_t refs);
uint64_t hz_bvh_nodes_bound(uint64_t refs);
uint64_t hz_bvh_scratch_bound(uint32_t tri_count, uint64_t refs);
#include "../../src/accel/bvh_build.c"
#undef hz_bvh_build
#undef hz_bvh_refit
#undef hz_bvh_fill_slot
#undef hz_accel_bytes_bound
#undef hz_accel_bytes_bound_geom
#undef hz_bvh_blocks_bound
#undef hz_bvh_nodes_bound
#undef hz_bvh_scratch_bound

#define MEM_BYTES (192u << 20)
static uint8_t mem[MEM_BYTES] HZ_ALIGNED(64);
static hz_arena_t arena;

static int setup(void **state)
{
    (void)state;
    hz_arena_init(&arena, "accel", mem, sizeof mem);
    return 0;
}

/* Any order is allowed (accel.h): reverse, so the chunked merges cannot lean on the order items ran in. */
static void run_reverse(void *user, void (*fn)(void *ctx, uint32_t item), void *ctx, uint32_t items)
{
    (void)user;
    for (uint32_t i = items; i-- > 0;)
        fn(ctx, i);
}

typedef enum { G_SOUP, G_CUBE, G_BIGTRIS, G_SLIVERS, G_BIGSOUP, G_COUNT } gen_t;

static void gen(gen_t k, hz_mesh_t *m)
{
    hz_error_t err;
    hz_status_t s = HZ_OK;
    switch (k) {
    case G_SOUP:
        s = hz_meshgen_soup(m, &arena, 5000, 1.0f, 0.2f, 3, &err);
        if (s == HZ_OK)
            s = hz_meshgen_append_degenerates(m, &arena, 200, 8, &err);
        break;
    case G_CUBE: s = hz_meshgen_cube_sphere(m, &arena, 16, 2.0f, false, &err); break;
    case G_BIGTRIS: s = hz_meshgen_soup(m, &arena, 2000, 1.0f, 2.5f, 4, &err); break;
    case G_SLIVERS:
        /* long thin triangles along the diagonals (as test_accel_build's), straddling every plane */
        s = hz_meshgen_soup(m, &arena, 3000, 1.0f, 0.1f, 12, &err);
        if (s == HZ_OK) {
            hz_rng_t r;
            hz_rng_seed(&r, 5, 5);
            for (uint32_t t = 0; t < 3000; t++) {
                float *a = m->pos + 12u * t;
                uint32_t diag = hz_rng_below(&r, 4);
                const float d[3] = { 1.0f, (diag & 1) ? 1.0f : -1.0f, (diag & 2) ? 1.0f : -1.0f };
                for (int c = 0; c < 3; c++) {
                    a[4 + c] = a[c] + 1.2f * d[c];
                    a[8 + c] = a[c] + 0.01f * (c == 1);
                }
            }
        }
        break;
    case G_BIGSOUP: s = hz_meshgen_soup(m, &arena, 60000, 1.0f, 0.05f, 9, &err); break;
    default: break;
    }
    assert_int_equal(s, HZ_OK);
}

static void test_same_tree(void **state)
{
    (void)state;
    for (int k = 0; k < G_COUNT; k++)
        for (int par = 0; par < 2; par++) {
            hz_arena_mark_t m0 = hz_arena_mark(&arena);
            hz_mesh_t m;
            gen((gen_t)k, &m);
            hz_accel_geom_t g = hz_meshgen_geom(&m);
            hz_accel_config_t cfg;
            hz_accel_config_default(&cfg);
            if (par) {
                cfg.run = run_reverse;
                cfg.run_threads = 4;
            }
            hz_bvh_t a, b;
            hz_bvh_build_out_t ao, bo;
            hz_error_t err;
            assert_int_equal(hz_bvh_build(&a, &g, &cfg, &arena, &ao, &err), HZ_OK);
            assert_int_equal(hz_bvh_build_twin(&b, &g, &cfg, &arena, &bo, &err), HZ_OK);
            print_message("gen %d%s: %u refs (%u spatial splits), SAH %.9g / %.9g\n", k, par ? " (chunked)" : "",
                          ao.ref_count, ao.spatial_splits, (double)ao.sah_cost, (double)bo.sah_cost);
            assert_int_equal(ao.ref_count, bo.ref_count);
            assert_int_equal(ao.spatial_splits, bo.spatial_splits);
            assert_memory_equal(&ao.sah_cost, &bo.sah_cost, sizeof ao.sah_cost);
            assert_int_equal(a.node_count, b.node_count);
            assert_int_equal(a.block_count, b.block_count);
            assert_int_equal(a.leaf_count, b.leaf_count);
            assert_int_equal(a.depth, b.depth);
            assert_memory_equal(a.nodes, b.nodes, a.node_count * sizeof(hz_bvh_node_t));
            assert_memory_equal(a.blocks, b.blocks, a.block_count * sizeof(hz_bvh_block_t));
            hz_arena_reset(&arena, m0);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_same_tree, setup),
    };
    return HZ_RUN(tests);
}
