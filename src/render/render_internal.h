/*
 * render_internal.h — state shared by the renderer's own files (src/render). Not a public API; the render modes
 * (src/recon) see the renderer through mode.h only.
 *
 * Work is organised per tile (HZ_RENDER_TILE^2 pixels) and per "batch": one sample of every pixel of the
 * tile. A batch's camera rays are traced as coherent packets; everything they spawn (shadow rays,
 * reflections, continuation rays through blended layers) goes through two per-worker queues traced in packets
 * of HZ_RENDER_LANES, depth first, until both are empty. Each ray carries the batch slot it contributes to.
 */
#ifndef HZ_RENDER_INTERNAL_H
#define HZ_RENDER_INTERNAL_H

#include "hz/config.h"
#include "hz/render.h"
#include "mode.h"
#include "shade.h"
/* Which G-buffer record a ray's first hit fills. */
enum { GSLOT_NONE = 0, GSLOT_PRIMARY = 1, GSLOT_SECONDARY = 2 };

typedef struct hz_view {
    hz_vec3_t eye;
    hz_vec3_t fwd, right, up;  /* right and up scaled so that pixel (x, y) maps to fwd + sx right + sy up */
    float spread;              /* ray-cone spread angle of one pixel (radians) */
    uint32_t width, height;
    /* projection (hz_view_project): right and up over their squared lengths, times half the image size */
    hz_vec3_t proj_x, proj_y;
} hz_view_t;

typedef struct ray_job {
    float o[3], d[3];          /* d is unit length */
    float w[3];                /* throughput: what one unit of radiance along the ray adds to the slot */
    float cone_w, cone_s;      /* ray cone: width at o, spread angle */
    float travelled;           /* distance from the camera to o along the path */
    float vis;                 /* visibility left after the blended layers of this segment */
    float time;                /* ray.time: normalised in the accel's key interval (frame time without blur) */
    uint16_t slot;             /* batch slot (pixel of the tile) */
    uint8_t gslot;             /* GSLOT_* */
    uint8_t bounces;           /* mirror reflections so far */
    uint16_t layers;           /* blended layers crossed so far */
    uint16_t dither;           /* 1: this ray takes the stochastic transparency decision (hz/dither.h) */
} ray_job_t;

typedef struct shadow_job {
    float o[3], d[3];          /* d unit length, towards the light */
    float tmax;                /* distance to the light, shortened a little */
    float w[3];                /* radiance added to the slot times the transmittance to the light */
    float time;                /* the time of the ray whose hit casts it */
    uint16_t slot;
    uint8_t gslot;             /* counts into shadow / shadow2 of the slot's pixel when blocked */
    uint8_t light;             /* the light's index (mod 256): packets are gathered per light */
    uint8_t dither;            /* 1: from a stochastic fragment with rr_shadows: blended occluders by roulette */
} shadow_job_t;

/* Mirror data of a primary hit, for the reflected hit's motion vector. */
typedef struct mirror_rec {
    float p[3], n[3];          /* hit point and normal now */
    float pp[3], np[3];        /* the same at the previous frame */
} mirror_rec_t;

/* A lane's set of the blended triangles a shadow ray met (hz_worker_t): 2^HZ_RENDER_SHADOW_SET_BITS slots, at
 * least twice the layer cap, their indices bytes. */
#define HZ_RENDER_SHADOW_SET_BITS 8
#define HZ_RENDER_SHADOW_SET (1u << HZ_RENDER_SHADOW_SET_BITS)
typedef char hz_render_shadow_set_fits[2 * HZ_RENDER_MAX_LAYERS <= HZ_RENDER_SHADOW_SET &&
                                               HZ_RENDER_SHADOW_SET_BITS <= 8
                                           ? 1
                                           : -1];

