/* DRM/KMS display sink and page-flip / vblank v-sync source (see drm.h). */
#define _GNU_SOURCE 1 /* O_CLOEXEC, struct timespec details in libdrm's headers */
#include "drm_port.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include <drm_fourcc.h>
#include <xf86drm.h>
#include <xf86drmMode.h>

#include "clock.h"
#include "threads.h"

#define MAX_BUFS 3
#define RING 64

enum { BUF_FREE = 0, BUF_PENDING, BUF_SCANOUT };

typedef struct drm_ev {
    int64_t t_ns;
    uint64_t sequence;
    int64_t frame_id;
} drm_ev_t;

typedef struct drm_impl {
    int used, fd;
    char card[64], conn_name[48];
    uint32_t conn_id, crtc_id;
    drmModeModeInfo mode;
    drmModeCrtc *saved;
    int nbufs;
    struct {
        uint32_t handle, fb, pitch;
        uint64_t size;
        uint8_t *map;
        int state;
        uint64_t id;
    } buf[MAX_BUFS];
    int flip_pending;
    int seq_api;           /* vblank edges from drmCrtcQueueSequence */
    int seq_queued;
    int64_t shown_id;      /* frame on screen (for vblank edges) */
    drm_ev_t ring[RING];
    uint32_t r_head, r_n;
    hz_drm_stats_t st;
} drm_impl_t;

static drm_impl_t pool[1];

static void push_edge(drm_impl_t *im, int64_t t, uint64_t seq, int64_t id)
{
    /* Drivers without a vblank counter (virtio-gpu) send sequence 0 with every event: only a counting
     * driver's sequence numbers must increase; timestamps always must. */
    int counting = im->seq_api || seq != 0 || im->st.last_sequence != 0;
    if (seq != 0)
        im->st.sequenced++;
    if (im->st.flip_events + im->st.vblank_events > 1 &&
        ((counting && seq <= im->st.last_sequence) || t <= im->st.last_t_ns))
        im->st.out_of_order++;
    im->st.last_sequence = seq;
    im->st.last_t_ns = t;
    if (im->r_n == RING) { /* the oldest is overwritten; the loop drains every refresh, so this means a stall */
        im->r_head = (im->r_head + 1) % RING;
        im->r_n--;
    }
    drm_ev_t *e = &im->ring[(im->r_head + im->r_n) % RING];
    e->t_ns = t;
    e->sequence = seq;
    e->frame_id = id;
    im->r_n++;
}

static void on_flip(int fd, unsigned int seq, unsigned int sec, unsigned int usec, void *data)
{
    (void)fd;
    drm_impl_t *im = &pool[0];
    int b = (int)(intptr_t)data;
    for (int i = 0; i < im->nbufs; i++)
        if (im->buf[i].state == BUF_SCANOUT)
            im->buf[i].state = BUF_FREE;
    if (b >= 0 && b < im->nbufs)
        im->buf[b].state = BUF_SCANOUT;
    im->flip_pending = 0;
    im->st.flip_events++;
    int64_t id = b >= 0 && b < im->nbufs && im->buf[b].id != UINT64_MAX ? (int64_t)im->buf[b].id : -1;
    im->shown_id = id;
    if (!im->seq_api)
        push_edge(im, (int64_t)sec * 1000000000 + (int64_t)usec * 1000, seq, id);
}

static void on_sequence(int fd, uint64_t seq, uint64_t ns, uint64_t data)
{
    (void)fd;
    (void)data;
    drm_impl_t *im = &pool[0];
    im->seq_queued = 0;
    im->st.vblank_events++;
    push_edge(im, (int64_t)ns, seq, im->shown_id);
}

/* Reads the events waiting, or waits for one until deadline (CLOCK_MONOTONIC ns; 0: do not wait). */
static hz_status_t pump(drm_impl_t *im, int64_t deadline, int *got, hz_error_t *err)
{
    *got = 0;
    for (;;) {
        int64_t now = hz_clock_ns();
        int ms = deadline > now ? (int)((deadline - now + 999999) / 1000000) : 0;
        struct pollfd p = { im->fd, POLLIN, 0 };
        int r = poll(&p, 1, ms);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0)
            return hz_error_set(err, HZ_E_DEVICE, "%s: poll: %s", im->card, strerror(errno));
        if (r == 0)
            return HZ_OK;
        drmEventContext ctx;
        memset(&ctx, 0, sizeof ctx);
        ctx.version = 4;
        ctx.page_flip_handler = on_flip;
        ctx.sequence_handler = on_sequence;
        if (drmHandleEvent(im->fd, &ctx) != 0)
            return hz_error_set(err, HZ_E_DEVICE, "%s: reading DRM events failed: %s", im->card, strerror(errno));
        *got = 1;
        return HZ_OK;
    }
}

