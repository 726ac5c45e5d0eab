/* Renderer set-up and frame sequencing (see hz/render.h); everything a render mode does is behind its row of
 * hz_render_modes[] (mode.h). */
#include "deflight.h"
#include "hz/fixed.h"
#include "hz/hash.h"
#include "../pattern/timeseq.h"
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
    return (unsigned)m < HZ_MODE_COUNT ? hz_render_modes[m]->name : "unknown";
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
    const hz_mode_ops_t *ops = hz_render_modes[o->mode];
    if (o->msaa4 && (!(ops->flags & HZ_MODE_TAKES_MSAA4) || o->spp != 4))
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
    return ops->check ? ops->check(o, err) : HZ_OK;
}

typedef struct needs {
    bool blend, mask, textures, mirrors, motion, camera_moves, mv;
    uint32_t blend_tris;       /* triangles of a scene with blended surfaces (their dither maps), else 0 */
    uint32_t blend_mats;       /* and its materials (their opacity bounds), else 0 */
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
    n.blend_tris = n.blend ? s->triangle_count : 0u;
    n.blend_mats = n.blend ? s->material_count : 0u;
    return n;
}

/* The frame state a configuration gives a mode (everything but the frame counters and the G-buffer). */
static void frame_setup(hz_render_frame_t *f, const hz_render_opts_t *o, const needs_t *n)
{
    f->opts = *o;
    f->tiles_x = (o->width + HZ_RENDER_TILE - 1) / HZ_RENDER_TILE;
    f->tiles_y = (o->height + HZ_RENDER_TILE - 1) / HZ_RENDER_TILE;
    f->need_mv = n->mv;
    f->has_mirrors = n->mirrors;
    f->blur = o->shutter > 0.0f;
    /* The dither stage exists only where something is blended (hybrid:0 never leaves the exact path). */
    f->dither = n->blend && o->transparency != HZ_TRANSP_EXACT &&
                !(o->transparency == HZ_TRANSP_HYBRID && o->hybrid_x <= 0.0f);
}

/* The region: the G-buffer (by the mode's needs) and the mode's arrays, counted or taken by *p into f (NULL when
 * counting) and the mode's state. */
static void region_layout(hz_render_frame_t *f, void *state, hz_memplan_t *p)
{
    const hz_mode_ops_t *ops = hz_render_modes[f->opts.mode];
    const size_t px = (size_t)f->opts.width * f->opts.height;
    const bool attrs = (ops->flags & HZ_MODE_KEEPS_SURFACE) != 0;
    hz_gbuffer_t *gb = &f->gb;
    hz_memset(gb, 0, sizeof *gb);
    gb->width = f->opts.width, gb->height = f->opts.height;
    hz_memplan_part(p, HZ_PART_GBUFFER);
    if (attrs)
        gb->depth = hz_memplan_array(p, px, 4);
    gb->object = hz_memplan_array(p, px, 2);
    if (attrs) {
        gb->normal = hz_memplan_array(p, px, 12);
        gb->shadow = hz_memplan_array(p, px, 1);
    }
    gb->flags = hz_memplan_array(p, px, 1);
    hz_memplan_part(p, HZ_PART_GBUFFER2);
    if (f->has_mirrors) {
        gb->object2 = hz_memplan_array(p, px, 2);
        if (attrs) {
            gb->normal2 = hz_memplan_array(p, px, 12);
            gb->shadow2 = hz_memplan_array(p, px, 1);
        }
        gb->flags2 = hz_memplan_array(p, px, 1);
    }
    hz_memplan_part(p, HZ_PART_MV);
    if (f->need_mv)
        gb->mv = hz_memplan_array(p, px, 8);
    if (f->need_mv && f->has_mirrors)
        gb->mv_reflect = hz_memplan_array(p, px, 8);
    hz_memplan_part(p, HZ_PART_STATE);
    hz_memset(state, 0, ops->state_bytes);
    ops->layout(state, f, p);
    hz_memplan_part(p, HZ_PART_STATE);
}

/* The triangles' dither maps (hz_transp_maps) and the materials' opacity bounds (hz_transp_bounds), after the
 * region in the frame arena. */
static size_t maps_bytes(const needs_t *n)
{
    if (!n->blend_tris)
        return 0u;
    return hz_align_up((size_t)n->blend_tris * 4u, HZ_MEMPLAN_ALIGN) +
           hz_align_up((size_t)n->blend_mats * 4u, HZ_MEMPLAN_ALIGN) + 2u * HZ_MEMPLAN_ALIGN;
}

