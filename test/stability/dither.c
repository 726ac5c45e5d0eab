/* Stage dither: stochastic transparency (seed 004: --transparency rr, std, dtaa, dtaa-star, hybrid:X; the
 * thresholds of src/pattern/dither.c, the decision of src/render/transp.c and its division-free cell form, TAA's
 * 7x7 window and cell mean for dithered pixels, the motion-vector alignment of hz/dither.h) at the edges: alpha 0, 1e-30, 1 - 1e-7 and 1, 1000 stacked layers, STD and DTAA
 * thresholds at the ends of their maps and of the fixed-point range, motion-vector alignment at huge vectors.
 * References: the scene without the layer or with an opaque one, the documented decision rule (hz/dither.h,
 * hz/render.h) evaluated here in double over the layers, the threshold formulas evaluated here from the tables
 * in 64-bit integers, and the floor/ceil multiples of the alignment in 64-bit integers. */
#include <stdlib.h>

#include "hz/dither.h"
#include "hz/hash.h"
#include "stab_util.h"

#define W 32
#define H 24

typedef struct method {
    const char *name;
    hz_transp_t t;
    float x; /* hybrid's visibility threshold */
} method_t;

static const method_t methods[] = {
    { "rr", HZ_TRANSP_RR, 0.5f },         { "std", HZ_TRANSP_STD, 0.5f },
    { "dtaa", HZ_TRANSP_DTAA, 0.5f },     { "dtaa-star", HZ_TRANSP_DTAA_STAR, 0.5f },
    { "hybrid:0", HZ_TRANSP_HYBRID, 0.0f }, { "hybrid:0.5", HZ_TRANSP_HYBRID, 0.5f },
    { "hybrid:1", HZ_TRANSP_HYBRID, 1.0f },
};
#define NMETHODS (sizeof methods / sizeof methods[0])

/* Renders `frames` frames (full mode at 1 spp, or TAA) with method m; out gets the last frame (W * H * 3).
 * Stack cases render a quarter of the pixels (every ray crosses up to 1000 layers). */
static uint32_t img_w = W, img_h = H;
static bool rr_shadows;

static void render_m(stab_result_t *r, const su_scene_t *b, const method_t *m, hz_render_mode_t mode,
                     uint32_t frames, float *out)
{
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = img_w, o.height = img_h, o.mode = mode, o.rr_shadows = rr_shadows;
    if (m)
        o.transparency = m->t, o.hybrid_x = m->x;
    su_render_t s;
    hz_error_t err;
    STAB_OK(r, su_render_open(&s, b, &o, &err), &err);
    for (uint32_t f = 0; f < frames; f++) {
        STAB_OK(r, su_render_frame(&s, f, (float)f / 60.0f, &err), &err);
        su_render_check(r, &s);
        STAB_BAIL(r);
    }
    memcpy(out, hz_render_output(s.r)->rgb, sizeof(float) * img_w * img_h * 3);
    su_render_close(&s);
}

/* A blended layer of alpha `alpha` under every stochastic method against the reference scene (no layer: the
 * fragment is dropped; an opaque layer: kept), full mode; and 4 TAA frames (7x7 window, aligned motion) finite.
 * The bound is the exact method's (transparency stage): a dropped layer's wall is reached through the scene's
 * bounds-scaled offsets, so float rounding of the lighting differs. */
