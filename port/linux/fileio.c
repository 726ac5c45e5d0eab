/* Atomic file output and bounded file input (see fileio.h). */
#include "fileio.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

hz_status_t hz_out_open(hz_out_t *out, const char *path, hz_error_t *err)
{
    out->f = NULL;
    size_t n = strlen(path);
    if (n == 0 || n >= sizeof out->path)
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s: output path is empty or too long", path);
    memcpy(out->path, path, n + 1);
    memcpy(out->tmp, path, n);
    memcpy(out->tmp + n, ".tmp.XXXXXX", sizeof ".tmp.XXXXXX");
    int fd = mkstemp(out->tmp);
    if (fd < 0)
        return hz_error_set(err, HZ_E_IO, "%s: cannot create a temporary file next to it: %s", path,
                            strerror(errno));
    /* mkstemp makes 0600 files; outputs are ordinary user files. */
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    out->f = fdopen(fd, "wb");
    if (!out->f) {
        int e = errno;
        close(fd);
        unlink(out->tmp);
        return hz_error_set(err, HZ_E_IO, "%s: %s", path, strerror(e));
    }
    return HZ_OK;
}

hz_status_t hz_out_commit(hz_out_t *out, hz_error_t *err)
{
    if (!out->f)
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s: not open", out->path);
    int bad = ferror(out->f) || fflush(out->f) != 0;
    int e = errno;
    if (fclose(out->f) != 0 && !bad) {
        bad = 1;
        e = errno;
    }
    out->f = NULL;
    if (bad) {
        unlink(out->tmp);
        return hz_error_set(err, HZ_E_IO, "%s: write failed: %s", out->path, strerror(e));
    }
    if (rename(out->tmp, out->path) != 0) {
        e = errno;
        unlink(out->tmp);
        return hz_error_set(err, HZ_E_IO, "%s: cannot rename the finished file into place: %s", out->path,
                            strerror(e));
    }
    return HZ_OK;
}

void hz_out_abort(hz_out_t *out)
{
    if (out->f) {
        fclose(out->f);
        out->f = NULL;
        unlink(out->tmp);
    }
}

hz_status_t hz_file_write_atomic(const char *path, const void *data, size_t size, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    if (size && fwrite(data, 1, size, out.f) != size) {
        int e = errno;
        hz_out_abort(&out);
        return hz_error_set(err, HZ_E_IO, "%s: write failed: %s", path, strerror(e));
    }
    return hz_out_commit(&out, err);
}

hz_status_t hz_file_read(const char *path, void *buf, size_t cap, size_t *size, hz_error_t *err)
{
    *size = 0;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return hz_error_set(err, HZ_E_IO, "%s: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return hz_error_set(err, HZ_E_IO, "%s: not a regular file", path);
    }
    if ((unsigned long long)st.st_size > cap) {
        close(fd);
        return hz_error_set(err, HZ_E_NO_MEMORY, "%s: file has %lld bytes, the buffer holds %zu", path,
                            (long long)st.st_size, cap);
    }
    size_t got = 0;
    while (got < (size_t)st.st_size) {
        ssize_t r = read(fd, (char *)buf + got, (size_t)st.st_size - got);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0) {
            int e = r < 0 ? errno : EIO;
            close(fd);
            return hz_error_set(err, HZ_E_IO, "%s: read failed after %zu bytes: %s", path, got, strerror(e));
        }
        got += (size_t)r;
    }
    close(fd);
    *size = got;
    return HZ_OK;
}

hz_status_t hz_mkdirs(const char *path, hz_error_t *err)
{
    char tmp[4096];
    size_t n = strlen(path);
    if (n == 0 || n >= sizeof tmp)
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s: directory path is empty or too long", path);
    memcpy(tmp, path, n + 1);
    for (size_t i = 1; i <= n; i++) {
        if (tmp[i] == '/' || tmp[i] == '\0') {
            char c = tmp[i];
            tmp[i] = '\0';
            if (mkdir(tmp, 0777) != 0 && errno != EEXIST)
                return hz_error_set(err, HZ_E_IO, "%s: cannot create directory %s: %s", path, tmp,
                                    strerror(errno));
            tmp[i] = c;
        }
    }
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode))
        return hz_error_set(err, HZ_E_IO, "%s: exists and is not a directory", path);
    return HZ_OK;
}
