#!/bin/sh
# Totals the .res files that the test scripts wrote and prints the last line of `make test`:
#   N passed, N failed
# preceded by the ten slowest test binaries (the runner's wall time, the .res files' fifth field).
# Exits non-zero when anything failed or when a results directory is missing (a half-run suite is a failure).
set -u
passed=0 failed=0 skipped=0
times=""
for dir in "$@"; do
    if [ ! -d "$dir" ] || [ -z "$(ls "$dir"/*.res 2>/dev/null)" ]; then
        echo "summary: no results in $dir" >&2
        failed=$((failed + 1))
        continue
    fi
    for res in "$dir"/*.res; do
        read -r name p f s secs _ <"$res"
        [ -n "${secs:-}" ] && times="$times$secs $name
"
        passed=$((passed + p)) failed=$((failed + f)) skipped=$((skipped + s))
    done
done
if [ -n "$times" ]; then
    echo "slowest:"
    printf '%s' "$times" | sort -rn | head -n 10 | awk '{ printf "  %5d s  %s\n", $1, $2 }'
fi
[ "$skipped" -ne 0 ] && echo "($skipped skipped)"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
