#!/bin/sh
# governor-table.sh LABEL=DIR ... — one line per run of `hzrt latency --render scene` (or `hzrt render` on a
# display): its deadline miss rate, p99 latency in display periods, refreshes per shown frame, and the share of
# time at each quality level with that level's error against level 0 (PSNR dB / mean FLIP, when the run measured
# it with --level-error), and for load steps: the most misses within any one second ("step") and the miss rate of
# the frames outside that second ("rest"). Reads each DIR/report.json and DIR/frames.csv; a run without them is
# reported as "no report".
set -u
printf '%-22s %9s %10s %9s %5s %8s  %s\n' "run" "miss %" "p99 lat." "refr/frm" "step" "rest %" \
    "time at each level (PSNR dB / FLIP against level 0)"
for arg in "$@"; do
    label=${arg%%=*} dir=${arg#*=}
    json=$dir/report.json
    if [ ! -s "$json" ]; then
        printf '%-22s %s\n' "$label" "no report ($json)"
        continue
    fi
    # misses in the worst one-second window of frame starts, and the miss rate outside it
    step=$(awk -F, 'NR > 1 { t[n] = $3; late[n] = ($15 == "late"); n++ }
        END {
            best = 0; bi = 0; j = 0; cur = 0
            for (i = 0; i < n; i++) {
                cur += late[i]
                while (t[i] - t[j] >= 1e9) { cur -= late[j]; j++ }
                if (cur > best) { best = cur; bi = i; bj = j }
            }
            rest = 0; rn = 0
            for (i = 0; i < n; i++) if (best == 0 || i < bj || i > bi) { rest += late[i]; rn++ }
            printf "%d %.3f", best, rn ? 100 * rest / rn : 0
        }' "$dir/frames.csv" 2>/dev/null || echo "? ?")
    awk -v label="$label" -v step="$step" '
        function num(s, key,   r) {
            if (match(s, "\"" key "\": *-?[0-9.]+")) { r = substr(s, RSTART, RLENGTH); sub(/.*: */, "", r); return r + 0 }
            return -1
        }
        function str(s, key,   r) {
            if (match(s, "\"" key "\": *\"[^\"]*\"")) { r = substr(s, RSTART, RLENGTH); sub(/^[^:]*: *"/, "", r); sub(/"$/, "", r); return r }
            return ""
        }
        /"vsync":/ { period = num($0, "period_ns"); if (period <= 0) period = num($0, "nominal_period_ns") }
        /"frames": \{"rendered"/ { miss = num($0, "miss_rate_ppm") / 1e4; shown = num($0, "shown"); rep = num($0, "repeated") }
        /"latency": \{/ { p99 = num($0, "p99_ns") }
        /"level": [0-9]/ {
            share = num($0, "time_share")
            if (share > 0) {
                cost = ""
                if (num($0, "psnr_db") >= 0) cost = sprintf(" (%.1f dB / %.3f)", num($0, "psnr_db"), num($0, "flip"))
                levels = levels sprintf("%sL%d %.1f%%%s", levels == "" ? "" : ", ", num($0, "level"), 100 * share, cost)
            }
        }
        END {
            lat = period > 0 ? sprintf("%.2f P", p99 / period) : "?"
            rpf = shown > 0 ? sprintf("%.2f", (shown + rep) / shown) : "?"
            split(step, st, " ")
            printf "%-22s %9.3f %10s %9s %5s %8s  %s\n", label, miss, lat, rpf, st[1], st[2], levels == "" ? "(one level)" : levels
        }' "$json"
done
