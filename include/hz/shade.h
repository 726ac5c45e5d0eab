/*
 * hz/shade.h — surface interpolation and texturing of a packet of hits, in structure-of-arrays (the renderer's
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
 *  - `textures` false skips texturing (the renderer's scene has no textured material in use).
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

typedef struct hz_shade_ctx {
    const hz_scene_t *scene;
    const hz_posekeys_t *keys; /* NULL: the scene's current pose */
    bool textures;
} hz_shade_ctx_t;

/* One packet's hits: the ray (direction unit length, time, cone) and the hit (prim, barycentrics, distance). */
typedef struct hz_shade_in {
    uint32_t prim[HZ_SHADE_LANES] HZ_ALIGNED(32); /* every array 32-byte aligned: the kernels load them whole */
    float u[HZ_SHADE_LANES], v[HZ_SHADE_LANES], t[HZ_SHADE_LANES];
    float dx[HZ_SHADE_LANES], dy[HZ_SHADE_LANES], dz[HZ_SHADE_LANES];
    float time[HZ_SHADE_LANES];
    float cone_w[HZ_SHADE_LANES], cone_s[HZ_SHADE_LANES];
} hz_shade_in_t;

typedef struct hz_shade_out {
    float px[HZ_SHADE_LANES] HZ_ALIGNED(32), py[HZ_SHADE_LANES], pz[HZ_SHADE_LANES];
    float ngx[HZ_SHADE_LANES], ngy[HZ_SHADE_LANES], ngz[HZ_SHADE_LANES];
    float nsx[HZ_SHADE_LANES], nsy[HZ_SHADE_LANES], nsz[HZ_SHADE_LANES];
    float albedo[3][HZ_SHADE_LANES];
    float alpha[HZ_SHADE_LANES];          /* opacity of a blended material, 1 otherwise */
    float tu[HZ_SHADE_LANES], tv[HZ_SHADE_LANES]; /* texture coordinates; 0 where no texture was read */
    uint8_t textured[HZ_SHADE_LANES];
} hz_shade_out_t;

void hz_shade_surfaces(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t mask, hz_shade_out_t *out);
void hz_shade_surfaces_scalar(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t mask, hz_shade_out_t *out);
/* "avx2", "neon" or "scalar": which kernel hz_shade_surfaces runs. */
const char *hz_shade_path(void);

#endif /* HZ_SHADE_H */
