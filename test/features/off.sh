#!/bin/sh
# The all-off build (make FEATURES_OFF=all: no textures, mirrors, transparency or motion) renders a scene that
# needs none of them, and refuses, by name, a scene or an option that needs each: exit status 72 (64 + the
# "unsupported" status), the feature, its switch and the boards that have it. Its firmware really lacks the
# features' code (symbols that only they use are gone).
#   off.sh RESULTS_DIR HZRT SCENES_DIR
set -u
results=$1 hzrt=$2 scenes=$3
mkdir -p "$results"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0

# expect NAME STATUS PATTERN CMD...: exit status STATUS and every |-separated part of PATTERN in the output.
expect() {
    name=$1 want=$2 pattern=$3
    shift 3
    out=$("$@" 2>&1)
    got=$?
    bad=""
    [ "$got" != "$want" ] && bad="exit status $got, expected $want"
    old_ifs=$IFS IFS='|'
    for p in $pattern; do
        [ -z "$bad" ] && ! printf '%s\n' "$out" | grep -qF -- "$p" && bad="output lacks '$p'"
    done
    IFS=$old_ifs
    if [ -n "$bad" ]; then
        echo "  FAIL  features-off $name: $bad"
        printf '%s\n' "$out" | head -n 5 | sed 's/^/        /'
        fail=$((fail + 1))
    else
        pass=$((pass + 1))
    fi
}

r() { "$hzrt" render "$@" --size 32x18 --quiet --out "$tmp/out"; }
boards="boards with it: aarch64-generic, host-sim"

expect is-all-off 0 "textures=0 mirrors=0 transparency=0 motion=0" "$hzrt" board
# a scene that needs none of them renders, in every mode
for m in tdense taa full adaptive; do
    expect "plain-scene-$m" 0 "" r "$scenes/CornellBox-Original.hzb" --mode "$m"
done
[ -s "$tmp/out/last.png" ] || [ -s "$tmp/out/last.ppm" ] || { echo "  FAIL  features-off plain-scene: no last frame"; fail=$((fail + 1)); }
# a mirror scene renders without its reflections only when asked to (no bounces)
expect mirror-scene-no-bounces 0 "" r "$scenes/CornellBox-Mirror.hzb" --bounces 0
# each feature a scene needs, refused by name
expect scene-mirrors 72 "the scene needs mirrors|HZ_FEATURE_MIRRORS 0|$boards" r "$scenes/CornellBox-Mirror.hzb"
expect scene-motion 72 "the scene needs motion (moving objects)|HZ_FEATURE_MOTION 0|$boards" r "$scenes/BoxAnimated.hzb"
expect scene-transparency-textures 72 \
    "the scene needs transparency (blended surfaces)|HZ_FEATURE_TRANSPARENCY 0|$boards|it also needs textures" \
    r "$scenes/AlphaBlendModeTest-small.hzb"
expect builtin-every-feature 72 "builtin: the scene needs transparency|it also needs textures, mirrors, motion" r builtin
# each option that needs one, refused by name
expect option-shutter 72 "motion blur (shutter > 0) needs motion|HZ_FEATURE_MOTION 0" \
    r "$scenes/CornellBox-Original.hzb" --shutter 0.5
expect option-transparency 72 "a stochastic transparency method needs transparency|HZ_FEATURE_TRANSPARENCY 0" \
    r "$scenes/CornellBox-Original.hzb" --mode taa --transparency std

# The code is gone: functions only the features use are not in the firmware.
if command -v nm >/dev/null; then
    syms=$(nm "$hzrt" | awk '{ print $NF }')
    for f in hz_transp_keep hz_transp_shadow_blocks blend_alpha k_sample; do
        if printf '%s\n' "$syms" | grep -qx "$f"; then
            echo "  FAIL  features-off code-left-out: $f is in the all-off firmware"
            fail=$((fail + 1))
        else
            pass=$((pass + 1))
        fi
    done
fi

echo "  ok    features-off           $pass passed$( [ $fail -ne 0 ] && echo ", $fail failed")"
echo "features-off $pass $fail 0" >"$results/features-off.res"
