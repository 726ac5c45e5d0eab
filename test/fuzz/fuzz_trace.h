/*
 * Shared by the trace fuzz targets (fuzz_vcd.c, fuzz_ecsv.c): an edge recorder that checks what the streaming
 * readers promise (hz/traceio.h) and hands the edges on to the v-sync model the way the frame loop does.
 *
 * Every input is read twice: in one piece and in chunks of a size taken from the input, since both readers take
 * their input "in chunks of any size"; the two reads must agree on the status, the message and every edge. A
 * refusal must carry its status and a message naming the line. Edges must have a level of 0 or 1 and times that
 * are >= 0 and never go backwards. The rising edges then drive two v-sync models (learning the period, and with
 * a 60 Hz nominal one), which must answer every edge with exactly one event (hz/vsync.h). Any violation
 * aborts, which libFuzzer records as a crash.
 */
#ifndef HZ_FUZZ_TRACE_H
#define HZ_FUZZ_TRACE_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hz/traceio.h"
#include "hz/vsync.h"

#define FUZZ_TRACE_KEEP 8192 /* rising edges kept for the v-sync models */

typedef struct fuzz_edges {
    uint64_t n, hash;
    int64_t last_t;
    int64_t rising[FUZZ_TRACE_KEEP];
    size_t n_rising;
} fuzz_edges_t;

static void fuzz_edges_reset(fuzz_edges_t *e)
{
    e->n = 0;
    e->hash = 1469598103934665603ull;
    e->last_t = 0;
    e->n_rising = 0;
}

static hz_status_t fuzz_edge(void *ctx, int64_t t, int level, hz_error_t *err)
{
    (void)err;
    fuzz_edges_t *e = ctx;
    if ((level != 0 && level != 1) || t < 0 || (e->n && t < e->last_t))
        abort(); /* the readers promise levels 0/1 and times >= 0 that never go backwards */
    e->hash = (e->hash ^ (uint64_t)t) * 1099511628211ull;
    e->hash = (e->hash ^ (uint64_t)level) * 1099511628211ull;
    e->n++;
    e->last_t = t;
    if (level == 1 && e->n_rising < FUZZ_TRACE_KEEP)
        e->rising[e->n_rising++] = t;
    return HZ_OK;
}

/* A refusal names its status and says where. */
static void fuzz_check_refusal(hz_status_t s, const hz_error_t *err)
{
    if (s == HZ_OK)
        return;
    if (err->code != s || !strstr(err->msg, "line "))
        abort();
}

/* The two reads agree. */
static void fuzz_check_same(hz_status_t s1, const hz_error_t *e1, const fuzz_edges_t *a, hz_status_t s2,
                            const hz_error_t *e2, const fuzz_edges_t *b)
{
    if (s1 != s2 || strcmp(e1->msg, e2->msg) || a->n != b->n || a->hash != b->hash)
        abort();
}

/* Chunk size for the second read: 1..64 bytes, from the input's last byte. */
static size_t fuzz_chunk(const uint8_t *data, size_t size)
{
    return size ? (size_t)(data[size - 1] % 64u) + 1 : 1;
}

static void fuzz_vsync_run(const fuzz_edges_t *e, int64_t nominal_ns)
{
    static hz_vsync_t v;
    hz_vsync_cfg_t cfg = { 0 };
    hz_error_t err;
    cfg.nominal_period_ns = nominal_ns;
    if (hz_vsync_init(&v, &cfg, &err) != HZ_OK)
        abort();
    uint64_t events = 0;
    hz_vsync_event_t ev;
    for (size_t i = 0; i < e->n_rising; i++) {
        hz_vsync_push(&v, e->rising[i]);
        while (hz_vsync_pop(&v, &ev)) {
            if (ev.index > i || (ev.kind != HZ_VSYNC_EDGE && ev.kind != HZ_VSYNC_SPURIOUS))
                abort();
            events++;
        }
    }
    hz_vsync_flush(&v);
    while (hz_vsync_pop(&v, &ev))
        events++;
    if (events != e->n_rising || hz_vsync_counts(&v)->inputs != e->n_rising)
        abort(); /* every input edge gets exactly one event */
    if (e->n_rising) {
        int64_t t = e->rising[e->n_rising - 1];
        (void)hz_vsync_slot_time(&v, hz_vsync_slot_at_or_after(&v, t));
        (void)hz_vsync_period_ns(&v);
        (void)hz_vsync_offset_ppb(&v);
    }
}

static void fuzz_vsync(const fuzz_edges_t *e)
{
    fuzz_vsync_run(e, 0);
    fuzz_vsync_run(e, 16666667);
}

#endif /* HZ_FUZZ_TRACE_H */
