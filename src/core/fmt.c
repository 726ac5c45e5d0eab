/* hz_fmt: snprintf subset for messages built inside the freestanding core (see hz/fmt.h). */
#include "hz/fmt.h"

#include <stdint.h>

typedef struct out {
    char *buf;
    size_t size;
    size_t len; /* characters the full output has so far (may exceed size) */
} out_t;

static void put(out_t *o, char c)
{
    if (o->len + 1 < o->size)
        o->buf[o->len] = c;
    o->len++;
}

static void put_str(out_t *o, const char *s)
{
    while (*s)
        put(o, *s++);
}

static void put_uint(out_t *o, unsigned long long v, unsigned base, int upper, int width, char pad)
{
    const char *digits = upper ? "0123456789ABCDEF" : "0123456789abcdef";
    char tmp[24]; /* 2^64 has 20 decimal digits, 16 hex */
    int n = 0;
    do {
        tmp[n++] = digits[v % base];
        v /= base;
    } while (v);
    while (width-- > n)
        put(o, pad);
    while (n)
        put(o, tmp[--n]);
}

static void put_int(out_t *o, long long v, int width, char pad)
{
    /* Negate through unsigned so LLONG_MIN is exact. */
    unsigned long long mag = v < 0 ? 0ull - (unsigned long long)v : (unsigned long long)v;
    if (v < 0) {
        if (pad == '0') {
            put(o, '-');
            put_uint(o, mag, 10, 0, width - 1, pad);
            return;
        }
        /* Space padding goes before the sign: count the digits first. */
        int digits = 1;
        for (unsigned long long t = mag; t >= 10; t /= 10)
            digits++;
        for (int w = width - digits - 1; w > 0; w--)
            put(o, ' ');
        put(o, '-');
        put_uint(o, mag, 10, 0, 0, ' ');
        return;
    }
    put_uint(o, mag, 10, 0, width, pad);
}

size_t hz_vfmt(char *buf, size_t size, const char *fmt, va_list ap)
{
    out_t o = { buf, size, 0 };
    const char *p = fmt ? fmt : "(null format)";

    while (*p) {
        if (*p != '%') {
            put(&o, *p++);
            continue;
        }
        const char *conv = p++;
        char pad = ' ';
        int width = 0;
        int lng = 0; /* 0 int, 1 long, 2 long long, 3 size_t */
        if (*p == '0') {
            pad = '0';
            p++;
        }
        while (*p >= '0' && *p <= '9' && width < 64)
            width = width * 10 + (*p++ - '0');
        if (*p == 'l') {
            p++;
            lng = 1;
            if (*p == 'l') {
                p++;
                lng = 2;
            }
        } else if (*p == 'z') {
            p++;
            lng = 3;
        }
        char c = *p;
        if (c) p++;
        switch (c) {
        case '%':
            put(&o, '%');
            break;
        case 'c':
            put(&o, (char)va_arg(ap, int));
            break;
        case 's': {
            const char *s = va_arg(ap, const char *);
            put_str(&o, s ? s : "(null)");
            break;
        }
        case 'd':
        case 'i': {
            long long v = lng == 0 ? va_arg(ap, int)
                        : lng == 1 ? va_arg(ap, long)
                        : lng == 2 ? va_arg(ap, long long)
                                   : (long long)va_arg(ap, size_t);
            put_int(&o, v, width, pad);
            break;
        }
        case 'u':
        case 'x':
        case 'X': {
            unsigned long long v = lng == 0 ? va_arg(ap, unsigned)
                                 : lng == 1 ? va_arg(ap, unsigned long)
                                 : lng == 2 ? va_arg(ap, unsigned long long)
                                            : (unsigned long long)va_arg(ap, size_t);
            put_uint(&o, v, c == 'u' ? 10u : 16u, c == 'X', width, pad);
            break;
        }
        case 'p':
            put_str(&o, "0x");
            put_uint(&o, (unsigned long long)(uintptr_t)va_arg(ap, void *), 16, 0, 0, ' ');
            break;
        default:
            /* Unknown conversion: copy it and the rest literally, consume no more arguments. */
            put_str(&o, conv);
            goto done;
        }
    }
done:
    if (size > 0)
        buf[o.len < size ? o.len : size - 1] = '\0';
    return o.len;
}

size_t hz_fmt(char *buf, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    size_t n = hz_vfmt(buf, size, fmt, ap);
    va_end(ap);
    return n;
}
