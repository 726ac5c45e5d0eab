/* The latency report: summary text, CSV, JSON, SVG (see report.h). */
#include "latency_report.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "fileio.h"

/* Static: the histogram is 8 KiB and reports are made one at a time. */
const char *hz_report_dur(char *buf, size_t cap, int64_t ns)
{
    int64_t a = ns < 0 ? -ns : ns;
    if (a >= 1000000000)
        snprintf(buf, cap, "%.3f s", ns / 1e9);
    else if (a >= 1000000)
        snprintf(buf, cap, "%.3f ms", ns / 1e6);
    else if (a >= 1000)
        snprintf(buf, cap, "%.1f us", ns / 1e3);
    else
        snprintf(buf, cap, "%lld ns", (long long)ns);
    return buf;
}

static const char *why_name(int why)
{
    switch (why) {
    case HZ_VSYNC_WHY_OFFGRID: return "off-grid";
    case HZ_VSYNC_WHY_DUPLICATE: return "duplicate";
    case HZ_VSYNC_WHY_BACKWARDS: return "out-of-order";
    case HZ_VSYNC_WHY_NOLOCK: return "before-lock";
    default: return "";
    }
}

static const char *cls_name(int cls)
{
    switch (cls) {
    case HZ_ECLS_VSYNC: return "vsync";
    case HZ_ECLS_SPURIOUS: return "spurious";
    case HZ_ECLS_PENDING: return "pending";
    default: return "other-edge";
    }
}

bool hz_report_too_short(const hz_lockv_result_t *L)
{
    /* no other reason, and fewer edges in the whole run than one locked stretch takes */
    return L->verdict == HZ_LOCK_NO_RUN && L->inputs < (uint64_t)L->cfg.min_run;
}

const char *hz_report_lock_verdict(const hz_lockv_result_t *L)
{
    return L->verdict == HZ_LOCK_OK ? "locked" : hz_report_too_short(L) ? "too short to judge a lock" : "no lock";
}

const char *hz_report_lock_reasons(char *buf, size_t cap, const hz_lockv_result_t *L)
{
    size_t n = 0;
    buf[0] = '\0';
    if (hz_report_too_short(L)) {
        snprintf(buf, cap, "%llu v-sync edge%s in the whole run, a locked stretch needs %u in a row (run longer, or "
                 "lower --lock-min-run)", (unsigned long long)L->inputs, L->inputs == 1 ? "" : "s", L->cfg.min_run);
        return buf;
    }
    if (L->verdict & HZ_LOCK_NO_RUN)
        n += (size_t)snprintf(buf + n, n < cap ? cap - n : 0, "%sno locked stretch of %u accepted edges (longest %llu)",
                              n ? "; " : "", L->cfg.min_run, (unsigned long long)L->longest);
    if ((L->verdict & HZ_LOCK_RELOCKS) && n < cap)
        n += (size_t)snprintf(buf + n, cap - n, "%s%llu relocks in %llu accepted edges (limit %.2f%%)", n ? "; " : "",
                              (unsigned long long)L->relocks, (unsigned long long)L->accepted,
                              L->cfg.max_relock_ppm / 1e4);
    if ((L->verdict & HZ_LOCK_SPURIOUS) && n < cap)
        n += (size_t)snprintf(buf + n, cap - n, "%s%llu of %llu edges spurious (limit %.2f%%)", n ? "; " : "",
                              (unsigned long long)L->spurious, (unsigned long long)L->inputs,
                              L->cfg.max_spurious_ppm / 1e4);
    if ((L->verdict & HZ_LOCK_MISSED) && n < cap)
        snprintf(buf + n, cap - n, "%s%llu missed pulses against %llu accepted edges (limit %.2f%% of the slots)",
                 n ? "; " : "", (unsigned long long)L->missed, (unsigned long long)L->accepted,
                 L->cfg.max_missed_ppm / 1e4);
    return buf;
}

