/*
 * taa_internal.h — the TAA mode's state, shared by its resolve (taa.c) and the resolve's SIMD twin
 * (taa_lanes.c). Not a public API.
 */
#ifndef HZ_TAA_INTERNAL_H
#define HZ_TAA_INTERNAL_H

#include "../render/mode.h"

typedef struct hz_taa {
    hz_image_t out;            /* the displayed frame */
    float *cur[3];             /* this frame's samples in YCoCg (the box's space), a plane of w x h per channel */
    uint16_t *hist[2];         /* resolved history, ping-pong, half-float RGB (hz/pack.h) */
    uint32_t hist_index;       /* hist[hist_index] is the previous frame's */
    bool hist_valid;
    uint16_t *prev_object;     /* the previous frame's primary object ids */
    float jitter[2];           /* this frame's sub-pixel offset, in pixels */
} hz_taa_t;

/* The resolve of tiles first .. first + count - 1 (one tile row), with the board's SIMD where it has one
 * (taa_lanes.c) unless opts.scalar_recon; hz_taa_resolve_tile_scalar and hz_taa_resolve_pixel are its scalar
 * twin (bit-identical). A run rather than a tile, so that a tile's inputs can be fetched while the one before
 * it resolves. */
void hz_taa_resolve_tiles(hz_taa_t *t, const hz_render_frame_t *f, uint32_t first, uint32_t count);
void hz_taa_resolve_tile_scalar(hz_taa_t *t, const hz_render_frame_t *f, uint32_t tile);
void hz_taa_resolve_pixel(hz_taa_t *t, const hz_render_frame_t *f, uint32_t x, uint32_t y);

/* The traced tile in b (hz_render_sample_tile, one sample per pixel) into t->cur: each pixel's radiance stored
 * as hz_render_store does (non-finite values counted in b->stats and, like negative ones, made 0) and converted
 * to YCoCg. hz_taa_store_samples uses the board's SIMD where it has one (packets of HZ_RENDER_LANES slots that
 * are 2 rows of pixels, hz_tile_slots' layout); hz_taa_store_samples_scalar is its twin, the same values. */
void hz_taa_store_samples(hz_taa_t *t, hz_batch_t *b);
void hz_taa_store_samples_scalar(hz_taa_t *t, hz_batch_t *b);

/* A dithered pixel's variance box is (2 HZ_TAA_DITHER_RADIUS + 1)^2 pixels, widened by HZ_TAA_DITHER_GAMMA, and
 * its sample the mean over the dither's cell of half-side hz_taa_cell_radius (taa.c says why). */
#define HZ_TAA_DITHER_RADIUS 3
#define HZ_TAA_DITHER_GAMMA 1.5f

/* Half the side of the dither's cell: 1 (STD, hybrid), 2 (DTAA), 0 (RR: white noise, no period). */
HZ_INLINE int hz_taa_cell_radius(const hz_render_frame_t *f)
{
    return (int)(hz_transp_mv_align(f->opts.transparency) / 2u);
}

/* RGB -> YCoCg, the TAA box's colour space: each sample is converted once, as the trace stores it, so the
 * resolve and its SIMD twin read the same values. */
HZ_INLINE void hz_taa_to_ycocg(const float *rgb, float *o)
{
    o[0] = 0.25f * rgb[0] + 0.5f * rgb[1] + 0.25f * rgb[2];
    o[1] = 0.5f * rgb[0] - 0.5f * rgb[2];
    o[2] = -0.25f * rgb[0] + 0.5f * rgb[1] - 0.25f * rgb[2];
}

/* Slot `slot` of b, a pixel hz_render_sample_tile traced (its pixel index is not UINT32_MAX), into t->cur: the
 * value hz_render_store makes of it, in YCoCg. */
HZ_INLINE void hz_taa_store_slot(hz_taa_t *t, hz_batch_t *b, uint32_t slot)
{
    float c[3], q[3];
    hz_render_store(b, c, &b->radiance[slot * 3], 1.0f);
    hz_taa_to_ycocg(c, q);
    for (int k = 0; k < 3; k++)
        t->cur[k][b->pixel[slot]] = q[k];
}

#endif
