/* The activity mask of selective and adaptive supersampling, integer-only (see hz/adaptive_mask.h). */
#include "hz/adaptive_mask.h"

/* (dx, dy) of the three neighbours of each subpixel (Fig. 4); y grows downwards. */
const int8_t hz_amask_neighbours[4][3][2] = {
    { { -1, 0 }, { -1, -1 }, { 0, -1 } }, /* top-left: W, NW, N */
    { { 0, -1 }, { 1, -1 }, { 1, 0 } },   /* top-right: N, NE, E */
    { { 0, 1 }, { -1, 1 }, { -1, 0 } },   /* bottom-left: S, SW, W */
    { { 1, 0 }, { 1, 1 }, { 0, 1 } },     /* bottom-right: E, SE, S */
};

/* round(65536 x 1.36, 1.02, 2.04) */
const uint32_t hz_amask_channel_q16[3] = { 89129u, 66847u, 133693u };

void hz_amask_config_default(hz_amask_config_t *c)
{
    hz_memset(c, 0, sizeof *c);
    /* round(65536 x 0.6) = 39322, round(65536 x 0.05) = 3277, round(65536 x 0.06) = 3932 */
    c->tau[HZ_TAU_COL] = 39322u;
    c->tau[HZ_TAU_POID] = 3277u;
    c->tau[HZ_TAU_PSN] = 3932u;
    c->tau[HZ_TAU_PSC] = 3932u;
    c->tau[HZ_TAU_PTE] = 39322u;
    c->tau[HZ_TAU_SOID] = 3277u;
    c->tau[HZ_TAU_SSN] = 3932u;
    c->tau[HZ_TAU_SSC] = 3932u;
    c->tau[HZ_TAU_STE] = 39322u;
    c->normal_cos = HZ_AMASK_NORMAL_COS_DEFAULT;
}

/* ---- contrast ---- */

/* The usable values' running max, min and count: finite values only (NaN and Inf are left out), negative ones (and
 * -0) as 0 (no light). Non-negative binary32 patterns order like the values they encode. */
typedef struct ext_scan {
    uint32_t hi, lo, used;
} ext_scan_t;

static const ext_scan_t ext_empty = { 0u, 0xffffffffu, 0u };

HZ_INLINE ext_scan_t ext_add(ext_scan_t e, uint32_t v)
{
    if ((v & 0x7f800000u) == 0x7f800000u)
        return e;
    v = (v >> 31) ? 0u : v;
    e.hi = v > e.hi ? v : e.hi;
    e.lo = v < e.lo ? v : e.lo;
    e.used++;
    return e;
}

HZ_INLINE ext_scan_t ext_merge(ext_scan_t a, ext_scan_t b)
{
    a.hi = b.hi > a.hi ? b.hi : a.hi;
    a.lo = b.lo < a.lo ? b.lo : a.lo;
    a.used += b.used;
    return a;
}

/* A scan's max and min as aligned integers: A = Imax's significand << 7, B = Imin's shifted to A's exponent.
 * Returns how many values were usable. Inlined: a scan passed by value to a call was rebuilt in a register from
 * two 32-bit stores, and the 64-bit load stalled on the failed store forwarding (two thirds of row_blocks'
 * samples). */
HZ_INLINE uint32_t ext_align(ext_scan_t e, uint64_t *a, uint64_t *b)
{
    const uint32_t hi = e.hi, lo = e.lo;
    if (e.used == 0) {
        *a = *b = 0;
        return 0;
    }
    if (hi == lo) { /* flat: C = 0 (also all black) */
        *a = *b = hi ? 1u : 0u;
        return e.used;
    }
    uint32_t eh = hi >> 23, el = lo >> 23;
    uint64_t mh = (uint64_t)(hi & 0x7fffffu) | (eh ? 0x800000u : 0u);
    uint64_t ml = (uint64_t)(lo & 0x7fffffu) | (el ? 0x800000u : 0u);
    eh = eh ? eh : 1u; /* denormals share the smallest normal exponent */
    el = el ? el : 1u;
    uint32_t d = eh - el;
    *a = mh << 7;
    *b = d >= 32u ? 0u : (ml << 7) >> d;
    return e.used;
}

