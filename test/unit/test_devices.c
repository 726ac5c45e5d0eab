/*
 * Display devices against fake kernels (the sysio table): fbdev at 16/24/32 bpp with and without panning,
 * FBIO_WAITFORVSYNC present, absent and silent; V4L2 output format negotiation, conversion, and dequeue
 * timestamps naming the frame shown; missing nodes and wrong device kinds. The real kernel paths run in the
 * VM tier (make vmtest).
 * hz-test: devices (needs the fbdev or V4L2 port)
 */
#include "hz_test.h"

#include <errno.h>
#include <linux/fb.h>
#include <linux/videodev2.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <time.h>

#include "devices.h"
#include "threads.h"
#include "hz/frameloop.h"
#include "vsource.h"
#include "hz/hz.h"

#ifndef FBIO_WAITFORVSYNC
#define FBIO_WAITFORVSYNC _IOW('F', 0x20, __u32)
#endif

static void sleep_ms(int ms)
{
    struct timespec ts = { ms / 1000, (long)(ms % 1000) * 1000000 };
    nanosleep(&ts, NULL);
}

/* ---------------------------------------------------------------------------------------------------- */
/* A fake framebuffer */

typedef struct fake_fb {
    struct fb_var_screeninfo var;
    struct fb_fix_screeninfo fix;
    int can_pan, can_grow, vsync_mode; /* vsync: 0 ENOTTY, 1 every 2 ms, 2 never */
    int pans, last_pan;
    volatile int release;
} fake_fb_t;

static fake_fb_t fb;
static uint8_t fb_mem[4 << 20];

static void fake_fb_setup(int bpp, int w, int h, int yvirt, int can_pan, int can_grow)
{
    memset(&fb, 0, sizeof fb);
    fb.var.xres = fb.var.xres_virtual = (uint32_t)w;
    fb.var.yres = (uint32_t)h;
    fb.var.yres_virtual = (uint32_t)yvirt;
    fb.var.bits_per_pixel = (uint32_t)bpp;
    if (bpp == 16) {
        fb.var.red = (struct fb_bitfield){ 11, 5, 0 };
        fb.var.green = (struct fb_bitfield){ 5, 6, 0 };
        fb.var.blue = (struct fb_bitfield){ 0, 5, 0 };
    } else if (bpp == 24) {
        fb.var.red = (struct fb_bitfield){ 0, 8, 0 };
        fb.var.green = (struct fb_bitfield){ 8, 8, 0 };
        fb.var.blue = (struct fb_bitfield){ 16, 8, 0 };
    } else if (bpp == 32) {
        fb.var.red = (struct fb_bitfield){ 16, 8, 0 };
        fb.var.green = (struct fb_bitfield){ 8, 8, 0 };
        fb.var.blue = (struct fb_bitfield){ 0, 8, 0 };
    } else {
        fb.var.red = (struct fb_bitfield){ 0, 8, 0 };
        fb.var.green = (struct fb_bitfield){ 0, 8, 0 };
        fb.var.blue = (struct fb_bitfield){ 0, 8, 0 };
    }
    fb.fix.type = FB_TYPE_PACKED_PIXELS;
    fb.fix.visual = bpp == 8 ? FB_VISUAL_PSEUDOCOLOR : FB_VISUAL_TRUECOLOR;
    fb.fix.line_length = (uint32_t)(w * bpp / 8 + 64); /* padded rows, as real drivers do */
    fb.fix.smem_len = sizeof fb_mem;
    fb.fix.ypanstep = 1;
    fb.can_pan = can_pan;
    fb.can_grow = can_grow;
    memset(fb_mem, 0x55, sizeof fb_mem);
}

static int fb_open(const char *path, int flags)
{
    (void)flags;
    if (!strcmp(path, "/fake/fb"))
        return 100;
    errno = ENOENT;
    return -1;
}

static int fb_close(int fd)
{
    (void)fd;
    return 0;
}

