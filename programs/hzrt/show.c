/* One run of the frame loop from a command line (see show.h). */
#include "show.h"

#include <errno.h>
#include <math.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <signal.h>

#include "et_flip.h"
#include "et_metrics.h"
#include "cli.h"
#include "clock.h"
#include "devices.h"
#include "drm_port.h"
#include "fileio.h"
#include "filesink.h"
#include "hz/frameloop.h"
#include "hz/hz.h"
#include "hz/marker.h"
#include "hz/pixconv.h"
#include "imageio.h"
#include "latency.h"
#include "latency_report.h"
#include "phase.h"
#include "pools.h"
#include "renderopts.h"
#include "showopts.h"
#include "summary.h"
#include "vsource.h"

void hz_show_defaults(hz_show_cfg_t *c)
{
    memset(c, 0, sizeof *c);
    c->cmd = "render";
    c->what = HZ_SHOW_PATTERN;
    c->render_scale = 1;
    c->sink = "none";
    c->out = "out";
    c->video = c->png = true;
    c->source = HZ_VSYNC_SOURCE == HZ_VSYNC_GPIO ? "gpio" : HZ_VSYNC_SOURCE == HZ_VSYNC_FBDEV ? "fbdev" : "sim";
    c->hz = HZ_DISPLAY_HZ;
    c->seed = 1;
    c->signal = "";
    c->edge_mode = HZ_VSYNC_GPIO_EDGE;
    c->percentile = 100;
    c->lookahead = 1;
    c->marker = -1;
    c->budget = -1;
    c->w = 320, c->h = 180;
}

/* ---- values given as text ---- */

/* "3ms", "800us", "250ns", "1.5ms", "2s", "0.5P" (of period_ns). */
static int parse_time(const char *opt, const char *s, int64_t period_ns, int64_t *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    double scale = 0;
    if (errno == 0 && end != s && v >= 0) {
        if (!strcmp(end, "ns"))
            scale = 1;
        else if (!strcmp(end, "us"))
            scale = 1e3;
        else if (!strcmp(end, "ms"))
            scale = 1e6;
        else if (!strcmp(end, "s"))
            scale = 1e9;
        else if (!strcmp(end, "P") && period_ns > 0)
            scale = (double)period_ns;
    }
    if (scale == 0 || v * scale > 1e15) {
        hz_cli_error("%s: '%s' is not a time like 3ms, 800us, 250ns or 0.5P (a fraction of the period)", opt, s);
        return 0;
    }
    *out = (int64_t)(v * scale + 0.5);
    return 1;
}

static int parse_fraction(const char *opt, const char *s, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(s ? s : "", &end);
    if (!s || errno || end == s || *end || !(v >= lo && v <= hi)) {
        hz_cli_error("%s: '%s' is not a number in [%g, %g]", opt, s ? s : "", lo, hi);
        return 0;
    }
    *out = v;
    return 1;
}

static int parse_model(const char *spec, int64_t period_ns, hz_rtm_cfg_t *m)
{
    char buf[128];
    snprintf(buf, sizeof buf, "%s", spec);
    char *parts[5] = { 0 };
    int n = 0;
    for (char *t = strtok(buf, ":"); t && n < 5; t = strtok(NULL, ":"))
        parts[n++] = t;
    memset(m, 0, sizeof *m);
    struct { const char *name; hz_rtm_kind_t kind; int args; } kinds[] = {
        { "const", HZ_RTM_CONST, 1 }, { "uniform", HZ_RTM_UNIFORM, 2 }, { "spikes", HZ_RTM_SPIKES, 3 },
        { "triangle", HZ_RTM_TRIANGLE, 3 }, { "step", HZ_RTM_STEP, 3 },
    };
    for (size_t k = 0; n > 0 && k < sizeof kinds / sizeof kinds[0]; k++) {
        if (strcmp(parts[0], kinds[k].name))
            continue;
        if (n - 1 != kinds[k].args)
            break;
        m->kind = kinds[k].kind;
        if (!parse_time("--render-model", parts[1], period_ns, &m->a_ns))
            return 0;
        if (kinds[k].args >= 2 && !parse_time("--render-model", parts[2], period_ns, &m->b_ns))
            return 0;
        if (kinds[k].args == 3) {
            double v;
            if (m->kind == HZ_RTM_SPIKES) {
                if (!parse_fraction("--render-model spike %", parts[3], 0, 100, &v))
                    return 0;
                m->rate_ppm = (uint32_t)(v * 1e4 + 0.5);
            } else {
                if (!parse_fraction("--render-model frames", parts[3], 1, 1e12, &v))
                    return 0;
                m->frames = (uint64_t)v;
            }
        }
        return 1;
    }
    hz_cli_error("--render-model: '%s' is not one of const:T, uniform:A:B, spikes:A:B:PCT, triangle:A:B:N, "
                 "step:A:B:N", spec);
    return 0;
}

/* SCHED_FIFO and locked memory for on-target measurement runs; what was granted goes into the report. */
static void rt_setup(char *out, size_t cap)
{
    struct sched_param sp;
    memset(&sp, 0, sizeof sp);
    sp.sched_priority = 50;
    int fifo = sched_setscheduler(0, SCHED_FIFO, &sp) == 0;
    int e1 = errno;
    /* MCL_ONFAULT: pages are locked as they are first touched, so the board's large static arenas are not all
     * made resident up front; what the loop uses stays in RAM from its first frame on. */
#ifdef MCL_ONFAULT
    int locked = mlockall(MCL_CURRENT | MCL_FUTURE | MCL_ONFAULT) == 0;
#else
    int locked = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
#endif
    int e2 = errno;
    snprintf(out, cap, "%s, %s",
             fifo ? "SCHED_FIFO 50" : (e1 == EPERM ? "SCHED_FIFO refused (EPERM)" : "SCHED_FIFO failed"),
             locked ? "memory locked" : (e2 == EPERM || e2 == ENOMEM ? "mlockall refused" : "mlockall failed"));
    if (!fifo || !locked)
        hz_cli_error("warning: --rt: %s", out);
}