/* Max and min of the usable values as aligned integers (ext_align). */
static uint32_t extremes(const uint32_t *bits, uint32_t n, uint64_t *a, uint64_t *b)
{
    ext_scan_t e = ext_empty;
    for (uint32_t i = 0; i < n; i++)
        e = ext_add(e, bits[i]);
    return ext_align(e, a, b);
}

uint32_t hz_amask_contrast_q16(const uint32_t *bits, uint32_t n, bool *usable)
{
    uint64_t a, b;
    uint32_t used = extremes(bits, n, &a, &b);
    if (usable)
        *usable = used >= 2;
    if (used < 2 || a == 0)
        return 0;
    return (uint32_t)(((a - b) << 16) / (a + b));
}

bool hz_amask_contrast_at_least(const uint32_t *bits, uint32_t n, uint32_t thr_q16)
{
    uint64_t a, b;
    if (extremes(bits, n, &a, &b) < 2 || thr_q16 > HZ_AMASK_ONE)
        return false;
    if (a == 0)
        return thr_q16 == 0; /* all black: C = 0 */
    return ((a - b) << 16) >= (uint64_t)thr_q16 * (a + b);
}

/* ---- attributes ---- */

static bool in_focus(const hz_amask_config_t *c, uint16_t object)
{
    uint32_t lo = 0, hi = c->focus_count < HZ_AMASK_MAX_FOCUS ? c->focus_count : HZ_AMASK_MAX_FOCUS;
    while (lo < hi) {
        uint32_t mid = (lo + hi) / 2u;
        if (c->focus[mid] == object)
            return true;
        if (c->focus[mid] < object)
            lo = mid + 1u;
        else
            hi = mid;
    }
    return false;
}

static bool normals_differ(const int8_t *a, const int8_t *b, int32_t cos_q15)
{
    int64_t aa = (int64_t)a[0] * a[0] + (int64_t)a[1] * a[1] + (int64_t)a[2] * a[2];
    int64_t bb = (int64_t)b[0] * b[0] + (int64_t)b[1] * b[1] + (int64_t)b[2] * b[2];
    if (aa == 0 || bb == 0)
        return aa != bb; /* two misses agree; a miss and a hit do not */
    int64_t dot = (int64_t)a[0] * b[0] + (int64_t)a[1] * b[1] + (int64_t)a[2] * b[2];
    if (cos_q15 < 0)
        cos_q15 = 0;
    if (cos_q15 > 32768)
        cos_q15 = 32768;
    if (dot <= 0)
        return cos_q15 > 0 || dot < 0;
    /* dot >= cos |a| |b|  <=>  dot^2 2^30 >= cos^2 |a|^2 |b|^2 (both sides below 2^63) */
    uint64_t lhs = (uint64_t)(dot * dot) << 30;
    uint64_t rhs = (uint64_t)((int64_t)cos_q15 * cos_q15) * (uint64_t)(aa * bb);
    return lhs < rhs;
}

HZ_STATIC_ASSERT(offsetof(hz_amask_hit_t, object) == 0 && offsetof(hz_amask_hit_t, n) == 2 &&
                     offsetof(hz_amask_hit_t, shadow) == 5,
                 amask_hit_layout);

/* Whether two hits are the same hit (a flat surface): object, normal and shadow count alike, so nothing differs
 * (a normal agrees with itself). Bytes 0-5 compared as two overlapping words (0-3 and 2-5): the common case, once
 * for every pair of every pixel, without a branch per field. */
static bool same_hit(const hz_amask_hit_t *a, const hz_amask_hit_t *b)
{
    uint32_t a0, a1, b0, b1;
    hz_memcpy(&a0, a, 4);
    hz_memcpy(&a1, (const uint8_t *)a + 2, 4);
    hz_memcpy(&b0, b, 4);
    hz_memcpy(&b1, (const uint8_t *)b + 2, 4);
    return (a0 ^ b0) == 0 && (a1 ^ b1) == 0;
}

