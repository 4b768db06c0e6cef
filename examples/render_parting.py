# SPDX-License-Identifier: LGPL-2.1-or-later
"""Renders the parting demo's result to PNG with FreeCAD's GUI (run under xvfb-run, see
run_demo.sh).

Opens $MFGEOM_OUT/demo_parting.FCStd (default <repo>/out, written by demo_parting.py),
activates the Manufacturing Geometry workbench, shows the Mould analysis (faces coloured
core / cavity / undercut, arrows along +-d and the side core, the visibility sphere) and
writes demo_parting.png, then the NC 3-axis analysis (faces by set-up) to
demo_parting_nc.png; saves the document again from the GUI so it opens with the Mould
analysis shown.  Ends with os._exit(rc): the GUI would otherwise keep running.
"""

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
WIDTH, HEIGHT = 1200, 800


def show_only(doc, visible):
    for o in doc.Objects:
        if o.ViewObject is not None:
            o.ViewObject.Visibility = o in visible


def render():
    out = os.path.abspath(os.environ.get("MFGEOM_OUT") or os.path.join(REPO, "out"))
    fcstd = os.path.join(out, "demo_parting.FCStd")
    if not os.path.exists(fcstd):
        raise FileNotFoundError(f"{fcstd} not found: run examples/demo_parting.py first")
    Gui.activateWorkbench("MfgeomWorkbench")
    doc = App.openDocument(fcstd)
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    analyses = {o.Mode: o for o in doc.Objects
                if getattr(getattr(o, "Proxy", None), "Type", "") == "Mfgeom::PartingAnalysis"}
    view = Gui.ActiveDocument.ActiveView
    images = []
    for mode, name in (("NC3Axis", "demo_parting_nc.png"), ("Mould", "demo_parting.png")):
        obj = analyses[mode]
        vobj = obj.ViewObject
        proxy = vobj.Proxy
        if proxy is None or getattr(proxy, "sphere_faces", None) is None:
            raise RuntimeError(f"{obj.Label}: the view provider drew no visibility sphere")
        show_only(doc, [obj])
        Gui.updateGui()
        view.viewIsometric()
        view.fitAll()
        camera = view.getCameraNode()
        if hasattr(camera, "height"):  # orthographic: fitAll leaves a wide margin
            camera.height.setValue(camera.height.getValue() * 0.6)
        Gui.updateGui()
        path = os.path.join(out, name)
        view.saveImage(path, WIDTH, HEIGHT, "White")
        images.append(path)
        count = proxy.sphere_count
        sys.stdout.write(f"render_parting: {path}: {obj.Label}, {proxy.arrow_count} arrows, "
                         f"sphere {len(count)} vertices, coverage 0..{int(count.max())}, "
                         f"{int((count == count.max()).sum())} in the maximum region\n")
    doc.save()  # from the GUI: the file keeps its view (the Mould analysis shown)
    return images


try:
    render()
    rc = 0
except Exception:
    traceback.print_exc()
    rc = 1
compat.exit_now(rc)  # output flushed first (FreeCAD 1.0 buffers C stdio in a pipe)
