/* errtime methods through hzrt's renderer (see et_render.h). */
#include "et_render.h"

#include <stdio.h>
#include <string.h>

#include "accel_backend.h"
#include "blur_setup.h"
#include "hz/config.h"
#include "pools.h"
#include "scenefile.h"
#include "render_run.h"
#include "threads.h"

/* The open scene: the pools are process-wide, so there is one. */
typedef struct et_scene {
    bool open;
    hz_pools_t *pools;
    hz_scene_t scene;
    hz_accel_t *accel;
    uint32_t threads;
    hz_arena_mark_t scene_mark, accel_mark, frame_mark, thread_marks[HZ_MAX_THREADS];
    char settings[192];
} et_scene_t;

static et_scene_t g_scene;

typedef struct et_state {
    et_scene_t *sc;
    hz_renderer_t *r;
    float refresh_hz;
    uint64_t camera;   /* camera rays of the last frame */
    bool still;        /* a still view: every frame at scene time 0 (et_stability.h) */
    uint64_t rendered; /* frames this renderer drew: its own frame index (TAA's jitter phase, tdense's subframe),
                        * which differs from the displayed frame's for held methods */
    /* motion blur: the run's own pose keys and accel, above these marks */
    hz_posekeys_t keys;
    hz_accel_t *accel;
    hz_arena_mark_t scene_mark, accel_mark;
} et_state_t;

static float g_shutter = -1.0f; /* --shutter override (< 0: the methods' own) */

void hz_et_render_set_shutter(float shutter)
{
    g_shutter = shutter;
}

static float shutter_of(const hz_et_render_params_t *p)
{
    return p->shutter > 0.0f && g_shutter > 0.0f ? g_shutter : p->shutter;
}

static void give_back_threads(et_scene_t *sc)
{
    for (uint32_t t = 0; t < sc->threads; t++)
        hz_arena_reset(&sc->pools->thread[t], sc->thread_marks[t]);
}

static void opts_for(const hz_et_render_params_t *p, uint32_t w, uint32_t h, hz_render_opts_t *o)
{
    hz_render_opts_default(o);
    o->width = w;
    o->height = h;
    o->mode = p->mode;
    o->spp = p->spp ? p->spp : 1;
    o->taa_clip = p->taa_clip;
    o->taa_catmull_rom = p->taa_catmull_rom;
    o->seed = p->seed;
    if (p->mode == HZ_MODE_ADAPTIVE) {
        if (p->adaptive_knob == HZ_ET_TAU_COL_ONLY)
            for (int k = 0; k < HZ_TAU_COUNT; k++)
                o->adaptive.tau[k] = 1.0f; /* 1 switches an attribute off (hz_amask) */
        o->adaptive.tau[HZ_TAU_COL] = p->adaptive_tau;
        if (p->adaptive_knob == HZ_ET_TAU_ALPHA)
            o->adaptive.tau[HZ_TAU_PTE] = o->adaptive.tau[HZ_TAU_STE] = p->adaptive_tau;
        o->adaptive.bilinear = p->adaptive_bilinear;
        o->adaptive.footprint = p->adaptive_footprint;
    }
    o->transparency = p->transparency;
    o->hybrid_x = p->hybrid_x;
    o->shutter = shutter_of(p);
}

static void give_back_blur(et_state_t *st)
{
    if (!st->accel)
        return;
    hz_accel_release(st->accel);
    st->accel = NULL;
    hz_arena_reset(&st->sc->pools->accel, st->accel_mark);
    hz_arena_reset(&st->sc->pools->scene, st->scene_mark);
}

