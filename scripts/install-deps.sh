#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Installs the development, test and benchmark tools of mfgeom on Debian 12 (as root, apt).
# Building the library alone needs none of this: scripts/build.sh needs only cmake and cc.
set -euo pipefail

PACKAGES=(
  build-essential cmake                       # the C library
  python3-numpy python3-pytest                # binding and its tests
  freecad xvfb xauth                          # the workbench, headless GUI tests
  clang libclang-rt-14-dev                    # libFuzzer target
  libgeos-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev  # benchmark peers
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
