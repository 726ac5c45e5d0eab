/* Packet surfaces (src/render/shade.h): the board's SIMD kernel against its scalar twin, bit for bit, on real hits —
 * random rays from inside the bounds of baked scenes (textured Sponza, blended, cutout and
 * alpha-textured materials, a mirror box, the built-in scene, pose keys at random ray times), packets with some
 * lanes empty, and lanes with extreme ray cones and non-finite barycentrics. Also the motion vectors of hits
 * in lanes (hz_view_motion_lanes), on still and moving points, against hz_view_point_motion, and the any-hit tests' texture alpha
 * against an oracle.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include <math.h>
#include <string.h>

#include "hz/hash.h"
#include "../../src/render/shade.h"
#include "render_fixture.h"
#include "../../src/render/render_internal.h" /* hz_view_point_motion and its lanes */
#include "../../src/render/shade_internal.h"  /* hz_shade_footprint_lane */

#define PACKETS 8000

typedef struct tally {
    uint32_t lanes, textured, blended, cutout, mirror, keyed, far_cone, lit, skipped, footprint, filtered;
} tally_t;

#define LIGHTS (HZ_SHADE_LIGHTS + 2) /* the last two only through hz_shade_light_lane */

static void open_scene(rfix_t *f, const char *file)
{
    char path[512];
    hz_error_t err;
    const char *p = file;
    if (strcmp(file, "builtin") != 0) {
        p = rfix_scene_path(file, path, sizeof path);
        if (!p)
            fail_msg("HZ_SCENES_DIR is not set (make test sets it)");
    }
    if (rfix_open(f, p, HZ_ACCEL_NATIVE, &err) != HZ_OK)
        fail_msg("%s: %s", file, err.msg);
}

static float unit(hz_rng_t *r)
{
    return hz_u32_to_unit(hz_rng_u32(r));
}

/* Bit-for-bit equality of every output of the live lanes. */
static void compare(const hz_shade_out_t *a, const hz_shade_out_t *b, uint32_t mask, const char *what)
{
    const float *fa[] = { a->px, a->py, a->pz, a->ngx, a->ngy, a->ngz, a->nsx, a->nsy, a->nsz, a->albedo[0],
                          a->albedo[1], a->albedo[2], a->alpha, a->tu, a->tv };
    const float *fb[] = { b->px, b->py, b->pz, b->ngx, b->ngy, b->ngz, b->nsx, b->nsy, b->nsz, b->albedo[0],
                          b->albedo[1], b->albedo[2], b->alpha, b->tu, b->tv };
    for (uint32_t i = 0; i < HZ_SHADE_LANES; i++) {
        if (!(mask >> i & 1u))
            continue;
        for (size_t k = 0; k < sizeof fa / sizeof fa[0]; k++)
            if (memcmp(&fa[k][i], &fb[k][i], sizeof(float)) != 0)
                fail_msg("%s: lane %u output %zu: simd %.9g, scalar %.9g", what, i, k, (double)fa[k][i],
                         (double)fb[k][i]);
        if (a->textured[i] != b->textured[i])
            fail_msg("%s: lane %u textured %u vs %u", what, i, a->textured[i], b->textured[i]);
        const float *la[] = { a->lox, a->loy, a->loz, a->skip }, *lb[] = { b->lox, b->loy, b->loz, b->skip };
        for (size_t k = 0; k < 4; k++)
            if (memcmp(&la[k][i], &lb[k][i], sizeof(float)) != 0)
                fail_msg("%s: lane %u origin/skip %zu: simd %.9g, scalar %.9g", what, i, k, (double)la[k][i],
                         (double)lb[k][i]);
    }
    for (uint32_t l = 0; l < HZ_SHADE_LIGHTS; l++) {
        if ((a->lit[l] & mask) != (b->lit[l] & mask))
            fail_msg("%s: light %u lit lanes %#x vs %#x", what, l, a->lit[l] & mask, b->lit[l] & mask);
        const hz_shade_light_t *x = &a->light[l], *y = &b->light[l];
        const float *ga[] = { x->ox, x->oy, x->oz, x->dx, x->dy, x->dz, x->tmax, x->k };
        const float *gb[] = { y->ox, y->oy, y->oz, y->dx, y->dy, y->dz, y->tmax, y->k };
        for (uint32_t i = 0; i < HZ_SHADE_LANES; i++)
            if ((a->lit[l] & mask) >> i & 1u)
                for (size_t k = 0; k < 8; k++)
                    if (memcmp(&ga[k][i], &gb[k][i], sizeof(float)) != 0)
                        fail_msg("%s: light %u lane %u field %zu: simd %.9g, scalar %.9g", what, l, i, k,
                                 (double)ga[k][i], (double)gb[k][i]);
    }
}

