/* 2x2 tile orderings and ĝ(ℓf, α) (src/pattern/tileorder.c): the 24 orderings and their classes, the integer
 * angle and length against libm, a table of (motion, expected pattern) cases, the random band's statistics, the
 * 4-frame schedule, and golden hashes that x86-64 and AArch64 (under qemu) must both reproduce. The golden
 * values come from an independent Python model: tools/gen/tileorder_golden.py. */
#include "hz_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hz/hash.h"
#include "hz/tileorder.h"

#define PI 3.14159265358979323846
#define HG HZ_TILECYCLE_HOURGLASS
#define BT HZ_TILECYCLE_BOWTIE
#define SQ HZ_TILECYCLE_SQUARE

static void test_table_is_lexicographic_permutations(void **state)
{
    (void)state;
    /* Enumerate the permutations independently (nested loops in lexicographic order) and compare. */
    unsigned o = 0;
    for (uint8_t a = 0; a < 4; a++)
        for (uint8_t b = 0; b < 4; b++)
            for (uint8_t c = 0; c < 4; c++)
                for (uint8_t d = 0; d < 4; d++) {
                    if (a == b || a == c || a == d || b == c || b == d || c == d)
                        continue;
                    const uint8_t seq[4] = { a, b, c, d };
                    assert_int_equal(hz_tileorder_index(seq), (int)o);
                    for (unsigned s = 0; s < 4; s++) {
                        assert_int_equal(hz_tileorder_pixel(o, s), seq[s]);
                        assert_int_equal(hz_tileorder_subframe(o, seq[s]), s);
                    }
                    o++;
                }
    assert_int_equal(o, HZ_TILEORDER_COUNT);
    const uint8_t dup[4] = { 0, 1, 1, 3 }, big[4] = { 0, 1, 2, 4 };
    assert_int_equal(hz_tileorder_index(dup), -1);
    assert_int_equal(hz_tileorder_index(big), -1);
}

static void test_every_ordering_visits_all_pixels(void **state)
{
    (void)state;
    for (unsigned o = 0; o < HZ_TILEORDER_COUNT; o++) {
        /* Any four consecutive frames (any starting subframe) trace each pixel exactly once. */
        for (uint32_t start = 0; start < 8; start++) {
            unsigned seen = 0;
            for (uint32_t f = start; f < start + 4; f++)
                seen |= 1u << hz_tileorder_pixel(o, hz_tdense_subframe(f));
            assert_int_equal(seen, 0xf);
        }
    }
}

/* Transpose of a pixel index: swap row and column. */
static unsigned transpose(unsigned p)
{
    return ((p & 1u) << 1) | (p >> 1);
}

static void test_cycle_classes(void **state)
{
    (void)state;
    unsigned count[3] = { 0, 0, 0 };
    for (unsigned o = 0; o < HZ_TILEORDER_COUNT; o++) {
        hz_tilecycle_t c = hz_tileorder_cycle(o);
        count[c]++;
        /* Geometry, checked with coordinates instead of index bits: sum the steps of the closed path. */
        int diag = 0, horiz = 0, vert = 0;
        for (unsigned s = 0; s < 4; s++) {
            unsigned p = hz_tileorder_pixel(o, s), q = hz_tileorder_pixel(o, s + 1);
            int dx = (int)(q % 2) - (int)(p % 2), dy = (int)(q / 2) - (int)(p / 2);
            diag += dx != 0 && dy != 0;
            horiz += dx != 0 && dy == 0;
            vert += dx == 0 && dy != 0;
        }
        if (c == SQ) {
            assert_int_equal(diag, 0);
            assert_int_equal(horiz, 2);
            assert_int_equal(vert, 2);
        } else {
            assert_int_equal(diag, 2); /* the two crossing diagonals of ⧗ and ⋈ */
            assert_int_equal(horiz, c == HG ? 2 : 0);
            assert_int_equal(vert, c == BT ? 2 : 0);
        }
        /* Every rotation (other start) and the reversal of an ordering stay in its class. */
        for (unsigned r = 0; r < 4; r++) {
            uint8_t rot[4], rev[4];
            for (unsigned s = 0; s < 4; s++) {
                rot[s] = (uint8_t)hz_tileorder_pixel(o, s + r);
                rev[s] = (uint8_t)hz_tileorder_pixel(o, r + 4 - s);
            }
            assert_int_equal(hz_tileorder_cycle((unsigned)hz_tileorder_index(rot)), c);
            assert_int_equal(hz_tileorder_cycle((unsigned)hz_tileorder_index(rev)), c);
        }
        /* Transposing the tile swaps hourglass and bowtie and keeps the square. */
        uint8_t tr[4];
        for (unsigned s = 0; s < 4; s++)
            tr[s] = (uint8_t)transpose(hz_tileorder_pixel(o, s));
        hz_tilecycle_t ct = hz_tileorder_cycle((unsigned)hz_tileorder_index(tr));
        assert_int_equal(ct, c == HG ? BT : c == BT ? HG : SQ);
    }
    assert_int_equal(count[SQ], 8);
    assert_int_equal(count[HG], 8);
    assert_int_equal(count[BT], 8);
    /* The canonical orderings (Fig. 4): hourglass 0 1 / 2 3, bowtie 0 2 / 1 3 (subframe of each pixel). */
    const unsigned hg_layout[4] = { 0, 1, 2, 3 }, bt_layout[4] = { 0, 2, 1, 3 }, sq_layout[4] = { 0, 1, 3, 2 };
    for (unsigned p = 0; p < 4; p++) {
        assert_int_equal(hz_tileorder_subframe(hz_tileorder_of_cycle(HG), p), hg_layout[p]);
        assert_int_equal(hz_tileorder_subframe(hz_tileorder_of_cycle(BT), p), bt_layout[p]);
        assert_int_equal(hz_tileorder_subframe(hz_tileorder_of_cycle(SQ), p), sq_layout[p]);
    }
    assert_int_equal(hz_tileorder_cycle(HZ_TILEORDER_HOURGLASS), HG);
    assert_int_equal(hz_tileorder_cycle(HZ_TILEORDER_BOWTIE), BT);
    assert_int_equal(hz_tileorder_cycle(HZ_TILEORDER_SQUARE), SQ);
    assert_string_equal(hz_tilecycle_name(HG), "hourglass");
    assert_string_equal(hz_tilecycle_name(BT), "bowtie");
    assert_string_equal(hz_tilecycle_name(SQ), "square");
}

