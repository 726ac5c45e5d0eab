/*
 * bench_common.h — what hzbench's scene groups (tdense, adaptive, transparency) share: the median of their
 * rounds (bench_util.h), and (bench_scene.h) a baked scene opened into the board pools with its native accel.
 *
 * Contract: includes both (bench_util.h: hz_bench_median, the scene loop, the thread default).
 */
#ifndef HZ_BENCH_COMMON_H
#define HZ_BENCH_COMMON_H

#include "bench_scene.h"
#include "bench_util.h"

#endif
