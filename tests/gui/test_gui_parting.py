# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD GUI test of the parting analysis (issue 7), run as a macro under a virtual X
server by tests/gui/run_gui_tests.sh: ``xvfb-run -a freecad tests/gui/test_gui_parting.py``.

On the bundled cup with a radial hole: the command with the part selected opens the task
panel, OK creates a valid analysis (not Touched) through the console in one undo step;
the view's DiffuseColor paints the hole's faces (the undercut) in the undercut colour and
the others by side; the visibility sphere node has per-vertex colours and its maximum
region holds the chosen direction; the arrows are there; the panel shows the result and
exports JSON / CSV; undo removes the analysis and shows the source again; a wrong
selection (an edge, nothing) shows a message and creates nothing; a screenshot is
saved.  Prints ``freecad-gui-parting: N passed, M failed``; leaves with os._exit(rc).
"""

import json
import math
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
COMMAND = "Mfgeom_PartingAnalysis"
OUT = os.environ.get("MFGEOM_GUI_OUT") or os.path.join(ROOT, "out", "gui-tests")


dialogs = DialogCloser()


def task_panel():
    """The open parting panel's widgets by object name, and the task view's buttons."""
    _, QtGui = qt()
    Gui.updateGui()
    mw = Gui.getMainWindow()
    combos = [w for w in mw.findChildren(QtGui.QComboBox)
              if w.objectName() == "mode" and w.isVisible()]
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


def analyses(doc):
    return [o for o in doc.Objects
            if getattr(getattr(o, "Proxy", None), "Type", "") == "Mfgeom::PartingAnalysis"]


def rgb(c):
    return tuple(round(x, 3) for x in c[:3])


@check("workbench activates; command in toolbar")
def _():
    _, QtGui = qt()
    Gui.activateWorkbench(WORKBENCH)
    assert COMMAND in Gui.listCommands()
    mw = Gui.getMainWindow()
    bars = [b for b in mw.findChildren(QtGui.QToolBar)
            if b.windowTitle() == "Manufacturing Geometry"]
    texts = [a.text() for a in bars[0].actions()]
    assert "Parting analysis" in texts and "Classify points" in texts, texts
    assert os.path.isfile(Gui.Command.get(COMMAND).getInfo()["pixmap"])


@check("wrong selection (nothing, an edge) shows a message and creates nothing")
def _():
    import cup_hole
    import Part
    doc = App.newDocument("PartingGui")
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    part = doc.addObject("Part::Feature", "CupHole")
    part.Shape = cup_hole.make()
    doc.recompute()
    state.update(doc=doc, part=part)
    assert isinstance(part.Shape, Part.Shape)
    undo = doc.UndoCount
    for select in ([], ["Edge1"]):
        Gui.Selection.clearSelection()
        if select:
            Gui.Selection.addSelection(part, select[0])
        dialogs.take()
        Gui.runCommand(COMMAND)
        assert pump(lambda: dialogs.texts, 5), f"no message for selection {select}"
        texts = dialogs.take()
        assert task_panel() is None, "a panel opened on a wrong selection"
        want = "Edge1" if select else "Select a solid"
        assert any(want in t for t in texts), texts
        assert analyses(doc) == [] and doc.UndoCount == undo


@check("command with the part selected: OK creates a valid analysis in one undo step")
def _():
    doc, part = state["doc"], state["part"]
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part)
    undo = doc.UndoCount
    Gui.runCommand(COMMAND)
    panel = task_panel()
    assert panel is not None, "no task panel"
    assert panel["mode"].currentData() == "Mould" and not panel["allFaces"].isEnabled()
    assert not panel["exportJson"].isEnabled()
    press(panel["ok"])
    assert task_panel() is None, "OK left the panel open: " + \
        (panel["message"].text() if panel else "")
    new = analyses(doc)
    assert len(new) == 1, new
    obj = new[0]
    assert obj.isValid() and "Touched" not in obj.State, (obj.getStatusString(), obj.State)
    assert doc.UndoCount == undo + 1, (undo, doc.UndoCount)
    # the panel's deflection box rounds to its decimals; untouched, the default stays exact
    assert obj.NormalDeflection.Value == math.degrees(1e-3), obj.NormalDeflection.Value
    assert not part.Visibility, "the source stays shown under its coloured copy"
    # the hole: a cylinder along x and its floor (cup_hole.py's faces)
    hole = sorted(f"Face{i + 1}" for i, f in enumerate(part.Shape.Faces)
                  if (f.Surface.TypeId == "Part::GeomCylinder"
                      and abs(abs(f.Surface.Axis.x) - 1) < 1e-9)
                  or (f.Surface.TypeId == "Part::GeomPlane"
                      and abs(f.normalAt(0, 0).x - 1) < 1e-9))
    assert len(hole) == 2 and sorted(obj.UncoveredFaces) == hole, (obj.UncoveredFaces, hole)
    state["obj"], state["hole"] = obj, hole


@check("undercut faces in the undercut colour, zero-draft walls pink, the others by side")
def _():
    from mfgeom import palette
    from mfgeom.gui.parting_view import class_color
    obj, hole, part = state["obj"], state["hole"], state["part"]
    # the cup's outer wall and its pocket's wall are parallel to the axis: zero draft
    walls = [f"Face{i + 1}" for i, f in enumerate(part.Shape.Faces)
             if f.Surface.TypeId == "Part::GeomCylinder" and f"Face{i + 1}" not in hole]
    assert sorted(obj.ZeroDraftFaces) == sorted(walls) and len(walls) == 2, \
        (list(obj.ZeroDraftFaces), walls)
    colors = obj.ViewObject.DiffuseColor
    assert len(colors) == len(part.Shape.Faces), (len(colors), len(part.Shape.Faces))
    for i, c in enumerate(colors):
        name = f"Face{i + 1}"
        if name in hole:
            want = palette.UNDERCUT
        elif name in walls:
            want = class_color("zero_draft")
        elif name in obj.CoreFaces:
            want = palette.CORE_SIDE
        elif name in obj.CavityFaces:
            want = palette.CAVITY_SIDE
        else:
            want = palette.SHAPE_GREY
        assert rgb(c) == rgb(want), (name, rgb(c), rgb(want))
    assert obj.CoreFaces and obj.CavityFaces
    # what Coin draws: the material of the hole's triangles
    proxy = obj.ViewObject.Proxy
    drawn = proxy._material.diffuseColor.getValues()
    k = int(hole[0][4:]) - 1
    assert rgb(drawn[k].getValue()) == rgb(palette.UNDERCUT)
    assert (proxy.triangle_faces == k).any(), "no triangle of the hole is drawn"


@check("visibility sphere with per-vertex colours; chosen direction in the maximum region")
def _():
    import numpy as np
    from pivy import coin
    from mfgeom import palette
    obj = state["obj"]
    proxy = obj.ViewObject.Proxy
    faces = proxy.sphere_faces
    assert isinstance(faces, coin.SoIndexedFaceSet)
    # the face set sits under the object's scene graph
    search = coin.SoSearchAction()
    search.setNode(faces)
    search.setInterest(coin.SoSearchAction.FIRST)
    search.apply(obj.ViewObject.RootNode)
    assert search.getPath() is not None, "sphere not in the object's scene"
    path = search.getPath()
    materials = [path.getNode(i) for i in range(path.getLength())]
    sep = materials[-2]
    mats = [sep.getChild(i) for i in range(sep.getNumChildren())
            if isinstance(sep.getChild(i), coin.SoMaterial)]
    binding = [sep.getChild(i) for i in range(sep.getNumChildren())
               if isinstance(sep.getChild(i), coin.SoMaterialBinding)]
    count = proxy.sphere_count
    assert len(count) == 2562 and faces.coordIndex.getNum() == 5120 * 4
    assert binding[0].value.getValue() == coin.SoMaterialBinding.PER_VERTEX_INDEXED
    assert mats[0].diffuseColor.getNum() == len(count)
    # Mould on the cup with hole: 5 surfaces, the direction covers 4; the planes (top,
    # bottom) count everywhere, so the sphere's counts run 2 .. 4
    assert (int(count.min()), int(count.max())) == (2, 4), (count.min(), count.max())
    top = np.flatnonzero(count == count.max())
    cols = mats[0].diffuseColor.getValues()
    assert all(rgb(cols[i].getValue()) == rgb(palette.SPHERE_MAX) for i in top)
    from mfgeom.gui.parting_view import icosphere
    verts, _ = icosphere()
    d = np.array([obj.Direction.x, obj.Direction.y, obj.Direction.z])
    assert max(verts[top] @ d) > np.cos(np.radians(2.5)), "maximum region away from d"
    assert proxy.sphere_radius > 0


@check("arrows: +d, -d and the side core along the hole's axis")
def _():
    obj = state["obj"]
    proxy = obj.ViewObject.Proxy
    assert proxy.arrow_count == 3 and proxy._arrows.getNumChildren() == 3
    assert len(obj.SideCoreDirections) == 1
    assert abs(abs(obj.SideCoreDirections[0].x) - 1) < 1e-9


def rgb8(c):
    return tuple(int(round(255 * x)) for x in c[:3])


def check_legend(panel, obj, meanings):
    """The panel's legend lists one swatch per colour the view paints (what is drawn:
    the swatch's pixels and the view's DiffuseColor), each with the label of its class;
    ``meanings`` ((property with face names, words the label must hold)) checks that
    the faces of each class are painted in the colour the legend gives those words."""
    Gui.updateGui()
    box = panel["legend"]
    assert box.isVisible(), "the legend is hidden"
    _, QtGui = qt()
    swatches = {w.objectName()[len("legendSwatch_"):]: w
                for w in box.findChildren(QtGui.QLabel)
                if w.objectName().startswith("legendSwatch_")}
    texts = {w.objectName()[len("legendText_"):]: w.text()
             for w in box.findChildren(QtGui.QLabel)
             if w.objectName().startswith("legendText_")}
    assert swatches and set(swatches) == set(texts), (sorted(swatches), sorted(texts))
    shown = {}
    for key, w in swatches.items():
        img = w.grab().toImage()
        c = img.pixelColor(img.width() // 2, img.height() // 2)
        shown[key] = (c.red(), c.green(), c.blue())
    painted = {rgb8(c) for c in obj.ViewObject.DiffuseColor}
    # every colour on the part is explained, and nothing else is listed
    assert painted == set(shown.values()), (sorted(painted), shown)
    assert len(set(shown.values())) == len(shown), f"two classes share a colour: {shown}"
    from mfgeom import palette
    from mfgeom.gui.parting_view import FACE_CLASSES
    mould = [FACE_CLASSES[k][1] for k in ("core", "cavity", "zero_draft", "insufficient_draft",
                                          "undercut", "shadowed", "no_direction", "other")]
    least = min(palette.contrast(a, b, v) for v in palette.VISIONS
                for i, a in enumerate(mould) for b in mould[i + 1:])
    assert least >= 10, f"two Mould classes differ by {least:.1f} CIELAB units only"
    colors = obj.ViewObject.DiffuseColor
    for prop, words in meanings:
        keys = [k for k, t in texts.items() if words.lower() in t.lower()]
        assert len(keys) == 1, (words, texts)
        names = getattr(obj, prop)
        assert names, f"no {prop} to check"
        for name in names:
            assert rgb8(colors[int(name[4:]) - 1]) == shown[keys[0]], \
                (prop, name, rgb8(colors[int(name[4:]) - 1]), texts[keys[0]], shown[keys[0]])
    return texts


@check("display modes switch; double click edits, shows the result, exports")
def _():
    obj = state["obj"]
    vobj = obj.ViewObject
    assert set(vobj.listDisplayModes()) >= {"Result", "Part", "Sphere", "Surfaces"}
    vobj.DisplayMode = "Sphere"
    Gui.updateGui()
    vobj.DisplayMode = "Result"
    vobj.Proxy.doubleClicked(vobj)
    panel = task_panel()
    assert panel is not None, "double click opened no panel"
    assert "Undercuts" in panel["result"].text(), panel["result"].text()
    # the legend: core, cavity, zero draft, undercut, each with the colour of its faces
    texts = check_legend(panel, obj, (("CoreFaces", "Core side"), ("CavityFaces", "Cavity"),
                                      ("ZeroDraftFaces", "Zero draft"),
                                      ("UncoveredFaces", "Undercut (")))
    assert len(texts) == 4 or (len(texts) == 5 and "other" in texts), texts
    from mfgeom.gui import parting_panel
    path_json = os.path.join(OUT, "parting.json")
    path_csv = os.path.join(OUT, "parting.csv")
    parting_panel.export_report(obj, path_json)
    parting_panel.export_report(obj, path_csv)
    rep = json.load(open(path_json))
    assert sorted(rep["undercut_faces"]) == state["hole"] and rep["mode"] == "Mould"
    rows = open(path_csv).read().splitlines()
    assert len(rows) == 1 + len(state["part"].Shape.Faces), rows
    # NC 3-axis through the panel: Apply recomputes in one undo step
    undo = obj.Document.UndoCount
    panel["mode"].setCurrentIndex(1)
    assert panel["allFaces"].isEnabled()
    press(panel["apply"])
    assert obj.Mode == "NC3Axis" and obj.isValid() and len(obj.Setups) == 2, obj.getStatusString()
    assert "Set-up 2" in panel["result"].text(), panel["result"].text()
    texts = check_legend(panel, obj, ())
    assert "Set-up 1" in texts.values() and "Set-up 2" in texts.values(), texts
    assert obj.Document.UndoCount == undo + 1
    press(panel["cancel"])
    assert task_panel() is None
    obj.Document.undo()   # back to Mould
    obj.Document.recompute()
    assert obj.Mode == "Mould" and obj.isValid()


@check("screenshot")
def _():
    path = screenshot(OUT, "parting.png")
    assert os.path.getsize(path) > 10000
    state["image"] = path


@check("undo removes the analysis and shows the source again")
def _():
    doc, part = state["doc"], state["part"]
    doc.undo()   # the creation
    assert analyses(doc) == [], analyses(doc)
    assert part.Visibility, "the source stays hidden after undo"
    doc.redo()
    assert len(analyses(doc)) == 1 and analyses(doc)[0].isValid()
    assert not part.Visibility
    doc.undo()
    assert analyses(doc) == []


@check("deleting the analysis shows the source again")
def _():
    doc, part = state["doc"], state["part"]
    doc.redo()
    obj = analyses(doc)[0]
    assert not part.Visibility
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(obj)
    Gui.runCommand("Std_Delete")
    Gui.updateGui()
    assert analyses(doc) == [] and part.Visibility


@check("make function echoed in the Python console")
def _():
    _, QtGui = qt()
    mw = Gui.getMainWindow()
    texts = [w.toPlainText() for w in mw.findChildren(QtGui.QPlainTextEdit)
             + mw.findChildren(QtGui.QTextEdit) if w.objectName() == "Python console"]
    call = ("mfgeom.make_parting_analysis(App.getDocument('PartingGui'), "
            "App.getDocument('PartingGui').getObject('CupHole'), mode='Mould', "
            "draft_angle='0.0 deg', weighting='Count')")
    assert texts and call in texts[0], texts[0][-600:] if texts else "no console"


finish("freecad-gui-parting")
