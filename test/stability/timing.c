/* Stage timing: the v-sync model, pacing, frame statistics and the trace readers on synthetic traces with known
 * ground truth (hz/vsynth.h) and hand-made inputs at the edges: timestamps that cross 2^32 and approach 2^63,
 * lost and extra pulses, +-1000 ppm drift, no edges, equal edges, a clock that steps back, statistics over the
 * whole int64 range. Oracles: the generator's truth, exact 128-bit arithmetic, documented refusals. */
#include <limits.h>
#include <stdlib.h>

#include "hz/frames.h"
#include "hz/pace.h"
#include "hz/traceio.h"
#include "hz/tstat.h"
#include "hz/vsync.h"
#include "hz/vsynth.h"
#include "stab_util.h"

#define HZ240_Q16 (((int64_t)1000000000 * 65536) / 240)

typedef struct run {
    uint64_t inputs, events, accepted, spurious, slot_jumps;
    int64_t last_slot;
    bool have_slot;
} run_t;

/* Counts the model's events (slots of accepted edges must increase). */
static void drain(hz_vsync_t *v, run_t *u)
{
    hz_vsync_event_t ev;
    while (hz_vsync_pop(v, &ev)) {
        u->events++;
        if (ev.kind == HZ_VSYNC_EDGE) {
            u->accepted++;
            if (u->have_slot && ev.slot <= u->last_slot)
                u->slot_jumps++;
            u->last_slot = ev.slot, u->have_slot = true;
        } else
            u->spurious++;
    }
}

/* One input edge, and its events drained. */
static void feed(hz_vsync_t *v, run_t *u, int64_t t)
{
    hz_vsync_push(v, t);
    u->inputs++;
    drain(v, u);
}

static void finish(hz_vsync_t *v, run_t *u)
{
    hz_vsync_flush(v);
    drain(v, u);
}

/* Runs a vsynth trace of `slots` refreshes through a fresh model; returns the counts and the truth. */
static void synth_run(stab_result_t *r, const hz_vsynth_cfg_t *cfg, int64_t nominal_ns, run_t *u, hz_vsync_t *v,
                      hz_vsynth_t *g)
{
    hz_error_t err;
    hz_vsync_cfg_t vc = { nominal_ns, 0, 0 };
    STAB_OK(r, hz_vsync_init(v, &vc, &err), &err);
    STAB_OK(r, hz_vsynth_init(g, cfg, &err), &err);
    memset(u, 0, sizeof *u);
    hz_vsynth_edge_t e;
    while (hz_vsynth_next(g, &e))
        feed(v, u, e.t_ns);
    finish(v, u);
    STAB_CHECK(r, u->events == u->inputs, "%llu inputs gave %llu events", (unsigned long long)u->inputs,
               (unsigned long long)u->events);
    STAB_CHECK(r, u->slot_jumps == 0, "accepted slots did not increase %llu times", (unsigned long long)u->slot_jumps);
}

/* Relative period error against the generator's true period of its last slot, in ppm. */
static double period_ppm(const hz_vsync_t *v, const hz_vsynth_t *g, uint64_t slot)
{
    double truth = (double)hz_vsynth_period_q16(g, slot), est = (double)hz_vsync_period_q16(v);
    return fabs(est - truth) / truth * 1e6;
}

