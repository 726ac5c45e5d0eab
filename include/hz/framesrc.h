/*
 * hz/framesrc.h — what the frame loop asks for: "render frame n into this RGB buffer".
 *
 * Contract: the frame loop (hz/frameloop.h) owns the image buffer (W x H RGB24 from the frame arena) and calls
 * render() once per frame, from one thread, in frame order. req->display_ns is the predicted scan-out time of
 * the frame's target edge (animate the scene to that instant, not to "now"); req->slot is that edge's number
 * on the display (refreshes since the v-sync model's origin: the difference of two frames' slots is exactly how
 * many refreshes apart they are shown, the way to exact animation times on a simulated display); req->period_ns
 * is the display period. req->level is the quality level the governor chose (0: the best; a source without
 * levels always gets 0). render() fills every pixel and returns HZ_OK, or an error in err (the loop stops and
 * reports it). It must not allocate: steady-state frames allocate nothing anywhere.
 * A source with quality levels describes them in `levels` (hz/governor.h: their number and prior cost
 * weights); NULL: one level.
 *
 * Two sources exist: hz_framesrc_testpattern() below (deterministic, cheap: tests and wiring checks) and the
 * built-in scene through the renderer (port/linux/scenesrc.h: `hzrt latency --render scene`).
 */
#ifndef HZ_FRAMESRC_H
#define HZ_FRAMESRC_H

#include <stddef.h>
#include <stdint.h>

#include "hz/status.h"

typedef struct hz_rgb8_image {
    uint8_t *rgb;  /* RGB24 */
    int w, h;
    size_t stride; /* bytes per row, >= 3 w */
} hz_rgb8_image_t;

typedef struct hz_frame_req {
    uint64_t id;        /* frame number, 0, 1, 2, ... */
    int64_t display_ns; /* predicted scan-out time (CLOCK_MONOTONIC domain, or the simulation's clock) */
    int64_t period_ns;
    int64_t slot;       /* the target edge's slot */
    uint32_t level;     /* quality level, 0 = best */
} hz_frame_req_t;

struct hz_gov_cfg;

typedef struct hz_framesrc {
    const char *name; /* for reports: "test pattern", "built-in scene" */
    void *ctx;
    hz_status_t (*render)(void *ctx, const hz_frame_req_t *req, hz_rgb8_image_t *out, hz_error_t *err);
    const struct hz_gov_cfg *levels; /* NULL: one quality level */
} hz_framesrc_t;

/* The synthetic source: hz_testpattern_draw() of the frame id. ctx is unused. */
hz_framesrc_t hz_framesrc_testpattern(void);

/* A moving pattern that depends only on (id, w, h): a gradient, a hashed 8x8 checker that changes every 16
 * frames, a vertical bar moving 8 px and a horizontal bar moving 4 px per frame. Every pixel of two
 * consecutive frames' bars differs, so a repeated or torn frame shows. */
void hz_testpattern_draw(uint8_t *rgb, size_t stride, int w, int h, uint64_t id);

#endif /* HZ_FRAMESRC_H */