static void alpha_case(stab_result_t *r, float alpha, int ref_mode, double bound)
{
    static float img[W * H * 3], ref[W * H * 3], exact[W * H * 3];
    su_scene_t b;
    su_wall_layer(&b, ref_mode, 1.0f);
    render_m(r, &b, NULL, HZ_MODE_FULL, 1, ref);
    STAB_BAIL(r);
    su_wall_layer(&b, HZ_ALPHA_BLEND, alpha);
    render_m(r, &b, NULL, HZ_MODE_FULL, 1, exact);
    STAB_BAIL(r);
    double worst = 0;
    const char *worst_m = "";
    for (size_t m = 0; m < NMETHODS; m++) {
        render_m(r, &b, &methods[m], HZ_MODE_FULL, 1, img);
        STAB_BAIL(r);
        /* hybrid:X with X < 1 meets the first layer at visibility 1 > X: exact compositing (render.h); the
         * exact method itself is checked against these references in the transparency stage */
        const bool first_exact = methods[m].t == HZ_TRANSP_HYBRID && methods[m].x < 1.0f;
        const float *want = first_exact ? exact : ref;
        double e = 0;
        for (size_t i = 0; i < W * H * 3; i++)
            e = fmax(e, fabs((double)img[i] - want[i]) / fmax(fabs((double)want[i]), 1e-3));
        stab_error(r, e);
        STAB_CHECK(r, e <= (first_exact ? 1e-6 : bound), "%s: alpha %.9g differs from %s by %g > %g",
                   methods[m].name, (double)alpha,
                   first_exact ? "the exact method" : ref_mode < 0 ? "no layer" : "an opaque layer", e,
                   first_exact ? 1e-6 : bound);
        if (e >= worst)
            worst = e, worst_m = methods[m].name;
        render_m(r, &b, &methods[m], HZ_MODE_TAA, 4, img);
        STAB_BAIL(r);
    }
    stab_note(r, "alpha %.9g: rr/std/dtaa/dtaa-star/hybrid:1 = %s; hybrid:0/0.5 = exact; within %.3g (worst %s); "
                 "TAA finite", (double)alpha, ref_mode < 0 ? "no layer" : "opaque layer", worst, worst_m);
}

static void c_alpha_0(stab_result_t *r) { alpha_case(r, 0.0f, -1, 1e-4); }
static void c_alpha_1e_30(stab_result_t *r) { alpha_case(r, 1e-30f, -1, 1e-4); }
/* At the cut the camera ray always drops the layer; the wall's default deep shadow ray composites it exactly
 * (transmittance 0.99, as the exact method does), while a Russian-roulette shadow ray (rr_shadows) applies the
 * same cut: with it the wall is lit as without the layer. */
static void c_alpha_cut(stab_result_t *r)
{
    rr_shadows = true;
    alpha_case(r, 0.01f, -1, 1e-4);
}
static void c_alpha_1m1e_7(stab_result_t *r) { alpha_case(r, 1.0f - 1e-7f, HZ_ALPHA_OPAQUE, 1e-5); }
static void c_alpha_1(stab_result_t *r) { alpha_case(r, 1.0f, HZ_ALPHA_OPAQUE, 1e-6); }

/* n parallel blended layers of alpha a (quads with vertices of their own), one object, ambient light only, black
 * background. The rule (hz/render.h,
 * hz/dither.h) in double: the exact prefix composites layer i adding vis a c (vis *= 1 - a) while the path is
 * exact (hybrid: while vis > X; stops below min_visibility or at HZ_RENDER_MAX_LAYERS); a stochastic ray then
 * either keeps one layer (adding vis c: shaded as opaque) or drops them all (alpha <= 0.01: always dropped).
 * Every pixel must be one of those values; the fraction keeping a layer must be near its probability. */
