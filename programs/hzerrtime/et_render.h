/*
 * et_render.h — errtime methods and scenes that go through hzrt's renderer (hz/render.h): the scene is loaded
 * into the board pools, the accel built once, and every method renders the sequence with the static thread pool
 * exactly as `hzrt render` does (hz_render_begin_frame, each pass's items through hz_threads_run,
 * hz_render_end_frame).
 *
 * Contract:
 *  - hz_et_render_open(file, env, seq, err) loads `file` ("builtin" or a .hzb name inside env->scene_dir) with
 *    hz_scenefile_open into hz_pools_get()'s scene arena, builds the native accel into its accel arena, starts
 *    the thread pool (env->threads, 0 = one per online CPU) and fills the sequence: scene_data (the loaded
 *    scene), scene_hash (FNV-1a 64 of the scene image's bytes: the .hzb file, or the built-in scene as
 *    generated), camera ("baked path from t = 0") and settings. The settings hold what the reference depends on
 *    besides the scene: the backend, max bounces, min visibility, and a fingerprint of the renderer itself (the
 *    FNV-1a 64 of the float bits of two small full-frame probe renders of this scene, 1 and 16 spp), so a
 *    change to the renderer's output makes a new cache entry instead of reusing a stale reference.
 *    One scene is open at a time (the pools are process-wide); hz_et_render_close() stops the pool, releases
 *    the accel and gives the pools back as they were before open. Closing with nothing open does nothing.
 *  - A method's params are an hz_et_render_params_t. begin creates a renderer whose frame memory (images,
 *    G-buffer, TAA history) comes from the arena errtime hands over and whose per-thread ray queues come from
 *    the pools' thread arenas (given back in end or when begin fails); render(i) renders frame i at scene time
 *    i / refresh_hz, copies the output into the driver's image (a memcpy, inside the timed call) and reports
 *    rays = primary + shadow + secondary rays from the renderer's frame stats. A frame that dropped rays (full
 *    ray queue) or replaced non-finite values fails with HZ_E_INTERNAL: its image would not be the renderer's
 *    answer. Nothing is allocated in render.
 *  - Method seeds: every method uses seed 0, the reference hz_et_render_reference uses its own seed so its
 *    sample positions are not those of the method being scored.
 */
#ifndef HZ_ERRTIME_RENDER_H
#define HZ_ERRTIME_RENDER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "errtime.h"
#include "hz/render.h"

typedef struct hz_et_env {
    const char *scene_dir; /* where <name>.hzb files are (make scenes: build/scenes) */
    uint32_t threads;      /* render threads; 0 = one per online CPU (capped at HZ_MAX_THREADS) */
} hz_et_env_t;

/* Which of adaptive supersampling's nine thresholds (hz_tau_t) a method's knob sets; 0 is tau_alpha. */
typedef enum hz_et_adaptive_knob {
    HZ_ET_TAU_ALPHA = 0,   /* tau_col = tau_pte = tau_ste (Table 2's tau_alpha); the geometric ones Table 2's */
    HZ_ET_TAU_COL,         /* tau_col alone; the other eight Table 2's (Fig. 7, multiple measures) */
    HZ_ET_TAU_COL_ONLY     /* tau_col; the other eight 1, switched off (Fig. 7, colour measure only) */
} hz_et_adaptive_knob_t;

typedef struct hz_et_render_params {
    hz_render_mode_t mode; /* full, taa, tdense */
    uint32_t spp;         /* full mode */
    bool taa_clip;        /* TAA: clip towards the box centre instead of clamping per channel */
    bool taa_catmull_rom; /* TAA: history fetched with Catmull-Rom instead of bilinear */
    uint32_t seed;
    float adaptive_tau;   /* adaptive: the thresholds adaptive_knob names take it; the rest Table 2's */
    hz_et_adaptive_knob_t adaptive_knob;
    bool adaptive_bilinear; /* adaptive: inactive subpixels interpolated (hz_adaptive_opts_t.bilinear) */
    bool adaptive_footprint; /* adaptive: presample textures over the pixel (hz_adaptive_opts_t.footprint) */
    hz_transp_t transparency; /* blended surfaces (hz/dither.h); 0 = exact */
    float hybrid_x;
    /* motion blur (hz/render.h "Motion blur"): shutter > 0 builds pose keys and a motion accel for the run */
    float shutter;        /* fraction of the frame interval 1 / refresh_hz (hz_et_render_set_shutter overrides) */
    hz_accel_blur_t blur; /* native motion BVH: msbvh, interp, swept */
    bool embree;          /* Embree's motion blur instead of the native BVH */
    hz_accel_rigid_t rigid; /* native: rigid objects as instances (default) or refitted with the rest */
} hz_et_render_params_t;

