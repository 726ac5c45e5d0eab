/*
 * Native BVH build: memory bounds hold and refusals are clean, the structure is sound (every triangle reachable,
 * every point of every triangle inside a leaf box that holds it, nested boxes, depth-first order, leaves inside
 * blocks), builds are deterministic, bad geometry is refused with the triangle named, degenerate inputs
 * (coincident triangles, non-finite vertices, nothing at all) build, and refit after moving vertices gives the
 * same hits as a fresh build.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "accel_fixture.h"

#define MEM_BYTES (128u << 20)
static uint8_t mem[MEM_BYTES] HZ_ALIGNED(64);
static hz_arena_t arena;

static int setup(void **state)
{
    (void)state;
    hz_arena_init(&arena, "accel", mem, sizeof mem);
    return 0;
}

static const hz_bvh_t *bvh_of(const hz_accel_t *a)
{
    return a->impl;
}

typedef struct box3 {
    float lo[3], hi[3];
} box3_t;

static box3_t child_box(const hz_bvh_node_t *n, int i)
{
    box3_t b = { { n->lo_x[i], n->lo_y[i], n->lo_z[i] }, { n->hi_x[i], n->hi_y[i], n->hi_z[i] } };
    return b;
}

static bool contains_pt(const box3_t *b, const float p[3])
{
    for (int k = 0; k < 3; k++)
        if (!(p[k] >= b->lo[k] && p[k] <= b->hi[k]))
            return false;
    return true;
}

/* Sample points computed from barycentrics carry rounding error of a few ulps of the vertex coordinates. */
static bool contains_pt_approx(const box3_t *b, const float p[3], float mag)
{
    for (int k = 0; k < 3; k++) {
        float e = 8.0f * FLT_EPSILON * mag;
        if (!(p[k] + e >= b->lo[k] && p[k] - e <= b->hi[k]))
            return false;
    }
    return true;
}

static bool contains_box(const box3_t *outer, const box3_t *inner)
{
    for (int k = 0; k < 3; k++)
        if (inner->lo[k] <= inner->hi[k] && !(inner->lo[k] >= outer->lo[k] && inner->hi[k] <= outer->hi[k]))
            return false;
    return true;
}

/* Structure checks; returns the number of leaf references. */
static uint32_t check_structure(const hz_accel_t *a, const hz_accel_geom_t *g, bool exact_leaf_boxes)
{
    const hz_bvh_t *b = bvh_of(a);
    uint32_t refs = 0, leaves = 0;
    assert_true(b->node_count >= 1);
    for (uint32_t i = 0; i < b->node_count; i++) {
        const hz_bvh_node_t *n = &b->nodes[i];
        for (int c = 0; c < HZ_BVH_W; c++) {
            uint32_t w = n->child[c];
            box3_t cb = child_box(n, c);
            if (w == HZ_BVH_EMPTY) {
                assert_true(cb.lo[0] > cb.hi[0]);
                continue;
            }
            if (!hz_bvh_is_leaf(w)) {
                assert_true(w > i && w < b->node_count); /* depth-first pre-order */
                const hz_bvh_node_t *k = &b->nodes[w];
                for (int j = 0; j < HZ_BVH_W; j++) {
                    box3_t kb = child_box(k, j);
                    assert_true(contains_box(&cb, &kb));
                }
                continue;
            }
            leaves++;
            uint32_t slot = hz_bvh_leaf_slot(w), cnt = hz_bvh_leaf_count(w);
            assert_true(cnt >= 1 && cnt <= HZ_BVH_W);
            assert_true(slot / HZ_BVH_W < b->block_count);
            assert_true(slot % HZ_BVH_W + cnt <= HZ_BVH_W); /* one block */
            const hz_bvh_block_t *bl = &b->blocks[slot / HZ_BVH_W];
            for (uint32_t s = slot % HZ_BVH_W; s < slot % HZ_BVH_W + cnt; s++) {
                uint32_t prim = bl->prim[s] & HZ_BVH_PRIM_MASK;
                assert_true(prim < g->tri_count);
                bool flagged = g->tri_flags && (g->tri_flags[prim] & HZ_ACCEL_TRI_ANYHIT);
                assert_int_equal((bl->prim[s] & HZ_BVH_PRIM_ANYHIT) != 0, flagged);
                bool finite = true;
                for (int v = 0; v < 3; v++)
                    for (int k = 0; k < 3; k++)
                        finite = finite && isfinite(g->pos[4u * g->tri[3u * prim + (uint32_t)v] + (uint32_t)k]);
                for (int v = 0; v < 3; v++) /* a triangle moved to a non-finite place is stored as a point */
                    for (int k = 0; k < 3; k++)
                        assert_true(bl->v[v][k][s] ==
                                    (finite ? g->pos[4u * g->tri[3u * prim + (uint32_t)v] + (uint32_t)k] : 0.0f));
                bool point = true; /* all vertices equal: never hit, refit leaves it out of boxes */
                for (int k = 0; k < 3; k++)
                    point = point && bl->v[0][k][s] == bl->v[1][k][s] && bl->v[0][k][s] == bl->v[2][k][s];
                if (exact_leaf_boxes && !point) /* no spatial splits: the leaf box holds the whole triangle */
                    for (int v = 0; v < 3; v++) {
                        float p[3] = { bl->v[v][0][s], bl->v[v][1][s], bl->v[v][2][s] };
                        assert_true(contains_pt(&cb, p));
                    }
                refs++;
            }
        }
    }
    assert_int_equal(leaves, a->info.leaf_count);
    assert_int_equal(refs, a->info.ref_count);
    assert_true(a->info.depth <= HZ_BVH_MAX_DEPTH);
    return refs;
}

