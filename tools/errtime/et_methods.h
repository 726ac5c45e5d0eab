/*
 * et_methods.h — what errtime can run: scenes, and per scene the methods and the reference. This table is the
 * one place later issues extend (a renderer method is a row in a method array; a scene is a row here).
 *
 * Contract: `open` fills in the sequence's scene_data, scene_hash, camera and settings (size, frame count,
 * warm-up and refresh rate are already set from the command line) and may allocate from the arena, which lives
 * until errtime exits. `methods` run in table order; `reference` renders the cached reference sequence.
 */
#ifndef HZ_ERRTIME_METHODS_H
#define HZ_ERRTIME_METHODS_H

#include <stddef.h>
#include <stdint.h>

#include "errtime.h"

typedef struct hz_et_scene {
    const char *name;  /* --scene value */
    const char *about; /* one line for --list */
    hz_status_t (*open)(hz_et_sequence_t *seq, hz_arena_t *arena, hz_error_t *err);
    const hz_et_method_t *methods;
    size_t method_count;
    const hz_et_method_t *reference;
    uint32_t width, height, frames; /* defaults for the report (0: the command line's); --size/--frames win */
} hz_et_scene_t;

extern const hz_et_scene_t hz_et_scenes[];
extern const size_t hz_et_scene_count;

#endif