/* "kind:rest" -> kind and rest (rest "" when absent). */
static void split_spec(const char *spec, char *kind, size_t kcap, const char **rest)
{
    const char *colon = strchr(spec, ':');
    size_t n = colon ? (size_t)(colon - spec) : strlen(spec);
    if (n >= kcap)
        n = kcap - 1;
    memcpy(kind, spec, n);
    kind[n] = '\0';
    *rest = colon ? colon + 1 : "";
}

/* ---- the scene's summary and files ---- */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double percentile_of(const double *sorted, uint32_t n, double p)
{
    if (n == 0)
        return 0.0;
    double idx = p * (n - 1);
    uint32_t lo = (uint32_t)idx;
    uint32_t hi = lo + 1 < n ? lo + 1 : lo;
    return sorted[lo] + (sorted[hi] - sorted[lo]) * (idx - lo);
}

static double sorted_ms[HZ_SCENESRC_MAX_TIMED];

static const char *signal_name(int sig)
{
    return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : sig == SIGHUP ? "SIGHUP" : "a signal";
}

/* summary.json's settings: every image-changing option of both tables, as the run used it. */
static char *settings_json(const hz_show_cfg_t *c, const hz_render_opts_t *eff)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    if (!f)
        return NULL;
    bool first = true;
    if (c->ropts)
        hz_ropts_settings(f, c->ropts, eff, &first);
    hz_sopts_settings(f, c, &first);
    fclose(f);
    return buf;
}

static hz_status_t write_scene_outputs(const hz_show_cfg_t *c, double run_s, int interrupted, hz_error_t *err)
{
    hz_renderer_t *r = hz_scenesrc_renderer();
    const hz_scenesrc_stats_t *st = hz_scenesrc_stats();
    const hz_scene_t *scene = hz_scenesrc_scene();
    const hz_render_opts_t *o = &hz_scenesrc_ladder()->level[0].opts; /* as rendered: focus names resolved */
    char path[4096];
    hz_status_t s;
    if (c->pfm && st->frames) {
        snprintf(path, sizeof path, "%s/last.pfm", c->out);
        if ((s = hz_pfm_write(path, hz_render_output(r), err)) != HZ_OK)
            return s;
    }
    if (c->adaptive && c->adaptive->map_path && st->frames) {
        const hz_image_t *img = hz_render_output(r);
        if ((s = hz_adaptive_map_write(c->adaptive->map_path, r, img->width, img->height, err)) != HZ_OK)
            return s;
    }
    /* The first frame is left out of the frame-time statistics when there are several (it pays for page faults
     * and cold caches), and said so. */
    uint32_t skip = st->timed > 1 ? 1u : 0u, n = st->timed - skip;
    memcpy(sorted_ms, st->render_ms + skip, n * sizeof(double));
    qsort(sorted_ms, n, sizeof(double), cmp_double);
    double sum = 0, render_s = 0;
    for (uint32_t i = 0; i < n; i++)
        sum += sorted_ms[i];
    for (uint32_t i = 0; i < st->timed; i++)
        render_s += st->render_ms[i] * 1e-3;
    hz_render_stats_t total;
    hz_render_frame_stats(r, NULL, &total);
    uint64_t rays = total.primary_rays + total.shadow_rays + total.secondary_rays;
    uint32_t frames = (uint32_t)st->frames;
    char feats[160];
    hz_scene_features_str(scene->features, feats, sizeof feats);
    hz_summary_t sm = {
        .scene = c->scene.scene, .mode = hz_render_mode_name(o->mode),
        .spp = frames ? (double)total.primary_rays / ((double)o->width * o->height * frames) : 0.0,
        .start = (double)c->scene.start * 1e-9, .width = o->width, .height = o->height, .hz = o->frame_hz,
        .frames = frames, .threads = st->threads,
        .backend = hz_scenesrc_accel()->info.backend, .build_ms = st->build_ms,
        .ms_p50 = percentile_of(sorted_ms, n, 0.5), .ms_p99 = percentile_of(sorted_ms, n, 0.99),
        .ms_mean = n ? sum / n : 0, .ms_max = n ? sorted_ms[n - 1] : 0, .frames_timed = n, .rays = rays,
        .rays_per_frame = frames ? (double)rays / frames : 0, .mrays_per_s = render_s > 0 ? rays / render_s * 1e-6 : 0,
        .run_s = run_s, .features = feats, .stats = total, .pools = hz_pools_get(),
        .interrupted = interrupted ? signal_name(interrupted) : NULL,
    };
    char light[256], partial[256];
    const hz_light_t *dl = hz_render_default_light(r);
    if (dl) {
        snprintf(light, sizeof light, "the scene has no lights: lit by a default key light at (%.4g %.4g %.4g) "
                 "(a sidecar 'light = ...' line replaces it)", (double)dl->position[0], (double)dl->position[1],
                 (double)dl->position[2]);
        sm.notes[sm.n_notes++] = light;
    }
    if (o->mode == HZ_MODE_TDENSE && frames < 4) {
        snprintf(partial, sizeof partial, "tdense traces one pixel of every 2x2 tile per frame: %u frame%s leave%s "
                 "the image partly filled in (4 frames make it complete; --mode full renders a complete frame at once)",
                 frames, frames == 1 ? "" : "s", frames == 1 ? "s" : "");
        sm.notes[sm.n_notes++] = partial;
    }
    if (o->shutter > 0.0f) {
        const hz_accel_t *accel = hz_scenesrc_accel();
        sm.shutter = (double)o->shutter;
        sm.blur_accel = accel->info.time_keys < 2 ? "static accel (nothing moves: camera blur only)"
                        : c->scene.backend == HZ_ACCEL_EMBREE ? "Embree motion blur"
                        : accel->info.instances               ? (accel->info.instance_tris < accel->info.tri_count
                                                                     ? hz_accel_blur_name(accel->info.blur)
                                                                     : "rigid instances")
                                                              : hz_accel_blur_name(accel->info.blur);
        sm.instances = accel->info.instances, sm.instance_tris = accel->info.instance_tris;
        if (c->scene.backend != HZ_ACCEL_EMBREE && accel->info.time_keys >= 2u && !accel->info.instances)
            sm.key_sets = accel->info.key_sets, sm.nodes = accel->info.node_count,
            sm.segments = hz_accel_segments_name(c->scene.segments);
        sm.time_keys = accel->info.time_keys, sm.refits = accel->info.refits, sm.rebuilds = accel->info.rebuilds;
    }
    hz_summary_adaptive_t ads;
    if (o->mode == HZ_MODE_ADAPTIVE) {
        hz_adaptive_summary(&total, frames, o->width, o->height, hz_render_gbuffer(r)->object2 != NULL, &ads);
        sm.adaptive = &ads;
    }
    char *settings = settings_json(c, o);
    if (!settings)
        return hz_error_set(err, HZ_E_NO_MEMORY, "summary.json: no memory for the settings");
    sm.settings = settings;
    snprintf(path, sizeof path, "%s/summary.json", c->out);
    s = hz_summary_write_json(&sm, path, err);
    if (s == HZ_OK && !c->quiet)
        hz_summary_print(&sm, stdout);
    free(settings);
    return s;
}