/* Every triangle is covered by the leaf boxes that hold it: points sampled over the triangle (vertices, edges,
 * inside) each lie in at least one such box. This is what spatial splits must preserve when they clip. */
static void check_coverage(const hz_accel_t *a, const hz_accel_geom_t *g, uint32_t stride)
{
    const hz_bvh_t *b = bvh_of(a);
    /* leaf boxes per triangle: gather (prim, box) pairs, then check by triangle */
    uint32_t n = a->info.ref_count;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    uint32_t *prim = hz_arena_alloc_array(&arena, n, sizeof(uint32_t), 16);
    box3_t *box = hz_arena_alloc_array(&arena, n, sizeof(box3_t), 16);
    uint32_t *first = hz_arena_calloc(&arena, g->tri_count + 1u, sizeof(uint32_t), 16);
    uint32_t *order = hz_arena_alloc_array(&arena, n, sizeof(uint32_t), 16);
    assert_non_null(prim), assert_non_null(box), assert_non_null(first), assert_non_null(order);
    uint32_t r = 0;
    for (uint32_t i = 0; i < b->node_count; i++)
        for (int c = 0; c < HZ_BVH_W; c++) {
            uint32_t w = b->nodes[i].child[c];
            if (w == HZ_BVH_EMPTY || !hz_bvh_is_leaf(w))
                continue;
            uint32_t slot = hz_bvh_leaf_slot(w);
            for (uint32_t s = 0; s < hz_bvh_leaf_count(w); s++) {
                prim[r] = b->blocks[(slot + s) / HZ_BVH_W].prim[(slot + s) % HZ_BVH_W] & HZ_BVH_PRIM_MASK;
                box[r] = child_box(&b->nodes[i], c);
                first[prim[r] + 1]++;
                r++;
            }
        }
    assert_int_equal(r, n);
    for (uint32_t t = 0; t < g->tri_count; t++)
        first[t + 1] += first[t];
    uint32_t *fill = hz_arena_alloc_array(&arena, g->tri_count, sizeof(uint32_t), 16);
    assert_non_null(fill);
    memcpy(fill, first, g->tri_count * sizeof(uint32_t));
    for (uint32_t i = 0; i < n; i++)
        order[fill[prim[i]]++] = i;
    uint32_t missing = 0, tested = 0;
    for (uint32_t t = 0; t < g->tri_count; t += stride) {
        const float *v[3];
        bool finite = true;
        float mag = 0.0f;
        for (int k = 0; k < 3; k++) {
            v[k] = g->pos + 4u * g->tri[3u * t + (uint32_t)k];
            finite = finite && isfinite(v[k][0]) && isfinite(v[k][1]) && isfinite(v[k][2]);
            mag = fmaxf(mag, fmaxf(fabsf(v[k][0]), fmaxf(fabsf(v[k][1]), fabsf(v[k][2]))));
        }
        if (!finite) {
            assert_int_equal(first[t + 1] - first[t], 0); /* skipped, never referenced */
            continue;
        }
        bool point = true; /* never hit; refit keeps such triangles out of the boxes */
        for (int k = 0; k < 3; k++)
            point = point && v[0][k] == v[1][k] && v[0][k] == v[2][k];
        if (point && first[t + 1] > first[t])
            continue;
        assert_true(first[t + 1] > first[t]); /* every finite triangle is referenced */
        const int steps = 6;
        for (int i = 0; i <= steps; i++)
            for (int j = 0; i + j <= steps; j++) {
                float u = (float)i / steps, w = (float)j / steps, p[3];
                for (int k = 0; k < 3; k++)
                    p[k] = (1.0f - u - w) * v[0][k] + u * v[1][k] + w * v[2][k];
                if (i == 0 && j == 0)
                    memcpy(p, v[0], sizeof p);
                if (i == steps)
                    memcpy(p, v[1], sizeof p);
                if (j == steps)
                    memcpy(p, v[2], sizeof p);
                bool in = false;
                bool exact = (i == 0 && j == 0) || i == steps || j == steps; /* a vertex */
                for (uint32_t q = first[t]; q < first[t + 1] && !in; q++)
                    in = exact ? contains_pt(&box[order[q]], p) : contains_pt_approx(&box[order[q]], p, mag);
                if (!in && missing < 3) {
                    print_message("tri %u (%u refs) point (%.9g %.9g %.9g) i %d j %d outside:", t, first[t + 1] - first[t],
                                  (double)p[0], (double)p[1], (double)p[2], i, j);
                    for (uint32_t q = first[t]; q < first[t + 1]; q++)
                        print_message(" [%.9g %.9g %.9g | %.9g %.9g %.9g]", (double)box[order[q]].lo[0],
                                      (double)box[order[q]].lo[1], (double)box[order[q]].lo[2],
                                      (double)box[order[q]].hi[0], (double)box[order[q]].hi[1],
                                      (double)box[order[q]].hi[2]);
                    print_message("\n");
                }
                missing += !in;
                tested++;
            }
    }
    assert_true(tested > 0);
    assert_int_equal(missing, 0);
    hz_arena_reset(&arena, m0);
}

