#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The FreeCAD 1.0 job: the workbench's FreeCAD suites and the README demo on FreeCAD 1.0
# (Debian 13's package), in a Debian 13 root beside this Debian 12 machine.
#   run.sh root       make or reuse the root (tests/freecad1/setup_root.sh; as root)
#   run.sh build      build the library inside the root, into build-freecad1/
#   run.sh tests      FreeCAD App + GUI tests (tests/run_freecad_tests.sh) and the pytest
#                     files that import FreeCAD (test_cli_parting.py, test_cli_mould.py) on FreeCAD 1.0
#   run.sh demo       the README demo (examples/run_demo.sh) on FreeCAD 1.0, into out-freecad1/
#   run.sh roundtrip  a document of every mfgeom object saved on this machine's FreeCAD
#                     (0.20) opened, checked and recomputed on 1.0, and the other way round
#   run.sh all        all of these in order (the default)
# tests/run_all.sh runs each step as its own suite.  The C suites do not run here: the
# library's code is the same and they already ran on this machine's compiler.
set -uo pipefail
cd "$(dirname "$0")/../.."
ROOT=$(pwd)
HERE=tests/freecad1
LIB=/src/build-freecad1/libmfgeom.so   # as the root sees this checkout

inside() { bash "$HERE/chroot_run.sh" "$ROOT" "$@"; }

step_root() { bash "$HERE/setup_root.sh"; }
step_build() {
  inside 'cmake -S . -B build-freecad1 -DCMAKE_BUILD_TYPE=Release -DMFG_BUILD_TESTS=OFF >/dev/null &&
          cmake --build build-freecad1 -j"$(nproc)" >/dev/null && ls -l build-freecad1/libmfgeom.so &&
          freecadcmd --version 2>/dev/null | head -n1; python3 --version'
}
# the FreeCAD suites, then the binding tests that import FreeCAD from plain python3 (where
# Part.makeCompound crashed on 1.0 without Mod/Part on the path); the rest of pytest does
# not touch FreeCAD and already ran
step_tests() {
  inside "MFGEOM_LIBRARY=$LIB bash tests/run_freecad_tests.sh &&
    MFGEOM_LIBRARY=$LIB PYTHONPATH=/src/workbench python3 -m pytest -q -p no:cacheprovider \
      tests/python/test_cli_parting.py tests/python/test_cli_mould.py"
}
step_demo() { inside "MFGEOM_LIBRARY=$LIB MFGEOM_OUT=/src/out-freecad1 bash examples/run_demo.sh"; }

# roundtrip_one SAVE_ON CHECK_ON DIR: tests/freecad/roundtrip_save.py on one version,
# roundtrip_check.py on the other ("host" = this machine's FreeCAD, "root" = FreeCAD 1.0)
# As a user runs it: the workbench installed as an add-on (a user directory whose Mod/
# links this checkout); FreeCAD 1.0 refuses to import a proxy's module from anywhere else
# while it restores a document ("module not permitted").
on_host() {
  local home; home=$(mktemp -d "${TMPDIR:-/tmp}/mfgeom-fchome.XXXXXX")
  mkdir -p "$home/Mod"; ln -s "$ROOT" "$home/Mod/mfgeom"
  FREECAD_USER_HOME=$home MFGEOM_LIBRARY="$ROOT/build/libmfgeom.so" \
    MFGEOM_ROUNDTRIP_DIR="$ROOT/$1" freecadcmd "tests/freecad/$2" 2>&1
  local rc=$?; rm -rf "$home"; return $rc
}
on_root() {
  inside "mkdir -p /tmp/fchome/Mod && ln -s /src /tmp/fchome/Mod/mfgeom &&
    FREECAD_USER_HOME=/tmp/fchome MFGEOM_LIBRARY=$LIB MFGEOM_ROUNDTRIP_DIR=/src/$1 \
    freecadcmd tests/freecad/$2 2>&1"
}
roundtrip_one() {
  local dir=$3 log
  rm -rf "$ROOT/$dir"; mkdir -p "$ROOT/$dir"
  log=$("on_$1" "$dir" roundtrip_save.py) || { echo "$log" | tail -30; return 1; }
  echo "$log" | grep -a "^roundtrip-save: "
  log=$("on_$2" "$dir" roundtrip_check.py); local rc=$?
  echo "$log" | grep -aE "^(FAIL|roundtrip-check: )"
  [ $rc -eq 0 ] && echo "$log" | grep -qaE "^roundtrip-check: [0-9]+ passed, 0 failed" ||
    { echo "$log" | tail -40; return 1; }
}
step_roundtrip() {
  [ -f "$ROOT/build/libmfgeom.so" ] || { echo "roundtrip: build/libmfgeom.so missing"; return 1; }
  roundtrip_one host root out-freecad1/roundtrip-from-host &&
    roundtrip_one root host out-freecad1/roundtrip-from-1.0
}

case ${1:-all} in
  root) step_root ;;
  build) step_build ;;
  tests) step_tests ;;
  demo) step_demo ;;
  roundtrip) step_roundtrip ;;
  all) step_root && step_build && step_tests && step_demo && step_roundtrip ;;
  *) echo "usage: $0 [root|build|tests|demo|roundtrip|all]" >&2; exit 2 ;;
esac