static int fb_ioctl(int fd, unsigned long req, void *arg)
{
    (void)fd;
    switch (req) {
    case FBIOGET_FSCREENINFO: memcpy(arg, &fb.fix, sizeof fb.fix); return 0;
    case FBIOGET_VSCREENINFO: memcpy(arg, &fb.var, sizeof fb.var); return 0;
    case FBIOPUT_VSCREENINFO: {
        const struct fb_var_screeninfo *v = arg;
        if (!fb.can_grow) {
            errno = EINVAL;
            return -1;
        }
        fb.var.yres_virtual = v->yres_virtual;
        return 0;
    }
    case FBIOPAN_DISPLAY: {
        const struct fb_var_screeninfo *v = arg;
        if (!fb.can_pan || v->yoffset + fb.var.yres > fb.var.yres_virtual) {
            errno = EINVAL;
            return -1;
        }
        fb.var.yoffset = v->yoffset;
        fb.pans++;
        fb.last_pan = (int)v->yoffset;
        return 0;
    }
    case FBIO_WAITFORVSYNC:
        if (fb.vsync_mode == 0) {
            errno = ENOTTY;
            return -1;
        }
        if (fb.vsync_mode == 1) {
            sleep_ms(2);
            return 0;
        }
        while (!fb.release)
            sleep_ms(1);
        return 0;
    default: errno = ENOTTY; return -1;
    }
}

static void *fb_mmap(void *addr, size_t len, int prot, int flags, int fd, off_t off)
{
    (void)addr;
    (void)prot;
    (void)flags;
    (void)fd;
    if (off != 0 || len > sizeof fb_mem) {
        errno = EINVAL;
        return MAP_FAILED;
    }
    return fb_mem;
}

static int fb_munmap(void *addr, size_t len)
{
    (void)addr;
    (void)len;
    return 0;
}

static const hz_sysio_t fake_fb_io = { fb_open, fb_close, fb_ioctl, fb_mmap, fb_munmap, poll };

#define W 96
#define H 40
static uint8_t rgb[W * H * 3], expect[4 << 20];

static void check_fb_frame(const hz_fb_layout_t *l, size_t row0, uint64_t id)
{
    hz_testpattern_draw(rgb, W * 3, W, H, id);
    memset(expect, 0x55, (size_t)fb.fix.line_length * H);
    hz_fb_pack(l, rgb, W * 3, expect, fb.fix.line_length, W, H);
    assert_memory_equal(fb_mem + row0 * fb.fix.line_length, expect, (size_t)fb.fix.line_length * H);
}

static void present(hz_sink_t *s, uint64_t id)
{
    hz_error_t err;
    hz_testpattern_draw(rgb, W * 3, W, H, id);
    hz_rgb8_image_t img = { rgb, W, H, W * 3 };
    assert_int_equal(s->present(s, &img, id, &err), HZ_OK);
}

static void test_fbdev_16bpp_page_flips(void **state)
{
    (void)state;
    hz_error_t err;
    hz_sink_t s;
    fake_fb_setup(16, W, H, H, 1, 1); /* the driver grows the virtual screen on request */
    assert_int_equal(hz_fbdev_sink_open(&s, "/fake/fb", &fake_fb_io, &err), HZ_OK);
    assert_int_equal(s.w, W);
    assert_int_equal(s.h, H);
    assert_non_null(strstr(s.name, "16 bpp (r5@11 g6@5 b5@0), page flips by panning"));
    hz_fb_layout_t l = { 16, 11, 5, 5, 6, 0, 5 };
    present(&s, 0);
    assert_int_equal(fb.last_pan, H); /* drawn into the second page, then shown */
    check_fb_frame(&l, H, 0);
    present(&s, 1);
    assert_int_equal(fb.last_pan, 0);
    check_fb_frame(&l, 0, 1);
    present(&s, 2);
    assert_int_equal(fb.last_pan, H);
    check_fb_frame(&l, H, 2);
    hz_sink_close(&s);
    assert_int_equal(fb.var.yoffset, 0); /* the original offset is back */
}

