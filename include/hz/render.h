/*
 * hz/render.h — the Whitted renderer every technique plugs into: camera rays in packets, shading with textures,
 * point lights and shadow rays, mirrors, alpha cutouts and exactly composited blended surfaces, a G-buffer with
 * motion vectors, and the full-frame (N spp) and TAA modes.
 *
 * Contract:
 *  - hz_render_create() takes everything it will ever need from `frame_arena` (images, G-buffer, history) and
 *    from one arena per worker thread (ray queues), sized by hz_render_plan(); nothing is allocated per frame.
 *    It leaves out what the scene does not need: no motion vectors for a static scene under a still camera, no
 *    secondary G-buffer without mirrors, no history outside TAA, no continuation or any-hit work without
 *    transparency.
 *  - A frame is: hz_render_begin_frame (animates the scene to `time`, refits the accel, sets the camera and
 *    this frame's jitter), then for each pass p < hz_render_pass_count(), every item i <
 *    hz_render_pass_items(p) run once through hz_render_pass_run(r, p, i, thread) — in any order, on any
 *    threads, with `thread` < thread_count unique among concurrently running calls — and then
 *    hz_render_end_frame. Items of one pass write disjoint pixels, so the image is bit-identical for every
 *    thread count and schedule. The port supplies the threads (src/ has none).
 *  - Radiance is linear RGB float; every value written to the output is finite and >= 0 (a NaN or Inf from
 *    any stage is replaced by 0 and counted in stats.nonfinite).
 *  - Transparency: alpha-tested (MASK) triangles are decided by the accel's any-hit callback; blended (BLEND)
 *    surfaces are composited front to back with continuation rays, and along shadow rays (in any order, one
 *    occlusion pass), until the remaining visibility drops below opts.min_visibility (at most
 *    HZ_RENDER_MAX_LAYERS layers per path, after which the path ends as if opaque: counted in stats.layer_cap).
 *  - Mirrors reflect up to opts.max_bounces times (0..3).
 *  - Motion vectors (G-buffer mv): for each pixel, its primary hit's position at the previous frame (object
 *    motion through the previous vertex positions, camera motion through the previous camera) minus its
 *    position now, in pixels. With motion blur they stay those of the frame's time. mv_reflect: the same for the reflected hit seen in a mirror (the motion of its
 *    virtual image behind the mirror plane), or the primary value where there is no mirror (seed 001 Fig. 5).
 *  - Motion blur (seed 002): with opts.shutter S > 0 the shutter is open for S / frame_hz seconds centred on
 *    the frame's time. Each sample draws its time from src/pattern/timeseq.h (full mode: sample k of N, stratified over
 *    the N samples of the pixel; TAA: over 16 frames; tdense: over 4 cycles), the camera is evaluated at it
 *    (views at HZ_RENDER_CAMERA_KEYS times across the shutter, interpolated linearly) and every ray carries
 *    it (ray.time, normalised to the accel's key interval); shadow, mirror and continuation rays inherit it
 *    and shading uses the geometry at the ray's time. A moving scene needs opts.keys: pose keys
 *    (hz/posekeys.h, hz_render_plan's time_keys and keys_bytes) that the accel was built over; each
 *    begin_frame evaluates them for the frame's shutter (tdense with opts.tdense_cycle_keys: once per
 *    4-subframe cycle, over the cycle's whole interval, so the accel is refitted once per cycle) and refits.
 *    shutter 0 renders exactly what it did without the option.
 */
#ifndef HZ_RENDER_H
#define HZ_RENDER_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/accel.h"
#include "hz/adaptive.h"
#include "hz/arena.h"
#include "hz/dither.h"
#include "hz/image.h"
#include "hz/posekeys.h"
#include "hz/scene.h"
#include "hz/status.h"
#include "hz/tileorder.h"

#define HZ_RENDER_MAX_LAYERS 128
#define HZ_RENDER_TILE 8 /* tiles are 8 x 8 pixels */
#define HZ_RENDER_CAMERA_KEYS 9 /* motion blur: camera views across the shutter */

