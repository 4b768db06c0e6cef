#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Runs the FreeCAD App tests (freecadcmd) and GUI tests (freecad under xvfb) of the
# workbench; exits non-zero if either fails, prints a summary line or logs a traceback.
set -uo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)

export MFGEOM_LIBRARY=${MFGEOM_LIBRARY:-$ROOT/build/libmfgeom.so}
if [ ! -f "$MFGEOM_LIBRARY" ]; then
  echo "freecad tests: $MFGEOM_LIBRARY missing, building it"
  { cmake -S . -B build >/dev/null && cmake --build build -j2 >/dev/null; } ||
    { echo "freecad tests: build failed"; exit 1; }
fi

# FreeCAD 0.20 reads add-ons from <user dir>/Mod; FREECAD_USER_HOME points the user dir
# at a throw-away directory whose Mod/mfgeom links this checkout (FreeCAD then follows
# package.xml to workbench/), so the real ~/.local/share/FreeCAD, ~/.FreeCAD and their
# user.cfg are never touched and an installed copy of mfgeom cannot shadow this one.
FREECAD_USER_HOME=$(mktemp -d "${TMPDIR:-/tmp}/mfgeom-fchome.XXXXXX")
trap 'rm -rf "$FREECAD_USER_HOME"' EXIT
mkdir -p "$FREECAD_USER_HOME/Mod"
ln -s "$ROOT" "$FREECAD_USER_HOME/Mod/mfgeom"
export FREECAD_USER_HOME
export QTWEBENGINE_DISABLE_SANDBOX=1

failed=0

echo "--- FreeCAD App tests (freecadcmd)"
app_log="$FREECAD_USER_HOME/app.log"
freecadcmd tests/freecad/test_app.py > "$app_log" 2>&1
app_rc=$?
grep -E "^(FAIL|ERROR): |^freecad-app: " "$app_log"
if [ $app_rc -ne 0 ] || ! grep -qE "^freecad-app: [0-9]+ passed, 0 failed$" "$app_log"; then
  echo "app tests: FAILED (exit $app_rc)"
  sed -n '/^=\{20,\}/,/^-\{20,\}$/p' "$app_log" | head -120
  failed=1
elif grep -q "Traceback" "$app_log"; then
  echo "app tests: traceback in the log:"; grep -n -A12 "Traceback" "$app_log"; failed=1
fi

echo "--- FreeCAD parting tests (freecadcmd)"
parting_log="$FREECAD_USER_HOME/parting.log"
freecadcmd tests/freecad/test_parting_app.py > "$parting_log" 2>&1
parting_rc=$?
grep -E "^(FAIL|ERROR): |^freecad-parting: " "$parting_log"
if [ $parting_rc -ne 0 ] || ! grep -qE "^freecad-parting: [0-9]+ passed, 0 failed$" "$parting_log" ||
   grep -q "Traceback" "$parting_log"; then
  echo "parting tests: FAILED (exit $parting_rc)"; grep -n -A12 "Traceback" "$parting_log" | head -120
  failed=1
fi

echo "--- FreeCAD Gaussian map tests (freecadcmd)"
gauss_log="$FREECAD_USER_HOME/gauss_map.log"
freecadcmd tests/freecad/test_gauss_map_app.py > "$gauss_log" 2>&1
gauss_rc=$?
grep -E "^(FAIL|ERROR): |^freecad-gauss-map: " "$gauss_log"
if [ $gauss_rc -ne 0 ] || ! grep -qE "^freecad-gauss-map: [0-9]+ passed, 0 failed$" "$gauss_log" ||
   grep -q "Traceback" "$gauss_log"; then
  echo "gauss map tests: FAILED (exit $gauss_rc)"; grep -n -A12 "Traceback" "$gauss_log" | head -120
  failed=1
fi

