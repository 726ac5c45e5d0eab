/* Scene opening for the Linux port (see scenefile.h). */
#include "scenefile.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hz/builtin.h"
#include "phase.h"

hz_status_t hz_scenefile_read(const char *path, hz_arena_t *arena, const void **data, size_t *size,
                              hz_error_t *err)
{
    /* O_NONBLOCK: opening a FIFO must not wait for a writer (it is refused below, as every non-regular file) */
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0)
        return hz_error_set(err, HZ_E_IO, "%s: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return hz_error_set(err, HZ_E_IO, "%s: not a regular file", path);
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    size_t have = hz_arena_available(arena, 64);
    if ((unsigned long long)st.st_size > have) {
        close(fd);
        return hz_error_set(err, HZ_E_NO_MEMORY, "%s: arena '%s': needs %lld bytes, has %zu", path, arena->name,
                            (long long)st.st_size, have);
    }
    hz_arena_mark_t mark = hz_arena_mark(arena);
    uint8_t *buf = hz_arena_alloc(arena, (size_t)st.st_size, 64);
    if (!buf && st.st_size) {
        close(fd);
        return hz_arena_error(arena, err);
    }
    size_t got = 0;
    hz_phase_t prog;
    hz_phase_begin(&prog, false, "reading %s (%.1f MB)", path, (double)st.st_size * 1e-6);
    while (got < (size_t)st.st_size) {
        /* In pieces, so a large scene shows its progress. */
        size_t want = (size_t)st.st_size - got;
        ssize_t r = read(fd, buf + got, want < ((size_t)8 << 20) ? want : ((size_t)8 << 20));
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0) {
            int e = r < 0 ? errno : EIO;
            hz_phase_end(&prog);
            close(fd);
            hz_arena_reset(arena, mark);
            return hz_error_set(err, HZ_E_IO, "%s: read failed after %zu of %lld bytes: %s", path, got,
                                (long long)st.st_size, r < 0 ? strerror(e) : "file shrank");
        }
        got += (size_t)r;
        hz_phase_update(&prog, (float)got / (float)st.st_size);
    }
    hz_phase_end(&prog);
    close(fd);
    *data = buf;
    *size = got;
    return HZ_OK;
}

hz_status_t hz_scenefile_open(const char *name, hz_pools_t *pools, hz_scene_t *scene, hz_error_t *err)
{
    const void *image = NULL;
    size_t size = 0;
    hz_arena_mark_t mark = hz_arena_mark(&pools->scene);
    hz_status_t s;
    if (!strcmp(name, "builtin"))
        s = hz_builtin_scene_image(&pools->scene, &pools->frame, &image, &size, err);
    else
        s = hz_scenefile_read(name, &pools->scene, &image, &size, err);
    if (s != HZ_OK)
        return s;
    s = hz_scene_load(scene, image, size, &pools->scene, err);
    if (s != HZ_OK) {
        hz_error_prefix(err, name);
        hz_arena_reset(&pools->scene, mark);
    }
    return s;
}
