/*
 * hz/base.h — compiler glue shared by every module: alignment, inlining, restrict, byte copies.
 *
 * Contract: only preprocessor definitions and GCC/Clang builtins; no libc header. hz_memcpy/hz_memset/
 * hz_memmove map to compiler builtins, which the compiler inlines for small constant sizes and otherwise turns
 * into calls to memcpy/memset/memmove: the only libc symbols the core may reference (make check-freestanding).
 */
#ifndef HZ_BASE_H
#define HZ_BASE_H

#include <stddef.h>
#include <stdint.h>

#define HZ_ALIGNED(n) __attribute__((aligned(n)))
#define HZ_INLINE static inline __attribute__((always_inline))
#define HZ_LIKELY(x) __builtin_expect(!!(x), 1)
#define HZ_UNLIKELY(x) __builtin_expect(!!(x), 0)
/* Before a short constant-count loop over vector values (a pixel's three channels, four window slots): at -O2
 * GCC keeps such a loop rolled and its per-channel vectors in stack arrays, a store and a load per use. */
#define HZ_UNROLL _Pragma("GCC unroll 8")
#define HZ_ARRAY_LEN(a) (sizeof(a) / sizeof((a)[0]))
#define HZ_UNUSED(x) ((void)(x))

#define hz_memcpy(d, s, n) __builtin_memcpy((d), (s), (n))
#define hz_memset(d, c, n) __builtin_memset((d), (c), (n))
#define hz_memmove(d, s, n) __builtin_memmove((d), (s), (n))

/* Compile-time assertion usable at file scope in C99. */
#define HZ_STATIC_ASSERT(cond, name) typedef char hz_static_assert_##name[(cond) ? 1 : -1]

HZ_INLINE size_t hz_align_up(size_t x, size_t pow2)
{
    return (x + (pow2 - 1)) & ~(pow2 - 1);
}

#endif /* HZ_BASE_H */
