/* Atomic file output and bounded file input (see fileio.h). */
#include "fileio.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Temporaries the signal handler removes: paths copied here (an hz_out_t may be moved by its owner), a slot is
 * published by setting its flag after the path is complete. */
static char tracked_path[HZ_OUT_TRACKED][4096 + 16];
static volatile sig_atomic_t tracked_used[HZ_OUT_TRACKED];

static int track(const char *tmp)
{
    for (int i = 0; i < HZ_OUT_TRACKED; i++)
        if (!tracked_used[i]) {
            memcpy(tracked_path[i], tmp, strlen(tmp) + 1);
            tracked_used[i] = 1;
            return i;
        }
    return -1;
}

static void untrack(hz_out_t *out)
{
    if (out->slot >= 0 && out->slot < HZ_OUT_TRACKED)
        tracked_used[out->slot] = 0;
    out->slot = -1;
}

static void remove_tracked(int sig)
{
    for (int i = 0; i < HZ_OUT_TRACKED; i++)
        if (tracked_used[i])
            unlink(tracked_path[i]); /* async-signal-safe */
    signal(sig, SIG_DFL);
    raise(sig);
}

void hz_out_remove_on_signals(void)
{
    static const int sigs[] = { SIGINT, SIGTERM, SIGHUP, SIGQUIT };
    for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
        struct sigaction sa, old;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = remove_tracked;
        sigemptyset(&sa.sa_mask);
        /* A signal ignored by whoever started us (nohup, a shell's background job) stays ignored. */
        if (sigaction(sigs[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN)
            continue;
        sigaction(sigs[i], &sa, NULL);
    }
}

hz_status_t hz_out_open(hz_out_t *out, const char *path, hz_error_t *err)
{
    out->f = NULL;
    out->slot = -1;
    size_t n = strlen(path);
    if (n == 0 || n >= sizeof out->path)
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s: output path is empty or too long", path);
    memcpy(out->path, path, n + 1);
    memcpy(out->tmp, path, n);
    memcpy(out->tmp + n, ".tmp.XXXXXX", sizeof ".tmp.XXXXXX");
    /* Signals are held while the temporary exists but is not yet tracked. */
    sigset_t all, old;
    sigfillset(&all);
    sigprocmask(SIG_BLOCK, &all, &old);
    int fd = mkstemp(out->tmp);
    if (fd >= 0)
        out->slot = track(out->tmp);
    int e0 = errno;
    sigprocmask(SIG_SETMASK, &old, NULL);
    if (fd < 0)
        return hz_error_set(err, HZ_E_IO, "%s: cannot create a temporary file next to it: %s", path,
                            strerror(e0));
    /* mkstemp makes 0600 files; outputs are ordinary user files. */
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    out->f = fdopen(fd, "wb");
    if (!out->f) {
        int e = errno;
        close(fd);
        unlink(out->tmp);
        untrack(out);
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
        untrack(out);
        return hz_error_set(err, HZ_E_IO, "%s: write failed: %s", out->path, strerror(e));
    }
    int renamed = rename(out->tmp, out->path) == 0;
    e = errno;
    untrack(out);
    if (!renamed) {
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
        untrack(out);
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

static hz_status_t mkdirs(const char *path, char *created, size_t cap, hz_error_t *err)
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
            if (mkdir(tmp, 0777) == 0) {
                size_t used = created ? strlen(created) : 0;
                if (created && used + strlen(tmp) + 3 < cap)
                    snprintf(created + used, cap - used, "%s%s", used ? ", " : "", tmp);
            } else if (errno != EEXIST) {
                return hz_error_set(err, HZ_E_IO, "%s: cannot create directory %s: %s", path, tmp,
                                    strerror(errno));
            }
            tmp[i] = c;
        }
    }
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode))
        return hz_error_set(err, HZ_E_IO, "%s: exists and is not a directory", path);
    return HZ_OK;
}

hz_status_t hz_mkdirs(const char *path, hz_error_t *err)
{
    return mkdirs(path, NULL, 0, err);
}

hz_status_t hz_out_dir_prepare(const char *path, char *created, size_t cap, hz_error_t *err)
{
    if (created && cap)
        created[0] = '\0';
    hz_status_t s = mkdirs(path, created, cap, err);
    if (s != HZ_OK)
        return s;
    /* A real file, not access(2): that also catches read-only mounts and ACLs access() may not see. */
    char probe[4096 + 32];
    if (snprintf(probe, sizeof probe, "%s/.hz-probe.XXXXXX", path) >= (int)sizeof probe)
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s: directory path is too long", path);
    int fd = mkstemp(probe);
    if (fd < 0)
        return hz_error_set(err, HZ_E_IO, "%s: the output folder is not writable: %s", path, strerror(errno));
    close(fd);
    unlink(probe);
    return HZ_OK;
}
