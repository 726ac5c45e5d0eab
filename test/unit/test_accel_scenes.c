/*
 * The native accel on the baked shared scenes ($HZ_SCENES_DIR, see accel_scenes.h):
 *  - every kernel (scalar reference, SIMD single ray, packets and tiles of 8 to 32 packets, both packet widths)
 *    returns bit-identical hits and occlusion on camera rays plus random rays of the dragon (res4), the Cornell
 *    box and Dabrovic Sponza;
 *  - watertightness on the dragon (res4): rays aimed exactly at its vertices and at points of its shared edges
 *    cross the surface there; not one may pass through (10^6 rays on the host, 4x10^4 under qemu). Only edges
 *    with exactly two triangles (and vertices whose edges all are) are aimed at, and only rays crossing every
 *    face there at more than ~12 degrees: a ray grazing the surface may rightly miss it.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "accel_fixture.h"
#include "accel_scenes.h"

/* Under qemu-user (NEON) every traversal is emulated: fewer rays through the same builds, kernels and forms (the
 * host traces 25x as many). */
#if defined(HZ_SIMD_NEON)
#define N_CAM 4000u
#define N_RAYS 8000u
#define N_WATER 40000u
#else
#define N_CAM 100000u
#define N_RAYS 200000u
#define N_WATER 1000000u
#endif

static hz_rayhit_t in[N_RAYS], ref[N_RAYS], out[N_RAYS];
static uint8_t occ_ref[N_RAYS], occ_out[N_RAYS];

/* Every kernel and form against the scalar reference on `name`'s native build (default config); *info (when not
 * NULL) gets the build's figures and *geom the view, for further builds of the same scene. */
static void check_scene_build(const char *name, hz_accel_info_t *info, hz_accel_geom_t *geom)
{
    hz_scene_t sc;
    hz_accel_geom_t g;
    if (!fx_scene_load(name, &sc, &g))
        skip();
    hz_pools_t *p = hz_pools_get();
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &p->accel, &err), HZ_OK);
    if (info)
        *info = a->info;
    if (geom)
        *geom = g;
    fx_scene_rays(&sc, in, N_CAM, N_RAYS, 321);
    fx_trace1(a, HZ_ACCEL_KERNEL_SCALAR, in, ref, N_RAYS, NULL);
    uint32_t hits = 0;
    for (uint32_t i = 0; i < N_RAYS; i++)
        hits += ref[i].hit.geom_id == 0;
    const hz_accel_kernel_t ks[] = { HZ_ACCEL_KERNEL_SIMD_SINGLE, HZ_ACCEL_KERNEL_SIMD_PACKET,
                                     HZ_ACCEL_KERNEL_SIMD_MASKED, HZ_ACCEL_KERNEL_AUTO };
    uint32_t differ = 0;
    for (size_t q = 0; q < HZ_ARRAY_LEN(ks); q++)
        for (int form = 0; form < 3; form++) {
            if (form == 0)
                fx_trace1(a, ks[q], in, out, N_RAYS, NULL);
            else
                fx_trace_packets(a, ks[q], HZ_ACCEL_COHERENT, form == 1 ? HZ_BVH_W : (HZ_BVH_W == 8 ? 4 : 8), false,
                                 in, out, N_RAYS, NULL);
            for (uint32_t i = 0; i < N_RAYS; i++)
                if (!fx_same(&ref[i], &out[i]) && differ++ < 3)
                    print_message("%s %s form %d: ray %u: prim %u/%u t %.9g/%.9g\n", name, hz_accel_kernel_name(ks[q]),
                                  form, i, ref[i].hit.prim_id, out[i].hit.prim_id, (double)ref[i].ray.tfar,
                                  (double)out[i].ray.tfar);
        }
    /* tiles (large packets): 8 and 32 packets per call, both widths; the camera rays come in pixel rows */
    const int tiles[][2] = { { HZ_BVH_W, 8 }, { HZ_BVH_W, 32 }, { HZ_BVH_W == 8 ? 4 : 8, 16 } };
    for (size_t q = 0; q < HZ_ARRAY_LEN(tiles); q++) {
        fx_trace_tiles(a, HZ_ACCEL_KERNEL_AUTO, HZ_ACCEL_COHERENT, tiles[q][0], tiles[q][1], q == 0, in, out, NULL,
                       N_RAYS, NULL);
        for (uint32_t i = 0; i < N_RAYS; i++) {
            if (q == 0 && i % 7 == 6)
                differ += !fx_same(&in[i], &out[i]);
            else if (!fx_same(&ref[i], &out[i]) && differ++ < 3)
                print_message("%s tile %d x %d: ray %u: prim %u/%u t %.9g/%.9g\n", name, tiles[q][0], tiles[q][1], i,
                              ref[i].hit.prim_id, out[i].hit.prim_id, (double)ref[i].ray.tfar, (double)out[i].ray.tfar);
        }
    }
    for (uint32_t i = 0; i < N_RAYS; i++)
        occ_ref[i] = ref[i].hit.geom_id == 0;
    for (size_t q = 0; q < HZ_ARRAY_LEN(ks); q++)
        for (int w = 0; w <= HZ_BVH_W; w += HZ_BVH_W) {
            fx_occlusion(a, ks[q], HZ_ACCEL_COHERENT, w, in, occ_out, N_RAYS, NULL);
            for (uint32_t i = 0; i < N_RAYS; i++)
                differ += occ_out[i] != occ_ref[i];
        }
    for (size_t q = 0; q < HZ_ARRAY_LEN(tiles); q++) {
        fx_trace_tiles(a, HZ_ACCEL_KERNEL_AUTO, HZ_ACCEL_COHERENT, tiles[q][0], tiles[q][1], false, in, NULL, occ_out,
                       N_RAYS, NULL);
        for (uint32_t i = 0; i < N_RAYS; i++)
            differ += occ_out[i] != occ_ref[i];
    }
    print_message("%s: %u triangles, %u rays (%u hit), every kernel and packet form: %u differences\n", name,
                  g.tri_count, N_RAYS, hits, differ);
    assert_true(hits > N_RAYS / 10);
    assert_int_equal(differ, 0);
}

