/* Sorting, selection, distributions and histograms over int64 nanoseconds (see hz/tstat.h). */
#include "hz/tstat.h"

#include "wide.h"

static void sift_down(int64_t *v, size_t root, size_t n)
{
    for (;;) {
        size_t child = 2 * root + 1;
        if (child >= n)
            return;
        if (child + 1 < n && v[child + 1] > v[child])
            child++;
        if (v[root] >= v[child])
            return;
        int64_t t = v[root];
        v[root] = v[child];
        v[child] = t;
        root = child;
    }
}

void hz_sort_i64(int64_t *v, size_t n)
{
    if (n < 2)
        return;
    for (size_t i = n / 2; i-- > 0;)
        sift_down(v, i, n);
    for (size_t end = n - 1; end > 0; end--) {
        int64_t t = v[0];
        v[0] = v[end];
        v[end] = t;
        sift_down(v, 0, end);
    }
}

static void swap64(int64_t *a, int64_t *b)
{
    int64_t t = *a;
    *a = *b;
    *b = t;
}

int64_t hz_select_i64(int64_t *v, size_t n, size_t k)
{
    if (n == 0)
        return 0;
    if (k >= n)
        k = n - 1;
    size_t lo = 0, hi = n - 1;
    /* Quickselect with a median-of-three pivot; after 2 log2(n) + 8 rounds something adversarial is going
     * on and the rest is sorted instead, which bounds the worst case. */
    unsigned budget = 8;
    for (size_t m = n; m; m >>= 1)
        budget += 2;
    while (hi > lo) {
        if (budget-- == 0) {
            hz_sort_i64(v + lo, hi - lo + 1);
            return v[k];
        }
        size_t mid = lo + (hi - lo) / 2;
        if (v[mid] < v[lo])
            swap64(&v[mid], &v[lo]);
        if (v[hi] < v[lo])
            swap64(&v[hi], &v[lo]);
        if (v[hi] < v[mid])
            swap64(&v[hi], &v[mid]);
        int64_t pivot = v[mid];
        size_t i = lo, j = hi;
        while (i <= j) {
            while (v[i] < pivot)
                i++;
            while (v[j] > pivot)
                j--;
            if (i <= j) {
                swap64(&v[i], &v[j]);
                i++;
                if (j == 0)
                    break;
                j--;
            }
        }
        /* Now v[lo..j] <= pivot <= v[i..hi] and everything strictly between equals the pivot. */
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return v[k];
    }
    return v[k];
}

int64_t hz_dist_rank(const int64_t *sorted, size_t n, uint32_t per_mille_x10)
{
    if (n == 0)
        return 0;
    if (per_mille_x10 > 1000)
        per_mille_x10 = 1000;
    /* rank = ceil(p * n), p = per_mille_x10 / 1000; at least 1. */
    uint64_t rank = ((uint64_t)n * per_mille_x10 + 999u) / 1000u;
    if (rank < 1)
        rank = 1;
    return sorted[rank - 1];
}

/* |a - b| for any two int64 values, exactly. */
static uint64_t dev_abs(int64_t a, int64_t b)
{
    return a >= b ? (uint64_t)a - (uint64_t)b : (uint64_t)b - (uint64_t)a;
}

void hz_dist_compute(int64_t *v, size_t n, hz_dist_t *d)
{
    d->n = n;
    d->min = d->p50 = d->p90 = d->p99 = d->p999 = d->max = d->mean = d->sd = 0;
    if (n == 0)
        return;
    hz_sort_i64(v, n);
    d->min = v[0];
    d->max = v[n - 1];
    d->p50 = hz_dist_rank(v, n, 500);
    d->p90 = hz_dist_rank(v, n, 900);
    d->p99 = hz_dist_rank(v, n, 990);
    d->p999 = hz_dist_rank(v, n, 999);
    /* Exact mean: sum of offsets from the minimum (non-negative) in 128 bits. */
    hz_u128_t sum = { 0, 0 };
    for (size_t i = 0; i < n; i++) {
        hz_u128_t t = { 0, (uint64_t)v[i] - (uint64_t)v[0] };
        sum = hz_u128_add(sum, t);
    }
    uint64_t rem = 0;
    uint64_t q = hz_u128_div(sum, n, &rem);
    if (rem >= n - rem)
        q++; /* round half up */
    d->mean = (int64_t)((uint64_t)v[0] + q);
    /* Squared deviations from the rounded mean: its rounding error e (|e| <= 1/2 ns) adds e^2 <= 1/4 ns^2 to
     * the variance, so sd is exact to within 1 ns. A deviation needs 64 unsigned bits (values at both ends of
     * the int64 range; v[i] - mean in int64 overflowed there) and its square 128, so a sum of squares can
     * overflow: then each square is divided by n first (quotients and remainders summed apart), which is
     * exact too and cannot overflow, as the variance is below 2^126. */
    hz_u128_t ss = { 0, 0 };
    int wrapped = 0;
    for (size_t i = 0; i < n; i++) {
        uint64_t dev = dev_abs(v[i], d->mean);
        hz_u128_t sq = hz_u128_mul(dev, dev), next = hz_u128_add(ss, sq);
        if (next.hi < ss.hi || (next.hi == ss.hi && next.lo < ss.lo))
            wrapped = 1;
        ss = next;
    }
    hz_u128_t var = hz_u128_div_full(ss, n);
    if (wrapped) {
        hz_u128_t q = { 0, 0 }, rs = { 0, 0 };
        for (size_t i = 0; i < n; i++) {
            uint64_t dev = dev_abs(v[i], d->mean);
            hz_u128_t sq = hz_u128_mul(dev, dev), qi = hz_u128_div_full(sq, n);
            /* sq - qi n < n fits a word, so the low words (mod 2^64) give it */
            hz_u128_t r1 = { 0, sq.lo - qi.lo * (uint64_t)n };
            q = hz_u128_add(q, qi);
            rs = hz_u128_add(rs, r1);
        }
        var = hz_u128_add(q, hz_u128_div_full(rs, n));
    }
    uint64_t sd = hz_u128_isqrt(var);
    d->sd = sd > (uint64_t)INT64_MAX ? INT64_MAX : (int64_t)sd;
}

hz_status_t hz_hist_init(hz_hist_t *h, int64_t lo_ns, int64_t bin_ns, uint32_t nbins, hz_error_t *err)
{
    if (bin_ns <= 0)
        return hz_error_set(err, HZ_E_INVALID_ARG, "histogram: bin width %lld ns must be positive",
                            (long long)bin_ns);
    if (nbins < 1 || nbins > HZ_HIST_BINS_MAX)
        return hz_error_set(err, HZ_E_INVALID_ARG, "histogram: %u bins is outside [1, %u]", nbins,
                            (unsigned)HZ_HIST_BINS_MAX);
    h->lo_ns = lo_ns;
    h->bin_ns = bin_ns;
    h->nbins = nbins;
    h->n = h->below = h->above = 0;
    for (uint32_t i = 0; i < HZ_HIST_BINS_MAX; i++)
        h->count[i] = 0;
    return HZ_OK;
}

void hz_hist_add(hz_hist_t *h, int64_t v)
{
    h->n++;
    if (v < h->lo_ns) {
        h->below++;
        return;
    }
    uint64_t off = (uint64_t)v - (uint64_t)h->lo_ns;
    uint64_t bin = off / (uint64_t)h->bin_ns;
    if (bin >= h->nbins)
        h->above++;
    else
        h->count[bin]++;
}
