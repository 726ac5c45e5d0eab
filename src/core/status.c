/* Status codes and fixed-buffer error reports (see hz/status.h). */
#include "hz/status.h"

#include "hz/fmt.h"

static const char *const status_names[HZ_STATUS_COUNT] = {
    [HZ_OK] = "ok",
    [HZ_E_INVALID_ARG] = "invalid argument",
    [HZ_E_NO_MEMORY] = "no memory",
    [HZ_E_OVERFLOW] = "size overflow",
    [HZ_E_FORMAT] = "malformed input",
    [HZ_E_VERSION] = "unsupported version",
    [HZ_E_CORRUPT] = "corrupt input",
    [HZ_E_RANGE] = "out of range",
    [HZ_E_UNSUPPORTED] = "unsupported",
    [HZ_E_IO] = "i/o error",
    [HZ_E_DEVICE] = "device error",
    [HZ_E_TIMEOUT] = "timed out",
    [HZ_E_INTERNAL] = "internal error",
};

const char *hz_status_str(hz_status_t s)
{
    if ((unsigned)s >= (unsigned)HZ_STATUS_COUNT)
        return "unknown status";
    return status_names[s];
}

int hz_status_exit_code(hz_status_t s)
{
    if (s == HZ_OK)
        return 0;
    if ((unsigned)s >= (unsigned)HZ_STATUS_COUNT)
        return 64 + (int)HZ_E_INTERNAL;
    return 64 + (int)s;
}

void hz_error_clear(hz_error_t *err)
{
    if (!err)
        return;
    err->code = HZ_OK;
    err->msg[0] = '\0';
}

hz_status_t hz_error_vset(hz_error_t *err, hz_status_t code, const char *fmt, va_list ap)
{
    if (err) {
        err->code = code;
        hz_vfmt(err->msg, sizeof err->msg, fmt, ap);
    }
    return code;
}

hz_status_t hz_error_set(hz_error_t *err, hz_status_t code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    hz_error_vset(err, code, fmt, ap);
    va_end(ap);
    return code;
}

void hz_error_prefix(hz_error_t *err, const char *prefix)
{
    if (!err || !prefix)
        return;
    char old[HZ_ERROR_MSG_BYTES];
    /* Copy first: the formatter must not read the buffer it writes. */
    for (size_t i = 0; i < sizeof old; i++) {
        old[i] = err->msg[i];
        if (!old[i])
            break;
    }
    old[sizeof old - 1] = '\0';
    hz_fmt(err->msg, sizeof err->msg, "%s: %s", prefix, old);
}
