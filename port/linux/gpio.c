/*
 * GPIO v-sync capture through libgpiod (see devices.h). Built against the libgpiod the Makefile found:
 * HZ_LIBGPIOD_MAJOR 1 (the v1 API, Debian 12's 1.6) or 2 (libgpiod 2.x: request/settings objects, edge-event
 * buffers with kernel sequence numbers). Both request both edges so the loop sees pulse widths; libgpiod
 * allocates its handles once here at open, nothing per edge.
 */
#include <dirent.h>
#include <errno.h>
#include <gpiod.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "clock.h"
#include "devices.h"

#ifndef HZ_LIBGPIOD_MAJOR
#error "the Makefile sets HZ_LIBGPIOD_MAJOR from the libgpiod it found"
#endif
#ifndef HZ_LIBGPIOD_VERSION
#define HZ_LIBGPIOD_VERSION "?"
#endif

#define POOL 2
#define EVENTS 64
#define CONSUMER "hzrt-vsync"

const char *hz_gpio_backend(void)
{
    return HZ_LIBGPIOD_MAJOR == 1 ? "libgpiod " HZ_LIBGPIOD_VERSION " (v1 API)"
                                  : "libgpiod " HZ_LIBGPIOD_VERSION " (v2 API)";
}

static hz_status_t chip_error(const char *chip, int e, hz_error_t *err)
{
    if (e == ENOENT || e == ENODEV)
        return hz_error_set(err, HZ_E_DEVICE, "GPIO chip '%s': no such chip (gpiodetect lists name and label of each)",
                            chip);
    if (e == ENOTTY)
        return hz_error_set(err, HZ_E_DEVICE, "GPIO chip '%s': not a GPIO character device", chip);
    if (e == EACCES || e == EPERM)
        return hz_error_set(err, HZ_E_DEVICE, "GPIO chip '%s': permission denied (run as root or join group 'gpio')",
                            chip);
    return hz_error_set(err, HZ_E_DEVICE, "GPIO chip '%s': cannot open: %s", chip, strerror(e));
}

#if HZ_LIBGPIOD_MAJOR == 1

typedef struct gpio_impl {
    int used;
    struct gpiod_chip *chip;
    struct gpiod_line *line;
    struct gpiod_line_event ev[EVENTS];
    int ev_n, ev_i;
    char desc[96];
} gpio_impl_t;

static gpio_impl_t pool[POOL];

static hz_status_t gpio_next(hz_vsource_t *s, int64_t deadline, hz_edge_t *e, int *result, hz_error_t *err)
{
    gpio_impl_t *im = s->impl;
    while (im->ev_i == im->ev_n) {
        int64_t left = deadline - hz_clock_ns();
        if (left < 0)
            left = 0;
        struct timespec ts = { (time_t)(left / 1000000000), (long)(left % 1000000000) };
        int r = gpiod_line_event_wait(im->line, &ts);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0)
            return hz_error_set(err, HZ_E_DEVICE, "%s: waiting for edge events: %s", im->desc, strerror(errno));
        if (r == 0) {
            *result = HZ_VS_TIMEOUT;
            return HZ_OK;
        }
        int n = gpiod_line_event_read_multiple(im->line, im->ev, EVENTS);
        if (n < 0)
            return hz_error_set(err, HZ_E_DEVICE, "%s: reading edge events: %s", im->desc, strerror(errno));
        im->ev_n = n;
        im->ev_i = 0;
    }
    const struct gpiod_line_event *ev = &im->ev[im->ev_i++];
    e->t_ns = (int64_t)ev->ts.tv_sec * 1000000000 + ev->ts.tv_nsec;
    e->level = ev->event_type == GPIOD_LINE_EVENT_RISING_EDGE;
    e->frame_id = -1;
    *result = HZ_VS_EDGE;
    return HZ_OK;
}

static void gpio_close(hz_vsource_t *s)
{
    gpio_impl_t *im = s->impl;
    if (!im)
        return;
    if (im->line)
        gpiod_line_release(im->line);
    if (im->chip)
        gpiod_chip_close(im->chip);
    im->used = 0;
    s->impl = NULL;
}

