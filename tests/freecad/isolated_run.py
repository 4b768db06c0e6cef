# SPDX-License-Identifier: LGPL-2.1-or-later
"""Runs a test body in its own freecadcmd, for the FreeCAD App tests whose case makes a
recompute fail on purpose: FreeCAD 0.20 prints the traceback of execute() (one frame),
which the runners' log checks would take for a crash, so those cases run apart."""

import json
import os
import subprocess
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

ISOLATED_PREAMBLE = """
import json
import sys
sys.path.append({workbench!r})
import FreeCAD as App
import Part
import mfgeom
"""


def isolated(name, body):
    """Runs ``body`` in its own freecadcmd (workbench on sys.path, mfgeom imported) and
    returns the JSON it prints on a line starting with '=== result '."""
    folder = tempfile.mkdtemp()
    script = os.path.join(folder, f"{name}.py")
    with open(script, "w", encoding="utf-8") as f:
        f.write(ISOLATED_PREAMBLE.format(workbench=os.path.join(REPO, "workbench")) + body)
    run = subprocess.run(["freecadcmd", script], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True, timeout=300)
    lines = [line for line in run.stdout.splitlines() if line.startswith("=== result ")]
    if len(lines) != 1:
        raise AssertionError(f"{name}: no result line\n{run.stdout[-3000:]}")
    return json.loads(lines[0][len("=== result "):])
