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

/* Installs the clean-up of open temporaries on SIGINT, SIGTERM, SIGHUP and SIGQUIT (see above). */
void hz_out_remove_on_signals(void);

#endif
