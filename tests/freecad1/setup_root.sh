#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Makes (or reuses) a Debian 13 "trixie" root with FreeCAD 1.0 and the test tools, for the
# FreeCAD 1.0 suite (tests/freecad1/run.sh).  As root.  The root is kept in
# $MFGEOM_FREECAD1_ROOT (default /var/cache/mfgeom/freecad1-trixie) and reused when its
# stamp says it was made from the same package list; debootstrap takes its packages from
# the mirror apt already uses (/etc/apt/sources.list.d/), the only archive this machine reaches.
set -euo pipefail
ROOTFS=${MFGEOM_FREECAD1_ROOT:-/var/cache/mfgeom/freecad1-trixie}
# what the FreeCAD 1.0 suites need inside the root: FreeCAD, the build of the library,
# the binding's Python modules, and Xvfb for the GUI tests
PACKAGES="freecad python3-numpy python3-pytest cmake gcc make libc6-dev xvfb xauth
  xfonts-base procps git python3-shapely"
PACKAGES=$(echo $PACKAGES)   # one line: it goes into a command line
STAMP_TEXT="mfgeom freecad1 root: $PACKAGES"

if [ -f "$ROOTFS/.mfgeom-stamp" ] && [ "$(cat "$ROOTFS/.mfgeom-stamp")" = "$STAMP_TEXT" ]; then
  echo "freecad1 root: reusing $ROOTFS"
  exit 0
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "freecad1 root: $ROOTFS is missing; making it needs root (debootstrap, chroot)" >&2
  exit 1
fi

# A root made from an older package list: add what the list gained (minutes, not the
# debootstrap and FreeCAD of a new root).
in_root() {  # in_root DIR COMMAND: COMMAND in DIR with /proc and /dev bound, in its own mount namespace
  unshare --mount --propagation private /bin/sh -c 'mount --bind /proc "$0/proc" &&
    mount --rbind /dev "$0/dev" && exec chroot "$0" /bin/sh -c "$1"' "$1" "$2"
}
if [ -f "$ROOTFS/.mfgeom-stamp" ]; then
  echo "freecad1 root: updating $ROOTFS to the package list"
  if in_root "$ROOTFS" "apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
       apt-get install -y -qq --no-install-recommends $PACKAGES && apt-get clean" >>"$ROOTFS.log" 2>&1; then
    echo "$STAMP_TEXT" > "$ROOTFS/.mfgeom-stamp"
    echo "freecad1 root: ready ($(du -sh "$ROOTFS" | cut -f1))"
    exit 0
  fi
  echo "freecad1 root: updating failed; making it anew"
fi

# the mirror of the first deb822 source (or one-line source) apt uses
MIRROR=${MFGEOM_DEBIAN_MIRROR:-$(sed -n 's/^URIs: *\([^ ]*\).*/\1/p' /etc/apt/sources.list.d/*.sources 2>/dev/null |
  grep -v security | head -n1)}
[ -n "$MIRROR" ] || MIRROR=$(awk '$1=="deb"{print $2; exit}' /etc/apt/sources.list 2>/dev/null)
[ -n "$MIRROR" ] || { echo "freecad1 root: no Debian mirror found in apt's sources" >&2; exit 1; }
command -v debootstrap >/dev/null || {
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap >/dev/null; }

echo "freecad1 root: making $ROOTFS from $MIRROR (debootstrap trixie, then FreeCAD)"
rm -rf "$ROOTFS.new"; mkdir -p "$(dirname "$ROOTFS")"
debootstrap --variant=minbase trixie "$ROOTFS.new" "$MIRROR" >"$ROOTFS.log" 2>&1 ||
  { tail -20 "$ROOTFS.log"; exit 1; }
cleanup() { for m in dev/pts dev proc; do umount "$ROOTFS.new/$m" 2>/dev/null || true; done; }
trap cleanup EXIT
mount --bind /proc "$ROOTFS.new/proc"; mount --bind /dev "$ROOTFS.new/dev"
mount --bind /dev/pts "$ROOTFS.new/dev/pts"
chroot "$ROOTFS.new" /bin/sh -c "apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
  apt-get install -y -qq --no-install-recommends $PACKAGES" >>"$ROOTFS.log" 2>&1 ||
  { tail -20 "$ROOTFS.log"; exit 1; }
chroot "$ROOTFS.new" apt-get clean
cleanup; trap - EXIT
echo "$STAMP_TEXT" > "$ROOTFS.new/.mfgeom-stamp"
rm -rf "$ROOTFS"; mv "$ROOTFS.new" "$ROOTFS"
echo "freecad1 root: ready ($(du -sh "$ROOTFS" | cut -f1))"