void hz_report_compute(hz_report_t *r, const hz_loop_cfg_t *cfg, const hz_report_info_t *info, hz_loop_result_t *res)
{
    memset(r, 0, sizeof *r);
    r->cfg = cfg;
    r->info = *info;
    r->res = res;
    int64_t *sc = res->scratch;
    size_t m = 0;
    /* v-sync residuals (accepted edges), signed and absolute */
    for (size_t i = 0; i < res->n_edges; i++)
        if (res->edges[i].cls == HZ_ECLS_VSYNC)
            sc[m++] = res->edges[i].residual_ns;
    hz_dist_compute(sc, m, &r->residual);
    m = 0;
    for (size_t i = 0; i < res->n_edges; i++)
        if (res->edges[i].cls == HZ_ECLS_VSYNC)
            sc[m++] = llabs(res->edges[i].residual_ns);
    hz_dist_compute(sc, m, &r->abs_residual);
    /* intervals between consecutive accepted edges, per refresh (gaps divided by the slots they span) */
    m = 0;
    const hz_edge_rec_t *prev = NULL;
    for (size_t i = 0; i < res->n_edges; i++) {
        const hz_edge_rec_t *e = &res->edges[i];
        if (e->cls != HZ_ECLS_VSYNC)
            continue;
        if (prev && e->slot > prev->slot && !e->relock)
            sc[m++] = (e->t_ns - prev->t_ns) / (e->slot - prev->slot);
        prev = e;
    }
    hz_dist_compute(sc, m, &r->interval);
    /* pulse width: a v-sync edge to the next edge of the other polarity */
    m = 0;
    if (cfg->edge_mode != HZ_EDGE_ANY)
        for (size_t i = 0; i + 1 < res->n_edges; i++)
            if (res->edges[i].cls == HZ_ECLS_VSYNC && res->edges[i + 1].cls == HZ_ECLS_OTHER)
                sc[m++] = res->edges[i + 1].t_ns - res->edges[i].t_ns;
    r->pulses = m;
    hz_dist_compute(sc, m, &r->pulse);
    int64_t p = res->period_ns > 0 ? res->period_ns : (cfg->nominal_period_ns > 0 ? cfg->nominal_period_ns : 16666667);
    if (cfg->frames_mode) {
        hz_frames_summarise(res->frames, res->n_frames, sc, &r->frames);
        /* bin P/32 from 0, as many periods as the slowest frame needs (up to 32) */
        int64_t bin = p / 32 > 0 ? p / 32 : 1;
        int64_t periods = r->frames.latency.max / p + 1;
        if (periods > HZ_HIST_BINS_MAX / 32)
            periods = HZ_HIST_BINS_MAX / 32;
        hz_hist_init(&r->hist, 0, bin, (uint32_t)(periods * 32), NULL);
        for (size_t i = 0; i < res->n_frames; i++)
            if (res->frames[i].flags & HZ_FRAME_RESOLVED)
                hz_hist_add(&r->hist, res->frames[i].actual_edge_ns - res->frames[i].start_ns);
        r->hist_is_latency = 1;
        /* levels: each shown frame holds the display until the next shown frame's edge (the last: one refresh) */
        const hz_frame_rec_t *shown = NULL;
        for (size_t i = 0; i < res->n_frames; i++) {
            const hz_frame_rec_t *x = &res->frames[i];
            uint32_t l = x->level < HZ_GOV_MAX_LEVELS ? x->level : HZ_GOV_MAX_LEVELS - 1;
            r->level_frames[l]++;
            if (!(x->flags & HZ_FRAME_RESOLVED) || (x->flags & HZ_FRAME_DROPPED))
                continue;
            if (shown && x->actual_slot > shown->actual_slot) {
                uint64_t k = (uint64_t)(x->actual_slot - shown->actual_slot);
                r->level_refreshes[shown->level < HZ_GOV_MAX_LEVELS ? shown->level : HZ_GOV_MAX_LEVELS - 1] += k;
                r->refreshes += k;
            }
            shown = x;
        }
        if (shown) {
            r->level_refreshes[shown->level < HZ_GOV_MAX_LEVELS ? shown->level : HZ_GOV_MAX_LEVELS - 1]++;
            r->refreshes++;
        }
    } else {
        /* residuals: 64 bins across +-max |residual| (at least +-1 us) */
        int64_t span = r->abs_residual.max > 1000 ? r->abs_residual.max : 1000;
        int64_t bin = (2 * span + 63) / 64;
        hz_hist_init(&r->hist, -32 * bin, bin, 65, NULL);
        for (size_t i = 0; i < res->n_edges; i++)
            if (res->edges[i].cls == HZ_ECLS_VSYNC)
                hz_hist_add(&r->hist, res->edges[i].residual_ns);
    }
}

static void dist_row(FILE *f, const char *label, const hz_dist_t *d, const char *note)
{
    char a[6][24], mean[24], sd[24];
    fprintf(f, "  %-44s %7llu", label, (unsigned long long)d->n);
    if (d->n == 0) {
        fprintf(f, "  (none)\n");
        return;
    }
    fprintf(f, " %10s %10s %10s %10s %10s %10s   %s +- %s%s%s\n", hz_report_dur(a[0], 24, d->min),
            hz_report_dur(a[1], 24, d->p50), hz_report_dur(a[2], 24, d->p90), hz_report_dur(a[3], 24, d->p99),
            hz_report_dur(a[4], 24, d->p999), hz_report_dur(a[5], 24, d->max), hz_report_dur(mean, 24, d->mean),
            hz_report_dur(sd, 24, d->sd), note ? "  " : "", note ? note : "");
}

