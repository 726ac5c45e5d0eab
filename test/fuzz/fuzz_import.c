/*
 * libFuzzer target for the baker's model import (programs/hzbake): OBJ, PLY (also gzipped) and glTF/glb through
 * assimp, and the baker's own furball XML reader, followed by the conversion to a .hzb image
 * (hz_bake_scene_finish) with a sidecar.
 *
 * Input: the first byte picks the kind (its value mod 8: 0 .obj, 1 .ply, 2 .ply.gz gzipped here, 3 and 7 .gltf,
 * 4 .glb, 5 furball .xml, 6 .ply.gz as given; OBJ has one slot, as assimp's OBJ reader alone takes ~80 ms an
 * input here: it clears a fresh 16 MiB buffer each time); the rest is up to four files separated by
 * "#hzfuzz-file#": the model (m.<ext>), the file it refers to (m.mtl for OBJ, m.bin otherwise), a sidecar (m.hzs;
 * a refused one means the defaults) and a texture (t.png). test/fuzz/corpus/import holds seeds in this form
 * (test/fuzz/mkseeds.py).
 *
 * As in hzbake, the import runs in a child process, so that a crash in assimp (which is known to crash on some
 * malformed files) cannot take the fuzzer down. The child is a server that imports input after input (forking
 * one per input costs 10-40 ms here) and is replaced whenever it dies. Its coverage counters are copied back to
 * this process through shared memory after each input, so libFuzzer still sees what the import reached. What
 * the child's answer means:
 *  - it answered: the import either refused the model with a status and a message naming the input's file, or
 *    made an image, which must pass the runtime loader (hz_scene_plan, and fuzz_scene.h's checks). The heap
 *    calls of each input must balance, or LeakSanitizer scans for a leak.
 *  - it died (a sanitizer report, a signal, an abort, exit()) or hung (no answer within HZ_FUZZ_IMPORT_TIMEOUT
 *    seconds, default 5; then it prints three stack samples and is killed): the report's first stack frame in
 *    hzrt's code or a library's says whose it was (for a hang: hzrt's if any sample shows its code; when no
 *    sample unwinds, the baker's last phase, "importing (assimp)" or its own). In assimp, stb_image or zlib, it
 *    is a finding of that library, not of hzrt: its input and report are kept once per crash site as
 *    <artifact_prefix>lib-<site hash> (+ .log), counted, and the fuzzer goes on. In hzrt's code (or anywhere
 *    unknown), the child's report is printed and this process aborts, which libFuzzer records as a crash.
 * Run it with -rss_limit_mb=0 (no watcher thread, so fork() is safe) and -malloc_limit_mb above the 3 GiB at
 * which this target's ASan refuses an allocation (test/fuzz/fuzz-all.sh does).
 */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <assimp/cimport.h>
#include <sanitizer/allocator_interface.h>
#include <sanitizer/common_interface_defs.h>
#include <sanitizer/lsan_interface.h>
#include <zlib.h>

#include "fuzz_scene.h"
#include "scene.h"
#include "sidecar.h"

#define SEP "#hzfuzz-file#"
#define MAX_PARTS 4
#define IMAGE_CAP (64u << 20)
#define LOG_CAP (64u << 10)

/* Child -> parent, in shared memory. */
typedef struct result {
    int finished;
    hz_status_t status;
    char msg[HZ_ERROR_MSG_BYTES];
    size_t image_size;
    int image_fits;
    int leak_scan; /* the heap calls did not balance: LeakSanitizer scanned (and found nothing) */
} result_t;

/* The coverage counters of this binary (fuzz_counters.c) and searches libFuzzer does not see (fuzz_judge.c). */
uint8_t *hz_fuzz_counters(size_t *n);
char *hz_fuzz_find(const char *hay, const char *needle);
int hz_fuzz_starts(const char *s, const char *prefix);
int hz_fuzz_ub_report(const char *log);

static char dir[256], prefix[1024] = "./";
static result_t *shared;
static uint8_t *counters, *shared_counters, *shared_image;
static size_t n_counters;
static unsigned timeout_s = 5;
static int verbose; /* HZ_FUZZ_IMPORT_VERBOSE=1: say what became of each input */
static const char *save_dir; /* HZ_FUZZ_IMPORT_SAVE_HZB=DIR: keep each baked image (seeds for fuzz_hzb) */
/* HZ_FUZZ_IMPORT_SELFTEST=overflow|leak|hang: the child fails that way in hzrt's code after each import, so that
 * run-fuzz.sh can check that such a failure is blamed on hzrt (the fuzzer stops) and not taken for a library's. */
