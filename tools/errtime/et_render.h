/*
 * et_render.h — errtime's renderer scenes: the built-in scene and the baked Sponza and Conference (from
 * $HZ_SCENES_DIR, default build/scenes), each with the temporally dense method and its baselines, all on the
 * same camera path, size and threads:
 *   tdense     hz=240  one sample per 2x2 tile per displayed frame (HZ_MODE_TDENSE, seed 001)
 *   full-1spp  hz=60   1 spp at pixel centres, rendered every 4th displayed frame and held (hold 4)
 *   full-1spp  hz=240  1 spp every displayed frame
 *   taa        hz=60   1 jittered spp + TAA resolve, every 4th frame, held
 *   taa        hz=240  the same every displayed frame
 * The reference is the full-frame renderer at 64 stratified spp. "hz" is the rate a method renders at when the
 * sequence's refresh is 240 Hz (the display rate: --refresh 240).
 *
 * Contract: hz_et_render_open loads the scene into the board pools, builds the native accel and starts the
 * thread pool (all cores), once per process; a method's renderer takes its images from errtime's arena and its
 * ray queues from the board's thread arenas (released when the method ends). Frame i is scene time
 * start + i / refresh.
 */
#ifndef HZ_ERRTIME_RENDER_H
#define HZ_ERRTIME_RENDER_H

#include "errtime.h"

#define HZ_ET_RENDER_METHOD_COUNT 5
extern const hz_et_method_t hz_et_render_methods[HZ_ET_RENDER_METHOD_COUNT];
extern const hz_et_method_t hz_et_render_reference;

/* file: a .hzb name under $HZ_SCENES_DIR, or NULL for the built-in scene. */
hz_status_t hz_et_render_open(hz_et_sequence_t *seq, const char *file, float start, hz_error_t *err);

#endif
