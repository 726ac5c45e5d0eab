/*
 * Lock verdict: synthetic event streams exactly at and one past every threshold (minimum run, relock,
 * spurious and missed fractions, the far-from-nominal warning), the measured period against the generator's
 * true period, and the real v-sync model fed traces that must and must not lock.
 */
#include "hz_test.h"

#include <stdlib.h>
#include <string.h>

#include "hz/lockv.h"
#include "hz/vsync.h"
#include "hz/vsynth.h"

#define P 4166667ll /* 240 Hz */

typedef struct feed {
    hz_lockv_t l;
    int64_t slot, t;
} feed_t;

static void start(feed_t *f, const hz_lockv_cfg_t *cfg)
{
    memset(f, 0, sizeof *f);
    hz_lockv_init(&f->l, cfg);
    f->t = 1000000;
}

/* n accepted edges one period apart; the first flagged relock when asked, `missed` slots skipped before it. */
static void accept(feed_t *f, uint64_t n, int relock, uint32_t missed)
{
    for (uint64_t i = 0; i < n; i++) {
        hz_vsync_event_t ev = { 0 };
        uint32_t gap = i == 0 ? missed : 0;
        f->slot += 1 + gap;
        f->t += (int64_t)(1 + gap) * P;
        ev.kind = HZ_VSYNC_EDGE;
        ev.slot = f->slot;
        ev.t_ns = f->t;
        ev.missed_before = f->l.accepted ? gap : 0;
        ev.relock = (uint8_t)(relock && i == 0);
        hz_lockv_event(&f->l, &ev);
    }
}

static void spurious(feed_t *f, uint64_t n)
{
    for (uint64_t i = 0; i < n; i++) {
        hz_vsync_event_t ev = { 0 };
        ev.kind = HZ_VSYNC_SPURIOUS;
        ev.why = HZ_VSYNC_WHY_OFFGRID;
        ev.t_ns = f->t + P / 3;
        hz_lockv_event(&f->l, &ev);
    }
}

static int verdict(const feed_t *f, hz_lockv_result_t *r)
{
    hz_lockv_result(&f->l, r);
    return r->verdict;
}

static void test_min_run(void **state)
{
    (void)state;
    hz_lockv_cfg_t cfg = { 0 };
    feed_t f;
    hz_lockv_result_t r;
    start(&f, &cfg);
    accept(&f, HZ_LOCK_MIN_RUN - 1, 0, 0);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_NO_RUN);
    assert_int_equal(r.period_q16, 0); /* nothing measured, nothing echoed */
    accept(&f, 1, 0, 0);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_OK);
    assert_int_equal(r.period_q16, P * 65536);
    assert_int_equal(r.longest, HZ_LOCK_MIN_RUN);
    /* Many short stretches never add up to a lock: 10 stretches of 31 edges each (relocks then also
     * exceed their fraction). */
    start(&f, &cfg);
    for (int i = 0; i < 10; i++)
        accept(&f, HZ_LOCK_MIN_RUN - 1, i > 0, 0);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_NO_RUN | HZ_LOCK_RELOCKS);
    assert_int_equal(r.stretches, 10);
    assert_int_equal(r.period_q16, 0);
    /* A configured run length. */
    cfg.min_run = 8;
    start(&f, &cfg);
    accept(&f, 8, 0, 0);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_OK);
}

static void test_relock_fraction(void **state)
{
    (void)state;
    hz_lockv_cfg_t cfg = { 0 };
    feed_t f;
    hz_lockv_result_t r;
    /* 1% of 200 accepted edges = 2 relocks: passes; the third fails. */
    start(&f, &cfg);
    accept(&f, 100, 0, 0);
    accept(&f, 50, 1, 0);
    accept(&f, 50, 1, 0);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_OK);
    assert_int_equal(r.relocks, 2);
    assert_int_equal(r.stretches, 3);
    start(&f, &cfg);
    accept(&f, 100, 0, 0);
    accept(&f, 50, 1, 0);
    accept(&f, 49, 1, 0);
    accept(&f, 1, 1, 0);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_RELOCKS);
    /* Only stretches of min_run edges measure: the 1-edge stretch and a 31-edge one count nothing. */
    assert_int_equal(r.qualifying, 3);
    assert_int_equal(r.span_slots, 99 + 49 + 48);
}