__extension__ typedef unsigned __int128 u128;

static hz_q16_t q16(double v)
{
    return (hz_q16_t)lrint(v * 65536.0);
}

static void test_angle_against_libm(void **state)
{
    (void)state;
    /* Exact cases first, then the CORDIC result against libm over all magnitudes. */
    assert_int_equal(hz_tileorder_angle(0, 0), 0);
    assert_int_equal(hz_tileorder_angle(q16(3), 0), 0);
    assert_int_equal(hz_tileorder_angle(q16(-3), 0), 0);
    assert_int_equal(hz_tileorder_angle(0, q16(-0.5)), HZ_QANGLE_RIGHT);
    assert_int_equal(hz_tileorder_angle(q16(2), q16(-2)), HZ_QANGLE_DIAG);
    assert_int_equal(hz_tileorder_angle(INT32_MIN, INT32_MIN), HZ_QANGLE_DIAG);
    assert_int_equal(hz_tileorder_angle(INT32_MIN, 0), 0);
    hz_rng_t r;
    hz_rng_seed(&r, 17, 1);
    int64_t worst = 0;
    for (int i = 0; i < 200000; i++) {
        int32_t mx = (int32_t)hz_rng_u32(&r) >> (hz_rng_u32(&r) & 31);
        int32_t my = (int32_t)hz_rng_u32(&r) >> (hz_rng_u32(&r) & 31);
        double ref = atan2(fabs((double)my), fabs((double)mx)) / (PI / 2) * 1073741824.0;
        int64_t err = llabs((int64_t)hz_tileorder_angle(mx, my) - (int64_t)llrint(ref));
        if (err > worst)
            worst = err;
        /* Symmetry: the four quadrants and the sign of zero give the same folded angle. */
        if (mx != INT32_MIN && my != INT32_MIN) {
            assert_int_equal(hz_tileorder_angle(-mx, my), hz_tileorder_angle(mx, my));
            assert_int_equal(hz_tileorder_angle(mx, -my), hz_tileorder_angle(mx, my));
        }
    }
    /* Within one unit of 2^-30 quarter turns (1.5e-9 rad). */
    assert_true(worst <= 1);
    /* γ is π/40. */
    assert_true(fabs(HZ_QANGLE_GAMMA / 1073741824.0 * (PI / 2) - PI / 40) < 2e-9);
}

