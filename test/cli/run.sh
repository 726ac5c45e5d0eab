#!/bin/sh
# Command-line behaviour of hzrt: help, usage errors, bad inputs (each a clear message and a distinct exit
# status), and that a good run leaves exactly its outputs behind (no temporary files).
#   run.sh RESULTS_DIR HZRT [HZBENCH]
set -u
results=$1 hzrt=$2 hzbench=${3:-}
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
for c in render info accel board latency; do
    expect "$c-help-exit-status" 0 "exit status: 0 ok, 2 bad command line" "$hzrt" $c --help
done
expect latency-fbdev-absent-source 72 "^hzrt: --source fbdev: this build has no fbdev port" "$hzrt" latency --source fbdev --frames 3
expect accel-native-plan 0 "native build needs at most" "$hzrt" accel builtin
if "$hzrt" accel builtin --embree >"$tmp/embree.txt" 2>&1; then
    if grep -q "native build needs" "$tmp/embree.txt" || ! grep -q "Embree allocates its own memory" "$tmp/embree.txt"; then
        echo "  FAIL  cli accel-embree-plan: --embree prints the native memory plan"; fail=$((fail + 1))
    else
        pass=$((pass + 1))
    fi
fi
# Long phases are named as they run (HZ_PROGRESS=all shows every phase, however short, on a non-terminal).
expect progress-native-build 0 "hzrt: native build of builtin (3016 triangles): done in" env HZ_PROGRESS=all \
    "$hzrt" accel builtin
expect progress-single-frame 0 "hzrt: rendering builtin (32x16, mode full): done in" env HZ_PROGRESS=all \
    "$hzrt" render builtin --mode full --size 32x16 --out "$tmp/prog"
expect progress-quiet 0 "" sh -c "! HZ_PROGRESS=all \"$hzrt\" render builtin --size 32x16 --quiet --out \"$tmp/prog\" 2>&1 | grep -q 'done in'"
if [ -f "${HZ_SCENES_DIR:-/nonexistent}/dragon-res4.hzb" ]; then
    expect progress-reading 0 "hzrt: reading $HZ_SCENES_DIR/dragon-res4.hzb" env HZ_PROGRESS=all "$hzrt" render \
        "$HZ_SCENES_DIR/dragon-res4.hzb" --size 32x16 --out "$tmp/prog"
    expect progress-quiet-reading 0 "" sh -c "! HZ_PROGRESS=all \"$hzrt\" render \"$HZ_SCENES_DIR/dragon-res4.hzb\" --size 32x16 --quiet --out \"$tmp/prog\" 2>&1 | grep -q 'reading'"
fi
expect no-command 2 "usage" "$hzrt"
expect unknown-command 2 "unknown command 'bogus'" "$hzrt" bogus
expect render-no-scene 2 "which scene" "$hzrt" render
expect render-bad-spp 2 "square" "$hzrt" render builtin --mode full --spp 3
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
# Options of one mode are refused in the others (they would do nothing there).
expect render-spp-in-tdense 2 "\-\-spp does nothing in tdense mode" "$hzrt" render builtin --mode tdense --spp 16
expect render-spp-in-taa 2 "\-\-spp does nothing in taa mode" "$hzrt" render builtin --mode taa --spp 4
expect render-spp-default-mode 2 "\-\-spp does nothing in tdense mode" "$hzrt" render builtin --spp 4
expect render-ordering-in-full 2 "\-\-ordering does nothing in full mode" "$hzrt" render builtin --mode full --ordering bowtie
expect render-taa-clip-in-full 2 "\-\-taa-clip does nothing in full mode" "$hzrt" render builtin --mode full --taa-clip
expect render-taa-cr-in-tdense 2 "\-\-taa-catmull-rom does nothing in tdense" "$hzrt" render builtin --taa-catmull-rom
expect render-msaa4-in-taa 2 "\-\-msaa4 does nothing in taa mode" "$hzrt" render builtin --mode taa --msaa4
expect render-reflected-in-taa 2 "\-\-no-reflected-mv does nothing in taa" "$hzrt" render builtin --mode taa --no-reflected-mv
expect render-help-tdense 0 "--no-reflected-mv" "$hzrt" render --help
expect render-unknown-option 2 "unknown option '--fast'" "$hzrt" render builtin --fast
expect render-bad-transparency 2 "--transparency: 'stochastic' is not exact, rr, std" "$hzrt" render builtin --transparency stochastic
expect render-bad-hybrid 2 "--transparency: 'hybrid:1.5' is not exact" "$hzrt" render builtin --transparency hybrid:1.5
expect render-bad-hybrid-empty 2 "--transparency: 'hybrid:' is not exact" "$hzrt" render builtin --transparency hybrid:
expect render-help-transparency 0 "dtaa-star" "$hzrt" render --help
expect render-transparency-std 0 "mode taa" "$hzrt" render builtin --mode taa --size 32x18 --frames 2 --transparency hybrid:0.5 --no-y4m --out "$tmp/o-std"
expect render-bad-shutter 2 "--shutter: '1.5' is not a number in \\[0, 1\\]" "$hzrt" render builtin --shutter 1.5
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
# The summary reports what was done: samples per pixel actually traced, the start time.
expect render-tdense-spp 0 "mode tdense, 0.25 spp per frame" "$hzrt" render builtin --size 64x36 --frames 2 --start 0.5 --out "$tmp/td"
expect render-full-spp 0 "mode full, 4 spp per frame" "$hzrt" render builtin --mode full --spp 4 --size 32x16 --out "$tmp/f4"
expect render-start-line 0 "scene time 0.5 to 0.5042 s" "$hzrt" render builtin --size 32x16 --frames 2 --start 0.5 --out "$tmp/td"
if command -v python3 >/dev/null 2>&1; then
    python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['spp']==0.25 and d['start']==0.5, d" \
        "$tmp/td/summary.json" && pass=$((pass + 1)) ||
        { echo "  FAIL  cli render-summary-json: spp or start wrong in summary.json"; fail=$((fail + 1)); }
