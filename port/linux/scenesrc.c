/* The built-in scene as a frame source (see scenesrc.h): the renderer of issue 5 behind hz_framesrc_t. */
#include "scenesrc.h"

#include <string.h>
#include <unistd.h>

#include "accel_backend.h"
#include "hz/image.h"
#include "hz/render.h"
#include "pools.h"
#include "scenefile.h"
#include "threads.h"

typedef struct scene_src {
    int open;
    hz_scene_t scene;
    hz_accel_t *accel;
    hz_renderer_t *r;
    int threads;
    int have_t0;
    int64_t t0_ns;
    int scale;
    uint8_t *row; /* one rendered row in sRGB (scaled renders) */
    hz_arena_mark_t scene_mark, accel_mark, frame_mark;
} scene_src_t;

static scene_src_t g;

typedef struct job {
    hz_renderer_t *r;
    uint32_t pass;
} job_t;

static void run_item(void *user, uint32_t item, int thread)
{
    job_t *j = (job_t *)user;
    hz_render_pass_run(j->r, j->pass, item, (uint32_t)thread);
}

static hz_status_t render_scene(void *ctx, const hz_frame_req_t *req, hz_rgb8_image_t *out, hz_error_t *err)
{
    scene_src_t *s = ctx;
    /* Animation time is the frame's scan-out time, so motion on screen follows the display's clock. */
    if (!s->have_t0) {
        s->t0_ns = req->display_ns;
        s->have_t0 = 1;
    }
    float t = (float)((double)(req->display_ns - s->t0_ns) * 1e-9);
    hz_status_t st = hz_render_begin_frame(s->r, req->id, t, err);
    if (st != HZ_OK)
        return st;
    for (uint32_t p = 0; p < hz_render_pass_count(s->r); p++) {
        job_t j = { s->r, p };
        hz_threads_run(run_item, &j, hz_render_pass_items(s->r, p));
    }
    hz_render_end_frame(s->r);
    const hz_image_t *img = hz_render_output(s->r);
    if (s->scale == 1) {
        for (int y = 0; y < out->h; y++)
            hz_srgb8_encode_n(img->rgb + (size_t)y * img->width * 3, out->rgb + (size_t)y * out->stride,
                              (size_t)out->w * 3);
        return HZ_OK;
    }
    for (int y = 0; y < out->h; y++) {
        uint8_t *d = out->rgb + (size_t)y * out->stride;
        if (y % s->scale) {
            memcpy(d, d - out->stride, (size_t)out->w * 3);
            continue;
        }
        hz_srgb8_encode_n(img->rgb + (size_t)(y / s->scale) * img->width * 3, s->row, (size_t)img->width * 3);
        for (int x = 0; x < out->w; x++)
            memcpy(d + (size_t)x * 3, s->row + (size_t)(x / s->scale) * 3, 3);
    }
    return HZ_OK;
}

void hz_scene_framesrc_close(void)
{
    if (!g.open)
        return;
    hz_threads_stop();
    if (g.accel)
        hz_accel_release(g.accel);
    /* Give the arenas back as they were before the open (everything allocated since is released). */
    hz_pools_t *pools = hz_pools_get();
    hz_arena_reset(&pools->frame, g.frame_mark);
    hz_arena_reset(&pools->accel, g.accel_mark);
    hz_arena_reset(&pools->scene, g.scene_mark);
    memset(&g, 0, sizeof g);
}

hz_status_t hz_scene_framesrc(hz_framesrc_t *src, int w, int h, int scale, hz_error_t *err)
{
    hz_scene_framesrc_close();
    if (scale < 1 || scale > 64 || w < 1 || h < 1)
        return hz_error_set(err, HZ_E_INVALID_ARG, "built-in scene: %dx%d at scale %d", w, h, scale);
    hz_pools_t *pools = hz_pools_get();
    if (!pools)
        return hz_error_set(err, HZ_E_INTERNAL, "built-in scene: could not set up the static arenas");
    g.scene_mark = hz_arena_mark(&pools->scene);
    g.accel_mark = hz_arena_mark(&pools->accel);
    g.frame_mark = hz_arena_mark(&pools->frame);
    g.open = 1;
    hz_status_t s = hz_scenefile_open("builtin", pools, &g.scene, err);
    hz_accel_geom_t geom;
    if (s == HZ_OK)
        s = hz_render_accel_geom(&g.scene, &pools->accel, &geom, err);
    if (s == HZ_OK)
        s = hz_accel_backend_build(HZ_ACCEL_NATIVE, &g.accel, &geom, &pools->accel, err);
    if (s != HZ_OK) {
        hz_scene_framesrc_close();
        return s;
    }
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    g.threads = cpus < 1 ? 1 : cpus > HZ_MAX_THREADS ? HZ_MAX_THREADS : (int)cpus;
    s = hz_threads_start(g.threads, err);
    if (s != HZ_OK) {
        hz_accel_release(g.accel);
        g.accel = NULL;
        hz_scene_framesrc_close();
        return s;
    }
    g.scale = scale;
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = (uint32_t)((w + scale - 1) / scale);
    o.height = (uint32_t)((h + scale - 1) / scale);
    if (scale > 1 && !(g.row = hz_arena_alloc(&pools->frame, (size_t)o.width * 3, 64))) {
        hz_arena_error(&pools->frame, err);
        hz_scene_framesrc_close();
        return err ? err->code : HZ_E_NO_MEMORY;
    }
    s = hz_render_create(&g.r, &g.scene, g.accel, &o, &pools->frame, pools->thread, (uint32_t)g.threads, err);
    if (s != HZ_OK) {
        hz_scene_framesrc_close();
        return s;
    }
    src->name = scale > 1 ? "built-in scene (scaled up)" : "built-in scene";
    src->ctx = &g;
    src->render = render_scene;
    return HZ_OK;
}