static void test_length_frac_exact(void **state)
{
    (void)state;
    assert_int_equal(hz_tileorder_length_frac(0, 0), 0);
    assert_int_equal(hz_tileorder_length_frac(q16(0.25), 0), q16(0.25));
    assert_int_equal(hz_tileorder_length_frac(0, q16(-0.75)), q16(0.75));
    assert_int_equal(hz_tileorder_length_frac(q16(3), q16(4)), 0);     /* |(3,4)| = 5 */
    assert_int_equal(hz_tileorder_length_frac(q16(0.375), q16(0.5)), q16(0.625));
    assert_int_equal(hz_tileorder_length_frac(INT32_MIN, 0), 0);       /* 32768 px */
    assert_int_equal(hz_tileorder_length_frac(INT32_MIN, INT32_MIN), /* 32768 * sqrt(2) */
                     (hz_q16_t)((uint32_t)floor(32768.0 * sqrt(2.0) * 65536.0) & 0xffffu));
    hz_rng_t r;
    hz_rng_seed(&r, 5, 2);
    for (int i = 0; i < 100000; i++) {
        int32_t mx = (int32_t)hz_rng_u32(&r) >> (hz_rng_u32(&r) & 31);
        int32_t my = (int32_t)hz_rng_u32(&r) >> (hz_rng_u32(&r) & 31);
        /* ℓ in Q16.16 is floor(sqrt(mx^2 + my^2)): check the defining inequality in 128-bit arithmetic. */
        u128 sum = (u128)((int64_t)mx * mx) + (u128)((int64_t)my * my);
        hz_q16_t lf = hz_tileorder_length_frac(mx, my);
        assert_true(lf >= 0 && lf < HZ_Q16_ONE);
        uint64_t approx = (uint64_t)sqrt((double)sum);
        uint64_t len = approx;
        while ((u128)len * len > sum)
            len--;
        while ((u128)(len + 1) * (len + 1) <= sum)
            len++;
        assert_int_equal(lf, (hz_q16_t)(len & 0xffffu));
    }
}

/* Motion of length `len` px in direction `deg` degrees, quadrant chosen by the signs. */
static void polar(double len, double deg, int sx, int sy, hz_q16_t *mx, hz_q16_t *my)
{
    *mx = sx * q16(len * cos(deg * PI / 180.0));
    *my = sy * q16(len * sin(deg * PI / 180.0));
}

typedef struct ghat_case {
    double len, deg;
    hz_tilecycle_t expect;
    const char *why;
} ghat_case_t;

static void test_ghat_table(void **state)
{
    (void)state;
    /* Expected patterns derived by hand from the rule in hz/tileorder.h. With t = α / 90°, the shear-up band
     * (below the random band) is hourglass iff frac(ℓf - t/2) in (0.25, 0.75); shear-down (above) iff
     * frac(ℓf + t/2) in (0.25, 0.75). */
    static const ghat_case_t cases[] = {
        /* horizontal (Eq. 4) */
        { 0.5, 0, HG, "horizontal, lf 0.5" },
        { 1.5, 0, HG, "horizontal, lf 0.5 after the integer part" },
        { 0.1, 0, BT, "horizontal, lf 0.1" },
        { 0.9, 0, BT, "horizontal, lf 0.9" },
        { 7.3, 0, HG, "horizontal, lf 0.3" },
        { 2.0, 0, BT, "horizontal, lf 0" },
        /* vertical (Eq. 5) */
        { 0.5, 90, BT, "vertical, lf 0.5" },
        { 0.1, 90, HG, "vertical, lf 0.1" },
        { 0.9, 90, HG, "vertical, lf 0.9" },
        { 3.6, 90, BT, "vertical, lf 0.6" },
        /* lower transition (shear up), 10°: t/2 = 0.0556 -> hourglass band (0.3056, 0.8056) */
        { 0.28, 10, BT, "10 deg, lf 0.28: Eq. 4 alone would say hourglass" },
        { 0.78, 10, HG, "10 deg, lf 0.78: Eq. 4 alone would say bowtie" },
        /* 22.5°: t/2 = 0.125 -> band (0.375, 0.875) */
        { 0.3, 22.5, BT, "22.5 deg, lf 0.3" },
        { 0.5, 22.5, HG, "22.5 deg, lf 0.5" },
        { 0.8, 22.5, HG, "22.5 deg, lf 0.8" },
        { 0.95, 22.5, BT, "22.5 deg, lf 0.95" },
        { 12.8, 22.5, HG, "22.5 deg, lf 0.8 after 12 px" },
        /* 40° (just below the band, 40.5°): t/2 = 0.2222 -> band (0.4722, 0.9722) */
        { 0.45, 40, BT, "40 deg, lf 0.45" },
        { 0.95, 40, HG, "40 deg, lf 0.95" },
        /* upper transition (shear down), 50°: t/2 = 0.2778 -> hourglass iff lf in (0.9722, 1) or [0, 0.4722) */
        { 0.45, 50, HG, "50 deg, lf 0.45" },
        { 0.95, 50, BT, "50 deg, lf 0.95" },
        /* 67.5°: t/2 = 0.375 -> hourglass iff lf in (0.875, 1) or [0, 0.375) */
        { 0.3, 67.5, HG, "67.5 deg, lf 0.3: Eq. 5 alone would say bowtie" },
        { 0.6, 67.5, BT, "67.5 deg, lf 0.6" },
        { 0.9, 67.5, HG, "67.5 deg, lf 0.9" },
        /* 80°: t/2 = 0.4444 -> hourglass iff lf in (0.8056, 1) or [0, 0.3056) */
        { 0.28, 80, HG, "80 deg, lf 0.28" },
        { 0.32, 80, BT, "80 deg, lf 0.32" },
        { 0.82, 80, HG, "80 deg, lf 0.82" },
    };
    for (size_t i = 0; i < HZ_ARRAY_LEN(cases); i++) {
        /* Every quadrant gives the same answer (symmetry), and the random word must not matter here. */
        for (int q = 0; q < 4; q++) {
            hz_q16_t mx, my;
            polar(cases[i].len, cases[i].deg, (q & 1) ? -1 : 1, (q & 2) ? -1 : 1, &mx, &my);
            for (uint32_t rnd = 0; rnd < 2; rnd++) {
                hz_tilecycle_t got = hz_tileorder_ghat(mx, my, rnd << 31, HZ_GHAT_FULL);
                if (got != cases[i].expect)
                    fail_msg("%s (quadrant %d): got %s, want %s", cases[i].why, q, hz_tilecycle_name(got),
                             hz_tilecycle_name(cases[i].expect));
            }
        }
    }
}