static void test_fbdev_24_and_32bpp(void **state)
{
    (void)state;
    hz_error_t err;
    hz_sink_t s;
    /* 24 bpp, the driver neither grows nor pans: single-buffered, and it says so. */
    fake_fb_setup(24, W, H, H, 0, 0);
    assert_int_equal(hz_fbdev_sink_open(&s, "/fake/fb", &fake_fb_io, &err), HZ_OK);
    assert_non_null(strstr(s.name, "single-buffered (no panning: may tear)"));
    present(&s, 7);
    hz_fb_layout_t l24 = { 24, 0, 8, 8, 8, 16, 8 };
    check_fb_frame(&l24, 0, 7);
    assert_int_equal(fb.pans, 0);
    hz_sink_close(&s);
    /* 32 bpp XRGB with room for two pages already. */
    fake_fb_setup(32, W, H, 2 * H, 1, 0);
    assert_int_equal(hz_fbdev_sink_open(&s, "/fake/fb", &fake_fb_io, &err), HZ_OK);
    present(&s, 9);
    hz_fb_layout_t l32 = { 32, 16, 8, 8, 8, 0, 8 };
    check_fb_frame(&l32, H, 9);
    hz_sink_close(&s);
}

static void test_fbdev_errors(void **state)
{
    (void)state;
    hz_error_t err;
    hz_sink_t s;
    fake_fb_setup(8, W, H, H, 0, 0);
    assert_int_equal(hz_fbdev_sink_open(&s, "/fake/fb", &fake_fb_io, &err), HZ_E_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "/fake/fb: unsupported pixel format"));
    fb.fix.visual = FB_VISUAL_TRUECOLOR;
    assert_int_equal(hz_fbdev_sink_open(&s, "/fake/fb", &fake_fb_io, &err), HZ_E_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "8 bits per pixel"));
    assert_int_equal(hz_fbdev_sink_open(&s, "/dev/fb9", &fake_fb_io, &err), HZ_E_DEVICE);
    assert_string_equal(err.msg, "/dev/fb9: no such device node (is the display driver loaded?)");
    /* The real system: a node that is not a framebuffer. */
    assert_int_equal(hz_fbdev_sink_open(&s, "/dev/null", NULL, &err), HZ_E_DEVICE);
    assert_non_null(strstr(err.msg, "/dev/null: not a framebuffer device"));
    assert_int_equal(hz_fbdev_sink_open(&s, "/dev/hz-no-such-fb", NULL, &err), HZ_E_DEVICE);
    assert_non_null(strstr(err.msg, "no such device node"));
}

