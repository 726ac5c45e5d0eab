/* One renderer frame on the static thread pool (see render_run.h). */
#include "render_run.h"

#include <sched.h>

#include "clock.h"
#include "threads.h"

typedef struct pass_job {
    hz_renderer_t *r;
    uint32_t pass;
    hz_phase_t *prog; /* NULL: none */
    uint32_t *done, total;
} pass_job_t;

static void run_item(void *user, uint32_t item, int thread)
{
    pass_job_t *j = (pass_job_t *)user;
    hz_render_pass_run(j->r, j->pass, item, (uint32_t)thread);
    if (j->prog) {
        uint32_t d = __atomic_add_fetch(j->done, 1u, __ATOMIC_RELAXED);
        if (thread == 0) /* the caller: progress lines come from one thread */
            hz_phase_update(j->prog, (float)d / (float)j->total);
    }
}

void hz_render_run_pass(hz_renderer_t *r, uint32_t pass)
{
    pass_job_t j = { r, pass, NULL, NULL, 0 };
    hz_threads_run(run_item, &j, hz_render_pass_items(r, pass));
}

/* ---- overlapped passes (hz_render_overlap_units) ----
 * Every pool thread runs one loop: it takes the next resolve unit when that unit's trace rows have all
 * returned, else the next trace item, else (no trace left) waits for the unit. A thread waits only on trace
 * items other threads are running (it holds none itself), so the frame always finishes; which thread runs
 * what changes nothing in the frame (hz/render.h). */

#define OVERLAP_MAX_ROWS (HZ_IMAGE_MAX_DIM / HZ_RENDER_TILE + 1u)

typedef struct overlap_job {
    hz_renderer_t *r;
    uint32_t trace_items, row_items, units;
    uint32_t next_trace, next_unit; /* atomic */
    uint32_t *row_left;             /* per trace row: items not yet returned (atomic) */
    bool timed;
    int64_t resolve_ns;             /* atomic: summed over threads, when timed */
    hz_phase_t *prog;
    uint32_t done, total;           /* atomic done */
} overlap_job_t;

static uint32_t overlap_rows_left[OVERLAP_MAX_ROWS];


static bool unit_ready(const overlap_job_t *j, uint32_t u)
{
    uint32_t lo, hi;
    hz_render_overlap_needs(j->r, u, &lo, &hi);
    for (uint32_t row = lo; row <= hi; row++)
        if (__atomic_load_n(&j->row_left[row], __ATOMIC_ACQUIRE))
            return false;
    return true;
}

static void overlap_progress(overlap_job_t *j, int thread)
{
    if (!j->prog)
        return;
    uint32_t d = __atomic_add_fetch(&j->done, 1u, __ATOMIC_RELAXED);
    if (thread == 0)
        hz_phase_update(j->prog, (float)d / (float)j->total);
}

