/*
 * hz/status.h — status codes and error reports.
 *
 * Contract: every fallible hz function returns hz_status_t (HZ_OK == 0) or reports through an hz_error_t the
 * caller passes in. An hz_error_t carries the code plus a human-readable sentence that names the input and the
 * reason ("scene.hzb: section 'triangles': index 4711 >= vertex count 4096"). Messages are formatted into a
 * fixed buffer (no allocation) and are truncated, never overflowed. hz_status_str() never returns NULL.
 * Codes are stable: ports map them to distinct process exit statuses (see hz_status_exit_code).
 */
#ifndef HZ_STATUS_H
#define HZ_STATUS_H

#include <stdarg.h>
#include <stddef.h>

typedef enum hz_status {
    HZ_OK = 0,
    HZ_E_INVALID_ARG,  /* caller broke a documented precondition */
    HZ_E_NO_MEMORY,    /* an arena refused a request: needed > available */
    HZ_E_OVERFLOW,     /* a size or count computation would overflow */
    HZ_E_FORMAT,       /* input is malformed (bad magic, truncated, field out of range) */
    HZ_E_VERSION,      /* input has a format version this build does not read */
    HZ_E_CORRUPT,      /* input failed an integrity check (CRC mismatch) */
    HZ_E_RANGE,        /* an index or value lies outside its valid range */
    HZ_E_UNSUPPORTED,  /* valid request this build or board does not provide */
    HZ_E_IO,           /* reading or writing a file or device failed */
    HZ_E_DEVICE,       /* a device is missing, busy or misbehaves */
    HZ_E_TIMEOUT,      /* an expected event did not arrive in time */
    HZ_E_INTERNAL,     /* a bug: an invariant did not hold */
    HZ_STATUS_COUNT
} hz_status_t;

#define HZ_ERROR_MSG_BYTES 256

typedef struct hz_error {
    hz_status_t code;
    char msg[HZ_ERROR_MSG_BYTES]; /* NUL-terminated; "" when code == HZ_OK */
} hz_error_t;

/* Short constant name of a code, e.g. "no memory". Unknown codes give "unknown status". */
const char *hz_status_str(hz_status_t s);

/* Process exit status a command-line port uses for a code: 0 for HZ_OK, 64 + code otherwise (distinct per
 * code, clear of the shell's 126..255 range and of 1/2 which getopt-style usage errors use). */
int hz_status_exit_code(hz_status_t s);

/* Clears err (code HZ_OK, empty message). err may be NULL. */
void hz_error_clear(hz_error_t *err);

/* Sets err->code and formats err->msg with hz_fmt (see hz/fmt.h). Returns code, so callers can write
 * `return hz_error_set(err, HZ_E_FORMAT, "...", ...);`. err may be NULL (the code is still returned). */
hz_status_t hz_error_set(hz_error_t *err, hz_status_t code, const char *fmt, ...);
hz_status_t hz_error_vset(hz_error_t *err, hz_status_t code, const char *fmt, va_list ap);

/* Prepends "prefix: " to an existing message (used to add the file name at the outer layer). */
void hz_error_prefix(hz_error_t *err, const char *prefix);

#endif /* HZ_STATUS_H */