static hz_status_t queue_vblank(drm_impl_t *im, hz_error_t *err)
{
    if (!im->seq_api || im->seq_queued)
        return HZ_OK;
    uint64_t queued = 0;
    if (drmCrtcQueueSequence(im->fd, im->crtc_id, DRM_CRTC_SEQUENCE_RELATIVE | DRM_CRTC_SEQUENCE_NEXT_ON_MISS, 1,
                             &queued, 0) != 0)
        return hz_error_set(err, HZ_E_DEVICE, "%s: drmCrtcQueueSequence: %s", im->card, strerror(errno));
    im->seq_queued = 1;
    return HZ_OK;
}

/* ---- sink ---- */

static void drm_close(hz_sink_t *s)
{
    drm_impl_t *im = s->impl;
    if (!im)
        return;
    if (im->fd >= 0) {
        int got;
        for (int i = 0; i < 10 && im->flip_pending; i++)
            pump(im, hz_clock_ns() + 100000000, &got, NULL);
        if (im->saved)
            drmModeSetCrtc(im->fd, im->saved->crtc_id, im->saved->buffer_id, im->saved->x, im->saved->y, &im->conn_id,
                           1, &im->saved->mode);
        for (int i = 0; i < im->nbufs; i++) {
            if (im->buf[i].map && im->buf[i].map != MAP_FAILED)
                munmap(im->buf[i].map, im->buf[i].size);
            if (im->buf[i].fb)
                drmModeRmFB(im->fd, im->buf[i].fb);
            if (im->buf[i].handle)
                drmModeDestroyDumbBuffer(im->fd, im->buf[i].handle);
        }
        drmDropMaster(im->fd);
        close(im->fd);
    }
    if (im->saved)
        drmModeFreeCrtc(im->saved);
    memset(im, 0, sizeof *im);
    im->fd = -1;
    s->impl = NULL;
}

/* RGB24 rows as XRGB8888 (hz_threads_convert's form: the copy runs in bands on the pool, as it sits between the
 * render and the flip). */
static void xrgb_rows(const void *ctx, const uint8_t *src, size_t src_stride, uint8_t *dst, size_t dst_stride, int w,
                      int h)
{
    (void)ctx;
    for (int y = 0; y < h; y++) {
        const uint8_t *p = src + (size_t)y * src_stride;
        uint32_t *q = (uint32_t *)(void *)(dst + (size_t)y * dst_stride);
        for (int x = 0; x < w; x++, p += 3)
            q[x] = 0xff000000u | (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
    }
}

static void copy_frame(drm_impl_t *im, int b, const hz_rgb8_image_t *img)
{
    hz_threads_convert(xrgb_rows, NULL, img->rgb, img->stride, im->buf[b].map, im->buf[b].pitch, img->w, img->h);
}

static hz_status_t drm_present(hz_sink_t *s, const hz_rgb8_image_t *img, uint64_t id, hz_error_t *err)
{
    drm_impl_t *im = s->impl;
    if (img->w != s->w || img->h != s->h)
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s: frame %dx%d, mode %dx%d", s->name, img->w, img->h, s->w,
                            s->h);
    int b = -1;
    for (int i = 0; i < im->nbufs && b < 0; i++)
        if (im->buf[i].state == BUF_FREE)
            b = i;
    int64_t limit = hz_clock_ns() + 1000000000;
    while (b < 0 || im->flip_pending) {
        int got;
        if (hz_clock_ns() >= limit)
            return hz_error_set(err, HZ_E_TIMEOUT, "%s: a page flip did not complete within 1 s", s->name);
        hz_status_t st = pump(im, limit, &got, err);
        if (st != HZ_OK)
            return st;
        for (int i = 0; i < im->nbufs && b < 0; i++)
            if (im->buf[i].state == BUF_FREE)
                b = i;
    }
    copy_frame(im, b, img);
    im->buf[b].id = id;
    if (drmModePageFlip(im->fd, im->crtc_id, im->buf[b].fb, DRM_MODE_PAGE_FLIP_EVENT, (void *)(intptr_t)b) != 0)
        return hz_error_set(err, HZ_E_DEVICE, "%s: drmModePageFlip: %s", s->name, strerror(errno));
    im->buf[b].state = BUF_PENDING;
    im->flip_pending = 1;
    im->st.flips++;
    return HZ_OK;
}

