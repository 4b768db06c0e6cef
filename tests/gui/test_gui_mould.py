# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD GUI test of the mould commands (issue 21), run as a macro under a virtual X
server by tests/gui/run_gui_tests.sh: ``xvfb-run -a freecad tests/gui/test_gui_mould.py``.

On the bundled cup with a radial hole and its Mould analysis: "Parting line" with the
analysis selected opens its task panel and OK creates a valid PartingLine (one planar
outer loop, the side core's shut-off loop) drawn thick in the parting colour; "Parting
surface" on it, with a margin typed in the panel, creates the surface; "Core and cavity"
on the analysis creates MouldBlocks whose checks all pass, core / cavity / insert
coloured by side; each through the Python console (the make call echoed) in one undo
step; a wrong selection shows a message and creates nothing; editing the margin in the
panel recomputes; a screenshot of the blocks is saved.  Prints
``freecad-gui-mould: N passed, M failed``; leaves with os._exit(rc).
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
COMMANDS = {"line": "Mfgeom_PartingLine", "surface": "Mfgeom_PartingSurface",
            "blocks": "Mfgeom_MouldBlocks"}
TYPES = {"line": "Mfgeom::PartingLine", "surface": "Mfgeom::PartingSurface",
         "blocks": "Mfgeom::MouldBlocks"}

dialogs = DialogCloser()


def task_panel():
    """The open mould panel's widgets by object name, and the task view's buttons."""
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
    widgets["apply"] = boxes[0].button(QtGui.QDialogButtonBox.Apply)
    return widgets


def of_type(doc, kind):
    return [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "Type", "") == TYPES[kind]]


def rgb(c):
    return tuple(round(x, 3) for x in c[:3])


def run_command(kind, selected):
    Gui.Selection.clearSelection()
    for obj in selected:
        Gui.Selection.addSelection(obj)
    Gui.runCommand(COMMANDS[kind])
    return task_panel()


@check("workbench activates; the three mould commands in the toolbar")
def _():
    _, QtGui = qt()
    Gui.activateWorkbench(WORKBENCH)
    mw = Gui.getMainWindow()
    bars = [b for b in mw.findChildren(QtGui.QToolBar)
            if b.windowTitle() == "Manufacturing Geometry"]
    texts = [a.text() for a in bars[0].actions()]
    for text in ("Parting line", "Parting surface", "Core and cavity"):
        assert text in texts, texts
    for cmd in COMMANDS.values():
        assert os.path.isfile(Gui.Command.get(cmd).getInfo()["pixmap"]), cmd


@check("a wrong selection (nothing, the part) shows a message and creates nothing")
def _():
    import cup_hole
    import mfgeom
    doc = App.newDocument("MouldGui")
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    part = doc.addObject("Part::Feature", "CupHole")
    part.Shape = cup_hole.make()
    part.Placement = App.Placement(App.Vector(5, -3, 2), App.Rotation(App.Vector(1, 2, 0.5), 20))
    doc.recompute()
    analysis = mfgeom.make_parting_analysis(doc, part, mode="Mould")
    state.update(doc=doc, part=part, analysis=analysis)
    undo = doc.UndoCount
    count = len(doc.Objects)
    for selected in ([], [part]):
        dialogs.take()
        panel = run_command("line", selected)
        assert pump(lambda: dialogs.texts, 5), f"no message for selection {selected}"
        texts = dialogs.take()
        assert panel is None and task_panel() is None, "a panel opened on a wrong selection"
        assert any("parting analysis" in t for t in texts), texts
    assert len(doc.Objects) == count and doc.UndoCount == undo


@check("Parting line: OK creates a valid line in one undo step, drawn thick")
def _():
    from mfgeom import palette
    doc, analysis = state["doc"], state["analysis"]
    undo = doc.UndoCount
    panel = run_command("line", [analysis])
    assert panel is not None, "no task panel"
    assert panel["zeroDraftSide"].currentData() == "Cavity"
    press(panel["ok"])
    assert task_panel() is None, "OK left the panel open: " + \
        (panel["message"].text() if panel else "")
    lines = of_type(doc, "line")
    assert len(lines) == 1
    line = lines[0]
    assert line.isValid() and "Touched" not in line.State, line.getStatusString()
    assert doc.UndoCount == undo + 1, (undo, doc.UndoCount)
    assert line.LoopCount == 1 and line.Loops[0].startswith("outer, planar"), line.Loops
    assert len(line.ShutOffLoops) == 1 and len(line.Shape.Wires) == 2
    assert line.ViewObject.LineWidth >= 4
    assert rgb(line.ViewObject.LineColor) == rgb(palette.PARTING_LINE)
    state["line"] = line


