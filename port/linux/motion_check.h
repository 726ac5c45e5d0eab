/*
 * motion_check.h — the motion-blur BVH against brute force at each ray's time: the check behind
 * `hzrt accel --motion-check N` and the stability suite's motion-blur cases.
 *
 * Contract:
 *  - hz_mcheck_batch(a, g, rays, lanes, stats, counts) takes up to 8 rays (their own origin, direction, tnear,
 *    tfar and time) and compares, for each, hz_accel_brute_intersect1 over every triangle of g at the ray's time
 *    (the independent reference) with the accel's single-ray closest hit, its occlusion query and the same ray
 *    as a lane of an 8-wide packet. A hit the reference has and a kernel lacks is a miss; any other difference
 *    (hit where the reference has none, another triangle, t, u, v or ng not bit-identical) is a mismatch.
 *    counts->rays, hits (reference hits), misses and mismatches are added to; stats (may be NULL) gets the
 *    closest-hit queries' traversal figures.
 *  - hz_mcheck_ray(g, lo, hi, i, seed, rh) is ray i of the random check: even rays aim at a random point of a
 *    random triangle at the ray's time, odd rays are random lines through the box [lo, hi] (hz_mcheck_bounds:
 *    the finite coordinates of every key); one in eight sits exactly on a key time. Deterministic in (i, seed).
 *  - hz_mcheck_run(a, g, n, seed, progress, stats, counts) checks rays 0..n-1 in batches of 8 (progress: a line
 *    on stderr every 2 s).
 */
#ifndef HZ_PORT_MOTION_CHECK_H
#define HZ_PORT_MOTION_CHECK_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/accel.h"

typedef struct hz_mcheck_counts {
    uint64_t rays, hits, misses, mismatches;
} hz_mcheck_counts_t;

void hz_mcheck_bounds(const hz_accel_geom_t *g, float lo[3], float hi[3]);
void hz_mcheck_ray(const hz_accel_geom_t *g, const float lo[3], const float hi[3], uint64_t i, uint32_t seed,
                   hz_rayhit_t *rh);
void hz_mcheck_batch(const hz_accel_t *a, const hz_accel_geom_t *g, const hz_rayhit_t *rays, int lanes,
                     hz_accel_stats_t *stats, hz_mcheck_counts_t *counts);
void hz_mcheck_run(const hz_accel_t *a, const hz_accel_geom_t *g, uint64_t n, uint32_t seed, bool progress,
                   hz_accel_stats_t *stats, hz_mcheck_counts_t *counts);

#endif
