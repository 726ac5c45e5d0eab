/* The tdense resolve of one pixel row in SIMD lanes (src/core/lanes.h: 8 pixels at a time on AVX2, 4 on NEON),
 * bit-identical to hz_tdense_resolve_pixel (tdense.c), which is its scalar twin.
 *
 * Every lane computes Fig. 3's cases (the sliding 3x3 longest motion, the newest-subframe box, the static
 * window's update and average, the bilinear reprojection and clamp (its taps loaded, not gathered, where the
 * lanes' footprints are consecutive), the window's RGB9E5 codes, the history's half codes) and selects per lane,
 * with the scalar code's operations in its order, so each result has the same bits; a case no lane of a group
 * needs is skipped. The pixels of a row past its last full group of lanes go to hz_tdense_resolve_pixel. The
 * history is in half-float planes so that a tap or a store of one channel for all lanes is one conversion
 * instruction: decoding four RGB9E5 taps and encoding the new code had been about a seventh of this kernel. */
#include "../core/pack_lanes.h"
#include "hz/pack.h"
#include "hz/vmath.h"
#include "tdense_internal.h"

typedef struct lmotion {
    hz_lf_t x, y, l2;
} lmotion_t;

typedef hz_lrgb_t lrgb_t;

/* The motion of a group from its (x, y) half pairs (x in the low 16 bits, little-endian); `checked`: no code has
 * exponent 31, so the conversion instruction reads every one as hz_half_unpack does. */
HZ_INLINE lmotion_t motion_lanes(hz_li_t v, int checked)
{
    lmotion_t m;
#ifdef HZ_LANES_HW_HALF
    if (checked) {
        m.x = hz_lanes_half_hw_unpack(hz_li_and(v, hz_li_set(0xffff)));
        m.y = hz_lanes_half_hw_unpack(hz_li_shr(v, 16));
    } else
#endif
    {
        (void)checked;
        m.x = hz_lanes_half_unpack_bits(hz_li_and(v, hz_li_set(0xffff)));
        m.y = hz_lanes_half_unpack_bits(hz_li_shr(v, 16));
    }
    m.l2 = hz_lf_add(hz_lf_mul(m.x, m.x), hz_lf_mul(m.y, m.y));
    return m;
}

/* Bit 15 and bit 31 of each lane: the low and the high half code has exponent 31 (its exponent field plus one
 * carries into the sign bit's place; the low half's carry stops there). */
HZ_INLINE hz_li_t half_pair_e31(hz_li_t v)
{
    const hz_li_t field = hz_li_and(v, hz_li_set(0x7c007c00));
    return hz_li_and(hz_li_add(field, hz_li_set(0x04000400)), hz_li_set(INT32_MIN | 0x8000));
}

/* longer(a, b): b where b.l2 > a.l2, else a. */
HZ_INLINE lmotion_t longer(lmotion_t a, lmotion_t b)
{
    hz_li_t gt = hz_lf_gt(b.l2, a.l2);
    lmotion_t r;
    r.x = hz_lf_sel(gt, b.x, a.x);
    r.y = hz_lf_sel(gt, b.y, a.y);
    r.l2 = hz_lf_sel(gt, b.l2, a.l2);
    return r;
}

HZ_INLINE lmotion_t broadcast(hz_tdense_motion_t m)
{
    lmotion_t r;
    r.x = hz_lf_set(m.x);
    r.y = hz_lf_set(m.y);
    r.l2 = hz_lf_set(m.l2);
    return r;
}

/* Column maxima at x .. x + HZ_LANES - 1 (all inside the row). hz_tdense_put never stores a code with exponent
 * 31, so one test for the three rows (the state is public, so it is still tested) lets all six conversions use
 * the instruction. */
HZ_INLINE lmotion_t column_lanes(const uint16_t *r0, const uint16_t *r1, const uint16_t *r2, size_t x)
{
    const hz_li_t v0 = hz_li_load(r0 + 2 * x), v1 = hz_li_load(r1 + 2 * x), v2 = hz_li_load(r2 + 2 * x);
    if (HZ_LIKELY(!hz_li_any(hz_li_or(hz_li_or(half_pair_e31(v0), half_pair_e31(v1)), half_pair_e31(v2)))))
        return longer(longer(motion_lanes(v0, 1), motion_lanes(v1, 1)), motion_lanes(v2, 1));
    return longer(longer(motion_lanes(v0, 0), motion_lanes(v1, 0)), motion_lanes(v2, 0));
}

