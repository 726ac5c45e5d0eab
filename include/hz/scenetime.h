/*
 * hz/scenetime.h — the scene clock: time enters the core as signed 64-bit nanoseconds (hz_time_ns_t), which
 * counts 292 years exactly; float appears only for offsets inside one loop period, where it keeps its precision.
 *
 * Contract:
 *  - hz_time_ns_t is nanoseconds of scene time (0 = the scene's start); any value, negative included, is valid.
 *  - hz_time_wrap_s(t, period) is t modulo period (the period rounded to whole nanoseconds), in [0, period) as
 *    float seconds, computed in integers (exact for every t); a period <= 0 or not finite means "no loop": t in
 *    float seconds. hz_time_from_s converts seconds (finite) to the nearest nanosecond, saturating.
 *  - Integer-only except the final conversions; no state, no OS.
 */
#ifndef HZ_SCENETIME_H
#define HZ_SCENETIME_H

#include <stdint.h>

#include "hz/base.h"

typedef int64_t hz_time_ns_t;

#define HZ_NS_PER_S 1000000000ll

HZ_INLINE hz_time_ns_t hz_time_from_s(double s)
{
    if (!(s == s))
        return 0;
    if (s >= 9.2e9)
        return INT64_MAX;
    if (s <= -9.2e9)
        return INT64_MIN;
    double ns = s * 1e9;
    return (hz_time_ns_t)(ns >= 0.0 ? ns + 0.5 : ns - 0.5);
}

HZ_INLINE float hz_time_wrap_s(hz_time_ns_t t, double period_s)
{
    if (!(period_s > 0.0) || period_s > 9.2e9)
        return (float)((double)t * 1e-9);
    int64_t p = (int64_t)(period_s * 1e9 + 0.5);
    if (p < 1)
        p = 1;
    int64_t w = t % p;
    if (w < 0)
        w += p;
    float f = (float)((double)w * 1e-9);
    return f >= (float)period_s ? 0.0f : f; /* rounding to float can land exactly on the period */
}

/* Frame n of a display at hz refreshes per second after start: start + n / hz, to the nanosecond. */
HZ_INLINE hz_time_ns_t hz_time_of_frame(hz_time_ns_t start, uint64_t n, uint32_t hz)
{
    return start + (hz_time_ns_t)(n / hz) * HZ_NS_PER_S + (hz_time_ns_t)((n % hz) * (uint64_t)HZ_NS_PER_S / hz);
}

#endif /* HZ_SCENETIME_H */
