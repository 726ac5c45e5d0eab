/*
 * hz/hzb.h — the baked scene format (.hzb), version 2, field by field.
 *
 * A firmware-like renderer never parses text formats: scenes are imported on the host (programs/hzbake) and stored
 * in this compact binary form, which the core validates completely (src/scene/load.c) before using it in place.
 *
 * Layout (all integers and floats little-endian, IEEE-754 binary32 floats):
 *
 *   offset 0     hz_hzb_header_t (256 bytes)
 *   offset 256   section table: header.section_count x hz_hzb_section_t (32 bytes each)
 *   then         sections, each starting at a multiple of HZ_HZB_ALIGN (64) bytes, zero padding between them
 *
 * Every section is an array of fixed-size elements (elem_bytes); its size is a whole number of elements. Each
 * section carries a CRC-32 (IEEE 802.3, as zlib's crc32) of its bytes; the header carries a CRC-32 of its own
 * first 252 bytes. A section id appears at most once; unknown ids are an error. Version 1 files (no skinning
 * sections, header words 164..251 zero) still load; a version 1 file with a version 2 section is refused. A buffer holding a
 * whole .hzb file at a 64-byte aligned address gives 16-byte aligned float4 arrays for direct SIMD loads.
 *
 * Geometry is flattened into world space at bake time: objects are ranges of triangles and vertices (instanced
 * meshes in the source are expanded, and the INSTANCING feature bit records it). Every triangle of an object
 * references only that object's vertices, so animating an object rewrites only its own vertex range.
 *
 * Animation (time t in seconds; header.duration > 0 makes all motion loop with that period):
 *  - HZ_MOTION_RIGID: the object's vertices (POSITIONS, in the object's own frame) are transformed by
 *    T(t) * R(t) * S(t) interpolated from its rigid keys (translation and scale linear, rotation normalised
 *    lerp on the shorter arc), clamped to the first/last key outside their range.
 *  - HZ_MOTION_VERTEX: per-vertex keys sampled at key_rate frames per second (VERTEX_KEYS, and optionally
 *    VERTEX_KEY_NORMALS), linearly interpolated between frames, wrapping around the key range.
 *  - HZ_MOTION_SPIN: rotation by params[6] radians/s about the axis params[3..5] through params[0..2].
 *  - HZ_MOTION_OSCILLATE: translation by params[0..2] * sin(2 pi params[3] t + params[4]).
 *  - HZ_MOTION_SWAY: smooth per-vertex deformation (strands swaying, seed 002's moving hairball): a vertex at
 *    rest position p moves to p + a h^2 sin(w t + pi (u.x + u.y + u.z)), with centre c = params[0..2],
 *    a = params[3..5], w = params[6] (rad/s), r0 = params[7] >= 0, d = p - c, h = max(0, |d| - r0) (height above
 *    the root sphere) and u = d / |d| (0 at c). Normals keep their rest values (thin strands bend slowly).
 *  - HZ_MOTION_SKIN: linear-blend skinning at run time (version 2). The object's POSITIONS/NORMALS are the
 *    mesh in its bind pose; key_first/key_count index SKIN_BINDS (the object's joints, key_count >= 1);
 *    SKIN_WEIGHTS holds, per vertex, up to 4 of those binds with unorm16 weights summing to exactly 65535.
 *    A bind names a JOINTS entry (its world transform J(t) as rigid keys in RIGID_KEYS, interpolated like a
 *    RIGID object's) and the bind's inverse bind matrix B; the vertex moves to sum_k w_k J_k(t) B_k p and its
 *    normal to normalise(sum_k w_k J_k(t) B_k n) (the blended matrix, not its inverse transpose). Joints are
 *    shared by every object skinned to them, so a skeleton's keys are stored once however many meshes use it.
 *    Without a loop (duration 0) the pose holds after each joint's last key, as for RIGID.
 *  For rigid, spin and oscillate, POSITIONS are world positions at t = 0 (spin/oscillate) or in object space (rigid).
 *
 * Texture coordinates (UVS): (0, 0) is the top-left corner of a texture's level 0, u grows to the right and v
 * downwards (glTF's convention; programs/hzbake flips OBJ's); texel (x, y) of a w x h level covers u in [x/w, (x+1)/w)
 * and v in [y/h, (y+1)/h); coordinates outside [0, 1) repeat. Texel rows are stored top row first.
 */
#ifndef HZ_HZB_H
#define HZ_HZB_H

#include <stdint.h>

#include "hz/base.h"

