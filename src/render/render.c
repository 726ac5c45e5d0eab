/* Renderer set-up, frame sequencing and the full-frame mode (see hz/render.h). */
#include "hz/deflight.h"
#include "hz/fixed.h"
#include "hz/hash.h"
#include "hz/timeseq.h"
#include "render_internal.h"

#define STACK_JOBS 4096u   /* depth-first ray queue per worker (bounded growth: see render_internal.h) */
#define SHADOW_JOBS 256u   /* shadow queue per worker; flushed in packets when full */

void hz_render_opts_default(hz_render_opts_t *o)
{
    hz_memset(o, 0, sizeof *o);
    o->width = 640;
    o->height = 360;
    o->mode = HZ_MODE_FULL;
    o->spp = 1;
    o->max_bounces = 3;
    o->min_visibility = 0.001f;
    o->taa_gamma = 1.0f;
    o->taa_alpha = 0.1f;
    o->taa_clip = false;
    o->taa_catmull_rom = false;
    o->msaa4 = false;
    o->tdense_rule = HZ_GHAT_FULL;
    o->tdense_reflect_mv = true;
    o->tdense_gamma = 1.0f;
    hz_adaptive_opts_default(&o->adaptive);
    o->seed = 0;
    o->transparency = HZ_TRANSP_EXACT;
    o->hybrid_x = 0.5f;
    o->rr_shadows = false;
    o->shutter = 0.0f;
    o->frame_hz = HZ_DISPLAY_HZ;
    o->keys = NULL;
    o->tdense_cycle_keys = true;
}

const char *hz_render_mode_name(hz_render_mode_t m)
{
    static const char *const names[HZ_MODE_COUNT] = { "full", "taa", "tdense", "adaptive" };
    return (unsigned)m < HZ_MODE_COUNT ? names[m] : "unknown";
}

hz_status_t hz_render_opts_check(const hz_render_opts_t *o, hz_error_t *err)
{
    if (o->width < 1 || o->height < 1 || o->width > HZ_IMAGE_MAX_DIM || o->height > HZ_IMAGE_MAX_DIM)
        return hz_error_set(err, HZ_E_INVALID_ARG, "size %ux%u outside 1..%u", o->width, o->height,
                            HZ_IMAGE_MAX_DIM);
    if ((unsigned)o->mode >= HZ_MODE_COUNT)
        return hz_error_set(err, HZ_E_INVALID_ARG, "unknown mode %d", (int)o->mode);
    uint32_t s = hz_isqrt_u64(o->spp);
    if (o->spp < 1 || o->spp > 1024 || s * s != o->spp)
        return hz_error_set(err, HZ_E_INVALID_ARG, "spp %u: must be a square number in 1..1024", o->spp);
    if (o->max_bounces > 3)
        return hz_error_set(err, HZ_E_INVALID_ARG, "max bounces %u: at most 3", o->max_bounces);
    if (!(o->min_visibility >= 0.0f && o->min_visibility < 1.0f))
        return hz_error_set(err, HZ_E_INVALID_ARG, "min visibility must lie in [0, 1)");
    if (!(o->taa_gamma > 0.0f && o->taa_gamma <= 16.0f) || !(o->taa_alpha > 0.0f && o->taa_alpha <= 1.0f))
        return hz_error_set(err, HZ_E_INVALID_ARG, "TAA gamma must lie in (0, 16], alpha in (0, 1]");
    if (o->msaa4 && (o->mode != HZ_MODE_FULL || o->spp != 4))
        return hz_error_set(err, HZ_E_INVALID_ARG, "the 4x MSAA positions need full mode with 4 spp");
    if ((unsigned)o->tdense_rule >= HZ_GHAT_RULE_COUNT)
        return hz_error_set(err, HZ_E_INVALID_ARG, "unknown tdense ordering rule %d", (int)o->tdense_rule);
    if (!(o->tdense_gamma > 0.0f && o->tdense_gamma <= 16.0f))
        return hz_error_set(err, HZ_E_INVALID_ARG, "tdense gamma must lie in (0, 16]");
    if ((unsigned)o->transparency >= HZ_TRANSP_COUNT)
        return hz_error_set(err, HZ_E_INVALID_ARG, "unknown transparency method %d", (int)o->transparency);
    if (!(o->hybrid_x >= 0.0f && o->hybrid_x <= 1.0f))
        return hz_error_set(err, HZ_E_INVALID_ARG, "hybrid visibility threshold must lie in [0, 1]");
    if (!(o->shutter >= 0.0f && o->shutter <= 1.0f))
        return hz_error_set(err, HZ_E_INVALID_ARG, "shutter must lie in [0, 1] (a fraction of the frame interval)");
    if (o->shutter > 0.0f && (o->frame_hz < 1 || o->frame_hz > 1000))
        return hz_error_set(err, HZ_E_INVALID_ARG, "shutter: frame rate %u Hz outside 1..1000", o->frame_hz);
    if (o->shutter == 0.0f && o->keys)
        return hz_error_set(err, HZ_E_INVALID_ARG, "pose keys given without a shutter (motion blur is off)");
    if (o->mode == HZ_MODE_ADAPTIVE) {
        /* The subpixel pass traces at the frame's time; blurred presamples against sharp subpixels would mix. */
        if (o->shutter > 0.0f)
            return hz_error_set(err, HZ_E_INVALID_ARG, "motion blur (shutter > 0) is not built for adaptive mode");
        hz_amask_config_t c;
        return hz_adaptive_config(&o->adaptive, &c, err);
    }
    return HZ_OK;
}

