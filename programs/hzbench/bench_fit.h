/*
 * bench_fit.h — `hzbench --check-fit`: do the scenes of the selected groups fit the board's arenas, as each group
 * would use them? Checked from the plans, before anything is built or rendered, so `make test` can run it for
 * every group in seconds (a group whose scene does not fit otherwise stops `make bench` half-way).
 *
 * Contract:
 *  - hz_bench_fit_open(fit, group, label, file, fs) marks the board pools and loads the scene (`file` NULL: the
 *    built-in one; else fit->scenes_dir/file) into the scene arena, for real; a scene that is missing or does not
 *    load is printed and counted as a failure, and the call returns false (nothing to close).
 *  - hz_bench_fit_accel(fs, cfg, time_keys, what) checks the native build's bound (hz_accel_bytes_bound_geom:
 *    the scene's triangles with `time_keys` keys, 0 or 1 static, and cfg, NULL the default) against the accel
 *    arena's free bytes (Embree's builds are not bounded beforehand: its memory monitor refuses past the
 *    arena's free bytes while it builds).
 *  - hz_bench_fit_scenes(fit, group, scenes, count, fn, ctx) opens each scene {label, file} of a group's list
 *    in turn and calls fn(fs, ctx) between open and close; hz_bench_fit_named does the same for scene names
 *    (file NAME.hzb).
 *  - hz_bench_fit_line(fs, what, arena, need, have) prints and counts one check; hz_bench_fit_fail(fs, what,
 *    why) one that could not be made (a scene that does not load, a configuration without a plan), as failed.
 *  - hz_bench_fit_render(fs, ro, n, what) checks that the n renderers `ro` (alive at once, as the group
 *    creates them) fit: their plans' frame bytes summed against the frame arena, their thread bytes summed
 *    against one thread arena, and the pose keys of a shutter (the largest plan's keys_bytes) against the scene
 *    arena. Returns the plans' largest time_keys, for hz_bench_fit_accel.
 *  - hz_bench_fit_close(fs) gives the pools back as open found them.
 *  - Every check prints one line: group, scene, what, the bytes it needs and has, and "fits" or "DOES NOT FIT";
 *    fit->checked and fit->failed count them.
 */
#ifndef HZ_BENCH_FIT_H
#define HZ_BENCH_FIT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "bench_scene.h"
#include "hz/render.h"

typedef struct hz_bench_fit {
    const char *scenes_dir;
    int checked, failed;
} hz_bench_fit_t;

typedef struct hz_bench_fit_scene {
    hz_bench_fit_t *fit;
    const char *group, *label;
    hz_bench_scene_t bs;
} hz_bench_fit_scene_t;

bool hz_bench_fit_open(hz_bench_fit_t *fit, const char *group, const char *label, const char *file,
                       hz_bench_fit_scene_t *fs);
void hz_bench_fit_accel(hz_bench_fit_scene_t *fs, const hz_accel_config_t *cfg, uint32_t time_keys, const char *what);
typedef void (*hz_bench_fit_fn)(hz_bench_fit_scene_t *fs, const void *ctx);

void hz_bench_fit_scenes(hz_bench_fit_t *fit, const char *group, const char *const (*scenes)[2], size_t count,
                         hz_bench_fit_fn fn, const void *ctx);
void hz_bench_fit_named(hz_bench_fit_t *fit, const char *group, const char *const *names, int count,
                        hz_bench_fit_fn fn, const void *ctx);
void hz_bench_fit_line(hz_bench_fit_scene_t *fs, const char *what, const char *arena, size_t need, size_t have);
void hz_bench_fit_fail(hz_bench_fit_scene_t *fs, const char *what, const char *why);
uint32_t hz_bench_fit_render(hz_bench_fit_scene_t *fs, const hz_render_opts_t *ro, int n, const char *what);
void hz_bench_fit_close(hz_bench_fit_scene_t *fs);

#endif
