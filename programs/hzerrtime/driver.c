/* errtime's driver: reference cache, timed method runs, scoring (see errtime.h). */
#include "errtime.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "clock.h"
#include "fileio.h"
#include "et_flip.h"
#include "imageio.h"
#include "et_metrics.h"
#include "et_progress.h"

/* Path buffers: a cache entry's directory, its temporary twin, and the files inside. */
#define DIR_BYTES 4096
#define TMP_BYTES (DIR_BYTES + 32)
#define FILE_BYTES (TMP_BYTES + 32)

uint32_t hz_et_window(uint32_t refresh_hz)
{
    uint32_t k = (refresh_hz + 30) / 60;
    return k ? k : 1;
}

size_t hz_et_arena_bytes(const hz_et_sequence_t *seq, float ppd)
{
    size_t frame = 0;
    if (hz_image_check_size(seq->width, seq->height, &frame, NULL) != HZ_OK)
        return 0;
    size_t k = hz_et_window(seq->refresh_hz);
    size_t flip = hz_flip_scratch_bytes(seq->width, seq->height, ppd);
    size_t ssim = hz_ssim_scratch_bytes(seq->width, seq->height);
    /* out, 2k ring frames, 2 means, one reference being read; render times; scratch for the larger metric. */
    return (3 + 2 * k + 1) * (frame + 64) + (size_t)seq->frames * sizeof(int64_t) + (flip > ssim ? flip : ssim) +
           4096;
}

/* ---- cache ---- */

static uint64_t fnv1a64(const char *s)
{
    uint64_t h = 0xcbf29ce484222325ull;
    for (; *s; s++) {
        h ^= (uint8_t)*s;
        h *= 0x100000001b3ull;
    }
    return h;
}

static const char *or_empty(const char *s)
{
    return s ? s : "";
}

/* File-name-safe copy of s (letters, digits, '-', '_', '.'; a leading '.' becomes '_'). */
static void safe_name(char *out, size_t size, const char *s)
{
    size_t n = 0;
    for (; *s && n + 1 < size; s++) {
        char c = *s;
        bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                  c == '_' || c == '.';
        out[n] = ok && !(n == 0 && c == '.') ? c : '_';
        n++;
    }
    if (n == 0 && size > 1)
        out[n++] = '_';
    out[n] = '\0';
}

hz_status_t hz_et_cache_entry(const hz_et_sequence_t *seq, const hz_et_method_t *reference, const char *cache_dir,
                              char *dir, size_t dir_size, char *key, size_t key_size, hz_error_t *err)
{
    int n = snprintf(key, key_size,
                     "hzrt errtime reference cache v%d\nscene %s\nscene_hash %016llx\ncamera %s\nsettings %s\n"
                     "size %ux%u\nframes %u\nrefresh_hz %u\nreference %s %s=%.17g\n",
                     HZ_ET_CACHE_VERSION, or_empty(seq->scene), (unsigned long long)seq->scene_hash,
                     or_empty(seq->camera), or_empty(seq->settings), (unsigned)seq->width, (unsigned)seq->height,
                     (unsigned)seq->frames, (unsigned)seq->refresh_hz, or_empty(reference->name),
                     or_empty(reference->knob), reference->value);
    if (n < 0 || (size_t)n >= key_size)
        return hz_error_set(err, HZ_E_RANGE, "errtime: the cache key is longer than %zu bytes", key_size);
    char name[65];
    safe_name(name, sizeof name, or_empty(seq->scene));
    n = snprintf(dir, dir_size, "%s/%s-%016llx", cache_dir, name, (unsigned long long)fnv1a64(key));
    if (n < 0 || (size_t)n >= dir_size)
        return hz_error_set(err, HZ_E_RANGE, "%s: cache path too long", cache_dir);
    return HZ_OK;
}

static void frame_path(char *buf, size_t size, const char *dir, uint32_t i)
{
    snprintf(buf, size, "%s/ref-%05u.pfm", dir, (unsigned)i);
}