typedef struct needs {
    bool blend, mask, textures, mirrors, motion, camera_moves, mv;
} needs_t;

static needs_t scene_needs(const hz_scene_t *s)
{
    needs_t n;
    n.blend = HZ_FEATURE_TRANSPARENCY && (s->features & HZ_FEAT_BLEND);
    n.mask = HZ_FEATURE_TRANSPARENCY && (s->features & HZ_FEAT_CUTOUT);
    n.textures = HZ_FEATURE_TEXTURES && (s->features & HZ_FEAT_TEXTURES) && s->uv;
    n.mirrors = HZ_FEATURE_MIRRORS && (s->features & HZ_FEAT_MIRROR);
    n.motion = HZ_FEATURE_MOTION && (s->features & HZ_FEAT_MOTION) && s->prev_pos;
    n.camera_moves = (s->features & HZ_FEAT_CAMERA_PATH) != 0;
    n.mv = n.motion || n.camera_moves;
    return n;
}

/* Sizes of every frame-arena allocation, in the order create makes them (64-byte alignment each); *parts (may
 * be NULL) gets them by part (hz_render_plan_t). */
static size_t frame_bytes(const hz_render_opts_t *o, const needs_t *n, hz_render_plan_t *parts)
{
    size_t px = (size_t)o->width * o->height, a = 64, total = 0;
    hz_render_plan_t pp;
    hz_memset(&pp, 0, sizeof pp);
    size_t *part = &pp.state_bytes; /* what each ADD is counted in */
#define ADD(bytes) (total += hz_align_up((bytes), a) + a, *part += hz_align_up((bytes), a) + a)
    ADD(sizeof(struct hz_renderer));
    part = &pp.display_bytes;
    if (o->mode != HZ_MODE_TDENSE)
        ADD(px * 12); /* out (tdense displays its own frames) */
    const bool attrs = hz_render_mode_keeps_surface(o->mode);
    part = &pp.gbuffer_bytes;
    if (attrs)
        ADD(px * 4);  /* depth */
    ADD(px * 2);      /* object */
    if (attrs) {
        ADD(px * 12); /* normal */
        ADD(px);      /* shadow */
    }
    ADD(px);          /* flags */
    part = &pp.gbuffer2_bytes;
    if (n->mirrors) {
        ADD(px * 2);
        if (attrs) {
            ADD(px * 12);
            ADD(px);
        }
        ADD(px);
    }
    part = &pp.mv_bytes;
    if (n->mv)
        ADD(px * 8);
    if (n->mv && n->mirrors)
        ADD(px * 8);
    part = &pp.state_bytes;
    if (o->mode == HZ_MODE_TAA) {
        ADD(px * 12); /* cur */
        ADD(px * 6);  /* hist[0], half float */
        ADD(px * 6);  /* hist[1] */
        ADD(px * 2);  /* prev_object */
    }
#undef ADD
    if (o->mode == HZ_MODE_TDENSE) {
        size_t display, td = hz_tdense_plan(o->width, o->height, n->mv, &display);
        total += td;
        pp.display_bytes += display;
        pp.state_bytes += td - display;
    }
    if (o->mode == HZ_MODE_ADAPTIVE) {
        size_t ad = hz_adaptive_frame_bytes(o->width, o->height, n->mirrors);
        total += ad;
        pp.state_bytes += ad;
    }
    if (parts)
        *parts = pp;
    return total;
}

static size_t thread_bytes(void)
{
    return hz_align_up(sizeof(hz_worker_t), 64) + 64 + STACK_JOBS * sizeof(ray_job_t) + 64 +
           SHADOW_JOBS * sizeof(shadow_job_t) + 64;
}

