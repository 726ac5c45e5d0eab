/* Stage fixed: Q16.16 arithmetic (hz/fixed.h), the integer square roots and the tile-ordering decision ĝ
 * (hz/tileorder.h) at the ends of their ranges, against exact references in 64/128-bit integers and double. */
#include <stdlib.h>

#include "hz/fixed.h"
#include "hz/tileorder.h"
#include "hz/vmath.h"
#include "../../src/recon/tdense_internal.h" /* hz_tdense_ghat */
#include "stab_util.h"

__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;

static const int32_t edge_vals[] = { INT32_MIN, INT32_MIN + 1, -2147450880, -65537, -65536, -32768, -1, 0, 1,
                                     32767, 32768, 65535, 65536, 65537, 46341 * 256, 2147450880,
                                     INT32_MAX - 1, INT32_MAX, 181 << 16, 12345678, -87654321 };
#define NE (sizeof edge_vals / sizeof edge_vals[0])

/* round(x / d), ties away from zero, saturated to int32 (the contract of hz_q16_mul / hz_q16_div). */
static int32_t ref_round_div(i128 x, i128 d)
{
    if (d < 0)
        x = -x, d = -d;
    i128 q = x >= 0 ? (2 * x + d) / (2 * d) : -((-2 * x + d) / (2 * d));
    return q > INT32_MAX ? INT32_MAX : q < INT32_MIN ? INT32_MIN : (int32_t)q;
}

static void c_q16_mul(stab_result_t *r)
{
    uint32_t n = 0;
    for (size_t i = 0; i < NE; i++)
        for (size_t j = 0; j < NE; j++, n++) {
            int32_t a = edge_vals[i], b = edge_vals[j];
            int32_t want = ref_round_div((i128)a * b, 65536), got = hz_q16_mul(a, b);
            STAB_CHECK(r, got == want, "q16_mul(%d, %d) = %d, exact %d", a, b, got, want);
        }
    stab_note(r, "%u products at the range ends: exact rounding and saturation", n);
}

static void c_q16_div(stab_result_t *r)
{
    uint32_t n = 0;
    for (size_t i = 0; i < NE; i++)
        for (size_t j = 0; j < NE; j++, n++) {
            int32_t a = edge_vals[i], b = edge_vals[j], got = hz_q16_div(a, b), want;
            if (b == 0)
                want = a > 0 ? HZ_Q16_MAX : a < 0 ? HZ_Q16_MIN : 0;
            else {
                /* round(a * 65536 / b), ties away from zero */
                i128 x = (i128)a * 65536, d = b;
                if (d < 0)
                    x = -x, d = -d;
                i128 q = x >= 0 ? (2 * x + d) / (2 * d) : -((-2 * x + d) / (2 * d));
                want = q > INT32_MAX ? INT32_MAX : q < INT32_MIN ? INT32_MIN : (int32_t)q;
            }
            STAB_CHECK(r, got == want, "q16_div(%d, %d) = %d, exact %d", a, b, got, want);
        }
    stab_note(r, "%u quotients incl. division by 0: exact rounding and saturation", n);
}

static void c_q16_add_sub_abs(stab_result_t *r)
{
    for (size_t i = 0; i < NE; i++) {
        int32_t a = edge_vals[i];
        int64_t aa = a < 0 ? -(int64_t)a : a;
        STAB_CHECK(r, hz_q16_abs(a) == (aa > INT32_MAX ? INT32_MAX : aa), "abs(%d)", a);
        STAB_CHECK(r, hz_q16_frac(a) == (int32_t)((int64_t)a - (int64_t)hz_q16_floor_int(a) * 65536),
                   "frac/floor of %d disagree", a);
        STAB_CHECK(r, (int64_t)hz_q16_floor_int(a) * 65536 <= a && (int64_t)hz_q16_floor_int(a) * 65536 > (int64_t)a - 65536,
                   "floor of %d", a);
        for (size_t j = 0; j < NE; j++) {
            int32_t b = edge_vals[j];
            int64_t s = (int64_t)a + b, d = (int64_t)a - b;
            STAB_CHECK(r, hz_q16_add(a, b) == (s > INT32_MAX ? INT32_MAX : s < INT32_MIN ? INT32_MIN : s), "add");
            STAB_CHECK(r, hz_q16_sub(a, b) == (d > INT32_MAX ? INT32_MAX : d < INT32_MIN ? INT32_MIN : d), "sub");
        }
    }
    const float fl[] = { 1e30f, -1e30f, INFINITY, -INFINITY, NAN, 32767.99999f, -32768.0f, 1e-30f, -0.0f };
    const int32_t want[] = { HZ_Q16_MAX, HZ_Q16_MIN, HZ_Q16_MAX, HZ_Q16_MIN, 0, HZ_Q16_MAX, HZ_Q16_MIN, 0, 0 };
    for (size_t i = 0; i < sizeof fl / sizeof fl[0]; i++)
        STAB_CHECK(r, hz_q16_from_float(fl[i]) == want[i], "q16_from_float(%g) = %d, want %d", (double)fl[i],
                   hz_q16_from_float(fl[i]), want[i]);
    stab_note(r, "add/sub/abs/floor/frac saturate exactly; floats 1e30/Inf/NaN saturate or give 0");
}