fi
head -c 8 "$tmp/run/frames.y4m" | grep -q YUV4MPEG && pass=$((pass + 1)) ||
    { echo "  FAIL  cli render-ok: frames.y4m lacks the YUV4MPEG2 signature"; fail=$((fail + 1)); }

# Output folders: an unwritable --out is refused before the work (single frame and latency alike), and the
# folders --out creates are named.
mkdir -p "$tmp/ro" && chmod 555 "$tmp/ro"
ro=$tmp/ro
[ -w "$ro" ] && ro=/proc/self  # root writes anywhere but in /proc
expect render-out-readonly 73 "$ro: the output folder is not writable" "$hzrt" render builtin --size 32x16 --out "$ro"
if "$hzrt" render builtin --size 32x16 --out "$ro" 2>&1 | grep -q "frame time"; then
    echo "  FAIL  cli render-out-readonly-early: the render ran before the folder was refused"; fail=$((fail + 1))
else
    pass=$((pass + 1))
fi
expect latency-out-readonly 73 "$ro: the output folder is not writable" "$hzrt" latency --virtual --source sim \
    --hz 240 --render-model uniform:0.2P:0.8P --frames 50 --out "$ro"
expect render-out-created 0 "created $tmp/new, $tmp/new/a, $tmp/new/a/b" "$hzrt" render builtin --size 32x16 \
    --out "$tmp/new/a/b"
# An interrupted render (SIGINT, SIGTERM) leaves no temporary file behind and ends as the signal does.
if command -v python3 >/dev/null 2>&1; then
    for sig in INT TERM; do
        if python3 - "$hzrt" "$tmp/sig-$sig" "$sig" <<'PYEOF'
import glob, os, signal, subprocess, sys, time
hzrt, out, sig = sys.argv[1], sys.argv[2], getattr(signal, "SIG" + sys.argv[3])
p = subprocess.Popen([hzrt, "render", "builtin", "--size", "320x180", "--frames", "100000", "--threads", "1",
                      "--quiet", "--out", out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
deadline = time.time() + 60
while time.time() < deadline and not glob.glob(out + "/*.tmp.*"):
    time.sleep(0.05)
seen = glob.glob(out + "/*.tmp.*")
time.sleep(0.3)
p.send_signal(sig)
rc = p.wait(timeout=60)
left = glob.glob(out + "/*.tmp.*") + glob.glob(out + "/.hz-probe.*")
ok = bool(seen) and not left and rc == -sig
if not ok:
    print("temporaries seen %s, left %s, status %s" % (seen, left, rc))
sys.exit(0 if ok else 1)
PYEOF
        then pass=$((pass + 1)); else echo "  FAIL  cli render-sig$sig-leftovers"; fail=$((fail + 1)); fi
    done
fi

# hzbench: a missing scene is named before anything is measured.
if [ -n "$hzbench" ]; then
    expect bench-missing-scene 73 "scene 'dragon' is missing: $tmp/noscenes/dragon.hzb" \
        "$hzbench" --only accel --scenes "$tmp/noscenes" --scene dragon --rounds 1
fi

echo "  ok    cli                    $pass passed$( [ $fail -ne 0 ] && echo ", $fail failed")"
echo "cli $pass $fail 0" >"$results/cli.res"
