/* Tests of the adaptive supersampling activity mask (hz/adaptive_mask.h): the Fig. 4 neighbour table, each
 * attribute's disagreement rule, Mitchell's contrast and its edge cases, flat regions and straight edges, a
 * brute-force double-precision oracle on random fields, packing, and a golden hash that x86-64 and AArch64
 * (under qemu) must both reproduce. The golden value comes from an independent Python model:
 * tools/gen/amask_golden.py. */
#include "hz_test.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "hz/adaptive_mask.h"

#define PI 3.14159265358979323846

static uint32_t fbits(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}

static float bitsf(uint32_t u)
{
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static uint32_t q16(double t)
{
    return (uint32_t)floor(t * 65536.0 + 0.5);
}

/* A pixel: grey colour v, object obj, normal +z, no shadow, untextured; no secondary hit. */
static hz_amask_px_t px(float v, uint16_t obj)
{
    hz_amask_px_t p;
    memset(&p, 0, sizeof p);
    p.rgb[0] = p.rgb[1] = p.rgb[2] = fbits(v);
    p.hit[0].object = obj;
    p.hit[0].n[2] = 127;
    p.hit[0].flags = HZ_AMASK_HIT;
    p.hit[1].object = 0xffff;
    return p;
}

static void test_neighbour_table(void **state)
{
    (void)state;
    /* Subpixel q lies in the quadrant (sx, sy) = (+-1, +-1) of its pixel; the three pixels touching that
     * quadrant's outer corner are (sx, 0), (sx, sy) and (0, sy). */
    for (int q = 0; q < 4; q++) {
        int sx = (q & 1) ? 1 : -1, sy = (q & 2) ? 1 : -1;
        bool seen[3] = { false, false, false };
        for (int k = 0; k < 3; k++) {
            int dx = hz_amask_neighbours[q][k][0], dy = hz_amask_neighbours[q][k][1];
            if (dx == sx && dy == 0)
                seen[0] = true;
            else if (dx == sx && dy == sy)
                seen[1] = true;
            else if (dx == 0 && dy == sy)
                seen[2] = true;
            else
                fail_msg("subpixel %d: neighbour (%d, %d) is not on its side", q, dx, dy);
        }
        assert_true(seen[0] && seen[1] && seen[2]);
    }
    /* The paper's names: top-left W, NW, N. */
    assert_int_equal(hz_amask_neighbours[0][0][0], -1);
    assert_int_equal(hz_amask_neighbours[0][0][1], 0);
    assert_int_equal(hz_amask_neighbours[0][1][0], -1);
    assert_int_equal(hz_amask_neighbours[0][1][1], -1);
}

static void test_defaults_are_table2(void **state)
{
    (void)state;
    hz_amask_config_t c;
    hz_amask_config_default(&c);
    assert_int_equal(c.tau[HZ_TAU_COL], q16(0.6));
    assert_int_equal(c.tau[HZ_TAU_PTE], q16(0.6));
    assert_int_equal(c.tau[HZ_TAU_STE], q16(0.6));
    assert_int_equal(c.tau[HZ_TAU_POID], q16(0.05));
    assert_int_equal(c.tau[HZ_TAU_SOID], q16(0.05));
    assert_int_equal(c.tau[HZ_TAU_PSN], q16(0.06));
    assert_int_equal(c.tau[HZ_TAU_SSN], q16(0.06));
    assert_int_equal(c.tau[HZ_TAU_PSC], q16(0.06));
    assert_int_equal(c.tau[HZ_TAU_SSC], q16(0.06));
    assert_int_equal(c.normal_cos, (int32_t)floor(cos(15.0 * PI / 180.0) * 32768.0 + 0.5));
    assert_int_equal(hz_amask_channel_q16[0], q16(1.36));
    assert_int_equal(hz_amask_channel_q16[1], q16(1.02));
    assert_int_equal(hz_amask_channel_q16[2], q16(2.04));
}

/* Disagreement of P with three copies of Q. */
static uint32_t dis(const hz_amask_config_t *c, const hz_amask_px_t *p, const hz_amask_px_t *q, uint32_t *tau)
{
    const hz_amask_px_t *nb[3] = { q, q, q };
    return hz_amask_disagree(c, p, nb, tau);
}

static void test_attribute_rules(void **state)
{
    (void)state;
    hz_amask_config_t c;
    hz_amask_config_default(&c);
    uint32_t tau;
    hz_amask_px_t p = px(0.5f, 3), q = p;
    assert_int_equal(dis(&c, &p, &q, &tau), 0);
    assert_int_equal(tau, c.tau[HZ_TAU_COL]);
    /* object id */
    q.hit[0].object = 4;
    assert_int_equal(dis(&c, &p, &q, &tau), HZ_AMASK_BIT(HZ_TAU_POID));
    assert_int_equal(tau, c.tau[HZ_TAU_POID]);
    /* shadow count */
    q = p;
    q.hit[0].shadow = 1;
    assert_int_equal(dis(&c, &p, &q, &tau), HZ_AMASK_BIT(HZ_TAU_PSC));
    assert_int_equal(tau, c.tau[HZ_TAU_PSC]);
    /* texture existence: on whenever P is textured, even among identical neighbours; not when only Q is */
    q = p;
    q.hit[0].flags |= HZ_AMASK_TEXTURED;
    assert_int_equal(dis(&c, &p, &q, &tau), 0);
    p.hit[0].flags |= HZ_AMASK_TEXTURED;
    assert_int_equal(dis(&c, &p, &p, &tau), HZ_AMASK_BIT(HZ_TAU_PTE));
    assert_int_equal(tau, c.tau[HZ_TAU_PTE]);
    /* secondary hit: each class has its own bit */
    p = px(0.5f, 3);
    p.hit[1].object = 7;
    p.hit[1].flags = HZ_AMASK_HIT | HZ_AMASK_TEXTURED;
    p.hit[1].n[1] = 127;
    q = p;
    q.hit[1].object = 8;
    q.hit[1].shadow = 2;
    q.hit[1].n[1] = 0, q.hit[1].n[0] = 127;
    assert_int_equal(dis(&c, &p, &q, &tau), HZ_AMASK_BIT(HZ_TAU_SOID) | HZ_AMASK_BIT(HZ_TAU_SSC) |
                                                HZ_AMASK_BIT(HZ_TAU_SSN) | HZ_AMASK_BIT(HZ_TAU_STE));
    /* the smallest of the disagreeing thresholds */
    c.tau[HZ_TAU_SSN] = 100, c.tau[HZ_TAU_SOID] = 50, c.tau[HZ_TAU_SSC] = 70;
    dis(&c, &p, &q, &tau);
    assert_int_equal(tau, 50);
    /* 1 switches a class off: it no longer disagrees, and alone it falls back to tau_col (not to 1) */
    hz_amask_config_default(&c);
    c.tau[HZ_TAU_POID] = HZ_AMASK_ONE;
    p = px(0.5f, 3), q = px(0.5f, 4);
    assert_int_equal(dis(&c, &p, &q, &tau), 0);
    assert_int_equal(tau, c.tau[HZ_TAU_COL]);
    /* a class above tau_col replaces it where it disagrees */
    c.tau[HZ_TAU_POID] = q16(0.9);
    assert_int_equal(dis(&c, &p, &q, &tau), HZ_AMASK_BIT(HZ_TAU_POID));
    assert_int_equal(tau, q16(0.9));
    /* one disagreeing neighbour of three is enough */
    hz_amask_config_default(&c);
    const hz_amask_px_t *nb[3] = { &p, &p, &q };
    assert_int_equal(hz_amask_disagree(&c, &p, nb, &tau), HZ_AMASK_BIT(HZ_TAU_POID));
}

static hz_amask_px_t with_normal(double deg)
{
    hz_amask_px_t p = px(0.5f, 1);
    double r = deg * PI / 180.0;
    p.hit[0].n[0] = (int8_t)lround(127.0 * sin(r));
    p.hit[0].n[1] = 0;
    p.hit[0].n[2] = (int8_t)lround(127.0 * cos(r));
    return p;
}

static void test_normal_rule(void **state)
{
    (void)state;
    hz_amask_config_t c;
    hz_amask_config_default(&c);
    uint32_t tau;
    hz_amask_px_t p = with_normal(0);
    hz_amask_px_t a = with_normal(13), b = with_normal(17), anti = p;
    assert_int_equal(dis(&c, &p, &a, &tau), 0);
    assert_int_equal(dis(&c, &p, &b, &tau), HZ_AMASK_BIT(HZ_TAU_PSN));
    assert_int_equal(tau, c.tau[HZ_TAU_PSN]);
    /* antiparallel: the cross product is 0, yet the normals differ */
    anti.hit[0].n[2] = -127;
    assert_int_equal(dis(&c, &p, &anti, &tau), HZ_AMASK_BIT(HZ_TAU_PSN));
    /* misses: two agree, a miss and a hit differ (the object id differs too) */
    hz_amask_px_t m1 = px(0.5f, 0xffff), m2 = m1;
    memset(m1.hit[0].n, 0, 3), memset(m2.hit[0].n, 0, 3);
    m1.hit[0].flags = m2.hit[0].flags = 0;
    assert_int_equal(dis(&c, &m1, &m2, &tau), 0);
    assert_true(dis(&c, &p, &m1, &tau) & HZ_AMASK_BIT(HZ_TAU_PSN));
    /* the angle is configurable: 20 degrees accepts 17 */
    c.normal_cos = (int32_t)lround(cos(20.0 * PI / 180.0) * 32768.0);
    assert_int_equal(dis(&c, &p, &b, &tau), 0);
}

static void test_focus(void **state)
{
    (void)state;
    hz_amask_config_t c;
    hz_amask_config_default(&c);
    c.focus_count = 2;
    c.focus[0] = 5, c.focus[1] = 9;
    uint32_t tau;
    hz_amask_px_t p = px(0.5f, 3), q = px(0.5f, 4), f = px(0.5f, 9);
    assert_int_equal(dis(&c, &p, &q, &tau), 0); /* neither involved */
    assert_int_equal(tau, c.tau[HZ_TAU_COL]);
    assert_int_equal(dis(&c, &p, &f, &tau), HZ_AMASK_BIT(HZ_TAU_POID)); /* the neighbour is focused */
    assert_int_equal(dis(&c, &f, &p, &tau), HZ_AMASK_BIT(HZ_TAU_POID)); /* P is */
    p.hit[0].flags |= HZ_AMASK_TEXTURED;
    assert_int_equal(dis(&c, &p, &p, &tau), 0); /* texture existence only for focused objects */
    f.hit[0].flags |= HZ_AMASK_TEXTURED;
    assert_int_equal(dis(&c, &f, &f, &tau), HZ_AMASK_BIT(HZ_TAU_PTE));
    /* A focused mirror (object 5) reflecting objects 3 and 4, neither focused: its reflected hits take part, on
     * either side of the pair; the same reflections in an unfocused mirror (object 6) do not. */
    hz_amask_px_t m3 = px(0.5f, 5), m4 = px(0.5f, 5), u3 = px(0.5f, 6), u4 = px(0.5f, 6);
    m3.hit[1].object = u3.hit[1].object = 3, m4.hit[1].object = u4.hit[1].object = 4;
    m3.hit[1].n[2] = m4.hit[1].n[2] = u3.hit[1].n[2] = u4.hit[1].n[2] = 127;
    m3.hit[1].flags = m4.hit[1].flags = u3.hit[1].flags = u4.hit[1].flags = HZ_AMASK_HIT;
    assert_int_equal(dis(&c, &m3, &m4, &tau), HZ_AMASK_BIT(HZ_TAU_SOID));
    assert_int_equal(tau, c.tau[HZ_TAU_SOID]);
    assert_int_equal(dis(&c, &u3, &m4, &tau), HZ_AMASK_BIT(HZ_TAU_POID) | HZ_AMASK_BIT(HZ_TAU_SOID)); /* Q's */
    assert_int_equal(dis(&c, &u3, &u4, &tau), 0);
    m3.hit[1].flags |= HZ_AMASK_TEXTURED, u3.hit[1].flags |= HZ_AMASK_TEXTURED;
    assert_int_equal(dis(&c, &m3, &m3, &tau), HZ_AMASK_BIT(HZ_TAU_STE)); /* texture existence in the mirror */
    assert_int_equal(dis(&c, &u3, &u3, &tau), 0);
    /* the block (strips, shared pairs) agrees with the per-subpixel rule on a mirror edge */
    {
        enum { BW = 6, BH = 4 };
        hz_amask_px_t w[(BW + 2) * (BH + 2)];
        uint8_t mk[BW * BH];
        for (int i = 0; i < (BW + 2) * (BH + 2); i++) {
            const int x = i % (BW + 2), y = i / (BW + 2);
            w[i] = x < 4 ? (y & 1 ? m3 : m4) : (y & 1 ? u3 : u4);
            w[i].rgb[0] = fbits(x == 3 ? 0.9f : 0.5f);
        }
        hz_amask_block(&c, w, BW + 2, BW, BH, mk, BW);
        for (int y = 0; y < BH; y++)
            for (int x = 0; x < BW; x++)
                for (uint32_t q = 0; q < 4; q++) {
                    const hz_amask_px_t *nbq[3];
                    for (int k = 0; k < 3; k++)
                        nbq[k] = &w[(y + 1 + hz_amask_neighbours[q][k][1]) * (BW + 2) + x + 1 +
                                    hz_amask_neighbours[q][k][0]];
                    assert_int_equal((mk[y * BW + x] >> q) & 1u,
                                     hz_amask_subpixel(&c, &w[(y + 1) * (BW + 2) + x + 1], nbq) ? 1u : 0u);
                }
    }
}

static void test_contrast_values(void **state)
{
    (void)state;
    bool ok;
    uint32_t v[4] = { fbits(0.002f), fbits(0.001f), fbits(0.0015f), fbits(0.002f) };
    /* scale invariance: 1/3 at any brightness, denormals included */
    assert_int_equal(hz_amask_contrast_q16(v, 4, &ok), 21845);
    assert_true(ok);
    uint32_t big[2] = { fbits(2000.0f), fbits(1000.0f) }, tiny[2] = { fbits(2e-40f), fbits(1e-40f) };
    assert_int_equal(hz_amask_contrast_q16(big, 2, NULL), 21845);
    assert_int_equal(hz_amask_contrast_q16(tiny, 2, NULL), 21845);
    /* exact threshold: C = 1/3 passes at 21845/65536 and fails just above 1/3 */
    assert_true(hz_amask_contrast_at_least(v, 4, 21845));
    assert_false(hz_amask_contrast_at_least(v, 4, 21846));
    /* Imax + Imin = 0: C = 0, active only at threshold 0 */
    uint32_t black[4] = { 0, 0, fbits(-0.0f), 0 };
    assert_int_equal(hz_amask_contrast_q16(black, 4, &ok), 0);
    assert_true(ok);
    assert_true(hz_amask_contrast_at_least(black, 4, 0));
    assert_false(hz_amask_contrast_at_least(black, 4, 1));
    /* one value zero: full contrast, however dark the other */
    uint32_t one0[2] = { fbits(1e-6f), 0 };
    assert_int_equal(hz_amask_contrast_q16(one0, 2, NULL), 65536);
    assert_true(hz_amask_contrast_at_least(one0, 2, 65536));
    assert_false(hz_amask_contrast_at_least(one0, 2, 65537));
    /* negative counts as 0 */
    uint32_t neg[2] = { fbits(-3.0f), fbits(1.0f) };
    assert_int_equal(hz_amask_contrast_q16(neg, 2, NULL), 65536);
    /* NaN and Inf are left out; with fewer than two values left nothing activates, even at threshold 0 */
    uint32_t nan = 0x7fc00000u, inf = 0x7f800000u, ninf = 0xff800000u;
    uint32_t mix[4] = { nan, fbits(0.5f), inf, fbits(0.5f) };
    assert_int_equal(hz_amask_contrast_q16(mix, 4, &ok), 0);
    assert_true(ok);
    assert_false(hz_amask_contrast_at_least(mix, 4, 1));
    uint32_t lone[4] = { nan, fbits(0.5f), inf, ninf };
    assert_int_equal(hz_amask_contrast_q16(lone, 4, &ok), 0);
    assert_false(ok);
    assert_false(hz_amask_contrast_at_least(lone, 4, 0));
    /* the rounded C agrees with double arithmetic on random pairs */
    uint32_t s = 12345;
    for (int i = 0; i < 20000; i++) {
        s ^= s << 13, s ^= s >> 17, s ^= s << 5;
        float a = bitsf(s & 0x7f7fffffu);
        s ^= s << 13, s ^= s >> 17, s ^= s << 5;
        float b = a * ((float)(s & 0xffff) / 65536.0f);
        uint32_t pair[2] = { fbits(a), fbits(b) };
        double hi = a > b ? a : b, lo = a > b ? b : a;
        double want = hi + lo > 0 ? (hi - lo) / (hi + lo) * 65536.0 : 0.0;
        uint32_t got = hz_amask_contrast_q16(pair, 2, NULL);
        assert_true(fabs((double)got - want) <= 1.0);
    }
}

/* Window helper: a (w + 2) x (h + 2) field with replicated borders from an inner generator. */
#define W 12
#define H 10
static hz_amask_px_t win[(W + 2) * (H + 2)];
static uint8_t mask[W * H];

static void replicate(hz_amask_px_t inner[H][W])
{
    for (int y = -1; y <= H; y++)
        for (int x = -1; x <= W; x++) {
            int cx = x < 0 ? 0 : x >= W ? W - 1 : x, cy = y < 0 ? 0 : y >= H ? H - 1 : y;
            win[(y + 1) * (W + 2) + x + 1] = inner[cy][cx];
        }
}

static hz_amask_px_t field[H][W];

static void test_flat_region_and_nan(void **state)
{
    (void)state;
    hz_amask_config_t c;
    hz_amask_config_default(&c);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            field[y][x] = px(0.25f, 2);
            field[y][x].hit[0].flags |= HZ_AMASK_TEXTURED; /* tau_pte applies, C = 0 stays below it */
        }
    replicate(field);
    assert_int_equal(hz_amask_block(&c, win, W + 2, W, H, mask, W), 0);
    for (int i = 0; i < W * H; i++)
        assert_int_equal(mask[i], 0);
    /* a NaN and an Inf presample: they activate nothing, neither themselves nor their neighbours */
    field[4][4].rgb[0] = 0x7fc00000u, field[4][4].rgb[1] = 0xffc00001u, field[4][4].rgb[2] = 0x7f800000u;
    field[6][8].rgb[1] = 0x7f800000u;
    replicate(field);
    assert_int_equal(hz_amask_block(&c, win, W + 2, W, H, mask, W), 0);
    /* tau 0 supersamples everything (the paper's "always") */
    for (int k = 0; k < HZ_TAU_COUNT; k++)
        c.tau[k] = 0;
    field[4][4] = field[6][8] = px(0.25f, 2);
    replicate(field);
    assert_int_equal(hz_amask_block(&c, win, W + 2, W, H, mask, W), 4 * W * H);
}

