/*
 * scenesrc.h — the built-in scene as a frame source for the display-locked frame loop (hzrt latency --render
 * scene, the VM loop-back test, make latency-sim).
 *
 * Contract: hz_scene_framesrc() loads the built-in scene into the board's pools (scene arena), builds the
 * native BVH (accel arena), starts the worker pool and creates a renderer at ceil(w / scale) x ceil(h / scale)
 * with the renderer's default options (frame arena, thread arenas): all the allocation happens here, once.
 * scale > 1 renders fewer pixels and repeats each one scale x scale times (nearest neighbour), for displays
 * larger than the renderer sustains (software emulation, slow boards). The returned source's render()
 * animates the scene to the frame's predicted scan-out time (req->display_ns, counted from the first frame's),
 * renders it on the worker pool and writes 8-bit sRGB into the loop's RGB24 buffer; it allocates nothing.
 * Errors keep the loader's, accel's and renderer's status codes (HZ_E_NO_MEMORY names the arena and both
 * byte counts when the board's arenas are too small for the size asked for).
 * hz_scene_framesrc_close() stops the workers, releases the accel and resets the scene, accel and frame arenas
 * to where they were before the open (so anything allocated from them since, loop records included, is gone:
 * close after the results are used). One scene source exists at a time.
 */
#ifndef HZ_PORT_SCENESRC_H
#define HZ_PORT_SCENESRC_H

#include "hz/framesrc.h"
#include "hz/status.h"

hz_status_t hz_scene_framesrc(hz_framesrc_t *src, int w, int h, int scale, hz_error_t *err);
void hz_scene_framesrc_close(void);

#endif