static void stack_case(stab_result_t *r, uint32_t n, float a, uint32_t shrink)
{
    su_scene_t b;
    su_begin(&b);
    b.ambient[0] = b.ambient[1] = b.ambient[2] = 1.0f;
    const double c = 0.5;
    uint32_t mat = su_material_alpha(&b, (float)c, (float)c, (float)c, a, HZ_ALPHA_BLEND);
    for (uint32_t i = 0; i < n; i++) {
        float z = -0.01f * (float)i;
        const float q0[3] = { -50, -50, z }, q1[3] = { 50, -50, z }, q2[3] = { 50, 50, z }, q3[3] = { -50, 50, z };
        su_quad(&b, q0, q1, q2, q3, mat);
    }
    su_object(&b);
    /* dark and behind every surface (no shadow rays): without lights the scene would get the default key light */
    su_light(&b, 0, 0, -100, 0.0f);
    const float eye[3] = { 0, 0, 5 }, target[3] = { 0, 0, 0 };
    su_camera(&b, 0, eye, target, 0.3f);
    const float min_vis = 0.001f;
    const bool droppable = (uint32_t)(a * 65536.0f) <= HZ_DITHER_MIN_ALPHA;
    static float img[W * H * 3];
    img_w = W / shrink, img_h = H / shrink;
    const uint32_t npx = img_w * img_h;
    for (size_t m = 0; m < NMETHODS; m++) {
        const method_t *me = &methods[m];
        if (shrink > 3 && me->t == HZ_TRANSP_HYBRID && me->x <= 0.0f)
            continue; /* hybrid:0 is the exact method: transparency/stacked_1000 is this very stack */
        double P = 0, vis = 1, keep_v = -1;
        float visf = 1.0f;
        bool dither = me->t != HZ_TRANSP_HYBRID || !(1.0f > me->x);
        if (me->t == HZ_TRANSP_HYBRID && me->x <= 0.0f)
            dither = false;
        for (uint32_t i = 0; i < n; i++) {
            if (dither) {
                keep_v = droppable ? -1 : P + vis * c;
                break;
            }
            P += vis * (double)a * c;
            float leftf = visf * (1.0f - a);
            if (!(leftf >= min_vis) || i + 1 >= HZ_RENDER_MAX_LAYERS)
                break;
            visf = leftf, vis = vis * (1.0 - (double)a);
            dither = me->t == HZ_TRANSP_HYBRID && me->x > 0.0f && !(visf > me->x);
        }
        render_m(r, &b, me, HZ_MODE_FULL, 1, img);
        STAB_BAIL(r);
        uint32_t kept = 0;
        double e = 0;
        for (size_t p = 0; p < npx; p++) {
            double v = img[3 * p];
            double ed = fabs(v - P) / fmax(P, 1e-3), ek = keep_v >= 0 ? fabs(v - keep_v) / keep_v : INFINITY;
            kept += ek < ed;
            e = fmax(e, fmin(ed, ek));
        }
        stab_error(r, e);
        STAB_CHECK(r, e <= 1e-4, "%s: %u layers of alpha %g: a pixel is %g off the rule's values (%g or %g)",
                   me->name, n, (double)a, e, P, keep_v);
        double frac = (double)kept / npx;
        /* rr decides every layer independently; std, dtaa-star and hybrid's std give each quad (a particle: its own
         * vertices) its own map, so the layers stop masking each other, but all share the pixel's blue-noise rank:
         * a layer is kept where its map's cell is 0 and rank / 4096 <= K a (K = 9 cells, 5 strata), so many
         * layers cover min(1, K a) of the pixels; plain DTAA has one map for all: a */
        const double k = me->t == HZ_TRANSP_DTAA_STAR ? 5.0 : 9.0;
        if (keep_v >= 0 && me->t == HZ_TRANSP_RR)
            STAB_CHECK(r, frac >= 0.95, "rr: %u independent layers of alpha %g: only %.2f of the pixels keep one", n,
                       (double)a, frac);
        else if (keep_v >= 0 && me->t != HZ_TRANSP_DTAA)
            STAB_CHECK(r, fabs(frac - fmin(1.0, k * a)) <= 0.1, "%s: %u particles of alpha %g cover %.2f of the "
                       "pixels, not min(1, %g a)", me->name, n, (double)a, frac, k);
        else if (keep_v >= 0)
            STAB_CHECK(r, fabs(frac - a) <= 0.2, "%s: one object of alpha %g covers %.2f of the pixels", me->name,
                       (double)a, frac);
        if (m == 1 || m == 5)
            stab_note(r, "%s: %.2f keep (%.6g) else %.6g", me->name, frac, keep_v, P);
    }
}

/* Thin layers keep hybrid's exact prefix going for up to HZ_RENDER_MAX_LAYERS continuation rays, each through
 * 2000 overlapping triangles: the cut runs on 8x6 pixels, alpha 0.02 (coverage) only with FULL=1. */
static void c_stacked_1000(stab_result_t *r) { stack_case(r, 1000, 0.5f, r->full ? 1 : 3); }
static void c_stacked_1000_cut(stab_result_t *r) { stack_case(r, 1000, 0.01f, 4); }
static void c_stacked_1000_thin(stab_result_t *r) { stack_case(r, 1000, 0.02f, 1); }

