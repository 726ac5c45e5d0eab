/*
 * hz/tileorder.h — pixel orderings of 2x2 tiles for temporally dense rendering (seed 001, Andersson et al.,
 * "Temporally Dense Ray Tracing", HPG 2019): the 24 orderings, their cycle classes, the per-tile choice
 * ĝ(ℓf, α) between hourglass and bowtie, and the 4-frame schedule with the fixed 4x MSAA jitter.
 *
 * Contract: integer-only (src/pattern/, built with -mgeneral-regs-only) and bit-identical on every ISA; no
 * state, no allocation. Motion comes in as Q16.16 pixels per frame; converting the renderer's float motion
 * vectors is the caller's job (src/recon/tdense.c).
 *
 * Pixel layout of a tile (row 0 on top, as image rows; p = 2 * row + column):
 *
 *     +---+---+
 *     | 0 | 1 |      0 top-left   1 top-right
 *     +---+---+
 *     | 2 | 3 |      2 bottom-left 3 bottom-right
 *     +---+---+
 *
 * An ordering is the sequence (p0, p1, p2, p3) of pixels traced in subframes 0..3; its index is the rank of
 * that sequence among the 24 permutations of {0,1,2,3} in lexicographic order (index 0 = 0,1,2,3; index 23 =
 * 3,2,1,0). Drawn as a closed path through the pixel centres (p3 back to p0, since the sequence repeats), every
 * ordering traces one of the three Hamiltonian cycles of the 2x2 grid, 8 orderings each (4 starts x 2 directions):
 *
 *     square     the perimeter, no diagonal step           e.g. 0 1 / 3 2   (numbers = subframe of each pixel)
 *     hourglass  both diagonals + the two horizontal edges  e.g. 0 1 / 2 3   (the outline of the glyph ⧗)
 *     bowtie     both diagonals + the two vertical edges    e.g. 0 2 / 1 3   (the outline of the glyph ⋈)
 *
 * This is Fig. 4 (left) of the paper. The bowtie is the transpose of the hourglass, which is why the paper's
 * rule for vertical motion (its Eq. 5) is exactly the rule for horizontal motion (Eq. 4) with the two classes
 * swapped. The canonical orderings used for rendering are HZ_TILEORDER_HOURGLASS (0 1 / 2 3, the order the
 * paper's Section 3 figure numbers the tile) and its transpose HZ_TILEORDER_BOWTIE (0 2 / 1 3).
 *
 * ĝ(ℓf, α) (paper Section 3.2.3, Fig. 10 right): ℓ = |m| (rounded down to 2^-16 px), ℓf = ℓ - floor(ℓ),
 * α = atan2(|my|, |mx|) in [0, π/2] (the other quadrants by symmetry):
 *   - my == 0 (horizontal, Eq. 4; also zero motion): hourglass iff ℓf in (0.25, 0.75), else bowtie;
 *   - mx == 0 (vertical, Eq. 5): hourglass iff ℓf in [0, 0.25] or [0.75, 1), else bowtie;
 *   - α in (0, π/4 - γ]: the "shear up" transition (Fig. 10 middle-left);
 *   - α in [π/4 + γ, π/2): the "shear down" transition (Fig. 10 middle-right);
 *   - α in (π/4 - γ, π/4 + γ), γ = π/40: random, from the top bit of a caller-supplied hash word.
 * The transitions are the two simplest continuous deformations of Eq. 4 (α = 0) into Eq. 5 (α = π/2): the
 * hourglass band (0.25, 0.75) slides by ±t/2 with t = α / (π/2), i.e. hourglass iff frac(ℓf ∓ t/2) lies in
 * (0.25, 0.75). Which of the two the paper drew on which side is not recoverable from its text: we take the
 * upward slide (+) below the band and the downward slide (-) above it; the CLI can force either everywhere.
 * Angles are computed by integer CORDIC in units of 2^-30 quarter turns (HZ_QANGLE_RIGHT = π/2), accurate to
 * a few units; exact for horizontal, vertical and exact diagonal motion. γ = floor(2^30 / 20) units.
 *
 * Schedule (Section 3.1.1, 3.2.2): frame f traces subframe f mod 4 of every tile; orderings change only when
 * f mod 4 == 0, so a tile completes a full frame before its ordering changes; static pixels are traced at the
 * MSAA position (f / 4) mod 4, so after 16 frames a static pixel has been sampled at all four positions.
 */
