/*
 * render_internal.h — state shared by the renderer's files (src/render, src/recon). Not a public API.
 *
 * Work is organised per tile (HZ_RENDER_TILE^2 pixels) and per "batch": one sample of every pixel of the
 * tile. A batch's camera rays are traced as coherent packets; everything they spawn (shadow rays,
 * reflections, continuation rays through blended layers) goes through two per-worker queues traced in packets
 * of HZ_RENDER_LANES, depth first, until both are empty. Each ray carries the batch slot it contributes to.
 */
#ifndef HZ_RENDER_INTERNAL_H
#define HZ_RENDER_INTERNAL_H

#include "hz/adaptive.h"
#include "hz/config.h"
#include "hz/render.h"
#include "hz/tdense.h"

#if HZ_SIMD_LANES >= 8
#define HZ_RENDER_LANES 8
#else
#define HZ_RENDER_LANES 4
#endif

#define HZ_TILE_PIXELS (HZ_RENDER_TILE * HZ_RENDER_TILE)
/* Blended triangles one shadow ray can composite in its single occlusion pass; rays crossing more take the
 * exact layer-by-layer path. */
#define HZ_SHADOW_LAYERS 32

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
    float w[3];                /* radiance added to the slot if the light is visible */
    float vis;                 /* transmittance of the blended layers crossed so far */
    float time;                /* the time of the ray whose hit casts it */
    uint16_t slot;
    uint8_t gslot;             /* counts into shadow / shadow2 of the slot's pixel when blocked */
    uint8_t light;             /* the light's index (mod 256): packets are gathered per light */
    uint16_t layers;
    uint8_t camera;            /* 1: from a camera ray's hit (packets of these are coherent) */
    uint8_t dither;            /* 1: from a stochastic fragment with rr_shadows: blended occluders by roulette */
} shadow_job_t;

/* Mirror data of a primary hit, for the reflected hit's motion vector. */
typedef struct mirror_rec {
    float p[3], n[3];          /* hit point and normal now */
    float pp[3], np[3];        /* the same at the previous frame */
} mirror_rec_t;

typedef struct hz_worker {
    ray_job_t *stack;
    uint32_t stack_n, stack_cap;
    shadow_job_t *shadows;
    uint32_t shadow_n, shadow_cap;
    float radiance[HZ_TILE_PIXELS * 3];
    uint32_t pixel[HZ_TILE_PIXELS];          /* slot -> pixel index; UINT32_MAX for slots outside the image */
    uint8_t alpha_touched[HZ_TILE_PIXELS];   /* a cutout was tested on the slot's primary path */
    uint8_t dither_touched[HZ_TILE_PIXELS];  /* a stochastic decision met a blended surface on the slot's path */
    uint32_t dither_frame;                   /* frame index the thresholds use (full mode: frame * spp + k) */
    bool write_gbuffer;                      /* this batch fills the G-buffer */
    mirror_rec_t mirror[HZ_TILE_PIXELS];
    /* Shadow packet in flight (scenes with blended surfaces): per lane the transmittance of the blended
     * triangles met so far and which ones (the any-hit callback may see a triangle more than once). */
    float shadow_vis[HZ_RENDER_LANES];
    uint32_t shadow_prims[HZ_RENDER_LANES][HZ_SHADOW_LAYERS];
    uint8_t shadow_nprims[HZ_RENDER_LANES];
    uint8_t shadow_overflow[HZ_RENDER_LANES];
    hz_accel_ctx_t ctx;
    hz_render_stats_t stats;
    struct hz_renderer *r;
} hz_worker_t;

/* adaptive mode (src/recon/adaptive.c): the compact attribute map and the activity mask of this frame. */
typedef struct hz_adaptive_state {
    hz_amask_config_t cfg;
    hz_amask_hit_t *attr;      /* levels hits per pixel (primary, then the mirror hit where the scene has mirrors) */
    uint32_t levels;
    uint8_t *mask;             /* bit q: subpixel q active */
} hz_adaptive_state_t;

