#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Builds libmfgeom.so into build/ and links it beside the binding: needs only cmake and a C
# compiler, runs as a normal user in the add-on folder (an Addon Manager clone has no library).
#
#   bash scripts/build.sh           from the repository / add-on folder
#
# Always a release build without sanitizers, whatever build/ was configured with before:
# this is the library FreeCAD loads, and an instrumented one would abort FreeCAD.
set -euo pipefail
cd "$(dirname "$0")/.."

missing=()
command -v cmake >/dev/null 2>&1 || missing+=("cmake")
if [ -n "${CC:-}" ]; then
  command -v "${CC%% *}" >/dev/null 2>&1 || missing+=("a C compiler (CC=$CC)")
elif ! command -v cc >/dev/null 2>&1 && ! command -v gcc >/dev/null 2>&1 &&
     ! command -v clang >/dev/null 2>&1; then
  missing+=("a C compiler")
fi
if [ ${#missing[@]} -gt 0 ]; then
  hint="sudo apt-get install cmake gcc"
  if [ -r /etc/os-release ]; then
    ids=$(. /etc/os-release; echo "${ID:-} ${ID_LIKE:-}")
    case " $ids " in
      *" debian "*|*" ubuntu "*) hint="sudo apt-get install cmake gcc" ;;
      *" fedora "*|*" rhel "*)   hint="sudo dnf install cmake gcc" ;;
      *suse*)                    hint="sudo zypper install cmake gcc" ;;
      *" arch "*)                hint="sudo pacman -S cmake gcc" ;;
    esac
  fi
  if [ "$(uname -s)" = Darwin ]; then hint="xcode-select --install; brew install cmake"; fi
  printf 'build: missing %s. Install them (e.g. %s), then run this script again.\n' \
    "$(IFS=,; echo "${missing[*]}" | sed 's/,/ and /g')" "$hint" >&2
  exit 1
fi

jobs=$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2)
echo "build: configuring $(pwd)/build"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DMFG_SANITIZE=OFF
echo "build: compiling libmfgeom.so"
cmake --build build --target mfgeom -j"$jobs"
# The binding looks next to itself first: a relative link keeps it current with build/
# and keeps working when the folder is moved.
ln -sfn ../../build/libmfgeom.so workbench/mfgeom/libmfgeom.so
echo "build: built $(pwd)/build/libmfgeom.so"
