/*
 * devices.h — display sinks and v-sync sources backed by kernel devices: fbdev, V4L2 output (and capture, for
 * loop-back checks and grabbers), GPIO edge events. Each exists when its port is in the board's BOARD_PORTS
 * (HZ_PORT_FBDEV, HZ_PORT_V4L2, HZ_PORT_GPIO); hz_devices_missing() explains an absent one.
 *
 * Contract (see vsource.h for the source and sink interfaces):
 *  - fbdev sink: mmap of the framebuffer; 16, 24 or 32 bpp packed true colour (any channel order the driver
 *    describes); double-buffered with FBIOPAN_DISPLAY when the virtual height holds two frames (it asks for
 *    that with FBIOPUT_VSCREENINFO) and the driver pans, otherwise single-buffered (the name says "may tear").
 *    Frames smaller than the mode are drawn at the top left. The original pan offset is restored on close.
 *  - fbdev v-sync: FBIO_WAITFORVSYNC in a helper thread, stamped with CLOCK_MONOTONIC on return; a driver that
 *    lacks it fails with HZ_E_UNSUPPORTED on the first wait, one that never returns times out in the loop.
 *  - V4L2 output: single-planar mmap streaming, RGB24, XRGB32 or YUYV (converted from RGB24); a format the
 *    device does not offer is HZ_E_UNSUPPORTED listing the ones it offers. Its v-sync source is the dequeue
 *    timestamps of the buffers, each naming the frame it carried (exact scan-out resolution).
 *  - V4L2 capture: mmap streaming in one of the same formats, for loop-back tests and HDMI grabbers.
 *  - GPIO: edge events (both edges, or one polarity to halve the event load) on chip/line with consumer
 *    "hzrt-vsync" through libgpiod (v1 API, or v2 when built against libgpiod 2.x); a busy line is
 *    HZ_E_DEVICE naming its holder; kernel sequence numbers (v2) count lost events.
 */
#ifndef HZ_PORT_DEVICES_H
#define HZ_PORT_DEVICES_H

#include <stdint.h>

#include "hz/pixconv.h"
#include "sysio.h"
#include "vsource.h"

/* Why a device kind is not in this build ("" when it is). kind: "fbdev", "v4l2", "gpio". */
const char *hz_devices_missing(const char *kind);

hz_status_t hz_fbdev_sink_open(hz_sink_t *s, const char *path, const hz_sysio_t *io, hz_error_t *err);
hz_status_t hz_fbdev_vsource_open(hz_vsource_t *s, const char *path, const hz_sysio_t *io, hz_error_t *err);

/* V4L2 output: the sink and, when vs is not NULL, its dequeue-timestamp v-sync source. w/h 0: keep the
 * device's current size. */
hz_status_t hz_v4l2_out_open(hz_sink_t *sink, hz_vsource_t *vs, const char *path, hz_pix_fmt_t fmt, int w, int h,
                             const hz_sysio_t *io, hz_error_t *err);

typedef struct hz_v4l2_frame {
    const uint8_t *data;
    size_t bytes, stride;
    int index;
    uint32_t sequence;
    int64_t t_ns;      /* buffer timestamp (CLOCK_MONOTONIC when the driver says so) */
    int monotonic;     /* the driver stamps with CLOCK_MONOTONIC */
} hz_v4l2_frame_t;

typedef struct hz_v4l2_cap hz_v4l2_cap_t;
hz_status_t hz_v4l2_cap_open(hz_v4l2_cap_t **cap, const char *path, hz_pix_fmt_t fmt, int w, int h,
                             const hz_sysio_t *io, hz_error_t *err);
/* Waits up to timeout_ms for a filled buffer; HZ_E_TIMEOUT when none came. Give it back with release. */
hz_status_t hz_v4l2_cap_next(hz_v4l2_cap_t *cap, int timeout_ms, hz_v4l2_frame_t *f, hz_error_t *err);
hz_status_t hz_v4l2_cap_release(hz_v4l2_cap_t *cap, int index, hz_error_t *err);
void hz_v4l2_cap_close(hz_v4l2_cap_t *cap);
void hz_v4l2_cap_size(const hz_v4l2_cap_t *cap, int *w, int *h, size_t *stride);

typedef struct hz_gpio_cfg {
    const char *chip;  /* name ("gpiochip0"), path ("/dev/gpiochip0"), label ("pinctrl-bcm2711") or number */
    int line;
    int active_low;
    const char *consumer; /* NULL: "hzrt-vsync" */
    int one_edge;         /* 0: both edges (pulse widths in the report); 1: rising only; -1: falling only */
} hz_gpio_cfg_t;

hz_status_t hz_gpio_vsource_open(hz_vsource_t *s, const hz_gpio_cfg_t *cfg, hz_error_t *err);
/* "libgpiod 1.6.3 (v1 API)" and the like, or why GPIO is off. */
const char *hz_gpio_backend(void);

#endif
