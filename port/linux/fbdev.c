/* fbdev display sink and FBIO_WAITFORVSYNC v-sync source (see devices.h). */
#include <errno.h>
#include <fcntl.h>
#include <linux/fb.h>
#include <linux/kd.h>
#include <stdint.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "clock.h"
#include "devices.h"
#include "threads.h"

#include <linux/types.h>
#include <sys/ioctl.h>
#ifndef FBIO_WAITFORVSYNC
#define FBIO_WAITFORVSYNC _IOW('F', 0x20, __u32)
#endif

#define POOL 2

static hz_status_t open_error(const char *path, int e, hz_error_t *err)
{
    if (e == ENOENT)
        return hz_error_set(err, HZ_E_DEVICE, "%s: no such device node (is the display driver loaded?)", path);
    if (e == EACCES || e == EPERM)
        return hz_error_set(err, HZ_E_DEVICE, "%s: permission denied (run as root or join group 'video')", path);
    return hz_error_set(err, HZ_E_DEVICE, "%s: cannot open: %s", path, strerror(e));
}

/* ---- sink ---- */

typedef struct fb_impl {
    int used;
    const hz_sysio_t *io;
    int fd;
    char path[128];
    struct fb_var_screeninfo var, orig;
    struct fb_fix_screeninfo fix;
    hz_fb_layout_t layout;
    uint8_t *mem;
    size_t mem_len;
    int buffers, back;
    int tty;          /* the console, switched to graphics mode while we own the display (-1: not) */
    int tty_mode;
} fb_impl_t;

static fb_impl_t fb_pool[POOL];

static void fb_close(hz_sink_t *s)
{
    fb_impl_t *im = s->impl;
    if (!im)
        return;
    if (im->mem && im->mem != MAP_FAILED)
        im->io->munmap(im->mem, im->mem_len);
    if (im->tty >= 0) {
        hz_sysio_ioctl(im->io, im->tty, KDSETMODE, (void *)(uintptr_t)im->tty_mode);
        im->io->close(im->tty);
        im->tty = -1;
    }
    if (im->fd >= 0) {
        if (im->buffers == 2) {
            struct fb_var_screeninfo v = im->var;
            v.yoffset = im->orig.yoffset;
            hz_sysio_ioctl(im->io, im->fd, FBIOPAN_DISPLAY, &v);
        }
        im->io->close(im->fd);
    }
    im->used = 0;
    s->impl = NULL;
}

static void pack_rows(const void *layout, const uint8_t *src, size_t src_stride, uint8_t *dst, size_t dst_stride,
                      int w, int h)
{
    hz_fb_pack(layout, src, src_stride, dst, dst_stride, w, h);
}

static hz_status_t fb_present(hz_sink_t *s, const hz_rgb8_image_t *img, uint64_t id, hz_error_t *err)
{
    (void)id;
    fb_impl_t *im = s->impl;
    int w = img->w < (int)im->var.xres ? img->w : (int)im->var.xres;
    int h = img->h < (int)im->var.yres ? img->h : (int)im->var.yres;
    /* Double-buffered: draw into the page not on screen, then pan to it at the next v-blank.
     * Single-buffered: draw where the screen is. */
    size_t row0 = im->buffers == 2 ? (size_t)im->back * im->var.yres : im->var.yoffset;
    uint8_t *dst = im->mem + row0 * im->fix.line_length + (size_t)im->var.xoffset * (size_t)(im->layout.bpp / 8);
    hz_threads_convert(pack_rows, &im->layout, img->rgb, img->stride, dst, im->fix.line_length, w, h);
    if (im->buffers == 2) {
        struct fb_var_screeninfo v = im->var;
        v.yoffset = (uint32_t)row0;
        v.activate = FB_ACTIVATE_VBL;
        if (hz_sysio_ioctl(im->io, im->fd, FBIOPAN_DISPLAY, &v) < 0)
            return hz_error_set(err, HZ_E_DEVICE, "%s: FBIOPAN_DISPLAY to line %zu failed: %s", im->path, row0,
                                strerror(errno));
        im->back ^= 1;
    }
    return HZ_OK;
}

