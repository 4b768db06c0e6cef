# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD GUI test of the "Thickness analysis" command (issue 21, section 4), run as a
macro under a virtual X server by tests/gui/run_gui_tests.sh:
``xvfb-run -a freecad tests/gui/test_gui_thickness.py``.

On the bundled ribbed tray (walls 3, rib 2): a wrong selection shows a message and
creates nothing; with the tray selected the command opens its task panel, the thresholds
typed there, OK creates a valid ThicknessAnalysis in one undo step through the Python
console; the view colours every sample (pink below the minimum, brown above the maximum,
the blue ramp between), the legend shows the window and both highlight swatches, the
thinnest and thickest spots are marked; the panel shows the histogram and exports the
CSV; editing a threshold recolours; a screenshot is saved.  Prints
``freecad-gui-thickness: N passed, M failed``; leaves with os._exit(rc).
"""

import os
import sys

import FreeCAD as App
import FreeCADGui as Gui

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
for path in (os.path.join(ROOT, "examples", "parts"), os.path.join(ROOT, "workbench")):
    if path not in sys.path:
        sys.path.append(path)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_harness import DialogCloser, check, finish, press, pump, qt, screenshot, state  # noqa: E402

WORKBENCH = "MfgeomWorkbench"
OUT = os.environ.get("MFGEOM_GUI_OUT") or os.path.join(ROOT, "out", "gui-tests")
COMMAND = "Mfgeom_ThicknessAnalysis"
TYPE = "Mfgeom::ThicknessAnalysis"

dialogs = DialogCloser()


def task_panel():
    """The open panel's widgets by object name, and the task view's buttons."""
    _, QtGui = qt()
    Gui.updateGui()
    mw = Gui.getMainWindow()
    labels = [w for w in mw.findChildren(QtGui.QLabel) if w.objectName() == "what"
              and w.isVisible()]
    if not Gui.Control.activeDialog() or not labels:
        return None
    panel = labels[0].parentWidget()
    widgets = {w.objectName(): w for w in panel.findChildren(QtGui.QWidget) if w.objectName()}
    boxes = [b for b in mw.findChildren(QtGui.QDialogButtonBox)
             if b.isVisible() and b.button(QtGui.QDialogButtonBox.Ok) is not None]
    assert len(boxes) == 1, f"{len(boxes)} visible OK button boxes"
    widgets["ok"] = boxes[0].button(QtGui.QDialogButtonBox.Ok)
    return widgets


def analyses(doc):
    return [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "Type", "") == TYPE]


def run_command(selected):
    Gui.Selection.clearSelection()
    for obj in selected:
        Gui.Selection.addSelection(obj)
    Gui.runCommand(COMMAND)
    return task_panel()


@check("workbench activates; Thickness analysis in the toolbar with its icon")
def _():
    _, QtGui = qt()
    Gui.activateWorkbench(WORKBENCH)
    mw = Gui.getMainWindow()
    bars = [b for b in mw.findChildren(QtGui.QToolBar)
            if b.windowTitle() == "Manufacturing Geometry"]
    assert "Thickness analysis" in [a.text() for a in bars[0].actions()]
    assert os.path.isfile(Gui.Command.get(COMMAND).getInfo()["pixmap"])


@check("a wrong selection (nothing, a face object) shows a message and creates nothing")
def _():
    import Part
    import thin_wall
    doc = App.newDocument("ThicknessGui")
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    tray = doc.addObject("Part::Feature", "Tray")
    tray.Shape = thin_wall.make()
    face = doc.addObject("Part::Feature", "Sheet")
    face.Shape = Part.makePlane(10, 10, App.Vector(100, 0, 0))
    doc.recompute()
    state.update(doc=doc, tray=tray)
    undo, count = doc.UndoCount, len(doc.Objects)
    for selected, words in (([], "Select a solid"), ([face], "not a solid")):
        dialogs.take()
        panel = run_command(selected)
        assert pump(lambda: dialogs.texts, 5), f"no message for selection {selected}"
        texts = dialogs.take()
        assert panel is None and task_panel() is None, "a panel opened on a wrong selection"
        assert any(words in t for t in texts), texts
    assert len(doc.Objects) == count and doc.UndoCount == undo


@check("OK creates a valid analysis in one undo step with the thresholds typed")
def _():
    doc, tray = state["doc"], state["tray"]
    undo = doc.UndoCount
    panel = run_command([tray])
    assert panel is not None, "no task panel"
    panel["minThickness"].setValue(2.5)
    panel["maxThickness"].setValue(3.6)
    press(panel["ok"])
    assert task_panel() is None, "OK left the panel open: " + \
        (panel["message"].text() if panel else "")
    found = analyses(doc)
    assert len(found) == 1
    a = found[0]
    assert a.isValid() and "Touched" not in a.State, a.getStatusString()
    assert doc.UndoCount == undo + 1
    assert a.MinThickness.Value == 2.5 and a.MaxThickness.Value == 3.6
    assert abs(a.Thinnest - 2.0) < 1e-6 and a.Thickest > 3.6, (a.Thinnest, a.Thickest)
    state["a"] = a


@check("samples coloured: pink thin, brown thick, the blue ramp between; legend, marks")
def _():
    import numpy as np
    from mfgeom import palette
    a = state["a"]
    vp = a.ViewObject.Proxy
    assert a.ViewObject.DisplayMode == "Thickness", a.ViewObject.DisplayMode
    colours = np.asarray(vp.samples.colours)
    thick = np.asarray(a.VertexThickness)
    assert colours.shape == (len(thick), 3)
    assert np.allclose(colours[thick < 2.5], palette.THIN_WALL)
    assert np.allclose(colours[thick > 3.6], palette.THICK_WALL)
    mid = (thick >= 2.5) & (thick <= 3.6)
    assert mid.sum() > len(thick) // 2
    assert np.allclose(colours[mid], palette.wall_colors(thick[mid], 2.5, 3.6))
    assert vp.legend.labels[0] == "2.5 mm" and vp.legend.labels[-1] == "3.6 mm", vp.legend.labels
    assert vp.mark_labels == ["thinnest 2 mm", f"thickest {a.Thickest:.3g} mm"], vp.mark_labels
    state["image"] = screenshot(OUT, "thickness.png", clear_selection=True)


@check("the panel shows the histogram and exports the CSV; editing recolours")
def _():
    import tempfile
    import numpy as np
    from mfgeom import palette
    from mfgeom.gui.thickness_panel import ThicknessPanel
    doc, a = state["doc"], state["a"]
    Gui.ActiveDocument.setEdit(a.Name, 0)
    panel = task_panel()
    assert panel is not None and abs(panel["minThickness"].value() - 2.5) < 1e-9
    text = panel["histogram"].text()
    assert "Area by wall thickness" in text and "thin" in text and "thick" in text, text
    assert panel["exportCsv"].isEnabled()
    undo = doc.UndoCount
    panel["minThickness"].setValue(1.5)
    press(panel["ok"])
    assert task_panel() is None
    assert a.isValid() and a.MinThickness.Value == 1.5 and doc.UndoCount == undo + 1
    colours = np.asarray(a.ViewObject.Proxy.samples.colours)
    assert not np.isclose(colours, palette.THIN_WALL, atol=1e-6).all(axis=1).any(), \
        "a sample is still drawn thin"
    with tempfile.TemporaryDirectory() as out:
        path = ThicknessPanel(obj=a).export_csv(os.path.join(out, "tray.csv"))
        with open(path) as f:
            assert f.readline().startswith("x_mm,y_mm,z_mm,face,thickness_mm,status")
    Gui.Control.closeDialog()


@check("the make call echoed in the Python console")
def _():
    _, QtGui = qt()
    mw = Gui.getMainWindow()
    texts = [w.toPlainText() for w in mw.findChildren(QtGui.QPlainTextEdit)
             + mw.findChildren(QtGui.QTextEdit) if w.objectName() == "Python console"]
    assert texts, "no console"
    assert "mfgeom.make_thickness_analysis(App.getDocument('ThicknessGui'), " in texts[0], \
        texts[0][-800:]


finish("freecad-gui-thickness")
