/*
 * render_fixture.h — shared by the renderer tests: open a scene into the board pools, build the accel, render
 * a sequence with the thread pool, compare images. Header-only (static functions) so each test binary stays
 * self-contained.
 */
#ifndef HZ_TEST_RENDER_FIXTURE_H
#define HZ_TEST_RENDER_FIXTURE_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accel_backend.h"
#include "hz/render.h"
#include "pools.h"
#include "render_run.h"
#include "scenefile.h"
#include "threads.h"

/* Not every test uses every helper. */
#define HZ_UNUSED_FN __attribute__((unused))

typedef struct rfix {
    hz_pools_t *pools;
    hz_scene_t scene;
    hz_accel_t *accel;
    hz_renderer_t *r;
    hz_arena_mark_t scene_mark, accel_mark, frame_mark, thread_marks[HZ_MAX_THREADS];
    int threads;
} rfix_t;

/* Path of a baked scene in $HZ_SCENES_DIR (NULL when the variable is unset). */
HZ_UNUSED_FN static const char *rfix_scene_path(const char *file, char *buf, size_t size)
{
    const char *dir = getenv("HZ_SCENES_DIR");
    if (!dir)
        return NULL;
    snprintf(buf, size, "%s/%s", dir, file);
    return buf;
}

/* Marks the pools (rfix_close goes back to them) and opens the scene. */
static hz_status_t rfix_open_scene(rfix_t *f, const char *scene, hz_error_t *err)
{
    memset(f, 0, sizeof *f);
    f->pools = hz_pools_get();
    if (!f->pools)
        return hz_error_set(err, HZ_E_INTERNAL, "no pools");
    f->scene_mark = hz_arena_mark(&f->pools->scene);
    f->accel_mark = hz_arena_mark(&f->pools->accel);
    f->frame_mark = hz_arena_mark(&f->pools->frame);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        f->thread_marks[t] = hz_arena_mark(&f->pools->thread[t]);
    return hz_scenefile_open(scene, f->pools, &f->scene, err);
}

static hz_status_t rfix_open(rfix_t *f, const char *scene, hz_accel_backend_t backend, hz_error_t *err)
{
    hz_status_t s = rfix_open_scene(f, scene, err);
    if (s != HZ_OK)
        return s;
    hz_accel_geom_t g;
    s = hz_accel_geom_from_scene(&g, &f->scene, &f->pools->accel, err);
    if (s == HZ_OK)
        s = hz_accel_backend_build(backend, &f->accel, &g, &f->pools->accel, err);
    return s;
}

/* rfix_open with the native accel on "builtin" or on a file of $HZ_SCENES_DIR (HZ_E_INVALID_ARG when the
 * variable is unset: make test sets it). */
HZ_UNUSED_FN static hz_status_t rfix_open_named(rfix_t *f, const char *name, hz_error_t *err)
{
    char buf[512];
    const char *scene = strcmp(name, "builtin") ? rfix_scene_path(name, buf, sizeof buf) : "builtin";
    if (!scene)
        return hz_error_set(err, HZ_E_INVALID_ARG, "HZ_SCENES_DIR is not set (make test sets it): %s is needed",
                            name);
    return rfix_open(f, scene, HZ_ACCEL_NATIVE, err);
}

HZ_UNUSED_FN static hz_status_t rfix_renderer(rfix_t *f, const hz_render_opts_t *o, int threads, hz_error_t *err)
{
    hz_arena_reset(&f->pools->frame, f->frame_mark);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        hz_arena_reset(&f->pools->thread[t], f->thread_marks[t]);
    hz_threads_stop();
    hz_status_t s = hz_threads_start(threads, err);
    if (s != HZ_OK)
        return s;
    f->threads = threads;
    return hz_render_create(&f->r, &f->scene, f->accel, o, &f->pools->frame, f->pools->thread, (uint32_t)threads,
                            err);
}

HZ_UNUSED_FN static hz_status_t rfix_frame(rfix_t *f, uint64_t index, float t, hz_error_t *err)
{
    return hz_render_run_frame(f->r, index, t, err);
}

static void rfix_close(rfix_t *f)
{
    hz_threads_stop();
    hz_accel_release(f->accel);
    if (!f->pools)
        return;
    hz_arena_reset(&f->pools->frame, f->frame_mark);
    hz_arena_reset(&f->pools->accel, f->accel_mark);
    hz_arena_reset(&f->pools->scene, f->scene_mark);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        hz_arena_reset(&f->pools->thread[t], f->thread_marks[t]);
}

/* PSNR in dB of two linear images after clamping to [0, 1] (inf for identical images). */
HZ_UNUSED_FN static double rfix_psnr(const hz_image_t *a, const hz_image_t *b)
{
    double se = 0;
    size_t n = hz_image_pixels(a) * 3;
    for (size_t i = 0; i < n; i++) {
        double x = a->rgb[i] < 0 ? 0 : a->rgb[i] > 1 ? 1 : a->rgb[i];
        double y = b->rgb[i] < 0 ? 0 : b->rgb[i] > 1 ? 1 : b->rgb[i];
        se += (x - y) * (x - y);
    }
    return se == 0 ? INFINITY : 10.0 * log10(n / se);
}

#endif