/* HZ_LANES tiles of one tile row starting one before `first` (the tile of lane 0's pixel): this subframe's pixel
 * of each (0..3) and their samples. Lanes pick their tiles from it with hz_*_perm: no gathers. */
typedef struct tile_row {
    hz_li_t pix;
    hz_lf_t c[3];
} tile_row_t;

/* This subframe's pixel (0..3) of every ordering: orderings 0..15 in 2-bit fields of word[0], 16..31 (24..31
 * repeat 0..7, as hz_tileorder_pixel's order % 24 does) in word[1]. */
typedef struct order_pixels {
    uint32_t word[2];
    unsigned subframe;
} order_pixels_t;

static void order_pixels_init(order_pixels_t *op, unsigned subframe)
{
    op->word[0] = op->word[1] = 0;
    op->subframe = subframe;
    for (unsigned o = 0; o < 32; o++)
        op->word[o >> 4] |= (uint32_t)hz_tileorder_pixel(o, subframe) << (2u * (o & 15u));
}

/* Lane i: the pixel of ordering o_i, by two shifts instead of a table gather (gathers are slow on some cores
 * and this runs twice for every group of pixels). Orderings of 32 or more never occur (the ĝ writes 0..23)
 * but are answered as the scalar code answers them. */
HZ_INLINE hz_li_t order_pixel_lanes(const order_pixels_t *op, hz_li_t o)
{
    if (HZ_UNLIKELY(hz_li_any(hz_li_gt(o, hz_li_set(31))))) {
        int32_t v[HZ_LANES];
        hz_li_store(v, o);
        for (int i = 0; i < HZ_LANES; i++)
            v[i] = (int32_t)hz_tileorder_pixel((unsigned)v[i], op->subframe);
        return hz_li_load(v);
    }
    const hz_li_t sh = hz_li_shl(o, 1);
    const hz_li_t a = hz_li_shr_lanes(hz_li_set((int32_t)op->word[0]), sh);
    const hz_li_t b = hz_li_shr_lanes(hz_li_set((int32_t)op->word[1]), hz_li_sub(sh, hz_li_set(32)));
    return hz_li_and(hz_li_or(a, b), hz_li_set(3));
}

HZ_INLINE void tile_row_load(const hz_tdense_t *td, const order_pixels_t *lut, size_t first, tile_row_t *r)
{
    r->pix = order_pixel_lanes(lut, hz_li_load_u8(td->orders + first - 1));
    HZ_UNROLL
    for (int k = 0; k < 3; k++)
        r->c[k] = hz_lf_load(td->sub_rgb[k] + first - 1);
}

/* One candidate of the newest-subframe box (newest_box in tdense.c): the tile at lane idx of row, tile (ctx,
 * cty), where `valid`; skipped when its pixel this subframe is not adjacent (`across`: the tile lies beside,
 * `updown`: above or below) or, with `bounds`, lies outside the image (callers leave `bounds` out where no
 * candidate tile can be cut by the image's edge). Adds its sample to sum/sq and counts it in n (masks are -1).
 * A skipped candidate adds +0: the sums start at +0 and can never be -0, so x + 0 is x, as the twin leaves it. */
HZ_INLINE void box_candidate(const hz_tdense_t *td, const tile_row_t *row, hz_li_t idx, hz_li_t valid, hz_li_t ctx,
                             int32_t cty, hz_li_t px, int32_t py, int across, int updown, int bounds,
                             hz_lf_t sum[3], hz_lf_t sq[3], hz_li_t *n)
{
    hz_li_t pix = hz_li_perm(row->pix, idx);
    hz_li_t pbx = hz_li_and(pix, hz_li_set(1)), pby = hz_li_shr(pix, 1);
    hz_li_t use = valid;
    if (bounds) {
        hz_li_t nx = hz_li_add(hz_li_add(ctx, ctx), pbx), ny = hz_li_add(hz_li_set(2 * cty), pby);
        use = hz_li_and(use, hz_li_and(hz_li_gt(hz_li_set((int32_t)td->cfg.width), nx),
                                       hz_li_gt(hz_li_set((int32_t)td->cfg.height), ny)));
    }
    if (across)
        use = hz_li_andnot(use, hz_li_eq(pbx, px));
    if (updown)
        use = hz_li_andnot(use, hz_li_eq(pby, hz_li_set(py)));
    HZ_UNROLL
    for (int k = 0; k < 3; k++) {
        hz_lf_t c = hz_lf_keep(use, hz_lf_perm(row->c[k], idx));
        sum[k] = hz_lf_add(sum[k], c);
        sq[k] = hz_lf_add(sq[k], hz_lf_mul(c, c));
    }
    *n = hz_li_sub(*n, use);
}