typedef struct hz_worker {
    hz_batch_t b;              /* first member: a mode's batch pointer is its worker's (hz_render_trace) */
    ray_job_t *stack;
    uint32_t stack_n, stack_cap;
    shadow_job_t *shadows;
    uint32_t shadow_n, shadow_cap;
    uint8_t alpha_touched[HZ_TILE_PIXELS];   /* a cutout was tested on the slot's primary path */
    uint8_t dither_touched[HZ_TILE_PIXELS];  /* a stochastic decision met a blended surface on the slot's path */
    uint16_t dither_cell[HZ_TILE_PIXELS];    /* the per-sample part of the slot's threshold (hz_transp_cells) */
    bool write_gbuffer;                      /* this batch fills the G-buffer */
    mirror_rec_t mirror[HZ_TILE_PIXELS];
    /* Shadow packet in flight (scenes with blended surfaces): per lane the transmittance of the blended
     * triangles met so far and which ones (the any-hit callback may see a triangle more than once), up to the
     * layer cap of every path: a shadow ray that meets more with visibility left ends as blocked (counted in
     * stats.layer_cap), as a camera path does. The triangles met are a set per lane: open addressing from the
     * top bits of prim * golden, prim + 1 in a slot (prims are below 2^31), 0 in an empty one; at most
     * HZ_RENDER_MAX_LAYERS of its HZ_RENDER_SHADOW_SET slots are taken (at most half), so a search ends within
     * a few probes, and the slots taken are listed to empty them for the next ray. */
    float shadow_vis[HZ_RENDER_LANES];
    uint32_t shadow_set[HZ_RENDER_LANES][HZ_RENDER_SHADOW_SET];
    uint8_t shadow_taken[HZ_RENDER_LANES][HZ_RENDER_MAX_LAYERS];
    uint16_t shadow_nprims[HZ_RENDER_LANES]; /* slots taken, up to HZ_RENDER_MAX_LAYERS */
    uint8_t shadow_overflow[HZ_RENDER_LANES];
    hz_accel_ctx_t ctx;
    struct hz_renderer *r;
} hz_worker_t;

struct hz_renderer {
    hz_render_frame_t f;       /* first member: what the mode sees (mode.h) */
    const hz_mode_ops_t *mode; /* hz_render_modes[f.opts.mode] */
    void *mode_state;          /* its state: mode_store */
    uint64_t mode_store[HZ_RENDER_MODE_STATE_MAX / 8];
    hz_scene_t *scene;
    hz_accel_t *accel;
    /* What this scene needs (features leave stages out). */
    bool has_blend, has_mask, has_textures, has_motion, camera_moves;
    float offset_scale;        /* scene size for secondary-ray origin offsets (hz_accel_offset_origin) */
    hz_view_t view, prev_view;
    hz_shade_footprint_t footprint; /* view's pixel steps (hz_view_footprint), set with it each frame */
    bool have_prev;
    const uint32_t *tri_maps;  /* scenes with blended surfaces: each triangle's dither maps (hz_transp_maps) */
    const uint32_t *blend_bound; /* and each material's opacity bound (hz_transp_bounds); NULL: none, every
                                  * layer's opacity is taken */
    float time;                /* scene time inside the loop (seconds), for ray time */
    hz_time_ns_t time_ns;      /* scene time of this frame */
    /* The frame arena's part that holds the G-buffer and the mode (re-laid out by hz_render_reconfigure). */
    hz_arena_t region;
    /* Motion blur (opts.shutter > 0): sample times t in [0, 1) of the frame's shutter map to ray.time
     * tmap_a + t * tmap_b in the pose keys' interval; the camera is interpolated between cam_views. */
    bool cam_blur;
    hz_posekeys_t *keys;       /* NULL: the accel is static (no keys) */
    float tmap_a, tmap_b;
    hz_view_t cam_views[HZ_RENDER_CAMERA_KEYS];
    uint64_t keys_frame, keys_cycle; /* the frame whose begin evaluated the keys (and its cycle's first frame) */
    hz_time_ns_t keys_t;
    float keys_lo, keys_hi;
    uint64_t key_evals;        /* key evaluations + refits so far (tdense cycles save them) */
    uint32_t frame_refits;     /* accel refits of this frame's begin */
    hz_worker_t *workers_by_thread[HZ_MAX_THREADS]; /* each from its thread's arena */
    uint32_t thread_count;
    hz_render_stats_t last, total;
    const hz_light_t *lights;  /* the scene's, or default_light when it has none (src/render/deflight.h) */
    uint32_t light_count;
    hz_light_t default_light;
    bool default_lit;
};