hz_status_t hz_render_plan(const hz_scene_t *scene, const hz_render_opts_t *opts, hz_render_plan_t *plan,
                           hz_error_t *err)
{
    hz_status_t s = hz_render_opts_check(opts, err);
    if (s != HZ_OK)
        return s;
    needs_t n = scene_needs(scene);
    plan->frame_bytes = frame_bytes(opts, &n, plan);
    plan->thread_bytes = thread_bytes();
    plan->anyhit = n.mask || n.blend;
    plan->transparency = n.blend;
    plan->time_keys = 0;
    plan->keys_bytes = 0;
    if (opts->shutter > 0.0f && n.motion) {
        /* tdense with one key interval per cycle: the keys span four frames' shutters. */
        float frames = opts->mode == HZ_MODE_TDENSE && opts->tdense_cycle_keys ? 3.0f + opts->shutter : opts->shutter;
        uint32_t k = hz_posekeys_count(scene, frames / (float)opts->frame_hz);
        if (k >= 2) {
            plan->time_keys = k;
            plan->keys_bytes = hz_posekeys_bytes(scene, k);
        }
    }
    return HZ_OK;
}

/* Every record says "no hit" until a ray writes it: tdense traces a quarter of the pixels per frame, so
 * without this the first frames' G-buffer showed whatever the arena held (poison: negative depths). */
static void gbuffer_clear(hz_gbuffer_t *gb, size_t px)
{
    for (size_t i = 0; i < px; i++) {
        if (gb->depth)
            gb->depth[i] = __builtin_inff();
        gb->object[i] = HZ_GB_NO_OBJECT;
        if (gb->object2)
            gb->object2[i] = HZ_GB_NO_OBJECT;
    }
    if (gb->normal) {
        hz_memset(gb->normal, 0, px * 12);
        hz_memset(gb->shadow, 0, px);
    }
    hz_memset(gb->flags, 0, px);
    if (gb->object2) {
        if (gb->normal2) {
            hz_memset(gb->normal2, 0, px * 12);
            hz_memset(gb->shadow2, 0, px);
        }
        hz_memset(gb->flags2, 0, px);
    }
}

static void *take(hz_arena_t *a, size_t bytes, bool *ok)
{
    void *p = hz_arena_alloc(a, bytes, 64);
    if (!p)
        *ok = false;
    return p;
}