/* Classes on which hit level h of P and Q disagree (object id, shadow count, normal), honouring the focus; none
 * for the same hit, tested first (inline, so the common case costs its callers no call). */
HZ_INLINE uint32_t hit_bits(const hz_amask_config_t *c, const hz_amask_hit_t *a, const hz_amask_hit_t *b, uint32_t h)
{
    static const hz_tau_t oid[2] = { HZ_TAU_POID, HZ_TAU_SOID }, sn[2] = { HZ_TAU_PSN, HZ_TAU_SSN };
    static const hz_tau_t sc[2] = { HZ_TAU_PSC, HZ_TAU_SSC };
    if (same_hit(a, b))
        return 0;
    uint32_t why = 0;
    if (a->object != b->object)
        why |= HZ_AMASK_BIT(oid[h]);
    if (a->shadow != b->shadow)
        why |= HZ_AMASK_BIT(sc[h]);
    if (normals_differ(a->n, b->n, c->normal_cos))
        why |= HZ_AMASK_BIT(sn[h]);
    return why;
}

/* Whether pixel p's hit at level h takes part under the focus: its object there is focused, or (the reflected
 * hit) the mirror it was reflected in is: a focused mirror shows everything it reflects. */
static bool focused_at(const hz_amask_config_t *c, const hz_amask_px_t *p, uint32_t h)
{
    return c->focus_count == 0 || in_focus(c, p->hit[h].object) || (h == 1 && in_focus(c, p->hit[0].object));
}

/* The same, honouring the focus: nothing when neither P (a_in) nor Q is involved. Symmetric in P and Q. */
static uint32_t pair_bits(const hz_amask_config_t *c, const hz_amask_px_t *p, bool a_in, const hz_amask_px_t *q,
                          uint32_t h)
{
    if (!a_in && !focused_at(c, q, h))
        return 0;
    return hit_bits(c, &p->hit[h], &q->hit[h], h);
}

/* Whether P's hit at level h takes part (focus), and its texture-existence bit. */
static bool involved(const hz_amask_config_t *c, const hz_amask_px_t *p, uint32_t h, uint32_t *tex)
{
    static const hz_tau_t te[2] = { HZ_TAU_PTE, HZ_TAU_STE };
    bool in = focused_at(c, p, h);
    if (in && (p->hit[h].flags & HZ_AMASK_TEXTURED))
        *tex |= HZ_AMASK_BIT(te[h]);
    return in;
}

/* The switched-on classes of `why` and the threshold they select (else tau_col). */
static uint32_t select_tau(const hz_amask_config_t *c, uint32_t why, uint32_t *tau_q16)
{
    uint32_t tau = HZ_AMASK_ONE + 1u, kept = 0;
    for (uint32_t k = 1; k < HZ_TAU_COUNT; k++)
        if ((why & HZ_AMASK_BIT(k)) && c->tau[k] < HZ_AMASK_ONE) {
            kept |= HZ_AMASK_BIT(k);
            if (c->tau[k] < tau)
                tau = c->tau[k];
        }
    if (!kept)
        tau = c->tau[HZ_TAU_COL] < HZ_AMASK_ONE ? c->tau[HZ_TAU_COL] : HZ_AMASK_ONE;
    *tau_q16 = tau;
    return kept;
}

uint32_t hz_amask_disagree(const hz_amask_config_t *c, const hz_amask_px_t *p, const hz_amask_px_t *const nb[3],
                           uint32_t *tau_q16)
{
    uint32_t why = 0, tau;
    for (uint32_t h = 0; h < 2; h++) {
        bool in = involved(c, p, h, &why);
        for (uint32_t k = 0; k < 3; k++)
            why |= pair_bits(c, p, in, nb[k], h);
    }
    uint32_t kept = select_tau(c, why, &tau);
    if (tau_q16)
        *tau_q16 = tau;
    return kept;
}

