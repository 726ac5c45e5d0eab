/* Files as the frame loop's sink (see filesink.h). */
#include "filesink.h"

#include <stdio.h>
#include <string.h>

#include "imageio.h"

typedef struct file_sink {
    bool used, video_open;
    hz_y4m_t y4m;
    hz_rgb8_image_t last;
    bool have_last;
    uint64_t frames;
} file_sink_t;

static file_sink_t one; /* one file sink at a time */

static hz_status_t present(hz_sink_t *s, const hz_rgb8_image_t *img, uint64_t id, hz_error_t *err)
{
    file_sink_t *f = s->impl;
    if (id == UINT64_MAX)
        return HZ_OK;
    if (f->video_open) {
        hz_status_t st = hz_y4m_write_rgb8(&f->y4m, img->rgb, (uint32_t)img->w, (uint32_t)img->h, img->stride, err);
        if (st != HZ_OK)
            return st;
    }
    f->last = *img;
    f->have_last = true;
    f->frames++;
    return HZ_OK;
}

static void close_sink(hz_sink_t *s)
{
    file_sink_t *f = s->impl;
    if (!f)
        return;
    if (f->video_open)
        hz_y4m_abort(&f->y4m);
    f->video_open = false;
    f->used = false;
    s->impl = NULL;
}

hz_status_t hz_file_sink_open(hz_sink_t *s, const hz_file_sink_cfg_t *cfg, hz_error_t *err)
{
    memset(s, 0, sizeof *s);
    file_sink_t *f = &one;
    if (f->used)
        return hz_error_set(err, HZ_E_INTERNAL, "file sink: already open");
    memset(f, 0, sizeof *f);
    if (cfg->video) {
        char path[4096];
        snprintf(path, sizeof path, "%s/frames.y4m", cfg->dir);
        hz_y4m_opts_t yo = { HZ_Y4M_C420JPEG, HZ_Y4M_BT709, true, cfg->hz, 1 };
        hz_status_t st = hz_y4m_open(&f->y4m, path, (uint32_t)cfg->w, (uint32_t)cfg->h, &yo, err);
        if (st != HZ_OK)
            return st;
        f->video_open = true;
    }
    f->used = true;
    snprintf(s->name, sizeof s->name, "files in %s%s", cfg->dir, cfg->video ? " (frames.y4m, last frame)" : " (last frame)");
    s->w = cfg->w, s->h = cfg->h;
    s->present = present;
    s->close = close_sink;
    s->impl = f;
    return HZ_OK;
}

const hz_rgb8_image_t *hz_file_sink_last(const hz_sink_t *s)
{
    const file_sink_t *f = s->impl;
    return f && f->have_last ? &f->last : NULL;
}

uint64_t hz_file_sink_frames(const hz_sink_t *s)
{
    const file_sink_t *f = s->impl;
    return f ? f->frames : 0;
}

hz_status_t hz_file_sink_commit(hz_sink_t *s, hz_error_t *err)
{
    file_sink_t *f = s->impl;
    if (!f || !f->video_open)
        return HZ_OK;
    f->video_open = false;
    return hz_y4m_close(&f->y4m, err);
}
