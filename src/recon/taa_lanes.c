/* The TAA resolve of one 8x8 tile in SIMD lanes (src/core/lanes.h: a tile row at a time on AVX2, half a row on
 * NEON), bit-identical to hz_taa_resolve_pixel (taa.c), its scalar twin.
 *
 * The trace stores each sample already in YCoCg, one plane per channel (hz_taa_store_samples, at the end of this
 * file), so the neighbourhood box of a tile inside the image reads the planes directly, HZ_LANES neighbours at a
 * time (a tile at the image's edge reads a 10x10 block copied with the twin's edge clamp); the sums run in the
 * twin's order. Converting the samples once per tile here, from interleaved RGB, had been a sixth of this
 * resolve's instructions and its main wait for memory. The motion vectors come in with deinterleaving loads,
 * not gathers. Motion, the
 * off-screen and disocclusion tests, the bilinear history fetch, the clamp, the blend and the half-float codes
 * run lane by lane with the twin's operations. Pixels whose path dithered take the twin's 7x7 box, read from a
 * 14x14 block of the tile's YCoCg and dither flags built only for tiles that have such pixels, and the mean over
 * the dither's cell (masked sums: adding +0 where the twin skips a pixel gives the same bits, since the sum
 * starts at +0 and never becomes -0). Left to the twin: tiles cut by the image edge, and the non-default
 * Catmull-Rom fetch and clip. */
#include "../core/pack_lanes.h"
#include "taa_internal.h"

#define T HZ_RENDER_TILE
#define B (T + 2) /* the tile and a ring of one pixel */
#define DR HZ_TAA_DITHER_RADIUS
#define BW (T + 2 * DR) /* the tile and a ring of DR pixels */

/* A tile's YCoCg and dither flags with a ring of DR pixels, edge-clamped as the twin reads them (pix). */
typedef struct wide {
    float yc[3][BW][BW];
    uint8_t dith[BW][BW];
} wide_t;

static void wide_fill(wide_t *wb, const hz_taa_t *t, const hz_render_frame_t *f, uint32_t x0, uint32_t y0)
{
    const int32_t w = (int32_t)f->opts.width, h = (int32_t)f->opts.height;
    for (int32_t by = 0; by < BW; by++) {
        int32_t y = (int32_t)y0 + by - DR;
        y = y < 0 ? 0 : y >= h ? h - 1 : y;
        for (int32_t bx = 0; bx < BW; bx++) {
            int32_t x = (int32_t)x0 + bx - DR;
            x = x < 0 ? 0 : x >= w ? w - 1 : x;
            const size_t px = (size_t)y * (size_t)w + (size_t)x;
            HZ_UNROLL
            for (int k = 0; k < 3; k++)
                wb->yc[k][by][bx] = t->cur[k][px];
            wb->dith[by][bx] = (f->gb.flags[px] & HZ_GB_DITHER) ? 0xFFu : 0u;
        }
    }
}

/* Whether a pixel of the tile at (x0, y0) took a dithered path. */
static bool tile_dithered(const hz_render_frame_t *f, uint32_t x0, uint32_t y0)
{
    for (uint32_t y = y0; f->dither && y < y0 + T; y++)
        for (uint32_t x = x0; x < x0 + T; x++)
            if (f->gb.flags[(size_t)y * f->opts.width + x] & HZ_GB_DITHER)
                return true;
    return false;
}

/* One channel's mean and extent (gamma times the deviation) over the n x n box whose top-left values are at p
 * (rows stride floats apart), summed in the twin's order (row by row, left to right). A channel at a time, so
 * that the two sums stay in registers: summed for all three channels at once, they went through the stack on
 * every add (a store-to-load chain per term; a third of the resolve's samples). */
