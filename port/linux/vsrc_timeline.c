/* Timeline v-sync sources: the simulated display and VCD/CSV replay (see vsource.h). Implementation objects
 * come from small static pools: nothing here calls malloc. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hz/traceio.h"
#include "vsource.h"

#define POOL 4

/* ---- simulated display ---- */

typedef struct sim_impl {
    int used;
    hz_vsynth_t gen;
} sim_impl_t;

static sim_impl_t sim_pool[POOL];

static hz_status_t sim_next(hz_vsource_t *s, int64_t deadline, hz_edge_t *e, int *result, hz_error_t *err)
{
    (void)deadline;
    (void)err;
    sim_impl_t *im = s->impl;
    hz_vsynth_edge_t ed;
    if (!hz_vsynth_next(&im->gen, &ed)) {
        *result = HZ_VS_END;
        return HZ_OK;
    }
    e->t_ns = ed.t_ns;
    e->level = 1;
    e->frame_id = -1;
    *result = HZ_VS_EDGE;
    return HZ_OK;
}

static void sim_close(hz_vsource_t *s)
{
    sim_impl_t *im = s->impl;
    if (im)
        im->used = 0;
    s->impl = NULL;
}

hz_status_t hz_vsource_sim(hz_vsource_t *s, const hz_vsynth_cfg_t *cfg, hz_error_t *err)
{
    memset(s, 0, sizeof *s);
    sim_impl_t *im = NULL;
    for (int i = 0; i < POOL && !im; i++)
        if (!sim_pool[i].used)
            im = &sim_pool[i];
    if (!im)
        return hz_error_set(err, HZ_E_NO_MEMORY, "simulated display: more than %d open at once", POOL);
    hz_status_t st = hz_vsynth_init(&im->gen, cfg, err);
    if (st != HZ_OK)
        return st;
    im->used = 1;
    s->impl = im;
    s->live = 0;
    s->next = sim_next;
    s->close = sim_close;
    long long p = (long long)(cfg->period_q16 >> 16);
    snprintf(s->name, sizeof s->name, "simulated display, period %lld ns, jitter +-%lld ns, drift %+.1f ppm",
             p, (long long)cfg->jitter_ns, cfg->drift_ppb_start / 1000.0);
    return HZ_OK;
}

/* ---- VCD / CSV replay ---- */

#define TRACE_QUEUE 512
#define TRACE_SLICE 128 /* bytes parsed at a time: bounds the edges one slice can produce */

typedef struct trace_impl {
    int used;
    int fd;
    int vcd; /* 1 VCD, 0 CSV */
    hz_vcd_t vp;
    hz_ecsv_t cp;
    char path[256];
    char buf[65536];
    size_t len, pos;
    int eof, finished;
    hz_edge_t q[TRACE_QUEUE];
    size_t q_head, q_n;
    uint64_t edges;
} trace_impl_t;

static trace_impl_t trace_pool[POOL];

static hz_status_t trace_edge(void *ctx, int64_t t, int level, hz_error_t *err)
{
    trace_impl_t *im = ctx;
    if (im->q_n == TRACE_QUEUE)
        return hz_error_set(err, HZ_E_INTERNAL, "trace queue overflow");
    hz_edge_t *e = &im->q[(im->q_head + im->q_n++) % TRACE_QUEUE];
    e->t_ns = t;
    e->level = level;
    e->frame_id = -1;
    im->edges++;
    return HZ_OK;
}

static hz_status_t trace_fill(trace_impl_t *im, hz_error_t *err)
{
    while (im->q_n == 0 && !im->finished) {
        if (im->pos == im->len && !im->eof) {
            ssize_t r;
            do
                r = read(im->fd, im->buf, sizeof im->buf);
            while (r < 0 && errno == EINTR);
            if (r < 0)
                return hz_error_set(err, HZ_E_IO, "%s: read failed: %s", im->path, strerror(errno));
            im->len = (size_t)r;
            im->pos = 0;
            if (r == 0)
                im->eof = 1;
        }
        hz_status_t s;
        if (im->pos < im->len) {
            size_t n = im->len - im->pos < TRACE_SLICE ? im->len - im->pos : TRACE_SLICE;
            s = im->vcd ? hz_vcd_feed(&im->vp, im->buf + im->pos, n, trace_edge, im, err)
                        : hz_ecsv_feed(&im->cp, im->buf + im->pos, n, trace_edge, im, err);
            im->pos += n;
        } else {
            s = im->vcd ? hz_vcd_finish(&im->vp, trace_edge, im, err) : hz_ecsv_finish(&im->cp, trace_edge, im, err);
            im->finished = 1;
        }
        if (s != HZ_OK) {
            hz_error_prefix(err, im->path);
            return s;
        }
    }
    return HZ_OK;
}