/* Mitchell's test of the four colour references of a subpixel against the threshold tau. */
static bool colour_active(const hz_amask_px_t *p, const hz_amask_px_t *const nb[3], uint32_t tau)
{
    for (uint32_t ch = 0; ch < 3; ch++) {
        uint32_t v[4] = { p->rgb[ch], nb[0]->rgb[ch], nb[1]->rgb[ch], nb[2]->rgb[ch] };
        uint32_t thr = (uint32_t)(((uint64_t)hz_amask_channel_q16[ch] * tau + 32768u) >> 16);
        if (hz_amask_contrast_at_least(v, 4, thr))
            return true;
    }
    return false;
}

bool hz_amask_subpixel(const hz_amask_config_t *c, const hz_amask_px_t *p, const hz_amask_px_t *const nb[3])
{
    uint32_t tau;
    hz_amask_disagree(c, p, nb, &tau);
    return colour_active(p, nb, tau);
}

/* hz_amask_block over column strips of at most STRIP pixels, row by row, with every comparison that two
 * pixels' subpixels share made once (bit-identical to hz_amask_subpixel per subpixel, which test_adaptive_mask
 * checks):
 *  - the attribute comparison of two neighbours is symmetric (focus: either is involved), so each pair of the
 *    window is compared once: per window row the horizontal pairs, and between two rows the vertical and both
 *    diagonal pairs, the latter kept for the next pixel row;
 *  - the four colour references of a subpixel are the 2x2 block of pixels on its corner (P's top-left subpixel:
 *    the block of NW, N, W, P), and each block is the corner of four subpixels of four pixels: its per-channel
 *    extremes are found once. */
#define STRIP 16u

typedef struct block_ext {
    uint64_t a[3], b[3];
    uint32_t used[3];
    bool active_none; /* block_active at the thresholds of no disagreement (tau_memo_t.none) */
} block_ext_t;

/* Window pixel (x, y) of the strip: involved at hit 0 (bit 0) and hit 1 (bit 1), and its texture bits. */
typedef struct px_in {
    uint8_t in;
    uint32_t tex;
} px_in_t;

static void row_involved(const hz_amask_config_t *c, const hz_amask_px_t *row, uint32_t n, px_in_t *out)
{
    for (uint32_t i = 0; i < n; i++) {
        uint32_t tex = 0;
        bool i0 = involved(c, &row[i], 0, &tex), i1 = involved(c, &row[i], 1, &tex);
        out[i].in = (uint8_t)((i0 ? 1u : 0u) | (i1 ? 2u : 0u));
        out[i].tex = tex;
    }
}

static uint32_t pair_of(const hz_amask_config_t *c, const hz_amask_px_t *p, px_in_t pi, const hz_amask_px_t *q,
                        px_in_t qi)
{
    uint32_t why = 0;
    for (uint32_t h = 0; h < 2; h++)
        if ((pi.in | qi.in) & (1u << h))
            why |= hit_bits(c, &p->hit[h], &q->hit[h], h);
    return why;
}

/* Extremes of each 2x2 block of rows r0 (above) and r1, blocks k = 0..n-1 (columns k and k + 1): each column's
 * pair is scanned once and shared by the two blocks it belongs to (max, min and count do not depend on order). */
static void row_blocks(const hz_amask_px_t *r0, const hz_amask_px_t *r1, uint32_t n, block_ext_t *out)
{
    ext_scan_t left[3];
    for (uint32_t ch = 0; ch < 3; ch++)
        left[ch] = ext_add(ext_add(ext_empty, r0[0].rgb[ch]), r1[0].rgb[ch]);
    for (uint32_t k = 0; k < n; k++)
        for (uint32_t ch = 0; ch < 3; ch++) {
            const ext_scan_t right = ext_add(ext_add(ext_empty, r0[k + 1].rgb[ch]), r1[k + 1].rgb[ch]);
            out[k].used[ch] = ext_align(ext_merge(left[ch], right), &out[k].a[ch], &out[k].b[ch]);
            left[ch] = right;
        }
}

/* block_active's per-channel thresholds for tau (each channel's factor of tau, rounded). */
static void channel_thresholds(uint32_t tau, uint32_t thr[3])
{
    for (uint32_t ch = 0; ch < 3; ch++)
        thr[ch] = (uint32_t)(((uint64_t)hz_amask_channel_q16[ch] * tau + 32768u) >> 16);
}