HZ_INLINE void box_stats(const float *p, uint32_t stride, uint32_t n, hz_lf_t gamma, hz_lf_t *mean, hz_lf_t *ext)
{
    hz_lf_t sum = hz_lf_set(0.0f), sum2 = sum;
    for (uint32_t dy = 0; dy < n; dy++)
        for (uint32_t dx = 0; dx < n; dx++) {
            const hz_lf_t q = hz_lf_load(p + dy * stride + dx);
            sum = hz_lf_add(sum, q);
            sum2 = hz_lf_add(sum2, hz_lf_mul(q, q));
        }
    const hz_lf_t count = hz_lf_set((float)(n * n));
    *mean = hz_lf_div(sum, count);
    hz_lf_t var = hz_lf_sub(hz_lf_div(sum2, count), hz_lf_mul(*mean, *mean));
    var = hz_lf_sel(hz_lf_gt(var, hz_lf_set(0.0f)), var, hz_lf_set(0.0f));
    *ext = hz_lf_mul(gamma, hz_lf_sqrt(var));
}

/* The dithered lanes' sample, box mean and extent (hz_taa_resolve_pixel's dither branch): (tx, ty) the lanes'
 * first pixel in the tile; moving: lanes whose camera or surface moved. */
static void dither_box_lanes(const wide_t *wb, const hz_render_frame_t *f, uint32_t tx, uint32_t ty, hz_li_t moving,
                             hz_lrgb_t *c, hz_lrgb_t *mean, hz_lrgb_t *ext)
{
    float g = f->opts.taa_gamma;
    g *= HZ_TAA_DITHER_GAMMA;
    HZ_UNROLL
    for (int k = 0; k < 3; k++)
        box_stats(&wb->yc[k][ty][tx], BW, 2 * DR + 1, hz_lf_set(g), &mean->c[k], &ext->c[k]);
    const int cell = hz_taa_cell_radius(f);
    if (cell <= 0 || !hz_li_any(moving))
        return;
    hz_lrgb_t cs;
    HZ_UNROLL
    for (int k = 0; k < 3; k++)
        cs.c[k] = hz_lf_set(0.0f);
    hz_li_t n = hz_li_set(0);
    for (int dy = -cell; dy <= cell; dy++)
        for (int dx = -cell; dx <= cell; dx++) {
            const uint32_t by = (uint32_t)((int)ty + DR + dy), bx = (uint32_t)((int)tx + DR + dx);
            const hz_li_t in = hz_li_not(hz_li_eq(hz_li_load_u8(&wb->dith[by][bx]), hz_li_set(0)));
            HZ_UNROLL
            for (int k = 0; k < 3; k++)
                cs.c[k] = hz_lf_add(cs.c[k], hz_lf_sel(in, hz_lf_load(&wb->yc[k][by][bx]), hz_lf_set(0.0f)));
            n = hz_li_sub(n, in); /* in is -1 where the pixel counts */
        }
    /* n >= 1 in every dithered lane (the pixel itself); other lanes are not used */
    const hz_lf_t inv = hz_lf_div(hz_lf_set(1.0f), hz_lf_from_li(hz_li_max(n, hz_li_set(1))));
    HZ_UNROLL
    for (int k = 0; k < 3; k++)
        c->c[k] = hz_lf_sel(moving, hz_lf_mul(cs.c[k], inv), c->c[k]);
}

HZ_INLINE void to_ycocg_lanes(const hz_lrgb_t *c, hz_lrgb_t *o)
{
    const hz_lf_t q = hz_lf_set(0.25f), h = hz_lf_set(0.5f), mq = hz_lf_set(-0.25f);
    o->c[0] = hz_lf_add(hz_lf_add(hz_lf_mul(q, c->c[0]), hz_lf_mul(h, c->c[1])), hz_lf_mul(q, c->c[2]));
    o->c[1] = hz_lf_sub(hz_lf_mul(h, c->c[0]), hz_lf_mul(h, c->c[2]));
    o->c[2] = hz_lf_sub(hz_lf_add(hz_lf_mul(mq, c->c[0]), hz_lf_mul(h, c->c[1])), hz_lf_mul(q, c->c[2]));
}

HZ_INLINE hz_li_t clamp_index(hz_li_t v, int32_t n)
{
    return hz_li_min(hz_li_max(v, hz_li_set(0)), hz_li_set(n - 1));
}

/* prev_object[y * w + x] for in-range indices i < n (n >= 2): a word read that never passes the array's end. */
HZ_INLINE hz_li_t object_at(const uint16_t *obj, hz_li_t i, int32_t n)
{
    hz_li_t last = hz_li_eq(i, hz_li_set(n - 1));
    hz_li_t word = hz_li_gather_bytes32(obj, hz_li_shl(hz_li_min(i, hz_li_set(n - 2)), 1));
    return hz_li_sel(last, hz_li_shr(word, 16), hz_li_and(word, hz_li_set(0xffff)));
}

