/*
 * hz/arena.h — static-arena (bump) allocator: the only way memory is obtained in src/.
 *
 * Contract:
 *  - The caller provides the buffer (a static array sized by the board) and keeps it alive; the arena never
 *    calls malloc and never frees.
 *  - hz_arena_alloc returns memory aligned to `align` (a power of two; 0 means HZ_ARENA_DEFAULT_ALIGN) or
 *    NULL. A refusal allocates nothing (the arena is unchanged apart from the refusal record) and records the
 *    bytes needed (request + alignment padding) and the bytes available, so the caller can report
 *    "arena 'accel': needs N bytes, has M". Requests never wrap around the address space.
 *  - A zero-size request returns a non-NULL aligned pointer that must not be dereferenced and consumes no
 *    bytes (it is refused only when the alignment padding alone does not fit).
 *  - hz_arena_alloc_array checks count * size for overflow (refused as HZ_E_OVERFLOW).
 *  - Marks: hz_arena_mark() records the fill level; hz_arena_reset(a, m) releases everything allocated after
 *    m. Releasing to a mark above the current level is refused. With HZ_ARENA_POISON the released bytes are
 *    overwritten with 0xA5 so a use-after-reset shows up in tests.
 *  - high_water is the maximum fill level ever reached (for the memory report); only hz_arena_init clears it.
 * Not thread-safe: each thread uses its own arena.
 */
#ifndef HZ_ARENA_H
#define HZ_ARENA_H

#include <stddef.h>
#include <stdint.h>

#include "hz/base.h"
#include "hz/status.h"

#define HZ_ARENA_DEFAULT_ALIGN 16u

typedef struct hz_arena {
    const char *name;   /* for messages, e.g. "scene" */
    uint8_t *base;
    size_t cap;         /* bytes in the buffer */
    size_t used;        /* bytes handed out, including alignment padding */
    size_t high_water;  /* maximum of used since init */
    /* The last refusal (zeroed by init): what was asked for and what was left at that time. */
    hz_status_t last_status;
    size_t last_needed;
    size_t last_available;
} hz_arena_t;

typedef size_t hz_arena_mark_t;

/* Sets up an arena over buf[0..cap). buf may be NULL only when cap == 0 (an arena that refuses everything,
 * used for features a scene leaves out). */
hz_status_t hz_arena_init(hz_arena_t *a, const char *name, void *buf, size_t cap);

void *hz_arena_alloc(hz_arena_t *a, size_t size, size_t align);
void *hz_arena_alloc_array(hz_arena_t *a, size_t count, size_t elem_size, size_t align);

/* Same as the above but the memory is zero-filled. */
void *hz_arena_calloc(hz_arena_t *a, size_t count, size_t elem_size, size_t align);

hz_arena_mark_t hz_arena_mark(const hz_arena_t *a);
hz_status_t hz_arena_reset(hz_arena_t *a, hz_arena_mark_t mark);

/* Bytes still available for a request with the given alignment. */
size_t hz_arena_available(const hz_arena_t *a, size_t align);

/* Fills err with the last refusal of arena a ("arena 'scene': needs N bytes, has M bytes"). */
hz_status_t hz_arena_error(const hz_arena_t *a, hz_error_t *err);

#endif /* HZ_ARENA_H */