echo "--- FreeCAD clearance tests (freecadcmd)"
clearance_log="$FREECAD_USER_HOME/clearance.log"
freecadcmd tests/freecad/test_clearance_app.py > "$clearance_log" 2>&1
clearance_rc=$?
grep -E "^(FAIL|ERROR): |^freecad-clearance: " "$clearance_log"
if [ $clearance_rc -ne 0 ] || ! grep -qE "^freecad-clearance: [0-9]+ passed, 0 failed$" "$clearance_log" ||
   grep -q "Traceback" "$clearance_log"; then
  echo "clearance tests: FAILED (exit $clearance_rc)"; grep -n -A12 "Traceback" "$clearance_log" | head -120
  failed=1
fi

echo "--- FreeCAD ray check tests (freecadcmd)"
ray_log="$FREECAD_USER_HOME/ray_check.log"
freecadcmd tests/freecad/test_ray_check_app.py > "$ray_log" 2>&1
ray_rc=$?
grep -E "^(FAIL|ERROR): |^freecad-ray-check: " "$ray_log"
if [ $ray_rc -ne 0 ] || ! grep -qE "^freecad-ray-check: [0-9]+ passed, 0 failed$" "$ray_log" ||
   grep -q "Traceback" "$ray_log"; then
  echo "ray check tests: FAILED (exit $ray_rc)"; grep -n -A12 "Traceback" "$ray_log" | head -120
  failed=1
fi

echo "--- FreeCAD rotational sweep tests (freecadcmd)"
sweep_log="$FREECAD_USER_HOME/sweep.log"
freecadcmd tests/freecad/test_sweep_app.py > "$sweep_log" 2>&1
sweep_rc=$?
grep -E "^(FAIL|ERROR): |^sweep library: |^freecad-sweep: " "$sweep_log"
# FreeCAD prints a traceback for every failed recompute; the ones of the issue-8 known gaps
# (the library's refusal, zero-area triangles: the tests skip them, naming the gap) are
# expected, any other is a failure
sweep_tb=$(grep -c "Traceback" "$sweep_log")
sweep_gap_tb=$(grep -A3 "Traceback" "$sweep_log" |
  grep -cE "could not be made a closed 2-manifold|zero-area triangles")
if [ $sweep_rc -ne 0 ] || ! grep -qE "^freecad-sweep: [0-9]+ passed, 0 failed$" "$sweep_log" ||
   [ "$sweep_tb" -gt "$sweep_gap_tb" ]; then
  echo "sweep tests: FAILED (exit $sweep_rc)"; grep -n -A12 "Traceback" "$sweep_log" | head -120
  failed=1
fi

echo "--- FreeCAD medial axis / surface tests (freecadcmd)"
medial_log="$FREECAD_USER_HOME/medial.log"
freecadcmd tests/freecad/test_medial_app.py > "$medial_log" 2>&1
medial_rc=$?
grep -E "^(FAIL|ERROR): |^medial library: |^freecad-medial: " "$medial_log"
if [ $medial_rc -ne 0 ] || ! grep -qE "^freecad-medial: [0-9]+ passed, 0 failed$" "$medial_log" ||
   grep -q "Traceback" "$medial_log"; then
  echo "medial tests: FAILED (exit $medial_rc)"; grep -n -A12 "Traceback" "$medial_log" | head -120
  failed=1
fi

echo "--- FreeCAD corpus of real parts (freecadcmd)"
corpus_log="$FREECAD_USER_HOME/corpus.log"
freecadcmd tests/freecad/test_corpus_app.py > "$corpus_log" 2>&1
corpus_rc=$?
grep -E "^(FAIL|ERROR): |^corpus-failure: |^corpus: |^freecad-corpus: " "$corpus_log"
if [ $corpus_rc -ne 0 ] || ! grep -qE "^freecad-corpus: [0-9]+ passed, 0 failed$" "$corpus_log"; then
  echo "corpus tests: FAILED (exit $corpus_rc)"; failed=1
fi

echo "--- FreeCAD GUI tests (freecad under xvfb)"
bash tests/gui/run_gui_tests.sh || failed=1

if [ $failed -ne 0 ]; then echo "freecad tests: FAILED"; exit 1; fi
echo "freecad tests: all passed"