/* fetch_bilinear (tdense.c) of the half-float planes prev (w x h) at (sx, sy), lane by lane. */
HZ_INLINE lrgb_t fetch_bilinear(const uint16_t *prev, uint32_t w, uint32_t h, hz_lf_t sx, hz_lf_t sy)
{
    sx = hz_lf_clamp_ordered(sx, hz_lf_set(0.0f), hz_lf_set((float)w - 1.0f));
    sy = hz_lf_clamp_ordered(sy, hz_lf_set(0.0f), hz_lf_set((float)h - 1.0f));
    hz_li_t x0 = hz_li_from_lf(sx), y0 = hz_li_from_lf(sy);
    hz_lf_t fx = hz_lf_sub(sx, hz_lf_from_li(x0)), fy = hz_lf_sub(sy, hz_lf_from_li(y0));
    hz_li_t x1 = hz_li_add(x0, hz_li_set(1)), y1 = hz_li_add(y0, hz_li_set(1));
    x1 = hz_li_sel(hz_li_gt(hz_li_set((int32_t)w), x1), x1, x0);
    y1 = hz_li_sel(hz_li_gt(hz_li_set((int32_t)h), y1), y1, y0);
    const hz_li_t wv = hz_li_set((int32_t)w);
    hz_li_t row0 = hz_li_mul(y0, wv), row1 = hz_li_mul(y1, wv);
    const size_t px = (size_t)w * h;
    /* Footprints side by side in the same two rows (the motion's integer part alike, none clamped at the right
     * edge: most pixels): the four taps are runs of consecutive codes, loaded instead of gathered. */
    const int32_t x00 = hz_li_first(x0), r0 = hz_li_first(row0), r1 = hz_li_first(row1);
    const hz_li_t run = hz_li_add(hz_li_set(x00), hz_li_iota());
    const int contiguous = x00 + HZ_LANES < (int32_t)w &&
                           !hz_li_any(hz_li_or(hz_li_not(hz_li_eq(x0, run)),
                                               hz_li_or(hz_li_not(hz_li_eq(row0, hz_li_set(r0))),
                                                        hz_li_not(hz_li_eq(row1, hz_li_set(r1))))));
    const hz_li_t i00 = hz_li_add(row0, x0), i01 = hz_li_add(row0, x1);
    const hz_li_t i10 = hz_li_add(row1, x0), i11 = hz_li_add(row1, x1);
    lrgb_t o;
    HZ_UNROLL
    for (int k = 0; k < 3; k++) {
        const uint16_t *plane = prev + (size_t)k * px;
        hz_lf_t a, b, c, d;
        if (contiguous) { /* x1 = x0 + 1 in every lane then */
            const uint16_t *t0 = plane + r0 + x00, *t1 = plane + r1 + x00;
            a = hz_lanes_half_load(t0), b = hz_lanes_half_load(t0 + 1);
            c = hz_lanes_half_load(t1), d = hz_lanes_half_load(t1 + 1);
        } else {
            a = hz_lanes_half_gather(plane, i00), b = hz_lanes_half_gather(plane, i01);
            c = hz_lanes_half_gather(plane, i10), d = hz_lanes_half_gather(plane, i11);
        }
        hz_lf_t top = hz_lf_add(a, hz_lf_mul(hz_lf_sub(b, a), fx));
        hz_lf_t bot = hz_lf_add(c, hz_lf_mul(hz_lf_sub(d, c), fx));
        o.c[k] = hz_lf_add(top, hz_lf_mul(hz_lf_sub(bot, top), fy));
    }
    return o;
}

