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

/* Max and min of the usable values (finite; negative as 0) as aligned integers: A = Imax's significand << 7,
 * B = Imin's shifted to A's exponent. Returns how many values were usable. */
static uint32_t extremes(const uint32_t *bits, uint32_t n, uint64_t *a, uint64_t *b)
{
    uint32_t hi = 0, lo = 0xffffffffu, used = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t v = bits[i];
        if ((v & 0x7f800000u) == 0x7f800000u)
            continue; /* NaN or Inf: left out */
        v = (v >> 31) ? 0u : v; /* negative (or -0): no light */
        /* Non-negative binary32 patterns order like the values they encode. */
        hi = v > hi ? v : hi;
        lo = v < lo ? v : lo;
        used++;
    }
    if (used == 0) {
        *a = *b = 0;
        return 0;
    }
    if (hi == lo) { /* flat: C = 0 (also all black) */
        *a = *b = hi ? 1u : 0u;
        return used;
    }
    uint32_t eh = hi >> 23, el = lo >> 23;
    uint64_t mh = (uint64_t)(hi & 0x7fffffu) | (eh ? 0x800000u : 0u);
    uint64_t ml = (uint64_t)(lo & 0x7fffffu) | (el ? 0x800000u : 0u);
    eh = eh ? eh : 1u; /* denormals share the smallest normal exponent */
    el = el ? el : 1u;
    uint32_t d = eh - el;
    *a = mh << 7;
    *b = d >= 32u ? 0u : (ml << 7) >> d;
    return used;
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

/* Classes on which hit level h of P and Q disagree (object id, shadow count, normal), honouring the focus. */
static uint32_t pair_bits(const hz_amask_config_t *c, const hz_amask_hit_t *a, bool a_in, const hz_amask_hit_t *b,
                          uint32_t h)
{
    static const hz_tau_t oid[2] = { HZ_TAU_POID, HZ_TAU_SOID }, sn[2] = { HZ_TAU_PSN, HZ_TAU_SSN };
    static const hz_tau_t sc[2] = { HZ_TAU_PSC, HZ_TAU_SSC };
    if (!a_in && !in_focus(c, b->object))
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

/* Whether P's hit at level h takes part (focus), and its texture-existence bit. */
static bool involved(const hz_amask_config_t *c, const hz_amask_px_t *p, uint32_t h, uint32_t *tex)
{
    static const hz_tau_t te[2] = { HZ_TAU_PTE, HZ_TAU_STE };
    bool in = c->focus_count == 0 || in_focus(c, p->hit[h].object);
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
            why |= pair_bits(c, &p->hit[h], in, &nb[k]->hit[h], h);
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

static bool same_hit(const hz_amask_hit_t *a, const hz_amask_hit_t *b)
{
    return a->object == b->object && a->n[0] == b->n[0] && a->n[1] == b->n[1] && a->n[2] == b->n[2] &&
           a->shadow == b->shadow && a->flags == b->flags;
}

static bool same_px(const hz_amask_px_t *a, const hz_amask_px_t *b)
{
    return a->rgb[0] == b->rgb[0] && a->rgb[1] == b->rgb[1] && a->rgb[2] == b->rgb[2] &&
           same_hit(&a->hit[0], &b->hit[0]) && same_hit(&a->hit[1], &b->hit[1]);
}

uint32_t hz_amask_block(const hz_amask_config_t *c, const hz_amask_px_t *win, uint32_t stride, uint32_t w,
                        uint32_t h, uint8_t *mask, uint32_t mask_stride)
{
    uint32_t active = 0;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const hz_amask_px_t *p = &win[(size_t)(y + 1) * stride + x + 1];
            uint32_t pair[3][3], tex = 0;
            bool in[2] = { involved(c, p, 0, &tex), involved(c, p, 1, &tex) };
            /* A neighbourhood of copies of P (flat walls, sky): no attribute disagrees and C = 0 everywhere, so
             * all four subpixels share one answer, the same the general path would give. */
            bool flat = true;
            for (int k = 0; k < 9 && flat; k++)
                flat = same_px(p + (ptrdiff_t)(k / 3 - 1) * (ptrdiff_t)stride + (k % 3 - 1), p);
            if (flat) {
                const hz_amask_px_t *self[3] = { p, p, p };
                uint32_t tau;
                select_tau(c, tex, &tau);
                uint8_t m = colour_active(p, self, tau) ? 0xf : 0;
                mask[(size_t)y * mask_stride + x] = m;
                active += hz_amask_count(m);
                continue;
            }
            /* Each of the 8 neighbours is compared once; subpixels share them (Fig. 4). */
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    const hz_amask_px_t *q = p + (ptrdiff_t)dy * (ptrdiff_t)stride + dx;
                    pair[dy + 1][dx + 1] = dx || dy ? pair_bits(c, &p->hit[0], in[0], &q->hit[0], 0) |
                                                          pair_bits(c, &p->hit[1], in[1], &q->hit[1], 1)
                                                    : 0u;
                }
            uint8_t m = 0;
            for (uint32_t sq = 0; sq < 4; sq++) {
                const hz_amask_px_t *nb[3];
                uint32_t why = tex, tau;
                for (uint32_t k = 0; k < 3; k++) {
                    int dx = hz_amask_neighbours[sq][k][0], dy = hz_amask_neighbours[sq][k][1];
                    nb[k] = p + (ptrdiff_t)dy * (ptrdiff_t)stride + dx;
                    why |= pair[dy + 1][dx + 1];
                }
                select_tau(c, why, &tau);
                if (colour_active(p, nb, tau))
                    m |= (uint8_t)(1u << sq);
            }
            mask[(size_t)y * mask_stride + x] = m;
            active += hz_amask_count(m);
        }
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