/* camera.c */
void hz_view_setup(hz_view_t *v, const hz_camera_t *cam, uint32_t width, uint32_t height);
/* Unit direction through pixel (x + 0.5 + jx, y + 0.5 + jy). Inline: returned from a call, the direction went
 * through the stack in pieces and the caller's copy into the ray stalled on store forwarding (two fifths of
 * hz_render_trace's samples). */
HZ_INLINE hz_vec3_t hz_view_ray_dir(const hz_view_t *v, float px, float py)
{
    float sx = 2.0f * px / (float)v->width - 1.0f;
    float sy = 1.0f - 2.0f * py / (float)v->height;
    hz_vec3_t d = hz_v3_add(v->fwd, hz_v3_add(hz_v3_scale(v->right, sx), hz_v3_scale(v->up, sy)));
    return hz_v3_normalize(d);
}
/* hz_view_ray_dir of HZ_SHADE_LANES pixels (x[i], y[i]) at once, into dx, dy, dz: the same bits (lanes where the
 * direction is not finite or its squared length is not a normal float take hz_view_ray_dir itself). */
void hz_view_ray_dirs(const hz_view_t *v, const float *x, const float *y, float *dx, float *dy, float *dz);
/* The pixel steps of hz_view_ray_dir's unnormalised direction and fwd / |fwd|^2 (textures over the pixel). */
void hz_view_footprint(const hz_view_t *v, hz_shade_footprint_t *fp);
/* Pixel coordinates (continuous, pixel centres at +0.5) of a world point; false if behind the camera. */
bool hz_view_project(const hz_view_t *v, hz_vec3_t p, float *px, float *py);
/* Screen motion in pixels of a world point that is at p now and was at pp one frame ago: its projection by prev
 * minus its projection by cur, or HZ_VIEW_MV_FAR on both axes where either camera does not see it. */
#define HZ_VIEW_MV_FAR 65536.0f
/* (The points by address: passed by value to a call, a point went through the stack in pieces and the callee's
 * wide load of them stalled on store forwarding, in the per-hit loops.) */
void hz_view_point_motion(const hz_view_t *cur, const hz_view_t *prev, const hz_vec3_t *p, const hz_vec3_t *pp,
                          float out[2]);
/* hz_view_point_motion of HZ_SHADE_LANES points, now at p and one frame ago at pp (x, y, z arrays, 32-byte
 * aligned; pp may be p for geometry that does not move), with the same bits in every lane: camera_lanes.c on
 * SIMD boards, a loop over the scalar function elsewhere. */
void hz_view_motion_lanes(const hz_view_t *cur, const hz_view_t *prev, const float *const p[3],
                          const float *const pp[3], float *mx, float *my);

/* texture.c */
/* Base colour (linear RGB) and alpha of texture t at uv, mip level from the ray-cone footprint lod. */
void hz_texture_sample(const hz_scene_t *s, int32_t tex, float u, float v, float lod, float rgba[4]);
/* Alpha only, finest level (cutout decisions must not depend on distance). */
float hz_texture_alpha(const hz_scene_t *s, int32_t tex, float u, float v);
float hz_log2_approx(float x);
/* What hz_texture_sample does before filtering (the packet kernels share it): whether texture tex can be read at
 * (u, v) (else the sample is 1, 1, 1, 1), the level lod selects, and a level's first texel and size. The first
 * two are inline: the packet kernels ask them lane by lane. */
HZ_INLINE bool hz_texture_usable(const hz_scene_t *s, int32_t tex, float u, float v)
{
    return !(tex < 0 || (uint32_t)tex >= s->texture_count || !hz_isfinitef(u) || !hz_isfinitef(v));
}
HZ_INLINE uint32_t hz_texture_level_of(const hz_texture_t *t, float lod)
{
    float l = hz_isfinitef(lod) ? lod + 0.5f : 0.0f;
    return l <= 0.0f ? 0u : (uint32_t)hz_minf(l, (float)(t->levels - 1));
}
size_t hz_texture_level_first(const hz_texture_t *t, uint32_t level, uint32_t *w, uint32_t *h);
/* One step down a texture's mip chain: the next level starts after this one's texels and halves each side (down
 * to 1). hz_texture_level_first and the packet kernels' level walk both take their levels from it. */