typedef enum { G_SPHERE, G_CUBE, G_SOUP, G_BIGTRIS, G_SLIVERS, G_COUNT } gen_t;

/* Long thin triangles along the cube's diagonals: their boxes are huge and overlap everywhere, the case spatial
 * splits exist for. */
static hz_status_t slivers(hz_mesh_t *m, uint32_t count, hz_error_t *err)
{
    hz_status_t s = hz_meshgen_soup(m, &arena, count, 1.0f, 0.1f, 12, err);
    if (s != HZ_OK)
        return s;
    hz_rng_t r;
    hz_rng_seed(&r, 5, 5);
    for (uint32_t t = 0; t < count; t++) {
        float *a = m->pos + 12u * t, d[3];
        uint32_t diag = hz_rng_below(&r, 4);
        d[0] = 1.0f, d[1] = (diag & 1) ? 1.0f : -1.0f, d[2] = (diag & 2) ? 1.0f : -1.0f;
        for (int k = 0; k < 3; k++) {
            a[4 + k] = a[k] + 1.2f * d[k];        /* far end */
            a[8 + k] = a[k] + 0.01f * (k == 1);   /* thin */
        }
    }
    return HZ_OK;
}

static void gen(gen_t k, hz_mesh_t *m)
{
    hz_error_t err;
    hz_status_t s = HZ_OK;
    switch (k) {
    case G_SPHERE: s = hz_meshgen_sphere(m, &arena, 40, 80, 1.0f, &err); break;
    case G_CUBE: s = hz_meshgen_cube_sphere(m, &arena, 16, 2.0f, false, &err); break;
    case G_SOUP:
        s = hz_meshgen_soup(m, &arena, 5000, 1.0f, 0.2f, 3, &err);
        if (s == HZ_OK)
            s = hz_meshgen_append_degenerates(m, &arena, 200, 8, &err);
        break;
    case G_BIGTRIS: s = hz_meshgen_soup(m, &arena, 2000, 1.0f, 2.5f, 4, &err); break; /* large, overlapping */
    case G_SLIVERS: s = slivers(m, 3000, &err); break;
    default: break;
    }
    assert_int_equal(s, HZ_OK);
}

