/* hzbake — the scene baker: imports a model (OBJ, PLY, glTF via assimp; Embree furball XML) plus its sidecar
 * and writes a validated .hzb (see tools/README.md and `hzbake --help`).
 *
 * The import and conversion run in a child process: importers crash on some malformed inputs (assimp 5.2 aborts
 * on a truncated PLY), and a crash there must become a clear error, not a crash of the baker. The child writes
 * the image into the temporary output file; the parent waits (with a time limit), validates the image with the
 * runtime's own loader (hz_scene_plan) and only then renames it over the target. Any failure leaves the target
 * as it was. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "bake.h"
#include "cli.h"
#include "fileio.h"
#include "hz/scene.h"
#include "opttab.h"
#include "scene.h"
#include "sidecar.h"

#define BAKE_VERSION "1.0"

/* The command line (opttab.h): the help is printed from this table. */
enum { B_SIDECAR, B_TEXTURE_MAX, B_TIMEOUT, B_INFO, B_QUIET, B_VERBOSE, B_VERSION };

static const hz_opt_t options[] = {
    { .name = "--sidecar", .alias = "-s", .arg = "FILE", .kind = HZ_OPT_TEXT, .id = B_SIDECAR,
      .help = "scene settings (.hzs: lights, camera path, material and motion overrides); default: MODEL's name "
              "with .hzs instead of its extension, if that exists" },
    { .name = "--texture-max", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = 16384, .id = B_TEXTURE_MAX,
      .help = "largest stored texture level (overrides the sidecar; default 1024)" },
    { .name = "--timeout", .arg = "S", .kind = HZ_OPT_INT, .lo = 1, .hi = 86400, .id = B_TIMEOUT,
      .help = "give up on an import that takes longer than S seconds (default 600)" },
    { .name = "--info", .arg = "FILE.hzb", .kind = HZ_OPT_TEXT, .id = B_INFO,
      .help = "validate a baked scene and print its header, sections, objects and memory plan" },
    { .name = "--quiet", .alias = "-q", .kind = HZ_OPT_FLAG, .id = B_QUIET, .help = "no summary line" },
    { .name = "--verbose", .alias = "-v", .kind = HZ_OPT_FLAG, .id = B_VERBOSE, .help = "progress of each step" },
    { .name = "--help", .alias = "-h", .kind = HZ_OPT_FLAG, .id = HZ_OPT_ID_HELP, .help = "this text" },
    { .name = "--version", .kind = HZ_OPT_FLAG, .id = B_VERSION, .help = "version" },
};

static const hz_opt_prog_t program = {
    .name = "hzbake",
    .table = options,
    .n = sizeof options / sizeof options[0],
    .max_operands = 2,
    .synopsis =
        "usage: hzbake [options] MODEL OUT.hzb\n"
        "       hzbake --info FILE.hzb\n"
        "\n"
        "Bakes MODEL and its sidecar into OUT.hzb, the scene format hzrt loads (include/hz/hzb.h).\n"
        "MODEL: .obj (+ .mtl), .ply, .ply.gz, .gltf, .glb (through assimp), or an Embree furball .xml\n"
        "(+ .bin or .bin.gz beside it). Textures (PNG, JPEG) are decoded and get mip levels.\n"
        "\n"
        "options:\n",
    .epilogue =
        "\n"
        "The output is written to a temporary file, validated with the runtime loader and renamed into\n"
        "place: a failed bake leaves OUT.hzb as it was. OUT.hzb is never one of the inputs: naming the model\n"
        "or the sidecar is refused before the bake (status 2), a file the import reads (a texture, a .mtl)\n"
        "when it is read (status 65). Missing textures and a missing .mtl are warnings (the material keeps\n"
        "its colour, or gets the default grey).\n"
        "\n"
        "exit status: 0 ok (warnings may have been printed), 2 bad command line (an unknown option, a missing\n"
        "  value, a value outside its limits), and 64 + hz status code:\n"
        "  65 the output is a file the model reads, 66 out of memory, 67 too large, 68 malformed model,\n"
        "  sidecar or scene, 70 corrupt .hzb (a checksum fails: --info, or the baked image's own check),\n"
        "  71 value out of range (e.g. NaN vertex), 72 unsupported format, 73 file missing or unreadable,\n"
        "  75 import timed out, 76 the importer crashed (or another internal failure)\n",
};