static void test_straight_edges(void **state)
{
    (void)state;
    hz_amask_config_t c;
    hz_amask_config_default(&c);
    /* vertical edge between columns 4 and 5: column 4's right subpixels and column 5's left ones */
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            field[y][x] = x < 5 ? px(0.1f, 1) : px(0.8f, 2);
    replicate(field);
    assert_int_equal(hz_amask_block(&c, win, W + 2, W, H, mask, W), 4 * H);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            assert_int_equal(mask[y * W + x], x == 4 ? 0xa : x == 5 ? 0x5 : 0);
    /* horizontal edge between rows 2 and 3, same colours but different objects: only tau_poid = 0 finds it */
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            field[y][x] = y < 3 ? px(0.5f, 1) : px(0.5f, 2);
    replicate(field);
    assert_int_equal(hz_amask_block(&c, win, W + 2, W, H, mask, W), 0);
    c.tau[HZ_TAU_POID] = 0;
    assert_int_equal(hz_amask_block(&c, win, W + 2, W, H, mask, W), 4 * W);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            assert_int_equal(mask[y * W + x], y == 2 ? 0xc : y == 3 ? 0x3 : 0);
    /* a soft colour step within one object: tau_col = 0.6 ignores it (C = 0.2 < 0.612), tau 0.1 does not */
    hz_amask_config_default(&c);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            field[y][x] = px(x < 6 ? 0.4f : 0.6f, 1);
    replicate(field);
    assert_int_equal(hz_amask_block(&c, win, W + 2, W, H, mask, W), 0);
    c.tau[HZ_TAU_COL] = q16(0.1);
    assert_int_equal(hz_amask_block(&c, win, W + 2, W, H, mask, W), 4 * H);
}

