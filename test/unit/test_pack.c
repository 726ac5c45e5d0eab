/* Compact frame-state formats (hz/pack.h): decoding against libm's ldexp, encoding against brute-force nearest
 * codes, and the edge cases (0, float subnormals, the largest code, NaN/Inf/negative -> finite).
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include <math.h>
#include <string.h>

#include "hz/hash.h"
#include "hz/pack.h"
#include "hz/vmath.h"
#if defined(HZ_BOARD_SIMD_AVX2) || defined(HZ_BOARD_SIMD_NEON)
#include "../../src/core/pack_lanes.h"
#endif

/* Half: code -> value by the IEEE 754 definition, independently of the code under test. */
static double ref_half(uint16_t h)
{
    int e = (h >> 10) & 31, m = h & 1023;
    return e == 0 ? ldexp(m, -24) : ldexp(1024 + m, e - 25);
}

static void test_half_decode_every_code(void **state)
{
    (void)state;
    for (uint32_t h = 0; h <= 0x7bffu; h++) {
        assert_true((double)hz_half_unpack((uint16_t)h) == ref_half((uint16_t)h));
        assert_int_equal(hz_half_pack(hz_half_unpack((uint16_t)h)), h); /* round trip */
    }
}

/* Every midpoint between neighbouring codes rounds to the even one, and a hair above or below it to the
 * nearer one (covers the subnormal/normal boundary and every exponent step). */
static void test_half_round_to_nearest_even(void **state)
{
    (void)state;
    for (uint32_t h = 0; h < 0x7bffu; h++) {
        double a = ref_half((uint16_t)h), b = ref_half((uint16_t)(h + 1)), mid = 0.5 * (a + b);
        uint16_t even = (h & 1u) ? (uint16_t)(h + 1) : (uint16_t)h;
        assert_int_equal(hz_half_pack((float)mid), even);
        float above = nextafterf((float)mid, INFINITY), below = nextafterf((float)mid, 0.0f);
        assert_int_equal(hz_half_pack(above), h + 1);
        assert_int_equal(hz_half_pack(below), h);
    }
}

static void test_half_edges(void **state)
{
    (void)state;
    assert_int_equal(hz_half_pack(0.0f), 0);
    assert_int_equal(hz_half_pack(-0.0f), 0);
    assert_int_equal(hz_half_pack(-3.0f), 0);
    assert_int_equal(hz_half_pack(NAN), 0);
    assert_int_equal(hz_half_pack(INFINITY), 0x7bff);
    assert_int_equal(hz_half_pack(-INFINITY), 0);
    assert_int_equal(hz_half_pack(1e30f), 0x7bff);
    assert_true(hz_half_unpack(0x7bff) == HZ_HALF_MAX);
    assert_int_equal(hz_half_pack(1e-45f), 0); /* float subnormal */
    assert_int_equal(hz_half_pack(ldexpf(1.0f, -24)), 1); /* smallest half subnormal */
    assert_int_equal(hz_half_pack(ldexpf(1.0f, -14)), 0x0400); /* smallest normal */
    assert_int_equal(hz_half_pack(1.0f), 0x3c00);
    /* Codes outside what pack produces still read as finite. */
    assert_true(isfinite(hz_half_unpack(0x7c00)) && isfinite(hz_half_unpack(0x7e00)));
    assert_true(isfinite(hz_half_unpack(0xfc00)));
    float in[3] = { 0.25f, 2.0f, 1000.0f }, out[3];
    uint16_t h3[3];
    hz_half_pack3(h3, in);
    hz_half_unpack3(out, h3);
    assert_memory_equal(in, out, sizeof in);
}

/* RGB9E5: code -> value by the format's definition. */
static void ref_9e5(uint32_t c, double v[3])
{
    int e = (int)(c >> 27);
    for (int k = 0; k < 3; k++)
        v[k] = ldexp((double)((c >> (9 * k)) & 511u), e - 24);
}

/* Brute force: over every shared exponent whose range holds the largest channel, round each channel to the
 * nearest multiple; the smallest achievable maximum error. */