hz_status_t hz_render_create(hz_renderer_t **out, hz_scene_t *scene, hz_accel_t *accel,
                             const hz_render_opts_t *opts, hz_arena_t *frame_arena, hz_arena_t *thread_arenas,
                             uint32_t thread_count, hz_error_t *err)
{
    *out = NULL;
    hz_status_t s = hz_render_opts_check(opts, err);
    if (s != HZ_OK)
        return s;
    if (thread_count < 1 || thread_count > HZ_MAX_THREADS)
        return hz_error_set(err, HZ_E_INVALID_ARG, "thread count %u outside 1..%d", thread_count, HZ_MAX_THREADS);
    needs_t n = scene_needs(scene);
    /* Refuse up front, naming the arena and both counts, rather than half-way through. */
    size_t need = frame_bytes(opts, &n, NULL), have = hz_arena_available(frame_arena, 64);
    if (need > have)
        return hz_error_set(err, HZ_E_NO_MEMORY, "arena '%s': a %ux%u %s renderer needs %zu bytes, has %zu",
                            frame_arena->name, opts->width, opts->height, hz_render_mode_name(opts->mode), need,
                            have);
    for (uint32_t t = 0; t < thread_count; t++) {
        size_t tn = thread_bytes(), th = hz_arena_available(&thread_arenas[t], 64);
        if (tn > th)
            return hz_error_set(err, HZ_E_NO_MEMORY, "arena '%s' %u: needs %zu bytes, has %zu",
                                thread_arenas[t].name, t, tn, th);
    }
    if (opts->shutter > 0.0f && n.motion) {
        const hz_posekeys_t *k = opts->keys;
        if (!k || k->count < 2)
            return hz_error_set(err, HZ_E_INVALID_ARG, "shutter %g on a moving scene needs pose keys (hz_render_plan)",
                                (double)opts->shutter);
        if (k->vertex_count != scene->vertex_count || accel->geom.time_keys != k->count ||
            accel->geom.pos_keys[0] != k->pos[0])
            return hz_error_set(err, HZ_E_INVALID_ARG, "shutter: the accel was not built over these pose keys");
    }
    hz_arena_mark_t mark = hz_arena_mark(frame_arena);
    bool ok = true;
    size_t px = (size_t)opts->width * opts->height;
    struct hz_renderer *r = take(frame_arena, sizeof *r, &ok);
    if (!ok)
        return hz_arena_error(frame_arena, err);
    hz_memset(r, 0, sizeof *r);
    r->opts = *opts;
    r->scene = scene;
    r->lights = scene->lights, r->light_count = scene->light_count;
    if (scene->light_count == 0) {
        hz_deflight_place(scene, &r->default_light);
        r->lights = &r->default_light, r->light_count = 1, r->default_lit = true;
    }
    r->accel = accel;
    r->has_blend = n.blend, r->has_mask = n.mask, r->has_textures = n.textures, r->has_mirrors = n.mirrors;
    r->has_motion = n.motion, r->camera_moves = n.camera_moves, r->need_mv = n.mv;
    /* The dither stage exists only where something is blended (hybrid:0 never leaves the exact path). */
    r->dither = n.blend && opts->transparency != HZ_TRANSP_EXACT &&
                !(opts->transparency == HZ_TRANSP_HYBRID && opts->hybrid_x <= 0.0f);
    r->blur = opts->shutter > 0.0f;
    r->cam_blur = r->blur && n.camera_moves;
    r->keys = r->blur && n.motion ? opts->keys : NULL;
    r->tmap_a = 0.0f, r->tmap_b = 1.0f;
    const hz_hzb_header_t *hb = scene->header;
    r->offset_scale = 0.0f;
    for (int c = 0; c < 3; c++)
        r->offset_scale = hz_maxf(r->offset_scale, hz_maxf(hz_absf(hb->bounds_min[c]), hz_absf(hb->bounds_max[c])));
    r->tiles_x = (opts->width + HZ_RENDER_TILE - 1) / HZ_RENDER_TILE;
    r->tiles_y = (opts->height + HZ_RENDER_TILE - 1) / HZ_RENDER_TILE;
    r->out.width = opts->width, r->out.height = opts->height;
    if (opts->mode != HZ_MODE_TDENSE)
        r->out.rgb = take(frame_arena, px * 12, &ok);
    hz_gbuffer_t *gb = &r->gb;
    gb->width = opts->width, gb->height = opts->height;
    const bool attrs = hz_render_mode_keeps_surface(opts->mode);
    if (attrs)
        gb->depth = take(frame_arena, px * 4, &ok);
    gb->object = take(frame_arena, px * 2, &ok);
    if (attrs) {
        gb->normal = take(frame_arena, px * 12, &ok);
        gb->shadow = take(frame_arena, px, &ok);
    }
    gb->flags = take(frame_arena, px, &ok);
    if (n.mirrors) {
        gb->object2 = take(frame_arena, px * 2, &ok);
        if (attrs) {
            gb->normal2 = take(frame_arena, px * 12, &ok);
            gb->shadow2 = take(frame_arena, px, &ok);
        }
        gb->flags2 = take(frame_arena, px, &ok);
    }
    if (n.mv)
        gb->mv = take(frame_arena, px * 8, &ok);
    if (n.mv && n.mirrors)
        gb->mv_reflect = take(frame_arena, px * 8, &ok);
    if (opts->mode == HZ_MODE_TAA) {
        r->cur = r->out;
        r->cur.rgb = take(frame_arena, px * 12, &ok);
        r->hist[0] = take(frame_arena, px * 6, &ok);
        r->hist[1] = take(frame_arena, px * 6, &ok);
        r->prev_object = take(frame_arena, px * 2, &ok);
    }
    if (!ok) {
        s = hz_arena_error(frame_arena, err);
        hz_arena_reset(frame_arena, mark);
        return s;
    }
    if (opts->mode == HZ_MODE_TDENSE) {
        hz_tdense_config_t tc = hz_tdense_config_default(opts->width, opts->height);
        tc.rule = opts->tdense_rule;
        tc.seed = opts->seed;
        tc.reflect_mv = opts->tdense_reflect_mv;
        tc.gamma = opts->tdense_gamma;
        tc.motion = n.mv;
        if ((s = hz_tdense_init(&r->td, &tc, frame_arena, err)) != HZ_OK) {
            hz_arena_reset(frame_arena, mark);
            return s;
        }
    } else {
        hz_memset(r->out.rgb, 0, px * 12);
    }
    if (opts->mode == HZ_MODE_ADAPTIVE && (s = hz_adaptive_init(r, frame_arena, err)) != HZ_OK) {
        hz_arena_reset(frame_arena, mark);
        return s;
    }
    if (gb->mv)
        hz_memset(gb->mv, 0, px * 8);
    if (gb->mv_reflect)
        hz_memset(gb->mv_reflect, 0, px * 8);
    gbuffer_clear(gb, px);
    r->thread_count = thread_count;
    for (uint32_t t = 0; t < thread_count; t++) {
        hz_arena_t *ta = &thread_arenas[t];
        hz_worker_t *w = hz_arena_alloc(ta, sizeof *w, 64);
        ray_job_t *stack = hz_arena_alloc_array(ta, STACK_JOBS, sizeof(ray_job_t), 64);
        shadow_job_t *shadows = hz_arena_alloc_array(ta, SHADOW_JOBS, sizeof(shadow_job_t), 64);
        if (!w || !stack || !shadows) {
            hz_arena_reset(frame_arena, mark);
            return hz_arena_error(ta, err);
        }
        hz_memset(w, 0, sizeof *w);
        w->stack = stack, w->stack_cap = STACK_JOBS;
        w->shadows = shadows, w->shadow_cap = SHADOW_JOBS;
        w->r = r;
        hz_accel_ctx_init(&w->ctx);
        if (n.mask || n.blend) {
            w->ctx.anyhit = hz_render_anyhit;
            w->ctx.user = w;
        }
        r->workers_by_thread[t] = w;
    }
    *out = r;
    return HZ_OK;
}

