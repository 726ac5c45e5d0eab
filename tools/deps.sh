#!/bin/sh
# Installs the Debian packages given as arguments when they are missing.
#   pkg        required: a failed install stops with an error
#   ?pkg       optional: a failed install prints a warning and the build goes on without it
#   pkg:arm64  a foreign-architecture package: adds the arm64 architecture to dpkg first
# As root it runs apt-get; otherwise it prints the exact apt-get line and fails, so nothing is half-done.
set -u

missing=""
optional_missing=""
for spec in "$@"; do
    opt=0
    pkg=$spec
    case $spec in \?*) opt=1; pkg=${spec#\?} ;; esac
    status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
    case $status in
        *"install ok installed"*) ;;
        *) if [ $opt = 1 ]; then optional_missing="$optional_missing $pkg"; else missing="$missing $pkg"; fi ;;
    esac
done
[ -z "$missing$optional_missing" ] && exit 0

if [ "$(id -u)" != 0 ]; then
    if [ -n "$missing" ]; then
        echo "deps: missing Debian packages:$missing" >&2
        needs_arm64=$(echo "$missing" | grep -c ':arm64' || true)
        [ "$needs_arm64" != 0 ] && echo "  sudo dpkg --add-architecture arm64 && sudo apt-get update" >&2
        echo "  sudo apt-get install -y --no-install-recommends$missing" >&2
        exit 1
    fi
    echo "deps: warning: optional packages missing (features that need them are left out):$optional_missing" >&2
    exit 0
fi

export DEBIAN_FRONTEND=noninteractive
updated=0
update() {
    echo "deps: apt-get update"
    apt-get update -qq >/dev/null || { echo "deps: apt-get update failed" >&2; exit 1; }
    updated=1
}
install() { apt-get install -y -qq --no-install-recommends "$@" >/dev/null; }

case "$missing$optional_missing" in
    *:arm64*)
        if ! dpkg --print-foreign-architectures | grep -qx arm64; then
            echo "deps: dpkg --add-architecture arm64"
            dpkg --add-architecture arm64 || exit 1
            update
        fi ;;
esac
# Fresh machines have no package lists; stale lists show up as a failed install, retried once after an update.
[ $updated = 1 ] || [ -n "$(find /var/lib/apt/lists -maxdepth 1 -name '*Packages*' 2>/dev/null | head -n 1)" ] || update
install_retry() {
    install "$@" && return 0
    [ $updated = 1 ] && return 1
    update
    install "$@"
}
if [ -n "$missing" ]; then
    echo "deps: apt-get install$missing"
    install_retry $missing || { echo "deps: could not install:$missing" >&2; exit 1; }
fi
for pkg in $optional_missing; do
    echo "deps: apt-get install $pkg (optional)"
    install_retry "$pkg" 2>/dev/null ||
        echo "deps: warning: optional package $pkg could not be installed; what needs it is left out" >&2
done
exit 0