static double best_9e5_error(const float c[3])
{
    double best = INFINITY;
    for (int e = 0; e < 32; e++) {
        double q = ldexp(1.0, e - 24), err = 0.0;
        int ok = 1;
        for (int k = 0; k < 3; k++) {
            double m = floor(c[k] / q + 0.5);
            if (m > 511)
                ok = 0;
            err = fmax(err, fabs(m * q - c[k]));
        }
        if (ok)
            best = fmin(best, err);
    }
    return best;
}

static void test_9e5_nearest(void **state)
{
    (void)state;
    hz_rng_t r;
    hz_rng_seed(&r, 9, 5);
    for (int i = 0; i < 50000; i++) {
        float c[3];
        int scale = (int)(hz_rng_u32(&r) % 40u) - 26; /* 2^-26 .. 2^13 */
        for (int k = 0; k < 3; k++) /* channels of different magnitudes: the shared exponent's hard case */
            c[k] = ldexpf(hz_u32_to_unit(hz_rng_u32(&r)), scale - (int)(hz_rng_u32(&r) % 12u));
        uint32_t code = hz_rgb9e5_pack(c);
        double v[3], err = 0.0;
        float back[3];
        ref_9e5(code, v);
        hz_rgb9e5_unpack(code, back);
        for (int k = 0; k < 3; k++) {
            assert_true((double)back[k] == v[k]);
            err = fmax(err, fabs(v[k] - c[k]));
        }
        assert_true(err <= best_9e5_error(c) * (1.0 + 1e-12) + 1e-30);
        assert_int_equal(hz_rgb9e5_pack(back), code); /* round trip */
    }
}

static void test_9e5_edges(void **state)
{
    (void)state;
    float zero[3] = { 0, 0, 0 }, v[3];
    assert_int_equal(hz_rgb9e5_pack(zero), 0);
    float bad[3] = { NAN, -INFINITY, -1.0f };
    assert_int_equal(hz_rgb9e5_pack(bad), 0);
    float inf[3] = { INFINITY, 1e30f, HZ_RGB9E5_MAX };
    hz_rgb9e5_unpack(hz_rgb9e5_pack(inf), v);
    for (int k = 0; k < 3; k++)
        assert_true(v[k] == HZ_RGB9E5_MAX);
    float tiny[3] = { 1e-45f, ldexpf(1.0f, -24), ldexpf(1.0f, -26) }; /* float subnormal, smallest code, below */
    hz_rgb9e5_unpack(hz_rgb9e5_pack(tiny), v);
    assert_true(v[0] == 0.0f && v[1] == ldexpf(1.0f, -24) && v[2] == 0.0f);
    /* Rounding that carries into the next exponent: 511.75 * 2^-8 needs exponent 2^-7's range. */
    float carry[3] = { 511.75f / 256.0f, 0.0f, 1.0f };
    hz_rgb9e5_unpack(hz_rgb9e5_pack(carry), v);
    assert_true(v[0] == 2.0f && v[2] == 1.0f);
    /* Exact for values with <= 9 significant bits against the largest channel. */
    float exact[3] = { 1.5f, 0.25f, 3.0f };
    hz_rgb9e5_unpack(hz_rgb9e5_pack(exact), v);
    assert_memory_equal(exact, v, sizeof v);
    for (uint32_t c = 0; c < 0xffffffffu - 0x01000193u; c += 0x01000193u) { /* any code reads as finite */
        hz_rgb9e5_unpack(c, v);
        assert_true(isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]) && v[0] >= 0 && v[1] >= 0 && v[2] >= 0);
    }
}