static void print_hist(FILE *f, const hz_report_t *r)
{
    const hz_hist_t *h = &r->hist;
    uint32_t lo = h->nbins, hi = 0;
    uint64_t peak = 0;
    for (uint32_t i = 0; i < h->nbins; i++)
        if (h->count[i]) {
            if (lo == h->nbins)
                lo = i;
            hi = i;
            if (h->count[i] > peak)
                peak = h->count[i];
        }
    char b1[24], b2[24], bw[24];
    fprintf(f, "histogram of %s, bin %s%s: %llu values, %llu below, %llu above the range\n",
            r->hist_is_latency ? "latency" : "v-sync residuals", hz_report_dur(bw, 24, h->bin_ns),
            r->hist_is_latency ? " (P/32)" : "", (unsigned long long)h->n, (unsigned long long)h->below,
            (unsigned long long)h->above);
    if (lo == h->nbins)
        return;
    uint32_t rows = hi - lo + 1, step = (rows + 39) / 40;
    for (uint32_t i = lo; i <= hi; i += step) {
        uint64_t c = 0;
        for (uint32_t k = i; k < i + step && k <= hi; k++)
            c += h->count[k];
        int64_t a = h->lo_ns + (int64_t)i * h->bin_ns, b = a + (int64_t)step * h->bin_ns;
        int bar = peak ? (int)((c * 50 + peak * step - 1) / (peak * step)) : 0;
        if (c && bar == 0)
            bar = 1;
        fprintf(f, "  %10s .. %10s %8llu %.*s\n", hz_report_dur(b1, 24, a), hz_report_dur(b2, 24, b),
                (unsigned long long)c, bar, "##################################################");
    }
}

