#!/bin/sh
# `make test`: a short run of each fuzz target from its seeds, recorded for test/summary.sh.
#   run-fuzz.sh RESULTS_DIR FUZZ_O RUNS TARGET...
# Every target runs RUNS inputs (the model import, a child process a few ms an input, RUNS / 40), seeds
# first; the seeds and FUZZ_O's corpora stay untouched (new inputs go to a temporary directory). A failed check
# leaves its input in RESULTS_DIR/fuzz-artifacts/ and fails that target's test. With the import target it also
# checks the import fuzzer's judge of whose code failed (fuzz_import_judge).
set -u
results=$1 out=$2 runs=$3
shift 3
. "$(dirname "$0")/targets.sh"
mkdir -p "$results/fuzz-artifacts"
for t in "$@"; do
    name=fuzz_$t log=$results/fuzz_$t.log seeds=$(fuzz_seeds "$t" "$out")
    n=$runs
    [ "$t" = import ] && n=$((runs / 40 > 0 ? runs / 40 : 1))
    work=$(mktemp -d)
    # shellcheck disable=SC2086 # one or more directories
    if [ -z "$(ls $seeds 2>/dev/null)" ]; then
        printf '  FAIL  %-18s %-28s no seeds in %s\n' host "$name" "$seeds"
        echo "host/$name 0 1 0" >"$results/$name.res"
        rm -rf "$work"
        continue
    fi
    mkdir "$work/corpus" "$work/tmp"
    t0=$(date +%s)
    # shellcheck disable=SC2046 # the options are words on purpose
    TMPDIR=$work/tmp "$out/$name" -runs="$n" -seed=1 -max_total_time=300 -print_final_stats=1 \
        -artifact_prefix="$results/fuzz-artifacts/" $(fuzz_opts "$t") "$work/corpus" $seeds >"$log" 2>&1
    rc=$?
    secs=$(( $(date +%s) - t0 ))
    rm -rf "$work"
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    if [ $rc -eq 0 ] && [ -n "$execs" ] && [ "$execs" -gt 0 ]; then
        printf '  ok    %-18s %-28s %3d passed (%s inputs) (%d s)\n' host "$name" 1 "$execs" "$secs"
        echo "host/$name 1 0 0" >"$results/$name.res"
    else
        printf '  FAIL  %-18s %-28s exit %d; see %s\n' host "$name" $rc "$log"
        grep -E 'ERROR|SUMMARY|runtime error|artifact|fuzz_import: the' "$log" | head -n 10 | sed 's/^/        /'
        echo "host/$name 0 1 0" >"$results/$name.res"
    fi
done

# The model import's judge: a failure in hzrt's code (an overflow, a leak, a hang) must stop the fuzzer, and each
# input of test/fuzz/judge/ (assimp 5.2.5 crashing on an OBJ's material library; assimp leaking a glTF stream it
# opened through the baker's file callbacks, the baker's allocation an indirect leak) must be kept as a library
# finding, not stop it.
case " $* " in *" import "*)
    name=fuzz_import_judge log=$results/$name.log seed=$(fuzz_seeds import "$out")/xml-furball-strands
    work=$(mktemp -d) bad=""
    for st in overflow leak hang; do
        HZ_FUZZ_IMPORT_SELFTEST=$st HZ_FUZZ_IMPORT_TIMEOUT=1 TMPDIR=$work "$out/fuzz_import" -rss_limit_mb=0 \
            -artifact_prefix="$work/" "$seed" >"$log.$st" 2>&1 &&
            bad="$bad $st: not a failure;"
        grep -q "abnormally .* in hzrt's code" "$log.$st" || bad="$bad $st: not blamed on hzrt;"
    done
    for input in "$(dirname "$0")"/judge/*; do
        j=$(basename "$input")
        TMPDIR=$work "$out/fuzz_import" -rss_limit_mb=0 -artifact_prefix="$work/" "$input" >"$log.$j" 2>&1 ||
            bad="$bad $j stopped the fuzzer;"
        grep -q 'library finding (assimp\|1 refused' "$log.$j" || bad="$bad $j was not kept as a library finding;"
    done
    rm -rf "$work"
    if [ -z "$bad" ]; then
        printf '  ok    %-18s %-28s %3d passed\n' host "$name" 1
        echo "host/$name 1 0 0" >"$results/$name.res"
    else
        printf '  FAIL  %-18s %-28s%s see %s*\n' host "$name" "$bad" "$log"
        echo "host/$name 0 1 0" >"$results/$name.res"
    fi
    ;;
esac
exit 0