/* The renderer's methods (full-frame, TAA, adaptive supersampling at tau_alpha 0.1, 0.3, 0.6 and 1, with
 * bilinear inactive subpixels at 0.1, 0.3 and 0.6, and seed 003's Fig. 7 pair at tau_col 0.1, 0.2, 0.3 and 0.4:
 * adaptive-colour-only (every geometry attribute off) and adaptive-multiple (Table 2's attribute thresholds);
 * later modes add rows here) and the 256-spp reference. */
#define HZ_ET_RENDER_METHOD_COUNT 27
extern const hz_et_method_t hz_et_render_methods[HZ_ET_RENDER_METHOD_COUNT];
extern const hz_et_method_t hz_et_render_reference;

/* Display-rate comparison (issue 8, seed 001) for sequences shown on a 240 Hz display (refresh_hz 240):
 *   tdense     hz=240  one sample per 2x2 tile per displayed frame (HZ_MODE_TDENSE)
 *   full-1spp  hz=60   1 spp at pixel centres, rendered every 4th displayed frame and held (hold 4)
 *   full-1spp  hz=240  1 spp every displayed frame
 *   taa        hz=60   1 jittered spp + TAA resolve, every 4th displayed frame, held
 *   taa        hz=240  the same every displayed frame
 * "hz" is the rate a method renders at. The reference is the full-frame renderer at 64 stratified spp (these
 * sequences are long: 64 spp keeps a cold report within its time budget; its own error is far below the
 * methods'). */
#define HZ_ET_DISPLAY_METHOD_COUNT 5
extern const hz_et_method_t hz_et_display_methods[HZ_ET_DISPLAY_METHOD_COUNT];
extern const hz_et_method_t hz_et_display_reference;

/* Transparency (seed 004) on scenes with blended surfaces: TAA with each --transparency method (exact, rr, std,
 * dtaa, dtaa-star; hybrid with its threshold as the knob), against the 256-spp exact reference. A sequence whose
 * camera label is "still" is rendered at scene time 0 for every frame (the still view of the stability figure,
 * et_stability.h). */
#define HZ_ET_TRANSP_METHOD_COUNT 8
extern const hz_et_method_t hz_et_transp_methods[HZ_ET_TRANSP_METHOD_COUNT];
/* On a 240 Hz display (beyond the paper): std and exact under tdense at 240 Hz against std and exact + TAA at
 * 60 Hz (held for 4 displayed frames), scored display-integrated against hz_et_display_reference. */
#define HZ_ET_TRANSP_DISPLAY_METHOD_COUNT 4
extern const hz_et_method_t hz_et_transp_display_methods[HZ_ET_TRANSP_DISPLAY_METHOD_COUNT];
/* Motion blur at equal time budget (seed 002): the same renderer (full frame, 1, 4 and 16 spp) with the shutter
 * open (default 1: the whole frame interval) over three accels built for the run beside the scene's own:
 *   msbvh      the native MSBVH (over every moving triangle, rigid objects refitted too)
 *   interp     the native interpolated BVH (the paper's baseline; likewise)
 *   instances  rigid objects as instances in object space, the MSBVH for the rest (the renderer's default)
 *   embree     Embree's motion blur (host builds with Embree; absent elsewhere)
 * against the full-frame renderer at 256 spp with the same shutter (MSBVH). The images of the three at equal
 * spp agree (same rays at the same times): their error at equal time is what the accel's speed buys. */
#if HZ_HAVE_EMBREE
#define HZ_ET_BLUR_METHOD_COUNT 12
#else
#define HZ_ET_BLUR_METHOD_COUNT 9
#endif
extern const hz_et_method_t hz_et_blur_methods[HZ_ET_BLUR_METHOD_COUNT];
extern const hz_et_method_t hz_et_blur_reference;
#define HZ_ET_BLUR_SHUTTER 1.0f

/* --shutter: the shutter of every motion-blur method and reference (in (0, 1]); < 0 restores their own. */
void hz_et_render_set_shutter(float shutter);

hz_status_t hz_et_render_open(const char *file, const hz_et_env_t *env, hz_et_sequence_t *seq, hz_error_t *err);
/* hz_et_render_open, with the shutter in the sequence's settings (so references of different shutters are
 * cached apart). */
hz_status_t hz_et_render_open_blur(const char *file, const hz_et_env_t *env, hz_et_sequence_t *seq, hz_error_t *err);
void hz_et_render_close(void);

#endif