static float halton(uint32_t i, uint32_t base)
{
    float f = 1.0f, v = 0.0f;
    while (i > 0) {
        f /= (float)base;
        v += f * (float)(i % base);
        i /= base;
    }
    return v;
}

/* Motion blur: the camera across this frame's shutter, and the pose keys (evaluated and refitted when they do
 * not hold this frame's interval already). Times are offsets from the frame's time: the frame index tells how
 * far apart two frames are (1 / frame_hz each), so no absolute times are subtracted. */
static hz_status_t blur_begin(hz_renderer_t *r, uint64_t frame_index, hz_time_ns_t time, hz_error_t *err)
{
    const float hz = (float)r->opts.frame_hz, half = 0.5f * r->opts.shutter / hz;
    if (r->cam_blur) {
        for (uint32_t i = 0; i < HZ_RENDER_CAMERA_KEYS; i++) {
            float dt = -half + 2.0f * half * ((float)i / (float)(HZ_RENDER_CAMERA_KEYS - 1));
            hz_camera_t cam = hz_scene_camera_ns(r->scene, time + hz_time_from_s(dt));
            hz_view_setup(&r->cam_views[i], &cam, r->opts.width, r->opts.height);
        }
    }
    hz_posekeys_t *k = r->keys;
    if (!k)
        return HZ_OK;
    /* tdense: one interval over the cycle's four shutters (the renderer is told frames, not cycles: the cycle's
     * first frame is frame_index - subframe). */
    bool cycle = r->opts.mode == HZ_MODE_TDENSE && r->opts.tdense_cycle_keys;
    uint64_t sub = cycle ? r->td.frame % 4u : 0u;
    bool reuse = cycle && r->key_evals > 0 && frame_index - sub == r->keys_cycle && frame_index >= r->keys_frame &&
                 k->valid && k->time == r->keys_t && k->lo == r->keys_lo && k->hi == r->keys_hi;
    if (!reuse) {
        float lo = cycle ? -(float)sub / hz - half : -half, hi = cycle ? (float)(3u - sub) / hz + half : half;
        hz_posekeys_eval_ns(k, r->scene, time, lo, hi);
        r->keys_frame = frame_index, r->keys_cycle = frame_index - sub;
        r->keys_t = time, r->keys_lo = lo, r->keys_hi = hi;
        r->key_evals++;
        r->frame_refits = 1;
        hz_status_t s = hz_accel_refit(r->accel, err);
        if (s != HZ_OK)
            return s;
    }
    /* This frame's shutter, relative to the keys' first time. */
    float span = r->keys_hi - r->keys_lo;
    float start = (float)(frame_index - r->keys_frame) / hz - half - r->keys_lo;
    r->tmap_a = span > 0.0f ? start / span : 0.0f;
    r->tmap_b = span > 0.0f ? 2.0f * half / span : 0.0f;
    return HZ_OK;
}

hz_status_t hz_render_begin_frame(hz_renderer_t *r, uint64_t frame_index, float time, hz_error_t *err)
{
    if (!hz_isfinitef(time))
        return hz_error_set(err, HZ_E_INVALID_ARG, "frame time is not finite");
    return hz_render_begin_frame_ns(r, frame_index, hz_time_from_s(time), err);
}

