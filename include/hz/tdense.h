/*
 * hz/tdense.h — temporally dense reconstruction (seed 001, Andersson et al., HPG 2019, Fig. 3): each displayed
 * frame traces one sample per 2x2 tile, at the pixel the tile's ordering names for this subframe, and composites a
 * full-resolution frame from it, the earlier subframes and the previous displayed frame.
 *
 * Contract:
 *  - All memory comes from the arena at hz_tdense_init (hz_tdense_bytes tells how much); frames allocate
 *    nothing. Nothing here touches the OS.
 *  - One frame is: hz_tdense_begin_frame; for every tile (any order, any threads), hz_tdense_tile_sample says
 *    which pixel to trace and with which jitter, and hz_tdense_put stores what the tracer found there; then
 *    (after all puts: a barrier) hz_tdense_resolve_rows over a partition of the tile rows (any split, any
 *    threads); then hz_tdense_end_frame. Puts for different tiles and resolves of disjoint row ranges may run
 *    concurrently; the output is bit-identical for every split and thread count (each pixel is computed from
 *    state no other work item writes in the same phase).
 *  - Motion vectors are in pixels per frame, screen space (x right, y down), previous position minus current
 *    position (hz/render.h's G-buffer convention): the content at pixel p was at p + m in the previous frame.
 *    For a pixel whose primary ray hit a mirror the tracer also passes the motion of the reflected hit
 *    (Fig. 5); it is used unless reflect_mv is off.
 *  - Per pixel (Fig. 3): the pixel is dynamic when the longest motion vector m in its 3x3 neighbourhood is
 *    non-zero, or the camera moved this frame. Static pixels average their samples at the four 4x MSAA positions
 *    (a moving window: one slot per position, the newest sample at a position replaces the previous one),
 *    traced with jitter; dynamic pixels are traced at the pixel centre, a new one is stored directly, an old one
 *    is the previous displayed frame, bilinearly resampled at p + m and clamped to the box mean ± γσ (per
 *    channel, RGB) of the pixel's immediate neighbours that belong to the newest subframe (Fig. 7 right). Turning
 *    dynamic empties the window. There is no exponential history anywhere. A pixel that has never been traced
 *    nor reprojected from a traced one (the first frames after init/reset) shows the box mean.
 *  - Tile orderings change only at the start of a cycle of four frames: the last frame of a cycle chooses the
 *    next cycle's ordering of each tile with ĝ (hz/tileorder.h) from the longest motion vector over the 3x3
 *    neighbourhoods of the tile's four pixels (the same motion that decided whether they are dynamic).
 *  - Odd widths/heights: the last tile column/row is partial; a tile whose named pixel lies outside the image
 *    traces nothing that frame.
 *  - Compact state (hz/pack.h): window samples are kept as RGB9E5, the previous displayed frame and motion
 *    vectors as half floats (the frame in one plane per channel, which the SIMD resolve converts eight codes
 *    at a time). A traced sample is displayed at full precision in the frame that traced it; what is kept for
 *    later frames is rounded to those formats.
 *  - Non-finite colours are displayed as given in the frame that traced them (a broken tracer shows up) and kept
 *    as 0 (the packs have no NaN; the largest value kept is HZ_HALF_MAX, in the window HZ_RGB9E5_MAX);
 *    non-finite or huge motion vectors are sanitised (NaN as 0, clamped to ±HZ_TDENSE_MAX_MOTION px).
 */
#ifndef HZ_TDENSE_H
#define HZ_TDENSE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hz/arena.h"
#include "hz/image.h"
#include "hz/pack.h"
#include "hz/status.h"
#include "hz/tileorder.h"

#define HZ_TDENSE_MAX_MOTION 16384.0f
#define HZ_TDENSE_TILE_PAD 8u /* elements of padding around each per-tile array (hz_tdense_t) */
#define HZ_TDENSE_HIST_PAD 8u /* codes of padding after each history frame's planes (the SIMD gather reads words) */

typedef struct hz_tdense_config {
    uint32_t width, height;  /* the displayed frame, 1..HZ_IMAGE_MAX_DIM each */
    hz_ghat_rule_t rule;     /* HZ_GHAT_FULL: the paper's ĝ; the others for its comparisons */
    uint32_t seed;           /* for the random band of ĝ */
    bool reflect_mv;         /* mirrors use the reflected hit's motion (default true) */
    float gamma;             /* variance box half-width in standard deviations (default 1) */
    bool motion;             /* anything can move (default true); false: every motion vector is 0 and none is
                              * stored (a still scene under a still camera) */
} hz_tdense_config_t;

/* Defaults for a width x height frame: full ĝ, seed 0, reflected motion on, γ = 1. */
hz_tdense_config_t hz_tdense_config_default(uint32_t width, uint32_t height);

/* Per-pixel flag bits (hz_tdense_t.flags). */
#define HZ_TDENSE_SAMPLES 0x0fu /* bit j: the window holds the sample at MSAA position j */
#define HZ_TDENSE_DYNAMIC 0x10u /* the pixel was dynamic in the last resolved frame */
#define HZ_TDENSE_SEEN 0x20u    /* the pixel has shown traced content at least once */
#define HZ_TDENSE_KEPT 0x40u    /* the last frame kept the pixel's value (static, no new sample) */

