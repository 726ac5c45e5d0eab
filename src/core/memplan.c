/* Count-or-take memory layouts (see memplan.h). */
#include "memplan.h"

#include "hz/base.h"

static void start(hz_memplan_t *p, hz_arena_t *arena)
{
    hz_memset(p, 0, sizeof *p);
    p->arena = arena;
}

void hz_memplan_count(hz_memplan_t *p)
{
    start(p, NULL);
}

size_t hz_memplan_room(const hz_arena_t *a)
{
    return a->cap - a->used;
}

void hz_memplan_take(hz_memplan_t *p, hz_arena_t *arena)
{
    start(p, arena);
}

void hz_memplan_part(hz_memplan_t *p, unsigned part)
{
    p->part_now = part < HZ_MEMPLAN_PARTS ? part : HZ_MEMPLAN_PARTS - 1;
}

static size_t add_sat(size_t a, size_t b)
{
    return a > (size_t)-1 - b ? (size_t)-1 : a + b;
}

void *hz_memplan_alloc(hz_memplan_t *p, size_t bytes)
{
    const size_t a = HZ_MEMPLAN_ALIGN;
    size_t counted = bytes > (size_t)-1 - 2 * a ? (size_t)-1 : hz_align_up(bytes, a) + a;
    p->bytes = add_sat(p->bytes, counted);
    p->part[p->part_now] = add_sat(p->part[p->part_now], counted);
    if (!p->arena || p->refused)
        return NULL;
    void *m = hz_arena_alloc(p->arena, bytes, a);
    if (!m)
        p->refused = true;
    return m;
}

void *hz_memplan_array(hz_memplan_t *p, size_t count, size_t size)
{
    if (size && count > (size_t)-1 / size) {
        p->bytes = (size_t)-1;
        p->part[p->part_now] = (size_t)-1;
        p->refused = p->refused || p->arena != NULL;
        return NULL;
    }
    return hz_memplan_alloc(p, count * size);
}
