/*
 * modeplan.h — the memory plan of every render mode against this board's arenas, for `hzrt info` and the
 * up-front check of `hzrt render`.
 *
 * Contract:
 *  - hz_modeplan_check() plans a render of `scene` with `opts` on `threads` threads (hz_render_plan) and checks
 *    it, and the accel build's peak for the scene's triangles, against the pools as they are now (available
 *    bytes at 64-byte alignment). On a misfit it writes into `why` the arena and both byte counts, in the words
 *    `hzrt info` prints, and returns false. It allocates nothing.
 *  - hz_modeplan_print() prints, for every mode 0..HZ_MODE_COUNT-1 (a mode added to hz_render_mode_t appears
 *    by itself) at width x height: frame bytes, bytes per pixel by part, what the scene leaves out, and the
 *    verdict; then the cost of each optional feature per mode (what a scene without it saves). Returns whether
 *    the default mode (HZ_MODEPLAN_DEFAULT_MODE, `hzrt render`'s default) fits.
 */
#ifndef HZ_PORT_MODEPLAN_H
#define HZ_PORT_MODEPLAN_H

#include <stdbool.h>
#include <stdio.h>

#include "hz/render.h"
#include "pools.h"

#define HZ_MODEPLAN_DEFAULT_MODE HZ_DISPLAY_MODE

bool hz_modeplan_check(const hz_scene_t *scene, hz_pools_t *pools, const hz_render_opts_t *opts, int threads,
                       hz_render_plan_t *plan, char *why, size_t why_size);
bool hz_modeplan_print(FILE *f, const hz_scene_t *scene, hz_pools_t *pools, uint32_t width, uint32_t height);

#endif
