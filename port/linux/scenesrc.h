/*
 * scenesrc.h — the hook where the frame loop gets a rendered scene (hzrt latency --render scene, the VM
 * loop-back test, the simulated 240 Hz run).
 *
 * Contract: hz_scene_framesrc() fills *src with a frame source (hz/framesrc.h) that renders `scene` (a baked
 * .hzb path, or "builtin") at w x h into the loop's RGB24 buffer in `mode` (HZ_MODE_TDENSE or HZ_MODE_FULL),
 * animated to req->display_ns. Setup (scene load, BVH build, arenas) happens here, once (it starts the static
 * thread pool with `threads` threads, 0: one per core); render() allocates nothing.
 * Scene time 0 is the first frame's display time. Errors (the scene or its renderer does not fit the board's
 * arenas) name the arena and both byte counts.
 */
#ifndef HZ_PORT_SCENESRC_H
#define HZ_PORT_SCENESRC_H

#include "hz/framesrc.h"
#include "hz/render.h"
#include "hz/status.h"

/* scale >= 1 renders at (w / scale) x (h / scale) and shows each rendered pixel as a scale x scale block, the
 * cheap way to drive a panel whose resolution the CPU cannot fill at its refresh rate (and to keep the VM tier's
 * software-emulated renders short). w and h must be multiples of scale. */
hz_status_t hz_scene_framesrc(hz_framesrc_t *src, const char *scene, int w, int h, int scale, int threads,
                              hz_render_mode_t mode, hz_error_t *err);

#endif
