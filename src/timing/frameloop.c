/* The display-locked frame loop (see hz/frameloop.h). */
#include "hz/frameloop.h"

#include "hz/fmt.h"
#include "hz/governor.h"
#include "hz/marker.h"

#define NO_POS ((uint32_t)0xffffffffu)

typedef struct loop {
    const hz_loop_cfg_t *cfg;
    hz_timebase_t *tb;
    hz_vsource_t *src;
    hz_loop_result_t *res;
    hz_vsync_t *model;
    hz_pace_t *pacer;
    hz_framelog_t log;
    uint32_t *vs_pos;       /* model input index -> edge log position */
    size_t vs_cap;
    uint64_t vs_inputs;
    /* timeline sources */
    int have_peek, ended;
    hz_edge_t peek;
    int64_t offset;
    /* liveness */
    int64_t last_edge_t;    /* loop clock time of the newest input edge (any polarity) */
    uint64_t edges_in;
    int64_t edge_timeout;
    hz_sink_t *sink;
    hz_rgb8_image_t *warmup; /* a blank frame for priming sink-driven sources (NULL: none) */
    int64_t recent[8];  /* the last v-sync-polarity edge times, for messages */
    uint32_t n_recent;
} loop_t;

/* Large state lives in statics, not on the stack (the model alone is ~20 KiB). One loop runs at a time. */
static hz_vsync_t g_model;
static hz_pace_t g_pacer;
static hz_rtm_t g_rtm;
static hz_lockv_t g_lock;
static hz_gov_t g_gov;

static int is_vsync(const loop_t *L, int level)
{
    switch (L->cfg->edge_mode) {
    case HZ_EDGE_ANY: return 1;
    case HZ_EDGE_FALLING: return level == 0;
    default: return level == 1;
    }
}

static void take_events(loop_t *L)
{
    hz_vsync_event_t ev;
    while (hz_vsync_pop(L->model, &ev)) {
        uint32_t pos = ev.index < L->vs_cap ? L->vs_pos[ev.index] : NO_POS;
        if (pos != NO_POS) {
            hz_edge_rec_t *r = &L->res->edges[pos];
            r->cls = ev.kind == HZ_VSYNC_EDGE ? HZ_ECLS_VSYNC : HZ_ECLS_SPURIOUS;
            r->slot = ev.slot;
            r->residual_ns = ev.residual_ns;
            r->missed_before = ev.missed_before;
            r->why = ev.why;
            r->relock = ev.relock;
        }
        hz_framelog_edge(&L->log, L->model, &ev);
        hz_lockv_event(&g_lock, &ev);
    }
}

static void take_edge(loop_t *L, const hz_edge_t *e)
{
    hz_loop_result_t *R = L->res;
    uint32_t pos = NO_POS;
    if (R->n_edges < L->cfg->max_edges) {
        pos = (uint32_t)R->n_edges++;
        hz_edge_rec_t *r = &R->edges[pos];
        hz_memset(r, 0, sizeof *r);
        r->t_ns = e->t_ns;
        r->level = (uint8_t)e->level;
        r->frame_id = e->frame_id;
        r->cls = HZ_ECLS_OTHER;
    } else {
        R->edges_unlogged++;
    }
    L->edges_in++;
    L->last_edge_t = e->t_ns;
    if (!is_vsync(L, e->level))
        return;
    if (pos != NO_POS)
        R->edges[pos].cls = HZ_ECLS_PENDING;
    if (L->vs_inputs < L->vs_cap)
        L->vs_pos[L->vs_inputs] = pos;
    L->vs_inputs++;
    L->recent[L->n_recent++ % 8] = e->t_ns;
    hz_vsync_push(L->model, e->t_ns);
    take_events(L);
}

/* The next edge no later than deadline (loop clock). Timeline edges are mapped onto the loop clock, which
 * sleeps (real) or jumps (virtual) to them. */
