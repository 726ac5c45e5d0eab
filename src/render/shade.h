/*
 * shade.h — surface interpolation and texturing of a packet of hits, in structure-of-arrays (the renderer's
 * shading front end; src/render/shade_packet.c with its SIMD kernels shade_avx2.c / shade_neon.c).
 *
 * Contract:
 *  - A packet is HZ_SHADE_LANES hits (8 with AVX2, 4 with NEON and on scalar boards, the renderer's packet
 *    width). `mask` bit i says lane i holds a hit; the other lanes are ignored and their outputs undefined, but
 *    their inputs must still name a valid triangle (the caller repeats a live lane), so that gathers stay in
 *    bounds.
 *  - For each live lane, hz_shade_surfaces computes what the renderer's scalar shading computed per hit, bit
 *    for bit: the hit point (barycentrics of the triangle at the ray's time: pose keys when `keys` is set), the
 *    unit geometric normal ng and shading normal ns facing the ray's side (ns falls back to ng when the
 *    interpolated normal points below the surface), the material's base colour times the base texture and the
 *    opacity of blended materials times their alpha texture, both bilinear on the mip level the ray cone picks
 *    (texture.c), and whether a texture was read. It uses the same operations in the same order as the scalar
 *    twin hz_shade_surfaces_scalar (no FMA, correctly rounded division and square root, the project's own
 *    floor, log2 and normalisation); rare lanes the fast path cannot take (zero, tiny or huge vectors in a
 *    normalisation, texel indices beyond 2^31) are done by the scalar helpers themselves. Tests compare the two.
 *  - Then, for the same lanes, what the light loop needs (the renderer's per-hit code, bit for bit too): the
 *    shadow-ray origin off the surface (hz_accel_offset_origin of the point along ng with the context's
 *    offset_scale; also the mirror ray's origin), the terminator skip (src/render/terminator.h, on the scene's own pose),
 *    and for each of the first HZ_SHADE_LIGHTS lights of the context: whether it lights the surface (in front of
 *    both normals, at a positive distance), the unit direction to it, the shadow ray's start (moved along it by
 *    the skip) and length, and the factor k = cos / pi (/ distance^2 for inverse-square falloff) the light's
 *    colour is weighted with. hz_shade_light_lane gives the same for any light of one lane (lights past the
 *    first HZ_SHADE_LIGHTS; the packet kernels use it nowhere else).
 *  - `textures` false skips texturing (the renderer's scene has no textured material in use).
 *  - `footprint` (NULL: none) filters textures over the pixel: a lane with eye_dist > 0 is a ray on a camera
 *    ray's line (the camera ray or a layer behind it) at that distance from the eye; its texture samples become
 *    the mean of HZ_SHADE_TAPS bilinear taps on the same mip level, placed on a 2x2 grid over the pixel's
 *    footprint on the hit plane (the pixel's two edges through the plane, from the camera's per-pixel
 *    direction steps: ray differentials). Lanes whose footprint is not finite (a ray in the plane, a
 *    degenerate triangle) keep the one sample at the hit. Same bits on both paths.
 *  - Nothing is allocated; the functions are reentrant.
 */
#ifndef HZ_SHADE_H
#define HZ_SHADE_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/config.h"
#include "hz/posekeys.h"
#include "hz/scene.h"

#if HZ_SIMD_LANES >= 8
#define HZ_SHADE_LANES 8
#else
#define HZ_SHADE_LANES 4
#endif
#define HZ_SHADE_LIGHTS 4 /* lights per packet computed lane-parallel */

/* The camera's change of ray direction per pixel step, for the unnormalised direction fwd + sx right + sy up
 * (ex: one pixel right, ey: one pixel down), and fwd / |fwd|^2 (the depth along fwd per unit distance). */
typedef struct hz_shade_footprint {
    float ex[3], ey[3], f[3];
} hz_shade_footprint_t;

typedef struct hz_shade_ctx {
    const hz_scene_t *scene;
    const hz_posekeys_t *keys; /* NULL: the scene's current pose */
    bool textures;
    const hz_light_t *lights;
    uint32_t light_count;
    float offset_scale;        /* hz_accel_offset_origin's scale */
    const hz_shade_footprint_t *footprint; /* NULL: every texture sample is one bilinear tap */
} hz_shade_ctx_t;

/* One light as seen from the lanes of a packet. */
typedef struct hz_shade_light {
    float ox[HZ_SHADE_LANES] HZ_ALIGNED(32), oy[HZ_SHADE_LANES], oz[HZ_SHADE_LANES]; /* shadow ray start */
    float dx[HZ_SHADE_LANES], dy[HZ_SHADE_LANES], dz[HZ_SHADE_LANES];                 /* unit, towards the light */
    float tmax[HZ_SHADE_LANES];
    float k[HZ_SHADE_LANES];
} hz_shade_light_t;

/* One packet's hits: the ray (direction unit length, time, cone) and the hit (prim, barycentrics, distance). */
typedef struct hz_shade_in {
    uint32_t prim[HZ_SHADE_LANES] HZ_ALIGNED(32); /* every array 32-byte aligned: the kernels load them whole */
    float u[HZ_SHADE_LANES], v[HZ_SHADE_LANES], t[HZ_SHADE_LANES];
    float dx[HZ_SHADE_LANES], dy[HZ_SHADE_LANES], dz[HZ_SHADE_LANES];
    float time[HZ_SHADE_LANES];
    float cone_w[HZ_SHADE_LANES], cone_s[HZ_SHADE_LANES];
    float eye_dist[HZ_SHADE_LANES]; /* read only with a footprint: > 0 filters the lane's textures over its pixel */
} hz_shade_in_t;

typedef struct hz_shade_out {
    float px[HZ_SHADE_LANES] HZ_ALIGNED(32), py[HZ_SHADE_LANES], pz[HZ_SHADE_LANES];
    float ngx[HZ_SHADE_LANES], ngy[HZ_SHADE_LANES], ngz[HZ_SHADE_LANES];
    float nsx[HZ_SHADE_LANES], nsy[HZ_SHADE_LANES], nsz[HZ_SHADE_LANES];
    float albedo[3][HZ_SHADE_LANES];
    float alpha[HZ_SHADE_LANES];          /* opacity of a blended material, 1 otherwise */
    float tu[HZ_SHADE_LANES], tv[HZ_SHADE_LANES]; /* texture coordinates; 0 where no texture was read */
    float lox[HZ_SHADE_LANES] HZ_ALIGNED(32), loy[HZ_SHADE_LANES], loz[HZ_SHADE_LANES]; /* offset origin */
    float skip[HZ_SHADE_LANES];
    hz_shade_light_t light[HZ_SHADE_LIGHTS];
    uint32_t lit[HZ_SHADE_LIGHTS];        /* bit i: the light reaches lane i's surface (else: not lit, no ray) */
    uint8_t textured[HZ_SHADE_LANES];
} hz_shade_out_t;

void hz_shade_surfaces(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t mask, hz_shade_out_t *out);
void hz_shade_surfaces_scalar(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t mask, hz_shade_out_t *out);
/* Light l (any index below light_count) for lane i of a packet whose surfaces `o` holds (its origin, skip and
 * normals): its entries of hz_shade_light_t in the lane of *out, and whether it lights the surface. */
bool hz_shade_light_lane(const hz_shade_ctx_t *c, const hz_shade_out_t *o, uint32_t i, uint32_t l,
                         hz_shade_light_t *out);
/* "avx2", "neon" or "scalar": which kernel hz_shade_surfaces runs. */
const char *hz_shade_path(void);

#endif /* HZ_SHADE_H */
