/*
 * hz/adaptive.h — selective and adaptive supersampling as a render mode (HZ_MODE_ADAPTIVE, seed 003, Jin et al.,
 * HPG 2009): its options (the nine thresholds of Table 1, the normal angle, the focus objects) and the
 * accumulation weights. The activity mask itself is integer logic in hz/adaptive_mask.h; the passes live in
 * src/recon/adaptive.c.
 *
 * Contract:
 *  - A frame is three passes over the 8x8 tiles. Pass 0, presample: one ray through each pixel centre (exactly
 *    the full mode's 1 spp), the output image keeps the shaded colour (it is also the colour reference: no
 *    copy) and the geometry attributes of the primary and first mirror hit are packed from the G-buffer into
 *    the compact attribute map (hz_amask_hit_t, 8 bytes a hit: 16 B/px with mirrors, 8 without; the paper uses
 *    32). Pass 1, test: each pixel's 4-bit mask (1 B/px) from its 3x3 neighbourhood (image edges replicate).
 *    Pass 2, extra samples: a tile's active subpixels, packed in Morton order, get 4 stratified samples each,
 *    traced in packets of HZ_RENDER_LANES camera rays (two subpixels per AVX2 packet, one per NEON packet);
 *    the pixel becomes centre x (4 - n) / 4 + (sum of its 4n samples) / 16 (Fig. 5): weights sum to 1.
 *  - The 16 sample positions of a pixel are the full mode's 16-spp positions (stratum k = 4 row + column of a
 *    4x4 grid, jittered by the same hash): with every subpixel active a pixel is the 16-spp pixel, with none
 *    it is the 1-spp pixel (test_render_adaptive checks both).
 *  - Items of a pass write disjoint pixels and read only what earlier passes wrote: the image is bit-identical
 *    for every thread count.
 *  - Thresholds are in [0, 1] (τ = 1 switches an attribute off; τcol = 1 leaves only attribute-driven
 *    sampling); they become Q16 integers (round(65536 τ)) for the mask.
 */
#ifndef HZ_ADAPTIVE_H
#define HZ_ADAPTIVE_H

#include <stddef.h>
#include <stdint.h>

#include "hz/adaptive_mask.h"
#include "hz/status.h"

typedef struct hz_adaptive_opts {
    float tau[HZ_TAU_COUNT];     /* hz_tau_t order; default Table 2's caption */
    float normal_angle_deg;      /* normals within this angle agree; default 15 */
    uint32_t focus_count;        /* 0: all objects */
    uint16_t focus[HZ_AMASK_MAX_FOCUS]; /* object ids (any order; duplicates allowed) */
    /* 1: in a pixel with active subpixels, each inactive one takes the presample's colours interpolated
     * bilinearly at its own centre instead of the pixel's centre colour (seed 003 section 6); costs px x 12
     * bytes (a copy of the presample). 0 (default): Fig. 5's weights. */
    int bilinear;
    /* 1: the presample's textures are the mean over each pixel's footprint on the hit plane (2x2 bilinear taps
     * on the ray cone's mip level, placed by ray differentials: src/render/shade.h), the box filter the
     * supersampled pixels apply, so a pixel left at one sample is not sharper than one with sixteen (with camera
     * motion blur, the frame camera's footprint). 0: one bilinear sample at the hit. */
    int footprint;
} hz_adaptive_opts_t;

void hz_adaptive_opts_default(hz_adaptive_opts_t *o);
/* "col", "poid", "psn", "psc", "pte", "soid", "ssn", "ssc", "ste" (the --tau-NAME options). */
const char *hz_tau_name(hz_tau_t k);
/* Checks the options (HZ_E_INVALID_ARG naming the threshold or the focus list) and converts them. */
hz_status_t hz_adaptive_config(const hz_adaptive_opts_t *o, hz_amask_config_t *c, hz_error_t *err);

/* Fig. 5: weight of the centre colour and of each extra sample for a pixel with `active` (0..4) active
 * subpixels. */
void hz_adaptive_weights(uint32_t active, float *centre, float *sample);

/* Frame-arena bytes of the adaptive mode beyond the full mode's (attribute map and mask), and per pixel. */
size_t hz_adaptive_frame_bytes(uint32_t width, uint32_t height, int mirrors);
uint32_t hz_adaptive_attr_bytes_per_pixel(int mirrors);

#endif /* HZ_ADAPTIVE_H */
