/*
 * hz/adaptive_mask.h — the activity mask of selective and adaptive supersampling (seed 003, Jin, Ihm, Chang,
 * Park, Lee, Jung, "Selective and Adaptive Supersampling for Real-Time Ray Tracing", HPG 2009): which of the
 * four subpixels of each pixel get extra samples, decided from the presampled colour references and geometry
 * attributes of the pixel and its neighbours; and the packing of the active subpixels of a tile into a list
 * that the renderer traces as full, coherent packets (the paper's ActSubPixBuffer).
 *
 * Contract: integer-only (src/pattern/, built with -mgeneral-regs-only) and bit-identical on every ISA; no state,
 * no allocation. The inputs are integers: colour references as the IEEE-754 binary32 bit patterns of linear
 * radiance (what the presample wrote), normals quantised to int8 (round(127 n)), thresholds in Q16 (65536 = 1).
 * Converting from float is the caller's job (src/recon/adaptive.c).
 *
 * Subpixels and neighbours (Fig. 4): q = 2 * row + column inside the pixel; each subpixel compares its pixel P
 * with the three neighbours on its side:
 *
 *     NW  N  NE        q 0 (top-left):     W, NW, N       q 1 (top-right):    N, NE, E
 *     W   P  E         q 2 (bottom-left):  S, SW, W       q 3 (bottom-right): E, SE, S
 *     SW  S  SE        (hz_amask_neighbours, as (dx, dy) with y growing downwards like image rows)
 *
 * Step 1, the threshold (Section 4.2.2, Table 1). Each attribute class k is compared between P and each of the
 * three neighbours Q, at the primary hit (hit[0]) and at the first secondary, mirror hit (hit[1]):
 *   - object id (τpoid, τsoid), shadow count (τpsc, τssc): disagree when the values differ;
 *   - shading normal (τpsn, τssn): the paper says two normals differ "if their cross product is less than a
 *     preset value". Read literally that would call parallel normals different, so we read it as the angle
 *     test it stands for: normals a, b agree iff a . b >= cos θ0 |a| |b| (θ0 = normal_cos, default 15°), i.e.
 *     on the front hemisphere iff |a x b| <= sin θ0 |a| |b|; antiparallel normals (cross product 0, dot < 0)
 *     differ. Two missing normals (0, 0, 0; no hit) agree, a missing and a present one differ;
 *   - texture existence (τpte, τste): "on" whenever P itself is textured at that hit, whatever the neighbours.
 * The threshold is the smallest τ among the disagreeing classes, else τcol. A class whose τ is >= 1 (65536) is
 * switched off: it never disagrees (so the subpixel falls back to τcol, not to 1). A class with τ above τcol
 * does replace τcol where it disagrees (that is how a user gives a feature less effort).
 * Focus (the paper's "fairy focused"): with focus_count > 0, a comparison of P and Q at hit h counts only when
 * P or Q is involved at that hit, texture existence only when P is. A pixel is involved at a hit when its object
 * there is in the (sorted) focus list, and at the reflected hit also when its primary object (the mirror) is: a
 * focused mirror shows everything it reflects.
 *
 * Step 2, Mitchell's contrast per channel over the four colour references (P and the three neighbours):
 * C = (Imax - Imin) / (Imax + Imin), active iff C_R >= 1.36 τ or C_G >= 1.02 τ or C_B >= 2.04 τ (the three
 * factors in Q16: 89129, 66847, 133693, times τ rounded to Q16). ">=" so that τ = 0 always supersamples, as the
 * paper says; τ = 1 never activates (C <= 1 < 1.02). Exact definition:
 *   - values are non-negative binary32 bit patterns; negative values (sign bit) count as 0; NaN and Inf are
 *     left out, and a channel with fewer than two values left never activates (so a non-finite presample
 *     neither activates its own subpixels nor poisons its neighbours' tests);
 *   - Imax + Imin = 0 (all black): C = 0, which activates only at τ = 0;
 *   - otherwise C is the exact ratio, scale-invariant down to the smallest denormal: Imax and Imin are aligned to
 *     Imax's exponent (Imin truncated to 31 bits below Imax's leading bit, an error below 2^-24 in C), so
 *     C(0.002, 0.001) = 1/3 and a near-black 1e-6 next to 0 is full contrast (C = 1), as Mitchell's measure is.
 *
 * Packing (Section 4.3.2): hz_amask_pack lists the active subpixels of a tile of masks in Morton (Z) order over
 * the tile's 2w x 2h subpixel grid, so consecutive entries are spatial neighbours and every 2 (AVX2, 8 lanes)
 * or 1 (NEON, 4 lanes) entries of 4 samples each fill one packet; only the tile's last packet can be partial.
 */
#ifndef HZ_ADAPTIVE_MASK_H
#define HZ_ADAPTIVE_MASK_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/base.h"

/* The nine thresholds of Table 1, in this order everywhere (options, config, reports). */
typedef enum hz_tau {
    HZ_TAU_COL = 0, /* colour reference (no attribute disagrees) */
    HZ_TAU_POID,    /* primary hit: object id */
    HZ_TAU_PSN,     /* primary hit: shading normal */
    HZ_TAU_PSC,     /* primary hit: shadow count */
    HZ_TAU_PTE,     /* primary hit: texture existence */
    HZ_TAU_SOID,    /* secondary (mirror) hit: object id */
    HZ_TAU_SSN,
    HZ_TAU_SSC,
    HZ_TAU_STE,
    HZ_TAU_COUNT
} hz_tau_t;

