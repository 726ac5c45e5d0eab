/* Real system calls behind the sysio table (see sysio.h). */
#include "sysio.h"

#include <errno.h>
#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

static int sys_open(const char *path, int flags)
{
    return open(path, flags);
}

static int sys_ioctl(int fd, unsigned long request, void *arg)
{
    return ioctl(fd, request, arg);
}

const hz_sysio_t hz_sysio_linux = { sys_open, close, sys_ioctl, mmap, munmap, poll };

int hz_sysio_ioctl(const hz_sysio_t *io, int fd, unsigned long request, void *arg)
{
    int r;
    do
        r = io->ioctl(fd, request, arg);
    while (r < 0 && errno == EINTR);
    return r;
}