void hz_report_print(FILE *f, hz_report_t *r)
{
    const hz_loop_result_t *res = r->res;
    const hz_loop_cfg_t *cfg = r->cfg;
    const hz_vsync_counts_t *c = &res->counts;
    char a[24], b[24], d[24], e[24];
    fprintf(f, "source    %s\n", r->info.source);
    if (cfg->frames_mode) {
        fprintf(f, "frames    %s, %dx%d%s, sink %s\n", r->info.frames, r->info.w, r->info.h,
                r->info.marker ? ", frame-id marker" : "", r->info.sink);
    }
    fprintf(f, "clock     %s; stopped: %s\n", r->info.clock, res->stop_reason);
    fprintf(f, "v-sync    %llu edges classified: %llu accepted, %llu spurious (%llu off-grid, %llu duplicate, "
               "%llu out of order, %llu before lock); %llu missed pulses; %llu relocks",
            (unsigned long long)(c->accepted + c->spurious), (unsigned long long)c->accepted,
            (unsigned long long)c->spurious, (unsigned long long)c->offgrid, (unsigned long long)c->duplicate,
            (unsigned long long)c->backwards, (unsigned long long)c->nolock, (unsigned long long)c->missed,
            (unsigned long long)c->relocks);
    if (res->kernel_dropped)
        fprintf(f, "; %llu lost by the kernel", (unsigned long long)res->kernel_dropped);
    if (res->edges_unlogged)
        fprintf(f, "; %llu beyond the edge log (used, not in edges.csv)", (unsigned long long)res->edges_unlogged);
    fprintf(f, "\n");
    const hz_lockv_result_t *L = &res->lock;
    if (L->verdict == HZ_LOCK_OK) {
        double hz = 1e9 * 65536.0 / (double)L->period_q16;
        fprintf(f, "          lock: %llu of %llu accepted edges in %llu locked stretch%s of >= %u edges; period over "
                   "them %.3f us = %.4f Hz",
                (unsigned long long)L->qualifying_edges, (unsigned long long)L->accepted,
                (unsigned long long)L->qualifying, L->qualifying == 1 ? "" : "es", L->cfg.min_run,
                L->period_q16 / 65536.0 / 1e3, hz);
        if (res->nominal_period_ns > 0 && !L->far)
            fprintf(f, " (%+.2f ppm against the nominal %s)", L->offset_ppb / 1000.0,
                    hz_report_dur(a, 24, res->nominal_period_ns));
        fprintf(f, "; acceptance +-%s\n", hz_report_dur(b, 24, res->tol_ns));
        fprintf(f, "          residual jitter of accepted edges (time - prediction): SD %s, p99 |r| %s, max |r| %s\n",
                hz_report_dur(a, 24, r->residual.sd), hz_report_dur(b, 24, r->abs_residual.p99),
                hz_report_dur(d, 24, r->abs_residual.max));
        if (L->far)
            fprintf(f, "warning   the measured rate %.4f Hz is %+.1f%% off the nominal %.4f Hz (--hz): the display "
                       "runs another mode, or --hz is wrong (--hz 0 learns the rate)\n",
                    hz, (1.0 / (1.0 + L->offset_ppb / 1e9) - 1.0) * 100.0, 1e9 / (double)res->nominal_period_ns);
    } else {
        char why[256];
        fprintf(f, "          %s: %s; no rate reported\n", hz_report_lock_verdict(L),
                hz_report_lock_reasons(why, sizeof why, L));
    }
    if (r->pulses)
        fprintf(f,
                "          pulse width (v-sync edge to the opposite edge): p50 %s, min %s, max %s over %llu pulses\n",
                hz_report_dur(a, 24, r->pulse.p50), hz_report_dur(b, 24, r->pulse.min),
                hz_report_dur(d, 24, r->pulse.max), (unsigned long long)r->pulses);
    if (cfg->frames_mode) {
        const hz_frames_summary_t *s = &r->frames;
        int64_t guard = cfg->pace.guard_ns < 0 ? res->period_ns / 16 : cfg->pace.guard_ns;
        fprintf(f, "pacing    start = target edge - latch %s - budget; budget = p%u.%u of the last %u frame costs + "
                   "guard %s%s; lookahead %u\n",
                hz_report_dur(a, 24, cfg->pace.latch_ns), (cfg->pace.percentile ? cfg->pace.percentile : 1000) / 10,
                (cfg->pace.percentile ? cfg->pace.percentile : 1000) % 10,
                cfg->pace.window ? cfg->pace.window : HZ_PACE_WINDOW_MAX, hz_report_dur(b, 24, guard),
                cfg->pace.cap || (r->info.levels && r->info.levels->governor) ? ", at most lookahead periods - latch"
                                                                               : "",
                cfg->pace.lookahead ? cfg->pace.lookahead : 1);
        fprintf(f, "frames    %llu rendered; %llu shown: %llu on time, %llu late (by 1: %llu, 2: %llu, 3: %llu, "
                   "4+: %llu), %llu early; %llu dropped; %llu repeated refreshes; %llu unresolved; %llu resolved "
                   "against an inferred (missed) edge\n",
                (unsigned long long)s->frames, (unsigned long long)s->resolved, (unsigned long long)s->on_time,
                (unsigned long long)s->late, (unsigned long long)s->late_by[0], (unsigned long long)s->late_by[1],
                (unsigned long long)s->late_by[2], (unsigned long long)s->late_by[3], (unsigned long long)s->early,
                (unsigned long long)s->dropped, (unsigned long long)s->repeated, (unsigned long long)s->unresolved,
                (unsigned long long)s->inferred);
        fprintf(f, "          deadline miss rate %.3f%% (%llu of %llu shown frames)\n", s->miss_ppm / 1e4,
                (unsigned long long)s->late, (unsigned long long)s->resolved);
        /* The two figures a display-locked renderer is judged by, in periods: a frame every refresh needs the
         * render time under one period, and a latency of at most two means it was shown at the next edge. */
        int64_t period = res->period_ns > 0 ? res->period_ns : res->nominal_period_ns;
        if (s->latency.n && period > 0 && s->resolved)
            fprintf(f, "          p99 latency %s = %.2f periods; %.2f refreshes per shown frame (1.00: a new frame "
                       "every refresh)\n",
                    hz_report_dur(a, 24, s->latency.p99), (double)s->latency.p99 / (double)period,
                    (double)(s->resolved + s->repeated) / (double)s->resolved);
        fprintf(f, "per-frame distributions, nearest-rank percentiles over the frames counted (n):\n");
        fprintf(f, "  %-44s %7s %10s %10s %10s %10s %10s %10s   %s\n", "", "n", "min", "p50", "p90", "p99", "p99.9",
                "max", "mean +- SD");
        dist_row(f, "latency = scan-out edge - render start", &s->latency, "(shown frames)");
        dist_row(f, "slack = target edge - render done", &s->slack, "(shown frames; < 0 missed)");
        dist_row(f, "render time = done - start", &s->render, "(all frames)");
        dist_row(f, "frame cost = done - planned start", &s->cost, "(all frames)");
        dist_row(f, "phase error = scan-out edge - prediction", &s->phase, "(shown, edge observed)");
        const hz_report_levels_t *lv = r->info.levels;
        if (lv && lv->count > 1) {
            fprintf(f, "quality   governor %s, %llu level changes (%llu forced by a deadline at risk); share of time at "
                       "each level%s:\n",
                    lv->governor ? "on" : "off", (unsigned long long)res->level_changes,
                    (unsigned long long)res->level_forced,
                    lv->error_frames ? " and its error against level 0 (PSNR, mean FLIP of the frames as shown)" : "");
            for (uint32_t l = 0; l < lv->count; l++) {
                if (!r->level_frames[l] && l > 0)
                    continue;
                fprintf(f, "  L%-2u %-46s %6.2f%% of the time, %llu frames", l, lv->name[l],
                        r->refreshes ? 100.0 * (double)r->level_refreshes[l] / (double)r->refreshes : 0.0,
                        (unsigned long long)r->level_frames[l]);
                if (lv->measured[l] && l > 0)
                    fprintf(f, "; %.2f dB, FLIP %.4f", lv->psnr_db[l], lv->flip[l]);
                fprintf(f, "\n");
            }
        }
    } else {
        fprintf(f, "per-edge distributions, nearest-rank percentiles (n):\n");
        fprintf(f, "  %-44s %7s %10s %10s %10s %10s %10s %10s   %s\n", "", "n", "min", "p50", "p90", "p99", "p99.9",
                "max", "mean +- SD");
        dist_row(f, "interval between accepted edges, per refresh", &r->interval, NULL);
        dist_row(f, "residual = edge - prediction", &r->residual, NULL);
    }
    print_hist(f, r);
    (void)e;
}

