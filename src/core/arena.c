/* Static-arena bump allocator (see hz/arena.h). */
#include "hz/arena.h"

#include "hz/config.h"
#include "hz/fmt.h"

static int is_pow2(size_t x)
{
    return x != 0 && (x & (x - 1)) == 0;
}

static void refuse(hz_arena_t *a, hz_status_t why, size_t needed, size_t available)
{
    a->last_status = why;
    a->last_needed = needed;
    a->last_available = available;
}

/* Base of buffer-less arenas, so that even they hand out non-NULL pointers for zero-size requests. */
static uint8_t empty_base[64] __attribute__((aligned(64)));

hz_status_t hz_arena_init(hz_arena_t *a, const char *name, void *buf, size_t cap)
{
    if (!a)
        return HZ_E_INVALID_ARG;
    if (!buf && cap)
        return HZ_E_INVALID_ARG;
    /* The end pointer must not wrap, or padding arithmetic below would lie. */
    if (buf && (uintptr_t)buf + cap < (uintptr_t)buf)
        return HZ_E_INVALID_ARG;
    a->name = name ? name : "(unnamed)";
    a->base = buf ? (uint8_t *)buf : empty_base;
    a->cap = cap;
    a->used = 0;
    a->high_water = 0;
    a->last_status = HZ_OK;
    a->last_needed = 0;
    a->last_available = 0;
    return HZ_OK;
}

/* Padding that brings the current top to `align`; align is a power of two. */
static size_t padding_for(const hz_arena_t *a, size_t align)
{
    uintptr_t top = (uintptr_t)a->base + a->used;
    return (size_t)((0u - top) & (uintptr_t)(align - 1));
}

void *hz_arena_alloc(hz_arena_t *a, size_t size, size_t align)
{
    if (!a)
        return NULL;
    if (align == 0)
        align = HZ_ARENA_DEFAULT_ALIGN;
    size_t available = a->cap - a->used;
    if (!is_pow2(align)) {
        refuse(a, HZ_E_INVALID_ARG, size, available);
        return NULL;
    }
    size_t pad = padding_for(a, align);
    /* Saturate on overflow: the request cannot fit either way, and the report stays meaningful. */
    size_t needed = size > (size_t)-1 - pad ? (size_t)-1 : pad + size;
    if (needed > available) {
        refuse(a, HZ_E_NO_MEMORY, needed, available);
        return NULL;
    }
    uint8_t *p = a->base + a->used + pad;
    if (size == 0)
        return p; /* consumes nothing, not even the padding */
    a->used += needed;
    if (a->used > a->high_water)
        a->high_water = a->used;
    return p;
}

void *hz_arena_alloc_array(hz_arena_t *a, size_t count, size_t elem_size, size_t align)
{
    if (!a)
        return NULL;
    if (elem_size != 0 && count > (size_t)-1 / elem_size) {
        refuse(a, HZ_E_OVERFLOW, (size_t)-1, a->cap - a->used);
        return NULL;
    }
    return hz_arena_alloc(a, count * elem_size, align);
}

void *hz_arena_calloc(hz_arena_t *a, size_t count, size_t elem_size, size_t align)
{
    void *p = hz_arena_alloc_array(a, count, elem_size, align);
    if (p && count != 0 && elem_size != 0)
        __builtin_memset(p, 0, count * elem_size);
    return p;
}

hz_arena_mark_t hz_arena_mark(const hz_arena_t *a)
{
    return a ? a->used : 0;
}

hz_status_t hz_arena_reset(hz_arena_t *a, hz_arena_mark_t mark)
{
    if (!a || mark > a->used)
        return HZ_E_INVALID_ARG;
#if HZ_ARENA_POISON
    if (a->used > mark)
        __builtin_memset(a->base + mark, 0xA5, a->used - mark);
#endif
    a->used = mark;
    return HZ_OK;
}

size_t hz_arena_available(const hz_arena_t *a, size_t align)
{
    if (!a)
        return 0;
    if (align == 0)
        align = HZ_ARENA_DEFAULT_ALIGN;
    if (!is_pow2(align))
        return 0;
    size_t left = a->cap - a->used;
    size_t pad = padding_for(a, align);
    return pad >= left ? 0 : left - pad;
}

hz_status_t hz_arena_error(const hz_arena_t *a, hz_error_t *err)
{
    if (!a)
        return hz_error_set(err, HZ_E_INVALID_ARG, "no arena");
    switch (a->last_status) {
    case HZ_OK:
        hz_error_clear(err);
        return HZ_OK;
    case HZ_E_OVERFLOW:
        return hz_error_set(err, HZ_E_OVERFLOW, "arena '%s': element count times size overflows (has %zu bytes)",
                            a->name, a->last_available);
    case HZ_E_INVALID_ARG:
        return hz_error_set(err, HZ_E_INVALID_ARG, "arena '%s': alignment is not a power of two", a->name);
    default:
        return hz_error_set(err, a->last_status, "arena '%s': needs %zu bytes, has %zu bytes", a->name,
                            a->last_needed, a->last_available);
    }
}