hz_status_t hz_fbdev_sink_open(hz_sink_t *s, const char *path, const hz_sysio_t *io, hz_error_t *err)
{
    memset(s, 0, sizeof *s);
    if (!io)
        io = &hz_sysio_linux;
    fb_impl_t *im = NULL;
    for (int i = 0; i < POOL && !im; i++)
        if (!fb_pool[i].used)
            im = &fb_pool[i];
    if (!im)
        return hz_error_set(err, HZ_E_NO_MEMORY, "fbdev: more than %d framebuffers open", POOL);
    memset(im, 0, sizeof *im);
    im->io = io;
    im->tty = -1;
    snprintf(im->path, sizeof im->path, "%s", path);
    im->fd = io->open(path, O_RDWR | O_CLOEXEC);
    if (im->fd < 0)
        return open_error(path, errno, err);
    im->used = 1;
    s->impl = im;
    s->close = fb_close;
    hz_status_t st = HZ_OK;
    if (hz_sysio_ioctl(io, im->fd, FBIOGET_FSCREENINFO, &im->fix) < 0 ||
        hz_sysio_ioctl(io, im->fd, FBIOGET_VSCREENINFO, &im->var) < 0) {
        st = hz_error_set(err, HZ_E_DEVICE, "%s: not a framebuffer device (%s)", path, strerror(errno));
        goto fail;
    }
    im->orig = im->var;
    if (im->fix.type != FB_TYPE_PACKED_PIXELS ||
        (im->fix.visual != FB_VISUAL_TRUECOLOR && im->fix.visual != FB_VISUAL_DIRECTCOLOR)) {
        st = hz_error_set(err, HZ_E_UNSUPPORTED,
                          "%s: unsupported pixel format: framebuffer type %u visual %u (packed true colour only)",
                          path, im->fix.type, im->fix.visual);
        goto fail;
    }
    if (im->var.red.msb_right || im->var.green.msb_right || im->var.blue.msb_right) {
        st = hz_error_set(err, HZ_E_UNSUPPORTED, "%s: unsupported pixel format: bit-reversed (msb_right) channels",
                          path);
        goto fail;
    }
    hz_fb_layout_t l = { (int)im->var.bits_per_pixel, (int)im->var.red.offset, (int)im->var.red.length,
                         (int)im->var.green.offset, (int)im->var.green.length, (int)im->var.blue.offset,
                         (int)im->var.blue.length };
    st = hz_fb_layout_check(&l, err);
    if (st != HZ_OK) {
        char prefix[160];
        snprintf(prefix, sizeof prefix, "%s: unsupported pixel format", path);
        hz_error_prefix(err, prefix);
        goto fail;
    }
    im->layout = l;
    if (im->var.xres < 16 || im->var.yres < 16 || im->fix.line_length < im->var.xres * (im->var.bits_per_pixel / 8)) {
        st = hz_error_set(err, HZ_E_DEVICE, "%s: implausible mode %ux%u, %u bytes per line", path, im->var.xres,
                          im->var.yres, im->fix.line_length);
        goto fail;
    }
    /* Two frames in the virtual screen and a driver that pans: page flips. Ask for the room if needed. */
    im->buffers = 1;
    if (im->var.yres_virtual < 2 * im->var.yres) {
        struct fb_var_screeninfo v = im->var;
        v.yres_virtual = 2 * im->var.yres;
        v.activate = FB_ACTIVATE_NOW;
        if (hz_sysio_ioctl(io, im->fd, FBIOPUT_VSCREENINFO, &v) == 0) {
            hz_sysio_ioctl(io, im->fd, FBIOGET_VSCREENINFO, &im->var);
            hz_sysio_ioctl(io, im->fd, FBIOGET_FSCREENINFO, &im->fix);
        }
    }
    if (im->var.yres_virtual >= 2 * im->var.yres && im->fix.ypanstep != 0) {
        struct fb_var_screeninfo v = im->var;
        v.yoffset = 0;
        if (hz_sysio_ioctl(io, im->fd, FBIOPAN_DISPLAY, &v) == 0)
            im->buffers = 2;
    }
    /* Map the whole virtual screen the driver offers (bounded by its video memory), and check that the
     * pages we draw lie inside it. */
    size_t rows_needed = im->buffers == 2 ? 2 * (size_t)im->var.yres : (size_t)im->var.yoffset + im->var.yres;
    size_t rows = im->var.yres_virtual > rows_needed ? im->var.yres_virtual : rows_needed;
    im->mem_len = (size_t)im->fix.line_length * rows;
    if (im->fix.smem_len && im->mem_len > im->fix.smem_len)
        im->mem_len = im->fix.smem_len;
    if (im->mem_len < (size_t)im->fix.line_length * rows_needed ||
        im->var.xoffset + im->var.xres > im->fix.line_length / (im->var.bits_per_pixel / 8)) {
        if (im->buffers == 2) {
            im->buffers = 1;
            rows_needed = (size_t)im->var.yoffset + im->var.yres;
        }
        if (im->mem_len < (size_t)im->fix.line_length * rows_needed ||
            im->var.xoffset + im->var.xres > im->fix.line_length / (im->var.bits_per_pixel / 8)) {
            st = hz_error_set(err, HZ_E_DEVICE, "%s: video memory of %zu bytes does not hold the %ux%u frame at "
                              "offset %u,%u", path, im->mem_len, im->var.xres, im->var.yres, im->var.xoffset,
                              im->var.yoffset);
            goto fail;
        }
    }
    im->mem = io->mmap(NULL, im->mem_len, PROT_READ | PROT_WRITE, MAP_SHARED, im->fd, 0);
    if (im->mem == MAP_FAILED) {
        im->mem = NULL;
        st = hz_error_set(err, HZ_E_DEVICE, "%s: mmap of %zu bytes failed: %s", path, im->mem_len, strerror(errno));
        goto fail;
    }
    /* The framebuffer console would keep drawing its text and blinking cursor over our frames: put the VT in
     * graphics mode while we own the display (best effort; restored on close). */
    const char *console = "console left as it was (no access to /dev/tty0)";
    int tty = io->open("/dev/tty0", O_RDWR | O_CLOEXEC);
    if (tty >= 0) {
        int mode = KD_TEXT;
        if (hz_sysio_ioctl(io, tty, KDGETMODE, &mode) == 0 &&
            hz_sysio_ioctl(io, tty, KDSETMODE, (void *)(uintptr_t)KD_GRAPHICS) == 0) {
            im->tty = tty;
            im->tty_mode = mode;
            console = "console in graphics mode";
        } else {
            io->close(tty);
            console = "console left as it was (KDSETMODE refused)";
        }
    }
    /* The back buffer is the one not on screen. */
    im->back = im->buffers == 2 && im->var.yoffset == 0 ? 1 : 0;
    s->w = (int)im->var.xres;
    s->h = (int)im->var.yres;
    s->present = fb_present;
    snprintf(s->name, sizeof s->name, "fbdev %s %ux%u %u bpp (r%u@%u g%u@%u b%u@%u), %s; %s", path, im->var.xres,
             im->var.yres, im->var.bits_per_pixel, im->var.red.length, im->var.red.offset, im->var.green.length,
             im->var.green.offset, im->var.blue.length, im->var.blue.offset,
             im->buffers == 2 ? "page flips by panning" : "single-buffered (no panning: may tear)", console);
    return HZ_OK;
fail:
    fb_close(s);
    return st;
}