/* ---- source ---- */

static hz_status_t drm_next(hz_vsource_t *s, int64_t deadline, hz_edge_t *e, int *result, hz_error_t *err)
{
    drm_impl_t *im = s->impl;
    for (;;) {
        if (im->r_n) {
            drm_ev_t *x = &im->ring[im->r_head];
            im->r_head = (im->r_head + 1) % RING;
            im->r_n--;
            e->t_ns = x->t_ns;
            e->level = 1;
            e->frame_id = x->frame_id;
            *result = HZ_VS_EDGE;
            return HZ_OK;
        }
        hz_status_t st = queue_vblank(im, err);
        if (st != HZ_OK)
            return st;
        if (hz_clock_ns() >= deadline) {
            *result = HZ_VS_TIMEOUT;
            return HZ_OK;
        }
        int got;
        st = pump(im, deadline, &got, err);
        if (st != HZ_OK)
            return st;
    }
}

static void drm_src_close(hz_vsource_t *s)
{
    s->impl = NULL; /* the sink owns the device */
}

/* ---- opening ---- */

static hz_status_t open_card(drm_impl_t *im, const char *want, hz_error_t *err)
{
    char path[64];
    if (want && *want) {
        if (want[0] == '/')
            snprintf(path, sizeof path, "%s", want);
        else if (want[0] >= '0' && want[0] <= '9')
            snprintf(path, sizeof path, "/dev/dri/card%s", want);
        else
            snprintf(path, sizeof path, "/dev/dri/%s", want);
        im->fd = open(path, O_RDWR | O_CLOEXEC);
        snprintf(im->card, sizeof im->card, "%s", path);
        if (im->fd < 0) {
            int e = errno;
            if (e == ENOENT)
                return hz_error_set(err, HZ_E_DEVICE, "DRM card %s: no such device (is a KMS driver loaded? ls "
                                    "/dev/dri)", path);
            if (e == EACCES || e == EPERM)
                return hz_error_set(err, HZ_E_DEVICE, "DRM card %s: permission denied (run as root or join group "
                                    "'video')", path);
            return hz_error_set(err, HZ_E_DEVICE, "DRM card %s: cannot open: %s", path, strerror(e));
        }
        /* Any file opens: only a DRM driver answers DRM_IOCTL_VERSION. */
        drmVersionPtr v = drmGetVersion(im->fd);
        if (!v) {
            close(im->fd);
            im->fd = -1;
            return hz_error_set(err, HZ_E_DEVICE, "DRM card %s: not a DRM device (no DRM driver answers on it; "
                                "cards are /dev/dri/cardN)", path);
        }
        drmFreeVersion(v);
        return HZ_OK;
    }
    for (int n = 0; n < 16; n++) {
        snprintf(path, sizeof path, "/dev/dri/card%d", n);
        int fd = open(path, O_RDWR | O_CLOEXEC);
        if (fd < 0)
            continue;
        drmModeRes *res = drmModeGetResources(fd);
        int connected = 0;
        for (int i = 0; res && i < res->count_connectors && !connected; i++) {
            drmModeConnector *c = drmModeGetConnector(fd, res->connectors[i]);
            connected = c && c->connection == DRM_MODE_CONNECTED && c->count_modes > 0;
            if (c)
                drmModeFreeConnector(c);
        }
        if (res)
            drmModeFreeResources(res);
        if (connected) {
            im->fd = fd;
            snprintf(im->card, sizeof im->card, "%s", path);
            return HZ_OK;
        }
        close(fd);
    }
    return hz_error_set(err, HZ_E_DEVICE, "DRM: no card in /dev/dri/card0..15 with a connected display (is a KMS "
                        "driver loaded?)");
}

static uint32_t mode_mhz(const drmModeModeInfo *m)
{
    if (!m->htotal || !m->vtotal)
        return m->vrefresh * 1000u;
    uint64_t mhz = (uint64_t)m->clock * 1000000ull / ((uint64_t)m->htotal * m->vtotal);
    if (m->flags & DRM_MODE_FLAG_INTERLACE)
        mhz *= 2;
    if (m->flags & DRM_MODE_FLAG_DBLSCAN)
        mhz /= 2;
    return (uint32_t)mhz;
}

