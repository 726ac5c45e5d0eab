/*
 * fileio.h — files written so that nothing is lost: every output goes to a temporary file in the target's
 * directory and is renamed over the target only when complete. A failed or interrupted write leaves the old
 * file (if any) untouched and no partial file behind.
 *
 * Contract: hz_out_open() creates "<path>.tmp.XXXXXX" next to path; write through out->f; hz_out_commit()
 * flushes, checks every write succeeded, closes and renames; hz_out_abort() closes and removes the temporary.
 * Errors name the path and the reason (strerror) in err. Exactly one of commit/abort must follow a
 * successful open.
 */
#ifndef HZ_PORT_FILEIO_H
#define HZ_PORT_FILEIO_H

#include <stddef.h>
#include <stdio.h>

#include "hz/status.h"

typedef struct hz_out {
    FILE *f;
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

#endif
