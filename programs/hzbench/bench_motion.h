/*
 * bench_motion.h — the motion-blur part of `make bench` (hzbench --only motion): the native motion BVHs (seed
 * 002: MSBVH, interpolated BVH, swept BVH) against Embree's motion blur, side by side in one run.
 *
 * For each scene (default furball-sway and sponza-rotated, hz-12b's moving hairball and Rotated Sponza: baked
 * .hzb with their own animation, posed at K keys over `interval` seconds around t = 1 s; a scene that does not
 * move gets procedural keys, said in the output) it builds every BVH (build_ms: median over rounds, one thread),
 * refits it (refit_ms, the same keys re-read), renders "a frame" of width x height pixels: one primary ray per
 * pixel from the scene's camera at the pixel's time (a hash of the pixel, one time per pixel) and one shadow ray
 * from its hit to the scene's first light at the same time, in 8-ray packets (render_ms: thread CPU time, median
 * of rounds, interleaved between BVHs), and counts per ray (HZ_FEATURE_STATS) the triangles intersected and the
 * wide nodes traversed (max and average over both kinds of rays). Every BVH must return the same hits as the
 * MSBVH (native ones bit for bit: checked, a difference fails the run). Rows go to csv_path with exactly the
 * columns scene, bvh, refs, nodes, spatial_splits, sah, isect_max, isect_avg, trav_max, trav_avg, render_ms,
 * build_ms, refit_ms, bytes_per_tri, mrays_per_s (Embree's row leaves what Embree does not report empty).
 */
#ifndef HZ_BENCH_MOTION_H
#define HZ_BENCH_MOTION_H

#include <stdint.h>

#define HZ_BENCH_MOTION_MAX_SCENES 8

typedef struct hz_bench_motion_opts {
    const char *scenes_dir; /* default $HZ_SCENES_DIR, else build/scenes */
    const char *scenes[HZ_BENCH_MOTION_MAX_SCENES];
    int scene_count;        /* 0: furball-sway, sponza-rotated */
    int rounds;             /* default 3 */
    uint32_t width, height; /* default 512 x 512 */
    float interval;         /* shutter interval, seconds (default 1/24: a film frame, shutter fully open) */
    uint32_t max_keys;      /* cap on K for scenes over 1M triangles (memory; default 2) */
    const char *csv_path;   /* NULL: no CSV */
} hz_bench_motion_opts_t;

int hz_bench_motion(const hz_bench_motion_opts_t *opts);

/* --check-fit: each scene's pose keys and its three native motion BVHs against the board's arenas (bench_fit.h). */
struct hz_bench_fit;
void hz_bench_motion_fit(const hz_bench_motion_opts_t *opts, struct hz_bench_fit *fit);

#endif
