/*
 * errtime.h — error against run time: renders a sequence with every requested method and knob setting, scores
 * each displayed frame against a reference sequence and times it, and fills one report row per setting
 * (et_report.h). Later issues add methods by adding table entries (programs/hzerrtime/et_methods.c); the driver does not
 * change.
 *
 * Contract:
 *  - A sequence is `frames` displayed frames of `width` x `height` at `refresh_hz`; frame i is shown at
 *    t = i / refresh_hz. Frames [0, warmup) are rendered (so temporal methods build their history) but neither
 *    timed nor scored.
 *  - A method is a name (one polyline in the chart), a knob label and value (one point), and callbacks:
 *      begin(method, seq, arena, &state, err)  once per run: allocate everything from `arena` (released after
 *                                              end), reset history. May be NULL (state = NULL).
 *      render(state, i, out, &rays, err)       draw displayed frame i (called for i = 0, 1, ... in order; with
 *                                              hold n only for i = 0, n, 2n, ...) into out (linear RGB, seq
 *                                              size) and report the rays traced. Timed (wall clock,
 *                                              CLOCK_MONOTONIC) around this call only; it should allocate
 *                                              nothing. out is the same image for every frame of a run and the
 *                                              driver only reads it, so it may carry history.
 *      end(state)                              may be NULL.
 *  - The reference method (e.g. full-frame 256 spp) renders every frame once into the cache:
 *      <cache_dir>/<scene>-<16 hex digits>/ref-<i>.pfm plus key.txt, where the hex digits are the FNV-1a 64
 *    hash of the key text (scene name and content hash, camera, settings, size, frames, refresh rate, reference
 *    method and knob; HZ_ET_CACHE_VERSION). A cache entry is built in a temporary directory and renamed into
 *    place complete, so an interrupted run never leaves a partial entry; an entry whose key.txt differs from the
 *    key is refused (HZ_E_CORRUPT) rather than trusted, as is one with a missing or unreadable frame (the
 *    error names the file; delete the entry to rebuild it).
 *  - Scoring, per measured frame i: both the method's frame and reference frame i are quantised to 8-bit sRGB
 *    (hz_image_quantize_srgb8: what the display shows), then MSE (sRGB 8-bit and linear), SSIM and FLIP (ppd)
 *    are taken (et_metrics.h, et_flip.h). Display-integrated error, for every i with all of i-k+1 .. i measured
 *    (k = max(1, round(refresh_hz / 60))): FLIP and sRGB 8-bit MSE of the mean of the last k displayed frames
 *    against the mean of the k reference frames at the same instants (averaged in linear light).
 *    A row reports PSNR from the mean MSE over frames (so one identical frame does not make it infinite), the
 *    mean SSIM and mean FLIP over frames, and the median and p99 (nearest rank) of the render times in ms.
 *    With hold n, every displayed frame is scored (repeats included) and the times are those of the rendered
 *    frames divided by n (cost per displayed frame, comparable with methods that render every frame); rays
 *    per frame are per displayed frame too. Requires frames - warmup >= n.
 *  - Videos (video_dir set): <video_dir>/<scene>-<method>-<knob><value>.y4m and <scene>-reference.y4m, the
 *    quantised frames as displayed (warm-up included), 8-bit 4:4:4, BT.709 full range, at refresh_hz (play or
 *    convert with ffmpeg -colorspace bt709 -i file.y4m ...). Written outside the timed call.
 *  - Requirements: frames >= warmup + k (at least one full display-integration window); the arena must hold
 *    the method's state plus about 2k + 3 frames and the metric scratch (hz_et_arena_bytes gives the driver's
 *    part). Errors name the method and frame.
 */
#ifndef HZ_ERRTIME_ERRTIME_H
#define HZ_ERRTIME_ERRTIME_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "hz/arena.h"
#include "hz/image.h"
#include "hz/status.h"
#include "et_report.h"

#define HZ_ET_CACHE_VERSION 1

typedef struct hz_et_sequence {
    const char *scene;      /* label (report rows, cache directory name) */
    uint64_t scene_hash;    /* hash of the scene's content, e.g. of its .hzb bytes */
    const char *camera;     /* camera path label */
    const char *settings;   /* anything else the reference depends on (renderer version, bounces ...) */
    uint32_t width, height;
    uint32_t frames, warmup, refresh_hz;
    const void *scene_data; /* handed to the methods as it is */
} hz_et_sequence_t;

typedef struct hz_et_method hz_et_method_t;
struct hz_et_method {
    const char *name;  /* e.g. "full-frame" */
    const char *knob;  /* e.g. "spp" */
    double value;      /* e.g. 4 */
    hz_status_t (*begin)(const hz_et_method_t *m, const hz_et_sequence_t *seq, hz_arena_t *arena, void **state,
                         hz_error_t *err);
    hz_status_t (*render)(void *state, uint32_t frame, hz_image_t *out, uint64_t *rays, hz_error_t *err);
    void (*end)(void *state);
    const void *params; /* the method's own parameters (e.g. the spp as an integer) */
    uint32_t hold;      /* 0 or 1: renders every displayed frame; n > 1: renders frames 0, n, 2n, ... (at
                         * refresh_hz / n, e.g. "@60Hz" on a 240 Hz display) and the display repeats each for n
                         * frames, the way a slower renderer's output looks on a fast display */
    uint64_t (*camera_rays)(void *state); /* may be NULL: camera rays of the frame render just drew (the row's
                                           * camera_rays_per_pixel; NaN without it) */
};

typedef struct hz_et_config {
    const char *cache_dir; /* reference cache root (created if missing) */
    float ppd;             /* FLIP observer; HZ_FLIP_DEFAULT_PPD */
    hz_arena_t *arena;     /* methods' state, frames and metric scratch; back where it was after each method */
    FILE *progress;        /* progress bar stream (stderr) or NULL */
    bool progress_tty;     /* draw it (hz_cli_stderr_is_tty()) */
    const char *video_dir; /* if set: every method's displayed frames, and the reference's, as Y4M videos */
} hz_et_config_t;

/* Frames the eye integrates at this refresh rate: max(1, round(refresh / 60)). */
uint32_t hz_et_window(uint32_t refresh_hz);

/* Median and p99 (nearest rank: the ceil(0.99 n)-th smallest) of n > 0 render times in ns, as ms; sorts ns. */
void hz_et_time_stats(int64_t *ns, size_t n, double *median_ms, double *p99_ms);

/* Arena bytes the driver itself needs for a sequence (frames, rings, metric scratch), without method state. */
size_t hz_et_arena_bytes(const hz_et_sequence_t *seq, float ppd);

/* The cache entry's directory for a sequence and reference (no file system access), and its key text. */
hz_status_t hz_et_cache_entry(const hz_et_sequence_t *seq, const hz_et_method_t *reference, const char *cache_dir,
                              char *dir, size_t dir_size, char *key, size_t key_size, hz_error_t *err);

/* Makes sure the reference frames are cached (rendering them if not). *rendered tells whether it rendered. */
hz_status_t hz_et_reference(const hz_et_sequence_t *seq, const hz_et_method_t *reference, const hz_et_config_t *cfg,
                            bool *rendered, hz_error_t *err);

/* Runs methods[0..count) and fills rows[0..count) (Pareto flags included). Calls hz_et_reference first. */
hz_status_t hz_et_run(const hz_et_sequence_t *seq, const hz_et_method_t *reference, const hz_et_method_t *methods,
                      size_t count, const hz_et_config_t *cfg, hz_et_row_t *rows, hz_error_t *err);

#endif
