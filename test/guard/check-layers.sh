#!/bin/sh
# check-layers [--record DIR] [--root DIR]: the include graph runs one way — the programs (programs/, tools/) over
# the ports (port/) over the core (src/) over the public headers (include/hz). Refused, naming file and line:
#   - a public header (include/hz) that includes anything but another public header, the board's board.h or a
#     standard one;
#   - a core file (src/) that includes a port or program header (any quoted path leaving src/ other than hz/,
#     or naming port/, programs/ or tools/);
#   - a port file that includes a program header: a path into programs/, or the name of a header that only
#     programs/ has (ports include each other by name, so a program header's name is how one would leak in);
#   - a port or program file that includes a core header other than through include/hz (a path into src/, or
#     a module's *_internal.h).
# Unit tests may look inside the core (white-box); they are not checked here.
set -u
. "$(dirname "$0")/lib.sh"
root=.
[ "${1:-}" = "--root" ] && { root=$2; shift 2; }
bad=$(
    find "$root/include" -name '*.h' | sort | while read -r f; do
        grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$f" | grep -v -e '"hz/[a-z0-9_]*\.h"' -e '"board\.h"' |
            sed "s|^|public header includes a non-public file: $f:|"
    done
    find "$root/src" -name '*.[ch]' | sort | while read -r f; do
        grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$f" |
            grep -E '"(\.\./\.\./|/)|"[^"]*(port|programs|tools)/' |
            sed "s|^|core file includes a port or program header: $f:|"
    done
    prog_headers=$(find "$root/programs" -name '*.h' 2>/dev/null | sed 's|.*/||' | sort -u)
    port_headers=$(find "$root/port" -name '*.h' 2>/dev/null | sed 's|.*/||' | sort -u)
    find "$root/port" -name '*.[ch]' 2>/dev/null | sort | while read -r f; do
        grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$f" | while IFS= read -r line; do
            inc=$(printf '%s\n' "$line" | sed 's/^[^"]*"\([^"]*\)".*/\1/')
            case $inc in
                *programs/*) printf 'port file includes a program header: %s:%s\n' "$f" "$line"; continue ;;
                */*) continue ;; # hz/ (public), or a path the other checks judge
            esac
            if printf '%s\n' "$prog_headers" | grep -qx -- "$inc" && ! printf '%s\n' "$port_headers" | grep -qx -- "$inc"; then
                printf 'port file includes a program header: %s:%s\n' "$f" "$line"
            fi
        done
    done
    find "$root/port" "$root/programs" "$root/tools" -name '*.[ch]' 2>/dev/null | sort | while read -r f; do
        grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$f" | grep -E '"[^"]*(src/|_internal\.h")' |
            sed "s|^|port or program includes a core header past include/hz: $f:|"
    done
)
if [ -n "$bad" ]; then
    echo "check-layers: the include graph goes the wrong way:"
    printf '%s\n' "$bad" | sed 's/^/  /'
    record "guard/layers" 0 1
    exit 1
fi
echo "check-layers: ok (include/hz <- src <- port <- programs, tools: one way)"
record "guard/layers" 1 0
exit 0
