/* V4L2 output sink with dequeue-timestamp v-sync, and V4L2 capture (see devices.h). */
#include <errno.h>
#include <fcntl.h>
#include <linux/videodev2.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

#include "clock.h"
#include "devices.h"
#include "threads.h"

#define POOL 2
#define MAX_BUFS 4
#define EDGE_Q 16

typedef struct vbuf {
    uint8_t *mem;
    size_t len;
    int queued;
    int64_t frame_id;
} vbuf_t;

typedef struct vdev {
    int used;
    const hz_sysio_t *io;
    int fd;
    char path[128];
    uint32_t type;
    hz_pix_fmt_t fmt;
    int w, h;
    size_t stride, size;
    vbuf_t buf[MAX_BUFS];
    int nbufs;
    int streaming;
    int ts_kind; /* V4L2_BUF_FLAG_TIMESTAMP_* of the last dequeued buffer */
    hz_edge_t q[EDGE_Q];
    int q_head, q_n;
} vdev_t;

static vdev_t out_pool[POOL];
static vdev_t cap_pool[POOL];

static const char *fourcc_str(uint32_t f, char *buf)
{
    for (int i = 0; i < 4; i++) {
        char c = (char)((f >> (8 * i)) & 0xff);
        buf[i] = c >= 32 && c < 127 ? c : '?';
    }
    buf[4] = '\0';
    return buf;
}

static void vdev_release(vdev_t *d)
{
    if (d->fd >= 0 && d->streaming) {
        int type = (int)d->type;
        hz_sysio_ioctl(d->io, d->fd, VIDIOC_STREAMOFF, &type);
    }
    for (int i = 0; i < d->nbufs; i++)
        if (d->buf[i].mem)
            d->io->munmap(d->buf[i].mem, d->buf[i].len);
    if (d->fd >= 0) {
        struct v4l2_requestbuffers rb;
        memset(&rb, 0, sizeof rb);
        rb.type = d->type;
        rb.memory = V4L2_MEMORY_MMAP;
        hz_sysio_ioctl(d->io, d->fd, VIDIOC_REQBUFS, &rb); /* count 0: free them */
        d->io->close(d->fd);
    }
    d->fd = -1;
    d->used = 0;
}

