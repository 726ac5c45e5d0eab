/*
 * A scene as a frame source (see scenesrc.h): the scene, its accel and a renderer set up once in the board
 * pools; each frame renders at the governor's level on the static thread pool and becomes the loop's RGB24
 * frame (exact sRGB, hz_srgb8_encode_n; upscaled by hz/rgb8.h when rendered smaller).
 */
#include "scenesrc.h"

#include <string.h>
#include <unistd.h>

#include "accel_backend.h"
#include "blur_setup.h"
#include "clock.h"
#include "hz/image.h"
#include "hz/rgb8.h"
#include "modeplan.h"
#include "phase.h"
#include "pools.h"
#include "render_run.h"
#include "scenefile.h"
#include "threads.h"

typedef struct scenesrc {
    hz_scenesrc_cfg_t cfg;
    hz_scene_t scene;
    hz_accel_t *accel;
    hz_renderer_t *r;
    hz_ladder_t ladder;
    uint32_t level;        /* the renderer's configuration */
    bool have_first;
    int64_t first_slot, first_display_ns;
    uint8_t *small;        /* a level's frame before upscaling (max level size below the frame's) */
    void *upscale;         /* hz_rgb8_upscale's scratch */
    int out_w, out_h;
    hz_scenesrc_stats_t stats;
    bool open;
    /* the pools as open found them: close gives everything back */
    hz_arena_mark_t scene_mark, accel_mark, frame_mark, thread_mark[HZ_MAX_THREADS];
} scenesrc_t;

static scenesrc_t state;
static hz_posekeys_t keys; /* motion blur: the scene's pose across the shutter (opts.keys) */
static double render_ms[HZ_SCENESRC_MAX_TIMED];

/* A band of float RGB rows as sRGB codes (hz_threads_convert's form: the encode runs on the pool, as one thread
 * alone would leave the others idle between frames). */
static void encode_band(const void *ctx, const uint8_t *src, size_t src_stride, uint8_t *dst, size_t dst_stride,
                        int w, int h)
{
    (void)ctx;
    for (int y = 0; y < h; y++)
        hz_srgb8_encode_n((const float *)(const void *)(src + (size_t)y * src_stride), dst + (size_t)y * dst_stride,
                          (size_t)w * 3);
}

static void encode_rows(const hz_image_t *img, uint8_t *dst, size_t dstride)
{
    const size_t sstride = (size_t)img->width * 3 * sizeof(float); /* bytes */
    hz_threads_convert(encode_band, NULL, (const uint8_t *)(const void *)img->rgb, sstride, dst, dstride,
                       (int)img->width, (int)img->height);
}

/* The rendered float frame of `level` -> out (the sink's size). */
static void encode(scenesrc_t *s, uint32_t level, const hz_image_t *img, hz_rgb8_image_t *out)
{
    if ((int)img->width == out->w && (int)img->height == out->h) {
        encode_rows(img, out->rgb, out->stride);
        return;
    }
    const size_t sstride = (size_t)img->width * 3;
    encode_rows(img, s->small, sstride);
    hz_rgb8_upscale(s->small, img->width, img->height, sstride, out->rgb, (uint32_t)out->w, (uint32_t)out->h,
                    out->stride, level == 0, s->upscale);
}

static hz_status_t set_level(scenesrc_t *s, uint32_t level, hz_error_t *err)
{
    if (level >= s->ladder.count)
        level = s->ladder.count - 1;
    if (level == s->level)
        return HZ_OK;
    hz_render_opts_t o = s->ladder.level[level].opts;
    o.reserve_bytes = s->cfg.opts.reserve_bytes;
    hz_status_t st = hz_render_reconfigure(s->r, &o, err);
    if (st != HZ_OK) {
        hz_error_prefix(err, s->ladder.level[level].name);
        return st;
    }
    s->level = level;
    return HZ_OK;
}

hz_status_t hz_scenesrc_render_at(uint64_t id, uint32_t level, hz_time_ns_t t, hz_rgb8_image_t *out,
                                  hz_error_t *err)
{
    scenesrc_t *s = &state;
    hz_status_t st = set_level(s, level, err);
    if (st != HZ_OK)
        return st;
    int64_t t0 = hz_clock_ns();
    if (s->cfg.frame_progress) {
        /* one frame that may take long: its own progress */
        hz_phase_t prog;
        const hz_render_opts_t *o = &s->ladder.level[s->level].opts;
        hz_phase_begin(&prog, s->cfg.quiet, "rendering %s (%ux%u, mode %s)", s->cfg.scene, o->width, o->height,
                       hz_render_mode_name(o->mode));
        st = hz_render_run_frame_progress_ns(s->r, id, t, &prog, err);
        hz_phase_end(&prog);
    } else {
        st = hz_render_run_frame_ns(s->r, id, t, err);
    }
    if (st != HZ_OK)
        return st;
    double ms = (double)(hz_clock_ns() - t0) * 1e-6;
    if (s->stats.timed < HZ_SCENESRC_MAX_TIMED)
        render_ms[s->stats.timed++] = ms;
    s->stats.frames++;
    s->stats.level_frames[s->level]++;
    s->stats.last_level = s->level;
    encode(s, s->level, hz_render_output(s->r), out);
    return HZ_OK;
}

