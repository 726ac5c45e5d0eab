/*
 * mode.h — the render-mode interface: what a mode module (src/recon: full, taa, tdense, adaptive) gives the
 * renderer, and the renderer's services it may call. Not a public API; src/recon includes it, src/render never
 * includes a src/recon header (the modes reach the renderer through the table below only).
 *
 * Contract:
 *  - A mode is one module with one hz_mode_ops_t row in hz_render_modes[] (src/recon/modes.c), indexed by
 *    hz_render_mode_t. The renderer tests no mode anywhere else: memory, passes, overlap, output, history and
 *    the motion-blur key interval all come from the row. Adding a mode is one module, one enum value in
 *    hz/render.h and one row.
 *  - A mode owns its state (state_bytes, held inside the renderer) and every array it keeps, which it names
 *    in layout(): the same function counts them for hz_render_plan and takes them in hz_render_create (and
 *    again, within the renderer's reservation, when hz_render_reconfigure changes size or mode), so the plan and
 *    the allocation cannot disagree (src/core/memplan.h). layout() must not read or write the state's arrays:
 *    when counting they are NULL. init() runs after a take: it sets the arrays' first contents.
 *  - A mode reads the renderer through hz_render_frame_t (options, tiles, frame index, G-buffer, what the scene
 *    needs) and traces through hz_render_trace, hz_render_trace_tile or hz_render_sample_tile with its thread's
 *    hz_batch_t; it writes only its own state and its batch.
 *  - Passes: for p < passes(), items pass_items(p) run once each via pass_run on any threads (thread-unique
 *    batches); items of one pass write disjoint pixels. overlap_units/needs/run as hz_render_overlap_* (hz/render.h);
 *    a mode without overlap leaves them NULL.
 */
#ifndef HZ_RENDER_MODE_H
#define HZ_RENDER_MODE_H

#include <stdbool.h>
#include <stdint.h>

#include "../core/memplan.h"
#include "hz/config.h"
#include "hz/render.h"
#include "hz/vmath.h"

#if HZ_SIMD_LANES >= 8
#define HZ_RENDER_LANES 8
#else
#define HZ_RENDER_LANES 4
#endif
#define HZ_TILE_PIXELS (HZ_RENDER_TILE * HZ_RENDER_TILE)
/* The largest state a mode may have (hz_mode_ops_t.state_bytes): the renderer holds it inline. */
#define HZ_RENDER_MODE_STATE_MAX 512u

/* Parts of a frame-arena plan (hz_render_plan_t's split). */
enum { HZ_PART_STATE = 0, HZ_PART_DISPLAY, HZ_PART_GBUFFER, HZ_PART_GBUFFER2, HZ_PART_MV };

/* What a mode sees of the renderer. The renderer sets it; modes read it (opts is the current configuration). */
typedef struct hz_render_frame {
    hz_render_opts_t opts;
    uint32_t tiles_x, tiles_y;   /* HZ_RENDER_TILE tiles over opts.width x opts.height */
    uint64_t frame;              /* the frame index of this frame */
    bool camera_moved;           /* the camera differs from the previous frame's (false on the first) */
    bool need_mv;                /* the G-buffer has motion vectors (something moves) */
    bool has_mirrors;            /* the G-buffer has the secondary (mirror) records */
    bool blur;                   /* motion blur: samples take times in the shutter */
    bool dither;                 /* a stochastic transparency method meets blended surfaces */
    hz_gbuffer_t gb;
} hz_render_frame_t;

/* One thread's batch: the slots of up to HZ_TILE_PIXELS samples traced together (consecutive HZ_RENDER_LANES
 * slots form a packet), the radiance each slot gathered, and the thread's counters. */
typedef struct hz_batch {
    uint32_t pixel[HZ_TILE_PIXELS];          /* slot -> pixel index; UINT32_MAX: an empty slot */
    float radiance[HZ_TILE_PIXELS * 3];      /* added to by hz_render_trace */
    uint32_t dither_frame;                   /* frame index the dither thresholds use */
    bool footprint;                          /* camera rays filter textures over their pixel (shade.h) */
    hz_render_stats_t stats;
} hz_batch_t;

/* How hz_render_trace_tile places a tile's samples: spp per pixel (1: pixel centres), or every pixel at one
 * fixed offset (fixed_jitter), or the 4x MSAA positions (msaa4, spp 4); stratified per-pixel positions
 * otherwise. With motion blur, sample k of a pixel takes time index time_index (when time_count > 0) of
 * time_count, else k of spp. footprint: the camera rays' textures are the mean over the pixel's footprint
 * (src/render/shade.h) instead of one bilinear sample at the hit. */
typedef struct hz_tile_sampling {
    uint32_t spp;
    const float *fixed_jitter;   /* NULL: none */
    bool msaa4;
    uint32_t time_index, time_count;
    bool footprint;              /* textures filtered over each pixel (meant for 1 spp at pixel centres) */
} hz_tile_sampling_t;