static void check_scene(const char *name)
{
    check_scene_build(name, NULL, NULL);
}

static void test_dragon_kernels(void **state)
{
    (void)state;
    check_scene("dragon-res4");
}

static void test_cornell_kernels(void **state)
{
    (void)state;
    check_scene("CornellBox-Original");
}

/* Every kernel on Sponza; and spatial splits pay off on architecture: its SAH cost drops by more than a tenth
 * against a build without them, within the budget (the kernels' build is the one with splits). */
static void test_sponza_kernels_and_spatial_splits(void **state)
{
    (void)state;
    hz_accel_info_t with;
    hz_accel_geom_t g;
    check_scene_build("sponza", &with, &g);
    hz_pools_t *p = hz_pools_get();
    hz_accel_config_t cfg;
    hz_accel_config_default(&cfg);
    cfg.spatial_splits = false;
    hz_accel_t *without;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&without, &g, &cfg, &p->accel, &err), HZ_OK);
    print_message("sponza: SAH %.2f with spatial splits (%u splits, %u refs for %u triangles), %.2f without\n",
                  (double)with.sah_cost, with.spatial_splits, with.ref_count, g.tri_count,
                  (double)without->info.sah_cost);
    hz_accel_config_default(&cfg);
    assert_true(with.spatial_splits > 0);
    assert_true(with.ref_count <= g.tri_count + (uint32_t)((float)g.tri_count * cfg.split_budget));
    assert_true(with.sah_cost < 0.9f * without->info.sah_cost);
}

/* ---- watertightness on the dragon ---- */
typedef struct edge {
    uint32_t a, b, t;
} edge_t;

static int edge_cmp(const void *x, const void *y)
{
    const edge_t *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    if (p->b != q->b)
        return p->b < q->b ? -1 : 1;
    return p->t < q->t ? -1 : p->t > q->t;
}

