#!/bin/sh
# run.sh — the VM test tier (make vmtest): boots Debian's arm64 kernel under qemu-system-aarch64 (virt machine,
# software emulation), runs the AArch64 unit tests and the device checks inside it, pulses the PL061 GPIO
# line 3 from the monitor when the guest asks, and turns the guest's console into the same result files
# test/run-tests.sh writes (one .res per program), so test/summary.sh counts them.
#
#   run.sh RESULTS_DIR CACHE_DIR INIT HZRT_STATIC DEVICE_TEST UNIT_TEST...
#
# RESULTS_DIR  receives <program>.log and <program>.res, console.log and the kernel's identity
# CACHE_DIR    keeps the kernel .deb and its unpacked tree between runs (build/vm/kernel)
# INIT         the static AArch64 init (test/vm/init.c)
# HZRT_STATIC  the static AArch64 hzrt (put in /bin; the device test may run it)
# DEVICE_TEST  test_vm_devices (dynamic AArch64, cmocka)
# UNIT_TEST    the AArch64 unit test binaries of `make test` (dynamic; their libraries are copied in)
#
# VM_ENV (optional): NAME=VALUE words the tests get in the guest, as `make test` exports them on the host
# (HZ_SCENES_DIR=...). A VALUE that is a host directory is shared into the guest read-only (virtio-9p) at
# the same path, so tests that read data files find them where the host tests do.
# A guest that does not finish within VM_LIMIT_S (default 600 s: a hang guard, generous for loaded 2-core machines) is killed and counted as a failure.
set -u
results=$1 cache=$2 init=$3 hzrt=$4 devtest=$5
shift 5
limit=${VM_LIMIT_S:-600}
pulses_gap=${VM_PULSE_GAP_S:-0.4}
label=vm-aarch64
mkdir -p "$results" "$cache"
results=$(cd "$results" && pwd) cache=$(cd "$cache" && pwd)
rm -f "$results"/*.res "$results"/*.log

fail_tier() { # record one failure for the whole tier with a reason, then stop
    echo "  FAIL  $label: $*"
    echo "$label/vm-tier 0 1 0" >"$results/vm-tier.res"
    exit 0
}

for tool in qemu-system-aarch64 cpio gzip dpkg-deb modinfo; do
    command -v $tool >/dev/null 2>&1 || fail_tier "$tool is missing (make deps installs qemu-system-arm, cpio, kmod)"
done

# ---- kernel: Debian's current arm64 image, downloaded once into the cache ----
pkg=$(apt-cache depends linux-image-arm64:arm64 2>/dev/null |
    sed -n 's/.*Depends: \(linux-image-[0-9][^ :]*\).*/\1/p' | head -n 1)
deb=""
if [ -n "$pkg" ]; then
    deb=$(ls "$cache"/"$pkg"_*_arm64.deb 2>/dev/null | head -n 1)
    if [ -z "$deb" ]; then
        echo "  vm: apt-get download $pkg:arm64 (cached in $cache)"
        (cd "$cache" && apt-get download "$pkg:arm64" >/dev/null 2>"$results/apt-download.log") || true
        deb=$(ls "$cache"/"$pkg"_*_arm64.deb 2>/dev/null | head -n 1)
    fi
fi
if [ -z "$deb" ]; then
    # No package lists for arm64, or no network: any kernel cached earlier will do.
    deb=$(ls -t "$cache"/linux-image-*_arm64.deb 2>/dev/null | head -n 1)
    why=$(tail -n 1 "$results/apt-download.log" 2>/dev/null)
    [ -n "$deb" ] || fail_tier "no arm64 kernel: linux-image-arm64:arm64 depends on '${pkg:-nothing}' and apt-get \
download failed ($why); try: dpkg --add-architecture arm64 && apt-get update"
fi
tree="$cache/$(basename "$deb" .deb)"
if [ ! -d "$tree/boot" ]; then
    rm -rf "$tree.tmp" && mkdir -p "$tree.tmp" && dpkg-deb -x "$deb" "$tree.tmp" && mv "$tree.tmp" "$tree" ||
        fail_tier "cannot unpack $deb"