static void clean_trace_from(stab_result_t *r, int64_t t0, uint64_t slots, const char *what)
{
    hz_vsynth_cfg_t c;
    memset(&c, 0, sizeof c);
    c.period_q16 = HZ240_Q16, c.t0_ns = t0, c.jitter_ns = 20000, c.slots = slots, c.seed = 5;
    run_t u;
    static hz_vsync_t v;
    static hz_vsynth_t g;
    synth_run(r, &c, 4166667, &u, &v, &g);
    STAB_BAIL(r);
    double ppm = period_ppm(&v, &g, slots - 1);
    stab_error(r, ppm * 1e-6);
    const hz_vsync_counts_t *k = hz_vsync_counts(&v);
    stab_note(r, "%s: %llu edges; %llu accepted; %llu spurious; period off %.3f ppm", what,
              (unsigned long long)u.inputs, (unsigned long long)u.accepted, (unsigned long long)u.spurious, ppm);
    STAB_CHECK(r, u.accepted == slots && k->missed == 0, "%llu of %llu edges accepted, %llu missed",
               (unsigned long long)u.accepted, (unsigned long long)slots, (unsigned long long)k->missed);
    /* 20 us uniform jitter over a 128-edge window: the least-squares period has a standard deviation of
     * sigma sqrt(12 / n^3) / P = 6.6 ppm; 25 ppm is almost 4 of them */
    STAB_CHECK(r, ppm < 25.0, "period estimate off by %.2f ppm", ppm);
    int64_t next = hz_vsync_slot_time(&v, u.last_slot + 1);
    STAB_CHECK(r, next > hz_vsync_slot_time(&v, u.last_slot), "the next edge is not after the last");
}

/* Timestamps crossing 2^31 and 2^32 ns (a 32-bit counter would wrap there). */
static void c_ts_32bit_wrap(stab_result_t *r)
{
    clean_trace_from(r, ((int64_t)1 << 31) - 200LL * 4166667, 400, "across 2^31 ns");
    STAB_BAIL(r);
    r->note[0] = 0;
    clean_trace_from(r, ((int64_t)1 << 32) - 200LL * 4166667, 400, "across 2^32 ns");
}

/* Timestamps ending 1000 periods below 2^63 - 1: the model's predictions and fit (128-bit) must neither
 * overflow (UBSan in SAN=1) nor lose the lock. */
static void c_ts_64bit_near_max(stab_result_t *r)
{
    clean_trace_from(r, INT64_MAX - 3000LL * 4166667, 2000, "up to 2^63 - 4e9 ns");
    STAB_BAIL(r);
    /* and far ahead: slot numbers beyond the range saturate instead of wrapping */
    static hz_vsync_t v;
    hz_vsync_cfg_t vc = { 4166667, 0, 0 };
    hz_error_t err;
    STAB_OK(r, hz_vsync_init(&v, &vc, &err), &err);
    for (int64_t i = 0; i < 64; i++)
        hz_vsync_push(&v, INT64_MAX - (64 - i) * 4166667LL);
    hz_vsync_flush(&v);
    hz_vsync_event_t ev;
    while (hz_vsync_pop(&v, &ev))
        ;
    STAB_CHECK(r, hz_vsync_locked(&v), "no lock on edges just below 2^63");
    int64_t s = hz_vsync_slot_at_or_after(&v, INT64_MAX);
    int64_t t = hz_vsync_slot_time(&v, s + 1000000);
    stab_note(r, "slot at 2^63-1: %lld; a million slots later: %lld ns", (long long)s, (long long)t);
    STAB_CHECK(r, t >= hz_vsync_slot_time(&v, s), "predictions past 2^63 wrapped around");
    int64_t lo = hz_vsync_slot_at_or_after(&v, INT64_MIN); /* predictions saturate: must not loop */
    STAB_CHECK(r, lo < s, "slot at INT64_MIN %lld not before %lld", (long long)lo, (long long)s);
}

static hz_status_t count_edge(void *ctx, int64_t t_ns, int level, hz_error_t *err)
{
    (void)err, (void)level;
    int64_t *c = ctx;
    c[0]++;
    c[1] = t_ns;
    return HZ_OK;
}

