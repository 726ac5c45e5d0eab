/*
 * bench_util.h — what hzbench's scene groups share: medians of rounds, the scene loop and the thread default.
 *
 * Contract:
 *  - hz_bench_median(v, n) sorts v[0..n) in place (n > 0) and returns its median (the mean of the middle two
 *    for even n).
 *  - hz_bench_quantile(v, n, q) sorts v[0..n) in place (n > 0) and returns its q-quantile by nearest rank.
 *  - hz_bench_scenes(group, scenes, count, dir, threads, fn, ctx, max_rows, err) starts the thread pool with
 *    `threads`, then for each scene {label, file} (file NULL: the built-in scene; else dir/file, skipped with a
 *    printed line naming `group` when unreadable) calls fn(label, path, ctx, row, err) with row = the rows done
 *    so far, until max_rows; stops the pool. Returns the rows done, or -1 with err (prefixed with the label)
 *    when fn fails.
 *  - hz_bench_threads(n) is n, or for n == 0 the online CPUs capped at HZ_MAX_THREADS.
 *  - hz_bench_scene_list(dir, scenes, count, defaults, n): a NULL *dir becomes $HZ_SCENES_DIR or build/scenes;
 *    an empty list (*count == 0) becomes the n defaults.
 *  - hz_bench_open_named(dir, name, pools, scene, geom) re-initialises the pools, opens dir/name.hzb into them
 *    and makes its accel geometry view (in the scene arena); 0, or after printing the error (a missing scene
 *    names `make scenes`) the exit status to return.
 *  - hz_bench_scene_present(dir, name, label): whether dir/name.hzb is readable; if not, prints "bench: <label>scene
 *    'name' is missing: path: reason" (label "" or e.g. "--motion-sweep: "), so a group can name every missing
 *    scene before it measures anything.
 *  - hz_bench_csv_beside(csv, suffix, buf, size): the path of a table beside csv: X.csv (or X) -> X-suffix.csv.
 */
#ifndef HZ_BENCH_UTIL_H
#define HZ_BENCH_UTIL_H

#include <stdbool.h>
#include <stddef.h>

#include "hz/accel.h"
#include "hz/scene.h"
#include "hz/status.h"
#include "pools.h"

typedef hz_status_t (*hz_bench_scene_fn)(const char *label, const char *path, void *ctx, int row, hz_error_t *err);

double hz_bench_median(double *v, int n);
double hz_bench_quantile(double *v, size_t n, double q);
int hz_bench_scenes(const char *group, const char *const (*scenes)[2], size_t count, const char *dir, int threads,
                    hz_bench_scene_fn fn, void *ctx, int max_rows, hz_error_t *err);
int hz_bench_threads(int n);
void hz_bench_scene_list(const char **dir, const char **scenes, int *count, const char *const *defaults, int n);
int hz_bench_open_named(const char *dir, const char *name, hz_pools_t *pools, hz_scene_t *scene,
                        hz_accel_geom_t *geom);
bool hz_bench_scene_present(const char *dir, const char *name, const char *label);
void hz_bench_csv_beside(const char *csv, const char *suffix, char *buf, size_t size);

#endif
