/*
 * hz/frames.h — per-frame records, scan-out resolution and the latency summary.
 *
 * Contract (integer-only, freestanding; the caller owns the record array):
 *  - A record holds a frame's plan (target slot and its predicted edge, budget, period), what happened
 *    (planned start, start, render done, submit) and, once known, the edge it was scanned out at.
 *  - Scan-out rule: a frame submitted at time s is shown from the first display edge at or after s + latch.
 *    hz_framelog_edge() applies it when the v-sync model accepts an edge: every waiting record whose
 *    s + latch is at or before that edge is resolved, against the accepted edge itself or, when the model
 *    counted missed pulses in between, against the predicted time of the missed slot (flag EDGE_INFERRED:
 *    the display still refreshed, only the capture lost the pulse). The rule holds for displays that latch a
 *    new frame at the refresh after it was handed over: fbdev panning at v-blank, V4L2 outputs (vivid keeps
 *    the newest buffer on screen and returns the previous one at the refresh that replaced it).
 *  - Summary: latency = scan-out edge - render start; slack = target edge - render done (negative: the
 *    deadline was missed); late-by-n = actual slot - target slot; phase error = actual edge - the edge the
 *    plan predicted for that slot; dropped = superseded before any edge showed it (two frames on one slot:
 *    all but the last); repeated = refreshes between two shown frames that showed the older one again.
 *    Distributions cover the resolved frames (latency, slack, phase) or all frames (render time, cost); the
 *    counts say how many were unresolved, so nothing is left out silently.
 */
#ifndef HZ_FRAMES_H
#define HZ_FRAMES_H

#include <stddef.h>
#include <stdint.h>

#include "hz/status.h"
#include "hz/tstat.h"
#include "hz/vsync.h"

enum {
    HZ_FRAME_RESOLVED = 1u << 0,
    HZ_FRAME_EDGE_INFERRED = 1u << 1, /* shown at a slot whose pulse the capture missed */
    HZ_FRAME_LATE = 1u << 2,          /* actual slot after the target slot */
    HZ_FRAME_DROPPED = 1u << 3,       /* never shown: the next frame took its slot */
    HZ_FRAME_EARLY = 1u << 4          /* shown before its target slot */
};

typedef struct hz_frame_rec {
    uint64_t id;
    int64_t planned_ns, start_ns, done_ns, submit_ns;
    int64_t target_slot, target_edge_ns, budget_ns, period_ns;
    int64_t actual_slot, actual_edge_ns;
    uint32_t flags;
    uint32_t level;   /* the quality level it was rendered at (hz/governor.h; 0: the best) */
} hz_frame_rec_t;

typedef struct hz_framelog {
    hz_frame_rec_t *rec;
    size_t cap, n;
    size_t next_unresolved;
    int64_t latch_ns;
    int have_edge;
    int64_t last_slot, last_t;
} hz_framelog_t;

hz_status_t hz_framelog_init(hz_framelog_t *log, hz_frame_rec_t *rec, size_t cap, int64_t latch_ns,
                             hz_error_t *err);
/* A zeroed record appended to the log, or NULL when the log is full. Add a frame's record when it is
 * submitted (with submit_ns set): resolution walks the records in submit order. */
hz_frame_rec_t *hz_framelog_add(hz_framelog_t *log);
/* Feed every event of the v-sync model (spurious ones are ignored). */
void hz_framelog_edge(hz_framelog_t *log, const hz_vsync_t *v, const hz_vsync_event_t *ev);
size_t hz_framelog_unresolved(const hz_framelog_t *log);

typedef struct hz_frames_summary {
    uint64_t frames, resolved, unresolved, inferred;
    uint64_t on_time, early, late, late_by[4]; /* late_by[i]: late by i + 1 slots; [3]: 4 or more */
    uint64_t dropped, repeated;
    uint64_t miss_ppm;                          /* late per million resolved frames */
    hz_dist_t latency, slack, render, cost, phase;
} hz_frames_summary_t;

/* Summarises rec[0..n) (in frame order), setting the DROPPED and LATE flags on the records. scratch must
 * hold n values. */
void hz_frames_summarise(hz_frame_rec_t *rec, size_t n, int64_t *scratch, hz_frames_summary_t *s);

#endif /* HZ_FRAMES_H */