#define HZ_HZB_MAGIC "HZB\0\r\n\x1a\n" /* 8 bytes; catches text-mode transfers like PNG's signature */
#define HZ_HZB_VERSION 2u
#define HZ_HZB_VERSION_MIN 1u /* oldest version the loader reads */
#define HZ_HZB_ALIGN 64u
#define HZ_HZB_NAME_BYTES 32u /* names are NUL-padded UTF-8, always NUL-terminated within 32 bytes */

/* Feature mask: what the scene needs. The loader recomputes it from the content and refuses a file whose mask
 * disagrees, so the mask can be trusted to leave stages and memory out. */
enum hz_feature {
    HZ_FEAT_MOTION = 1u << 0,      /* some object moves (rigid, vertex keys, spin, oscillate) */
    HZ_FEAT_BLEND = 1u << 1,       /* some material is alpha-blended (transparency) */
    HZ_FEAT_CUTOUT = 1u << 2,      /* some material is alpha-tested (MASK) */
    HZ_FEAT_MIRROR = 1u << 3,      /* some material has mirror reflectance > 0 */
    HZ_FEAT_TEXTURES = 1u << 4,    /* some material samples a texture */
    HZ_FEAT_INSTANCING = 1u << 5,  /* the source instanced meshes (expanded at bake time) */
    HZ_FEAT_CAMERA_PATH = 1u << 6, /* more than one camera key */
    HZ_FEAT_SKINNING = 1u << 7,    /* some object uses per-vertex keys or runtime skinning */
    HZ_FEAT_NORMALS = 1u << 8,     /* per-vertex shading normals present */
};
#define HZ_FEAT_ALL 0x1ffu

enum hz_hzb_section_id {
    HZ_SEC_POSITIONS = 1,          /* float[4] per vertex: x, y, z, 0 */
    HZ_SEC_NORMALS = 2,            /* float[4] per vertex: unit x, y, z, 0 (optional) */
    HZ_SEC_UVS = 3,                /* float[2] per vertex (optional; required if a material has a texture) */
    HZ_SEC_TRIANGLES = 4,          /* uint32[3] per triangle: vertex indices */
    HZ_SEC_TRI_INFO = 5,           /* uint32 per triangle: material index (bits 0-15) | object index << 16 */
    HZ_SEC_MATERIALS = 6,          /* hz_hzb_material_t */
    HZ_SEC_TEXTURES = 7,           /* hz_hzb_texture_t */
    HZ_SEC_TEXELS = 8,             /* uint8[4] RGBA8 texels of every texture level (sRGB colour, linear alpha) */
    HZ_SEC_OBJECTS = 9,            /* hz_hzb_object_t */
    HZ_SEC_RIGID_KEYS = 10,        /* hz_hzb_rigid_key_t */
    HZ_SEC_VERTEX_KEYS = 11,       /* float[4] per keyed vertex per frame (positions) */
    HZ_SEC_VERTEX_KEY_NORMALS = 12,/* float[4] per keyed vertex per frame (normals; optional) */
    HZ_SEC_LIGHTS = 13,            /* hz_hzb_light_t */
    HZ_SEC_CAMERA_KEYS = 14,       /* hz_hzb_camera_key_t */
    HZ_SEC_JOINTS = 15,            /* hz_hzb_joint_t (version 2) */
    HZ_SEC_SKIN_BINDS = 16,        /* hz_hzb_skin_bind_t (version 2) */
    HZ_SEC_SKIN_WEIGHTS = 17,      /* hz_hzb_skin_weight_t per vertex (version 2; all zero outside SKIN objects) */
    HZ_SEC_ID_MAX = 17
};

