#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Installs the development, test and benchmark tools of mfgeom on Debian 12 (bookworm) or 13
# (trixie) (as root, apt).  Building the library alone needs none of this: scripts/build.sh
# needs only cmake and cc.
set -euo pipefail

# The libFuzzer runtime is versioned with the release's default clang (bookworm: clang 14,
# trixie: clang 19); another release asks apt which clang-N the clang package pulls in.
codename=$( (. /etc/os-release 2>/dev/null && echo "${VERSION_CODENAME:-}") || true)
case "$codename" in
  bookworm) clang_major=14 ;;
  trixie) clang_major=19 ;;
  *) clang_major=$(apt-cache depends clang 2>/dev/null | sed -nE 's/.*Depends: clang-([0-9]+)$/\1/p' | head -1) ;;
esac
if [ -z "${clang_major:-}" ]; then
  echo "install-deps: Debian release '${codename:-unknown}' not known and apt cannot tell the" \
       "default clang's version (run apt-get update first); tested on bookworm and trixie" >&2
  exit 1
fi

PACKAGES=(
  build-essential cmake                       # the C library
  python3-numpy python3-pytest                # binding and its tests
  freecad xvfb xauth                          # the workbench, headless GUI tests
  clang "libclang-rt-$clang_major-dev"        # libFuzzer target
  libgeos-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev python3-openvdb python3-scipy  # benchmark peers
  python3-shapely python3-matplotlib          # Python peers (tests + bench)
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: everything is installed"
  exit 0
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: missing packages: ${missing[*]} - run this script as root (or install them)" >&2
  exit 1
fi
echo "install-deps: installing ${missing[*]}"
apt-get update -qq
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