/* The moving window of static pixels that got a jittered sample (lanes in `window`; `bit` is the sample's slot as
 * a bit there, 0 elsewhere; out holds the sample there): the sample's code replaces its slot, and the pixel shows the average of
 * the slots its flags f and the new bit name, summed in MSAA order (window_average in tdense.c; a skipped slot
 * adds +0 to a sum of non-negative values). The other lanes' slots are written back unchanged. */
HZ_INLINE void window_lanes(uint32_t *win, hz_li_t window, hz_li_t bit, hz_li_t f, lrgb_t *out)
{
    hz_li_t slot[4];
    hz_li_load4(win, slot);
    const hz_li_t code = hz_lanes_rgb9e5_pack(out), zero = hz_li_set(0);
    const hz_li_t mask = hz_li_or(f, bit);
    lrgb_t sum;
    HZ_UNROLL
    for (int k = 0; k < 3; k++)
        sum.c[k] = hz_lf_set(0.0f);
    hz_li_t n = zero;
    HZ_UNROLL
    for (int j = 0; j < 4; j++) {
        const hz_li_t jbit = hz_li_set(1 << j);
        slot[j] = hz_li_sel(hz_li_not(hz_li_eq(hz_li_and(bit, jbit), zero)), code, slot[j]);
        const hz_li_t has = hz_li_not(hz_li_eq(hz_li_and(mask, jbit), zero));
        const lrgb_t c = hz_lanes_rgb9e5_unpack(slot[j]);
        HZ_UNROLL
        for (int k = 0; k < 3; k++)
            sum.c[k] = hz_lf_add(sum.c[k], hz_lf_keep(has, c.c[k]));
        n = hz_li_sub(n, has);
    }
    hz_li_store4(win, slot);
    const hz_li_t four = hz_li_eq(n, hz_li_set(4));
    const hz_lf_t count = hz_lf_from_li(hz_li_max(n, hz_li_set(1))); /* n >= 1 in the window's lanes */
    HZ_UNROLL
    for (int k = 0; k < 3; k++) {
        const hz_lf_t avg = hz_lf_sel(four, hz_lf_mul(sum.c[k], hz_lf_set(0.25f)), hz_lf_div(sum.c[k], count));
        out->c[k] = hz_lf_sel(window, avg, out->c[k]);
    }
}

/* HZ_LANES pixels x0 .. x0 + HZ_LANES - 1 of row y with their 3x3 longest motion m. `inside`: every candidate
 * tile of the box lies in the tile grid with its pixel in the image (resolve_row_lanes says when), so the box
 * needs no bounds and every pixel has at least its own tile's sample (n >= 1). */
