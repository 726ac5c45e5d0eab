/*
 * render_run.h — one frame of the renderer on the port's static thread pool: begin_frame, every pass's items
 * spread over the pool (hz_threads_run), end_frame. What `hzrt render`, the frame loop's scene source, errtime
 * and the benchmarks all do per frame.
 *
 * Contract: the pool must be started with as many threads as the renderer was created for (or fewer); the
 * result does not depend on the thread count. Allocates nothing. tdense and TAA frames run their trace and
 * resolve passes as one overlapped run (hz_render_overlap_units: a tile row's resolve starts as soon as the
 * rows next to it are traced, on whichever thread is free) unless opts.serial_passes asks for a barrier.
 */
#ifndef HZ_PORT_RENDER_RUN_H
#define HZ_PORT_RENDER_RUN_H

#include "hz/render.h"
#include "phase.h"

/* time: scene time in nanoseconds (hz/scenetime.h); the float variants take seconds (short runs, tests). */
hz_status_t hz_render_run_frame_ns(hz_renderer_t *r, uint64_t index, hz_time_ns_t time, hz_error_t *err);
hz_status_t hz_render_run_frame(hz_renderer_t *r, uint64_t index, float time, hz_error_t *err);

/* Pass `pass` of the current frame (between begin_frame and end_frame), every item spread over the pool: for
 * callers that time the passes one by one (hzbench's adaptive group). */
void hz_render_run_pass(hz_renderer_t *r, uint32_t pass);

/* The same, and where the time went (CLOCK_MONOTONIC, ns): ns[0] begin_frame (animation, refit, camera),
 * ns[1] the first pass (tracing), ns[2] the other passes (resolves) and end_frame. ns may be NULL. In an
 * overlapped frame ns[2] is the resolve units' time summed over the pool's threads and divided by their
 * number (plus end_frame), and ns[1] the rest of the overlapped run. */
hz_status_t hz_render_run_frame_parts(hz_renderer_t *r, uint64_t index, float time, int64_t ns[3],
                                      hz_error_t *err);
hz_status_t hz_render_run_frame_parts_ns(hz_renderer_t *r, uint64_t index, hz_time_ns_t time, int64_t ns[3],
                                         hz_error_t *err);

/* The same, updating prog with the fraction of the frame's work items done (from the calling thread), for a
 * single long frame; prog may be NULL. */
hz_status_t hz_render_run_frame_progress_ns(hz_renderer_t *r, uint64_t index, hz_time_ns_t time,
                                            hz_phase_t *prog, hz_error_t *err);

#endif