/* A VCD whose time runs past 2^63 ns, and one crossing 2^32 ticks: refused naming the line / read exactly. */
static void c_vcd_time_overflow(stab_result_t *r)
{
    static hz_vcd_t p;
    hz_error_t err;
    int64_t c[2] = { 0, 0 };
    const char *ok = "$timescale 1 us $end\n$var wire 1 ! vsync $end\n$enddefinitions $end\n"
                     "#0\n0!\n#4294967290\n1!\n#4294967300\n0!\n#4294967310\n1!\n";
    STAB_OK(r, hz_vcd_init(&p, "", &err), &err);
    STAB_OK(r, hz_vcd_feed(&p, ok, strlen(ok), count_edge, c, &err), &err);
    STAB_OK(r, hz_vcd_finish(&p, count_edge, c, &err), &err);
    STAB_CHECK(r, c[0] == 3 && c[1] == 4294967310000LL, "edges %lld, last %lld ns", (long long)c[0], (long long)c[1]);
    const char *bad = "$timescale 1 s $end\n$var wire 1 ! vsync $end\n$enddefinitions $end\n"
                      "#0\n0!\n#9223372037\n1!\n";
    STAB_OK(r, hz_vcd_init(&p, "", &err), &err);
    hz_status_t s = hz_vcd_feed(&p, bad, strlen(bad), count_edge, c, &err);
    if (s == HZ_OK)
        s = hz_vcd_finish(&p, count_edge, c, &err);
    STAB_REFUSED(r, s, HZ_E_RANGE, &err, "line 6");
}

/* CSV edges: t_us across 2^32 us read exactly; 2^63 ns refused naming the line. */
static void c_ecsv_time_overflow(stab_result_t *r)
{
    static hz_ecsv_t p;
    hz_error_t err;
    int64_t c[2] = { 0, 0 };
    const char *ok = "t_us\n4294967295.999\n4294967296.001\n9223372036854775.807\n";
    hz_ecsv_init(&p);
    STAB_OK(r, hz_ecsv_feed(&p, ok, strlen(ok), count_edge, c, &err), &err);
    STAB_OK(r, hz_ecsv_finish(&p, count_edge, c, &err), &err);
    STAB_CHECK(r, c[0] == 3 && c[1] == INT64_MAX, "edges %lld, last %lld ns", (long long)c[0], (long long)c[1]);
    const char *bad = "t_ns\n1\n9223372036854775808\n";
    hz_ecsv_init(&p);
    hz_status_t s = hz_ecsv_feed(&p, bad, strlen(bad), count_edge, c, &err);
    if (s == HZ_OK)
        s = hz_ecsv_finish(&p, count_edge, c, &err);
    STAB_REFUSED(r, s, HZ_E_FORMAT, &err, "line 3");
}

/* Lost pulses and extra ones (glitches between edges, bounces just after one): every slot with a real edge
 * gets exactly one accepted edge, no glitch is ever accepted, missed pulses are counted exactly. A bounce
 * 1..20 us after a real edge may win its slot when it lies nearer the prediction (with 30 us jitter the two
 * cannot be told apart): counted as a swap, not an error. */