/* Shoots PACKETS packets of random rays from inside the scene's bounds, keeps the hits, and compares. */
static void run_scene(const char *file, bool with_keys, tally_t *t)
{
    rfix_t f;
    hz_error_t err;
    open_scene(&f, file);
    const hz_scene_t *s = &f.scene;
    hz_posekeys_t keys;
    float lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t v = 0; v < s->vertex_count; v++)
        for (int a = 0; a < 3; a++)
            lo[a] = fminf(lo[a], s->pos[v * 4 + a]), hi[a] = fmaxf(hi[a], s->pos[v * 4 + a]);
    hz_rng_t rng;
    hz_rng_seed(&rng, 16, (uint64_t)strlen(file));
    /* Lights inside the bounds, both falloffs; the scene's own first where it has them. */
    hz_light_t lights[LIGHTS];
    memset(lights, 0, sizeof lights);
    for (uint32_t l = 0; l < LIGHTS; l++) {
        if (l < s->light_count) {
            lights[l] = s->lights[l];
            continue;
        }
        for (int a = 0; a < 3; a++)
            lights[l].position[a] = lo[a] + (hi[a] - lo[a]) * unit(&rng), lights[l].color[a] = unit(&rng);
        lights[l].falloff = l & 1u ? HZ_FALLOFF_NONE : HZ_FALLOFF_INV_SQUARE;
    }
    float scale = 0.0f;
    for (int a = 0; a < 3; a++)
        scale = fmaxf(scale, fmaxf(fabsf(lo[a]), fabsf(hi[a])));
    hz_shade_ctx_t c = { s, NULL, s->uv != NULL, lights, LIGHTS, scale, NULL };
    if (with_keys) {
        uint32_t k = hz_posekeys_count(s, 1.0f / 24.0f);
        assert_true(k >= 2);
        assert_int_equal(hz_posekeys_init(&keys, s, k, &f.pools->frame, &err), HZ_OK);
        hz_posekeys_eval(&keys, s, 0.5f, -1.0f / 48.0f, 1.0f / 48.0f);
        c.keys = &keys;
    }
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    memset(t, 0, sizeof *t);
    for (int pk = 0; pk < PACKETS; pk++) {
        hz_shade_in_t in;
        hz_shade_out_t simd, scalar;
        /* Every other packet filters textures over a pixel footprint: a random camera step (pixel-sized to
         * huge), some lanes off, some at distances whose taps overflow. */
        hz_shade_footprint_t fp;
        const float fs = pk % 6 == 1 ? 10.0f : 2e-3f;
        for (int a = 0; a < 3; a++)
            fp.ex[a] = fs * (unit(&rng) - 0.5f), fp.ey[a] = fs * (unit(&rng) - 0.5f), fp.f[a] = unit(&rng) - 0.5f;
        c.footprint = pk & 1 ? &fp : NULL;
        memset(&simd, 0xa5, sizeof simd);
        memset(&scalar, 0x5a, sizeof scalar);
        uint32_t mask = 0, live = 0;
        for (uint32_t i = 0; i < HZ_SHADE_LANES; i++) {
            hz_rayhit_t rh;
            memset(&rh, 0, sizeof rh);
            rh.ray.org_x = lo[0] + (hi[0] - lo[0]) * unit(&rng);
            rh.ray.org_y = lo[1] + (hi[1] - lo[1]) * unit(&rng);
            rh.ray.org_z = lo[2] + (hi[2] - lo[2]) * unit(&rng);
            hz_vec3_t d = hz_v3_normalize(hz_v3(unit(&rng) - 0.5f, unit(&rng) - 0.5f, unit(&rng) - 0.5f));
            rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
            rh.ray.tfar = INFINITY;
            rh.ray.mask = 0xffffffffu;
            rh.hit.geom_id = rh.hit.prim_id = HZ_ACCEL_INVALID_ID;
            hz_accel_intersect1(f.accel, &ctx, &rh);
            /* About one lane in five stays empty (a miss or dropped): packets partly full. */
            if (rh.hit.geom_id == HZ_ACCEL_INVALID_ID || hz_rng_below(&rng, 5) == 0)
                continue;
            if (!mask)
                live = i;
            mask |= 1u << i;
            in.prim[i] = rh.hit.prim_id, in.u[i] = rh.hit.u, in.v[i] = rh.hit.v, in.t[i] = rh.ray.tfar;
            in.dx[i] = d.x, in.dy[i] = d.y, in.dz[i] = d.z;
            in.time[i] = unit(&rng);
            uint32_t e = hz_rng_below(&rng, 16);
            in.eye_dist[i] = e == 0 ? 0.0f : e == 1 ? 3e38f : e == 2 ? NAN : rh.ray.tfar * (0.5f + unit(&rng));
            uint32_t cone = hz_rng_below(&rng, 8);
            /* Pixel-sized cones mostly; some zero (finest level) and some huge (coarsest level). */
            in.cone_w[i] = cone == 0 ? 0.0f : cone == 1 ? 1e6f : 1e-3f * unit(&rng);
            in.cone_s[i] = cone == 0 ? 0.0f : cone == 1 ? 10.0f : 2e-3f * unit(&rng);
            t->far_cone += cone == 1;
            if (hz_rng_below(&rng, 97) == 0)
                in.u[i] = NAN; /* non-finite texture coordinates: the sample is the constant 1 */
            const hz_material_t *m = &s->materials[s->tri_info[rh.hit.prim_id] & 0xffffu];
            t->lanes++;
            t->blended += m->alpha_mode == HZ_ALPHA_BLEND;
            t->cutout += m->alpha_mode == HZ_ALPHA_MASK;
            t->mirror += m->mirror > 0.0f;
            t->keyed += with_keys;
        }
        if (!mask)
            continue;
        for (uint32_t i = 0; i < HZ_SHADE_LANES; i++)
            if (!(mask >> i & 1u)) { /* the contract: empty lanes name a valid triangle */
                in.prim[i] = in.prim[live], in.u[i] = in.u[live], in.v[i] = in.v[live], in.t[i] = in.t[live];
                in.dx[i] = in.dx[live], in.dy[i] = in.dy[live], in.dz[i] = in.dz[live];
                in.time[i] = in.time[live], in.cone_w[i] = in.cone_w[live], in.cone_s[i] = in.cone_s[live];
                in.eye_dist[i] = in.eye_dist[live];
            }
        hz_shade_surfaces(&c, &in, mask, &simd);
        hz_shade_surfaces_scalar(&c, &in, mask, &scalar);
        compare(&simd, &scalar, mask, file);
        if (c.footprint) { /* lanes the footprint changed: the taps are exercised, not all at the hit */
            hz_shade_ctx_t plain = c;
            hz_shade_out_t one;
            plain.footprint = NULL;
            hz_shade_surfaces_scalar(&plain, &in, mask, &one);
            for (uint32_t i = 0; i < HZ_SHADE_LANES; i++)
                if (mask >> i & 1u) {
                    t->footprint += in.eye_dist[i] > 0.0f && scalar.textured[i];
                    t->filtered += memcmp(&one.albedo[0][i], &scalar.albedo[0][i], sizeof(float)) != 0;
                }
        }
        for (uint32_t i = 0; i < HZ_SHADE_LANES; i++) {
            if (!(mask >> i & 1u))
                continue;
            t->textured += scalar.textured[i];
            t->skipped += scalar.skip[i] > 0.0f;
            for (uint32_t l = 0; l < HZ_SHADE_LIGHTS; l++)
                t->lit += scalar.lit[l] >> i & 1u;
            /* Lights past the packet's: one lane at a time, from either path's surfaces. */
            for (uint32_t l = HZ_SHADE_LIGHTS; l < LIGHTS; l++) {
                hz_shade_light_t x, y;
                memset(&x, 0, sizeof x), memset(&y, 0, sizeof y);
                bool lx = hz_shade_light_lane(&c, &simd, i, l, &x), ly = hz_shade_light_lane(&c, &scalar, i, l, &y);
                assert_int_equal(lx, ly);
                assert_memory_equal(&x, &y, sizeof x);
            }
        }
    }
    print_message("%s (%s): %u lanes, %u textured, %u blended, %u cutout, %u mirror, %u with keys, %u huge cones, "
                  "%u lit (of %u lane-lights), %u with a terminator skip, %u textured with a footprint (%u filtered)\n",
                  file, hz_shade_path(), t->lanes, t->textured, t->blended, t->cutout, t->mirror, t->keyed,
                  t->far_cone, t->lit, t->lanes * HZ_SHADE_LIGHTS, t->skipped, t->footprint, t->filtered);
    assert_true(t->lit > t->lanes / 4);
    rfix_close(&f);
}

