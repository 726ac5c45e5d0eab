/*
 * The stability suite's runner: every case of every stage in a child process with a time limit, one line per
 * case, a CSV (case, checks, result, nonfinite, max_error, status), the notes beside it, a .res line for
 * test/summary.sh, and the closing `N passed, N failed` (cases).
 *
 *   hzstab [--full] [--only SUBSTR] [--csv FILE] [--notes FILE] [--res FILE --label L] [--timeout S] [--list]
 *
 * Exit status 0 when every case passed, 1 otherwise (2 for a usage error).
 */
#include <errno.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "stab.h"

extern const stab_stage_t stab_stage_geometry, stab_stage_rays, stab_stage_motion, stab_stage_transparency,
    stab_stage_recon, stab_stage_timing, stab_stage_fixed, stab_stage_memory;
extern const stab_stage_t stab_stage_blur, stab_stage_dither, stab_stage_adaptive;

/* Report order: the data flow of a frame, then the numeric kernels and memory. */
static const stab_stage_t *const stages[] = {
    &stab_stage_geometry, &stab_stage_rays,   &stab_stage_motion, &stab_stage_transparency,
    &stab_stage_recon,    &stab_stage_timing, &stab_stage_fixed,  &stab_stage_memory,
    /* the techniques: motion blur and the 64-bit clock, stochastic transparency, adaptive supersampling */
    &stab_stage_blur,     &stab_stage_dither, &stab_stage_adaptive,
};

void stab_failf(stab_result_t *r, const char *file, int line, const char *fmt, ...)
{
    if (r->fail[0])
        return;
    const char *base = strrchr(file, '/');
    int n = snprintf(r->fail, sizeof r->fail, "%s:%d: ", base ? base + 1 : file, line);
    va_list ap;
    va_start(ap, fmt);
    if (n > 0 && (size_t)n < sizeof r->fail)
        vsnprintf(r->fail + n, sizeof r->fail - (size_t)n, fmt, ap);
    va_end(ap);
}

void stab_note(stab_result_t *r, const char *fmt, ...)
{
    size_t n = strlen(r->note);
    if (n && n + 2 < sizeof r->note)
        memcpy(r->note + n, "; ", 3), n += 2;
    va_list ap;
    va_start(ap, fmt);
    if (n < sizeof r->note)
        vsnprintf(r->note + n, sizeof r->note - n, fmt, ap);
    va_end(ap);
}

uint64_t stab_count_nonfinite(stab_result_t *r, const float *v, size_t n)
{
    uint64_t c = 0;
    for (size_t i = 0; i < n; i++)
        c += !isfinite(v[i]);
    r->nonfinite += c;
    return c;
}

void stab_error(stab_result_t *r, double e)
{
    if (!isfinite(e)) {
        r->nonfinite++;
        return;
    }
    if (isnan(r->max_error) || e > r->max_error)
        r->max_error = e;
}

/* CSV and notes fields carry no commas, tabs or newlines. */
static void clean(char *s)
{
    for (; *s; s++)
        if (*s == ',' || *s == '\n' || *s == '\r' || *s == '\t')
            *s = ';';
}

static int run_case(const stab_case_t *c, int full, unsigned timeout_s, stab_result_t *out, char *result,
                    size_t rsize)
{
    int fd[2];
    memset(out, 0, sizeof *out);
    out->max_error = NAN;
    out->status = -1;
    out->full = full;
    if (pipe(fd) != 0) {
        snprintf(result, rsize, "FAIL: pipe: %s", strerror(errno));
        return 0;
    }
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0) {
        snprintf(result, rsize, "FAIL: fork: %s", strerror(errno));
        close(fd[0]), close(fd[1]);
        return 0;
    }
    if (pid == 0) {
        close(fd[0]);
        alarm(timeout_s);
        stab_result_t r = *out;
        c->run(&r);
        ssize_t w = write(fd[1], &r, sizeof r);
        _exit(w == (ssize_t)sizeof r ? 0 : 3);
    }
    close(fd[1]);
    stab_result_t r;
    size_t got = 0;
    while (got < sizeof r) {
        ssize_t n = read(fd[0], (char *)&r + got, sizeof r - got);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        got += (size_t)n;
    }
    close(fd[0]);
    int st = 0;
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR)
        ;
    if (WIFSIGNALED(st)) {
        int sig = WTERMSIG(st);
        snprintf(result, rsize, "FAIL: %s (signal %d)", sig == SIGALRM ? "hang: over the time limit" : "crash",
                 sig);
        return 0;
    }
    if (!WIFEXITED(st) || WEXITSTATUS(st) != 0 || got != sizeof r) {
        snprintf(result, rsize, "FAIL: exit status %d without a result (sanitizer report in the log?)",
                 WIFEXITED(st) ? WEXITSTATUS(st) : -1);
        return 0;
    }
    r.note[sizeof r.note - 1] = 0;
    r.fail[sizeof r.fail - 1] = 0;
    *out = r;
    if (r.fail[0]) {
        snprintf(result, rsize, "FAIL: %s", r.fail);
        return 0;
    }
    if (r.nonfinite) {
        snprintf(result, rsize, "FAIL: %llu non-finite values", (unsigned long long)r.nonfinite);
        return 0;
    }
    snprintf(result, rsize, "pass");
    return 1;
}

