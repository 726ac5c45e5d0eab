#!/bin/sh
# summarise.sh — one line per latency run from the report.json files hzrt latency wrote:
#
#   summarise.sh DIR...      (each DIR holds a report.json; a DIR of runs is searched one level down)
#
# Columns: run, frames shown, deadline miss rate, late, dropped, repeated refreshes, latency p50 / p99 /
# p99.9 / max (scan-out edge - render start, ms), v-sync period (us), missed and spurious edges. Plain sh +
# awk: nothing to install on the board or the host.
set -u
[ $# -ge 1 ] || { echo "usage: summarise.sh DIR..." >&2; exit 2; }
reports=""
for d in "$@"; do
    if [ -f "$d/report.json" ]; then reports="$reports $d/report.json"
    else for r in "$d"/*/report.json; do [ -f "$r" ] && reports="$reports $r"; done
    fi
done
[ -n "$reports" ] || { echo "summarise.sh: no report.json under $*" >&2; exit 1; }
printf '%-40s %7s %8s %5s %5s %6s %8s %8s %8s %8s %10s %6s %6s\n' run shown miss% late drop repeat \
    p50ms p99ms p99.9ms maxms period_us missed spur
for r in $reports; do
    awk -v run="$(dirname "$r")" '
        function num(key,   s) {                 # first "key": number after the current section marker
            s = text
            if (section != "") { if (!index(s, section)) return "-"; s = substr(s, index(s, section)) }
            if (!match(s, "\"" key "\": *-?[0-9.]+")) return "-"
            s = substr(s, RSTART, RLENGTH); sub(/.*: */, "", s); return s
        }
        { text = text $0 "\n" }
        END {
            section = "\"frames\":";   shown = num("shown"); late = num("late"); drop = num("dropped");
                                      rep = num("repeated"); ppm = num("miss_rate_ppm")
            section = "\"latency\":";  p50 = num("p50_ns"); p99 = num("p99_ns"); p999 = num("p99_9_ns")
                                      mx = num("max_ns")
            section = "\"vsync\":";    per = num("period_ns"); mis = num("missed"); spu = num("spurious")
            ms = "%8.3f"
            miss = ppm == "-" ? "-" : sprintf("%.3f", ppm / 1e4)
            printf "%-40s %7s %8s %5s %5s %6s ", run, shown, miss, late, drop, rep
            if (p50 == "-") printf "%8s %8s %8s %8s ", "-", "-", "-", "-"
            else printf ms " " ms " " ms " " ms " ", p50 / 1e6, p99 / 1e6, p999 / 1e6, mx / 1e6
            printf "%10.3f %6s %6s\n", per / 1e3, mis, spu
        }' "$r"
done
