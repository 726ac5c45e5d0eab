#!/bin/sh
# check-includes [--record DIR] [--src SRC]: the modules of src/ (its folders) include each other one way only:
# an edge m -> n for every `#include "../n/..."` in src/m; a cycle (m reaches n and n reaches m) is refused,
# naming both modules and the files that make the edges. The render modes (src/recon) reach the renderer through
# src/render/mode.h; the renderer never includes a src/recon header.
set -u
. "$(dirname "$0")/lib.sh"
src=src
[ "${1:-}" = "--src" ] && { src=$2; shift 2; }
edges=$(for f in $(find "$src" -name '*.[ch]' | sort); do
    m=$(echo "${f#$src/}" | cut -d/ -f1)
    sed -n 's|^[[:space:]]*#[[:space:]]*include[[:space:]]*"\.\./\([a-z_]*\)/.*|\1|p' "$f" | while read -r n; do
        [ "$n" != "$m" ] && echo "$m $n $f"
    done
done)
cycles=$(printf '%s\n' "$edges" | awk 'NF == 3 {
        e[$1 " " $2] = e[$1 " " $2] ? e[$1 " " $2] : $3; m[$1] = 1; m[$2] = 1; r[$1 " " $2] = 1 }
    END {
        for (k in m) for (i in m) for (j in m) if (r[i " " k] && r[k " " j]) r[i " " j] = 1
        for (i in m) for (j in m) if (i < j && r[i " " j] && r[j " " i])
            printf "%s <-> %s (e.g. %s includes ../%s, and %s reaches %s)\n", i, j, e[i " " j] ? e[i " " j] : i, j, j, i
    }')
if [ -n "$cycles" ]; then
    echo "check-includes: include cycles between modules of $src:"
    printf '%s\n' "$cycles" | sed 's/^/  /'
    record "guard/includes" 0 1
    exit 1
fi
echo "check-includes: ok ($(printf '%s\n' "$edges" | awk 'NF == 3 { print $1, $2 }' | sort -u | wc -l) module edges, no cycle)"
record "guard/includes" 1 0
exit 0
