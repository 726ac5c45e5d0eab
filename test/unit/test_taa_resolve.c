/* The TAA resolve in SIMD lanes (hz_taa_resolve_tiles, taa_lanes.c) against its scalar twin
 * (hz_taa_resolve_tile_scalar, taa.c) on inputs no scene makes: samples that are NaN, infinite, negative, above
 * the half-float range or subnormal; history codes that are NaN or infinite; motion vectors that are NaN,
 * infinite, huge or leave the image; object ids that change; dithered pixels under every transparency method,
 * still and moving cameras, a fresh history, extreme gamma and alpha. Every output float and history code must
 * have the same bits. Frames of several sizes, so that runs of tiles end short and edge tiles go to the twin.
 * The store of a traced tile into the YCoCg sample planes in lanes (hz_taa_store_samples) against its twin on
 * the same kind of radiance, with tiles cut by the image's edge.
 */
#include <string.h>

#include "hz_test.h"

#include "../../src/recon/taa_internal.h"
#include "hz/pack.h"

#define WMAX 80
#define HMAX 48
#define PX (WMAX * HMAX)

static float cur[3][PX], out_lanes[PX * 3], out_scalar[PX * 3], mv[PX * 2];
static uint16_t hist_prev[PX * 3], hist_lanes[PX * 3], hist_scalar[PX * 3];
static uint16_t object[PX], prev_object[PX];
static uint8_t flags[PX];

static uint32_t rng = 12345u;
static uint32_t next(void)
{
    rng ^= rng << 13, rng ^= rng >> 17, rng ^= rng << 5;
    return rng;
}
static float unit(void) { return (float)(next() >> 8) * (1.0f / 16777216.0f); }

static float bits_float(uint32_t b)
{
    float v;
    memcpy(&v, &b, 4);
    return v;
}

/* A sample: mostly ordinary radiance, sometimes a value the resolve must survive. */
static float sample(void)
{
    switch (next() % 24u) {
    case 0: return bits_float(0x7fc00000u);                    /* NaN */
    case 1: return bits_float(0x7f800000u);                    /* +inf */
    case 2: return bits_float(0xff800000u);                    /* -inf */
    case 3: return -unit() * 4.0f;                             /* negative */
    case 4: return 65504.0f + unit() * 1e6f;                   /* beyond the half range */
    case 5: return bits_float(1u + (next() & 0x7fffffu));      /* subnormal */
    case 6: return bits_float(0x80000000u);                    /* -0 */
    case 7: return 3.0e38f;                                    /* squares overflow */
    default: return unit() * (next() & 1u ? 1.0f : 8.0f);
    }
}

static float motion(void)
{
    switch (next() % 16u) {
    case 0: return bits_float(0x7fc00000u);
    case 1: return bits_float(next() & 1u ? 0x7f800000u : 0xff800000u);
    case 2: return (unit() - 0.5f) * 2e6f;
    case 3: return (unit() - 0.5f) * 200.0f; /* off the image */
    case 4:
    case 5: return 0.0f;
    default: return (unit() - 0.5f) * 6.0f;
    }
}

static uint16_t half_code(void)
{
    switch (next() % 16u) {
    case 0: return 0x7c00u; /* +inf */
    case 1: return 0x7e00u; /* NaN */
    case 2: return 0xfc00u; /* -inf */
    case 3: return (uint16_t)(0x8000u | (next() & 0x7bffu)); /* negative */
    default: {
        float v = unit() * 4.0f;
        uint16_t c[3];
        float t[3] = { v, v, v };
        hz_half_pack3(c, t);
        return c[0];
    }
    }
}