#ifndef HZ_TILEORDER_H
#define HZ_TILEORDER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hz/base.h"
#include "hz/fixed.h"

#define HZ_TILEORDER_COUNT 24u
#define HZ_TILEORDER_HOURGLASS 0u /* 0,1,2,3: 0 1 / 2 3 */
#define HZ_TILEORDER_SQUARE 1u    /* 0,1,3,2: 0 1 / 3 2 */
#define HZ_TILEORDER_BOWTIE 2u    /* 0,2,1,3: 0 2 / 1 3 */

typedef enum hz_tilecycle {
    HZ_TILECYCLE_SQUARE = 0,
    HZ_TILECYCLE_HOURGLASS = 1,
    HZ_TILECYCLE_BOWTIE = 2
} hz_tilecycle_t;

/* The orderings packed two bits per subframe: pixel of subframe s = (hz_tileorder_packed[order] >> 2s) & 3. */
extern const uint8_t hz_tileorder_packed[HZ_TILEORDER_COUNT];

/* Pixel (0..3) that ordering `order` (< 24) traces in subframe `subframe` (taken mod 4). */
HZ_INLINE unsigned hz_tileorder_pixel(unsigned order, unsigned subframe)
{
    return (hz_tileorder_packed[order % HZ_TILEORDER_COUNT] >> (2u * (subframe & 3u))) & 3u;
}
/* Subframe (0..3) in which ordering `order` traces pixel `pixel` (< 4): the inverse of hz_tileorder_pixel. */
unsigned hz_tileorder_subframe(unsigned order, unsigned pixel);
/* Index of the ordering that visits seq[0..3]; -1 if seq is not a permutation of {0,1,2,3}. */
int hz_tileorder_index(const uint8_t seq[4]);
/* Cycle class of ordering `order` (< 24), derived from the steps of its closed path. */
hz_tilecycle_t hz_tileorder_cycle(unsigned order);
/* Canonical ordering rendered for a class (HZ_TILEORDER_HOURGLASS / _BOWTIE / _SQUARE). */
unsigned hz_tileorder_of_cycle(hz_tilecycle_t cycle);
/* Short lower-case name of a class ("square", "hourglass", "bowtie"). */
const char *hz_tilecycle_name(hz_tilecycle_t cycle);

/* Angles in units of 2^-30 quarter turns. */
typedef uint32_t hz_qangle_t;
#define HZ_QANGLE_RIGHT ((hz_qangle_t)1 << 30) /* π/2 */
#define HZ_QANGLE_DIAG ((hz_qangle_t)1 << 29)  /* π/4 */
#define HZ_QANGLE_GAMMA ((hz_qangle_t)53687091u) /* π/40 = 2^30 / 20, rounded down */

/* α = atan2(|my|, |mx|) folded into [0, HZ_QANGLE_RIGHT]; 0 for zero motion. */
hz_qangle_t hz_tileorder_angle(hz_q16_t mx, hz_q16_t my);
/* ℓf: fractional part of |m| (|m| rounded down to 2^-16 px), as Q16.16 in [0, 1). Exact for any input. */
hz_q16_t hz_tileorder_length_frac(hz_q16_t mx, hz_q16_t my);