/* ---- oracle: the rules restated in double precision, straight from the paper's text ---- */

static uint32_t xs(uint32_t *s)
{
    *s ^= *s << 13, *s ^= *s >> 17, *s ^= *s << 5;
    return *s;
}

static double val(uint32_t b, bool *ok)
{
    float f = bitsf(b);
    *ok = isfinite(f);
    return *ok ? (f > 0 ? f : 0.0) : 0.0;
}

static bool oracle_subpixel(const hz_amask_config_t *c, const hz_amask_px_t *p, const hz_amask_px_t *const nb[3],
                            bool *tie)
{
    double cosv = c->normal_cos / 32768.0, tau = 2.0;
    bool any = false;
    for (int h = 0; h < 2; h++) {
        const hz_amask_hit_t *a = &p->hit[h];
        bool dis[4] = { false, false, false, (a->flags & HZ_AMASK_TEXTURED) != 0 }; /* oid sn sc te */
        for (int k = 0; k < 3; k++) {
            const hz_amask_hit_t *b = &nb[k]->hit[h];
            dis[0] |= a->object != b->object;
            dis[2] |= a->shadow != b->shadow;
            double la = sqrt((double)a->n[0] * a->n[0] + a->n[1] * a->n[1] + a->n[2] * a->n[2]);
            double lb = sqrt((double)b->n[0] * b->n[0] + b->n[1] * b->n[1] + b->n[2] * b->n[2]);
            if (la == 0 || lb == 0) {
                dis[1] |= (la == 0) != (lb == 0);
            } else {
                double cs = ((double)a->n[0] * b->n[0] + a->n[1] * b->n[1] + a->n[2] * b->n[2]) / (la * lb);
                if (fabs(cs - cosv) < 1e-6)
                    *tie = true;
                dis[1] |= cs < cosv;
            }
        }
        static const int taus[2][4] = { { HZ_TAU_POID, HZ_TAU_PSN, HZ_TAU_PSC, HZ_TAU_PTE },
                                        { HZ_TAU_SOID, HZ_TAU_SSN, HZ_TAU_SSC, HZ_TAU_STE } };
        for (int k = 0; k < 4; k++) {
            double t = c->tau[taus[h][k]] / 65536.0;
            if (dis[k] && t < 1.0) {
                any = true;
                tau = t < tau ? t : tau;
            }
        }
    }
    if (!any)
        tau = c->tau[HZ_TAU_COL] / 65536.0;
    static const double factor[3] = { 1.36, 1.02, 2.04 };
    for (int ch = 0; ch < 3; ch++) {
        const hz_amask_px_t *all[4] = { p, nb[0], nb[1], nb[2] };
        double hi = -1, lo = 1e300;
        int n = 0;
        for (int k = 0; k < 4; k++) {
            bool ok;
            double v = val(all[k]->rgb[ch], &ok);
            if (!ok)
                continue;
            n++;
            hi = v > hi ? v : hi;
            lo = v < lo ? v : lo;
        }
        if (n < 2)
            continue;
        double cc = hi + lo > 0 ? (hi - lo) / (hi + lo) : 0.0;
        double thr = floor(factor[ch] * 65536.0 + 0.5) * floor(tau * 65536.0 + 0.5) / 65536.0;
        thr = floor(thr + 0.5) / 65536.0;
        if (fabs(cc - thr) < 1e-6)
            *tie = true;
        if (cc >= thr)
            return true;
    }
    return false;
}