static void test_ghat_boundaries_zero_and_huge(void **state)
{
    (void)state;
    const hz_q16_t ulp = 1, quarter = HZ_Q16_ONE / 4, three = 3 * HZ_Q16_ONE / 4;
    /* Exactly on 0.25 / 0.75: open interval for horizontal (bowtie), closed for vertical (hourglass). */
    assert_int_equal(hz_tileorder_ghat(quarter, 0, 0, HZ_GHAT_FULL), BT);
    assert_int_equal(hz_tileorder_ghat(three, 0, 0, HZ_GHAT_FULL), BT);
    assert_int_equal(hz_tileorder_ghat(quarter + ulp, 0, 0, HZ_GHAT_FULL), HG);
    assert_int_equal(hz_tileorder_ghat(three - ulp, 0, 0, HZ_GHAT_FULL), HG);
    assert_int_equal(hz_tileorder_ghat(-quarter, 0, 0, HZ_GHAT_FULL), BT);
    assert_int_equal(hz_tileorder_ghat(-(5 * HZ_Q16_ONE + three), 0, 0, HZ_GHAT_FULL), BT);
    assert_int_equal(hz_tileorder_ghat(0, quarter, 0, HZ_GHAT_FULL), HG);
    assert_int_equal(hz_tileorder_ghat(0, -three, 0, HZ_GHAT_FULL), HG);
    assert_int_equal(hz_tileorder_ghat(0, quarter + ulp, 0, HZ_GHAT_FULL), BT);
    assert_int_equal(hz_tileorder_ghat(0, -(three - ulp), 0, HZ_GHAT_FULL), BT);
    /* Off-axis, exactly on the boundaries: (0.75, 1) has |m| = 1.25, (2.25, 3) has 3.75, both at 53.13°,
     * shear down by t/2 = 0.2952: frac(0.25 + 0.2952) -> hourglass, frac(0.75 + 0.2952) = 0.0452 -> bowtie. */
    assert_int_equal(hz_tileorder_length_frac(q16(0.75), q16(1)), quarter);
    assert_int_equal(hz_tileorder_ghat(q16(0.75), q16(1), 0, HZ_GHAT_FULL), HG);
    assert_int_equal(hz_tileorder_length_frac(q16(-2.25), q16(3)), three);
    assert_int_equal(hz_tileorder_ghat(q16(-2.25), q16(3), 0, HZ_GHAT_FULL), BT);
    /* Zero motion reads as horizontal with lf = 0: bowtie (it only matters for static tiles, where the
     * ordering has no visible effect). */
    assert_int_equal(hz_tileorder_ghat(0, 0, 0, HZ_GHAT_FULL), BT);
    assert_int_equal(hz_tileorder_ghat(0, 0, 0xffffffffu, HZ_GHAT_FULL), BT);
    /* Huge and saturated motion. */
    assert_int_equal(hz_tileorder_ghat(INT32_MIN, 0, 0, HZ_GHAT_FULL), BT);             /* 32768.0 */
    assert_int_equal(hz_tileorder_ghat(INT32_MAX, 0, 0, HZ_GHAT_FULL), BT);             /* 32767.99998 */
    assert_int_equal(hz_tileorder_ghat(q16(-20000.5), 0, 0, HZ_GHAT_FULL), HG);
    assert_int_equal(hz_tileorder_ghat(0, q16(30000.5), 0, HZ_GHAT_FULL), BT);
    hz_q16_t mx, my;
    polar(10000.5, 22.5, -1, 1, &mx, &my); /* lf ~0.5 within 2^-15: inside (0.375, 0.875) */
    assert_int_equal(hz_tileorder_ghat(mx, my, 0, HZ_GHAT_FULL), HG);
    /* The exact diagonal is in the random band, at any length. */
    assert_int_equal(hz_tileorder_ghat(INT32_MIN, INT32_MAX, 0, HZ_GHAT_FULL), BT);
    assert_int_equal(hz_tileorder_ghat(INT32_MIN, INT32_MAX, 0x80000000u, HZ_GHAT_FULL), HG);
}