typedef struct hz_hzb_header {
    uint8_t magic[8];           /*   0: HZ_HZB_MAGIC */
    uint32_t version;           /*   8: HZ_HZB_VERSION */
    uint32_t header_bytes;      /*  12: sizeof(hz_hzb_header_t) = 256 */
    uint64_t file_bytes;        /*  16: total file size; a buffer of another size is refused */
    uint32_t section_count;     /*  24: entries in the section table (<= HZ_SEC_ID_MAX) */
    uint32_t features;          /*  28: enum hz_feature bits */
    uint32_t vertex_count;      /*  32 */
    uint32_t triangle_count;    /*  36 */
    uint32_t material_count;    /*  40: >= 1 */
    uint32_t texture_count;     /*  44 */
    uint32_t object_count;      /*  48: >= 1, <= 65536 */
    uint32_t light_count;       /*  52 */
    uint32_t camera_key_count;  /*  56 */
    uint32_t rigid_key_count;   /*  60 */
    uint32_t vertex_key_count;  /*  64: float4 entries in VERTEX_KEYS */
    uint32_t texel_count;       /*  68: RGBA8 texels in TEXELS */
    float bounds_min[3];        /*  72: of POSITIONS at t = 0 after object transforms */
    float bounds_max[3];        /*  84 */
    float duration;             /*  96: animation loop period in seconds; 0 = no loop */
    float background[3];        /* 100: linear RGB radiance of rays that leave the scene */
    float ambient[3];           /* 112: linear RGB ambient term added to diffuse shading */
    float camera_fov_y;         /* 124: default vertical field of view (radians) when no camera keys */
    uint32_t camera_flags;      /* 128: bit 0: camera path loops with duration */
    uint8_t name[HZ_HZB_NAME_BYTES]; /* 132: scene name */
    uint32_t joint_count;       /* 164: entries in JOINTS (version 2; 0 in version 1) */
    uint32_t skin_bind_count;   /* 168: entries in SKIN_BINDS (version 2; 0 in version 1) */
    uint32_t reserved[20];      /* 172: zero */
    uint32_t header_crc;        /* 252: CRC-32 of bytes 0..251 */
} hz_hzb_header_t;

typedef struct hz_hzb_section {
    uint32_t id;                /* enum hz_hzb_section_id */
    uint32_t elem_bytes;        /* must equal the id's element size */
    uint64_t offset;            /* from the start of the file; multiple of HZ_HZB_ALIGN */
    uint64_t size;              /* bytes; a multiple of elem_bytes */
    uint32_t crc32;             /* of the section's bytes */
    uint32_t reserved;          /* zero */
} hz_hzb_section_t;

enum hz_alpha_mode {
    HZ_ALPHA_OPAQUE = 0,        /* alpha ignored */
    HZ_ALPHA_MASK = 1,          /* cutout: a hit counts iff alpha >= alpha_cutoff */
    HZ_ALPHA_BLEND = 2,         /* transparent: composited front to back with opacity alpha */
};

typedef struct hz_hzb_material {
    float base_color[3];        /*  0: linear RGB albedo, multiplied with the base texture */
    float alpha;                /* 12: opacity in [0, 1], multiplied with the alpha texture's A channel */
    float alpha_cutoff;         /* 16: MASK threshold in [0, 1] */
    float mirror;               /* 20: mirror reflectance in [0, 1]; the rest is diffuse */
    uint32_t alpha_mode;        /* 24: enum hz_alpha_mode */
    int32_t base_texture;       /* 28: texture index or -1 */
    int32_t alpha_texture;      /* 32: texture whose A channel scales alpha, or -1 */
    uint32_t flags;             /* 36: reserved, zero */
    uint8_t name[HZ_HZB_NAME_BYTES]; /* 40 */
    uint32_t reserved[6];       /* 72: zero */
} hz_hzb_material_t;            /* 96 bytes */

typedef struct hz_hzb_texture {
    uint32_t width;             /*  0: level 0 size, 1..16384 */
    uint32_t height;            /*  4 */
    uint32_t levels;            /*  8: 1..15, each level halves (floor, min 1) the previous */
    uint32_t flags;             /* 12: bit 0: has alpha < 255 somewhere */
    uint32_t first_texel;       /* 16: index into TEXELS of level 0; levels follow each other */
    uint32_t texel_count;       /* 20: sum over levels of w*h */
    uint8_t name[HZ_HZB_NAME_BYTES]; /* 24 */
    uint32_t reserved[2];       /* 56: zero */
} hz_hzb_texture_t;             /* 64 bytes */

enum hz_motion_kind {
    HZ_MOTION_NONE = 0,
    HZ_MOTION_RIGID = 1,        /* key_first/key_count index RIGID_KEYS */
    HZ_MOTION_VERTEX = 2,       /* key_first: first float4 in VERTEX_KEYS; key_count frames of vertex_count */
    HZ_MOTION_SPIN = 3,
    HZ_MOTION_OSCILLATE = 4,
    HZ_MOTION_SWAY = 5,         /* params: centre, amplitude, angular frequency, root radius (see the top) */
    HZ_MOTION_SKIN = 6,         /* key_first/key_count index SKIN_BINDS; weights in SKIN_WEIGHTS (version 2) */
};