static void test_sponza(void **state)
{
    (void)state;
    tally_t t;
    run_scene("sponza.hzb", false, &t);
    assert_true(t.lanes > PACKETS);
    assert_true(t.textured > t.lanes / 2); /* nearly every Sponza material has a base texture */
    assert_true(t.far_cone > 0);
    assert_true(t.filtered > t.footprint / 2); /* most footprints change the texture's value */
}

/* The footprint's gradients (hz_shade_footprint_lane) against finite differences computed here in double: for
 * camera rays through pixel centres of Sponza's camera, the rays through the centre +- h pixels meet the hit
 * triangle's plane, and their texture coordinates come from barycentrics solved by Cramer's rule. */
static void test_footprint_gradients(void **state)
{
    (void)state;
    rfix_t f;
    open_scene(&f, "sponza.hzb");
    const hz_scene_t *s = &f.scene;
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    hz_rng_t rng;
    hz_rng_seed(&rng, 29, 3);
    uint32_t checked = 0;
    double worst = 0.0;
    for (int view = 0; view < 4; view++) {
        hz_view_t v;
        const uint32_t W = view & 1 ? 640 : 1024, H = view & 1 ? 360 : 1024;
        hz_view_setup(&v, (hz_camera_t[]){ hz_scene_camera(s, 1.5f * (float)view) }, W, H);
        hz_shade_footprint_t fp; /* the steps of fwd + sx right + sy up per pixel, sx = 2 x / W - 1, sy = 1 - 2 y / H */
        const float ff = hz_v3_dot(v.fwd, v.fwd);
        const float fwd[3] = { v.fwd.x, v.fwd.y, v.fwd.z }, rt[3] = { v.right.x, v.right.y, v.right.z };
        const float up[3] = { v.up.x, v.up.y, v.up.z };
        for (int a = 0; a < 3; a++)
            fp.ex[a] = rt[a] * (2.0f / (float)W), fp.ey[a] = up[a] * (-2.0f / (float)H), fp.f[a] = fwd[a] / ff;
        hz_shade_ctx_t c = { s, NULL, true, NULL, 0, 1.0f, &fp };
        for (int k = 0; k < 500; k++) {
            const double x = (double)hz_rng_below(&rng, W) + 0.5, y = (double)hz_rng_below(&rng, H) + 0.5;
            hz_vec3_t d = hz_view_ray_dir(&v, (float)x, (float)y);
            hz_rayhit_t rh;
            memset(&rh, 0, sizeof rh);
            rh.ray.org_x = v.eye.x, rh.ray.org_y = v.eye.y, rh.ray.org_z = v.eye.z;
            rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
            rh.ray.tfar = INFINITY;
            rh.ray.mask = 0xffffffffu;
            rh.hit.geom_id = rh.hit.prim_id = HZ_ACCEL_INVALID_ID;
            hz_accel_intersect1(f.accel, &ctx, &rh);
            if (rh.hit.geom_id == HZ_ACCEL_INVALID_ID)
                continue;
            const uint32_t *t = s->tri + (size_t)rh.hit.prim_id * 3;
            double P[3][3], UV[3][2];
            hz_vec3_t pv[3];
            for (int i = 0; i < 3; i++) {
                for (int a = 0; a < 3; a++)
                    P[i][a] = s->pos[t[i] * 4 + a];
                UV[i][0] = s->uv[t[i] * 2], UV[i][1] = s->uv[t[i] * 2 + 1];
                pv[i] = hz_v3((float)P[i][0], (float)P[i][1], (float)P[i][2]);
            }
            double e1[3], e2[3], n[3];
            for (int a = 0; a < 3; a++)
                e1[a] = P[1][a] - P[0][a], e2[a] = P[2][a] - P[0][a];
            n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2];
            n[2] = e1[0] * e2[1] - e1[1] * e2[0];
            const double nl = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            /* uv where the ray through pixel (px, py) meets the plane */
            double uvq[4][2];
            const double h = 1e-3, ox[4] = { h, -h, 0, 0 }, oy[4] = { 0, 0, h, -h };
            bool ok = nl > 0.0;
            for (int q = 0; q < 4 && ok; q++) {
                double sx = 2.0 * (x + ox[q]) / W - 1.0, sy = 1.0 - 2.0 * (y + oy[q]) / H;
                double D[3] = { fwd[0] + sx * rt[0] + sy * up[0], fwd[1] + sx * rt[1] + sy * up[1],
                                fwd[2] + sx * rt[2] + sy * up[2] };
                double E[3] = { v.eye.x, v.eye.y, v.eye.z };
                double dn = D[0] * n[0] + D[1] * n[1] + D[2] * n[2];
                double dl = sqrt(D[0] * D[0] + D[1] * D[1] + D[2] * D[2]);
                if (fabs(dn) < 0.1 * nl * dl) { /* grazing: finite differences are ill-conditioned */
                    ok = false;
                    break;
                }
                double tt = ((P[0][0] - E[0]) * n[0] + (P[0][1] - E[1]) * n[1] + (P[0][2] - E[2]) * n[2]) / dn;
                double r[3] = { E[0] + tt * D[0] - P[0][0], E[1] + tt * D[1] - P[0][1], E[2] + tt * D[2] - P[0][2] };
                /* r = b e1 + g e2: Cramer on the normal equations */
                double a11 = 0, a12 = 0, a22 = 0, r1 = 0, r2 = 0;
                for (int a = 0; a < 3; a++)
                    a11 += e1[a] * e1[a], a12 += e1[a] * e2[a], a22 += e2[a] * e2[a], r1 += r[a] * e1[a],
                        r2 += r[a] * e2[a];
                double det = a11 * a22 - a12 * a12, b = (r1 * a22 - r2 * a12) / det, g = (a11 * r2 - a12 * r1) / det;
                for (int m = 0; m < 2; m++)
                    uvq[q][m] = (1.0 - b - g) * UV[0][m] + b * UV[1][m] + g * UV[2][m];
            }
            if (!ok)
                continue;
            const double want[4] = { (uvq[0][0] - uvq[1][0]) / (2 * h), (uvq[2][0] - uvq[3][0]) / (2 * h),
                                     (uvq[0][1] - uvq[1][1]) / (2 * h), (uvq[2][1] - uvq[3][1]) / (2 * h) };
            hz_shade_in_t in;
            memset(&in, 0, sizeof in);
            in.prim[0] = rh.hit.prim_id, in.u[0] = rh.hit.u, in.v[0] = rh.hit.v, in.t[0] = rh.ray.tfar;
            in.dx[0] = d.x, in.dy[0] = d.y, in.dz[0] = d.z;
            in.eye_dist[0] = rh.ray.tfar; /* a unit direction from the eye */
            float g[4];
            assert_true(hz_shade_footprint_lane(&c, &in, 0, pv, g));
            double scale = fabs(want[0]) + fabs(want[1]) + fabs(want[2]) + fabs(want[3]);
            for (int m = 0; m < 4; m++) {
                double err = fabs((double)g[m] - want[m]) / scale;
                worst = err > worst ? err : worst;
                if (err > 2e-3)
                    fail_msg("view %d pixel (%g, %g) prim %u: gradient %d %.9g, finite differences %.9g", view, x, y,
                             rh.hit.prim_id, m, (double)g[m], want[m]);
            }
            checked++;
        }
    }
    print_message("footprint gradients: %u hits, worst relative error %.2e\n", checked, worst);
    assert_true(checked > 1000);
    /* No footprint: a lane off (distance 0 or NaN), a ray in the triangle's plane, a degenerate triangle. */
    hz_shade_footprint_t fp = { { 1e-3f, 0, 0 }, { 0, -1e-3f, 0 }, { 0, 0, 1 } };
    hz_shade_ctx_t c = { s, NULL, true, NULL, 0, 1.0f, &fp };
    hz_shade_in_t in;
    memset(&in, 0, sizeof in);
    in.dz[0] = 1.0f;
    in.eye_dist[0] = 5.0f;
    float g[4];
    hz_vec3_t flat[3] = { hz_v3(0, 0, 1), hz_v3(1, 0, 1), hz_v3(0, 1, 1) }; /* facing the ray: a footprint */
    assert_true(hz_shade_footprint_lane(&c, &in, 0, flat, g));
    hz_vec3_t edge_on[3] = { hz_v3(0, 0, 1), hz_v3(1, 0, 1), hz_v3(0, 0, 2) }; /* the plane y = 0 holds d */
    assert_false(hz_shade_footprint_lane(&c, &in, 0, edge_on, g));
    hz_vec3_t point[3] = { hz_v3(0, 0, 1), hz_v3(0, 0, 1), hz_v3(0, 0, 1) };
    assert_false(hz_shade_footprint_lane(&c, &in, 0, point, g));
    in.eye_dist[0] = 0.0f;
    assert_false(hz_shade_footprint_lane(&c, &in, 0, flat, g));
    in.eye_dist[0] = NAN;
    assert_false(hz_shade_footprint_lane(&c, &in, 0, flat, g));
    c.footprint = NULL;
    in.eye_dist[0] = 5.0f;
    assert_false(hz_shade_footprint_lane(&c, &in, 0, flat, g));
    rfix_close(&f);
}

