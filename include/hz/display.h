/*
 * hz/display.h — where v-sync edges come from, where frames go, and whose clock the frame loop runs on: the
 * interfaces between the portable frame loop (hz/frameloop.h) and a port's devices.
 *
 * Contract:
 *  - A timebase is either real (the port's CLOCK_MONOTONIC, sleeping for real: hz_tb_init_real in the port) or
 *    virtual (a counter the loop advances: simulations run as fast as the CPU allows and are bit-for-bit
 *    repeatable; hz_tb_init_virtual here).
 *  - A v-sync source delivers edges in time order. Live sources (GPIO, fbdev FBIO_WAITFORVSYNC, V4L2 output
 *    dequeue, DRM vblank) stamp edges with the kernel's CLOCK_MONOTONIC and block in next() until an edge arrives
 *    or the deadline passes (HZ_VS_TIMEOUT). Timeline sources (simulated display, VCD/CSV replay) know every edge
 *    in advance: next() returns the next one at once (or HZ_VS_END) and the frame loop maps their time onto its
 *    own clock, sleeping until each edge in real time or jumping to it in virtual time.
 *  - An edge may carry the id of a frame it concerns (V4L2 output: the frame whose buffer came back at it),
 *    else -1; it is logged, resolution uses the scan-out rule of hz/frames.h.
 *    A source whose edges are the sink's own refreshes (needs_frames) only ticks while frames are queued: the
 *    frame loop keeps it fed with blank warm-up frames (id UINT64_MAX) until the v-sync model locks.
 *  - A sink shows an RGB24 frame (present) and reports its mode; present() must not block for long (a full
 *    V4L2 queue waits for a buffer at most one second, then fails). A sink may also keep what it is shown (files).
 *  - close() releases everything; every source and sink can be closed after a failed open (no-op).
 * Errors name the device or file and the reason, with distinct hz status codes: a missing node or busy line
 * is HZ_E_DEVICE, an ioctl the driver lacks HZ_E_UNSUPPORTED, a silent display HZ_E_TIMEOUT.
 */
#ifndef HZ_DISPLAY_H
#define HZ_DISPLAY_H

#include <stdint.h>

#include "hz/framesrc.h"
#include "hz/status.h"

typedef struct hz_timebase {
    int virtual_time;
    int64_t vnow;
    /* real time: the port's clock (set by its hz_tb_init_real) */
    int64_t (*clock_now)(void);
    void (*clock_sleep_until)(int64_t t_ns);
} hz_timebase_t;

void hz_tb_init_virtual(hz_timebase_t *tb, int64_t start_ns);
int64_t hz_tb_now(const hz_timebase_t *tb);
/* Real: sleeps until t (absolute, the port's clock). Virtual: the clock jumps to t if t is later. */
void hz_tb_sleep_until(hz_timebase_t *tb, int64_t t);
/* Virtual only: time passes (a modelled render). */
void hz_tb_advance(hz_timebase_t *tb, int64_t dt);

enum { HZ_VS_EDGE = 1, HZ_VS_TIMEOUT, HZ_VS_END };

typedef struct hz_edge {
    int64_t t_ns;
    int level;        /* 1 rising, 0 falling */
    int64_t frame_id; /* the frame shown at this edge, -1 if the source cannot tell */
} hz_edge_t;

typedef struct hz_vsource hz_vsource_t;
struct hz_vsource {
    char name[160];
    int live;            /* 1: device edges in CLOCK_MONOTONIC; 0: a timeline */
    int both_levels;     /* edges of both polarities are reported */
    int needs_frames;    /* edges come only while frames are queued (V4L2 output): the loop primes it */
    uint64_t dropped;    /* edges the kernel said it lost */
    /* Live: wait until deadline_ns (CLOCK_MONOTONIC). Timeline: deadline ignored. *result is HZ_VS_*. */
    hz_status_t (*next)(hz_vsource_t *s, int64_t deadline_ns, hz_edge_t *e, int *result, hz_error_t *err);
    void (*close)(hz_vsource_t *s);
    void *impl;
};

typedef struct hz_sink hz_sink_t;
struct hz_sink {
    char name[160];
    int w, h;            /* the mode frames must have; 0: any size */
    hz_status_t (*present)(hz_sink_t *s, const hz_rgb8_image_t *img, uint64_t id, hz_error_t *err);
    void (*close)(hz_sink_t *s);
    void *impl;
};

void hz_vsource_close(hz_vsource_t *s);
void hz_sink_close(hz_sink_t *s);

#endif