/* ---- --info ---- */

static int info(const char *path)
{
    hz_error_t err;
    uint8_t *raw;
    size_t size;
    if (hz_bake_read_file(path, &raw, &size, &err) != HZ_OK)
        return hz_cli_report(&err);
    void *buf = NULL;
    if (posix_memalign(&buf, HZ_HZB_ALIGN, size ? size : 1) != 0) {
        free(raw);
        hz_bake_err(&err, HZ_E_NO_MEMORY, "%s: cannot allocate %zu bytes", path, size);
        return hz_cli_report(&err);
    }
    memcpy(buf, raw, size);
    free(raw);
    hz_scene_plan_t plan;
    if (hz_scene_plan(buf, size, &plan, &err) != HZ_OK) {
        hz_error_prefix(&err, path);
        free(buf);
        return hz_cli_report(&err);
    }
    const hz_hzb_header_t *h = buf;
    char feats[160];
    hz_scene_features_str(h->features, feats, sizeof feats);
    char shown[4 * HZ_HZB_NAME_BYTES + 1]; /* names come from the file: control bytes as \xNN */
    printf("scene        %s (%s)\n", hz_cli_printable(shown, sizeof shown, (const char *)h->name, HZ_HZB_NAME_BYTES),
           path);
    printf("format       .hzb version %u, %llu bytes, %u sections\n", h->version, (unsigned long long)h->file_bytes,
           h->section_count);
    printf("features     %s (0x%03x)\n", feats, h->features);
    printf("geometry     %u triangles, %u vertices, %u objects\n", h->triangle_count, h->vertex_count, h->object_count);
    printf("materials    %u materials, %u textures (%u texels)\n", h->material_count, h->texture_count, h->texel_count);
    printf("lights       %u\n", h->light_count);
    printf("animation    %u camera keys, %u rigid keys, %u vertex keys, loop %g s%s\n", h->camera_key_count,
           h->rigid_key_count, h->vertex_key_count, (double)h->duration,
           (h->camera_flags & 1u) ? ", camera loops" : "");
    if (h->joint_count)
        printf("skinning     %u joints, %u binds (skinned at run time)\n", h->joint_count, h->skin_bind_count);
    printf("bounds       (%g %g %g) .. (%g %g %g)\n", (double)h->bounds_min[0], (double)h->bounds_min[1],
           (double)h->bounds_min[2], (double)h->bounds_max[0], (double)h->bounds_max[1], (double)h->bounds_max[2]);
    printf("sections\n");
    const hz_hzb_section_t *t = (const hz_hzb_section_t *)((const uint8_t *)buf + sizeof *h);
    for (uint32_t i = 0; i < h->section_count; i++)
        printf("  %-20s %12llu bytes at %10llu, crc %08x\n", hz_hzb_section_name(t[i].id),
               (unsigned long long)t[i].size, (unsigned long long)t[i].offset, t[i].crc32);
    hz_scene_t scene;
    hz_arena_t arena;
    void *state = NULL;
    if (plan.arena_bytes && posix_memalign(&state, HZ_HZB_ALIGN, plan.arena_bytes) != 0) {
        free(buf);
        hz_bake_err(&err, HZ_E_NO_MEMORY, "%s: cannot allocate %zu bytes of animation state", path, plan.arena_bytes);
        return hz_cli_report(&err);
    }
    hz_arena_init(&arena, "scene", state, plan.arena_bytes);
    if (hz_scene_load(&scene, buf, size, &arena, &err) == HZ_OK) {
        static const char *const kinds[] = { "static", "rigid keys", "vertex keys", "spin", "oscillate", "sway",
                                             "skinned" };
        printf("objects\n");
        for (uint32_t i = 0; i < scene.object_count; i++) {
            const hz_object_t *o = &scene.objects[i];
            if (i == 40 && scene.object_count > 48) {
                printf("  ... %u more\n", scene.object_count - 40);
                break;
            }
            printf("  %-4u %-32s %9u tris %9u verts  %s\n", i,
                   hz_cli_printable(shown, sizeof shown, (const char *)o->name, HZ_HZB_NAME_BYTES), o->triangle_count,
                   o->vertex_count, kinds[o->motion]);
        }
        printf("materials\n");
        for (uint32_t i = 0; i < scene.material_count && i < 64; i++) {
            static const char *const modes[] = { "opaque", "mask", "blend" };
            const hz_material_t *m = &scene.materials[i];
            printf("  %-4u %-32s color %.3g %.3g %.3g  %s", i,
                   hz_cli_printable(shown, sizeof shown, (const char *)m->name, HZ_HZB_NAME_BYTES), (double)m->base_color[0],
                   (double)m->base_color[1], (double)m->base_color[2], modes[m->alpha_mode]);
            if (m->alpha_mode == HZ_ALPHA_MASK)
                printf(" >= %.3g", (double)m->alpha_cutoff);
            if (m->alpha < 1.0f)
                printf(" alpha %.3g", (double)m->alpha);
            if (m->mirror > 0.0f)
                printf(" mirror %.3g", (double)m->mirror);
            if (m->base_texture >= 0)
                printf(" texture %d", m->base_texture);
            if (m->alpha_texture >= 0 && m->alpha_mode != HZ_ALPHA_OPAQUE)
                printf(" alpha-texture %d", m->alpha_texture);
            printf("\n");
        }
    }
    printf("memory plan\n");
    printf("  scene image          %12zu bytes (%.1f MiB, used in place)\n", plan.file_bytes,
           plan.file_bytes / 1048576.0);
    printf("  animation state      %12zu bytes (%.1f MiB, %u animated vertices)\n", plan.arena_bytes,
           plan.arena_bytes / 1048576.0, plan.animated_vertices);
    printf("  scene arena needs    %12zu bytes (%.1f MiB)\n", plan.file_bytes + plan.arena_bytes + 2 * HZ_HZB_ALIGN,
           (plan.file_bytes + plan.arena_bytes + 2 * HZ_HZB_ALIGN) / 1048576.0);
    free(state);
    free(buf);
    return 0;
}

