/* errtime's scene and method tables (see et_methods.h). */
#include "et_methods.h"

#include "et_render.h"
#include "et_synthetic.h"

static hz_status_t synthetic_open(hz_et_sequence_t *seq, hz_arena_t *arena, hz_error_t *err)
{
    (void)arena;
    (void)err;
    seq->scene_data = NULL;
    seq->scene_hash = 1; /* the scene is code: bump when hz_synth_shade changes */
    seq->camera = "fixed";
    seq->settings = "analytic";
    return HZ_OK;
}

static hz_status_t builtin_open(hz_et_sequence_t *seq, hz_arena_t *arena, hz_error_t *err)
{
    (void)arena;
    return hz_et_render_open(seq, NULL, 1.0f, err);
}

static hz_status_t sponza_open(hz_et_sequence_t *seq, hz_arena_t *arena, hz_error_t *err)
{
    (void)arena;
    return hz_et_render_open(seq, "sponza.hzb", 2.0f, err);
}

static hz_status_t conference_open(hz_et_sequence_t *seq, hz_arena_t *arena, hz_error_t *err)
{
    (void)arena;
    return hz_et_render_open(seq, "conference.hzb", 2.0f, err);
}

const hz_et_scene_t hz_et_scenes[] = {
    { "synthetic", "built-in analytic animation (rotating checkerboard, sweeping disc); needs no renderer",
      synthetic_open, hz_synth_methods, HZ_SYNTH_METHOD_COUNT, &hz_synth_reference, 0, 0, 0 },
    { "builtin", "the built-in scene (camera path, moving objects, mirror, transparency) from t = 1 s: tdense and "
      "its baselines", builtin_open, hz_et_render_methods, HZ_ET_RENDER_METHOD_COUNT, &hz_et_render_reference,
      256, 144, 48 },
    { "sponza", "sponza.hzb from $HZ_SCENES_DIR (make scenes), camera path from t = 2 s: tdense and its baselines",
      sponza_open, hz_et_render_methods, HZ_ET_RENDER_METHOD_COUNT, &hz_et_render_reference, 256, 144, 48 },
    { "conference", "conference.hzb from $HZ_SCENES_DIR (make scenes), camera path from t = 2 s: tdense and its "
      "baselines", conference_open, hz_et_render_methods, HZ_ET_RENDER_METHOD_COUNT, &hz_et_render_reference,
      256, 144, 48 },
};
const size_t hz_et_scene_count = sizeof hz_et_scenes / sizeof hz_et_scenes[0];
