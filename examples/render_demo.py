# SPDX-License-Identifier: LGPL-2.1-or-later
"""Renders the demo's result to PNG with FreeCAD's GUI (run under xvfb-run, see run_demo.sh).

Opens $MFGEOM_OUT/demo_pointclass.FCStd (default <repo>/out), activates the Manufacturing
Geometry workbench, shows the coloured points on the bracket from an isometric view and
from above, and writes demo_pointclass.png and demo_pointclass_top.png beside it.
Ends with os._exit(rc): the GUI would otherwise keep running.
"""

import json
import os
import sys
import traceback

import FreeCAD as App
import FreeCADGui as Gui

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
if os.path.join(REPO, "workbench") not in sys.path:  # FreeCAD has it when installed
    sys.path.append(os.path.join(REPO, "workbench"))

from mfgeom import compat  # noqa: E402


def render():
    out = os.path.abspath(os.environ.get("MFGEOM_OUT") or os.path.join(REPO, "out"))
    fcstd = os.path.join(out, "demo_pointclass.FCStd")
    if not os.path.exists(fcstd):
        raise FileNotFoundError(f"{fcstd} not found: run examples/demo_pointclass.py first")
    Gui.activateWorkbench("MfgeomWorkbench")
    doc = App.openDocument(fcstd)
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    features = [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "Type", "") ==
                "Mfgeom::PointClassification"]
    if not features:
        raise RuntimeError("the demo document holds no point classification")
    for obj in features:
        if not obj.isValid():
            raise RuntimeError(f"{obj.Label} is not valid: {obj.getStatusString()}")
        if sum(obj.ViewObject.Proxy.counts_shown().values()) != len(obj.Classes):
            raise RuntimeError(f"{obj.Label}: the view does not show every point")
    with open(os.path.join(out, "demo_pointclass.json"), encoding="utf-8") as f:
        show = set(json.load(f)["show"])
    for obj in doc.Objects:
        if obj.ViewObject is not None:
            obj.ViewObject.Visibility = obj.Name in show
    view = Gui.ActiveDocument.ActiveView
    Gui.runCommand("Std_DrawStyle", 0)  # as is: shaded faces with edges
    view.viewIsometric()
    view.fitAll()
    images = []
    for name, orient in (("demo_pointclass.png", view.viewIsometric),
                         ("demo_pointclass_top.png", view.viewTop)):
        orient()
        view.fitAll()
        Gui.updateGui()
        path = os.path.join(out, name)
        view.saveImage(path, 1600, 1000, "White")
        images.append(path)
    for path in images:
        App.Console.PrintMessage(f"render_demo: wrote {path}\n")
    return 0


try:
    rc = render()
except Exception:  # report, then leave with a failing code: the GUI must not stay up
    traceback.print_exc()
    rc = 1
compat.exit_now(rc)  # output flushed first (FreeCAD 1.0 buffers C stdio in a pipe)
