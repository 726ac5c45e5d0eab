#!/bin/sh
# `make fuzz`: runs each fuzz target for SECONDS, JOBS targets at a time, and reports per target what libFuzzer
# did (executions, coverage as libFuzzer's cov/ft) and what it found.
#   fuzz-all.sh FUZZ_O SECONDS JOBS TARGET...
# Each target keeps its state in FUZZ_O/TARGET/: corpus/ (what the fuzzer grew; seeds are read, never written),
# artifacts/ (inputs that failed a check: crash-, leak-, timeout-, oom-; library findings of the model import:
# lib-), last.log and ledger (one line per run: date, seconds, executions, cov, ft, findings), so runs add up.
# The report (also FUZZ_O/report.txt) gives this run's figures and the executions of all runs together. The
# exit status is 1 when a target found something in hzrt's code (an artifact other than lib-) or did not run.
set -u
out=$1 seconds=$2 jobs=$3
shift 3
. "$(dirname "$0")/targets.sh"
case $jobs in '' | *[!0-9]* | 0) jobs=1 ;; esac

run_target() {
    t=$1 d=$out/$1
    mkdir -p "$d/corpus" "$d/artifacts" "$d/tmp"
    ls "$d/artifacts" >"$d/artifacts.before"
    # shellcheck disable=SC2046 # the options are words on purpose
    TMPDIR=$d/tmp "$out/fuzz_$t" -max_total_time="$seconds" -print_final_stats=1 -artifact_prefix="$d/artifacts/" \
        $(fuzz_opts "$t") "$d/corpus" $(fuzz_seeds "$t" "$out") >"$d/last.log" 2>&1
    echo $? >"$d/last.rc"
    rm -rf "$d/tmp"
}

# Lanes: target i runs in lane i mod JOBS; each lane runs its targets one after another.
lane=0
while [ $lane -lt "$jobs" ]; do
    (
        i=0
        for t in "$@"; do
            [ $((i % jobs)) -eq $lane ] && run_target "$t"
            i=$((i + 1))
        done
    ) &
    lane=$((lane + 1))
done
wait

report=$out/report.txt
{
    echo "fuzz: $seconds s per target, $jobs at a time ($(date -u +%Y-%m-%dT%H:%M:%SZ))"
    printf '%-8s %12s %8s %6s %7s %9s %15s\n' target executions exec/s cov ft findings "all runs: execs"
    for t in "$@"; do
        d=$out/$t log=$out/$t/last.log
        execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
        rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n 1)
        cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
        ft=$(grep -o 'ft: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
        new=$(ls "$d/artifacts" | grep -vxF -f "$d/artifacts.before" | grep -E '^(crash|leak|timeout|oom)-')
        nnew=$(printf '%s' "$new" | grep -c .)
        rc=$(cat "$d/last.rc")
        echo "$(date -u +%s) $seconds ${execs:-0} ${cov:-0} ${ft:-0} $nnew" >>"$d/ledger"
        total=$(awk '{ s += $3 } END { printf "%d", s }' "$d/ledger")
        printf '%-8s %12s %8s %6s %7s %9s %15s\n' "$t" "${execs:-?}" "${rate:-?}" "${cov:-?}" "${ft:-?}" "$nnew" "$total"
        for a in $new; do
            echo "         found: $d/artifacts/$a"
            grep -m 3 -E 'ERROR|runtime error|fuzz_import: the' "$log" | sed 's/^/           /'
        done
        lib=$(grep '^fuzz_import: .* inputs: ' "$log" | tail -n 1 | sed -n 's/.*not hzrt.s code): //p')
        [ -n "$lib" ] && echo "         library findings (assimp, stb_image, zlib; not hzrt's code): $lib; kept as $d/artifacts/lib-*"
        if [ -z "$execs" ] || { [ "$rc" -ne 0 ] && [ "$nnew" -eq 0 ]; }; then
            echo "         $t did not run to its end (exit status $rc): see $log"
        fi
    done
} | tee "$report"
! grep -q 'found:\|did not run' "$report"