static void test_half_signed(void **state)
{
    (void)state;
    assert_int_equal(hz_half_pack_signed(0.0f), 0);
    assert_int_equal(hz_half_pack_signed(-0.0f), 0);
    assert_int_equal(hz_half_pack_signed(NAN), 0);
    assert_int_equal(hz_half_pack_signed(-NAN), 0);
    assert_int_equal(hz_half_pack_signed(INFINITY), 0x7bff);
    assert_int_equal(hz_half_pack_signed(-INFINITY), 0xfbff);
    assert_true(hz_half_unpack(0xfbff) == -HZ_HALF_MAX);
    assert_int_equal(hz_half_pack_signed(-1e-45f), 0); /* float subnormal below half's range: +0 */
    assert_int_equal(hz_half_pack_signed(-ldexpf(1.0f, -24)), 0x8001);
    assert_true(hz_half_unpack(hz_half_pack_signed(-16384.0f)) == -16384.0f);
    /* A motion far below a pixel stays non-zero (a static pixel is exactly 0, as in float). */
    assert_true(hz_half_unpack(hz_half_pack_signed(1e-3f)) > 0.0f);
    assert_true(hz_half_unpack(hz_half_pack_signed(-1e-3f)) < 0.0f);
    /* Symmetric in sign, and every negative code round-trips. */
    for (uint32_t h = 1; h <= 0x7bffu; h++) {
        float v = hz_half_unpack((uint16_t)h);
        assert_true(hz_half_unpack((uint16_t)(h | 0x8000u)) == -v);
        assert_int_equal(hz_half_pack_signed(-v), h | 0x8000u);
        assert_int_equal(hz_half_pack_signed(v), h);
    }
}

#if defined(HZ_BOARD_SIMD_AVX2) || defined(HZ_BOARD_SIMD_NEON)
/* Floats that exercise the codecs: every exponent with a few mantissas (round-half cases included), both signs,
 * zeros, NaN, infinities, subnormals. */
static float probe(uint32_t i, hz_rng_t *rng)
{
    static const float special[] = { 0.0f, -0.0f, NAN, INFINITY, -INFINITY, 65504.0f, 65520.0f, 65408.0f, 1e-45f,
                                     5.9604645e-8f, 2.9802322e-8f, 8.940697e-8f, 6.1035156e-5f, 6.097555e-5f };
    if (i < HZ_ARRAY_LEN(special))
        return special[i];
    uint32_t e = (i / 8u) % 256u, m = hz_rng_u32(rng) & 0x7fffffu;
    if (i % 8u == 1u)
        m = 0x1000u; /* exactly half a half-float step */
    if (i % 8u == 2u)
        m = 0x3000u;
    return hz_float_from_bits((i % 8u == 7u ? 0x80000000u : 0u) | (e << 23) | m);
}

static void test_lanes_codecs_match_scalar(void **state)
{
    (void)state;
    /* Every half code through the lanes' unpack; a sweep of floats through the half and RGB9E5 packs and every
     * RGB9E5 code's unpack: the same bits as the scalar codecs. */
    int32_t in[HZ_LANES];
    float f[HZ_LANES];
    for (uint32_t h = 0; h < 65536u; h += HZ_LANES) {
        for (int i = 0; i < HZ_LANES; i++)
            in[i] = (int32_t)(h + (uint32_t)i);
        hz_lf_store(f, hz_lanes_half_unpack(hz_li_load(in)));
        for (int i = 0; i < HZ_LANES; i++)
            assert_int_equal(hz_float_bits(f[i]), hz_float_bits(hz_half_unpack((uint16_t)(h + (uint32_t)i))));
    }
    hz_rng_t rng;
    hz_rng_seed(&rng, 7, 9);
    for (uint32_t j = 0; j < 200000u; j += HZ_LANES) {
        float v[3][HZ_LANES];
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < HZ_LANES; i++)
                v[k][i] = probe(j + (uint32_t)i + 7919u * (uint32_t)k, &rng);
        int32_t half[HZ_LANES], code[HZ_LANES];
        hz_li_store(half, hz_lanes_half_pack(hz_lf_load(v[0])));
        hz_lrgb_t c;
        for (int k = 0; k < 3; k++)
            c.c[k] = hz_lf_load(v[k]);
        hz_li_store(code, hz_lanes_rgb9e5_pack(&c));
        for (int i = 0; i < HZ_LANES; i++) {
            if ((uint32_t)half[i] != hz_half_pack(v[0][i]))
                fail_msg("half pack of %08x: lanes %04x, scalar %04x", hz_float_bits(v[0][i]), half[i],
                         hz_half_pack(v[0][i]));
            const float rgb[3] = { v[0][i], v[1][i], v[2][i] };
            if ((uint32_t)code[i] != hz_rgb9e5_pack(rgb))
                fail_msg("rgb9e5 pack of %08x %08x %08x: lanes %08x, scalar %08x", hz_float_bits(rgb[0]),
                         hz_float_bits(rgb[1]), hz_float_bits(rgb[2]), code[i], hz_rgb9e5_pack(rgb));
        }
        /* random RGB9E5 codes back */
        for (int i = 0; i < HZ_LANES; i++)
            code[i] = (int32_t)hz_rng_u32(&rng);
        hz_lrgb_t u = hz_lanes_rgb9e5_unpack(hz_li_load(code));
        float out[3][HZ_LANES];
        for (int k = 0; k < 3; k++)
            hz_lf_store(out[k], u.c[k]);
        for (int i = 0; i < HZ_LANES; i++) {
            float ref[3];
            hz_rgb9e5_unpack((uint32_t)code[i], ref);
            for (int k = 0; k < 3; k++)
                assert_int_equal(hz_float_bits(out[k][i]), hz_float_bits(ref[k]));
        }
    }
}

