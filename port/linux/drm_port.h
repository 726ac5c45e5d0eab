/*
 * drm_port.h — DRM/KMS display sink and its v-sync source (libdrm; port "drm" in BOARD_PORTS, HZ_PORT_DRM).
 *
 * Contract:
 *  - hz_drm_sink_open() opens a card (/dev/dri/cardN, "cardN" or "N"; NULL or "": the first card with a
 *    connected connector), becomes DRM master, picks a connector (its name like "HDMI-A-1" / "Virtual-1", its
 *    numeric id, or NULL: the first connected one), a mode (w x h @ millihertz; 0: the connector's preferred
 *    mode, else its first), a CRTC the connector's encoders can drive, and creates `buffers` (2 or 3) XRGB8888
 *    dumb buffers (drmModeAddFB2). It sets the mode with a black frame; the old CRTC state comes back on close.
 *  - present() converts the RGB24 frame to XRGB8888 into a buffer that is neither scanned out nor waiting for
 *    a flip, waits (at most 1 s) for a pending flip to complete, then drmModePageFlip(..,
 *    DRM_MODE_PAGE_FLIP_EVENT): one flip in flight at a time, as legacy KMS allows. Frames must have the mode's
 *    size (sink w/h).
 *  - The v-sync source (vs not NULL): with drmCrtcGetSequence/drmCrtcQueueSequence (drivers with vblank
 *    interrupts) every vblank is an edge (ns timestamp, 64-bit sequence), queued one ahead, and flip events
 *    only name the frame each shows; otherwise (e.g. virtio-gpu) the page-flip events are the edges (us
 *    timestamps, 32-bit sequence), each naming the frame that became visible, and the source needs frames
 *    queued (needs_frames). Timestamps are CLOCK_MONOTONIC (refused otherwise).
 *  - Errors are HZ_E_DEVICE naming the card and the reason: no card, not a KMS device, no connected connector
 *    (the message lists the connectors and their state), a mode not offered (lists the offered ones), the
 *    master held by another process; HZ_E_UNSUPPORTED when the driver has no dumb buffers.
 *  - hz_drm_stats() counts flips submitted, flip events received, and how many events came out of order
 *    (timestamp not increasing, or, from a driver that counts vblanks, sequence not increasing; drivers
 *    without a counter send sequence 0): a test's evidence that the events are in order and monotonic.
 */
#ifndef HZ_PORT_DRM_H
#define HZ_PORT_DRM_H

#include <stdint.h>

#include "vsource.h"

typedef struct hz_drm_cfg {
    const char *card;      /* NULL/"": scan /dev/dri/card0..15 */
    const char *connector; /* NULL/"": the first connected */
    int w, h;              /* 0: preferred mode */
    uint32_t millihertz;   /* 0: any refresh at that size */
    int buffers;           /* 2 or 3; 0: 2 */
} hz_drm_cfg_t;

typedef struct hz_drm_stats {
    uint64_t flips, flip_events, vblank_events, out_of_order;
    uint64_t sequenced;   /* events with a nonzero sequence number (0 on drivers without a vblank counter) */
    uint64_t last_sequence;
    int64_t last_t_ns;
    int has_sequence_api; /* drmCrtcQueueSequence works on this CRTC */
} hz_drm_stats_t;

/* "CARD[:CONNECTOR[:WxH[@HZ]]]" (each part may be empty) into cfg; strings point into buf. */
hz_status_t hz_drm_parse_spec(const char *spec, hz_drm_cfg_t *cfg, char *buf, size_t cap, hz_error_t *err);
hz_status_t hz_drm_sink_open(hz_sink_t *sink, hz_vsource_t *vs, const hz_drm_cfg_t *cfg, hz_error_t *err);
void hz_drm_stats(const hz_sink_t *sink, hz_drm_stats_t *st);

#endif
