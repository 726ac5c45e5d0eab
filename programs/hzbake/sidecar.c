/* Sidecar (.hzs) parser (see sidecar.h; the grammar is in tools/README.md). Table-driven for the simple keys,
 * with small hand parsers for the repeatable ones (light, camera, key). */
#include "sidecar.h"

#include <ctype.h>
#include <errno.h>
#include <fnmatch.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define HZ_BAKE_PI 3.14159265358979323846

enum section { SEC_SCENE, SEC_MATERIAL, SEC_OBJECT };
enum kind { K_FLOAT, K_VEC3, K_COLOR, K_UINT, K_BOOL, K_NAME, K_ENUM };

typedef struct keydef {
    const char *key;
    int section;
    int kind;
    unsigned bit;
    size_t offset;            /* into hz_bake_sidecar_t, hz_bake_sc_material_t or hz_bake_sc_object_t */
    double lo, hi;            /* inclusive range (K_FLOAT, K_UINT, K_COLOR components) */
    const char *const *names; /* K_ENUM: NULL-terminated; the value stored is the index (uint32_t) */
    const uint32_t *values;   /* K_ENUM: value per name (NULL: the index) */
    const char *help;
} keydef_t;

static const char *const alpha_modes[] = { "opaque", "mask", "blend", NULL };
static const char *const normal_modes[] = { "smooth", "none", NULL };
static const char *const skinning_modes[] = { "runtime", "keys", NULL };
static const char *const motions[] = { "none", "spin", "oscillate", "keys", "sway", NULL };
static const uint32_t motion_values[] = { HZ_MOTION_NONE, HZ_MOTION_SPIN, HZ_MOTION_OSCILLATE, HZ_MOTION_RIGID,
                                          HZ_MOTION_SWAY };

#define SC(f) offsetof(hz_bake_sidecar_t, f)
#define MT(f) offsetof(hz_bake_sc_material_t, f)
#define OB(f) offsetof(hz_bake_sc_object_t, f)
static const keydef_t keys[] = {
    { "name", SEC_SCENE, K_NAME, HZ_BAKE_SC_NAME, SC(name), 0, 0, NULL, NULL, "scene name (up to 31 bytes)" },
    { "background", SEC_SCENE, K_COLOR, HZ_BAKE_SC_BACKGROUND, SC(background), 0, 1e6, NULL, NULL, "R G B" },
    { "ambient", SEC_SCENE, K_COLOR, HZ_BAKE_SC_AMBIENT, SC(ambient), 0, 1e6, NULL, NULL, "R G B" },
    { "duration", SEC_SCENE, K_FLOAT, HZ_BAKE_SC_DURATION, SC(duration), 0, 1e6, NULL, NULL, "seconds" },
    { "fov", SEC_SCENE, K_FLOAT, HZ_BAKE_SC_FOV, SC(fov_deg), 1, 179, NULL, NULL, "degrees" },
    { "camera_loop", SEC_SCENE, K_BOOL, HZ_BAKE_SC_CAMERA_LOOP, SC(camera_loop), 0, 1, NULL, NULL, "yes or no" },
    { "texture_max", SEC_SCENE, K_UINT, HZ_BAKE_SC_TEXTURE_MAX, SC(texture_max), 1, 16384, NULL, NULL, "texels" },
    { "tube_sides", SEC_SCENE, K_UINT, HZ_BAKE_SC_TUBE_SIDES, SC(tube_sides), 1, 64, NULL, NULL, "1 or 3..64" },
    { "tube_radius_scale", SEC_SCENE, K_FLOAT, HZ_BAKE_SC_TUBE_RADIUS, SC(tube_radius_scale), 1e-3, 1e3, NULL, NULL,
      "factor" },
    { "normals", SEC_SCENE, K_ENUM, HZ_BAKE_SC_NORMALS, SC(normals), 0, 0, normal_modes, NULL, "smooth or none" },
    { "smooth_angle", SEC_SCENE, K_FLOAT, HZ_BAKE_SC_SMOOTH_ANGLE, SC(smooth_angle_deg), 0, 180, NULL, NULL,
      "degrees" },
    { "skin_rate", SEC_SCENE, K_FLOAT, HZ_BAKE_SC_SKIN_RATE, SC(skin_rate), 0.1, 1000, NULL, NULL, "frames/s" },
    { "rigid_rate", SEC_SCENE, K_FLOAT, HZ_BAKE_SC_RIGID_RATE, SC(rigid_rate), 0.1, 1000, NULL, NULL, "keys/s" },
    { "animation", SEC_SCENE, K_UINT, HZ_BAKE_SC_ANIMATION, SC(animation), 0, 1e6, NULL, NULL, "index" },
    { "skinning", SEC_SCENE, K_ENUM, HZ_BAKE_SC_SKINNING, SC(skinning), 0, 0, skinning_modes, NULL,
      "runtime or keys" },

    { "color", SEC_MATERIAL, K_COLOR, HZ_BAKE_SC_COLOR, MT(color), 0, 1, NULL, NULL, "R G B in [0, 1]" },
    { "alpha", SEC_MATERIAL, K_FLOAT, HZ_BAKE_SC_ALPHA, MT(alpha), 0, 1, NULL, NULL, "opacity in [0, 1]" },
    { "alpha_mode", SEC_MATERIAL, K_ENUM, HZ_BAKE_SC_ALPHA_MODE, MT(alpha_mode), 0, 0, alpha_modes, NULL,
      "opaque, mask or blend" },
    { "alpha_cutoff", SEC_MATERIAL, K_FLOAT, HZ_BAKE_SC_ALPHA_CUTOFF, MT(alpha_cutoff), 0, 1, NULL, NULL, "[0, 1]" },
    { "mirror", SEC_MATERIAL, K_FLOAT, HZ_BAKE_SC_MIRROR, MT(mirror), 0, 1, NULL, NULL, "reflectance in [0, 1]" },

    { "motion", SEC_OBJECT, K_ENUM, HZ_BAKE_SC_MOTION, OB(motion), 0, 0, motions, motion_values,
      "none, spin, oscillate, keys or sway" },
    { "pivot", SEC_OBJECT, K_VEC3, HZ_BAKE_SC_PIVOT, OB(pivot), -1e9, 1e9, NULL, NULL, "X Y Z or center" },
    { "axis", SEC_OBJECT, K_VEC3, HZ_BAKE_SC_AXIS, OB(axis), -1e9, 1e9, NULL, NULL, "X Y Z" },
    { "speed", SEC_OBJECT, K_FLOAT, HZ_BAKE_SC_SPEED, OB(speed_deg), -1e6, 1e6, NULL, NULL, "degrees/s" },
    { "amplitude", SEC_OBJECT, K_VEC3, HZ_BAKE_SC_AMPLITUDE, OB(amplitude), -1e9, 1e9, NULL, NULL, "X Y Z" },
    { "frequency", SEC_OBJECT, K_FLOAT, HZ_BAKE_SC_FREQUENCY, OB(frequency), 0, 1e4, NULL, NULL, "Hz" },
    { "phase", SEC_OBJECT, K_FLOAT, HZ_BAKE_SC_PHASE, OB(phase_deg), -1e6, 1e6, NULL, NULL, "degrees" },
};