static hz_status_t trace_next(hz_vsource_t *s, int64_t deadline, hz_edge_t *e, int *result, hz_error_t *err)
{
    (void)deadline;
    trace_impl_t *im = s->impl;
    hz_status_t st = trace_fill(im, err);
    if (st != HZ_OK)
        return st;
    if (im->q_n == 0) {
        if (im->edges == 0)
            return hz_error_set(err, HZ_E_FORMAT, "%s: the trace has no edges", im->path);
        *result = HZ_VS_END;
        return HZ_OK;
    }
    *e = im->q[im->q_head];
    im->q_head = (im->q_head + 1) % TRACE_QUEUE;
    im->q_n--;
    *result = HZ_VS_EDGE;
    return HZ_OK;
}

static void trace_close(hz_vsource_t *s)
{
    trace_impl_t *im = s->impl;
    if (im) {
        if (im->fd >= 0)
            close(im->fd);
        im->used = 0;
    }
    s->impl = NULL;
}

static hz_status_t trace_open(hz_vsource_t *s, const char *path, const char *signal, int vcd, hz_error_t *err)
{
    memset(s, 0, sizeof *s);
    trace_impl_t *im = NULL;
    for (int i = 0; i < POOL && !im; i++)
        if (!trace_pool[i].used)
            im = &trace_pool[i];
    if (!im)
        return hz_error_set(err, HZ_E_NO_MEMORY, "trace replay: more than %d open at once", POOL);
    /* O_NONBLOCK: opening a FIFO must not wait for a writer. A trace is replayed from a regular file: a FIFO, a
     * terminal or a device could block a read for ever, which --timeout-ms (edges, not reads) cannot end. */
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0)
        return hz_error_set(err, HZ_E_IO, "%s: cannot open the trace: %s", path,
                            strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return hz_error_set(err, HZ_E_IO, "%s: not a regular file (a FIFO, device or folder): a trace is replayed from "
                            "a file; save the capture first", path);
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    memset(im, 0, sizeof *im);
    im->fd = fd;
    im->vcd = vcd;
    snprintf(im->path, sizeof im->path, "%s", path);
    if (vcd) {
        hz_status_t st = hz_vcd_init(&im->vp, signal, err);
        if (st != HZ_OK) {
            close(fd);
            return st;
        }
    } else {
        hz_ecsv_init(&im->cp);
    }
    im->used = 1;
    s->impl = im;
    s->live = 0;
    s->both_levels = 1;
    s->next = trace_next;
    s->close = trace_close;
    snprintf(s->name, sizeof s->name, "%s replay of %s%s%s", vcd ? "VCD" : "CSV", path,
             vcd && signal && *signal ? ", signal " : "", vcd && signal ? signal : "");
    return HZ_OK;
}

hz_status_t hz_vsource_vcd(hz_vsource_t *s, const char *path, const char *signal, hz_error_t *err)
{
    return trace_open(s, path, signal ? signal : "", 1, err);
}

hz_status_t hz_vsource_csv(hz_vsource_t *s, const char *path, hz_error_t *err)
{
    return trace_open(s, path, "", 0, err);
}

/* ---- null sink ---- */

static hz_status_t null_present(hz_sink_t *s, const hz_rgb8_image_t *img, uint64_t id, hz_error_t *err)
{
    (void)s;
    (void)img;
    (void)id;
    (void)err;
    return HZ_OK;
}

void hz_sink_null(hz_sink_t *s)
{
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "none (frames are rendered and timed, not shown)");
    s->present = null_present;
}