typedef enum hz_render_mode {
    HZ_MODE_FULL = 0, /* every pixel, opts.spp stratified samples */
    HZ_MODE_TAA = 1,  /* every pixel, 1 jittered sample, temporal anti-aliasing resolve */
    HZ_MODE_TDENSE = 2, /* one sample per 2x2 tile per frame, temporally dense composite (seed 001, hz/tdense.h) */
    HZ_MODE_ADAPTIVE = 3, /* presample + activity mask + packed extra samples (seed 003, hz/adaptive.h) */
    HZ_MODE_COUNT
} hz_render_mode_t;

typedef struct hz_render_opts {
    uint32_t width, height;
    hz_render_mode_t mode;
    uint32_t spp;          /* full mode: a square (1, 4, 9, ... 256); 1 = pixel centres */
    bool msaa4;            /* full mode, spp 4: the fixed 4x MSAA positions (hz_msaa4_jitter16, the static
                            * pattern of tdense) in that order, instead of stratified random positions */
    uint32_t max_bounces;  /* mirror reflections per path, 0..3 (default 3) */
    float min_visibility;  /* transparency: stop when less is left (default 0.001) */
    /* TAA */
    float taa_gamma;       /* variance box: mean +- gamma * sigma (default 1) */
    float taa_alpha;       /* weight of the new sample (default 0.1) */
    bool taa_clip;         /* clip towards the box centre instead of clamping per channel */
    bool taa_catmull_rom;  /* history fetched with Catmull-Rom instead of bilinear */
    /* tdense */
    hz_ghat_rule_t tdense_rule; /* per-tile ordering rule (default HZ_GHAT_FULL, the paper's ĝ) */
    bool tdense_reflect_mv;     /* mirrors use the reflected hit's motion (default true) */
    float tdense_gamma;         /* variance box of old dynamic pixels: mean +- gamma * sigma (default 1) */
    /* adaptive */
    hz_adaptive_opts_t adaptive; /* thresholds, normal angle, focus objects (hz/adaptive.h) */
    uint32_t seed;         /* decorrelates sample patterns between runs that want it */
    /* Transparency of blended surfaces (seed 004, hz/dither.h): exact compositing (default) or one stochastic
     * decision per camera path (rr, std, dtaa, dtaa-star), or exact while the path's visibility > hybrid_x and
     * then one STD decision (hybrid). A stochastic fragment is shaded as opaque with one deep shadow ray (as in
     * the paper), or with rr_shadows one binary shadow ray that treats blended occluders by Russian roulette;
     * TAA widens its window to 7x7, aligns motion vectors to the dither's cell (3 px; 5 for DTAA) and skips its
     * object-id test where the G-buffer has HZ_GB_DITHER. Scenes without blended surfaces leave all of it out
     * (identical to exact). */
    hz_transp_t transparency;
    float hybrid_x;        /* hybrid: in [0, 1]; 0 behaves as exact, 1 as std */
    bool rr_shadows;       /* stochastic fragments: Russian-roulette shadow rays instead of deep ones */
    /* motion blur */
    float shutter;         /* open fraction of the frame interval 1 / frame_hz, in [0, 1]; 0 = no blur */
    uint32_t frame_hz;     /* the frame rate the shutter refers to (default HZ_DISPLAY_HZ) */
    hz_posekeys_t *keys;   /* shutter > 0 and a moving scene: the pose keys the accel reads (else NULL) */
    bool tdense_cycle_keys; /* tdense: one key interval and refit per 4-subframe cycle (default true) */
    /* The tdense and TAA resolves run with the board's SIMD (8 pixels at a time on AVX2, 4 on NEON); true runs
     * their scalar twins instead, which give bit-identical frames (for tests and side-by-side timing). */
    bool scalar_recon;
    /* Shading through its twin, same images: the kernels' scalar twin (src/render/shade.h), every hit shaded on
     * its own and every shadow ray through the queue, where the packet paths shade camera hits a packet at once
     * and trace their shadow rays straight from the kernel's lanes. Tests and benchmarks compare the two. */
    bool scalar_shading;
    /* tdense and TAA frames overlap their trace and resolve passes (hz_render_overlap_units); true keeps a
     * barrier between them instead (same images: for tests and side-by-side timing). */
    bool serial_passes;
    /* Frame-arena bytes hz_render_create holds for the G-buffer and the mode's state, so that
     * hz_render_reconfigure can later switch to other sizes and modes whose hz_render_plan region_bytes fit
     * (0: just what this configuration needs). */
    size_t reserve_bytes;
} hz_render_opts_t;