static void random_px(uint32_t *s, hz_amask_px_t *p)
{
    memset(p, 0, sizeof *p);
    for (int ch = 0; ch < 3; ch++) {
        uint32_t r = xs(s);
        /* mostly similar greys, some black, some huge or tiny, a few NaN/Inf/negative */
        switch (r % 16) {
        case 0: p->rgb[ch] = 0; break;
        case 1: p->rgb[ch] = 0x7f800000u | (r >> 9 & 1); break;
        case 2: p->rgb[ch] = fbits(-(float)(r >> 8) / 16777216.0f); break;
        case 3: p->rgb[ch] = xs(s) & 0x7fffffffu; break;
        default: p->rgb[ch] = fbits(0.3f + (float)(r >> 8 & 0xff) / 1024.0f); break;
        }
    }
    for (int h = 0; h < 2; h++) {
        uint32_t r = xs(s);
        p->hit[h].object = (uint16_t)(r % 3 == 0 ? 0xffff : r % 4);
        p->hit[h].shadow = (uint8_t)(r >> 4 & 1);
        p->hit[h].flags = (uint8_t)((r >> 5 & 1) ? HZ_AMASK_TEXTURED | HZ_AMASK_HIT : HZ_AMASK_HIT);
        for (int k = 0; k < 3; k++)
            p->hit[h].n[k] = (int8_t)((int32_t)(xs(s) % 255u) - 127);
        if (r >> 6 & 1)
            p->hit[h].n[0] = 0, p->hit[h].n[1] = 0, p->hit[h].n[2] = 120;
    }
}

