#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# chroot_run.sh CHECKOUT COMMAND...: runs COMMAND (with bash -c) inside the FreeCAD 1.0 root
# (tests/freecad1/setup_root.sh) with CHECKOUT bound at /src and the working directory there.
# Each call gets its own mount namespace (unshare -m), so the bind mounts of /proc, /dev and
# the checkout vanish with the call: concurrent calls do not see or undo each other's mounts,
# and an interrupted call leaves nothing mounted.
set -euo pipefail
ROOTFS=${MFGEOM_FREECAD1_ROOT:-/var/cache/mfgeom/freecad1-trixie}
CHECKOUT=$(cd "$1" && pwd); shift
[ -f "$ROOTFS/.mfgeom-stamp" ] || { echo "chroot_run: no FreeCAD 1.0 root at $ROOTFS" >&2; exit 1; }
mkdir -p "$ROOTFS/src"
exec unshare --mount --propagation private /bin/bash -c '
  set -e
  R=$1; C=$2; shift 2
  mount --bind /proc "$R/proc"; mount --rbind /dev "$R/dev"; mount --bind "$C" "$R/src"
  mount -t tmpfs tmpfs "$R/tmp"
  exec chroot "$R" /usr/bin/env -i HOME=/root PATH=/usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin \
    LANG=C.UTF-8 TERM=dumb /bin/bash -c "cd /src && $*"
' chroot_run "$ROOTFS" "$CHECKOUT" "$@"
