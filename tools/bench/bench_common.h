/*
 * bench_common.h — what hzbench's scene groups (tdense, adaptive, transparency) share: the median of their
 * rounds, and (bench_scene.h) a baked scene opened into the board pools with its native accel.
 *
 * Contract: hz_bench_median sorts v[0..n) in place (n > 0) and returns the middle value (the mean of the two
 * middle ones for even n). Header-only (static functions).
 */
#ifndef HZ_BENCH_COMMON_H
#define HZ_BENCH_COMMON_H

#include <stdlib.h>

#include "bench_scene.h"

static inline int hz_bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static inline double hz_bench_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, hz_bench_cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

#endif