static int usage(void)
{
    fprintf(stderr, "usage: hzstab [--full] [--only SUBSTR] [--csv FILE] [--notes FILE] [--res FILE --label L] "
                    "[--timeout SECONDS] [--list]\n");
    return 2;
}

int main(int argc, char **argv)
{
    int full = 0, list = 0;
    const char *only = NULL, *csv_path = NULL, *notes_path = NULL, *res_path = NULL, *label = "stability";
    unsigned timeout_s = 300;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--full"))
            full = 1;
        else if (!strcmp(a, "--list"))
            list = 1;
        else if (i + 1 < argc && !strcmp(a, "--only"))
            only = argv[++i];
        else if (i + 1 < argc && !strcmp(a, "--csv"))
            csv_path = argv[++i];
        else if (i + 1 < argc && !strcmp(a, "--notes"))
            notes_path = argv[++i];
        else if (i + 1 < argc && !strcmp(a, "--res"))
            res_path = argv[++i];
        else if (i + 1 < argc && !strcmp(a, "--label"))
            label = argv[++i];
        else if (i + 1 < argc && !strcmp(a, "--timeout")) {
            char *end;
            unsigned long v = strtoul(argv[++i], &end, 10);
            if (*end || v == 0 || v > 86400) {
                fprintf(stderr, "hzstab: --timeout '%s': want whole seconds, 1..86400\n", argv[i]);
                return 2;
            }
            timeout_s = (unsigned)v;
        } else
            return usage();
    }
    FILE *csv = NULL, *notes = NULL;
    if (csv_path && !(csv = fopen(csv_path, "w"))) {
        fprintf(stderr, "hzstab: %s: %s\n", csv_path, strerror(errno));
        return 2;
    }
    if (notes_path && !(notes = fopen(notes_path, "w"))) {
        fprintf(stderr, "hzstab: %s: %s\n", notes_path, strerror(errno));
        return 2;
    }
    if (csv)
        fprintf(csv, "case,checks,result,nonfinite,max_error,status\n");
    unsigned passed = 0, failed = 0;
    for (size_t s = 0; s < sizeof stages / sizeof stages[0]; s++)
        for (size_t i = 0; i < stages[s]->count; i++) {
            const stab_case_t *c = &stages[s]->cases[i];
            char name[128], result[400], checks[200];
            snprintf(name, sizeof name, "%s/%s", stages[s]->name, c->name);
            if (only && !strstr(name, only))
                continue;
            if ((c->flags & STAB_FULL_ONLY) && !full)
                continue;
            if (list) {
                printf("%-44s %s\n", name, c->checks);
                continue;
            }
            stab_result_t r;
            struct timespec t0, t1;
            clock_gettime(CLOCK_MONOTONIC, &t0);
            int ok = run_case(c, full, timeout_s, &r, result, sizeof result);
            clock_gettime(CLOCK_MONOTONIC, &t1);
            double sec = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
            passed += (unsigned)ok, failed += (unsigned)!ok;
            printf("  %-5s %-44s %6.2f s  %s%s%s\n", ok ? "ok" : "FAIL", name, sec, ok ? r.note : result, ok || !r.note[0] ? "" : " -- ", ok ? "" : r.note);
            fflush(stdout);
            snprintf(checks, sizeof checks, "%s", c->checks);
            clean(checks), clean(result), clean(r.note);
            char err[32];
            if (isnan(r.max_error))
                snprintf(err, sizeof err, "-");
            else
                snprintf(err, sizeof err, "%.3g", r.max_error);
            const char *st = r.status < 0 ? "-" : hz_status_str((hz_status_t)r.status);
            if (csv)
                fprintf(csv, "%s,%s,%s,%llu,%s,%s\n", name, checks, result, (unsigned long long)r.nonfinite, err,
                        st);
            if (notes)
                fprintf(notes, "%s\t%s\n", name, r.note);
        }
    if (list)
        return 0;
    if (csv)
        fclose(csv);
    if (notes)
        fclose(notes);
    if (res_path) {
        FILE *f = fopen(res_path, "w");
        if (!f) {
            fprintf(stderr, "hzstab: %s: %s\n", res_path, strerror(errno));
            return 2;
        }
        fprintf(f, "%s/stability %u %u 0\n", label, passed, failed);
        fclose(f);
    }
    printf("%u passed, %u failed\n", passed, failed);
    return failed ? 1 : 0;
}