static hz_status_t rbegin(const hz_et_method_t *m, const hz_et_sequence_t *seq, hz_arena_t *arena, void **state,
                          hz_error_t *err)
{
    et_scene_t *sc = (et_scene_t *)seq->scene_data;
    if (!sc || sc != &g_scene || !sc->open)
        return hz_error_set(err, HZ_E_INVALID_ARG, "no renderer scene is open (hz_et_render_open)");
    et_state_t *st = hz_arena_alloc(arena, sizeof *st, 64);
    if (!st)
        return hz_arena_error(arena, err);
    hz_render_opts_t o;
    opts_for(m->params, seq->width, seq->height, &o);
    st->sc = sc;
    st->rendered = 0;
    st->refresh_hz = (float)seq->refresh_hz;
    st->still = seq->camera && !strcmp(seq->camera, "still");
    st->accel = NULL;
    const hz_et_render_params_t *p = m->params;
    hz_status_t s = HZ_OK;
    if (o.shutter > 0.0f) {
        /* A motion accel of the method's kind over pose keys, both above the scene's own; rend gives them back. */
        o.frame_hz = seq->refresh_hz;
        st->scene_mark = hz_arena_mark(&sc->pools->scene);
        st->accel_mark = hz_arena_mark(&sc->pools->accel);
        hz_accel_config_t cfg;
        hz_accel_config_default(&cfg);
        cfg.rigid = p->rigid;
        s = hz_blur_build_cfg(&sc->scene, &o, p->embree ? HZ_ACCEL_EMBREE : HZ_ACCEL_NATIVE, p->blur, &cfg,
                              sc->pools, &st->keys, &st->accel, err);
    }
    if (s == HZ_OK)
        s = hz_render_create(&st->r, &sc->scene, st->accel ? st->accel : sc->accel, &o, arena, sc->pools->thread,
                             sc->threads, err);
    if (s != HZ_OK) {
        give_back_threads(sc);
        give_back_blur(st);
        return s;
    }
    *state = st;
    return HZ_OK;
}

static hz_status_t rrender(void *state, uint32_t frame, hz_image_t *out, uint64_t *rays, hz_error_t *err)
{
    et_state_t *st = state;
    float t = st->still ? 0.0f : (float)frame / st->refresh_hz;
    hz_status_t s = hz_render_run_frame(st->r, st->rendered++, t, err);
    if (s != HZ_OK)
        return s;
    if ((s = hz_image_copy(out, hz_render_output(st->r), err)) != HZ_OK)
        return s;
    hz_render_stats_t last;
    hz_render_frame_stats(st->r, &last, NULL);
    *rays = last.primary_rays + last.shadow_rays + last.secondary_rays;
    st->camera = last.primary_rays;
    if (last.queue_full || last.nonfinite)
        return hz_error_set(err, HZ_E_INTERNAL, "the renderer dropped %llu rays (full queue) and replaced %llu "
                            "non-finite values", (unsigned long long)last.queue_full,
                            (unsigned long long)last.nonfinite);
    return HZ_OK;
}

static uint64_t rcamera(void *state)
{
    return ((et_state_t *)state)->camera;
}

static void rend(void *state)
{
    et_state_t *st = state;
    give_back_threads(st->sc);
    give_back_blur(st);
}

/* ---- the table ---- */

/* Designated initialisers: a field a row leaves out is 0 (exact transparency, no shutter, ...). */
#define FULL(n) { .mode = HZ_MODE_FULL, .spp = n }
static const hz_et_render_params_t p_full1 = FULL(1), p_full4 = FULL(4), p_full9 = FULL(9), p_full16 = FULL(16);
static const hz_et_render_params_t p_taa = { .mode = HZ_MODE_TAA, .spp = 1 };
static const hz_et_render_params_t p_taa_clip = { .mode = HZ_MODE_TAA, .spp = 1, .taa_clip = true };
static const hz_et_render_params_t p_taa_cr = { .mode = HZ_MODE_TAA, .spp = 1, .taa_catmull_rom = true };
static const hz_et_render_params_t p_taa_clip_cr = { .mode = HZ_MODE_TAA, .spp = 1, .taa_clip = true,
                                                     .taa_catmull_rom = true };
#define ADAPTIVE(t) { .mode = HZ_MODE_ADAPTIVE, .spp = 1, .adaptive_tau = t }
static const hz_et_render_params_t p_ad01 = ADAPTIVE(0.1f), p_ad03 = ADAPTIVE(0.3f), p_ad06 = ADAPTIVE(0.6f),
                                   p_ad10 = ADAPTIVE(1.0f);
#define ADAPTIVE_BILINEAR(t) { .mode = HZ_MODE_ADAPTIVE, .spp = 1, .adaptive_tau = t, .adaptive_bilinear = true }
static const hz_et_render_params_t p_ab01 = ADAPTIVE_BILINEAR(0.1f), p_ab03 = ADAPTIVE_BILINEAR(0.3f),
                                   p_ab06 = ADAPTIVE_BILINEAR(0.6f);
