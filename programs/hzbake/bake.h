/*
 * programs/hzbake/bake.h — the pieces of the scene baker (hzbake) that its modules share: growable arrays,
 * messages, whole-file and gzip input, paths, and the in-memory scene that the importers fill and
 * scene.c turns into a .hzb image.
 *
 * Contract: the baker is a hosted host tool (libc, libm, assimp, stb_image, zlib). Fallible functions return
 * hz_status_t and describe the failure in an hz_error_t whose message names the input file and the reason.
 * Running out of memory is not recoverable in the baker: hz_bake_vec_push() and hz_bake_xmalloc() print a message and
 * exit with the HZ_E_NO_MEMORY exit status (the import runs in a child process, so the parent reports it).
 *
 * Scene conventions (see tools/README.md): objects are appended one at a time (hz_bake_object_begin / _end) and own
 * a contiguous range of vertices and triangles; positions and normals are float4 with w = 0; UVs put (0, 0)
 * at the top-left texel of a texture (u right, v down: the glTF convention; OBJ's v is flipped on import).
 */
#ifndef HZ_BAKE_H
#define HZ_BAKE_H

#include <stddef.h>
#include <stdint.h>

#include "hz/hzb.h"
#include "hz/status.h"

/* ---- growable arrays ---- */

typedef struct hz_bake_vec {
    void *data;
    size_t len, cap, elem;
} hz_bake_vec_t;

#define HZ_BAKE_VEC_INIT(type)                                                                                         \
    {                                                                                                                  \
        NULL, 0, 0, sizeof(type)                                                                                       \
    }

void hz_bake_vec_init(hz_bake_vec_t *v, size_t elem);
/* Appends n zeroed elements and returns a pointer to the first; exits on out-of-memory. */
void *hz_bake_vec_push(hz_bake_vec_t *v, size_t n);
void hz_bake_vec_free(hz_bake_vec_t *v);
#define HZ_BAKE_AT(vec, type, i) (&((type *)(vec).data)[i])

void *hz_bake_xmalloc(size_t n);
void *hz_bake_xcalloc(size_t n, size_t size);
char *hz_bake_xstrdup(const char *s);

/* ---- messages ---- */

extern int hz_bake_verbose;  /* progress lines on stderr */
extern int hz_bake_warnings; /* number of warnings printed */