static void test_bounds_structure_coverage(void **state)
{
    (void)state;
    for (int k = 0; k < G_COUNT; k++)
        for (int spatial = 0; spatial < 2; spatial++)
            for (uint32_t leaf = 1; leaf <= HZ_BVH_W; leaf *= 2) {
                hz_arena_mark_t m0 = hz_arena_mark(&arena);
                hz_mesh_t m;
                gen((gen_t)k, &m);
                hz_accel_geom_t g = hz_meshgen_geom(&m);
                hz_accel_config_t cfg;
                hz_accel_config_default(&cfg);
                cfg.spatial_splits = spatial;
                cfg.leaf_max = leaf;
                hz_accel_bytes_t bound = hz_accel_bytes_bound(g.tri_count, &cfg);
                hz_arena_mark_t before = hz_arena_mark(&arena);
                hz_accel_t *a;
                hz_error_t err;
                assert_int_equal(hz_accel_build_native(&a, &g, &cfg, &arena, &err), HZ_OK);
                size_t used = hz_arena_mark(&arena) - before;
                assert_true(used <= bound.kept);
                assert_true(a->info.bytes <= bound.kept);
                assert_true(a->info.bytes_peak <= bound.peak);
                if (leaf == HZ_BVH_W && spatial)
                    print_message("gen %d: %u tris, %u refs (%u spatial splits), %zu bytes (bound %zu), peak %zu "
                                  "(bound %zu), SAH %.2f\n",
                                  k, g.tri_count, a->info.ref_count, a->info.spatial_splits, used, bound.kept,
                                  a->info.bytes_peak, bound.peak, (double)a->info.sah_cost);
                uint32_t refs = check_structure(a, &g, !spatial);
                assert_true(refs >= g.tri_count - a->info.tri_skipped);
                if (!spatial)
                    assert_int_equal(refs, g.tri_count - a->info.tri_skipped);
                else
                    assert_true(refs <= g.tri_count + (uint32_t)(g.tri_count * cfg.split_budget));
                check_coverage(a, &g, 1);
                hz_arena_reset(&arena, m0);
            }
}

/* Spatial splits do happen where triangles are long, and do not raise the SAH cost (what they gain on real
 * architecture is asserted on Sponza in test_accel_scenes). */
static void test_spatial_splits_help(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    gen(G_SLIVERS, &m);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_config_t cfg;
    hz_accel_config_default(&cfg);
    hz_accel_t *with, *without;
    hz_error_t err;
    cfg.split_budget = 1.0f;
    assert_int_equal(hz_accel_build_native(&with, &g, &cfg, &arena, &err), HZ_OK);
    cfg.spatial_splits = false;
    assert_int_equal(hz_accel_build_native(&without, &g, &cfg, &arena, &err), HZ_OK);
    print_message("slivers: SAH %.2f with spatial splits (%u, %u refs), %.2f without\n",
                  (double)with->info.sah_cost, with->info.spatial_splits, with->info.ref_count,
                  (double)without->info.sah_cost);
    assert_true(with->info.spatial_splits > 0);
    assert_true(with->info.ref_count > g.tri_count);
    assert_true(with->info.sah_cost <= without->info.sah_cost);
    hz_arena_reset(&arena, m0);
}

static void test_deterministic(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    gen(G_SOUP, &m);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    hz_accel_t *a, *b;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    assert_int_equal(hz_accel_build_native(&b, &g, NULL, &arena, &err), HZ_OK);
    const hz_bvh_t *x = bvh_of(a), *y = bvh_of(b);
    assert_int_equal(x->node_count, y->node_count);
    assert_int_equal(x->block_count, y->block_count);
    assert_memory_equal(x->nodes, y->nodes, x->node_count * sizeof(hz_bvh_node_t));
    assert_memory_equal(x->blocks, y->blocks, x->block_count * sizeof(hz_bvh_block_t));
    hz_arena_reset(&arena, m0);
}