/* History pixel (x, y) (in range), half-float RGB: two word reads inside the pixel's six bytes. */
HZ_INLINE hz_lrgb_t hist_at(const uint16_t *hist, hz_li_t x, hz_li_t y, int32_t w)
{
    hz_li_t i = hz_li_add(hz_li_mul(y, hz_li_set(w)), x);
    hz_li_t off = hz_li_shl(hz_li_add(hz_li_add(i, i), i), 1); /* bytes: 6 per pixel */
    hz_li_t rg = hz_li_gather_bytes32(hist, off), gb = hz_li_gather_bytes32(hist, hz_li_add(off, hz_li_set(2)));
    hz_lrgb_t o;
    o.c[0] = hz_lanes_half_unpack(hz_li_and(rg, hz_li_set(0xffff)));
    o.c[1] = hz_lanes_half_unpack(hz_li_shr(rg, 16));
    o.c[2] = hz_lanes_half_unpack(hz_li_shr(gb, 16));
    return o;
}

/* Where the box reads the samples: yc[k] is the lanes' first pixel in channel k's plane or block, whose rows lie
 * stride floats apart. */
typedef struct samples {
    const float *yc[3];
    uint32_t stride;
} samples_t;

/* Lanes x .. x + HZ_LANES - 1 of row y; s: their samples (each with its ring of one pixel around it); (bx, by):
 * the lanes' first pixel in the frame of a block of the tile and its ring (the tile's first pixel at (1, 1)), by
 * which the wide block is read; wb: the wide block where the tile has dithered pixels, else NULL. */