/* ---- FBIO_WAITFORVSYNC source ---- */

typedef struct vs_msg {
    int64_t t_ns;
    int err; /* errno of a failed wait, 0 for an edge */
} vs_msg_t;

typedef struct fbvs_impl {
    int used;
    const hz_sysio_t *io;
    int fd;
    int pipe_r, pipe_w;
    char path[128];
    pthread_t thread;
    int thread_started;
    volatile int stop;
    volatile int exited;
} fbvs_impl_t;

static fbvs_impl_t fbvs_pool[POOL];

static void *waiter(void *arg)
{
    fbvs_impl_t *im = arg;
    while (!im->stop) {
        __u32 crtc = 0;
        vs_msg_t m;
        int r = hz_sysio_ioctl(im->io, im->fd, FBIO_WAITFORVSYNC, &crtc);
        m.t_ns = hz_clock_ns();
        m.err = r < 0 ? errno : 0;
        if (write(im->pipe_w, &m, sizeof m) != (ssize_t)sizeof m || m.err)
            break;
    }
    im->exited = 1;
    return NULL;
}

static hz_status_t fbvs_next(hz_vsource_t *s, int64_t deadline, hz_edge_t *e, int *result, hz_error_t *err)
{
    fbvs_impl_t *im = s->impl;
    for (;;) {
        int64_t now = hz_clock_ns();
        int64_t wait = deadline - now;
        int ms = wait <= 0 ? 0 : (int)((wait + 999999) / 1000000);
        struct pollfd p = { im->pipe_r, POLLIN, 0 };
        int r = poll(&p, 1, ms);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0)
            return hz_error_set(err, HZ_E_IO, "%s: poll: %s", im->path, strerror(errno));
        if (r == 0) {
            *result = HZ_VS_TIMEOUT;
            return HZ_OK;
        }
        vs_msg_t m;
        ssize_t n = read(im->pipe_r, &m, sizeof m);
        if (n != (ssize_t)sizeof m)
            return hz_error_set(err, HZ_E_IO, "%s: v-sync waiter stopped", im->path);
        if (m.err == ENOTTY || m.err == EINVAL || m.err == EOPNOTSUPP)
            return hz_error_set(err, HZ_E_UNSUPPORTED,
                                "%s: the driver does not implement FBIO_WAITFORVSYNC (%s): use --source gpio or sim",
                                im->path, strerror(m.err));
        if (m.err)
            return hz_error_set(err, HZ_E_DEVICE, "%s: FBIO_WAITFORVSYNC failed: %s", im->path, strerror(m.err));
        e->t_ns = m.t_ns;
        e->level = 1;
        e->frame_id = -1;
        *result = HZ_VS_EDGE;
        return HZ_OK;
    }
}