static const char *selftest;

static struct {
    unsigned long long runs, refused, imaged, too_big, library, library_sites, scans;
} stats;
#define MAX_SITES 256
static uint64_t sites[MAX_SITES];

/* Heap calls of the child, counted by allocator hooks: a full leak check (a scan of the whole heap, about
 * 100 ms) runs only when they do not balance. */
static volatile int in_child;
static volatile unsigned long long child_mallocs, child_frees;

static void count_malloc(const volatile void *p, size_t n)
{
    (void)p;
    (void)n;
    if (in_child)
        child_mallocs++;
}

static void count_free(const volatile void *p)
{
    if (in_child && p)
        child_frees++;
}

const char *__asan_default_options(void);
const char *__asan_default_options(void)
{
    /* A stack trace for abort() and for the hang signal; an allocation over 3 GiB is a report with the
     * requester's stack rather than a libFuzzer out-of-memory exit from inside the child. */
    return "handle_abort=1:max_allocation_size_mb=3072:allocator_may_return_null=0";
}

const char *__ubsan_default_options(void);
const char *__ubsan_default_options(void)
{
    return "print_stacktrace=1";
}

static pid_t server_pid;
static int req_fd = -1, rep_fd = -1;

static void cleanup(void)
{
    if (server_pid > 0) {
        close(req_fd); /* the server's end of input: it leaves */
        waitpid(server_pid, NULL, 0);
        server_pid = 0;
    }
    static const char *const names[] = { "m.obj", "m.ply", "m.ply.gz", "m.gltf", "m.glb", "m.xml", "m.mtl",
                                         "m.bin", "m.hzs", "t.png", "child.log", "phase.log" };
    char p[512];
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(p, sizeof p, "%s/%s", dir, names[i]);
        unlink(p);
    }
    rmdir(dir);
    if (stats.runs)
        fprintf(stderr,
                "fuzz_import: %llu inputs: %llu refused, %llu baked and loaded, %llu images over the harness's %u "
                "MiB, %llu heap scans for leaks; library findings (assimp, stb_image, zlib; not hzrt's code): %llu "
                "inputs at %llu sites\n",
                stats.runs, stats.refused, stats.imaged, stats.too_big, IMAGE_CAP >> 20, stats.scans, stats.library,
                stats.library_sites);
}

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    for (int i = 1; i < *argc; i++)
        if (!strncmp((*argv)[i], "-artifact_prefix=", 17))
            snprintf(prefix, sizeof prefix, "%s", (*argv)[i] + 17);
    verbose = getenv("HZ_FUZZ_IMPORT_VERBOSE") && atoi(getenv("HZ_FUZZ_IMPORT_VERBOSE")) > 0;
    save_dir = getenv("HZ_FUZZ_IMPORT_SAVE_HZB");
    selftest = getenv("HZ_FUZZ_IMPORT_SELFTEST");
    const char *t = getenv("HZ_FUZZ_IMPORT_TIMEOUT");
    if (t && atoi(t) > 0)
        timeout_s = (unsigned)atoi(t);
    const char *tmp = getenv("TMPDIR");
    snprintf(dir, sizeof dir, "%s/hzfuzz-import-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(dir)) {
        perror("fuzz_import: mkdtemp");
        exit(1);
    }
    counters = hz_fuzz_counters(&n_counters);
    size_t bytes = sizeof(result_t) + 64 + n_counters + IMAGE_CAP;
    uint8_t *m = mmap(NULL, bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED) {
        perror("fuzz_import: mmap");
        exit(1);
    }
    shared = (result_t *)m;
    shared_counters = m + sizeof(result_t);
    shared_image = m + ((sizeof(result_t) + n_counters + 63) & ~(size_t)63);
    signal(SIGPIPE, SIG_IGN); /* a write to a server that just died is an error return, not our death */
    __sanitizer_install_malloc_and_free_hooks(count_malloc, count_free);
    /* assimp keeps its last error message in a static string: give it its buffer here, so that a child's
     * refusal does not leave one behind that looks like a leak to the counts above. */
    static const char junk[] = "not a model at all, and a long enough message to need the heap";
    const struct aiScene *none = aiImportFileFromMemory(junk, sizeof junk, 0, "ply");
    if (none)
        aiReleaseImport(none);
    atexit(cleanup);
    return 0;
}