/* Opens the node, checks its capabilities, negotiates the format and maps `want` buffers. */
static hz_status_t vdev_open(vdev_t *d, const char *path, uint32_t type, hz_pix_fmt_t fmt, int w, int h, int want,
                             const hz_sysio_t *io, hz_error_t *err)
{
    memset(d, 0, sizeof *d);
    d->io = io ? io : &hz_sysio_linux;
    d->type = type;
    d->fmt = fmt;
    snprintf(d->path, sizeof d->path, "%s", path);
    d->fd = d->io->open(path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (d->fd < 0) {
        int e = errno;
        if (e == ENOENT)
            return hz_error_set(err, HZ_E_DEVICE, "%s: no such device node (is the V4L2 driver loaded?)", path);
        if (e == EACCES || e == EPERM)
            return hz_error_set(err, HZ_E_DEVICE, "%s: permission denied (run as root or join group 'video')",
                                path);
        return hz_error_set(err, HZ_E_DEVICE, "%s: cannot open: %s", path, strerror(e));
    }
    d->used = 1;
    const char *what = type == V4L2_BUF_TYPE_VIDEO_OUTPUT ? "output" : "capture";
    struct v4l2_capability cap;
    memset(&cap, 0, sizeof cap);
    if (hz_sysio_ioctl(d->io, d->fd, VIDIOC_QUERYCAP, &cap) < 0)
        return hz_error_set(err, HZ_E_DEVICE, "%s: not a V4L2 device (%s)", path, strerror(errno));
    uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
    uint32_t need = type == V4L2_BUF_TYPE_VIDEO_OUTPUT ? V4L2_CAP_VIDEO_OUTPUT : V4L2_CAP_VIDEO_CAPTURE;
    uint32_t mplane = type == V4L2_BUF_TYPE_VIDEO_OUTPUT ? V4L2_CAP_VIDEO_OUTPUT_MPLANE : V4L2_CAP_VIDEO_CAPTURE_MPLANE;
    if (!(caps & need)) {
        if (caps & mplane)
            return hz_error_set(err, HZ_E_UNSUPPORTED, "%s (%s): only the multi-planar %s API, which hzrt does not "
                                "speak", path, (const char *)cap.card, what);
        return hz_error_set(err, HZ_E_DEVICE, "%s (%s): not a video %s device (capabilities 0x%08x)", path,
                            (const char *)cap.card, what, caps);
    }
    if (!(caps & V4L2_CAP_STREAMING))
        return hz_error_set(err, HZ_E_UNSUPPORTED, "%s (%s): no streaming I/O", path, (const char *)cap.card);
    /* The format must be one the device offers: list them for the message if not. */
    uint32_t want_fcc = hz_pix_fourcc(fmt);
    char offered[160] = "";
    int found = 0;
    for (uint32_t i = 0; i < 64; i++) {
        struct v4l2_fmtdesc fd;
        memset(&fd, 0, sizeof fd);
        fd.index = i;
        fd.type = type;
        if (hz_sysio_ioctl(d->io, d->fd, VIDIOC_ENUM_FMT, &fd) < 0)
            break;
        if (fd.pixelformat == want_fcc)
            found = 1;
        char f4[5];
        size_t n = strlen(offered);
        if (n + 8 < sizeof offered)
            snprintf(offered + n, sizeof offered - n, "%s%s", n ? " " : "", fourcc_str(fd.pixelformat, f4));
    }
    char f4[5];
    if (!found)
        return hz_error_set(err, HZ_E_UNSUPPORTED, "%s: unsupported pixel format %s (%s): the device offers %s",
                            path, hz_pix_name(fmt), fourcc_str(want_fcc, f4), offered[0] ? offered : "none");
    struct v4l2_format f;
    memset(&f, 0, sizeof f);
    f.type = type;
    if (hz_sysio_ioctl(d->io, d->fd, VIDIOC_G_FMT, &f) < 0)
        return hz_error_set(err, HZ_E_DEVICE, "%s: VIDIOC_G_FMT: %s", path, strerror(errno));
    if (w > 0) {
        f.fmt.pix.width = (uint32_t)w;
        f.fmt.pix.height = (uint32_t)h;
    }
    f.fmt.pix.pixelformat = want_fcc;
    f.fmt.pix.field = V4L2_FIELD_NONE;
    f.fmt.pix.bytesperline = 0;
    f.fmt.pix.sizeimage = 0;
    if (hz_sysio_ioctl(d->io, d->fd, VIDIOC_S_FMT, &f) < 0)
        return hz_error_set(err, errno == EBUSY ? HZ_E_DEVICE : HZ_E_UNSUPPORTED, "%s: VIDIOC_S_FMT %s: %s", path,
                            hz_pix_name(fmt), strerror(errno));
    if (f.fmt.pix.pixelformat != want_fcc) {
        char g4[5];
        return hz_error_set(err, HZ_E_UNSUPPORTED, "%s: unsupported pixel format %s: the driver chose %s instead",
                            path, hz_pix_name(fmt), fourcc_str(f.fmt.pix.pixelformat, g4));
    }
    if (w > 0 && ((int)f.fmt.pix.width != w || (int)f.fmt.pix.height != h))
        return hz_error_set(err, HZ_E_UNSUPPORTED, "%s: the device cannot do %dx%d (it offers %ux%u in %s)", path, w,
                            h, f.fmt.pix.width, f.fmt.pix.height, hz_pix_name(fmt));
    if (f.fmt.pix.field != V4L2_FIELD_NONE)
        return hz_error_set(err, HZ_E_UNSUPPORTED, "%s: interlaced modes (field %u) are not supported", path,
                            f.fmt.pix.field);
    d->w = (int)f.fmt.pix.width;
    d->h = (int)f.fmt.pix.height;
    d->stride = f.fmt.pix.bytesperline;
    d->size = f.fmt.pix.sizeimage;
    hz_status_t st = hz_pix_check(fmt, d->w, d->h, err);
    if (st != HZ_OK) {
        hz_error_prefix(err, path);
        return st;
    }
    if (d->stride < (size_t)d->w * (size_t)hz_pix_bpp(fmt) || d->size < d->stride * (size_t)d->h)
        return hz_error_set(err, HZ_E_DEVICE, "%s: implausible format: %zu bytes per line, %zu per image for %dx%d",
                            path, d->stride, d->size, d->w, d->h);
    struct v4l2_requestbuffers rb;
    memset(&rb, 0, sizeof rb);
    rb.count = (uint32_t)want;
    rb.type = type;
    rb.memory = V4L2_MEMORY_MMAP;
    if (hz_sysio_ioctl(d->io, d->fd, VIDIOC_REQBUFS, &rb) < 0)
        return hz_error_set(err, errno == EBUSY ? HZ_E_DEVICE : HZ_E_UNSUPPORTED, "%s: VIDIOC_REQBUFS (mmap): %s%s",
                            path, strerror(errno), errno == EBUSY ? " (another program streams on it)" : "");
    if (rb.count < 2)
        return hz_error_set(err, HZ_E_DEVICE, "%s: the driver gave %u buffers, at least 2 are needed", path, rb.count);
    d->nbufs = rb.count > MAX_BUFS ? MAX_BUFS : (int)rb.count;
    for (int i = 0; i < d->nbufs; i++) {
        struct v4l2_buffer b;
        memset(&b, 0, sizeof b);
        b.type = type;
        b.memory = V4L2_MEMORY_MMAP;
        b.index = (uint32_t)i;
        if (hz_sysio_ioctl(d->io, d->fd, VIDIOC_QUERYBUF, &b) < 0)
            return hz_error_set(err, HZ_E_DEVICE, "%s: VIDIOC_QUERYBUF %d: %s", path, i, strerror(errno));
        void *m = d->io->mmap(NULL, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, d->fd, (off_t)b.m.offset);
        if (m == MAP_FAILED)
            return hz_error_set(err, HZ_E_DEVICE, "%s: mmap of buffer %d: %s", path, i, strerror(errno));
        d->buf[i].mem = m;
        d->buf[i].len = b.length;
        d->buf[i].frame_id = -1;
        if (b.length < d->size)
            return hz_error_set(err, HZ_E_DEVICE, "%s: buffer %d holds %u bytes, an image needs %zu", path, i, b.length,
                                d->size);
    }
    return HZ_OK;
}

static int64_t tv_ns(const struct timeval *tv)
{
    return (int64_t)tv->tv_sec * 1000000000 + (int64_t)tv->tv_usec * 1000;
}

/* Dequeues one buffer if one is ready. 1: got one into *b, 0: none ready. */
static int vdev_dq(vdev_t *d, struct v4l2_buffer *b, hz_error_t *err, hz_status_t *st)
{
    memset(b, 0, sizeof *b);
    b->type = d->type;
    b->memory = V4L2_MEMORY_MMAP;
    *st = HZ_OK;
    if (hz_sysio_ioctl(d->io, d->fd, VIDIOC_DQBUF, b) < 0) {
        if (errno == EAGAIN)
            return 0;
        *st = hz_error_set(err, HZ_E_DEVICE, "%s: VIDIOC_DQBUF: %s", d->path, strerror(errno));
        return 0;
    }
    if (b->index >= (uint32_t)d->nbufs) {
        *st = hz_error_set(err, HZ_E_DEVICE, "%s: the driver returned buffer %u of %d", d->path, b->index, d->nbufs);
        return 0;
    }
    d->buf[b->index].queued = 0;
    d->ts_kind = (int)(b->flags & V4L2_BUF_FLAG_TIMESTAMP_MASK);
    return 1;
}

/* Waits up to ms for the fd to be ready for `events`. 1 ready, 0 timed out. */
static int vdev_wait(vdev_t *d, short events, int ms, hz_error_t *err, hz_status_t *st)
{
    *st = HZ_OK;
    for (;;) {
        struct pollfd p = { d->fd, events, 0 };
        int r = d->io->poll(&p, 1, ms);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0) {
            *st = hz_error_set(err, HZ_E_IO, "%s: poll: %s", d->path, strerror(errno));
            return 0;
        }
        if (r > 0 && (p.revents & (POLLERR | POLLNVAL)) && !(p.revents & events)) {
            *st = hz_error_set(err, HZ_E_DEVICE, "%s: the device reports an error (not streaming?)", d->path);
            return 0;
        }
        return r > 0;
    }
}

