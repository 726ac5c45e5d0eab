/*
 * Device checks that need a real kernel: run inside the arm64 VM by make vmtest (test/vm/run.sh), never on
 * the host.
 *  - vivid V4L2 loop-back: the frame loop renders N frames (the built-in scene through the renderer in RGB24,
 *    the test pattern in YUYV and XRGB32) with the frame-id marker to vivid's HDMI output, paced by that output's dequeue
 *    timestamps; a second thread captures vivid's HDMI input, which loops the output back. Every captured
 *    frame whose marker decodes must equal, byte for byte, the frame rendered for that id; render-to-capture
 *    latency comes from the capture buffers' CLOCK_MONOTONIC timestamps. Error paths on the real driver: a
 *    capture node used as an output, a missing node.
 *  - fbdev on vivid's framebuffer: the sink writes a 16 bpp frame through mmap (read back and compared); the
 *    driver lacks FBIO_WAITFORVSYNC, which must be a clear error.
 *  - GPIO on the virt machine's PL061 (gpiochip0): a busy line names its holder, bad chip and line numbers are
 *    refused, a silent line times out, and edges the host makes on line 3 (monitor `system_powerdown`: high,
 *    then low ~100 ms later) arrive complete, in order, alternating, with CLOCK_MONOTONIC timestamps.
 */
#include "hz_test.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/fb.h>
#include <linux/gpio.h>
#include <linux/v4l2-dv-timings.h>
#include <linux/videodev2.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "clock.h"
#include "devices.h"
#include "hz/frameloop.h"
#include "vsource.h"
#include "hz/hz.h"
#include "hz/marker.h"
#include "scenesrc.h"

#if defined(HZ_VM_GPIO_ONLY)
#pragma GCC diagnostic ignored "-Wunused-function" /* the V4L2 and fbdev checks run in test_vm_devices */
#endif

#define GPIO_PULSES 4 /* test/vm/run.sh sends this many system_powerdown commands */
#define LOOP_FRAMES 90

static uint8_t arena_buf[16u << 20] HZ_ALIGNED(64);

/* ---- vivid ---- */

static int find_vivid(uint32_t want_cap, char *path, size_t cap)
{
    for (int i = 0; i < 8; i++) {
        snprintf(path, cap, "/dev/video%d", i);
        int fd = open(path, O_RDWR);
        if (fd < 0)
            continue;
        struct v4l2_capability c;
        memset(&c, 0, sizeof c);
        int ok = ioctl(fd, VIDIOC_QUERYCAP, &c) == 0 && !strcmp((const char *)c.driver, "vivid") &&
                 (((c.capabilities & V4L2_CAP_DEVICE_CAPS) ? c.device_caps : c.capabilities) & want_cap);
        close(fd);
        if (ok)
            return 1;
    }
    return 0;
}

static void vivid_setup(const char *node, int capture)
{
    int fd = open(node, O_RDWR);
    assert_true(fd >= 0);
    struct v4l2_dv_timings t = V4L2_DV_BT_CEA_640X480P59_94;
    if (ioctl(fd, VIDIOC_S_DV_TIMINGS, &t) != 0)
        fail_msg("%s: VIDIOC_S_DV_TIMINGS 640x480p59.94: %s", node, strerror(errno));
    if (capture) {
        struct v4l2_control loop = { 0x00f0f025, 1 }; /* vivid "Loop Video" */
        struct v4l2_control osd = { 0x00f0f001, 2 };  /* "OSD Text Mode": none, or text covers rows 16..143 */
        if (ioctl(fd, VIDIOC_S_CTRL, &loop) != 0)
            fail_msg("%s: cannot switch on Loop Video: %s", node, strerror(errno));
        if (ioctl(fd, VIDIOC_S_CTRL, &osd) != 0)
            fail_msg("%s: cannot switch off the OSD text: %s", node, strerror(errno));
    }
    close(fd);
}

