/* `--mode adaptive` options, activity map and summary figures (see adaptive_cli.h). */
#include "adaptive_cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "imageio.h"

static bool parse_tau(const char *opt, const char *v, float *out)
{
    char *end = NULL;
    double t = v ? strtod(v, &end) : 0.0;
    if (!v || !*v || *end || !(t >= 0.0 && t <= 1.0)) {
        hz_cli_error("render: %s: '%s' is not a threshold in [0, 1] (1 switches it off)", opt, v ? v : "");
        return false;
    }
    *out = (float)t;
    return true;
}

int hz_adaptive_cli_option(const char *opt, const char *v, hz_adaptive_opts_t *ao, hz_adaptive_cli_t *st)
{
    if (strncmp(opt, "--tau", 5) && strcmp(opt, "--focus-objects") && strcmp(opt, "--adaptive-map") &&
        strcmp(opt, "--normal-angle"))
        return 0;
    if (!strcmp(opt, "--tau")) {
        float t;
        if (!parse_tau(opt, v, &t))
            return -HZ_EXIT_USAGE;
        ao->tau[HZ_TAU_COL] = ao->tau[HZ_TAU_PTE] = ao->tau[HZ_TAU_STE] = t; /* the paper's tau_alpha */
    } else if (!strncmp(opt, "--tau-", 6)) {
        int k = -1;
        for (int i = 0; i < HZ_TAU_COUNT; i++)
            if (!strcmp(opt + 6, hz_tau_name((hz_tau_t)i)))
                k = i;
        if (k < 0)
            return 0; /* not ours: the caller reports the unknown option */
        if (!parse_tau(opt, v, &ao->tau[k]))
            return -HZ_EXIT_USAGE;
    } else if (!strcmp(opt, "--normal-angle")) {
        char *end = NULL;
        double d = v ? strtod(v, &end) : 0.0;
        if (!v || !*v || *end || !(d >= 0.0 && d <= 90.0)) {
            hz_cli_error("render: --normal-angle: '%s' is not an angle in [0, 90] degrees", v ? v : "");
            return -HZ_EXIT_USAGE;
        }
        ao->normal_angle_deg = (float)d;
    } else if (!strcmp(opt, "--focus-objects")) {
        if (!v || !*v) {
            hz_cli_error("render: --focus-objects: missing list (object ids or names, comma-separated)");
            return -HZ_EXIT_USAGE;
        }
        st->focus = v;
    } else if (!strcmp(opt, "--adaptive-map")) {
        if (!v || !*v) {
            hz_cli_error("render: --adaptive-map: missing file name (e.g. map.png)");
            return -HZ_EXIT_USAGE;
        }
        st->map_path = v;
    } else {
        return 0;
    }
    if (!st->first)
        st->first = opt;
    return 2;
}

int hz_adaptive_cli_check(const hz_adaptive_cli_t *st, hz_render_mode_t mode)
{
    if (st->first && mode != HZ_MODE_ADAPTIVE) {
        hz_cli_error("render: %s applies only to --mode adaptive (this run is --mode %s)", st->first,
                     hz_render_mode_name(mode));
        return HZ_EXIT_USAGE;
    }
    return 0;
}

void hz_adaptive_cli_usage(FILE *f)
{
    fprintf(f,
            "\nadaptive mode (--mode adaptive; seed 003: presample, activity mask, 4 extra samples per active\n"
            "subpixel): thresholds in [0, 1], smaller = more samples, 1 switches an attribute off\n"
            "  --tau T           tau-col, tau-pte and tau-ste together (the paper's tau_alpha); default 0.6\n"
            "  --tau-col T       colour contrast where no attribute disagrees; default 0.6\n"
            "  --tau-poid T      primary hit object id; default 0.05    --tau-soid T  mirror hit; default 0.05\n"
            "  --tau-psn T       primary shading normal; default 0.06   --tau-ssn T   mirror hit; default 0.06\n"
            "  --tau-psc T       primary shadow count; default 0.06     --tau-ssc T   mirror hit; default 0.06\n"
            "  --tau-pte T       primary texture; default 0.6           --tau-ste T   mirror hit; default 0.6\n"
            "  --normal-angle D  normals within D degrees agree; default 15\n"
            "  --focus-objects L attributes count only where these objects are involved (ids or names, comma-\n"
            "                    separated; `hzrt info SCENE` lists them)\n"
            "  --adaptive-map F  write the last frame's active subpixels per pixel (black, red, green, blue, white\n"
            "                    for 0..4) to F (.png, .ppm or .pfm)\n");
}