/* ---- output ---- */

static void out_push_edge(vdev_t *d, const struct v4l2_buffer *b)
{
    /* Monotonic driver timestamps mark the refresh; a driver that copies the application's timestamp (or
     * stamps nothing useful) gets the dequeue time instead. */
    int64_t t = d->ts_kind == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC ? tv_ns(&b->timestamp) : hz_clock_ns();
    if (d->q_n == EDGE_Q) {
        d->q_head = (d->q_head + 1) % EDGE_Q;
        d->q_n--;
    }
    hz_edge_t *e = &d->q[(d->q_head + d->q_n++) % EDGE_Q];
    e->t_ns = t;
    e->level = 1;
    e->frame_id = d->buf[b->index].frame_id;
}

static void convert_rows(const void *fmt, const uint8_t *src, size_t src_stride, uint8_t *dst, size_t dst_stride,
                         int w, int h)
{
    hz_pix_convert(*(const hz_pix_fmt_t *)fmt, src, src_stride, dst, dst_stride, w, h);
}

static hz_status_t out_present(hz_sink_t *s, const hz_rgb8_image_t *img, uint64_t id, hz_error_t *err)
{
    vdev_t *d = s->impl;
    int idx = -1;
    for (int i = 0; i < d->nbufs && idx < 0; i++)
        if (!d->buf[i].queued)
            idx = i;
    hz_status_t st = HZ_OK;
    int64_t give_up = hz_clock_ns() + 1000000000;
    while (idx < 0) {
        struct v4l2_buffer b;
        int64_t left = give_up - hz_clock_ns();
        if (left <= 0)
            return hz_error_set(err, HZ_E_TIMEOUT, "%s: no output buffer came back within 1 s (the device stopped "
                                "consuming frames)", d->path);
        if (!vdev_wait(d, POLLOUT, (int)(left / 1000000) + 1, err, &st)) {
            if (st != HZ_OK)
                return st;
            continue;
        }
        if (vdev_dq(d, &b, err, &st)) {
            out_push_edge(d, &b);
            idx = (int)b.index;
        } else if (st != HZ_OK) {
            return st;
        }
    }
    int w = img->w < d->w ? img->w : d->w, h = img->h < d->h ? img->h : d->h;
    if (d->fmt == HZ_PIX_YUYV)
        w &= ~1;
    hz_threads_convert(convert_rows, &d->fmt, img->rgb, img->stride, d->buf[idx].mem, d->stride, w, h);
    struct v4l2_buffer b;
    memset(&b, 0, sizeof b);
    b.type = d->type;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = (uint32_t)idx;
    b.bytesused = (uint32_t)d->size;
    b.field = V4L2_FIELD_NONE;
    int64_t now = hz_clock_ns();
    b.timestamp.tv_sec = (time_t)(now / 1000000000);
    b.timestamp.tv_usec = (suseconds_t)(now % 1000000000 / 1000);
    if (hz_sysio_ioctl(d->io, d->fd, VIDIOC_QBUF, &b) < 0)
        return hz_error_set(err, HZ_E_DEVICE, "%s: VIDIOC_QBUF: %s", d->path, strerror(errno));
    d->buf[idx].queued = 1;
    d->buf[idx].frame_id = (int64_t)id;
    if (!d->streaming) {
        int type = (int)d->type;
        if (hz_sysio_ioctl(d->io, d->fd, VIDIOC_STREAMON, &type) < 0)
            return hz_error_set(err, HZ_E_DEVICE, "%s: VIDIOC_STREAMON: %s", d->path, strerror(errno));
        d->streaming = 1;
    }
    return HZ_OK;
}