static const char *const section_names[] = { "scene", "material", "object" };

void hz_bake_sidecar_defaults(hz_bake_sidecar_t *sc)
{
    memset(sc, 0, sizeof *sc);
    sc->ambient[0] = sc->ambient[1] = sc->ambient[2] = 0.03f;
    sc->texture_max = 1024;
    sc->tube_sides = 3;
    sc->tube_radius_scale = 1.0f;
    sc->normals = HZ_BAKE_NORMALS_SMOOTH;
    sc->smooth_angle_deg = 60.0f;
    sc->skin_rate = 30.0f;
    sc->rigid_rate = 30.0f;
    hz_bake_vec_init(&sc->lights, sizeof(hz_hzb_light_t));
    hz_bake_vec_init(&sc->cameras, sizeof(hz_bake_sc_camera_t));
    hz_bake_vec_init(&sc->materials, sizeof(hz_bake_sc_material_t));
    hz_bake_vec_init(&sc->objects, sizeof(hz_bake_sc_object_t));
}

void hz_bake_sidecar_free(hz_bake_sidecar_t *sc)
{
    for (size_t i = 0; i < sc->objects.len; i++)
        hz_bake_vec_free(&HZ_BAKE_AT(sc->objects, hz_bake_sc_object_t, i)->keys);
    hz_bake_vec_free(&sc->lights);
    hz_bake_vec_free(&sc->cameras);
    hz_bake_vec_free(&sc->materials);
    hz_bake_vec_free(&sc->objects);
}

/* ---- parsing state ---- */

typedef struct parser {
    hz_bake_sidecar_t *sc;
    const char *path;
    int line;
    int section;
    void *target;  /* struct the current section's keys write into */
    unsigned *set; /* its set bits */
    hz_error_t *err;
} parser_t;

