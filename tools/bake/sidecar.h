/*
 * tools/bake/sidecar.h — scene sidecars (*.hzs): what model formats lack (lights, a camera path, mirror and
 * transparency overrides per material, procedural motion per object, scene-wide settings), as key = value text.
 *
 * Contract: bk_sidecar_parse() reads the whole text strictly: every line is a comment, blank, a section header
 * ([material NAME], [object NAME], [scene]) or `key = value` with a key known in its section and a value of the
 * right form and range. The first problem stops parsing with "FILE:LINE: reason" (HZ_E_FORMAT for syntax,
 * unknown or repeated keys; HZ_E_RANGE for values out of range). Section NAMEs are shell patterns (fnmatch)
 * matched later against the model's material / object names; bk_sidecar_unmatched() names a section that
 * matched nothing, so typos do not pass silently. The grammar is documented in tools/README.md.
 */
#ifndef HZ_BAKE_SIDECAR_H
#define HZ_BAKE_SIDECAR_H

#include <stdint.h>

#include "bake.h"

enum bk_sc_set {
    /* scene */
    BK_SC_NAME = 1u << 0, BK_SC_BACKGROUND = 1u << 1, BK_SC_AMBIENT = 1u << 2, BK_SC_DURATION = 1u << 3,
    BK_SC_FOV = 1u << 4, BK_SC_CAMERA_LOOP = 1u << 5, BK_SC_TEXTURE_MAX = 1u << 6, BK_SC_TUBE_SIDES = 1u << 7,
    BK_SC_TUBE_RADIUS = 1u << 8, BK_SC_NORMALS = 1u << 9, BK_SC_SMOOTH_ANGLE = 1u << 10, BK_SC_SKIN_RATE = 1u << 11,
    BK_SC_RIGID_RATE = 1u << 12, BK_SC_ANIMATION = 1u << 13,
    /* material */
    BK_SC_COLOR = 1u << 0, BK_SC_ALPHA = 1u << 1, BK_SC_ALPHA_MODE = 1u << 2, BK_SC_ALPHA_CUTOFF = 1u << 3,
    BK_SC_MIRROR = 1u << 4,
    /* object */
    BK_SC_MOTION = 1u << 0, BK_SC_PIVOT = 1u << 1, BK_SC_AXIS = 1u << 2, BK_SC_SPEED = 1u << 3,
    BK_SC_AMPLITUDE = 1u << 4, BK_SC_FREQUENCY = 1u << 5, BK_SC_PHASE = 1u << 6,
};

typedef struct bk_sc_key {
    float time, translate[3], axis[3], angle_deg, scale[3];
    int line;
} bk_sc_key_t;

typedef struct bk_sc_camera {
    hz_hzb_camera_key_t key;
    int line;
} bk_sc_camera_t;

typedef struct bk_sc_material {
    char pattern[256];
    int line;
    unsigned set;
    float color[3], alpha, alpha_cutoff, mirror;
    uint32_t alpha_mode;
    int matched;
} bk_sc_material_t;

typedef struct bk_sc_object {
    char pattern[256];
    int line;
    unsigned set;
    uint32_t motion;  /* enum hz_motion_kind; HZ_MOTION_RIGID for `motion = keys` */
    int pivot_center; /* pivot = center: the object's bounds centre at t = 0 */
    float pivot[3], axis[3], speed_deg, amplitude[3], frequency, phase_deg;
    bk_vec_t keys;    /* bk_sc_key_t */
    int matched;
} bk_sc_object_t;

enum bk_normals { BK_NORMALS_SMOOTH = 0, BK_NORMALS_NONE = 1 };

typedef struct bk_sidecar {
    char path[4096];  /* "" when there is none (defaults) */
    unsigned set;
    char name[HZ_HZB_NAME_BYTES];
    float background[3], ambient[3], duration, fov_deg;
    int camera_loop;
    uint32_t texture_max, tube_sides;
    float tube_radius_scale, smooth_angle_deg, skin_rate, rigid_rate;
    uint32_t normals, animation;
    bk_vec_t lights;  /* hz_hzb_light_t */
    bk_vec_t cameras; /* bk_sc_camera_t */
    bk_vec_t materials; /* bk_sc_material_t */
    bk_vec_t objects;   /* bk_sc_object_t */
} bk_sidecar_t;

/* Defaults: no lights or camera keys, black background, ambient 0.03, texture_max 1024, tube_sides 3,
 * smooth normals with a 60 degree crease angle, skin_rate 30, rigid_rate 30, animation 0. */
void bk_sidecar_defaults(bk_sidecar_t *sc);
/* Parses text (size bytes, need not be NUL-terminated) named `path` into sc (which holds the defaults). */
hz_status_t bk_sidecar_parse(bk_sidecar_t *sc, const char *path, const char *text, size_t size, hz_error_t *err);
/* Reads and parses a file. */
hz_status_t bk_sidecar_load(bk_sidecar_t *sc, const char *path, hz_error_t *err);
void bk_sidecar_free(bk_sidecar_t *sc);
/* After matching: HZ_E_FORMAT naming the first material/object section that matched nothing, listing names. */
hz_status_t bk_sidecar_unmatched(const bk_sidecar_t *sc, const bk_scene_t *s, hz_error_t *err);
/* fnmatch-style pattern test used for section names. */
int bk_sidecar_match(const char *pattern, const char *name);

#endif /* HZ_BAKE_SIDECAR_H */