#define HZ_AMASK_ONE 65536u     /* τ = 1 in Q16: the attribute is switched off */
#define HZ_AMASK_MAX_FOCUS 64u  /* --focus-objects list length */
#define HZ_AMASK_MAX_TILE 16u   /* hz_amask_pack: tiles up to 16 x 16 pixels */
/* cos 15° in Q15: default largest angle between two agreeing normals. */
#define HZ_AMASK_NORMAL_COS_DEFAULT 31651

/* Attribute-class bits returned by hz_amask_disagree (bit k - 1 for hz_tau_t k >= 1). */
#define HZ_AMASK_BIT(tau) (1u << ((unsigned)(tau) - 1u))

/* One hit's geometry attributes: 8 bytes. */
enum { HZ_AMASK_HIT = 1u << 0, HZ_AMASK_TEXTURED = 1u << 1 };
typedef struct hz_amask_hit {
    uint16_t object;  /* object id; 0xffff: none (a miss) */
    int8_t n[3];      /* shading normal, round(127 n); 0 0 0 on a miss */
    uint8_t shadow;   /* lights whose shadow ray was blocked (saturating) */
    uint8_t flags;    /* HZ_AMASK_HIT, HZ_AMASK_TEXTURED */
    uint8_t pad;      /* 0 */
} hz_amask_hit_t;

/* One presampled pixel as the test sees it. */
typedef struct hz_amask_px {
    uint32_t rgb[3];          /* binary32 bits of the colour reference */
    hz_amask_hit_t hit[2];    /* primary, first secondary (all 0 / object 0xffff where there is none) */
} hz_amask_px_t;

typedef struct hz_amask_config {
    uint32_t tau[HZ_TAU_COUNT]; /* Q16, 0..65536 (larger values act as 65536) */
    int32_t normal_cos;         /* Q15 cosine of the agreeing angle, 0..32768 */
    uint32_t focus_count;       /* 0: every object is involved */
    uint16_t focus[HZ_AMASK_MAX_FOCUS]; /* sorted ascending, no duplicates */
} hz_amask_config_t;

/* Fig. 4: neighbour k (0..2) of subpixel q (0..3) as (dx, dy). */
extern const int8_t hz_amask_neighbours[4][3][2];
/* Mitchell's factors 1.36, 1.02, 2.04 in Q16. */
extern const uint32_t hz_amask_channel_q16[3];

/* Table 2's caption: τpoid = τsoid = 0.05, τpsn = τssn = 0.06, τpsc = τssc = 0.06, τα = τcol = τpte = τste = 0.6
 * (all rounded to Q16); normals within 15°; no focus. */
void hz_amask_config_default(hz_amask_config_t *c);

/* Contrast C of n values (binary32 bits) as above, in Q16 rounded down (0..65536); *usable gets whether at least
 * two values were finite (may be NULL). */
uint32_t hz_amask_contrast_q16(const uint32_t *bits, uint32_t n, bool *usable);
/* Whether C of the n values is >= thr (Q16; thr > 65536 never). Exact, not through the rounded C. */
bool hz_amask_contrast_at_least(const uint32_t *bits, uint32_t n, uint32_t thr_q16);

/* The attribute classes on which P disagrees with the neighbours (HZ_AMASK_BIT mask, switched-off classes
 * left out) and the threshold they select (Q16). */
uint32_t hz_amask_disagree(const hz_amask_config_t *c, const hz_amask_px_t *p, const hz_amask_px_t *const nb[3],
                           uint32_t *tau_q16);
/* Whether subpixel q of P is active given its three neighbours (in hz_amask_neighbours[q] order). */
bool hz_amask_subpixel(const hz_amask_config_t *c, const hz_amask_px_t *p, const hz_amask_px_t *const nb[3]);

/* Masks (bit q = subpixel q active) of a w x h block of pixels. `win` holds (w + 2) x (h + 2) pixels, row by row
 * with `stride` pixels per row: the block and a one-pixel border (the caller fills the border outside the image
 * by replicating the edge pixels). mask[y * mask_stride + x] for x < w, y < h. Returns the active subpixels. */
uint32_t hz_amask_block(const hz_amask_config_t *c, const hz_amask_px_t *win, uint32_t stride, uint32_t w,
                        uint32_t h, uint8_t *mask, uint32_t mask_stride);

/* The active subpixels of a w x h tile of masks (w, h <= HZ_AMASK_MAX_TILE) in Morton order over the 2w x 2h
 * subpixels: list[i] = (y * w + x) << 2 | q. Returns the count (at most 4 w h). */
uint32_t hz_amask_pack(const uint8_t *mask, uint32_t mask_stride, uint32_t w, uint32_t h, uint16_t *list);

/* Active subpixels of a mask (0..4). */
HZ_INLINE uint32_t hz_amask_count(uint8_t m)
{
    return (uint32_t)(m & 1u) + ((m >> 1) & 1u) + ((m >> 2) & 1u) + ((m >> 3) & 1u);
}

#endif /* HZ_ADAPTIVE_MASK_H */