/* STD thresholds for every map at every blue-noise position (frame = map mod 18: every serpentine shift), and at
 * x, y, frame near 2^32: equal to floor(((v << 12) + n) 65536 / 36864) evaluated here in 64 bits, with v read from
 * the map at the serpentine cell (Listing 4, written here again) and n from the blue-noise table; 0 and
 * floor(65536 8/9) (v = 8, n = 0) occur, the largest is below 1 (65534); the decision at those edges; DTAA and
 * DTAA* the same way over their 5 strata and 120 permutations. */
static uint32_t ref_std(uint32_t x, uint32_t y, uint32_t f, unsigned map)
{
    uint32_t g = f % 18u, sx = g % 3u, row = g / 3u;
    if (row & 1u)
        sx = 2u - sx;
    uint32_t cx = (x % 3u + sx) % 3u, cy = (y % 3u + row % 3u) % 3u;
    uint64_t v = hz_dither_maps[map][3u * cy + cx], nn = hz_dither_blue64[(y % 64u) * 64u + x % 64u];
    return (uint32_t)((((v << 12) + nn) << 16) / 36864u);
}

static void c_std_thresholds(stab_result_t *r)
{
    uint32_t tmin = UINT32_MAX, tmax = 0;
    uint64_t at_8_9 = 0, bad = 0;
    const uint32_t t89 = (uint32_t)((8ull << 28) / 36864u); /* floor(65536 * 8 / 9) */
    for (unsigned m = 0; m < HZ_DITHER_MAPS; m++)
        for (uint32_t y = 0; y < 64; y++)
            for (uint32_t x = 0; x < 64; x++) {
                uint32_t f = m % 18u, t = hz_dither_std_threshold(x, y, f, m);
                bad += t != ref_std(x, y, f, m);
                tmin = t < tmin ? t : tmin, tmax = t > tmax ? t : tmax;
                at_8_9 += t == t89;
            }
    STAB_CHECK(r, bad == 0, "%llu STD thresholds differ from the formula", (unsigned long long)bad);
    const uint32_t big[] = { 0xffffffffu, 0xfffffffeu, 0x80000000u, 0x7fffffffu };
    for (size_t i = 0; i < 4; i++)
        for (size_t j = 0; j < 4; j++)
            for (unsigned m = 0; m < HZ_DITHER_MAPS; m += 7) {
                uint32_t t = hz_dither_std_threshold(big[i], big[j], big[(i + j) % 4] - (uint32_t)m, m);
                STAB_CHECK(r, t == ref_std(big[i], big[j], big[(i + j) % 4] - (uint32_t)m, m),
                           "STD threshold at (%u, %u) differs from the formula", big[i], big[j]);
            }
    STAB_CHECK(r, tmin == 0 && at_8_9 > 0 && tmax == 65534u, "threshold range [%u, %u], 8/9 seen %llu times", tmin,
               tmax, (unsigned long long)at_8_9);
    /* the decision at the edges (hz/dither.h) */
    STAB_CHECK(r, hz_dither_keep(t89, t89) && !hz_dither_keep(t89 - 1u, t89), "alpha = threshold 8/9 not kept");
    STAB_CHECK(r, hz_dither_keep(HZ_DITHER_MIN_ALPHA + 1u, 0) && !hz_dither_keep(HZ_DITHER_MIN_ALPHA, 0) &&
                      !hz_dither_keep(0, 0), "the 0.01 cut at threshold 0");
    STAB_CHECK(r, hz_dither_keep(65535u, tmax) && hz_dither_keep(65536u, 65535u) && hz_dither_keep(0xffffffffu, 0),
               "alpha just below 1 not kept at the largest threshold");
    /* DTAA / DTAA* */
    uint64_t dbad = 0;
    uint32_t dmax = 0, dmin = UINT32_MAX;
    for (int perm = -1; perm < (int)HZ_DITHER_DTAA_PERMS; perm++)
        for (uint32_t y = 0; y < 64; y++)
            for (uint32_t x = 0; x < 64; x++) {
                uint32_t f = (uint32_t)(perm + 1) % 5u, t = hz_dither_dtaa_threshold(x, y, f, perm);
                uint32_t s = (x % 5u + 2u * (y % 5u) + 3u * f) % 5u;
                if (perm >= 0)
                    s = hz_dither_dtaa_perm_apply((unsigned)perm, s);
                uint64_t want = ((((uint64_t)s << 12) + hz_dither_blue64[y * 64u + x]) << 16) / 20480u;
                dbad += t != want;
                dmax = t > dmax ? t : dmax, dmin = t < dmin ? t : dmin;
            }
    STAB_CHECK(r, dbad == 0, "%llu DTAA thresholds differ from the formula", (unsigned long long)dbad);
    STAB_CHECK(r, dmin == 0 && dmax < 65536u && hz_dither_keep(65535u, dmax), "DTAA range [%u, %u]", dmin, dmax);
    /* every permutation is one */
    for (unsigned p = 0; p < HZ_DITHER_DTAA_PERMS; p++) {
        unsigned seen = 0;
        for (unsigned s = 0; s < 5; s++)
            seen |= 1u << hz_dither_dtaa_perm_apply(p, s);
        STAB_CHECK(r, seen == 31u, "DTAA* permutation %u is not one", p);
    }
    r->status = HZ_OK;
    stab_note(r, "288 maps x 64x64: STD = formula; range [%u, %u]; 8/9 (%u) seen %llu times; DTAA range [%u, %u]",
              tmin, tmax, t89, (unsigned long long)at_8_9, dmin, dmax);
}