static void overlap_loop(void *user, uint32_t item, int thread)
{
    overlap_job_t *j = (overlap_job_t *)user;
    unsigned spins = 0;
    (void)item;
    for (;;) {
        uint32_t u = __atomic_load_n(&j->next_unit, __ATOMIC_RELAXED);
        if (u < j->units && unit_ready(j, u)) {
            if (__atomic_compare_exchange_n(&j->next_unit, &u, u + 1u, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
                int64_t t0 = j->timed ? hz_clock_ns() : 0;
                hz_render_overlap_run(j->r, u);
                if (j->timed)
                    __atomic_fetch_add(&j->resolve_ns, hz_clock_ns() - t0, __ATOMIC_RELAXED);
                overlap_progress(j, thread);
                spins = 0;
            }
            continue;
        }
        if (__atomic_load_n(&j->next_trace, __ATOMIC_RELAXED) < j->trace_items) {
            uint32_t t = __atomic_fetch_add(&j->next_trace, 1u, __ATOMIC_RELAXED);
            if (t < j->trace_items) {
                hz_render_pass_run(j->r, 0, t, (uint32_t)thread);
                __atomic_fetch_sub(&j->row_left[t / j->row_items], 1u, __ATOMIC_RELEASE);
                overlap_progress(j, thread);
                spins = 0;
                continue;
            }
        }
        if (u >= j->units)
            return;
        /* Only units are left and the next one waits for trace items still running elsewhere: spin briefly,
         * then give the CPU away (on a loaded machine the thread we wait for may need it). */
        if (++spins < 64)
            hz_threads_relax();
        else
            sched_yield();
    }
}

/* Both passes of a tdense or TAA frame as one run; *resolve_ns (when not NULL) gets the resolve units' time
 * summed over threads and divided by their number. */
static void run_overlapped(hz_renderer_t *r, uint32_t units, hz_phase_t *prog, uint32_t total,
                           int64_t *resolve_ns)
{
    uint32_t rows, row_items;
    hz_render_overlap_units(r, &rows, &row_items);
    overlap_job_t j = { r, hz_render_pass_items(r, 0), row_items, units, 0, 0, overlap_rows_left,
                        resolve_ns != NULL, 0, prog, 0, total ? total : 1u };
    for (uint32_t row = 0; row < rows && row < OVERLAP_MAX_ROWS; row++)
        overlap_rows_left[row] = row_items;
    int threads = hz_threads_count();
    hz_threads_run(overlap_loop, &j, (uint32_t)(threads > 0 ? threads : 1));
    if (resolve_ns)
        *resolve_ns = j.resolve_ns / (threads > 0 ? threads : 1);
}

static hz_status_t run_frame_ns(hz_renderer_t *r, uint64_t index, hz_time_ns_t time, int64_t ns[3],
                                hz_phase_t *prog, hz_error_t *err)
{
    int64_t t0 = ns ? hz_clock_ns() : 0;
    hz_status_t s = hz_render_begin_frame_ns(r, index, time, err);
    if (s != HZ_OK)
        return s;
    int64_t t1 = ns ? hz_clock_ns() : 0, t2 = t1;
    uint32_t done = 0, total = 0, rows, row_items;
    const uint32_t units = hz_render_overlap_units(r, &rows, &row_items);
    if (prog)
        for (uint32_t p = 0; p < hz_render_pass_count(r); p++)
            total += units && p ? units : hz_render_pass_items(r, p);
    if (units && rows <= OVERLAP_MAX_ROWS) {
        /* the split of an overlapped frame: the resolve units' share of the threads' time, the rest tracing */
        int64_t resolve = 0;
        run_overlapped(r, units, prog, total, ns ? &resolve : NULL);
        if (ns)
            t2 = hz_clock_ns() - resolve;
    } else {
        for (uint32_t p = 0; p < hz_render_pass_count(r); p++) {
            pass_job_t j = { r, p, prog, &done, total ? total : 1u };
            hz_threads_run(run_item, &j, hz_render_pass_items(r, p));
            if (p == 0 && ns)
                t2 = hz_clock_ns();
        }
    }
    hz_render_end_frame(r);
    if (ns) {
        ns[0] = t1 - t0;
        ns[1] = t2 - t1;
        ns[2] = hz_clock_ns() - t2;
    }
    return HZ_OK;
}

/* Seconds as float: refused when not finite or past what float seconds can say (9e9 s). */
static hz_status_t seconds_to_ns(float time, hz_time_ns_t *ns, hz_error_t *err)
{
    if (!(time == time) || time > 9e9f || time < -9e9f)
        return hz_error_set(err, HZ_E_INVALID_ARG, "frame time is not finite");
    *ns = hz_time_from_s(time);
    return HZ_OK;
}

hz_status_t hz_render_run_frame_parts_ns(hz_renderer_t *r, uint64_t index, hz_time_ns_t time, int64_t ns[3],
                                         hz_error_t *err)
{
    return run_frame_ns(r, index, time, ns, NULL, err);
}

hz_status_t hz_render_run_frame_parts(hz_renderer_t *r, uint64_t index, float time, int64_t ns[3],
                                      hz_error_t *err)
{
    hz_time_ns_t t = 0;
    hz_status_t s = seconds_to_ns(time, &t, err);
    return s != HZ_OK ? s : run_frame_ns(r, index, t, ns, NULL, err);
}

hz_status_t hz_render_run_frame_progress_ns(hz_renderer_t *r, uint64_t index, hz_time_ns_t time,
                                            hz_phase_t *prog, hz_error_t *err)
{
    return run_frame_ns(r, index, time, NULL, prog, err);
}

hz_status_t hz_render_run_frame(hz_renderer_t *r, uint64_t index, float time, hz_error_t *err)
{
    return hz_render_run_frame_parts(r, index, time, NULL, err);
}

hz_status_t hz_render_run_frame_ns(hz_renderer_t *r, uint64_t index, hz_time_ns_t time, hz_error_t *err)
{
    return run_frame_ns(r, index, time, NULL, NULL, err);
}
