#!/bin/sh
# collect.sh — from the development machine: copy hzrt and capture.sh to a board over ssh, run a capture
# there, fetch the results back and summarise them.
#
#   collect.sh [-B BOARD] [-s SECONDS] [-o DIR] [-n] user@board-host [-- extra `hzrt latency` options]
#
#   -B BOARD    which build to copy: build/BOARD/bin/hzrt (default rpi4; build it with make BOARD=...)
#   -s SECONDS  capture length (default 30)
#   -o DIR      where the results land here (default out/latency-runs)
#   -n          edges only (no rendering)
# Needs ssh and scp with key login; the remote user must be allowed --rt and the GPIO/framebuffer nodes.
set -u
board=rpi4 seconds=30 dest=out/latency-runs edges=""
while [ $# -gt 0 ]; do
    case $1 in
        -B) board=$2; shift 2 ;;
        -s) seconds=$2; shift 2 ;;
        -o) dest=$2; shift 2 ;;
        -n) edges=-n; shift ;;
        -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        -*) echo "collect.sh: unknown option '$1' (try -h)" >&2; exit 2 ;;
        *) break ;;
    esac
done
[ $# -ge 1 ] || { echo "collect.sh: which board? (user@host)" >&2; exit 2; }
target=$1
shift
[ "${1:-}" = "--" ] && shift
here=$(cd "$(dirname "$0")" && pwd)
bin=build/$board/bin/hzrt
[ -x "$bin" ] || { echo "collect.sh: no $bin: run make BOARD=$board first" >&2; exit 2; }
run="hzrt-latency-$(date +%Y%m%d-%H%M%S)"
ssh "$target" "mkdir -p /tmp/$run" || exit 1
scp -q "$bin" "$here/capture.sh" "$target:/tmp/$run/" || exit 1
# shellcheck disable=SC2029 # the remote command is built here on purpose
ssh -t "$target" "cd /tmp/$run && sh ./capture.sh -b ./hzrt -s $seconds -o $run $edges -- $*"
rc=$?
mkdir -p "$dest"
scp -q "$target:/tmp/$run/$run.tar.gz" "$dest/" && tar -xzf "$dest/$run.tar.gz" -C "$dest" || exit 1
ssh "$target" "rm -rf /tmp/$run"
sh "$here/summarise.sh" "$dest/$run"
exit $rc
