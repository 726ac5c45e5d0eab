/* errtime's renderer scenes and methods (see et_render.h). */
#include "et_render.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accel_backend.h"
#include "hz/render.h"
#include "pools.h"
#include "scenefile.h"
#include "threads.h"

/* What a scene entry opened: shared by all its methods. One at a time: opening the next scene of a
 * multi-scene run releases the previous one (pools back to where the first open found them). */
typedef struct et_scene {
    hz_scene_t scene;
    hz_accel_t *accel;
    float start;  /* scene time of frame 0 */
} et_scene_t;

static et_scene_t opened;
static bool have_marks, threads_started;
static hz_arena_mark_t scene_mark, accel_mark;

typedef struct et_params {
    hz_render_mode_t mode;
    uint32_t spp;
} et_params_t;

typedef struct et_state {
    hz_renderer_t *r;
    const hz_et_sequence_t *seq;
    uint64_t rendered; /* frames this renderer drew (its own frame index: TAA's jitter phase, tdense's subframe) */
    hz_arena_mark_t thread_marks[HZ_MAX_THREADS];
} et_state_t;

typedef struct job {
    hz_renderer_t *r;
    uint32_t pass;
} job_t;

static void run_item(void *user, uint32_t item, int thread)
{
    job_t *j = user;
    hz_render_pass_run(j->r, j->pass, item, (uint32_t)thread);
}

static hz_status_t et_begin(const hz_et_method_t *m, const hz_et_sequence_t *seq, hz_arena_t *arena, void **state,
                            hz_error_t *err)
{
    const et_params_t *p = m->params;
    const et_scene_t *sc = seq->scene_data;
    hz_pools_t *pools = hz_pools_get();
    et_state_t *st = hz_arena_alloc(arena, sizeof *st, 16);
    if (!st)
        return hz_arena_error(arena, err);
    memset(st, 0, sizeof *st);
    st->seq = seq;
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        st->thread_marks[t] = hz_arena_mark(&pools->thread[t]);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = seq->width, o.height = seq->height, o.mode = p->mode, o.spp = p->spp;
    /* The renderer's images live in errtime's arena (released after the method); its per-thread queues in the
     * board's thread arenas (released in et_end). */
    hz_status_t s = hz_render_create(&st->r, (hz_scene_t *)&sc->scene, sc->accel, &o, arena, pools->thread,
                                     (uint32_t)hz_threads_count(), err);
    *state = st;
    return s;
}

static hz_status_t et_render(void *state, uint32_t frame, hz_image_t *out, uint64_t *rays, hz_error_t *err)
{
    et_state_t *st = state;
    const et_scene_t *sc = st->seq->scene_data;
    float t = sc->start + (float)frame / (float)st->seq->refresh_hz;
    hz_status_t s = hz_render_begin_frame(st->r, st->rendered++, t, err);
    if (s != HZ_OK)
        return s;
    for (uint32_t p = 0; p < hz_render_pass_count(st->r); p++) {
        job_t j = { st->r, p };
        hz_threads_run(run_item, &j, hz_render_pass_items(st->r, p));
    }
    hz_render_end_frame(st->r);
    hz_render_stats_t last;
    hz_render_frame_stats(st->r, &last, NULL);
    *rays = last.primary_rays + last.shadow_rays + last.secondary_rays;
    return hz_image_copy(out, hz_render_output(st->r), err);
}

static void et_end(void *state)
{
    et_state_t *st = state;
    hz_pools_t *pools = hz_pools_get();
    for (int t = 0; t < HZ_MAX_THREADS; t++)
        hz_arena_reset(&pools->thread[t], st->thread_marks[t]);
}

static const et_params_t ref_params = { HZ_MODE_FULL, 64 };
static const et_params_t full1 = { HZ_MODE_FULL, 1 }, taa = { HZ_MODE_TAA, 1 }, tdense = { HZ_MODE_TDENSE, 1 };

const hz_et_method_t hz_et_render_reference = { "full", "spp", 64, et_begin, et_render, et_end, &ref_params, 0 };

const hz_et_method_t hz_et_render_methods[HZ_ET_RENDER_METHOD_COUNT] = {
    { "tdense", "hz", 240, et_begin, et_render, et_end, &tdense, 0 },
    { "full-1spp", "hz", 60, et_begin, et_render, et_end, &full1, 4 },
    { "full-1spp", "hz", 240, et_begin, et_render, et_end, &full1, 0 },
    { "taa", "hz", 60, et_begin, et_render, et_end, &taa, 4 },
    { "taa", "hz", 240, et_begin, et_render, et_end, &taa, 0 },
};

/* FNV-1a 64 of the header and the section table: the table holds every section's CRC-32, so this keys the
 * whole file's content. */
static uint64_t scene_hash(const hz_scene_t *s)
{
    const uint8_t *b = (const uint8_t *)s->header;
    size_t n = 256 + (size_t)s->header->section_count * 32;
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}

hz_status_t hz_et_render_open(hz_et_sequence_t *seq, const char *file, float start, hz_error_t *err)
{
    char path[4096];
    if (file) {
        const char *dir = getenv("HZ_SCENES_DIR");
        snprintf(path, sizeof path, "%s/%s", dir && *dir ? dir : "build/scenes", file);
    } else {
        snprintf(path, sizeof path, "builtin");
    }
    hz_pools_t *pools = hz_pools_get();
    if (!pools)
        return hz_error_set(err, HZ_E_INTERNAL, "errtime: no board pools");
    if (!have_marks) {
        scene_mark = hz_arena_mark(&pools->scene);
        accel_mark = hz_arena_mark(&pools->accel);
        have_marks = true;
    } else {
        hz_accel_release(opened.accel);
        memset(&opened, 0, sizeof opened);
        hz_arena_reset(&pools->accel, accel_mark);
        hz_arena_reset(&pools->scene, scene_mark);
    }
    hz_status_t s = hz_scenefile_open(path, pools, &opened.scene, err);
    if (s != HZ_OK)
        return s;
    hz_accel_geom_t g;
    if ((s = hz_render_accel_geom(&opened.scene, &pools->accel, &g, err)) != HZ_OK ||
        (s = hz_accel_backend_build(HZ_ACCEL_NATIVE, &opened.accel, &g, &pools->accel, err)) != HZ_OK)
        return s;
    if (!threads_started && (s = hz_threads_start(0, err)) != HZ_OK)
        return s;
    threads_started = true;
    opened.start = start;
    seq->scene_data = &opened;
    seq->scene_hash = scene_hash(&opened.scene);
    seq->camera = "path";
    seq->settings = "renderer v1, native accel, 3 bounces";
    return HZ_OK;
}
