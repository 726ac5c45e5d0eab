#!/bin/sh
# Runs cmocka test binaries and records their counts for test/summary.sh.
#   run-tests.sh RESULTS_DIR LABEL "LAUNCHER" BIN...
# Each binary's output goes to RESULTS_DIR/<bin>.log; RESULTS_DIR/<bin>.res gets "label/bin passed failed skipped
# seconds".
# The line printed per binary ends with its wall time (the 15-minute budget of make test is watched by it).
# A binary that exits non-zero without reporting a failed test (a crash, a sanitizer abort, a missing library)
# counts as one failure; one that exits 0 without running a test also fails, so nothing passes by silence.
# HZ_TEST_JOBS=N runs N binaries side by side (for emulated boards, whose binaries are single-threaded).
# Each binary runs under a time limit (HZ_TEST_TIMEOUT seconds, default 900: generous, the slowest binary takes
# a few minutes under qemu on 2 cores): a hung test is killed and counts as a failure that names it, instead of
# stalling the suite.
set -u
results=$1 label=$2 launcher=$3
shift 3
[ -d "$results" ] || mkdir -p "$results"
export CMOCKA_MESSAGE_OUTPUT=stdout
status=0
limit=${HZ_TEST_TIMEOUT:-900}
run_one() {
    bin=$1
    name=$(basename "$bin")
    log=$results/$name.log
    t0=$(date +%s)
    # shellcheck disable=SC2086 # the launcher is a command line on purpose
    timeout -k 10 "$limit" $launcher "$bin" >"$log" 2>&1
    rc=$?
    secs=$(( $(date +%s) - t0 ))
    passed=$(sed -n 's/^\[  PASSED  \] \([0-9][0-9]*\) test.*/\1/p' "$log" | awk '{s+=$1} END {print s+0}')
    failed=$(sed -n 's/^\[  FAILED  \] \([0-9][0-9]*\) test.*/\1/p' "$log" | awk '{s+=$1} END {print s+0}')
    skipped=$(sed -n 's/^\[  SKIPPED \] \([0-9][0-9]*\) test.*/\1/p' "$log" | awk '{s+=$1} END {print s+0}')
    if [ $rc -eq 124 ] || [ $rc -eq 137 ]; then
        failed=$((failed + 1))
        echo "  $label: $name timed out after $limit s (HZ_TEST_TIMEOUT) and was stopped; see $log"
        echo "[  FAILED  ] $name: timed out after $limit s" >>"$log"
    elif [ $rc -ne 0 ] && [ "$failed" -eq 0 ]; then
        failed=1
        echo "  $label: $name exited with status $rc without a test report (crash?); see $log"
    fi
    if [ $rc -eq 0 ] && [ "$passed" -eq 0 ] && [ "$skipped" -eq 0 ]; then
        failed=1
        echo "  $label: $name ran no test; see $log"
    fi
    if [ "$failed" -ne 0 ]; then
        status=1
        printf '  FAIL  %-18s %-28s %3d passed, %d failed (%d s)\n' "$label" "$name" "$passed" "$failed" "$secs"
        grep -E '^\[ +(ERROR|LINE|FAILED) +\]' "$log" | head -n 20 | sed 's/^/        /'
    else
        printf '  ok    %-18s %-28s %3d passed%s (%d s)\n' "$label" "$name" "$passed" \
            "$( [ "$skipped" -ne 0 ] && echo ", $skipped skipped")" "$secs"
    fi
    echo "$label/$name $passed $failed $skipped $secs" >"$results/$name.res"
}
# HZ_TEST_JOBS binaries at once (default 1): lane k runs binaries k, k + N, k + 2N, ... in order.
jobs=${HZ_TEST_JOBS:-1}
if [ "$jobs" -le 1 ]; then
    for bin in "$@"; do run_one "$bin"; done
else
    lane=0
    while [ $lane -lt "$jobs" ]; do
        (
            n=0
            for bin in "$@"; do
                [ $((n % jobs)) -eq $lane ] && run_one "$bin"
                n=$((n + 1))
            done
        ) &
        lane=$((lane + 1))
    done
    wait
fi
exit 0