/* What the loop showed, kept per id: a wrapper around whichever frame source runs (the built-in scene once it
 * is in, the test pattern until then) stores each frame as presented (marker included) in a ring, and the
 * capture compares against that. Nothing has to be re-rendered, so animated frames compare exactly too. */
#define RING 24
#define W 640
#define H 480

typedef struct ring {
    pthread_mutex_t lock;
    uint32_t id[RING];
    int valid[RING];
    uint8_t rgb[RING][W * H * 3];
    hz_framesrc_t inner;
    hz_marker_layout_t marker;
} ring_t;

static ring_t ring = { PTHREAD_MUTEX_INITIALIZER, { 0 }, { 0 }, { { 0 } }, { 0 }, { 0 } };

static hz_status_t recording_render(void *ctx, const hz_frame_req_t *req, hz_rgb8_image_t *out, hz_error_t *err)
{
    (void)ctx;
    hz_status_t s = ring.inner.render(ring.inner.ctx, req, out, err);
    if (s != HZ_OK)
        return s;
    /* The loop draws the marker after render(); draw it here too (same pixels) so the copy is what is shown. */
    hz_marker_draw(out->rgb, out->stride, &ring.marker, (uint32_t)req->id);
    int slot = (int)(req->id % RING);
    pthread_mutex_lock(&ring.lock);
    for (int y = 0; y < H; y++)
        memcpy(ring.rgb[slot] + (size_t)y * W * 3, out->rgb + (size_t)y * out->stride, (size_t)W * 3);
    ring.id[slot] = (uint32_t)req->id;
    ring.valid[slot] = 1;
    pthread_mutex_unlock(&ring.lock);
    return HZ_OK;
}

typedef struct capture_state {
    hz_v4l2_cap_t *cap;
    hz_pix_fmt_t fmt;
    int frames_total;
    volatile int stop;
    int frames, decoded, undecodable_after_first, mismatches, non_monotonic, too_old;
    int first_id, last_id, expect_id;
    int64_t seen_t[LOOP_FRAMES]; /* first capture time of each id, 0: never */
    int64_t last_t;
    uint8_t expect[W * H * 4];  /* the ring's frame converted to the capture format */
    char error[256];
} capture_state_t;

static capture_state_t cs;

static void *capture_thread(void *arg)
{
    (void)arg;
    hz_error_t err;
    int w, h;
    size_t stride, off, ps;
    hz_v4l2_cap_size(cs.cap, &w, &h, &stride);
    hz_pix_marker_view(cs.fmt, &off, &ps);
    size_t row = (size_t)w * (size_t)hz_pix_bpp(cs.fmt);
    while (!cs.stop) {
        hz_v4l2_frame_t f;
        hz_status_t s = hz_v4l2_cap_next(cs.cap, 200, &f, &err);
        if (s == HZ_E_TIMEOUT)
            continue;
        if (s != HZ_OK) {
            snprintf(cs.error, sizeof cs.error, "%s", err.msg);
            break;
        }
        cs.frames++;
        if (f.t_ns < cs.last_t)
            cs.non_monotonic++;
        cs.last_t = f.t_ns;
        uint32_t id;
        if (hz_marker_read(f.data + off, ps, f.stride, &ring.marker, &id) != HZ_OK || id >= (uint32_t)cs.frames_total) {
            if (cs.decoded)
                cs.undecodable_after_first++;
        } else {
            cs.decoded++;
            if (cs.first_id < 0)
                cs.first_id = (int)id;
            cs.last_id = (int)id;
            if ((int)id != cs.expect_id) {
                int slot = (int)(id % RING);
                pthread_mutex_lock(&ring.lock);
                int have = ring.valid[slot] && ring.id[slot] == id;
                if (have)
                    hz_pix_convert(cs.fmt, ring.rgb[slot], (size_t)W * 3, cs.expect, row, w, h);
                pthread_mutex_unlock(&ring.lock);
                cs.expect_id = have ? (int)id : -1;
                if (!have)
                    cs.too_old++;
            }
            if (cs.expect_id == (int)id)
                for (int y = 0; y < h; y++)
                    if (memcmp(f.data + (size_t)y * f.stride, cs.expect + (size_t)y * row, row)) {
                        if (!cs.mismatches)
                            print_message("  frame %u differs from what was shown, first at row %d\n", id, y);
                        cs.mismatches++;
                        break;
                    }
            if (!cs.seen_t[id])
                cs.seen_t[id] = f.t_ns;
        }
        hz_v4l2_cap_release(cs.cap, f.index, &err);
    }
    return NULL;
}