static hz_status_t get_edge(loop_t *L, int64_t deadline, hz_edge_t *e, int *result, hz_error_t *err)
{
    if (L->src->live)
        return L->src->next(L->src, deadline, e, result, err);
    if (!L->have_peek && !L->ended) {
        int r;
        hz_status_t s = L->src->next(L->src, deadline, &L->peek, &r, err);
        if (s != HZ_OK)
            return s;
        if (r == HZ_VS_EDGE) {
            L->peek.t_ns += L->offset;
            L->have_peek = 1;
        } else {
            L->ended = 1;
        }
    }
    if (L->have_peek && L->peek.t_ns <= deadline) {
        hz_tb_sleep_until(L->tb, L->peek.t_ns);
        *e = L->peek;
        L->have_peek = 0;
        *result = HZ_VS_EDGE;
        return HZ_OK;
    }
    if (L->ended && !L->have_peek) {
        *result = HZ_VS_END;
        return HZ_OK;
    }
    hz_tb_sleep_until(L->tb, deadline);
    *result = HZ_VS_TIMEOUT;
    return HZ_OK;
}

static hz_status_t silence_error(loop_t *L, int64_t now, hz_error_t *err)
{
    const hz_vsync_counts_t *c = hz_vsync_counts(L->model);
    if (L->edges_in == 0)
        return hz_error_set(err, HZ_E_TIMEOUT,
                            "%s: no v-sync edge within %lld ms: the display never signalled v-sync (check the "
                            "wiring, the edge polarity and that the display is on)",
                            L->src->name, (long long)(L->edge_timeout / 1000000));
    return hz_error_set(err, HZ_E_TIMEOUT,
                        "%s: no v-sync edge for %lld ms (after %llu edges, %llu accepted; the last %lld ms ago)",
                        L->src->name, (long long)(L->edge_timeout / 1000000), (unsigned long long)L->edges_in,
                        (unsigned long long)c->accepted, (long long)((now - L->last_edge_t) / 1000000));
}

/* The port asked the run to end (cfg->stop). */
static int stopped(const loop_t *L)
{
    return L->cfg->stop && *L->cfg->stop;
}

/* Takes in edges until `until` (loop clock), or until the port asks the run to end. *ended: the timeline ran out. */
static hz_status_t wait_until(loop_t *L, int64_t until, int *ended, hz_error_t *err)
{
    *ended = 0;
    for (;;) {
        if (stopped(L))
            return HZ_OK;
        int64_t now = hz_tb_now(L->tb);
        int64_t silent_at = L->last_edge_t + L->edge_timeout;
        if (now >= silent_at && L->src->live)
            return silence_error(L, now, err);
        if (now >= until)
            return HZ_OK;
        int64_t deadline = until < silent_at || !L->src->live ? until : silent_at;
        hz_edge_t e;
        int r;
        hz_status_t s = get_edge(L, deadline, &e, &r, err);
        if (s != HZ_OK)
            return s;
        if (r == HZ_VS_EDGE)
            take_edge(L, &e);
        else if (r == HZ_VS_END) {
            *ended = 1;
            return HZ_OK;
        }
    }
}

/* Edges already due, without waiting. */
static hz_status_t drain(loop_t *L, int *ended, hz_error_t *err)
{
    *ended = 0;
    for (;;) {
        hz_edge_t e;
        int r;
        hz_status_t s = get_edge(L, hz_tb_now(L->tb), &e, &r, err);
        if (s != HZ_OK)
            return s;
        if (r == HZ_VS_TIMEOUT)
            return HZ_OK;
        if (r == HZ_VS_END) {
            *ended = 1;
            return HZ_OK;
        }
        take_edge(L, &e);
    }
}

/* A sink-driven source (V4L2 output) ticks only with frames queued: feed it blank frames, which the device
 * takes at its own pace (present waits for a free buffer), until the model locks. */
static hz_status_t prime(loop_t *L, hz_error_t *err)
{
    hz_rgb8_image_t *img = L->warmup;
    if (!img || !L->src->needs_frames)
        return HZ_OK;
    hz_status_t s = L->sink->present(L->sink, img, UINT64_MAX, err);
    if (s != HZ_OK) {
        hz_error_prefix(err, L->sink->name);
        return s;
    }
    return HZ_OK;
}

