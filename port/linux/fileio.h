/*
 * fileio.h — files written so that nothing is lost: every output goes to a temporary file in the target's
 * directory and is renamed over the target only when complete. A failed or interrupted write leaves the old
 * file (if any) untouched and no partial file behind.
 *
 * Contract: hz_out_open() creates "<path>.tmp.XXXXXX" next to path; write through out->f; hz_out_commit()
 * flushes, checks every write succeeded, closes and renames; hz_out_abort() closes and removes the temporary.
 * Errors name the path and the reason (strerror) in err. Exactly one of commit/abort must follow a
 * successful open.
 *
 * Signals: after hz_out_remove_on_signals(), SIGINT, SIGTERM, SIGHUP and SIGQUIT remove every temporary file
 * that is still open (at most HZ_OUT_TRACKED at a time are tracked) and then end the process as the signal
 * would have: an interrupted run leaves nothing behind.
 */
#ifndef HZ_PORT_FILEIO_H
#define HZ_PORT_FILEIO_H

#include <stddef.h>
#include <signal.h>
#include <stdio.h>

#include "hz/status.h"

#define HZ_OUT_TRACKED 16

typedef struct hz_out {
    FILE *f;
    int slot; /* this temporary's entry in the signal clean-up table, -1 when untracked */
    char path[4096];
    char tmp[4096 + 16];
} hz_out_t;

hz_status_t hz_out_open(hz_out_t *out, const char *path, hz_error_t *err);
hz_status_t hz_out_commit(hz_out_t *out, hz_error_t *err);
void hz_out_abort(hz_out_t *out);

/* Whole buffer to path, atomically. */
hz_status_t hz_file_write_atomic(const char *path, const void *data, size_t size, hz_error_t *err);

/* Reads a whole regular file into buf (at most cap bytes). A larger file is refused with HZ_E_NO_MEMORY and
 * both sizes; *size gets the byte count read. */
hz_status_t hz_file_read(const char *path, void *buf, size_t cap, size_t *size, hz_error_t *err);

/* mkdir -p; existing directories are fine. */
hz_status_t hz_mkdirs(const char *path, hz_error_t *err);

/* An output folder made ready before any work: mkdir -p, then proof that a file can be created in it (a
 * read-only folder or file system is refused now, not after the run). `created` (may be NULL) gets the folders
 * this call made, outermost first, separated by ", " ("" when all existed). */
hz_status_t hz_out_dir_prepare(const char *path, char *created, size_t cap, hz_error_t *err);

/* The same, and *made_from (may be NULL) gets the length of the outermost folder of path this call made (0: it
 * made none): hz_out_dir_unmake(path, made_from) removes them again, innermost first, each only while empty (a
 * run that fails before writing anything leaves no folder behind). */
hz_status_t hz_out_dir_make(const char *path, char *created, size_t cap, size_t *made_from, hz_error_t *err);
void hz_out_dir_unmake(const char *path, size_t made_from);

/* One check of a run's outputs before any work. Outputs and inputs are registered with what they are for
 * messages ("--adaptive-map", "last.png in --out", "the scene"); hz_outs_check() then refuses
 *   HZ_E_INVALID_ARG: an output that is an input (the same file, also through a link) or another output (the
 *     same name in the same folder): the command line is wrong;
 *   HZ_E_IO: an output whose folder does not exist or cannot be written, or that names a folder;
 * each naming both paths. Nothing is created or written but a probe file, removed at once. */
#define HZ_OUTS_MAX 16
typedef struct hz_outs {
    struct { char path[4096]; const char *what; } out[HZ_OUTS_MAX], in[4];
    int n_out, n_in;
} hz_outs_t;

void hz_outs_init(hz_outs_t *o);
void hz_outs_output(hz_outs_t *o, const char *path, const char *what);
void hz_outs_input(hz_outs_t *o, const char *path, const char *what);
hz_status_t hz_outs_check(const hz_outs_t *o, hz_error_t *err);

/* Installs the clean-up of open temporaries on SIGINT, SIGTERM, SIGHUP and SIGQUIT (see above). */
void hz_out_remove_on_signals(void);

/* While a run can stop cleanly: with flag non-NULL, the first SIGINT, SIGTERM or SIGHUP only sets *flag to the
 * signal's number and writes note (may be NULL) to stderr; the run finishes what it has and then calls
 * hz_out_die(*flag). A second signal, and SIGQUIT, act at once as above. NULL ends the deferral. */
void hz_out_signals_defer(volatile sig_atomic_t *flag, const char *note);
/* Removes the open temporaries and ends the process as signal sig would. */
void hz_out_die(int sig);

#endif