#define ADAPTIVE_FOOTPRINT(t) { .mode = HZ_MODE_ADAPTIVE, .spp = 1, .adaptive_tau = t, .adaptive_footprint = true }
static const hz_et_render_params_t p_af01 = ADAPTIVE_FOOTPRINT(0.1f), p_af03 = ADAPTIVE_FOOTPRINT(0.3f),
                                   p_af06 = ADAPTIVE_FOOTPRINT(0.6f), p_af10 = ADAPTIVE_FOOTPRINT(1.0f);
#define FIG7(knob, t) { .mode = HZ_MODE_ADAPTIVE, .spp = 1, .adaptive_tau = t, .adaptive_knob = knob }
static const hz_et_render_params_t p_co01 = FIG7(HZ_ET_TAU_COL_ONLY, 0.1f), p_co02 = FIG7(HZ_ET_TAU_COL_ONLY, 0.2f),
                                   p_co03 = FIG7(HZ_ET_TAU_COL_ONLY, 0.3f), p_co04 = FIG7(HZ_ET_TAU_COL_ONLY, 0.4f);
static const hz_et_render_params_t p_mm01 = FIG7(HZ_ET_TAU_COL, 0.1f), p_mm02 = FIG7(HZ_ET_TAU_COL, 0.2f),
                                   p_mm03 = FIG7(HZ_ET_TAU_COL, 0.3f), p_mm04 = FIG7(HZ_ET_TAU_COL, 0.4f);
/* The reference: 256 stratified samples with a seed no method uses. */
static const hz_et_render_params_t p_ref = { .mode = HZ_MODE_FULL, .spp = 256, .seed = 0x5eed };

#define METHOD(name, knob, value, params) { name, knob, value, rbegin, rrender, rend, params, 0, rcamera }
#define HELD(name, knob, value, params, hold) { name, knob, value, rbegin, rrender, rend, params, hold, rcamera }

const hz_et_method_t hz_et_render_reference = METHOD("full-frame", "spp", 256, &p_ref);

/* Every method the renderer offers, in chart order. Later render modes add their rows here (one polyline per
 * name, one point per knob value), e.g. adaptive supersampling (seed 003) with its threshold as the knob. */
const hz_et_method_t hz_et_render_methods[HZ_ET_RENDER_METHOD_COUNT] = {
    METHOD("full-frame", "spp", 1, &p_full1),
    METHOD("full-frame", "spp", 4, &p_full4),
    METHOD("full-frame", "spp", 9, &p_full9),
    METHOD("full-frame", "spp", 16, &p_full16),
    METHOD("taa", "spp", 1, &p_taa),                   /* clamp per channel, bilinear history (the defaults) */
    METHOD("taa-clip", "spp", 1, &p_taa_clip),         /* clip towards the box centre */
    METHOD("taa-catmull-rom", "spp", 1, &p_taa_cr),    /* Catmull-Rom history fetch */
    METHOD("taa-clip-cr", "spp", 1, &p_taa_clip_cr),   /* both */
    METHOD("adaptive", "tau", 0.1, &p_ad01),          /* seed 003, Table 2's defaults but tau_alpha */
    METHOD("adaptive", "tau", 0.3, &p_ad03),
    METHOD("adaptive", "tau", 0.6, &p_ad06),
    METHOD("adaptive", "tau", 1.0, &p_ad10),
    METHOD("adaptive-bilinear", "tau", 0.1, &p_ab01),  /* seed 003 section 6: inactive subpixels interpolated */
    METHOD("adaptive-bilinear", "tau", 0.3, &p_ab03),
    METHOD("adaptive-bilinear", "tau", 0.6, &p_ab06),
    METHOD("adaptive-footprint", "tau", 0.1, &p_af01), /* the presample's textures over the pixel's footprint */
    METHOD("adaptive-footprint", "tau", 0.3, &p_af03),
    METHOD("adaptive-footprint", "tau", 0.6, &p_af06),
    METHOD("adaptive-footprint", "tau", 1.0, &p_af10),
    METHOD("adaptive-colour-only", "tau-col", 0.1, &p_co01), /* seed 003 Fig. 7, first row */
    METHOD("adaptive-colour-only", "tau-col", 0.2, &p_co02),
    METHOD("adaptive-colour-only", "tau-col", 0.3, &p_co03),
    METHOD("adaptive-colour-only", "tau-col", 0.4, &p_co04),
    METHOD("adaptive-multiple", "tau-col", 0.1, &p_mm01),    /* Fig. 7, second row */
    METHOD("adaptive-multiple", "tau-col", 0.2, &p_mm02),
    METHOD("adaptive-multiple", "tau-col", 0.3, &p_mm03),
    METHOD("adaptive-multiple", "tau-col", 0.4, &p_mm04),
};

