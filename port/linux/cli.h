/*
 * cli.h — helpers the command-line entry points share: error messages, strict argument parsing, exit codes.
 *
 * Contract: messages go to stderr prefixed with the program name ("hzrt: --spp: 'x' is not an integer").
 * Parsers accept the whole argument or nothing (no trailing junk, no overflow) and print what was wrong,
 * naming the option. Exit statuses: 0 success, HZ_EXIT_USAGE for a bad command line, and
 * hz_status_exit_code(status) (64 + code) for failures at run time, so each kind of failure is distinct.
 */
#ifndef HZ_PORT_CLI_H
#define HZ_PORT_CLI_H

#include <stdbool.h>
#include <stddef.h>

#include "hz/status.h"

#define HZ_EXIT_USAGE 2

extern const char *hz_cli_prog;

void hz_cli_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Prints "prog: <err->msg>" (or the status name when the message is empty); returns the exit status. */
int hz_cli_report(const hz_error_t *err);

/* Parse a decimal integer in [min, max]; on failure print why and return false. */
bool hz_cli_parse_long(const char *opt, const char *arg, long min, long max, long *out);
/* Parse "WxH" with both in [min, max]. */
bool hz_cli_parse_size(const char *opt, const char *arg, int min, int max, int *w, int *h);

/* Text from a file (a scene's or an object's name) made safe to print: bytes below 0x20 and 0x7f as \xNN, the
 * rest as they are (names are UTF-8); at most max bytes of s, up to its NUL. Returns buf. */
const char *hz_cli_printable(char *buf, size_t cap, const char *s, size_t max);

/* True when stderr is a terminal (progress bars only then). */
bool hz_cli_stderr_is_tty(void);

#endif
