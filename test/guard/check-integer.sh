#!/bin/sh
# check-integer [--record DIR] CC ARCH SRC...
# Integer-only code (src/pattern/ and the integer core) must not touch floating point:
#  1. no `float`/`double` token in the sources (comments excluded);
#  2. each source compiles with -mgeneral-regs-only for ARCH (x86_64 or aarch64), which makes any FP or SIMD
#     register use a compile error on both ISAs.
set -u
. "$(dirname "$0")/lib.sh"
cc=$1 arch=$2
shift 2
case $arch in
    x86_64) board=host-sim ;;
    aarch64) board=aarch64-generic ;;
    *) echo "check-integer: unknown arch '$arch'"; exit 2 ;;
esac
fail=0
for f in "$@"; do
    hits=$(strip_comments "$f" | grep -nwE 'float|double|_Float16|__fp16')
    if [ -n "$hits" ]; then
        echo "check-integer: $f names a floating-point type:"
        printf '%s\n' "$hits" | head -n 5 | sed 's/^/    /'
        fail=1
    fi
    if ! out=$($cc -std=c99 -Wall -Wextra -Werror -pedantic -O2 -ffreestanding -mgeneral-regs-only \
            -Iinclude -Iboards/$board -c "$f" -o /dev/null 2>&1); then
        echo "check-integer: $f does not compile with -mgeneral-regs-only ($arch):"
        printf '%s\n' "$out" | grep -E 'error' | head -n 5 | sed 's/^/    /'
        fail=1
    fi
done
if [ $fail = 0 ]; then
    echo "check-integer: ok ($# sources, $arch)"
    record "check-integer/$arch" 1 0
else
    record "check-integer/$arch" 0 1
fi
exit $fail