typedef struct hz_hzb_object {
    uint8_t name[HZ_HZB_NAME_BYTES]; /*  0 */
    uint32_t first_triangle;    /* 32 */
    uint32_t triangle_count;    /* 36 */
    uint32_t first_vertex;      /* 40 */
    uint32_t vertex_count;      /* 44 */
    uint32_t motion;            /* 48: enum hz_motion_kind */
    uint32_t key_first;         /* 52 */
    uint32_t key_count;         /* 56 */
    float key_rate;             /* 60: vertex keys per second (HZ_MOTION_VERTEX) */
    float params[8];            /* 64: spin / oscillate parameters (see the top comment) */
} hz_hzb_object_t;              /* 96 bytes */

typedef struct hz_hzb_rigid_key {
    float time;                 /*  0: seconds, strictly increasing within an object */
    float translation[3];       /*  4 */
    float rotation[4];          /* 16: unit quaternion x, y, z, w */
    float scale[3];             /* 32 */
    float reserved;             /* 44: zero */
} hz_hzb_rigid_key_t;           /* 48 bytes */

enum hz_light_falloff { HZ_FALLOFF_INV_SQUARE = 0, HZ_FALLOFF_NONE = 1 };

typedef struct hz_hzb_light {
    float position[3];          /*  0 */
    float color[3];             /* 12: linear RGB; radiant intensity for inverse-square falloff */
    uint32_t falloff;           /* 24: enum hz_light_falloff */
    uint32_t reserved;          /* 28: zero */
} hz_hzb_light_t;               /* 32 bytes */

typedef struct hz_hzb_camera_key {
    float time;                 /*  0: seconds, strictly increasing */
    float eye[3];               /*  4 */
    float target[3];            /* 16 */
    float up[3];                /* 28 */
    float fov_y;                /* 40: radians, in (0, pi) */
    float reserved;             /* 44: zero */
} hz_hzb_camera_key_t;          /* 48 bytes: eye/target are interpolated by Catmull-Rom, fov linearly */

typedef struct hz_hzb_joint {
    uint8_t name[HZ_HZB_NAME_BYTES]; /*  0: the skeleton node's name */
    uint32_t key_first;         /* 32: its world transform: key_count rigid keys from key_first in RIGID_KEYS */
    uint32_t key_count;         /* 36: >= 1 */
    uint32_t reserved[2];       /* 40: zero */
} hz_hzb_joint_t;               /* 48 bytes */

typedef struct hz_hzb_skin_bind {
    uint32_t joint;             /*  0: index into JOINTS */
    uint32_t reserved[3];       /*  4: zero */
    float inv_bind[12];         /* 16: inverse bind matrix, column-major 3x4 (columns x, y, z, translation; the
                                 *     bottom row is 0 0 0 1) */
} hz_hzb_skin_bind_t;           /* 64 bytes */

typedef struct hz_hzb_skin_weight {
    uint16_t bind[4];           /* 0: indices into the object's binds (< its key_count) */
    uint16_t weight[4];         /* 8: unorm16 weights, summing to exactly 65535 in a SKIN object */
} hz_hzb_skin_weight_t;         /* 16 bytes */

HZ_STATIC_ASSERT(sizeof(hz_hzb_header_t) == 256, hzb_header_size);
HZ_STATIC_ASSERT(sizeof(hz_hzb_joint_t) == 48, hzb_joint_size);
HZ_STATIC_ASSERT(sizeof(hz_hzb_skin_bind_t) == 64, hzb_skin_bind_size);
HZ_STATIC_ASSERT(sizeof(hz_hzb_skin_weight_t) == 16, hzb_skin_weight_size);
HZ_STATIC_ASSERT(sizeof(hz_hzb_section_t) == 32, hzb_section_size);
HZ_STATIC_ASSERT(sizeof(hz_hzb_material_t) == 96, hzb_material_size);
HZ_STATIC_ASSERT(sizeof(hz_hzb_texture_t) == 64, hzb_texture_size);
HZ_STATIC_ASSERT(sizeof(hz_hzb_object_t) == 96, hzb_object_size);
HZ_STATIC_ASSERT(sizeof(hz_hzb_rigid_key_t) == 48, hzb_rigid_key_size);
HZ_STATIC_ASSERT(sizeof(hz_hzb_light_t) == 32, hzb_light_size);
HZ_STATIC_ASSERT(sizeof(hz_hzb_camera_key_t) == 48, hzb_camera_key_size);

/* Element size of a section id; 0 for unknown ids. */
uint32_t hz_hzb_elem_bytes(uint32_t section_id);
/* Name of a section id for messages ("triangles"); "unknown" for unknown ids. */
const char *hz_hzb_section_name(uint32_t section_id);

#endif /* HZ_HZB_H */