static void test_ghat_band_edges_and_rules(void **state)
{
    (void)state;
    const hz_qangle_t lo = HZ_QANGLE_DIAG - HZ_QANGLE_GAMMA, hi = HZ_QANGLE_DIAG + HZ_QANGLE_GAMMA;
    /* lf = 0.95 at the band edges: shear up at lo (t/2 = 0.225 -> 0.725 in band: hourglass); random just
     * inside; shear down at hi (t/2 = 0.275 -> frac(1.225) = 0.225 out of band: bowtie). */
    const hz_q16_t lf = q16(0.95);
    assert_int_equal(hz_tileorder_ghat_polar(lf, lo, 0, HZ_GHAT_FULL), HG);
    assert_int_equal(hz_tileorder_ghat_polar(lf, lo, 0x80000000u, HZ_GHAT_FULL), HG);
    assert_int_equal(hz_tileorder_ghat_polar(lf, lo + 1, 0, HZ_GHAT_FULL), BT);
    assert_int_equal(hz_tileorder_ghat_polar(lf, lo + 1, 0x80000000u, HZ_GHAT_FULL), HG);
    assert_int_equal(hz_tileorder_ghat_polar(lf, hi - 1, 0, HZ_GHAT_FULL), BT);
    assert_int_equal(hz_tileorder_ghat_polar(lf, hi - 1, 0x80000000u, HZ_GHAT_FULL), HG);
    assert_int_equal(hz_tileorder_ghat_polar(lf, hi, 0x80000000u, HZ_GHAT_FULL), BT);
    assert_int_equal(hz_tileorder_ghat_polar(lf, hi, 0, HZ_GHAT_FULL), BT);
    /* Only the top bit of the random word counts. */
    assert_int_equal(hz_tileorder_ghat_polar(lf, HZ_QANGLE_DIAG, 0x7fffffffu, HZ_GHAT_FULL), BT);
    /* The comparison rules of Fig. 10. */
    hz_q16_t mx, my;
    polar(0.5, 42, 1, 1, &mx, &my); /* |mx| > |my| */
    assert_int_equal(hz_tileorder_ghat(mx, my, 0, HZ_GHAT_DOMINANT), HG);
    polar(0.5, 48, 1, -1, &mx, &my);
    assert_int_equal(hz_tileorder_ghat(mx, my, 0, HZ_GHAT_DOMINANT), BT);
    assert_int_equal(hz_tileorder_ghat(q16(0.1), q16(0.1), 0, HZ_GHAT_DOMINANT), BT); /* |m| 0.1414, horizontal */
    /* At 45° the shear-up band is (0.5, 1) and the shear-down band (0, 0.5). */
    polar(0.7, 45, 1, 1, &mx, &my);
    assert_int_equal(hz_tileorder_ghat(mx, my, 0, HZ_GHAT_SHEAR_UP), HG);
    assert_int_equal(hz_tileorder_ghat(mx, my, 0, HZ_GHAT_SHEAR_DOWN), BT);
    polar(0.3, 45, 1, 1, &mx, &my);
    assert_int_equal(hz_tileorder_ghat(mx, my, 0, HZ_GHAT_SHEAR_UP), BT);
    assert_int_equal(hz_tileorder_ghat(mx, my, 0, HZ_GHAT_SHEAR_DOWN), HG);
    /* Forced patterns ignore the motion. */
    hz_rng_t r;
    hz_rng_seed(&r, 1, 1);
    for (int i = 0; i < 1000; i++) {
        int32_t a = (int32_t)hz_rng_u32(&r), b = (int32_t)hz_rng_u32(&r);
        assert_int_equal(hz_tileorder_ghat(a, b, hz_rng_u32(&r), HZ_GHAT_HOURGLASS), HG);
        assert_int_equal(hz_tileorder_ghat(a, b, hz_rng_u32(&r), HZ_GHAT_BOWTIE), BT);
        /* The full rule never picks the square. */
        assert_int_not_equal(hz_tileorder_ghat(a, b, hz_rng_u32(&r), HZ_GHAT_FULL), SQ);
    }
    assert_string_equal(hz_ghat_rule_name(HZ_GHAT_FULL), "full");
    assert_string_equal(hz_ghat_rule_name(HZ_GHAT_SHEAR_DOWN), "shear-down");
    assert_null(hz_ghat_rule_name(HZ_GHAT_RULE_COUNT));
}