static hz_status_t pick_output(drm_impl_t *im, const hz_drm_cfg_t *cfg, hz_error_t *err)
{
    drmModeRes *res = drmModeGetResources(im->fd);
    if (!res)
        return hz_error_set(err, HZ_E_DEVICE, "%s: not a KMS device (drmModeGetResources: %s)", im->card,
                            strerror(errno));
    char list[512] = "";
    size_t ln = 0;
    drmModeConnector *conn = NULL;
    for (int i = 0; i < res->count_connectors && !conn; i++) {
        drmModeConnector *c = drmModeGetConnector(im->fd, res->connectors[i]);
        if (!c)
            continue;
        const char *tn = drmModeGetConnectorTypeName(c->connector_type);
        char name[48];
        snprintf(name, sizeof name, "%s-%u", tn ? tn : "Unknown", c->connector_type_id);
        int connected = c->connection == DRM_MODE_CONNECTED && c->count_modes > 0;
        if (ln < sizeof list)
            ln += (size_t)snprintf(list + ln, sizeof list - ln, "%s%s (id %u, %s)", ln ? ", " : "", name,
                                   c->connector_id, connected ? "connected" : "not connected");
        int named = cfg->connector && *cfg->connector;
        int match = named ? (!strcmp(cfg->connector, name) || (unsigned)atoi(cfg->connector) == c->connector_id)
                          : connected;
        if (match && connected) {
            conn = c;
            snprintf(im->conn_name, sizeof im->conn_name, "%s", name);
        } else {
            if (match && named) {
                hz_status_t st = hz_error_set(err, HZ_E_DEVICE, "%s: connector %s is not connected", im->card, name);
                drmModeFreeConnector(c);
                drmModeFreeResources(res);
                return st;
            }
            drmModeFreeConnector(c);
        }
    }
    if (!conn) {
        hz_status_t st = cfg->connector && *cfg->connector
                             ? hz_error_set(err, HZ_E_DEVICE, "%s: no connector '%s' (there are: %s)", im->card,
                                            cfg->connector, list[0] ? list : "none")
                             : hz_error_set(err, HZ_E_DEVICE, "%s: no connected connector (there are: %s)", im->card,
                                            list[0] ? list : "none");
        drmModeFreeResources(res);
        return st;
    }
    im->conn_id = conn->connector_id;
    /* the mode */
    int found = -1;
    char modes[512] = "";
    size_t mn = 0;
    for (int i = 0; i < conn->count_modes; i++) {
        const drmModeModeInfo *m = &conn->modes[i];
        uint32_t mhz = mode_mhz(m);
        if (mn < sizeof modes)
            mn += (size_t)snprintf(modes + mn, sizeof modes - mn, "%s%ux%u@%.2f", mn ? " " : "", m->hdisplay,
                                   m->vdisplay, mhz / 1000.0);
        if (found >= 0)
            continue;
        if (cfg->w) {
            if (m->hdisplay == cfg->w && m->vdisplay == cfg->h &&
                (!cfg->millihertz || (mhz > cfg->millihertz ? mhz - cfg->millihertz : cfg->millihertz - mhz) <= 500))
                found = i;
        } else if (m->type & DRM_MODE_TYPE_PREFERRED) {
            found = i;
        }
    }
    if (found < 0 && !cfg->w)
        found = 0;
    if (found < 0) {
        char want[48];
        if (cfg->millihertz)
            snprintf(want, sizeof want, "%dx%d@%.3f", cfg->w, cfg->h, cfg->millihertz / 1000.0);
        else
            snprintf(want, sizeof want, "%dx%d", cfg->w, cfg->h);
        hz_status_t st = hz_error_set(err, HZ_E_DEVICE, "%s: %s does not offer %s (it offers: %s)", im->card,
                                      im->conn_name, want, modes);
        drmModeFreeConnector(conn);
        drmModeFreeResources(res);
        return st;
    }
    im->mode = conn->modes[found];
    /* the CRTC: the one the connector's encoder drives now, else the first any of its encoders can drive */
    im->crtc_id = 0;
    drmModeEncoder *enc = conn->encoder_id ? drmModeGetEncoder(im->fd, conn->encoder_id) : NULL;
    if (enc && enc->crtc_id)
        im->crtc_id = enc->crtc_id;
    if (enc)
        drmModeFreeEncoder(enc);
    for (int i = 0; i < conn->count_encoders && !im->crtc_id; i++) {
        drmModeEncoder *e = drmModeGetEncoder(im->fd, conn->encoders[i]);
        for (int k = 0; e && k < res->count_crtcs && !im->crtc_id; k++)
            if (e->possible_crtcs & (1u << k))
                im->crtc_id = res->crtcs[k];
        if (e)
            drmModeFreeEncoder(e);
    }
    drmModeFreeConnector(conn);
    drmModeFreeResources(res);
    if (!im->crtc_id)
        return hz_error_set(err, HZ_E_DEVICE, "%s: no CRTC can drive %s", im->card, im->conn_name);
    return HZ_OK;
}