/* ---- the error of each quality level ---- */

/* 8-bit frame -> linear float, as the display shows it. */
static void decode8(const uint8_t *rgb, size_t n, float *out)
{
    for (size_t i = 0; i < n; i++)
        out[i] = hz_srgb8_decode(rgb[i]);
}

/* Each used level's frames against level 0's: the same k frames from the run's start, the last compared. */
static hz_status_t level_errors(const hz_show_cfg_t *c, int w, int h, hz_report_levels_t *lv, hz_error_t *err)
{
    const hz_ladder_t *ld = hz_scenesrc_ladder();
    const hz_scenesrc_stats_t *st = hz_scenesrc_stats();
    const uint32_t k = c->level_error_frames;
    size_t px = (size_t)w * h;
    uint8_t *rgb = malloc(px * 3);
    float *ref = malloc(px * 12), *test = malloc(px * 12);
    const float ppd = HZ_FLIP_DEFAULT_PPD;
    size_t scratch_bytes = hz_flip_scratch_bytes((uint32_t)w, (uint32_t)h, ppd);
    void *scratch = malloc(scratch_bytes);
    hz_status_t s = HZ_OK;
    if (!rgb || !ref || !test || !scratch) {
        s = hz_error_set(err, HZ_E_NO_MEMORY, "level errors: no memory for %dx%d frames", w, h);
        goto done;
    }
    hz_rgb8_image_t out = { rgb, w, h, (size_t)w * 3 };
    hz_image_t ref_img = { (uint32_t)w, (uint32_t)h, ref }, test_img = { (uint32_t)w, (uint32_t)h, test };
    for (uint32_t l = 0; l < ld->count && s == HZ_OK; l++) {
        if (l > 0 && !st->level_frames[l])
            continue; /* only the levels the run used (and the reference) */
        hz_renderer_t *r = hz_scenesrc_renderer();
        for (uint32_t f = 0; f < k && s == HZ_OK; f++) {
            if (f == 0) {
                /* the level's renderer from a cut, like the first frame of a run */
                if ((s = hz_scenesrc_render_at(0, l, c->scene.start, &out, err)) != HZ_OK)
                    break;
                hz_render_reset_history(r);
            }
            s = hz_scenesrc_render_at(f, l, hz_time_of_frame(c->scene.start, f, c->scene.opts.frame_hz), &out, err);
        }
        if (s != HZ_OK)
            break;
        decode8(rgb, px * 3, l == 0 ? ref : test);
        lv->psnr_db[l] = INFINITY, lv->flip[l] = 0.0;
        lv->measured[l] = true;
        if (l == 0)
            continue;
        hz_mse_t m;
        if ((s = hz_mse(&ref_img, &test_img, &m, err)) != HZ_OK)
            break;
        lv->psnr_db[l] = hz_psnr(m.srgb8, 255.0); /* of the sRGB codes, as hzerrtime's tables */
        hz_arena_t a;
        hz_arena_init(&a, "flip scratch", scratch, scratch_bytes);
        double flip = 0;
        if ((s = hz_flip(&ref_img, &test_img, ppd, &a, NULL, &flip, err)) != HZ_OK)
            break;
        lv->flip[l] = flip;
    }
    lv->error_frames = k;
done:
    free(rgb);
    free(ref);
    free(test);
    free(scratch);
    return s;
}

/* ---- the run ---- */

static int usage_error(void)
{
    return HZ_EXIT_USAGE;
}

/* HZ_OW_* bits of a source or sink kind (the board's for `display`); 0: not a kind there is. */
static unsigned source_bits(const char *kind)
{
    static const struct { const char *kind; unsigned bit; } k[] = {
        { "offline", HZ_OW_OFFLINE }, { "sim", HZ_OW_SIM }, { "gpio", HZ_OW_GPIO }, { "fbdev", HZ_OW_FBDEV_SRC },
        { "drm", HZ_OW_DRM_SRC }, { "v4l2", HZ_OW_V4L2_SRC }, { "vcd", HZ_OW_VCD }, { "csv", HZ_OW_CSV },
    };
    for (size_t i = 0; i < sizeof k / sizeof k[0]; i++)
        if (!strcmp(kind, k[i].kind))
            return k[i].bit;
    return 0;
}