static void truth_case(stab_result_t *r, uint32_t miss, uint32_t glitch, uint32_t bounce)
{
    hz_vsynth_cfg_t c;
    memset(&c, 0, sizeof c);
    c.period_q16 = HZ240_Q16, c.jitter_ns = 30000, c.slots = 4000, c.seed = 12;
    c.miss_ppm = miss, c.glitch_ppm = glitch, c.bounce_ppm = bounce;
    static hz_vsync_t v;
    static hz_vsynth_t g;
    hz_error_t err;
    hz_vsync_cfg_t vc = { 4166667, 0, 0 };
    STAB_OK(r, hz_vsync_init(&v, &vc, &err), &err);
    STAB_OK(r, hz_vsynth_init(&g, &c, &err), &err);
    size_t cap = 3 * c.slots + 16;
    int64_t *slot_of = calloc(cap, sizeof *slot_of);
    uint8_t *kind = calloc(cap, 1);          /* 0 real, 1 bounce, 2 glitch */
    uint8_t *real_slot = calloc(c.slots + 8, 1), *taken = calloc(c.slots + 8, 1);
    uint64_t inputs = 0, events = 0, glitch_acc = 0, swaps = 0, twice = 0, real_slots = 0, acc_slots = 0;
    int64_t last_real_t = INT64_MIN / 2;
    hz_vsynth_edge_t e;
    hz_vsync_event_t ev;
    for (;;) {
        bool more = hz_vsynth_next(&g, &e);
        if (more) {
            slot_of[inputs] = e.slot;
            kind[inputs] = e.real ? 0 : (e.t_ns - last_real_t <= 20000 ? 1 : 2);
            if (e.real)
                last_real_t = e.t_ns, real_slot[e.slot] = 1;
            hz_vsync_push(&v, e.t_ns);
            inputs++;
        } else
            hz_vsync_flush(&v);
        while (hz_vsync_pop(&v, &ev)) {
            events++;
            if (ev.kind != HZ_VSYNC_EDGE)
                continue;
            uint8_t k = kind[ev.index];
            int64_t sl = slot_of[ev.index];
            glitch_acc += k == 2;
            swaps += k == 1;
            if (sl >= 0 && sl < (int64_t)c.slots)
                twice += taken[sl]++ > 0;
        }
        if (!more)
            break;
    }
    for (uint64_t s = 0; s < c.slots; s++)
        real_slots += real_slot[s], acc_slots += real_slot[s] && taken[s] == 1;
    const hz_vsync_counts_t *k = hz_vsync_counts(&v);
    stab_note(r, "%llu edges (%llu real; %llu lost; %llu glitches; %llu bounces): slots with a real edge %llu; "
                 "accepted once %llu; glitches accepted %llu; bounce swaps %llu; missed counted %llu",
              (unsigned long long)inputs, (unsigned long long)g.real_edges, (unsigned long long)g.lost,
              (unsigned long long)g.glitches, (unsigned long long)g.bounces, (unsigned long long)real_slots,
              (unsigned long long)acc_slots, (unsigned long long)glitch_acc, (unsigned long long)swaps,
              (unsigned long long)k->missed);
    free(slot_of), free(kind), free(real_slot), free(taken);
    STAB_CHECK(r, events == inputs, "%llu inputs gave %llu events", (unsigned long long)inputs,
               (unsigned long long)events);
    STAB_CHECK(r, glitch_acc == 0, "%llu glitches accepted", (unsigned long long)glitch_acc);
    STAB_CHECK(r, twice == 0, "%llu slots accepted twice", (unsigned long long)twice);
    STAB_CHECK(r, acc_slots == real_slots, "%llu of %llu real slots accepted", (unsigned long long)acc_slots,
               (unsigned long long)real_slots);
    STAB_CHECK(r, k->missed == g.lost, "missed %llu, truth %llu", (unsigned long long)k->missed,
               (unsigned long long)g.lost);
    stab_error(r, period_ppm(&v, &g, c.slots - 1) * 1e-6);
}

static void c_missing_pulses(stab_result_t *r) { truth_case(r, 100000, 0, 0); }
static void c_spurious_pulses(stab_result_t *r) { truth_case(r, 0, 50000, 50000); }
static void c_missing_and_spurious(stab_result_t *r) { truth_case(r, 50000, 20000, 20000); }

/* +-1000 ppm drift against a nominal 240 Hz (a display running fast or slow): the fit follows it to 5 ppm
 * and reports the offset. */
static void drift_case(stab_result_t *r, int32_t ppb)
{
    hz_vsynth_cfg_t c;
    memset(&c, 0, sizeof c);
    c.period_q16 = HZ240_Q16, c.jitter_ns = 20000, c.slots = 3000, c.seed = 3;
    c.drift_ppb_start = c.drift_ppb_end = ppb;
    run_t u;
    static hz_vsync_t v;
    static hz_vsynth_t g;
    synth_run(r, &c, 4166667, &u, &v, &g);
    STAB_BAIL(r);
    double ppm = period_ppm(&v, &g, c.slots - 1);
    int64_t off = hz_vsync_offset_ppb(&v);
    stab_error(r, ppm * 1e-6);
    stab_note(r, "drift %d ppb: %llu of %llu accepted; period off %.3f ppm; reported offset %lld ppb", (int)ppb,
              (unsigned long long)u.accepted, (unsigned long long)u.inputs, ppm, (long long)off);
    STAB_CHECK(r, u.accepted == u.inputs, "%llu edges rejected", (unsigned long long)(u.inputs - u.accepted));
    STAB_CHECK(r, ppm < 25.0, "period off by %.2f ppm", ppm); /* see clean_trace_from */
    STAB_CHECK(r, llabs(off - ppb) < 10000, "offset %lld ppb, drift %d ppb", (long long)off, (int)ppb);
}