/* The half pack at every rounding boundary: for each code, its value, the midpoint to the next code and one
 * ulp either side of both, through the board's pack (the conversion instruction where it has one), the
 * lanes' bit steps and the scalar codec: all three agree. */
static void test_lanes_half_pack_at_every_boundary(void **state)
{
    (void)state;
    enum { PER = 5 };
    float v[HZ_LANES];
    int32_t hw[HZ_LANES], bits[HZ_LANES];
    int n = 0;
    uint32_t checked = 0;
    for (uint32_t h = 0; h < 0x7c00u; h++) {
        float a = hz_half_unpack((uint16_t)h), b = h + 1 < 0x7c00u ? hz_half_unpack((uint16_t)(h + 1)) : 65520.0f;
        float mid = (float)(0.5 * ((double)a + (double)b));
        const float probes[PER] = { a, nextafterf(a, 0.0f), mid, nextafterf(mid, 0.0f), nextafterf(mid, INFINITY) };
        for (int j = 0; j < PER; j++) {
            v[n++] = probes[j];
            if (n < HZ_LANES && !(h + 1 == 0x7c00u && j == PER - 1))
                continue;
            hz_li_store(hw, hz_lanes_half_pack(hz_lf_load(v)));
            hz_li_store(bits, hz_lanes_half_pack_bits(hz_lf_load(v)));
            for (int i = 0; i < n; i++) {
                uint32_t ref = hz_half_pack(v[i]);
                if ((uint32_t)hw[i] != ref || (uint32_t)bits[i] != ref)
                    fail_msg("half pack of %08x: lanes %04x, lane bits %04x, scalar %04x", hz_float_bits(v[i]),
                             hw[i], bits[i], ref);
            }
            checked += (uint32_t)n;
            n = 0;
        }
    }
    assert_true(checked == 0x7c00u * PER);
}

#ifdef HZ_LANES_HW_HALF
/* The half RGB run load reads HZ_LANES pixels as hz_half_unpack does, and refuses a run holding an exponent-31
 * code (which the instruction would read as an infinity or NaN). */
static void test_lanes_half3_load(void **state)
{
    (void)state;
    uint16_t codes[3 * HZ_LANES];
    for (uint32_t h = 0; h < 0x7c00u; h += 3 * HZ_LANES - 1) {
        for (int i = 0; i < 3 * HZ_LANES; i++)
            codes[i] = (uint16_t)((h + (uint32_t)i * 977u) % 0x7c00u | (i & 1 ? 0x8000u : 0u));
        hz_lrgb_t o;
        memset(&o, 0, sizeof o);
        assert_true(hz_lanes_half3_load(codes, &o));
        float c[3][HZ_LANES];
        for (int k = 0; k < 3; k++)
            hz_lf_store(c[k], o.c[k]);
        for (int i = 0; i < HZ_LANES; i++)
            for (int k = 0; k < 3; k++)
                assert_int_equal(hz_float_bits(c[k][i]), hz_float_bits(hz_half_unpack(codes[3 * i + k])));
    }
    for (int j = 0; j < 3 * HZ_LANES; j++) {
        for (int i = 0; i < 3 * HZ_LANES; i++)
            codes[i] = 0x3c00;
        codes[j] = (uint16_t)(j & 1 ? 0x7c00 : 0xfe01);
        hz_lrgb_t o;
        memset(&o, 0, sizeof o);
        assert_false(hz_lanes_half3_load(codes, &o));
    }
}
#endif