hz_status_t hz_adaptive_cli_resolve(const hz_adaptive_cli_t *st, const hz_scene_t *scene, hz_adaptive_opts_t *ao,
                                    hz_error_t *err)
{
    ao->focus_count = 0;
    if (!st->focus)
        return HZ_OK;
    for (const char *p = st->focus; *p;) {
        const char *e = strchr(p, ',');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        char item[HZ_HZB_NAME_BYTES + 16];
        if (len == 0 || len >= sizeof item)
            return hz_error_set(err, HZ_E_INVALID_ARG, "--focus-objects: empty or overlong item in '%s'", st->focus);
        memcpy(item, p, len);
        item[len] = '\0';
        char *end = NULL;
        long id = strtol(item, &end, 10);
        if (*end) { /* a name */
            id = -1;
            for (uint32_t i = 0; i < scene->object_count; i++)
                if (!strncmp((const char *)scene->objects[i].name, item, HZ_HZB_NAME_BYTES))
                    id = (long)i;
            if (id < 0)
                return hz_error_set(err, HZ_E_INVALID_ARG, "--focus-objects: the scene has no object named '%s'",
                                    item);
        } else if (id < 0 || id >= (long)scene->object_count) {
            return hz_error_set(err, HZ_E_INVALID_ARG, "--focus-objects: object id %s outside 0..%u", item,
                                scene->object_count ? scene->object_count - 1 : 0);
        }
        if (ao->focus_count == HZ_AMASK_MAX_FOCUS)
            return hz_error_set(err, HZ_E_INVALID_ARG, "--focus-objects: more than %u objects", HZ_AMASK_MAX_FOCUS);
        ao->focus[ao->focus_count++] = (uint16_t)id;
        if (!e)
            break;
        p = e + 1;
    }
    return HZ_OK;
}

hz_status_t hz_adaptive_map_write(const char *path, const hz_renderer_t *r, uint32_t width, uint32_t height,
                                  hz_error_t *err)
{
    static const float colour[5][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 1 } };
    const uint8_t *mask = hz_render_adaptive_mask(r);
    if (!mask)
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s: the activity map needs --mode adaptive", path);
    hz_image_t img = { width, height, NULL };
    img.rgb = malloc((size_t)width * height * 3 * sizeof(float));
    if (!img.rgb)
        return hz_error_set(err, HZ_E_NO_MEMORY, "%s: no memory for a %ux%u map", path, width, height);
    for (size_t i = 0; i < (size_t)width * height; i++)
        memcpy(img.rgb + i * 3, colour[hz_amask_count(mask[i])], sizeof colour[0]);
    hz_status_t s = hz_image_write(path, &img, err);
    free(img.rgb);
    return s;
}

void hz_adaptive_summary(const hz_render_stats_t *t, uint32_t frames, uint32_t width, uint32_t height,
                         bool mirrors, hz_summary_adaptive_t *out)
{
    double px = (double)width * height * (frames ? frames : 1);
    out->extra_rays_per_pixel = (double)t->extra_rays / px;
    out->rays_per_pixel = 1.0 + out->extra_rays_per_pixel;
    out->sample_ratio_9spp = out->rays_per_pixel / 9.0;
    out->lanes_per_packet = t->extra_packets ? (double)t->extra_rays / (double)t->extra_packets : 0.0;
    out->active_fraction = (double)t->active_subpixels / (4.0 * px);
    out->attr_bytes_per_pixel = hz_adaptive_attr_bytes_per_pixel(mirrors);
}
