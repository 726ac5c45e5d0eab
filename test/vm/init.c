/*
 * init — PID 1 of the VM test tier (make vmtest): a static AArch64 program, so the initramfs needs no shell.
 *
 * It mounts /dev, /proc, /sys and /tmp, loads the kernel modules listed in /modules/order ("file.ko [params]"
 * per line, dependencies first), sets the variables of /vm-env ("NAME=VALUE" per line), mounts the host
 * directories of /vm-mounts ("tag path": virtio-9p, read-only, at the host's path), runs every program listed
 * in /tests/list (one per line: name, then optional arguments) with a time limit, and powers the machine off.
 * The host reads the console: each program's output is framed by "HZVM-BEGIN <name>" and
 * "HZVM-END <name> <exit status> <seconds>", and "HZVM-DONE" ends the run.
 * Module failures are printed as "HZVM-MODULE-FAIL <file> <errno text>" (the device tests then fail with a
 * clear message rather than hang).
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mount.h>
#include <sys/types.h>
#include <sys/reboot.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define PROGRAM_LIMIT_S 150

static void say(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void say(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    fflush(stdout);
}

static void load_modules(void)
{
    FILE *f = fopen("/modules/order", "r");
    char line[512];
    if (!f) {
        say("HZVM-MODULE-FAIL /modules/order %s\n", strerror(errno));
        return;
    }
    while (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        if (!line[0])
            continue;
        char *params = strchr(line, ' ');
        if (params)
            *params++ = '\0';
        char path[600];
        snprintf(path, sizeof path, "/modules/%s", line);
        int fd = open(path, O_RDONLY | O_CLOEXEC);
        if (fd < 0 || syscall(SYS_finit_module, fd, params ? params : "", 0) != 0) {
            if (errno != EEXIST)
                say("HZVM-MODULE-FAIL %s %s\n", line, strerror(errno));
        }
        if (fd >= 0)
            close(fd);
    }
    fclose(f);
}

static int run(char *cmdline)
{
    char *argv[16];
    int argc = 0;
    for (char *t = strtok(cmdline, " "); t && argc < 15; t = strtok(NULL, " "))
        argv[argc++] = t;
    argv[argc] = NULL;
    if (!argc)
        return 0;
    const char *name = strrchr(argv[0], '/') ? strrchr(argv[0], '/') + 1 : argv[0];
    say("HZVM-BEGIN %s\n", name);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    pid_t pid = fork();
    if (pid == 0) {
        execv(argv[0], argv);
        printf("init: cannot run %s: %s\n", argv[0], strerror(errno));
        _exit(127);
    }
    int status = 0, rc = -1;
    for (int waited = 0;; waited++) {
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid) {
            rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            break;
        }
        if (waited >= PROGRAM_LIMIT_S * 10) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            say("init: %s did not finish within %d s: killed\n", name, PROGRAM_LIMIT_S);
            rc = 124;
            break;
        }
        struct timespec ts = { 0, 100000000 };
        nanosleep(&ts, NULL);
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    say("HZVM-END %s %d %.1f\n", name, rc, (t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) / 1e9);
    return rc;
}

/* The kernel's framebuffer console takes over every framebuffer that appears (vivid's fb0 included) and
 * draws its blinking cursor into it. Unbind it so the fbdev check sees only what hzrt wrote. */
static void unbind_fbcon(void)
{
    for (int i = 0; i < 8; i++) {
        char path[64], name[128] = "";
        snprintf(path, sizeof path, "/sys/class/vtconsole/vtcon%d/name", i);
        FILE *f = fopen(path, "r");
        if (!f)
            continue;
        if (!fgets(name, sizeof name, f))
            name[0] = '\0';
        fclose(f);
        if (!strstr(name, "frame buffer"))
            continue;
        snprintf(path, sizeof path, "/sys/class/vtconsole/vtcon%d/bind", i);
        f = fopen(path, "w");
        if (f) {
            fputs("0\n", f);
            fclose(f);
        }
    }
}

static void mkdirs(const char *path)
{
    char p[512];
    snprintf(p, sizeof p, "%s", path);
    for (char *c = p + 1; *c; c++)
        if (*c == '/') {
            *c = '\0';
            mkdir(p, 0755);
            *c = '/';
        }
    mkdir(p, 0755);
}

static void environment_and_shares(void)
{
    char line[1024];
    FILE *f = fopen("/vm-env", "r");
    while (f && fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        char *eq = strchr(line, '=');
        if (eq) {
            *eq = '\0';
            setenv(line, eq + 1, 1);
        }
    }
    if (f)
        fclose(f);
    f = fopen("/vm-mounts", "r");
    while (f && fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        char *path = strchr(line, ' ');
        if (!path)
            continue;
        *path++ = '\0';
        mkdirs(path);
        if (mount(line, path, "9p", MS_RDONLY, "trans=virtio,version=9p2000.L") != 0)
            say("HZVM-MOUNT-FAIL %s %s %s\n", line, path, strerror(errno));
    }
    if (f)
        fclose(f);
}

int main(void)
{
    mount("devtmpfs", "/dev", "devtmpfs", 0, NULL);
    mount("proc", "/proc", "proc", 0, NULL);
    mount("sysfs", "/sys", "sysfs", 0, NULL);
    mkdir("/tmp", 0777);
    mount("tmpfs", "/tmp", "tmpfs", 0, NULL);
    setenv("CMOCKA_MESSAGE_OUTPUT", "stdout", 1);
    setenv("PATH", "/bin:/tests", 1);
    chdir("/tmp");
    struct utsname u;
    uname(&u);
    say("HZVM-BOOT %s %s %s\n", u.sysname, u.release, u.machine);
    load_modules();
    unbind_fbcon();
    environment_and_shares();
    FILE *f = fopen("/tests/list", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        run(line);
    }
    if (f)
        fclose(f);
    say("HZVM-DONE\n");
    sync();
    reboot(RB_POWER_OFF);
    return 0;
}