/* The plane codecs (the tdense history): every code hz_half_pack writes (the finite non-negative ones) is read by
 * the run load and by the gather as hz_half_unpack reads it, the gather at any index up to the last code (whose
 * word reaches one code past it: the padding the caller keeps); the store writes hz_half_pack's codes for values
 * across the range, out of it, NaN and infinities. */
static void test_lanes_half_planes(void **state)
{
    (void)state;
    enum { N = 0x7c00 + HZ_LANES + 1 };
    static uint16_t plane[N + 1];
    for (uint32_t i = 0; i < N; i++)
        plane[i] = (uint16_t)(i < 0x7c00u ? i : i - 0x7c00u);
    plane[N] = 0xffff; /* the padding: never read as a code */
    float got[HZ_LANES];
    for (uint32_t h = 0; h + HZ_LANES <= N; h += 3) {
        hz_lf_store(got, hz_lanes_half_load(plane + h));
        for (int i = 0; i < HZ_LANES; i++)
            assert_true(memcmp(&got[i], &(float){ hz_half_unpack(plane[h + (uint32_t)i]) }, 4) == 0);
    }
    int32_t idx[HZ_LANES];
    hz_rng_t r;
    hz_rng_seed(&r, 7, 1);
    for (int round = 0; round < 20000; round++) {
        for (int i = 0; i < HZ_LANES; i++)
            idx[i] = round == 0 ? (int32_t)N - 1 - i : (int32_t)hz_rng_below(&r, N);
        hz_lf_store(got, hz_lanes_half_gather(plane, hz_li_load(idx)));
        for (int i = 0; i < HZ_LANES; i++)
            assert_true(memcmp(&got[i], &(float){ hz_half_unpack(plane[idx[i]]) }, 4) == 0);
    }
    uint16_t out[HZ_LANES];
    float v[HZ_LANES];
    for (int round = 0; round < 200000; round++) {
        for (int i = 0; i < HZ_LANES; i++) {
            uint32_t bits = hz_rng_u32(&r);
            memcpy(&v[i], &bits, 4);
        }
        if (round % 4 == 1)
            for (int i = 0; i < HZ_LANES; i++)
                v[i] = ldexpf((float)(hz_rng_u32(&r) >> 8) / 16777216.0f, (int)hz_rng_below(&r, 44) - 28);
        if (round == 2)
            v[0] = NAN, v[1] = INFINITY, v[2] = -INFINITY, v[3] = 65519.99f;
        hz_lanes_half_store(out, hz_lf_load(v));
        for (int i = 0; i < HZ_LANES; i++)
            if (out[i] != hz_half_pack(v[i]))
                fail_msg("%a: stored %04x, hz_half_pack %04x", (double)v[i], out[i], hz_half_pack(v[i]));
    }
}

/* The interleaved half store (the TAA history) writes hz_half_pack's code of every lane and channel in place,
 * random bit patterns (NaN, infinities, negatives, beyond the range) and values around the subnormal range. */
static void test_lanes_half3_store(void **state)
{
    (void)state;
    hz_rng_t r;
    hz_rng_seed(&r, 11, 3);
    uint16_t out[3 * HZ_LANES + 1];
    float v[3][HZ_LANES];
    for (int round = 0; round < 100000; round++) {
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < HZ_LANES; i++) {
                uint32_t bits = hz_rng_u32(&r);
                memcpy(&v[k][i], &bits, 4);
                if (round % 3 == 1)
                    v[k][i] = ldexpf((float)(hz_rng_u32(&r) >> 8) / 16777216.0f, (int)hz_rng_below(&r, 44) - 28);
            }
        out[3 * HZ_LANES] = 0xbeef; /* the store stays within its 3 HZ_LANES codes */
        hz_lrgb_t c;
        for (int k = 0; k < 3; k++)
            c.c[k] = hz_lf_load(v[k]);
        hz_lanes_half3_store(out, &c);
        assert_int_equal(out[3 * HZ_LANES], 0xbeef);
        for (int i = 0; i < HZ_LANES; i++)
            for (int k = 0; k < 3; k++)
                if (out[3 * i + k] != hz_half_pack(v[k][i]))
                    fail_msg("lane %d channel %d %a: stored %04x, hz_half_pack %04x", i, k, (double)v[k][i],
                             out[3 * i + k], hz_half_pack(v[k][i]));
    }
}

