/*
 * hz/frameloop.h — the one frame loop for files and displays: lock onto v-sync, pace, pick a quality level,
 * render, present, record. Portable: the clock, the v-sync source and the sink are the port's (hz/display.h).
 *
 * Contract:
 *  - hz_loop_run() locks the v-sync model on the source (HZ_E_TIMEOUT naming the source if it does not lock
 *    within lock time-out), then per frame: takes in the edges that arrived, plans the frame (hz/pace.h),
 *    waits until its start while taking in edges, renders it through the hz_framesrc_t hook (the only place
 *    pixels come from: the built-in scene through the renderer, or the test pattern), draws the frame-id
 *    marker when asked, holds the frame until the edge before its target has passed, presents it to the sink
 *    and records it. Afterwards it waits (bounded) for the edges that show the last frames and settles the
 *    model. In edges-only mode (frames_mode 0) it only captures and classifies edges.
 *  - Time: a real timebase needs a live source or a timeline (which is then replayed in real time); a virtual
 *    timebase needs a timeline and a render-time model (hz/rtmodel.h): render times are modelled, frames are
 *    still rendered for real. Live sources with a virtual clock are refused.
 *  - A silent source is an error, not a hang: HZ_E_TIMEOUT when no edge at all came for edge_timeout_ns.
 *  - Memory: everything comes from the arena passed in (records, edge log, image), sized by hz_loop_bytes();
 *    a run that does not fit is refused up front with both byte counts. The steady state allocates nothing.
 *  - cfg->stop ends a run early, between frames: what was done is recorded as at a normal end.
 *  - Every input edge is logged (edge log) with its classification, until the log is full; edges beyond it
 *    are still used and counted (edges_unlogged), never dropped silently.
 *  - Every v-sync model event also feeds the lock verdict (hz/lockv.h): res->lock says whether the run held
 *    a lock worth reporting and gives the period measured over its locked stretches.
 *  - A timeline's edges are shifted onto the loop clock (it starts one nominal period after the loop does):
 *    res->trace_offset_ns is that shift, so a report can give the trace's own times back.
 *  - Quality: with cfg->governor and a source that has levels, each frame's level comes from the governor,
 *    which is told every frame's cost (render done - planned start, what the pacer sees); the level is in the
 *    frame's record. In real time, once locked and before the first frame, every level is rendered once (not
 *    shown, cheapest first) so that the governor's first pick is measured, not guessed. Without a governor,
 *    every frame is level 0.
 */
#ifndef HZ_FRAMELOOP_H
#define HZ_FRAMELOOP_H

#include <stddef.h>
#include <stdint.h>

#include "hz/arena.h"
#include "hz/frames.h"
#include "hz/lockv.h"
#include "hz/pace.h"
#include "hz/rtmodel.h"
#include "hz/vsync.h"
#include "hz/display.h"

enum { HZ_EDGE_RISING = 0, HZ_EDGE_FALLING, HZ_EDGE_ANY };
enum { HZ_ECLS_OTHER = 0, HZ_ECLS_VSYNC, HZ_ECLS_SPURIOUS, HZ_ECLS_PENDING };

typedef struct hz_edge_rec {
    int64_t t_ns; /* on the loop's clock (a timeline's own time is t_ns - hz_loop_result_t.trace_offset_ns) */
    int64_t slot;
    int64_t residual_ns;
    int64_t frame_id;
    uint32_t missed_before;
    uint8_t level, cls, why, relock;
} hz_edge_rec_t;

typedef struct hz_loop_cfg {
    int frames_mode;          /* 1: render and present frames; 0: capture and classify edges only */
    uint64_t frames;          /* stop after this many frames (0: by duration) */
    int64_t duration_ns;      /* stop after this long (0: by frames; both 0 in edges-only mode: until the end) */
    int64_t nominal_period_ns;
    uint32_t vsync_window;
    int64_t tol_min_ns;
    hz_pace_cfg_t pace;
    int64_t edge_timeout_ns;  /* longest silence tolerated; 0: max(500 ms, 10 periods) */
    int64_t lock_timeout_ns;  /* longest wait for the v-sync model to lock; 0: edge time-out + 12 periods */
    int edge_mode;            /* HZ_EDGE_RISING, _FALLING or _ANY (photodiode on the flash square) */
    int marker;
    int w, h;
    const hz_rtm_cfg_t *rtm;  /* virtual time: the render-time model */
    size_t max_frames, max_edges;
    hz_lockv_cfg_t lock;      /* the lock verdict's limits (zeros: defaults; nominal period filled in) */
    /* The frame-budget governor (hz/governor.h), for a frame source with quality levels: 1 picks each frame's
     * level so that it fits the budget (lookahead periods minus the latch lead and the pacing guard); 0 keeps
     * level 0. The governor's own settings (dwell, margins) come from the source's levels. */
    int governor;
    /* Non-NULL: a flag the port sets (a signal handler, say) to end the run early. The loop looks at it between
     * frames and while it waits for edges; once it is non-zero no further frame starts, the run settles as at
     * its normal end and stop_reason says "interrupted". */
    const volatile int *stop;
} hz_loop_cfg_t;

typedef struct hz_loop_result {
    hz_frame_rec_t *frames;
    size_t n_frames;
    hz_edge_rec_t *edges;
    size_t n_edges;
    uint64_t edges_unlogged;
    int64_t *scratch; /* max(max_frames, max_edges) values for summaries */
    hz_vsync_counts_t counts;
    int64_t period_ns, period_q16, offset_ppb, sigma_ns, tol_ns, nominal_period_ns;
    int64_t t_origin, t_end;  /* loop clock at start and end */
    uint64_t kernel_dropped;
    int locked;
    hz_lockv_result_t lock;   /* the verdict over the whole run, and the rate its locked stretches measured */
    int64_t trace_offset_ns;  /* loop clock - trace time for a timeline source (0 for live sources) */
    int marker_cell;
    char stop_reason[96];
    uint32_t levels;          /* quality levels the source offered (1: none) */
    int64_t calibration_ns;   /* governor: time spent rendering each level once before the first frame */
    uint64_t level_changes, level_forced; /* governor: changes, and those a deadline at risk forced */
} hz_loop_result_t;

size_t hz_loop_bytes(const hz_loop_cfg_t *cfg);
hz_status_t hz_loop_run(const hz_loop_cfg_t *cfg, hz_timebase_t *tb, hz_vsource_t *src, hz_sink_t *sink,
                        const hz_framesrc_t *frames, hz_arena_t *arena, hz_loop_result_t *res, hz_error_t *err);

#endif
