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
expect render-bad-mode 2 "not tdense, full or taa" "$hzrt" render builtin --mode xyz
expect render-bad-ordering 2 "'zigzag' is not full, dominant" "$hzrt" render builtin --ordering zigzag
expect render-bad-tdense-gamma 2 "--tdense-gamma: '0' is not a number" "$hzrt" render builtin --tdense-gamma 0
expect render-msaa4-needs-4spp 2 "4x MSAA positions need full mode with 4 spp" "$hzrt" render builtin --mode full --msaa4
expect render-help-tdense 0 "--no-reflected-mv" "$hzrt" render --help
expect render-unknown-option 2 "unknown option '--fast'" "$hzrt" render builtin --fast
expect render-bad-shutter 2 "--shutter: '1.5' is not a fraction" "$hzrt" render builtin --shutter 1.5
expect render-blur-bvh-needs-shutter 2 "does nothing without motion blur" "$hzrt" render builtin --blur-bvh interp
expect render-bad-blur-bvh 2 "'kd' is not msbvh, interp or swept" "$hzrt" render builtin --shutter 1 --blur-bvh kd
expect render-blur-bvh-not-embree 2 "Embree builds its own motion blur" "$hzrt" render builtin --shutter 1 --backend embree --blur-bvh msbvh
expect render-blur-ok 0 "frame time" "$hzrt" render builtin --size 32x18 --frames 5 --threads 2 --shutter 0.5 --blur-bvh interp --out "$tmp/blur"
expect render-missing-file 73 "$tmp/nope.hzb: No such file" "$hzrt" render "$tmp/nope.hzb" --out "$tmp/o1"
head -c 300 /dev/urandom >"$tmp/random.hzb"
expect info-garbage 68 "random.hzb: not a .hzb file" "$hzrt" info "$tmp/random.hzb"
: >"$tmp/empty.hzb"
expect info-empty 68 "truncated" "$hzrt" info "$tmp/empty.hzb"
expect info-directory 73 "not a regular file" "$hzrt" info "$tmp"
: >"$tmp/file"
expect render-out-not-dir 73 "Not a directory" "$hzrt" render builtin --out "$tmp/file/sub"

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
