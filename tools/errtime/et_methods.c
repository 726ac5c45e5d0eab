/* errtime's scene and method tables (see et_methods.h). */
#include "et_methods.h"

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

const hz_et_scene_t hz_et_scenes[] = {
    { "synthetic", "built-in analytic animation (rotating checkerboard, sweeping disc); needs no renderer",
      synthetic_open, hz_synth_methods, HZ_SYNTH_METHOD_COUNT, &hz_synth_reference, 0, 0, 0 },
};
const size_t hz_et_scene_count = sizeof hz_et_scenes / sizeof hz_et_scenes[0];
