#!/bin/sh
# Totals the .res files that the test scripts wrote and prints the last line of `make test`:
#   N passed, N failed
# Exits non-zero when anything failed or when a results directory is missing (a half-run suite is a failure).
set -u
passed=0 failed=0 skipped=0
for dir in "$@"; do
    if [ ! -d "$dir" ] || [ -z "$(ls "$dir"/*.res 2>/dev/null)" ]; then
        echo "summary: no results in $dir" >&2
        failed=$((failed + 1))
        continue
    fi
    for res in "$dir"/*.res; do
        read -r _ p f s <"$res"
        passed=$((passed + p)) failed=$((failed + f)) skipped=$((skipped + s))
    done
done
[ "$skipped" -ne 0 ] && echo "($skipped skipped)"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