static void fbvs_close(hz_vsource_t *s)
{
    fbvs_impl_t *im = s->impl;
    if (!im)
        return;
    if (im->thread_started) {
        im->stop = 1;
        /* A waiting ioctl returns at the next v-sync; one that never does (a dead display) cannot be
         * interrupted portably, so give it 200 ms and then leave the thread detached. */
        for (int i = 0; i < 200 && !im->exited; i++) {
            struct timespec ts = { 0, 1000000 };
            nanosleep(&ts, NULL);
        }
        if (im->exited) {
            pthread_join(im->thread, NULL);
        } else {
            pthread_detach(im->thread);
            s->impl = NULL;
            return; /* the slot stays taken: the thread still uses it */
        }
    }
    if (im->pipe_r >= 0)
        close(im->pipe_r);
    if (im->pipe_w >= 0)
        close(im->pipe_w);
    if (im->fd >= 0)
        im->io->close(im->fd);
    im->used = 0;
    s->impl = NULL;
}

hz_status_t hz_fbdev_vsource_open(hz_vsource_t *s, const char *path, const hz_sysio_t *io, hz_error_t *err)
{
    memset(s, 0, sizeof *s);
    if (!io)
        io = &hz_sysio_linux;
    fbvs_impl_t *im = NULL;
    for (int i = 0; i < POOL && !im; i++)
        if (!fbvs_pool[i].used)
            im = &fbvs_pool[i];
    if (!im)
        return hz_error_set(err, HZ_E_NO_MEMORY, "fbdev v-sync: more than %d open", POOL);
    memset(im, 0, sizeof *im);
    im->io = io;
    im->pipe_r = im->pipe_w = -1;
    snprintf(im->path, sizeof im->path, "%s", path);
    im->fd = io->open(path, O_RDWR | O_CLOEXEC);
    if (im->fd < 0)
        return open_error(path, errno, err);
    im->used = 1;
    s->impl = im;
    s->close = fbvs_close;
    struct fb_fix_screeninfo fix;
    if (hz_sysio_ioctl(io, im->fd, FBIOGET_FSCREENINFO, &fix) < 0) {
        int e = errno;
        fbvs_close(s);
        return hz_error_set(err, HZ_E_DEVICE, "%s: not a framebuffer device (%s)", path, strerror(e));
    }
    int fds[2];
    if (pipe(fds) != 0) {
        int e = errno;
        fbvs_close(s);
        return hz_error_set(err, HZ_E_IO, "%s: pipe: %s", path, strerror(e));
    }
    im->pipe_r = fds[0];
    im->pipe_w = fds[1];
    if (pthread_create(&im->thread, NULL, waiter, im) != 0) {
        fbvs_close(s);
        return hz_error_set(err, HZ_E_INTERNAL, "%s: cannot start the v-sync waiter thread", path);
    }
    im->thread_started = 1;
    s->live = 1;
    s->next = fbvs_next;
    snprintf(s->name, sizeof s->name, "fbdev FBIO_WAITFORVSYNC on %s (user-space timestamps)", path);
    return HZ_OK;
}