static void test_oracle(void **state)
{
    (void)state;
    uint32_t s = 0x9e3779b9u;
    int compared = 0, ties = 0;
    for (int trial = 0; trial < 40000; trial++) {
        hz_amask_config_t c;
        hz_amask_config_default(&c);
        for (int k = 0; k < HZ_TAU_COUNT; k++)
            if (xs(&s) % 3 == 0)
                c.tau[k] = xs(&s) % 70000u;
        hz_amask_px_t p, n[3];
        random_px(&s, &p);
        for (int k = 0; k < 3; k++) {
            if (xs(&s) % 2)
                n[k] = p;
            else
                random_px(&s, &n[k]);
        }
        const hz_amask_px_t *nb[3] = { &n[0], &n[1], &n[2] };
        bool tie = false;
        bool want = oracle_subpixel(&c, &p, nb, &tie);
        if (tie) {
            ties++;
            continue;
        }
        compared++;
        if (hz_amask_subpixel(&c, &p, nb) != want)
            fail_msg("trial %d: mask %d, oracle %d", trial, !want, want);
    }
    assert_true(compared > 39000);
    (void)ties;
}

/* hz_amask_block (shared neighbour comparisons, the flat-neighbourhood shortcut) against hz_amask_subpixel on
 * blocky random fields: large runs of identical pixels with random ones in between. */