static void resolve_lanes(hz_taa_t *t, const hz_render_frame_t *f, uint32_t x, uint32_t y, const samples_t *s,
                          uint32_t bx, uint32_t by, const wide_t *wb)
{
    const int32_t w = (int32_t)f->opts.width, h = (int32_t)f->opts.height;
    const hz_gbuffer_t *gb = &f->gb;
    const size_t p0 = (size_t)y * (size_t)w + x;
    const hz_li_t zero = hz_li_set(0), one = hz_li_set(1);

    hz_lrgb_t c, mean, ext;
    HZ_UNROLL
    for (int k = 0; k < 3; k++) {
        c.c[k] = hz_lf_load(s->yc[k]);
        box_stats(s->yc[k] - s->stride - 1, s->stride, 3, hz_lf_set(f->opts.taa_gamma), &mean.c[k], &ext.c[k]);
    }

    const hz_li_t xi = hz_li_add(hz_li_set((int32_t)x), hz_li_iota());
    hz_lf_t hx = hz_lf_add(hz_lf_from_li(xi), hz_lf_set(0.5f)), hy = hz_lf_set((float)y + 0.5f);
    hz_li_t reset = t->hist_valid ? zero : hz_li_set(-1);
    hz_lf_t mx = hz_lf_set(0.0f), my = mx;
    if (gb->mv)
        hz_lf_load2(gb->mv + 2 * p0, &mx, &my);
    if (t->hist_valid && gb->mv) {
        hx = hz_lf_add(hx, mx);
        hy = hz_lf_add(hy, my);
    }
    hz_li_t inside = hz_li_and(hz_li_and(hz_li_not(hz_lf_lt(hx, hz_lf_set(0.0f))), hz_li_not(hz_lf_lt(hy, hz_lf_set(0.0f)))),
                               hz_li_and(hz_lf_lt(hx, hz_lf_set((float)w)), hz_lf_lt(hy, hz_lf_set((float)h))));
    /* hx >= 0 is "not below 0 and not NaN": NaN fails lt(hx, w) anyway */
    reset = hz_li_or(reset, hz_li_not(inside));
    /* Dithered lanes: the wide box and the cell's mean; their object changes by design (no disocclusion test). */
    hz_li_t dith = zero;
    if (wb) {
        dith = hz_li_not(hz_li_eq(hz_li_and(hz_li_load_u8(gb->flags + p0), hz_li_set(HZ_GB_DITHER)), zero));
        if (hz_li_any(dith)) {
            /* camera moved, or the surface (no motion vectors: mx = my = 0, still) */
            const hz_li_t moving = f->camera_moved ? hz_li_set(-1)
                                                   : hz_li_not(hz_li_and(hz_lf_eq(mx, hz_lf_set(0.0f)),
                                                                         hz_lf_eq(my, hz_lf_set(0.0f))));
            hz_lrgb_t dc = c, dmean, dext;
            dither_box_lanes(wb, f, bx - 1u, by - 1u, hz_li_and(moving, dith), &dc, &dmean, &dext);
            HZ_UNROLL
            for (int k = 0; k < 3; k++) {
                c.c[k] = hz_lf_sel(dith, dc.c[k], c.c[k]);
                mean.c[k] = hz_lf_sel(dith, dmean.c[k], mean.c[k]);
                ext.c[k] = hz_lf_sel(dith, dext.c[k], ext.c[k]);
            }
        }
    }

    /* history footprint: the four pixels around (hx - 0.5, hy - 0.5) */
    hz_lf_t fx = hz_lf_sub(hx, hz_lf_set(0.5f)), fy = hz_lf_sub(hy, hz_lf_set(0.5f));
    hz_lf_t flx = hz_lf_floor(fx), fly = hz_lf_floor(fy);
    hz_li_t ix = hz_li_from_lf(flx), iy = hz_li_from_lf(fly);
    hz_li_t xa = clamp_index(ix, w), xb = clamp_index(hz_li_add(ix, one), w);
    hz_li_t ya = clamp_index(iy, h), yb = clamp_index(hz_li_add(iy, one), h);

    /* disocclusion (seen_before in taa.c): the object now here was at none of the four */
    const hz_li_t object = hz_li_load_u16(gb->object + p0);
    const int32_t n = w * h;
    const hz_li_t wv = hz_li_set(w);
    hz_li_t ra = hz_li_mul(ya, wv), rb = hz_li_mul(yb, wv);
    /* Where the lanes' footprints are side by side in the same two rows (the motion's integer part alike, none
     * clamped at the edge: most of every frame), the four taps are runs of consecutive pixels: loads instead of
     * gathers, the same values. */
    const int32_t xa0 = hz_li_first(xa), ra0 = hz_li_first(ra), rb0 = hz_li_first(rb);
    const hz_li_t run = hz_li_add(hz_li_set(xa0), hz_li_iota());
    const int contiguous = xa0 + HZ_LANES < w && !hz_li_any(hz_li_or(
        hz_li_or(hz_li_not(hz_li_eq(xa, run)), hz_li_not(hz_li_eq(xb, hz_li_add(run, one)))),
        hz_li_or(hz_li_not(hz_li_eq(ra, hz_li_set(ra0))), hz_li_not(hz_li_eq(rb, hz_li_set(rb0))))));
    hz_li_t seen;
    if (contiguous) {
        const uint16_t *oa = t->prev_object + ra0 + xa0, *ob = t->prev_object + rb0 + xa0;
        seen = hz_li_eq(hz_li_load_u16(oa), object);
        seen = hz_li_or(seen, hz_li_eq(hz_li_load_u16(oa + 1), object));
        seen = hz_li_or(seen, hz_li_eq(hz_li_load_u16(ob), object));
        seen = hz_li_or(seen, hz_li_eq(hz_li_load_u16(ob + 1), object));
    } else {
        seen = hz_li_eq(object_at(t->prev_object, hz_li_add(ra, xa), n), object);
        seen = hz_li_or(seen, hz_li_eq(object_at(t->prev_object, hz_li_add(ra, xb), n), object));
        seen = hz_li_or(seen, hz_li_eq(object_at(t->prev_object, hz_li_add(rb, xa), n), object));
        seen = hz_li_or(seen, hz_li_eq(object_at(t->prev_object, hz_li_add(rb, xb), n), object));
    }
    reset = hz_li_or(reset, hz_li_andnot(hz_li_not(seen), dith));

    hz_lrgb_t res = c;
    if (hz_li_any(hz_li_not(reset))) {
        const uint16_t *hist = t->hist[t->hist_index];
        hz_lf_t ax = hz_lf_sub(fx, flx), ay = hz_lf_sub(fy, fly);
        hz_lrgb_t a, b, cc, d, hrgb, hy3;
#ifdef HZ_LANES_HW_HALF
        const uint16_t *ha = hist + 3 * ((size_t)ra0 + (size_t)xa0), *hb = hist + 3 * ((size_t)rb0 + (size_t)xa0);
        if (!(contiguous && hz_lanes_half3_load(ha, &a) && hz_lanes_half3_load(ha + 3, &b) &&
              hz_lanes_half3_load(hb, &cc) && hz_lanes_half3_load(hb + 3, &d)))
#endif
        {
            a = hist_at(hist, xa, ya, w), b = hist_at(hist, xb, ya, w);
            cc = hist_at(hist, xa, yb, w), d = hist_at(hist, xb, yb, w);
        }
        HZ_UNROLL
        for (int k = 0; k < 3; k++) {
            hz_lf_t top = hz_lf_add(a.c[k], hz_lf_mul(hz_lf_sub(b.c[k], a.c[k]), ax));
            hz_lf_t bot = hz_lf_add(cc.c[k], hz_lf_mul(hz_lf_sub(d.c[k], cc.c[k]), ax));
            hrgb.c[k] = hz_lf_add(top, hz_lf_mul(hz_lf_sub(bot, top), ay));
        }
        to_ycocg_lanes(&hrgb, &hy3);
        const hz_lf_t alpha = hz_lf_set(f->opts.taa_alpha);
        HZ_UNROLL
        for (int k = 0; k < 3; k++) {
            /* ext >= 0 (gamma > 0, render options) or NaN: no lane's low end is above its high end */
            hz_lf_t v = hz_lf_clamp_ordered(hy3.c[k], hz_lf_sub(mean.c[k], ext.c[k]), hz_lf_add(mean.c[k], ext.c[k]));
            v = hz_lf_add(v, hz_lf_mul(alpha, hz_lf_sub(c.c[k], v)));
            res.c[k] = hz_lf_sel(reset, c.c[k], v);
        }
    }
    hz_lf_t rgb[3];
    rgb[0] = hz_lf_sub(hz_lf_add(res.c[0], res.c[1]), res.c[2]);
    rgb[1] = hz_lf_add(res.c[0], res.c[2]);
    rgb[2] = hz_lf_sub(hz_lf_sub(res.c[0], res.c[1]), res.c[2]);
    hz_lrgb_t v;
    const hz_lf_t inf = hz_lf_from_bits(hz_li_set(0x7f800000));
    HZ_UNROLL
    for (int k = 0; k < 3; k++) {
        /* finite and > 0: above 0 and below infinity (NaN is neither) */
        hz_li_t ok = hz_li_and(hz_lf_gt(rgb[k], hz_lf_set(0.0f)), hz_lf_lt(rgb[k], inf));
        v.c[k] = hz_lf_keep(ok, rgb[k]);
    }
    hz_lf_store3(t->out.rgb + p0 * 3, v.c[0], v.c[1], v.c[2]);
    hz_lanes_half3_store(t->hist[t->hist_index ^ 1u] + p0 * 3, &v);
}

