/*
 * et_synthetic.h — errtime's built-in analytic scene, so the whole pipeline (reference cache, timing, scoring,
 * reports) runs and is tested without the renderer: a rotating checkerboard behind a disc that sweeps across
 * the frame, defined exactly at every point (x, y) and time t = frame / refresh_hz.
 *
 * Methods (the same estimators a renderer uses, applied to the analytic image):
 *  - "supersample", knob "spp": per pixel and frame, spp samples of the image over the pixel's area
 *    (stratified on a sqrt(spp) grid when spp is a square, jittered per frame by an integer hash), box-filtered.
 *    Rays per frame = width * height * spp. The reference is supersample at 256 spp with different jitter.
 *  - "accumulate", knob "alpha": one jittered sample per pixel and frame blended into an exponential history
 *    (out = alpha * new + (1 - alpha) * previous out): less noise, ghosting behind motion. Rays = width * height.
 *  - "tdense", knob "hz": temporally dense rendering (hz/tdense.h, seed 001) at the display rate: one sample
 *    per 2x2 tile and frame, with the scene's exact motion vectors (disc step; board rotation).
 *    Rays = width * height / 4.
 *  - "supersample@60Hz" (spp 1) and "accumulate@60Hz" (alpha 0.1): the same methods rendered every 4th frame
 *    and held (hold = 4; at a 240 Hz display that is 60 Hz).
 * Everything is deterministic (hz_hash3 of pixel, frame and sample), so runs are reproducible.
 */
#ifndef HZ_ERRTIME_SYNTHETIC_H
#define HZ_ERRTIME_SYNTHETIC_H

#include <stddef.h>

#include "errtime.h"

extern const hz_et_method_t hz_synth_reference;
#define HZ_SYNTH_METHOD_COUNT 10
extern const hz_et_method_t hz_synth_methods[HZ_SYNTH_METHOD_COUNT];

/* Exact linear RGB of the scene at (x, y) pixels (y down) and time t seconds, for a width x height frame. */
void hz_synth_shade(float x, float y, float t, uint32_t width, uint32_t height, float rgb[3]);

#endif