/* The deinterleaving loads are hz_lf_store3's inverse and read pairs in order. */
static void test_lanes_deinterleaving_loads(void **state)
{
    (void)state;
    float src[3 * HZ_LANES], back[3 * HZ_LANES], r[HZ_LANES], g[HZ_LANES], b[HZ_LANES];
    for (int i = 0; i < 3 * HZ_LANES; i++)
        src[i] = (float)(100 + i);
    hz_lf_t x, y, z;
    hz_lf_load3(src, &x, &y, &z);
    hz_lf_store(r, x), hz_lf_store(g, y), hz_lf_store(b, z);
    for (int i = 0; i < HZ_LANES; i++) {
        assert_true(r[i] == src[3 * i] && g[i] == src[3 * i + 1] && b[i] == src[3 * i + 2]);
    }
    hz_lf_store3(back, x, y, z);
    assert_memory_equal(back, src, sizeof src);
    hz_lf_load2(src + 1, &x, &y);
    hz_lf_store(r, x), hz_lf_store(g, y);
    for (int i = 0; i < HZ_LANES; i++)
        assert_true(r[i] == src[1 + 2 * i] && g[i] == src[2 + 2 * i]);
}

/* The lanes' floor against libm's, as bits (a zero's sign and NaN included): the edges, then random words. */
static void test_lanes_floor(void **state)
{
    (void)state;
    float in[64];
    const float edges[] = { 0.0f, -0.0f, 0.5f, -0.5f, 1.0f, -1.0f, -1e-30f, 1e-45f, -1e-45f, 2.999999f, -2.999999f,
                            8388607.5f, -8388607.5f, 8388608.0f, -8388609.0f, 1e30f, -1e30f, INFINITY, -INFINITY,
                            NAN };
    hz_rng_t r;
    hz_rng_seed(&r, 31, 0);
    for (int round = 0; round < 2000; round++) {
        for (int i = 0; i < 64; i++) {
            const uint32_t bits = hz_rng_u32(&r);
            memcpy(&in[i], &bits, 4);
        }
        if (round == 0)
            memcpy(in, edges, sizeof edges);
        for (int i = 0; i < 64; i += HZ_LANES) {
            float got[HZ_LANES];
            hz_lf_store(got, hz_lf_floor(hz_lf_load(in + i)));
            for (int l = 0; l < HZ_LANES; l++) {
                const float want = floorf(in[i + l]), one = hz_floorf(in[i + l]);
                if (isnan(want)) {
                    assert_true(isnan(got[l]) && isnan(one));
                } else {
                    assert_memory_equal(&got[l], &want, 4);
                    assert_memory_equal(&one, &want, 4);
                }
            }
        }
    }
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_half_decode_every_code), cmocka_unit_test(test_half_round_to_nearest_even),
        cmocka_unit_test(test_half_edges),             cmocka_unit_test(test_9e5_nearest),
        cmocka_unit_test(test_9e5_edges),              cmocka_unit_test(test_half_signed),
#if defined(HZ_BOARD_SIMD_AVX2) || defined(HZ_BOARD_SIMD_NEON)
        cmocka_unit_test(test_lanes_codecs_match_scalar),
        cmocka_unit_test(test_lanes_half_pack_at_every_boundary),
        cmocka_unit_test(test_lanes_deinterleaving_loads),
        cmocka_unit_test(test_lanes_half_planes),
        cmocka_unit_test(test_lanes_half3_store),
        cmocka_unit_test(test_lanes_floor),
#ifdef HZ_LANES_HW_HALF
        cmocka_unit_test(test_lanes_half3_load),
#endif
#endif
    };
    return HZ_RUN(tests);
}
