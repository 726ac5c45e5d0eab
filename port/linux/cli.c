/* Command-line helpers (see cli.h). */
#include "cli.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

const char *hz_cli_prog = "hzrt";

void hz_cli_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s: ", hz_cli_prog);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

int hz_cli_report(const hz_error_t *err)
{
    if (err->code == HZ_OK)
        return 0;
    hz_cli_error("%s", err->msg[0] ? err->msg : hz_status_str(err->code));
    return hz_status_exit_code(err->code);
}

bool hz_cli_parse_long(const char *opt, const char *arg, long min, long max, long *out)
{
    if (!arg || !*arg) {
        hz_cli_error("%s: missing value (an integer in [%ld, %ld])", opt, min, max);
        return false;
    }
    char *end = NULL;
    errno = 0;
    long v = strtol(arg, &end, 10);
    if (errno || *end || end == arg) {
        hz_cli_error("%s: '%s' is not an integer in [%ld, %ld]", opt, arg, min, max);
        return false;
    }
    if (v < min || v > max) {
        hz_cli_error("%s: %ld is outside [%ld, %ld]", opt, v, min, max);
        return false;
    }
    *out = v;
    return true;
}

bool hz_cli_parse_size(const char *opt, const char *arg, int min, int max, int *w, int *h)
{
    long lw, lh;
    char *end = NULL;
    if (!arg || !*arg)
        goto bad;
    errno = 0;
    lw = strtol(arg, &end, 10);
    if (errno || end == arg || (*end != 'x' && *end != 'X'))
        goto bad;
    const char *hs = end + 1;
    lh = strtol(hs, &end, 10);
    if (errno || end == hs || *end)
        goto bad;
    if (lw < min || lw > max || lh < min || lh > max) {
        hz_cli_error("%s: %ldx%ld: width and height must lie in [%d, %d]", opt, lw, lh, min, max);
        return false;
    }
    *w = (int)lw;
    *h = (int)lh;
    return true;
bad:
    hz_cli_error("%s: '%s' is not a size like 640x360", opt, arg ? arg : "");
    return false;
}

const char *hz_cli_printable(char *buf, size_t cap, const char *s, size_t max)
{
    size_t n = 0;
    if (!cap)
        return buf;
    for (size_t i = 0; i < max && s[i] && n + 5 < cap; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c < 0x20 || c == 0x7f)
            n += (size_t)snprintf(buf + n, cap - n, "\\x%02x", c);
        else
            buf[n++] = (char)c;
    }
    buf[n] = 0;
    return buf;
}

bool hz_cli_stderr_is_tty(void)
{
    return isatty(STDERR_FILENO) == 1;
}
