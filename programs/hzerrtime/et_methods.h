/*
 * et_methods.h — what errtime can run: scenes, and per scene the methods and the reference. This table is the
 * one place later issues extend (a renderer method is a row in hz_et_render_methods, et_render.c; a scene is a
 * row here).
 *
 * Contract: `open` fills in the sequence's scene_data, scene_hash, camera and settings (size, frame count,
 * warm-up and refresh rate are already set from the command line or the entry's defaults) from the entry's
 * `file` and the environment (scene folder, threads); it may allocate from the arena, which lives until the
 * scene's run is over. `close` (may be NULL) gives back what open took, after the scene's run; errtime opens
 * one scene at a time. `methods` run in table order; `reference` renders the cached reference sequence.
 * width/height/frames/warmup/refresh_hz are the scene's defaults for the report (`make report` runs every scene
 * at these); 0 means the command line's value. The `@240` entries run the display-rate comparison of temporally
 * dense rendering (seed 001) on a 240 Hz display.
 */
#ifndef HZ_ERRTIME_METHODS_H
#define HZ_ERRTIME_METHODS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "errtime.h"
#include "et_render.h"

typedef struct hz_et_scene hz_et_scene_t;
struct hz_et_scene {
    const char *name;  /* --scene value */
    const char *about; /* one line for --list */
    const char *file;  /* what open loads: a .hzb file name in the scene folder, "builtin", or NULL */
    hz_status_t (*open)(const hz_et_scene_t *scene, const hz_et_env_t *env, hz_et_sequence_t *seq,
                        hz_arena_t *arena, hz_error_t *err);
    void (*close)(void);
    const hz_et_method_t *methods;
    size_t method_count;
    const hz_et_method_t *reference;
    uint32_t width, height, frames, warmup; /* report defaults; --size/--frames/--warmup win */
    uint32_t refresh_hz;                    /* display refresh of the sequence; 0: --refresh (default 60) */
    uint32_t still_frames; /* > 0: also the still-view stability figure of every method (et_stability.h) */
};

extern const hz_et_scene_t hz_et_scenes[];
extern const size_t hz_et_scene_count;

/* The entry named `name`, or NULL. */
const hz_et_scene_t *hz_et_scene_find(const char *name);

/* Any baked scene file (`hzerrtime --scene PATH.hzb`): whether a --scene item names one (it ends in .hzb), and
 * its entry: the renderer's standard methods (full-frame 1/4/9/16 spp, TAA, adaptive) against the 256-spp
 * reference, named after the file (folder and extension dropped, into name[size]), with the command line's size
 * and length; open loads it from the path as given (relative to the working directory), not from --scenes. */
bool hz_et_scene_is_file(const char *item, size_t len);
void hz_et_scene_from_file(const char *path, char *name, size_t size, hz_et_scene_t *out);

#endif
