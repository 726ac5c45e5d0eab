#!/bin/sh
# fetch.sh DIR ARCH... — Debian 13 ("trixie") libgpiod-dev (libgpiod 2.x) for each ARCH (amd64, arm64), fetched
# with `apt-get download` through a private apt configuration under DIR and unpacked into DIR/ARCH (headers,
# static library, pkg-config file). Nothing on the system changes: no sources entry, no install, no dpkg state.
# The packages' shared libraries need a newer glibc than Debian 12's: only the headers and, where it links, the
# static library are used. Exit status 0 when every ARCH was unpacked, else 1 with the reason on stderr (CI's
# `make test` records that as a failed check, never a skip).
set -u
mkdir -p "$1" || exit 1
dir=$(cd "$1" && pwd) # apt reads relative Dir:: paths against its own directories: absolute only
shift
mirror=${GPIOD2_MIRROR:-$(sed -n 's/^URIs: *\(http[^ ]*debian\)$/\1/p' /etc/apt/sources.list.d/debian.sources 2>/dev/null | head -n 1)}
[ -n "$mirror" ] || mirror=http://deb.debian.org/debian
keyring=/usr/share/keyrings/debian-archive-keyring.gpg
apt="$dir/apt"
mkdir -p "$apt/lists/partial" "$apt/cache/archives/partial" "$dir/debs"
echo "deb [signed-by=$keyring] $mirror trixie main" >"$apt/sources.list"
: >"$apt/status"
archs=amd64,arm64 # both lists at once: one update serves every board
opts="-o Dir::Etc::SourceList=$apt/sources.list -o Dir::Etc::SourceParts=/dev/null -o Dir::State::Lists=$apt/lists
      -o Dir::State::Status=$apt/status -o Dir::Cache=$apt/cache -o APT::Architectures=$archs
      -o APT::Architecture=amd64 -o Debug::NoLocking=1 -o Acquire::Languages=none"
# shellcheck disable=SC2086 # opts is a list of options on purpose
if [ ! -f "$apt/updated" ]; then
    # apt-get update can exit 0 with nothing fetched (an unreachable mirror is only a warning): check the lists.
    if ! apt-get $opts -qq update >"$apt/update.log" 2>&1 ||
        [ -z "$(find "$apt/lists" -maxdepth 1 -name '*trixie*Packages*' 2>/dev/null | head -n 1)" ]; then
        echo "gpiod2: cannot fetch Debian trixie's package lists from $mirror (see $apt/update.log):" \
            "$(grep -m 1 -E '^(E|W):' "$apt/update.log")" >&2
        exit 1
    fi
    touch "$apt/updated"
fi
status=0
for a in "$@"; do
    if [ ! -f "$dir/$a/.ok" ]; then
        rm -rf "$dir/$a"
        # shellcheck disable=SC2086
        (cd "$dir/debs" && apt-get $opts -qq download "libgpiod-dev:$a") >"$apt/download-$a.log" 2>&1 ||
            { echo "gpiod2: apt-get download libgpiod-dev:$a from trixie failed (see $apt/download-$a.log)" >&2
              status=1; continue; }
        deb=$(ls "$dir/debs"/libgpiod-dev_*_"$a".deb 2>/dev/null | tail -n 1)
        mkdir -p "$dir/$a" && dpkg-deb -x "$deb" "$dir/$a" ||
            { echo "gpiod2: cannot unpack $deb" >&2; status=1; continue; }
        # Point the pkg-config file at the unpacked tree; drop the shared-library links (their targets are in
        # libgpiod3, which needs trixie's glibc), so -lgpiod finds the static library.
        sed -i "s|^prefix=.*|prefix=$(cd "$dir/$a" && pwd)/usr|" "$dir/$a"/usr/lib/*/pkgconfig/libgpiod.pc
        find "$dir/$a/usr/lib" -name 'libgpiod*.so' -type l -delete
        ver=$(dpkg-deb -f "$deb" Version)
        echo "$ver" >"$dir/$a/.ok"
    fi
done
exit $status