static unsigned sink_bits(const char *kind)
{
    if (!strcmp(kind, "display"))
        return !strcmp(HZ_DISPLAY_SINK, "drm") ? HZ_OW_DRM | HZ_OW_FBDEV /* fbdev without a DRM card */
               : !strcmp(HZ_DISPLAY_SINK, "none") ? HZ_OW_NONE
                                                  : HZ_OW_FBDEV;
    static const struct { const char *kind; unsigned bit; } k[] = {
        { "files", HZ_OW_FILES }, { "none", HZ_OW_NONE }, { "drm", HZ_OW_DRM }, { "fbdev", HZ_OW_FBDEV },
        { "v4l2", HZ_OW_V4L2 },
    };
    for (size_t i = 0; i < sizeof k / sizeof k[0]; i++)
        if (!strcmp(kind, k[i].kind))
            return k[i].bit;
    return 0;
}

/* Set by the first SIGINT, SIGTERM or SIGHUP while the loop runs (fileio.h): the run ends after the frame in
 * progress and keeps what it finished. */
static volatile sig_atomic_t interrupted;
typedef char sig_atomic_is_int[sizeof(sig_atomic_t) == sizeof(int) ? 1 : -1]; /* the loop reads it as an int */
static const char interrupt_note[] = "\nhzrt: interrupted: finishing the frame in progress and keeping what is done "
                                     "(interrupt again to quit at once)\n";

static int show_run(hz_show_cfg_t *c, size_t *made_from);

bool hz_show_check_only = false;

int hz_show_run(hz_show_cfg_t *c)
{
    size_t made_from = 0;
    interrupted = 0;
    int rc = show_run(c, &made_from);
    if (rc != 0 && rc != HZ_EXIT_NOLOCK)
        hz_out_dir_unmake(c->out, made_from); /* a failed run leaves no (empty) folder it made */
    if (interrupted)
        hz_out_die(interrupted); /* what was finished is written: now end as the signal asked */
    return rc;
}