hz_status_t hz_gpio_vsource_open(hz_vsource_t *s, const hz_gpio_cfg_t *cfg, hz_error_t *err)
{
    memset(s, 0, sizeof *s);
    gpio_impl_t *im = NULL;
    for (int i = 0; i < POOL && !im; i++)
        if (!pool[i].used)
            im = &pool[i];
    if (!im)
        return hz_error_set(err, HZ_E_NO_MEMORY, "gpio: more than %d lines open", POOL);
    memset(im, 0, sizeof *im);
    errno = 0;
    im->chip = gpiod_chip_open_lookup(cfg->chip);
    if (!im->chip)
        return chip_error(cfg->chip, errno ? errno : ENOENT, err);
    im->used = 1;
    s->impl = im;
    s->close = gpio_close;
    unsigned lines = gpiod_chip_num_lines(im->chip);
    snprintf(im->desc, sizeof im->desc, "GPIO %s (%s) line %d", gpiod_chip_name(im->chip), gpiod_chip_label(im->chip),
             cfg->line);
    if (cfg->line < 0 || (unsigned)cfg->line >= lines) {
        hz_status_t st = hz_error_set(err, HZ_E_DEVICE, "GPIO chip '%s' (%s) has lines 0..%u, not %d", cfg->chip,
                                      gpiod_chip_label(im->chip), lines - 1, cfg->line);
        gpio_close(s);
        return st;
    }
    im->line = gpiod_chip_get_line(im->chip, (unsigned)cfg->line);
    if (!im->line) {
        hz_status_t st = hz_error_set(err, HZ_E_DEVICE, "%s: %s", im->desc, strerror(errno));
        gpio_close(s);
        return st;
    }
    struct gpiod_line_request_config rc;
    rc.consumer = cfg->consumer ? cfg->consumer : CONSUMER;
    rc.request_type = cfg->one_edge > 0   ? GPIOD_LINE_REQUEST_EVENT_RISING_EDGE
                      : cfg->one_edge < 0 ? GPIOD_LINE_REQUEST_EVENT_FALLING_EDGE
                                          : GPIOD_LINE_REQUEST_EVENT_BOTH_EDGES;
    rc.flags = cfg->active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
    if (gpiod_line_request(im->line, &rc, 0) < 0) {
        int e = errno;
        hz_status_t st;
        if (e == EBUSY) {
            gpiod_line_update(im->line);
            const char *holder = gpiod_line_consumer(im->line);
            st = hz_error_set(err, HZ_E_DEVICE, "%s is busy: held by '%s' (free it, or pick another line)", im->desc,
                              holder && *holder ? holder : "an unnamed consumer");
        } else {
            st = hz_error_set(err, HZ_E_DEVICE, "%s: cannot request edge events: %s", im->desc, strerror(e));
        }
        im->line = NULL; /* not requested: nothing to release */
        gpio_close(s);
        return st;
    }
    s->live = 1;
    s->both_levels = !cfg->one_edge;
    s->next = gpio_next;
    snprintf(s->name, sizeof s->name, "%s%s, %s, %s", im->desc, cfg->active_low ? " active-low" : "",
             cfg->one_edge > 0 ? "rising edges" : cfg->one_edge < 0 ? "falling edges" : "both edges",
             hz_gpio_backend());
    return HZ_OK;
}

#else /* libgpiod 2.x */

typedef struct gpio_impl {
    int used;
    struct gpiod_chip *chip;
    struct gpiod_line_request *req;
    struct gpiod_edge_event_buffer *buf;
    int ev_n, ev_i;
    unsigned long last_seqno;
    int have_seqno;
    char desc[96];
} gpio_impl_t;

static gpio_impl_t pool[POOL];