@check("Parting surface: the margin typed in the panel, OK creates the surface")
def _():
    doc, line = state["doc"], state["line"]
    undo = doc.UndoCount
    panel = run_command("surface", [line])
    assert panel is not None, "no task panel"
    panel["margin"].setValue(6.0)
    press(panel["ok"])
    assert task_panel() is None, "OK left the panel open"
    surfaces = of_type(doc, "surface")
    assert len(surfaces) == 1 and surfaces[0].isValid(), surfaces
    surface = surfaces[0]
    assert surface.Margin.Value == 6.0 and surface.PartingSurfaceCount == 1
    assert surface.ShutOffCount == 0 and surface.Shape.Faces
    assert doc.UndoCount == undo + 1


@check("Core and cavity: OK creates the blocks, every check passes, coloured by side")
def _():
    from mfgeom import palette
    doc, analysis = state["doc"], state["analysis"]
    undo = doc.UndoCount
    panel = run_command("blocks", [analysis])
    assert panel is not None, "no task panel"
    panel["margin"].setValue(5.0)
    press(panel["ok"])
    assert task_panel() is None, "OK left the panel open: " + \
        (panel["message"].text() if panel else "")
    blocks = of_type(doc, "blocks")
    assert len(blocks) == 1
    mb = blocks[0]
    assert mb.isValid() and "Touched" not in mb.State, mb.getStatusString()
    assert doc.UndoCount == undo + 1
    assert mb.Checks and all(c.endswith(": ok") for c in mb.Checks), mb.Checks
    assert mb.Core.Solids and mb.Cavity.Solids and len(mb.Inserts.Solids) == 1
    # the line existed (ZeroDraftSide Cavity): reused; a surface of margin 5 was made
    assert len(of_type(doc, "line")) == 1 and len(of_type(doc, "surface")) == 2
    colours = [rgb(c) for c in mb.ViewObject.DiffuseColor]
    nc, nv = len(mb.Core.Faces), len(mb.Cavity.Faces)
    assert len(colours) == len(mb.Shape.Faces), (len(colours), len(mb.Shape.Faces))
    assert set(colours[:nc]) == {rgb(palette.MOULD_CORE)}
    assert set(colours[nc:nc + nv]) == {rgb(palette.MOULD_CAVITY)}
    assert set(colours[nc + nv:]) == {rgb(palette.MOULD_INSERT)}
    state["blocks"] = mb
    state["image"] = screenshot(OUT, "mould.png", clear_selection=True)


@check("editing the margin in the panel recomputes the blocks (one undo step)")
def _():
    doc, mb = state["doc"], state["blocks"]
    before = mb.Volumes[0]
    undo = doc.UndoCount
    Gui.ActiveDocument.setEdit(mb.Name, 0)
    panel = task_panel()
    assert panel is not None and abs(panel["margin"].value() - 5.0) < 1e-9
    panel["margin"].setValue(8.0)
    press(panel["ok"])
    assert task_panel() is None
    assert mb.isValid() and mb.Margin.Value == 8.0 and mb.Volumes[0] > before
    assert all(c.endswith(": ok") for c in mb.Checks), mb.Checks
    assert doc.UndoCount == undo + 1


@check("Export STEP from the blocks' panel writes core, cavity and insert")
def _():
    import tempfile
    import Part
    from mfgeom.gui.mould_panel import MouldPanel
    mb = state["blocks"]
    Gui.ActiveDocument.setEdit(mb.Name, 0)
    panel = task_panel()
    assert panel is not None and panel["exportStep"].isEnabled()
    press(panel["ok"])
    assert task_panel() is None
    with tempfile.TemporaryDirectory() as out:
        # the button's action with the folder given (the button asks with a dialog)
        files = MouldPanel("blocks", obj=mb).export_step(out)
        assert sorted(files) == ["cavity", "core", "insert1"], files
        total = sum(Part.read(f).Volume for f in files.values()) + state["part"].Shape.Volume
        assert abs(total - mb.Volumes[0]) <= 1e-6 * mb.Volumes[0], (total, mb.Volumes[0])
        assert sorted(os.listdir(out)) == sorted(os.path.basename(f) for f in files.values())


@check("the make calls echoed in the Python console")
def _():
    _, QtGui = qt()
    mw = Gui.getMainWindow()
    texts = [w.toPlainText() for w in mw.findChildren(QtGui.QPlainTextEdit)
             + mw.findChildren(QtGui.QTextEdit) if w.objectName() == "Python console"]
    assert texts, "no console"
    for call in ("mfgeom.make_parting_line(App.getDocument('MouldGui'), ",
                 "mfgeom.make_parting_surface(App.getDocument('MouldGui'), ",
                 "mfgeom.make_mould_blocks(App.getDocument('MouldGui'), "):
        assert call in texts[0], (call, texts[0][-800:])


finish("freecad-gui-mould")
