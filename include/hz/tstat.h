/*
 * hz/tstat.h — statistics over integer nanoseconds: sorting, selection, distributions, histograms.
 *
 * Contract: integer-only and freestanding; nothing allocates (callers pass the arrays). Results are exact:
 *  - Percentiles use the nearest-rank definition: the p-th percentile of n values is the value of rank
 *    ceil(p * n) (1-based) in ascending order, so every reported percentile is a value that occurred.
 *  - mean is sum / n rounded to nearest; sd is the population standard deviation (floor of the root of the mean
 *    squared deviation, exact to 1 ns), accumulated in 128 bits so no input can overflow it.
 *  - hz_sort_i64 is an in-place heapsort (O(n log n), no recursion); hz_select_i64 returns the k-th smallest
 *    (0-based) and reorders the array (O(n) expected, O(n log n) worst case: it falls back to the heapsort).
 *  - A histogram has nbins bins of width bin_ns starting at lo_ns; values below lo_ns or at/after the end are
 *    counted in `below` / `above`, never dropped: below + above + sum(count) == n.
 */
#ifndef HZ_TSTAT_H
#define HZ_TSTAT_H

#include <stddef.h>
#include <stdint.h>

#include "hz/status.h"

void hz_sort_i64(int64_t *v, size_t n);
int64_t hz_select_i64(int64_t *v, size_t n, size_t k);

typedef struct hz_dist {
    uint64_t n;
    int64_t min, p50, p90, p99, p999, max;
    int64_t mean;
    int64_t sd;
} hz_dist_t;

/* Sorts v[0..n) in place and fills d. n == 0 gives a zeroed d. */
void hz_dist_compute(int64_t *v, size_t n, hz_dist_t *d);

/* Nearest-rank percentile of a sorted array; per_mille_x10 is the percentile times 10 (999 = p99.9). */
int64_t hz_dist_rank(const int64_t *sorted, size_t n, uint32_t per_mille_x10);

#define HZ_HIST_BINS_MAX 1024

typedef struct hz_hist {
    int64_t lo_ns, bin_ns;
    uint32_t nbins;
    uint64_t n, below, above;
    uint64_t count[HZ_HIST_BINS_MAX];
} hz_hist_t;

/* bin_ns > 0 and 1 <= nbins <= HZ_HIST_BINS_MAX, else HZ_E_INVALID_ARG with the reason in err. */
hz_status_t hz_hist_init(hz_hist_t *h, int64_t lo_ns, int64_t bin_ns, uint32_t nbins, hz_error_t *err);
void hz_hist_add(hz_hist_t *h, int64_t v);

#endif /* HZ_TSTAT_H */