static bool exists(const char *path, bool *is_dir)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return false;
    if (is_dir)
        *is_dir = S_ISDIR(st.st_mode);
    return true;
}

/* Removes a temporary entry: its frames, its key and the directory. */
static void remove_entry(const char *dir, uint32_t frames)
{
    char p[FILE_BYTES];
    for (uint32_t i = 0; i < frames; i++) {
        frame_path(p, sizeof p, dir, i);
        unlink(p);
    }
    snprintf(p, sizeof p, "%s/key.txt", dir);
    unlink(p);
    rmdir(dir);
}

static hz_status_t check_entry(const char *dir, const char *key, const hz_et_sequence_t *seq, hz_error_t *err)
{
    char p[FILE_BYTES], got[4096];
    snprintf(p, sizeof p, "%s/key.txt", dir);
    size_t n = 0;
    hz_error_t e;
    if (hz_file_read(p, got, sizeof got - 1, &n, &e) != HZ_OK)
        return hz_error_set(err, HZ_E_CORRUPT, "reference cache %s is incomplete (%s); delete it to rebuild it",
                            dir, e.msg);
    got[n] = '\0';
    if (strcmp(got, key) != 0)
        return hz_error_set(err, HZ_E_CORRUPT, "reference cache %s/key.txt does not match this sequence; delete "
                            "the directory to rebuild it", dir);
    for (uint32_t i = 0; i < seq->frames; i++) {
        bool is_dir = false;
        frame_path(p, sizeof p, dir, i);
        if (!exists(p, &is_dir) || is_dir)
            return hz_error_set(err, HZ_E_CORRUPT, "reference cache: %s is missing; delete %s to rebuild it", p,
                                dir);
    }
    return HZ_OK;
}

static hz_status_t method_error(hz_error_t *err, const hz_et_method_t *m, const char *what, int64_t frame)
{
    char prefix[160];
    if (frame >= 0)
        snprintf(prefix, sizeof prefix, "%s %s=%g, frame %lld: %s", m->name, m->knob, m->value, (long long)frame,
                 what);
    else
        snprintf(prefix, sizeof prefix, "%s %s=%g: %s", m->name, m->knob, m->value, what);
    hz_error_prefix(err, prefix);
    return err ? err->code : HZ_E_INTERNAL;
}

static hz_status_t render_reference(const hz_et_sequence_t *seq, const hz_et_method_t *ref, const hz_et_config_t *cfg,
                                    const char *tmp, const char *key, hz_error_t *err)
{
    hz_arena_t *a = cfg->arena;
    hz_arena_mark_t mark = hz_arena_mark(a);
    hz_image_t out;
    hz_status_t s = hz_image_alloc(&out, a, seq->width, seq->height, err);
    if (s != HZ_OK)
        return method_error(err, ref, "reference frame", -1);
    void *state = NULL;
    if (ref->begin && (s = ref->begin(ref, seq, a, &state, err)) != HZ_OK) {
        hz_arena_reset(a, mark);
        return method_error(err, ref, "reference begin", -1);
    }
    hz_progress_t prog;
    hz_progress_begin(&prog, cfg->progress, cfg->progress_tty, seq->frames);
    char label[64];
    snprintf(label, sizeof label, "reference %s %s=%g", ref->name, ref->knob, ref->value);
    hz_progress_label(&prog, label);
    char path[FILE_BYTES];
    for (uint32_t i = 0; i < seq->frames && s == HZ_OK; i++) {
        uint64_t rays = 0;
        if ((s = ref->render(state, i, &out, &rays, err)) != HZ_OK) {
            method_error(err, ref, "reference render", i);
            break;
        }
        frame_path(path, sizeof path, tmp, i);
        s = hz_pfm_write(path, &out, err);
        hz_progress_step(&prog, 1);
    }
    if (ref->end)
        ref->end(state);
    hz_progress_end(&prog);
    hz_arena_reset(a, mark);
    if (s != HZ_OK)
        return s;
    snprintf(path, sizeof path, "%s/key.txt", tmp);
    return hz_file_write_atomic(path, key, strlen(key), err);
}