void hz_bake_warn(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void hz_bake_progress(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* The import child names the phase it enters ("baking skinning of mesh 'Cesium_Man' (2 s, 60 frames)"); the
 * parent, which waits on it, shows a phase that lasts longer than a second by that name (on a terminal, or
 * with -v). Writes one line to hz_bake_phase_fd (the parent's pipe; -1: nowhere). */
extern int hz_bake_phase_fd;
void hz_bake_phase(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Formats err (like hz_error_set, but with the full printf language) and returns code. */
hz_status_t hz_bake_err(hz_error_t *err, hz_status_t code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
double hz_bake_now(void);
/* A number for a message: %g, but "inf", "-inf" and "nan" (never "-nan") where it is not finite. */
const char *hz_bake_num(char *buf, size_t cap, double v);

/* ---- files ---- */

/* Reads a whole file (NUL-terminated for text use; *size excludes the NUL). */
hz_status_t hz_bake_read_file(const char *path, uint8_t **data, size_t *size, hz_error_t *err);
/* Reads and inflates a gzip file; a truncated or corrupt stream is an HZ_E_FORMAT error. */
hz_status_t hz_bake_read_gzip(const char *path, uint8_t **data, size_t *size, hz_error_t *err);
int hz_bake_file_exists(const char *path);
/* The output is never an input. hz_bake_guard_output(out) notes the output's identity (when it exists) before the
 * import; every reader then asks hz_bake_input_ok(path) before opening a file: false (and the first such path
 * kept for hz_bake_input_clash()) when path is the output itself, also through another name or a link. The
 * readers here (read_file, read_gzip) return HZ_E_INVALID_ARG for it. */
void hz_bake_guard_output(const char *out);
int hz_bake_input_ok(const char *path);
const char *hz_bake_input_clash(void); /* "" when none */
/* Ends with suffix, ignoring ASCII case. */
int hz_bake_ends_with(const char *s, const char *suffix);
/* Directory part of path ("." when none), written to out. */
void hz_bake_dirname(const char *path, char *out, size_t size);
/* Last path component. */
const char *hz_bake_basename(const char *path);
/* Resolves a file referenced by a model (texture, .bin): relative to dir; backslashes become slashes; when the
 * exact name does not exist, a case-insensitive match in the same directory is accepted (models made on
 * Windows often disagree with their files' case). Returns 1 and the path in out when found. */
int hz_bake_resolve(const char *dir, const char *ref, char *out, size_t size);
/* Copies src into dst[size], truncating (always NUL-terminated). */
void hz_bake_strcpy(char *dst, size_t size, const char *src);
/* Copies a name into a NUL-padded .hzb name field (truncated to 31 bytes on a UTF-8 boundary). */
void hz_bake_set_name(uint8_t dst[HZ_HZB_NAME_BYTES], const char *name);

/* ---- the scene being built ---- */

typedef struct hz_bake_material {
    hz_hzb_material_t m;
    char name[256];
    float source_color[3]; /* the model's own colour, used when a texture is missing */
} hz_bake_material_t;

typedef struct hz_bake_texture {
    hz_hzb_texture_t t;
    char path[8192];
    int alpha_from_luma; /* an alpha map without an alpha channel: its grey value is the alpha */
} hz_bake_texture_t;

typedef struct hz_bake_object {
    hz_hzb_object_t o;
    char name[256];      /* node name (or mesh name when the node has none) */
    char mesh_name[256]; /* the source mesh's name; sidecar sections match either */
    int has_normals;     /* the importer supplied normals for every vertex */
} hz_bake_object_t;

typedef struct hz_bake_scene {
    hz_bake_vec_t pos;       /* float[4] */
    hz_bake_vec_t nrm;       /* float[4] (zero for objects without normals until hz_bake_scene_finish fills them) */
    hz_bake_vec_t uv;        /* float[2] */
    hz_bake_vec_t tri;       /* uint32[3] */
    hz_bake_vec_t info;      /* uint32: material | object << 16 */
    hz_bake_vec_t mats;      /* hz_bake_material_t */
    hz_bake_vec_t texs;      /* hz_bake_texture_t */
    hz_bake_vec_t texels;    /* uint8[4] */
    hz_bake_vec_t objs;      /* hz_bake_object_t */
    hz_bake_vec_t rkeys;     /* hz_hzb_rigid_key_t */
    hz_bake_vec_t vkeys;     /* float[4] */
    hz_bake_vec_t vkey_nrm;  /* float[4] */
    hz_bake_vec_t lights;    /* hz_hzb_light_t */
    hz_bake_vec_t cams;      /* hz_hzb_camera_key_t */
    hz_bake_vec_t joints;    /* hz_hzb_joint_t (runtime skinning) */
    hz_bake_vec_t joint_src; /* const void *: the source node of each joint (shared by every mesh it skins) */
    hz_bake_vec_t binds;     /* hz_hzb_skin_bind_t */
    hz_bake_vec_t weights;   /* hz_hzb_skin_weight_t, indexed by vertex (may be shorter than pos: zero-padded) */
    int any_uv;              /* some object has UVs */
    float anim_duration;     /* longest source animation in seconds (0 if none) */
    uint32_t extra_features; /* HZ_FEAT_INSTANCING */
    char model[4096];        /* the model's path, for messages */
} hz_bake_scene_t;

void hz_bake_scene_init(hz_bake_scene_t *s, const char *model);
void hz_bake_scene_free(hz_bake_scene_t *s);

/* Starts an object at the current ends of the vertex and triangle arrays; returns its index. */
uint32_t hz_bake_object_begin(hz_bake_scene_t *s, const char *name, const char *mesh_name);
/* Appends n vertices (zeroed) to the current object; returns the index of the first. */
uint32_t hz_bake_add_vertices(hz_bake_scene_t *s, uint32_t n);
/* Appends a triangle of the current object (indices are absolute) with material mat. */
void hz_bake_add_triangle(hz_bake_scene_t *s, uint32_t a, uint32_t b, uint32_t c, uint32_t mat);
/* Closes the current object. weld != 0 merges vertices with identical position, normal and UV (OBJ and
 * unindexed sources repeat them per face); triangle order is kept. Returns HZ_E_RANGE when the object has a
 * non-finite position, normal or UV (the message names the model, object and vertex). */
hz_status_t hz_bake_object_end(hz_bake_scene_t *s, int has_normals, int weld, hz_error_t *err);

/* Texture lookup/decode with de-duplication by (path, alpha_from_luma). Returns the texture index, or -1
 * after a warning naming the file and the reason (missing or undecodable): the caller falls back to the
 * material's colour. max_size limits the stored level 0 (coarser levels of the full chain are kept). */
int hz_bake_texture_get(hz_bake_scene_t *s, const char *path, int alpha_from_luma, uint32_t max_size,
                        const char *material);
/* Decodes an image held in memory (an embedded glTF texture); same contract as hz_bake_texture_get. */
int hz_bake_texture_from_memory(hz_bake_scene_t *s, const char *key, const uint8_t *data, size_t size,
                                int alpha_from_luma, uint32_t max_size, const char *material);

#endif /* HZ_BAKE_H */