fi
vmlinuz=$(ls "$tree"/boot/vmlinuz-* 2>/dev/null | head -n 1)
kver=${vmlinuz##*/vmlinuz-}
moddir="$tree/lib/modules/$kver"
[ -f "$vmlinuz" ] && [ -d "$moddir" ] || fail_tier "$deb holds no kernel image and modules"

# ---- initramfs ----
stage=$(mktemp -d)
trap 'rm -rf "$stage"; [ -n "${qpid:-}" ] && kill "$qpid" 2>/dev/null' EXIT
mkdir -p "$stage/dev" "$stage/proc" "$stage/sys" "$stage/tmp" "$stage/bin" "$stage/tests" "$stage/modules" \
    "$stage/lib/aarch64-linux-gnu"
cp "$init" "$stage/init" && cp "$hzrt" "$stage/bin/hzrt" || fail_tier "missing $init or $hzrt"

# Modules: vivid and everything it depends on, dependencies first (modinfo -F depends, depth first).
: >"$stage/modules/order"
add_module() { # NAME [PARAMS]; `local` is not POSIX but dash, bash and busybox sh all have it
    local name=$1 params=${2:-} f dep
    grep -qx "$name.ko" "$stage/modules/order.names" 2>/dev/null && return 0
    f=$(find "$moddir" -name "$name.ko" | head -n 1)
    [ -n "$f" ] || { echo "HZVM: module $name not in $deb" >>"$results/initramfs.log"; return 1; }
    for dep in $(modinfo -F depends "$f" | tr ',' ' '); do
        add_module "$dep" || return 1
    done
    cp "$f" "$stage/modules/"
    echo "$name.ko" >>"$stage/modules/order.names"
    echo "$name.ko $params" >>"$stage/modules/order"
}
# vivid: one instance with an HDMI capture (video0), an HDMI output (video1) and a framebuffer (fb0).
add_module vivid "n_devs=1 node_types=0x10101 num_inputs=1 input_types=0x3 num_outputs=1 output_types=0x1" ||
    fail_tier "cannot collect vivid's modules from $deb (see $results/initramfs.log)"

# DRM: QEMU's virtio-gpu (virtio_pci, virtio-gpu and their dependencies) for the DRM/KMS sink check.
for m in virtio_pci virtio-gpu; do
    add_module $m || fail_tier "cannot collect $m from $deb (see $results/initramfs.log)"
done

# The tests' environment, and their data directories over virtio-9p (read-only, same paths as on the host).
# The screendump folder is one of them: the host writes QEMU's screendumps there for test_vm_drm to read.
: >"$stage/vm-env"
: >"$stage/vm-mounts"
share_args=""
nshare=0
screen="$results/screen"
rm -rf "$screen" && mkdir -p "$screen"
VM_ENV="${VM_ENV:-} HZ_VM_SCREEN_DIR=$screen"
for kv in ${VM_ENV:-}; do
    case $kv in *=*) ;; *) continue ;; esac
    echo "$kv" >>"$stage/vm-env"
    dir=${kv#*=}
    if [ -d "$dir" ]; then
        nshare=$((nshare + 1))
        share_args="$share_args -fsdev local,id=fs$nshare,path=$dir,security_model=none,readonly=on"
        share_args="$share_args -device virtio-9p-device,fsdev=fs$nshare,mount_tag=hz$nshare"
        echo "hz$nshare $dir" >>"$stage/vm-mounts"
    fi
done
if [ $nshare -gt 0 ]; then
    for m in virtio_mmio 9pnet_virtio 9p; do
        add_module $m || fail_tier "cannot collect the 9p modules from $deb (see $results/initramfs.log)"
    done
fi

# Programs, and the shared libraries they need (the multiarch arm64 ones the host ran them with).
: >"$stage/tests/list"
libs=""
for t in "$@" "$devtest"; do
    cp "$t" "$stage/tests/" || fail_tier "missing $t"
    echo "/tests/$(basename "$t")" >>"$stage/tests/list"
done
find_lib() {
    for d in /lib/aarch64-linux-gnu /usr/lib/aarch64-linux-gnu /usr/aarch64-linux-gnu/lib; do
        [ -e "$d/$1" ] && { echo "$d/$1"; return 0; }
    done
    return 1
}
todo=$(for t in "$stage"/tests/*; do [ -f "$t" ] && [ -x "$t" ] && echo "$t"; done)
seen=""
while [ -n "$todo" ]; do
    next=""
    for f in $todo; do
        for need in $(aarch64-linux-gnu-readelf -d "$f" 2>/dev/null | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
            case " $seen " in *" $need "*) continue ;; esac
            seen="$seen $need"
            src=$(find_lib "$need") || fail_tier "library $need (needed by $(basename "$f")) not found for arm64"
            cp -L "$src" "$stage/lib/aarch64-linux-gnu/$need"
            next="$next $stage/lib/aarch64-linux-gnu/$need"
        done
    done
    todo=$next
done
interp=$(find_lib ld-linux-aarch64.so.1) || fail_tier "no arm64 ld-linux-aarch64.so.1 (libc6:arm64)"
cp -L "$interp" "$stage/lib/ld-linux-aarch64.so.1"
initrd="$results/initrd.gz"
(cd "$stage" && find . | cpio -o -H newc 2>/dev/null | gzip -1 >"$initrd") || fail_tier "cannot pack the initramfs"

# ---- boot ----
log="$results/console.log"
mon="$results/monitor"
rm -f "$log" "$mon.in" "$mon.out"
mkfifo "$mon.in" "$mon.out" || fail_tier "mkfifo failed"
# shellcheck disable=SC2086 # share_args is a list of arguments
qemu-system-aarch64 -M virt -cpu cortex-a72 -smp 2 -m 1024 -display none -nic none -no-reboot $share_args \
    -device virtio-gpu-pci,xres=${VM_DRM_XRES:-320},yres=${VM_DRM_YRES:-240} \
    -kernel "$vmlinuz" -initrd "$initrd" -append "console=ttyAMA0 panic=-1 quiet" \
    -serial "file:$log" -monitor "pipe:$mon" >"$results/qemu.log" 2>&1 &
qpid=$!
# Keep the monitor's output drained (and its FIFOs open) for as long as qemu runs.
cat "$mon.out" >"$results/monitor.log" &
catpid=$!
exec 7>"$mon.in"
start=$(date +%s)
served=0
dumps=0
while kill -0 "$qpid" 2>/dev/null; do
    # Each "HZVM-SCREENDUMP name" asks for the displayed surface in $screen/name.ppm, then name.done.
    asked=$(grep -c '^HZVM-SCREENDUMP' "$log" 2>/dev/null)
    if [ "${asked:-0}" -gt $dumps ]; then
        dumps=$((dumps + 1))
        name=$(sed -n 's/^HZVM-SCREENDUMP \([A-Za-z0-9_-]*\).*/\1/p' "$log" | sed -n "${dumps}p")
        echo "screendump $screen/$name.ppm" >&7
        # The monitor writes the file before it answers; wait until its size holds still.
        prev=-1
        for i in 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20; do
            sleep 0.3
            size=$(stat -c %s "$screen/$name.ppm" 2>/dev/null || echo -1)
            [ "$size" -gt 0 ] && [ "$size" = "$prev" ] && break
            prev=$size
        done
        : >"$screen/$name.done"
    fi
    # Each "HZVM-GPIO-READY n" the guest prints asks for n pulses on line 3.
    asked=$(grep -c '^HZVM-GPIO-READY' "$log" 2>/dev/null)
    if [ "${asked:-0}" -gt $served ]; then
        served=$((served + 1))
        n=$(sed -n 's/^HZVM-GPIO-READY \([0-9]*\).*/\1/p' "$log" | sed -n "${served}p")
        sleep 0.3
        i=0
        while [ $i -lt "${n:-4}" ]; do
            echo system_powerdown >&7
            sleep "$pulses_gap"
            i=$((i + 1))
        done
    fi
    if [ $(($(date +%s) - start)) -ge "$limit" ]; then
        kill "$qpid" 2>/dev/null
        wait "$qpid" 2>/dev/null
        exec 7>&-
        kill "$catpid" 2>/dev/null
        fail_tier "the VM did not finish within $limit s (console: $log)"
    fi
    sleep 0.2
done
wait "$qpid"
qrc=$?
exec 7>&-
kill "$catpid" 2>/dev/null
qpid=""
elapsed=$(($(date +%s) - start))
grep -q '^HZVM-BOOT' "$log" 2>/dev/null ||
    fail_tier "the kernel did not start init (qemu exit $qrc; see $results/qemu.log, $log)"
echo "  vm: $(sed -n 's/^HZVM-BOOT //p' "$log" | tr -d '\r') ($deb), ${elapsed} s"
grep '^HZVM-MODULE-FAIL' "$log" | tr -d '\r' | sed 's/^/  vm: /'

# ---- results: one .res per program, counted like test/run-tests.sh does ----
status=0
for t in "$@" "$devtest"; do
    name=$(basename "$t")
    out="$results/$name.log"
    awk -v n="$name" '$0 ~ "^HZVM-BEGIN "n"\r?$" {on=1; next} $0 ~ "^HZVM-END "n" " {on=0} on' "$log" |
        tr -d '\r' >"$out"
    rc=$(sed -n "s/^HZVM-END $name \([0-9-]*\).*/\1/p" "$log" | tr -d '\r' | head -n 1)
    passed=$(sed -n 's/^\[  PASSED  \] \([0-9][0-9]*\) test.*/\1/p' "$out" | awk '{s+=$1} END {print s+0}')
    failed=$(sed -n 's/^\[  FAILED  \] \([0-9][0-9]*\) test.*/\1/p' "$out" | awk '{s+=$1} END {print s+0}')
    skipped=$(sed -n 's/^\[  SKIPPED \] \([0-9][0-9]*\) test.*/\1/p' "$out" | awk '{s+=$1} END {print s+0}')
    if [ -z "$rc" ]; then
        failed=$((failed + 1))
        echo "  $label: $name never finished (the VM stopped first); see $out"
    elif [ "$rc" -ne 0 ] && [ "$failed" -eq 0 ]; then
        failed=1
        echo "  $label: $name exited with status $rc without a test report; see $out"
    fi
    [ "${rc:-1}" = 0 ] && [ "$passed" -eq 0 ] && [ "$skipped" -eq 0 ] && failed=1
    if [ "$failed" -ne 0 ]; then
        status=1
        printf '  FAIL  %-18s %-28s %3d passed, %d failed\n' "$label" "$name" "$passed" "$failed"
        grep -E '^\[ +(ERROR|LINE|FAILED) +\]' "$out" | head -n 20 | sed 's/^/        /'
    else
        printf '  ok    %-18s %-28s %3d passed%s\n' "$label" "$name" "$passed" \
            "$( [ "$skipped" -ne 0 ] && echo ", $skipped skipped")"
    fi
    echo "$label/$name $passed $failed $skipped" >"$results/$name.res"
done
# The device checks' figures, for the log of make test.
grep '^  ' "$results/$(basename "$devtest").log" | sed 's/^/  vm:/'
grep -q '^HZVM-GPIO-MISSING' "$log" &&
    echo "  vm: GPIO checks FAILED, the port is missing: $(sed -n 's/^HZVM-GPIO-MISSING //p' "$log" | head -n 1)"
for t in "$@"; do
    case $(basename "$t") in test_vm_drm) grep '^  DRM' "$results/test_vm_drm.log" | sed 's/^/  vm:/' ;; esac
    case $(basename "$t") in test_vm_gpiod2) grep '^  ' "$results/test_vm_gpiod2.log" | sed 's/^/  vm (libgpiod 2):/' ;; esac
done
exit 0