static void test_blended(void **state)
{
    (void)state;
    tally_t t;
    run_scene("AlphaBlendModeTest.hzb", false, &t);
    assert_true(t.blended > 100);
    assert_true(t.cutout > 100);
    assert_true(t.textured > 100);
}

static void test_mirror_box(void **state)
{
    (void)state;
    tally_t t;
    run_scene("CornellBox-Mirror.hzb", false, &t);
    assert_true(t.mirror > 50);
    assert_int_equal(t.textured, 0);
}

static void test_builtin(void **state)
{
    (void)state;
    tally_t t;
    run_scene("builtin", false, &t);
    assert_true(t.lanes > PACKETS);
}

/* The any-hit tests' alpha (hz_texture_alpha: level 0, alpha only) against an oracle written here from the
 * texels: bilinear at texel centres, corners wrapped with %, the same float steps. Bit for bit, on every texture of
 * the smoke sprites and Lost Empire's cut-outs, at random coordinates far outside [0, 1) and at the ones where
 * wrapping and rounding bite (texel edges, -1e-9, 1, exact integers); non-finite coordinates read as 1. */
static float alpha_oracle(const hz_scene_t *s, const hz_texture_t *t, float u, float v)
{
    const int32_t w = (int32_t)t->width, h = (int32_t)t->height;
    const uint8_t *px = s->texels + t->first_texel * 4;
    float fu = (u - floorf(u)) * (float)w - 0.5f, fv = (v - floorf(v)) * (float)h - 0.5f;
    float x0f = floorf(fu), y0f = floorf(fv), ax = fu - x0f, ay = fv - y0f;
    int32_t x[2] = { (int32_t)x0f, (int32_t)x0f + 1 }, y[2] = { (int32_t)y0f, (int32_t)y0f + 1 };
    float c[2][2];
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            int32_t xi = ((x[i] % w) + w) % w, yj = ((y[j] % h) + h) % h;
            c[j][i] = (float)px[((size_t)yj * (size_t)w + (size_t)xi) * 4 + 3] * (1.0f / 255.0f);
        }
    float top = c[0][0] + (c[0][1] - c[0][0]) * ax, bot = c[1][0] + (c[1][1] - c[1][0]) * ax;
    return top + (bot - top) * ay;
}

