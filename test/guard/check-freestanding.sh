#!/bin/sh
# check-freestanding [--record DIR] [--src DIR] NM OBJ...   (HZ_GUARD_LABEL names the result, e.g. the board)
# The core (src/) must stay freestanding:
#  1. the objects' undefined symbols (nm -u) are a subset of ALLOWED below;
#  2. no source under the src dir calls malloc/calloc/realloc/free or a stdio function, or names FILE or errno;
#  3. sources include only freestanding headers and compiler intrinsics headers.
# ALLOWED, and why:
#  memcpy memset memmove  what gcc emits for struct copies and hz_memcpy/hz_memset of non-constant size; every
#                         libc and every freestanding runtime provides them.
#  _GLOBAL_OFFSET_TABLE_ the linker defines it in every position-independent link; the assembler names it when
#                         code takes a function's address through the GOT (e.g. the renderer's any-hit
#                         callback). It is not a library symbol.
# Nothing else: no libgcc helper is needed today. If one appears (e.g. __popcountdi2 on a target without a
# popcount instruction), add it here with its reason.
set -u
. "$(dirname "$0")/lib.sh"
src_dir=src
if [ "${1:-}" = "--src" ]; then src_dir=$2; shift 2; fi
nm=$1
shift
ALLOWED="memcpy memset memmove _GLOBAL_OFFSET_TABLE_"
fail=0

# Symbols the core defines itself do not count: only what it needs from outside.
defined=$(for obj in "$@"; do $nm --defined-only "$obj" | awk 'NF >= 3 {print $3}'; done | sort -u)
for obj in "$@"; do
    for sym in $($nm -u "$obj" | awk '{print $NF}'); do
        printf '%s\n' "$defined" | grep -qxF "$sym" && continue
        case " $ALLOWED " in
            *" $sym "*) ;;
            *) echo "check-freestanding: $obj references '$sym' (allowed: $ALLOWED)"; fail=1 ;;
        esac
    done
done

HEADERS_OK="stdint.h stddef.h stdbool.h float.h limits.h stdarg.h immintrin.h arm_neon.h"
for f in $(find "$src_dir" -name '*.[ch]' | sort); do
    text=$(strip_comments "$f")
    hits=$(printf '%s\n' "$text" | grep -nE '\b(malloc|calloc|realloc|free|aligned_alloc|posix_memalign|printf|fprintf|sprintf|snprintf|vsnprintf|puts|fputs|fopen|fwrite|fread|exit|abort)[[:space:]]*\(|\bFILE\b|\berrno\b')
    if [ -n "$hits" ]; then
        echo "check-freestanding: $f uses a hosted facility:"
        printf '%s\n' "$hits" | head -n 5 | sed 's/^/    /'
        fail=1
    fi
    for h in $(printf '%s\n' "$text" | sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*<\([^>]*\)>.*/\1/p'); do
        case " $HEADERS_OK " in
            *" $h "*) ;;
            *) echo "check-freestanding: $f includes <$h> (src/ may include only: $HEADERS_OK)"; fail=1 ;;
        esac
    done
done

if [ $fail = 0 ]; then
    echo "check-freestanding: ok ($# objects, sources under $src_dir)"
    record "check-freestanding/${HZ_GUARD_LABEL:-core}" 1 0
else
    record "check-freestanding/${HZ_GUARD_LABEL:-core}" 0 1
fi
exit $fail