/* ---- files ---- */

static hz_status_t write_frames_csv(const char *path, const hz_report_t *r, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    FILE *f = out.f;
    fprintf(f, "id,planned_ns,start_ns,done_ns,submit_ns,target_slot,target_edge_ns,actual_slot,actual_edge_ns,"
               "latency_ns,slack_ns,render_ns,late_by,budget_ns,status,level\n");
    const hz_loop_result_t *res = r->res;
    for (size_t i = 0; i < res->n_frames; i++) {
        const hz_frame_rec_t *x = &res->frames[i];
        int shown = !!(x->flags & HZ_FRAME_RESOLVED);
        const char *status = !shown                              ? "unresolved"
                             : (x->flags & HZ_FRAME_DROPPED)     ? "dropped"
                             : (x->flags & HZ_FRAME_LATE)        ? "late"
                             : (x->flags & HZ_FRAME_EARLY)       ? "early"
                                                                 : "on-time";
        fprintf(f, "%llu,%lld,%lld,%lld,%lld,%lld,%lld,", (unsigned long long)x->id, (long long)x->planned_ns,
                (long long)x->start_ns, (long long)x->done_ns, (long long)x->submit_ns, (long long)x->target_slot,
                (long long)x->target_edge_ns);
        if (shown)
            fprintf(f, "%lld,%lld,%lld,", (long long)x->actual_slot, (long long)x->actual_edge_ns,
                    (long long)(x->actual_edge_ns - x->start_ns));
        else
            fprintf(f, ",,,");
        fprintf(f, "%lld,%lld,", (long long)(x->target_edge_ns - x->done_ns), (long long)(x->done_ns - x->start_ns));
        if (shown)
            fprintf(f, "%lld", (long long)(x->actual_slot - x->target_slot));
        fprintf(f, ",%lld,%s%s,%u\n", (long long)x->budget_ns, status,
                (x->flags & HZ_FRAME_EDGE_INFERRED) ? "+inferred-edge" : "", x->level);
    }
    return hz_out_commit(&out, err);
}

static hz_status_t write_edges_csv(const char *path, const hz_report_t *r, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    FILE *f = out.f;
    const hz_loop_result_t *res = r->res;
    fprintf(f, "# hzrt edges: one row per input edge, in order; readable by hzrt latency --source csv:FILE\n");
    fprintf(f, "# t_ns: the source's own time (a trace's timestamps as recorded); loop_ns: the same edge on the frame "
               "loop's clock (frames.csv), t_ns + %lld\n",
            (long long)res->trace_offset_ns);
    fprintf(f, "t_ns,level,class,slot,residual_ns,missed_before,reason,frame_id,loop_ns\n");
    for (size_t i = 0; i < res->n_edges; i++) {
        const hz_edge_rec_t *e = &res->edges[i];
        fprintf(f, "%lld,%d,%s,", (long long)(e->t_ns - res->trace_offset_ns), e->level, cls_name(e->cls));
        if (e->cls == HZ_ECLS_VSYNC || e->cls == HZ_ECLS_SPURIOUS)
            fprintf(f, "%lld,%lld,%u,%s%s,", (long long)e->slot, (long long)e->residual_ns, e->missed_before,
                    why_name(e->why), e->relock ? "relock" : "");
        else
            fprintf(f, ",,,,");
        if (e->frame_id >= 0)
            fprintf(f, "%lld", (long long)e->frame_id);
        fprintf(f, ",%lld\n", (long long)e->t_ns);
    }
    return hz_out_commit(&out, err);
}

