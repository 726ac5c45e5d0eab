#!/bin/sh
# Command-line behaviour of hzrt: help, usage errors, bad inputs (each a clear message and a distinct exit
# status), and that a good run leaves exactly its outputs behind (no temporary files).
#   run.sh RESULTS_DIR HZRT
set -u
results=$1 hzrt=$2
mkdir -p "$results"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0

# expect NAME STATUS PATTERN CMD...: exit status STATUS and PATTERN somewhere in stdout+stderr.
expect() {
    name=$1 want=$2 pattern=$3
    shift 3
    out=$("$@" 2>&1)
    got=$?
    if [ "$got" != "$want" ]; then
        echo "  FAIL  cli $name: exit status $got, expected $want"
        printf '%s\n' "$out" | head -n 5 | sed 's/^/        /'
        fail=$((fail + 1))
    elif [ -n "$pattern" ] && ! printf '%s\n' "$out" | grep -q -- "$pattern"; then
        echo "  FAIL  cli $name: output lacks '$pattern'"
        printf '%s\n' "$out" | head -n 5 | sed 's/^/        /'
        fail=$((fail + 1))
    else
        pass=$((pass + 1))
    fi
}

expect help 0 "usage: hzrt" "$hzrt" --help
expect render-help 0 "samples per pixel" "$hzrt" render --help
expect info-help 0 "usage: hzrt info" "$hzrt" info --help
expect no-command 2 "usage" "$hzrt"
expect unknown-command 2 "unknown command 'bogus'" "$hzrt" bogus
expect render-no-scene 2 "which scene" "$hzrt" render
expect render-bad-spp 2 "square" "$hzrt" render builtin --spp 3
expect render-bad-size 2 "--size" "$hzrt" render builtin --size 0x5
expect render-bad-frames 2 "'abc' is not an integer" "$hzrt" render builtin --frames abc
expect render-bad-mode 2 "not tdense, full, taa or adaptive" "$hzrt" render builtin --mode xyz
expect render-tau-outside-adaptive 2 "--tau applies only to --mode adaptive" "$hzrt" render builtin --tau 0.3
expect render-map-outside-adaptive 2 "--adaptive-map applies only to --mode adaptive" "$hzrt" render builtin --mode full --adaptive-map "$tmp/m.png"
expect render-bad-tau 2 "--tau-psn: '2' is not a threshold in \[0, 1\]" "$hzrt" render builtin --mode adaptive --tau-psn 2
expect render-bad-normal-angle 2 "--normal-angle: '-1' is not an angle" "$hzrt" render builtin --mode adaptive --normal-angle -1
expect render-unknown-focus 65 "no object named 'nosuch'" "$hzrt" render builtin --mode adaptive --focus-objects nosuch --out "$tmp/o2"
expect render-help-adaptive 0 "--tau-soid" "$hzrt" render --help
expect render-bad-ordering 2 "'zigzag' is not full, dominant" "$hzrt" render builtin --ordering zigzag
expect render-bad-tdense-gamma 2 "--tdense-gamma: '0' is not a number" "$hzrt" render builtin --tdense-gamma 0
expect render-msaa4-needs-4spp 2 "4x MSAA positions need full mode with 4 spp" "$hzrt" render builtin --mode full --msaa4
expect render-help-tdense 0 "--no-reflected-mv" "$hzrt" render --help
expect render-unknown-option 2 "unknown option '--fast'" "$hzrt" render builtin --fast
expect render-missing-file 73 "$tmp/nope.hzb: No such file" "$hzrt" render "$tmp/nope.hzb" --out "$tmp/o1"
head -c 300 /dev/urandom >"$tmp/random.hzb"
expect info-garbage 68 "random.hzb: not a .hzb file" "$hzrt" info "$tmp/random.hzb"
: >"$tmp/empty.hzb"
expect info-empty 68 "truncated" "$hzrt" info "$tmp/empty.hzb"
expect info-directory 73 "not a regular file" "$hzrt" info "$tmp"
: >"$tmp/file"
expect render-out-not-dir 73 "Not a directory" "$hzrt" render builtin --out "$tmp/file/sub"

# Adaptive supersampling: the summary's figures and the activity map.
expect render-adaptive-ok 0 "extra rays/px" "$hzrt" render builtin --mode adaptive --size 64x36 --threads 2 --tau 0.3 \
    --focus-objects 0,1 --adaptive-map "$tmp/ad/map.png" --out "$tmp/ad"
[ -s "$tmp/ad/map.png" ] || { echo "  FAIL  cli render-adaptive-ok: map missing"; fail=$((fail + 1)); }
grep -q '"sample_ratio_9spp"' "$tmp/ad/summary.json" 2>/dev/null ||
    { echo "  FAIL  cli render-adaptive-ok: summary.json lacks the adaptive figures"; fail=$((fail + 1)); }

# A good run: its outputs and nothing else.
expect render-ok 0 "frame time" "$hzrt" render builtin --size 64x36 --frames 3 --threads 2 --out "$tmp/run"
for f in frames.y4m summary.json; do
    [ -s "$tmp/run/$f" ] || { echo "  FAIL  cli render-ok: $f missing"; fail=$((fail + 1)); }
done
[ -s "$tmp/run/last.png" ] || [ -s "$tmp/run/last.ppm" ] || { echo "  FAIL  cli render-ok: last frame missing"; fail=$((fail + 1)); }
leftover=$(find "$tmp/run" -name '*.tmp.*' | head -n 1)
[ -z "$leftover" ] || { echo "  FAIL  cli render-ok: temporary file left: $leftover"; fail=$((fail + 1)); }
if command -v python3 >/dev/null 2>&1; then
    python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['frames']==3 and d['rays']['total']>0" \
        "$tmp/run/summary.json" && pass=$((pass + 1)) ||
        { echo "  FAIL  cli render-ok: summary.json is not the expected JSON"; fail=$((fail + 1)); }
fi
head -c 8 "$tmp/run/frames.y4m" | grep -q YUV4MPEG && pass=$((pass + 1)) ||
    { echo "  FAIL  cli render-ok: frames.y4m lacks the YUV4MPEG2 signature"; fail=$((fail + 1)); }

echo "  ok    cli                    $pass passed$( [ $fail -ne 0 ] && echo ", $fail failed")"
echo "cli $pass $fail 0" >"$results/cli.res"