hz_status_t hz_et_reference(const hz_et_sequence_t *seq, const hz_et_method_t *reference, const hz_et_config_t *cfg,
                            bool *rendered, hz_error_t *err)
{
    char dir[DIR_BYTES], key[2048];
    *rendered = false;
    hz_status_t s = hz_et_cache_entry(seq, reference, cfg->cache_dir, dir, sizeof dir, key, sizeof key, err);
    if (s != HZ_OK)
        return s;
    bool is_dir = false;
    if (exists(dir, &is_dir)) {
        if (!is_dir)
            return hz_error_set(err, HZ_E_CORRUPT, "reference cache %s is not a directory; delete it", dir);
        return check_entry(dir, key, seq, err);
    }
    if ((s = hz_mkdirs(cfg->cache_dir, err)) != HZ_OK)
        return s;
    char tmp[TMP_BYTES];
    snprintf(tmp, sizeof tmp, "%s.tmp-XXXXXX", dir);
    if (!mkdtemp(tmp))
        return hz_error_set(err, HZ_E_IO, "%s: cannot create a temporary cache directory: %s", tmp, strerror(errno));
    s = render_reference(seq, reference, cfg, tmp, key, err);
    if (s != HZ_OK) {
        remove_entry(tmp, seq->frames);
        return s;
    }
    if (rename(tmp, dir) != 0) {
        int e = errno;
        remove_entry(tmp, seq->frames);
        if ((e == EEXIST || e == ENOTEMPTY) && exists(dir, NULL)) /* another run finished the same entry first */
            return check_entry(dir, key, seq, err);
        return hz_error_set(err, HZ_E_IO, "%s: cannot move the finished cache entry into place: %s", dir,
                            strerror(e));
    }
    *rendered = true;
    return HZ_OK;
}

/* ---- runs ---- */

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return x < y ? -1 : x > y;
}

void hz_et_time_stats(int64_t *ns, size_t n, double *median_ms, double *p99_ms)
{
    qsort(ns, n, sizeof *ns, cmp_i64);
    double median = n % 2 ? (double)ns[n / 2] : 0.5 * ((double)ns[n / 2 - 1] + (double)ns[n / 2]);
    /* Nearest rank in integers: ceil(99 n / 100). */
    size_t rank = (99 * n + 99) / 100;
    *median_ms = median * 1e-6;
    *p99_ms = (double)ns[rank - 1] * 1e-6;
}

typedef struct acc {
    double mse8, mse_lin, ssim, flip;
    uint32_t frames;
    double di_mse8, di_flip;
    uint32_t windows;
    uint64_t rays, camera_rays;
} acc_t;

static hz_status_t load_reference(const char *dir, uint32_t i, const hz_et_sequence_t *seq, hz_arena_t *a,
                                  hz_image_t *dst, hz_error_t *err)
{
    char path[FILE_BYTES];
    frame_path(path, sizeof path, dir, i);
    hz_arena_mark_t m = hz_arena_mark(a);
    hz_image_t img;
    hz_status_t s = hz_pfm_read(path, a, &img, err);
    if (s == HZ_OK && (img.width != seq->width || img.height != seq->height))
        s = hz_error_set(err, HZ_E_CORRUPT, "%s: %ux%u, the sequence is %ux%u (delete the cache entry)", path,
                         (unsigned)img.width, (unsigned)img.height, (unsigned)seq->width, (unsigned)seq->height);
    if (s == HZ_OK)
        s = hz_image_copy(dst, &img, err);
    hz_arena_reset(a, m);
    return s;
}