static hz_status_t render(void *ctx, const hz_frame_req_t *req, hz_rgb8_image_t *out, hz_error_t *err)
{
    scenesrc_t *s = (scenesrc_t *)ctx;
    if (!s->have_first) {
        s->first_slot = req->slot;
        s->first_display_ns = req->display_ns;
        s->have_first = true;
    }
    hz_time_ns_t t;
    if (s->cfg.clock == HZ_SCENE_CLOCK_SLOTS) {
        int64_t n = req->slot - s->first_slot;
        t = hz_time_of_frame(s->cfg.start, n > 0 ? (uint64_t)n : 0u, s->cfg.opts.frame_hz);
    } else {
        t = s->cfg.start + (req->display_ns - s->first_display_ns);
    }
    return hz_scenesrc_render_at(req->id, req->level, t, out, err);
}

/* Stops the pool, releases the accel and gives the pools back as open found them. */
static void release(scenesrc_t *s, hz_pools_t *pools)
{
    hz_threads_stop();
    hz_accel_release(s->accel);
    s->accel = NULL;
    s->r = NULL;
    hz_arena_reset(&pools->frame, s->frame_mark);
    hz_arena_reset(&pools->accel, s->accel_mark);
    hz_arena_reset(&pools->scene, s->scene_mark);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        hz_arena_reset(&pools->thread[t], s->thread_mark[t]);
}

static hz_status_t open_all(scenesrc_t *s, const hz_scenesrc_cfg_t *cfg, hz_pools_t *pools, hz_error_t *err);

static int machine_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > HZ_MAX_THREADS ? HZ_MAX_THREADS : (int)n;
}

hz_status_t hz_scenesrc_open(const hz_scenesrc_cfg_t *cfg, hz_framesrc_t *src, hz_error_t *err)
{
    scenesrc_t *s = &state;
    if (s->open)
        return hz_error_set(err, HZ_E_INTERNAL, "scene source: already open");
    memset(s, 0, sizeof *s);
    s->cfg = *cfg;
    hz_pools_t *pools = hz_pools_get();
    if (!pools)
        return hz_pools_error(err, "scene source");
    s->scene_mark = hz_arena_mark(&pools->scene);
    s->accel_mark = hz_arena_mark(&pools->accel);
    s->frame_mark = hz_arena_mark(&pools->frame);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        s->thread_mark[t] = hz_arena_mark(&pools->thread[t]);
    hz_status_t st = open_all(s, cfg, pools, err);
    if (st != HZ_OK) {
        release(s, pools);
        return st;
    }
    s->stats.render_ms = render_ms;
    s->stats.threads = s->cfg.threads;
    s->open = true;
    src->name = strcmp(cfg->scene, "builtin") ? "scene" : "built-in scene";
    src->ctx = s;
    src->render = render;
    src->levels = s->ladder.count > 1 ? &s->ladder.gov : NULL;
    return HZ_OK;
}

