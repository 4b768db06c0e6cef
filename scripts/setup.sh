#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Installs what mfgeom needs on Debian 12 (as root) and builds libmfgeom.so into build/.
set -euo pipefail
cd "$(dirname "$0")/.."

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
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "setup: missing packages: ${missing[*]} - run this script as root (or install them)" >&2
    exit 1
  fi
  echo "setup: installing ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
# The workbench loads the library from next to the binding when installed in FreeCAD's
# Mod folder; a symlink keeps it current with the build.
ln -sf ../../build/libmfgeom.so workbench/mfgeom/libmfgeom.so
echo "setup: built $(pwd)/build/libmfgeom.so"
