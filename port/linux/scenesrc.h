/*
 * scenesrc.h — a scene through the renderer as the frame loop's source (hz/framesrc.h): what `hzrt render`,
 * `hzrt latency --render scene` and `hzrt show` draw, in every mode and with every render option.
 *
 * Contract:
 *  - hz_scenesrc_open() sets everything up once, in the board pools: loads the scene (hook `prepare` may then
 *    resolve what needs it, e.g. adaptive focus names), refuses up front a render that does not fit the board
 *    (naming the arena and both counts), starts the static thread pool, builds the accel (motion-blur keys when
 *    the shutter is open) and creates the renderer. With `levels`, the renderer holds memory for every level of
 *    the governor's ladder (hz/ladder.h) and the source offers them; without, it has one level.
 *  - render() renders frame req->id at req->level (reconfiguring the renderer when the level changes), then
 *    writes it into the loop's RGB24 frame as exact sRGB codes: directly when the rendered size is the frame's,
 *    as blocks for the user's whole-number render scale at level 0, bilinearly upscaled for the governor's
 *    levels (hz/rgb8.h). Scene time: with clock HZ_SCENE_CLOCK_SLOTS, start + (req->slot - the first frame's
 *    slot) / hz exactly (a simulated display: the same frames as a plain sequence, at any render speed); with
 *    HZ_SCENE_CLOCK_DISPLAY, start + req->display_ns - the first frame's display_ns (a real display's clock,
 *    nanoseconds all the way so that hours of running do not quantise the animation). render() allocates
 *    nothing.
 *  - The statistics (per-frame render time on the wall clock, frames per level, build time) and the renderer
 *    stay readable after the loop, until hz_scenesrc_close(), which stops the pool, releases the accel and gives
 *    the pools back as open found them (so does a failed open): anything taken from them after open is
 *    released too.
 *  - One scene source at a time (the state is static).
 */
#ifndef HZ_PORT_SCENESRC_H
#define HZ_PORT_SCENESRC_H

#include <stdbool.h>

#include "hz/accel.h"
#include "hz/framesrc.h"
#include "hz/ladder.h"
#include "hz/render.h"
#include "hz/scenetime.h"
#include "hz/status.h"

enum { HZ_SCENE_CLOCK_DISPLAY = 0, HZ_SCENE_CLOCK_SLOTS = 1 };

#define HZ_SCENESRC_MAX_TIMED 100000 /* frames whose render times are kept for the summary */

typedef struct hz_scenesrc_cfg {
    const char *scene;             /* a .hzb path or "builtin" */
    hz_render_opts_t opts;         /* level 0: mode, render size, every render option (frame_hz: the display) */
    hz_accel_backend_t backend;
    hz_accel_blur_t blur;          /* motion-blur BVH of the native backend (with a shutter) */
    hz_accel_rigid_t rigid;        /* ... and what it does with rigid motion (default: instances) */
    hz_accel_segments_t segments;  /* ... and its nodes' motion segments (default: per node) */
    int threads;                   /* render threads; 0: one per core */
    int out_w, out_h;              /* the frames the sink shows (0: the render size) */
    bool levels;                   /* offer the governor's ladder */
    int clock;                     /* HZ_SCENE_CLOCK_* */
    hz_time_ns_t start;            /* scene time of the first frame */
    bool quiet;                    /* no progress lines */
    bool frame_progress;           /* a progress line for each frame that takes long (a run of one frame) */
    /* called once the scene is loaded, before anything is planned (NULL: none) */
    hz_status_t (*prepare)(void *ctx, const hz_scene_t *scene, hz_render_opts_t *opts, hz_error_t *err);
    void *prepare_ctx;
} hz_scenesrc_cfg_t;

typedef struct hz_scenesrc_stats {
    double build_ms;
    int threads;                   /* render threads the pool runs */
    uint64_t frames;               /* rendered */
    uint32_t timed;                /* frames with a kept render time (the first HZ_SCENESRC_MAX_TIMED) */
    const double *render_ms;       /* [timed]: wall-clock render time of each frame */
    uint64_t level_frames[HZ_GOV_MAX_LEVELS];
    uint32_t last_level;
} hz_scenesrc_stats_t;

hz_status_t hz_scenesrc_open(const hz_scenesrc_cfg_t *cfg, hz_framesrc_t *src, hz_error_t *err);
/* A configuration with default render options in `mode`, rendered at (w / scale) x (h / scale) into w x h frames,
 * the native backend, one thread per core, the display clock from time 0, one level and no progress lines: what
 * tests and tools start from before they change what they need. */
void hz_scenesrc_cfg_init(hz_scenesrc_cfg_t *c, const char *scene, hz_render_mode_t mode, int w, int h, int scale);
/* hz_scenesrc_open of that configuration with `threads` (w, h multiples of scale). */
hz_status_t hz_scenesrc_open_simple(hz_framesrc_t *src, const char *scene, int w, int h, int scale, int threads,
                                    hz_render_mode_t mode, hz_error_t *err);
const hz_scenesrc_stats_t *hz_scenesrc_stats(void);
hz_renderer_t *hz_scenesrc_renderer(void);
const hz_scene_t *hz_scenesrc_scene(void);
hz_accel_t *hz_scenesrc_accel(void);
/* The ladder (one level when opened without levels). */
const hz_ladder_t *hz_scenesrc_ladder(void);
/* Render frame `id` at `level`, scene time t, into out (what render() does, without the loop: the level-error
 * measurement and tests). */
hz_status_t hz_scenesrc_render_at(uint64_t id, uint32_t level, hz_time_ns_t t, hz_rgb8_image_t *out,
                                  hz_error_t *err);
void hz_scenesrc_close(void);

#endif