/* Counts what a configuration needs: the renderer (with the mode's state inside) and its region (at least
 * opts.reserve_bytes), by part. */
static void count_plan(const hz_render_opts_t *o, const needs_t *n, hz_render_plan_t *plan)
{
    static uint64_t scratch[HZ_RENDER_MODE_STATE_MAX / 8];
    hz_render_frame_t f;
    hz_memset(&f, 0, sizeof f);
    frame_setup(&f, o, n);
    hz_memplan_t p;
    hz_memplan_count(&p);
    region_layout(&f, scratch, &p);
    plan->region_bytes = p.bytes;
    size_t region = p.bytes > o->reserve_bytes ? p.bytes : o->reserve_bytes;
    /* the renderer, then the region, each at 64 bytes (the region's arrays are counted from an aligned start) */
    size_t head = hz_align_up(sizeof(struct hz_renderer), HZ_MEMPLAN_ALIGN) + 2 * HZ_MEMPLAN_ALIGN;
    head += maps_bytes(n);
    plan->frame_bytes = head + region;
    plan->display_bytes = p.part[HZ_PART_DISPLAY];
    plan->gbuffer_bytes = p.part[HZ_PART_GBUFFER];
    plan->gbuffer2_bytes = p.part[HZ_PART_GBUFFER2];
    plan->mv_bytes = p.part[HZ_PART_MV];
    plan->state_bytes = head + p.part[HZ_PART_STATE] + (region - p.bytes);
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
    if (s == HZ_OK)
        s = hz_render_features_check(scene, opts, err);
    if (s != HZ_OK)
        return s;
    if (hz_render_modes[opts->mode]->state_bytes > HZ_RENDER_MODE_STATE_MAX)
        return hz_error_set(err, HZ_E_INTERNAL, "mode %s: state of %zu bytes over %u", hz_render_mode_name(opts->mode),
                            hz_render_modes[opts->mode]->state_bytes, HZ_RENDER_MODE_STATE_MAX);
    needs_t n = scene_needs(scene);
    count_plan(opts, &n, plan);
    plan->thread_bytes = thread_bytes();
    plan->anyhit = n.mask || n.blend;
    plan->transparency = n.blend;
    plan->time_keys = 0;
    plan->keys_bytes = 0;
    if (opts->shutter > 0.0f && n.motion) {
        /* A mode whose pose keys span several frames (tdense: its 4-subframe cycle) needs keys over all their
         * shutters. */
        const hz_mode_ops_t *ops = hz_render_modes[opts->mode];
        uint32_t span = ops->key_frames ? ops->key_frames(opts) : 1u;
        float frames = span > 1u ? (float)(span - 1u) + opts->shutter : opts->shutter;
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
    if (gb->mv)
        hz_memset(gb->mv, 0, px * 8);
    if (gb->mv_reflect)
        hz_memset(gb->mv_reflect, 0, px * 8);
}

/* Lays the region out for r->f.opts (already checked to fit) and gives the mode its first state. */
static hz_status_t region_start(struct hz_renderer *r, hz_error_t *err)
{
    hz_arena_reset(&r->region, 0);
    r->mode = hz_render_modes[r->f.opts.mode];
    hz_memplan_t p;
    hz_memplan_take(&p, &r->region);
    r->mode_state = r->mode_store;
    region_layout(&r->f, r->mode_state, &p);
    if (p.refused) /* the count said it fits: a layout that takes more than it counts */
        return hz_error_set(err, HZ_E_INTERNAL, "mode %s took more of its region than it planned",
                            r->mode->name);
    gbuffer_clear(&r->f.gb, (size_t)r->f.opts.width * r->f.opts.height);
    return r->mode->init ? r->mode->init(r->mode_state, &r->f, err) : HZ_OK;
}

hz_status_t hz_render_create(hz_renderer_t **out, hz_scene_t *scene, hz_accel_t *accel,
                             const hz_render_opts_t *opts, hz_arena_t *frame_arena, hz_arena_t *thread_arenas,
                             uint32_t thread_count, hz_error_t *err)
{
    *out = NULL;
    hz_render_plan_t plan;
    hz_status_t s = hz_render_plan(scene, opts, &plan, err);
    if (s != HZ_OK)
        return s;
    if (thread_count < 1 || thread_count > HZ_MAX_THREADS)
        return hz_error_set(err, HZ_E_INVALID_ARG, "thread count %u outside 1..%d", thread_count, HZ_MAX_THREADS);
    needs_t n = scene_needs(scene);
    /* Refuse up front, naming the arena and both counts, rather than half-way through. */
    size_t need = plan.frame_bytes, have = hz_memplan_room(frame_arena);
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
    struct hz_renderer *r = hz_arena_alloc(frame_arena, sizeof *r, 64);
    size_t region_cap = plan.frame_bytes - (hz_align_up(sizeof *r, 64) + 128) - maps_bytes(&n);
    uint8_t *region = r ? hz_arena_alloc(frame_arena, region_cap, 64) : NULL;
    uint32_t *maps = region && n.blend_tris ? hz_arena_alloc_array(frame_arena, n.blend_tris, 4, 64) : NULL;
    uint32_t *bounds = maps && n.blend_mats ? hz_arena_alloc_array(frame_arena, n.blend_mats, 4, 64) : NULL;
    if (!r || !region || (n.blend_tris && !maps) || (n.blend_mats && !bounds)) {
        s = hz_arena_error(frame_arena, err);
        hz_arena_reset(frame_arena, mark);
        return s;
    }
    hz_memset(r, 0, sizeof *r);
    hz_arena_init(&r->region, frame_arena->name, region, region_cap);
    frame_setup(&r->f, opts, &n);
    r->scene = scene;
    r->lights = scene->lights, r->light_count = scene->light_count;
    if (scene->light_count == 0) {
        hz_deflight_place(scene, &r->default_light);
        r->lights = &r->default_light, r->light_count = 1, r->default_lit = true;
    }
    r->accel = accel;
    r->has_blend = n.blend, r->has_mask = n.mask, r->has_textures = n.textures;
    if (HZ_FEATURE_TRANSPARENCY && maps) { /* a build without transparency has none (transp.c leaves them out) */
        hz_transp_maps(scene, maps);
        if (bounds)
            hz_transp_bounds(scene, n.textures, bounds);
    }
    r->tri_maps = maps;
    r->blend_bound = bounds; /* NULL without blended surfaces (so in a build without transparency) */
    r->has_motion = n.motion, r->camera_moves = n.camera_moves;
    r->cam_blur = r->f.blur && n.camera_moves;
    r->keys = r->f.blur && n.motion ? opts->keys : NULL;
    r->tmap_a = 0.0f, r->tmap_b = 1.0f;
    const hz_hzb_header_t *hb = scene->header;
    r->offset_scale = 0.0f;
    for (int c = 0; c < 3; c++)
        r->offset_scale = hz_maxf(r->offset_scale, hz_maxf(hz_absf(hb->bounds_min[c]), hz_absf(hb->bounds_max[c])));
    if ((s = region_start(r, err)) != HZ_OK) {
        hz_arena_reset(frame_arena, mark);
        return s;
    }
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
        if (HZ_FEATURE_TRANSPARENCY && (n.mask || n.blend)) {
            w->ctx.anyhit = hz_render_anyhit;
            w->ctx.user = w;
        }
        r->workers_by_thread[t] = w;
    }
    *out = r;
    return HZ_OK;
}

