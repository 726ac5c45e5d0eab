/*
 * summary.h — the end-of-run summary of `hzrt render`: printed for people and written as JSON for tools.
 *
 * Contract: frame times are wall-clock milliseconds per displayed frame (begin of the frame to end of its last
 * pass, sinks excluded); percentiles are over the timed frames (the first frame of a multi-frame run is left
 * out and frames_timed says how many remain). The JSON is one object, written via temp file + rename.
 * `settings` (a JSON object's members, from the option tables: renderopts.h, showopts.h) holds every setting
 * that changes the image, so two runs that differ in one record different settings; the rays are given in
 * total and per frame in separate objects; an interrupted run says so ("interrupted": the signal's name).
 */
#ifndef HZ_PORT_SUMMARY_H
#define HZ_PORT_SUMMARY_H

#include <stdint.h>
#include <stdio.h>

#include "hz/render.h"
#include "pools.h"

/* --mode adaptive: camera rays per pixel and what they bought (adaptive_cli.h fills it). */
typedef struct hz_summary_adaptive {
    double extra_rays_per_pixel, rays_per_pixel, sample_ratio_9spp, lanes_per_packet, active_fraction;
    uint32_t attr_bytes_per_pixel;
} hz_summary_adaptive_t;

typedef struct hz_summary {
    const char *scene, *mode, *backend, *features;
    double spp; /* samples traced per pixel per frame: primary rays / (pixels x frames), what was done */
    uint32_t width, height, hz, frames, frames_timed;
    double start; /* scene time of the first frame, seconds */
    const char *notes[4]; /* lines on what the run added or left out (a default light, a partial tdense image) */
    int n_notes;
    const char *settings; /* JSON members of the image-changing settings */
    const char *interrupted; /* the signal that ended the run early ("SIGINT"), or NULL */
    /* motion blur (shutter > 0): the accel that blurs, its time keys, refits and rebuilds */
    double shutter;
    const char *blur_accel;
    uint32_t time_keys, refits, rebuilds;
    uint32_t instances, instance_tris; /* rigid instances of the native backend (0: none) */
    uint64_t key_sets;    /* box sets its motion BVH's nodes keep (0: none, e.g. Embree) */
    uint32_t nodes;       /* ... over this many nodes */
    const char *segments; /* per-node or every-key */
    int threads;
    double build_ms, ms_p50, ms_p99, ms_mean, ms_max, run_s;
    uint64_t rays;
    double rays_per_frame, mrays_per_s;
    hz_render_stats_t stats;
    const hz_pools_t *pools;
    const hz_summary_adaptive_t *adaptive; /* NULL outside --mode adaptive */
} hz_summary_t;

void hz_summary_print(const hz_summary_t *s, FILE *f);
hz_status_t hz_summary_write_json(const hz_summary_t *s, const char *path, hz_error_t *err);

#endif