/* Motion blur (see et_render.h). */
#define BLUR_R(n, kind, emb, rig)                                                                                  \
    { .mode = HZ_MODE_FULL, .spp = n, .shutter = HZ_ET_BLUR_SHUTTER, .blur = kind, .embree = emb, .rigid = rig }
#define BLUR(n, kind, emb) BLUR_R(n, kind, emb, HZ_ACCEL_RIGID_REFIT)
static const hz_et_render_params_t p_ms1 = BLUR(1, HZ_ACCEL_BLUR_MSBVH, false), p_ms4 = BLUR(4, HZ_ACCEL_BLUR_MSBVH, false),
                                   p_ms16 = BLUR(16, HZ_ACCEL_BLUR_MSBVH, false);
static const hz_et_render_params_t p_in1 = BLUR(1, HZ_ACCEL_BLUR_INTERP, false),
                                   p_in4 = BLUR(4, HZ_ACCEL_BLUR_INTERP, false),
                                   p_in16 = BLUR(16, HZ_ACCEL_BLUR_INTERP, false);
static const hz_et_render_params_t p_is1 = BLUR_R(1, HZ_ACCEL_BLUR_MSBVH, false, HZ_ACCEL_RIGID_INSTANCE),
                                   p_is4 = BLUR_R(4, HZ_ACCEL_BLUR_MSBVH, false, HZ_ACCEL_RIGID_INSTANCE),
                                   p_is16 = BLUR_R(16, HZ_ACCEL_BLUR_MSBVH, false, HZ_ACCEL_RIGID_INSTANCE);
static const hz_et_render_params_t p_mb_ref = { .mode = HZ_MODE_FULL, .spp = 256, .seed = 0x5eed,
                                                .shutter = HZ_ET_BLUR_SHUTTER, .blur = HZ_ACCEL_BLUR_MSBVH };
const hz_et_method_t hz_et_blur_reference = METHOD("full-frame-mb", "spp", 256, &p_mb_ref);
#if HZ_HAVE_EMBREE
static const hz_et_render_params_t p_em1 = BLUR(1, HZ_ACCEL_BLUR_MSBVH, true), p_em4 = BLUR(4, HZ_ACCEL_BLUR_MSBVH, true),
                                   p_em16 = BLUR(16, HZ_ACCEL_BLUR_MSBVH, true);
#endif
const hz_et_method_t hz_et_blur_methods[HZ_ET_BLUR_METHOD_COUNT] = {
    METHOD("msbvh", "spp", 1, &p_ms1),  METHOD("msbvh", "spp", 4, &p_ms4),  METHOD("msbvh", "spp", 16, &p_ms16),
    METHOD("interp", "spp", 1, &p_in1), METHOD("interp", "spp", 4, &p_in4), METHOD("interp", "spp", 16, &p_in16),
    METHOD("instances", "spp", 1, &p_is1), METHOD("instances", "spp", 4, &p_is4),
    METHOD("instances", "spp", 16, &p_is16),
#if HZ_HAVE_EMBREE
    METHOD("embree", "spp", 1, &p_em1), METHOD("embree", "spp", 4, &p_em4), METHOD("embree", "spp", 16, &p_em16),
#endif
};

static const hz_et_render_params_t p_tdense = { .mode = HZ_MODE_TDENSE, .spp = 1 };
static const hz_et_render_params_t p_ref64 = { .mode = HZ_MODE_FULL, .spp = 64, .seed = 0x5eed };

const hz_et_method_t hz_et_display_reference = METHOD("full-frame", "spp", 64, &p_ref64);