static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; s && *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

static void json_dist(FILE *f, const char *name, const hz_dist_t *d, int last)
{
    fprintf(f, "    \"%s\": {\"n\": %llu, \"min_ns\": %lld, \"p50_ns\": %lld, \"p90_ns\": %lld, \"p99_ns\": %lld, "
               "\"p99_9_ns\": %lld, \"max_ns\": %lld, \"mean_ns\": %lld, \"sd_ns\": %lld}%s\n",
            name, (unsigned long long)d->n, (long long)d->min, (long long)d->p50, (long long)d->p90, (long long)d->p99,
            (long long)d->p999, (long long)d->max, (long long)d->mean, (long long)d->sd, last ? "" : ",");
}

static hz_status_t write_json(const char *path, const hz_report_t *r, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    FILE *f = out.f;
    const hz_loop_result_t *res = r->res;
    const hz_vsync_counts_t *c = &res->counts;
    const hz_lockv_result_t *lk = &res->lock;
    fprintf(f, "{\n  \"source\": ");
    json_str(f, r->info.source);
    fprintf(f, ",\n  \"clock\": ");
    json_str(f, r->info.clock);
    fprintf(f, ",\n  \"stopped\": ");
    json_str(f, res->stop_reason);
    fprintf(f, ",\n  \"percentiles\": \"nearest rank over the frames (or edges) counted in n\",\n");
    fprintf(f, "  \"vsync\": {\"accepted\": %llu, \"spurious\": %llu, \"offgrid\": %llu, \"duplicate\": %llu, "
               "\"out_of_order\": %llu, \"before_lock\": %llu, \"missed\": %llu, \"relocks\": %llu, "
               "\"kernel_dropped\": %llu, \"edges_unlogged\": %llu, \"period_ns\": %.3f, \"nominal_period_ns\": %lld, "
               "\"offset_ppm\": %.3f, \"tolerance_ns\": %lld, \"locked\": %s},\n",
            (unsigned long long)c->accepted, (unsigned long long)c->spurious, (unsigned long long)c->offgrid,
            (unsigned long long)c->duplicate, (unsigned long long)c->backwards, (unsigned long long)c->nolock,
            (unsigned long long)c->missed, (unsigned long long)c->relocks, (unsigned long long)res->kernel_dropped,
            (unsigned long long)res->edges_unlogged, lk->verdict ? 0.0 : lk->period_q16 / 65536.0,
            (long long)res->nominal_period_ns, lk->verdict ? 0.0 : lk->offset_ppb / 1000.0, (long long)res->tol_ns,
            lk->verdict ? "false" : "true");
    char why[256];
    fprintf(f, "  \"lock\": {\"verdict\": \"%s\", \"reasons\": ",
            lk->verdict == HZ_LOCK_OK ? "locked" : hz_report_too_short(lk) ? "too short" : "no lock");
    json_str(f, lk->verdict ? hz_report_lock_reasons(why, sizeof why, lk) : "");
    fprintf(f, ", \"stretches\": %llu, \"qualifying_stretches\": %llu, \"qualifying_edges\": %llu, "
               "\"longest_stretch\": %llu, \"min_run\": %u, \"max_relock_pct\": %.4f, \"max_spurious_pct\": %.4f, "
               "\"max_missed_pct\": %.4f, \"far_from_nominal\": %s, \"trace_offset_ns\": %lld},\n",
            (unsigned long long)lk->stretches, (unsigned long long)lk->qualifying,
            (unsigned long long)lk->qualifying_edges, (unsigned long long)lk->longest, lk->cfg.min_run,
            lk->cfg.max_relock_ppm / 1e4, lk->cfg.max_spurious_ppm / 1e4, lk->cfg.max_missed_ppm / 1e4,
            lk->far ? "true" : "false", (long long)res->trace_offset_ns);
    if (r->cfg->frames_mode) {
        const hz_frames_summary_t *x = &r->frames;
        fprintf(f, "  \"frames_source\": ");
        json_str(f, r->info.frames);
        if (r->info.scene_file) {
            fprintf(f, ",\n  \"scene\": {\"file\": ");
            json_str(f, r->info.scene_file);
            fprintf(f, ", \"mode\": ");
            json_str(f, r->info.mode);
            fprintf(f, ", \"render_size\": [%d, %d], \"render_scale\": %d, \"threads\": %d}", r->info.render_w,
                    r->info.render_h, r->info.render_scale, r->info.threads);
        }
        fprintf(f, ",\n  \"sink\": ");
        json_str(f, r->info.sink);
        fprintf(f, ",\n  \"size\": [%d, %d],\n", r->info.w, r->info.h);
        fprintf(f, "  \"frames\": {\"rendered\": %llu, \"shown\": %llu, \"on_time\": %llu, \"late\": %llu, "
                   "\"late_by\": [%llu, %llu, %llu, %llu], \"early\": %llu, \"dropped\": %llu, \"repeated\": %llu, "
                   "\"unresolved\": %llu, \"inferred_edge\": %llu, \"miss_rate_ppm\": %llu},\n",
                (unsigned long long)x->frames, (unsigned long long)x->resolved, (unsigned long long)x->on_time,
                (unsigned long long)x->late, (unsigned long long)x->late_by[0], (unsigned long long)x->late_by[1],
                (unsigned long long)x->late_by[2], (unsigned long long)x->late_by[3], (unsigned long long)x->early,
                (unsigned long long)x->dropped, (unsigned long long)x->repeated, (unsigned long long)x->unresolved,
                (unsigned long long)x->inferred, (unsigned long long)x->miss_ppm);
        fprintf(f, "  \"distributions\": {\n");
        json_dist(f, "latency", &x->latency, 0);
        json_dist(f, "slack", &x->slack, 0);
        json_dist(f, "render", &x->render, 0);
        json_dist(f, "cost", &x->cost, 0);
        json_dist(f, "phase_error", &x->phase, 0);
        json_dist(f, "vsync_residual", &r->residual, 1);
        fprintf(f, "  },\n");
        const hz_report_levels_t *lv = r->info.levels;
        if (lv) {
            fprintf(f, "  \"quality\": {\"governor\": %s, \"changes\": %llu, \"forced\": %llu, \"error_frames\": %u, "
                       "\"error_of\": \"frames as shown, against level 0 after error_frames frames (PSNR dB, mean FLIP)\", "
                       "\"levels\": [",
                    lv->governor ? "true" : "false", (unsigned long long)res->level_changes,
                    (unsigned long long)res->level_forced, lv->error_frames);
            for (uint32_t l = 0; l < lv->count; l++) {
                fprintf(f, "%s\n    {\"level\": %u, \"name\": ", l ? "," : "", l);
                json_str(f, lv->name[l]);
                fprintf(f, ", \"frames\": %llu, \"time_share\": %.6f", (unsigned long long)r->level_frames[l],
                        r->refreshes ? (double)r->level_refreshes[l] / (double)r->refreshes : 0.0);
                if (lv->measured[l] && l > 0)
                    fprintf(f, ", \"psnr_db\": %.4f, \"flip\": %.6f", lv->psnr_db[l], lv->flip[l]);
                fprintf(f, "}");
            }
            fprintf(f, "\n  ]},\n");
        }
    } else {
        fprintf(f, "  \"distributions\": {\n");
        json_dist(f, "interval", &r->interval, 0);
        json_dist(f, "vsync_residual", &r->residual, 0);
        json_dist(f, "pulse_width", &r->pulse, 1);
        fprintf(f, "  },\n");
    }
    const hz_hist_t *h = &r->hist;
    fprintf(f, "  \"histogram\": {\"of\": \"%s\", \"lo_ns\": %lld, \"bin_ns\": %lld, \"below\": %llu, \"above\": %llu, "
               "\"counts\": [",
            r->hist_is_latency ? "latency" : "vsync_residual", (long long)h->lo_ns, (long long)h->bin_ns,
            (unsigned long long)h->below, (unsigned long long)h->above);
    for (uint32_t i = 0; i < h->nbins; i++)
        fprintf(f, "%s%llu", i ? ", " : "", (unsigned long long)h->count[i]);
    fprintf(f, "]}\n}\n");
    return hz_out_commit(&out, err);
}