static uint64_t fnv(const void *p, size_t n)
{
    const uint8_t *b = p;
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

static int write_file(const char *name, const uint8_t *data, size_t size)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "wb");
    if (!f)
        return 0;
    int ok = fwrite(data, 1, size, f) == size;
    return fclose(f) == 0 && ok;
}

static int write_gzip(const char *name, const uint8_t *data, size_t size)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    gzFile f = gzopen(p, "wb1");
    if (!f)
        return 0;
    int ok = size == 0 || gzwrite(f, data, (unsigned)size) == (int)size;
    return gzclose(f) == Z_OK && ok;
}

/* ---- the child ---- */

static void child_quiet_death(void)
{
    /* Replaces libFuzzer's death callback in the child: the parent decides what the report means. */
}

static void child_exit_hook(void)
{
    /* exit() somewhere in the import (registered last, so it runs before libFuzzer's and LeakSanitizer's
     * exit handlers): show who called it and leave without them. */
    fprintf(stderr, "==%d==ERROR: fuzz_import: exit() called in the import child\n", (int)getpid());
    __sanitizer_print_stack_trace();
    _exit(3);
}

/* One input in the server: files are in dir, the model's name is `model`. */
static void import_one(const char *model)
{
    hz_bake_sidecar_t sc;
    hz_error_t err;
    char p[512];
    hz_bake_sidecar_defaults(&sc);
    snprintf(p, sizeof p, "%s/m.hzs", dir);
    if (hz_bake_file_exists(p) && hz_bake_sidecar_load(&sc, p, &err) != HZ_OK) {
        hz_bake_sidecar_free(&sc);
        hz_bake_sidecar_defaults(&sc); /* a refused sidecar: the model is still worth importing */
    }
    hz_bake_scene_t s;
    hz_bake_scene_init(&s, model);
    hz_error_clear(&err);
    hz_status_t st = hz_bake_ends_with(model, ".xml") ? hz_bake_import_furball(&s, model, &sc, &err)
                                                      : hz_bake_import_assimp(&s, model, &sc, &err);
    hz_bake_image_t img = { NULL, 0, { 0 } };
    if (st == HZ_OK)
        st = hz_bake_scene_finish(&s, &sc, &img, &err);
    hz_bake_scene_free(&s);
    hz_bake_sidecar_free(&sc);
    shared->status = st;
    memcpy(shared->msg, err.msg, sizeof shared->msg);
    if (st == HZ_OK) {
        shared->image_size = img.size;
        shared->image_fits = img.size <= IMAGE_CAP;
        if (shared->image_fits)
            memcpy(shared_image, img.data, img.size);
    }
    free(img.data);
    if (selftest && !strcmp(selftest, "overflow")) {
        char *volatile b = malloc(8);
        b[8] = 1;
        free(b);
    } else if (selftest && !strcmp(selftest, "leak")) {
        void *volatile lost = malloc(24);
        lost = NULL;
    } else if (selftest && !strcmp(selftest, "hang")) {
        for (volatile unsigned i = 0;; i++)
            ;
    }
}

#define SAMPLE_MARK "==hzfuzz-sample==\n"

/* SIGUSR1 in the child: a stack sample of where it is (the parent asks for a few when an input hangs). */
static __attribute__((noinline)) void sample_stack(int sig)
{
    (void)sig;
    if (write(2, SAMPLE_MARK, sizeof SAMPLE_MARK - 1) < 0)
        return;
    __sanitizer_print_stack_trace();
    if (write(2, "\n", 1) < 0) /* not a tail call: this frame stays on the printed stack */
        return;
}

/* The child: imports one input per byte on `req` (the kind), answers on `rep`, ends when `req` closes. Its
 * stderr is the log file and the baker's phase lines ("importing (assimp)", "converting ...") go to phase.log,
 * both emptied before each input; its coverage counters are zeroed before each input and copied out after it. */
