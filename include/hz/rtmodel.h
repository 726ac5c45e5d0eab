/*
 * hz/rtmodel.h — synthetic render-time models for simulated (virtual-time) runs and pacing tests.
 *
 * Contract (integer-only, deterministic for a seed): hz_rtm_next() gives frame n's render time in ns and
 * how late the render thread woke for it (uniform in [0, wake_ns]). Models, with a, b in ns:
 *   const      a
 *   uniform    uniform in [a, b]
 *   spikes     a, but b with probability rate_ppm per million frames
 *   triangle   from a up to b and back down over `frames` frames, repeating
 *   step       a before frame `frames`, b from then on
 * hz_rtm_max_ns() is the largest render time the model can produce (tests use it to state their premise,
 * e.g. "render time below 80% of the period").
 */
#ifndef HZ_RTMODEL_H
#define HZ_RTMODEL_H

#include <stdint.h>

#include "hz/hash.h"
#include "hz/status.h"

typedef enum hz_rtm_kind {
    HZ_RTM_CONST = 1,
    HZ_RTM_UNIFORM,
    HZ_RTM_SPIKES,
    HZ_RTM_TRIANGLE,
    HZ_RTM_STEP
} hz_rtm_kind_t;

typedef struct hz_rtm_cfg {
    hz_rtm_kind_t kind;
    int64_t a_ns, b_ns;
    uint32_t rate_ppm;  /* spikes */
    uint64_t frames;    /* triangle: period; step: the frame it steps at */
    int64_t wake_ns;    /* oversleep, uniform in [0, wake_ns] */
    uint64_t seed;
} hz_rtm_cfg_t;

typedef struct hz_rtm {
    hz_rtm_cfg_t cfg;
    hz_rng_t rng;
} hz_rtm_t;

hz_status_t hz_rtm_init(hz_rtm_t *m, const hz_rtm_cfg_t *cfg, hz_error_t *err);
void hz_rtm_next(hz_rtm_t *m, uint64_t frame, int64_t *render_ns, int64_t *wake_late_ns);
int64_t hz_rtm_max_ns(const hz_rtm_cfg_t *cfg);

#endif /* HZ_RTMODEL_H */
