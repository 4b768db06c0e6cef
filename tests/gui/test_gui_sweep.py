# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD GUI test of the rotational sweep (issue 8), run as a macro under a virtual X
server by tests/gui/run_gui_tests.sh: ``xvfb-run -a freecad tests/gui/test_gui_sweep.py``.

On a 2 x 3 x 4 box: the command in the toolbar; a wrong selection (nothing, a face that
is no solid, two solids) shows a message and creates nothing; the box's vertical edge
selected, the command opens the task panel with that edge as the axis, OK creates a
valid sweep (not Touched) through the console in one undo step, shown (visible, display
mode "Mesh", the Coin face set holds the result's triangles) with the analytic volume;
double click edits it: Solid on Apply (Part's display mode, a valid solid), a zero custom
direction shows the message and keeps the sweep; a screenshot is saved; undo removes the
sweep.  Prints ``freecad-gui-sweep: N passed, M failed``; leaves with os._exit(rc).
"""

import math
import os
import sys

import FreeCAD as App
import FreeCADGui as Gui

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
if os.path.join(ROOT, "workbench") not in sys.path:
    sys.path.append(os.path.join(ROOT, "workbench"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_harness import DialogCloser, check, finish, press, pump, qt, screenshot, state  # noqa: E402

WORKBENCH = "MfgeomWorkbench"
COMMAND = "Mfgeom_RotationalSweep"
OUT = os.environ.get("MFGEOM_GUI_OUT") or os.path.join(ROOT, "out", "gui-tests")
A, B, C = 2.0, 3.0, 4.0

dialogs = DialogCloser()


def task_panel():
    """The open sweep panel's widgets by object name, and the task view's buttons."""
    _, QtGui = qt()
    Gui.updateGui()
    mw = Gui.getMainWindow()
    combos = [w for w in mw.findChildren(QtGui.QComboBox)
              if w.objectName() == "representation" and w.isVisible()]
    if not Gui.Control.activeDialog() or not combos:
        return None
    panel = combos[0].parentWidget()
    widgets = {w.objectName(): w for w in panel.findChildren(QtGui.QWidget) if w.objectName()}
    boxes = [b for b in mw.findChildren(QtGui.QDialogButtonBox)
             if b.isVisible() and b.button(QtGui.QDialogButtonBox.Ok) is not None]
    assert len(boxes) == 1, f"{len(boxes)} visible OK button boxes"
    for key, role in (("ok", QtGui.QDialogButtonBox.Ok), ("cancel", QtGui.QDialogButtonBox.Cancel),
                      ("apply", QtGui.QDialogButtonBox.Apply)):
        widgets[key] = boxes[0].button(role)
    return widgets


def sweeps(doc):
    return [o for o in doc.Objects
            if getattr(getattr(o, "Proxy", None), "Type", "") == "Mfgeom::RotationalSweep"]


@check("workbench activates; command in toolbar with its icon")
def _():
    _, QtGui = qt()
    Gui.activateWorkbench(WORKBENCH)
    assert COMMAND in Gui.listCommands()
    mw = Gui.getMainWindow()
    bars = [b for b in mw.findChildren(QtGui.QToolBar)
            if b.windowTitle() == "Manufacturing Geometry"]
    texts = [a.text() for a in bars[0].actions()]
    assert "Rotational sweep" in texts, texts
    assert os.path.isfile(Gui.Command.get(COMMAND).getInfo()["pixmap"])


@check("wrong selection (nothing, a face, two solids) shows a message and creates nothing")
def _():
    import Part
    doc = App.newDocument("SweepGui")
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = A, B, C
    other = doc.addObject("Part::Box", "Other")
    other.Placement.Base = App.Vector(10, 0, 0)
    sheet = doc.addObject("Part::Feature", "Sheet")
    sheet.Shape = Part.makePlane(2, 2, App.Vector(0, -5, 0))
    doc.recompute()
    state.update(doc=doc, box=box, other=other, sheet=sheet)
    undo = doc.UndoCount
    for select, want in (([], "Select a solid"), ([(sheet, "Face1")], "neither a solid"),
                         ([(box, ""), (other, "")], "one solid")):
        Gui.Selection.clearSelection()
        for obj, sub in select:
            if sub:
                Gui.Selection.addSelection(obj, sub)
            else:
                Gui.Selection.addSelection(obj)
        dialogs.take()
        Gui.runCommand(COMMAND)
        assert pump(lambda: dialogs.texts, 5), f"no message for selection {select}"
        texts = dialogs.take()
        assert task_panel() is None, "a panel opened on a wrong selection"
        assert any(want in t for t in texts), (want, texts)
        assert sweeps(doc) == [] and doc.UndoCount == undo
    other.Visibility = False
    sheet.Visibility = False


@check("the box's edge selected: OK creates a valid, visible sweep in one undo step")
def _():
    doc, box = state["doc"], state["box"]
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(box, "Edge1")   # Part::Box Edge1: (0,0,0) -> (0,0,H)
    undo = doc.UndoCount
    Gui.runCommand(COMMAND)
    panel = task_panel()
    assert panel is not None, "no task panel"
    assert panel["axis"].currentData() == "object", panel["axis"].currentText()
    assert "Box.Edge1" in panel["axis"].currentText()
    d = [panel[f"d{c}"].value() for c in "xyz"]
    assert d == [0.0, 0.0, 1.0] and not panel["dz"].isEnabled(), d
    # the defaults scaled to the part: 1/1000 of its 5.39 mm diagonal, rounded down
    assert (panel["tolerance"].value(), panel["deflection"].value()) == (0.005, 0.005)
    assert "5.385 mm diagonal" in panel["defaultsNote"].text(), panel["defaultsNote"].text()
    panel["angle"].setValue(90.0)
    panel["tolerance"].setValue(0.1)   # the user's value goes into the call as it is
    press(panel["ok"])
    left = task_panel()
    assert left is None, "OK left the panel open: " + (left["message"].text() if left else "")
    new = sweeps(doc)
    assert len(new) == 1, new
    obj = new[0]
    assert obj.isValid() and "Touched" not in obj.State, (obj.getStatusString(), obj.State)
    assert doc.UndoCount == undo + 1, (undo, doc.UndoCount)
    assert obj.AxisObject is not None and obj.AxisObject[1] == ["Edge1"]
    exact = C * (A * B + (A * A + B * B) * math.pi / 4)
    assert abs(obj.Volume - exact) <= 0.1 * obj.Area, (obj.Volume, exact)
    vobj = obj.ViewObject
    assert obj.Visibility and vobj.Visibility
    assert vobj.DisplayMode == "Mesh", vobj.DisplayMode
    proxy = vobj.Proxy
    assert proxy._faces.coordIndex.getNum() == 4 * obj.TriangleCount
    assert proxy.triangle_count == obj.TriangleCount > 0 and proxy.edge_count > 0
    state["obj"] = obj


@check("double click edits: Solid on Apply, a zero direction is refused")
def _():
    obj = state["obj"]
    vobj = obj.ViewObject
    vobj.Proxy.doubleClicked(vobj)
    panel = task_panel()
    assert panel is not None, "double click opened no panel"
    assert "Volume" in panel["result"].text(), panel["result"].text()
    undo = obj.Document.UndoCount
    # Solid: planar faces of the exact mesh's coplanar triangles (zero-area ones join a
    # neighbour), a valid solid of the library's volume, Part's display mode
    panel["representation"].setCurrentIndex(1)
    press(panel["apply"])
    assert obj.Representation == "Solid" and obj.isValid(), obj.getStatusString()
    assert obj.Shape.isValid() and len(obj.Shape.Solids) == 1
    assert abs(obj.Shape.Volume / obj.Volume - 1) < 1e-6
    assert len(obj.Shape.Faces) < obj.TriangleCount
    assert vobj.DisplayMode == "Flat Lines", vobj.DisplayMode
    assert obj.Document.UndoCount == undo + 1
    # a custom axis with a zero direction: the message, the sweep unchanged
    volume = obj.Volume
    panel["axis"].setCurrentIndex(panel["axis"].findData("custom"))
    for c in "xyz":
        panel[f"d{c}"].setValue(0.0)
    press(panel["apply"])
    assert "direction is zero" in panel["message"].text(), panel["message"].text()
    assert obj.isValid() and obj.Volume == volume and obj.AxisObject is not None
    assert obj.Document.UndoCount == undo + 1
    press(panel["cancel"])
    assert task_panel() is None
    if obj.Representation == "Solid":
        obj.Document.undo()   # back to Mesh
        obj.Document.recompute()
    assert obj.Representation == "Mesh" and obj.isValid()
    Gui.updateGui()
    assert vobj.DisplayMode == "Mesh", vobj.DisplayMode


@check("screenshot")
def _():
    path = screenshot(OUT, "sweep.png")
    assert os.path.getsize(path) > 5000
    state["image"] = path


@check("make function echoed in the Python console")
def _():
    _, QtGui = qt()
    mw = Gui.getMainWindow()
    texts = [w.toPlainText() for w in mw.findChildren(QtGui.QPlainTextEdit)
             + mw.findChildren(QtGui.QTextEdit) if w.objectName() == "Python console"]
    call = ("mfgeom.make_rotational_sweep(App.getDocument('SweepGui'), "
            "App.getDocument('SweepGui').getObject('Box'), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), "
            "90.0, 0.1, deflection=0.005, axis=(App.getDocument('SweepGui').getObject('Box'), "
            "'Edge1'))")
    assert texts and call in texts[0], texts[0][-600:] if texts else "no console"


@check("undo removes the sweep, redo brings it back")
def _():
    doc = state["doc"]
    doc.undo()
    assert sweeps(doc) == [], sweeps(doc)
    doc.redo()
    assert len(sweeps(doc)) == 1 and sweeps(doc)[0].isValid()



@check("only the solid selected: a global axis through an edited point")
def _():
    doc, box = state["doc"], state["box"]
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(box)
    before = sweeps(doc)
    Gui.runCommand(COMMAND)
    panel = task_panel()
    assert panel is not None, "no task panel"
    assert panel["axis"].currentData() == "Z" and panel["axis"].findData("object") < 0
    panel["axis"].setCurrentIndex(panel["axis"].findData("X"))
    assert [panel[f"d{c}"].value() for c in "xyz"] == [1.0, 0.0, 0.0]
    assert panel["py"].isEnabled() and not panel["dx"].isEnabled()
    # the box's top back edge along x (y = B, z = C); the library's first version
    # leaves the swept surface open about the bottom one (y = B, z = 0)
    panel["py"].setValue(B)
    panel["pz"].setValue(C)
    panel["angle"].setValue(90.0)
    press(panel["ok"])
    assert task_panel() is None, "OK left the panel open"
    new = [o for o in sweeps(doc) if o not in before]
    assert len(new) == 1 and new[0].isValid(), new
    obj = new[0]
    assert obj.AxisObject is None
    assert (obj.AxisPoint.y, obj.AxisPoint.z, obj.AxisDirection.x) == (B, C, 1.0)
    # about the box's A edge: the B x C section turns about its corner
    exact = A * (B * C + (B * B + C * C) * math.pi / 4)
    assert abs(obj.Volume - exact) <= 0.01 * obj.Area, (obj.Volume, exact)


finish("freecad-gui-sweep")