static void c_isqrt(stab_result_t *r)
{
    uint32_t n = 0;
    for (int k = 0; k <= 64; k++)
        for (int d = -2; d <= 2; d++) {
            uint64_t base = k == 64 ? UINT64_MAX : ((uint64_t)1 << k);
            uint64_t x = base + (uint64_t)(int64_t)d;
            if (k == 64 && d > 0)
                continue;
            uint64_t s = hz_isqrt_u64(x);
            u128 s2 = (u128)s * s,
                                           s3 = (u128)(s + 1) * (s + 1);
            STAB_CHECK(r, s2 <= x && s3 > x, "isqrt(%llu) = %llu", (unsigned long long)x, (unsigned long long)s);
            n++;
        }
    for (uint64_t q = 4294967290ull; q <= 4294967295ull; q++)
        for (int d = -1; d <= 1; d++) {
            uint64_t x = q * q + (uint64_t)(int64_t)d;
            uint64_t s = hz_isqrt_u64(x), want = d < 0 ? q - 1 : q;
            STAB_CHECK(r, s == want, "isqrt(%llu^2 %+d) = %llu", (unsigned long long)q, d, (unsigned long long)s);
            n++;
        }
    STAB_CHECK(r, hz_q16_sqrt(-1) == 0 && hz_q16_sqrt(HZ_Q16_MIN) == 0, "sqrt of negative");
    STAB_CHECK(r, hz_q16_sqrt(HZ_Q16_MAX) == (hz_q16_t)hz_isqrt_u64((uint64_t)HZ_Q16_MAX << 16), "sqrt of MAX");
    stab_note(r, "%u roots around powers of two and 2^32 squares: exact floor", n);
}

/* ĝ at huge motion: |m| up to the Q16.16 range (32767 px), INT32_MIN components (|INT32_MIN| has no int32),
 * every rule: always hourglass or bowtie, and the tdense resolve's ĝ the same; ℓf exact against a 128-bit root;
 * α within a few units of atan2. */