/* Decision rules: the paper's ĝ and the alternatives it compares (Fig. 10), plus the two forced patterns. */
typedef enum hz_ghat_rule {
    HZ_GHAT_FULL = 0,     /* Fig. 10 right: shear up / random band / shear down */
    HZ_GHAT_DOMINANT,     /* Fig. 10 left: Eq. 4 if |mx| >= |my|, else Eq. 5 */
    HZ_GHAT_SHEAR_UP,     /* Fig. 10 middle-left for every direction */
    HZ_GHAT_SHEAR_DOWN,   /* Fig. 10 middle-right for every direction */
    HZ_GHAT_HOURGLASS,    /* always hourglass */
    HZ_GHAT_BOWTIE,       /* always bowtie */
    HZ_GHAT_RULE_COUNT
} hz_ghat_rule_t;

/* Name of a rule as the CLI spells it ("full", "dominant", "shear-up", "shear-down", "hourglass", "bowtie");
 * NULL for an unknown value. */
const char *hz_ghat_rule_name(hz_ghat_rule_t rule);

/* ĝ for motion m = (mx, my) in Q16.16 pixels per frame. `rnd` is a uniformly random word for this tile and
 * cycle (only its top bit is used, only inside the random band of HZ_GHAT_FULL). Returns hourglass or bowtie. */
hz_tilecycle_t hz_tileorder_ghat(hz_q16_t mx, hz_q16_t my, uint32_t rnd, hz_ghat_rule_t rule);
/* The off-axis part of ĝ (mx != 0 and my != 0), from ℓf (Q16.16, [0, 1)) and α (0 < α < π/2) directly; the
 * dominant-direction rule reads α <= π/4 as "|mx| >= |my|". hz_tileorder_ghat calls it for off-axis motion. */
hz_tilecycle_t hz_tileorder_ghat_polar(hz_q16_t lf, hz_qangle_t a, uint32_t rnd, hz_ghat_rule_t rule);

/* The random word hz_tileorder_choose uses for tile (tx, ty) in cycle `cycle` with seed `seed`: the same as
 * hz_tileorder_tile_random_keyed(tx, ty, hz_tileorder_cycle_key(cycle, seed)), whose key a loop over tiles
 * computes once. */
uint32_t hz_tileorder_tile_random(uint32_t tx, uint32_t ty, uint32_t cycle, uint32_t seed);
uint32_t hz_tileorder_cycle_key(uint32_t cycle, uint32_t seed);
uint32_t hz_tileorder_tile_random_keyed(uint32_t tx, uint32_t ty, uint32_t key);

/* Choose the ordering of tile rows [ty0, ty1) of a tiles_x-wide grid: orders[ty * tiles_x + tx] =
 * canonical ordering of ĝ(motion[2 * i], motion[2 * i + 1]) with i = ty * tiles_x + tx. Rows are independent, so
 * any split into row ranges gives the same result. */
void hz_tileorder_choose(const hz_q16_t *motion, size_t tiles_x, size_t ty0, size_t ty1, uint32_t cycle,
                         uint32_t seed, hz_ghat_rule_t rule, uint8_t *orders);

/* The 4-frame schedule. */
HZ_INLINE unsigned hz_tdense_subframe(uint32_t frame)
{
    return frame & 3u;
}
/* MSAA position used by static pixels in frame `frame`: constant for a whole cycle of 4 frames. */
HZ_INLINE unsigned hz_tdense_jitter_index(uint32_t frame)
{
    return (frame >> 2) & 3u;
}
/* Orderings may change only at the first frame of a cycle. */
HZ_INLINE bool hz_tdense_cycle_start(uint32_t frame)
{
    return (frame & 3u) == 0;
}
HZ_INLINE uint32_t hz_tdense_cycle(uint32_t frame)
{
    return frame >> 2;
}

/* The standard 4x MSAA sample positions, in 1/16 pixel from the pixel centre (x right, y down):
 * (-2,-6), (6,-2), (-6,2), (2,6). */
extern const int8_t hz_msaa4_jitter16[4][2];

#endif /* HZ_TILEORDER_H */
