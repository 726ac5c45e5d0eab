/* `--mode adaptive`: the focus list and map name, focus names resolved, activity map, summary figures (see
 * adaptive_cli.h). */
#include "adaptive_cli.h"

#include <fnmatch.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "imageio.h"

bool hz_adaptive_cli_focus_ok(const char *list, char *why, size_t cap)
{
    uint32_t items = 0;
    for (const char *p = list;; items++) {
        const char *e = strchr(p, ',');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        if (len == 0) {
            snprintf(why, cap, "'%s' has an empty item (give object ids or names, comma-separated)", list);
            return false;
        }
        if (len >= HZ_HZB_NAME_BYTES) {
            snprintf(why, cap, "'%.*s' is longer than an object name (%u bytes)", (int)len, p, HZ_HZB_NAME_BYTES - 1);
            return false;
        }
        if (items == HZ_AMASK_MAX_FOCUS) {
            snprintf(why, cap, "more than %u items", HZ_AMASK_MAX_FOCUS);
            return false;
        }
        if (!e)
            return true;
        p = e + 1;
    }
}

/* Case-insensitive suffix test. */
static bool has_ext(const char *name, const char *ext)
{
    size_t n = strlen(name), e = strlen(ext);
    if (n < e)
        return false;
    for (size_t i = 0; i < e; i++) {
        char c = name[n - e + i];
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if (c != ext[i])
            return false;
    }
    return true;
}

bool hz_adaptive_cli_map_ok(const char *path, char *why, size_t cap)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    if (!*base) {
        snprintf(why, cap, "'%s' names a folder, not a file (e.g. %smap.png)", path, path);
        return false;
    }
    const char *exts[] = { ".png", ".ppm", ".pfm" };
    for (int k = 0; k < 3; k++) {
        if (!has_ext(base, exts[k]))
            continue;
        if (strlen(base) == 4) {
            snprintf(why, cap, "'%s' has an extension but no file name before it (e.g. %.*smap%s)", path,
                     (int)(base - path), path, exts[k]);
            return false;
        }
        if (k == 0 && !hz_png_supported()) {
            snprintf(why, cap, "'%s': this build writes no PNG (no libpng): use .ppm or .pfm", path);
            return false;
        }
        return true;
    }
    const char *dot = strrchr(base, '.');
    snprintf(why, cap, "'%s': %s%s%s is not an image extension this writes (.png, .ppm or .pfm)", path,
             dot ? "'" : "", dot ? dot : "no extension", dot ? "'" : "");
    return false;
}

/* Object names for a message: "0 'floor', 1 'ceiling', ..." (non-printing bytes as \xNN). */
static void list_objects(char *buf, size_t cap, const hz_scene_t *scene)
{
    size_t n = 0;
    buf[0] = 0;
    for (uint32_t i = 0; i < scene->object_count && n + 48 < cap; i++) {
        char name[4 * HZ_HZB_NAME_BYTES + 1];
        hz_cli_printable(name, sizeof name, (const char *)scene->objects[i].name, HZ_HZB_NAME_BYTES);
        n += (size_t)snprintf(buf + n, cap - n, "%s%u '%s'", i ? ", " : "", i, name);
        if (i == 11 && scene->object_count > 12) {
            snprintf(buf + n, cap - n, ", ... (%u in all; hzrt info lists them)", scene->object_count);
            break;
        }
    }
}

static int cmp_u16(const void *a, const void *b)
{
    return (int)*(const uint16_t *)a - (int)*(const uint16_t *)b;
}

hz_status_t hz_adaptive_cli_resolve(const hz_adaptive_cli_t *st, const hz_scene_t *scene, hz_adaptive_opts_t *ao,
                                    hz_error_t *err)
{
    ao->focus_count = 0;
    if (!st->focus)
        return HZ_OK;
    char names[512];
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
        uint32_t before = ao->focus_count;
        if (*end || end == item) { /* a name: every object called so, or matching the pattern */
            for (uint32_t i = 0; i < scene->object_count; i++) {
                char name[HZ_HZB_NAME_BYTES + 1];
                memcpy(name, scene->objects[i].name, HZ_HZB_NAME_BYTES);
                name[HZ_HZB_NAME_BYTES] = 0;
                if (!strcmp(name, item) || fnmatch(item, name, 0) == 0) {
                    if (ao->focus_count == HZ_AMASK_MAX_FOCUS)
                        return hz_error_set(err, HZ_E_INVALID_ARG, "--focus-objects: more than %u objects",
                                            HZ_AMASK_MAX_FOCUS);
                    ao->focus[ao->focus_count++] = (uint16_t)i;
                }
            }
            if (ao->focus_count == before) {
                list_objects(names, sizeof names, scene);
                return hz_error_set(err, HZ_E_INVALID_ARG, "--focus-objects: the scene has no object named '%s' (%s)",
                                    item, names);
            }
        } else if (id < 0 || id >= (long)scene->object_count) {
            return hz_error_set(err, HZ_E_INVALID_ARG, "--focus-objects: object id %s outside 0..%u", item,
                                scene->object_count ? scene->object_count - 1 : 0);
        } else {
            if (ao->focus_count == HZ_AMASK_MAX_FOCUS)
                return hz_error_set(err, HZ_E_INVALID_ARG, "--focus-objects: more than %u objects", HZ_AMASK_MAX_FOCUS);
            ao->focus[ao->focus_count++] = (uint16_t)id;
        }
        if (!e)
            break;
        p = e + 1;
    }
    /* sorted, each id once: what was taken, as summary.json lists it */
    qsort(ao->focus, ao->focus_count, sizeof ao->focus[0], cmp_u16);
    uint32_t n = 0;
    for (uint32_t i = 0; i < ao->focus_count; i++)
        if (!n || ao->focus[n - 1] != ao->focus[i])
            ao->focus[n++] = ao->focus[i];
    ao->focus_count = n;
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
