/*
 * The built-in scene as a frame source (see scenesrc.h).
 *
 * PLUG-IN POINT for the renderer: replace the body of hz_scene_framesrc() with "build the built-in scene once
 * (pools: scene/accel/frame arenas), then set src->render to a function that renders it at req->display_ns into
 * out->rgb (RGB24, out->stride bytes per row)". Nothing else in the timing path changes: the frame loop, the
 * marker, the sinks and the VM loop-back test all take whatever hz_framesrc_t this returns.
 */
#include "scenesrc.h"

hz_status_t hz_scene_framesrc(hz_framesrc_t *src, int w, int h, hz_error_t *err)
{
    (void)src;
    return hz_error_set(err, HZ_E_UNSUPPORTED,
                        "--render scene: the renderer is not in this build yet (issue 5); the built-in scene "
                        "plugs in at port/linux/scenesrc.c (%dx%d requested); use --render pattern", w, h);
}
