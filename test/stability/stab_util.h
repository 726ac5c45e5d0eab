/*
 * stab_util.h — what the stability cases share: a scene builder that writes a .hzb image in memory and loads
 * it through the validating loader, a one-thread renderer harness that checks every output for non-finite
 * values, native accel builds over plain arrays, an independent double-precision ray/triangle oracle, and a
 * comparison of every traversal kernel and packet width against the scalar reference.
 *
 * Contract: everything comes from the board's pools (hz_pools_get) or from malloc in the test; nothing is
 * released (each case runs in its own process). Functions that can fail return an hz_status_t with err set.
 */
#ifndef HZ_STAB_UTIL_H
#define HZ_STAB_UTIL_H

#include <stdbool.h>
#include <stdint.h>

#include "hz/accel.h"
#include "hz/hzb.h"
#include "hz/posekeys.h"
#include "hz/render.h"
#include "hz/scene.h"
#include "pools.h"
#include "stab.h"

/* ---- scene builder ---- */
typedef struct su_scene {
    float *pos;                    /* 4 per vertex */
    uint32_t nv, cap_v;
    uint32_t *tri, *info;
    uint32_t nt, cap_t;
    hz_hzb_material_t mat[16];
    uint32_t nmat;
    hz_hzb_object_t obj[64];
    uint32_t nobj;
    hz_hzb_light_t light[4];
    uint32_t nlight;
    hz_hzb_camera_key_t cam[16];
    uint32_t ncam;
    hz_hzb_rigid_key_t rkey[16];
    uint32_t nrkey;
    float *uv;                     /* 2 per vertex (0, 0 unless su_uv sets them); written when a texture exists */
    uint32_t cap_uv;
    hz_hzb_texture_t tex[4];
    uint32_t ntex;
    uint8_t *texels;               /* RGBA8, every texture's levels in order */
    uint32_t ntexel, cap_texel;
    float *vkeys;                  /* 4 per entry */
    uint32_t nvkeys, cap_vkeys;
    float duration, background[3], ambient[3], fov_y;
    uint32_t camera_flags;
    uint32_t obj_first_t, obj_first_v; /* of the object being built */
} su_scene_t;

void su_begin(su_scene_t *b);
/* A diffuse material (alpha mode HZ_ALPHA_OPAQUE unless set by su_material_alpha). Returns its index. */
uint32_t su_material(su_scene_t *b, float r, float g, float bl);
uint32_t su_material_alpha(su_scene_t *b, float r, float g, float bl, float alpha, uint32_t mode);
uint32_t su_vertex(su_scene_t *b, float x, float y, float z);
/* Texture coordinates of vertex v. */
void su_uv(su_scene_t *b, uint32_t v, float u, float t);
/* A texture of `levels` levels from level 0's w x h RGBA8 texels (sRGB colour): each further level is the box
 * average of the one before (floor halving, as the format asks). Returns its index for a material's
 * base_texture or alpha_texture. */
uint32_t su_texture(su_scene_t *b, const uint8_t *rgba, uint32_t w, uint32_t h, uint32_t levels);
void su_tri(su_scene_t *b, uint32_t v0, uint32_t v1, uint32_t v2, uint32_t mat);
/* Quad p0 p1 p2 p3 (two triangles, new vertices). */
void su_quad(su_scene_t *b, const float p0[3], const float p1[3], const float p2[3], const float p3[3],
             uint32_t mat);
/* Ends the object made of the vertices and triangles added since the last su_object (static: motion NONE).
 * Returns the object so the caller can set motion fields. */
hz_hzb_object_t *su_object(su_scene_t *b);
void su_light(su_scene_t *b, float x, float y, float z, float power);
void su_camera(su_scene_t *b, float t, const float eye[3], const float target[3], float fov_y);
/* Appends a mesh (float4 positions scaled and offset, indices) to the object being built. */
void su_mesh(su_scene_t *b, const float *pos, uint32_t nv, const uint32_t *tri, uint32_t nt, uint32_t mat,
             float scale, const float offset[3]);
/* A test room at scale s: floor and back wall (object 0), a sphere of radius s at height 1.2 s (object 1), one
 * light. The caller adds the camera. */
void su_room(su_scene_t *b, float s);
/* A lit wall behind (object 0, z = -3) and a quad of half-size `size` in front (object 1, the caller sets its
 * motion), a light and a camera at z = 6: the motion stages' scene. */
hz_hzb_object_t *su_wall_and_quad(su_scene_t *b, float size);
/* A lit opaque wall (z = -1) and, when layer_mode >= 0, a quad in front of it (z = 0) with that alpha mode and
 * alpha; camera at z = 4: the transparency stages' scene. */