/* The per-sample cell and the division-free decisions (hz_dither_std_cell / hz_dither_std_keep, the DTAA pair)
 * against the threshold formula evaluated here in 64 bits: every map (permutation), every cell (stratum), every
 * blue-noise rank, alpha at threshold - 1, threshold and threshold + 1, and the 0.01 cut and 1; the cell at x, y,
 * frame near 2^32 decodes to the formula's cell and rank. */
static void c_cell_keep(stab_result_t *r)
{
    uint64_t checked = 0, bad = 0;
    /* every rank with FULL=1; else every 17th, from an offset that walks all 17 residues over the maps (emulated
     * AArch64 runs the whole set in minutes) */
    const uint32_t step = r->full ? 1u : 17u;
    for (unsigned m = 0; m < HZ_DITHER_MAPS; m++)
        for (unsigned cell = 0; cell < 9u; cell++)
            for (uint32_t n = (m + cell) % step; n < 4096u; n += step) {
                uint64_t t = ((((uint64_t)hz_dither_maps[m][cell] << 12) + n) << 16) / 36864u;
                const uint64_t as[5] = { t ? t - 1u : 0u, t, t + 1u, HZ_DITHER_MIN_ALPHA, HZ_DITHER_ONE };
                for (int i = 0; i < 5; i++) {
                    bool want = as[i] > HZ_DITHER_MIN_ALPHA && (as[i] >= HZ_DITHER_ONE || as[i] >= t);
                    bad += hz_dither_std_keep((uint32_t)as[i], m, (uint16_t)(cell << 12 | n)) != want;
                    checked++;
                }
            }
    for (int perm = -1; perm < (int)HZ_DITHER_DTAA_PERMS; perm++)
        for (unsigned st = 0; st < 5u; st++)
            for (uint32_t n = ((uint32_t)(perm + 1) + st) % step; n < 4096u; n += step) {
                uint64_t sv = perm >= 0 ? hz_dither_dtaa_perm_apply((unsigned)perm, st) : st;
                uint64_t t = (((sv << 12) + n) << 16) / 20480u;
                for (uint64_t a = t ? t - 1u : 0u; a <= t + 1u; a++) {
                    bool want = a > HZ_DITHER_MIN_ALPHA && (a >= HZ_DITHER_ONE || a >= t);
                    bad += hz_dither_dtaa_keep((uint32_t)a, perm, (uint16_t)(st << 12 | n)) != want;
                    checked++;
                }
            }
    STAB_CHECK(r, bad == 0, "%llu of %llu cell decisions differ from the formula", (unsigned long long)bad,
               (unsigned long long)checked);
    const uint32_t big[] = { 0xffffffffu, 0xfffffffeu, 0x80000000u, 0x7fffffffu, 0u };
    for (size_t i = 0; i < 5; i++)
        for (size_t j = 0; j < 5; j++)
            for (unsigned m = 0; m < HZ_DITHER_MAPS; m += 11) {
                uint32_t x = big[i], y = big[j], f = big[(i + j) % 5] - (uint32_t)m;
                uint16_t c = hz_dither_std_cell(x, y, f);
                uint32_t t = ref_std(x, y, f, m);
                STAB_CHECK(r, (c >> 12) < 9u && hz_dither_std_keep(t, m, c) == (t > HZ_DITHER_MIN_ALPHA) &&
                                  (t == 0 || !hz_dither_std_keep(t - 1u, m, c)),
                           "STD cell at (%u, %u, %u) disagrees with the formula", x, y, f);
                STAB_CHECK(r, (c & 0xfffu) == hz_dither_blue64[(y % 64u) * 64u + x % 64u], "blue rank at (%u, %u)", x, y);
            }
    r->status = HZ_OK;
    stab_note(r, "%llu decisions (288 maps x 9 cells, 121 DTAA orders x 5 strata, x 4096 ranks / %u, at the "
                 "threshold edges) = formula; cells at the 32-bit ends decode", (unsigned long long)checked, step);
}