static void test_block_matches_subpixel(void **state)
{
    (void)state;
    uint32_t s = 77;
    for (int trial = 0; trial < 200; trial++) {
        hz_amask_config_t c;
        hz_amask_config_default(&c);
        if (trial % 4 == 1)
            c.tau[HZ_TAU_COL] = 0, c.tau[HZ_TAU_PTE] = 0;
        if (trial % 4 == 2)
            c.focus_count = 1, c.focus[0] = 1;
        hz_amask_px_t base[3];
        for (int k = 0; k < 3; k++)
            random_px(&s, &base[k]);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                uint32_t r = xs(&s) % 16;
                if (r < 12)
                    field[y][x] = base[(x / 5 + y / 4) % 3];
                else
                    random_px(&s, &field[y][x]);
            }
        replicate(field);
        hz_amask_block(&c, win, W + 2, W, H, mask, W);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                const hz_amask_px_t *p = &win[(y + 1) * (W + 2) + x + 1];
                uint8_t want = 0;
                for (int q = 0; q < 4; q++) {
                    const hz_amask_px_t *nb[3];
                    for (int k = 0; k < 3; k++)
                        nb[k] = p + hz_amask_neighbours[q][k][1] * (W + 2) + hz_amask_neighbours[q][k][0];
                    if (hz_amask_subpixel(&c, p, nb))
                        want |= (uint8_t)(1u << q);
                }
                if (mask[y * W + x] != want)
                    fail_msg("trial %d pixel (%d, %d): block %x, subpixel tests %x", trial, x, y, mask[y * W + x],
                             want);
            }
    }
}