static hz_status_t out_next(hz_vsource_t *s, int64_t deadline, hz_edge_t *e, int *result, hz_error_t *err)
{
    vdev_t *d = s->impl;
    for (;;) {
        if (d->q_n) {
            *e = d->q[d->q_head];
            d->q_head = (d->q_head + 1) % EDGE_Q;
            d->q_n--;
            *result = HZ_VS_EDGE;
            return HZ_OK;
        }
        int64_t now = hz_clock_ns();
        if (now >= deadline) {
            *result = HZ_VS_TIMEOUT;
            return HZ_OK;
        }
        int ms = (int)((deadline - now + 999999) / 1000000);
        int queued = 0;
        for (int i = 0; i < d->nbufs; i++)
            queued += d->buf[i].queued;
        if (!d->streaming || !queued) {
            /* Nothing on its way to the display: nothing can come back before the next present. */
            struct timespec ts = { (time_t)(deadline / 1000000000), (long)(deadline % 1000000000) };
            clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
            *result = HZ_VS_TIMEOUT;
            return HZ_OK;
        }
        hz_status_t st;
        if (!vdev_wait(d, POLLOUT, ms, err, &st)) {
            if (st != HZ_OK)
                return st;
            continue;
        }
        struct v4l2_buffer b;
        if (vdev_dq(d, &b, err, &st))
            out_push_edge(d, &b);
        else if (st != HZ_OK)
            return st;
    }
}

