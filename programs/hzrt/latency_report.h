/*
 * latency_report.h — what `hzrt latency` prints and writes: the summary on a stream, and per-frame CSV, per-edge CSV,
 * JSON and an SVG histogram in a directory.
 *
 * Contract:
 *  - hz_report_compute() derives everything from a loop result: the frame summary (hz/frames.h), the v-sync
 *    residual and pulse-width distributions, the histogram of latency with bin P/32 (frames) or of residuals
 *    (edges only). Percentiles are nearest-rank over the frames (or edges) counted, and every count that
 *    was excluded from a distribution is printed next to it: unresolved frames, inferred edges, edges past the
 *    log, the histogram's overflow. Nothing is culled silently.
 *  - Quality levels: each frame's level is in frames.csv; the share of time at a level is the share of the
 *    refreshes that showed a frame of that level (a shown frame holds the display until the next shown one).
 *  - hz_report_write() writes frames.csv (one row per frame), edges.csv (one row per input edge; readable
 *    again by --source csv:FILE), report.json and histogram.svg into dir (created if needed), each through a
 *    temporary file and a rename, so an interrupted run leaves no half-written file.
 */
#ifndef HZ_PORT_REPORT_H
#define HZ_PORT_REPORT_H

#include <stdio.h>

#include <stdbool.h>

#include "hz/frameloop.h"
#include "hz/governor.h"
#include "hz/frames.h"
#include "hz/tstat.h"

/* A scene's quality levels (hz/ladder.h) as the report names them, and each one's error against level 0 when it
 * was measured (show.h). */
typedef struct hz_report_levels {
    uint32_t count;
    bool governor;
    char name[HZ_GOV_MAX_LEVELS][80];
    bool measured[HZ_GOV_MAX_LEVELS];
    double psnr_db[HZ_GOV_MAX_LEVELS], flip[HZ_GOV_MAX_LEVELS];
    uint32_t error_frames;
} hz_report_levels_t;

typedef struct hz_report_info {
    const char *source, *sink, *frames;
    const char *clock;      /* "real time" or "simulated clock, render model ..." */
    int w, h;
    int marker;
    const hz_report_levels_t *levels; /* NULL: frames without quality levels (the test pattern) */
    /* a scene's frames: the file (or "builtin"), the mode and render size of level 0, the render scale and the
     * render threads (report.json's "scene"); scene_file NULL: the test pattern */
    const char *scene_file, *mode;
    int render_w, render_h, render_scale, threads;
} hz_report_info_t;

typedef struct hz_report {
    const hz_loop_cfg_t *cfg;
    hz_report_info_t info;
    hz_loop_result_t *res;
    hz_frames_summary_t frames;
    hz_dist_t residual, abs_residual, pulse, interval;
    uint64_t pulses;
    hz_hist_t hist;
    int hist_is_latency;
    /* per quality level: frames rendered, and refreshes that showed one of them (the share of time) */
    uint64_t level_frames[HZ_GOV_MAX_LEVELS], level_refreshes[HZ_GOV_MAX_LEVELS], refreshes;
} hz_report_t;

void hz_report_compute(hz_report_t *r, const hz_loop_cfg_t *cfg, const hz_report_info_t *info, hz_loop_result_t *res);
void hz_report_print(FILE *f, hz_report_t *r);
hz_status_t hz_report_write(const char *dir, hz_report_t *r, hz_error_t *err);

/* A run too short to judge a lock: no reason but the missing locked stretch, and fewer v-sync edges in the
 * whole run than one locked stretch (min_run) takes. Not a lock either (exit status 3, no period), but it says
 * "too short to judge a lock" rather than "no lock". */
bool hz_report_too_short(const hz_lockv_result_t *lock);
/* "locked", "no lock" or "too short to judge a lock". */
const char *hz_report_lock_verdict(const hz_lockv_result_t *lock);
/* Every reason of a no-lock verdict, in words with the counts and limits. */
const char *hz_report_lock_reasons(char *buf, size_t cap, const hz_lockv_result_t *lock);

/* "4.167 ms", "12.3 us", "850 ns": a duration for humans. */
const char *hz_report_dur(char *buf, size_t cap, int64_t ns);

#endif