static hz_status_t wait_for_lock(loop_t *L, int *ended, hz_error_t *err)
{
    int64_t p = L->cfg->nominal_period_ns > 0 ? L->cfg->nominal_period_ns : 16666667;
    int64_t wait = L->cfg->lock_timeout_ns > 0 ? L->cfg->lock_timeout_ns : L->edge_timeout + (HZ_VSYNC_ACQ + 4) * p;
    int64_t limit = hz_tb_now(L->tb) + wait;
    *ended = 0;
    while (!hz_vsync_locked(L->model)) {
        int64_t now = hz_tb_now(L->tb);
        if (now >= limit) {
            const hz_vsync_counts_t *c = hz_vsync_counts(L->model);
            if (L->edges_in == 0)
                return silence_error(L, now, err);
            char gaps[96] = "";
            uint32_t k = L->n_recent < 8 ? L->n_recent : 8;
            for (uint32_t i = 1; i < k; i++) {
                int64_t d = L->recent[(L->n_recent - k + i) % 8] - L->recent[(L->n_recent - k + i - 1) % 8];
                size_t used = 0;
                while (gaps[used])
                    used++;
                /* ms with two decimals, in integers (no floating point in src/timing) */
                int64_t c = (d < 0 ? -d : d) / 10000;
                hz_fmt(gaps + used, sizeof gaps - used, "%s%s%lld.%02lld", i > 1 ? " " : "", d < 0 ? "-" : "",
                       (long long)(c / 100), (long long)(c % 100));
            }
            return hz_error_set(err, HZ_E_TIMEOUT,
                                "%s: no v-sync lock within %lld ms: %llu edges seen, no majority on a steady grid "
                                "(%llu rejected; expected period %lld us; last intervals %s ms)",
                                L->src->name, (long long)(wait / 1000000),
                                (unsigned long long)L->edges_in, (unsigned long long)c->spurious,
                                (long long)(p / 1000), gaps);
        }
        hz_edge_t e;
        int r;
        hz_status_t s = prime(L, err);
        if (s != HZ_OK)
            return s;
        s = get_edge(L, L->warmup && L->src->needs_frames ? now : limit, &e, &r, err);
        if (s != HZ_OK)
            return s;
        if (r == HZ_VS_EDGE)
            take_edge(L, &e);
        else if (r == HZ_VS_END) {
            *ended = 1;
            return HZ_OK;
        }
    }
    return HZ_OK;
}

size_t hz_loop_bytes(const hz_loop_cfg_t *cfg)
{
    size_t n = 0;
    size_t scratch = cfg->max_frames > cfg->max_edges ? cfg->max_frames : cfg->max_edges;
    n += cfg->max_frames * sizeof(hz_frame_rec_t) + 64;
    n += cfg->max_edges * sizeof(hz_edge_rec_t) + 64;
    n += cfg->max_edges * sizeof(uint32_t) + 64;
    n += scratch * sizeof(int64_t) + 64;
    if (cfg->frames_mode)
        n += (size_t)cfg->w * (size_t)cfg->h * 3 + 64;
    return n;
}

static void finish(loop_t *L, const char *why)
{
    hz_loop_result_t *R = L->res;
    hz_vsync_flush(L->model);
    take_events(L);
    R->n_frames = L->log.n;
    R->counts = *hz_vsync_counts(L->model);
    R->period_ns = hz_vsync_period_ns(L->model);
    R->period_q16 = hz_vsync_period_q16(L->model);
    R->offset_ppb = hz_vsync_offset_ppb(L->model);
    R->sigma_ns = hz_vsync_sigma_ns(L->model);
    R->tol_ns = hz_vsync_tolerance_ns(L->model);
    R->locked = hz_vsync_locked(L->model);
    hz_lockv_result(&g_lock, &R->lock);
    R->trace_offset_ns = L->offset;
    R->kernel_dropped = L->src->dropped;
    R->t_end = hz_tb_now(L->tb);
    hz_fmt(R->stop_reason, sizeof R->stop_reason, "%s", why);
}

