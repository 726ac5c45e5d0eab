/*
 * bench_motion.h — the motion-blur part of `make bench` (hzbench --only motion): the native motion BVHs (seed
 * 002: MSBVH, interpolated BVH, swept BVH) against Embree's motion blur, side by side in one run.
 *
 * For each scene (default hairball, sponza-rotated, furball-sway and tentacles: the moving hairball, Rotated Sponza,
 * the swaying furball and a deforming skinned character, baked .hzb with their own animation, posed at K keys over `interval` seconds around t = 1 s; a scene that does not move gets
 * procedural keys, said in the output) it builds every BVH (the MSBVH once per split budget, the largest,
 * HZ_ACCEL_SPLIT_BUDGET_MAX, standing for "unbounded" when its budget_stops is 0; build_ms: median over rounds,
 * one thread; a BVH whose memory bound does not fit the accel arena is skipped and said so; every native BVH
 * with leaves of at most leaf_max triangles when it is set, as the table's first line then says), refits it
 * (refit_ms, the same keys re-read), and renders two frames of width x height pixels, the paper's Table 1 way:
 * one primary ray per pixel from the scene's camera at the pixel's time (a hash of the pixel) and one secondary
 * ray from its hit at the same time: a shadow ray to the scene's first light, or an ambient-occlusion ray
 * (cosine-distributed about the facing normal, a tenth of the scene's bounding-box diagonal long), in 8-ray
 * packets (render_ms: thread CPU time, median of rounds, interleaved between BVHs). Per ray (HZ_FEATURE_STATS)
 * it counts the triangles intersected and the wide nodes traversed (max and average over both rays of a pixel).
 * Every BVH must return the same hits as the first MSBVH (native ones bit for bit: checked, a difference fails
 * the run). Rows go to csv_path with exactly the columns scene, bvh, refs, nodes, spatial_splits, sah,
 * isect_max, isect_avg, trav_max, trav_avg, render_ms, build_ms, refit_ms, bytes_per_tri, mrays_per_s,
 * secondary (shadow or ao), split_budget, budget_stops (Embree's row leaves what Embree does not report empty).
 * Then, for a scene with its own animation and at most a million triangles, the seed's Fig. 5: the MSBVH's SAH
 * cost over 12 frames at 24 Hz, refitted every frame against built anew, printed and written beside csv_path
 * (X.csv -> X-sah.csv: scene, frame, time_s, sah_refit, sah_rebuilt).
 * Then, on sweep_scene (default the hairball when it is one of the scenes), leaf sizes: with leaves of at most 2,
 * 4 and the default number of triangles (seed 002's trees held about 3.8), the MSBVH at budget 1 and at the
 * largest budget (one row where that is 1 or less) and the interpolated BVH, built together per leaf size and
 * rendered interleaved (hits checked against the first BVH's, bit for bit), printed and written beside csv_path
 * (X.csv -> X-leaf.csv: scene, leaf_max, bvh, split_budget, secondary, refs, nodes, bytes_per_tri, isect_avg,
 * isect_max, isect_avg_pct_interp, trav_avg, render_ms, render_vs_interp; the last two against the interpolated
 * BVH with the same leaves).
 * Last, the motion-size sweep on sweep_scene: its shutter
 * interval scaled by 1/8 .. 8 (capped at 10 s; K follows the interval), per interval the motion over triangle size
 * (per triangle its vertices' longest path over the keys over its mean edge length at the middle key; median and
 * mean) and, for the MSBVH at the largest budget, the interpolated and the swept BVH (built, refitted, one untimed
 * frame of each secondary kind with statistics), printed and written beside csv_path (X.csv -> X-sweep.csv: scene,
 * interval_s, keys, motion_over_size_median, motion_over_size_mean, bvh, secondary, isect_avg, isect_max,
 * isect_avg_pct_interp, sah, refs). Boards without HZ_FEATURE_STATS and scenes without an animation say so and
 * sweep nothing. Every scene, the sweep's included, is checked to exist before anything is measured.
 */
#ifndef HZ_BENCH_MOTION_H
#define HZ_BENCH_MOTION_H

#include <stdbool.h>
#include <stdint.h>

#define HZ_BENCH_MOTION_MAX_SCENES 8
#define HZ_BENCH_MOTION_MAX_BUDGETS 6

typedef struct hz_bench_motion_opts {
    const char *scenes_dir; /* default $HZ_SCENES_DIR, else build/scenes */
    const char *scenes[HZ_BENCH_MOTION_MAX_SCENES];
    int scene_count;        /* 0: hairball, sponza-rotated, furball-sway, tentacles */
    int rounds;             /* default 3 */
    uint32_t width, height; /* default 512 x 512 */
    float interval;         /* shutter interval, seconds (default 1/24: a film frame, shutter fully open) */
    float budgets[HZ_BENCH_MOTION_MAX_BUDGETS]; /* the MSBVH's split budgets, one row each */
    int budget_count;       /* 0: 0.25, 0.5, 1 and HZ_ACCEL_SPLIT_BUDGET_MAX */
    uint32_t leaf_max;      /* triangles per leaf of every native BVH, 1..HZ_BVH_WIDTH; 0: the accel's default */
    const char *csv_path;   /* NULL: no CSV */
    const char *sweep_scene; /* the motion-size sweep's scene; NULL: hairball when it is measured; "none": no sweep */
} hz_bench_motion_opts_t;

/* *swept: the leaf-size and sweep CSVs were written (csv_path set, a sweep scene, the run succeeded). */
int hz_bench_motion(const hz_bench_motion_opts_t *opts, bool *swept);

/* --check-fit: each scene's pose keys and its three native motion BVHs against the board's arenas (bench_fit.h). */
struct hz_bench_fit;
void hz_bench_motion_fit(const hz_bench_motion_opts_t *opts, struct hz_bench_fit *fit);

#endif