HZ_INLINE void resolve_lanes(hz_tdense_t *td, uint32_t x0, uint32_t y, const order_pixels_t *lut,
                             lmotion_t m, const uint16_t *prev, uint16_t *cur, int inside)
{
    const uint32_t w = td->cfg.width, tw = td->tiles_x;
    const int32_t ty = (int32_t)(y >> 1), py = (int32_t)(y & 1u);
    const size_t p0 = (size_t)y * w + x0;
    const hz_li_t zero = hz_li_set(0), ones = hz_li_set(-1);
    const hz_li_t x = hz_li_add(hz_li_set((int32_t)x0), hz_li_iota());
    const hz_li_t tx = hz_li_shr(x, 1), px = hz_li_and(x, hz_li_set(1));

    /* Lane i's own tile is first + i / 2, the one beside it first + i / 2 - 1 (left pixel of its tile) or
     * + 1 (right pixel): lanes 1 + i / 2 and i / 2 + 2 (i & 1) of a tile row loaded from first - 1. */
    const hz_li_t half = hz_li_shr(hz_li_iota(), 1);
    const hz_li_t own_idx = hz_li_add(half, hz_li_set(1));
    const hz_li_t across_idx = hz_li_add(half, hz_li_shl(hz_li_and(hz_li_iota(), hz_li_set(1)), 1));
    const size_t first = (size_t)ty * tw + x0 / 2;
    tile_row_t own;
    tile_row_load(td, lut, first, &own);
    const hz_li_t pix0 = hz_li_perm(own.pix, own_idx);
    const hz_li_t fresh = hz_li_eq(pix0, hz_li_or(hz_li_set(py << 1), px));
    const hz_li_t jit = hz_li_perm(hz_li_load_u8((const uint8_t *)td->sub_jitter + first - 1), own_idx);
    const hz_li_t jpos = hz_li_gt(hz_li_set(0x80), jit); /* int8 >= 0 */
    const hz_li_t stat = td->camera_moved ? zero : hz_lf_eq(m.l2, hz_lf_set(0.0f));
    const hz_li_t window = hz_li_and(stat, hz_li_and(fresh, jpos)); /* a jittered sample for the window */

    /* newest-subframe box over up to four candidates, in newest_box's order */
    hz_lf_t sum[3], sq[3];
    HZ_UNROLL
    for (int k = 0; k < 3; k++)
        sum[k] = sq[k] = hz_lf_set(0.0f);
    hz_li_t n = zero;
    const int32_t cy = py ? (ty + 1 < (int32_t)td->tiles_y ? ty + 1 : -1) : ty - 1;
    const hz_li_t right = hz_li_eq(px, hz_li_set(1));
    const hz_li_t cx = hz_li_sel(right, hz_li_add(tx, hz_li_set(1)), hz_li_sub(tx, hz_li_set(1)));
    const hz_li_t cx_ok = inside ? ones : hz_li_sel(right, hz_li_gt(hz_li_set((int32_t)tw), cx), hz_li_gt(tx, zero));
    box_candidate(td, &own, own_idx, ones, tx, ty, px, py, 0, 0, !inside, sum, sq, &n);
    box_candidate(td, &own, across_idx, cx_ok, cx, ty, px, py, 1, 0, !inside, sum, sq, &n);
    if (cy >= 0) {
        tile_row_t other;
        tile_row_load(td, lut, (size_t)cy * tw + x0 / 2, &other);
        box_candidate(td, &other, own_idx, ones, tx, cy, px, py, 0, 1, !inside, sum, sq, &n);
        box_candidate(td, &other, across_idx, cx_ok, cx, cy, px, py, 1, 1, !inside, sum, sq, &n);
    }
    /* 1 / n as the twin divides it: n is 0..4, the table's quotients are correctly rounded like the twin's */
    static const float inverse[8] = { 1.0f, 1.0f / 2.0f, 1.0f / 3.0f, 1.0f / 4.0f, 0.0f, 0.0f, 0.0f, 0.0f };
    const hz_li_t has = inside ? ones : hz_li_gt(n, zero);
    const hz_lf_t inv = hz_lf_keep(has, hz_lf_perm(hz_lf_load(inverse), hz_li_sub(n, hz_li_set(1))));
    lrgb_t mean, var;
    HZ_UNROLL
    for (int k = 0; k < 3; k++) {
        mean.c[k] = hz_lf_mul(sum[k], inv);
        var.c[k] = hz_lf_max_first(hz_lf_sub(hz_lf_mul(sq[k], inv), hz_lf_mul(mean.c[k], mean.c[k])),
                                   hz_lf_set(0.0f));
    }

    const hz_li_t f = hz_li_load_u8(td->flags + p0);
    const hz_li_t seen = hz_li_not(hz_li_eq(hz_li_and(f, hz_li_set(HZ_TDENSE_SEEN)), zero));
    const size_t plane = (size_t)w * td->cfg.height; /* codes per history plane */
    const hz_li_t old = hz_li_andnot(ones, fresh);
    const hz_li_t keep = hz_li_and(stat, hz_li_and(old, seen)); /* static, old, seen: the previous frame's */
    const hz_li_t reproject = hz_li_andnot(hz_li_and(old, seen), stat);

    /* each lane's colour: its new sample, the box mean (never seen), the previous frame's value (kept) or
     * the reprojected and clamped one; the kept and reprojected values are made only where a lane needs them */
    lrgb_t out = mean;
    if (hz_li_any(keep)) {
        HZ_UNROLL
        for (int k = 0; k < 3; k++)
            out.c[k] = hz_lf_sel(keep, hz_lanes_half_load(prev + (size_t)k * plane + p0), out.c[k]);
    }
    if (hz_li_any(reproject)) {
        hz_lf_t sx = hz_lf_add(hz_lf_from_li(x), m.x), sy = hz_lf_add(hz_lf_set((float)y), m.y);
        const lrgb_t moved = fetch_bilinear(prev, w, td->cfg.height, sx, sy);
        const hz_lf_t gamma = hz_lf_set(td->cfg.gamma);
        HZ_UNROLL
        for (int k = 0; k < 3; k++) {
            /* half >= 0 or NaN (gamma >= 0), so lo <= hi or NaN: the ordered clamp is the twin's */
            hz_lf_t hw = hz_lf_mul(gamma, hz_lf_sqrt(var.c[k]));
            hz_lf_t c = hz_lf_clamp_ordered(moved.c[k], hz_lf_sub(mean.c[k], hw), hz_lf_add(mean.c[k], hw));
            if (!inside)
                c = hz_lf_sel(has, c, moved.c[k]);
            /* mean where no candidate: it is +0 then (sum 0 times inv 0) */
            c = hz_lf_sel(hz_lf_finite(c), c, mean.c[k]);
            out.c[k] = hz_lf_sel(reproject, c, out.c[k]);
        }
    }
    HZ_UNROLL
    for (int k = 0; k < 3; k++)
        out.c[k] = hz_lf_sel(fresh, hz_lf_perm(own.c[k], own_idx), out.c[k]);
    /* the window slot of each static pixel with a jittered sample, as a bit (0 in the other lanes) */
    static const int32_t slot_bit[8] = { 1, 2, 4, 8, 0, 0, 0, 0 };
    hz_li_t bit = zero;
    if (hz_li_any(window)) {
        bit = hz_li_and(window, hz_li_perm(hz_li_load(slot_bit), hz_li_and(jit, hz_li_set(3))));
        window_lanes(td->window + 4 * p0, window, bit, hz_li_and(f, hz_li_set(HZ_TDENSE_SAMPLES)), &out);
    }

    /* history codes and flags. A kept lane shows the previous frame's value, whose codes it writes again: the
     * scalar twin copies them (or finds them there when the previous frame kept them too), the same bits, as
     * a half code that hz_half_pack wrote comes back from hz_half_pack(hz_half_unpack(code)). */
    HZ_UNROLL
    for (int k = 0; k < 3; k++)
        hz_lanes_half_store(cur + (size_t)k * plane + p0, out.c[k]);
    const hz_li_t dyn_bit = hz_li_set(HZ_TDENSE_DYNAMIC), samples = hz_li_set(HZ_TDENSE_SAMPLES);
    hz_li_t f_stat = hz_li_andnot(f, dyn_bit);
    /* a fresh static pixel: a jittered sample adds its slot, a centre sample empties the window */
    f_stat = hz_li_sel(fresh, hz_li_sel(window, hz_li_or(f_stat, bit), hz_li_andnot(f_stat, samples)), f_stat);
    hz_li_t f1 = hz_li_sel(stat, f_stat, hz_li_or(hz_li_andnot(f, samples), dyn_bit));
    hz_li_t nf = hz_li_sel(keep, hz_li_or(f1, hz_li_set(HZ_TDENSE_KEPT)),
                           hz_li_andnot(hz_li_or(f1, hz_li_set(HZ_TDENSE_SEEN)), hz_li_set(HZ_TDENSE_KEPT)));
    hz_li_store_u8(td->flags + p0, nf);

    hz_lf_store3(hz_image_at(&td->out, x0, y), out.c[0], out.c[1], out.c[2]);
}