struct hz_renderer {
    hz_render_opts_t opts;
    hz_scene_t *scene;
    hz_accel_t *accel;
    /* What this scene needs (features leave stages out). */
    bool has_blend, has_mask, has_textures, has_mirrors, has_motion, camera_moves, need_mv;
    bool dither;               /* a stochastic transparency method is on and the scene blends something */
    float offset_scale;        /* scene size for secondary-ray origin offsets (hz_accel_offset_origin) */
    hz_view_t view, prev_view;
    bool have_prev;
    uint64_t frame;
    float time;                /* scene time inside the loop (seconds), for ray time */
    hz_time_ns_t time_ns;      /* scene time of this frame */
    float jitter[2];           /* this frame's sub-pixel offset (TAA), in pixels */
    uint32_t tiles_x, tiles_y;
    hz_image_t out;            /* displayed frame */
    hz_image_t cur;            /* TAA: this frame's raw samples */
    uint16_t *hist[2];         /* TAA: resolved history, ping-pong, half-float RGB (hz/pack.h) */
    uint32_t hist_index;       /* hist[hist_index] is the previous frame's */
    bool hist_valid;
    uint16_t *prev_object;     /* TAA: previous frame's primary object ids */
    hz_tdense_t td;            /* tdense: subframe placement and composite (its frames are the output) */
    hz_adaptive_state_t ad;    /* adaptive: attribute map and mask */
    hz_gbuffer_t gb;
    /* Motion blur (opts.shutter > 0): sample times t in [0, 1) of the frame's shutter map to ray.time
     * tmap_a + t * tmap_b in the pose keys' interval; the camera is interpolated between cam_views. */
    bool blur, cam_blur;
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
    const hz_light_t *lights;  /* the scene's, or default_light when it has none (hz/deflight.h) */
    uint32_t light_count;
    hz_light_t default_light;
    bool default_lit;
};

/* camera.c */
void hz_view_setup(hz_view_t *v, const hz_camera_t *cam, uint32_t width, uint32_t height);
/* Unit direction through pixel (x + 0.5 + jx, y + 0.5 + jy). */
hz_vec3_t hz_view_ray_dir(const hz_view_t *v, float px, float py);
/* Pixel coordinates (continuous, pixel centres at +0.5) of a world point; false if behind the camera. */
bool hz_view_project(const hz_view_t *v, hz_vec3_t p, float *px, float *py);
/* Screen motion in pixels of a world point that is at p now and was at pp one frame ago: its projection by prev
 * minus its projection by cur, or HZ_VIEW_MV_FAR on both axes where either camera does not see it. */
#define HZ_VIEW_MV_FAR 65536.0f
void hz_view_point_motion(const hz_view_t *cur, const hz_view_t *prev, hz_vec3_t p, hz_vec3_t pp, float out[2]);
/* hz_view_point_motion of HZ_SHADE_LANES points that did not move (pp = p; 32-byte aligned arrays), with the
 * same bits in every lane: camera_lanes.c on SIMD boards, a loop over the scalar function elsewhere. */
void hz_view_still_motion_lanes(const hz_view_t *cur, const hz_view_t *prev, const float *px, const float *py,
                                const float *pz, float *mx, float *my);

/* texture.c */
/* Base colour (linear RGB) and alpha of texture t at uv, mip level from the ray-cone footprint lod. */
void hz_texture_sample(const hz_scene_t *s, int32_t tex, float u, float v, float lod, float rgba[4]);
/* Alpha only, finest level (cutout decisions must not depend on distance). */
float hz_texture_alpha(const hz_scene_t *s, int32_t tex, float u, float v);
float hz_log2_approx(float x);
/* What hz_texture_sample does before filtering (the packet kernels share it): whether texture tex can be read at
 * (u, v) (else the sample is 1, 1, 1, 1), the level lod selects, and a level's first texel and size. */
