/*
 * tdense_internal.h — what the scalar tdense resolve (tdense.c) shares with its SIMD twin (tdense_lanes.c).
 *
 * Contract:
 *  - hz_tdense_resolve_pixel is the reference: one pixel of Fig. 3, given the longest motion m of its 3x3
 *    neighbourhood. The SIMD row resolve gives bit-identical results for every pixel (same operations in the
 *    same order) and hands pixels it does not vectorise (window updates, row ends) to it.
 *  - hz_tdense_column_motion: the longest of the motions at column x of the rows r0, r1, r2 (in that order;
 *    NULL rows: no motion), the building block of the sliding 3x3 maximum.
 *  - The per-tile arrays have HZ_TDENSE_TILE_PAD elements of padding on either side (hz/tdense.h): the SIMD
 *    row loads HZ_LANES tiles starting one before the first it needs.
 */
#ifndef HZ_TDENSE_INTERNAL_H
#define HZ_TDENSE_INTERNAL_H

#include "../core/memplan.h"
#include "hz/tdense.h"

/* The state's arrays for cfg, counted or taken by p (src/core/memplan.h): the one description behind
 * hz_tdense_plan, hz_tdense_init and the tdense render mode. The displayed frame is counted in part
 * HZ_TDENSE_PART_DISPLAY, the rest in HZ_TDENSE_PART_STATE; sets td's configuration and tile counts. */
enum { HZ_TDENSE_PART_STATE = 0, HZ_TDENSE_PART_DISPLAY = 1 };
void hz_tdense_layout(hz_tdense_t *td, const hz_tdense_config_t *cfg, hz_memplan_t *p);
/* hz_tdense_init's checks of cfg (size, rule, gamma). */
hz_status_t hz_tdense_check(const hz_tdense_config_t *cfg, hz_error_t *err);

typedef struct hz_tdense_motion {
    float x, y, l2;
} hz_tdense_motion_t;

hz_tdense_motion_t hz_tdense_column_motion(const uint16_t *r0, const uint16_t *r1, const uint16_t *r2, size_t x);

void hz_tdense_resolve_pixel(hz_tdense_t *td, uint32_t x, uint32_t y, unsigned subframe, hz_tdense_motion_t m,
                             const uint16_t *prev, uint16_t *cur);

/* ĝ at the end of a cycle (tdense_ghat.c): hz_tileorder_ghat(mx, my, hz_tileorder_tile_random_keyed(tx, ty, key),
 * rule), the same decision for every input, mostly in double precision (the random word made only where it
 * is read). hz_tdense_ghat_certain is its fast part: the decision (a hz_tilecycle_t, or HZ_TDENSE_GHAT_RANDOM:
 * the random band decides) where the double-precision angle and length make it certain, -1 where they do not
 * (near an edge of the bands, on an axis, and for the rules that need no angle). */
#define HZ_TDENSE_GHAT_RANDOM 3
int hz_tdense_ghat_certain(hz_q16_t mx, hz_q16_t my, hz_ghat_rule_t rule);
hz_tilecycle_t hz_tdense_ghat(hz_q16_t mx, hz_q16_t my, uint32_t tx, uint32_t ty, uint32_t key, hz_ghat_rule_t rule);

/* Pixel of tile (tx, ty) traced this frame, as image coordinates; false when outside the image. */
HZ_INLINE bool hz_tdense_tile_pixel(const hz_tdense_t *td, uint32_t tx, uint32_t ty, uint32_t *px, uint32_t *py)
{
    unsigned p = hz_tileorder_pixel(hz_tdense_tile_order(td, tx, ty), hz_tdense_subframe(td->frame));
    *px = 2 * tx + (p & 1u);
    *py = 2 * ty + (p >> 1);
    return *px < td->cfg.width && *py < td->cfg.height;
}

/* MSAA index a pixel is traced at: the cycle's position when static, -1 (centre) when dynamic or when the
 * camera moved (every pixel is dynamic then). */
HZ_INLINE int hz_tdense_trace_msaa(const hz_tdense_t *td, size_t pixel)
{
    if (td->camera_moved || (td->flags[pixel] & HZ_TDENSE_DYNAMIC))
        return -1;
    return (int)hz_tdense_jitter_index(td->frame);
}

/* hz_tdense_tile_sample, inline for the mode's trace loop (it runs for every tile of every frame). */
HZ_INLINE bool hz_tdense_sample_at(const hz_tdense_t *td, uint32_t tx, uint32_t ty, uint32_t *px, uint32_t *py,
                                   float jitter[2], int *msaa)
{
    jitter[0] = jitter[1] = 0.0f;
    *msaa = -1;
    if (!hz_tdense_tile_pixel(td, tx, ty, px, py))
        return false;
    int j = hz_tdense_trace_msaa(td, (size_t)*py * td->cfg.width + *px);
    if (j >= 0) {
        jitter[0] = (float)hz_msaa4_jitter16[j][0] * (1.0f / 16.0f);
        jitter[1] = (float)hz_msaa4_jitter16[j][1] * (1.0f / 16.0f);
    }
    *msaa = j;
    return true;
}

/* hz_tdense_put for a sample placed by hz_tdense_tile_sample in this frame: tile index t (ty * tiles_x + tx), its
 * pixel p (py * width + px) and msaa as the sampling returned them, so nothing is looked up twice. The same
 * state as hz_tdense_put's. */
void hz_tdense_put_sample(hz_tdense_t *td, size_t t, size_t p, int msaa, const float rgb[3], const float mv[2],
                          const float *mv_reflect);

/* Lanes per group on AVX2 and NEON boards (lanes.h's HZ_LANES; here so that tdense.c needs no SIMD header). */
#if defined(HZ_BOARD_SIMD_AVX2)
#define HZ_TDENSE_LANES 8
#elif defined(HZ_BOARD_SIMD_NEON)
#define HZ_TDENSE_LANES 4
#endif

/* The longest motion over the 4x4 pixel block around each of the tiles tx0 .. tx0 + HZ_TDENSE_LANES - 1 of tile
 * row ty (all inside the row; the blocks clamped to the image), scanned in longest_in's order (tdense.c): the
 * components into mx and my. Needs motion vectors (td->mv). */
void hz_tdense_block_motion_lanes(const hz_tdense_t *td, uint32_t ty, uint32_t tx0, float *mx, float *my);

/* A motion vector (x, y) as the compositor keeps it: each component NaN as 0, clamped to
 * +-HZ_TDENSE_MAX_MOTION, then hz_half_pack_signed; x's code in the low 16 bits, y's in the high.
 * hz_tdense_motion_code_lanes (tdense_lanes.c, AVX2 and NEON boards): the same bits by the ISA's conversion,
 * for the put of every traced sample. */
uint32_t hz_tdense_motion_code(float x, float y);
uint32_t hz_tdense_motion_code_lanes(float x, float y);

/* Pixel row y with lanes (defined in tdense_lanes.c on AVX2 and NEON boards). */
void hz_tdense_resolve_row_lanes(hz_tdense_t *td, uint32_t y, unsigned subframe, const uint16_t *prev,
                                 uint16_t *cur);

#endif /* HZ_TDENSE_INTERNAL_H */