static void test_spurious_fraction(void **state)
{
    (void)state;
    hz_lockv_cfg_t cfg = { 0 };
    feed_t f;
    hz_lockv_result_t r;
    /* 10% of 1000 inputs: 100 spurious pass, 101 fail. */
    start(&f, &cfg);
    accept(&f, 900, 0, 0);
    spurious(&f, 100);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_OK);
    start(&f, &cfg);
    accept(&f, 899, 0, 0);
    spurious(&f, 101);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_SPURIOUS);
    assert_int_equal(r.inputs, 1000);
    /* A stated limit of 50%. */
    cfg.max_spurious_ppm = 500000;
    start(&f, &cfg);
    accept(&f, 500, 0, 0);
    spurious(&f, 500);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_OK);
    spurious(&f, 1);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_SPURIOUS);
}

static void test_missed_fraction(void **state)
{
    (void)state;
    hz_lockv_cfg_t cfg = { 0 };
    feed_t f;
    hz_lockv_result_t r;
    /* 90 accepted + 10 missed: 10% passes; 89 + 11 fails. The period stays the true one across gaps. */
    start(&f, &cfg);
    accept(&f, 40, 0, 0);
    accept(&f, 50, 0, 10);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_OK);
    assert_int_equal(r.missed, 10);
    assert_int_equal(r.period_q16, P * 65536);
    start(&f, &cfg);
    accept(&f, 40, 0, 0);
    accept(&f, 49, 0, 11);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_MISSED);
}

static void test_far_from_nominal(void **state)
{
    (void)state;
    hz_lockv_cfg_t cfg = { 0 };
    feed_t f;
    hz_lockv_result_t r;
    /* 240 Hz measured against --hz 60: -75%, far. */
    cfg.nominal_period_ns = 16666667;
    start(&f, &cfg);
    accept(&f, 100, 0, 0);
    assert_int_equal(verdict(&f, &r), HZ_LOCK_OK);
    assert_true(r.far);
    assert_true(llabs(r.offset_ppb + 750000000ll) < 100000);
    /* Within 1%: not far (a nominal 0.99% off); 1.01% off is. */
    cfg.nominal_period_ns = P * 10000 / 10099;
    start(&f, &cfg);
    accept(&f, 100, 0, 0);
    verdict(&f, &r);
    assert_false(r.far);
    cfg.nominal_period_ns = P * 10000 / 10101;
    start(&f, &cfg);
    accept(&f, 100, 0, 0);
    verdict(&f, &r);
    assert_true(r.far);
    /* No nominal: no ppm, no warning. */
    cfg.nominal_period_ns = 0;
    start(&f, &cfg);
    accept(&f, 100, 0, 0);
    verdict(&f, &r);
    assert_false(r.far);
    assert_int_equal(r.offset_ppb, 0);
}

/* The real model on generated traces. */
static int model_verdict(const hz_vsynth_cfg_t *g, int64_t nominal, uint64_t edges, hz_lockv_result_t *r)
{
    static hz_vsync_t v;
    static hz_vsynth_t gen;
    hz_lockv_t l;
    hz_error_t err;
    hz_vsync_cfg_t vc = { 0 };
    vc.nominal_period_ns = nominal;
    assert_int_equal(hz_vsync_init(&v, &vc, &err), HZ_OK);
    assert_int_equal(hz_vsynth_init(&gen, g, &err), HZ_OK);
    hz_lockv_cfg_t lc = { 0 };
    lc.nominal_period_ns = nominal;
    hz_lockv_init(&l, &lc);
    hz_vsync_event_t ev;
    hz_vsynth_edge_t e;
    for (uint64_t i = 0; i < edges && hz_vsynth_next(&gen, &e); i++) {
        hz_vsync_push(&v, e.t_ns);
        while (hz_vsync_pop(&v, &ev))
            hz_lockv_event(&l, &ev);
    }
    hz_vsync_flush(&v);
    while (hz_vsync_pop(&v, &ev))
        hz_lockv_event(&l, &ev);
    hz_lockv_result(&l, r);
    print_message("  model: %llu inputs, %llu accepted, %llu spurious, %llu relocks, %llu missed, longest %llu, "
                  "verdict %d, %+.3f ppm\n", (unsigned long long)r->inputs, (unsigned long long)r->accepted,
                  (unsigned long long)r->spurious, (unsigned long long)r->relocks, (unsigned long long)r->missed,
                  (unsigned long long)r->longest, r->verdict, r->offset_ppb / 1000.0);
    return r->verdict;
}

