/* Frame records: scan-out resolution and the summary (see hz/frames.h). */
#include "hz/frames.h"

#include "wide.h"

hz_status_t hz_framelog_init(hz_framelog_t *log, hz_frame_rec_t *rec, size_t cap, int64_t latch_ns,
                             hz_error_t *err)
{
    if (!rec || cap == 0)
        return hz_error_set(err, HZ_E_INVALID_ARG, "frame log: no room for records");
    if (latch_ns < 0)
        return hz_error_set(err, HZ_E_INVALID_ARG, "frame log: negative latch lead");
    hz_framelog_t zero = { 0 };
    *log = zero;
    log->rec = rec;
    log->cap = cap;
    log->latch_ns = latch_ns;
    return HZ_OK;
}

hz_frame_rec_t *hz_framelog_add(hz_framelog_t *log)
{
    if (log->n == log->cap)
        return 0;
    hz_frame_rec_t *r = &log->rec[log->n++];
    hz_frame_rec_t zero = { 0 };
    *r = zero;
    return r;
}

static void advance(hz_framelog_t *log)
{
    while (log->next_unresolved < log->n && (log->rec[log->next_unresolved].flags & HZ_FRAME_RESOLVED))
        log->next_unresolved++;
}

void hz_framelog_edge(hz_framelog_t *log, const hz_vsync_t *v, const hz_vsync_event_t *ev)
{
    if (ev->kind != HZ_VSYNC_EDGE)
        return;
    int64_t first_slot = ev->slot - (int64_t)ev->missed_before;
    if (!log->have_edge)
        first_slot = ev->slot; /* nothing is known before the first edge */
    for (size_t i = log->next_unresolved; i < log->n; i++) {
        hz_frame_rec_t *r = &log->rec[i];
        if (r->flags & HZ_FRAME_RESOLVED)
            continue;
        int64_t ready = r->submit_ns + log->latch_ns;
        if (ready > ev->t_ns)
            break; /* records are in submit order: the rest wait for later edges */
        int64_t slot = ev->slot, t = ev->t_ns;
        uint32_t inferred = 0;
        for (int64_t s = first_slot; s < ev->slot; s++) {
            int64_t ts = hz_vsync_slot_time(v, s);
            if (ts >= ready && (!log->have_edge || s > log->last_slot)) {
                slot = s;
                t = ts;
                inferred = HZ_FRAME_EDGE_INFERRED;
                break;
            }
        }
        r->actual_slot = slot;
        r->actual_edge_ns = t;
        r->flags |= HZ_FRAME_RESOLVED | inferred;
    }
    log->have_edge = 1;
    log->last_slot = ev->slot;
    log->last_t = ev->t_ns;
    advance(log);
}

size_t hz_framelog_unresolved(const hz_framelog_t *log)
{
    size_t u = 0;
    for (size_t i = log->next_unresolved; i < log->n; i++)
        u += !(log->rec[i].flags & HZ_FRAME_RESOLVED);
    return u;
}

void hz_frames_summarise(hz_frame_rec_t *rec, size_t n, int64_t *scratch, hz_frames_summary_t *s)
{
    hz_frames_summary_t zero = { 0 };
    *s = zero;
    s->frames = n;
    /* Flags first: late/early, then dropped (a later frame on the same or an earlier slot). */
    int64_t next_shown = INT64_MAX;
    for (size_t i = n; i-- > 0;) {
        hz_frame_rec_t *r = &rec[i];
        r->flags &= ~(uint32_t)(HZ_FRAME_LATE | HZ_FRAME_DROPPED | HZ_FRAME_EARLY);
        if (!(r->flags & HZ_FRAME_RESOLVED))
            continue;
        if (r->actual_slot > r->target_slot)
            r->flags |= HZ_FRAME_LATE;
        else if (r->actual_slot < r->target_slot)
            r->flags |= HZ_FRAME_EARLY;
        if (r->actual_slot >= next_shown)
            r->flags |= HZ_FRAME_DROPPED;
        else
            next_shown = r->actual_slot;
    }
    int64_t prev_shown = 0;
    int have_prev = 0;
    for (size_t i = 0; i < n; i++) {
        const hz_frame_rec_t *r = &rec[i];
        if (!(r->flags & HZ_FRAME_RESOLVED)) {
            s->unresolved++;
            continue;
        }
        s->resolved++;
        s->inferred += !!(r->flags & HZ_FRAME_EDGE_INFERRED);
        if (r->flags & HZ_FRAME_LATE) {
            int64_t by = r->actual_slot - r->target_slot;
            s->late++;
            s->late_by[by >= 4 ? 3 : by - 1]++;
        } else if (r->flags & HZ_FRAME_EARLY) {
            s->early++;
        } else {
            s->on_time++;
        }
        if (r->flags & HZ_FRAME_DROPPED) {
            s->dropped++;
            continue;
        }
        if (have_prev && r->actual_slot > prev_shown + 1)
            s->repeated += (uint64_t)(r->actual_slot - prev_shown - 1);
        prev_shown = r->actual_slot;
        have_prev = 1;
    }
    s->miss_ppm = s->resolved ? (s->late * 1000000u + s->resolved / 2) / s->resolved : 0;
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (rec[i].flags & HZ_FRAME_RESOLVED)
            scratch[m++] = rec[i].actual_edge_ns - rec[i].start_ns;
    hz_dist_compute(scratch, m, &s->latency);
    m = 0;
    for (size_t i = 0; i < n; i++)
        if (rec[i].flags & HZ_FRAME_RESOLVED)
            scratch[m++] = rec[i].target_edge_ns - rec[i].done_ns;
    hz_dist_compute(scratch, m, &s->slack);
    m = 0;
    for (size_t i = 0; i < n; i++)
        if ((rec[i].flags & HZ_FRAME_RESOLVED) && !(rec[i].flags & HZ_FRAME_EDGE_INFERRED))
            scratch[m++] = rec[i].actual_edge_ns -
                           (rec[i].target_edge_ns + (rec[i].actual_slot - rec[i].target_slot) * rec[i].period_ns);
    hz_dist_compute(scratch, m, &s->phase);
    for (size_t i = 0; i < n; i++)
        scratch[i] = rec[i].done_ns - rec[i].start_ns;
    hz_dist_compute(scratch, n, &s->render);
    for (size_t i = 0; i < n; i++)
        scratch[i] = rec[i].done_ns - rec[i].planned_ns;
    hz_dist_compute(scratch, n, &s->cost);
}
