/*
 * hz/ladder.h — the quality levels the frame-budget governor (hz/governor.h) chooses from: what a renderer
 * configured by the user can give up, cheapest last.
 *
 * Contract:
 *  - Level 0 is the configuration asked for, unchanged (so a run whose governor never leaves level 0 renders
 *    exactly what it would without one). Each further level is cheaper by a prior estimate (its weight, relative
 *    to level 0): the render scale (3/4, 1/2, 1/3, 1/4, 1/6, 1/8, 1/12, 1/16 of width and height, shown
 *    upscaled; the last two for per-ray costs such as a dense particle cloud that even 1/8 does not absorb),
 *    then the knobs that cost per pixel — mirror bounces (at most 1, then 0), blended surfaces' exact compositing traded for
 *    hybrid:X (X 0.5, then 1: one stochastic decision), adaptive thresholds doubled — and a cheaper mode where one
 *    is (adaptive -> taa -> tdense, full -> tdense).
 *  - A knob the scene does not use (no mirrors, nothing blended) is left alone and makes no level of its own;
 *    levels whose estimate is not lower than the level before are dropped.
 *  - Sizes never go below HZ_LADDER_MIN_SIZE pixels a side. Motion blur is kept at every level (the shutter
 *    cannot change without a new accel); adaptive mode, which has none, keeps none.
 *  - hz_ladder_build fills levels[] and the governor's level count and weights; hz_ladder_reserve says what
 *    hz_render_opts_t.reserve_bytes must be so that hz_render_reconfigure can switch to every level.
 */
#ifndef HZ_LADDER_H
#define HZ_LADDER_H

#include <stddef.h>
#include <stdint.h>

#include "hz/governor.h"
#include "hz/render.h"

#define HZ_LADDER_MIN_SIZE 16u

typedef struct hz_ladder_level {
    hz_render_opts_t opts;
    uint32_t scale_num, scale_den; /* the render scale of width and height */
    char name[80];                 /* "1/2 tdense 320x180, 1 bounce, hybrid:0.5" */
} hz_ladder_level_t;

typedef struct hz_ladder {
    uint32_t count;
    hz_ladder_level_t level[HZ_GOV_MAX_LEVELS];
    hz_gov_cfg_t gov;              /* count and weights; dwell and margins 0 (the governor's defaults) */
} hz_ladder_t;

/* The levels for base (checked options) on scene. HZ_E_INVALID_ARG when base is not valid. */
hz_status_t hz_ladder_build(hz_ladder_t *l, const hz_scene_t *scene, const hz_render_opts_t *base, hz_error_t *err);
/* The largest hz_render_plan region_bytes over the levels (what base.reserve_bytes must hold). */
hz_status_t hz_ladder_reserve(const hz_ladder_t *l, const hz_scene_t *scene, size_t *bytes, hz_error_t *err);

#endif