/* Opens the Y4M stream of one method (or the reference when m is NULL); no-op without video_dir. */
static hz_status_t open_video(hz_y4m_t *v, bool *open, const hz_et_sequence_t *seq, const hz_et_method_t *m,
                              const hz_et_config_t *cfg, hz_error_t *err)
{
    *open = false;
    if (!cfg->video_dir)
        return HZ_OK;
    char scene[72], what[128], path[FILE_BYTES];
    safe_name(scene, sizeof scene, or_empty(seq->scene));
    if (m) {
        char raw[128];
        snprintf(raw, sizeof raw, "%s-%s%g", m->name, m->knob, m->value);
        safe_name(what, sizeof what, raw);
    } else {
        snprintf(what, sizeof what, "reference");
    }
    hz_status_t s = hz_mkdirs(cfg->video_dir, err);
    if (s != HZ_OK)
        return s;
    if (snprintf(path, sizeof path, "%s/%s-%s.y4m", cfg->video_dir, scene, what) >= (int)sizeof path)
        return hz_error_set(err, HZ_E_RANGE, "%s: video path too long", cfg->video_dir);
    hz_y4m_opts_t o = { HZ_Y4M_C444, HZ_Y4M_BT709, true, seq->refresh_hz, 1 };
    s = hz_y4m_open(v, path, seq->width, seq->height, &o, err);
    *open = s == HZ_OK;
    return s;
}

