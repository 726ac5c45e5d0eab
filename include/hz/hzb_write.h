/*
 * hz/hzb_write.h — serialises scene content into a .hzb image (see hz/hzb.h): used by the baker and by the
 * built-in scene, which goes through the same validating loader as a file would.
 *
 * Contract: the caller fills an hz_hzb_source_t with pointers and counts (NULL pointers with zero counts for
 * absent sections). hz_hzb_write_size() returns the exact image size, or 0 if it would overflow size_t.
 * hz_hzb_write() lays out header, section table and 64-byte aligned sections into out[0..cap), computes the
 * feature mask from the content (plus src->extra_features for what the content cannot show, i.e.
 * HZ_FEAT_INSTANCING), the bounds at t = 0 and every CRC, and writes nothing beyond cap. It does not validate
 * the content: run hz_scene_plan() on the result (the baker does) to get the loader's verdict.
 */
#ifndef HZ_HZB_WRITE_H
#define HZ_HZB_WRITE_H

#include <stddef.h>

#include "hz/hzb.h"
#include "hz/status.h"

typedef struct hz_hzb_source {
    const char *name;
    uint32_t vertex_count;
    const float *positions;           /* 4 floats per vertex */
    const float *normals;             /* 4 floats per vertex, or NULL */
    const float *uvs;                 /* 2 floats per vertex, or NULL */
    uint32_t triangle_count;
    const uint32_t *triangles;        /* 3 per triangle */
    const uint32_t *tri_info;         /* material | object << 16 */
    uint32_t material_count;
    const hz_hzb_material_t *materials;
    uint32_t texture_count;
    const hz_hzb_texture_t *textures;
    uint32_t texel_count;
    const uint8_t *texels;            /* 4 bytes per texel */
    uint32_t object_count;
    const hz_hzb_object_t *objects;
    uint32_t rigid_key_count;
    const hz_hzb_rigid_key_t *rigid_keys;
    uint32_t vertex_key_count;        /* float4 entries */
    const float *vertex_keys;
    const float *vertex_key_normals;  /* same count, or NULL */
    uint32_t light_count;
    const hz_hzb_light_t *lights;
    uint32_t camera_key_count;
    const hz_hzb_camera_key_t *camera_keys;
    uint32_t joint_count;             /* runtime skinning (HZ_MOTION_SKIN objects) */
    const hz_hzb_joint_t *joints;
    uint32_t skin_bind_count;
    const hz_hzb_skin_bind_t *skin_binds;
    const hz_hzb_skin_weight_t *skin_weights; /* vertex_count entries, or NULL when no object is SKIN */
    float duration;
    float background[3];
    float ambient[3];
    float camera_fov_y;
    uint32_t camera_flags;
    uint32_t extra_features;
} hz_hzb_source_t;

size_t hz_hzb_write_size(const hz_hzb_source_t *src);
hz_status_t hz_hzb_write(const hz_hzb_source_t *src, void *out, size_t cap, size_t *written, hz_error_t *err);

#endif