/* resolve_lanes for groups inside the image's interior, and for the others: two copies, each specialised. */
static void resolve_inside(hz_tdense_t *td, uint32_t x0, uint32_t y, const order_pixels_t *lut, lmotion_t m,
                           const uint16_t *prev, uint16_t *cur)
{
    resolve_lanes(td, x0, y, lut, m, prev, cur, 1);
}

static void resolve_edge(hz_tdense_t *td, uint32_t x0, uint32_t y, const order_pixels_t *lut, lmotion_t m,
                         const uint16_t *prev, uint16_t *cur)
{
    resolve_lanes(td, x0, y, lut, m, prev, cur, 0);
}

void hz_tdense_resolve_row_lanes(hz_tdense_t *td, uint32_t y, unsigned subframe, const uint16_t *prev,
                                 uint16_t *cur)
{
    const uint32_t w = td->cfg.width, h = td->cfg.height, L = HZ_LANES;
    const uint16_t *r0 = td->mv ? td->mv + 2 * (size_t)(y ? y - 1 : 0) * w : NULL;
    const uint16_t *r1 = td->mv ? td->mv + 2 * (size_t)y * w : NULL;
    const uint16_t *r2 = td->mv ? td->mv + 2 * (size_t)(y + 1 < h ? y + 1 : y) * w : NULL;
    order_pixels_t lut;
    order_pixels_init(&lut, subframe);
    const uint32_t full = w / L * L;
    static const hz_tdense_motion_t still = { 0.0f, 0.0f, 0.0f };
    /* The box's candidate tiles of a group lie in the grid with their pixels in the image when the tile rows
     * (this one and the one above or below) are whole and the group keeps a tile and a pixel clear of the
     * left edge (x0 >= 2) and two tiles of the right (x0 + L + 2 <= w: the tile beside the last lane and its
     * right pixel). */
    const uint32_t ty = y >> 1;
    const int rows_inside = 2 * ty + 2 <= h && ((y & 1u) ? ty + 1 >= td->tiles_y || 2 * ty + 4 <= h : 1);
    /* columns x0 - 1 (the previous group's), x0 .. x0 + L - 1 and x0 + L (the next group's first) */
    lmotion_t prev_col = broadcast(td->mv ? hz_tdense_column_motion(r0, r1, r2, 0) : still), col, next_col;
    if (full)
        col = td->mv ? column_lanes(r0, r1, r2, 0) : broadcast(still);
    for (uint32_t x0 = 0; x0 < full; x0 += L) {
        if (!td->mv)
            next_col = broadcast(still);
        else if (x0 + 2 * L <= w)
            next_col = column_lanes(r0, r1, r2, x0 + L);
        else
            next_col = broadcast(hz_tdense_column_motion(r0, r1, r2, x0 + L < w ? x0 + L : w - 1));
        lmotion_t left, right;
        left.x = hz_lf_shift_in_left(prev_col.x, col.x);
        left.y = hz_lf_shift_in_left(prev_col.y, col.y);
        left.l2 = hz_lf_shift_in_left(prev_col.l2, col.l2);
        right.x = hz_lf_shift_in_right(col.x, next_col.x);
        right.y = hz_lf_shift_in_right(col.y, next_col.y);
        right.l2 = hz_lf_shift_in_right(col.l2, next_col.l2);
        const lmotion_t m = longer(longer(left, col), right);
        if (rows_inside && x0 >= 2 && x0 + L + 2 <= w)
            resolve_inside(td, x0, y, &lut, m, prev, cur);
        else
            resolve_edge(td, x0, y, &lut, m, prev, cur);
        prev_col = col;
        col = next_col;
    }
    for (uint32_t x = full; x < w; x++) {
        hz_tdense_motion_t m = still;
        if (td->mv) {
            hz_tdense_motion_t a = hz_tdense_column_motion(r0, r1, r2, x ? x - 1 : 0);
            hz_tdense_motion_t b = hz_tdense_column_motion(r0, r1, r2, x);
            hz_tdense_motion_t c = hz_tdense_column_motion(r0, r1, r2, x + 1 < w ? x + 1 : x);
            m = b.l2 > a.l2 ? b : a;
            m = c.l2 > m.l2 ? c : m;
        }
        hz_tdense_resolve_pixel(td, x, y, subframe, m, prev, cur);
    }
}