/* Whether direction d crosses every face in tris (normals nrm) at more than ~12 degrees, from the same side. */
static bool crosses(const double *nrm, const uint32_t *tris, uint32_t n, const double d[3])
{
    double dl = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    int sign = 0;
    for (uint32_t i = 0; i < n; i++) {
        const double *q = nrm + 3u * tris[i];
        double c = (q[0] * d[0] + q[1] * d[1] + q[2] * d[2]) / dl;
        if (fabs(c) < 0.2)
            return false;
        int s = c > 0 ? 1 : -1;
        if (sign && s != sign)
            return false;
        sign = s;
    }
    return true;
}

static void test_dragon_watertight(void **state)
{
    (void)state;
    hz_scene_t sc;
    hz_accel_geom_t g;
    if (!fx_scene_load("dragon-res4", &sc, &g))
        skip();
    hz_pools_t *p = hz_pools_get();
    hz_accel_t *a;
    hz_error_t err;
    assert_int_equal(hz_accel_build_native(&a, &g, NULL, &p->accel, &err), HZ_OK);
    const uint32_t nt = g.tri_count, nv = g.vertex_count;
    edge_t *e = malloc(3u * nt * sizeof *e);
    double *nrm = malloc(3u * nt * sizeof *nrm);
    uint8_t *vbad = calloc(nv, 1);
    uint32_t *vfirst = calloc(nv + 1u, sizeof(uint32_t)), *vtris = malloc(3u * nt * sizeof(uint32_t));
    uint32_t *man = malloc(3u * nt * sizeof(uint32_t)); /* index into e of the first of a manifold pair */
    assert_non_null(e), assert_non_null(nrm), assert_non_null(vbad), assert_non_null(vfirst);
    assert_non_null(vtris), assert_non_null(man);
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *v = g.tri + 3u * t;
        double p0[3], e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            p0[k] = g.pos[4u * v[0] + (uint32_t)k];
            e1[k] = g.pos[4u * v[1] + (uint32_t)k] - p0[k];
            e2[k] = g.pos[4u * v[2] + (uint32_t)k] - p0[k];
        }
        double n[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0] };
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; k++)
            nrm[3u * t + (uint32_t)k] = l > 0 ? n[k] / l : 0.0;
        for (uint32_t k = 0; k < 3; k++) {
            uint32_t x = v[k], y = v[(k + 1) % 3];
            e[3u * t + k].a = x < y ? x : y, e[3u * t + k].b = x < y ? y : x, e[3u * t + k].t = t;
            vfirst[v[k] + 1]++;
            if (l == 0)
                vbad[v[k]] = 1; /* degenerate faces: no direction crosses them */
        }
    }
    for (uint32_t i = 0; i < nv; i++)
        vfirst[i + 1] += vfirst[i];
    uint32_t *fill = malloc(nv * sizeof(uint32_t));
    assert_non_null(fill);
    memcpy(fill, vfirst, nv * sizeof(uint32_t));
    for (uint32_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            vtris[fill[g.tri[3u * t + (uint32_t)k]]++] = t;
    qsort(e, 3u * nt, sizeof *e, edge_cmp);
    uint32_t nman = 0;
    for (uint32_t i = 0; i < 3u * nt;) {
        uint32_t j = i;
        while (j < 3u * nt && e[j].a == e[i].a && e[j].b == e[i].b)
            j++;
        if (j - i == 2)
            man[nman++] = i;
        else
            vbad[e[i].a] = vbad[e[i].b] = 1; /* non-manifold edge: its vertices are not aimed at */
        i = j;
    }
    uint32_t ngood = 0;
    for (uint32_t v = 0; v < nv; v++)
        ngood += !vbad[v] && vfirst[v + 1] - vfirst[v] >= 3;
    assert_true(nman > nt && ngood > nv / 2);

    float c[3], r = 0.0f;
    for (int k = 0; k < 3; k++) {
        c[k] = 0.5f * (sc.header->bounds_min[k] + sc.header->bounds_max[k]);
        r = fmaxf(r, sc.header->bounds_max[k] - sc.header->bounds_min[k]);
    }
    hz_rng_t rng;
    hz_rng_seed(&rng, 99, 9);
    uint32_t leaks = 0;
    const uint32_t batch = N_RAYS;
    for (uint32_t done = 0, bi = 0; done < N_WATER; done += batch, bi++) {
        uint32_t cnt = N_WATER - done < batch ? N_WATER - done : batch;
        for (uint32_t i = 0; i < cnt; i++) {
            float o[3], pt[3], d[3];
            { /* origins around the dragon, some inside its bounds */
                float z = 2.0f * fx_unit(&rng) - 1.0f, ph = 2.0f * HZ_PI * fx_unit(&rng), sp, cp;
                float sr = hz_sqrtf(1.0f - z * z), rad = (0.2f + 1.3f * fx_unit(&rng)) * r;
                hz_sincosf(ph, &sp, &cp);
                o[0] = c[0] + rad * sr * cp, o[1] = c[1] + rad * sr * sp, o[2] = c[2] + rad * z;
            }
            for (;;) {
                uint32_t tris[64], nf;
                if (hz_rng_u32(&rng) & 1) { /* a vertex, exactly */
                    uint32_t v = hz_rng_below(&rng, nv);
                    /* unreferenced vertices exist; a closed fan has at least 3 faces */
                    if (vbad[v] || vfirst[v + 1] - vfirst[v] < 3 || vfirst[v + 1] - vfirst[v] > 64)
                        continue;
                    memcpy(pt, g.pos + 4u * v, sizeof pt);
                    nf = vfirst[v + 1] - vfirst[v];
                    memcpy(tris, vtris + vfirst[v], nf * sizeof(uint32_t));
                } else { /* a point on a shared edge, as close as floats get */
                    const edge_t *x = &e[man[hz_rng_below(&rng, nman)]];
                    float s = fx_unit(&rng);
                    for (int k = 0; k < 3; k++)
                        pt[k] = g.pos[4u * x->a + (uint32_t)k] +
                                (g.pos[4u * x->b + (uint32_t)k] - g.pos[4u * x->a + (uint32_t)k]) * s;
                    tris[0] = x[0].t, tris[1] = x[1].t, nf = 2;
                }
                double dd[3];
                for (int k = 0; k < 3; k++)
                    d[k] = pt[k] - o[k], dd[k] = d[k];
                if (crosses(nrm, tris, nf, dd))
                    break;
            }
            fx_set_ray(&in[i], o, d, 0.999f, 1.001f, i);
        }
        hz_accel_kernel_t k = (hz_accel_kernel_t)(1 + bi % 4);
        if (bi % 2)
            fx_trace_packets(a, k, HZ_ACCEL_COHERENT, HZ_BVH_W, false, in, out, cnt, NULL);
        else
            fx_trace1(a, k, in, out, cnt, NULL);
        for (uint32_t i = 0; i < cnt; i++) {
            if (out[i].hit.geom_id != 0 && leaks++ < 5)
                print_message("leak: org (%.9g %.9g %.9g) dir (%.9g %.9g %.9g), kernel %s\n", (double)in[i].ray.org_x,
                              (double)in[i].ray.org_y, (double)in[i].ray.org_z, (double)in[i].ray.dir_x,
                              (double)in[i].ray.dir_y, (double)in[i].ray.dir_z, hz_accel_kernel_name(k));
        }
    }
    print_message("dragon-res4: %u rays at vertices (%u of %u usable) and shared edges (%u), %u leaks\n", N_WATER, ngood,
                  nv, nman, leaks);
    assert_int_equal(leaks, 0);
    free(e), free(nrm), free(vbad), free(vfirst), free(vtris), free(man), free(fill);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dragon_kernels),
        cmocka_unit_test(test_cornell_kernels),
        cmocka_unit_test(test_sponza_kernels_and_spatial_splits),
        cmocka_unit_test(test_dragon_watertight),
    };
    return HZ_RUN(tests);
}