static void test_pack(void **state)
{
    (void)state;
    enum { TW = 8, TH = 8 };
    uint8_t m[TW * TH];
    uint16_t list[4 * TW * TH];
    memset(m, 0xf, sizeof m);
    uint32_t n = hz_amask_pack(m, TW, TW, TH, list);
    assert_int_equal(n, 4 * TW * TH);
    /* Morton order: every aligned pair is one row of a pixel's quadrants, every 4 one whole pixel, every 16 a
     * 2x2 block of pixels */
    bool seen[4 * TW * TH] = { false };
    for (uint32_t i = 0; i < n; i++) {
        assert_false(seen[list[i]]);
        seen[list[i]] = true;
        assert_int_equal(list[i] & 3u, i & 3u);
        uint32_t pix = list[i] >> 2, x = pix % TW, y = pix / TW;
        uint32_t blk = i / 16;
        assert_int_equal(x / 2, (blk & 1) | ((blk >> 1) & 2));
        assert_int_equal(y / 2, ((blk >> 1) & 1) | ((blk >> 2) & 2));
    }
    /* a sparse mask keeps the order and the entries */
    memset(m, 0, sizeof m);
    m[3 * TW + 5] = 0x9;
    m[0] = 0x2;
    n = hz_amask_pack(m, TW, TW, TH, list);
    assert_int_equal(n, 3);
    assert_int_equal(list[0], (0 << 2) | 1);
    assert_int_equal(list[1], ((3 * TW + 5) << 2) | 0);
    assert_int_equal(list[2], ((3 * TW + 5) << 2) | 3);
    /* partial tiles (image edges) */
    memset(m, 0xf, sizeof m);
    assert_int_equal(hz_amask_pack(m, TW, 3, 5, list), 60);
    for (int i = 0; i < 60; i++)
        assert_true((list[i] >> 2) < 15);
    assert_int_equal(hz_amask_pack(m, TW, 17, 1, list), 0); /* too wide */
}