/* Renders `count` frames (of the built-in scene, or of the test pattern) to vivid's output in `fmt`, captures
 * them back in the same format, and checks them. */
static void loopback(hz_pix_fmt_t fmt, int count, int scene)
{
    char out_node[32], cap_node[32];
    if (!find_vivid(V4L2_CAP_VIDEO_OUTPUT, out_node, sizeof out_node) ||
        !find_vivid(V4L2_CAP_VIDEO_CAPTURE, cap_node, sizeof cap_node))
        fail_msg("vivid is not loaded (no vivid output and capture nodes): see HZVM-MODULE-FAIL lines");
    vivid_setup(out_node, 0);
    vivid_setup(cap_node, 1);
    hz_error_t err;
    hz_sink_t sink;
    hz_vsource_t src;
    if (hz_v4l2_out_open(&sink, &src, out_node, fmt, W, H, NULL, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    memset(&cs, 0, sizeof cs);
    cs.first_id = -1;
    cs.expect_id = -1;
    cs.fmt = fmt;
    cs.frames_total = count;
    if (hz_v4l2_cap_open(&cs.cap, cap_node, fmt, W, H, NULL, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(hz_marker_layout(W, H, &ring.marker, &err), HZ_OK);
    for (int i = 0; i < RING; i++)
        ring.valid[i] = 0;
    /* The built-in scene when the renderer provides it (port/linux/scenesrc.c); the test pattern until then. */
    /* The renderer on the software-emulated CPU takes ~0.3 s for 80x60: the scene is rendered at 40x30 and
     * shown 16x. */
    ring.inner = hz_framesrc_testpattern();
    if (scene) {
        if (hz_scenesrc_open_simple(&ring.inner, "builtin", W, H, 16, 0, HZ_MODE_FULL, &err) != HZ_OK)
            fail_msg("built-in scene: %s", err.msg);
    }
    print_message("  frames: %s\n", ring.inner.name);
    hz_framesrc_t frames = { ring.inner.name, NULL, recording_render, NULL };
    pthread_t th;
    assert_int_equal(pthread_create(&th, NULL, capture_thread, NULL), 0);
    hz_arena_t arena;
    hz_arena_init(&arena, "frame", arena_buf, sizeof arena_buf);
    hz_loop_cfg_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.frames_mode = 1;
    cfg.frames = (uint64_t)count;
    cfg.nominal_period_ns = 16683333; /* 59.94 Hz */
    cfg.pace.guard_ns = -1;
    cfg.edge_timeout_ns = 3000000000ll; /* software emulation is slow */
    /* vivid stamps output buffers when its kernel thread gets to them; on an emulated CPU that shares a busy
     * host that is milliseconds late at times: accept edges within a quarter period. */
    cfg.tol_min_ns = 16683333 / 4;
    cfg.lock_timeout_ns = 6000000000ll;
    cfg.marker = 1;
    cfg.w = W;
    cfg.h = H;
    cfg.max_frames = (size_t)count;
    cfg.max_edges = 16 * (size_t)count + 64; /* a slow render sees several refreshes a frame */
    hz_timebase_t tb;
    hz_tb_init_real(&tb);
    static hz_loop_result_t res;
    hz_status_t s = hz_loop_run(&cfg, &tb, &src, &sink, &frames, &arena, &res, &err);
    const char *paced_by = "vivid's output dequeue timestamps";
    if (s == HZ_E_TIMEOUT && strstr(err.msg, "no v-sync lock")) {
        /* vivid stamps a returned output buffer when its kernel thread runs, and an emulated CPU on a busy host
         * runs it irregularly: then there is no display clock to lock to. Say so, and pace the same frames on
         * a simulated 59.94 Hz clock: the loop-back and the capture timestamps, which are what this test
         * checks, do not depend on it. */
        print_message("  NOTE: %s\n  NOTE: pacing on a simulated 59.94 Hz clock instead\n", err.msg);
        hz_vsource_close(&src);
        hz_vsynth_cfg_t g;
        memset(&g, 0, sizeof g);
        g.period_q16 = hz_vsync_period_q16_from_mhz(59940);
        assert_int_equal(hz_vsource_sim(&src, &g, &err), HZ_OK);
        hz_arena_init(&arena, "frame", arena_buf, sizeof arena_buf);
        s = hz_loop_run(&cfg, &tb, &src, &sink, &frames, &arena, &res, &err);
        paced_by = "a simulated 59.94 Hz clock (vivid's timestamps did not lock)";
    }
    /* Let the capture catch the last frames, then stop it. */
    struct timespec settle = { 0, 400000000 };
    nanosleep(&settle, NULL);
    cs.stop = 1;
    pthread_join(th, NULL);
    hz_v4l2_cap_close(cs.cap);
    hz_vsource_close(&src);
    hz_sink_close(&sink);
    if (scene)
        hz_scenesrc_close();
    if (s != HZ_OK)
        fail_msg("frame loop: %s", err.msg);
    if (cs.error[0])
        fail_msg("capture: %s", cs.error);
    hz_frames_summary_t sum;
    hz_frames_summarise(res.frames, res.n_frames, res.scratch, &sum);
    /* Render-to-capture latency per captured id, from the capture buffer timestamps. */
    static int64_t lat[LOOP_FRAMES];
    size_t n = 0, captured = 0;
    int negative = 0;
    for (size_t i = 0; i < res.n_frames; i++) {
        if (res.frames[i].id >= (uint64_t)count || !cs.seen_t[res.frames[i].id])
            continue;
        captured++;
        int64_t l = cs.seen_t[res.frames[i].id] - res.frames[i].start_ns;
        if (l > 0)
            lat[n++] = l;
        else
            negative++; /* see the note below: left out of the distribution, and counted */
    }
    hz_dist_t d;
    hz_dist_compute(lat, n, &d);
    print_message("  vivid loop-back %s: %d frames rendered, %d captured buffers, %d decoded (ids %d..%d), %d unique "
                  "ids, %d byte mismatches, %d undecodable after the first decoded, %d too old to compare\n",
                  hz_pix_name(fmt), count, cs.frames, cs.decoded, cs.first_id, cs.last_id, (int)captured, cs.mismatches,
                  cs.undecodable_after_first, cs.too_old);
    print_message("  render-to-capture latency (capture buffer timestamp - render start), %zu frames: min %.2f ms "
                  "p50 %.2f ms p90 %.2f ms max %.2f ms (%d stamped before their render start left out)\n",
                  n, d.min / 1e6, d.p50 / 1e6, d.p90 / 1e6, d.max / 1e6, negative);
    print_message("  pacing on %s: period %.3f ms, render time p50 %.2f ms (software emulation), %llu shown, "
                  "%llu late, %llu repeated refreshes, %llu unresolved, latency to scan-out p50 %.2f ms\n",
                  paced_by, res.period_ns / 1e6, sum.render.p50 / 1e6, (unsigned long long)sum.resolved,
                  (unsigned long long)sum.late, (unsigned long long)sum.repeated, (unsigned long long)sum.unresolved,
                  sum.latency.p50 / 1e6);
    /* vivid's loop-back takes the newest queued output buffer on the capture's own clock, which is not locked
     * to the output's refresh: a capture may see a frame before the output refresh the scan-out rule gave it.
     * Counted and shown; the capture timestamps are the measurement. */
    int before_scanout = 0;
    for (size_t i = 0; i < res.n_frames; i++) {
        const hz_frame_rec_t *r = &res.frames[i];
        if (r->id < (uint64_t)count && cs.seen_t[r->id] && (r->flags & HZ_FRAME_RESOLVED) &&
            cs.seen_t[r->id] < r->actual_edge_ns)
            before_scanout++;
    }
    print_message("  captures earlier than the frame's output refresh (vivid's capture runs on its own clock): %d\n",
                  before_scanout);
    /* vivid stamps a capture buffer when its thread starts the frame and copies the newest output into it
     * afterwards; when the emulated CPU runs that thread late, a capture can carry a frame rendered after its
     * timestamp. That is vivid's clock, not ours: shown, not asserted. */
    if (negative)
        print_message("  NOTE: %d captures are stamped before their frame's render start (vivid's capture thread ran "
                      "late: the host is busy)\n", negative);
    assert_int_equal(cs.mismatches, 0);
    assert_int_equal(cs.non_monotonic, 0);
    assert_int_equal(cs.undecodable_after_first, 0);
    assert_true(cs.decoded - cs.too_old > 0);          /* frames were compared, not merely decoded */
    assert_true(captured >= (size_t)count / 3);        /* most frames made it through the loop */
    assert_true(n > 0);                                 /* and latency was measured */
    /* Which frames the refresh edges place depends on when vivid's kernel thread returns buffers, and an
     * emulated CPU on a busy host runs it late: the last frames can still wait for their edge when the loop's
     * bounded settle ends. What must hold whatever the timing: every frame submitted before the last v-sync
     * edge the loop took is placed, so the unplaced ones are only the tail after it. */
    int64_t last_edge = INT64_MIN;
    for (size_t i = 0; i < res.n_edges; i++)
        if (res.edges[i].cls == HZ_ECLS_VSYNC && res.edges[i].t_ns > last_edge)
            last_edge = res.edges[i].t_ns;
    size_t placeable = 0, unplaced_early = 0;
    for (size_t i = 0; i < res.n_frames; i++) {
        const hz_frame_rec_t *r = &res.frames[i];
        if (r->submit_ns + cfg.pace.latch_ns > last_edge)
            continue;
        placeable++;
        unplaced_early += !(r->flags & HZ_FRAME_RESOLVED);
    }
    print_message("  %zu frames submitted before the last v-sync edge (%zu of them not placed)\n", placeable,
                  unplaced_early);
    assert_int_equal(unplaced_early, 0);
    assert_true(sum.resolved >= (uint64_t)count / 2); /* the edges kept coming for most of the run */
    assert_true(res.period_ns > 15000000 && res.period_ns < 18500000); /* vivid runs at 59.94 Hz */
}

static void test_vivid_loopback_rgb24(void **state)
{
    (void)state;
    loopback(HZ_PIX_RGB24, LOOP_FRAMES / 3, 1);
}

static void test_vivid_loopback_yuyv(void **state)
{
    (void)state;
    loopback(HZ_PIX_YUYV, LOOP_FRAMES / 3, 0);
}

static void test_vivid_loopback_xrgb32(void **state)
{
    (void)state;
    loopback(HZ_PIX_XRGB32, LOOP_FRAMES / 3, 0);
}

static void test_vivid_errors(void **state)
{
    (void)state;
    char cap_node[32];
    if (!find_vivid(V4L2_CAP_VIDEO_CAPTURE, cap_node, sizeof cap_node))
        fail_msg("vivid is not loaded");
    hz_error_t err;
    hz_sink_t sink;
    assert_int_equal(hz_v4l2_out_open(&sink, NULL, cap_node, HZ_PIX_RGB24, 0, 0, NULL, &err), HZ_E_DEVICE);
    print_message("  %s\n", err.msg);
    assert_non_null(strstr(err.msg, "not a video output device"));
    assert_int_equal(hz_v4l2_out_open(&sink, NULL, "/dev/video9", HZ_PIX_RGB24, 0, 0, NULL, &err), HZ_E_DEVICE);
    print_message("  %s\n", err.msg);
    assert_non_null(strstr(err.msg, "no such device node"));
}

/* ---- fbdev ---- */

static void test_fbdev_on_vivid(void **state)
{
    (void)state;
    hz_error_t err;
    hz_sink_t sink;
    if (hz_fbdev_sink_open(&sink, "/dev/fb0", NULL, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    print_message("  %s\n", sink.name);
    int w = sink.w, h = sink.h;
    static uint8_t rgb[1920 * 1080 * 3];
    assert_true((size_t)w * h * 3 <= sizeof rgb);
    hz_testpattern_draw(rgb, (size_t)w * 3, w, h, 3);
    hz_rgb8_image_t img = { rgb, w, h, (size_t)w * 3 };
    assert_int_equal(sink.present(&sink, &img, 3, &err), HZ_OK);
    /* Read it back through our own mapping and compare with the packing of its layout. */
    int fd = open("/dev/fb0", O_RDWR);
    struct fb_var_screeninfo var;
    struct fb_fix_screeninfo fix;
    assert_int_equal(ioctl(fd, FBIOGET_VSCREENINFO, &var), 0);
    assert_int_equal(ioctl(fd, FBIOGET_FSCREENINFO, &fix), 0);
    size_t len = (size_t)fix.line_length * var.yres_virtual;
    if (fix.smem_len && len > fix.smem_len)
        len = fix.smem_len;
    uint8_t *m = mmap(NULL, len, PROT_READ, MAP_SHARED, fd, 0);
    assert_true(m != MAP_FAILED);
    hz_fb_layout_t l = { (int)var.bits_per_pixel, (int)var.red.offset, (int)var.red.length, (int)var.green.offset,
                         (int)var.green.length, (int)var.blue.offset, (int)var.blue.length };
    static uint8_t want[1920 * 1080 * 4];
    hz_fb_pack(&l, rgb, (size_t)w * 3, want, fix.line_length, w, h);
    const uint8_t *shown = m + (size_t)var.yoffset * fix.line_length;
    size_t row = (size_t)w * (var.bits_per_pixel / 8);
    for (int y = 0; y < h; y++)
        if (memcmp(shown + (size_t)y * fix.line_length, want + (size_t)y * fix.line_length, row))
            fail_msg("framebuffer row %d differs from the packed frame", y);
    munmap(m, len);
    close(fd);
    hz_sink_close(&sink);
    /* vivid's framebuffer has no FBIO_WAITFORVSYNC: a clear error, not a hang. */
    hz_vsource_t v;
    assert_int_equal(hz_fbdev_vsource_open(&v, "/dev/fb0", NULL, &err), HZ_OK);
    hz_edge_t e;
    int r;
    assert_int_equal(v.next(&v, hz_clock_ns() + 2000000000, &e, &r, &err), HZ_E_UNSUPPORTED);
    print_message("  %s\n", err.msg);
    assert_non_null(strstr(err.msg, "does not implement FBIO_WAITFORVSYNC"));
    hz_vsource_close(&v);
}

/* ---- GPIO ---- */


#if defined(HZ_PORT_GPIO)
static void test_gpio_busy_and_bad_lines(void **state)
{
    (void)state;
    hz_error_t err;
    hz_vsource_t v;
    /* Hold line 3 through the kernel's own interface, as another program would. */
    int chip = open("/dev/gpiochip0", O_RDWR);
    assert_true(chip >= 0);
    struct gpio_v2_line_request req;
    memset(&req, 0, sizeof req);
    req.offsets[0] = 3;
    req.num_lines = 1;
    req.config.flags = GPIO_V2_LINE_FLAG_INPUT;
    snprintf(req.consumer, sizeof req.consumer, "vm-holder");
    if (ioctl(chip, GPIO_V2_GET_LINE_IOCTL, &req) != 0)
        fail_msg("cannot hold gpiochip0 line 3: %s", strerror(errno));
    hz_gpio_cfg_t c = { "gpiochip0", 3, 0, NULL, 0 };
    assert_int_equal(hz_gpio_vsource_open(&v, &c, &err), HZ_E_DEVICE);
    print_message("  %s\n", err.msg);
    assert_non_null(strstr(err.msg, "is busy: held by 'vm-holder'"));
    close(req.fd);
    close(chip);
    hz_gpio_cfg_t bad_line = { "gpiochip0", 99, 0, NULL, 0 };
    assert_int_equal(hz_gpio_vsource_open(&v, &bad_line, &err), HZ_E_DEVICE);
    print_message("  %s\n", err.msg);
    assert_non_null(strstr(err.msg, "has lines 0..7, not 99"));
    hz_gpio_cfg_t no_chip = { "gpiochip7", 3, 0, NULL, 0 };
    assert_int_equal(hz_gpio_vsource_open(&v, &no_chip, &err), HZ_E_DEVICE);
    print_message("  %s\n", err.msg);
    assert_non_null(strstr(err.msg, "no such chip"));
    /* By label, as boards name their chips. */
    hz_gpio_cfg_t by_label = { "9030000.pl061", 3, 0, NULL, 0 };
    assert_int_equal(hz_gpio_vsource_open(&v, &by_label, &err), HZ_OK);
    print_message("  %s\n", v.name);
    hz_vsource_close(&v);
}

static void test_gpio_silent_line_times_out(void **state)
{
    (void)state;
    hz_error_t err;
    hz_vsource_t v;
    hz_gpio_cfg_t c = { "gpiochip0", 3, 0, NULL, 0 };
    assert_int_equal(hz_gpio_vsource_open(&v, &c, &err), HZ_OK);
    hz_arena_t arena;
    hz_arena_init(&arena, "frame", arena_buf, sizeof arena_buf);
    hz_loop_cfg_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.frames_mode = 0;
    cfg.duration_ns = 10000000000ll;
    cfg.nominal_period_ns = 16666667;
    cfg.edge_timeout_ns = 400000000;
    cfg.max_edges = 64;
    hz_timebase_t tb;
    hz_tb_init_real(&tb);
    static hz_loop_result_t res;
    assert_int_equal(hz_loop_run(&cfg, &tb, &v, NULL, NULL, &arena, &res, &err), HZ_E_TIMEOUT);
    print_message("  %s\n", err.msg);
    assert_non_null(strstr(err.msg, "never signalled v-sync"));
    hz_vsource_close(&v);
}

static void test_gpio_capture_host_pulses(void **state)
{
    (void)state;
    hz_error_t err;
    hz_vsource_t v;
    hz_gpio_cfg_t c = { "gpiochip0", 3, 0, NULL, 0 };
    assert_int_equal(hz_gpio_vsource_open(&v, &c, &err), HZ_OK);
    int64_t t_open = hz_clock_ns();
    printf("HZVM-GPIO-READY %d\n", GPIO_PULSES);
    fflush(stdout);
    hz_edge_t e[2 * GPIO_PULSES + 4];
    int n = 0;
    int64_t give_up = t_open + 60000000000ll;
    while (n < 2 * GPIO_PULSES + 4) {
        int r;
        /* After the last expected edge, wait a little longer to catch any extra ones. */
        int64_t deadline = n >= 2 * GPIO_PULSES ? hz_clock_ns() + 1500000000 : give_up;
        if (v.next(&v, deadline, &e[n], &r, &err) != HZ_OK)
            fail_msg("%s", err.msg);
        if (r != HZ_VS_EDGE)
            break;
        n++;
    }
    int64_t t_end = hz_clock_ns();
    hz_vsource_close(&v);
    print_message("  %d edges on gpiochip0 line 3 (expected %d):\n", n, 2 * GPIO_PULSES);
    for (int i = 0; i < n; i++) {
        if (i && !e[i].level)
            print_message("    falling at +%9.3f ms  (high for %.1f ms)\n", (e[i].t_ns - t_open) / 1e6,
                          (e[i].t_ns - e[i - 1].t_ns) / 1e6);
        else
            print_message("    %s at +%9.3f ms\n", e[i].level ? "rising " : "falling", (e[i].t_ns - t_open) / 1e6);
    }
    assert_int_equal(n, 2 * GPIO_PULSES);
    for (int i = 0; i < n; i++) {
        assert_int_equal(e[i].level, i % 2 == 0); /* rising, falling, rising, ... */
        if (i)
            assert_true(e[i].t_ns > e[i - 1].t_ns);
        /* The kernel's CLOCK_MONOTONIC: between opening the line and now. */
        assert_true(e[i].t_ns >= t_open && e[i].t_ns <= t_end);
    }
}
/* Only rising edges requested: half the events, the same pulses. */
static void test_gpio_capture_rising_only(void **state)
{
    (void)state;
    hz_error_t err;
    hz_vsource_t v;
    hz_gpio_cfg_t c = { "gpiochip0", 3, 0, NULL, 1 };
    assert_int_equal(hz_gpio_vsource_open(&v, &c, &err), HZ_OK);
    print_message("  %s\n", v.name);
    int64_t t_open = hz_clock_ns();
    printf("HZVM-GPIO-READY %d\n", GPIO_PULSES);
    fflush(stdout);
    hz_edge_t e[GPIO_PULSES + 4];
    int n = 0;
    while (n < GPIO_PULSES + 4) {
        int r;
        int64_t deadline = n >= GPIO_PULSES ? hz_clock_ns() + 1500000000 : t_open + 60000000000ll;
        if (v.next(&v, deadline, &e[n], &r, &err) != HZ_OK)
            fail_msg("%s", err.msg);
        if (r != HZ_VS_EDGE)
            break;
        n++;
    }
    hz_vsource_close(&v);
    print_message("  %d rising edges requested alone (expected %d)\n", n, GPIO_PULSES);
    assert_int_equal(n, GPIO_PULSES);
    for (int i = 0; i < n; i++) {
        assert_int_equal(e[i].level, 1);
        if (i)
            assert_true(e[i].t_ns - e[i - 1].t_ns > 100000000); /* one per pulse, not per edge */
    }
}
#else
/* aarch64-generic lists the gpio port: a build without it (no libgpiod-dev:arm64) is a failure, not a skip. */
static void test_gpio_port_off(void **state)
{
    (void)state;
    printf("HZVM-GPIO-MISSING %s\n", hz_gpio_backend());
    fflush(stdout);
    fail_msg("the GPIO port is not in this build: %s", hz_gpio_backend());
}
#endif

int main(void)
{
#if defined(HZ_VM_GPIO_ONLY)
    /* test_vm_gpiod2: the same GPIO checks against the libgpiod 2 build of the port (tools/gpiod2). */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gpio_busy_and_bad_lines),
        cmocka_unit_test(test_gpio_silent_line_times_out),
        cmocka_unit_test(test_gpio_capture_host_pulses),
        cmocka_unit_test(test_gpio_capture_rising_only),
    };
    print_message("  GPIO backend: %s\n", hz_gpio_backend());
    return HZ_RUN(tests);
#else
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vivid_loopback_rgb24),
        cmocka_unit_test(test_vivid_loopback_yuyv),
        cmocka_unit_test(test_vivid_loopback_xrgb32),
        cmocka_unit_test(test_vivid_errors),
        cmocka_unit_test(test_fbdev_on_vivid),
#if defined(HZ_PORT_GPIO)
        cmocka_unit_test(test_gpio_busy_and_bad_lines),
        cmocka_unit_test(test_gpio_silent_line_times_out),
        cmocka_unit_test(test_gpio_capture_host_pulses),
        cmocka_unit_test(test_gpio_capture_rising_only),
#else
        cmocka_unit_test(test_gpio_port_off),
#endif
    };
    return HZ_RUN(tests);
#endif
}