void hz_render_opts_default(hz_render_opts_t *o);
/* Checks sizes, spp, bounces, ranges; HZ_E_INVALID_ARG naming the option. */
hz_status_t hz_render_opts_check(const hz_render_opts_t *o, hz_error_t *err);
/* Features a board can compile out (HZ_FEATURE_* in hz/config.h) that the scene or the options need: a scene
 * with blended or cut-out surfaces (transparency), textures, mirrors (with max_bounces > 0) or moving objects
 * (motion), a shutter above 0 (motion) or a transparency method other than exact, in a build without that
 * feature, is refused: HZ_E_UNSUPPORTED naming the feature, its switch and the boards that have it (the others
 * it also needs are listed). hz_render_plan and hz_render_create check it first. */
hz_status_t hz_render_features_check(const hz_scene_t *s, const hz_render_opts_t *o, hz_error_t *err);
const char *hz_render_mode_name(hz_render_mode_t m);

/* G-buffer flags (per hit). */
enum {
    HZ_GB_HIT = 1u << 0,       /* the ray hit something (else background) */
    HZ_GB_TEXTURED = 1u << 1,  /* the material samples a texture */
    HZ_GB_ALPHA = 1u << 2,     /* alpha affected this pixel (a cutout was tested or a blended layer crossed) */
    HZ_GB_MIRROR = 1u << 3,    /* the surface reflects (mirror > 0) */
    HZ_GB_DITHER = 1u << 4,    /* a stochastic transparency decision met a blended surface on the pixel's
                                * camera path (the opacity mask TAA reads); never set with exact */
};
#define HZ_GB_NO_OBJECT 0xffffu

/* Per-pixel attributes (arrays of width * height; NULL where the scene or the mode leaves them out). Index
 * y * width + x. depth, normal and shadow (and normal2, shadow2) exist in the full and adaptive modes only
 * (hz_render_mode_keeps_surface): TAA and tdense read none of them, so they keep object, flags and motion. */
typedef struct hz_gbuffer {
    uint32_t width, height;
    float *depth;          /* primary hit distance along the ray (camera to hit), +inf on a miss */
    uint16_t *object;      /* primary hit object, HZ_GB_NO_OBJECT on a miss */
    float *normal;         /* 3 floats: primary shading normal facing the camera, 0 on a miss */
    uint8_t *shadow;       /* lights not visible from the primary hit */
    uint8_t *flags;        /* HZ_GB_* of the primary hit */
    uint16_t *object2;     /* first secondary (reflected) hit: object; NULL without mirrors */
    float *normal2;        /* NULL without mirrors, and in TAA and tdense */
    uint8_t *shadow2;
    uint8_t *flags2;
    float *mv;             /* 2 floats: previous minus current position, pixels; NULL when nothing moves */
    float *mv_reflect;     /* 2 floats, mirrors: motion of the reflected image; NULL without mirrors+motion */
} hz_gbuffer_t;

