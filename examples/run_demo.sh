#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Runs the demos headless (freecadcmd), then renders their results with FreeCAD's GUI under
# a virtual X server; everything lands in $MFGEOM_OUT (default out/).  First the main job,
# the parting analysis of the bundled cup with a hole (demo_parting.*), then the
# point-classification demo on the bracket (demo_pointclass.*); between them the mould
# (issue 21) of the cup and of the knob (demo_mould.*, mould/*.step).
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

run_step() {  # name, log, command...: the command's output cleaned, or the log on failure
  local what=$1 log=$2; shift 2
  if ! "$@" > "$log" 2>&1 || grep -q "Traceback" "$log"; then
    clean < "$log" >&2
    echo "run_demo: $what failed (log: $log)" >&2
    exit 1
  fi
}

echo "run_demo: parting analysis of the cup with a hole (freecadcmd)"
run_step "parting demo" "$MFGEOM_OUT/demo_parting.log" freecadcmd examples/demo_parting.py
clean < "$MFGEOM_OUT/demo_parting.log" | grep -avE '^(FreeCAD 0|\(c\)|FreeCAD (is|wouldn))|Recompute' || true
echo "run_demo: rendering the parting analysis (freecad GUI under xvfb)"
run_step "parting render" "$MFGEOM_OUT/render_parting.log" \
  timeout 300 xvfb-run -a freecad examples/render_parting.py
grep -a "render_parting:" "$MFGEOM_OUT/render_parting.log" || true
echo "run_demo: parting report $MFGEOM_OUT/demo_parting.{txt,json,csv}, document" \
     "$MFGEOM_OUT/demo_parting.FCStd, images $MFGEOM_OUT/demo_parting.png, demo_parting_nc.png"

echo "run_demo: mould of the cup with a hole and of the knob: parting line, surfaces, core," \
     "cavity and inserts (freecadcmd)"
run_step "mould demo" "$MFGEOM_OUT/demo_mould.log" freecadcmd examples/demo_mould.py
cat "$MFGEOM_OUT/demo_mould.txt"
echo "run_demo: rendering the moulds exploded along their directions (freecad GUI under xvfb)"
run_step "mould render" "$MFGEOM_OUT/render_mould.log" \
  timeout 300 xvfb-run -a freecad examples/render_mould.py
grep -a "render_mould:" "$MFGEOM_OUT/render_mould.log" || true
echo "run_demo: mould report $MFGEOM_OUT/demo_mould.txt, STEP files $MFGEOM_OUT/mould/*.step," \
     "document $MFGEOM_OUT/demo_mould.FCStd, image $MFGEOM_OUT/demo_mould.png"

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