/* Alignment of Q16 motion vectors to multiples of align (1..15) px at the ends of the documented range (+-2^30),
 * past it (INT32_MIN, INT32_MAX: saturated to the representable multiples, no overflow) and random: the result
 * is the lower or the upper multiple (64-bit reference), and over all 2^16 hash values the upper one is taken
 * exactly frac * 2^16 times (the bilinear weights). */
static void c_mv_align_huge(stab_result_t *r)
{
    int64_t ms[24] = { 0, 1, -1, 65535, -65536, 1 << 30, -(1 << 30), (1 << 30) - 1, -(1 << 30) + 1, INT32_MAX,
                       INT32_MIN, INT32_MAX - 1, INT32_MIN + 1 };
    uint32_t st = 5;
    for (int i = 13; i < 24; i++)
        st = hz_hash32(st), ms[i] = (int32_t)st;
    uint64_t checked = 0, saturated = 0;
    for (unsigned align = 1; align <= 15; align++) {
        const int64_t step = (int64_t)align << 16;
        for (int i = 0; i < 24; i++) {
            const int64_t m = ms[i];
            int64_t q = m >= 0 ? m / step : -((-m + step - 1) / step);
            int64_t lo = q * step, hi = lo + step, frac = ((m - lo) << 16) / step;
            uint32_t ups = 0;
            /* every hash value where the weights are counted (the fixed inputs, four alignments), else a sample */
            const bool count = i < 13 && (align == 1 || align == 3 || align == 5 || align == 15);
            for (uint32_t u = 0; u < 65536u; u += (count ? 1u : 257u)) {
                for (int axis = 0; axis < 2; axis++) {
                    int32_t v[2] = { (int32_t)m, (int32_t)m };
                    hz_dither_align_mv(v, align, axis ? u << 16 : u);
                    int64_t got = v[axis];
                    const bool fits_hi = hi <= INT32_MAX, fits_lo = lo >= INT32_MIN;
                    STAB_CHECK(r, got % step == 0, "align %u of %lld: %lld is not a multiple", align, (long long)m,
                               (long long)got);
                    STAB_CHECK(r, got == lo || got == hi, "align %u of %lld: %lld is neither %lld nor %lld", align,
                               (long long)m, (long long)got, (long long)lo, (long long)hi);
                    STAB_CHECK(r, (got != hi || fits_hi) && (got != lo || fits_lo),
                               "align %u of %lld: %lld does not fit 32 bits", align, (long long)m, (long long)got);
                    if (fits_hi && fits_lo && axis == 0)
                        ups += got == hi;
                    saturated += (!fits_hi || !fits_lo) && axis == 0;
                    checked++;
                }
            }
            if (count && hi <= INT32_MAX && lo >= INT32_MIN)
                STAB_CHECK(r, ups == (uint32_t)frac, "align %u of %lld: upper multiple %u times of 65536, want %lld",
                           align, (long long)m, ups, (long long)frac);
        }
    }
    r->status = HZ_OK;
    stab_note(r, "%llu alignments: floor or ceil multiple; bilinear counts exact; %llu at the int32 ends saturated",
              (unsigned long long)checked, (unsigned long long)saturated);
}

