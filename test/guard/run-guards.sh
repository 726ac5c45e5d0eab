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
# The layers: a public header, core files, port files and a program that each include the wrong way.
expect_fail "layers-public" "public header includes a non-public file: .*leak.h" \
    sh "$here/check-layers.sh" --root "$bad/layers"
expect_fail "layers-core-up" "core file includes a port or program header: .*up.c" \
    sh "$here/check-layers.sh" --root "$bad/layers"
expect_fail "layers-port-past" "includes a core header past include/hz: .*past.c" \
    sh "$here/check-layers.sh" --root "$bad/layers"
expect_fail "layers-program-internal" "includes a core header past include/hz: .*peek.c" \
    sh "$here/check-layers.sh" --root "$bad/layers"
expect_fail "layers-core-program" "core file includes a port or program header: .*prog.c" \
    sh "$here/check-layers.sh" --root "$bad/layers"
expect_fail "layers-port-program" "port file includes a program header: .*down.c:2:" \
    sh "$here/check-layers.sh" --root "$bad/layers"

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
# The makes below are make's own children when make test runs this: not of its job server.
unset MAKEFLAGS MFLAGS MAKELEVEL
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
# The documentation's commands (check-docs): a page with a missing make target, unknown options of hzrt's
# commands, hzbake and hzerrtime, an unknown hzrt command, an option on a continuation line, an issue number and
# commit hashes is refused, and every mistake is named (the guard runs once; each mistake is one case).
out=$(sh "$here/check-docs.sh" --root "$here/../.." "$bad/docs/README.md" 2>&1) && docs_rc=0 || docs_rc=$?
for case in "make-target:make no-such-target: no such target" "hzrt-option:no option --no-such-option" \
        "hzrt-command:hzrt frobnicate: no such command" "hzbake-option:no option --no-such-bake-option" \
        "hzerrtime-option:no option --bogus" "continued-line:no option --nope" \
        "issue-number:names an issue number: issue 12" "short-hash:a commit hash: 1c76226\$" \
        "long-hash:a commit hash: 1c76226a4c523e04531ee388ba12bc34581d1e5c"; do
    name=docs-${case%%:*} pattern=${case#*:}
    if [ "$docs_rc" != 0 ] && printf '%s\n' "$out" | grep -q -- "$pattern"; then
        echo "  ok    guard $name"
        record "guard/$name" 1 0
    else
        echo "  FAIL  guard $name: check-docs did not refuse a known-bad page with '$pattern':"
        printf '%s\n' "$out" | head -n 12 | sed 's/^/        /'
        record "guard/$name" 0 1
        fails=$((fails + 1))
    fi
done
# ... and accepts what is right in it: the board-fit target, a CRC, a block that is not shell.
if printf '%s\n' "$out" | grep -q "board-fit\|c8abb741\|not-checked"; then
    echo "  FAIL  guard docs-no-false-alarm: check-docs refused a correct line of the bad page:"
    printf '%s\n' "$out" | grep "board-fit\|c8abb741\|not-checked" | sed 's/^/        /'
    record "guard/docs-no-false-alarm" 0 1
    fails=$((fails + 1))
else
    echo "  ok    guard docs-no-false-alarm"
    record "guard/docs-no-false-alarm" 1 0
fi
# The real documentation passes (the same check, on README.md and doc/).
out=$(sh "$here/check-docs.sh" --root "$here/../.." 2>&1) && docs_rc=0 || docs_rc=$?
printf '%s\n' "$out" | sed 's/^/        /'
if [ "$docs_rc" = 0 ]; then
    echo "  ok    guard docs"
    record "guard/docs" 1 0
else
    echo "  FAIL  guard docs: README.md or doc/ shows a command that does not parse, an issue number or a hash"
    record "guard/docs" 0 1
    fails=$((fails + 1))
fi
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