/* Both components in lanes 0 and 1: sanitise_motion (NaN as 0: an unordered lane fails the equality; the clamp
 * as hz_clampf on ordered values), then hz_half_pack_signed: the magnitude's code (hz_lanes_half_pack, the
 * conversion instruction where the board has one) with the sign bit where the value is negative and its code
 * is not 0 (no -0 code). */
uint32_t hz_tdense_motion_code_lanes(float x, float y)
{
    /* x in lane 0, y in the others: built in registers (scalar stores read back as one vector would stall) */
    hz_lf_t v = hz_lf_sel(hz_li_eq(hz_li_iota(), hz_li_set(0)), hz_lf_set(x), hz_lf_set(y));
    v = hz_lf_sel(hz_lf_eq(v, v), v, hz_lf_set(0.0f));
    v = hz_lf_clamp(v, hz_lf_set(-HZ_TDENSE_MAX_MOTION), hz_lf_set(HZ_TDENSE_MAX_MOTION));
    const hz_li_t mag = hz_lanes_half_pack(hz_lf_abs(v));
    const hz_li_t neg = hz_li_andnot(hz_lf_lt(v, hz_lf_set(0.0f)), hz_li_eq(mag, hz_li_set(0)));
    const hz_li_t code = hz_li_or(mag, hz_li_and(neg, hz_li_set(0x8000)));
    return (uint32_t)hz_li_first(code) | (uint32_t)hz_li_first(hz_li_perm(code, hz_li_set(1))) << 16;
}

