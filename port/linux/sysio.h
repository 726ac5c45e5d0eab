/*
 * sysio.h — the system calls the display and v-sync ports make, behind a table so tests can stand in a fake
 * device (a framebuffer, a V4L2 output) on any machine.
 *
 * Contract: hz_sysio_linux forwards to the real calls; every function has the POSIX signature and reports
 * errors through errno like the real one. A port takes `const hz_sysio_t *io` (NULL means hz_sysio_linux).
 */
#ifndef HZ_PORT_SYSIO_H
#define HZ_PORT_SYSIO_H

#include <poll.h>
#include <stddef.h>
#include <sys/types.h>

typedef struct hz_sysio {
    int (*open)(const char *path, int flags);
    int (*close)(int fd);
    int (*ioctl)(int fd, unsigned long request, void *arg);
    void *(*mmap)(void *addr, size_t len, int prot, int flags, int fd, off_t offset);
    int (*munmap)(void *addr, size_t len);
    int (*poll)(struct pollfd *fds, nfds_t n, int timeout_ms);
} hz_sysio_t;

extern const hz_sysio_t hz_sysio_linux;

/* ioctl retried on EINTR. */
int hz_sysio_ioctl(const hz_sysio_t *io, int fd, unsigned long request, void *arg);

#endif