typedef struct hz_tdense {
    hz_tdense_config_t cfg;
    uint32_t tiles_x, tiles_y;
    uint32_t frame;        /* frames since init/reset: subframe = frame mod 4 */
    bool camera_moved;     /* this frame */
    bool in_frame;         /* between begin_frame and end_frame */
    /* Per-tile arrays have HZ_TDENSE_TILE_PAD readable elements before the first tile and after the last (the
     * SIMD resolve loads a group of tiles around the ones it needs). */
    uint8_t *orders;       /* tiles: ordering index of this cycle */
    uint8_t *next_orders;  /* tiles: chosen in the last frame of a cycle */
    float *sub_rgb[3];     /* tiles, one plane per channel: this frame's sample of each tile */
    int8_t *sub_jitter;    /* tiles: MSAA index the sample was traced at, -1 for the centre, -2 none traced */
    uint16_t *mv;          /* pixels x 2: motion of each pixel's newest sample (half float); NULL without motion */
    uint32_t *window;      /* pixels x 4: the moving window, one RGB9E5 sample per MSAA position */
    uint8_t *flags;        /* pixels: HZ_TDENSE_* bits */
    /* displayed frames as half floats in three planes (R, G, B: one code per pixel each, then HZ_TDENSE_HIST_PAD),
     * ping-pong: the one written is hist[frame & 1]. Only the resolve writes them (hz_half_pack's codes). */
    uint16_t *hist[2];
    hz_image_t out;        /* the displayed frame (linear float RGB) */
} hz_tdense_t;

/* Bytes hz_tdense_init takes from an arena for width x height (including alignment padding), or 0 when the
 * size is invalid; hz_tdense_bytes assumes motion, hz_tdense_plan says it (cfg.motion) and gives the part that
 * is the displayed frame (float RGB) in *display_bytes (may be NULL). Stored per pixel: 16 bytes of window,
 * 12 of history, 4 of motion (with motion), 1 of flags, 3.75 per pixel of per-tile state, the displayed frame. */
size_t hz_tdense_bytes(uint32_t width, uint32_t height);
size_t hz_tdense_plan(uint32_t width, uint32_t height, bool motion, size_t *display_bytes);

/* Checks cfg and allocates the state. HZ_E_INVALID_ARG for a bad size, rule or γ; HZ_E_NO_MEMORY (with needed
 * and available bytes) when the arena is too small, in which case nothing is kept. */
hz_status_t hz_tdense_init(hz_tdense_t *td, const hz_tdense_config_t *cfg, hz_arena_t *arena, hz_error_t *err);

/* Forgets all history (frame 0, orderings ĝ(0), empty windows, black frames). */
void hz_tdense_reset(hz_tdense_t *td);

/* Starts a frame. camera_moved: the camera differs from the previous frame's (restarts every window). */
void hz_tdense_begin_frame(hz_tdense_t *td, bool camera_moved);

/* The pixel tile (tx, ty) traces this frame and its jitter in pixels from the pixel centre (x right, y
 * down): an MSAA position when the pixel is static, (0, 0) when dynamic. Returns false (and traces nothing)
 * when the pixel lies outside the image. *msaa gets the MSAA index, or -1 for the centre. */
bool hz_tdense_tile_sample(const hz_tdense_t *td, uint32_t tx, uint32_t ty, uint32_t *px, uint32_t *py,
                           float jitter[2], int *msaa);

/* Stores what was traced for tile (tx, ty) this frame: linear RGB, motion of the primary hit, and the motion
 * of the reflected hit when the primary hit was a mirror (NULL otherwise). */
void hz_tdense_put(hz_tdense_t *td, uint32_t tx, uint32_t ty, const float rgb[3], const float mv[2],
                   const float *mv_reflect);

/* Composites tile rows [ty0, ty1) (pixel rows 2*ty0 .. 2*ty1-1) of this frame, with the board's SIMD (AVX2: 8
 * pixels at a time, NEON: 4) where it has one. hz_tdense_resolve_rows_scalar is its scalar twin: the two give
 * bit-identical frames and state. hz_tdense_resolve_path names the path the first takes ("avx2", "neon" or
 * "scalar"). */
void hz_tdense_resolve_rows(hz_tdense_t *td, uint32_t ty0, uint32_t ty1);
void hz_tdense_resolve_rows_scalar(hz_tdense_t *td, uint32_t ty0, uint32_t ty1);
const char *hz_tdense_resolve_path(void);

/* Ends the frame: the resolved frame becomes the previous frame; at the end of a cycle the chosen orderings
 * take effect. */
void hz_tdense_end_frame(hz_tdense_t *td);

/* The displayed frame: after hz_tdense_resolve_rows, the one being resolved; after hz_tdense_end_frame, the one
 * just finished. */
const hz_image_t *hz_tdense_output(const hz_tdense_t *td);

/* Ordering of tile (tx, ty) in this cycle. */
HZ_INLINE unsigned hz_tdense_tile_order(const hz_tdense_t *td, uint32_t tx, uint32_t ty)
{
    return td->orders[(size_t)ty * td->tiles_x + tx];
}

#endif /* HZ_TDENSE_H */