static void test_out_of_memory(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_mesh_t m;
    gen(G_SPHERE, &m);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    static uint8_t small[4u << 20] HZ_ALIGNED(64);
    hz_accel_bytes_t bound = hz_accel_bytes_bound(g.tri_count, NULL);
    /* a successful build first, to learn the true peak */
    hz_arena_t sa;
    hz_arena_init(&sa, "accel", small, sizeof small);
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &sa, &err), HZ_OK);
    size_t peak = sa.high_water;
    assert_true(peak <= bound.peak);
    /* every smaller arena refuses cleanly: error names both counts, arena left as it was */
    const size_t sizes[] = { 0, 64, 4096, peak / 4, peak / 2, peak - 4096, peak - 1 };
    for (size_t i = 0; i < HZ_ARRAY_LEN(sizes); i++) {
        hz_arena_init(&sa, "accel", small, sizes[i]);
        assert_int_equal(hz_accel_build_native(&a, &g, NULL, &sa, &err), HZ_E_NO_MEMORY);
        assert_int_equal(err.code, HZ_E_NO_MEMORY);
        assert_non_null(strstr(err.msg, "accel"));
        assert_non_null(strstr(err.msg, "needs"));
        assert_int_equal(sa.used, 0);
    }
    hz_arena_init(&sa, "accel", small, peak);
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &sa, &err), HZ_OK);
    /* the plan check refuses up front with both counts */
    hz_arena_init(&sa, "accel", small, bound.peak - 1 < sizeof small ? bound.peak - 1 : sizeof small);
    assert_int_equal(hz_accel_plan_check(g.tri_count, NULL, &sa, &err), HZ_E_NO_MEMORY);
    assert_non_null(strstr(err.msg, "triangles need up to"));
    print_message("plan: %s\n", err.msg);
    hz_arena_init(&sa, "accel", small, sizeof small);
    if (bound.peak <= sizeof small)
        assert_int_equal(hz_accel_plan_check(g.tri_count, NULL, &sa, &err), HZ_OK);
    hz_arena_reset(&arena, m0);
}

static void test_bad_geometry(void **state)
{
    (void)state;
    static float pos[4 * 4] HZ_ALIGNED(16) = { 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0 };
    uint32_t tri[6] = { 0, 1, 2, 0, 2, 4 };
    hz_accel_geom_t g = { pos, 4, tri, 2, NULL, 0, { NULL }, 0, NULL, false };
    hz_accel_t *a = (hz_accel_t *)&g;
    hz_error_t err;
    size_t used = arena.used;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_E_RANGE);
    assert_null(a);
    assert_non_null(strstr(err.msg, "triangle 1"));
    assert_non_null(strstr(err.msg, "vertex index 4"));
    assert_int_equal(arena.used, used);
    hz_accel_geom_t g2 = { pos + 1, 3, tri, 1, NULL, 0, { NULL }, 0, NULL, false }; /* misaligned */
    assert_int_equal(hz_accel_build_native(&a, &g2, NULL, &arena, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "aligned"));
    hz_accel_geom_t g3 = { pos, 4, NULL, 1, NULL, 0, { NULL }, 0, NULL, false };
    assert_int_equal(hz_accel_build_native(&a, &g3, NULL, &arena, &err), HZ_E_INVALID_ARG);
    hz_accel_geom_t g4 = { pos, 4, tri, HZ_ACCEL_MAX_TRIS + 1u, NULL, 0, { NULL }, 0, NULL, false };
    assert_int_equal(hz_accel_build_native(&a, &g4, NULL, &arena, &err), HZ_E_RANGE);
    assert_int_equal(hz_accel_build_native(&a, NULL, NULL, &arena, &err), HZ_E_INVALID_ARG);
    assert_int_equal(arena.used, used);
}