bool hz_texture_usable(const hz_scene_t *s, int32_t tex, float u, float v);
uint32_t hz_texture_level_of(const hz_texture_t *t, float lod);
size_t hz_texture_level_first(const hz_texture_t *t, uint32_t level, uint32_t *w, uint32_t *h);

/* trace.c */
/* Traces one sample of every slot of the worker's tile (w->pixel set by the caller; jitter[slot] in pixels,
 * each in [-0.5, 0.5]) and adds its radiance to w->radiance[slot]; fills the G-buffer when asked. Slots whose
 * pixel is UINT32_MAX are skipped: to trace a subset of pixels, put them in the first slots (consecutive
 * HZ_RENDER_LANES slots form a packet) and mark the rest UINT32_MAX, as tdense does. */
/* times: NULL, or with motion blur the sample time of each slot in [0, 1) of the frame's shutter. */
void hz_trace_batch(hz_worker_t *w, const float (*jitter)[2], const float *times, bool write_gbuffer);
/* Slot -> pixel of tile `tile`, ordered so that consecutive HZ_RENDER_LANES slots form compact packets. */
void hz_tile_slots(const struct hz_renderer *r, uint32_t tile, uint32_t pixel[HZ_TILE_PIXELS]);
bool hz_render_anyhit(void *user, uint32_t prim, float u, float v, float t, uint32_t ray_id, int lane);

/* adaptive.c (src/recon) */
hz_status_t hz_adaptive_init(struct hz_renderer *r, hz_arena_t *frame_arena, hz_error_t *err);
/* Pass 0, after the tile's 1-spp presample: packs the slots' G-buffer records into the attribute map. */
void hz_adaptive_keep_attrs(struct hz_renderer *r, const hz_worker_t *w);
void hz_adaptive_test_tile(struct hz_renderer *r, uint32_t tile);               /* pass 1 */
void hz_adaptive_extra_tile(struct hz_renderer *r, uint32_t tile, hz_worker_t *w); /* pass 2 */
/* transp.c: stochastic transparency (seed 004, hz/dither.h) */
/* Any-hit of a stochastic ray of batch slot `slot` at a blended triangle of opacity alpha: true keeps it (the
 * ray ends there, the fragment is shaded as opaque). Marks the slot's dither_touched unless alpha <= 0.01. */
bool hz_transp_keep(hz_worker_t *w, uint32_t prim, float u, float v, float alpha, uint32_t slot);
/* Any-hit of a stochastic fragment's shadow ray at a blended triangle: true blocks the light. */
bool hz_transp_shadow_blocks(const hz_worker_t *w, uint32_t prim, float u, float v, float alpha);
/* Motion-vector alignment (pixels) TAA uses where the method dithered: 3 (STD cell), 5 (DTAA), 1 (RR). */
unsigned hz_transp_mv_align(hz_transp_t t);

/* taa.c (src/recon): the TAA resolve of one tile, with the board's SIMD where it has one (taa_lanes.c) unless
 * opts.scalar_recon; hz_taa_resolve_tile_scalar and hz_taa_resolve_pixel are its scalar twin (bit-identical). */
void hz_taa_resolve_tile(struct hz_renderer *r, uint32_t tile);
void hz_taa_resolve_tile_scalar(struct hz_renderer *r, uint32_t tile);
void hz_taa_resolve_pixel(struct hz_renderer *r, uint32_t x, uint32_t y);
/* RGB -> YCoCg, the TAA box's colour space; one definition for the resolve and its SIMD twin (whose 10x10 block
 * must hold exactly the values the twin computes). */
HZ_INLINE void hz_taa_to_ycocg(const float *rgb, float *o)
{
    o[0] = 0.25f * rgb[0] + 0.5f * rgb[1] + 0.25f * rgb[2];
    o[1] = 0.5f * rgb[0] - 0.5f * rgb[2];
    o[2] = -0.25f * rgb[0] + 0.5f * rgb[1] - 0.25f * rgb[2];
}

#endif
