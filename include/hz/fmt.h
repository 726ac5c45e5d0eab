/*
 * hz/fmt.h — a small, allocation-free, libc-free string formatter for messages made inside src/.
 *
 * Contract: hz_fmt writes at most `size` bytes including the terminating NUL (when size > 0) and returns the
 * number of characters the full output would have had, like C99 snprintf. Supported conversions:
 *   %s %c %d %i %u %x %X %p %%  with length modifiers l, ll, z (size_t) and an optional field width and '0'
 *   flag for integers, e.g. "%08x", "%5zu", "%lld".
 * An unknown conversion ends argument processing: it and the rest of the format are copied literally, so a
 * bad format never reads an argument of the wrong type. A NULL %s prints "(null)".
 */
#ifndef HZ_FMT_H
#define HZ_FMT_H

#include <stdarg.h>
#include <stddef.h>

size_t hz_fmt(char *buf, size_t size, const char *fmt, ...);
size_t hz_vfmt(char *buf, size_t size, const char *fmt, va_list ap);

#endif /* HZ_FMT_H */