/* A blended quad (alpha 0.5) of half-size 1e8 sliding ~1e6 px per frame, and one at 1e30 px (speed near the
 * float range): TAA with every stochastic method (cell mean, 7x7 window) stays finite. */
static void c_dither_huge_motion(stab_result_t *r)
{
    static const float speeds[2] = { 1e7f, 1e30f };
    static float img[W * H * 3];
    for (int k = 0; k < 2; k++) {
        su_scene_t b;
        su_begin(&b);
        uint32_t m0 = su_material(&b, 0.6f, 0.6f, 0.6f), m1 = su_material_alpha(&b, 0.2f, 0.7f, 0.3f, 0.5f,
                                                                                   HZ_ALPHA_BLEND);
        const float w0[3] = { -8, -8, -3 }, w1[3] = { 8, -8, -3 }, w2[3] = { 8, 8, -3 }, w3[3] = { -8, 8, -3 };
        su_quad(&b, w0, w1, w2, w3, m0);
        su_object(&b);
        const float s = 1e8f, q0[3] = { -s, -s, 0 }, q1[3] = { s, -s, 0 }, q2[3] = { s, s, 0 }, q3[3] = { -s, s, 0 };
        su_quad(&b, q0, q1, q2, q3, m1);
        hz_hzb_object_t *o = su_object(&b);
        o->motion = HZ_MOTION_OSCILLATE, o->params[0] = speeds[k], o->params[3] = 0.76f;
        su_light(&b, 2, 3, 6, 60);
        const float eye[3] = { 0, 0, 6 }, target[3] = { 0, 0, 0 };
        su_camera(&b, 0, eye, target, 1.0f);
        for (size_t m = 0; m < NMETHODS; m++) {
            render_m(r, &b, &methods[m], HZ_MODE_TAA, 4, img);
            STAB_BAIL(r);
        }
    }
    stab_note(r, "oscillation amplitude 1e7 and 1e30 under 7 methods x 4 TAA frames: finite");
}

static const stab_case_t cases[] = {
    { "dither_alpha_0", "alpha 0 under rr/std/dtaa/dtaa-star/hybrid:0/0.5/1: = no layer (1e-4); TAA finite",
      c_alpha_0, 0 },
    { "dither_alpha_1e-30", "alpha 1e-30 under 7 methods: dropped = no layer (1e-4)", c_alpha_1e_30, 0 },
    { "dither_alpha_0.01", "alpha 0.01 (the documented cut) under 7 methods: dropped = no layer (1e-4)",
      c_alpha_cut, 0 },
    { "dither_alpha_1-1e-7", "alpha 1 - 1e-7 under 7 methods: kept = opaque layer (1e-5)", c_alpha_1m1e_7, 0 },
    { "dither_alpha_1", "alpha 1 under 7 methods: kept = opaque layer (1e-6)", c_alpha_1, 0 },
    { "dither_stacked_1000", "1000 layers of alpha 0.5 under 7 methods: every pixel a value of the rule (1e-4); "
                             "coverage ~ alpha", c_stacked_1000, 0 },
    { "dither_stacked_1000_cut", "1000 layers of alpha 0.01: dropped by every stochastic ray; rule (1e-4)",
      c_stacked_1000_cut, 0 },
    { "dither_stacked_1000_thin", "1000 layers of alpha 0.02: rule (1e-4); coverage ~ alpha",
      c_stacked_1000_thin, STAB_FULL_ONLY },
    { "std_thresholds", "STD/DTAA thresholds = formula over all maps; 0 and 8/9 reached; max < 1; decision edges",
      c_std_thresholds, 0 },
    { "cell_keep", "division-free STD/DTAA decisions from the per-sample cell = formula at every threshold edge",
      c_cell_keep, 0 },
    { "mv_align_huge", "mv alignment at +-2^30 and the int32 ends: floor/ceil multiple; saturates; exact weights",
      c_mv_align_huge, 0 },
    { "dither_huge_motion", "1e6 px and 1e30 motion under 7 methods in TAA: finite", c_dither_huge_motion, 0 },
};
STAB_STAGE(dither, cases);
