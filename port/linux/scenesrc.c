/*
 * A scene as a frame source (see scenesrc.h): the scene, its native BVH and a renderer are set up
 * once in the board pools; each frame animates to the frame's display time (relative to the first frame),
 * renders on the static thread pool and encodes to the loop's RGB24 buffer (exact sRGB, hz_srgb8_encode_n).
 */
#include "scenesrc.h"

#include <string.h>
#include <unistd.h>

#include "accel_backend.h"
#include "hz/image.h"
#include "hz/render.h"
#include "pools.h"
#include "render_run.h"
#include "scenefile.h"
#include "threads.h"

typedef struct scenesrc {
    hz_scene_t scene;
    hz_accel_t *accel;
    hz_renderer_t *r;
    int64_t t0_ns;
    bool have_t0;
    int scale;
    uint8_t *row;       /* one encoded rendered row (scaled mode) */
} scenesrc_t;

static scenesrc_t state;


static hz_status_t render(void *ctx, const hz_frame_req_t *req, hz_rgb8_image_t *out, hz_error_t *err)
{
    scenesrc_t *s = (scenesrc_t *)ctx;
    if (!s->have_t0) {
        s->t0_ns = req->display_ns;
        s->have_t0 = true;
    }
    /* Nanoseconds all the way into the core: a float of seconds since start would quantise the animation
     * after hours of running. */
    hz_status_t st = hz_render_run_frame_ns(s->r, req->id, req->display_ns - s->t0_ns, err);
    if (st != HZ_OK)
        return st;
    const hz_image_t *img = hz_render_output(s->r);
    int k = s->scale;
    if (k == 1) {
        for (int y = 0; y < out->h; y++)
            hz_srgb8_encode_n(img->rgb + (size_t)y * img->width * 3, out->rgb + (size_t)y * out->stride,
                              (size_t)out->w * 3);
        return HZ_OK;
    }
    for (uint32_t y = 0; y < img->height; y++) {
        hz_srgb8_encode_n(img->rgb + (size_t)y * img->width * 3, s->row, (size_t)img->width * 3);
        uint8_t *dst = out->rgb + (size_t)y * (size_t)k * out->stride;
        for (uint32_t x = 0; x < img->width; x++)
            for (int i = 0; i < k; i++)
                hz_memcpy(dst + ((size_t)x * (size_t)k + (size_t)i) * 3, s->row + (size_t)x * 3, 3);
        for (int j = 1; j < k; j++)
            hz_memcpy(dst + (size_t)j * out->stride, dst, (size_t)out->w * 3);
    }
    return HZ_OK;
}

hz_status_t hz_scene_framesrc(hz_framesrc_t *src, const char *scene, int w, int h, int scale, int threads,
                              hz_render_mode_t mode, hz_error_t *err)
{
    scenesrc_t *s = &state;
    hz_pools_t *pools = hz_pools_get();
    if (!pools)
        return hz_error_set(err, HZ_E_INTERNAL, "scene source: no static arenas");
    if (w < 1 || h < 1 || w > (int)HZ_IMAGE_MAX_DIM || h > (int)HZ_IMAGE_MAX_DIM)
        return hz_error_set(err, HZ_E_INVALID_ARG, "scene source: size %dx%d", w, h);
    if (scale < 1 || w % scale || h % scale)
        return hz_error_set(err, HZ_E_INVALID_ARG, "scene source: %dx%d is not a multiple of the render scale %d",
                            w, h, scale);
    s->scale = scale;
    s->row = hz_arena_alloc(&pools->frame, (size_t)(w / scale) * 3, 64);
    if (!s->row)
        return hz_arena_error(&pools->frame, err);
    if (threads < 1) {
        long cores = sysconf(_SC_NPROCESSORS_ONLN);
        threads = cores < 1 ? 1 : (int)cores;
    }
    threads = threads > HZ_MAX_THREADS ? HZ_MAX_THREADS : threads;
    hz_status_t st = hz_scenefile_open(scene, pools, &s->scene, err);
    hz_accel_geom_t g;
    if (st == HZ_OK)
        st = hz_accel_geom_from_scene(&g, &s->scene, &pools->accel, err);
    /* the pool first: the native build bins and builds subtrees on it (the same tree for any thread count) */
    if (st == HZ_OK)
        st = hz_threads_start(threads, err);
    if (st == HZ_OK) {
        hz_accel_config_t cfg;
        hz_accel_config_default(&cfg);
        hz_threads_accel_hook(&cfg);
        st = hz_accel_backend_build_cfg(HZ_ACCEL_NATIVE, &s->accel, &g, &cfg, &pools->accel, err);
    }
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = (uint32_t)(w / scale), o.height = (uint32_t)(h / scale);
    if (mode != HZ_MODE_TDENSE && mode != HZ_MODE_FULL)
        return hz_error_set(err, HZ_E_INVALID_ARG, "scene source: mode %s is not tdense or full",
                            hz_render_mode_name(mode));
    o.mode = mode;
    if (st == HZ_OK)
        st = hz_render_create(&s->r, &s->scene, s->accel, &o, &pools->frame, pools->thread, (uint32_t)threads, err);
    if (st != HZ_OK)
        return st;
    s->have_t0 = false;
    src->name = strcmp(scene, "builtin") ? "scene" : "built-in scene";
    src->ctx = s;
    src->render = render;
    return HZ_OK;
}
