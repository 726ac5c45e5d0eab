/*
 * phase.h — progress lines for the long phases of a command (reading a large scene, a native BVH build,
 * rendering), on stderr.
 *
 * Contract: hz_phase_begin(p, what) starts a phase named for what it is ("native build of furball.hzb,
 * 2733030 triangles"); hz_phase_update(p, fraction) may be called any number of times; hz_phase_end(p)
 * closes it. Nothing is printed for a phase shorter than HZ_PHASE_AFTER_S (1 s) or when disabled; past
 * that, a terminal gets one line rewritten in place ("what: 45% (7.1 s)") at most 10 times a second and a final
 * "what: done in 15.2 s", and the line never mixes with other output (it ends with a newline before end
 * returns). Enabled when stderr is a terminal, or when the environment has HZ_PROGRESS=1 (then every update
 * is its own line, at most one per second, for logs), or HZ_PROGRESS=all (the same for every phase however
 * short: for tests). hz_phase_accel is an hz_accel_config_t
 * progress callback whose user pointer is an hz_phase_t.
 */
#ifndef HZ_PORT_PHASE_H
#define HZ_PORT_PHASE_H

#include <stdbool.h>
#include <stdint.h>

#define HZ_PHASE_AFTER_S 1.0

typedef struct hz_phase {
    char what[192];
    int64_t t0, last;
    bool enabled, tty, shown;
    double after_s;
} hz_phase_t;

/* A command's --quiet for every phase of the run, also those begun deep in the port (reading the scene). */
extern bool hz_phase_muted;

/* quiet: the command's own --quiet (no progress at all). */
void hz_phase_begin(hz_phase_t *p, bool quiet, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
void hz_phase_update(hz_phase_t *p, float fraction);
void hz_phase_end(hz_phase_t *p);
void hz_phase_accel(void *user, float done);

#endif