/* Motion blur: the camera across this frame's shutter, and the pose keys (evaluated and refitted when they do
 * not hold this frame's interval already). Times are offsets from the frame's time: the frame index tells how
 * far apart two frames are (1 / frame_hz each), so no absolute times are subtracted. */
static hz_status_t blur_begin(hz_renderer_t *r, uint64_t frame_index, hz_time_ns_t time, hz_error_t *err)
{
    const float hz = (float)r->f.opts.frame_hz, half = 0.5f * r->f.opts.shutter / hz;
    if (r->cam_blur) {
        for (uint32_t i = 0; i < HZ_RENDER_CAMERA_KEYS; i++) {
            float dt = -half + 2.0f * half * ((float)i / (float)(HZ_RENDER_CAMERA_KEYS - 1));
            hz_camera_t cam = hz_scene_camera_ns(r->scene, time + hz_time_from_s(dt));
            hz_view_setup(&r->cam_views[i], &cam, r->f.opts.width, r->f.opts.height);
        }
    }
    hz_posekeys_t *k = r->keys;
    if (!k)
        return HZ_OK;
    /* A mode whose key interval spans several frames (tdense: the cycle's four shutters) evaluates the keys once
     * per interval (the renderer is told frames, not intervals: the interval's first frame is frame_index -
     * phase). */
    uint32_t span = r->mode->key_frames ? r->mode->key_frames(&r->f.opts) : 1u;
    bool cycle = span > 1u;
    uint64_t sub = cycle && r->mode->key_phase ? r->mode->key_phase(r->mode_state) % span : 0u;
    bool reuse = cycle && r->key_evals > 0 && frame_index - sub == r->keys_cycle && frame_index >= r->keys_frame &&
                 k->valid && k->time == r->keys_t && k->lo == r->keys_lo && k->hi == r->keys_hi;
    if (!reuse) {
        float lo = cycle ? -(float)sub / hz - half : -half,
              hi = cycle ? (float)(span - 1u - (uint32_t)sub) / hz + half : half;
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
    float span_s = r->keys_hi - r->keys_lo;
    float start = (float)(frame_index - r->keys_frame) / hz - half - r->keys_lo;
    r->tmap_a = span_s > 0.0f ? start / span_s : 0.0f;
    r->tmap_b = span_s > 0.0f ? 2.0f * half / span_s : 0.0f;
    return HZ_OK;
}

hz_status_t hz_render_begin_frame(hz_renderer_t *r, uint64_t frame_index, float time, hz_error_t *err)
{
    if (!hz_isfinitef(time))
        return hz_error_set(err, HZ_E_INVALID_ARG, "frame time is not finite");
    return hz_render_begin_frame_ns(r, frame_index, hz_time_from_s(time), err);
}

static bool same_view(const hz_view_t *a, const hz_view_t *b)
{
    return a->eye.x == b->eye.x && a->eye.y == b->eye.y && a->eye.z == b->eye.z && a->fwd.x == b->fwd.x &&
           a->fwd.y == b->fwd.y && a->fwd.z == b->fwd.z && a->right.x == b->right.x && a->right.y == b->right.y &&
           a->right.z == b->right.z && a->up.x == b->up.x && a->up.y == b->up.y && a->up.z == b->up.z;
}

hz_status_t hz_render_begin_frame_ns(hz_renderer_t *r, uint64_t frame_index, hz_time_ns_t time_ns, hz_error_t *err)
{
    float time = hz_time_wrap_s(time_ns, r->scene->header->duration);
    r->frame_refits = 0;
    if (HZ_FEATURE_MOTION && r->has_motion) {
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
    hz_view_setup(&r->view, &cam, r->f.opts.width, r->f.opts.height);
    hz_view_footprint(&r->view, &r->footprint);
    if (HZ_FEATURE_MOTION && r->f.blur) {
        hz_status_t s = blur_begin(r, frame_index, time_ns, err);
        if (s != HZ_OK)
            return s;
    }
    if (!r->have_prev)
        r->prev_view = r->view;
    r->f.frame = frame_index;
    r->time = time;
    r->time_ns = time_ns;
    /* Any change of the camera (seed 001, 3.2.2 restarts every static window on it). */
    r->f.camera_moved = r->have_prev && !same_view(&r->view, &r->prev_view);
    if (r->mode->begin_frame)
        r->mode->begin_frame(r->mode_state, &r->f);
    for (uint32_t t = 0; t < r->thread_count; t++)
        hz_memset(&r->workers_by_thread[t]->b.stats, 0, sizeof(hz_render_stats_t));
    return HZ_OK;
}

bool hz_render_mode_keeps_surface(hz_render_mode_t mode)
{
    return (unsigned)mode < HZ_MODE_COUNT && (hz_render_modes[mode]->flags & HZ_MODE_KEEPS_SURFACE);
}

uint32_t hz_render_pass_count(const hz_renderer_t *r)
{
    return r->mode->passes;
}

uint32_t hz_render_pass_items(const hz_renderer_t *r, uint32_t pass)
{
    return pass < r->mode->passes ? r->mode->pass_items(r->mode_state, &r->f, pass) : 0u;
}

float hz_render_sample_time(const hz_render_frame_t *f, uint32_t px, uint32_t index, uint32_t count)
{
    return hz_u32_to_unit(hz_timeseq_u32(px, index, count, f->opts.seed));
}

void hz_render_sample_tile(hz_render_frame_t *f, hz_batch_t *b, uint32_t tile, const hz_tile_sampling_t *s)
{
    const struct hz_renderer *r = (const struct hz_renderer *)(const void *)f; /* f is the renderer's first member */
    float jitter[HZ_TILE_PIXELS][2], times[HZ_TILE_PIXELS];
    hz_tile_slots(r, tile, b->pixel);
    hz_memset(b->radiance, 0, sizeof b->radiance);
    const uint32_t spp = s->spp, side = hz_isqrt_u64(spp);
    b->footprint = s->footprint;
    for (uint32_t k = 0; k < spp; k++) {
        for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++) {
            if (s->fixed_jitter) {
                jitter[slot][0] = s->fixed_jitter[0], jitter[slot][1] = s->fixed_jitter[1];
            } else if (s->msaa4) {
                jitter[slot][0] = (float)hz_msaa4_jitter16[k][0] * (1.0f / 16.0f);
                jitter[slot][1] = (float)hz_msaa4_jitter16[k][1] * (1.0f / 16.0f);
            } else if (spp == 1) {
                jitter[slot][0] = jitter[slot][1] = 0.0f;
            } else {
                /* Stratified: one sample in each cell of a side x side grid, placed by a per-pixel hash. */
                uint32_t h = hz_hash3(b->pixel[slot], k, f->opts.seed);
                float cx = (float)(k % side), cy = (float)(k / side);
                jitter[slot][0] = (cx + hz_u32_to_unit(h)) / (float)side - 0.5f;
                jitter[slot][1] = (cy + hz_u32_to_unit(hz_hash32(h))) / (float)side - 0.5f;
            }
            if (HZ_FEATURE_MOTION && f->blur && b->pixel[slot] != UINT32_MAX)
                times[slot] = s->time_count ? hz_render_sample_time(f, b->pixel[slot], s->time_index, s->time_count)
                                            : hz_render_sample_time(f, b->pixel[slot], k, spp);
        }
        b->dither_frame = (uint32_t)f->frame * spp + k; /* N spp walk N steps of the dither's sequence */
        hz_render_trace(f, b, (const float(*)[2])jitter, HZ_FEATURE_MOTION && f->blur ? times : NULL, k == 0);
    }
    b->footprint = false;
}

void hz_render_trace_tile(hz_render_frame_t *f, hz_batch_t *b, uint32_t tile, const hz_tile_sampling_t *s,
                          hz_image_t *dst)
{
    hz_render_sample_tile(f, b, tile, s);
    const float scale = 1.0f / (float)s->spp;
    for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++) {
        uint32_t px = b->pixel[slot];
        if (px != UINT32_MAX)
            hz_render_store(b, dst->rgb + (size_t)px * 3, &b->radiance[slot * 3], scale);
    }
}

