#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The FreeCAD 1.0 job: the workbench's FreeCAD suites and the README demo on FreeCAD 1.0
# (Debian 13's package), in a Debian 13 root beside this Debian 12 machine.
#   run.sh root       make or reuse the root (tests/freecad1/setup_root.sh; as root)
#   run.sh build      build the library inside the root, into build-freecad1/
#   run.sh tests      FreeCAD App + GUI tests (tests/run_freecad_tests.sh) on FreeCAD 1.0
#   run.sh demo       the README demo (examples/run_demo.sh) on FreeCAD 1.0, into out-freecad1/
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
step_tests() { inside "MFGEOM_LIBRARY=$LIB bash tests/run_freecad_tests.sh"; }
step_demo() { inside "MFGEOM_LIBRARY=$LIB MFGEOM_OUT=/src/out-freecad1 bash examples/run_demo.sh"; }

case ${1:-all} in
  root) step_root ;;
  build) step_build ;;
  tests) step_tests ;;
  demo) step_demo ;;
  all) step_root && step_build && step_tests && step_demo ;;
  *) echo "usage: $0 [root|build|tests|demo|all]" >&2; exit 2 ;;
esac