/* ---- the child: import, convert, write ---- */

typedef struct job {
    const char *model;
    const char *out;
    hz_bake_sidecar_t sc;
    long timeout_s;
    int quiet;
} job_t;

/* The boards' scene arenas, "name=MiB ..." from boards/<name>/board.h (the Makefile passes them);
 * HZ_BAKE_TEST_BOARDS replaces the list (tests only). */
#ifndef HZ_BAKE_BOARD_SCENE_ARENAS
#define HZ_BAKE_BOARD_SCENE_ARENAS ""
#endif

/* Warns when no board can load the output: its scene arena need exceeds the largest board's scene arena. */
static void warn_if_no_board_fits(const char *out, const hz_scene_plan_t *plan, const hz_hzb_header_t *h,
                                  const hz_bake_sidecar_t *sc)
{
    const char *list = getenv("HZ_BAKE_TEST_BOARDS");
    if (!list || !*list)
        list = HZ_BAKE_BOARD_SCENE_ARENAS;
    char best[64] = "";
    unsigned long long best_mib = 0;
    for (const char *p = list; *p;) {
        char name[64];
        unsigned long long mib;
        int used = 0;
        if (sscanf(p, " %63[^=]=%llu%n", name, &mib, &used) != 2 || used <= 0)
            break;
        if (mib > best_mib)
            best_mib = mib, snprintf(best, sizeof best, "%s", name);
        p += used;
    }
    size_t need = plan->file_bytes + plan->arena_bytes + 2 * HZ_HZB_ALIGN; /* what `hzrt info` checks */
    if (!best_mib || need <= (size_t)(best_mib << 20))
        return;
    size_t keys = (size_t)h->vertex_key_count * 16 * (h->features & HZ_FEAT_NORMALS ? 2 : 1);
    if (keys > need / 4)
        hz_bake_warn("%s: needs %zu bytes of scene arena, more than any board has (the largest, %s, has %llu "
                     "MiB): no board can load it. Vertex keys (skinned meshes sampled at skin_rate %.3g frames/s) "
                     "take about %zu bytes: skin at run time (`skinning = runtime` in the sidecar, the default), lower "
                     "skin_rate, or shorten the animation",
                     out, need, best, best_mib, (double)sc->skin_rate, keys);
    else
        hz_bake_warn("%s: needs %zu bytes of scene arena, more than any board has (the largest, %s, has %llu "
                     "MiB): no board can load it. Simplify the model, lower texture_max, or raise a board's "
                     "HZ_ARENA_SCENE_BYTES",
                     out, need, best, best_mib);
}