typedef struct hz_render_stats {
    uint64_t primary_rays, shadow_rays, secondary_rays; /* secondary: reflections and continuations */
    uint64_t nonfinite;    /* NaN/Inf values replaced by 0 (should stay 0) */
    uint64_t layer_cap;    /* paths cut at HZ_RENDER_MAX_LAYERS */
    uint64_t queue_full;   /* rays dropped because a ray queue was full (should stay 0) */
    /* adaptive: active subpixels, their extra camera rays (4 each, also in primary_rays) and the packets
     * those went out in (extra_rays / extra_packets = live lanes per packet) */
    uint64_t active_subpixels, extra_rays, extra_packets;
    uint64_t refits;       /* accel refits in begin_frame (motion blur in tdense: one per 4-subframe cycle) */
} hz_render_stats_t;

/* Memory a renderer needs: frame_bytes from the frame arena, thread_bytes from each thread arena. frame_bytes
 * by part (alignment padding included, the parts sum to frame_bytes): the displayed frame (float RGB), the
 * primary G-buffer, the secondary (mirror) G-buffer, the motion vectors (primary and reflected), and the mode's
 * own state (TAA history, the tdense window...). anyhit: the accel's any-hit callback is installed (cutouts or
 * blended surfaces); transparency: continuation rays through blended layers run. */
typedef struct hz_render_plan {
    size_t frame_bytes;
    size_t thread_bytes;
    size_t display_bytes, gbuffer_bytes, gbuffer2_bytes, mv_bytes, state_bytes;
    bool anyhit, transparency;
    size_t region_bytes;   /* the G-buffer's and the mode's share of frame_bytes, before opts.reserve_bytes */
    uint32_t time_keys;    /* motion blur: pose keys opts.keys needs (0: none) */
    size_t keys_bytes;     /* what hz_posekeys_init takes for them (from the scene arena, say), 0 without */
} hz_render_plan_t;

hz_status_t hz_render_plan(const hz_scene_t *scene, const hz_render_opts_t *opts, hz_render_plan_t *plan,
                           hz_error_t *err);

typedef struct hz_renderer hz_renderer_t;


hz_status_t hz_render_create(hz_renderer_t **out, hz_scene_t *scene, hz_accel_t *accel,
                             const hz_render_opts_t *opts, hz_arena_t *frame_arena, hz_arena_t *thread_arenas,
                             uint32_t thread_count, hz_error_t *err);

/* time_ns: the frame's scene time (hz/scenetime.h). The float variant takes seconds (finite; short runs). */
hz_status_t hz_render_begin_frame_ns(hz_renderer_t *r, uint64_t frame_index, hz_time_ns_t time_ns, hz_error_t *err);
hz_status_t hz_render_begin_frame(hz_renderer_t *r, uint64_t frame_index, float time, hz_error_t *err);
/* Whether a mode's G-buffer holds depth, normal and shadow counts (full and adaptive: adaptive's tests read
 * them, full keeps them for tools and tests that inspect a reference frame). */
bool hz_render_mode_keeps_surface(hz_render_mode_t mode);
uint32_t hz_render_pass_count(const hz_renderer_t *r);
uint32_t hz_render_pass_items(const hz_renderer_t *r, uint32_t pass);
void hz_render_pass_run(hz_renderer_t *r, uint32_t pass, uint32_t item, uint32_t thread);
void hz_render_end_frame(hz_renderer_t *r);

/* Overlapped passes (tdense and TAA). A resolve reads only this frame's trace results next to its pixels (3x3
 * neighbourhoods, tdense's newest-subframe box and ĝ's 4x4 blocks; TAA's 3x3 or 7x7 window, all within one
 * tile) and state no trace item touches, so a pool may run the two passes as one: trace items are pass 0's
 * (row-major, *row_items to a trace row, *trace_rows rows: a row of render tiles, or of tdense's areas of 8x8
 * tdense tiles), resolve units are tdense's trace-row bands or TAA's
 * tiles, and resolve unit u may start once every trace item
 * of the trace rows [*row_lo, *row_hi] from hz_render_overlap_needs has returned; those ranges never move back
 * as u grows, so units can be handed out in order. Every such order, on any number of threads, gives the frame
 * that the passes one after the other give, bit for bit. hz_render_overlap_units returns the number of resolve
 * units, or 0 where the passes must stay apart (full and adaptive modes, opts.serial_passes). */
