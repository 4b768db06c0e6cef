#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Runs the point-classification demo headless (freecadcmd), then renders its result with
# FreeCAD's GUI under a virtual X server; everything lands in $MFGEOM_OUT (default out/).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)

export MFGEOM_OUT=${MFGEOM_OUT:-$ROOT/out}
export MFGEOM_LIBRARY=${MFGEOM_LIBRARY:-$ROOT/build/libmfgeom.so}
if [ ! -f "$MFGEOM_LIBRARY" ]; then
  echo "run_demo: $MFGEOM_LIBRARY not found; build first: cmake -S . -B build && cmake --build build" >&2
  exit 1
fi
mkdir -p "$MFGEOM_OUT"

# A throw-away FreeCAD user directory whose Mod/ holds this checkout: FreeCAD finds the
# workbench through package.xml, and the real ~/.local/share/FreeCAD (or ~/.FreeCAD)
# and its user.cfg stay untouched.
FCHOME=$(mktemp -d "${TMPDIR:-/tmp}/mfgeom-fchome.XXXXXX")
trap 'rm -rf "$FCHOME"' EXIT
mkdir -p "$FCHOME/Mod"
ln -s "$ROOT" "$FCHOME/Mod/mfgeom"
export FREECAD_USER_HOME=$FCHOME
export QTWEBENGINE_DISABLE_SANDBOX=1  # as root the Start page's web engine needs it

# FreeCAD's console output carries tab-separated progress counters; keep the rest.
clean() { grep -avE '^  #' | sed -E 's/[\t\r]/ /g; s/ *\([0-9]+ %\)//g; s/^ +//' | grep -vE '^$|\.{6} *$' || true; }

echo "run_demo: classifying (freecadcmd)"
if ! freecadcmd examples/demo_pointclass.py > "$MFGEOM_OUT/demo_pointclass.log" 2>&1; then
  clean < "$MFGEOM_OUT/demo_pointclass.log" >&2
  echo "run_demo: demo failed (log: $MFGEOM_OUT/demo_pointclass.log)" >&2
  exit 1
fi
clean < "$MFGEOM_OUT/demo_pointclass.log"

echo "run_demo: rendering (freecad GUI under xvfb)"
log="$MFGEOM_OUT/render_demo.log"
if ! timeout 300 xvfb-run -a freecad examples/render_demo.py > "$log" 2>&1 ||
   grep -q "Traceback" "$log"; then
  clean < "$log" >&2
  echo "run_demo: render failed (log: $log)" >&2
  exit 1
fi
grep "render_demo:" "$log" || true
echo "run_demo: report $MFGEOM_OUT/demo_pointclass.txt, images $MFGEOM_OUT/demo_pointclass*.png"