static void c_drift_plus_1000ppm(stab_result_t *r) { drift_case(r, 1000000); }
static void c_drift_minus_1000ppm(stab_result_t *r) { drift_case(r, -1000000); }

/* No edges at all: nothing locks, every query answers, summaries of nothing are zero. */
static void c_zero_edges(stab_result_t *r)
{
    static hz_vsync_t v;
    hz_vsync_cfg_t vc = { 0, 0, 0 };
    hz_error_t err;
    STAB_OK(r, hz_vsync_init(&v, &vc, &err), &err);
    hz_vsync_flush(&v);
    hz_vsync_event_t ev;
    STAB_CHECK(r, !hz_vsync_pop(&v, &ev), "an event without an edge");
    STAB_CHECK(r, !hz_vsync_locked(&v) && hz_vsync_period_ns(&v) == 0, "locked without edges");
    (void)hz_vsync_slot_time(&v, 5), (void)hz_vsync_slot_at_or_after(&v, 1000), (void)hz_vsync_offset_ppb(&v);
    hz_dist_t d;
    hz_dist_compute(NULL, 0, &d);
    STAB_CHECK(r, d.n == 0 && d.mean == 0 && d.sd == 0 && d.max == 0, "distribution of nothing is not zero");
    hz_frames_summary_t s;
    int64_t scratch[1];
    hz_frames_summarise(NULL, 0, scratch, &s);
    STAB_CHECK(r, s.frames == 0 && s.miss_ppm == 0 && s.latency.n == 0, "summary of no frames is not zero");
    static hz_pace_t p;
    hz_pace_cfg_t pc;
    memset(&pc, 0, sizeof pc);
    STAB_OK(r, hz_pace_init(&p, &pc, &err), &err);
    int64_t b = hz_pace_budget(&p, 4166667);
    STAB_CHECK(r, b > 0 && b <= 4166667, "budget %lld without costs", (long long)b);
    stab_note(r, "no lock; period 0; empty summaries zero; budget without costs %lld ns", (long long)b);
}

/* 100 edges with one timestamp: one event each; all but the first rejected as not after the previous one. */
static void c_all_edges_equal(stab_result_t *r)
{
    static hz_vsync_t v;
    hz_vsync_cfg_t vc = { 4166667, 0, 0 };
    hz_error_t err;
    STAB_OK(r, hz_vsync_init(&v, &vc, &err), &err);
    run_t u;
    memset(&u, 0, sizeof u);
    for (int i = 0; i < 100; i++)
        feed(&v, &u, 123456789);
    finish(&v, &u);
    const hz_vsync_counts_t *k = hz_vsync_counts(&v);
    stab_note(r, "100 equal edges: %llu events; %llu backwards; locked %d", (unsigned long long)u.events,
              (unsigned long long)k->backwards, hz_vsync_locked(&v));
    STAB_CHECK(r, u.events == 100, "%llu events for 100 edges", (unsigned long long)u.events);
    STAB_CHECK(r, k->backwards == 99, "%llu rejected as not after the previous", (unsigned long long)k->backwards);
    STAB_CHECK(r, !hz_vsync_locked(&v), "locked on one timestamp");
    /* the same through statistics: a distribution of equal values */
    int64_t vals[100];
    for (int i = 0; i < 100; i++)
        vals[i] = -7;
    hz_dist_t d;
    hz_dist_compute(vals, 100, &d);
    STAB_CHECK(r, d.min == -7 && d.max == -7 && d.p999 == -7 && d.mean == -7 && d.sd == 0, "equal values' stats");
}

/* The clock steps back 2.5 ms (half a period, off the grid) after 500 edges and runs on: one edge is rejected as
 * backwards, the shifted ones off the grid until the model relocks (once), slots stay increasing, and the
 * period is right afterwards. */
