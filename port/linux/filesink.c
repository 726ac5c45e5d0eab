/* Files as the frame loop's sink (see filesink.h). */
#include "filesink.h"

#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "imageio.h"

/* The video is written by a thread of its own, so that a frame's conversion to Y'CbCr and its write overlap
 * the next frame's rendering: present() copies the frame into one of two buffers and returns; it waits only
 * when both hold frames not yet written. After its first failure the writer writes nothing more and keeps the
 * error: the next present() or the commit reports it. Only the writer touches the Y4M stream until commit or
 * close has joined it. */
#define BUFFERS 2

typedef struct file_sink {
    bool used, video_open;
    hz_y4m_t y4m;
    hz_rgb8_image_t last;
    bool have_last;
    uint64_t frames;
    /* the writer */
    bool writer;
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t cv;
    uint8_t *buf[BUFFERS];
    int w, h;
    unsigned head, pending; /* buf[head] is the next frame to write; `pending` frames wait */
    bool stop, discard, failed;
    hz_error_t werr;
} file_sink_t;

static file_sink_t one; /* one file sink at a time */

static void *writer_main(void *arg)
{
    file_sink_t *f = arg;
    pthread_mutex_lock(&f->lock);
    for (;;) {
        while (f->pending == 0 && !f->stop)
            pthread_cond_wait(&f->cv, &f->lock);
        if (f->pending == 0 || f->discard)
            break;
        const uint8_t *rgb = f->buf[f->head];
        bool write = !f->failed;
        pthread_mutex_unlock(&f->lock);
        hz_error_t e;
        hz_status_t st =
            write ? hz_y4m_write_rgb8(&f->y4m, rgb, (uint32_t)f->w, (uint32_t)f->h, (size_t)f->w * 3, &e) : HZ_OK;
        pthread_mutex_lock(&f->lock);
        if (st != HZ_OK && !f->failed) {
            f->werr = e;
            f->failed = true;
        }
        f->head = (f->head + 1) % BUFFERS;
        f->pending--;
        pthread_cond_broadcast(&f->cv);
    }
    pthread_mutex_unlock(&f->lock);
    return NULL;
}

/* Waits for the writer to finish (every queued frame written, or none when `discard`) and joins it. */
static void writer_stop(file_sink_t *f, bool discard)
{
    if (!f->writer)
        return;
    pthread_mutex_lock(&f->lock);
    f->stop = true;
    f->discard = discard;
    pthread_cond_broadcast(&f->cv);
    pthread_mutex_unlock(&f->lock);
    pthread_join(f->thread, NULL);
    pthread_cond_destroy(&f->cv);
    pthread_mutex_destroy(&f->lock);
    f->writer = false;
}

static hz_status_t failure(const file_sink_t *f, hz_error_t *err)
{
    if (err)
        *err = f->werr;
    return f->werr.code != HZ_OK ? f->werr.code : HZ_E_IO;
}

static hz_status_t present(hz_sink_t *s, const hz_rgb8_image_t *img, uint64_t id, hz_error_t *err)
{
    file_sink_t *f = s->impl;
    if (id == UINT64_MAX)
        return HZ_OK;
    if (f->video_open) {
        if (img->w != f->w || img->h != f->h)
            return hz_error_set(err, HZ_E_INVALID_ARG, "file sink: frame is %dx%d, the video %dx%d", img->w, img->h,
                                f->w, f->h);
        pthread_mutex_lock(&f->lock);
        while (f->pending == BUFFERS && !f->failed)
            pthread_cond_wait(&f->cv, &f->lock);
        bool failed = f->failed;
        unsigned slot = (f->head + f->pending) % BUFFERS;
        pthread_mutex_unlock(&f->lock);
        if (failed)
            return failure(f, err);
        /* The slot is free: the writer reads only the `pending` buffers from head on. */
        for (int y = 0; y < img->h; y++)
            memcpy(f->buf[slot] + (size_t)y * (size_t)f->w * 3, img->rgb + (size_t)y * img->stride, (size_t)f->w * 3);
        pthread_mutex_lock(&f->lock);
        f->pending++;
        pthread_cond_broadcast(&f->cv);
        pthread_mutex_unlock(&f->lock);
    }
    f->last = *img;
    f->have_last = true;
    f->frames++;
    return HZ_OK;
}

static void free_buffers(file_sink_t *f)
{
    for (int i = 0; i < BUFFERS; i++) {
        free(f->buf[i]);
        f->buf[i] = NULL;
    }
}

static void close_sink(hz_sink_t *s)
{
    file_sink_t *f = s->impl;
    if (!f)
        return;
    writer_stop(f, true);
    if (f->video_open)
        hz_y4m_abort(&f->y4m);
    free_buffers(f);
    f->video_open = false;
    f->used = false;
    s->impl = NULL;
}

static hz_status_t start_writer(file_sink_t *f, hz_error_t *err)
{
    const size_t bytes = (size_t)f->w * (size_t)f->h * 3;
    for (int i = 0; i < BUFFERS; i++)
        if (!(f->buf[i] = malloc(bytes ? bytes : 1)))
            return hz_error_set(err, HZ_E_NO_MEMORY, "file sink: no memory for %d frames of %zu bytes", BUFFERS,
                                bytes);
    if (pthread_mutex_init(&f->lock, NULL) != 0)
        return hz_error_set(err, HZ_E_DEVICE, "file sink: cannot make the writer's lock");
    if (pthread_cond_init(&f->cv, NULL) != 0) {
        pthread_mutex_destroy(&f->lock);
        return hz_error_set(err, HZ_E_DEVICE, "file sink: cannot make the writer's condition");
    }
    /* The writer takes no signals: the frame loop's thread handles them (an interrupt ends the run cleanly). */
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, &old);
    int e = pthread_create(&f->thread, NULL, writer_main, f);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (e != 0) {
        pthread_cond_destroy(&f->cv);
        pthread_mutex_destroy(&f->lock);
        return hz_error_set(err, HZ_E_DEVICE, "file sink: cannot start the writer: %s", strerror(e));
    }
    f->writer = true;
    return HZ_OK;
}

hz_status_t hz_file_sink_open(hz_sink_t *s, const hz_file_sink_cfg_t *cfg, hz_error_t *err)
{
    memset(s, 0, sizeof *s);
    file_sink_t *f = &one;
    if (f->used)
        return hz_error_set(err, HZ_E_INTERNAL, "file sink: already open");
    memset(f, 0, sizeof *f);
    f->w = cfg->w, f->h = cfg->h;
    if (cfg->video) {
        char path[4096];
        snprintf(path, sizeof path, "%s/frames.y4m", cfg->dir);
        hz_y4m_opts_t yo = { HZ_Y4M_C420JPEG, HZ_Y4M_BT709, true, cfg->hz, 1 };
        hz_status_t st = hz_y4m_open(&f->y4m, path, (uint32_t)cfg->w, (uint32_t)cfg->h, &yo, err);
        if (st != HZ_OK)
            return st;
        f->video_open = true;
        if ((st = start_writer(f, err)) != HZ_OK) {
            hz_y4m_abort(&f->y4m);
            free_buffers(f);
            f->video_open = false;
            return st;
        }
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
    writer_stop(f, false);
    free_buffers(f);
    if (f->failed) {
        hz_status_t st = failure(f, err);
        hz_y4m_abort(&f->y4m);
        f->video_open = false;
        return st;
    }
    f->video_open = false;
    return hz_y4m_close(&f->y4m, err);
}