hz_status_t hz_render_begin_frame_ns(hz_renderer_t *r, uint64_t frame_index, hz_time_ns_t time_ns, hz_error_t *err)
{
    float time = hz_time_wrap_s(time_ns, r->scene->header->duration);
    r->frame_refits = 0;
    if (r->has_motion) {
        hz_scene_animate_ns(r->scene, time_ns);
        if (!r->have_prev)
            hz_scene_animate_ns(r->scene, time_ns); /* no history yet: previous = current, zero object motion */
        hz_status_t s = r->keys ? HZ_OK : hz_accel_refit(r->accel, err);
        if (s != HZ_OK)
            return s;
        r->frame_refits = r->keys ? 0u : 1u;
    }
    if (r->have_prev)
        r->prev_view = r->view;
    hz_camera_t cam = hz_scene_camera_ns(r->scene, time_ns);
    hz_view_setup(&r->view, &cam, r->opts.width, r->opts.height);
    if (r->blur) {
        hz_status_t s = blur_begin(r, frame_index, time_ns, err);
        if (s != HZ_OK)
            return s;
    }
    if (!r->have_prev)
        r->prev_view = r->view;
    r->frame = frame_index;
    r->time = time;
    r->time_ns = time_ns;
    if (r->opts.mode == HZ_MODE_TDENSE) {
        /* Any change of the camera restarts every static window (seed 001, 3.2.2). */
        const hz_view_t *a = &r->view, *b = &r->prev_view;
        bool same = a->eye.x == b->eye.x && a->eye.y == b->eye.y && a->eye.z == b->eye.z && a->fwd.x == b->fwd.x &&
                    a->fwd.y == b->fwd.y && a->fwd.z == b->fwd.z && a->right.x == b->right.x &&
                    a->right.y == b->right.y && a->right.z == b->right.z && a->up.x == b->up.x &&
                    a->up.y == b->up.y && a->up.z == b->up.z;
        hz_tdense_begin_frame(&r->td, r->have_prev && !same);
    }
    /* TAA jitter: Halton (2, 3), 16 phases, centred on the pixel. */
    uint32_t phase = (uint32_t)(frame_index % 16u) + 1u;
    r->jitter[0] = halton(phase, 2) - 0.5f;
    r->jitter[1] = halton(phase, 3) - 0.5f;
    for (uint32_t t = 0; t < r->thread_count; t++)
        hz_memset(&r->workers_by_thread[t]->stats, 0, sizeof(hz_render_stats_t));
    return HZ_OK;
}

bool hz_render_mode_keeps_surface(hz_render_mode_t mode)
{
    return mode == HZ_MODE_FULL || mode == HZ_MODE_ADAPTIVE;
}

uint32_t hz_render_pass_count(const hz_renderer_t *r)
{
    return r->opts.mode == HZ_MODE_FULL ? 1u : r->opts.mode == HZ_MODE_ADAPTIVE ? 3u : 2u;
}

uint32_t hz_render_pass_items(const hz_renderer_t *r, uint32_t pass)
{
    if (pass >= hz_render_pass_count(r))
        return 0u;
    /* tdense resolves whole rows (its 3x3 neighbourhoods span tiles): one item per row of tiles. */
    return r->opts.mode == HZ_MODE_TDENSE && pass == 1 ? r->tiles_y : r->tiles_x * r->tiles_y;
}

/* Radiance -> image, replacing anything non-finite or negative (a bug upstream) by 0, counted. */
static void store(hz_worker_t *w, float *dst, const float *src, float scale)
{
    for (int c = 0; c < 3; c++) {
        float v = src[c] * scale;
        if (!hz_isfinitef(v)) {
            w->stats.nonfinite++;
            v = 0.0f;
        }
        dst[c] = v > 0.0f ? v : 0.0f;
    }
}

/* Motion blur: shutter time of sample `index` of `count` of pixel px (hz/timeseq.h), in [0, 1). */
static float sample_time(const hz_renderer_t *r, uint32_t px, uint32_t index, uint32_t count)
{
    return hz_u32_to_unit(hz_timeseq_u32(px, index, count, r->opts.seed));
}

static void trace_tile(hz_renderer_t *r, uint32_t tile, hz_worker_t *w, hz_image_t *dst)
{
    float jitter[HZ_TILE_PIXELS][2], times[HZ_TILE_PIXELS];
    hz_tile_slots(r, tile, w->pixel);
    hz_memset(w->radiance, 0, sizeof w->radiance);
    uint32_t spp = r->opts.mode == HZ_MODE_FULL ? r->opts.spp : 1u;
    uint32_t side = hz_isqrt_u64(spp);
    for (uint32_t k = 0; k < spp; k++) {
        for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++) {
            if (r->opts.mode == HZ_MODE_TAA) {
                jitter[slot][0] = r->jitter[0], jitter[slot][1] = r->jitter[1];
            } else if (r->opts.msaa4) {
                jitter[slot][0] = (float)hz_msaa4_jitter16[k][0] * (1.0f / 16.0f);
                jitter[slot][1] = (float)hz_msaa4_jitter16[k][1] * (1.0f / 16.0f);
            } else if (spp == 1) {
                jitter[slot][0] = jitter[slot][1] = 0.0f;
            } else {
                /* Stratified: one sample in each cell of a side x side grid, placed by a per-pixel hash. */
                uint32_t h = hz_hash3(w->pixel[slot], k, r->opts.seed);
                float cx = (float)(k % side), cy = (float)(k / side);
                jitter[slot][0] = (cx + hz_u32_to_unit(h)) / (float)side - 0.5f;
                jitter[slot][1] = (cy + hz_u32_to_unit(hz_hash32(h))) / (float)side - 0.5f;
            }
            /* Full mode stratifies time over the pixel's samples, TAA over 16 frames. */
            if (r->blur && w->pixel[slot] != UINT32_MAX)
                times[slot] = r->opts.mode == HZ_MODE_TAA ? sample_time(r, w->pixel[slot], (uint32_t)(r->frame % 16u), 16u)
                                                          : sample_time(r, w->pixel[slot], k, spp);
        }
        w->dither_frame = (uint32_t)r->frame * spp + k; /* N spp walk N steps of the dither's sequence */
        hz_trace_batch(w, (const float(*)[2])jitter, r->blur ? times : NULL, k == 0);
    }
    float scale = 1.0f / (float)spp;
    for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++) {
        uint32_t px = w->pixel[slot];
        if (px != UINT32_MAX)
            store(w, dst->rgb + (size_t)px * 3, &w->radiance[slot * 3], scale);
    }
}