static hz_status_t make_buffers(drm_impl_t *im, hz_error_t *err)
{
    for (int i = 0; i < im->nbufs; i++) {
        uint32_t w = im->mode.hdisplay, h = im->mode.vdisplay;
        if (drmModeCreateDumbBuffer(im->fd, w, h, 32, 0, &im->buf[i].handle, &im->buf[i].pitch, &im->buf[i].size))
            return hz_error_set(err, HZ_E_DEVICE, "%s: cannot create a %ux%u dumb buffer: %s", im->card, w, h,
                                strerror(errno));
        uint32_t handles[4] = { im->buf[i].handle }, pitches[4] = { im->buf[i].pitch }, offsets[4] = { 0 };
        if (drmModeAddFB2(im->fd, w, h, DRM_FORMAT_XRGB8888, handles, pitches, offsets, &im->buf[i].fb, 0))
            return hz_error_set(err, HZ_E_DEVICE, "%s: drmModeAddFB2 (XRGB8888 %ux%u): %s", im->card, w, h,
                                strerror(errno));
        uint64_t off = 0;
        if (drmModeMapDumbBuffer(im->fd, im->buf[i].handle, &off))
            return hz_error_set(err, HZ_E_DEVICE, "%s: cannot map a dumb buffer: %s", im->card, strerror(errno));
        im->buf[i].map = mmap(NULL, im->buf[i].size, PROT_READ | PROT_WRITE, MAP_SHARED, im->fd, (off_t)off);
        if (im->buf[i].map == MAP_FAILED) {
            im->buf[i].map = NULL;
            return hz_error_set(err, HZ_E_DEVICE, "%s: mmap of a dumb buffer: %s", im->card, strerror(errno));
        }
        memset(im->buf[i].map, 0, im->buf[i].size);
        im->buf[i].id = UINT64_MAX;
    }
    return HZ_OK;
}