static void test_model_traces(void **state)
{
    (void)state;
    hz_lockv_result_t r;
    hz_vsynth_cfg_t g;
    memset(&g, 0, sizeof g);
    g.period_q16 = P * 65536;
    g.jitter_ns = 20000;
    g.drift_ppb_start = g.drift_ppb_end = 100000; /* +100 ppm */
    g.seed = 7;
    assert_int_equal(model_verdict(&g, P, 2000, &r), HZ_LOCK_OK);
    /* Measured, not echoed: the +100 ppm drift shows (within 5 ppm), the nominal would say 0. */
    assert_true(llabs(r.offset_ppb - 100000) < 5000);
    /* 1% glitches and 1% missed: still a lock. */
    g.glitch_ppm = 10000;
    g.miss_ppm = 10000;
    assert_int_equal(model_verdict(&g, P, 2000, &r), HZ_LOCK_OK);
    /* 30% glitches: more than 10% of the edges are spurious. */
    g.glitch_ppm = 300000;
    g.miss_ppm = 0;
    assert_true(model_verdict(&g, P, 2000, &r) & HZ_LOCK_SPURIOUS);
    /* 30% missed pulses. */
    g.glitch_ppm = 0;
    g.miss_ppm = 300000;
    assert_true(model_verdict(&g, P, 2000, &r) & HZ_LOCK_MISSED);
    /* 20 edges of a clean display: too short to call. */
    g.miss_ppm = 0;
    assert_int_equal(model_verdict(&g, P, 20, &r), HZ_LOCK_NO_RUN);
    /* Random intervals between 0.5 P and 1.5 P (no display at all): no lock, no period. */
    static hz_vsync_t v;
    hz_lockv_t l;
    hz_error_t err;
    hz_vsync_cfg_t vc = { 0 };
    vc.nominal_period_ns = P;
    assert_int_equal(hz_vsync_init(&v, &vc, &err), HZ_OK);
    hz_lockv_cfg_t lc = { 0 };
    lc.nominal_period_ns = P;
    hz_lockv_init(&l, &lc);
    uint64_t x = 12345;
    int64_t t = 0;
    hz_vsync_event_t ev;
    for (int i = 0; i < 2000; i++) {
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        t += P / 2 + (int64_t)((x >> 33) % (uint64_t)P);
        hz_vsync_push(&v, t);
        while (hz_vsync_pop(&v, &ev))
            hz_lockv_event(&l, &ev);
    }
    hz_vsync_flush(&v);
    while (hz_vsync_pop(&v, &ev))
        hz_lockv_event(&l, &ev);
    hz_lockv_result(&l, &r);
    print_message("  random: %llu accepted, %llu spurious, %llu relocks, %llu missed, longest %llu, verdict %d\n",
                  (unsigned long long)r.accepted, (unsigned long long)r.spurious, (unsigned long long)r.relocks,
                  (unsigned long long)r.missed, (unsigned long long)r.longest, r.verdict);
    assert_int_not_equal(r.verdict, HZ_LOCK_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_min_run),
        cmocka_unit_test(test_relock_fraction),
        cmocka_unit_test(test_spurious_fraction),
        cmocka_unit_test(test_missed_fraction),
        cmocka_unit_test(test_far_from_nominal),
        cmocka_unit_test(test_model_traces),
    };
    return HZ_RUN(tests);
}