const hz_et_method_t hz_et_display_methods[HZ_ET_DISPLAY_METHOD_COUNT] = {
    METHOD("tdense", "hz", 240, &p_tdense),
    HELD("full-1spp", "hz", 60, &p_full1, 4),
    METHOD("full-1spp", "hz", 240, &p_full1),
    HELD("taa", "hz", 60, &p_taa, 4),
    METHOD("taa", "hz", 240, &p_taa),
};

#define TAA_T(t, x) { .mode = HZ_MODE_TAA, .spp = 1, .transparency = t, .hybrid_x = x }
static const hz_et_render_params_t p_t_exact = TAA_T(HZ_TRANSP_EXACT, 0.0f), p_t_rr = TAA_T(HZ_TRANSP_RR, 0.0f),
                                   p_t_std = TAA_T(HZ_TRANSP_STD, 0.0f), p_t_dtaa = TAA_T(HZ_TRANSP_DTAA, 0.0f),
                                   p_t_dtaas = TAA_T(HZ_TRANSP_DTAA_STAR, 0.0f),
                                   p_t_h25 = TAA_T(HZ_TRANSP_HYBRID, 0.25f), p_t_h50 = TAA_T(HZ_TRANSP_HYBRID, 0.5f),
                                   p_t_h75 = TAA_T(HZ_TRANSP_HYBRID, 0.75f);

const hz_et_method_t hz_et_transp_methods[HZ_ET_TRANSP_METHOD_COUNT] = {
    METHOD("taa-exact", "spp", 1, &p_t_exact),
    METHOD("taa-rr", "spp", 1, &p_t_rr),
    METHOD("taa-std", "spp", 1, &p_t_std),
    METHOD("taa-dtaa", "spp", 1, &p_t_dtaa),
    METHOD("taa-dtaa-star", "spp", 1, &p_t_dtaas),
    METHOD("taa-hybrid", "x", 0.25, &p_t_h25),
    METHOD("taa-hybrid", "x", 0.5, &p_t_h50),
    METHOD("taa-hybrid", "x", 0.75, &p_t_h75),
};

static const hz_et_render_params_t p_td_std = { .mode = HZ_MODE_TDENSE, .spp = 1, .transparency = HZ_TRANSP_STD };

const hz_et_method_t hz_et_transp_display_methods[HZ_ET_TRANSP_DISPLAY_METHOD_COUNT] = {
    METHOD("tdense-std", "hz", 240, &p_td_std),
    METHOD("tdense-exact", "hz", 240, &p_tdense),
    HELD("taa-std", "hz", 60, &p_t_std, 4),
    HELD("taa-exact", "hz", 60, &p_t_exact, 4),
};

/* ---- scenes ---- */