hz_status_t hz_drm_sink_open(hz_sink_t *sink, hz_vsource_t *vs, const hz_drm_cfg_t *cfg, hz_error_t *err)
{
    memset(sink, 0, sizeof *sink);
    if (vs)
        memset(vs, 0, sizeof *vs);
    drm_impl_t *im = &pool[0];
    if (im->used)
        return hz_error_set(err, HZ_E_NO_MEMORY, "drm: one display at a time");
    memset(im, 0, sizeof *im);
    im->fd = -1;
    im->nbufs = cfg->buffers ? cfg->buffers : 2;
    if (im->nbufs < 2 || im->nbufs > MAX_BUFS)
        return hz_error_set(err, HZ_E_INVALID_ARG, "drm: %d buffers (2 or 3)", im->nbufs);
    hz_status_t st = open_card(im, cfg->card, err);
    if (st != HZ_OK)
        return st;
    im->used = 1;
    sink->impl = im;
    sink->close = drm_close;
    snprintf(sink->name, sizeof sink->name, "%s", im->card);
    uint64_t cap = 0;
    if (drmGetCap(im->fd, DRM_CAP_DUMB_BUFFER, &cap) || !cap) {
        hz_error_set(err, HZ_E_UNSUPPORTED, "DRM card %s: the driver has no dumb buffers", im->card);
        drm_close(sink);
        return HZ_E_UNSUPPORTED;
    }
    if (!drmIsMaster(im->fd) && drmSetMaster(im->fd) != 0) {
        int e = errno;
        char card[64];
        snprintf(card, sizeof card, "%s", im->card);
        drm_close(sink);
        return hz_error_set(err, HZ_E_DEVICE, "DRM card %s: cannot become DRM master (%s): another process (a "
                            "compositor, X, another hzrt) holds the display; stop it or switch to a free VT",
                            card, strerror(e));
    }
    cap = 0;
    if (drmGetCap(im->fd, DRM_CAP_TIMESTAMP_MONOTONIC, &cap) || !cap) {
        hz_error_set(err, HZ_E_UNSUPPORTED, "DRM card %s: the driver does not stamp events with CLOCK_MONOTONIC",
                     im->card);
        drm_close(sink);
        return HZ_E_UNSUPPORTED;
    }
    if ((st = pick_output(im, cfg, err)) != HZ_OK || (st = make_buffers(im, err)) != HZ_OK) {
        drm_close(sink);
        return st;
    }
    im->saved = drmModeGetCrtc(im->fd, im->crtc_id);
    if (drmModeSetCrtc(im->fd, im->crtc_id, im->buf[0].fb, 0, 0, &im->conn_id, 1, &im->mode) != 0) {
        int e = errno;
        hz_status_t r = hz_error_set(err, HZ_E_DEVICE, "%s: cannot set %ux%u on %s: %s", im->card, im->mode.hdisplay,
                                     im->mode.vdisplay, im->conn_name, strerror(e));
        drm_close(sink);
        return r;
    }
    im->buf[0].state = BUF_SCANOUT;
    im->shown_id = -1;
    uint64_t seq = 0, ns = 0;
    im->seq_api = drmCrtcGetSequence(im->fd, im->crtc_id, &seq, &ns) == 0;
    im->st.has_sequence_api = im->seq_api;
    sink->w = im->mode.hdisplay;
    sink->h = im->mode.vdisplay;
    sink->present = drm_present;
    snprintf(sink->name, sizeof sink->name, "DRM %.40s %.32s %ux%u@%.2f, %d dumb XRGB8888 buffers, page flips", im->card,
             im->conn_name, im->mode.hdisplay, im->mode.vdisplay, mode_mhz(&im->mode) / 1000.0, im->nbufs);
    if (vs) {
        vs->impl = im;
        vs->live = 1;
        vs->needs_frames = !im->seq_api;
        vs->next = drm_next;
        vs->close = drm_src_close;
        snprintf(vs->name, sizeof vs->name, "DRM %.40s %.32s: %s", im->card, im->conn_name,
                 im->seq_api ? "vblank events (drmCrtcQueueSequence, ns)" : "page-flip events (us)");
    }
    return HZ_OK;
}

void hz_drm_stats(const hz_sink_t *sink, hz_drm_stats_t *st)
{
    const drm_impl_t *im = sink->impl;
    if (im)
        *st = im->st;
    else
        memset(st, 0, sizeof *st);
}

hz_status_t hz_drm_parse_spec(const char *spec, hz_drm_cfg_t *cfg, char *buf, size_t cap, hz_error_t *err)
{
    memset(cfg, 0, sizeof *cfg);
    if ((size_t)snprintf(buf, cap, "%s", spec ? spec : "") >= cap)
        return hz_error_set(err, HZ_E_INVALID_ARG, "--sink drm: '%s' is too long", spec);
    char *card = buf, *conn = strchr(buf, ':'), *mode = NULL;
    if (conn) {
        *conn++ = '\0';
        mode = strchr(conn, ':');
        if (mode)
            *mode++ = '\0';
    }
    cfg->card = card;
    cfg->connector = conn ? conn : "";
    if (mode && *mode) {
        int w = 0, h = 0, used = 0;
        double hz = 0;
        char tail = 0;
        int n = sscanf(mode, "%dx%d%n", &w, &h, &used);
        if (n == 2 && mode[used] == '@' && sscanf(mode + used + 1, "%lf%c", &hz, &tail) != 1)
            n = 0;
        if (n != 2 || w < 1 || h < 1 || w > 16384 || h > 16384 || (mode[used] && mode[used] != '@') || hz < 0 ||
            hz > 1000)
            return hz_error_set(err, HZ_E_INVALID_ARG, "--sink drm: mode '%s' is not WxH or WxH@HZ (e.g. 1920x1080@60)",
                                mode);
        cfg->w = w;
        cfg->h = h;
        cfg->millihertz = (uint32_t)(hz * 1000 + 0.5);
    }
    return HZ_OK;
}
