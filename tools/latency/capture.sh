#!/bin/sh
# capture.sh — on the board: run hzrt (the firmware) with v-sync captured on its GPIO input for a while, keep
# everything it measured, and print the summary.
#
#   capture.sh [-s SECONDS] [-o DIR] [-b HZRT] [-n] [-- extra `hzrt latency` options]
#
#   -s SECONDS  how long to run (default 30)
#   -o DIR      where the results go (default ./latency-<board>-<date>); packed as DIR.tar.gz as well
#   -b HZRT     the hzrt binary (default: ./hzrt, else hzrt on PATH)
#   -n          no rendering: capture and analyse the v-sync edges only (checks the wiring and the panel)
#
# Defaults follow the board hzrt was built for (`hzrt board`): its GPIO chip and line, its framebuffer. Extra
# options after -- go to `hzrt latency` (e.g. -- --source gpio:gpiochip0:17 --edge falling, or --sink v4l2:...).
# Runs with --rt (SCHED_FIFO, locked memory); run it as root or grant CAP_SYS_NICE and CAP_IPC_LOCK.
# Exit status: hzrt's (0 ok, 3 no lock, 75 no v-sync within the time-out, see `hzrt latency --help`).
set -u
seconds=30 out="" hzrt="" edges_only=0
while [ $# -gt 0 ]; do
    case $1 in
        -s) seconds=$2; shift 2 ;;
        -o) out=$2; shift 2 ;;
        -b) hzrt=$2; shift 2 ;;
        -n) edges_only=1; shift ;;
        --) shift; break ;;
        -h|--help) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "capture.sh: unknown option '$1' (try -h)" >&2; exit 2 ;;
    esac
done
if [ -z "$hzrt" ]; then
    if [ -x ./hzrt ]; then
        hzrt=./hzrt
    else
        hzrt=$(command -v hzrt) || { echo "capture.sh: no hzrt (give -b)" >&2; exit 2; }
    fi
fi
board=$("$hzrt" board | sed -n 's/^board *//p')
[ -n "$board" ] || { echo "capture.sh: $hzrt does not run here (wrong architecture?)" >&2; exit 2; }
[ -n "$out" ] || out="latency-$board-$(date +%Y%m%d-%H%M%S)"
mkdir -p "$out" || exit 1
{
    echo "date      $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "host      $(uname -a)"
    "$hzrt" board
    ls /dev/gpiochip* /dev/fb* /dev/video* 2>/dev/null | tr '\n' ' '
    echo
} >"$out/meta.txt"
set -- --rt --seconds "$seconds" --out "$out" "$@"
if [ $edges_only = 1 ]; then
    set -- --edges-only "$@"
else
    case " $* " in *" --sink "*) ;; *) set -- --sink fbdev "$@" ;; esac
fi
echo "capture.sh: $hzrt latency $*" | tee -a "$out/meta.txt"
"$hzrt" latency "$@" | tee "$out/summary.txt"
rc=$?
# tee hides hzrt's status in plain sh: ask the report whether it was written.
[ -f "$out/report.json" ] || rc=1
tar -czf "$out.tar.gz" "$out" && echo "capture.sh: results in $out/ and $out.tar.gz"
exit $rc