/* Test hooks (tests only): HZ_BAKE_TEST_CRASH=abort|segv|hang makes the child fail that way once the import
 * begins, to check that the parent turns it into a clean error. */
static void test_hook(void)
{
    const char *hook = getenv("HZ_BAKE_TEST_CRASH");
    if (!hook || !*hook)
        return;
    if (!strcmp(hook, "abort"))
        abort();
    if (!strcmp(hook, "segv"))
        raise(SIGSEGV);
    if (!strcmp(hook, "hang"))
        for (;;)
            pause();
}

static int child(job_t *job, FILE *out)
{
    hz_error_t err;
    hz_bake_scene_t s;
    hz_bake_scene_init(&s, job->model);
    test_hook();
    hz_status_t st;
    if (hz_bake_ends_with(job->model, ".xml"))
        st = hz_bake_import_furball(&s, job->model, &job->sc, &err);
    else
        st = hz_bake_import_assimp(&s, job->model, &job->sc, &err);
    if (st == HZ_OK && hz_bake_input_clash()[0])
        st = hz_bake_err(&err, HZ_E_INVALID_ARG, "%s: %s, a file the model reads, is the output %s too: baking would "
                         "replace it; choose another output path", job->model, hz_bake_input_clash(), job->out);
    hz_bake_image_t img = { NULL, 0, { 0 } };
    if (st == HZ_OK) {
        hz_bake_progress("converted: %zu triangles, %zu vertices, %zu objects, %zu materials, %zu textures", s.tri.len,
                         s.pos.len, s.objs.len, s.mats.len, s.texs.len);
        hz_bake_phase("building the scene image (%zu triangles)", s.tri.len);
        st = hz_bake_scene_finish(&s, &job->sc, &img, &err);
    }
    hz_bake_scene_free(&s);
    if (st != HZ_OK)
        return hz_cli_report(&err);
    hz_bake_progress("writing %zu bytes", img.size);
    hz_bake_phase("writing %zu bytes", img.size);
    if (fwrite(img.data, 1, img.size, out) != img.size || fflush(out) != 0) {
        hz_bake_err(&err, HZ_E_IO, "%s: write failed: %s", job->out, strerror(errno));
        free(img.data);
        return hz_cli_report(&err);
    }
    free(img.data);
    return 0;
}

/* ---- the parent ---- */

static const char *signal_name(int sig)
{
    switch (sig) {
    case SIGSEGV: return "segmentation fault";
    case SIGABRT: return "abort";
    case SIGBUS: return "bus error";
    case SIGFPE: return "arithmetic exception";
    case SIGILL: return "illegal instruction";
    case SIGKILL: return "killed";
    default: return "signal";
    }
}

static void sleep_ms(long ms)
{
    struct timespec ts = { ms / 1000, (ms % 1000) * 1000000L };
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
        ;
}

/* The child's current phase as the parent sees it (read from the pipe). */
typedef struct phase {
    int fd;
    char name[256];
    size_t fill;     /* bytes of a partial line in buf */
    double since;    /* when this phase began */
    double next;     /* when to say something about it next (0: not yet said) */
    int said;
    char buf[512];
} phase_t;

/* Seconds a phase lasts before it is said: 1, or 0 with HZ_PROGRESS=all in the environment (every phase, for
 * tests and the curious). */
static double phase_after(void)
{
    const char *e = getenv("HZ_PROGRESS");
    return e && !strcmp(e, "all") ? 0.0 : 1.0;
}

/* Phases are said on a terminal, with -v, or with HZ_PROGRESS=all. */
static int phase_shown(void)
{
    return hz_bake_verbose || hz_cli_stderr_is_tty() || phase_after() == 0.0;
}

/* Takes the newest complete phase line from the pipe; says a phase once it has lasted a second, then every
 * 5 s, on a terminal or with -v. */