static void c_ghat_huge_motion(stab_result_t *r)
{
    uint32_t n = 0;
    double max_angle_err = 0;
    for (size_t i = 0; i < NE; i++)
        for (size_t j = 0; j < NE; j++) {
            int32_t mx = edge_vals[i], my = edge_vals[j];
            u128 l2 = (u128)((int64_t)mx * mx) +
                                                 (u128)((int64_t)my * my);
            /* floor(sqrt(l2)) in Q16 units: l2 < 2^63, so a 64-bit root */
            uint64_t l = hz_isqrt_u64((uint64_t)l2);
            hz_q16_t lf = hz_tileorder_length_frac(mx, my);
            STAB_CHECK(r, lf == (hz_q16_t)(l & 0xffffu), "length_frac(%d, %d) = %d, exact %llu", mx, my, lf,
                       (unsigned long long)(l & 0xffffu));
            hz_qangle_t a = hz_tileorder_angle(mx, my);
            STAB_CHECK(r, a <= HZ_QANGLE_RIGHT, "angle(%d, %d) = %u beyond pi/2", mx, my, a);
            if (mx || my) {
                double ref = atan2(fabs((double)my), fabs((double)mx)) / (3.141592653589793 / 2) * 1073741824.0;
                max_angle_err = fmax(max_angle_err, fabs(ref - (double)a));
            }
            if (my == 0 && mx != 0)
                STAB_CHECK(r, a == 0, "horizontal motion angle %u", a);
            if (mx == 0 && my != 0)
                STAB_CHECK(r, a == HZ_QANGLE_RIGHT, "vertical motion angle %u", a);
            for (int rule = 0; rule < HZ_GHAT_RULE_COUNT; rule++)
                for (uint32_t rnd = 0; rnd < 2; rnd++) {
                    hz_tilecycle_t c = hz_tileorder_ghat(mx, my, rnd << 31, (hz_ghat_rule_t)rule);
                    STAB_CHECK(r, c == HZ_TILECYCLE_HOURGLASS || c == HZ_TILECYCLE_BOWTIE,
                               "ghat(%d, %d) rule %d gave cycle %d", mx, my, rule, (int)c);
                    /* the tdense resolve's ĝ (double precision where certain): the same decision */
                    const uint32_t key = 0x9e3779b9u * (rnd + 1u), tx = (uint32_t)i, ty = (uint32_t)j;
                    hz_tilecycle_t want = hz_tileorder_ghat(mx, my, hz_tileorder_tile_random_keyed(tx, ty, key),
                                                            (hz_ghat_rule_t)rule);
                    hz_tilecycle_t fast = hz_tdense_ghat(mx, my, tx, ty, key, (hz_ghat_rule_t)rule);
                    STAB_CHECK(r, fast == want, "tdense ghat(%d, %d) rule %d: %d, exact %d", mx, my, rule,
                               (int)fast, (int)want);
                }
            n++;
        }
    stab_error(r, max_angle_err);
    stab_note(r, "%u motions at the range ends; angle within %.0f units of atan2", n, max_angle_err);
    STAB_CHECK(r, max_angle_err <= 64, "angle off by %g units", max_angle_err);
}

/* Per-tile choice over a grid of saturated motions: every ordering valid, rows independent (any split). */
static void c_tileorder_choose_extremes(stab_result_t *r)
{
    enum { TX = 8, TY = 6 };
    hz_q16_t motion[TX * TY * 2];
    uint8_t a[TX * TY], b[TX * TY];
    for (int i = 0; i < TX * TY; i++)
        motion[2 * i] = edge_vals[(size_t)i % NE], motion[2 * i + 1] = edge_vals[(size_t)(i * 7) % NE];
    hz_tileorder_choose(motion, TX, 0, TY, 12345u, 99u, HZ_GHAT_FULL, a);
    hz_tileorder_choose(motion, TX, 0, 2, 12345u, 99u, HZ_GHAT_FULL, b);
    hz_tileorder_choose(motion, TX, 2, TY, 12345u, 99u, HZ_GHAT_FULL, b);
    for (int i = 0; i < TX * TY; i++) {
        STAB_CHECK(r, a[i] < HZ_TILEORDER_COUNT && hz_tileorder_cycle(a[i]) != HZ_TILECYCLE_SQUARE,
                   "tile %d ordering %u", i, a[i]);
        STAB_CHECK(r, a[i] == b[i], "tile %d differs between row splits", i);
    }
    stab_note(r, "%d tiles of saturated motion: valid orderings; split-independent", TX * TY);
}

static const stab_case_t cases[] = {
    { "q16_mul", "Q16.16 products at the range ends: exact rounding and saturation (128-bit reference)",
      c_q16_mul, 0 },
    { "q16_div", "Q16.16 quotients incl. /0: exact rounding and saturation", c_q16_div, 0 },
    { "q16_add_sub_abs", "add/sub/abs/floor/frac saturate; float 1e30/Inf/NaN to Q16 saturates", c_q16_add_sub_abs,
      0 },
    { "isqrt", "integer roots near powers of two and (2^32-k)^2: exact floor", c_isqrt, 0 },
    { "ghat_huge_motion", "ĝ at |m| up to 32767 px and INT32_MIN: valid cycle, the resolve's the same; exact length frac; angle",
      c_ghat_huge_motion, 0 },
    { "tileorder_choose_extremes", "orderings over saturated motion: valid; split-independent",
      c_tileorder_choose_extremes, 0 },
};
STAB_STAGE(fixed, cases);
