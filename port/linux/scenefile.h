/*
 * scenefile.h — scenes for the Linux port: "builtin" builds the built-in scene, anything else is a .hzb path
 * read into the board's scene arena. Either way the image goes through hz_scene_load's full validation.
 *
 * Contract: on success `scene` is loaded and lives in pools->scene (image + animation state); pools->frame is
 * used as scratch for the built-in scene and left as it was found. Errors are prefixed with the file name (or
 * "builtin") and keep the loader's status code: HZ_E_IO for unreadable files, HZ_E_NO_MEMORY when the file or
 * its state does not fit the arena (naming the arena and both byte counts), the format codes otherwise.
 */
#ifndef HZ_PORT_SCENEFILE_H
#define HZ_PORT_SCENEFILE_H

#include "hz/scene.h"
#include "pools.h"

hz_status_t hz_scenefile_open(const char *name, hz_pools_t *pools, hz_scene_t *scene, hz_error_t *err);

/* Reads a whole file into `arena` (64-byte aligned); refuses files larger than the arena's free space. */
hz_status_t hz_scenefile_read(const char *path, hz_arena_t *arena, const void **data, size_t *size,
                              hz_error_t *err);

#endif
