/*
 * programs/hzbake/sidecar.h — scene sidecars (*.hzs): what model formats lack (lights, a camera path, mirror and
 * transparency overrides per material, procedural motion per object, scene-wide settings), as key = value text.
 *
 * Contract: hz_bake_sidecar_parse() reads the whole text strictly: every line is a comment, blank, a section header
 * ([material NAME], [object NAME], [scene]) or `key = value` with a key known in its section and a value of the
 * right form and range. The first problem stops parsing with "FILE:LINE: reason" (HZ_E_FORMAT for syntax,
 * unknown or repeated keys; HZ_E_RANGE for values out of range). Section NAMEs are shell patterns (fnmatch)
 * matched later against the model's material / object names; hz_bake_sidecar_unmatched() names a section that
 * matched nothing, so typos do not pass silently. The grammar is documented in tools/README.md.
 */
#ifndef HZ_BAKE_SIDECAR_H
#define HZ_BAKE_SIDECAR_H

#include <stdint.h>

#include "bake.h"

enum hz_bake_sc_set {
    /* scene */
    HZ_BAKE_SC_NAME = 1u << 0,
    HZ_BAKE_SC_BACKGROUND = 1u << 1,
    HZ_BAKE_SC_AMBIENT = 1u << 2,
    HZ_BAKE_SC_DURATION = 1u << 3,
    HZ_BAKE_SC_FOV = 1u << 4,
    HZ_BAKE_SC_CAMERA_LOOP = 1u << 5,
    HZ_BAKE_SC_TEXTURE_MAX = 1u << 6,
    HZ_BAKE_SC_TUBE_SIDES = 1u << 7,
    HZ_BAKE_SC_TUBE_RADIUS = 1u << 8,
    HZ_BAKE_SC_NORMALS = 1u << 9,
    HZ_BAKE_SC_SMOOTH_ANGLE = 1u << 10,
    HZ_BAKE_SC_SKIN_RATE = 1u << 11,
    HZ_BAKE_SC_RIGID_RATE = 1u << 12,
    HZ_BAKE_SC_ANIMATION = 1u << 13,
    HZ_BAKE_SC_SKINNING = 1u << 14,
    /* material */
    HZ_BAKE_SC_COLOR = 1u << 0,
    HZ_BAKE_SC_ALPHA = 1u << 1,
    HZ_BAKE_SC_ALPHA_MODE = 1u << 2,
    HZ_BAKE_SC_ALPHA_CUTOFF = 1u << 3,
    HZ_BAKE_SC_MIRROR = 1u << 4,
    /* object */
    HZ_BAKE_SC_MOTION = 1u << 0,
    HZ_BAKE_SC_PIVOT = 1u << 1,
    HZ_BAKE_SC_AXIS = 1u << 2,
    HZ_BAKE_SC_SPEED = 1u << 3,
    HZ_BAKE_SC_AMPLITUDE = 1u << 4,
    HZ_BAKE_SC_FREQUENCY = 1u << 5,
    HZ_BAKE_SC_PHASE = 1u << 6,
};

typedef struct hz_bake_sc_key {
    float time, translate[3], axis[3], angle_deg, scale[3];
    int line;
} hz_bake_sc_key_t;

typedef struct hz_bake_sc_camera {
    hz_hzb_camera_key_t key;
    int line;
} hz_bake_sc_camera_t;

typedef struct hz_bake_sc_material {
    char pattern[256];
    int line;
    unsigned set;
    float color[3], alpha, alpha_cutoff, mirror;
    uint32_t alpha_mode;
    int matched;
} hz_bake_sc_material_t;

typedef struct hz_bake_sc_object {
    char pattern[256];
    int line;
    unsigned set;
    uint32_t motion;  /* enum hz_motion_kind; HZ_MOTION_RIGID for `motion = keys` */
    int pivot_center; /* pivot = center: the object's bounds centre at t = 0 */
    float pivot[3], axis[3], speed_deg, amplitude[3], frequency, phase_deg;
    hz_bake_vec_t keys; /* hz_bake_sc_key_t */
    int matched;
} hz_bake_sc_object_t;

enum hz_bake_normals { HZ_BAKE_NORMALS_SMOOTH = 0, HZ_BAKE_NORMALS_NONE = 1 };
/* How skinned meshes are baked: joints + weights skinned at run time (HZ_MOTION_SKIN), or the old per-vertex
 * keys sampled at skin_rate (HZ_MOTION_VERTEX; large: every vertex, every frame). */
enum hz_bake_skinning { HZ_BAKE_SKINNING_RUNTIME = 0, HZ_BAKE_SKINNING_KEYS = 1 };

typedef struct hz_bake_sidecar {
    char path[4096]; /* "" when there is none (defaults) */
    unsigned set;
    char name[HZ_HZB_NAME_BYTES];
    float background[3], ambient[3], duration, fov_deg;
    int camera_loop;
    uint32_t texture_max, tube_sides;
    float tube_radius_scale, smooth_angle_deg, skin_rate, rigid_rate;
    uint32_t normals, animation, skinning;
    hz_bake_vec_t lights;    /* hz_hzb_light_t */
    hz_bake_vec_t cameras;   /* hz_bake_sc_camera_t */
    hz_bake_vec_t materials; /* hz_bake_sc_material_t */
    hz_bake_vec_t objects;   /* hz_bake_sc_object_t */
} hz_bake_sidecar_t;

/* Defaults: no lights or camera keys, black background, ambient 0.03, texture_max 1024, tube_sides 3,
 * smooth normals with a 60 degree crease angle, skin_rate 30, rigid_rate 30, animation 0, skinning runtime. */
void hz_bake_sidecar_defaults(hz_bake_sidecar_t *sc);
/* Parses text (size bytes, need not be NUL-terminated) named `path` into sc (which holds the defaults). */
hz_status_t hz_bake_sidecar_parse(hz_bake_sidecar_t *sc, const char *path, const char *text, size_t size,
                                  hz_error_t *err);
/* Reads and parses a file. */
hz_status_t hz_bake_sidecar_load(hz_bake_sidecar_t *sc, const char *path, hz_error_t *err);
void hz_bake_sidecar_free(hz_bake_sidecar_t *sc);
/* After matching: HZ_E_FORMAT naming the first material/object section that matched nothing, listing names. */
hz_status_t hz_bake_sidecar_unmatched(const hz_bake_sidecar_t *sc, const hz_bake_scene_t *s, hz_error_t *err);
/* fnmatch-style pattern test used for section names. */
int hz_bake_sidecar_match(const char *pattern, const char *name);

#endif /* HZ_BAKE_SIDECAR_H */