static void resolve_tile(hz_taa_t *t, const hz_render_frame_t *f, uint32_t tile, bool prefetch_next)
{
    const uint32_t w = f->opts.width, h = f->opts.height;
    const uint32_t x0 = (tile % f->tiles_x) * T, y0 = (tile / f->tiles_x) * T;
    if (f->opts.taa_clip || f->opts.taa_catmull_rom || x0 + T > w || y0 + T > h || w * h < 2) {
        hz_taa_resolve_tile_scalar(t, f, tile);
        return;
    }
    /* Inside the image with its ring, the tile's box reads the sample planes; at the image's edge, a block of
     * the tile and its ring, edge-clamped as the twin reads them. */
    const bool inside = x0 > 0 && y0 > 0 && x0 + T < w && y0 + T < h;
    float yc[3][B][B];
    if (!inside) {
        for (uint32_t by = 0; by < B; by++) {
            int32_t y = (int32_t)(y0 + by) - 1;
            y = y < 0 ? 0 : y >= (int32_t)h ? (int32_t)h - 1 : y;
            for (uint32_t bx = 0; bx < B; bx++) {
                int32_t x = (int32_t)(x0 + bx) - 1;
                x = x < 0 ? 0 : x >= (int32_t)w ? (int32_t)w - 1 : x;
                HZ_UNROLL
                for (int k = 0; k < 3; k++)
                    yc[k][by][bx] = t->cur[k][(size_t)y * w + (size_t)x];
            }
        }
    } else if (prefetch_next && x0 + 2 * T < w) {
        /* The next tile's samples and ring, fetched while this one resolves: the trace wrote them a while
         * ago and they have mostly left the cache. */
        for (uint32_t by = 0; by < B; by++) {
            const size_t row = (size_t)(y0 + by - 1u) * w + x0 + T - 1u;
            HZ_UNROLL
            for (int k = 0; k < 3; k++) {
                hz_lanes_prefetch(t->cur[k] + row);
                hz_lanes_prefetch(t->cur[k] + row + B - 1u);
            }
        }
    }
    /* the wide block, where the tile has a dithered pixel */
    wide_t wbuf;
    const wide_t *wb = NULL;
    if (tile_dithered(f, x0, y0)) {
        wide_fill(&wbuf, t, f, x0, y0);
        wb = &wbuf;
    }
    for (uint32_t y = y0; y < y0 + T; y++)
        for (uint32_t x = x0; x < x0 + T; x += HZ_LANES) {
            const uint32_t bx = x - x0 + 1u, by = y - y0 + 1u;
            samples_t s;
            if (inside) {
                s.stride = w;
                HZ_UNROLL
                for (int k = 0; k < 3; k++)
                    s.yc[k] = t->cur[k] + (size_t)y * w + x;
            } else {
                s.stride = B;
                HZ_UNROLL
                for (int k = 0; k < 3; k++)
                    s.yc[k] = &yc[k][by][bx];
            }
            resolve_lanes(t, f, x, y, &s, bx, by, wb);
        }
}

