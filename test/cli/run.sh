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
# Boards whose arenas are reserved address space (hzrt board says so; host-sim) start under a virtual-memory
# limit below the arenas' total and refuse a command with the arenas' size and 66, where a .bss that large would
# be refused at exec (the program killed before main). Sanitizer builds are left out: ASan's shadow memory
# needs more address space than such a limit leaves.
if "$hzrt" board | grep -q "reserved address space"; then
    case $hzrt in
    *-san/*) ;;
    *) expect arenas-vm-limit 66 "^hzrt: info: could not reserve [0-9]* MiB of address space for the board's arenas" \
           sh -c 'ulimit -v 2000000 && exec "$0" info builtin' "$hzrt" ;;
    esac
fi
expect accel-budget-range 2 "accel: --budget: '4.5' is not a number in \[0, 4\]" "$hzrt" accel builtin --budget 4.5
expect accel-budget-stops 0 "spatial splits, [0-9]* stopped by the budget" "$hzrt" accel builtin --budget 4
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
# However many options a command line repeats, each one is checked for where it acts (the options after the
# 64th once went unchecked).
expect render-option-after-64 2 "\-\-ordering does nothing in full mode" "$hzrt" render builtin --mode full \
    $(i=0; while [ $i -lt 70 ]; do printf -- '--spp 1 '; i=$((i + 1)); done) --ordering bowtie
expect latency-option-after-64 2 "\-\-active-low does nothing with \-\-source sim" "$hzrt" latency --source sim \
    $(i=0; while [ $i -lt 70 ]; do printf -- '--hz 60 '; i=$((i + 1)); done) --active-low --frames 3
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
expect render-rigid-needs-shutter 2 "--rigid refit does nothing without motion blur" "$hzrt" render builtin --rigid refit
expect render-bad-rigid 2 "'tlas' is not instance or refit" "$hzrt" render builtin --shutter 1 --rigid tlas
expect render-rigid-not-embree 2 "Embree builds its own motion blur" "$hzrt" render builtin --shutter 1 --backend embree --rigid refit
expect render-rigid-instances 0 "rigid instances\? (.* triangles) in object space, never refitted" "$hzrt" render builtin --size 32x18 --frames 3 --threads 2 --shutter 0.5 --out "$tmp/rigid"
expect accel-rigid-needs-check 2 "need --motion-check N" "$hzrt" accel builtin --rigid refit
expect render-segments-needs-shutter 2 "--motion-segments every-key does nothing without motion blur" "$hzrt" render builtin --motion-segments every-key
expect render-bad-segments 2 "'some' is not per-node or every-key" "$hzrt" render builtin --shutter 1 --motion-segments some
expect render-segments-not-embree 2 "Embree builds its own motion blur" "$hzrt" render builtin --shutter 1 --backend embree --motion-segments per-node
expect accel-segments-needs-check 2 "need --motion-check N" "$hzrt" accel builtin --motion-segments every-key
expect accel-bad-segments 2 "'some' is not per-node or every-key" "$hzrt" accel builtin --motion-check 8 --motion-segments some
expect accel-segments-linear 0 "per-node motion segments: [0-9]* key box sets, 2.00 per node (every key: 9)" "$hzrt" accel builtin --motion-check 64 --motion collapse --keys 9
expect accel-segments-every-key 0 "every-key motion segments: [0-9]* key box sets, 9.00 per node (every key: 9)" "$hzrt" accel builtin --motion-check 64 --motion rotate --keys 9 --motion-segments every-key
expect accel-bad-rigid 2 "'tlas' is not instance or refit" "$hzrt" accel builtin --motion-check 8 --rigid tlas
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
# A video write that fails (the file-size limit here; the writer thread meets it) ends the run with the file and
# the reason, exit 64 + HZ_E_IO, and the folder the run made is gone.
expect render-video-write-fails 73 "frames.y4m: Y4M: write failed at frame [0-9]*: File too large" \
    sh -c 'trap "" XFSZ; ulimit -f 200; exec "$0" render builtin --size 160x90 --frames 60 --threads 2 --out "$1"' \
    "$hzrt" "$tmp/wf/run"
[ ! -e "$tmp/wf" ] || { echo "  FAIL  cli render-video-write-fails: $tmp/wf left behind"; fail=$((fail + 1)); }
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
# hzrt leaves a signal ignored when it starts ignored (nohup; a shell starts background jobs with SIGINT
# ignored, and make test may run in one): start it as a terminal would, with the signal at its default.
def default_signals():
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
p = subprocess.Popen([hzrt, "render", "builtin", "--size", "320x180", "--frames", "100000", "--threads", "1",
                      "--quiet", "--out", out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                     preexec_fn=default_signals)
deadline = time.time() + 60
while time.time() < deadline and not glob.glob(out + "/*.tmp.*"):
    time.sleep(0.05)
seen = glob.glob(out + "/*.tmp.*")
time.sleep(0.3)
p.send_signal(sig)
try:
    rc = p.wait(timeout=60)
except subprocess.TimeoutExpired:
    # what the process was doing, for the failure report; then it goes
    def read(path):
        try:
            return open(path).read().strip().replace("\n", "; ")
        except OSError as e:
            return str(e)
    print("still running 60 s after the signal: %s; wchan %s; syscall %s; files %s" % (
        [l for l in read("/proc/%d/status" % p.pid).split("; ") if l.startswith(("State", "SigPnd", "ShdPnd",
                                                                                  "SigBlk", "SigIgn", "SigCgt"))],
        read("/proc/%d/wchan" % p.pid), read("/proc/%d/syscall" % p.pid),
        sorted((f, os.path.getsize(f)) for f in glob.glob(out + "/*"))))
    p.kill()
    p.wait()
    sys.exit(1)
left = glob.glob(out + "/*.tmp.*") + glob.glob(out + "/.hz-probe.*")
ok = bool(seen) and not left and rc == -sig
# and it keeps what it finished: the frames so far, the last one, a summary marked interrupted
import json, os
kept = all(os.path.exists(out + "/" + f) for f in ("frames.y4m", "summary.json")) and \
    (os.path.exists(out + "/last.png") or os.path.exists(out + "/last.ppm"))
if kept:
    d = json.load(open(out + "/summary.json"))
    kept = d["interrupted"] == "SIG" + sys.argv[3] and d["frames"] > 0
ok = ok and kept
if not ok:
    print("temporaries seen %s, left %s, status %s, finished frames kept %s" % (seen, left, rc, kept))
sys.exit(0 if ok else 1)
PYEOF
        then pass=$((pass + 1)); else echo "  FAIL  cli render-sig$sig-leftovers"; fail=$((fail + 1)); fi
    done
fi

# What a new user and an adversary trip over: each case below failed on the tree before these checks.
# ok NAME CMD...: CMD succeeds.
ok() {
    name=$1
    shift
    if "$@" >/dev/null 2>&1; then pass=$((pass + 1)); else echo "  FAIL  cli $name"; fail=$((fail + 1)); fi
}
# Every output is checked before the work: never an input or another output; its folder exists and is
# writable; a run that fails leaves no folder it made.
expect map-bad-extension 2 "'.jpg' is not an image extension" "$hzrt" render builtin --mode adaptive --size 96x54 \
    --frames 30 --out "$tmp/d2" --adaptive-map "$tmp/map.jpg"
ok map-bad-extension-nothing-made test ! -e "$tmp/d2"
expect map-missing-folder 73 "the folder $tmp/nodir" "$hzrt" render builtin --mode adaptive --size 96x54 --frames 30 \
    --out "$tmp/d3" --adaptive-map "$tmp/nodir/map.png"
ok map-missing-folder-nothing-made test ! -e "$tmp/d3"
expect map-unwritable-folder 73 "not writable" "$hzrt" render builtin --mode adaptive --size 96x54 --frames 30 \
    --out "$tmp/d4" --adaptive-map "$ro/map.png"
expect map-is-last-png 2 "is also the run's last frame" "$hzrt" render builtin --mode adaptive --size 96x54 \
    --frames 2 --out "$tmp/d7" --adaptive-map "$tmp/d7/last.png"
expect corrupt-scene 68 "not a .hzb file" "$hzrt" render "$tmp/random.hzb" --out "$tmp/d9/sub"
ok corrupt-scene-no-folder test ! -e "$tmp/d9"
head -c 100 /dev/urandom >"$tmp/trace-in.csv"
cp "$tmp/trace-in.csv" "$tmp/edges.csv"
expect output-is-the-trace 2 "is the --source trace" "$hzrt" latency --source "csv:$tmp/edges.csv" --out "$tmp"
ok output-is-the-trace-untouched cmp "$tmp/trace-in.csv" "$tmp/edges.csv"
# Options that would do nothing are refused.
expect rr-shadows-exact 2 "\-\-rr-shadows does nothing with --transparency exact" "$hzrt" render builtin \
    --rr-shadows --size 32x18 --out "$tmp/e1"
expect jitter-offline 2 "\-\-jitter-us does nothing with --source offline" "$hzrt" render builtin --jitter-us 50 \
    --size 32x18 --out "$tmp/e1"
expect no-marker-files 2 "\-\-no-marker does nothing with --sink files" "$hzrt" render builtin --no-marker \
    --size 32x18 --out "$tmp/e1"
# Object names: a name takes every object it names (or matches, as a shell pattern).
expect focus-pattern 0 "" "$hzrt" render builtin --mode adaptive --focus-objects 'sp*' --size 32x18 --frames 1 \
    --quiet --out "$tmp/f0"
ok focus-pattern-ids grep -q '"focus_objects": \[3\]' "$tmp/f0/summary.json"
expect focus-unknown-lists 65 "0 'room', 1 'mirror'" "$hzrt" render builtin --mode adaptive --focus-objects nosuch \
    --size 32x18 --out "$tmp/f9"
if [ -f "${HZ_SCENES_DIR:-/nonexistent}/CornellBox-Mirror.hzb" ]; then
    expect focus-every-match 0 "" "$hzrt" render "$HZ_SCENES_DIR/CornellBox-Mirror.hzb" --mode adaptive \
        --focus-objects leftWall --size 32x18 --frames 1 --quiet --out "$tmp/f1"
    ok focus-every-match-ids grep -q '"focus_objects": \[4, 5\]' "$tmp/f1/summary.json"
    # Names from a file go to the terminal with their control bytes shown, not sent.
    if command -v python3 >/dev/null 2>&1; then
        python3 - "$HZ_SCENES_DIR/CornellBox-Mirror.hzb" "$tmp/esc.hzb" <<'PYEOF'
import struct, sys, zlib
img = bytearray(open(sys.argv[1], "rb").read())
img[132:164] = b"red\x1b[31mname" + bytes(32 - 12)
img[252:256] = struct.pack("<I", zlib.crc32(bytes(img[:252])) & 0xffffffff)
open(sys.argv[2], "wb").write(img)
PYEOF
        expect info-control-bytes 0 'red\\x1b\[31mname' "$hzrt" info "$tmp/esc.hzb"
        ok info-control-bytes-not-sent sh -c "! \"$hzrt\" info \"$tmp/esc.hzb\" | grep -q \"$(printf '\033')\""
    fi
fi
# A FIFO as a trace is refused at once (a time limit guards the test), not waited on for ever.
if command -v mkfifo >/dev/null 2>&1 && command -v timeout >/dev/null 2>&1; then
    mkfifo "$tmp/ff"
    sleep 30 >"$tmp/ff" &
    writer=$!
    expect fifo-trace 73 "not a regular file" timeout 20 "$hzrt" latency --source "vcd:$tmp/ff" --timeout-ms 500 \
        --out "$tmp/l1"
    kill "$writer" 2>/dev/null
    wait "$writer" 2>/dev/null
    mkfifo "$tmp/ff-scene" # no writer at all: opening it would wait for one
    expect fifo-scene 73 "not a regular file" timeout 20 "$hzrt" info "$tmp/ff-scene"
fi
# An empty trace is refused cheaply: the edge log is sized by the file, not by the whole frame arena.
: >"$tmp/empty.vcd"
if command -v python3 >/dev/null 2>&1; then
    if python3 - "$hzrt" "$tmp/empty.vcd" "$tmp/l2" <<'PYEOF'
import os, subprocess, sys
p = subprocess.Popen([sys.argv[1], "latency", "--source", "vcd:" + sys.argv[2], "--out", sys.argv[3]],
                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
_, status, usage = os.wait4(p.pid, 0)
rc = os.waitstatus_to_exitcode(status)
ok = rc == 68 and usage.ru_maxrss < 64 * 1024  # KiB: it took 268 MB before
if not ok:
    print("status %d, max RSS %d KiB" % (rc, usage.ru_maxrss))
sys.exit(0 if ok else 1)
PYEOF
    then pass=$((pass + 1)); else echo "  FAIL  cli empty-trace-light"; fail=$((fail + 1)); fi
fi
# Malformed arguments are command-line errors (2), not failures of the run.
expect focus-empty-item 2 "has an empty item" "$hzrt" render builtin --mode adaptive --focus-objects , --size 32x18 \
    --out "$tmp/g1"
expect render-scale-size 2 "not a multiple of --render-scale 3" "$hzrt" render builtin --render-scale 3 \
    --size 32x18 --out "$tmp/g1"
expect map-only-extension 2 "no file name before it" "$hzrt" render builtin --mode adaptive --size 32x18 \
    --adaptive-map "$tmp/x/.png" --out "$tmp/g1"
expect marker-too-small 2 "\-\-marker: frame-id marker needs" "$hzrt" render builtin --marker --size 32x18 \
    --out "$tmp/g1"
ok usage-errors-nothing-made test ! -e "$tmp/g1"
# summary.json records the settings that change the image (the table walk is test_options), the motion blur
# also with --quiet, and rays per frame apart from the totals; report.json names the scene's settings.
expect settings-default 0 "" "$hzrt" render builtin --size 32x18 --frames 2 --threads 2 --quiet --out "$tmp/s0"
expect settings-changed 0 "" "$hzrt" render builtin --size 32x18 --frames 2 --threads 2 --shutter 1 \
    --transparency std --quiet --out "$tmp/s1"
expect report-scene 0 "" "$hzrt" latency --virtual --source sim --render scene --render-model const:1ms --frames 40 \
    --size 32x18 --render-scale 2 --threads 2 --quiet --out "$tmp/l9"
if command -v python3 >/dev/null 2>&1; then
    python3 - "$tmp/s0/summary.json" "$tmp/s1/summary.json" "$tmp/l9/report.json" <<'PYEOF' &&
import json, sys
a, b, r = (json.load(open(p)) for p in sys.argv[1:])
assert a["settings"] != b["settings"], a["settings"]
assert b["settings"]["shutter"] == 1 and b["settings"]["transparency"] == "std", b["settings"]
assert a["settings"]["shutter"] == 0 and a["settings"]["transparency"] == "exact", a["settings"]
assert b["motion_blur"]["time_keys"] >= 2 and "motion_blur" not in a
assert "per_frame" not in b["rays"] and b["rays_per_frame"]["total"] * 2 == b["rays"]["total"], b["rays_per_frame"]
assert r["scene"] == {"file": "builtin", "mode": "tdense", "render_size": [16, 9], "render_scale": 2,
                      "threads": 2}, r["scene"]
PYEOF
        pass=$((pass + 1)) || { echo "  FAIL  cli settings-recorded"; fail=$((fail + 1)); }
    # A recorded trace with a scene renders the scene in real-time replay, in any mode.
    python3 - "$tmp/good.vcd" <<'PYEOF'
import sys
with open(sys.argv[1], "w") as f:
    f.write("$timescale 1 ns $end $var wire 1 ! v $end $enddefinitions $end\n#0 0!\n")
    for i in range(100):
        f.write("#%d 1!\n#%d 0!\n" % (2025764 + i * 4166667, 2025764 + i * 4166667 + 1000))
PYEOF
    expect trace-scene-full 0 "" "$hzrt" latency --source "vcd:$tmp/good.vcd" --render scene --mode full \
        --size 32x18 --threads 2 --quiet --out "$tmp/l10"
    python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['frames'] > 0 and d['mode'] == 'full'" \
        "$tmp/l10/summary.json" && pass=$((pass + 1)) ||
        { echo "  FAIL  cli trace-scene-renders"; fail=$((fail + 1)); }
    # Messages: a CSV that starts with a byte-order mark reads; a bad time shows its invisible bytes.
    python3 - "$tmp/bom.csv" "$tmp/nbsp.csv" <<'PYEOF'
import sys
rows = "".join("%d\n" % (2025764 + i * 4166667) for i in range(100))
open(sys.argv[1], "wb").write(b"\xef\xbb\xbf" + rows.encode())
open(sys.argv[2], "wb").write(b"4166667\xc2\xa0\n")
PYEOF
    expect csv-byte-order-mark 0 "" "$hzrt" latency --source "csv:$tmp/bom.csv" --quiet --out "$tmp/l11"
    expect csv-invisible-bytes 68 "time '4166667\\\\xc2\\\\xa0'" "$hzrt" latency --source "csv:$tmp/nbsp.csv" \
        --out "$tmp/l12"
fi
expect drm-not-a-device 74 "not a DRM device" "$hzrt" latency --sink drm:/dev/null --frames 5 --out "$tmp/m1"
if "$hzrt" board | grep -q '^board      host-sim'; then
    expect display-sink-host-sim 0 "display sink none" "$hzrt" latency --help
fi
errtime=$(dirname "$hzrt")/hzerrtime
if [ -x "$errtime" ]; then
    expect errtime-names-charts 0 "1 chart (synthetic.svg)" "$errtime" --scene synthetic --size 16x16 --frames 8 \
        --warmup 1 --methods supersample --cache "$tmp/etc" --out "$tmp/eto"
    # Its command line comes from its option table: refusals name the option and the reason, status 2, before
    # anything runs; the help shows the table's limits.
    expect errtime-unknown-option 2 "^hzerrtime: unknown option '--fast' (try hzerrtime --help)" "$errtime" --fast
    expect errtime-missing-value 2 "^hzerrtime: --frames needs a value N" "$errtime" --out "$tmp/etx" --frames
    expect errtime-frames-range 2 "^hzerrtime: --frames: 0 is outside \[1, 1000000\]" "$errtime" --frames 0 \
        --out "$tmp/etx"
    expect errtime-shutter-range 2 "^hzerrtime: --shutter: '1.5' is not a fraction in (0, 1\]" "$errtime" \
        --shutter 1.5 --out "$tmp/etx"
    expect errtime-size-range 2 "^hzerrtime: --size: 8x8: width and height must lie in \[11, " "$errtime" \
        --size 8x8 --out "$tmp/etx"
    expect errtime-stray-argument 2 "^hzerrtime: unexpected argument 'synthetic'" "$errtime" synthetic
    expect errtime-search-needs-adaptive 2 "^hzerrtime: --adaptive-search: scene synthetic has no adaptive method" \
        "$errtime" --scene synthetic --adaptive-search --out "$tmp/etx"
    expect errtime-search-left-out 2 "^hzerrtime: --adaptive-search: scene sponza has no adaptive method to search" \
        "$errtime" --scene sponza --methods full-frame,taa --adaptive-search --out "$tmp/etx"
    ok errtime-refusals-ran-nothing sh -c "! [ -e \"$tmp/etx\" ]"
    expect errtime-help-limits 0 "--refresh HZ .*\[1..960\]" "$errtime" --help
    expect errtime-list 0 "^synthetic: " "$errtime" --list
fi
# First runs: a tdense render without --frames is one complete image (4 frames); fewer frames say why the image
# is partly filled in; a short latency run is "too short to judge a lock"; limits are in --help.
expect first-run-complete 0 "frames       4 at a simulated" "$hzrt" render builtin --size 64x36 --threads 2 \
    --out "$tmp/fr"
ok first-run-no-partial-note sh -c "! grep -q 'partly filled' \"$tmp/fr/summary.json\""
expect one-tdense-frame-note 0 "partly filled in" "$hzrt" render builtin --size 64x36 --frames 1 --threads 2 \
    --out "$tmp/fr1"
expect latency-too-short 3 "too short to judge a lock" "$hzrt" latency --virtual --source sim --hz 60 \
    --render-model const:5ms --frames 8 --out "$tmp/ts"
ok latency-too-short-json grep -q '"verdict": "too short"' "$tmp/ts/report.json"
expect help-size 0 "\[8..8192 a side\]" "$hzrt" render --help
expect help-frames 0 "at most 100000 with --source offline" "$hzrt" render --help
expect help-hz 0 "\[0..1000\]" "$hzrt" render --help
expect help-normal-angle 0 "\[0..90\] (only in adaptive mode)" "$hzrt" render --help
expect help-ordering-modes 0 "(only in tdense mode)" "$hzrt" render --help
expect adaptive-shutter 0 "motion blur  shutter 0.5" "$hzrt" render builtin --mode adaptive --shutter 0.5 \
    --adaptive-bilinear --size 32x18 --threads 2 --out "$tmp/as"
expect grammar-frames-timed 0 "(1 frame timed)" "$hzrt" render builtin --size 32x18 --frames 2 --threads 2 \
    --out "$tmp/gr"
ok render-rigid-refit-none sh -c "\"$hzrt\" render builtin --size 32x18 --frames 3 --threads 2 --shutter 0.5 --rigid refit --out \"$tmp/rigid2\" | grep -q 'motion blur' && ! \"$hzrt\" render builtin --size 32x18 --frames 3 --threads 2 --shutter 0.5 --rigid refit --out \"$tmp/rigid2\" | grep -q 'in object space'"
expect grammar-refit 0 "2 time keys, 1 refit, 0 rebuilds" "$hzrt" render builtin --size 32x18 --frames 2 \
    --threads 2 --shutter 0.5 --out "$tmp/gr"
expect render-segments-summary 0 "every-key motion segments: 2.00 key box sets per node of 2 keys" "$hzrt" render \
    builtin --size 32x18 --frames 2 --threads 2 --shutter 0.5 --rigid refit --motion-segments every-key --out "$tmp/gr"
expect info-kept-left-out 0 "^kept         motion vectors" "$hzrt" info builtin
ok info-no-double-negative sh -c "! \"$hzrt\" info builtin | grep -q 'left out .*: yes'"

# hzbench: a missing scene is named before anything is measured; its command line comes from its option table
# (refusals name the option and the reason, status 2, before anything is measured; the help shows the limits).
if [ -n "$hzbench" ]; then
    expect bench-missing-scene 73 "scene 'dragon' is missing: $tmp/noscenes/dragon.hzb" \
        "$hzbench" --only accel --scenes "$tmp/noscenes" --scene dragon --rounds 1
    expect bench-unknown-option 2 "^hzbench: unknown option '--fast' (try hzbench --help)" "$hzbench" --fast
    expect bench-missing-value 2 "^hzbench: --csv needs a value FILE" "$hzbench" --only kernels --csv
    expect bench-rounds-range 2 "^hzbench: --rounds: 16 is outside \[1, 15\]" "$hzbench" --rounds 16
    expect bench-only-word 2 "^hzbench: --only: 'kernel' is not kernels, accel, tdense" "$hzbench" --only kernel
    expect bench-interval-range 2 "^hzbench: --motion-interval: '0' is not a number of seconds in (0, 10\]" \
        "$hzbench" --motion-interval 0
    expect bench-budget-range 2 "^hzbench: --motion-budget: '5' is not a fraction of the triangles in \[0, 4\]" \
        "$hzbench" --only motion --motion-budget 5
    expect bench-budget-count 2 "^hzbench: --motion-budget: at most 6 budgets" "$hzbench" --only motion \
        $(for k in 1 2 3 4 5 6 7; do printf -- '--motion-budget 0.%s ' $k; done)
    expect bench-leaf-range 2 "^hzbench: --motion-leaf: 0 is outside \[1, [48]\]" "$hzbench" --only motion \
        --motion-leaf 0
    expect bench-scene-count 2 "^hzbench: --scene: at most 16 scenes" "$hzbench" --only accel \
        $(for k in 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17; do printf -- '--scene s%s ' $k; done)
    expect bench-help-limits 0 "--realtime-frames N .*\[1..512\]" "$hzbench" --help
    # Every group of `make bench` fits this board's arenas with the scenes it measures (checked from the plans,
    # nothing built), and the check refuses a group that would not: a frame no frame arena holds.
    if [ -n "${HZ_SCENES_DIR:-}" ]; then
        expect bench-check-fit 0 "^fit: [0-9]* checks, 0 do not fit" "$hzbench" --check-fit --scenes "$HZ_SCENES_DIR"
        # --check-fit checks the MSBVH at every split budget the motion table builds (the bound grows with the
        # budget, so checking the default one alone passed tables that then skipped their largest budget).
        ok bench-fit-budgets sh -c '"$0" --only motion --scenes "$1" --motion-scene tentacles --motion-sweep none \
            --check-fit | grep -c "^fit motion  *tentacles  *native msbvh \(0.25\|0.5\|1\|4\), 3 keys" | grep -qx 4' \
            "$hzbench" "$HZ_SCENES_DIR"
        # The accel group times the native binned SAH build (spatial splits off) next to Embree's medium build:
        # its time, and where Embree is built in, the ratio of the two in the CSV and the summary's binned-1 column.
        expect bench-accel-binned 0 "^build    native binned SAH (no spatial splits) 1 thread [0-9.]* s, SAH [0-9.]*" \
            env HZ_BENCH_ONLY=primary:tile-256 "$hzbench" --only accel --scenes "$HZ_SCENES_DIR" --scene dragon-res4 \
            --rounds 1 --threads 1 --size 32x32 --accel-csv "$tmp/acc.csv"
        ok bench-accel-binned-csv awk -F, '$3 == "build" && $5 == "native binned" && $6 > 0 { t = 1 }
            $3 == "build" && $5 == "embree medium" && $6 > 0 { e = 1 }
            $3 == "build" && $5 == "ratio native binned/embree medium" && $6 > 0 { r = 1 }
            END { exit !(t && (!e || r)) }' "$tmp/acc.csv"
        # The motion-size sweep: a missing sweep scene is named before anything is measured; on the skinned
        # tentacles (smooth motion) the sweep writes 7 intervals x 3 BVHs x 2 secondary rays, the interpolated BVH
        # is its own 100%, and for the short intervals triangles move twice as far when the shutter is twice as
        # long (a path over a short stretch of smooth motion grows with its duration).
        expect bench-sweep-missing 73 "^hzbench: bench: --motion-sweep: scene 'nosuch' is missing" "$hzbench" \
            --only motion --scenes "$HZ_SCENES_DIR" --motion-scene tentacles --motion-sweep nosuch
        expect bench-sweep 0 "^motion-size sweep on tentacles" "$hzbench" --only motion --scenes "$HZ_SCENES_DIR" \
            --motion-scene tentacles --motion-sweep tentacles --rounds 1 --motion-size 48x48 --motion-budget 1 \
            --motion-csv "$tmp/mo.csv"
        ok bench-sweep-csv awk -F, 'NR == 1 { ok = $4 == "motion_over_size_median" && $10 == "isect_avg_pct_interp"; next }
            { n++ }
            $6 == "interp" && $10 != "100.0" { ok = 0 }
            $2 != last { if (last != "" && !($4 > med)) ok = 0; if (last != "" && k < 3 && ($4 < 1.8 * med || $4 > 2.2 * med)) ok = 0
                         if (last != "") k++; last = $2; med = $4 }
            END { exit !(ok && n == 42) }' "$tmp/mo-sweep.csv"
        # Leaf sizes on the sweep scene: 3 leaf sizes x (msbvh at the one budget, interp) x 2 secondary rays, each
        # interpolated BVH its own 100% and 1.00x, and two triangles per leaf intersect fewer per ray than the
        # default leaves (hits equal to the first BVH's, or the run fails).
        ok bench-leaf-sizes awk -F, 'NR == 1 { ok = $2 == "leaf_max" && $14 == "render_vs_interp"; next }
            { n++; seen[$2]++ }
            $3 == "interp" && ($11 != "100.0" || $14 != "1.000") { ok = 0 }
            $3 == "interp" && $5 == "shadow" { isect[$2] = $9 }
            END { exit !(ok && n == 12 && seen[2] == 4 && seen[4] == 4 && isect[2] > 0 && isect[2] < isect[8]) }' \
            "$tmp/mo-leaf.csv"
        # --motion-leaf: every native BVH with leaves of at most N triangles, said on the table's first line; on
        # the tentacles two per leaf test fewer triangles per ray than the default SIMD-width leaves.
        expect bench-leaf 0 "^native leaves of at most 2 triangles" "$hzbench" --only motion --scenes "$HZ_SCENES_DIR" \
            --motion-scene tentacles --motion-sweep none --rounds 1 --motion-size 48x48 --motion-budget 1 \
            --motion-leaf 2 --motion-csv "$tmp/mo2.csv"
        ok bench-leaf-isect awk -F, 'FNR == 1 { next } $2 == "interp" && $16 == "shadow" { v[FILENAME] = $8 }
            END { exit !(v[ARGV[1]] > 0 && v[ARGV[2]] > 0 && v[ARGV[2]] < v[ARGV[1]]) }' "$tmp/mo.csv" "$tmp/mo2.csv"
        # The adaptive group, small: per scene fixed 9 spp (9 camera rays a pixel), adaptive at three tau and at tau 1
        # focused on the objects at the centre of the view, which takes no more rays than tau 1 unfocused (the focus
        # only takes attribute disagreements away, so every threshold can only grow) and names its objects.
        expect bench-adaptive 0 "focus objects: [0-9]" "$hzbench" --only adaptive --scenes "$HZ_SCENES_DIR" \
            --adaptive-size 48x32 --rounds 1 --adaptive-csv "$tmp/ad.csv"
        ok bench-adaptive-csv awk -F, 'NR == 1 { ok = $11 == "focus_objects" && $13 == "focus_psnr_srgb8_db"; next }
            { n++ }
            $2 == "full-9spp" && $8 != "9.0000" { ok = 0 }
            $2 == "adaptive" && $3 == "1.00" { r1[$1] = $8 }
            $2 == "adaptive-focus" && $4 != "" { f++; if (!($1 in r1) || $8 > r1[$1] || $11 == "" || !($12 > 0)) ok = 0 }
            END { exit !(ok && n >= 5 && n % 5 == 0 && f >= 1) }' "$tmp/ad.csv"
    fi
    expect bench-check-fit-refuses 66 "tdense + taa 8192x8192 *frame .*DOES NOT FIT" "$hzbench" --check-fit \
        --only tdense --tdense-size 8192x8192
fi

echo "  ok    cli                    $pass passed$( [ $fail -ne 0 ] && echo ", $fail failed")"
echo "cli $pass $fail 0" >"$results/cli.res"