void hz_render_pass_run(hz_renderer_t *r, uint32_t pass, uint32_t item, uint32_t thread)
{
    if (thread >= r->thread_count || item >= hz_render_pass_items(r, pass))
        return;
    r->mode->pass_run(r->mode_state, &r->f, pass, item, &r->workers_by_thread[thread]->b);
}

/* Pass 0's items as rows x row_items: the mode's grid, else the render tiles. */
static void trace_grid(const hz_renderer_t *r, uint32_t *rows, uint32_t *row_items)
{
    *rows = r->f.tiles_y, *row_items = r->f.tiles_x;
    if (r->mode->trace_grid)
        r->mode->trace_grid(r->mode_state, &r->f, rows, row_items);
}

uint32_t hz_render_overlap_units(const hz_renderer_t *r, uint32_t *trace_rows, uint32_t *row_items)
{
    trace_grid(r, trace_rows, row_items);
    if (r->f.opts.serial_passes || !r->mode->overlap_units)
        return 0u;
    return r->mode->overlap_units(r->mode_state, &r->f);
}

void hz_render_overlap_needs(const hz_renderer_t *r, uint32_t unit, uint32_t *row_lo, uint32_t *row_hi)
{
    uint32_t lo = 0, hi = 0, rows, row_items;
    trace_grid(r, &rows, &row_items);
    if (r->mode->overlap_needs)
        r->mode->overlap_needs(r->mode_state, &r->f, unit, &lo, &hi);
    *row_lo = lo;
    *row_hi = hi < rows ? hi : rows - 1u;
}