static void test_random_band_statistics(void **state)
{
    (void)state;
    /* 64x64 tiles all moving at 45° (deep in the band) for 8 cycles: both choices occur, in about equal
     * shares overall, per cycle, and per tile over time. */
    enum { TX = 64, TY = 64, CYCLES = 8 };
    static hz_q16_t motion[TX * TY * 2];
    static uint8_t orders[TX * TY];
    static unsigned per_tile[TX * TY];
    for (unsigned i = 0; i < TX * TY; i++) {
        hz_q16_t mx, my;
        polar(0.3 + 0.01 * (i % 50), 43.0 + 0.001 * i, 1, (i & 1) ? 1 : -1, &mx, &my);
        motion[2 * i] = mx;
        motion[2 * i + 1] = my;
    }
    unsigned total = 0;
    for (uint32_t cycle = 0; cycle < CYCLES; cycle++) {
        hz_tileorder_choose(motion, TX, 0, TY, cycle, 1234u, HZ_GHAT_FULL, orders);
        unsigned hg = 0;
        for (unsigned i = 0; i < TX * TY; i++) {
            assert_true(orders[i] == HZ_TILEORDER_HOURGLASS || orders[i] == HZ_TILEORDER_BOWTIE);
            hg += orders[i] == HZ_TILEORDER_HOURGLASS;
            per_tile[i] += orders[i] == HZ_TILEORDER_HOURGLASS;
        }
        /* 4096 fair coin flips: mean 2048, sd 32; 45%..55% is more than 6 sd. */
        assert_true(hg > TX * TY * 45 / 100 && hg < TX * TY * 55 / 100);
        total += hg;
    }
    assert_true(total > TX * TY * CYCLES * 47 / 100 && total < TX * TY * CYCLES * 53 / 100);
    unsigned changed = 0;
    for (unsigned i = 0; i < TX * TY; i++)
        changed += per_tile[i] != 0 && per_tile[i] != CYCLES;
    assert_true(changed > TX * TY * 9 / 10); /* 1 - 2 * 2^-8 of the tiles expected */
    /* A different seed gives a different draw. */
    static uint8_t other[TX * TY];
    hz_tileorder_choose(motion, TX, 0, TY, 0, 4321u, HZ_GHAT_FULL, other);
    hz_tileorder_choose(motion, TX, 0, TY, 0, 1234u, HZ_GHAT_FULL, orders);
    assert_true(memcmp(other, orders, sizeof orders) != 0);
}

static void test_choose_rows_independent(void **state)
{
    (void)state;
    enum { TX = 37, TY = 23 };
    static hz_q16_t motion[TX * TY * 2];
    static uint8_t whole[TX * TY], split[TX * TY];
    hz_rng_t r;
    hz_rng_seed(&r, 77, 3);
    for (unsigned i = 0; i < TX * TY * 2; i++)
        motion[i] = (int32_t)hz_rng_u32(&r) >> (10 + (hz_rng_u32(&r) & 15));
    hz_tileorder_choose(motion, TX, 0, TY, 5, 9, HZ_GHAT_FULL, whole);
    memset(split, 0xee, sizeof split);
    for (size_t y0 = 0; y0 < TY; y0 += 4)
        hz_tileorder_choose(motion, TX, y0, y0 + 4 < TY ? y0 + 4 : TY, 5, 9, HZ_GHAT_FULL, split);
    assert_memory_equal(whole, split, sizeof whole);
    for (unsigned i = 0; i < TX * TY; i++) {
        uint32_t rnd = hz_tileorder_tile_random(i % TX, i / TX, 5, 9);
        assert_int_equal(whole[i], hz_tileorder_of_cycle(hz_tileorder_ghat(motion[2 * i], motion[2 * i + 1], rnd,
                                                                           HZ_GHAT_FULL)));
    }
}

