#!/bin/sh
# Fixed memory is a promise to boards: for one board, `hzrt info` of each reference scene says every render
# mode's plan and that the default mode fits at the display size, and the board's default command (`hzrt show`:
# the scene in the default mode at the display size, every governor level's memory held, through the frame
# loop) runs a few frames on a simulated display with no sink (under qemu for the AArch64 boards), writes its
# report and records the default mode in summary.json. (A separate one-frame `hzrt render` would repeat the
# show's scene load, build and plan: the files path is the CLI tests'.)
#   fit.sh RESULTS_FILE BOARD "LAUNCHER" HZRT SCENE...
# SCENE: a .hzb path or `builtin`. Writes "board-fit/BOARD PASSED FAILED 0" to RESULTS_FILE.
set -u
res=$1 board=$2 launcher=$3 hzrt=$4
shift 4
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
for scene in "$@"; do
    name=$(basename "$scene" .hzb)
    if ! $launcher "$hzrt" info "$scene" >"$tmp/info" 2>&1; then
        echo "  FAIL  board $board: hzrt info $name failed"; sed 's/^/        /' "$tmp/info" | tail -n 3
        fail=$((fail + 1)); continue
    fi
    # Every mode has a plan line, and the verdict is for the default mode.
    modes=$(grep -c ' B/px = ' "$tmp/info")
    if [ "$modes" -lt 3 ] || ! grep -q '^verdict      fits this board' "$tmp/info"; then
        echo "  FAIL  board $board: hzrt info $name does not say it fits ($modes mode plans):"
        grep -E 'B/px|NOT fit|^verdict' "$tmp/info" | sed 's/^/        /'
        fail=$((fail + 1)); continue
    fi
    if ! $launcher "$hzrt" show "$scene" --sink none --source sim --frames 16 --lock-min-run 8 --threads 2 --quiet \
            --out "$tmp/show" >"$tmp/show.log" 2>&1 || ! [ -s "$tmp/show/report.json" ] ||
        ! head -n 1 "$tmp/show/frames.csv" | grep -q ',level$'; then
        echo "  FAIL  board $board: hzrt show $name (the board's default command, 16 frames, simulated display) failed:"
        tail -n 3 "$tmp/show.log" | sed 's/^/        /'
        fail=$((fail + 1)); continue
    fi
    # ... in the default mode at the display size info named
    size=$(sed -n 's/^verdict .* at \([0-9]*\)x\([0-9]*\).*/\1, \2/p' "$tmp/info")
    if ! grep -q '"mode": *"tdense"' "$tmp/show/summary.json" || [ -z "$size" ] ||
        ! grep -q "\"size\": \[$size\]" "$tmp/show/summary.json"; then
        echo "  FAIL  board $board: $name shown, but not in the default mode (tdense) at the display size ($size)"
        fail=$((fail + 1)); continue
    fi
    echo "  ok    board $board: $name fits ($(grep '(hzrt render' "$tmp/info" | awk '{print $1, $4, $5}')), shows at ${size%%,*}x${size##* }"
    pass=$((pass + 1))
done
echo "board-fit/$board $pass $fail 0" >"$res"
[ "$fail" -eq 0 ]