static void phase_poll(phase_t *ph, const char *model, double now)
{
    if (ph->fd >= 0) {
        ssize_t r;
        while ((r = read(ph->fd, ph->buf + ph->fill, sizeof ph->buf - 1 - ph->fill)) > 0) {
            ph->fill += (size_t)r;
            char *nl;
            while ((nl = memchr(ph->buf, '\n', ph->fill)) != NULL) {
                *nl = 0;
                if (strcmp(ph->name, ph->buf)) {
                    if (ph->said && phase_shown())
                        fprintf(stderr, "%s: %s: %s: done in %.1f s\n", hz_cli_prog, model, ph->name,
                                now - ph->since);
                    hz_bake_strcpy(ph->name, sizeof ph->name, ph->buf);
                    ph->since = now, ph->next = 0, ph->said = 0;
                    if (phase_after() == 0.0) { /* every phase, also those that came and went between polls */
                        fprintf(stderr, "%s: %s: %s ...\n", hz_cli_prog, model, ph->name);
                        ph->said = 1, ph->next = now + 5.0;
                    }
                }
                size_t used = (size_t)(nl - ph->buf) + 1;
                memmove(ph->buf, nl + 1, ph->fill - used);
                ph->fill -= used;
            }
            if (ph->fill == sizeof ph->buf - 1)
                ph->fill = 0; /* a line too long to be ours */
        }
    }
    if (!phase_shown())
        return;
    if (!ph->said && now - ph->since >= phase_after()) {
        fprintf(stderr, "%s: %s: %s ...\n", hz_cli_prog, model, ph->name);
        ph->said = 1, ph->next = now + 5.0;
    } else if (ph->said && now >= ph->next) {
        fprintf(stderr, "%s: %s: still %s (%.0f s)\n", hz_cli_prog, model, ph->name, now - ph->since);
        ph->next = now + 5.0;
    }
}