/* Empty geometry, coincident triangles (no split can separate them), non-finite vertices. */
static void test_degenerate_inputs(void **state)
{
    (void)state;
    hz_arena_mark_t m0 = hz_arena_mark(&arena);
    hz_error_t err;
    hz_accel_t *a;
    hz_accel_geom_t empty = { NULL, 0, NULL, 0, NULL, 0, { NULL }, 0, NULL, false };
    assert_int_equal(hz_accel_build_native(&a, &empty, NULL, &arena, &err), HZ_OK);
    hz_rayhit_t in, out;
    float o[3] = { 0, 0, -1 }, d[3] = { 0, 0, 1 };
    fx_set_ray(&in, o, d, 0, INFINITY, 0);
    fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, &in, &out, 1, NULL);
    assert_true(fx_same(&in, &out));

    /* 3000 copies of one triangle plus a few others */
    const uint32_t n = 3000;
    float *pos = hz_arena_alloc_array(&arena, 4u * (n + 3u), sizeof(float), 16);
    uint32_t *tri = hz_arena_alloc_array(&arena, 3u * (n + 1u), sizeof(uint32_t), 16);
    assert_non_null(pos), assert_non_null(tri);
    const float base[4 * 6] = { -1, -1, 0, 0, 1, -1, 0, 0, 0, 1, 0, 0, NAN, 0, 0, 0, 1, INFINITY, 0, 0, 0, 0, 1, 0 };
    memcpy(pos, base, sizeof base);
    for (uint32_t t = 0; t < n; t++)
        tri[3 * t] = 0, tri[3 * t + 1] = 1, tri[3 * t + 2] = 2;
    tri[3 * 7] = 3, tri[3 * 7 + 1] = 4, tri[3 * 7 + 2] = 5; /* non-finite */
    hz_accel_geom_t g = { pos, 6, tri, n, NULL, 0, { NULL }, 0, NULL, false };
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &arena, &err), HZ_OK);
    assert_int_equal(a->info.tri_skipped, 1);
    check_structure(a, &g, false);
    check_coverage(a, &g, 1);
    fx_trace1(a, HZ_ACCEL_KERNEL_AUTO, &in, &out, 1, NULL);
    assert_int_equal(out.hit.prim_id, 0); /* lowest index among equal hits */
    assert_true(out.ray.tfar == 1.0f);
    hz_arena_reset(&arena, m0);
}

/* Refit: move every vertex (a twist and a shift), refit, and compare with a fresh build of the moved mesh:
 * closest hits do not depend on the tree, so they must agree exactly. */
static void test_refit(void **state)
{
    (void)state;
    for (int spatial = 0; spatial < 2; spatial++) {
        hz_arena_mark_t m0 = hz_arena_mark(&arena);
        hz_mesh_t m;
        gen(G_SOUP, &m);
        hz_accel_geom_t g = hz_meshgen_geom(&m);
        hz_accel_config_t cfg;
        hz_accel_config_default(&cfg);
        cfg.spatial_splits = spatial;
        hz_accel_t *a, *fresh;
        hz_error_t err;
        assert_int_equal(hz_accel_build_native(&a, &g, &cfg, &arena, &err), HZ_OK);
        size_t used = arena.used;
        for (uint32_t i = 0; i < m.vertex_count; i++) {
            float *p = m.pos + 4u * i, s, c;
            hz_sincosf(0.8f * p[1], &s, &c);
            float x = p[0] * c - p[2] * s, z = p[0] * s + p[2] * c;
            p[0] = x + 0.3f, p[2] = z, p[1] *= 1.5f;
        }
        m.pos[4u * 12] = NAN; /* a vertex moved to nowhere: its triangles disappear */
        assert_int_equal(hz_accel_refit(a, &err), HZ_OK);
        assert_int_equal(arena.used, used); /* refit allocates nothing */
        check_structure(a, &g, false);
        m.pos[4u * 12] = 0.25f;
        assert_int_equal(hz_accel_refit(a, &err), HZ_OK);
        check_structure(a, &g, !spatial);
        check_coverage(a, &g, 1);
        assert_int_equal(hz_accel_build_native(&fresh, &g, &cfg, &arena, &err), HZ_OK);
        static hz_rayhit_t in[20000], o1[20000], o2[20000];
        fx_random_rays(in, 20000, fx_mesh_bounds(&m), 31);
        for (int k = HZ_ACCEL_KERNEL_SCALAR; k < HZ_ACCEL_KERNEL_COUNT; k++) {
            fx_trace1(a, (hz_accel_kernel_t)k, in, o1, 20000, NULL);
            fx_trace1(fresh, (hz_accel_kernel_t)k, in, o2, 20000, NULL);
            uint32_t diff = 0, hits = 0;
            for (uint32_t i = 0; i < 20000; i++) {
                diff += !fx_same(&o1[i], &o2[i]);
                hits += o1[i].hit.geom_id == 0;
            }
            assert_int_equal(diff, 0);
            assert_true(hits > 1000);
        }
        hz_arena_reset(&arena, m0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bounds_structure_coverage),
        cmocka_unit_test(test_spatial_splits_help),
        cmocka_unit_test(test_deterministic),
        cmocka_unit_test(test_out_of_memory),
        cmocka_unit_test(test_bad_geometry),
        cmocka_unit_test(test_degenerate_inputs),
        cmocka_unit_test(test_refit),
    };
    return HZ_RUN_GROUP(tests, setup, NULL);
}
