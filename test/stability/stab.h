/*
 * stab.h — the stability suite's case interface (test/stability/, `make stability`).
 *
 * Contract:
 *  - A case is one entry of a stage table (stab_case_t: name, what it checks, the function) and one function
 *    `void f(stab_result_t *r)` that builds its input (a procedural scene in memory, a .hzb written to a file, a
 *    synthetic trace, an option set), runs the code under test and checks the property that must hold.
 *  - The runner (main.c) runs every case in a child process of its own with a time limit: a crash, a sanitizer
 *    abort or a hang fails the case (and only that case). A case passes when no STAB_CHECK failed and
 *    r->nonfinite is 0: every case counts the NaN/Inf values it finds in the images, hits and reports it
 *    produced (stab_count_nonfinite) so that no non-finite value passes silently.
 *  - Figures: nonfinite (the count above), max_error (against the case's independent reference: an analytic
 *    value, a double-precision or brute-force oracle; NAN where the property is exact or a refusal), status
 *    (what the code under test returned for the case's input: HZ_OK, or the documented refusal), and a short
 *    free-text note (r->note) for the report.
 *  - Cases allocate from the board's pools (port/linux/pools.h) and the C library's malloc in the test only;
 *    each runs in a fresh process, so nothing leaks from one case into the next.
 *
 * Adding a case: write `static void c_<name>(stab_result_t *r)` in the stage's file (test/stability/<stage>.c),
 * add `{ "<name>", "<what it checks>", c_<name>, 0 }` to that file's table. A new stage: a new file with a table
 * STAB_STAGE(<stage>) and one line in main.c's stage list (and the Makefile's STAB_SRCS).
 */
#ifndef HZ_STAB_H
#define HZ_STAB_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "hz/status.h"

typedef struct stab_result {
    uint64_t nonfinite;   /* NaN/Inf values seen in any output */
    double max_error;     /* against the reference; NAN when the case has none */
    int status;           /* hz_status_t of the input (-1: not applicable) */
    char note[200];       /* figures in words, for the report */
    char fail[320];       /* the first failed check; "" when every check held */
    int full;             /* 1 under `make stability FULL=1`: long variants run bigger inputs */
} stab_result_t;

typedef void (*stab_fn)(stab_result_t *r);

typedef struct stab_case {
    const char *name;     /* unique within its stage, [a-z0-9_] */
    const char *checks;   /* the property, in a few words (no commas: it goes into a CSV) */
    stab_fn run;
    unsigned flags;       /* STAB_FULL_ONLY: runs only with FULL=1 */
} stab_case_t;

#define STAB_FULL_ONLY 1u

typedef struct stab_stage {
    const char *name;
    const stab_case_t *cases;
    size_t count;
} stab_stage_t;

/* A stage file ends with STAB_STAGE(name, table): it defines stab_stage_<name>, which main.c lists. */
#define STAB_STAGE(sname, table)                                                                                  \
    const stab_stage_t stab_stage_##sname = { #sname, table, sizeof(table) / sizeof(table[0]) }

/* Records the first failure (file:line and the message) and returns from the case. */
void stab_failf(stab_result_t *r, const char *file, int line, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
#define STAB_CHECK(r, cond, ...)                                                                                  \
    do {                                                                                                          \
        if (!(cond)) {                                                                                            \
            stab_failf((r), __FILE__, __LINE__, __VA_ARGS__);                                                     \
            return;                                                                                               \
        }                                                                                                         \
    } while (0)
/* Returns from the case when a helper it called has failed it. */
#define STAB_BAIL(r)                                                                                              \
    do {                                                                                                          \
        if ((r)->fail[0])                                                                                         \
            return;                                                                                               \
    } while (0)
/* An hz call that must succeed. */
#define STAB_OK(r, call, err)                                                                                     \
    do {                                                                                                          \
        hz_status_t stab_s_ = (call);                                                                             \
        if (stab_s_ != HZ_OK) {                                                                                   \
            stab_failf((r), __FILE__, __LINE__, "%s: %s (%s)", #call, hz_status_str(stab_s_), (err)->msg);        \
            return;                                                                                               \
        }                                                                                                         \
    } while (0)

/* Appends a note (figures) to r->note, "; "-separated. */
void stab_note(stab_result_t *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Adds the count of non-finite values of v[0..n) to r->nonfinite and returns it. */
uint64_t stab_count_nonfinite(stab_result_t *r, const float *v, size_t n);
/* max_error = max(max_error, e) (NAN-aware: a NaN error counts as non-finite). */
void stab_error(stab_result_t *r, double e);
/* A clean refusal: status `want`, a message that contains `needle` (the input's name). */
#define STAB_REFUSED(r, got, want, err, needle)                                                                   \
    do {                                                                                                          \
        (r)->status = (int)(got);                                                                                 \
        STAB_CHECK(r, (got) == (want), "status %s, want %s (%s)", hz_status_str(got), hz_status_str(want),        \
                   (err)->msg);                                                                                   \
        STAB_CHECK(r, strstr((err)->msg, (needle)) != NULL, "message '%s' does not name '%s'", (err)->msg,        \
                   (needle));                                                                                     \
        stab_note(r, "refused: %s", (err)->msg);                                                                  \
    } while (0)

#endif