static void test_schedule_and_jitter(void **state)
{
    (void)state;
    /* 16 frames: each (subframe, jitter) pair exactly once, so each pixel of a tile with a fixed ordering gets
     * all four MSAA positions; the jitter and the ordering only change at cycle starts. */
    unsigned seen[4] = { 0, 0, 0, 0 };
    for (uint32_t f = 0; f < 16; f++) {
        seen[hz_tdense_subframe(f)] |= 1u << hz_tdense_jitter_index(f);
        if (!hz_tdense_cycle_start(f))
            assert_int_equal(hz_tdense_jitter_index(f), hz_tdense_jitter_index(f - 1));
        assert_int_equal(hz_tdense_cycle(f), f / 4);
    }
    for (unsigned s = 0; s < 4; s++)
        assert_int_equal(seen[s], 0xf);
    assert_true(hz_tdense_cycle_start(0) && hz_tdense_cycle_start(4) && !hz_tdense_cycle_start(5));
    /* The standard 4x MSAA positions, in 1/16 px, summing to zero (centred). */
    const int8_t expect[4][2] = { { -2, -6 }, { 6, -2 }, { -6, 2 }, { 2, 6 } };
    int sx = 0, sy = 0;
    for (unsigned j = 0; j < 4; j++) {
        assert_int_equal(hz_msaa4_jitter16[j][0], expect[j][0]);
        assert_int_equal(hz_msaa4_jitter16[j][1], expect[j][1]);
        sx += hz_msaa4_jitter16[j][0];
        sy += hz_msaa4_jitter16[j][1];
    }
    assert_int_equal(sx, 0);
    assert_int_equal(sy, 0);
}

static uint32_t mix(uint32_t h, uint32_t v)
{
    return (h ^ v) * 0x01000193u;
}

static void test_golden_hash(void **state)
{
    (void)state;
    /* The sweep of tools/gen/tileorder_golden.py: an 81x81 grid of motions in steps of 0.05 px, 4096 random
     * motions over all magnitudes, and the extremes; angle, fractional length and all six rules. */
    uint32_t h_angle = 0x811c9dc5u, h_frac = 0x811c9dc5u, h_rule = 0x811c9dc5u;
    uint32_t k = 0;
    hz_rng_t r;
    hz_rng_seed(&r, 7, 11);
    const int32_t ext[7] = { INT32_MIN, INT32_MAX, -1, 0, 1, 1 << 14, 3 << 14 };
    for (int phase = 0; phase < 3; phase++) {
        int n = phase == 0 ? 81 * 81 : phase == 1 ? 4096 : 49;
        for (int i = 0; i < n; i++, k++) {
            int32_t mx, my;
            if (phase == 0) {
                mx = (i % 81 - 40) * 3277;
                my = (i / 81 - 40) * 3277;
            } else if (phase == 1) {
                mx = (int32_t)hz_rng_u32(&r);
                mx >>= hz_rng_u32(&r) & 31;
                my = (int32_t)hz_rng_u32(&r);
                my >>= hz_rng_u32(&r) & 31;
            } else {
                mx = ext[i / 7];
                my = ext[i % 7];
            }
            h_angle = mix(h_angle, hz_tileorder_angle(mx, my));
            h_frac = mix(h_frac, (uint32_t)hz_tileorder_length_frac(mx, my));
            uint32_t rnd = hz_tileorder_tile_random(k, 0, 3, 5);
            for (int rule = 0; rule < HZ_GHAT_RULE_COUNT; rule++)
                h_rule = mix(h_rule, (uint32_t)hz_tileorder_ghat(mx, my, rnd, (hz_ghat_rule_t)rule));
        }
    }
    assert_int_equal(k, 10706);
    assert_int_equal(h_angle, 0x3a98e0ccu);
    assert_int_equal(h_frac, 0x6dc5c6adu);
    assert_int_equal(h_rule, 0x8a150887u);
}

/* hz_tileorder_ghat stops its CORDIC as soon as every angle the remaining steps can reach gets the same decision
 * with the exact length (the shear's shift a >> 15 over that range moves the length's fraction by less than a
 * quarter without crossing a band edge, or the whole range lies in the random band), and the dominant rule
 * stops its square root once the rest of the digits cannot move the length across a band edge: the decisions
 * must be those of ĝ on the full-precision angle and length (hz_tileorder_ghat_polar on hz_tileorder_angle and
 * hz_tileorder_length_frac), for random motion of every scale, for motion whose angle lies within a few units
 * of a step of a >> 15 or of a band edge, and for lengths within a few ulps of a band edge, where stopping
 * early is least safe. */