/* tdense: the tile traces one pixel of each of its 2x2 tdense tiles, the one the tile's ordering names for this
 * subframe (jittered where static). The chosen pixels take the first slots, in rows of tdense tiles, so they
 * form full packets; the other slots stay empty (UINT32_MAX), which hz_trace_batch skips. */
static void trace_tile_tdense(hz_renderer_t *r, uint32_t tile, hz_worker_t *w)
{
    enum { PER = HZ_RENDER_TILE / 2 };
    float jitter[HZ_TILE_PIXELS][2], times[HZ_TILE_PIXELS];
    uint16_t where[HZ_TILE_PIXELS][2];
    hz_tdense_t *td = &r->td;
    uint32_t tx0 = (tile % r->tiles_x) * PER, ty0 = (tile / r->tiles_x) * PER, n = 0;
    for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++)
        w->pixel[slot] = UINT32_MAX;
    for (uint32_t k = 0; k < PER * PER; k++) {
        uint32_t tx = tx0 + k % PER, ty = ty0 + k / PER, px, py;
        int msaa;
        if (tx >= td->tiles_x || ty >= td->tiles_y || !hz_tdense_tile_sample(td, tx, ty, &px, &py, jitter[n], &msaa))
            continue;
        w->pixel[n] = py * r->opts.width + px;
        where[n][0] = (uint16_t)tx, where[n][1] = (uint16_t)ty;
        /* A pixel is traced once per cycle: its times are stratified over 4 cycles (the static window). */
        if (r->blur)
            times[n] = sample_time(r, w->pixel[n], (td->frame / 4u) % 4u, 4u);
        n++;
    }
    hz_memset(w->radiance, 0, sizeof w->radiance);
    w->dither_frame = (uint32_t)r->frame;
    hz_trace_batch(w, (const float(*)[2])jitter, r->blur ? times : NULL, true);
    const hz_gbuffer_t *gb = &r->gb;
    static const float still[2] = { 0.0f, 0.0f };
    for (uint32_t slot = 0; slot < n; slot++) {
        uint32_t px = w->pixel[slot];
        float c[3];
        store(w, c, &w->radiance[slot * 3], 1.0f);
        const float *mv = gb->mv ? gb->mv + (size_t)px * 2 : still;
        const float *mvr = gb->mv_reflect && (gb->flags[px] & HZ_GB_MIRROR) ? gb->mv_reflect + (size_t)px * 2 : NULL;
        hz_tdense_put(td, where[slot][0], where[slot][1], c, mv, mvr);
    }
}

void hz_render_pass_run(hz_renderer_t *r, uint32_t pass, uint32_t item, uint32_t thread)
{
    if (thread >= r->thread_count || item >= hz_render_pass_items(r, pass))
        return;
    hz_worker_t *w = r->workers_by_thread[thread];
    if (r->opts.mode == HZ_MODE_TDENSE) {
        if (pass == 0)
            trace_tile_tdense(r, item, w);
        else
            (r->opts.scalar_recon ? hz_tdense_resolve_rows_scalar : hz_tdense_resolve_rows)(
                &r->td, item * (HZ_RENDER_TILE / 2), (item + 1) * (HZ_RENDER_TILE / 2));
    } else if (r->opts.mode == HZ_MODE_ADAPTIVE) {
        if (pass == 0) {
            trace_tile(r, item, w, &r->out); /* the presample: 1 spp at pixel centres */
            hz_adaptive_keep_attrs(r, w);
        } else if (pass == 1) {
            hz_adaptive_test_tile(r, item);
        } else {
            hz_adaptive_extra_tile(r, item, w);
        }
    } else if (pass == 0) {
        trace_tile(r, item, w, r->opts.mode == HZ_MODE_TAA ? &r->cur : &r->out);
    } else if (pass == 1 && r->opts.mode == HZ_MODE_TAA) {
        (r->opts.scalar_recon ? hz_taa_resolve_tile_scalar : hz_taa_resolve_tile)(r, item);
    }
}

/* tdense resolves the tdense tile rows of one trace tile row per unit (HZ_RENDER_TILE / 2 of them, the barrier
 * pass's items: single tdense rows measured 3-5% slower frames at 2 threads, from the resolve's per-call setup
 * and more switching between tracing and resolving); TAA one trace tile per unit. */