uint32_t hz_render_overlap_units(const hz_renderer_t *r, uint32_t *trace_rows, uint32_t *row_items);
void hz_render_overlap_needs(const hz_renderer_t *r, uint32_t unit, uint32_t *row_lo, uint32_t *row_hi);
void hz_render_overlap_run(hz_renderer_t *r, uint32_t unit);

/* The displayed frame (linear RGB), valid after hz_render_end_frame until the next begin. */
const hz_image_t *hz_render_output(const hz_renderer_t *r);
const hz_gbuffer_t *hz_render_gbuffer(const hz_renderer_t *r);
/* Counters of the last frame (summed over threads at end_frame) and since create. */
void hz_render_frame_stats(const hz_renderer_t *r, hz_render_stats_t *last, hz_render_stats_t *total);

/* The stochastic transparency decision (hz/dither.h) of a camera path's any-hit callback, run directly on n
 * candidate hits: triangle prims[i] at barycentrics (1/4, 1/4), met from its back when back[i] is non-zero,
 * for batch slot prims[i] mod the batch size of the first thread's last batch of the last frame (call it
 * after a frame; a candidate's decision then depends on nothing else). keep[i] (may be NULL) receives each decision; returns how many were kept. A triangle that is not
 * blended is kept (opaque), an index past the scene's triangles is not; a renderer without a dither stage
 * (exact, nothing blended) decides nothing and returns 0. For benchmarks (ns per rejected layer) and tests: it
 * changes no image. */
uint32_t hz_render_dither_decide(hz_renderer_t *r, const uint32_t *prims, const uint8_t *back, uint32_t n,
                                 uint8_t *keep);
/* tdense mode: the compositor's state (tile orderings, per-pixel flags: hz/tdense.h), for tests and tools that
 * show it; NULL in the other modes. */
const struct hz_tdense *hz_render_tdense(const hz_renderer_t *r);
/* adaptive mode: the last frame's activity mask (width * height bytes, bit q = subpixel q: 0 top-left, 1
 * top-right, 2 bottom-left, 3 bottom-right); NULL in the other modes. */
const uint8_t *hz_render_adaptive_mask(const hz_renderer_t *r);
/* The key light the renderer added because the scene has none (src/render/deflight.h), or NULL when the scene brings
 * its own lights. */
const hz_light_t *hz_render_default_light(const hz_renderer_t *r);
/* Switches r to configuration o from the next frame on (the governor's quality levels: another size, mode,
 * bounce count, transparency method or adaptive thresholds). What the scene needs and the motion blur (shutter,
 * frame rate, pose keys) stay as created: another shutter is HZ_E_INVALID_ARG. o's region (hz_render_plan's
 * region_bytes) must fit what create held (opts.reserve_bytes), else HZ_E_NO_MEMORY with both counts and r
 * unchanged. A change of size, mode or of the options a mode lays its state out by (tdense's rule, gamma and
 * mirror motion, the seed, the adaptive settings) lays the G-buffer and the mode state out anew and forgets
 * history, as after a cut; the other options take effect with their history kept. Allocates nothing. */
hz_status_t hz_render_reconfigure(hz_renderer_t *r, const hz_render_opts_t *o, hz_error_t *err);
/* Forget history (TAA) and previous-frame state, e.g. after a cut. */
void hz_render_reset_history(hz_renderer_t *r);
/* Switches the reconstruction passes to their scalar twins (true) or the board's SIMD (false) from the next
 * frame on, as opts.scalar_recon; frames are bit-identical either way (side-by-side timing in one process). */
void hz_render_set_scalar_recon(hz_renderer_t *r, bool scalar);
/* The same for opts.serial_passes. */
void hz_render_set_serial_passes(hz_renderer_t *r, bool serial);

#endif /* HZ_RENDER_H */