static hz_status_t perr(parser_t *p, hz_status_t code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static hz_status_t perr(parser_t *p, hz_status_t code, const char *fmt, ...)
{
    char msg[200];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return hz_bake_err(p->err, code, "%s:%d: %s", p->path, p->line, msg);
}

/* Splits s (modified in place) into whitespace-separated words; returns the count (at most max). */
static int split(char *s, char **words, int max)
{
    int n = 0;
    while (*s) {
        while (*s && isspace((unsigned char)*s))
            *s++ = 0;
        if (!*s)
            break;
        if (n == max)
            return max + 1;
        words[n++] = s;
        while (*s && !isspace((unsigned char)*s))
            s++;
    }
    return n;
}

static int parse_number(const char *w, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(w, &end);
    if (end == w || *end || errno == ERANGE || !isfinite(v))
        return 0;
    /* strtod accepts hex floats, "inf" and "nan"; only plain decimal numbers are allowed here. */
    for (const char *c = w; *c; c++)
        if (!(isdigit((unsigned char)*c) || *c == '.' || *c == '-' || *c == '+' || *c == 'e' || *c == 'E'))
            return 0;
    *out = v;
    return 1;
}

static hz_status_t number(parser_t *p, const char *what, const char *w, double lo, double hi, float *out)
{
    double v;
    if (!parse_number(w, &v))
        return perr(p, HZ_E_FORMAT, "%s: '%s' is not a number", what, w);
    if (v < lo || v > hi)
        return perr(p, HZ_E_RANGE, "%s: %s is outside [%g, %g]", what, w, lo, hi);
    *out = (float)v;
    return HZ_OK;
}

static hz_status_t numbers(parser_t *p, const char *what, char **w, int n, double lo, double hi, float *out)
{
    for (int i = 0; i < n; i++) {
        hz_status_t s = number(p, what, w[i], lo, hi, &out[i]);
        if (s)
            return s;
    }
    return HZ_OK;
}

static hz_status_t simple_key(parser_t *p, const keydef_t *k, char *value)
{
    char *w[8];
    int n = split(value, w, 7);
    char *base = (char *)p->target;
    switch (k->kind) {
    case K_FLOAT:
        if (n != 1)
            return perr(p, HZ_E_FORMAT, "%s: expected one number (%s)", k->key, k->help);
        return number(p, k->key, w[0], k->lo, k->hi, (float *)(base + k->offset));
    case K_VEC3:
        if (k->bit == HZ_BAKE_SC_PIVOT && n == 1 && !strcmp(w[0], "center")) {
            ((hz_bake_sc_object_t *)p->target)->pivot_center = 1;
            return HZ_OK;
        }
        /* fall through */
    case K_COLOR:
        if (n != 3)
            return perr(p, HZ_E_FORMAT, "%s: expected three numbers (%s)", k->key, k->help);
        return numbers(p, k->key, w, 3, k->lo, k->hi, (float *)(base + k->offset));
    case K_UINT: {
        float v;
        hz_status_t s;
        if (n != 1)
            return perr(p, HZ_E_FORMAT, "%s: expected one integer (%s)", k->key, k->help);
        if ((s = number(p, k->key, w[0], k->lo, k->hi, &v)))
            return s;
        if (v != floorf(v))
            return perr(p, HZ_E_FORMAT, "%s: '%s' is not an integer", k->key, w[0]);
        *(uint32_t *)(base + k->offset) = (uint32_t)v;
        return HZ_OK;
    }
    case K_BOOL:
        if (n == 1 && (!strcmp(w[0], "yes") || !strcmp(w[0], "true") || !strcmp(w[0], "1")))
            *(int *)(base + k->offset) = 1;
        else if (n == 1 && (!strcmp(w[0], "no") || !strcmp(w[0], "false") || !strcmp(w[0], "0")))
            *(int *)(base + k->offset) = 0;
        else
            return perr(p, HZ_E_FORMAT, "%s: expected yes or no", k->key);
        return HZ_OK;
    case K_NAME: {
        /* The whole value, spaces included (split() cut it: rejoin by measuring the original). */
        if (n < 1)
            return perr(p, HZ_E_FORMAT, "%s: empty", k->key);
        char joined[256] = "";
        for (int i = 0; i < n && i < 7; i++) {
            if (i)
                strncat(joined, " ", sizeof joined - strlen(joined) - 1);
            strncat(joined, w[i], sizeof joined - strlen(joined) - 1);
        }
        if (n > 7 || strlen(joined) > HZ_HZB_NAME_BYTES - 1)
            return perr(p, HZ_E_RANGE, "%s: longer than %u bytes", k->key, HZ_HZB_NAME_BYTES - 1);
        memcpy(base + k->offset, joined, strlen(joined) + 1);
        return HZ_OK;
    }
    case K_ENUM:
        if (n == 1)
            for (uint32_t i = 0; k->names[i]; i++)
                if (!strcmp(w[0], k->names[i])) {
                    *(uint32_t *)(base + k->offset) = k->values ? k->values[i] : i;
                    return HZ_OK;
                }
        return perr(p, HZ_E_FORMAT, "%s: expected %s", k->key, k->help);
    default: return perr(p, HZ_E_INTERNAL, "%s: unknown key kind", k->key);
    }
}

/* light = position X Y Z color R G B [falloff inverse-square|none] */
static hz_status_t light_key(parser_t *p, char *value)
{
    char *w[16];
    int n = split(value, w, 15);
    hz_hzb_light_t l;
    memset(&l, 0, sizeof l);
    int have_pos = 0, have_color = 0, have_falloff = 0;
    if (n > 15)
        return perr(p, HZ_E_FORMAT, "light: too many words");
    for (int i = 0; i < n;) {
        hz_status_t s;
        if (!strcmp(w[i], "position") && !have_pos) {
            if (i + 4 > n)
                return perr(p, HZ_E_FORMAT, "light: 'position' needs X Y Z");
            if ((s = numbers(p, "light position", w + i + 1, 3, -1e9, 1e9, l.position)))
                return s;
            have_pos = 1;
            i += 4;
        } else if (!strcmp(w[i], "color") && !have_color) {
            if (i + 4 > n)
                return perr(p, HZ_E_FORMAT, "light: 'color' needs R G B");
            if ((s = numbers(p, "light color", w + i + 1, 3, 0, 1e9, l.color)))
                return s;
            have_color = 1;
            i += 4;
        } else if (!strcmp(w[i], "falloff") && !have_falloff) {
            if (i + 2 > n)
                return perr(p, HZ_E_FORMAT, "light: 'falloff' needs inverse-square or none");
            if (!strcmp(w[i + 1], "inverse-square"))
                l.falloff = HZ_FALLOFF_INV_SQUARE;
            else if (!strcmp(w[i + 1], "none"))
                l.falloff = HZ_FALLOFF_NONE;
            else
                return perr(p, HZ_E_FORMAT, "light: falloff '%s' is not inverse-square or none", w[i + 1]);
            have_falloff = 1;
            i += 2;
        } else {
            return perr(p, HZ_E_FORMAT,
                        "light: unexpected '%s' (expected: position X Y Z color R G B "
                        "[falloff inverse-square|none])",
                        w[i]);
        }
    }
    if (!have_pos || !have_color)
        return perr(p, HZ_E_FORMAT, "light: expected position X Y Z color R G B [falloff inverse-square|none]");
    *(hz_hzb_light_t *)hz_bake_vec_push(&p->sc->lights, 1) = l;
    return HZ_OK;
}

/* camera = TIME eye X Y Z target X Y Z [up X Y Z] [fov DEGREES] */
static hz_status_t camera_key(parser_t *p, char *value)
{
    char *w[24];
    int n = split(value, w, 23);
    hz_bake_sc_camera_t c;
    memset(&c, 0, sizeof c);
    c.line = p->line;
    c.key.up[1] = 1.0f;
    float fov = 0.0f; /* 0: the scene's fov, resolved when the whole file is read */
    hz_status_t s;
    if (n < 1 || n > 23)
        return perr(p, HZ_E_FORMAT, "camera: expected TIME eye X Y Z target X Y Z [up X Y Z] [fov DEGREES]");
    if ((s = number(p, "camera time", w[0], 0, 1e6, &c.key.time)))
        return s;
    int have_eye = 0, have_target = 0, have_up = 0, have_fov = 0;
    for (int i = 1; i < n;) {
        int vec = !strcmp(w[i], "eye") ? 1 : !strcmp(w[i], "target") ? 2 : !strcmp(w[i], "up") ? 3 : 0;
        if (vec) {
            int *have = vec == 1 ? &have_eye : vec == 2 ? &have_target : &have_up;
            float *dst = vec == 1 ? c.key.eye : vec == 2 ? c.key.target : c.key.up;
            if (*have || i + 4 > n)
                return perr(p, HZ_E_FORMAT, "camera: '%s' given twice or without X Y Z", w[i]);
            if ((s = numbers(p, "camera vector", w + i + 1, 3, -1e9, 1e9, dst)))
                return s;
            *have = 1;
            i += 4;
        } else if (!strcmp(w[i], "fov") && !have_fov && i + 2 <= n) {
            if ((s = number(p, "camera fov", w[i + 1], 1, 179, &fov)))
                return s;
            have_fov = 1;
            i += 2;
        } else {
            return perr(p, HZ_E_FORMAT,
                        "camera: unexpected '%s' (expected: TIME eye X Y Z target X Y Z [up X Y Z] "
                        "[fov DEGREES])",
                        w[i]);
        }
    }
    if (!have_eye || !have_target)
        return perr(p, HZ_E_FORMAT, "camera: 'eye' and 'target' are required");
    if (c.key.eye[0] == c.key.target[0] && c.key.eye[1] == c.key.target[1] && c.key.eye[2] == c.key.target[2])
        return perr(p, HZ_E_RANGE, "camera: eye and target coincide");
    if (c.key.up[0] == 0 && c.key.up[1] == 0 && c.key.up[2] == 0)
        return perr(p, HZ_E_RANGE, "camera: up is zero");
    c.key.fov_y = fov * (float)(HZ_BAKE_PI / 180.0);
    if (p->sc->cameras.len) {
        const hz_bake_sc_camera_t *prev = HZ_BAKE_AT(p->sc->cameras, hz_bake_sc_camera_t, p->sc->cameras.len - 1);
        if (!(c.key.time > prev->key.time))
            return perr(p, HZ_E_RANGE, "camera: time %g does not follow the previous key's %g (line %d)",
                        (double)c.key.time, (double)prev->key.time, prev->line);
    }
    *(hz_bake_sc_camera_t *)hz_bake_vec_push(&p->sc->cameras, 1) = c;
    return HZ_OK;
}

/* key = TIME [translate X Y Z] [rotate AX AY AZ DEGREES] [scale S | scale SX SY SZ] */
static hz_status_t object_key(parser_t *p, char *value)
{
    hz_bake_sc_object_t *o = (hz_bake_sc_object_t *)p->target;
    char *w[24];
    int n = split(value, w, 23);
    hz_bake_sc_key_t k;
    memset(&k, 0, sizeof k);
    k.line = p->line;
    k.axis[1] = 1.0f;
    k.scale[0] = k.scale[1] = k.scale[2] = 1.0f;
    hz_status_t s;
    if (n < 1 || n > 23)
        return perr(p, HZ_E_FORMAT, "key: expected TIME [translate X Y Z] [rotate AX AY AZ DEGREES] [scale S]");
    if ((s = number(p, "key time", w[0], 0, 1e6, &k.time)))
        return s;
    int have_t = 0, have_r = 0, have_s = 0;
    for (int i = 1; i < n;) {
        if (!strcmp(w[i], "translate") && !have_t && i + 4 <= n) {
            if ((s = numbers(p, "key translate", w + i + 1, 3, -1e9, 1e9, k.translate)))
                return s;
            have_t = 1;
            i += 4;
        } else if (!strcmp(w[i], "rotate") && !have_r && i + 5 <= n) {
            if ((s = numbers(p, "key rotate axis", w + i + 1, 3, -1e9, 1e9, k.axis)) ||
                (s = number(p, "key rotate angle", w[i + 4], -1e6, 1e6, &k.angle_deg)))
                return s;
            if (k.axis[0] == 0 && k.axis[1] == 0 && k.axis[2] == 0)
                return perr(p, HZ_E_RANGE, "key: rotation axis is zero");
            have_r = 1;
            i += 5;
        } else if (!strcmp(w[i], "scale") && !have_s && i + 2 <= n) {
            double v;
            if (i + 4 <= n && parse_number(w[i + 2], &v)) {
                if ((s = numbers(p, "key scale", w + i + 1, 3, 1e-6, 1e6, k.scale)))
                    return s;
                i += 4;
            } else {
                if ((s = number(p, "key scale", w[i + 1], 1e-6, 1e6, &k.scale[0])))
                    return s;
                k.scale[1] = k.scale[2] = k.scale[0];
                i += 2;
            }
            have_s = 1;
        } else {
            return perr(p, HZ_E_FORMAT,
                        "key: unexpected '%s' (expected: TIME [translate X Y Z] "
                        "[rotate AX AY AZ DEGREES] [scale S | scale SX SY SZ])",
                        w[i]);
        }
    }
    if (o->keys.len) {
        const hz_bake_sc_key_t *prev = HZ_BAKE_AT(o->keys, hz_bake_sc_key_t, o->keys.len - 1);
        if (!(k.time > prev->time))
            return perr(p, HZ_E_RANGE, "key: time %g does not follow the previous key's %g (line %d)", (double)k.time,
                        (double)prev->time, prev->line);
    }
    *(hz_bake_sc_key_t *)hz_bake_vec_push(&o->keys, 1) = k;
    return HZ_OK;
}

/* Checks the finished section (an object's motion needs its parameters). */
static hz_status_t close_section(parser_t *p)
{
    if (p->section != SEC_OBJECT)
        return HZ_OK;
    hz_bake_sc_object_t *o = (hz_bake_sc_object_t *)p->target;
    int save = p->line;
    p->line = o->line;
    unsigned spin = HZ_BAKE_SC_PIVOT | HZ_BAKE_SC_AXIS | HZ_BAKE_SC_SPEED,
             osc = HZ_BAKE_SC_AMPLITUDE | HZ_BAKE_SC_FREQUENCY | HZ_BAKE_SC_PHASE;
    hz_status_t s = HZ_OK;
    unsigned given = o->set | (o->pivot_center ? HZ_BAKE_SC_PIVOT : 0);
    if (!(o->set & HZ_BAKE_SC_MOTION)) {
        if (given || o->keys.len)
            s = perr(p, HZ_E_FORMAT, "[object \"%s\"]: motion parameters without 'motion = ...'", o->pattern);
    } else if (o->motion == HZ_MOTION_SPIN) {
        if (!(o->set & HZ_BAKE_SC_AXIS) || !(o->set & HZ_BAKE_SC_SPEED))
            s = perr(p, HZ_E_FORMAT, "[object \"%s\"]: motion = spin needs 'axis' and 'speed'", o->pattern);
        else if (o->axis[0] == 0 && o->axis[1] == 0 && o->axis[2] == 0)
            s = perr(p, HZ_E_RANGE, "[object \"%s\"]: spin axis is zero", o->pattern);
        else if ((given & osc) || o->keys.len)
            s = perr(p, HZ_E_FORMAT, "[object \"%s\"]: oscillate parameters or keys given for motion = spin",
                     o->pattern);
    } else if (o->motion == HZ_MOTION_OSCILLATE) {
        if (!(o->set & HZ_BAKE_SC_AMPLITUDE) || !(o->set & HZ_BAKE_SC_FREQUENCY))
            s = perr(p, HZ_E_FORMAT, "[object \"%s\"]: motion = oscillate needs 'amplitude' and 'frequency'",
                     o->pattern);
        else if ((given & spin) || o->keys.len)
            s = perr(p, HZ_E_FORMAT, "[object \"%s\"]: spin parameters or keys given for motion = oscillate",
                     o->pattern);
    } else if (o->motion == HZ_MOTION_SWAY) {
        if (!(o->set & HZ_BAKE_SC_AMPLITUDE) || !(o->set & HZ_BAKE_SC_FREQUENCY))
            s = perr(p, HZ_E_FORMAT, "[object \"%s\"]: motion = sway needs 'amplitude' and 'frequency'", o->pattern);
        else if ((given & (HZ_BAKE_SC_AXIS | HZ_BAKE_SC_SPEED | HZ_BAKE_SC_PHASE)) || o->keys.len)
            s = perr(p, HZ_E_FORMAT, "[object \"%s\"]: motion = sway takes pivot, amplitude and frequency only",
                     o->pattern);
    } else if (o->motion == HZ_MOTION_RIGID) {
        if (!o->keys.len)
            s = perr(p, HZ_E_FORMAT, "[object \"%s\"]: motion = keys needs at least one 'key = ...' line", o->pattern);
        else if (given & (spin | osc))
            s = perr(p, HZ_E_FORMAT, "[object \"%s\"]: spin or oscillate parameters given for motion = keys",
                     o->pattern);
    } else if ((given & ~HZ_BAKE_SC_MOTION) || o->keys.len) {
        s = perr(p, HZ_E_FORMAT, "[object \"%s\"]: motion parameters given for motion = none", o->pattern);
    }
    p->line = save;
    return s;
}

/* [material NAME] / [object NAME] / [scene]; NAME bare or "quoted". */
static hz_status_t section_header(parser_t *p, char *s)
{
    hz_status_t st = close_section(p);
    if (st)
        return st;
    size_t n = strlen(s);
    if (n < 2 || s[n - 1] != ']')
        return perr(p, HZ_E_FORMAT, "section header must end with ']'");
    s[n - 1] = 0;
    s++;
    while (isspace((unsigned char)*s))
        s++;
    char *kind = s;
    while (*s && !isspace((unsigned char)*s))
        s++;
    if (*s)
        *s++ = 0;
    while (isspace((unsigned char)*s))
        s++;
    char *name = s;
    size_t nl = strlen(name);
    while (nl && isspace((unsigned char)name[nl - 1]))
        name[--nl] = 0;
    if (nl >= 2 && name[0] == '"' && name[nl - 1] == '"') {
        name[nl - 1] = 0;
        name++;
        if (strchr(name, '"'))
            return perr(p, HZ_E_FORMAT, "section name: stray '\"'");
    } else if (strchr(name, '"') || strpbrk(name, " \t")) {
        return perr(p, HZ_E_FORMAT, "section name with spaces or quotes must be written \"like this\"");
    }
    if (!strcmp(kind, "scene")) {
        if (*name)
            return perr(p, HZ_E_FORMAT, "[scene] takes no name");
        p->section = SEC_SCENE;
        p->target = p->sc;
        p->set = &p->sc->set;
        return HZ_OK;
    }
    if (!*name || strlen(name) >= 256)
        return perr(p, HZ_E_FORMAT, "[%s NAME]: the name is missing or longer than 255 bytes", kind);
    /* The same NAME twice: the later section would silently take over the earlier one's objects. */
    const hz_bake_vec_t *same = !strcmp(kind, "material") ? &p->sc->materials : !strcmp(kind, "object") ? &p->sc->objects
                                                                                                        : NULL;
    for (size_t i = 0; same && i < same->len; i++) {
        const char *pattern = same == &p->sc->materials ? HZ_BAKE_AT(*same, hz_bake_sc_material_t, i)->pattern
                                                        : HZ_BAKE_AT(*same, hz_bake_sc_object_t, i)->pattern;
        int line = same == &p->sc->materials ? HZ_BAKE_AT(*same, hz_bake_sc_material_t, i)->line
                                             : HZ_BAKE_AT(*same, hz_bake_sc_object_t, i)->line;
        if (!strcmp(pattern, name))
            return perr(p, HZ_E_FORMAT, "[%s \"%s\"] repeats the section of line %d: merge the two (the later one "
                        "would take over)", kind, name, line);
    }
    if (!strcmp(kind, "material")) {
        hz_bake_sc_material_t *m = hz_bake_vec_push(&p->sc->materials, 1);
        snprintf(m->pattern, sizeof m->pattern, "%s", name);
        m->line = p->line;
        p->section = SEC_MATERIAL;
        p->target = m;
        p->set = &m->set;
        return HZ_OK;
    }
    if (!strcmp(kind, "object")) {
        hz_bake_sc_object_t *o = hz_bake_vec_push(&p->sc->objects, 1);
        snprintf(o->pattern, sizeof o->pattern, "%s", name);
        o->line = p->line;
        hz_bake_vec_init(&o->keys, sizeof(hz_bake_sc_key_t));
        p->section = SEC_OBJECT;
        p->target = o;
        p->set = &o->set;
        return HZ_OK;
    }
    return perr(p, HZ_E_FORMAT, "unknown section '[%s]' (sections: [scene], [material NAME], [object NAME])", kind);
}

static hz_status_t key_line(parser_t *p, char *s)
{
    char *eq = strchr(s, '=');
    if (!eq)
        return perr(p, HZ_E_FORMAT, "expected 'key = value', a [section] or a # comment");
    *eq = 0;
    char *key = s, *value = eq + 1;
    size_t kl = strlen(key);
    while (kl && isspace((unsigned char)key[kl - 1]))
        key[--kl] = 0;
    while (isspace((unsigned char)*value))
        value++;
    if (!kl)
        return perr(p, HZ_E_FORMAT, "missing key before '='");
    for (size_t i = 0; i < kl; i++)
        if (!(islower((unsigned char)key[i]) || key[i] == '_')) {
            /* Invisible bytes (a byte-order mark mid-file, a non-breaking space) are shown as \xNN. */
            char shown[256];
            size_t n = 0;
            int invisible = 0;
            for (size_t k = 0; k < kl && n + 5 < sizeof shown; k++) {
                unsigned char c = (unsigned char)key[k];
                if (c >= 0x21 && c < 0x7f) {
                    shown[n++] = (char)c;
                } else {
                    n += (size_t)snprintf(shown + n, sizeof shown - n, "\\x%02x", c);
                    invisible = 1;
                }
            }
            shown[n] = 0;
            int bom = kl >= 3 && !memcmp(key, "\xef\xbb\xbf", 3);
            return perr(p, HZ_E_FORMAT, "'%s' is not a key (keys are lower_case words)%s", shown,
                        bom ? "; it starts with a UTF-8 byte-order mark (U+FEFF), which is only accepted at "
                              "the start of the file"
                            : invisible ? "; it holds bytes that do not print (shown as \\xNN)" : "");
        }
    if (!*value)
        return perr(p, HZ_E_FORMAT, "%s: missing value", key);
    if (p->section == SEC_SCENE && !strcmp(key, "light"))
        return light_key(p, value);
    if (p->section == SEC_SCENE && !strcmp(key, "camera"))
        return camera_key(p, value);
    if (p->section == SEC_OBJECT && !strcmp(key, "key"))
        return object_key(p, value);
    for (size_t i = 0; i < HZ_ARRAY_LEN(keys); i++) {
        const keydef_t *k = &keys[i];
        if (k->section != p->section || strcmp(k->key, key))
            continue;
        if (*p->set & k->bit)
            return perr(p, HZ_E_FORMAT, "%s: given twice in this section", key);
        if (k->bit == HZ_BAKE_SC_PIVOT && ((hz_bake_sc_object_t *)p->target)->pivot_center)
            return perr(p, HZ_E_FORMAT, "%s: given twice in this section", key);
        hz_status_t s = simple_key(p, k, value);
        if (s)
            return s;
        if (p->section == SEC_SCENE && k->bit == HZ_BAKE_SC_TUBE_SIDES && p->sc->tube_sides == 2)
            return perr(p, HZ_E_RANGE, "tube_sides = 2 makes a doubled flat ribbon; use 1 (ribbon) or 3..64");
        if (!(k->bit == HZ_BAKE_SC_PIVOT && ((hz_bake_sc_object_t *)p->target)->pivot_center))
            *p->set |= k->bit;
        return HZ_OK;
    }
    for (size_t i = 0; i < HZ_ARRAY_LEN(keys); i++)
        if (!strcmp(keys[i].key, key))
            return perr(p, HZ_E_FORMAT, "'%s' belongs in a [%s] section, not [%s]", key, section_names[keys[i].section],
                        section_names[p->section]);
    if (!strcmp(key, "light") || !strcmp(key, "camera"))
        return perr(p, HZ_E_FORMAT, "'%s' belongs in the [scene] part (before any [material]/[object])", key);
    if (!strcmp(key, "key"))
        return perr(p, HZ_E_FORMAT, "'key' belongs in an [object NAME] section");
    return perr(p, HZ_E_FORMAT, "unknown key '%s' in [%s]", key, section_names[p->section]);
}

hz_status_t hz_bake_sidecar_parse(hz_bake_sidecar_t *sc, const char *path, const char *text, size_t size,
                                  hz_error_t *err)
{
    parser_t p = { sc, path, 0, SEC_SCENE, sc, &sc->set, err };
    snprintf(sc->path, sizeof sc->path, "%s", path);
    size_t at = 0;
    char line[4096];
    /* A UTF-8 byte-order mark, as some Windows editors write it, is not part of the text. */
    if (size >= 3 && !memcmp(text, "\xef\xbb\xbf", 3))
        at = 3;
    while (at < size) {
        p.line++;
        size_t end = at;
        while (end < size && text[end] != '\n')
            end++;
        size_t n = end - at;
        if (n >= sizeof line)
            return perr(&p, HZ_E_FORMAT, "line longer than %zu bytes", sizeof line - 1);
        memcpy(line, text + at, n);
        line[n] = 0;
        at = end + 1;
        if (memchr(line, 0, n))
            return perr(&p, HZ_E_FORMAT, "NUL byte in text (is this a binary file?)");
        /* Comments: '#' outside double quotes. */
        int quoted = 0;
        for (char *c = line; *c; c++) {
            if (*c == '"')
                quoted = !quoted;
            else if (*c == '#' && !quoted) {
                *c = 0;
                break;
            }
        }
        char *s = line;
        while (isspace((unsigned char)*s))
            s++;
        size_t l = strlen(s);
        while (l && isspace((unsigned char)s[l - 1]))
            s[--l] = 0;
        if (!*s)
            continue;
        hz_status_t st = *s == '[' ? section_header(&p, s) : key_line(&p, s);
        if (st)
            return st;
    }
    hz_status_t st = close_section(&p);
    if (st)
        return st;
    p.line = 0;
    for (size_t i = 0; i < sc->cameras.len; i++) {
        hz_bake_sc_camera_t *c = HZ_BAKE_AT(sc->cameras, hz_bake_sc_camera_t, i);
        if (c->key.fov_y == 0.0f)
            c->key.fov_y = (sc->fov_deg > 0.0f ? sc->fov_deg : 60.0f) * (float)(HZ_BAKE_PI / 180.0);
    }
    if (sc->camera_loop && !(sc->duration > 0.0f))
        return hz_bake_err(err, HZ_E_FORMAT, "%s: camera_loop = yes needs a duration > 0", path);
    if (sc->camera_loop && sc->cameras.len) {
        const hz_bake_sc_camera_t *last = HZ_BAKE_AT(sc->cameras, hz_bake_sc_camera_t, sc->cameras.len - 1);
        if (!(last->key.time < sc->duration))
            return hz_bake_err(err, HZ_E_RANGE,
                               "%s:%d: a looping camera path needs every key time below the duration "
                               "(%g s)",
                               path, last->line, (double)sc->duration);
    }
    return HZ_OK;
}

hz_status_t hz_bake_sidecar_load(hz_bake_sidecar_t *sc, const char *path, hz_error_t *err)
{
    uint8_t *data;
    size_t size;
    hz_status_t s = hz_bake_read_file(path, &data, &size, err);
    if (s)
        return s;
    s = hz_bake_sidecar_parse(sc, path, (const char *)data, size, err);
    free(data);
    return s;
}

int hz_bake_sidecar_match(const char *pattern, const char *name)
{
    return fnmatch(pattern, name, 0) == 0;
}

static void list_names(char *buf, size_t size, const hz_bake_vec_t *v, int objects)
{
    size_t n = 0;
    buf[0] = 0;
    for (size_t i = 0; i < v->len && n + 40 < size; i++) {
        const char *name =
            objects ? HZ_BAKE_AT(*v, hz_bake_object_t, i)->name : HZ_BAKE_AT(*v, hz_bake_material_t, i)->name;
        n += (size_t)snprintf(buf + n, size - n, "%s'%s'", i ? ", " : "", name);
        if (i == 11 && v->len > 12) {
            snprintf(buf + n, size - n, ", ... (%zu in all)", v->len);
            break;
        }
    }
}

hz_status_t hz_bake_sidecar_unmatched(const hz_bake_sidecar_t *sc, const hz_bake_scene_t *s, hz_error_t *err)
{
    char names[200];
    for (size_t i = 0; i < sc->materials.len; i++) {
        const hz_bake_sc_material_t *m = HZ_BAKE_AT(sc->materials, hz_bake_sc_material_t, i);
        if (!m->matched) {
            list_names(names, sizeof names, &s->mats, 0);
            return hz_bake_err(err, HZ_E_FORMAT, "%s:%d: [material \"%s\"] matches no material of the model (%s)",
                               sc->path, m->line, m->pattern, names);
        }
    }
    for (size_t i = 0; i < sc->objects.len; i++) {
        const hz_bake_sc_object_t *o = HZ_BAKE_AT(sc->objects, hz_bake_sc_object_t, i);
        if (!o->matched) {
            list_names(names, sizeof names, &s->objs, 1);
            return hz_bake_err(err, HZ_E_FORMAT, "%s:%d: [object \"%s\"] matches no object of the model (%s)", sc->path,
                               o->line, o->pattern, names);
        }
    }
    return HZ_OK;
}
