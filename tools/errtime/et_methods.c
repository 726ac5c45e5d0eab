/* errtime's scene and method tables (see et_methods.h). */
#include "et_methods.h"

#include <string.h>

#include "et_synthetic.h"

static hz_status_t synthetic_open(const hz_et_scene_t *scene, const hz_et_env_t *env, hz_et_sequence_t *seq,
                                  hz_arena_t *arena, hz_error_t *err)
{
    (void)scene;
    (void)env;
    (void)arena;
    (void)err;
    seq->scene_data = NULL;
    seq->scene_hash = 1; /* the scene is code: bump when hz_synth_shade changes */
    seq->camera = "fixed";
    seq->settings = "analytic";
    return HZ_OK;
}

static hz_status_t render_open(const hz_et_scene_t *scene, const hz_et_env_t *env, hz_et_sequence_t *seq,
                               hz_arena_t *arena, hz_error_t *err)
{
    (void)arena;
    return hz_et_render_open(scene->file, env, seq, err);
}

static hz_status_t blur_open(const hz_et_scene_t *scene, const hz_et_env_t *env, hz_et_sequence_t *seq,
                             hz_arena_t *arena, hz_error_t *err)
{
    (void)arena;
    return hz_et_render_open_blur(scene->file, env, seq, err);
}

#define RENDERED(name, about, file, w, h, frames, warmup)                                                       \
    { name, about, file, render_open, hz_et_render_close, hz_et_render_methods, HZ_ET_RENDER_METHOD_COUNT,     \
      &hz_et_render_reference, w, h, frames, warmup, 0 }
/* tdense and its baselines shown on a 240 Hz display. */
#define AT240(name, about, file, w, h, frames, warmup)                                                          \
    { name, about, file, render_open, hz_et_render_close, hz_et_display_methods, HZ_ET_DISPLAY_METHOD_COUNT,   \
      &hz_et_display_reference, w, h, frames, warmup, 240 }

/* Motion blur (seed 002) on a 30 Hz display: msbvh, interp and Embree at equal time budget. */
#define BLURRED(name, about, file, w, h, frames, warmup)                                                        \
    { name, about, file, blur_open, hz_et_render_close, hz_et_blur_methods, HZ_ET_BLUR_METHOD_COUNT,            \
      &hz_et_blur_reference, w, h, frames, warmup, 30 }

/* The standard set (`make report`): sizes and lengths keep a cold run (256-spp references included) within
 * ~15 minutes on 2 cores; see README "Error against run time". */
const hz_et_scene_t hz_et_scenes[] = {
    RENDERED("CornellBox-Mirror", "Cornell box with a mirror box (CornellBox-Mirror.hzb), camera swinging",
             "CornellBox-Mirror.hzb", 192, 108, 56, 16),
    RENDERED("sponza", "Crytek Sponza (sponza.hzb), textured atrium, camera flying through",
             "sponza.hzb", 160, 90, 48, 16),
    RENDERED("lost-empire", "Lost Empire (lost-empire.hzb), Minecraft world with alpha cutouts, camera orbit",
             "lost-empire.hzb", 160, 90, 48, 16),
    RENDERED("builtin", "hzrt's built-in scene: motion, skinning, instancing, blended and cut-out surfaces, mirror",
             "builtin", 160, 90, 40, 16),
    AT240("builtin@240", "built-in scene on a 240 Hz display: tdense vs 1 spp and TAA at 60 and 240 Hz", "builtin",
          160, 90, 48, 16),
    AT240("sponza@240", "Sponza on a 240 Hz display: tdense vs 1 spp and TAA at 60 and 240 Hz", "sponza.hzb", 160, 90,
          48, 16),
    AT240("conference@240", "Conference on a 240 Hz display: tdense vs 1 spp and TAA at 60 and 240 Hz",
          "conference.hzb", 160, 90, 48, 16),
    BLURRED("builtin-blur", "built-in scene, motion blur (shutter 1 at 30 Hz): msbvh vs interp vs Embree", "builtin",
            160, 90, 24, 8),
    BLURRED("sponza-rotated-blur", "Rotated Sponza (sponza-rotated.hzb), motion blur (shutter 1 at 30 Hz)",
            "sponza-rotated.hzb", 160, 90, 24, 8),
    { "synthetic", "built-in analytic animation (rotating checkerboard, sweeping disc); needs no renderer", NULL,
      synthetic_open, NULL, hz_synth_methods, HZ_SYNTH_METHOD_COUNT, &hz_synth_reference, 0, 0, 0, 0, 0 },
};
const size_t hz_et_scene_count = sizeof hz_et_scenes / sizeof hz_et_scenes[0];

const hz_et_scene_t *hz_et_scene_find(const char *name)
{
    for (size_t i = 0; i < hz_et_scene_count; i++)
        if (!strcmp(hz_et_scenes[i].name, name))
            return &hz_et_scenes[i];
    return NULL;
}
