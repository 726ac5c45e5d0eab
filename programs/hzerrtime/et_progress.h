/*
 * et_progress.h — a one-line progress bar for long errtime runs.
 *
 * Contract: draws "label [#####-----]  42%  21/50  eta 12 s" on `f`, redrawn in place with '\r' whenever the
 * shown percentage or the label changes, and ended with a newline by hz_progress_end. It draws only when
 * `enabled` is true, which callers set to "stderr is a terminal" (hz_cli_stderr_is_tty), so logs and pipes
 * stay clean. Nothing is allocated.
 */
#ifndef HZ_ERRTIME_PROGRESS_H
#define HZ_ERRTIME_PROGRESS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

typedef struct hz_progress {
    FILE *f;
    bool enabled;
    char label[48];
    uint64_t total, done;
    int64_t t0_ns;
    int shown; /* last percentage drawn, -1 before the first draw */
} hz_progress_t;

void hz_progress_begin(hz_progress_t *p, FILE *f, bool enabled, uint64_t total);
/* Sets the label shown in front of the bar (e.g. "full-frame spp=4"). */
void hz_progress_label(hz_progress_t *p, const char *label);
void hz_progress_step(hz_progress_t *p, uint64_t n);
void hz_progress_end(hz_progress_t *p);

#endif