static void out_close_sink(hz_sink_t *s)
{
    vdev_t *d = s->impl;
    if (d && d->used)
        vdev_release(d);
    s->impl = NULL;
}

static void out_close_source(hz_vsource_t *s)
{
    /* The device belongs to the sink; the source only reads from it. */
    s->impl = NULL;
}

hz_status_t hz_v4l2_out_open(hz_sink_t *sink, hz_vsource_t *vs, const char *path, hz_pix_fmt_t fmt, int w, int h,
                             const hz_sysio_t *io, hz_error_t *err)
{
    memset(sink, 0, sizeof *sink);
    if (vs)
        memset(vs, 0, sizeof *vs);
    vdev_t *d = NULL;
    for (int i = 0; i < POOL && !d; i++)
        if (!out_pool[i].used)
            d = &out_pool[i];
    if (!d)
        return hz_error_set(err, HZ_E_NO_MEMORY, "v4l2: more than %d outputs open", POOL);
    hz_status_t st = vdev_open(d, path, V4L2_BUF_TYPE_VIDEO_OUTPUT, fmt, w, h, 3, io, err);
    if (st != HZ_OK) {
        vdev_release(d);
        return st;
    }
    sink->impl = d;
    sink->w = d->w;
    sink->h = d->h;
    sink->present = out_present;
    sink->close = out_close_sink;
    snprintf(sink->name, sizeof sink->name, "V4L2 output %s %dx%d %s, %d mmap buffers", path, d->w, d->h,
             hz_pix_name(fmt), d->nbufs);
    if (vs) {
        vs->impl = d;
        vs->live = 1;
        vs->needs_frames = 1;
        vs->next = out_next;
        vs->close = out_close_source;
        snprintf(vs->name, sizeof vs->name, "V4L2 output %s dequeue timestamps", path);
    }
    return HZ_OK;
}

/* ---- capture ---- */

struct hz_v4l2_cap {
    vdev_t d;
};

