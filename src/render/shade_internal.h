/*
 * shade_internal.h — what the packet-surface kernels (shade_avx2.c, shade_neon.c, both over shade_kernel.h)
 * share with their scalar twin in shade_packet.c: the per-lane steps that stay scalar (pose-key interpolation,
 * material look-up, the mip chain's levels), written once so both paths take them from the same code.
 */
#ifndef HZ_SHADE_INTERNAL_H
#define HZ_SHADE_INTERNAL_H

#include "shade.h"
#include "render_internal.h"

#define HZ_SHADE_INV_PI 0.31830988618379067f

/* Which textures a lane's material reads (hz_shade_lane_material). */
typedef struct hz_shade_lane_tex {
    bool any;        /* texturing on: the uv and the cone's level of detail are needed */
    int32_t base;    /* base texture, or -1 */
    bool base_alpha; /* blended, and its alpha texture is the base texture */
    int32_t alpha;   /* a separate alpha texture of a blended material, or -1 */
} hz_shade_lane_tex_t;

/* Live lanes' vertex positions (pos[vertex * 3 + axis][lane]) and, when the scene has them, normals, at each
 * lane's time from the pose keys or the scene. */
void hz_shade_fetch_scalar(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t mask,
                           float pos[9][HZ_SHADE_LANES], float nrm[9][HZ_SHADE_LANES]);
/* Lane i's untextured albedo and opacity (tu = tv = 0, not textured) and which textures it reads. */
void hz_shade_lane_material(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t i, hz_shade_out_t *o,
                            hz_shade_lane_tex_t *lt);
/* The mip levels of texture tex as the packet kernels read them: the level hz_texture_sample filters at level of
 * detail lod_base + size_term is hz_texture_level_of's, lod_base lane by lane (hz_shade_levels_head gives
 * size_term and top); hz_shade_levels_walk then walks the mip chain down to the deepest level the lanes need:
 * level l's texels start at first[l] and are w[l] x h[l], and bit l of `far` says they lie beyond a 32-bit
 * gather index (such a lane samples with hz_shade_sample_lane). Once per texture and packet, so that the lanes
 * of one texture take their levels lane-parallel. It holds values, never pointers into a frame. */
#define HZ_SHADE_MAX_LEVELS 32 /* a texture's levels: 1 + log2 of a 32-bit side at most */
typedef struct hz_shade_levels {
    float size_term; /* 0.5 log2(width height), the product hz_shade_sample_lane computes */
    int32_t top;     /* levels - 1 */
    uint32_t far;
    int32_t first[HZ_SHADE_MAX_LEVELS], w[HZ_SHADE_MAX_LEVELS], h[HZ_SHADE_MAX_LEVELS];
} hz_shade_levels_t;
/* tex must name a texture of s (0 <= tex < texture_count); upto <= top. */
void hz_shade_levels_head(const hz_scene_t *s, int32_t tex, hz_shade_levels_t *lv);
void hz_shade_levels_walk(const hz_scene_t *s, int32_t tex, int32_t upto, hz_shade_levels_t *lv);

/* Texture filtering over the pixel (hz_shade_ctx_t.footprint). hz_shade_footprint_lane: lane i's change of
 * texture coordinates per pixel step, g = { du/dx, du/dy, dv/dx, dv/dy }, for the triangle p[] (at the ray's
 * time) and the ray's direction and eye distance; false where it does not apply or is not finite. Tap k of
 * HZ_SHADE_TAPS sits at (hz_shade_tap_offset(k % side), hz_shade_tap_offset(k / side)) pixels from the hit, on
 * a side x side grid over the pixel. */
/* 2x2: on Sponza at 1024x1024 a 3x3 grid filtered closer to the 256-spp reference (mean FLIP of adaptive at tau 1
 * 0.0050 against 0.0060) but cost about three times the taps' time (a fifth of the frame against a twentieth). */
#define HZ_SHADE_TAP_SIDE 2
#define HZ_SHADE_TAPS (HZ_SHADE_TAP_SIDE * HZ_SHADE_TAP_SIDE)
bool hz_shade_footprint_lane(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t i, const hz_vec3_t p[3],
                             float g[4]);
static inline float hz_shade_tap_offset(uint32_t k)
{
    return (float)(2 * (int)k + 1 - HZ_SHADE_TAP_SIDE) / (float)(2 * HZ_SHADE_TAP_SIDE);
}
/* Texture tex at (tu, tv) for a lane, on the level lod_base plus half log2 of the texture's area: one
 * hz_texture_sample, or with gradients g (non-NULL) the mean of the taps, each hz_texture_sample at that level,
 * summed in tap order then scaled by 1 / HZ_SHADE_TAPS (the one sample at (tu, tv) where a tap is not finite). */
void hz_shade_sample_lane(const hz_scene_t *s, int32_t tex, float tu, float tv, float lod_base, const float *g,
                          float rgba[4]);

#endif