static int bake(job_t *job)
{
    hz_error_t err;
    double t0 = hz_bake_now();
    if (!hz_bake_file_exists(job->model)) {
        hz_bake_err(&err, HZ_E_IO, "%s: no such file (or not a regular file)", job->model);
        return hz_cli_report(&err);
    }
    if (!(hz_bake_ends_with(job->model, ".obj") || hz_bake_ends_with(job->model, ".ply") ||
          hz_bake_ends_with(job->model, ".ply.gz") || hz_bake_ends_with(job->model, ".gltf") ||
          hz_bake_ends_with(job->model, ".glb") || hz_bake_ends_with(job->model, ".xml"))) {
        const char *dot = strrchr(hz_bake_basename(job->model), '.');
        hz_bake_err(&err, HZ_E_UNSUPPORTED,
                    "%s: unsupported model format '%s' (the baker reads .obj, .ply, .ply.gz, "
                    ".gltf, .glb and Embree furball .xml)",
                    job->model, dot ? dot : "(no extension)");
        return hz_cli_report(&err);
    }
    hz_bake_guard_output(job->out); /* the import refuses to read the output (a texture, a .mtl named so) */
    hz_out_t out;
    if (hz_out_open(&out, job->out, &err) != HZ_OK)
        return hz_cli_report(&err);
    fflush(stdout);
    fflush(stderr);
    /* The child names its phases through a pipe, so the wait can say what is taking long. */
    int phase_pipe[2] = { -1, -1 };
    if (pipe(phase_pipe) == 0)
        fcntl(phase_pipe[0], F_SETFL, O_NONBLOCK);
    pid_t pid = fork();
    if (pid < 0) {
        hz_out_abort(&out);
        hz_bake_err(&err, HZ_E_INTERNAL, "cannot start the import process: %s", strerror(errno));
        return hz_cli_report(&err);
    }
    if (pid == 0) {
        if (phase_pipe[0] >= 0)
            close(phase_pipe[0]);
        hz_bake_phase_fd = phase_pipe[1];
        _exit(child(job, out.f));
    }
    if (phase_pipe[1] >= 0)
        close(phase_pipe[1]);
    static phase_t ph;
    memset(&ph, 0, sizeof ph);
    ph.fd = phase_pipe[0];
    ph.since = t0;
    hz_bake_strcpy(ph.name, sizeof ph.name, "importing");

    int status = 0;
    for (;;) {
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid)
            break;
        if (r < 0 && errno != EINTR) {
            hz_out_abort(&out);
            hz_bake_err(&err, HZ_E_INTERNAL, "%s: lost the import process: %s", job->model, strerror(errno));
            return hz_cli_report(&err);
        }
        double now = hz_bake_now();
        if (now - t0 > (double)job->timeout_s) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            hz_out_abort(&out);
            hz_bake_err(&err, HZ_E_TIMEOUT, "%s: the import took longer than %ld s and was stopped; %s is unchanged",
                        job->model, job->timeout_s, job->out);
            return hz_cli_report(&err);
        }
        phase_poll(&ph, job->model, now);
        sleep_ms(now - t0 < 1.0 ? 2 : 20);
    }
    if (ph.fd >= 0) {
        phase_poll(&ph, job->model, hz_bake_now()); /* the lines written just before the child ended */
        close(ph.fd);
    }
    if (ph.said && phase_shown())
        fprintf(stderr, "%s: %s: %s: done in %.1f s\n", hz_cli_prog, job->model, ph.name, hz_bake_now() - ph.since);
    double tv = hz_bake_now();
    if (WIFSIGNALED(status)) {
        hz_out_abort(&out);
        hz_bake_err(&err, HZ_E_INTERNAL, "%s: the importer crashed (%s, signal %d) while reading it; %s is unchanged",
                    job->model, signal_name(WTERMSIG(status)), WTERMSIG(status), job->out);
        return hz_cli_report(&err);
    }
    int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code != 0) {
        hz_out_abort(&out);
        if (code >= hz_status_exit_code(HZ_E_INVALID_ARG) && code <= hz_status_exit_code(HZ_E_INTERNAL))
            return code; /* the child reported the failure itself */
        /* Not one of ours: a runtime (a sanitizer, the C++ library) ended the process after a crash. */
        hz_bake_err(&err, HZ_E_INTERNAL,
                    "%s: the importer crashed (it exited with status %d without a report); %s is "
                    "unchanged",
                    job->model, code, job->out);
        return hz_cli_report(&err);
    }

    /* Validate what the child wrote, with the runtime's own loader, before it replaces anything. */
    uint8_t *raw;
    size_t size;
    if (hz_bake_read_file(out.tmp, &raw, &size, &err) != HZ_OK) {
        hz_out_abort(&out);
        return hz_cli_report(&err);
    }
    void *buf = NULL;
    if (posix_memalign(&buf, HZ_HZB_ALIGN, size ? size : 1) != 0) {
        free(raw);
        hz_out_abort(&out);
        hz_bake_err(&err, HZ_E_NO_MEMORY, "%s: cannot allocate %zu bytes to check the image", job->out, size);
        return hz_cli_report(&err);
    }
    memcpy(buf, raw, size);
    free(raw);
    hz_scene_plan_t plan;
    if (hz_scene_plan(buf, size, &plan, &err) != HZ_OK) {
        free(buf);
        hz_out_abort(&out);
        char msg[HZ_ERROR_MSG_BYTES];
        snprintf(msg, sizeof msg, "%s", err.msg);
        hz_bake_err(&err, err.code, "%s: the baked image fails validation (%s); %s is unchanged", job->model, msg,
                    job->out);
        return hz_cli_report(&err);
    }
    if (phase_shown() && hz_bake_now() - tv >= phase_after())
        fprintf(stderr, "%s: %s: checked the baked image with the runtime loader in %.1f s\n", hz_cli_prog, job->out,
                hz_bake_now() - tv);
    if (hz_out_commit(&out, &err) != HZ_OK) {
        free(buf);
        return hz_cli_report(&err);
    }
    warn_if_no_board_fits(job->out, &plan, (const hz_hzb_header_t *)buf, &job->sc);
    if (!job->quiet) {
        const hz_hzb_header_t *h = buf;
        char feats[160];
        hz_scene_features_str(h->features, feats, sizeof feats);
#define PL(n) ((n) == 1 ? "" : "s")
        printf("%s: %u triangle%s, %u vert%s, %u object%s, %u material%s, %u texture%s, %u light%s, %u camera "
               "key%s; features %s; %zu bytes; %.2f s\n",
               job->out, h->triangle_count, PL(h->triangle_count), h->vertex_count,
               h->vertex_count == 1 ? "ex" : "ices", h->object_count, PL(h->object_count), h->material_count,
               PL(h->material_count), h->texture_count, PL(h->texture_count), h->light_count, PL(h->light_count),
               h->camera_key_count, PL(h->camera_key_count), feats, size, hz_bake_now() - t0);
#undef PL
    }
    free(buf);
    return 0;
}