static hz_status_t run_method(const hz_et_sequence_t *seq, const hz_et_method_t *m, const char *dir,
                              const hz_et_config_t *cfg, bool ref_video, hz_progress_t *prog, hz_et_row_t *row,
                              hz_error_t *err)
{
    hz_arena_t *a = cfg->arena;
    const uint32_t k = hz_et_window(seq->refresh_hz), measured = seq->frames - seq->warmup;
    hz_image_t out, disp[16], ref[16], mean_d, mean_r;
    int64_t *ns = hz_arena_alloc_array(a, measured, sizeof(int64_t), 8);
    hz_status_t s = ns ? HZ_OK : hz_arena_error(a, err);
    if (s == HZ_OK)
        s = hz_image_alloc(&out, a, seq->width, seq->height, err);
    for (uint32_t j = 0; j < k && s == HZ_OK; j++)
        if ((s = hz_image_alloc(&disp[j], a, seq->width, seq->height, err)) == HZ_OK)
            s = hz_image_alloc(&ref[j], a, seq->width, seq->height, err);
    if (s == HZ_OK && (s = hz_image_alloc(&mean_d, a, seq->width, seq->height, err)) == HZ_OK)
        s = hz_image_alloc(&mean_r, a, seq->width, seq->height, err);
    if (s != HZ_OK)
        return method_error(err, m, "frames", -1);
    hz_y4m_t video, ref_stream;
    bool video_open = false, ref_open = false;
    if ((s = open_video(&video, &video_open, seq, m, cfg, err)) != HZ_OK ||
        (ref_video && (s = open_video(&ref_stream, &ref_open, seq, NULL, cfg, err)) != HZ_OK)) {
        if (video_open)
            hz_y4m_abort(&video);
        return s;
    }
    void *state = NULL;
    if (m->begin && (s = m->begin(m, seq, a, &state, err)) != HZ_OK) {
        if (video_open)
            hz_y4m_abort(&video);
        if (ref_open)
            hz_y4m_abort(&ref_stream);
        return method_error(err, m, "begin", -1);
    }
    acc_t acc;
    memset(&acc, 0, sizeof acc);
    const hz_image_t *dp[16], *rp[16];
    for (uint32_t j = 0; j < k; j++) {
        dp[j] = &disp[j];
        rp[j] = &ref[j];
    }
    const uint32_t hold = m->hold > 1 ? m->hold : 1;
    uint32_t timed = 0;
    for (uint32_t i = 0; i < seq->frames; i++) {
        uint64_t rays = 0, camera = 0;
        int64_t t0 = 0, t1 = 0;
        if (i % hold == 0) { /* otherwise the display repeats the last rendered frame */
            t0 = hz_clock_ns();
            s = m->render(state, i, &out, &rays, err);
            t1 = hz_clock_ns();
            if (s != HZ_OK) {
                method_error(err, m, "render", i);
                break;
            }
            camera = m->camera_rays ? m->camera_rays(state) : 0;
        }
        hz_image_t *d = &disp[i % k], *r = &ref[i % k];
        hz_image_copy(d, &out, NULL);
        hz_image_quantize_srgb8(d);
        if ((s = load_reference(dir, i, seq, a, r, err)) != HZ_OK)
            break;
        hz_image_quantize_srgb8(r);
        if ((video_open && (s = hz_y4m_write(&video, d, err)) != HZ_OK) ||
            (ref_open && (s = hz_y4m_write(&ref_stream, r, err)) != HZ_OK))
            break;
        if (i >= seq->warmup) {
            if (i % hold == 0)
                ns[timed++] = t1 - t0;
            acc.rays += rays;
            acc.camera_rays += camera;
            hz_mse_t mse;
            double ssim, flip;
            if ((s = hz_mse(r, d, &mse, err)) != HZ_OK || (s = hz_ssim(r, d, a, &ssim, err)) != HZ_OK ||
                (s = hz_flip(r, d, cfg->ppd, a, NULL, &flip, err)) != HZ_OK) {
                method_error(err, m, "scoring", i);
                break;
            }
            acc.mse8 += mse.srgb8;
            acc.mse_lin += mse.linear;
            acc.ssim += ssim;
            acc.flip += flip;
            acc.frames++;
        }
        if (i + 1 >= seq->warmup + k) {
            if ((s = hz_image_mean(&mean_d, dp, k, err)) != HZ_OK || (s = hz_image_mean(&mean_r, rp, k, err)) != HZ_OK)
                break;
            hz_mse_t mse;
            double flip;
            if ((s = hz_mse(&mean_r, &mean_d, &mse, err)) != HZ_OK ||
                (s = hz_flip(&mean_r, &mean_d, cfg->ppd, a, NULL, &flip, err)) != HZ_OK) {
                method_error(err, m, "display-integrated scoring", i);
                break;
            }
            acc.di_mse8 += mse.srgb8;
            acc.di_flip += flip;
            acc.windows++;
        }
        hz_progress_step(prog, 1);
    }
    if (m->end)
        m->end(state);
    if (video_open) {
        if (s == HZ_OK)
            s = hz_y4m_close(&video, err);
        else
            hz_y4m_abort(&video);
    }
    if (ref_open) {
        if (s == HZ_OK)
            s = hz_y4m_close(&ref_stream, err);
        else
            hz_y4m_abort(&ref_stream);
    }
    if (s != HZ_OK)
        return s;

    memset(row, 0, sizeof *row);
    snprintf(row->scene, sizeof row->scene, "%s", or_empty(seq->scene));
    snprintf(row->method, sizeof row->method, "%s", m->name);
    snprintf(row->knob, sizeof row->knob, "%s", m->knob);
    row->value = m->value;
    row->width = seq->width;
    row->height = seq->height;
    row->frames = seq->frames;
    row->measured = measured;
    row->refresh_hz = seq->refresh_hz;
    row->di_k = k;
    hz_et_time_stats(ns, timed, &row->ms_median, &row->ms_p99);
    row->ms_median /= hold;
    row->ms_p99 /= hold;
    row->rays_per_frame = (double)acc.rays / acc.frames;
    row->camera_rays_per_pixel = m->camera_rays ? (double)acc.camera_rays / acc.frames /
                                                      ((double)seq->width * seq->height)
                                                : NAN;
    row->psnr_srgb8 = hz_psnr(acc.mse8 / acc.frames, 255.0);
    row->psnr_linear = hz_psnr(acc.mse_lin / acc.frames, 1.0);
    row->ssim = acc.ssim / acc.frames;
    row->flip = acc.flip / acc.frames;
    row->di_flip = acc.di_flip / acc.windows;
    row->di_psnr_srgb8 = hz_psnr(acc.di_mse8 / acc.windows, 255.0);
    return HZ_OK;
}