static void test_ghat_early_cordic_decides_as_full(void **state)
{
    (void)state;
    static const hz_ghat_rule_t rules[] = { HZ_GHAT_FULL, HZ_GHAT_SHEAR_UP, HZ_GHAT_SHEAR_DOWN };
    hz_rng_t r;
    hz_rng_seed(&r, 23, 4);
    size_t checked = 0, edge = 0;
    for (int n = 0; n < 600000; n++) {
        int32_t mx, my;
        if (n % 4 == 1) {
            mx = (int32_t)hz_rng_u32(&r) >> (hz_rng_u32(&r) & 31);
            my = (int32_t)hz_rng_u32(&r) >> (hz_rng_u32(&r) & 31);
        } else if (n % 4 == 3) {
            /* a length whose fraction minus the shear lies within a few ulps of 0.25 or 0.75, where the
             * length's early stop is least safe */
            double a = (double)(hz_rng_u32(&r) % 1000000u + 1u) / 1000001.0 * (PI / 2.0);
            hz_q16_t tx = (hz_q16_t)lround(cos(a) * 65536.0 * 64.0), ty = (hz_q16_t)lround(sin(a) * 65536.0 * 64.0);
            double half_t = (double)(hz_tileorder_angle(tx, ty) >> 15) / 65536.0;
            double len = (double)(hz_rng_u32(&r) % 2048u) + ((hz_rng_u32(&r) & 1u) ? 0.25 : 0.75) +
                         ((hz_rng_u32(&r) & 1u) ? half_t : -half_t) +
                         (double)((int32_t)(hz_rng_u32(&r) % 9u) - 4) / 65536.0;
            mx = (int32_t)lround(len * cos(a) * 65536.0);
            my = (int32_t)lround(len * sin(a) * 65536.0);
            edge++;
        } else {
            /* an angle on a 2^15-unit step (or a band edge) of the full-precision angle, nudged by a few
             * units, at a random length from 1/64 px to 4096 px */
            uint32_t k = hz_rng_u32(&r) % ((HZ_QANGLE_RIGHT >> 15) + 1u);
            double units = (double)(k << 15);
            if ((n & 6) == 2)
                units = (double)(HZ_QANGLE_DIAG - HZ_QANGLE_GAMMA);
            else if ((n & 6) == 4)
                units = (double)(HZ_QANGLE_DIAG + HZ_QANGLE_GAMMA);
            units += (double)((int32_t)(hz_rng_u32(&r) % 17u) - 8);
            double a = units / (double)HZ_QANGLE_RIGHT * (PI / 2.0);
            double len = ldexp(1.0, (int)(hz_rng_u32(&r) % 19u) - 6) * (1.0 + (hz_rng_u32(&r) & 0xffffu) / 65536.0);
            mx = (int32_t)lround(len * cos(a) * 65536.0);
            my = (int32_t)lround(len * sin(a) * 65536.0);
            if (hz_rng_u32(&r) & 1u)
                mx = -mx;
            if (hz_rng_u32(&r) & 1u)
                my = -my;
            edge++;
        }
        if (mx == 0 || my == 0 || mx == INT32_MIN || my == INT32_MIN)
            continue;
        hz_q16_t lf = hz_tileorder_length_frac(mx, my);
        hz_qangle_t a = hz_tileorder_angle(mx, my);
        uint32_t rnd = hz_rng_u32(&r);
        /* dominant direction: Eq. 4 or Eq. 5 on the exact comparison of |mx| and |my| */
        bool band = lf > HZ_Q16_ONE / 4 && lf < 3 * HZ_Q16_ONE / 4;
        bool horizontal = (mx < 0 ? -(int64_t)mx : mx) >= (my < 0 ? -(int64_t)my : my);
        if (hz_tileorder_ghat(mx, my, rnd, HZ_GHAT_DOMINANT) != (horizontal == band ? HG : BT))
            fail_msg("rule dominant, motion (%d, %d) / 65536", mx, my);
        for (size_t k = 0; k < HZ_ARRAY_LEN(rules); k++) {
            hz_tilecycle_t want = hz_tileorder_ghat_polar(lf, a, rnd, rules[k]);
            hz_tilecycle_t got = hz_tileorder_ghat(mx, my, rnd, rules[k]);
            if (got != want)
                fail_msg("rule %s, motion (%d, %d) / 65536, angle %u: early %d, full %d", hz_ghat_rule_name(rules[k]),
                         mx, my, a, (int)got, (int)want);
            checked++;
        }
    }
    print_message("%zu decisions (%zu near a step or band edge) as on the full angle\n", checked, 3 * edge);
    assert_true(edge > 400000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table_is_lexicographic_permutations),
        cmocka_unit_test(test_every_ordering_visits_all_pixels),
        cmocka_unit_test(test_cycle_classes),
        cmocka_unit_test(test_angle_against_libm),
        cmocka_unit_test(test_length_frac_exact),
        cmocka_unit_test(test_ghat_table),
        cmocka_unit_test(test_ghat_boundaries_zero_and_huge),
        cmocka_unit_test(test_ghat_band_edges_and_rules),
        cmocka_unit_test(test_ghat_early_cordic_decides_as_full),
        cmocka_unit_test(test_random_band_statistics),
        cmocka_unit_test(test_choose_rows_independent),
        cmocka_unit_test(test_schedule_and_jitter),
        cmocka_unit_test(test_golden_hash),
    };
    return HZ_RUN(tests);
}