static void test_texture_alpha(void **state)
{
    (void)state;
    static const char *const files[] = { "sponza-smoke.hzb", "lost-empire.hzb" };
    hz_rng_t rng;
    hz_rng_seed(&rng, 7, 1);
    uint32_t checked = 0;
    for (size_t fi = 0; fi < sizeof files / sizeof files[0]; fi++) {
        rfix_t f;
        open_scene(&f, files[fi]);
        const hz_scene_t *s = &f.scene;
        for (uint32_t ti = 0; ti < s->texture_count; ti++) {
            const hz_texture_t *t = &s->textures[ti];
            for (int k = 0; k < 400; k++) {
                float u, v;
                if (k < 64) { /* texel edges and centres, and just outside [0, 1) */
                    static const float edge[] = { -1e-9f, 0.0f, 1.0f, -1.0f, 2.0f, 0.99999994f, -0.5f, 3.0f };
                    u = k < 8 ? edge[k] : (float)(k % 9) / (float)t->width;
                    v = k < 8 ? edge[7 - k] : (float)(k / 9) / (float)t->height + (k & 1 ? 0.5f / (float)t->height : 0);
                } else {
                    u = (unit(&rng) - 0.5f) * (k < 200 ? 4.0f : 3000.0f);
                    v = (unit(&rng) - 0.5f) * (k < 200 ? 4.0f : 3000.0f);
                }
                float got = hz_texture_alpha(s, (int32_t)ti, u, v), want = alpha_oracle(s, t, u, v);
                if (memcmp(&got, &want, sizeof got) != 0)
                    fail_msg("%s texture %u at (%.9g, %.9g): %.9g, oracle %.9g", files[fi], ti, (double)u, (double)v,
                             (double)got, (double)want);
                float rgba[4];
                hz_texture_sample(s, (int32_t)ti, u, v, 0.0f, rgba); /* the colour path's alpha: the same */
                assert_memory_equal(&rgba[3], &got, sizeof got);
                checked++;
            }
            assert_true(hz_texture_alpha(s, (int32_t)ti, NAN, 0.5f) == 1.0f);
            assert_true(hz_texture_alpha(s, (int32_t)ti, 0.5f, INFINITY) == 1.0f);
        }
        rfix_close(&f);
    }
    print_message("%u alpha lookups agree with the oracle\n", checked);
    assert_true(checked >= 800);
}

