#!/bin/sh
# Runs the loader fuzzer for a bounded number of inputs on the seed corpus and records the result for
# test/summary.sh.   run-fuzz.sh RESULTS_DIR FUZZER SEED_DIR RUNS
# The seeds stay untouched (new corpus entries go to a temporary directory); a crash leaves its input in
# RESULTS_DIR/fuzz-artifacts/ and fails the test.
set -u
results=$1 fuzzer=$2 seeds=$3 runs=$4
mkdir -p "$results/fuzz-artifacts"
log=$results/fuzz_hzb.log
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ -z "$(ls "$seeds" 2>/dev/null)" ]; then
    echo "  FAIL  host               fuzz_hzb: no seeds in $seeds"
    echo "host/fuzz_hzb 0 1 0" >"$results/fuzz_hzb.res"
    exit 0
fi
"$fuzzer" -runs="$runs" -seed=1 -max_len=8388608 -rss_limit_mb=4096 -timeout=20 -max_total_time=300 \
    -artifact_prefix="$results/fuzz-artifacts/" "$work" "$seeds" >"$log" 2>&1
rc=$?
execs=$(sed -n 's/^Done \([0-9][0-9]*\) runs.*/\1/p' "$log" | tail -n 1)
if [ $rc -eq 0 ] && [ -n "$execs" ] && [ "$execs" -gt 0 ]; then
    printf '  ok    %-18s %-28s %3d passed (%s inputs)\n' host fuzz_hzb 1 "$execs"
    echo "host/fuzz_hzb 1 0 0" >"$results/fuzz_hzb.res"
else
    printf '  FAIL  %-18s %-28s exit %d; see %s\n' host fuzz_hzb $rc "$log"
    grep -E 'ERROR|SUMMARY|artifact' "$log" | head -n 10 | sed 's/^/        /'
    echo "host/fuzz_hzb 0 1 0" >"$results/fuzz_hzb.res"
fi
exit 0