static void run_case(uint32_t w, uint32_t h, int seed)
{
    const size_t n = (size_t)w * h;
    for (size_t i = 0; i < n * 3; i++) {
        cur[i % 3][i / 3] = sample(); /* as YCoCg: any value, as if the trace had stored anything */
        hist_prev[i] = half_code();
    }
    const bool uniform_mv = seed % 3 == 0; /* camera-like: the contiguous history path */
    const float ux = (unit() - 0.5f) * 5.0f, uy = (unit() - 0.5f) * 5.0f;
    for (size_t i = 0; i < n; i++) {
        mv[2 * i] = uniform_mv && next() % 8u ? ux : motion();
        mv[2 * i + 1] = uniform_mv && next() % 8u ? uy : motion();
        object[i] = (uint16_t)(next() % 4u == 0 ? HZ_GB_NO_OBJECT : next() % 3u);
        prev_object[i] = (uint16_t)(next() % 5u == 0 ? HZ_GB_NO_OBJECT : next() % 3u);
        flags[i] = (uint8_t)(next() % 3u == 0 ? HZ_GB_DITHER : 0u);
    }

    hz_render_frame_t f;
    memset(&f, 0, sizeof f);
    hz_render_opts_default(&f.opts);
    f.opts.width = w, f.opts.height = h;
    static const hz_transp_t methods[] = { HZ_TRANSP_STD, HZ_TRANSP_DTAA, HZ_TRANSP_RR, HZ_TRANSP_HYBRID,
                                           HZ_TRANSP_EXACT };
    f.opts.transparency = methods[seed % 5];
    f.opts.taa_gamma = seed % 4 == 1 ? 16.0f : seed % 4 == 2 ? 1e-6f : 0.25f + unit() * 2.0f;
    f.opts.taa_alpha = seed % 7 == 3 ? 1.0f : 0.02f + unit() * 0.3f;
    f.tiles_x = (w + HZ_RENDER_TILE - 1) / HZ_RENDER_TILE;
    f.tiles_y = (h + HZ_RENDER_TILE - 1) / HZ_RENDER_TILE;
    f.camera_moved = seed % 2 == 0;
    f.dither = f.opts.transparency != HZ_TRANSP_EXACT;
    f.gb.width = w, f.gb.height = h;
    f.gb.object = object, f.gb.flags = flags;
    f.gb.mv = seed % 11 == 5 ? NULL : mv;

    hz_taa_t t;
    memset(&t, 0, sizeof t);
    t.out.width = w, t.out.height = h;
    for (int k = 0; k < 3; k++)
        t.cur[k] = cur[k];
    t.prev_object = prev_object;
    t.hist_valid = seed % 9 != 4;
    t.hist_index = 0;
    t.hist[0] = hist_prev;

    t.out.rgb = out_scalar, t.hist[1] = hist_scalar;
    for (uint32_t tile = 0; tile < f.tiles_x * f.tiles_y; tile++)
        hz_taa_resolve_tile_scalar(&t, &f, tile);
    /* lanes: each tile row in runs of 1 to 5 tiles, as the mode's work items hand them out */
    t.out.rgb = out_lanes, t.hist[1] = hist_lanes;
    for (uint32_t ty = 0; ty < f.tiles_y; ty++)
        for (uint32_t tx = 0; tx < f.tiles_x;) {
            uint32_t count = 1u + next() % 5u;
            count = count > f.tiles_x - tx ? f.tiles_x - tx : count;
            hz_taa_resolve_tiles(&t, &f, ty * f.tiles_x + tx, count);
            tx += count;
        }
    for (size_t k = 0; k < n * 3; k++) {
        uint32_t a, b;
        memcpy(&a, &out_lanes[k], 4);
        memcpy(&b, &out_scalar[k], 4);
        if (a != b || hist_lanes[k] != hist_scalar[k])
            fail_msg("%ux%u case %d pixel (%zu, %zu) channel %zu: lanes %08x/%04x, scalar %08x/%04x", w, h, seed,
                     k / 3 % w, k / 3 / w, k % 3, a, hist_lanes[k], b, hist_scalar[k]);
    }
}

static void test_lanes_match_scalar_on_extreme_inputs(void **state)
{
    (void)state;
    static const uint32_t sizes[][2] = { { 80, 48 }, { 72, 40 }, { 77, 45 }, { 16, 16 }, { 9, 8 } };
    const int cases = HZ_EMULATED_LESS(60, 20);
    for (int seed = 0; seed < cases; seed++)
        run_case(sizes[seed % 5][0], sizes[seed % 5][1], seed);
}

/* A tile's slots as hz_tile_slots lays them out (packets of 2 rows of HZ_RENDER_LANES / 2 pixels) for tile
 * (tx, ty) of a w x h frame. */
static void tile_slots(uint32_t w, uint32_t h, uint32_t tx, uint32_t ty, uint32_t pixel[HZ_TILE_PIXELS])
{
    const uint32_t pw = HZ_RENDER_LANES / 2, per_row = HZ_RENDER_TILE / pw;
    for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++) {
        uint32_t packet = slot / HZ_RENDER_LANES, lane = slot % HZ_RENDER_LANES;
        uint32_t x = tx * HZ_RENDER_TILE + (packet % per_row) * pw + lane % pw;
        uint32_t y = ty * HZ_RENDER_TILE + (packet / per_row) * 2 + lane / pw;
        pixel[slot] = x < w && y < h ? y * w + x : UINT32_MAX;
    }
}

static void test_sample_store_matches_scalar(void **state)
{
    (void)state;
    static float planes[2][3][PX];
    static hz_batch_t b;
    for (int round = 0; round < 40; round++) {
        const uint32_t w = round % 2 ? 77 : 80, h = round % 3 ? 45 : 48;
        const uint32_t tx = next() % ((w + 7) / 8), ty = next() % ((h + 7) / 8);
        memset(planes, 0xa5, sizeof planes);
        tile_slots(w, h, tx, ty, b.pixel);
        const bool tame = round % 4 == 0; /* whole packets of ordinary values: the lanes' own path */
        for (uint32_t i = 0; i < HZ_TILE_PIXELS * 3; i++)
            b.radiance[i] = tame ? unit() * 4.0f : sample();
        uint64_t nonfinite[2];
        for (int v = 0; v < 2; v++) {
            hz_taa_t t;
            memset(&t, 0, sizeof t);
            t.out.width = w, t.out.height = h;
            for (int k = 0; k < 3; k++)
                t.cur[k] = planes[v][k];
            b.stats.nonfinite = 0;
            (v ? hz_taa_store_samples : hz_taa_store_samples_scalar)(&t, &b);
            nonfinite[v] = b.stats.nonfinite;
        }
        assert_int_equal(nonfinite[0], nonfinite[1]);
        if (memcmp(planes[0], planes[1], sizeof planes[0]) != 0)
            fail_msg("round %d (%ux%u tile %u, %u): the planes differ", round, w, h, tx, ty);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lanes_match_scalar_on_extreme_inputs),
        cmocka_unit_test(test_sample_store_matches_scalar),
    };
    return HZ_RUN(tests);
}