/* ---- the renderer's services ---- */
/* Traces one sample of every non-empty slot (jitter in pixels in [-0.5, 0.5]; times: NULL or each slot's
 * shutter time in [0, 1)) and adds its radiance to b->radiance; fills the G-buffer when write_gbuffer. */
void hz_render_trace(hz_render_frame_t *f, hz_batch_t *b, const float (*jitter)[2], const float *times,
                     bool write_gbuffer);
/* Every pixel of tile `tile`, sampled as s says, into dst (the mean of its samples, finite and >= 0). The
 * first sample fills the G-buffer. */
void hz_render_trace_tile(hz_render_frame_t *f, hz_batch_t *b, uint32_t tile, const hz_tile_sampling_t *s,
                          hz_image_t *dst);
/* The same without the store: b->pixel names the tile's pixels (UINT32_MAX: none) and b->radiance holds the sum
 * of each one's samples, for a mode that keeps its samples in a layout of its own (hz_render_store them with
 * scale 1 / s->spp). */
void hz_render_sample_tile(hz_render_frame_t *f, hz_batch_t *b, uint32_t tile, const hz_tile_sampling_t *s);
/* rgb * scale -> dst, non-finite or negative values replaced by 0 (non-finite ones counted in b->stats). Inline:
 * every mode calls it per pixel. */
HZ_INLINE void hz_render_store(hz_batch_t *b, float *dst, const float *rgb, float scale)
{
    for (int c = 0; c < 3; c++) {
        float v = rgb[c] * scale;
        if (!hz_isfinitef(v)) {
            b->stats.nonfinite++;
            v = 0.0f;
        }
        dst[c] = v > 0.0f ? v : 0.0f;
    }
}
/* Motion blur: shutter time in [0, 1) of sample `index` of `count` of pixel px (src/pattern/timeseq.h). */
float hz_render_sample_time(const hz_render_frame_t *f, uint32_t px, uint32_t index, uint32_t count);
/* Side (pixels) of the method's dither cell, the box TAA averages a dithered pixel's sample over: 3 (STD),
 * 5 (DTAA), 1 (RR). */
unsigned hz_transp_mv_align(hz_transp_t t);

/* ---- the mode table ---- */
enum {
    HZ_MODE_TAKES_MSAA4 = 1u << 0,   /* opts.msaa4 means something */
    HZ_MODE_KEEPS_SURFACE = 1u << 1, /* the G-buffer keeps depth, normals and shadow counts */
};

typedef struct hz_mode_ops {
    const char *name;
    unsigned flags;                  /* HZ_MODE_* */
    size_t state_bytes;
    /* Mode-specific checks of a configuration (NULL: none). */
    hz_status_t (*check)(const hz_render_opts_t *o, hz_error_t *err);
    void (*layout)(void *state, const hz_render_frame_t *f, hz_memplan_t *p);
    hz_status_t (*init)(void *state, const hz_render_frame_t *f, hz_error_t *err);
    /* Motion blur: frames one pose-key interval spans (1, or tdense's 4-subframe cycle) and this frame's place in
     * it (NULL: always 0). */
    uint32_t (*key_frames)(const hz_render_opts_t *o);
    uint32_t (*key_phase)(const void *state);
    void (*begin_frame)(void *state, const hz_render_frame_t *f);
    uint32_t passes;
    uint32_t (*pass_items)(const void *state, const hz_render_frame_t *f, uint32_t pass);
    void (*pass_run)(void *state, hz_render_frame_t *f, uint32_t pass, uint32_t item, hz_batch_t *b);
    uint32_t (*overlap_units)(const void *state, const hz_render_frame_t *f);
    /* Pass 0's items as rows of row_items each, row-major: an overlapped run counts a trace row done when all its
     * items have returned, and overlap_needs names these rows (NULL: the render tiles, tiles_y x tiles_x). */
    void (*trace_grid)(const void *state, const hz_render_frame_t *f, uint32_t *rows, uint32_t *row_items);
    void (*overlap_needs)(const void *state, const hz_render_frame_t *f, uint32_t unit, uint32_t *lo, uint32_t *hi);
    void (*overlap_run)(void *state, hz_render_frame_t *f, uint32_t unit);
    void (*end_frame)(void *state, const hz_render_frame_t *f);
    const hz_image_t *(*output)(const void *state);
    /* Forget history (a cut); NULL: nothing to forget. */
    void (*reset)(void *state, const hz_render_frame_t *f);
} hz_mode_ops_t;

extern const hz_mode_ops_t *const hz_render_modes[HZ_MODE_COUNT];

/* The state of r's mode when it is `ops` (for a mode's own accessors), else NULL. */
void *hz_render_mode_state(const hz_renderer_t *r, const hz_mode_ops_t *ops);

#endif