/* The same generator and sweep as tools/gen/amask_golden.py. */
static uint32_t lcg(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

static void test_golden_hash(void **state)
{
    (void)state;
    enum { GW = 48, GH = 40 };
    static hz_amask_px_t g[(GW + 2) * (GH + 2)];
    static uint8_t gm[GW * GH];
    static uint16_t list[4 * 16 * 16];
    uint32_t s = 2009, h = 0x811c9dc5u, total = 0;
    for (int cfg = 0; cfg < 4; cfg++) {
        /* Regions of objects (diagonal bands), shadow and texture stripes, normals tilting along x, colours a
         * smooth ramp with noise, and a few NaN and black presamples. */
        for (int i = 0; i < (GW + 2) * (GH + 2); i++) {
            hz_amask_px_t *p = &g[i];
            int x = i % (GW + 2), y = i / (GW + 2);
            memset(p, 0, sizeof *p);
            for (int ch = 0; ch < 3; ch++) {
                uint32_t r = lcg(&s);
                uint32_t e = 123u + (uint32_t)((x + 2 * y + ch) / 23), m = (uint32_t)(x * 97 + y * 31) << 10;
                m = (m + (r & 0x1ffffu)) & 0x7fffffu;
                p->rgb[ch] = r % 211u == 0 ? 0x7fc00000u : r % 199u == 0 ? 0u : e << 23 | m;
            }
            for (int k = 0; k < 2; k++) {
                uint32_t r = lcg(&s);
                p->hit[k].object = (uint16_t)(r % 61u == 0 ? 0xffffu : (uint32_t)((x + y + 7 * k) / 9) % 5u);
                p->hit[k].shadow = (uint8_t)((x * x + y) % 37 < 5 ? 1 : 0);
                p->hit[k].flags = (uint8_t)(1u | (y % 11 == 3 ? 2u : 0u));
                p->hit[k].n[0] = (int8_t)((x * 5) % 255 - 127);
                p->hit[k].n[1] = (int8_t)((int32_t)(r >> 9 & 7u) - 3);
                p->hit[k].n[2] = 90;
            }
        }
        hz_amask_config_t c;
        hz_amask_config_default(&c);
        if (cfg >= 1)
            c.tau[HZ_TAU_COL] = 6554u * (uint32_t)cfg, c.tau[HZ_TAU_PTE] = 65536u;
        if (cfg == 3)
            c.focus_count = 2, c.focus[0] = 1, c.focus[1] = 3;
        total += hz_amask_block(&c, g, GW + 2, GW, GH, gm, GW);
        for (int i = 0; i < GW * GH; i++)
            h = (h ^ gm[i]) * 0x01000193u;
        for (int ty = 0; ty < GH; ty += 8)
            for (int tx = 0; tx < GW; tx += 16) {
                uint32_t n = hz_amask_pack(gm + ty * GW + tx, GW, 16, 8, list);
                for (uint32_t i = 0; i < n; i++)
                    h = (h ^ list[i]) * 0x01000193u;
            }
    }
    assert_int_equal(total, 6809u);
    assert_int_equal(h, 0xe5674cefu);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_neighbour_table),
        cmocka_unit_test(test_defaults_are_table2),
        cmocka_unit_test(test_attribute_rules),
        cmocka_unit_test(test_normal_rule),
        cmocka_unit_test(test_focus),
        cmocka_unit_test(test_contrast_values),
        cmocka_unit_test(test_flat_region_and_nan),
        cmocka_unit_test(test_straight_edges),
        cmocka_unit_test(test_oracle),
        cmocka_unit_test(test_block_matches_subpixel),
        cmocka_unit_test(test_pack),
        cmocka_unit_test(test_golden_hash),
    };
    return HZ_RUN(tests);
}