hz_status_t hz_v4l2_cap_open(hz_v4l2_cap_t **cap, const char *path, hz_pix_fmt_t fmt, int w, int h,
                             const hz_sysio_t *io, hz_error_t *err)
{
    *cap = NULL;
    vdev_t *d = NULL;
    for (int i = 0; i < POOL && !d; i++)
        if (!cap_pool[i].used)
            d = &cap_pool[i];
    if (!d)
        return hz_error_set(err, HZ_E_NO_MEMORY, "v4l2: more than %d captures open", POOL);
    hz_status_t st = vdev_open(d, path, V4L2_BUF_TYPE_VIDEO_CAPTURE, fmt, w, h, 4, io, err);
    for (int i = 0; st == HZ_OK && i < d->nbufs; i++) {
        struct v4l2_buffer b;
        memset(&b, 0, sizeof b);
        b.type = d->type;
        b.memory = V4L2_MEMORY_MMAP;
        b.index = (uint32_t)i;
        if (hz_sysio_ioctl(d->io, d->fd, VIDIOC_QBUF, &b) < 0)
            st = hz_error_set(err, HZ_E_DEVICE, "%s: VIDIOC_QBUF: %s", path, strerror(errno));
        else
            d->buf[i].queued = 1;
    }
    if (st == HZ_OK) {
        int type = (int)d->type;
        if (hz_sysio_ioctl(d->io, d->fd, VIDIOC_STREAMON, &type) < 0)
            st = hz_error_set(err, HZ_E_DEVICE, "%s: VIDIOC_STREAMON: %s", path, strerror(errno));
        else
            d->streaming = 1;
    }
    if (st != HZ_OK) {
        vdev_release(d);
        return st;
    }
    *cap = (hz_v4l2_cap_t *)(void *)d;
    return HZ_OK;
}

hz_status_t hz_v4l2_cap_next(hz_v4l2_cap_t *cap, int timeout_ms, hz_v4l2_frame_t *f, hz_error_t *err)
{
    vdev_t *d = &cap->d;
    int64_t give_up = hz_clock_ns() + (int64_t)timeout_ms * 1000000;
    for (;;) {
        struct v4l2_buffer b;
        hz_status_t st;
        if (vdev_dq(d, &b, err, &st)) {
            f->data = d->buf[b.index].mem;
            f->bytes = b.bytesused;
            f->stride = d->stride;
            f->index = (int)b.index;
            f->sequence = b.sequence;
            f->monotonic = d->ts_kind == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
            f->t_ns = f->monotonic ? tv_ns(&b.timestamp) : hz_clock_ns();
            return HZ_OK;
        }
        if (st != HZ_OK)
            return st;
        int64_t left = give_up - hz_clock_ns();
        if (left <= 0)
            return hz_error_set(err, HZ_E_TIMEOUT, "%s: no captured frame within %d ms", d->path, timeout_ms);
        if (!vdev_wait(d, POLLIN, (int)(left / 1000000) + 1, err, &st) && st != HZ_OK)
            return st;
    }
}

hz_status_t hz_v4l2_cap_release(hz_v4l2_cap_t *cap, int index, hz_error_t *err)
{
    vdev_t *d = &cap->d;
    struct v4l2_buffer b;
    memset(&b, 0, sizeof b);
    b.type = d->type;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = (uint32_t)index;
    if (index < 0 || index >= d->nbufs || hz_sysio_ioctl(d->io, d->fd, VIDIOC_QBUF, &b) < 0)
        return hz_error_set(err, HZ_E_DEVICE, "%s: VIDIOC_QBUF %d: %s", d->path, index, strerror(errno));
    d->buf[index].queued = 1;
    return HZ_OK;
}

void hz_v4l2_cap_close(hz_v4l2_cap_t *cap)
{
    if (cap && cap->d.used)
        vdev_release(&cap->d);
}

void hz_v4l2_cap_size(const hz_v4l2_cap_t *cap, int *w, int *h, size_t *stride)
{
    *w = cap->d.w;
    *h = cap->d.h;
    *stride = cap->d.stride;
}