static void test_fbdev_vsync_sources(void **state)
{
    (void)state;
    hz_error_t err;
    hz_vsource_t v;
    hz_edge_t e;
    int r;
    /* A driver without FBIO_WAITFORVSYNC: a clear error on the first wait. */
    fake_fb_setup(16, W, H, H, 0, 0);
    fb.vsync_mode = 0;
    assert_int_equal(hz_fbdev_vsource_open(&v, "/fake/fb", &fake_fb_io, &err), HZ_OK);
    hz_timebase_t real;
    hz_tb_init_real(&real);
    assert_int_equal(v.next(&v, hz_tb_now(&real) + 1000000000, &e, &r, &err), HZ_E_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "does not implement FBIO_WAITFORVSYNC"));
    hz_vsource_close(&v);
    /* A working one: edges in time order. */
    fb.vsync_mode = 1;
    assert_int_equal(hz_fbdev_vsource_open(&v, "/fake/fb", &fake_fb_io, &err), HZ_OK);
    int64_t prev = 0;
    hz_timebase_t tb;
    hz_tb_init_real(&tb);
    for (int i = 0; i < 5; i++) {
        assert_int_equal(v.next(&v, hz_tb_now(&tb) + 1000000000, &e, &r, &err), HZ_OK);
        assert_int_equal(r, HZ_VS_EDGE);
        assert_true(e.t_ns > prev);
        prev = e.t_ns;
    }
    hz_vsource_close(&v);
    /* One that never returns: the frame loop gives up with a time-out instead of hanging. */
    fb.vsync_mode = 2;
    fb.release = 0;
    assert_int_equal(hz_fbdev_vsource_open(&v, "/fake/fb", &fake_fb_io, &err), HZ_OK);
    static uint8_t abuf[1 << 20] HZ_ALIGNED(64);
    hz_arena_t a;
    hz_arena_init(&a, "frame", abuf, sizeof abuf);
    hz_sink_t sink;
    hz_sink_null(&sink);
    hz_framesrc_t fs = hz_framesrc_testpattern();
    hz_loop_cfg_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.frames_mode = 1;
    cfg.frames = 5;
    cfg.nominal_period_ns = 16666667;
    cfg.edge_timeout_ns = 40000000;
    cfg.w = W;
    cfg.h = H;
    cfg.max_frames = 5;
    cfg.max_edges = 64;
    static hz_loop_result_t res;
    assert_int_equal(hz_loop_run(&cfg, &tb, &v, &sink, &fs, &a, &res, &err), HZ_E_TIMEOUT);
    assert_non_null(strstr(err.msg, "FBIO_WAITFORVSYNC on /fake/fb"));
    assert_non_null(strstr(err.msg, "never signalled v-sync"));
    fb.release = 1;
    hz_vsource_close(&v);
}

/* ---------------------------------------------------------------------------------------------------- */
/* A fake V4L2 output: shows one queued buffer per 16.67 ms "refresh" (whenever two are queued) */

typedef struct fake_v4l2 {
    uint32_t formats[4];
    int nformats;
    int output; /* 0: a capture-only device */
    struct v4l2_pix_format pix;
    int queued[4], order[8], nq;
    uint32_t nbufs;
    int64_t clock_ns;
    int streaming;
} fake_v4l2_t;

static fake_v4l2_t vd;
static uint8_t vbuf[4][W * H * 4];

static int v_open(const char *path, int flags)
{
    (void)flags;
    if (!strcmp(path, "/fake/video"))
        return 200;
    errno = ENOENT;
    return -1;
}

