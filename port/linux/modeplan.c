/* Memory plans per render mode (see modeplan.h). */
#include "modeplan.h"

#include <stdbool.h>
#include <string.h>

static bool arena_fits(const hz_arena_t *a, const char *label, size_t need, char *why, size_t n)
{
    size_t have = hz_arena_available(a, 64);
    if (need <= have)
        return true;
    snprintf(why, n, "arena '%s' needs %zu bytes, has %zu", label, need, have);
    return false;
}

bool hz_modeplan_check(const hz_scene_t *scene, hz_pools_t *pools, const hz_render_opts_t *opts, int threads,
                       hz_render_plan_t *plan, char *why, size_t why_size)
{
    hz_error_t err;
    memset(plan, 0, sizeof *plan);
    if (hz_render_plan(scene, opts, plan, &err) != HZ_OK) {
        snprintf(why, why_size, "%s", err.msg);
        return false;
    }
    hz_accel_config_t acfg;
    hz_accel_config_default(&acfg);
    hz_accel_bytes_t ab = hz_accel_bytes_bound(scene->triangle_count, &acfg);
    if (!arena_fits(&pools->frame, "frame", plan->frame_bytes, why, why_size) ||
        !arena_fits(&pools->accel, "accel", ab.peak, why, why_size))
        return false;
    for (int t = 0; t < threads && t < HZ_MAX_THREADS; t++)
        if (!arena_fits(&pools->thread[t], "thread", plan->thread_bytes, why, why_size))
            return false;
    why[0] = '\0';
    return true;
}

static double per_px(size_t bytes, size_t px)
{
    return px ? (double)bytes / (double)px : 0.0;
}

/* The scene as the planner would see it with a feature on or off (the copy is only planned, never rendered:
 * prev_pos just has to be non-NULL for motion to count). */
static hz_scene_t with_feature(const hz_scene_t *s, uint32_t bits, bool on)
{
    hz_scene_t c = *s;
    if (on) {
        c.features |= bits;
        if ((bits & HZ_FEAT_MOTION) && !c.prev_pos)
            c.prev_pos = c.pos ? c.pos : (float *)(uintptr_t)64;
        if ((bits & HZ_FEAT_TEXTURES) && !c.uv)
            c.uv = (const float *)(uintptr_t)64;
    } else {
        c.features &= ~bits;
        if (bits & HZ_FEAT_MOTION)
            c.prev_pos = NULL;
    }
    return c;
}

static size_t plan_frame(const hz_scene_t *s, hz_render_opts_t *o)
{
    hz_render_plan_t p;
    hz_error_t err;
    return hz_render_plan(s, o, &p, &err) == HZ_OK ? p.frame_bytes : 0;
}

bool hz_modeplan_print(FILE *f, const hz_scene_t *scene, hz_pools_t *pools, uint32_t width, uint32_t height)
{
    size_t px = (size_t)width * height;
    bool default_fits = false;
    fprintf(f, "render modes at %ux%u (%zu pixels); per pixel: display + G-buffer + mirror G-buffer + motion + "
               "mode state\n", width, height, px);
    for (int m = 0; m < HZ_MODE_COUNT; m++) {
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = width, o.height = height, o.mode = (hz_render_mode_t)m;
        hz_render_plan_t p;
        char why[256];
        bool fits = hz_modeplan_check(scene, pools, &o, 1, &p, why, sizeof why);
        if (m == HZ_MODEPLAN_DEFAULT_MODE)
            default_fits = fits;
        fprintf(f, "  %-8s %11zu bytes %6.1f B/px = %.1f + %.1f + %.1f + %.1f + %.1f%s\n", hz_render_mode_name(o.mode),
                p.frame_bytes, per_px(p.frame_bytes, px), per_px(p.display_bytes, px), per_px(p.gbuffer_bytes, px),
                per_px(p.gbuffer2_bytes, px), per_px(p.mv_bytes, px), per_px(p.state_bytes, px),
                m == HZ_MODEPLAN_DEFAULT_MODE ? "  (hzrt render's default)" : "");
        if (fits)
            fprintf(f, "           fits: arena 'frame' needs %zu bytes, has %zu; 'thread' needs %zu, has %zu\n",
                    p.frame_bytes, hz_arena_available(&pools->frame, 64), p.thread_bytes,
                    hz_arena_available(&pools->thread[0], 64));
        else
            fprintf(f, "           does NOT fit: %s\n", why);
    }
    /* What this scene lets the renderer leave out (the same for every mode). */
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = width, o.height = height, o.mode = HZ_MODEPLAN_DEFAULT_MODE;
    hz_render_plan_t p;
    hz_error_t err;
    if (hz_render_plan(scene, &o, &p, &err) == HZ_OK) {
        /* two lists, not yes/no after "left out" (which read as a double negative) */
        const struct { const char *name; bool kept; } parts[] = {
            { "motion vectors", p.mv_bytes != 0 }, { "mirror G-buffer", p.gbuffer2_bytes != 0 },
            { "any-hit", p.anyhit }, { "transparency stage", p.transparency },
            { "animation state", scene->plan.arena_bytes != 0 },
        };
        for (int kept = 1; kept >= 0; kept--) {
            fprintf(f, "%-13s", kept ? "kept" : "left out");
            int n = 0;
            for (size_t i = 0; i < sizeof parts / sizeof parts[0]; i++)
                if (parts[i].kept == (kept != 0))
                    fprintf(f, "%s%s", n++ ? ", " : "", parts[i].name);
            fprintf(f, "%s\n", n ? "" : "nothing");
        }
    }
    /* Each optional feature's cost: the plan with it minus the plan without it, per mode. */
    static const struct { const char *name; uint32_t bits; } feats[] = {
        { "motion", HZ_FEAT_MOTION | HZ_FEAT_CAMERA_PATH },
        { "mirrors", HZ_FEAT_MIRROR },
        { "transparency", HZ_FEAT_BLEND | HZ_FEAT_CUTOUT },
    };
    fprintf(f, "feature cost (B/px a scene without the feature saves; 'has' = this scene has it):\n  %-17s",
            "feature");
    for (int m = 0; m < HZ_MODE_COUNT; m++)
        fprintf(f, " %8s", hz_render_mode_name((hz_render_mode_t)m));
    fprintf(f, "\n");
    for (size_t i = 0; i < sizeof feats / sizeof feats[0]; i++) {
        hz_scene_t on = with_feature(scene, feats[i].bits, true), off = with_feature(scene, feats[i].bits, false);
        fprintf(f, "  %-13s %-3s", feats[i].name, (scene->features & feats[i].bits) ? "has" : "");
        o.mode = HZ_MODEPLAN_DEFAULT_MODE;
        if (plan_frame(&on, &o) == 0 && plan_frame(&off, &o) != 0) { /* refused: hz_render_features_check */
            fprintf(f, " left out of this build (%s)\n", feats[i].name);
            continue;
        }
        for (int m = 0; m < HZ_MODE_COUNT; m++) {
            o.mode = (hz_render_mode_t)m;
            size_t a = plan_frame(&on, &o), b = plan_frame(&off, &o);
            fprintf(f, " %8.1f", per_px(a > b ? a - b : 0, px));
        }
        fprintf(f, "%s\n", feats[i].bits & HZ_FEAT_BLEND ? "  (no bytes: any-hit and continuation rays)" : "");
    }
    fprintf(f, "  %-17s %zu bytes in the scene arena (moving vertices, current and previous)\n", "animation",
            scene->plan.arena_bytes);
    return default_fits;
}