void su_wall_layer(su_scene_t *b, int layer_mode, float alpha);
/* The .hzb image (64-byte aligned, from pools->scene) and its size. */
hz_status_t su_image(const su_scene_t *b, const void **img, size_t *size, hz_error_t *err);
/* su_image + hz_scene_load with pools->scene. */
hz_status_t su_load(const su_scene_t *b, hz_scene_t *scene, hz_error_t *err);

/* ---- renderer harness (one thread, native accel) ---- */
typedef struct su_render {
    hz_scene_t scene;
    hz_accel_t *accel;
    hz_renderer_t *r;
    hz_render_opts_t opts;
    uint64_t nonfinite_stat, queue_full, layer_cap;
    hz_arena_mark_t marks[4];
    hz_posekeys_t keys;            /* su_render_open_blur: the pose keys of a shutter (opts.keys points here) */
} su_render_t;

hz_status_t su_render_open(su_render_t *s, const su_scene_t *b, const hz_render_opts_t *o, hz_error_t *err);
/* Releases what su_render_open took from the pools. */
void su_render_close(su_render_t *s);
hz_status_t su_render_frame(su_render_t *s, uint64_t index, float t, hz_error_t *err);
/* Motion blur: like su_render_open, but the accel comes from the port's hz_blur_build (native backend, motion
 * BVH `blur`): with o->shutter > 0 on a moving scene it is built over pose keys (s->keys, s->opts.keys). */
hz_status_t su_render_open_blur(su_render_t *s, const su_scene_t *b, const hz_render_opts_t *o,
                                hz_accel_blur_t blur, hz_error_t *err);
/* su_render_frame at a scene time in nanoseconds (the 64-bit clock, hz/scenetime.h). */
hz_status_t su_render_frame_ns(su_render_t *s, uint64_t index, hz_time_ns_t t, hz_error_t *err);
/* Counts non-finite values of the output, the G-buffer's normals and motion vectors (and depth values that
 * are NaN or -inf) into r->nonfinite, and the renderer's own nonfinite counter of the last frame as well. */
void su_render_check(stab_result_t *r, su_render_t *s);

/* Counts non-finite values of an image into r->nonfinite. */
void su_check_image(stab_result_t *r, const hz_image_t *img);

/* ---- accel over arrays ---- */
hz_status_t su_accel(hz_accel_t **a, const float *pos, uint32_t nv, const uint32_t *tri, uint32_t nt,
                     hz_error_t *err);
void su_ray(hz_rayhit_t *rh, double ox, double oy, double oz, double dx, double dy, double dz);

/* Double-precision Moller-Trumbore over every triangle: closest t (or -1 for none), its triangle, and how far
 * the decision is from a tie: the smallest barycentric coordinate of the winner (relative) and the relative
 * gap to the next-closest triangle's t. */
typedef struct su_ref {
    int32_t prim;
    double t, edge_margin, t_gap;
} su_ref_t;
su_ref_t su_ref_intersect(const float *pos, const uint32_t *tri, uint32_t nt, const hz_rayhit_t *rh);

/* Runs rays through the scalar kernel into out, then through every other kernel (single rays and 4-/8-wide
 * packets, coherent and not) and occlusion, failing the case at the first result that differs from the scalar
 * one bit for bit. Counts non-finite t/u/v/ng of hits into r->nonfinite. */
void su_check_kernels(stab_result_t *r, const hz_accel_t *a, const hz_rayhit_t *rays, uint32_t n,
                      hz_rayhit_t *out);

struct hz_rng;
/* Uniform in [0, 1) from the generator. */
double su_unit(struct hz_rng *g);
/* A random unit direction; every 8th (by i) has one zero component, every 16th two. */
void su_random_dir(struct hz_rng *g, uint32_t i, double d[3]);
/* n rays (malloc) from random points within `inner` of c, random directions. */
hz_rayhit_t *su_inside_rays(uint32_t n, const double c[3], double inner, uint64_t seed);
/* Builds a native accel over the arrays and checks rays: su_check_kernels, no non-finite hit, `closed`: every
 * ray hits (0 leaks), clear hits agree with su_ref_intersect in triangle and in t (relative error <= t_bound,
 * recorded as max_error); hits on triangles >= first_bad fail. */
void su_check_mesh(stab_result_t *r, const float *pos, uint32_t nv, const uint32_t *tri, uint32_t nt,
                   const hz_rayhit_t *rays, uint32_t n, bool closed, uint32_t first_bad, double t_bound);

/* Largest |a - b| / max(|b|, floor). */
double su_relerr(double a, double b, double floor_);

#endif