static int v_ioctl(int fd, unsigned long req, void *arg)
{
    (void)fd;
    switch (req) {
    case VIDIOC_QUERYCAP: {
        struct v4l2_capability *c = arg;
        memset(c, 0, sizeof *c);
        snprintf((char *)c->card, sizeof c->card, "fake");
        c->capabilities = (vd.output ? V4L2_CAP_VIDEO_OUTPUT : V4L2_CAP_VIDEO_CAPTURE) | V4L2_CAP_STREAMING;
        return 0;
    }
    case VIDIOC_ENUM_FMT: {
        struct v4l2_fmtdesc *d = arg;
        if (d->index >= (uint32_t)vd.nformats) {
            errno = EINVAL;
            return -1;
        }
        d->pixelformat = vd.formats[d->index];
        return 0;
    }
    case VIDIOC_G_FMT: ((struct v4l2_format *)arg)->fmt.pix = vd.pix; return 0;
    case VIDIOC_S_FMT: {
        struct v4l2_format *f = arg;
        int ok = 0;
        for (int i = 0; i < vd.nformats; i++)
            ok |= f->fmt.pix.pixelformat == vd.formats[i];
        if (!ok)
            f->fmt.pix.pixelformat = vd.formats[0];
        f->fmt.pix.width = W;
        f->fmt.pix.height = H;
        f->fmt.pix.field = V4L2_FIELD_NONE;
        uint32_t pf = f->fmt.pix.pixelformat;
        int bpp = pf == V4L2_PIX_FMT_YUYV ? 2 : pf == V4L2_PIX_FMT_RGB24 ? 3 : 4;
        f->fmt.pix.bytesperline = (uint32_t)(W * bpp);
        f->fmt.pix.sizeimage = f->fmt.pix.bytesperline * H;
        vd.pix = f->fmt.pix;
        return 0;
    }
    case VIDIOC_REQBUFS: {
        struct v4l2_requestbuffers *rb = arg;
        vd.nbufs = rb->count > 4 ? 4 : rb->count;
        rb->count = vd.nbufs;
        return 0;
    }
    case VIDIOC_QUERYBUF: {
        struct v4l2_buffer *b = arg;
        b->length = sizeof vbuf[0];
        b->m.offset = b->index * 4096;
        return 0;
    }
    case VIDIOC_QBUF: {
        struct v4l2_buffer *b = arg;
        vd.queued[b->index] = 1;
        vd.order[vd.nq++] = (int)b->index;
        return 0;
    }
    case VIDIOC_DQBUF: {
        struct v4l2_buffer *b = arg;
        if (!vd.streaming || vd.nq < 2) {
            errno = EAGAIN;
            return -1;
        }
        int idx = vd.order[0];
        memmove(vd.order, vd.order + 1, sizeof vd.order[0] * (size_t)--vd.nq);
        vd.queued[idx] = 0;
        vd.clock_ns += 16666667;
        b->index = (uint32_t)idx;
        b->flags = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
        b->timestamp.tv_sec = (time_t)(vd.clock_ns / 1000000000);
        b->timestamp.tv_usec = (suseconds_t)(vd.clock_ns % 1000000000 / 1000);
        return 0;
    }
    case VIDIOC_STREAMON: vd.streaming = 1; return 0;
    case VIDIOC_STREAMOFF: vd.streaming = 0; return 0;
    default: errno = ENOTTY; return -1;
    }
}

static void *v_mmap(void *addr, size_t len, int prot, int flags, int fd, off_t off)
{
    (void)addr;
    (void)len;
    (void)prot;
    (void)flags;
    (void)fd;
    return vbuf[off / 4096];
}

static int v_poll(struct pollfd *p, nfds_t n, int ms)
{
    (void)n;
    if (vd.streaming && vd.nq >= 2) {
        p->revents = p->events;
        return 1;
    }
    sleep_ms(ms > 5 ? 5 : ms);
    return 0;
}

static const hz_sysio_t fake_v4l2_io = { v_open, fb_close, v_ioctl, v_mmap, fb_munmap, v_poll };

static void test_v4l2_output_yuyv(void **state)
{
    (void)state;
    hz_error_t err;
    memset(&vd, 0, sizeof vd);
    vd.output = 1;
    vd.formats[0] = V4L2_PIX_FMT_YUYV;
    vd.nformats = 1;
    vd.clock_ns = 5000000000ll;
    hz_sink_t s;
    hz_vsource_t v;
    /* Not offered: the message lists what is. */
    assert_int_equal(hz_v4l2_out_open(&s, &v, "/fake/video", HZ_PIX_RGB24, 0, 0, &fake_v4l2_io, &err),
                     HZ_E_UNSUPPORTED);
    assert_string_equal(err.msg, "/fake/video: unsupported pixel format rgb24 (RGB3): the device offers YUYV");
    assert_int_equal(hz_v4l2_out_open(&s, &v, "/fake/video", HZ_PIX_YUYV, 0, 0, &fake_v4l2_io, &err), HZ_OK);
    assert_int_equal(s.w, W);
    assert_int_equal(v.needs_frames, 1);
    for (uint64_t id = 0; id < 6; id++) {
        present(&s, id);
        /* the buffer holds the converted frame */
        int idx = vd.order[vd.nq - 1];
        static uint8_t yuyv[W * H * 2];
        hz_pix_convert(HZ_PIX_YUYV, rgb, W * 3, yuyv, W * 2, W, H);
        assert_memory_equal(vbuf[idx], yuyv, sizeof yuyv);
    }
    /* Dequeues name the frames in order, stamped with the driver's clock. */
    hz_edge_t e;
    int r;
    hz_timebase_t tb;
    hz_tb_init_real(&tb);
    int64_t want = 0, prev_t = 0;
    for (;;) {
        assert_int_equal(v.next(&v, hz_tb_now(&tb) + 20000000, &e, &r, &err), HZ_OK);
        if (r != HZ_VS_EDGE)
            break;
        assert_int_equal(e.frame_id, want);
        assert_true(e.t_ns > prev_t);
        prev_t = e.t_ns;
        want++;
    }
    assert_true(want >= 4); /* 6 queued, the device keeps the last one on screen */
    hz_vsource_close(&v);
    hz_sink_close(&s);
}