static void c_clock_backwards(stab_result_t *r)
{
    static hz_vsync_t v;
    hz_vsync_cfg_t vc = { 4166667, 0, 0 };
    hz_error_t err;
    STAB_OK(r, hz_vsync_init(&v, &vc, &err), &err);
    run_t u;
    memset(&u, 0, sizeof u);
    int64_t t = 1000000000;
    for (int i = 0; i < 1500; i++) {
        if (i == 500)
            t -= 2500000 + 4166667;
        feed(&v, &u, t);
        t += 4166667;
    }
    finish(&v, &u);
    const hz_vsync_counts_t *k = hz_vsync_counts(&v);
    double ppm = fabs((double)hz_vsync_period_q16(&v) / 65536.0 - 4166667.0) / 4166667.0 * 1e6;
    stab_error(r, ppm * 1e-6);
    stab_note(r, "%llu events; backwards %llu; off-grid %llu; relocks %llu; period off %.3f ppm",
              (unsigned long long)u.events, (unsigned long long)k->backwards, (unsigned long long)k->offgrid,
              (unsigned long long)k->relocks, ppm);
    STAB_CHECK(r, u.events == u.inputs, "inputs without exactly one event");
    STAB_CHECK(r, u.slot_jumps == 0, "slots went backwards after the clock did");
    STAB_CHECK(r, k->backwards == 1, "%llu backwards rejections for one step", (unsigned long long)k->backwards);
    STAB_CHECK(r, k->relocks == 1, "%llu relocks for one step", (unsigned long long)k->relocks);
    STAB_CHECK(r, hz_vsync_locked(&v) && ppm < 5.0, "not locked again at the right period (%.2f ppm)", ppm);
}

/* Statistics over the whole int64 range: mean and sd against exact 128-bit arithmetic, percentiles are values
 * that occurred, histogram counts add up with values at both ends of the range. */
static void c_tstat_extremes(stab_result_t *r)
{
    enum { N = 1001 };
    static int64_t v[N];
    __extension__ __int128 sum = 0;
    for (int i = 0; i < N; i++) {
        v[i] = i % 3 == 0 ? INT64_MAX - i : i % 3 == 1 ? INT64_MIN + 1 + i : (int64_t)i * 1000003;
        sum += v[i];
    }
    long double mean = (long double)sum / N, ss = 0;
    for (int i = 0; i < N; i++)
        ss += ((long double)v[i] - mean) * ((long double)v[i] - mean);
    long double sd = sqrtl(ss / N);
    hz_dist_t d;
    hz_dist_compute(v, N, &d);
    double em = fabsl((long double)d.mean - mean), es = fabsl((long double)d.sd - sd) / sd;
    stab_error(r, es);
    stab_note(r, "mean %lld (exact %.0Lf); sd %lld (exact %.6Le); min/max at the int64 ends", (long long)d.mean, mean,
              (long long)d.sd, sd);
    STAB_CHECK(r, em <= 1.0, "mean off by %g", (double)em);
    STAB_CHECK(r, es <= 1e-12, "sd off by %g relative", (double)es);
    STAB_CHECK(r, d.min == INT64_MIN + 1 + 1 && d.max == INT64_MAX, "min/max wrong");
    static hz_hist_t h;
    hz_error_t err;
    STAB_OK(r, hz_hist_init(&h, INT64_MIN + 1, INT64_MAX / 512, 1024, &err), &err);
    for (int i = 0; i < N; i++)
        hz_hist_add(&h, v[i]);
    hz_hist_add(&h, INT64_MIN);
    hz_hist_add(&h, INT64_MAX);
    uint64_t in = 0;
    for (uint32_t b = 0; b < h.nbins; b++)
        in += h.count[b];
    STAB_CHECK(r, h.n == N + 2 && in + h.below + h.above == h.n, "histogram lost values: %llu + %llu + %llu != %llu",
               (unsigned long long)in, (unsigned long long)h.below, (unsigned long long)h.above,
               (unsigned long long)h.n);
    STAB_CHECK(r, h.below == 1, "%llu below the range starting at INT64_MIN + 1", (unsigned long long)h.below);
}

/* Pacing with costs of 0, negative, and INT64_MAX: the budget saturates (no wrap), plans start before their
 * edge, and a plan is always in the future of `now`. */
