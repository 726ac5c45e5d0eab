/* One renderer frame on the static thread pool (see render_run.h). */
#include "render_run.h"

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

static hz_status_t run_frame_ns(hz_renderer_t *r, uint64_t index, hz_time_ns_t time, int64_t ns[3],
                                hz_phase_t *prog, hz_error_t *err)
{
    int64_t t0 = ns ? hz_clock_ns() : 0;
    hz_status_t s = hz_render_begin_frame_ns(r, index, time, err);
    if (s != HZ_OK)
        return s;
    int64_t t1 = ns ? hz_clock_ns() : 0, t2 = t1;
    uint32_t done = 0, total = 0;
    if (prog)
        for (uint32_t p = 0; p < hz_render_pass_count(r); p++)
            total += hz_render_pass_items(r, p);
    for (uint32_t p = 0; p < hz_render_pass_count(r); p++) {
        pass_job_t j = { r, p, prog, &done, total ? total : 1u };
        hz_threads_run(run_item, &j, hz_render_pass_items(r, p));
        if (p == 0 && ns)
            t2 = hz_clock_ns();
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
