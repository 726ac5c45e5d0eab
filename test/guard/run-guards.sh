#!/bin/sh
# run-guards [--record DIR]: proves that the design guards can fail. Each case feeds a known-bad snippet to a
# guard and expects it to refuse (and, where it matters, to name the problem). One result per case.
set -u
. "$(dirname "$0")/lib.sh"
here=$(dirname "$0")
bad=$here/bad
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fails=0

# expect_fail NAME PATTERN CMD...: CMD must exit non-zero and print PATTERN.
expect_fail() {
    name=$1 pattern=$2
    shift 2
    if out=$("$@" 2>&1); then
        echo "  FAIL  guard $name: the guard accepted a known-bad input"
        record "guard/$name" 0 1
        fails=$((fails + 1))
    elif ! printf '%s\n' "$out" | grep -q -- "$pattern"; then
        echo "  FAIL  guard $name: refused, but without naming '$pattern':"
        printf '%s\n' "$out" | head -n 5 | sed 's/^/        /'
        record "guard/$name" 0 1
        fails=$((fails + 1))
    else
        echo "  ok    guard $name"
        record "guard/$name" 1 0
    fi
}

# Two modules that include each other: refused, both named.
expect_fail "include-cycle" "recon <-> render" sh "$here/check-includes.sh" --src "$bad/include-cycle"

for arch in x86_64 aarch64; do
    [ $arch = x86_64 ] && cc=gcc nm=nm || cc=aarch64-linux-gnu-gcc nm=aarch64-linux-gnu-nm
    # malloc hidden from the source scan: caught by the symbol check.
    $cc -std=c99 -O2 -ffreestanding -c "$bad/freestanding-hidden/alloc.c" -o "$tmp/alloc-$arch.o"
    expect_fail "freestanding-malloc-$arch" "references 'malloc'" \
        sh "$here/check-freestanding.sh" --src "$bad/freestanding-hidden" $nm "$tmp/alloc-$arch.o"
    # A float pasted together past the token scan: caught by -mgeneral-regs-only.
    expect_fail "integer-hidden-float-$arch" "does not compile with -mgeneral-regs-only" \
        sh "$here/check-integer.sh" $cc $arch "$bad/integer-hidden/order.c"
done
# stdio in the core: caught by the source scan (include, call and FILE).
expect_fail "freestanding-stdio-source" "includes <stdio.h>" \
    sh "$here/check-freestanding.sh" --src "$bad/freestanding-stdio" nm
expect_fail "freestanding-printf-source" "uses a hosted facility" \
    sh "$here/check-freestanding.sh" --src "$bad/freestanding-stdio" nm
# A plain float: caught by the token scan.
expect_fail "integer-float-token" "names a floating-point type" \
    sh "$here/check-integer.sh" gcc x86_64 "$bad/integer-plain/order.c"
# A board that misses a required setting: the #error names it.
printf '#include "hz/config.h"\nint hz_board_probe;\n' >"$tmp/probe.c"
expect_fail "board-missing-setting" "HZ_DISPLAY_HZ" \
    gcc -std=c99 -Iinclude -I"$bad/board-missing" -c "$tmp/probe.c" -o "$tmp/probe.o"
# `make bench` and `make report` on a fresh checkout bake the scenes they read before they run (dry run into an
# empty build root: the bake of each scene comes before the measuring command).
root=$here/../..
for case in "bench hzbench furball.hzb" "report hzerrtime lost-empire.hzb"; do
    set -- $case
    plan=$(make -n -C "$root" --no-print-directory "$1" BUILD_ROOT="$tmp/fresh" 2>&1)
    bake_at=$(printf '%s\n' "$plan" | grep -n "hzbake .*$3" | head -n 1 | cut -d: -f1)
    run_at=$(printf '%s\n' "$plan" | grep -n "bin/$2 --" | tail -n 1 | cut -d: -f1)
    if [ -n "$bake_at" ] && [ -n "$run_at" ] && [ "$bake_at" -lt "$run_at" ]; then
        echo "  ok    guard make-$1-bakes-first"
        record "guard/make-$1-bakes-first" 1 0
    else
        echo "  FAIL  guard make-$1-bakes-first: on a fresh checkout 'make $1' runs $2 without baking $3 first"
        record "guard/make-$1-bakes-first" 0 1
        fails=$((fails + 1))
    fi
