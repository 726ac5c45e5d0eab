/*
 * programs/hzbake/scene.h — from the baker's in-memory scene to a .hzb image, and the importers that fill it.
 *
 * Contract:
 *  - hz_bake_import_assimp() reads OBJ (+ .mtl), PLY (also .ply.gz) and glTF/glb through assimp;
 *    hz_bake_import_furball() reads Embree's RoundLineSegments XML (+ .bin or .bin.gz) and tessellates the
 *    strands into tubes. Both
 *    append objects, materials and textures to the scene and name the file and the reason in every error:
 *    HZ_E_FORMAT for a malformed model, HZ_E_UNSUPPORTED for content the baker does not handle, HZ_E_RANGE for
 *    non-finite values, HZ_E_IO for missing files. Missing textures are warnings (the material keeps its colour).
 *  - hz_bake_scene_finish() applies the sidecar (material overrides, object motion, lights, camera path, settings),
 *    repairs missing normals and serialises the scene with hz_hzb_write() into img->data (64-byte aligned,
 *    malloc'd; free() it). It does not validate: the caller runs hz_scene_plan() on the image.
 */
#ifndef HZ_BAKE_SCENE_H
#define HZ_BAKE_SCENE_H

#include "bake.h"
#include "sidecar.h"

typedef struct hz_bake_image {
    void *data;
    size_t size;
    uint8_t name[HZ_HZB_NAME_BYTES];
} hz_bake_image_t;

hz_status_t hz_bake_import_assimp(hz_bake_scene_t *s, const char *path, const hz_bake_sidecar_t *sc, hz_error_t *err);
hz_status_t hz_bake_import_furball(hz_bake_scene_t *s, const char *path, const hz_bake_sidecar_t *sc, hz_error_t *err);
hz_status_t hz_bake_scene_finish(hz_bake_scene_t *s, hz_bake_sidecar_t *sc, hz_bake_image_t *img, hz_error_t *err);

#endif /* HZ_BAKE_SCENE_H */
