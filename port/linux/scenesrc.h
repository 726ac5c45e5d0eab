/*
 * scenesrc.h — the hook where the frame loop gets "the built-in scene" (hzrt latency --render scene, the VM
 * loop-back test, the simulated 240 Hz run).
 *
 * Contract: hz_scene_framesrc() fills *src with a frame source (hz/framesrc.h) that renders the built-in scene
 * at w x h into the loop's RGB24 buffer, animated to req->display_ns. Setup (scene load, BVH build, arenas) may
 * happen here, once (it starts the static thread pool with one thread per core); render() allocates nothing.
 * Scene time 0 is the first frame's display time. Errors (the scene or its renderer does not fit the board's
 * arenas) name the arena and both byte counts.
 */
#ifndef HZ_PORT_SCENESRC_H
#define HZ_PORT_SCENESRC_H

#include "hz/framesrc.h"
#include "hz/status.h"

/* scale >= 1 renders at (w / scale) x (h / scale) and shows each rendered pixel as a scale x scale block, the
 * cheap way to drive a panel whose resolution the CPU cannot fill at its refresh rate (and to keep the VM tier's
 * software-emulated renders short). w and h must be multiples of scale. */
hz_status_t hz_scene_framesrc(hz_framesrc_t *src, int w, int h, int scale, hz_error_t *err);

#endif