void hz_render_overlap_run(hz_renderer_t *r, uint32_t unit)
{
    if (r->mode->overlap_run)
        r->mode->overlap_run(r->mode_state, &r->f, unit);
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
        add_stats(&r->last, &r->workers_by_thread[t]->b.stats);
    r->last.refits = r->frame_refits;
    add_stats(&r->total, &r->last);
    if (r->mode->end_frame)
        r->mode->end_frame(r->mode_state, &r->f);
    r->have_prev = true;
}

const hz_image_t *hz_render_output(const hz_renderer_t *r)
{
    return r->mode->output(r->mode_state);
}

const hz_gbuffer_t *hz_render_gbuffer(const hz_renderer_t *r)
{
    return &r->f.gb;
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

void *hz_render_mode_state(const hz_renderer_t *r, const hz_mode_ops_t *ops)
{
    return r->mode == ops ? r->mode_state : NULL;
}

void hz_render_set_scalar_recon(hz_renderer_t *r, bool scalar)
{
    r->f.opts.scalar_recon = scalar;
}

void hz_render_set_serial_passes(hz_renderer_t *r, bool serial)
{
    r->f.opts.serial_passes = serial;
}

/* What the scene needs, as create saw it (reconfigure keeps it). */
static needs_t needs_of(const struct hz_renderer *r)
{
    needs_t n = { r->has_blend, r->has_mask, r->has_textures, r->f.has_mirrors, r->has_motion, r->camera_moves,
                  r->f.need_mv, r->has_blend ? r->scene->triangle_count : 0u,
                  r->has_blend ? r->scene->material_count : 0u };
    return n;
}

static bool same_adaptive(const hz_adaptive_opts_t *a, const hz_adaptive_opts_t *b)
{
    bool same = a->normal_angle_deg == b->normal_angle_deg && a->focus_count == b->focus_count &&
                (a->bilinear != 0) == (b->bilinear != 0);
    for (int k = 0; k < HZ_TAU_COUNT; k++)
        same = same && a->tau[k] == b->tau[k];
    for (uint32_t i = 0; same && i < a->focus_count && i < HZ_AMASK_MAX_FOCUS; i++)
        same = a->focus[i] == b->focus[i];
    return same;
}

hz_status_t hz_render_reconfigure(hz_renderer_t *r, const hz_render_opts_t *o, hz_error_t *err)
{
    hz_status_t s = hz_render_opts_check(o, err);
    if (s == HZ_OK)
        s = hz_render_features_check(r->scene, o, err);
    if (s != HZ_OK)
        return s;
    const hz_render_opts_t *c = &r->f.opts;
    if (o->shutter != c->shutter || o->frame_hz != c->frame_hz || o->keys != c->keys ||
        o->tdense_cycle_keys != c->tdense_cycle_keys)
        return hz_error_set(err, HZ_E_INVALID_ARG, "reconfigure: motion blur (shutter, frame rate, pose keys) is "
                                                   "fixed at create");
    needs_t n = needs_of(r);
    hz_render_plan_t plan;
    count_plan(o, &n, &plan);
    if (plan.region_bytes > r->region.cap)
        return hz_error_set(err, HZ_E_NO_MEMORY, "arena '%s': a %ux%u %s renderer needs %zu bytes of the %zu held at "
                            "create (hz_render_opts_t.reserve_bytes)", r->region.name, o->width, o->height,
                            hz_render_mode_name(o->mode), plan.region_bytes, r->region.cap);
    const bool relayout = o->width != c->width || o->height != c->height || o->mode != c->mode ||
                          o->tdense_rule != c->tdense_rule || o->tdense_gamma != c->tdense_gamma ||
                          o->tdense_reflect_mv != c->tdense_reflect_mv || o->seed != c->seed ||
                          !same_adaptive(&o->adaptive, &c->adaptive);
    hz_render_opts_t keep = r->f.opts;
    frame_setup(&r->f, o, &n);
    r->f.opts.reserve_bytes = keep.reserve_bytes;
    if (!relayout)
        return HZ_OK;
    /* Another size or mode: the region laid out anew, and no history (the previous frame's views and motion
     * belong to the old layout): the next frame starts as after a cut. */
    if ((s = region_start(r, err)) != HZ_OK) {
        /* the old configuration is still counted to fit: put it back */
        hz_error_t ignored;
        frame_setup(&r->f, &keep, &n);
        region_start(r, &ignored);
        r->have_prev = false;
        return s;
    }
    r->have_prev = false;
    return HZ_OK;
}

void hz_render_reset_history(hz_renderer_t *r)
{
    r->have_prev = false;
    if (r->mode->reset)
        r->mode->reset(r->mode_state, &r->f);
}