static void test_v4l2_wrong_device_and_missing_node(void **state)
{
    (void)state;
    hz_error_t err;
    hz_sink_t s;
    memset(&vd, 0, sizeof vd);
    vd.output = 0;
    vd.formats[0] = V4L2_PIX_FMT_RGB24;
    vd.nformats = 1;
    assert_int_equal(hz_v4l2_out_open(&s, NULL, "/fake/video", HZ_PIX_RGB24, 0, 0, &fake_v4l2_io, &err), HZ_E_DEVICE);
    assert_non_null(strstr(err.msg, "/fake/video (fake): not a video output device"));
    assert_int_equal(hz_v4l2_out_open(&s, NULL, "/dev/video99", HZ_PIX_RGB24, 0, 0, &fake_v4l2_io, &err), HZ_E_DEVICE);
    assert_string_equal(err.msg, "/dev/video99: no such device node (is the V4L2 driver loaded?)");
    assert_int_equal(hz_v4l2_out_open(&s, NULL, "/dev/null", HZ_PIX_RGB24, 0, 0, NULL, &err), HZ_E_DEVICE);
    assert_non_null(strstr(err.msg, "/dev/null: not a V4L2 device"));
    hz_v4l2_cap_t *cap;
    assert_int_equal(hz_v4l2_cap_open(&cap, "/dev/hz-no-video", HZ_PIX_YUYV, 0, 0, NULL, &err), HZ_E_DEVICE);
}

static void test_gpio_missing_chip(void **state)
{
    (void)state;
    hz_error_t err;
    hz_vsource_t v;
    hz_gpio_cfg_t c = { "hz-no-such-chip", 3, 0, NULL, 0 };
    hz_status_t s = hz_gpio_vsource_open(&v, &c, &err);
#if defined(HZ_PORT_GPIO)
    assert_int_equal(s, HZ_E_DEVICE);
    assert_non_null(strstr(err.msg, "GPIO chip 'hz-no-such-chip': no such chip"));
#else
    assert_int_equal(s, HZ_E_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "this build has no GPIO port"));
#endif
    print_message("  gpio backend: %s\n", hz_gpio_backend());
}

int main(void)
{
    /* Sinks convert a frame in bands of rows on the pool: with three threads the bands (40 rows: 16, 16 and 8)
     * land on different threads, and every frame must still match one whole-frame conversion. */
    hz_error_t err;
    if (hz_threads_start(3, &err) != HZ_OK) {
        fprintf(stderr, "test_devices: %s\n", err.msg);
        return 1;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fbdev_16bpp_page_flips),
        cmocka_unit_test(test_fbdev_24_and_32bpp),
        cmocka_unit_test(test_fbdev_errors),
        cmocka_unit_test(test_fbdev_vsync_sources),
        cmocka_unit_test(test_v4l2_output_yuyv),
        cmocka_unit_test(test_v4l2_wrong_device_and_missing_node),
        cmocka_unit_test(test_gpio_missing_chip),
    };
    const int failed = HZ_RUN(tests);
    hz_threads_stop();
    return failed;
}