static void server(int req, int rep, int log_fd, int phase_fd)
{
    static const char *const model_names[8] = { "m.obj", "m.ply", "m.ply.gz", "m.gltf",
                                                "m.glb", "m.xml", "m.ply.gz", "m.gltf" };
    __sanitizer_set_death_callback(child_quiet_death);
    atexit(child_exit_hook);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    int null_fd = open("/dev/null", O_RDWR);
    if (null_fd >= 0) {
        dup2(null_fd, 0);
        dup2(null_fd, 1);
    }
    dup2(log_fd, 2);
    hz_bake_phase_fd = phase_fd;
    signal(SIGUSR1, sample_stack);
    unsigned char kind;
    while (read(req, &kind, 1) == 1) {
        if (ftruncate(2, 0) != 0 || lseek(2, 0, SEEK_SET) != 0 || ftruncate(phase_fd, 0) != 0 ||
            lseek(phase_fd, 0, SEEK_SET) != 0)
            _exit(5);
        char model[512];
        snprintf(model, sizeof model, "%s/%s", dir, model_names[kind % 8]);
        memset(counters, 0, n_counters);
        child_mallocs = child_frees = 0;
        in_child = 1;
        import_one(model);
        in_child = 0;
        /* Heap calls that do not balance: a leak, or state a library keeps (which the scan finds reachable). */
        if (child_mallocs != child_frees) {
            if (__lsan_do_recoverable_leak_check())
                _exit(4);
            shared->leak_scan = 1;
        }
        memcpy(shared_counters, counters, n_counters);
        shared->finished = 1;
        if (write(rep, "k", 1) != 1)
            _exit(6);
    }
    _exit(0);
}