hz_status_t hz_et_run(const hz_et_sequence_t *seq, const hz_et_method_t *reference, const hz_et_method_t *methods,
                      size_t count, const hz_et_config_t *cfg, hz_et_row_t *rows, hz_error_t *err)
{
    const uint32_t k = hz_et_window(seq->refresh_hz);
    hz_status_t s = hz_image_check_size(seq->width, seq->height, NULL, err);
    if (s != HZ_OK)
        return s;
    if (seq->width < HZ_SSIM_WINDOW || seq->height < HZ_SSIM_WINDOW)
        return hz_error_set(err, HZ_E_INVALID_ARG, "errtime: %ux%u is too small (SSIM needs at least %ux%u)",
                            (unsigned)seq->width, (unsigned)seq->height, HZ_SSIM_WINDOW, HZ_SSIM_WINDOW);
    if (seq->refresh_hz == 0 || seq->refresh_hz > 60 * 16)
        return hz_error_set(err, HZ_E_INVALID_ARG, "errtime: refresh rate %u Hz is outside 1..960",
                            (unsigned)seq->refresh_hz);
    if (seq->frames > 1000000 || seq->warmup > seq->frames || seq->frames - seq->warmup < k)
        return hz_error_set(err, HZ_E_INVALID_ARG, "errtime: %u frames with %u of warm-up leave fewer than the %u "
                            "measured frames one display-integration window needs", (unsigned)seq->frames,
                            (unsigned)seq->warmup, (unsigned)k);
    if (!reference || !reference->render || !cfg->cache_dir || !cfg->arena || !(cfg->ppd > 0.0f && cfg->ppd <= 1000.0f))
        return hz_error_set(err, HZ_E_INVALID_ARG, "errtime: no reference method, cache directory or arena, or a "
                            "ppd outside (0, 1000]");
    for (size_t j = 0; j < count; j++)
        if (!methods[j].render || !methods[j].name || !methods[j].knob)
            return hz_error_set(err, HZ_E_INVALID_ARG, "errtime: method %zu has no name, knob or render callback", j);
        else if (methods[j].hold > seq->frames - seq->warmup)
            return hz_error_set(err, HZ_E_INVALID_ARG, "errtime: method '%s' renders every %u frames, more than the "
                                "%u measured frames", methods[j].name, (unsigned)methods[j].hold,
                                (unsigned)(seq->frames - seq->warmup));
    bool rendered;
    if ((s = hz_et_reference(seq, reference, cfg, &rendered, err)) != HZ_OK)
        return s;
    char dir[DIR_BYTES], key[2048];
    if ((s = hz_et_cache_entry(seq, reference, cfg->cache_dir, dir, sizeof dir, key, sizeof key, err)) != HZ_OK)
        return s;
    hz_progress_t prog;
    hz_progress_begin(&prog, cfg->progress, cfg->progress_tty, (uint64_t)count * seq->frames);
    for (size_t j = 0; j < count; j++) {
        char label[64];
        snprintf(label, sizeof label, "%s %s=%g", methods[j].name, methods[j].knob, methods[j].value);
        hz_progress_label(&prog, label);
        hz_arena_mark_t mark = hz_arena_mark(cfg->arena);
        s = run_method(seq, &methods[j], dir, cfg, j == 0, &prog, &rows[j], err);
        hz_arena_reset(cfg->arena, mark);
        if (s != HZ_OK)
            break;
    }
    hz_progress_end(&prog);
    if (s != HZ_OK)
        return s;
    hz_et_pareto(rows, count);
    return HZ_OK;
}
