/*
 * memplan.h — one description of a module's arrays for both its memory plan and its allocation.
 *
 * Contract:
 *  - A module writes one layout function that asks hz_memplan_alloc() for every array it keeps. Run on a plan
 *    made by hz_memplan_count(), the same function only counts (every call returns NULL); run on a plan made by
 *    hz_memplan_take(), it takes the arrays from the arena. The count and the allocation therefore cannot
 *    disagree: a take never needs more than the count said.
 *  - Each request is counted as its size rounded up to the alignment plus one alignment (the worst padding in
 *    front of it), so an arena with `bytes` left (hz_memplan_room: at any alignment of its top) holds the whole
 *    layout.
 *  - Requests are counted in the part set by hz_memplan_part() (for reports that split a plan: display frame,
 *    G-buffer, ...); the parts sum to `bytes`.
 *  - A refused allocation (take) is recorded in `refused` and the arena's own refusal record; later requests
 *    still count, so the caller can report what the whole layout needs.
 */
#ifndef HZ_MEMPLAN_H
#define HZ_MEMPLAN_H

#include <stdbool.h>
#include <stddef.h>

#include "hz/arena.h"

#define HZ_MEMPLAN_PARTS 8
#define HZ_MEMPLAN_ALIGN 64u

typedef struct hz_memplan {
    hz_arena_t *arena;   /* NULL: count only */
    size_t bytes;
    size_t part[HZ_MEMPLAN_PARTS];
    unsigned part_now;
    bool refused;
} hz_memplan_t;

void hz_memplan_count(hz_memplan_t *p);
/* Bytes left in arena a, the figure a counted plan is compared with. */
size_t hz_memplan_room(const hz_arena_t *a);
void hz_memplan_take(hz_memplan_t *p, hz_arena_t *arena);
void hz_memplan_part(hz_memplan_t *p, unsigned part);
/* bytes at HZ_MEMPLAN_ALIGN: NULL when counting or refused. */
void *hz_memplan_alloc(hz_memplan_t *p, size_t bytes);
/* count * size bytes; an overflowing product is refused (and counted as SIZE_MAX). */
void *hz_memplan_array(hz_memplan_t *p, size_t count, size_t size);

#endif