HZ_INLINE void hz_texture_level_next(size_t *first, uint32_t *w, uint32_t *h)
{
    *first += (size_t)*w * *h;
    *w = *w > 1 ? *w / 2 : 1;
    *h = *h > 1 ? *h / 2 : 1;
}

/* trace.c (hz_render_trace in mode.h is its entry) */
/* Slot -> pixel of tile `tile`, ordered so that consecutive HZ_RENDER_LANES slots form compact packets. */
void hz_tile_slots(const struct hz_renderer *r, uint32_t tile, uint32_t pixel[HZ_TILE_PIXELS]);
/* Motion blur's pose keys; a constant NULL in a build without motion (HZ_FEATURE_MOTION 0), so that the
 * interpolation at the ray's time compiles out. */
#define HZ_RENDER_KEYS(r) (HZ_FEATURE_MOTION ? (r)->keys : NULL)
bool hz_render_anyhit(void *user, uint32_t prim, float u, float v, float t, uint32_t ray_id, int lane, unsigned back);

/* transp.c: stochastic transparency (seed 004, hz/dither.h) */
/* Each triangle's dither maps, one word: the STD map (0..287) of its front and back side, and the DTAA*
 * permutation (0..119) of both, chosen by hash of the triangle's group (a particle: see hz_transp_maps). */
#define HZ_TRANSP_MAPS_PACK(std0, std1, perm0, perm1) \
    ((uint32_t)(std0) | (uint32_t)(std1) << 9 | (uint32_t)(perm0) << 18 | (uint32_t)(perm1) << 25)
#define HZ_TRANSP_MAPS_STD(w, back) (((w) >> ((back) ? 9u : 0u)) & 0x1ffu)
#define HZ_TRANSP_MAPS_PERM(w, back) (((w) >> ((back) ? 25u : 18u)) & 0x7fu)
/* Fills maps[0..triangle_count) (hz_renderer.tri_maps). */
void hz_transp_maps(const hz_scene_t *s, uint32_t *maps);
/* The per-sample part of every slot's threshold (worker.dither_cell) for the batch's pixels and dither_frame. */
void hz_transp_cells(hz_worker_t *w);
/* Any-hit of a stochastic ray of batch slot `slot` at a blended triangle of opacity a (Q16), met from the side
 * `back` (the traversal's test): true keeps it (the ray ends there, the fragment is shaded as opaque). Marks
 * the slot's dither_touched unless a <= 0.01. */
bool hz_transp_keep(hz_worker_t *w, uint32_t prim, float u, float v, uint32_t a, uint32_t slot, unsigned back);
uint32_t hz_transp_alpha_q16(float alpha);
/* The Russian-roulette threshold (Q16) of a stochastic fragment's shadow ray at a blended triangle: the ray is
 * blocked iff hz_dither_keep(its opacity, this threshold). */
uint32_t hz_transp_shadow_threshold(const hz_worker_t *w, uint32_t prim, float u, float v);
/* Each material's opacity bound (Q16, hz_renderer.blend_bound): no hit on a blended surface of material i has
 * hz_transp_alpha_q16 of its opacity above bound[i] (its alpha times its alpha texture's largest level-0 texel,
 * with a margin for rounding; its own alpha where a triangle's texture coordinates may not be finite; `textures`
 * as hz_renderer.has_textures). Not blended: HZ_DITHER_ONE. */
void hz_transp_bounds(const hz_scene_t *s, bool textures, uint32_t *bound);
/* True when hz_transp_keep certainly rejects a layer of opacity at most `bound`: the same decision without the
 * opacity (so without a texture fetch). False says nothing; then the caller takes the opacity. */
bool hz_transp_rejects(const hz_worker_t *w, uint32_t prim, float u, float v, uint32_t bound, uint32_t slot,
                       unsigned back);

#endif