static int show_run(hz_show_cfg_t *c, size_t *made_from)
{
    hz_error_t err;
    hz_error_clear(&err);
    const char *cmd = c->cmd;
    hz_phase_muted = c->quiet;
    int64_t period = c->hz > 0 ? (int64_t)(1e9 / c->hz + 0.5) : 0;
    char kind[16];
    const char *rest;
    split_spec(c->source, kind, sizeof kind, &rest);
    const bool offline = !strcmp(kind, "offline");
    const bool timeline = offline || !strcmp(kind, "sim") || !strcmp(kind, "vcd") || !strcmp(kind, "csv");
    const bool trace_file = !strcmp(kind, "vcd") || !strcmp(kind, "csv");
    const bool edges_only = c->what == HZ_SHOW_EDGES;
    const bool scene = c->what == HZ_SHOW_SCENE;
    char skind[16];
    const char *srest;
    split_spec(c->sink, skind, sizeof skind, &srest);
    const bool files = !strcmp(skind, "files");
    /* ---- the combination, before anything is opened ---- */
    if (!source_bits(kind)) {
        hz_cli_error("%s: --source: '%s' is not offline, sim, gpio[:CHIP[:LINE]], fbdev[:DEV], v4l2, drm, vcd:FILE or "
                     "csv:FILE", cmd, c->source);
        return usage_error();
    }
    if (!sink_bits(skind)) {
        hz_cli_error("%s: --sink: '%s' is not files, none, display, drm[:CARD[:CONNECTOR[:WxH[@HZ]]]], fbdev[:DEV] or "
                     "v4l2:DEV[:FORMAT]", cmd, c->sink);
        return usage_error();
    }
    if (offline && (c->virt || c->model)) {
        hz_cli_error("%s: --virtual and --render-model simulate a display's clock; --source offline renders every "
                     "frame without one", cmd);
        return usage_error();
    }
    if (c->virt && !timeline) {
        hz_cli_error("%s: --virtual needs a timeline source (sim, vcd or csv), not '%s'", cmd, c->source);
        return usage_error();
    }
    if (c->virt && !edges_only && !c->model) {
        hz_cli_error("%s: --virtual needs --render-model (e.g. uniform:0.2P:0.8P)", cmd);
        return usage_error();
    }
    if (c->model && !c->virt) {
        hz_cli_error("%s: --render-model only applies with --virtual (in real time render times are measured)", cmd);
        return usage_error();
    }
    if (c->frames && c->seconds > 0) {
        hz_cli_error("%s: give --frames or --seconds, not both", cmd);
        return usage_error();
    }
    if (offline && c->seconds > 0) {
        hz_cli_error("%s: --seconds needs a display's clock; offline runs count --frames", cmd);
        return usage_error();
    }
    if (edges_only && (files || c->budget == 1)) {
        hz_cli_error("%s: capturing edges only renders no frames: %s does nothing", cmd,
                     files ? "--sink files" : "--budget on");
        return usage_error();
    }
    if (c->budget == 1 && (offline || c->virt)) {
        hz_cli_error("%s: --budget on needs a display that sets the pace in real time: %s", cmd,
                     offline ? "--source offline renders every frame however long it takes"
                             : "with --virtual render times come from --render-model, not from the quality levels");
        return usage_error();
    }
    if (c->budget == 1 && !scene) {
        hz_cli_error("%s: --budget on picks the quality of a scene's frames: it needs --render scene", cmd);
        return usage_error();
    }
    if (!scene && c->level_error_frames) {
        hz_cli_error("%s: --level-error measures a scene's quality levels: it needs --render scene", cmd);
        return usage_error();
    }
    if (!files && !c->video) {
        hz_cli_error("%s: --no-y4m: only the files sink writes frames.y4m (this run's sink is %s)", cmd, c->sink);
        return usage_error();
    }
    if (c->hz == 0 && (offline || !strcmp(kind, "sim"))) {
        hz_cli_error("%s: --hz 0 learns the rate from a display's edges; --source %s needs a rate", cmd, kind);
        return usage_error();
    }
    /* every other option given where it does nothing (the tables say where each acts) */
    unsigned where = source_bits(kind) | sink_bits(skind) |
                     (edges_only ? HZ_OW_EDGES : scene ? HZ_OW_SCENE : HZ_OW_PATTERN) |
                     (c->virt || offline ? HZ_OW_VIRTUAL : HZ_OW_REAL);
    int rc = hz_sopts_check(c, where);
    if (rc)
        return rc;
    /* offline, by default, one complete image: tdense fills in each 2x2 tile over 4 frames */
    if (offline && !c->frames && !(c->seconds > 0))
        c->frames = scene && c->scene.opts.mode == HZ_MODE_TDENSE ? 4 : 1;
    if (offline && c->frames > HZ_SHOW_MAX_OFFLINE_FRAMES) {
        hz_cli_error("%s: --frames: %llu is more than %d offline frames", cmd, (unsigned long long)c->frames,
                     HZ_SHOW_MAX_OFFLINE_FRAMES);
        return usage_error();
    }
    /* a frame size the command line sets (no sink mode to wait for) is checked against the render scale and the
     * marker now */
    const bool sink_has_mode = sink_bits(skind) & HZ_OW_DEVICE_SINKS;
    if (!edges_only && (!sink_has_mode || c->size_given) &&
        (c->marker < 0 ? (strcmp(skind, "none") && !files) : c->marker)) {
        hz_marker_layout_t ml;
        if (hz_marker_layout(c->w, c->h, &ml, &err) != HZ_OK) {
            hz_cli_error("%s: --marker: %s", cmd, err.msg);
            return usage_error();
        }
    }
    if (scene && (!sink_has_mode || c->size_given) && (c->w % c->render_scale || c->h % c->render_scale)) {
        hz_cli_error("%s: the %dx%d frame (--size) is not a multiple of --render-scale %d", cmd, c->w, c->h,
                     c->render_scale);
        return usage_error();
    }
    hz_rtm_cfg_t model;
    if (c->model) {
        if (!parse_model(c->model, period, &model))
            return usage_error();
        model.seed = (uint64_t)c->seed;
        if (c->wake && !parse_time("--wake", c->wake, period, &model.wake_ns))
            return usage_error();
    }
    hz_loop_cfg_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.frames_mode = !edges_only;
    cfg.nominal_period_ns = period;
    cfg.edge_mode = c->edge_mode;
    cfg.pace.percentile = (uint32_t)(c->percentile * 10 + 0.5);
    cfg.pace.window = (uint32_t)c->window;
    cfg.pace.lookahead = (uint32_t)c->lookahead;
    cfg.pace.guard_ns = -1;
    if (c->guard && !parse_time("--guard", c->guard, period, &cfg.pace.guard_ns))
        return usage_error();
    if (c->latch && !parse_time("--latch", c->latch, period, &cfg.pace.latch_ns))
        return usage_error();
    cfg.edge_timeout_ns = c->timeout_ms * 1000000LL;
    cfg.lock = c->lock;
    if (offline) {
        /* every frame for the refresh after the one before, rendered in no (simulated) time */
        memset(&model, 0, sizeof model);
        model.kind = HZ_RTM_CONST;
        cfg.rtm = &model;
    } else {
        cfg.rtm = c->model ? &model : NULL;
    }
    cfg.governor = scene && !edges_only && (c->budget == 1 || (c->budget < 0 && !offline && !c->virt));
    if (hz_show_check_only)
        return 0;

    /* The output folder before the run (one that cannot be written is refused now, not after it), and every
     * output in it or elsewhere: none may be an input or another output. */
    char created[1024];
    if (hz_out_dir_make(c->out, created, sizeof created, made_from, &err) != HZ_OK)
        return hz_cli_report(&err);
    {
        static hz_outs_t outs;
        hz_outs_init(&outs);
        char p[4096];
#define OUT_FILE(name, what)                                                                                   \
    do {                                                                                                       \
        snprintf(p, sizeof p, "%s/%s", c->out, name);                                                          \
        hz_outs_output(&outs, p, what);                                                                        \
    } while (0)
        if (files && c->video && (c->frames != 1 || !offline))
            OUT_FILE("frames.y4m", "the run's frames.y4m");
        if (files && c->png)
            OUT_FILE(hz_png_supported() ? "last.png" : "last.ppm", "the run's last frame");
        if (scene)
            OUT_FILE("summary.json", "the run's summary.json");
        if (scene && c->pfm)
            OUT_FILE("last.pfm", "the run's last.pfm");
        if (!offline) {
            if (!edges_only)
                OUT_FILE("frames.csv", "the run's frames.csv");
            OUT_FILE("edges.csv", "the run's edges.csv");
            OUT_FILE("report.json", "the run's report.json");
            OUT_FILE("histogram.svg", "the run's histogram.svg");
        }
#undef OUT_FILE
        if (scene && c->adaptive && c->adaptive->map_path)
            hz_outs_output(&outs, c->adaptive->map_path, "--adaptive-map");
        if (scene && strcmp(c->scene.scene, "builtin"))
            hz_outs_input(&outs, c->scene.scene, "the scene");
        if (trace_file && *rest)
            hz_outs_input(&outs, rest, "the --source trace");
        if (hz_outs_check(&outs, &err) != HZ_OK) {
            if (err.code != HZ_E_INVALID_ARG)
                return hz_cli_report(&err);
            hz_cli_error("%s: %s", cmd, err.msg);
            return usage_error();
        }
    }

    /* Real-time scheduling first: threads started later (the renderer's workers) inherit it. */
    char sched[128] = "";
    if (c->rt && !c->virt && !offline)
        rt_setup(sched, sizeof sched);

    /* ---- the sink first: its mode sets the frame size, and V4L2 output is also a source ---- */
    hz_sink_t sink;
    hz_vsource_t src;
    memset(&sink, 0, sizeof sink);
    memset(&src, 0, sizeof src);
    hz_status_t s = HZ_OK;
    int src_open = 0;
    int drm_fallback = 0;
    const int fw = c->w, fh = c->h; /* where the sink has no mode */
    if (!strcmp(skind, "display") && !edges_only) {
        /* The board's display: DRM where the board says so, fbdev when no DRM card or display is there. */
        snprintf(skind, sizeof skind, "%s", HZ_DISPLAY_SINK);
        drm_fallback = !strcmp(skind, "drm");
        srest = "";
    }
    if (edges_only || !strcmp(skind, "none")) {
        hz_sink_null(&sink);
    } else if (files) {
        if (*srest) {
            hz_cli_error("%s: --sink files takes no device ('%s'): the files go to --out", cmd, c->sink);
            return usage_error();
        }
        hz_file_sink_cfg_t fc = { c->out, c->video && (c->frames > 1 || !offline),
                                  (uint32_t)(c->hz > 0 ? c->hz + 0.5 : HZ_DISPLAY_HZ), fw, fh };
        s = hz_file_sink_open(&sink, &fc, &err);
    } else if (!strcmp(skind, "drm")) {
        hz_drm_cfg_t dc;
        char spec[256];
        s = *hz_devices_missing("drm") ? hz_error_set(&err, HZ_E_UNSUPPORTED, "--sink drm: %s", hz_devices_missing("drm"))
                                       : hz_drm_parse_spec(srest, &dc, spec, sizeof spec, &err);
        if (s == HZ_E_INVALID_ARG) {
            hz_cli_error("%s", err.msg);
            return usage_error();
        }
        if (s == HZ_OK) {
            dc.buffers = c->drm_buffers;
            s = hz_drm_sink_open(&sink, !strcmp(kind, "drm") ? &src : NULL, &dc, &err);
            src_open = s == HZ_OK && !strcmp(kind, "drm");
        }
        if (s != HZ_OK && drm_fallback && strcmp(kind, "drm")) {
            hz_cli_error("note: %s; using fbdev %s", err.msg, HZ_DISPLAY_DEVICE);
            hz_error_clear(&err);
            s = hz_fbdev_sink_open(&sink, HZ_DISPLAY_DEVICE, NULL, &err);
        }
    } else if (!strcmp(skind, "fbdev")) {
        s = hz_fbdev_sink_open(&sink, *srest ? srest : HZ_DISPLAY_DEVICE, NULL, &err);
    } else if (!strcmp(skind, "v4l2")) {
        char dev[256];
        snprintf(dev, sizeof dev, "%s", srest);
        char *fmt_s = strchr(dev, ':');
        hz_pix_fmt_t fmt = HZ_PIX_RGB24;
        if (fmt_s) {
            *fmt_s++ = '\0';
            s = hz_pix_parse(fmt_s, &fmt, &err);
        }
        if (s == HZ_OK && !*dev) {
            hz_cli_error("--sink v4l2:DEV needs the output device, e.g. v4l2:/dev/video1");
            return usage_error();
        }
        if (s == HZ_OK) {
            s = hz_v4l2_out_open(&sink, !strcmp(kind, "v4l2") ? &src : NULL, dev, fmt, c->size_given ? c->w : 0,
                                 c->size_given ? c->h : 0, NULL, &err);
            src_open = s == HZ_OK && !strcmp(kind, "v4l2");
        }
    } else {
        hz_cli_error("--sink: '%s' is not files, none, display, drm[:CARD[:CONNECTOR[:WxH[@HZ]]]], fbdev[:DEV] or "
                     "v4l2:DEV[:FORMAT]", c->sink);
        return usage_error();
    }
    if (s != HZ_OK)
        return hz_cli_report(&err);

    /* ---- the v-sync source ---- */
    if (!strcmp(kind, "sim") || offline) {
        hz_vsynth_cfg_t g;
        memset(&g, 0, sizeof g);
        g.period_q16 = hz_vsync_period_q16_from_mhz((uint64_t)((c->hz > 0 ? c->hz : HZ_DISPLAY_HZ) * 1000 + 0.5));
        if (!offline) {
            g.jitter_ns = (int64_t)(c->jitter_us * 1000);
            g.drift_ppb_start = g.drift_ppb_end = (int32_t)(c->drift_ppm * 1000);
            g.miss_ppm = (uint32_t)(c->miss_pct * 1e4);
            g.glitch_ppm = (uint32_t)(c->glitch_pct * 1e4);
        }
        g.seed = (uint64_t)c->seed;
        s = hz_vsource_sim(&src, &g, &err);
        if (s == HZ_OK && offline)
            snprintf(src.name, sizeof src.name, "offline (every frame, at simulated %.6g Hz times)", c->hz);
    } else if (trace_file) {
        if (!*rest) {
            hz_cli_error("--source %s:FILE needs a file", kind);
            hz_sink_close(&sink);
            return usage_error();
        }
        s = !strcmp(kind, "vcd") ? hz_vsource_vcd(&src, rest, c->signal, &err) : hz_vsource_csv(&src, rest, &err);
    } else if (!strcmp(kind, "gpio")) {
        if (*hz_devices_missing("gpio")) {
            hz_error_set(&err, HZ_E_UNSUPPORTED, "--source gpio: %s", hz_devices_missing("gpio"));
            s = err.code;
        } else {
            char chip[128];
            snprintf(chip, sizeof chip, "%s", *rest ? rest : HZ_VSYNC_GPIO_CHIP);
            long line = HZ_VSYNC_GPIO_LINE;
            char *colon = strchr(chip, ':');
            if (colon) {
                *colon++ = '\0';
                if (!hz_cli_parse_long("--source gpio:CHIP:LINE", colon, 0, 1023, &line)) {
                    hz_sink_close(&sink);
                    return usage_error();
                }
            }
            if (!*chip || line < 0) {
                hz_cli_error("--source gpio: this board names no v-sync GPIO; give gpio:CHIP:LINE");
                hz_sink_close(&sink);
                return usage_error();
            }
            hz_gpio_cfg_t gc = { chip, (int)line, c->active_low || HZ_VSYNC_GPIO_ACTIVE_LOW, NULL, 0 };
            if (c->one_edge)
                gc.one_edge = c->edge_mode == HZ_EDGE_FALLING ? -1 : 1;
            s = hz_gpio_vsource_open(&src, &gc, &err);
        }
    } else if (!strcmp(kind, "fbdev")) {
        s = hz_fbdev_vsource_open(&src, *rest ? rest : HZ_DISPLAY_DEVICE, NULL, &err);
    } else if (!strcmp(kind, "drm")) {
        if (!src_open) {
            hz_cli_error("--source drm takes the vblank or page-flip events of the DRM sink: add --sink drm[:...]");
            hz_sink_close(&sink);
            return usage_error();
        }
    } else if (!strcmp(kind, "v4l2")) {
        if (!src_open) {
            hz_cli_error("--source v4l2 takes the dequeue timestamps of a V4L2 output: add --sink v4l2:DEV");
            hz_sink_close(&sink);
            return usage_error();
        }
    } else {
        hz_cli_error("--source: '%s' is not offline, sim, gpio[:CHIP[:LINE]], fbdev[:DEV], v4l2, drm, vcd:FILE or "
                     "csv:FILE", c->source);
        hz_sink_close(&sink);
        return usage_error();
    }
    if (s != HZ_OK) {
        hz_sink_close(&sink);
        return hz_cli_report(&err);
    }

    /* ---- frames ---- */
    hz_framesrc_t frames = hz_framesrc_testpattern();
    cfg.w = sink.w ? sink.w : fw;
    cfg.h = sink.h ? sink.h : fh;
    if (sink.w && c->size_given && (c->w != sink.w || c->h != sink.h)) {
        hz_error_set(&err, HZ_E_UNSUPPORTED, "%s: the display mode is %dx%d, --size asked for %dx%d", sink.name,
                     sink.w, sink.h, c->w, c->h);
        s = err.code;
    }
    if (s == HZ_OK && scene) {
        /* the render size: the frame's over the render scale (the user's --size of a files run is the render
         * size; a display's mode sets it otherwise) */
        if (cfg.w % c->render_scale || cfg.h % c->render_scale) {
            hz_error_set(&err, HZ_E_INVALID_ARG, "the %dx%d frame is not a multiple of --render-scale %d", cfg.w,
                         cfg.h, c->render_scale);
            s = err.code;
        } else {
            c->scene.opts.width = (uint32_t)(cfg.w / c->render_scale);
            c->scene.opts.height = (uint32_t)(cfg.h / c->render_scale);
            c->scene.opts.frame_hz = (uint32_t)(c->hz > 0 ? c->hz + 0.5 : HZ_DISPLAY_HZ);
            c->scene.out_w = cfg.w, c->scene.out_h = cfg.h;
            c->scene.levels = cfg.governor;
            c->scene.clock = timeline ? HZ_SCENE_CLOCK_SLOTS : HZ_SCENE_CLOCK_DISPLAY;
            c->scene.quiet = c->quiet;
            c->scene.frame_progress = offline && c->frames == 1;
            hz_render_opts_t probe = c->scene.opts;
            if (hz_render_opts_check(&probe, &err) != HZ_OK) {
                hz_cli_error("%s: %s", cmd, err.msg);
                hz_vsource_close(&src);
                hz_sink_close(&sink);
                return usage_error();
            }
            s = hz_scenesrc_open(&c->scene, &frames, &err);
        }
    }
    cfg.marker = c->marker < 0 ? (strcmp(skind, "none") && !files) : c->marker;
    /* what the run uses, for summary.json's settings */
    c->marker = cfg.marker;
    c->budget = cfg.governor;
    c->w = cfg.w, c->h = cfg.h;
    /* ---- run length and record capacity ---- */
    double hz_cap = c->hz > 0 ? c->hz : 1000;
    double seconds = c->seconds > 0 ? c->seconds : (c->frames ? 0 : 10);
    cfg.frames = c->frames;
    cfg.duration_ns = (int64_t)(seconds * 1e9);
    if (edges_only && trace_file && c->seconds <= 0)
        cfg.duration_ns = 0; /* the whole trace */
    cfg.max_frames = c->frames ? c->frames : (size_t)(seconds * hz_cap * 1.1) + 64;
    hz_pools_t *pools = hz_pools_get();
    if (!pools && s == HZ_OK) {
        s = hz_pools_error(&err, "show");
    }
    if (s == HZ_OK) {
        if (edges_only && trace_file && cfg.duration_ns == 0) {
            /* A trace of unknown length: as many edges as the frame arena holds. */
            size_t per = sizeof(hz_edge_rec_t) + sizeof(uint32_t) + sizeof(int64_t);
            size_t avail = hz_arena_available(&pools->frame, 64);
            cfg.max_frames = 0;
            cfg.max_edges = avail > 1024 ? (avail - 1024) / per : 1;
            /* but no more than the file can hold: an edge takes at least two bytes of text (a VCD "1!", a CSV
             * "0\n"), so a small trace is refused or read without touching the whole arena */
            struct stat fst;
            if (stat(rest, &fst) == 0 && (uint64_t)fst.st_size / 2 + 16 < (uint64_t)cfg.max_edges)
                cfg.max_edges = (size_t)(fst.st_size / 2 + 16);
        } else {
            double refreshes = c->frames ? (double)c->frames * 4 : seconds * hz_cap;
            cfg.max_edges = (size_t)(refreshes * 2.5) + 256;
        }
        if (!cfg.frames_mode)
            cfg.max_frames = 0;
    }
    hz_loop_result_t res;
    memset(&res, 0, sizeof res);
    hz_timebase_t tb;
    if (c->virt || offline || (edges_only && !src.live))
        hz_tb_init_virtual(&tb, 0);
    else
        hz_tb_init_real(&tb);
    hz_arena_mark_t mark = pools ? hz_arena_mark(&pools->frame) : 0;
    int64_t run0 = hz_clock_ns();
    cfg.stop = (const volatile int *)&interrupted;
    hz_out_signals_defer(&interrupted, c->quiet ? NULL : interrupt_note);
    if (s == HZ_OK)
        s = hz_loop_run(&cfg, &tb, &src, &sink, &frames, &pools->frame, &res, &err);
    hz_out_signals_defer(NULL, NULL);
    double run_s = (double)(hz_clock_ns() - run0) * 1e-9;
    hz_vsource_close(&src);
    rc = 0;
    /* ---- what the run writes ---- */
    if (s == HZ_OK && files) {
        const hz_rgb8_image_t *last = hz_file_sink_last(&sink);
        if ((s = hz_file_sink_commit(&sink, &err)) == HZ_OK && c->png && last) {
            /* Builds without libpng (cross builds) write the same 8-bit sRGB pixels as PPM. */
            char path[4096];
            bool png = hz_png_supported();
            snprintf(path, sizeof path, "%s/last.%s", c->out, png ? "png" : "ppm");
            s = png ? hz_png_write_rgb8(path, last->rgb, (uint32_t)last->w, (uint32_t)last->h, last->stride, &err)
                    : hz_ppm_write_rgb8(path, last->rgb, (uint32_t)last->w, (uint32_t)last->h, last->stride, &err);
        }
    }
    char sink_name[160];
    snprintf(sink_name, sizeof sink_name, "%s", sink.name[0] ? sink.name : c->sink);
    hz_sink_close(&sink);
    if (s == HZ_OK && scene)
        s = write_scene_outputs(c, run_s, interrupted, &err);
    hz_report_levels_t levels;
    memset(&levels, 0, sizeof levels);
    if (s == HZ_OK && scene) {
        const hz_ladder_t *ld = hz_scenesrc_ladder();
        levels.count = ld->count;
        levels.governor = cfg.governor;
        for (uint32_t l = 0; l < ld->count; l++)
            snprintf(levels.name[l], sizeof levels.name[l], "%s", ld->level[l].name);
        if (cfg.governor && c->level_error_frames) {
            if (!c->quiet)
                fprintf(stderr, "%s: %s: measuring each used level's error against level 0 (%u frames each)\n",
                        hz_cli_prog, cmd, c->level_error_frames);
            s = level_errors(c, cfg.w, cfg.h, &levels, &err);
        }
    }
    if (s == HZ_OK && !offline) {
        /* Recorded traces keep their own times in edges.csv; the simulated display has no clock but the loop's. */
        if (!trace_file)
            res.trace_offset_ns = 0;
        char clock[160];
        if (c->virt && cfg.frames_mode)
            snprintf(clock, sizeof clock, "simulated clock, render-time model %s%s%s", c->model,
                     c->wake ? ", wake-up up to " : "", c->wake ? c->wake : "");
        else if (tb.virtual_time)
            snprintf(clock, sizeof clock, "trace time (analysed as fast as it reads)");
        else
            snprintf(clock, sizeof clock, "real time (CLOCK_MONOTONIC)%s%s", sched[0] ? ", " : "", sched);
        char what[512];
        if (scene)
            snprintf(what, sizeof what, "%s (%s), mode %s, rendered at %ux%u (scale 1/%d), %d threads", frames.name,
                     c->scene.scene, hz_render_mode_name(c->scene.opts.mode), c->scene.opts.width,
                     c->scene.opts.height, c->render_scale, hz_scenesrc_stats()->threads);
        else
            snprintf(what, sizeof what, "%s", frames.name);
        hz_report_info_t info = { src.name, sink_name, what, clock, cfg.w, cfg.h, cfg.marker, scene ? &levels : NULL,
                                  NULL, NULL, 0, 0, 0, 0 };
        if (scene) {
            info.scene_file = c->scene.scene;
            info.mode = hz_render_mode_name(c->scene.opts.mode);
            info.render_w = (int)c->scene.opts.width, info.render_h = (int)c->scene.opts.height;
            info.render_scale = c->render_scale;
            info.threads = hz_scenesrc_stats()->threads;
        }
        static hz_report_t rep;
        hz_report_compute(&rep, &cfg, &info, &res);
        if (!c->quiet)
            hz_report_print(stdout, &rep);
        s = hz_report_write(c->out, &rep, &err);
        if (s == HZ_OK && !c->quiet)
            printf("wrote     %s/{%sedges.csv,report.json,histogram.svg%s}\n", c->out,
                   cfg.frames_mode ? "frames.csv," : "", scene ? ",summary.json" : "");
        if (s == HZ_OK && res.lock.verdict != HZ_LOCK_OK) {
            char why[256];
            hz_cli_error("%s: %s: %s", src.name, hz_report_lock_verdict(&res.lock),
                         hz_report_lock_reasons(why, sizeof why, &res.lock));
            rc = HZ_EXIT_NOLOCK;
        } else if (s == HZ_OK && res.lock.far && c->quiet) {
            hz_cli_error("warning: %s: the measured rate %.4f Hz is far from --hz %g", src.name,
                         1e9 * 65536.0 / (double)res.lock.period_q16, c->hz);
        }
    } else if (s == HZ_OK && !c->quiet && files) {
        printf("wrote        %s/{%ssummary.json}\n", c->out,
               res.n_frames > 1 && c->video ? "frames.y4m,last.png," : "last.png,");
    }
    /* the loop's records, then the scene source's arenas, given back */
    if (pools)
        hz_arena_reset(&pools->frame, mark);
    if (scene)
        hz_scenesrc_close();
    if (s != HZ_OK)
        return hz_cli_report(&err);
    if (created[0] && !c->quiet)
        fprintf(stderr, "%s: %s: --out: created %s\n", hz_cli_prog, cmd, created);
    return rc;
}