/* Rows and columns outside the image are clamped onto its edge: the clamped rectangle of longest_in visited
 * with its edge row or column repeated, and a repeat right after the original changes nothing (longer keeps
 * the first of equals). Where the group's 4x4 blocks lie inside the image's columns (pixel columns 2 tx0 - 1 ..
 * 2 tx0 + 2 HZ_LANES), each row's four columns per tile are two deinterleaving loads of consecutive words (lane
 * i: words 2i, 2i + 1 and 2i + 2, 2i + 3 from the block's first column), visited in the order the gathers visit
 * them, and one exponent-31 test for the row lets all of them take the conversion instruction (motion_lanes);
 * the groups at the image's left and right edges gather their clamped columns. */
void hz_tdense_block_motion_lanes(const hz_tdense_t *td, uint32_t ty, uint32_t tx0, float *mx, float *my)
{
    const int32_t w = (int32_t)td->cfg.width, h = (int32_t)td->cfg.height;
    const int32_t *mv = (const int32_t *)(const void *)td->mv; /* (x, y) half pairs as words */
    const int32_t c0 = 2 * (int32_t)tx0 - 1;
    lmotion_t best;
    best.x = best.y = best.l2 = hz_lf_set(0.0f);
    if (c0 >= 0 && c0 + 2 * HZ_LANES + 1 < w) {
        for (int32_t dy = 0; dy < 4; dy++) {
            int32_t y = 2 * (int32_t)ty - 1 + dy;
            y = y < 0 ? 0 : y >= h ? h - 1 : y;
            const float *row = (const float *)(const void *)(mv + (size_t)y * (size_t)w + (size_t)c0);
            hz_lf_t a0, b0, a1, b1;
            hz_lf_load2(row, &a0, &b0);
            hz_lf_load2(row + 2, &a1, &b1);
            const hz_li_t v[4] = { hz_lf_bits(a0), hz_lf_bits(b0), hz_lf_bits(a1), hz_lf_bits(b1) };
            const int checked = !hz_li_any(hz_li_or(hz_li_or(half_pair_e31(v[0]), half_pair_e31(v[1])),
                                                    hz_li_or(half_pair_e31(v[2]), half_pair_e31(v[3]))));
            for (int k = 0; k < 4; k++)
                best = longer(best, motion_lanes(v[k], checked));
        }
    } else {
        const hz_li_t bx = hz_li_add(hz_li_set(c0), hz_li_shl(hz_li_iota(), 1));
        for (int32_t dy = 0; dy < 4; dy++) {
            int32_t y = 2 * (int32_t)ty - 1 + dy;
            y = y < 0 ? 0 : y >= h ? h - 1 : y;
            for (int32_t dx = 0; dx < 4; dx++) {
                hz_li_t x = hz_li_min(hz_li_max(hz_li_add(bx, hz_li_set(dx)), hz_li_set(0)), hz_li_set(w - 1));
                const hz_li_t v = hz_li_gather(mv, hz_li_add(x, hz_li_set(y * w)));
                best = longer(best, motion_lanes(v, !hz_li_any(half_pair_e31(v))));
            }
        }
    }
    hz_lf_store(mx, best.x);
    hz_lf_store(my, best.y);
}