static hz_status_t gpio_next(hz_vsource_t *s, int64_t deadline, hz_edge_t *e, int *result, hz_error_t *err)
{
    gpio_impl_t *im = s->impl;
    while (im->ev_i == im->ev_n) {
        int64_t left = deadline - hz_clock_ns();
        if (left < 0)
            left = 0;
        int r = gpiod_line_request_wait_edge_events(im->req, left);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0)
            return hz_error_set(err, HZ_E_DEVICE, "%s: waiting for edge events: %s", im->desc, strerror(errno));
        if (r == 0) {
            *result = HZ_VS_TIMEOUT;
            return HZ_OK;
        }
        int n = gpiod_line_request_read_edge_events(im->req, im->buf, EVENTS);
        if (n < 0)
            return hz_error_set(err, HZ_E_DEVICE, "%s: reading edge events: %s", im->desc, strerror(errno));
        im->ev_n = n;
        im->ev_i = 0;
    }
    struct gpiod_edge_event *ev = gpiod_edge_event_buffer_get_event(im->buf, (unsigned long)im->ev_i++);
    unsigned long seq = gpiod_edge_event_get_line_seqno(ev);
    /* The kernel numbers each line's events: a gap means its FIFO overflowed and dropped some. */
    if (im->have_seqno && seq > im->last_seqno + 1)
        s->dropped += seq - im->last_seqno - 1;
    im->last_seqno = seq;
    im->have_seqno = 1;
    e->t_ns = (int64_t)gpiod_edge_event_get_timestamp_ns(ev);
    e->level = gpiod_edge_event_get_event_type(ev) == GPIOD_EDGE_EVENT_RISING_EDGE;
    e->frame_id = -1;
    *result = HZ_VS_EDGE;
    return HZ_OK;
}

static void gpio_close(hz_vsource_t *s)
{
    gpio_impl_t *im = s->impl;
    if (!im)
        return;
    if (im->buf)
        gpiod_edge_event_buffer_free(im->buf);
    if (im->req)
        gpiod_line_request_release(im->req);
    if (im->chip)
        gpiod_chip_close(im->chip);
    im->used = 0;
    s->impl = NULL;
}

/* libgpiod 2 opens chips by path only: accept a path, a name (gpiochipN), a number or a label. */
static struct gpiod_chip *open_chip(const char *want, int *err_out)
{
    char path[300];
    int e = ENOENT;
    if (want[0] == '/') {
        struct gpiod_chip *c = gpiod_chip_open(want);
        *err_out = c ? 0 : errno;
        return c;
    }
    if (want[0] >= '0' && want[0] <= '9')
        snprintf(path, sizeof path, "/dev/gpiochip%s", want);
    else
        snprintf(path, sizeof path, "/dev/%s", want);
    struct gpiod_chip *c = gpiod_chip_open(path);
    if (c)
        return c;
    if (errno != ENOENT)
        e = errno;
    DIR *d = opendir("/dev");
    struct dirent *de;
    while (d && (de = readdir(d)) != NULL) {
        if (strncmp(de->d_name, "gpiochip", 8))
            continue;
        snprintf(path, sizeof path, "/dev/%s", de->d_name);
        c = gpiod_chip_open(path);
        if (!c)
            continue;
        struct gpiod_chip_info *info = gpiod_chip_get_info(c);
        int match = info && !strcmp(gpiod_chip_info_get_label(info), want);
        if (info)
            gpiod_chip_info_free(info);
        if (match)
            break;
        gpiod_chip_close(c);
        c = NULL;
    }
    if (d)
        closedir(d);
    *err_out = c ? 0 : e;
    return c;
}