static void test_pose_keys(void **state)
{
    (void)state;
    tally_t t;
    run_scene("CesiumMan-keys.hzb", true, &t);
    assert_true(t.keyed > 100);
    assert_true(t.textured > 100);
}

/* Random camera pairs (near each other, as consecutive frames are, and far apart) and points in front of, beside,
 * behind and on the eye plane of either camera, with huge, tiny and non-finite coordinates, still or moved (a
 * little, a lot, to a special point): every lane's motion vector has the bits of the scalar function's, and every
 * kind of point occurs. */
static float rnd(uint32_t *st, float lo, float hi)
{
    *st = hz_hash32(*st + 0x9e3779b9u);
    return lo + (hi - lo) * (float)(*st >> 8) * (1.0f / 16777216.0f);
}

static void test_motion_lanes(void **state)
{
    (void)state;
    uint32_t st = 7, seen = 0, far = 0, special = 0, moved = 0;
    for (int round = 0; round < 4000; round++) {
        hz_camera_t a, b;
        a.eye = hz_v3(rnd(&st, -50, 50), rnd(&st, -50, 50), rnd(&st, -50, 50));
        a.target = hz_v3_add(a.eye, hz_v3(rnd(&st, -1, 1), rnd(&st, -1, 1), rnd(&st, -1, 1) + 0.01f));
        a.up = hz_v3(rnd(&st, -0.3f, 0.3f), 1, rnd(&st, -0.3f, 0.3f)); /* tilted: every basis component nonzero */
        a.fov_y = rnd(&st, 0.2f, 2.0f);
        b = a;
        float step = round % 4 == 0 ? 10.0f : 0.05f;
        b.eye = hz_v3_add(a.eye, hz_v3(rnd(&st, -step, step), rnd(&st, -step, step), rnd(&st, -step, step)));
        b.target = hz_v3_add(b.eye, hz_v3_sub(a.target, a.eye));
        if (round % 8 == 1)
            b = a; /* a still camera: motion exactly zero */
        hz_view_t cur, prev;
        uint32_t w = 64 + (uint32_t)rnd(&st, 0, 2000), h = 36 + (uint32_t)rnd(&st, 0, 1200);
        hz_view_setup(&cur, &a, w, h);
        hz_view_setup(&prev, &b, w, h);
        float px[HZ_SHADE_LANES] HZ_ALIGNED(32), py[HZ_SHADE_LANES] HZ_ALIGNED(32), pz[HZ_SHADE_LANES] HZ_ALIGNED(32);
        float qx[HZ_SHADE_LANES] HZ_ALIGNED(32), qy[HZ_SHADE_LANES] HZ_ALIGNED(32), qz[HZ_SHADE_LANES] HZ_ALIGNED(32);
        for (int i = 0; i < HZ_SHADE_LANES; i++) {
            hz_vec3_t d = hz_v3(rnd(&st, -1, 1), rnd(&st, -1, 1), rnd(&st, -1, 1));
            hz_vec3_t p = hz_v3_add(a.eye, hz_v3_scale(d, rnd(&st, 0, round % 3 ? 100.0f : 1e-3f)));
            switch ((round + i) % 16) {
            case 0: p = a.eye; break;                                  /* on the eye: z = 0 */
            case 1: p.x = 1e30f; break;
            case 2: p.y = -1e38f; break;
            case 3: p.z = (float)(1.0 / 0.0); break;
            case 4: p.x = p.x - p.x + (float)(0.0 / 0.0); break;      /* NaN */
            case 5: p = hz_v3_add(a.eye, hz_v3_scale(cur.right, 1e-20f)); break; /* beside the eye plane */
            default: break;
            }
            special += (round + i) % 16 < 6;
            px[i] = p.x, py[i] = p.y, pz[i] = p.z;
            /* where the point moved: by a little or a lot, or to one of the special points of another lane */
            hz_vec3_t q = p;
            if (round % 2) {
                float move = round % 6 == 1 ? 20.0f : 0.1f;
                q = hz_v3_add(p, hz_v3(rnd(&st, -move, move), rnd(&st, -move, move), rnd(&st, -move, move)));
                switch ((round / 2 + 3 * i) % 32) {
                case 0: q = b.eye; break;
                case 1: q.y = 1e30f; break;
                case 2: q.z = (float)(-1.0 / 0.0); break;
                case 3: q.x = q.x - q.x + (float)(0.0 / 0.0); break;
                default: break;
                }
            }
            qx[i] = q.x, qy[i] = q.y, qz[i] = q.z;
        }
        float mx[HZ_SHADE_LANES] HZ_ALIGNED(32), my[HZ_SHADE_LANES] HZ_ALIGNED(32);
        const float *const pl[3] = { px, py, pz }, *const ql[3] = { qx, qy, qz };
        hz_view_motion_lanes(&cur, &prev, pl, round % 4 == 2 ? pl : ql, mx, my); /* pp aliasing p, as still hits */
        for (int i = 0; i < HZ_SHADE_LANES; i++) {
            float m[2];
            hz_vec3_t p = hz_v3(px[i], py[i], pz[i]), q = hz_v3(qx[i], qy[i], qz[i]);
            hz_view_point_motion(&cur, &prev, &p, &q, m);
            if (memcmp(&m[0], &mx[i], sizeof(float)) || memcmp(&m[1], &my[i], sizeof(float)))
                fail_msg("round %d lane %d: point (%g, %g, %g) from (%g, %g, %g): lanes (%.9g, %.9g), scalar (%.9g, "
                         "%.9g)", round, i, (double)px[i], (double)py[i], (double)pz[i], (double)qx[i], (double)qy[i],
                         (double)qz[i], (double)mx[i], (double)my[i], (double)m[0], (double)m[1]);
            if (m[0] == HZ_VIEW_MV_FAR)
                far++;
            else
                seen++, moved += round % 4 != 2 && memcmp(&p, &q, sizeof p) != 0;
        }
    }
    print_message("hit motion (%s): %u seen by both cameras (%u of them moved), %u far, %u special points\n",
                  hz_shade_path(), seen, moved, far, special);
    assert_true(moved > 4000 * HZ_SHADE_LANES / 16);
    assert_true(seen > 4000 * HZ_SHADE_LANES / 4);
    assert_true(far > 4000 * HZ_SHADE_LANES / 8);
}

