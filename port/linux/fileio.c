/* Atomic file output and bounded file input (see fileio.h). */
#include "fileio.h"

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
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

static volatile sig_atomic_t *defer_flag;
static const char *defer_note;
static size_t defer_len;

static void remove_tracked(int sig)
{
    volatile sig_atomic_t *flag = defer_flag;
    if (flag && !*flag && sig != SIGQUIT) {
        *flag = sig;
        if (defer_note)
            (void)!write(STDERR_FILENO, defer_note, defer_len); /* async-signal-safe */
        return;
    }
    for (int i = 0; i < HZ_OUT_TRACKED; i++)
        if (tracked_used[i])
            unlink(tracked_path[i]); /* async-signal-safe */
    signal(sig, SIG_DFL);
    raise(sig);
}

void hz_out_signals_defer(volatile sig_atomic_t *flag, const char *note)
{
    defer_note = note;
    defer_len = note ? strlen(note) : 0;
    defer_flag = flag;
}

void hz_out_die(int sig)
{
    defer_flag = NULL;
    remove_tracked(sig);
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

static hz_status_t mkdirs(const char *path, char *created, size_t cap, size_t *made_from, hz_error_t *err)
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
                if (made_from && !*made_from)
                    *made_from = i;
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
    return mkdirs(path, NULL, 0, NULL, err);
}

hz_status_t hz_out_dir_prepare(const char *path, char *created, size_t cap, hz_error_t *err)
{
    return hz_out_dir_make(path, created, cap, NULL, err);
}

void hz_out_dir_unmake(const char *path, size_t made_from)
{
    char tmp[4096];
    size_t n = strlen(path);
    if (!made_from || made_from > n || n >= sizeof tmp)
        return;
    memcpy(tmp, path, n + 1);
    for (size_t i = n; i >= made_from; i--) {
        if (tmp[i] == '/' || tmp[i] == '\0') {
            char c = tmp[i];
            tmp[i] = '\0';
            if (i > 0 && tmp[i - 1] != '/')
                rmdir(tmp); /* fails, harmlessly, once a folder holds anything */
            tmp[i] = c;
        }
        if (i == 0)
            break;
    }
}

hz_status_t hz_out_dir_make(const char *path, char *created, size_t cap, size_t *made_from, hz_error_t *err)
{
    if (created && cap)
        created[0] = '\0';
    if (made_from)
        *made_from = 0;
    hz_status_t s = mkdirs(path, created, cap, made_from, err);
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

/* ---- the outputs of a run, checked before it ---- */

void hz_outs_init(hz_outs_t *o)
{
    memset(o, 0, sizeof *o);
}

void hz_outs_output(hz_outs_t *o, const char *path, const char *what)
{
    if (o->n_out < HZ_OUTS_MAX) {
        snprintf(o->out[o->n_out].path, sizeof o->out[0].path, "%s", path);
        o->out[o->n_out++].what = what;
    }
}

void hz_outs_input(hz_outs_t *o, const char *path, const char *what)
{
    if (o->n_in < (int)(sizeof o->in / sizeof o->in[0])) {
        snprintf(o->in[o->n_in].path, sizeof o->in[0].path, "%s", path);
        o->in[o->n_in++].what = what;
    }
}

/* path's folder ("." for a bare name) into dir; returns the name after it. */
static const char *split_dir(const char *path, char *dir, size_t cap)
{
    const char *slash = strrchr(path, '/');
    if (!slash) {
        snprintf(dir, cap, ".");
        return path;
    }
    size_t n = (size_t)(slash - path);
    if (n == 0)
        n = 1; /* "/name": the root */
    snprintf(dir, cap, "%.*s", (int)n, path);
    return slash + 1;
}

hz_status_t hz_outs_check(const hz_outs_t *o, hz_error_t *err)
{
    struct stat in_st[4];
    bool in_ok[4];
    for (int k = 0; k < o->n_in; k++)
        in_ok[k] = stat(o->in[k].path, &in_st[k]) == 0;
    struct stat dir_st[HZ_OUTS_MAX];
    for (int i = 0; i < o->n_out; i++) {
        const char *path = o->out[i].path, *what = o->out[i].what;
        char dir[4096];
        const char *name = split_dir(path, dir, sizeof dir);
        if (!*name || !strcmp(name, ".") || !strcmp(name, ".."))
            return hz_error_set(err, HZ_E_IO, "%s: %s names a folder, not a file", path, what);
        if (stat(dir, &dir_st[i]) != 0)
            return hz_error_set(err, HZ_E_IO, "%s: %s: the folder %s: %s", path, what, dir, strerror(errno));
        if (!S_ISDIR(dir_st[i].st_mode))
            return hz_error_set(err, HZ_E_IO, "%s: %s: %s is not a folder", path, what, dir);
        struct stat st;
        if (stat(path, &st) == 0) {
            if (S_ISDIR(st.st_mode))
                return hz_error_set(err, HZ_E_IO, "%s: %s is a folder; it needs a file name", path, what);
            for (int k = 0; k < o->n_in; k++)
                if (in_ok[k] && st.st_dev == in_st[k].st_dev && st.st_ino == in_st[k].st_ino)
                    return hz_error_set(err, HZ_E_INVALID_ARG, "%s: %s is %s (%s), an input of this run: a run "
                                        "never writes over its inputs; choose another output", path, what,
                                        o->in[k].what, o->in[k].path);
        }
        for (int j = 0; j < i; j++) {
            char dj[4096];
            const char *nj = split_dir(o->out[j].path, dj, sizeof dj);
            if (dir_st[j].st_dev == dir_st[i].st_dev && dir_st[j].st_ino == dir_st[i].st_ino && !strcmp(nj, name))
                return hz_error_set(err, HZ_E_INVALID_ARG, "%s: %s is also %s (%s): give one of them another name",
                                    path, what, o->out[j].what, o->out[j].path);
        }
        /* a real file, not access(2): also read-only mounts and ACLs */
        bool probed = false;
        for (int j = 0; j < i && !probed; j++)
            probed = dir_st[j].st_dev == dir_st[i].st_dev && dir_st[j].st_ino == dir_st[i].st_ino;
        if (!probed) {
            char probe[4096 + 32];
            if (snprintf(probe, sizeof probe, "%s/.hz-probe.XXXXXX", dir) >= (int)sizeof probe)
                return hz_error_set(err, HZ_E_INVALID_ARG, "%s: path too long", path);
            int fd = mkstemp(probe);
            if (fd < 0)
                return hz_error_set(err, HZ_E_IO, "%s: %s: the folder %s is not writable: %s", path, what, dir,
                                    strerror(errno));
            close(fd);
            unlink(probe);
        }
    }
    return HZ_OK;
}
