# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD GUI test of the medial commands (issue 9), run as a macro under a virtual X
server by tests/gui/run_gui_tests.sh: ``xvfb-run -a freecad tests/gui/test_gui_medial.py``.

On the bundled ribbed tray (examples/parts/thin_wall.py): the three commands in the
toolbar with their icons; wrong selections (nothing, a curved face, a whole object for
the face command; nothing, a sheet, two solids for the solid commands) show a message and
create nothing; "Medial axis of face" on the tray's bottom face: the task panel, OK
creates a valid axis (analytic: 5 branches, largest radius half the tray's width) in one
undo step, echoed in the Python console; "Medial surface" on the tray: the panel offers
0.5 % of the bounding-box diagonal; OK creates the coloured medial surface (display
mode "Thickness", per-vertex colours on the ramp, the legend's labels span the thickness range); the axis' and the
surface's legends, both shown, stack one below the other (found in the screenshot's
pixels: two bars, the second at least the first's height lower; saved as
medial-legends.png), hiding the axis gives the surface's legend the whole band, a third
legend takes the third slot, deleting its feature frees it, undoing the deletion takes
it again and undoing the creation frees it; "Mid-surface for
FEM" with a CSV path creates the shell, writes the CSV and reports the thickness; the
screenshot shows the coloured mid-surface with its legend in the half-transparent tray
(before that: the medial axis on the tray).  "Mid-surface for FEM" from a solid (a 40 x
30 x 2 plate selected, not a medial surface): the panel offers the solid's tolerance,
OK makes the medial surface and the mid-surface in one undo step, a planar shell at z = 1
over [1, 39] x [1, 29], thickness 2 at every point, per face, min / max / mean, and
every object of the document valid; one thickness is one histogram bin, one colour and
one legend label; its edit panel shows its medial surface's tolerance and deflection
(screenshot mid-surface-plate.png).  Prints ``freecad-gui-medial: N passed, M
failed``; leaves with os._exit(rc).
"""

import os
import sys
import tempfile

import FreeCAD as App
import FreeCADGui as Gui

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
if os.path.join(ROOT, "workbench") not in sys.path:
    sys.path.append(os.path.join(ROOT, "workbench"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "examples", "parts"))
from gui_harness import DialogCloser, check, finish, press, pump, qt, screenshot, state  # noqa: E402
import thin_wall  # noqa: E402

WORKBENCH = "MfgeomWorkbench"
AXIS, SURFACE, MID = "Mfgeom_MedialAxis", "Mfgeom_MedialSurface", "Mfgeom_MidSurface"
OUT = os.environ.get("MFGEOM_GUI_OUT") or os.path.join(ROOT, "out", "gui-tests")

dialogs = DialogCloser()


def task_panel():
    """The open medial panel's widgets by object name, and the task view's buttons."""
    _, QtGui = qt()
    Gui.updateGui()
    mw = Gui.getMainWindow()
    spins = [w for w in mw.findChildren(QtGui.QDoubleSpinBox)
             if w.objectName() == "tolerance" and w.isVisible()]
    if not Gui.Control.activeDialog() or not spins:
        return None
    panel = spins[0].parentWidget()
    widgets = {w.objectName(): w for w in panel.findChildren(QtGui.QWidget) if w.objectName()}
    boxes = [b for b in mw.findChildren(QtGui.QDialogButtonBox)
             if b.isVisible() and b.button(QtGui.QDialogButtonBox.Ok) is not None]
    assert len(boxes) == 1, f"{len(boxes)} visible OK button boxes"
    for key, role in (("ok", QtGui.QDialogButtonBox.Ok), ("cancel", QtGui.QDialogButtonBox.Cancel),
                      ("apply", QtGui.QDialogButtonBox.Apply)):
        widgets[key] = boxes[0].button(role)
    return widgets


def of_type(doc, kind):
    return [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "Type", "") == kind]


def select(items):
    Gui.Selection.clearSelection()
    for obj, sub in items:
        if sub:
            Gui.Selection.addSelection(obj, sub)
        else:
            Gui.Selection.addSelection(obj)


def refused(command, items, want):
    """Runs ``command`` on the selection ``items``: a message containing ``want``, no
    panel, nothing new in the document."""
    doc = state["doc"]
    names, undo = [o.Name for o in doc.Objects], doc.UndoCount
    select(items)
    dialogs.take()
    Gui.runCommand(command)
    assert pump(lambda: dialogs.texts, 5), f"no message for {command} on {items}"
    texts = dialogs.take()
    assert task_panel() is None, "a panel opened on a wrong selection"
    assert any(want in t for t in texts), (want, texts)
    assert [o.Name for o in doc.Objects] == names and doc.UndoCount == undo


def console_text():
    _, QtGui = qt()
    mw = Gui.getMainWindow()
    texts = [w.toPlainText() for w in mw.findChildren(QtGui.QPlainTextEdit)
             + mw.findChildren(QtGui.QTextEdit) if w.objectName() == "Python console"]
    return texts[0] if texts else ""


@check("workbench activates; the three commands in the toolbar with their icons")
def _():
    _, QtGui = qt()
    Gui.activateWorkbench(WORKBENCH)
    mw = Gui.getMainWindow()
    bars = [b for b in mw.findChildren(QtGui.QToolBar)
            if b.windowTitle() == "Manufacturing Geometry"]
    texts = [a.text() for a in bars[0].actions()]
    for command, text in ((AXIS, "Medial axis of face"), (SURFACE, "Medial surface"),
                          (MID, "Mid-surface for FEM")):
        assert command in Gui.listCommands(), command
        assert text in texts, (text, texts)
        assert os.path.isfile(Gui.Command.get(command).getInfo()["pixmap"]), command


@check("wrong selections show a message and create nothing")
def _():
    import Part
    doc = App.newDocument("MedialGui")
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    tray = thin_wall.add_to(doc, "Tray")
    cyl = doc.addObject("Part::Cylinder", "Cyl")
    cyl.Placement.Base = App.Vector(80, 0, 0)
    sheet = doc.addObject("Part::Feature", "Sheet")
    sheet.Shape = Part.makePlane(5, 5, App.Vector(0, -20, 0))
    doc.recompute()
    state.update(doc=doc, tray=tray)
    side = next(f"Face{i + 1}" for i, f in enumerate(cyl.Shape.Faces)
                if f.Surface.TypeId != "Part::GeomPlane")
    refused(AXIS, [], "Select one planar face")
    refused(AXIS, [(cyl, side)], "not planar")
    refused(AXIS, [(tray, "")], "Select one planar face")
    refused(SURFACE, [], "Select a solid")
    refused(SURFACE, [(sheet, "Face1")], "not a solid")
    refused(SURFACE, [(tray, ""), (cyl, "")], "2 objects")
    refused(MID, [(sheet, "")], "not a solid")
    for obj in (cyl, sheet):
        doc.removeObject(obj.Name)
    doc.recompute()


@check("Medial axis of face: the tray's bottom face, OK creates the axis in one undo step")
def _():
    doc, tray = state["doc"], state["tray"]
    bottom = next(f"Face{i + 1}" for i, f in enumerate(tray.Shape.Faces)
                  if abs(f.BoundBox.ZMax) < 1e-9)
    select([(tray, bottom)])
    undo = doc.UndoCount
    Gui.runCommand(AXIS)
    panel = task_panel()
    assert panel is not None, "no task panel"
    assert f"{tray.Label}.{bottom}" in panel["what"].text(), panel["what"].text()
    panel["tolerance"].setValue(0.01)
    press(panel["ok"])
    assert task_panel() is None, "OK left the panel open"
    new = of_type(doc, "Mfgeom::MedialAxis")
    assert len(new) == 1, new
    obj = new[0]
    assert obj.isValid() and "Touched" not in obj.State, (obj.getStatusString(), obj.State)
    assert doc.UndoCount == undo + 1, (undo, doc.UndoCount)
    # a LENGTH x WIDTH rectangle: four corner branches and the centre line
    assert (obj.BranchCount, obj.JunctionCount) == (5, 2), (obj.BranchCount, obj.JunctionCount)
    assert abs(obj.MaxRadius - thin_wall.WIDTH / 2) < 1e-9, obj.MaxRadius
    vobj = obj.ViewObject
    assert vobj.Visibility and vobj.DisplayMode == "Width", vobj.DisplayMode
    # the wires coloured by width: a corner (radius 0) the ramp's first colour, the
    # centre line (radius WIDTH / 2) its last
    from mfgeom import palette
    colours, radii = vobj.Proxy.colours, list(obj.Radii)
    assert len(colours) == len(radii)
    for r, want in ((0.0, palette.THICKNESS_RAMP[0]),
                    (thin_wall.WIDTH / 2, palette.THICKNESS_RAMP[-1])):
        k = min(range(len(radii)), key=lambda i: abs(radii[i] - r))
        assert max(abs(a - b) for a, b in zip(colours[k], want)) < 1e-9, (r, colours[k])
    assert vobj.Proxy.legend.labels[-1] == f"{thin_wall.WIDTH:.3g} mm"
    assert "mfgeom.make_medial_axis(App.getDocument('MedialGui'), " \
           "(App.getDocument('MedialGui').getObject('Tray'), " in console_text()
    state["axis"] = obj


@check("Medial surface: the panel's default tolerance; OK creates the coloured medial surface")
def _():
    doc, tray = state["doc"], state["tray"]
    select([(tray, "")])
    undo = doc.UndoCount
    Gui.runCommand(SURFACE)
    panel = task_panel()
    assert panel is not None, "no task panel"
    want = 0.005 * tray.Shape.BoundBox.DiagonalLength
    assert abs(panel["tolerance"].value() - want) < 1e-6, (panel["tolerance"].value(), want)
    assert panel["major"].isChecked()
    press(panel["ok"])
    assert task_panel() is None, "OK left the panel open"
    new = of_type(doc, "Mfgeom::MedialSurface")
    assert len(new) == 1 and new[0].isValid(), new
    obj = new[0]
    assert doc.UndoCount == undo + 1
    vobj = obj.ViewObject
    assert vobj.DisplayMode == "Thickness", vobj.DisplayMode
    proxy = vobj.Proxy
    assert proxy.sheets.triangle_count == obj.SheetTriangleOffsets[-1] > 0
    labels = proxy.legend.labels
    assert labels[0] == f"{2 * obj.MinRadius:.3g} mm", labels
    assert labels[-1] == f"{2 * obj.MaxRadius:.3g} mm", labels
    # per-vertex colours: the thinnest vertex gets the ramp's first colour, the thickest
    # its last (the legend's ends)
    from mfgeom import palette
    radii = list(obj.SheetRadii)
    colours = proxy.sheets.colours
    assert max(abs(a - b) for a, b in zip(colours[radii.index(min(radii))],
                                          palette.THICKNESS_RAMP[0])) < 1e-9
    assert max(abs(a - b) for a, b in zip(colours[radii.index(max(radii))],
                                          palette.THICKNESS_RAMP[-1])) < 1e-9
    state["medial"] = obj


def legend_bars(path):
    """The legends' bars in the screenshot ``path``, found in its pixels: (top, bottom)
    rows of every run of at least 40 dark rows down the bars' black left outline (x =
    LEGEND_X[0] of the overlay's unit square, +-2 pixels), top first.  The titles start
    at that x too, but a line of text makes a run of at most ~15 rows."""
    _, QtGui = qt()
    from mfgeom.gui.medial_view import LEGEND_X
    image = QtGui.QImage(path)
    col = int(round((LEGEND_X[0] + 1.0) / 2.0 * image.width()))

    def dark(y):
        return any(sum(QtGui.QColor(image.pixel(x, y)).getRgb()[:3]) < 200
                   for x in range(col - 2, col + 3))

    runs, start = [], None
    for y in range(image.height() + 1):
        if y < image.height() and dark(y):
            start = y if start is None else start
        elif start is not None:
            if y - start >= 40:
                runs.append((start, y - 1))
            start = None
    return runs


def legend_screenshot(name):
    """Saves the MedialGui view (isometric, fit; the tray half-transparent) as ``name`` in
    OUT; returns the path."""
    state["tray"].ViewObject.Transparency = 80
    path = screenshot(OUT, name, doc=state["doc"].Name, clear_selection=True)
    sys.stdout.write(f"screenshot: {path}\n")
    return path


def assert_stacked(path, count):
    """``count`` legend bars in the screenshot, one below the other: each bar starts at
    least its own height (plus a gap for the next title) below the one above, so neither
    the bars nor their labels overlap."""
    bars = legend_bars(path)
    assert len(bars) == count, (count, bars)
    for (top0, bottom0), (top1, bottom1) in zip(bars, bars[1:]):
        height = bottom0 - top0 + 1
        assert height > 60 and bottom1 - top1 + 1 > 60, bars   # bars, not text
        assert top1 - top0 >= height + 20, bars
    return bars


@check("Legends stack: the medial axis' width legend and the medial surface's thickness "
       "legend both shown take two slots one below the other; hiding one moves the "
       "other up, a deleted feature frees its slot")
def _():
    from mfgeom.gui.medial_view import LEGEND_Y, arrange_legends
    doc, tray = state["doc"], state["tray"]
    axis, medial = state["axis"], state["medial"]
    legend = {name: state[name].ViewObject.Proxy.legend for name in ("axis", "medial")}
    assert axis.ViewObject.Visibility and medial.ViewObject.Visibility
    # shown in this order: the axis on top, the medial surface below it
    assert (legend["axis"].slot, legend["medial"].slot) == (0, 1), \
        (legend["axis"].slot, legend["medial"].slot)
    assert legend["axis"].count == legend["medial"].count == 2
    lower, upper = legend["medial"].span, legend["axis"].span
    assert upper[0] - lower[1] >= 0.15, (upper, lower)   # room for the lower title
    full = LEGEND_Y[1] - LEGEND_Y[0]
    bars = assert_stacked(legend_screenshot("medial-legends.png"), 2)
    # the lone legend fills the band; two share it
    axis.ViewObject.Visibility = False
    assert (legend["medial"].slot, legend["medial"].count) == (0, 1)
    assert legend["medial"].span == LEGEND_Y
    (top, bottom), = assert_stacked(legend_screenshot("medial-legend-alone.png"), 1)
    assert bottom - top > 1.9 * (bars[0][1] - bars[0][0]), ((top, bottom), bars)
    assert abs((bottom - top) - full / 2 * 700) < 4, (top, bottom)
    # shown again: the next free slot, below the medial surface's
    axis.ViewObject.Visibility = True
    assert (legend["medial"].slot, legend["axis"].slot) == (0, 1)
    # a third legend (another axis, on a wall) takes the third slot; deleting it in
    # the GUI frees it
    wall = next(f"Face{i + 1}" for i, f in enumerate(tray.Shape.Faces)
                if abs(f.BoundBox.XMin) < 1e-9 and abs(f.BoundBox.XMax) < 1e-9)
    import mfgeom
    doc.openTransaction("third axis")
    extra = mfgeom.make_medial_axis(doc, (tray, wall), 0.05)
    doc.commitTransaction()
    third = extra.ViewObject.Proxy.legend
    assert [lg.slot for lg in (legend["medial"], legend["axis"], third)] == [0, 1, 2]
    assert_stacked(legend_screenshot("medial-legends-3.png"), 3)
    extra_name = extra.Name
    select([(extra, "")])
    dialogs.take()
    Gui.runCommand("Std_Delete")
    Gui.updateGui()
    assert doc.getObject(extra_name) is None, [o.Name for o in doc.Objects]
    assert not dialogs.take()
    assert [(lg.slot, lg.count) for lg in (legend["medial"], legend["axis"])] \
        == [(0, 2), (1, 2)]
    # undo the deletion: it is back in the third slot; undo its creation (no view
    # provider hook runs): its slot is freed all the same
    doc.undo()
    extra = doc.getObject(extra_name)
    assert extra is not None and extra.ViewObject.Visibility
    assert (extra.ViewObject.Proxy.legend.slot, legend["medial"].count) == (2, 3)
    doc.undo()
    assert doc.getObject(extra_name) is None
    assert [(lg.slot, lg.count) for lg in (legend["medial"], legend["axis"])] \
        == [(0, 2), (1, 2)]
    assert len(arrange_legends(doc)) == 2
    assert_stacked(legend_screenshot("medial-legends-after-delete.png"), 2)


@check("Mid-surface for FEM: the medial surface selected, a CSV path, OK")
def _():
    doc = state["doc"]
    medial = state["medial"]
    select([(medial, "")])
    path = os.path.join(tempfile.mkdtemp(), "tray-thickness.csv")
    Gui.runCommand(MID)
    panel = task_panel()
    assert panel is not None, "no task panel"
    assert not panel["tolerance"].isEnabled()
    panel["csv"].setText(path)
    press(panel["ok"])
    assert task_panel() is None, "OK left the panel open"
    new = of_type(doc, "Mfgeom::MidSurface")
    assert len(new) == 1 and new[0].isValid(), new
    obj = new[0]
    assert os.path.isfile(path)
    with open(path, encoding="utf-8") as f:
        assert sum(1 for _line in f) == len(obj.Thickness) + 1
    assert obj.Shape.Faces and obj.MinThickness > 0
    assert abs(obj.MinThickness - thin_wall.RIB) < 2 * medial.Tolerance.Value, \
        obj.MinThickness
    assert obj.ViewObject.DisplayMode == "Thickness"
    assert obj.ViewObject.Proxy.sheets.triangle_count > 0
    state["mid"] = obj


@check("screenshot")
def _():
    doc = state["doc"]
    os.makedirs(OUT, exist_ok=True)
    tray = state["tray"]
    tray.ViewObject.Transparency = 80
    if "mid" in state:
        for name in ("medial", "axis"):
            state[name].ViewObject.Visibility = False
        state["mid"].ViewObject.Visibility = True
        name = "medial-mid-surface.png"
    else:
        name = "medial-axis.png"
    path = screenshot(OUT, name, doc=doc.Name, clear_selection=True)
    assert os.path.getsize(path) > 5000
    state["image"] = path


@check("undo removes the last feature, redo brings it back")
def _():
    doc = state["doc"]
    count = len(doc.Objects)
    doc.undo()
    assert len(doc.Objects) < count
    doc.redo()
    assert len(doc.Objects) == count and all(o.isValid() for o in doc.Objects)


@check("Mid-surface for FEM from a solid: a 40 x 30 x 2 plate selected, the panel, OK: "
       "the shell at mid-thickness (z = 1), thickness 2, the document valid, one undo "
       "step")
def _():
    import numpy as np
    A, B, C = 40.0, 30.0, 2.0
    doc = App.newDocument("MidFromSolid")
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    plate = doc.addObject("Part::Box", "Plate")
    plate.Length, plate.Width, plate.Height = A, B, C
    doc.recompute()
    select([(plate, "")])
    undo = doc.UndoCount
    Gui.runCommand(MID)
    panel = task_panel()
    assert panel is not None, "no task panel"
    assert panel["what"].text() == "Solid: Plate", panel["what"].text()
    assert panel["tolerance"].isEnabled() and panel["deflection"].isEnabled()
    tol = 0.005 * plate.Shape.BoundBox.DiagonalLength   # the offered default
    assert abs(panel["tolerance"].value() - tol) < 1e-6, (panel["tolerance"].value(), tol)
    tol = panel["tolerance"].value()
    press(panel["ok"])
    assert task_panel() is None, "OK left the panel open: " + panel["message"].text()
    mids, medials = of_type(doc, "Mfgeom::MidSurface"), of_type(doc, "Mfgeom::MedialSurface")
    assert len(mids) == 1 and len(medials) == 1, (mids, medials)
    obj, medial = mids[0], medials[0]
    assert obj.Source == medial and medial.Source == plate and medial.MajorOnly
    assert abs(medial.Tolerance.Value - tol) < 1e-9, medial.Tolerance.Value
    for o in doc.Objects:   # the document valid: no error objects, nothing left to do
        assert o.isValid() and "Touched" not in o.State, (o.Name, o.State,
                                                          o.getStatusString())
    assert doc.UndoCount == undo + 1, (undo, doc.UndoCount)
    assert "mfgeom.make_mid_surface(App.getDocument('MidFromSolid'), " \
           "App.getDocument('MidFromSolid').getObject('Plate'), None, " in console_text()
    # the shell: the plate's mid-plane z = C / 2 where the top and bottom faces are
    # the nearest, the rectangle [C/2, A - C/2] x [C/2, B - C/2] (the major part)
    shape = obj.Shape
    assert shape.ShapeType in ("Shell", "Face") and shape.isValid(), shape.ShapeType
    assert shape.Faces and not shape.Solids
    for face in shape.Faces:
        assert face.Surface.TypeId == "Part::GeomPlane", face.Surface.TypeId
        for v in face.Vertexes:
            assert abs(v.Point.z - C / 2) < 1e-6, v.Point
    box = shape.BoundBox
    for got, want in ((box.XMin, C / 2), (box.XMax, A - C / 2), (box.YMin, C / 2),
                      (box.YMax, B - C / 2)):
        assert abs(got - want) <= tol, (box, tol)
    assert abs(shape.Area - (A - C) * (B - C)) <= 2 * tol * (A + B), shape.Area
    # the thickness data: 2 everywhere
    thick = np.array(obj.Thickness)
    assert len(thick) == len(obj.ThicknessPoints) > 0
    assert np.abs(thick - C).max() <= 2 * tol, (thick.min(), thick.max())
    assert len(obj.FaceThickness) == len(shape.Faces)
    for value in list(obj.FaceThickness) + [obj.MinThickness, obj.MaxThickness,
                                            obj.MeanThickness]:
        assert abs(value - C) <= 2 * tol, value
    # the medial surface it was made from is hidden: one legend, the mid-surface's
    assert not medial.ViewObject.Visibility and obj.ViewObject.Visibility
    assert obj.ViewObject.DisplayMode == "Thickness"
    assert obj.ViewObject.Proxy.sheets.triangle_count > 0
    # one thickness (the radii differ by rounding only): one histogram bin, one colour
    # (the ramp's middle) and one label on the legend and in the panel's words
    assert len(obj.Histogram) == 2 and "100.0 %" in obj.Histogram[1], obj.Histogram
    from mfgeom import palette
    from mfgeom.gui.medial_panel import legend_text
    colours = obj.ViewObject.Proxy.sheets.colours
    assert np.abs(colours - palette.ramp_color(0.5)).max() < 1e-12, colours
    assert obj.ViewObject.Proxy.legend.labels == ["2 mm"], \
        obj.ViewObject.Proxy.legend.labels
    assert legend_text(obj.MinThickness, obj.MaxThickness) == \
        "Colour scale: one thickness, 2 mm"
    # edited (double click): the tolerance and deflection shown are its medial
    # surface's, read-only here
    Gui.ActiveDocument.setEdit(obj.Name, 0)
    panel = task_panel()
    assert panel is not None, "no edit panel"
    assert not panel["tolerance"].isEnabled() and not panel["deflection"].isEnabled()
    shown = (panel["tolerance"].value(), panel["deflection"].value())
    want = (medial.Tolerance.Value, medial.Deflection.Value)
    assert max(abs(a - b) for a, b in zip(shown, want)) < 1e-6, (shown, want)
    press(panel["cancel"])
    assert task_panel() is None
    plate.ViewObject.Transparency = 80
    view = Gui.getDocument(doc.Name).ActiveView
    view.viewIsometric()
    view.fitAll()
    Gui.updateGui()
    view.saveImage(os.path.join(OUT, "mid-surface-plate.png"), 1000, 700, "White")
    # one undo step takes both away, redo brings both back
    doc.undo()
    assert [o.Name for o in doc.Objects] == ["Plate"], [o.Name for o in doc.Objects]
    doc.redo()
    assert len(doc.Objects) == 3 and all(o.isValid() for o in doc.Objects)
    # its medial surface shown too, saved and opened again: two legends, stacked
    medial.ViewObject.Visibility = True
    path = os.path.join(tempfile.mkdtemp(), "plate.FCStd")
    doc.saveAs(path)
    App.closeDocument(doc.Name)   # with its legends: quietly (no traceback in the log)
    Gui.updateGui()
    doc = App.openDocument(path)
    Gui.updateGui()
    legends = [o.ViewObject.Proxy.legend for o in doc.Objects
               if o.Name.startswith(("MidSurface", "MedialSurface"))]
    assert len(legends) == 2, legends
    assert sorted((lg.slot, lg.count) for lg in legends) == [(0, 2), (1, 2)], \
        [(lg.slot, lg.count) for lg in legends]
    App.closeDocument(doc.Name)
    Gui.updateGui()


finish("freecad-gui-medial")