/* Camera ray directions in lanes (hz_view_ray_dirs) against hz_view_ray_dir: random cameras and image sizes,
 * pixels inside and far outside the image, and the coordinates that take hz_v3_normalize's other paths (a
 * squared length that overflows, non-finite coordinates): the same bits in every lane. */
static void test_ray_dirs_lanes(void **state)
{
    (void)state;
    uint32_t st = 11, special = 0;
    for (int round = 0; round < 4000; round++) {
        hz_camera_t a;
        a.eye = hz_v3(rnd(&st, -50, 50), rnd(&st, -50, 50), rnd(&st, -50, 50));
        a.target = hz_v3_add(a.eye, hz_v3(rnd(&st, -1, 1), rnd(&st, -1, 1), rnd(&st, -1, 1) + 0.01f));
        a.up = hz_v3(rnd(&st, -0.3f, 0.3f), 1, rnd(&st, -0.3f, 0.3f));
        a.fov_y = rnd(&st, 0.01f, 3.0f);
        hz_view_t v;
        uint32_t w = 1 + (uint32_t)rnd(&st, 0, 4000), h = 1 + (uint32_t)rnd(&st, 0, 2200);
        hz_view_setup(&v, &a, w, h);
        float x[HZ_SHADE_LANES] HZ_ALIGNED(32), y[HZ_SHADE_LANES] HZ_ALIGNED(32);
        for (int i = 0; i < HZ_SHADE_LANES; i++) {
            x[i] = rnd(&st, -0.5f, (float)w + 0.5f), y[i] = rnd(&st, -0.5f, (float)h + 0.5f);
            switch ((round + i) % 12) {
            case 0: x[i] = 3e37f; break;                          /* the squared length overflows */
            case 1: y[i] = -1e30f; break;
            case 2: x[i] = (float)(1.0 / 0.0); break;             /* not finite */
            case 3: y[i] = x[i] - x[i] + (float)(0.0 / 0.0); break; /* NaN */
            case 4: x[i] = rnd(&st, -1e6f, 1e6f); break;          /* far outside the image */
            default: break;
            }
            special += (round + i) % 12 < 5;
        }
        float dx[HZ_SHADE_LANES] HZ_ALIGNED(32), dy[HZ_SHADE_LANES] HZ_ALIGNED(32), dz[HZ_SHADE_LANES] HZ_ALIGNED(32);
        hz_view_ray_dirs(&v, x, y, dx, dy, dz);
        for (int i = 0; i < HZ_SHADE_LANES; i++) {
            const hz_vec3_t d = hz_view_ray_dir(&v, x[i], y[i]);
            if (memcmp(&d.x, &dx[i], sizeof(float)) || memcmp(&d.y, &dy[i], sizeof(float)) ||
                memcmp(&d.z, &dz[i], sizeof(float)))
                fail_msg("round %d lane %d: pixel (%g, %g) of %ux%u: lanes (%.9g, %.9g, %.9g), scalar (%.9g, %.9g, %.9g)",
                         round, i, (double)x[i], (double)y[i], w, h, (double)dx[i], (double)dy[i], (double)dz[i],
                         (double)d.x, (double)d.y, (double)d.z);
        }
    }
    print_message("ray directions (%s): %d lanes, %u special pixels\n", hz_shade_path(), 4000 * HZ_SHADE_LANES,
                  special);
    assert_true(special > 1000);
}

/* The path the board runs is its SIMD kernel where it has one (else the twin itself). */
static void test_path(void **state)
{
    (void)state;
#if defined(HZ_BOARD_SIMD_AVX2)
    assert_string_equal(hz_shade_path(), "avx2");
#elif defined(HZ_BOARD_SIMD_NEON)
    assert_string_equal(hz_shade_path(), "neon");
#else
    assert_string_equal(hz_shade_path(), "scalar");
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_path),     cmocka_unit_test(test_builtin),    cmocka_unit_test(test_sponza),
        cmocka_unit_test(test_blended),  cmocka_unit_test(test_mirror_box), cmocka_unit_test(test_pose_keys),
        cmocka_unit_test(test_motion_lanes), cmocka_unit_test(test_ray_dirs_lanes), cmocka_unit_test(test_texture_alpha),
        cmocka_unit_test(test_footprint_gradients),
    };
    return HZ_RUN(tests);
}