done
# Tests are found by pattern: a new test/unit/test_*.c is built and run with no Makefile edit, its hz-test tags
# keep it off the boards they name, and an unknown tag is refused by name. (A probe folder stands in for
# test/unit; every real test file must be on some tested board's list.)
mkdir -p "$tmp/unit"
printf '/* probe */\nint main(void) { return 0; }\n' >"$tmp/unit/test_probe.c"
printf '/*\n * probe\n * hz-test: native no-vm (why)\n */\nint main(void) { return 0; }\n' >"$tmp/unit/test_probe_native.c"
host=$(make -s -C "$root" --no-print-directory print-tests BOARD=host-sim TEST_UNIT_DIR="$tmp/unit" 2>&1)
emul=$(make -s -C "$root" --no-print-directory print-tests BOARD=aarch64-generic TEST_UNIT_DIR="$tmp/unit" 2>&1)
listed=$( (make -s -C "$root" --no-print-directory print-tests BOARD=host-sim; \
           make -s -C "$root" --no-print-directory print-tests BOARD=aarch64-generic) 2>&1 | tr ' ' '\n')
missing=""
for f in "$root"/test/unit/test_*.c; do
    n=$(basename "$f" .c)
    grep -q 'hz-test:.*manual' "$f" && continue
    printf '%s\n' "$listed" | grep -qx "$n" || missing="$missing $n"
done
if [ "$host" = "test_probe test_probe_native" ] && [ "$emul" = "test_probe" ] && [ -z "$missing" ]; then
    echo "  ok    guard tests-found-by-pattern"
    record "guard/tests-found-by-pattern" 1 0
else
    echo "  FAIL  guard tests-found-by-pattern: host-sim lists '$host', aarch64-generic '$emul'" \
         "(expected 'test_probe test_probe_native' and 'test_probe'); on no board:${missing:- none}"
    record "guard/tests-found-by-pattern" 0 1
    fails=$((fails + 1))
fi
printf '/*\n * hz-test: nativ\n */\nint main(void) { return 0; }\n' >"$tmp/unit/test_probe_typo.c"
expect_fail "test-tag-unknown" "test_probe_typo.c: unknown hz-test tag 'nativ'" \
    make -s -C "$root" --no-print-directory print-tests TEST_UNIT_DIR="$tmp/unit"
# The test runner: a binary that hangs is stopped at the time limit and counts as a failure naming it.
printf '#!/bin/sh\necho "[==========] Running 1 test(s)."\nsleep 60\n' >"$tmp/test_hangs"
chmod +x "$tmp/test_hangs"
t0=$(date +%s)
out=$(HZ_TEST_TIMEOUT=2 sh "$here/../run-tests.sh" "$tmp/runner" guard "" "$tmp/test_hangs" 2>&1)
took=$(( $(date +%s) - t0 ))
read -r _ rp rf _ <"$tmp/runner/test_hangs.res" 2>/dev/null || rf=0
if [ "$rf" -ge 1 ] && [ "$took" -lt 30 ] && printf '%s\n' "$out" | grep -q "test_hangs timed out after 2 s"; then
    echo "  ok    guard runner-time-limit"
    record "guard/runner-time-limit" 1 0
else
    echo "  FAIL  guard runner-time-limit: a hung binary was not stopped and failed by name (${took} s):"
    printf '%s\n' "$out" | head -n 5 | sed 's/^/        /'
    record "guard/runner-time-limit" 0 1
    fails=$((fails + 1))
fi
[ $fails = 0 ]
