/*
 * filesink.h — files as the frame loop's sink (hz/display.h): every presented frame appended to a Y4M video, the
 * last one kept for last.png.
 *
 * Contract: hz_file_sink_open() starts DIR/frames.y4m (when `video`; through a temporary file) at w x h and
 * `hz` frames per second; present() appends the frame (RGB24 as exact sRGB codes, so the video holds the bytes
 * hz_y4m_write gives for the linear frame) and remembers it; warm-up frames (id UINT64_MAX) are not kept. The
 * video is converted and written by a thread of the sink's own, overlapping the next frame: present() copies the
 * frame into one of two buffers and waits only while both are still to be written; a write that fails is
 * reported by the next present() or by the commit (its message names the file).
 * hz_file_sink_last() is the last frame presented (valid while the loop's image is: until its arena is reset).
 * hz_file_sink_commit() waits for the writer, then renames the video into place; close() without a commit
 * discards it (frames not yet written are dropped). Nothing is allocated per frame.
 */
#ifndef HZ_PORT_FILESINK_H
#define HZ_PORT_FILESINK_H

#include <stdbool.h>

#include "hz/display.h"

typedef struct hz_file_sink_cfg {
    const char *dir;
    bool video;
    uint32_t hz;
    int w, h;
} hz_file_sink_cfg_t;

hz_status_t hz_file_sink_open(hz_sink_t *s, const hz_file_sink_cfg_t *cfg, hz_error_t *err);
const hz_rgb8_image_t *hz_file_sink_last(const hz_sink_t *s);
uint64_t hz_file_sink_frames(const hz_sink_t *s);
hz_status_t hz_file_sink_commit(hz_sink_t *s, hz_error_t *err);

#endif