static hz_status_t open_all(scenesrc_t *s, const hz_scenesrc_cfg_t *cfg, hz_pools_t *pools, hz_error_t *err)
{
    hz_render_opts_t *o = &s->cfg.opts;
    s->out_w = cfg->out_w ? cfg->out_w : (int)o->width;
    s->out_h = cfg->out_h ? cfg->out_h : (int)o->height;
    if (s->out_w < (int)o->width || s->out_h < (int)o->height)
        return hz_error_set(err, HZ_E_INVALID_ARG, "scene source: render size %ux%u is larger than the %dx%d frame",
                            o->width, o->height, s->out_w, s->out_h);
    int threads = cfg->threads > 0 ? cfg->threads : machine_threads();
    s->cfg.threads = threads > HZ_MAX_THREADS ? HZ_MAX_THREADS : threads;
    hz_status_t st = hz_scenefile_open(cfg->scene, pools, &s->scene, err);
    /* A feature this build leaves out is refused by name now (the memory plans would only fail). */
    if (st == HZ_OK && (st = hz_render_features_check(&s->scene, o, err)) != HZ_OK)
        hz_error_prefix(err, cfg->scene);
    if (st == HZ_OK && cfg->prepare)
        st = cfg->prepare(cfg->prepare_ctx, &s->scene, o, err);
    if (st != HZ_OK)
        return st;
    /* The levels first: the renderer holds memory for the largest. */
    if (cfg->levels) {
        if ((st = hz_ladder_build(&s->ladder, &s->scene, o, err)) != HZ_OK)
            return st;
        size_t reserve;
        if ((st = hz_ladder_reserve(&s->ladder, &s->scene, &reserve, err)) != HZ_OK)
            return st;
        o->reserve_bytes = reserve;
    } else {
        s->ladder.count = 1;
        s->ladder.level[0].opts = *o;
        s->ladder.level[0].scale_num = s->ladder.level[0].scale_den = 1;
        s->ladder.gov.levels = 1;
        s->ladder.gov.weight_q16[0] = 65536;
    }
    s->ladder.level[0].opts.reserve_bytes = o->reserve_bytes;
    /* Refuse up front, before the accel build, with the numbers `hzrt info` prints. */
    hz_render_plan_t plan;
    char why[256];
    if (!hz_modeplan_check(&s->scene, pools, o, s->cfg.threads, &plan, why, sizeof why))
        return hz_error_set(err, HZ_E_NO_MEMORY, "a %ux%u %s render of %s does not fit board %s: %s (hzrt info %s "
                            "shows every mode)", o->width, o->height, hz_render_mode_name(o->mode), cfg->scene,
                            HZ_BOARD_NAME, why, cfg->scene);
    /* A level's frame before upscaling: the largest level smaller than the frame. */
    size_t small = 0;
    for (uint32_t i = 0; i < s->ladder.count; i++) {
        const hz_render_opts_t *lo = &s->ladder.level[i].opts;
        if ((int)lo->width != s->out_w || (int)lo->height != s->out_h) {
            size_t b = (size_t)lo->width * lo->height * 3;
            small = b > small ? b : small;
        }
    }
    if (small && (!(s->small = hz_arena_alloc(&pools->frame, small, 64)) ||
                  !(s->upscale = hz_arena_alloc(&pools->frame, hz_rgb8_upscale_scratch((uint32_t)s->out_w), 64))))
        return hz_arena_error(&pools->frame, err);
    /* The pool before the build: a native build bins and builds subtrees on it (the same tree for any thread
     * count). */
    if ((st = hz_threads_start(s->cfg.threads, err)) != HZ_OK)
        return st;
    int64_t t0 = hz_clock_ns();
    hz_phase_t prog;
    hz_accel_config_t acfg;
    hz_accel_config_default(&acfg);
    acfg.progress = hz_phase_accel, acfg.progress_user = &prog;
    acfg.rigid = cfg->rigid;
    acfg.segments = cfg->segments;
    if (cfg->backend == HZ_ACCEL_NATIVE)
        hz_threads_accel_hook(&acfg);
    hz_phase_begin(&prog, cfg->quiet, "%s build of %s (%u triangles)", hz_accel_backend_name(cfg->backend),
                   cfg->scene, s->scene.triangle_count);
    st = hz_blur_build_cfg(&s->scene, o, cfg->backend, cfg->blur, &acfg, pools, &keys, &s->accel, err);
    hz_phase_end(&prog);
    if (st == HZ_OK) {
        s->stats.build_ms = (double)(hz_clock_ns() - t0) * 1e-6;
        /* every level shares the shutter, and with it the pose keys */
        for (uint32_t i = 0; i < s->ladder.count; i++)
            s->ladder.level[i].opts.keys = o->keys;
        st = hz_render_create(&s->r, &s->scene, s->accel, o, &pools->frame, pools->thread, (uint32_t)s->cfg.threads,
                              err);
    }
    return st;
}

void hz_scenesrc_cfg_init(hz_scenesrc_cfg_t *c, const char *scene, hz_render_mode_t mode, int w, int h, int scale)
{
    memset(c, 0, sizeof *c);
    c->scene = scene;
    hz_render_opts_default(&c->opts);
    c->opts.mode = mode;
    scale = scale < 1 ? 1 : scale;
    c->opts.width = (uint32_t)(w / scale), c->opts.height = (uint32_t)(h / scale);
    c->backend = HZ_ACCEL_NATIVE;
    c->out_w = w, c->out_h = h;
    c->clock = HZ_SCENE_CLOCK_DISPLAY;
    c->quiet = true;
}

hz_status_t hz_scenesrc_open_simple(hz_framesrc_t *src, const char *scene, int w, int h, int scale, int threads,
                                    hz_render_mode_t mode, hz_error_t *err)
{
    if (scale < 1 || w < 1 || h < 1 || w % scale || h % scale)
        return hz_error_set(err, HZ_E_INVALID_ARG, "scene source: %dx%d is not a multiple of the render scale %d", w,
                            h, scale);
    hz_scenesrc_cfg_t c;
    hz_scenesrc_cfg_init(&c, scene, mode, w, h, scale);
    c.threads = threads;
    return hz_scenesrc_open(&c, src, err);
}

const hz_scenesrc_stats_t *hz_scenesrc_stats(void)
{
    return &state.stats;
}

hz_renderer_t *hz_scenesrc_renderer(void)
{
    return state.open ? state.r : NULL;
}

const hz_scene_t *hz_scenesrc_scene(void)
{
    return state.open ? &state.scene : NULL;
}

hz_accel_t *hz_scenesrc_accel(void)
{
    return state.open ? state.accel : NULL;
}

const hz_ladder_t *hz_scenesrc_ladder(void)
{
    return &state.ladder;
}

void hz_scenesrc_close(void)
{
    if (!state.open)
        return;
    release(&state, hz_pools_get());
    state.open = false;
}