static void c_pace_extremes(stab_result_t *r)
{
    static hz_vsync_t v;
    hz_vsync_cfg_t vc = { 4166667, 0, 0 };
    hz_error_t err;
    STAB_OK(r, hz_vsync_init(&v, &vc, &err), &err);
    hz_vsync_event_t ev;
    for (int i = 0; i < 64; i++) {
        hz_vsync_push(&v, 1000000000LL + i * 4166667LL);
        while (hz_vsync_pop(&v, &ev))
            ;
    }
    STAB_CHECK(r, hz_vsync_locked(&v), "no lock");
    static hz_pace_t p;
    hz_pace_cfg_t pc;
    memset(&pc, 0, sizeof pc);
    pc.latch_ns = 500000;
    STAB_OK(r, hz_pace_init(&p, &pc, &err), &err);
    const int64_t costs[] = { 0, -5, INT64_MIN, INT64_MAX, 1, INT64_MAX - 1 };
    int64_t now = 1000000000LL + 64 * 4166667LL;
    for (int rep = 0; rep < 40; rep++) {
        hz_pace_observe(&p, costs[rep % 6]);
        hz_pace_plan_t pl;
        hz_pace_plan(&p, &v, now, 0, &pl);
        STAB_CHECK(r, pl.budget_ns >= 0, "negative budget %lld", (long long)pl.budget_ns);
        STAB_CHECK(r, pl.start_ns <= pl.edge_ns, "start %lld after its edge %lld", (long long)pl.start_ns,
                   (long long)pl.edge_ns);
        STAB_CHECK(r, pl.edge_ns >= now, "target edge %lld before now %lld", (long long)pl.edge_ns, (long long)now);
    }
    stab_note(r, "costs 0; -5; INT64_MIN; INT64_MAX: budget %lld ns; plans stay ordered",
              (long long)hz_pace_budget(&p, 4166667));
}

static const stab_case_t cases[] = {
    { "ts_32bit_wrap", "edges across 2^31 and 2^32 ns: all accepted; slots continuous; period < 25 ppm",
      c_ts_32bit_wrap, 0 },
    { "ts_64bit_near_max", "edges up to 2^63 - 4e9 ns: all accepted; predictions past 2^63 do not wrap",
      c_ts_64bit_near_max, 0 },
    { "vcd_time_overflow", "VCD across 2^32 ticks read exactly; past 2^63 ns refused (range) naming the line",
      c_vcd_time_overflow, 0 },
    { "ecsv_time_overflow", "CSV t_us across 2^32 and up to 2^63-1 ns exact; 2^63 refused naming the line",
      c_ecsv_time_overflow, 0 },
    { "missing_pulses", "10% lost pulses: real edges accepted; missed = truth", c_missing_pulses, 0 },
    { "spurious_pulses", "5% glitches + 5% bounces: all rejected; real edges accepted", c_spurious_pulses, 0 },
    { "missing_and_spurious", "lost and extra pulses together: exact classification", c_missing_and_spurious, 0 },
    { "drift_plus_1000ppm", "+1000 ppm drift: all accepted; period < 25 ppm; offset reported", c_drift_plus_1000ppm,
      0 },
    { "drift_minus_1000ppm", "-1000 ppm drift: all accepted; period < 25 ppm; offset reported",
      c_drift_minus_1000ppm, 0 },
    { "zero_edges", "no edges: no lock; queries answer; empty summaries zero", c_zero_edges, 0 },
    { "all_edges_equal", "100 equal timestamps: one event each; 99 backwards; no lock", c_all_edges_equal, 0 },
    { "clock_backwards", "clock steps back: 1 backwards; 1 relock; slots increase; period right", c_clock_backwards,
      0 },
    { "tstat_extremes", "stats over the int64 range vs 128-bit exact; histogram keeps every value",
      c_tstat_extremes, 0 },
    { "pace_extremes", "costs 0/negative/INT64_MIN/INT64_MAX: budget saturates; plans ordered", c_pace_extremes,
      0 },
};
STAB_STAGE(timing, cases);