static uint64_t fnv1a64(uint64_t h, const void *data, size_t n)
{
    const uint8_t *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

/* Two small full-frame renders (1 and 16 spp, at t = 0 and 0.5 s) hashed: a fingerprint of what the renderer
 * makes of this scene. Uses the frame pool as scratch and gives it back. */
static hz_status_t fingerprint(et_scene_t *sc, uint64_t *out, hz_error_t *err)
{
    static const uint32_t spp[2] = { 1, 16 };
    static const float when[2] = { 0.0f, 0.5f };
    uint64_t h = 0xcbf29ce484222325ull;
    for (int k = 0; k < 2; k++) {
        hz_et_render_params_t p = FULL(spp[k]);
        hz_render_opts_t o;
        opts_for(&p, 40, 24, &o);
        hz_renderer_t *r = NULL;
        hz_status_t s = hz_render_create(&r, &sc->scene, sc->accel, &o, &sc->pools->frame, sc->pools->thread,
                                         sc->threads, err);
        if (s == HZ_OK)
            s = hz_render_run_frame(r, 0, when[k], err);
        if (s == HZ_OK) {
            const hz_image_t *img = hz_render_output(r);
            h = fnv1a64(h, img->rgb, hz_image_pixels(img) * 3 * sizeof(float));
        }
        hz_arena_reset(&sc->pools->frame, sc->frame_mark);
        give_back_threads(sc);
        if (s != HZ_OK)
            return s;
    }
    *out = h;
    return HZ_OK;
}

static void unwind(et_scene_t *sc)
{
    hz_threads_stop();
    if (sc->accel)
        hz_accel_release(sc->accel);
    sc->accel = NULL;
    hz_arena_reset(&sc->pools->frame, sc->frame_mark);
    hz_arena_reset(&sc->pools->accel, sc->accel_mark);
    hz_arena_reset(&sc->pools->scene, sc->scene_mark);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        hz_arena_reset(&sc->pools->thread[t], sc->thread_marks[t]);
    sc->open = false;
}

hz_status_t hz_et_render_open(const char *file, const hz_et_env_t *env, hz_et_sequence_t *seq, hz_error_t *err)
{
    et_scene_t *sc = &g_scene;
    if (sc->open)
        return hz_error_set(err, HZ_E_INVALID_ARG, "errtime: a renderer scene is already open; close it first");
    char path[4096];
    if (strchr(file, '/')) { /* a path (hzerrtime --scene PATH.hzb) */
        if (snprintf(path, sizeof path, "%s", file) >= (int)sizeof path)
            return hz_error_set(err, HZ_E_RANGE, "%s: scene path too long", file);
    } else if (strcmp(file, "builtin") != 0) {
        if (!env->scene_dir || !*env->scene_dir)
            return hz_error_set(err, HZ_E_INVALID_ARG, "errtime: no scene directory for %s", file);
        if (snprintf(path, sizeof path, "%s/%s", env->scene_dir, file) >= (int)sizeof path)
            return hz_error_set(err, HZ_E_RANGE, "%s: scene path too long", env->scene_dir);
    } else {
        snprintf(path, sizeof path, "builtin");
    }
    memset(sc, 0, sizeof *sc);
    sc->pools = hz_pools_get();
    if (!sc->pools)
        return hz_pools_error(err, "errtime");
    sc->scene_mark = hz_arena_mark(&sc->pools->scene);
    sc->accel_mark = hz_arena_mark(&sc->pools->accel);
    sc->frame_mark = hz_arena_mark(&sc->pools->frame);
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        sc->thread_marks[t] = hz_arena_mark(&sc->pools->thread[t]);
    sc->open = true;
    /* The pool first: the accel build may use it. */
    hz_status_t s = hz_threads_start((int)env->threads, err);
    if (s != HZ_OK) {
        unwind(sc);
        return s;
    }
    sc->threads = (uint32_t)hz_threads_count();
    s = hz_scenefile_open(path, sc->pools, &sc->scene, err);
    if (s != HZ_OK) {
        if (s == HZ_E_IO && strcmp(file, "builtin") != 0 && err) {
            size_t n = strlen(err->msg);
            snprintf(err->msg + n, sizeof err->msg - n, " (bake it with `make scenes`, or give --scenes DIR)");
        }
        unwind(sc);
        return s;
    }
    hz_accel_geom_t g;
    s = hz_accel_geom_from_scene(&g, &sc->scene, &sc->pools->accel, err);
    if (s == HZ_OK)
        s = hz_accel_backend_build(HZ_ACCEL_NATIVE, &sc->accel, &g, &sc->pools->accel, err);
    if (s != HZ_OK) {
        hz_error_prefix(err, path);
        unwind(sc);
        return s;
    }
    uint64_t probe = 0;
    if ((s = fingerprint(sc, &probe, err)) != HZ_OK) {
        hz_error_prefix(err, path);
        unwind(sc);
        return s;
    }
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    snprintf(sc->settings, sizeof sc->settings,
             "hzrt renderer, native accel, max_bounces %u, min_visibility %.9g, probe %016llx", o.max_bounces,
             (double)o.min_visibility, (unsigned long long)probe);
    seq->scene_data = sc;
    seq->scene_hash = fnv1a64(0xcbf29ce484222325ull, sc->scene.header, (size_t)sc->scene.header->file_bytes);
    seq->camera = "baked path from t = 0";
    seq->settings = sc->settings;
    return HZ_OK;
}

hz_status_t hz_et_render_open_blur(const char *file, const hz_et_env_t *env, hz_et_sequence_t *seq, hz_error_t *err)
{
    hz_status_t s = hz_et_render_open(file, env, seq, err);
    if (s != HZ_OK)
        return s;
    size_t n = strlen(g_scene.settings);
    snprintf(g_scene.settings + n, sizeof g_scene.settings - n, ", shutter %.9g",
             (double)shutter_of(&p_mb_ref));
    return HZ_OK;
}

void hz_et_render_close(void)
{
    if (g_scene.open)
        unwind(&g_scene);
}