static char *default_sidecar(const char *model)
{
    size_t n = strlen(model);
    char *p = hz_bake_xmalloc(n + 8);
    memcpy(p, model, n + 1);
    if (hz_bake_ends_with(p, ".gz"))
        p[n - 3] = 0;
    char *slash = strrchr(p, '/'), *dot = strrchr(p, '.');
    if (dot && (!slash || dot > slash + 1))
        *dot = 0;
    strcat(p, ".hzs");
    if (!hz_bake_file_exists(p)) {
        free(p);
        return NULL;
    }
    return p;
}

typedef struct args {
    job_t *job;
    const char *sidecar, *info_path;
    long texture_max;
} args_t;

static int take(void *ctx, const hz_opt_t *o, const hz_opt_val_t *v)
{
    args_t *a = ctx;
    switch (o->id) {
    case B_SIDECAR: a->sidecar = v->s; break;
    case B_TEXTURE_MAX: a->texture_max = v->n; break;
    case B_TIMEOUT: a->job->timeout_s = v->n; break;
    case B_INFO: a->info_path = v->s; break;
    case B_QUIET: a->job->quiet = 1; break;
    case B_VERBOSE: hz_bake_verbose = 1; break;
    case B_VERSION:
        printf("hzbake %s (.hzb version %u)\n", BAKE_VERSION, HZ_HZB_VERSION);
        return HZ_OPT_DONE;
    }
    return 0;
}

int main(int argc, char **argv)
{
    hz_cli_prog = "hzbake";
    hz_out_remove_on_signals(); /* an interrupted bake leaves no temporary file */
    job_t job;
    memset(&job, 0, sizeof job);
    job.timeout_s = 600;
    args_t args = { &job, NULL, NULL, -1 };
    const char *pos[2] = { NULL, NULL };
    int npos = 0;
    int rc = hz_opt_parse(&program, argc, argv, take, &args, pos, &npos);
    if (rc)
        return rc == HZ_OPT_DONE ? 0 : rc;
    const char *sidecar = args.sidecar, *info_path = args.info_path;
    long texture_max = args.texture_max;
    if (info_path) {
        if (npos || sidecar) {
            hz_cli_error("--info takes one .hzb file and nothing else");
            return HZ_EXIT_USAGE;
        }
        return info(info_path);
    }
    if (npos != 2) {
        hz_cli_error("expected MODEL and OUT.hzb (try hzbake --help)");
        return HZ_EXIT_USAGE;
    }
    job.model = pos[0];
    job.out = pos[1];
    hz_bake_sidecar_defaults(&job.sc);
    char *auto_sidecar = NULL;
    if (!sidecar)
        sidecar = auto_sidecar = default_sidecar(job.model);
    {
        /* The output is never an input (nor a folder, nor in a folder that is missing): checked before any work. */
        static hz_outs_t outs;
        hz_error_t err;
        hz_outs_init(&outs);
        hz_outs_output(&outs, job.out, "the output");
        hz_outs_input(&outs, job.model, "the model");
        if (sidecar)
            hz_outs_input(&outs, sidecar, "the sidecar");
        if (hz_outs_check(&outs, &err) != HZ_OK) {
            free(auto_sidecar);
            if (err.code != HZ_E_INVALID_ARG)
                return hz_cli_report(&err);
            hz_cli_error("%s", err.msg);
            return HZ_EXIT_USAGE;
        }
    }
    if (sidecar) {
        hz_error_t err;
        if (hz_bake_sidecar_load(&job.sc, sidecar, &err) != HZ_OK) {
            hz_bake_sidecar_free(&job.sc);
            free(auto_sidecar);
            return hz_cli_report(&err);
        }
        hz_bake_progress("sidecar %s: %zu lights, %zu camera keys, %zu material and %zu object sections", sidecar,
                         job.sc.lights.len, job.sc.cameras.len, job.sc.materials.len, job.sc.objects.len);
    }
    if (texture_max > 0)
        job.sc.texture_max = (uint32_t)texture_max;
    rc = bake(&job);
    hz_bake_sidecar_free(&job.sc);
    free(auto_sidecar);
    return rc;
}