hz_status_t hz_loop_run(const hz_loop_cfg_t *cfg, hz_timebase_t *tb, hz_vsource_t *src, hz_sink_t *sink,
                        const hz_framesrc_t *frames, hz_arena_t *arena, hz_loop_result_t *res, hz_error_t *err)
{
    hz_memset(res, 0, sizeof *res);
    if (src->live && tb->virtual_time)
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s is a live device: it cannot run on a simulated clock",
                            src->name);
    if (cfg->frames_mode && tb->virtual_time && !cfg->rtm)
        return hz_error_set(err, HZ_E_INVALID_ARG, "a simulated clock needs a render-time model");
    if (cfg->frames_mode && (!sink || !frames || cfg->w < 1 || cfg->h < 1))
        return hz_error_set(err, HZ_E_INVALID_ARG, "frame loop: no sink, frame source or frame size");
    if (cfg->max_edges == 0 || (cfg->frames_mode && cfg->max_frames == 0))
        return hz_error_set(err, HZ_E_INVALID_ARG, "frame loop: no room for records");
    size_t need = hz_loop_bytes(cfg), have = hz_arena_available(arena, 64);
    if (need > have)
        return hz_error_set(err, HZ_E_NO_MEMORY,
                            "this run needs %zu bytes of records and buffers (%zu frames, %zu edges%s), arena '%s' "
                            "has %zu: shorten the run or use a board with a larger frame arena",
                            need, cfg->max_frames, cfg->max_edges, cfg->frames_mode ? ", one RGB24 image" : "",
                            arena->name, have);
    loop_t L;
    hz_memset(&L, 0, sizeof L);
    L.cfg = cfg;
    L.tb = tb;
    L.src = src;
    L.res = res;
    L.model = &g_model;
    L.pacer = &g_pacer;
    L.sink = sink;
    size_t scratch_n = cfg->max_frames > cfg->max_edges ? cfg->max_frames : cfg->max_edges;
    hz_frame_rec_t *recs = cfg->max_frames
                               ? hz_arena_alloc_array(arena, cfg->max_frames, sizeof(hz_frame_rec_t), 64)
                               : NULL;
    res->edges = hz_arena_alloc_array(arena, cfg->max_edges, sizeof(hz_edge_rec_t), 64);
    L.vs_pos = hz_arena_alloc_array(arena, cfg->max_edges, sizeof(uint32_t), 64);
    L.vs_cap = cfg->max_edges;
    res->scratch = hz_arena_alloc_array(arena, scratch_n, sizeof(int64_t), 64);
    hz_rgb8_image_t img = { 0, cfg->w, cfg->h, (size_t)cfg->w * 3 };
    if (cfg->frames_mode)
        img.rgb = hz_arena_alloc_array(arena, (size_t)cfg->w * (size_t)cfg->h, 3, 64);
    if (!res->edges || !L.vs_pos || !res->scratch || (cfg->max_frames && !recs) || (cfg->frames_mode && !img.rgb))
        return hz_arena_error(arena, err);
    res->frames = recs;

    hz_vsync_cfg_t vc = { 0 };
    vc.nominal_period_ns = cfg->nominal_period_ns;
    vc.window = cfg->vsync_window;
    vc.tol_min_ns = cfg->tol_min_ns;
    hz_status_t s = hz_vsync_init(L.model, &vc, err);
    hz_lockv_cfg_t lc = cfg->lock;
    lc.nominal_period_ns = cfg->nominal_period_ns;
    hz_lockv_init(&g_lock, &lc);
    if (s == HZ_OK && cfg->frames_mode) {
        /* with a governor keeping frames within the period, one slow frame misses rather than raising the
         * latency of the next thousand (hz/pace.h) */
        hz_pace_cfg_t pc = cfg->pace;
        pc.cap = pc.cap || (cfg->governor && frames && frames->levels && frames->levels->levels > 1);
        s = hz_pace_init(L.pacer, &pc, err);
    }
    if (s == HZ_OK && cfg->frames_mode)
        s = hz_framelog_init(&L.log, recs, cfg->max_frames, cfg->pace.latch_ns, err);
    if (s != HZ_OK)
        return s;
    hz_marker_layout_t marker;
    if (cfg->frames_mode && cfg->marker) {
        s = hz_marker_layout(cfg->w, cfg->h, &marker, err);
        if (s != HZ_OK)
            return s;
        res->marker_cell = marker.cell;
    }
    int64_t p_nom = cfg->nominal_period_ns > 0 ? cfg->nominal_period_ns : 16666667;
    L.edge_timeout = cfg->edge_timeout_ns > 0 ? cfg->edge_timeout_ns
                                              : (10 * p_nom > 500000000 ? 10 * p_nom : 500000000);
    res->nominal_period_ns = cfg->nominal_period_ns;
    int64_t t0 = hz_tb_now(tb);
    res->t_origin = t0;
    L.last_edge_t = t0;

    /* A timeline starts one nominal period from now on the loop's clock. */
    if (!src->live) {
        int r;
        s = src->next(src, 0, &L.peek, &r, err);
        if (s != HZ_OK)
            return s;
        if (r != HZ_VS_EDGE)
            return hz_error_set(err, HZ_E_FORMAT, "%s: no edges", src->name);
        L.offset = t0 + p_nom - L.peek.t_ns;
        L.peek.t_ns += L.offset;
        L.have_peek = 1;
    }

    int ended = 0;
    if (!cfg->frames_mode) {
        /* Capture/replay: every edge until the end of the trace, the duration, or silence. */
        int64_t stop = cfg->duration_ns > 0 ? t0 + cfg->duration_ns : INT64_MAX;
        s = wait_until(&L, stop, &ended, err);
        if (s != HZ_OK)
            return s;
        finish(&L, stopped(&L) ? "interrupted" : ended ? "end of trace" : "duration reached");
        return HZ_OK;
    }

    hz_rgb8_image_t warmup = img;
    if (src->needs_frames) {
        hz_memset(img.rgb, 0, (size_t)cfg->w * (size_t)cfg->h * 3);
        L.warmup = &warmup;
    }
    s = wait_for_lock(&L, &ended, err);
    if (s != HZ_OK)
        return s;
    if (ended)
        return hz_error_set(err, HZ_E_FORMAT, "%s: the trace ended before the v-sync model locked", src->name);
    L.warmup = NULL;

    const int governed = cfg->governor && frames->levels && frames->levels->levels > 1;
    res->levels = frames->levels ? frames->levels->levels : 1u;
    if (governed && (s = hz_gov_init(&g_gov, frames->levels, err)) != HZ_OK)
        return s;
    /* what a frame may cost: the lookahead's periods minus the latch lead and the pacer's guard */
    const uint32_t ahead = cfg->pace.lookahead ? cfg->pace.lookahead : 1u;
    if (governed && !tb->virtual_time) {
        /* Before the first frame, each level rendered once (cheapest first, not shown) for the governor to
         * measure: the first frame is then one predicted to fit, not a guess that misses. The requests are the
         * first frame's, so the source's clock starts where it will. */
        hz_pace_plan_t plan;
        hz_pace_plan(L.pacer, L.model, hz_tb_now(tb), INT64_MIN, &plan);
        for (uint32_t l = frames->levels->levels; l-- > 0;) {
            hz_frame_req_t req = { 0, plan.edge_ns, plan.period_ns, plan.slot, l };
            int64_t t0 = hz_tb_now(tb);
            if ((s = frames->render(frames->ctx, &req, &img, err)) != HZ_OK) {
                hz_error_prefix(err, "calibrating the quality levels");
                return s;
            }
            hz_gov_observe(&g_gov, l, hz_tb_now(tb) - t0);
            res->calibration_ns += hz_tb_now(tb) - t0;
        }
        int64_t guard = cfg->pace.guard_ns >= 0 ? cfg->pace.guard_ns : plan.period_ns / 16;
        hz_gov_start(&g_gov, hz_tb_now(tb), (int64_t)ahead * plan.period_ns - cfg->pace.latch_ns - guard);
    }
    int64_t last_target = INT64_MIN;
    uint32_t last_level = 0;
    const char *why = "frame count reached";
    for (uint64_t n = 0;; n++) {
        int64_t now = hz_tb_now(tb);
        if (cfg->frames && n >= cfg->frames)
            break;
        if (stopped(&L)) {
            why = "interrupted";
            break;
        }
        if (cfg->duration_ns && now - t0 >= cfg->duration_ns) {
            why = "duration reached";
            break;
        }
        if (n >= cfg->max_frames) {
            why = "record log full";
            break;
        }
        s = drain(&L, &ended, err);
        if (s != HZ_OK)
            return s;
        if (ended) {
            why = "end of the display trace";
            break;
        }
        if (!hz_vsync_locked(L.model)) {
            s = wait_for_lock(&L, &ended, err); /* re-acquiring after a phase jump */
            if (s != HZ_OK)
                return s;
            if (ended) {
                why = "end of the display trace";
                break;
            }
        }
        now = hz_tb_now(tb);
        if (L.src->live && now - L.last_edge_t >= L.edge_timeout)
            return silence_error(&L, now, err);
        hz_pace_plan_t plan;
        hz_pace_plan(L.pacer, L.model, now, last_target == INT64_MIN ? INT64_MIN : last_target + 1, &plan);
        s = wait_until(&L, plan.start_ns, &ended, err);
        if (s != HZ_OK)
            return s;
        if (ended) {
            why = "end of the display trace";
            break;
        }
        if (stopped(&L)) {
            why = "interrupted";
            break;
        }
        int64_t render_ns = 0, wake_ns = 0;
        if (cfg->rtm) {
            if (n == 0) {
                s = hz_rtm_init(&g_rtm, cfg->rtm, err);
                if (s != HZ_OK)
                    return s;
            }
            hz_rtm_next(&g_rtm, n, &render_ns, &wake_ns);
            hz_tb_sleep_until(tb, plan.start_ns + wake_ns);
        }
        uint32_t level = 0;
        if (governed) {
            int64_t guard = cfg->pace.guard_ns >= 0 ? cfg->pace.guard_ns : plan.period_ns / 16;
            level = hz_gov_pick(&g_gov, hz_tb_now(tb), (int64_t)ahead * plan.period_ns - cfg->pace.latch_ns - guard);
        }
        int64_t start = hz_tb_now(tb);
        hz_frame_req_t req = { n, plan.edge_ns, plan.period_ns, plan.slot, level };
        s = frames->render(frames->ctx, &req, &img, err);
        if (s != HZ_OK) {
            char prefix[48];
            hz_fmt(prefix, sizeof prefix, "frame %llu (%s)", (unsigned long long)n, frames->name);
            hz_error_prefix(err, prefix);
            return s;
        }
        if (cfg->marker)
            hz_marker_draw(img.rgb, img.stride, &marker, (uint32_t)n);
        if (cfg->rtm)
            hz_tb_advance(tb, render_ns);
        int64_t done = hz_tb_now(tb);
        /* Hold a frame that is ready before the edge ahead of its target has passed: presenting it now
         * would show it a refresh early and drop its predecessor. */
        int64_t hold = hz_vsync_slot_time(L.model, plan.slot - 1) + hz_vsync_tolerance_ns(L.model);
        if (done < hold) {
            s = wait_until(&L, hold, &ended, err);
            if (s != HZ_OK)
                return s;
        }
        s = sink->present(sink, &img, n, err);
        if (s != HZ_OK) {
            hz_error_prefix(err, sink->name);
            return s;
        }
        int64_t submit = hz_tb_now(tb);
        hz_frame_rec_t *r = hz_framelog_add(&L.log);
        r->id = n;
        r->planned_ns = plan.start_ns;
        r->start_ns = start;
        r->done_ns = done;
        r->submit_ns = submit;
        r->target_slot = plan.slot;
        r->target_edge_ns = plan.edge_ns;
        r->budget_ns = plan.budget_ns;
        r->period_ns = plan.period_ns;
        r->level = level;
        if (governed && n > 0 && level != last_level)
            hz_pace_forget(L.pacer); /* the costs so far were another level's */
        last_level = level;
        hz_pace_observe(L.pacer, done - plan.start_ns);
        if (governed)
            hz_gov_observe(&g_gov, level, done - plan.start_ns);
        last_target = plan.slot;
        if (ended)
            break;
    }
    /* The last frames are shown at edges still to come: wait for them, bounded. */
    int64_t settle = hz_tb_now(tb) + 4 * (hz_vsync_period_ns(L.model) + cfg->pace.latch_ns) + 2 * L.edge_timeout / 10;
    while (!ended && hz_framelog_unresolved(&L.log) && hz_tb_now(tb) < settle) {
        hz_edge_t e;
        int r;
        s = get_edge(&L, settle, &e, &r, err);
        if (s != HZ_OK)
            return s;
        if (r == HZ_VS_EDGE)
            take_edge(&L, &e);
        else if (r == HZ_VS_END)
            ended = 1;
        else
            break;
    }
    if (governed) {
        res->level_changes = g_gov.changes;
        res->level_forced = g_gov.forced;
    }
    finish(&L, why);
    return HZ_OK;
}
