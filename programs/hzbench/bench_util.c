/* Shared by hzbench's scene groups (see bench_util.h). */
#include "bench_util.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "hz/config.h"
#include "scenefile.h"
#include "threads.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

double hz_bench_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double hz_bench_quantile(double *v, size_t n, double q)
{
    qsort(v, n, sizeof *v, cmp_double);
    size_t k = (size_t)ceil(q * (double)n);
    return v[k > 0 ? k - 1 : 0];
}

int hz_bench_scenes(const char *group, const char *const (*scenes)[2], size_t count, const char *dir, int threads,
                    hz_bench_scene_fn fn, void *ctx, int max_rows, hz_error_t *err)
{
    int n = 0;
    if (hz_threads_start(threads, err) != HZ_OK)
        return -1;
    for (size_t i = 0; i < count && n < max_rows; i++) {
        char path[4096];
        if (scenes[i][1]) {
            snprintf(path, sizeof path, "%s/%s", dir ? dir : ".", scenes[i][1]);
            if (access(path, R_OK) != 0) {
                printf("%-8s %-14s skipped: %s missing (make scenes)\n", group, scenes[i][0], path);
                continue;
            }
        } else {
            snprintf(path, sizeof path, "builtin");
        }
        if (fn(scenes[i][0], path, ctx, n, err) != HZ_OK) {
            hz_error_prefix(err, scenes[i][0]);
            hz_threads_stop();
            return -1;
        }
        n++;
    }
    hz_threads_stop();
    return n;
}

int hz_bench_threads(int n)
{
    if (n != 0)
        return n;
    long c = sysconf(_SC_NPROCESSORS_ONLN);
    return c < 1 ? 1 : c > HZ_MAX_THREADS ? HZ_MAX_THREADS : (int)c;
}

int hz_bench_open_named(const char *dir, const char *name, hz_pools_t *pools, hz_scene_t *scene,
                        hz_accel_geom_t *geom)
{
    hz_error_t err;
    hz_pools_init(pools);
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.hzb", dir, name);
    if (hz_scenefile_open(path, pools, scene, &err) != HZ_OK) {
        hz_cli_error("bench: %s (run `make scenes` first)", err.msg);
        return hz_status_exit_code(err.code);
    }
    if (hz_accel_geom_from_scene(geom, scene, &pools->scene, &err) != HZ_OK)
        return hz_cli_report(&err);
    return 0;
}

void hz_bench_scene_list(const char **dir, const char **scenes, int *count, const char *const *defaults, int n)
{
    if (!*dir)
        *dir = getenv("HZ_SCENES_DIR") ? getenv("HZ_SCENES_DIR") : "build/scenes";
    if (*count == 0) {
        for (int i = 0; i < n; i++)
            scenes[i] = defaults[i];
        *count = n;
    }
}

bool hz_bench_scene_present(const char *dir, const char *name, const char *label)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.hzb", dir, name);
    if (access(path, R_OK) == 0)
        return true;
    hz_cli_error("bench: %sscene '%s' is missing: %s: %s", label, name, path, strerror(errno));
    return false;
}

void hz_bench_csv_beside(const char *csv, const char *suffix, char *buf, size_t size)
{
    const size_t n = strlen(csv);
    const bool dot_csv = n >= 4 && !strcmp(csv + n - 4, ".csv");
    snprintf(buf, size, "%.*s-%s.csv", (int)(dot_csv ? n - 4 : n), csv, suffix);
}