static hz_status_t write_svg(const char *path, const hz_report_t *r, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    FILE *f = out.f;
    const hz_hist_t *h = &r->hist;
    uint32_t lo = 0, hi = h->nbins ? h->nbins - 1 : 0;
    if (r->hist_is_latency) {
        /* from 0 to the end of the period holding the slowest frame */
        while (hi > 0 && !h->count[hi])
            hi--;
        hi = (hi / 32 + 1) * 32 - 1;
        if (hi >= h->nbins)
            hi = h->nbins - 1;
    }
    uint64_t peak = 1;
    for (uint32_t i = lo; i <= hi; i++)
        if (h->count[i] > peak)
            peak = h->count[i];
    const int W = 900, H = 360, L = 70, R = 45, T = 50, B = 60;
    double pw = (double)(W - L - R) / (hi - lo + 1), ph = H - T - B;
    char a[24], b[24];
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" font-family=\"sans-serif\" "
               "font-size=\"12\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n", W, H);
    fprintf(f, "<text x=\"%d\" y=\"20\" font-size=\"14\">%s, n = %llu, bin %s%s</text>\n", L,
            r->hist_is_latency ? "Latency per frame (scan-out edge - render start)"
                               : "V-sync residuals (edge - prediction)",
            (unsigned long long)h->n, hz_report_dur(a, 24, h->bin_ns), r->hist_is_latency ? " = P/32" : "");
    fprintf(f, "<text x=\"%d\" y=\"38\" fill=\"#555\">%llu below and %llu above the plotted range (not drawn)"
               "</text>\n",
            L, (unsigned long long)h->below, (unsigned long long)h->above);
    for (uint32_t i = lo; i <= hi; i++) {
        if (!h->count[i])
            continue;
        double bh = ph * (double)h->count[i] / (double)peak;
        if (bh < 1)
            bh = 1;
        fprintf(f, "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"#3b6ea8\"/>\n", L + (i - lo) * pw,
                T + ph - bh, pw > 1.5 ? pw - 0.5 : pw, bh);
    }
    fprintf(f, "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", L, T + (int)ph, W - R,
            T + (int)ph);
    fprintf(f, "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", L, T, L, T + (int)ph);
    /* x ticks: period boundaries for latency, 8 ticks for residuals */
    uint32_t step = r->hist_is_latency ? 32 : (hi - lo + 1) / 8;
    if (step == 0)
        step = 1;
    for (uint32_t i = lo; i <= hi + 1; i += step) {
        double x = L + (i - lo) * pw;
        fprintf(f, "<line x1=\"%.2f\" y1=\"%d\" x2=\"%.2f\" y2=\"%d\" stroke=\"#999\"/>\n", x, T + (int)ph, x,
                T + (int)ph + 5);
        fprintf(f, "<text x=\"%.2f\" y=\"%d\" text-anchor=\"middle\">%s</text>\n", x, T + (int)ph + 18,
                hz_report_dur(a, 24, h->lo_ns + (int64_t)i * h->bin_ns));
    }
    fprintf(f, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">%s</text>\n", (L + W - R) / 2, H - 15,
            r->hist_is_latency ? "latency (ticks at whole display periods)" : "residual");
    fprintf(f, "<text x=\"15\" y=\"%d\" transform=\"rotate(-90 15 %d)\" text-anchor=\"middle\">"
               "frames per bin (max %llu)</text>\n",
            T + (int)ph / 2, T + (int)ph / 2, (unsigned long long)peak);
    if (r->hist_is_latency) {
        const hz_dist_t *d = &r->frames.latency;
        struct {
            const char *n;
            int64_t v;
            const char *col;
        } marks[] = { { "p50", d->p50, "#2a2" }, { "p99", d->p99, "#d80" }, { "p99.9", d->p999, "#c22" } };
        for (int k = 0; k < 3 && d->n; k++) {
            double x = L + ((double)(marks[k].v - h->lo_ns) / (double)h->bin_ns - lo) * pw;
            if (x < L || x > W - R)
                continue;
            fprintf(f, "<line x1=\"%.2f\" y1=\"%d\" x2=\"%.2f\" y2=\"%d\" stroke=\"%s\" "
                       "stroke-dasharray=\"4 3\"/>\n",
                    x, T, x, T + (int)ph, marks[k].col);
            fprintf(f, "<text x=\"%.2f\" y=\"%d\" fill=\"%s\">%s %s</text>\n", x + 3, T + 12 + 14 * k,
                    marks[k].col, marks[k].n, hz_report_dur(b, 24, marks[k].v));
        }
    }
    fprintf(f, "</svg>\n");
    return hz_out_commit(&out, err);
}

hz_status_t hz_report_write(const char *dir, hz_report_t *r, hz_error_t *err)
{
    hz_status_t s = hz_mkdirs(dir, err);
    if (s != HZ_OK)
        return s;
    char path[4096];
    if (r->cfg->frames_mode) {
        snprintf(path, sizeof path, "%s/frames.csv", dir);
        if ((s = write_frames_csv(path, r, err)) != HZ_OK)
            return s;
    }
    snprintf(path, sizeof path, "%s/edges.csv", dir);
    if ((s = write_edges_csv(path, r, err)) != HZ_OK)
        return s;
    snprintf(path, sizeof path, "%s/report.json", dir);
    if ((s = write_json(path, r, err)) != HZ_OK)
        return s;
    snprintf(path, sizeof path, "%s/histogram.svg", dir);
    return write_svg(path, r, err);
}