static void server_start(void)
{
    char p[512];
    snprintf(p, sizeof p, "%s/child.log", dir);
    int log_fd = open(p, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    snprintf(p, sizeof p, "%s/phase.log", dir);
    int phase_fd = open(p, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    int a[2], b[2];
    if (log_fd < 0 || phase_fd < 0 || pipe(a) != 0 || pipe(b) != 0) {
        perror("fuzz_import: log or pipes");
        abort();
    }
    fflush(stdout);
    fflush(stderr);
    server_pid = fork();
    if (server_pid < 0) {
        perror("fuzz_import: fork");
        abort();
    }
    if (server_pid == 0) {
        close(a[1]);
        close(b[0]);
        server(a[0], b[1], log_fd, phase_fd);
    }
    close(log_fd);
    close(phase_fd);
    close(a[0]);
    close(b[1]);
    req_fd = a[1];
    rep_fd = b[0];
}

/* Ends a dead (or hung, after the signal) server; returns its wait status. */
static int server_reap(void)
{
    int status = 0;
    close(req_fd);
    close(rep_fd);
    req_fd = rep_fd = -1;
    while (waitpid(server_pid, &status, 0) < 0 && errno == EINTR)
        ;
    server_pid = 0;
    return status;
}

/* Sends one input's kind and waits for the answer. Returns 1 when the server answered; 0 when it died or hung
 * (then *status and *hung say how, and the server is gone). */
static int server_run(int kind, int *status, int *hung)
{
    if (!server_pid)
        server_start();
    memset(shared, 0, sizeof *shared);
    unsigned char k = (unsigned char)kind;
    *hung = 0;
    if (write(req_fd, &k, 1) == 1) {
        struct pollfd pf = { rep_fd, POLLIN, 0 };
        int r;
        do
            r = poll(&pf, 1, (int)timeout_s * 1000);
        while (r < 0 && errno == EINTR);
        if (r == 0) {
            /* Three stack samples of where it hangs (one can land where no stack unwinds), then the end. */
            for (int i = 0; i < 3 && r == 0; i++) {
                kill(server_pid, SIGUSR1);
                do
                    r = poll(&pf, 1, 300);
                while (r < 0 && errno == EINTR);
            }
            char c;
            if (r > 0 && read(rep_fd, &c, 1) == 1)
                return 1; /* slow, not stuck: it answered */
            *hung = 1;
            kill(server_pid, SIGKILL);
        } else {
            char c;
            if (read(rep_fd, &c, 1) == 1)
                return 1;
        }
    }
    *status = server_reap();
    return 0;
}

/* ---- reading a dead child's report ---- */

/* Frames of the sanitizer runtime, libFuzzer and the allocator (linked into this binary), and this harness's
 * allocator and exit hooks: a hang caught inside a malloc shows them on top. */
static int plumbing(const char *frame)
{
    static const char *const marks[] = { "__interceptor", "__asan", "__sanitizer", "__lsan", "__ubsan",
                                         "compiler-rt", "fuzzer::", " in malloc", " in calloc", " in realloc",
                                         " in free", "operator new", "operator delete", "count_malloc",
                                         "count_free", "child_exit_hook", "sample_stack" };
    for (size_t i = 0; i < sizeof marks / sizeof marks[0]; i++)
        if (hz_fuzz_find(frame, marks[i]))
            return 1;
    return 0;
}

static const char *library_of(const char *frame)
{
    static const char *const assimp[] = { "libassimp", "libdraco", "libpoly2tri", "libminizip", "libpugixml",
                                          "libIrrXML" };
    for (size_t i = 0; i < sizeof assimp / sizeof assimp[0]; i++)
        if (hz_fuzz_find(frame, assimp[i]))
            return "assimp";
    if (hz_fuzz_find(frame, "libstb"))
        return "stb_image";
    if (hz_fuzz_find(frame, "libz.so"))
        return "zlib";
    return NULL;
}

/* hzrt's code (the baker, the core, this harness): a source file of the tree (it is built with -g). Frames of
 * this binary without one are the sanitizer runtime, its interceptors (strncmp, memcpy...) and libFuzzer. */
static int ours(const char *frame)
{
    return hz_fuzz_find(frame, "/programs/") || hz_fuzz_find(frame, "/src/") ||
        hz_fuzz_find(frame, "/port/linux/") || hz_fuzz_find(frame, "/test/fuzz/");
}

/* The first frame of the report's stack (of the allocation, for a leak) that is hzrt's code or a library's,
 * skipping libc, the C++ runtime and the sanitizer runtime. Returns its line, cut at its end; NULL when there
 * is none. */
static char *first_frame(char *log)
{
    char *from = hz_fuzz_find(log, "Direct leak");
    if (!from)
        from = hz_fuzz_find(log, "Indirect leak");
    if (!from)
        from = log;
    for (char *line = from; line && *line;) {
        char *end = strchr(line, '\n');
        if (end)
            *end = '\0';
        char *hash = line;
        while (*hash == ' ')
            hash++;
        int frame = hash[0] == '#' && hash[1] >= '0' && hash[1] <= '9' && hz_fuzz_find(hash, " 0x");
        if (frame && !plumbing(hash) && (library_of(hash) || ours(hash)))
            return hash;
        if (end)
            *end = '\n';
        line = end ? end + 1 : NULL;
    }
    return NULL;
}

static size_t read_log(char *buf, size_t cap)
{
    char p[512];
    snprintf(p, sizeof p, "%s/child.log", dir);
    FILE *f = fopen(p, "rb");
    if (!f)
        return 0;
    size_t n = fread(buf, 1, cap - 1, f);
    fclose(f);
    buf[n] = '\0';
    return n;
}

static void library_finding(const char *lib, const char *frame, const char *what, const uint8_t *data, size_t size,
                            const char *log, size_t log_size)
{
    stats.library++;
    /* The site: the kind of report and the frame's function, or its module and offset when it has no name
     * (never the address, which moves from run to run). */
    const char *in = hz_fuzz_find(frame, " in "), *mod = strchr(frame, '(');
    const char *where = in ? in + 4 : mod ? mod : frame;
    /* "==PID==ERROR: AddressSanitizer: SEGV on unknown address ...": the word after the tool's name. */
    const char *kind = hz_fuzz_find(log, "ERROR: ");
    kind = kind ? kind + 7 : what;
    if (!strncmp(what, "no answer", 9))
        kind = "hang";
    else if (hz_fuzz_starts(kind, "LeakSanitizer"))
        kind = "leak";
    else if (strchr(kind, ':') && strchr(kind, ':') < kind + strcspn(kind, "\n"))
        kind = strchr(kind, ':') + 2;
    char place[200];
    if (!strncmp(what, "no answer", 9))
        snprintf(place, sizeof place, "a loop in %s", lib); /* where a hang is caught says little */
    else
        snprintf(place, sizeof place, "%.*s", (int)strcspn(where, in ? " (" : ")"), where);
    uint64_t site = fnv(place, strlen(place)) ^ fnv(kind, strcspn(kind, " \n"));
    for (uint64_t i = 0; i < stats.library_sites && i < MAX_SITES; i++)
        if (sites[i] == site)
            return;
    if (stats.library_sites < MAX_SITES)
        sites[stats.library_sites] = site;
    stats.library_sites++;
    char name[1200];
    snprintf(name, sizeof name, "%slib-%016llx", prefix, (unsigned long long)site);
    FILE *f = fopen(name, "wb");
    if (f) {
        fwrite(data, 1, size, f);
        fclose(f);
    }
    char logname[1300];
    snprintf(logname, sizeof logname, "%s.log", name);
    f = fopen(logname, "wb");
    if (f) {
        fwrite(log, 1, log_size, f);
        fclose(f);
    }
    fprintf(stderr, "fuzz_import: library finding (%s, not hzrt's code): %s, %.*s at %s; input kept as %s\n", lib,
            what, (int)strcspn(kind, " \n"), kind, place, name);
}

/* The baker's last phase line of the input (phase.log) starts with `what`. */
static int phase_is(const char *what)
{
    char p[512], buf[4096];
    snprintf(p, sizeof p, "%s/phase.log", dir);
    FILE *f = fopen(p, "rb");
    if (!f)
        return 0;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    while (n && buf[n - 1] == '\n')
        buf[--n] = '\0';
    char *last = strrchr(buf, '\n');
    return hz_fuzz_starts(last ? last + 1 : buf, what);
}

/* The child died: whose code was it? */
static void judge_death(int status, int hung, const uint8_t *data, size_t size)
{
    static char log[LOG_CAP], scan[LOG_CAP];
    size_t n = read_log(log, sizeof log);
    memcpy(scan, log, n + 1);
    char what[96];
    if (hung)
        snprintf(what, sizeof what, "no answer within %u s", timeout_s);
    else if (WIFSIGNALED(status))
        snprintf(what, sizeof what, "killed by signal %d", WTERMSIG(status));
    else
        snprintf(what, sizeof what, "exit status %d", WEXITSTATUS(status));
    int ub = hz_fuzz_ub_report(scan);
    int cxx = hz_fuzz_find(scan, "operator new") || hz_fuzz_find(scan, "libstdc++");
    const char *frame = NULL, *lib = NULL;
    if (hung) {
        /* Each sample names a library or hzrt's code (or nothing, if it did not unwind). hzrt's code in any
         * sample makes the hang hzrt's: a loop of its own shows its frames on top of whatever it calls. */
        int any_ours = 0;
        for (char *smp = hz_fuzz_find(scan, SAMPLE_MARK); smp; smp = hz_fuzz_find(smp + 1, SAMPLE_MARK)) {
            char *next = hz_fuzz_find(smp + 1, SAMPLE_MARK);
            if (next)
                *next = '\0';
            /* The sample's own frames end at the signal trampoline in libc; the stuck code is below it. */
            char *below = hz_fuzz_find(smp, "libc.so");
            below = below ? strchr(below, '\n') : NULL;
            char *f = first_frame(below ? below : smp);
            if (f && library_of(f) && !lib)
                frame = f, lib = library_of(f);
            else if (f && !library_of(f))
                any_ours = 1, frame = f;
            if (next)
                *next = SAMPLE_MARK[0];
            else
                break;
        }
        if (any_ours)
            lib = NULL;
        else if (!lib && phase_is("importing (assimp)"))
            frame = "assimp's import (the baker's last phase; no stack sample unwound)", lib = "assimp";
    } else {
        /* A leak report lists the direct leaks, then the indirect ones: memory reachable only from a leaked
         * object, which its owner's code leaked with it. So the direct leaks say whose leak it is: assimp
         * losing a stream it opened through the baker's file callbacks shows the baker's allocation only as an
         * indirect leak. */
        char *direct = hz_fuzz_find(scan, "Direct leak of"), *indirect = hz_fuzz_find(scan, "Indirect leak of");
        if (direct && indirect && indirect > direct)
            *indirect = '\0';
        frame = ub ? NULL : first_frame(scan);
        lib = frame ? library_of(frame) : NULL;
    }
    if (!frame && !ub && !hung && cxx) {
        /* A stack that ends in the C++ runtime (the fast unwinder of malloc stacks stops at libstdc++, built
         * without frame pointers): only assimp is C++ here. ASAN_OPTIONS=fast_unwind_on_malloc=0 on a rerun of
         * the kept input shows the whole stack. */
        frame = "C++ code reached through libstdc++";
        lib = "assimp";
    }
    if (lib) {
        library_finding(lib, frame, what, data, size, log, n);
        return;
    }
    fprintf(stderr, "fuzz_import: the import child ended abnormally (%s) in hzrt's code%s; its report:\n%s\n", what,
            frame ? "" : " (or no stack frame says otherwise)", log);
    abort();
}

/* ---- one input ---- */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const model_names[8] = { "m.obj", "m.ply", "m.ply.gz", "m.gltf",
                                                "m.glb", "m.xml", "m.ply.gz", "m.gltf" };
    static const char *const companion[8] = { "m.mtl", "m.bin", "m.bin", "m.bin", "m.bin", "m.bin", "m.bin", "m.bin" };
    if (size < 1)
        return 0;
    int kind = data[0] % 8;
    const uint8_t *part[MAX_PARTS] = { NULL };
    size_t part_size[MAX_PARTS] = { 0 };
    size_t np = 0, at = 1;
    while (np < MAX_PARTS) {
        const uint8_t *s = NULL;
        for (size_t i = at; i + sizeof SEP - 1 <= size; i++)
            if (!memcmp(data + i, SEP, sizeof SEP - 1)) {
                s = data + i;
                break;
            }
        part[np] = data + at;
        part_size[np] = (s ? (size_t)(s - data) : size) - at;
        np++;
        if (!s)
            break;
        at = (size_t)(s - data) + sizeof SEP - 1;
    }
    static const char *const stale[] = { "m.obj", "m.ply", "m.ply.gz", "m.gltf", "m.glb", "m.xml",
                                         "m.mtl", "m.bin", "m.hzs", "t.png" };
    char p[512];
    for (size_t i = 0; i < sizeof stale / sizeof stale[0]; i++) {
        snprintf(p, sizeof p, "%s/%s", dir, stale[i]);
        unlink(p);
    }
    int ok = kind == 2 ? write_gzip(model_names[kind], part[0], part_size[0])
                       : write_file(model_names[kind], part[0], part_size[0]);
    if (np > 1)
        ok &= write_file(companion[kind], part[1], part_size[1]);
    if (np > 2)
        ok &= write_file("m.hzs", part[2], part_size[2]);
    if (np > 3)
        ok &= write_file("t.png", part[3], part_size[3]);
    if (!ok) {
        fprintf(stderr, "fuzz_import: cannot write the input's files into %s: %s\n", dir, strerror(errno));
        abort();
    }
    int status = 0, hung = 0;
    stats.runs++;
    if (!server_run(kind, &status, &hung) || !shared->finished) {
        judge_death(status, hung, data, size);
        return 0;
    }
    stats.scans += shared->leak_scan;
    /* Coverage the child reached, for libFuzzer's feedback. */
    for (size_t i = 0; i < n_counters; i++)
        if (shared_counters[i] > counters[i])
            counters[i] = shared_counters[i];
    if (shared->status != HZ_OK) {
        /* A refusal says why and names a file of the input. */
        if (!shared->msg[0] || !hz_fuzz_find(shared->msg, dir))
            abort();
        if (verbose)
            fprintf(stderr, "fuzz_import: refused: %s\n", shared->msg);
        stats.refused++;
        return 0;
    }
    if (!shared->image_fits) {
        stats.too_big++;
        return 0;
    }
    /* The baked image must pass the runtime loader, as hzbake checks before it keeps a file. */
    size_t n = shared->image_size;
    void *image = NULL;
    if (posix_memalign(&image, HZ_HZB_ALIGN, n ? n : 1) != 0)
        abort();
    memcpy(image, shared_image, n);
    hz_scene_plan_t plan;
    hz_error_t err;
    hz_error_clear(&err);
    hz_status_t st = hz_scene_plan(image, n, &plan, &err);
    if (st != HZ_OK) {
        fprintf(stderr, "fuzz_import: the baker made an image its runtime refuses: %s\n", err.msg);
        abort();
    }
    void *state = NULL;
    if (posix_memalign(&state, HZ_HZB_ALIGN, plan.arena_bytes ? plan.arena_bytes : 1) != 0)
        abort();
    st = fuzz_load_scene(image, n, state, plan.arena_bytes);
    free(state);
    free(image);
    if (st != HZ_OK)
        abort(); /* planned but not loadable */
    stats.imaged++;
    if (save_dir && *save_dir) {
        char name[600];
        snprintf(name, sizeof name, "%s/import-%016llx.hzb", save_dir, (unsigned long long)fnv(data, size));
        FILE *f = fopen(name, "wb");
        if (!f || fwrite(shared_image, 1, n, f) != n || fclose(f) != 0) {
            perror(name);
            abort();
        }
    }
    if (verbose)
        fprintf(stderr, "fuzz_import: baked and loaded: %zu bytes\n", n);
    return 0;
}