void hz_taa_resolve_tiles(hz_taa_t *t, const hz_render_frame_t *f, uint32_t first, uint32_t count)
{
    for (uint32_t i = 0; i < count; i++)
        resolve_tile(t, f, first + i, i + 1u < count);
}

/* A packet is 2 rows of HZ_LANES / 2 pixels (hz_tile_slots), each row consecutive in the planes. */
typedef char packet_is_lanes[HZ_RENDER_LANES == HZ_LANES ? 1 : -1];

void hz_taa_store_samples(hz_taa_t *t, hz_batch_t *b)
{
    const uint32_t half = HZ_LANES / 2;
    for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot += HZ_LANES) {
        const uint32_t lo = b->pixel[slot], hi = b->pixel[slot + half];
        hz_lrgb_t c, q;
        hz_lf_load3(&b->radiance[slot * 3], &c.c[0], &c.c[1], &c.c[2]);
        hz_li_t bad = hz_li_set(0);
        HZ_UNROLL
        for (int k = 0; k < 3; k++)
            bad = hz_li_or(bad, hz_li_not(hz_lf_finite(c.c[k])));
        /* A row of a packet runs left to right and the image's edge cuts it only at its right end (or whole), so
         * its last slot says whether it is whole. A packet cut by the edge, or with a value to count: the twin's
         * way, pixel by pixel. */
        const bool whole = b->pixel[slot + half - 1u] == lo + half - 1u && lo != UINT32_MAX &&
                           b->pixel[slot + HZ_LANES - 1u] == hi + half - 1u && hi != UINT32_MAX;
        if (!whole || hz_li_any(bad)) {
            for (uint32_t i = slot; i < slot + HZ_LANES; i++)
                if (b->pixel[i] != UINT32_MAX)
                    hz_taa_store_slot(t, b, i);
            continue;
        }
        HZ_UNROLL
        for (int k = 0; k < 3; k++) /* v * 1 is v; v > 0 ? v : +0 */
            c.c[k] = hz_lf_keep(hz_lf_gt(c.c[k], hz_lf_set(0.0f)), c.c[k]);
        to_ycocg_lanes(&c, &q);
        HZ_UNROLL
        for (int k = 0; k < 3; k++)
            hz_lf_store_halves(t->cur[k] + lo, t->cur[k] + hi, q.c[k]);
    }
}
