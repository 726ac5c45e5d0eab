/*
 * bench_accel.h — the accel part of `make bench` (hzbench): native against Embree on the shared scenes.
 *
 * For each scene (baked .hzb from `make scenes`) it builds both backends (build time, bytes per triangle),
 * makes three ray sets from the scene's camera at width x height (default 1024 x 1024) — primary (coherent,
 * 4x2-pixel packets), shadow rays from the primary hits to one light (the scene's first light, else the
 * documented default: the bounds' centre raised to 90% of their height), diffuse-bounce rays (cosine-weighted
 * about the hit's normal, incoherent) — and measures Mrays/s of every method on every set, with one thread and
 * with all of the pool's threads, interleaved round by round; figures are medians. Methods: native scalar
 * (single rays), native SIMD single ray, native SIMD packets (HZ_ACCEL_KERNEL_AUTO: the frustum packet for
 * coherent sets, single rays for incoherent ones), the two other packet forms for the incoherent study (frustum
 * and masked), Embree rtcIntersect1/rtcOccluded1 and rtcIntersect8/rtcOccluded8. The headline is the ratio of
 * the best native SIMD figure to the best Embree figure of the same set and thread count.
 * Single-thread figures use the thread's CPU time (robust against a shared machine), all-thread figures wall
 * time. Every native method must agree on the hits (checked: a mismatch is printed and fails the run).
 */
#ifndef HZ_BENCH_ACCEL_H
#define HZ_BENCH_ACCEL_H

#include <stdint.h>

#define HZ_BENCH_MAX_SCENES 16

typedef struct hz_bench_accel_opts {
    const char *scenes_dir;   /* default $HZ_SCENES_DIR, else build/scenes */
    const char *scenes[HZ_BENCH_MAX_SCENES];
    int scene_count;          /* 0: the list */
    int rounds;               /* default 5 */
    int threads;              /* 0: one per online CPU */
    uint32_t width, height;   /* primary rays; default 1024 x 1024 */
    const char *embree_config;/* Embree device config; default "" (Embree's choice) */
    const char *csv_path;     /* NULL: no CSV */
} hz_bench_accel_opts_t;

/* Runs the accel benchmark; returns a process exit status (0, or the failure's). */
int hz_bench_accel(const hz_bench_accel_opts_t *opts);

/* --check-fit: each scene and its native build against the board's arenas (bench_fit.h). */
struct hz_bench_fit;
void hz_bench_accel_fit(const hz_bench_accel_opts_t *opts, struct hz_bench_fit *fit);

#endif
