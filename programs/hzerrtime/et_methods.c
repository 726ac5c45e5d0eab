/* errtime's scene and method tables (see et_methods.h). */
#include "et_methods.h"

#include <stdio.h>
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
      &hz_et_render_reference, w, h, frames, warmup, 0, 0 }
/* tdense and its baselines shown on a 240 Hz display. */
#define AT240(name, about, file, w, h, frames, warmup)                                                          \
    { name, about, file, render_open, hz_et_render_close, hz_et_display_methods, HZ_ET_DISPLAY_METHOD_COUNT,   \
      &hz_et_display_reference, w, h, frames, warmup, 240, 0 }

/* Transparency (seed 004): every --transparency method with TAA, plus the still-view stability figure. */
#define TRANSP(name, about, file, w, h, frames, warmup)                                                         \
    { name, about, file, render_open, hz_et_render_close, hz_et_transp_methods, HZ_ET_TRANSP_METHOD_COUNT,     \
      &hz_et_render_reference, w, h, frames, warmup, 0, 16 }
#define TRANSP240(name, about, file, w, h, frames, warmup)                                                      \
    { name, about, file, render_open, hz_et_render_close, hz_et_transp_display_methods,                        \
      HZ_ET_TRANSP_DISPLAY_METHOD_COUNT, &hz_et_display_reference, w, h, frames, warmup, 240, 0 }

/* Motion blur (seed 002) on a 30 Hz display: msbvh, interp, rigid instances and Embree at equal time budget. */
#define BLURRED(name, about, file, w, h, frames, warmup)                                                        \
    { name, about, file, blur_open, hz_et_render_close, hz_et_blur_methods, HZ_ET_BLUR_METHOD_COUNT,            \
      &hz_et_blur_reference, w, h, frames, warmup, 30, 0 }

/* The standard set (`make report`): sizes and lengths keep a cold run (256-spp references included) within
 * ~15 minutes on 2 cores; see README "Error against run time". */
const hz_et_scene_t hz_et_scenes[] = {
    RENDERED("CornellBox-Mirror", "Cornell box with a mirror box (CornellBox-Mirror.hzb), camera swinging",
             "CornellBox-Mirror.hzb", 192, 108, 56, 16),
    RENDERED("sponza", "Crytek Sponza (sponza.hzb), textured atrium, camera flying through",
             "sponza.hzb", 160, 90, 48, 16),
    RENDERED("lost-empire", "Lost Empire (lost-empire.hzb), Minecraft world with alpha cutouts, camera orbit",
             "lost-empire.hzb", 160, 90, 48, 16),
    RENDERED("conference", "Conference room (conference.hzb), camera flying through (seed 003's Table 2 scene)",
             "conference.hzb", 160, 90, 48, 16),
    RENDERED("builtin", "hzrt's built-in scene: motion, skinning, instancing, blended and cut-out surfaces, mirror",
             "builtin", 160, 90, 40, 16),
    AT240("builtin@240", "built-in scene on a 240 Hz display: tdense vs 1 spp and TAA at 60 and 240 Hz", "builtin",
          160, 90, 48, 16),
    AT240("sponza@240", "Sponza on a 240 Hz display: tdense vs 1 spp and TAA at 60 and 240 Hz", "sponza.hzb", 160, 90,
          48, 16),
    AT240("conference@240", "Conference on a 240 Hz display: tdense vs 1 spp and TAA at 60 and 240 Hz",
          "conference.hzb", 160, 90, 48, 16),
    TRANSP("sponza-smoke", "Sponza with a 12000-particle smoke cloud (sponza-smoke.hzb), camera flying into it: "
           "transparency methods + TAA", "sponza-smoke.hzb", 64, 36, 16, 12),
    TRANSP("AlphaBlendModeTest", "glTF AlphaBlendModeTest (AlphaBlendModeTest.hzb): transparency methods + TAA",
           "AlphaBlendModeTest.hzb", 160, 90, 40, 16),
    TRANSP("builtin-transp", "built-in scene (blended particles): transparency methods + TAA", "builtin", 160, 90, 40,
           16),
    TRANSP("crossing", "blended panes and confetti moving through each other (crossing.hzb): transparency methods + "
           "TAA", "crossing.hzb", 160, 90, 40, 16),
    TRANSP240("sponza-smoke@240", "smoke on a 240 Hz display: std and exact under tdense vs + TAA at 60 Hz",
              "sponza-smoke.hzb", 64, 36, 32, 16),
    TRANSP240("AlphaBlendModeTest@240", "AlphaBlendModeTest on a 240 Hz display: std and exact under tdense vs "
              "+ TAA at 60 Hz", "AlphaBlendModeTest.hzb", 160, 90, 48, 16),
    BLURRED("builtin-blur", "built-in scene, motion blur (shutter 1 at 30 Hz): msbvh vs interp vs Embree", "builtin",
            160, 90, 24, 8),
    BLURRED("sponza-rotated-blur", "Rotated Sponza (sponza-rotated.hzb), motion blur (shutter 1 at 30 Hz)",
            "sponza-rotated.hzb", 160, 90, 24, 8),
    { "synthetic", "built-in analytic animation (rotating checkerboard, sweeping disc); needs no renderer", NULL,
      synthetic_open, NULL, hz_synth_methods, HZ_SYNTH_METHOD_COUNT, &hz_synth_reference, 0, 0, 0, 0, 0, 0 },
};
const size_t hz_et_scene_count = sizeof hz_et_scenes / sizeof hz_et_scenes[0];

bool hz_et_scene_is_file(const char *item, size_t len)
{
    return len > 4 && !strncmp(item + len - 4, ".hzb", 4);
}

void hz_et_scene_from_file(const char *path, char *name, size_t size, hz_et_scene_t *out)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t n = strlen(base) - (hz_et_scene_is_file(base, strlen(base)) ? 4 : 0);
    snprintf(name, size, "%.*s", (int)n, base);
    const hz_et_scene_t e = RENDERED(name, "a baked scene file given on the command line", path, 0, 0, 0, 0);
    *out = e;
}

const hz_et_scene_t *hz_et_scene_find(const char *name)
{
    for (size_t i = 0; i < hz_et_scene_count; i++)
        if (!strcmp(hz_et_scenes[i].name, name))
            return &hz_et_scenes[i];
    return NULL;
}
