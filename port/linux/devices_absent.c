/*
 * Device ports a board leaves out (see devices.h): hz_devices_missing() says why, and every entry point of an
 * absent port is defined here to fail with that reason (HZ_E_UNSUPPORTED), so callers need no #ifdefs and a
 * build without libgpiod still links and explains itself at run time.
 */
#include <string.h>

#include "devices.h"
#include "drm_port.h"
#include "hz/config.h"

#define NO_FBDEV "this build has no fbdev port (board " HZ_BOARD_NAME " does not list 'fbdev' in BOARD_PORTS)"
#define NO_V4L2 "this build has no V4L2 port (board " HZ_BOARD_NAME " does not list 'v4l2' in BOARD_PORTS)"
#define NO_GPIO                                                                                                  \
    "this build has no GPIO port: board " HZ_BOARD_NAME " does not list 'gpio' in BOARD_PORTS, or libgpiod for " \
    "its architecture was missing when it was built (make deps installs it; the build warns when it is off)"

#define NO_DRM                                                                                                  \
    "this build has no DRM port: board " HZ_BOARD_NAME " does not list 'drm' in BOARD_PORTS, or libdrm for its " \
    "architecture was missing when it was built (make deps installs libdrm-dev; the build warns when it is off)"

const char *hz_devices_missing(const char *kind)
{
#if !defined(HZ_PORT_DRM)
    if (!strcmp(kind, "drm"))
        return NO_DRM;
#endif
#if !defined(HZ_PORT_FBDEV)
    if (!strcmp(kind, "fbdev"))
        return NO_FBDEV;
#endif
#if !defined(HZ_PORT_V4L2)
    if (!strcmp(kind, "v4l2"))
        return NO_V4L2;
#endif
#if !defined(HZ_PORT_GPIO)
    if (!strcmp(kind, "gpio"))
        return NO_GPIO;
#endif
    (void)kind;
    return "";
}

#if !defined(HZ_PORT_FBDEV)
/* Names the option the user gave; the device only when it was given (the board's default device may be a
 * placeholder such as host-sim's "file"). */
static hz_status_t absent_fbdev(const char *opt, const char *path, hz_error_t *err)
{
    if (!strcmp(path, HZ_DISPLAY_DEVICE))
        return hz_error_set(err, HZ_E_UNSUPPORTED, "%s fbdev: %s", opt, NO_FBDEV);
    return hz_error_set(err, HZ_E_UNSUPPORTED, "%s fbdev:%s: %s", opt, path, NO_FBDEV);
}

hz_status_t hz_fbdev_sink_open(hz_sink_t *s, const char *path, const hz_sysio_t *io, hz_error_t *err)
{
    (void)io;
    memset(s, 0, sizeof *s);
    return absent_fbdev("--sink", path, err);
}

hz_status_t hz_fbdev_vsource_open(hz_vsource_t *s, const char *path, const hz_sysio_t *io, hz_error_t *err)
{
    (void)io;
    memset(s, 0, sizeof *s);
    return absent_fbdev("--source", path, err);
}
#endif

#if !defined(HZ_PORT_V4L2)
hz_status_t hz_v4l2_out_open(hz_sink_t *sink, hz_vsource_t *vs, const char *path, hz_pix_fmt_t fmt, int w, int h,
                             const hz_sysio_t *io, hz_error_t *err)
{
    (void)fmt;
    (void)w;
    (void)h;
    (void)io;
    memset(sink, 0, sizeof *sink);
    if (vs)
        memset(vs, 0, sizeof *vs);
    return hz_error_set(err, HZ_E_UNSUPPORTED, "%s: %s", path, NO_V4L2);
}

hz_status_t hz_v4l2_cap_open(hz_v4l2_cap_t **cap, const char *path, hz_pix_fmt_t fmt, int w, int h,
                             const hz_sysio_t *io, hz_error_t *err)
{
    (void)fmt;
    (void)w;
    (void)h;
    (void)io;
    *cap = NULL;
    return hz_error_set(err, HZ_E_UNSUPPORTED, "%s: %s", path, NO_V4L2);
}

hz_status_t hz_v4l2_cap_next(hz_v4l2_cap_t *cap, int timeout_ms, hz_v4l2_frame_t *f, hz_error_t *err)
{
    (void)cap;
    (void)timeout_ms;
    (void)f;
    return hz_error_set(err, HZ_E_UNSUPPORTED, "%s", NO_V4L2);
}

hz_status_t hz_v4l2_cap_release(hz_v4l2_cap_t *cap, int index, hz_error_t *err)
{
    (void)cap;
    (void)index;
    return hz_error_set(err, HZ_E_UNSUPPORTED, "%s", NO_V4L2);
}

void hz_v4l2_cap_close(hz_v4l2_cap_t *cap)
{
    (void)cap;
}

void hz_v4l2_cap_size(const hz_v4l2_cap_t *cap, int *w, int *h, size_t *stride)
{
    (void)cap;
    *w = *h = 0;
    *stride = 0;
}
#endif

#if !defined(HZ_PORT_GPIO)
hz_status_t hz_gpio_vsource_open(hz_vsource_t *s, const hz_gpio_cfg_t *cfg, hz_error_t *err)
{
    memset(s, 0, sizeof *s);
    return hz_error_set(err, HZ_E_UNSUPPORTED, "GPIO chip '%s' line %d: %s", cfg->chip, cfg->line, NO_GPIO);
}

const char *hz_gpio_backend(void)
{
    return "none (" NO_GPIO ")";
}
#endif

#if !defined(HZ_PORT_DRM)
hz_status_t hz_drm_parse_spec(const char *spec, hz_drm_cfg_t *cfg, char *buf, size_t cap, hz_error_t *err)
{
    (void)spec;
    (void)buf;
    (void)cap;
    memset(cfg, 0, sizeof *cfg);
    return hz_error_set(err, HZ_E_UNSUPPORTED, "%s", NO_DRM);
}

hz_status_t hz_drm_sink_open(hz_sink_t *sink, hz_vsource_t *vs, const hz_drm_cfg_t *cfg, hz_error_t *err)
{
    (void)cfg;
    memset(sink, 0, sizeof *sink);
    if (vs)
        memset(vs, 0, sizeof *vs);
    return hz_error_set(err, HZ_E_UNSUPPORTED, "%s", NO_DRM);
}

void hz_drm_stats(const hz_sink_t *sink, hz_drm_stats_t *st)
{
    (void)sink;
    memset(st, 0, sizeof *st);
}
#endif