/* hz_amask_contrast_at_least on a block's extremes, for each channel at its threshold. */
static bool block_active(const block_ext_t *e, const uint32_t thr[3])
{
    for (uint32_t ch = 0; ch < 3; ch++) {
        if (e->used[ch] < 2 || thr[ch] > HZ_AMASK_ONE)
            continue;
        if (e->a[ch] == 0 ? thr[ch] == 0
                          : ((e->a[ch] - e->b[ch]) << 16) >= (uint64_t)thr[ch] * (e->a[ch] + e->b[ch]))
            return true;
    }
    return false;
}

/* select_tau's thresholds for a class set, remembered for the last set asked: a strip's neighbouring subpixels
 * mostly disagree on the same classes (a silhouette, a shadow edge), and select_tau scans every class. */
typedef struct tau_memo {
    uint32_t on;      /* the classes switched on (tau below one): the others never select */
    uint32_t none[3]; /* thresholds when none of them disagrees: tau_col's */
    uint32_t kept;    /* the last set looked up (0: none yet) */
    uint32_t thr[3];  /* and its thresholds */
} tau_memo_t;

static void tau_memo_init(const hz_amask_config_t *c, tau_memo_t *m)
{
    uint32_t tau;
    m->on = select_tau(c, 0xffffffffu, &tau);
    select_tau(c, 0, &tau);
    channel_thresholds(tau, m->none);
    m->kept = 0;
}

static const uint32_t *tau_memo_thresholds(const hz_amask_config_t *c, tau_memo_t *m, uint32_t why)
{
    const uint32_t kept = why & m->on;
    if (!kept)
        return m->none;
    if (kept != m->kept) {
        uint32_t tau;
        select_tau(c, kept, &tau);
        channel_thresholds(tau, m->thr);
        m->kept = kept;
    }
    return m->thr;
}

/* Each block's activity at the thresholds of no disagreement, found once: most of the four subpixels that share
 * a block take those thresholds (their neighbours are the same surface), and block_active's channel tests branch on
 * the image's content. */
static void row_blocks_none(block_ext_t *e, uint32_t n, const tau_memo_t *m)
{
    for (uint32_t k = 0; k < n; k++)
        e[k].active_none = block_active(&e[k], m->none);
}

/* Pairs between window rows `up` and `dn` (strip width n window pixels): vertical v[x] = (x, up)-(x, dn);
 * diagonal d1[x] = (x, up)-(x + 1, dn), d2[x] = (x + 1, up)-(x, dn). */
static void row_pairs(const hz_amask_config_t *c, const hz_amask_px_t *up, const px_in_t *iu, const hz_amask_px_t *dn,
                      const px_in_t *id, uint32_t n, uint32_t *v, uint32_t *d1, uint32_t *d2)
{
    for (uint32_t x = 0; x < n; x++)
        v[x] = pair_of(c, &up[x], iu[x], &dn[x], id[x]);
    for (uint32_t x = 0; x + 1 < n; x++) {
        d1[x] = pair_of(c, &up[x], iu[x], &dn[x + 1], id[x + 1]);
        d2[x] = pair_of(c, &up[x + 1], iu[x + 1], &dn[x], id[x]);
    }
}