hz_status_t hz_gpio_vsource_open(hz_vsource_t *s, const hz_gpio_cfg_t *cfg, hz_error_t *err)
{
    memset(s, 0, sizeof *s);
    gpio_impl_t *im = NULL;
    for (int i = 0; i < POOL && !im; i++)
        if (!pool[i].used)
            im = &pool[i];
    if (!im)
        return hz_error_set(err, HZ_E_NO_MEMORY, "gpio: more than %d lines open", POOL);
    memset(im, 0, sizeof *im);
    int e = 0;
    im->chip = open_chip(cfg->chip, &e);
    if (!im->chip)
        return chip_error(cfg->chip, e ? e : ENOENT, err);
    im->used = 1;
    s->impl = im;
    s->close = gpio_close;
    struct gpiod_chip_info *info = gpiod_chip_get_info(im->chip);
    size_t lines = info ? gpiod_chip_info_get_num_lines(info) : 0;
    snprintf(im->desc, sizeof im->desc, "GPIO %s (%s) line %d", info ? gpiod_chip_info_get_name(info) : cfg->chip,
             info ? gpiod_chip_info_get_label(info) : "?", cfg->line);
    if (info)
        gpiod_chip_info_free(info);
    if (cfg->line < 0 || (size_t)cfg->line >= lines) {
        hz_status_t st = hz_error_set(err, HZ_E_DEVICE, "GPIO chip '%s' has lines 0..%zu, not %d", cfg->chip,
                                      lines ? lines - 1 : 0, cfg->line);
        gpio_close(s);
        return st;
    }
    unsigned int offset = (unsigned int)cfg->line;
    struct gpiod_line_settings *ls = gpiod_line_settings_new();
    struct gpiod_line_config *lc = gpiod_line_config_new();
    struct gpiod_request_config *rc = gpiod_request_config_new();
    hz_status_t st = HZ_OK;
    if (!ls || !lc || !rc) {
        st = hz_error_set(err, HZ_E_NO_MEMORY, "%s: libgpiod could not allocate its request", im->desc);
    } else {
        gpiod_line_settings_set_direction(ls, GPIOD_LINE_DIRECTION_INPUT);
        gpiod_line_settings_set_edge_detection(ls, cfg->one_edge > 0   ? GPIOD_LINE_EDGE_RISING
                                                   : cfg->one_edge < 0 ? GPIOD_LINE_EDGE_FALLING
                                                                       : GPIOD_LINE_EDGE_BOTH);
        gpiod_line_settings_set_active_low(ls, cfg->active_low ? true : false);
        gpiod_line_settings_set_event_clock(ls, GPIOD_LINE_CLOCK_MONOTONIC);
        gpiod_request_config_set_consumer(rc, cfg->consumer ? cfg->consumer : CONSUMER);
        gpiod_request_config_set_event_buffer_size(rc, EVENTS);
        if (gpiod_line_config_add_line_settings(lc, &offset, 1, ls) < 0) {
            st = hz_error_set(err, HZ_E_DEVICE, "%s: %s", im->desc, strerror(errno));
        } else {
            im->req = gpiod_chip_request_lines(im->chip, rc, lc);
            if (!im->req) {
                int re = errno;
                if (re == EBUSY) {
                    struct gpiod_line_info *li = gpiod_chip_get_line_info(im->chip, offset);
                    const char *holder = li ? gpiod_line_info_get_consumer(li) : NULL;
                    st = hz_error_set(err, HZ_E_DEVICE, "%s is busy: held by '%s' (free it, or pick another line)",
                                      im->desc, holder && *holder ? holder : "an unnamed consumer");
                    if (li)
                        gpiod_line_info_free(li);
                } else {
                    st = hz_error_set(err, HZ_E_DEVICE, "%s: cannot request edge events: %s", im->desc, strerror(re));
                }
            }
        }
    }
    if (ls)
        gpiod_line_settings_free(ls);
    if (lc)
        gpiod_line_config_free(lc);
    if (rc)
        gpiod_request_config_free(rc);
    if (st == HZ_OK && !(im->buf = gpiod_edge_event_buffer_new(EVENTS)))
        st = hz_error_set(err, HZ_E_NO_MEMORY, "%s: libgpiod could not allocate the event buffer", im->desc);
    if (st != HZ_OK) {
        gpio_close(s);
        return st;
    }
    s->live = 1;
    s->both_levels = !cfg->one_edge;
    s->next = gpio_next;
    snprintf(s->name, sizeof s->name, "%s%s, %s, %s", im->desc, cfg->active_low ? " active-low" : "",
             cfg->one_edge > 0 ? "rising edges" : cfg->one_edge < 0 ? "falling edges" : "both edges",
             hz_gpio_backend());
    return HZ_OK;
}

#endif
