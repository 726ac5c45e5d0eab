/* hzbench --check-fit (see bench_fit.h). */
#include "bench_fit.h"

#include <stdio.h>
#include <string.h>


void hz_bench_fit_line(hz_bench_fit_scene_t *fs, const char *what, const char *arena, size_t need, size_t have)
{
    bool ok = need <= have;
    fs->fit->checked++;
    fs->fit->failed += !ok;
    printf("fit %-12s %-18s %-36s %-6s %9.1f of %9.1f MiB  %s\n", fs->group, fs->label, what, arena,
           need / 1048576.0, have / 1048576.0, ok ? "fits" : "DOES NOT FIT");
}

void hz_bench_fit_fail(hz_bench_fit_scene_t *fs, const char *what, const char *why)
{
    fs->fit->checked++, fs->fit->failed++;
    printf("fit %-12s %-18s %s: %s\n", fs->group, fs->label, what, why);
}

bool hz_bench_fit_open(hz_bench_fit_t *fit, const char *group, const char *label, const char *file,
                       hz_bench_fit_scene_t *fs)
{
    memset(fs, 0, sizeof *fs);
    fs->fit = fit, fs->group = group, fs->label = label;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", fit->scenes_dir, file ? file : "");
    hz_error_t err;
    if (hz_bench_scene_load(&fs->bs, file ? path : "builtin", &err) != HZ_OK) {
        char why[HZ_ERROR_MSG_BYTES + 32];
        snprintf(why, sizeof why, "%s%s", err.msg, err.code == HZ_E_IO ? " (make scenes bakes it)" : "");
        hz_bench_fit_fail(fs, "DOES NOT LOAD", why);
        hz_bench_fit_close(fs);
        return false;
    }
    return true;
}

void hz_bench_fit_accel(hz_bench_fit_scene_t *fs, const hz_accel_config_t *cfg, uint32_t time_keys, const char *what)
{
    hz_accel_geom_t g;
    hz_accel_geom_init(&g);
    g.tri_count = fs->bs.scene.triangle_count;
    g.vertex_count = fs->bs.scene.vertex_count;
    g.time_keys = time_keys >= 2u ? time_keys : 0u;
    hz_accel_bytes_t b = hz_accel_bytes_bound_geom(&g, cfg);
    char w[64];
    if (g.time_keys)
        snprintf(w, sizeof w, "%s, %u keys", what, g.time_keys);
    hz_bench_fit_line(fs, g.time_keys ? w : what, "accel", b.peak, hz_arena_available(&fs->bs.pools->accel, 64));
}

uint32_t hz_bench_fit_render(hz_bench_fit_scene_t *fs, const hz_render_opts_t *ro, int n, const char *what)
{
    size_t frame = 0, thread = 0, keys = 0;
    uint32_t time_keys = 0;
    for (int i = 0; i < n; i++) {
        hz_render_plan_t p;
        hz_error_t err;
        if (hz_render_plan(&fs->bs.scene, &ro[i], &p, &err) != HZ_OK) {
            char w[96];
            snprintf(w, sizeof w, "%s: NO PLAN", what);
            hz_bench_fit_fail(fs, w, err.msg);
            return 0;
        }
        frame += p.frame_bytes, thread += p.thread_bytes;
        keys = p.keys_bytes > keys ? p.keys_bytes : keys;
        time_keys = p.time_keys > time_keys ? p.time_keys : time_keys;
    }
    hz_pools_t *pools = fs->bs.pools;
    char w[64];
    snprintf(w, sizeof w, "%s %ux%u", what, ro[0].width, ro[0].height);
    hz_bench_fit_line(fs, w, "frame", frame, hz_arena_available(&pools->frame, 64));
    /* every worker takes its share from its own thread arena */
    hz_bench_fit_line(fs, w, "thread", thread, hz_arena_available(&pools->thread[0], 64));
    if (keys)
        hz_bench_fit_line(fs, "pose keys of the shutter", "scene", keys, hz_arena_available(&pools->scene, 64));
    return time_keys;
}

void hz_bench_fit_close(hz_bench_fit_scene_t *fs)
{
    hz_bench_scene_close(&fs->bs);
}

void hz_bench_fit_scenes(hz_bench_fit_t *fit, const char *group, const char *const (*scenes)[2], size_t count,
                         hz_bench_fit_fn fn, const void *ctx)
{
    for (size_t i = 0; i < count; i++) {
        hz_bench_fit_scene_t fs;
        if (!hz_bench_fit_open(fit, group, scenes[i][0], scenes[i][1], &fs))
            continue;
        fn(&fs, ctx);
        hz_bench_fit_close(&fs);
    }
}

void hz_bench_fit_named(hz_bench_fit_t *fit, const char *group, const char *const *names, int count,
                        hz_bench_fit_fn fn, const void *ctx)
{
    for (int i = 0; i < count; i++) {
        char file[300];
        snprintf(file, sizeof file, "%s.hzb", names[i]);
        const char *const scene[1][2] = { { names[i], file } };
        hz_bench_fit_scenes(fit, group, scene, 1, fn, ctx);
    }
}
