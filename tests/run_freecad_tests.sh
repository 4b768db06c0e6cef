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
grep -aE "^(FAIL|ERROR|SKIP): |^freecad-app: " "$app_log"
if [ $app_rc -ne 0 ] || ! grep -qE "^freecad-app: [0-9]+ passed, 0 failed$" "$app_log"; then
  echo "app tests: FAILED (exit $app_rc)"
  sed -n '/^=\{20,\}/,/^-\{20,\}$/p' "$app_log" | head -120
  failed=1
elif grep -q "Traceback" "$app_log"; then
  echo "app tests: traceback in the log:"; grep -n -A12 "Traceback" "$app_log"; failed=1
fi

# app_suite TITLE FILE LABEL [EXTRA]: runs tests/freecad/FILE with freecadcmd; passes when
# it exits 0, prints "LABEL: N passed, 0 failed" and (unless EXTRA is "tracebacks-ok") logs
# no traceback.  The failures, skips and summary lines are echoed.  A suite where no test
# ran or every test was skipped exits 1 (tests/freecad/fc_testsupport.py).
app_suite() {
  local title=$1 file=$2 label=$3 extra=${4:-} log rc
  echo "--- FreeCAD $title (freecadcmd)"
  log="$FREECAD_USER_HOME/${file%.py}.log"
  freecadcmd "tests/freecad/$file" > "$log" 2>&1
  rc=$?
  grep -aE "^(FAIL|ERROR|SKIP): |^corpus-(failure|known|known-gaps): |^corpus: |^$label: " "$log"
  if [ $rc -ne 0 ] || ! grep -qE "^$label: [0-9]+ passed, 0 failed$" "$log" ||
     { [ "$extra" != "tracebacks-ok" ] && grep -q "Traceback" "$log"; }; then
    echo "$title: FAILED (exit $rc)"; grep -n -A12 "Traceback" "$log" | head -120
    failed=1
  fi
}

app_suite "parting tests" test_parting_app.py freecad-parting
app_suite "Gaussian map tests" test_gauss_map_app.py freecad-gauss-map
app_suite "clearance tests" test_clearance_app.py freecad-clearance
app_suite "ray check tests" test_ray_check_app.py freecad-ray-check

app_suite "rotational sweep tests" test_sweep_app.py freecad-sweep
app_suite "medial axis / surface tests" test_medial_app.py freecad-medial
# the mould tests open corpus documents of FreeCAD 0.20's Path workbench; FreeCAD 1.0 logs
# a traceback for each Path object it cannot restore (PathScripts moved): not ours, and
# the tests' own failures are in the summary line
app_suite "mould tests" test_mould_app.py freecad-mould tracebacks-ok
# the thickness analysis opens OCCT's bottle from the corpus (no Path objects)
app_suite "thickness tests" test_thickness_app.py freecad-thickness
# the corpus test runs each part in a child process; a child's traceback is its report
app_suite "corpus of real parts" test_corpus_app.py freecad-corpus tracebacks-ok

echo "--- FreeCAD GUI tests (freecad under xvfb)"
bash tests/gui/run_gui_tests.sh || failed=1

if [ $failed -ne 0 ]; then echo "freecad tests: FAILED"; exit 1; fi
echo "freecad tests: all passed"
