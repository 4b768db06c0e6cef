# SPDX-License-Identifier: LGPL-2.1-or-later
"""Renders the mould demo's result to PNG with FreeCAD's GUI (run under xvfb-run, see
run_demo.sh): opens $MFGEOM_OUT/demo_mould.FCStd (written by demo_mould.py) and, for each
mould in it, shows the part in place with its core moved along +d, its cavity along -d
and its inserts along their side-core directions (exploded by EXPLODE x the part's
size), core blue, cavity red, inserts indigo, part grey; writes demo_mould.png.  Ends
with os._exit(rc): the GUI would otherwise keep running.
"""

import json
import os
import sys
import traceback

import FreeCAD as App
import FreeCADGui as Gui

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
if os.path.join(REPO, "workbench") not in sys.path:
    sys.path.append(os.path.join(REPO, "workbench"))

from mfgeom import compat, palette  # noqa: E402
WIDTH, HEIGHT = 1400, 900
EXPLODE = 0.9


def render():
    out = os.path.abspath(os.environ.get("MFGEOM_OUT") or os.path.join(REPO, "out"))
    fcstd = os.path.join(out, "demo_mould.FCStd")
    if not os.path.exists(fcstd):
        raise FileNotFoundError(f"{fcstd} not found: run examples/demo_mould.py first")
    Gui.activateWorkbench("MfgeomWorkbench")
    doc = App.openDocument(fcstd)
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    moulds = [o for o in doc.Objects
              if getattr(getattr(o, "Proxy", None), "Type", "") == "Mfgeom::MouldBlocks"]
    if not moulds:
        raise RuntimeError("no MouldBlocks in the demo document")
    for o in doc.Objects:
        if o.ViewObject is not None:
            o.ViewObject.Visibility = False
    shown = []
    for mb in moulds:
        analysis = mb.PartingSurface.PartingLine.Analysis
        part = analysis.Source
        d = mb.Direction
        gap = EXPLODE * part.Shape.BoundBox.DiagonalLength
        pieces = [(mb.Core, d * gap, palette.MOULD_CORE, "Core"),
                  (mb.Cavity, d * -gap, palette.MOULD_CAVITY, "Cavity")]
        for k, s in enumerate(mb.Inserts.Solids):
            side = json.loads(analysis.SideCores[k])["direction"]
            pieces.append((s, App.Vector(*side) * gap, palette.MOULD_INSERT, f"Insert{k + 1}"))
        for shape, move, colour, what in pieces:
            obj = doc.addObject("Part::Feature", f"{mb.Name}_{what}_exploded")
            s = shape.copy()
            s.translate(move)
            obj.Shape = s
            obj.ViewObject.ShapeColor = colour
            obj.ViewObject.Transparency = 15
            shown.append(obj)
        part.ViewObject.Visibility = True
        part.ViewObject.ShapeColor = palette.SHAPE_GREY
        line = mb.PartingSurface.PartingLine
        line.ViewObject.Visibility = True
        shown += [part, line]
    doc.recompute()
    view = Gui.ActiveDocument.ActiveView
    Gui.Selection.clearSelection()
    view.viewIsometric()
    view.fitAll()
    camera = view.getCameraNode()
    if hasattr(camera, "height"):  # orthographic: fitAll leaves a wide margin
        camera.height.setValue(camera.height.getValue() * 0.65)
    Gui.updateGui()
    path = os.path.join(out, "demo_mould.png")
    view.saveImage(path, WIDTH, HEIGHT, "White")
    sys.stdout.write(f"render_mould: {path}: {len(moulds)} moulds, {len(shown)} objects shown "
                     "(core +d, cavity -d, inserts along their side cores)\n")


try:
    render()
    rc = 0
except Exception:
    traceback.print_exc()
    rc = 1
compat.exit_now(rc)
