/*
 * scenesrc.h — the hook where the frame loop gets "the built-in scene" (hzrt latency --render scene, the VM
 * loop-back test, the simulated 240 Hz run).
 *
 * Contract: hz_scene_framesrc() fills *src with a frame source (hz/framesrc.h) that renders the built-in scene
 * at w x h into the loop's RGB24 buffer, animated to req->display_ns. Setup (scene load, BVH build, arenas) may
 * happen here, once; render() must not allocate. Until the renderer exists it returns HZ_E_UNSUPPORTED and
 * callers fall back to, or ask for, the test pattern.
 */
#ifndef HZ_PORT_SCENESRC_H
#define HZ_PORT_SCENESRC_H

#include "hz/framesrc.h"
#include "hz/status.h"

hz_status_t hz_scene_framesrc(hz_framesrc_t *src, int w, int h, hz_error_t *err);

#endif
