/*
 * libFuzzer target for the sidecar parser (programs/hzbake/sidecar.c), the .hzs text a user writes next to a model.
 *
 * Each input is parsed as "fuzz.hzs". A refusal must carry its status (HZ_E_FORMAT or HZ_E_RANGE, the contract
 * of sidecar.h) and a message that starts with the file name. An accepted sidecar must hold only values inside
 * the ranges the grammar allows (so the baker can use them without checking again): finite numbers, camera and
 * object key times that increase, a non-zero camera up vector, no two-sided tube. Its section patterns are then
 * matched against a few model names, as the baker does, and the unmatched check must name a section. Everything
 * is freed (libFuzzer's leak detection watches each input). Any violation aborts.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sidecar.h"

#define PATH "fuzz.hzs"

static void need(int ok)
{
    if (!ok)
        abort();
}

static int finite_in(float v, double lo, double hi)
{
    return isfinite(v) && v >= lo && v <= hi;
}

static void check_scene(const hz_bake_sidecar_t *sc)
{
    need(memchr(sc->name, 0, sizeof sc->name) != NULL);
    for (int k = 0; k < 3; k++)
        need(finite_in(sc->background[k], 0, 1e6) && finite_in(sc->ambient[k], 0, 1e6));
    need(finite_in(sc->duration, 0, 1e6) && (sc->fov_deg == 0.0f || finite_in(sc->fov_deg, 1, 179)));
    need(sc->texture_max >= 1 && sc->texture_max <= 16384);
    need(sc->tube_sides >= 1 && sc->tube_sides <= 64 && sc->tube_sides != 2);
    need(finite_in(sc->tube_radius_scale, 1e-3, 1e3) && finite_in(sc->smooth_angle_deg, 0, 180));
    need(finite_in(sc->skin_rate, 0.1, 1000) && finite_in(sc->rigid_rate, 0.1, 1000));
    need(sc->normals <= HZ_BAKE_NORMALS_NONE && sc->skinning <= HZ_BAKE_SKINNING_KEYS && sc->animation <= 1000000);
    need(!sc->camera_loop || sc->duration > 0.0f);
    for (size_t i = 0; i < sc->lights.len; i++) {
        const hz_hzb_light_t *l = HZ_BAKE_AT(sc->lights, hz_hzb_light_t, i);
        for (int k = 0; k < 3; k++)
            need(finite_in(l->position[k], -1e9, 1e9) && finite_in(l->color[k], 0, 1e9));
    }
    for (size_t i = 0; i < sc->cameras.len; i++) {
        const hz_bake_sc_camera_t *c = HZ_BAKE_AT(sc->cameras, hz_bake_sc_camera_t, i);
        need(finite_in(c->key.time, 0, 1e6) && isfinite(c->key.fov_y) && c->key.fov_y > 0.0f);
        need(c->key.up[0] != 0.0f || c->key.up[1] != 0.0f || c->key.up[2] != 0.0f);
        if (i)
            need(c->key.time > HZ_BAKE_AT(sc->cameras, hz_bake_sc_camera_t, i - 1)->key.time);
        if (sc->camera_loop)
            need(c->key.time < sc->duration);
    }
}

static void check_sections(const hz_bake_sidecar_t *sc)
{
    for (size_t i = 0; i < sc->materials.len; i++) {
        const hz_bake_sc_material_t *m = HZ_BAKE_AT(sc->materials, hz_bake_sc_material_t, i);
        need(m->pattern[0] && memchr(m->pattern, 0, sizeof m->pattern));
        need(finite_in(m->alpha, 0, 1) && finite_in(m->alpha_cutoff, 0, 1) && finite_in(m->mirror, 0, 1));
        need(m->alpha_mode <= HZ_ALPHA_BLEND);
    }
    for (size_t i = 0; i < sc->objects.len; i++) {
        const hz_bake_sc_object_t *o = HZ_BAKE_AT(sc->objects, hz_bake_sc_object_t, i);
        need(o->pattern[0] && memchr(o->pattern, 0, sizeof o->pattern));
        need(finite_in(o->speed_deg, -1e6, 1e6) && finite_in(o->frequency, 0, 1e4));
        if (o->motion == HZ_MOTION_RIGID)
            need(o->keys.len > 0);
        else
            need(o->keys.len == 0);
        if (o->motion == HZ_MOTION_SPIN)
            need(o->axis[0] != 0.0f || o->axis[1] != 0.0f || o->axis[2] != 0.0f);
        for (size_t k = 0; k < o->keys.len; k++) {
            const hz_bake_sc_key_t *key = HZ_BAKE_AT(o->keys, hz_bake_sc_key_t, k);
            need(finite_in(key->time, 0, 1e6));
            need(key->axis[0] != 0.0f || key->axis[1] != 0.0f || key->axis[2] != 0.0f);
            for (int c = 0; c < 3; c++)
                need(finite_in(key->scale[c], 1e-6, 1e6));
            if (k)
                need(key->time > HZ_BAKE_AT(o->keys, hz_bake_sc_key_t, k - 1)->time);
        }
    }
}

/* The baker matches every section against every material and object name of the model. */
static void check_matching(hz_bake_sidecar_t *sc)
{
    static const char *const names[] = { "", "Cesium_Man", "material12", "leaf.001", "[x]*?",
                                         "a very long object name from an exporter that pads names "
                                         "with many words and digits 0123456789 0123456789 0123456789" };
    hz_bake_scene_t s;
    hz_bake_scene_init(&s, "fuzz-model");
    hz_bake_material_t *m = hz_bake_vec_push(&s.mats, 1);
    memcpy(m->name, "material12", sizeof "material12");
    hz_bake_object_t *o = hz_bake_vec_push(&s.objs, 1);
    memcpy(o->name, "Cesium_Man", sizeof "Cesium_Man");
    int unmatched = 0;
    for (size_t i = 0; i < sc->materials.len; i++) {
        hz_bake_sc_material_t *mt = HZ_BAKE_AT(sc->materials, hz_bake_sc_material_t, i);
        for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
            (void)hz_bake_sidecar_match(mt->pattern, names[k]);
        mt->matched = hz_bake_sidecar_match(mt->pattern, m->name);
        unmatched |= !mt->matched;
    }
    for (size_t i = 0; i < sc->objects.len; i++) {
        hz_bake_sc_object_t *ob = HZ_BAKE_AT(sc->objects, hz_bake_sc_object_t, i);
        for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
            (void)hz_bake_sidecar_match(ob->pattern, names[k]);
        ob->matched = hz_bake_sidecar_match(ob->pattern, o->name);
        unmatched |= !ob->matched;
    }
    hz_error_t err;
    hz_error_clear(&err);
    hz_status_t st = hz_bake_sidecar_unmatched(sc, &s, &err);
    need(unmatched ? st == HZ_E_FORMAT && strstr(err.msg, PATH ":") == err.msg : st == HZ_OK);
    hz_bake_scene_free(&s);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static hz_bake_sidecar_t sc;
    hz_error_t err;
    hz_error_clear(&err);
    hz_bake_sidecar_defaults(&sc);
    hz_status_t st = hz_bake_sidecar_parse(&sc, PATH, (const char *)data, size, &err);
    if (st != HZ_OK) {
        need((st == HZ_E_FORMAT || st == HZ_E_RANGE) && err.code == st);
        need(strncmp(err.msg, PATH ":", sizeof PATH) == 0);
    } else {
        check_scene(&sc);
        check_sections(&sc);
        check_matching(&sc);
    }
    hz_bake_sidecar_free(&sc);
    return 0;
}
