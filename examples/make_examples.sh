#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Regenerates the example documents shipped in examples/ (bracket.FCStd) by running their
# scripts in FreeCAD's GUI under a virtual X server: a document saved by freecadcmd has no
# GuiDocument.xml, and FreeCAD then opens every object hidden.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
export QTWEBENGINE_DISABLE_SANDBOX=1  # as root the Start page's web engine needs it
# A throw-away FreeCAD user directory, so the real one and its user.cfg stay untouched.
FCHOME=$(mktemp -d "${TMPDIR:-/tmp}/mfgeom-fchome.XXXXXX")
trap 'rm -rf "$FCHOME"' EXIT
export FREECAD_USER_HOME=$FCHOME
log="$FCHOME/bracket.log"
if ! timeout 300 xvfb-run -a freecad examples/bracket.py > "$log" 2>&1 || grep -q Traceback "$log"; then
  cat "$log" >&2
  echo "make_examples: bracket.py failed" >&2
  exit 1
fi
grep -a "^bracket:" "$log"
/usr/bin/python3 - "$ROOT/examples/bracket.FCStd" <<'PY'
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
assert "GuiDocument.xml" in names, names
print(f"make_examples: {sys.argv[1]} has GuiDocument.xml")
PY