#define TD_PER (HZ_RENDER_TILE / 2)
uint32_t hz_render_overlap_units(const hz_renderer_t *r, uint32_t *trace_rows, uint32_t *row_items)
{
    *trace_rows = r->tiles_y, *row_items = r->tiles_x;
    if (r->opts.serial_passes)
        return 0u;
    if (r->opts.mode == HZ_MODE_TDENSE)
        return (r->td.tiles_y + TD_PER - 1u) / TD_PER;
    if (r->opts.mode == HZ_MODE_TAA)
        return r->tiles_x * r->tiles_y;
    return 0u;
}

void hz_render_overlap_needs(const hz_renderer_t *r, uint32_t unit, uint32_t *row_lo, uint32_t *row_hi)
{
    uint32_t lo, hi;
    if (r->opts.mode == HZ_MODE_TDENSE) {
        /* the unit's tdense rows and the rows above and below them lie in trace rows u - 1 .. u + 1 */
        lo = unit ? unit - 1u : 0u;
        hi = unit + 1u;
    } else {
        const uint32_t row = unit / r->tiles_x;
        lo = row ? row - 1u : 0u;
        hi = row + 1u;
    }
    *row_lo = lo;
    *row_hi = hi < r->tiles_y ? hi : r->tiles_y - 1u;
}

void hz_render_overlap_run(hz_renderer_t *r, uint32_t unit)
{
    if (r->opts.mode == HZ_MODE_TDENSE && unit * TD_PER < r->td.tiles_y)
        (r->opts.scalar_recon ? hz_tdense_resolve_rows_scalar : hz_tdense_resolve_rows)(&r->td, unit * TD_PER,
                                                                                         (unit + 1u) * TD_PER);
    else if (r->opts.mode == HZ_MODE_TAA && unit < r->tiles_x * r->tiles_y)
        (r->opts.scalar_recon ? hz_taa_resolve_tile_scalar : hz_taa_resolve_tile)(r, unit);
}

static void add_stats(hz_render_stats_t *a, const hz_render_stats_t *b)
{
    a->primary_rays += b->primary_rays;
    a->shadow_rays += b->shadow_rays;
    a->secondary_rays += b->secondary_rays;
    a->nonfinite += b->nonfinite;
    a->layer_cap += b->layer_cap;
    a->queue_full += b->queue_full;
    a->active_subpixels += b->active_subpixels;
    a->extra_rays += b->extra_rays;
    a->extra_packets += b->extra_packets;
    a->refits += b->refits;
}

void hz_render_end_frame(hz_renderer_t *r)
{
    hz_memset(&r->last, 0, sizeof r->last);
    for (uint32_t t = 0; t < r->thread_count; t++)
        add_stats(&r->last, &r->workers_by_thread[t]->stats);
    r->last.refits = r->frame_refits;
    add_stats(&r->total, &r->last);
    if (r->opts.mode == HZ_MODE_TAA) {
        r->hist_index ^= 1u; /* the history just written becomes the previous frame's */
        r->hist_valid = true;
        hz_memcpy(r->prev_object, r->gb.object, (size_t)r->opts.width * r->opts.height * 2);
    }
    if (r->opts.mode == HZ_MODE_TDENSE)
        hz_tdense_end_frame(&r->td);
    r->have_prev = true;
}

const hz_image_t *hz_render_output(const hz_renderer_t *r)
{
    return r->opts.mode == HZ_MODE_TDENSE ? hz_tdense_output(&r->td) : &r->out;
}

const hz_gbuffer_t *hz_render_gbuffer(const hz_renderer_t *r)
{
    return &r->gb;
}

void hz_render_frame_stats(const hz_renderer_t *r, hz_render_stats_t *last, hz_render_stats_t *total)
{
    if (last)
        *last = r->last;
    if (total)
        *total = r->total;
}

const hz_light_t *hz_render_default_light(const hz_renderer_t *r)
{
    return r->default_lit ? &r->default_light : NULL;
}

const struct hz_tdense *hz_render_tdense(const hz_renderer_t *r)
{
    return r->opts.mode == HZ_MODE_TDENSE ? &r->td : NULL;
}

const uint8_t *hz_render_adaptive_mask(const hz_renderer_t *r)
{
    return r->opts.mode == HZ_MODE_ADAPTIVE ? r->ad.mask : NULL;
}

void hz_render_set_scalar_recon(hz_renderer_t *r, bool scalar)
{
    r->opts.scalar_recon = scalar;
}

void hz_render_set_serial_passes(hz_renderer_t *r, bool serial)
{
    r->opts.serial_passes = serial;
}

void hz_render_reset_history(hz_renderer_t *r)
{
    r->hist_valid = false;
    r->have_prev = false;
    if (r->opts.mode == HZ_MODE_TDENSE)
        hz_tdense_reset(&r->td);
}