static uint32_t block_strip(const hz_amask_config_t *c, const hz_amask_px_t *win, uint32_t stride, uint32_t w,
                            uint32_t h, uint8_t *mask, uint32_t mask_stride)
{
    const uint32_t n = w + 2; /* window pixels of a strip row */
    px_in_t in[3][STRIP + 2];
    uint32_t hrow[STRIP + 1], v[2][STRIP + 2], d1[2][STRIP + 1], d2[2][STRIP + 1];
    block_ext_t ext[2][STRIP + 1];
    tau_memo_t memo;
    tau_memo_init(c, &memo);
    row_involved(c, win, n, in[0]);
    row_involved(c, win + stride, n, in[1]);
    row_pairs(c, win, in[0], win + stride, in[1], n, v[0], d1[0], d2[0]);
    row_blocks(win, win + stride, n - 1, ext[0]);
    row_blocks_none(ext[0], n - 1, &memo);
    uint32_t active = 0;
    for (uint32_t y = 0; y < h; y++) {
        /* window rows y (above), y + 1 (the pixels), y + 2 (below); buffers [up] and [dn] alternate */
        const uint32_t up = y & 1u, dn = up ^ 1u;
        const hz_amask_px_t *row = win + (size_t)(y + 1) * stride, *below = row + stride;
        px_in_t *ir = in[(y + 1) % 3], *ib = in[(y + 2) % 3];
        row_involved(c, below, n, ib);
        row_pairs(c, row, ir, below, ib, n, v[dn], d1[dn], d2[dn]);
        row_blocks(row, below, n - 1, ext[dn]);
        row_blocks_none(ext[dn], n - 1, &memo);
        for (uint32_t x = 0; x + 1 < n; x++)
            hrow[x] = pair_of(c, &row[x], ir[x], &row[x + 1], ir[x + 1]);
        for (uint32_t x = 0; x < w; x++) {
            const uint32_t X = x + 1, tex = ir[X].tex;
            const uint32_t W = hrow[X - 1], E = hrow[X], N = v[up][X], S = v[dn][X];
            const uint32_t NW = d1[up][X - 1], SE = d1[dn][X], NE = d2[up][X], SW = d2[dn][X - 1];
            const uint32_t why[4] = { tex | W | NW | N, tex | N | NE | E, tex | S | SW | W, tex | E | SE | S };
            const block_ext_t *corner[4] = { &ext[up][X - 1], &ext[up][X], &ext[dn][X - 1], &ext[dn][X] };
            uint8_t m = 0;
            for (uint32_t q = 0; q < 4; q++)
                if ((why[q] & memo.on) ? block_active(corner[q], tau_memo_thresholds(c, &memo, why[q]))
                                       : corner[q]->active_none)
                    m |= (uint8_t)(1u << q);
            mask[(size_t)y * mask_stride + x] = m;
            active += hz_amask_count(m);
        }
    }
    return active;
}

uint32_t hz_amask_block(const hz_amask_config_t *c, const hz_amask_px_t *win, uint32_t stride, uint32_t w,
                        uint32_t h, uint8_t *mask, uint32_t mask_stride)
{
    uint32_t active = 0;
    for (uint32_t x0 = 0; x0 < w; x0 += STRIP)
        active += block_strip(c, win + x0, stride, w - x0 < STRIP ? w - x0 : STRIP, h, mask + x0, mask_stride);
    return active;
}

/* ---- packing ---- */

/* The even bits of x packed together (de-interleaving a Morton code). */
static uint32_t even_bits(uint32_t x)
{
    x &= 0x55555555u;
    x = (x | (x >> 1)) & 0x33333333u;
    x = (x | (x >> 2)) & 0x0f0f0f0fu;
    x = (x | (x >> 4)) & 0x00ff00ffu;
    return (x | (x >> 8)) & 0x0000ffffu;
}

uint32_t hz_amask_pack(const uint8_t *mask, uint32_t mask_stride, uint32_t w, uint32_t h, uint16_t *list)
{
    if (w > HZ_AMASK_MAX_TILE || h > HZ_AMASK_MAX_TILE)
        return 0;
    /* Morton order over the 2w x 2h subpixels is Morton order over the pixels with each pixel's quadrants
     * (q = 2 row + column, itself a 2-bit Morton code) in place of its lowest two bits: walk the pixel codes of
     * the enclosing power-of-two square, skipping those outside the tile and the inactive ones. */
    uint32_t n = 0, side = 1;
    while (side < w || side < h)
        side *= 2u;
    for (uint32_t code = 0; code < side * side; code++) {
        uint32_t x = even_bits(code), y = even_bits(code >> 1);
        if (x >= w || y >= h)
            continue;
        uint32_t m = mask[(size_t)y * mask_stride + x];
        for (uint32_t q = 0; m && q < 4; q++)
            if (m & (1u << q))
                list[n++] = (uint16_t)(((y * w + x) << 2) | q);
    }
    return n;
}
