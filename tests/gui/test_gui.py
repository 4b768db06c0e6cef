# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD GUI tests of the workbench, run as a macro: ``xvfb-run -a freecad test_gui.py``.

Use tests/gui/run_gui_tests.sh (it sets up the user Mod folder and the environment).
Activates the workbench, checks its toolbar, menu, command and preferences page, runs
"Classify points" on a GUI selection, checks undo and the message on a bad selection,
and renders the view to PNG, checking that the IN/ON/OUT colours are on screen.
Prints ``freecad-gui: N passed, M failed`` and leaves with os._exit(rc).
"""

import os
import sys
import tempfile

import FreeCAD as App
import FreeCADGui as Gui

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.append(os.path.join(REPO, "examples"))
sys.path.insert(0, HERE)
from gui_harness import DialogCloser, check, finish, press, pump, qt, state  # noqa: E402

OUT = os.environ.get("MFGEOM_GUI_OUT") or tempfile.mkdtemp(prefix="mfgeom-gui-")
os.makedirs(OUT, exist_ok=True)
WORKBENCH = "MfgeomWorkbench"
COMMAND = "Mfgeom_ClassifyPoints"
PARAMS = "User parameter:BaseApp/Preferences/Mod/mfgeom"



def bracket_top(part):
    import bracket
    return bracket.top_face_name(part)


dialogs = DialogCloser()


def task_panel():
    """The open Classify points task panel as a user sees it: its widgets by object name
    and the task view's OK / Cancel buttons (None when no panel is open)."""
    _QtCore, QtGui = qt()
    Gui.updateGui()
    mw = Gui.getMainWindow()
    spins = [w for w in mw.findChildren(QtGui.QAbstractSpinBox)
             if w.objectName() == "tolerance" and w.isVisible()]
    if not Gui.Control.activeDialog() or not spins:
        return None
    panel = spins[0].parentWidget()
    widgets = {w.objectName(): w for w in panel.findChildren(QtGui.QWidget) if w.objectName()}
    boxes = [b for b in mw.findChildren(QtGui.QDialogButtonBox)
             if b.isVisible() and b.button(QtGui.QDialogButtonBox.Ok) is not None]
    assert len(boxes) == 1, f"{len(boxes)} visible OK button boxes"
    widgets["ok"] = boxes[0].button(QtGui.QDialogButtonBox.Ok)
    widgets["cancel"] = boxes[0].button(QtGui.QDialogButtonBox.Cancel)
    widgets["tolerance_text"] = spins[0].findChild(QtGui.QLineEdit)
    return widgets


def dock_text(name):
    """The text of the Report view or the Python console."""
    _QtCore, QtGui = qt()
    mw = Gui.getMainWindow()
    for widget in mw.findChildren(QtGui.QTextEdit) + mw.findChildren(QtGui.QPlainTextEdit):
        if widget.objectName() == name:
            return widget.toPlainText()
    raise AssertionError(f"no {name!r} in the main window")


@check("workbench is registered and activates")
def _():
    assert WORKBENCH in Gui.listWorkbenches(), sorted(Gui.listWorkbenches())
    Gui.activateWorkbench(WORKBENCH)
    assert Gui.activeWorkbench().name() == WORKBENCH, Gui.activeWorkbench().name()
    wb = Gui.getWorkbench(WORKBENCH)
    assert wb.MenuText == "Manufacturing Geometry"
    assert os.path.isfile(wb.Icon), wb.Icon


@check("command, toolbar and menu exist")
def _():
    QtCore, QtGui = qt()
    assert COMMAND in Gui.listCommands()
    mw = Gui.getMainWindow()
    bars = [b for b in mw.findChildren(QtGui.QToolBar)
            if b.windowTitle() == "Manufacturing Geometry"]
    assert bars, "no toolbar 'Manufacturing Geometry'"
    texts = [a.text() for a in bars[0].actions()]
    assert "Classify points" in texts, texts
    menus = [m.title() for m in mw.menuBar().findChildren(QtGui.QMenu)]
    assert "&Manufacturing Geometry" in menus, menus
    res = Gui.Command.get(COMMAND).getInfo()
    assert os.path.isfile(res["pixmap"]), res


@check("every registered command: its icon exists and loads, MenuText and ToolTip set; the "
       "toolbar and the menu list exactly the registered commands; every icon in icons/ is used")
def _():
    _QtCore, QtGui = qt()
    from mfgeom import paths
    from mfgeom.gui import commands
    names = commands.COMMAND_NAMES
    registered = sorted(c for c in Gui.listCommands() if c.startswith("Mfgeom_"))
    assert registered == sorted(names) and len(set(names)) == len(names), (registered, names)
    used = set()
    for name in names:
        res = commands.COMMANDS[name].GetResources()
        pixmap = res["Pixmap"]
        assert os.path.isfile(pixmap), (name, pixmap)
        assert not QtGui.QIcon(pixmap).isNull(), (name, pixmap)
        image = QtGui.QPixmap(pixmap)
        assert not image.isNull() and image.width() > 0, (name, pixmap)
        assert res["MenuText"].strip() and res["ToolTip"].strip(), (name, res)
        info = Gui.Command.get(name).getInfo()
        assert info["menuText"] == res["MenuText"], (name, info)
        used.add(os.path.basename(pixmap))
    menu_texts = [commands.COMMANDS[n].GetResources()["MenuText"] for n in names]
    mw = Gui.getMainWindow()
    bars = [b for b in mw.findChildren(QtGui.QToolBar)
            if b.windowTitle() == "Manufacturing Geometry"]
    assert len(bars) == 1, [b.windowTitle() for b in bars]
    in_bar = [a.text() for a in bars[0].actions() if not a.isSeparator()]
    assert in_bar == menu_texts, (in_bar, menu_texts)
    menus = [m for m in mw.menuBar().findChildren(QtGui.QMenu)
             if m.title() == "&Manufacturing Geometry"]
    assert len(menus) == 1, [m.title() for m in menus]
    in_menu = [a.text() for a in menus[0].actions() if not a.isSeparator()]
    assert in_menu == menu_texts, (in_menu, menu_texts)
    # the rest of icons/: the workbench's and the preferences page's (found by its name)
    wb = Gui.getWorkbench(WORKBENCH)
    used |= {os.path.basename(wb.Icon), "preferences-manufacturing_geometry.svg"}
    for icon in sorted(used):
        assert not QtGui.QPixmap(paths.icon(icon)).isNull(), icon
    assert sorted(os.listdir(paths.icons_dir())) == sorted(used), (
        sorted(os.listdir(paths.icons_dir())), sorted(used))


@check("preferences page loads and is bound to the parameter")
def _():
    from mfgeom import paths
    form = Gui.PySideUic.loadUi(paths.resource("preferences.ui"))
    spin = [w for w in form.children() if w.objectName() == "groupClassify"][0]
    names = {w.objectName(): w for w in spin.children()}
    tol = names["spinTolerance"]
    assert bytes(tol.property("prefEntry")).decode() == "DefaultTolerance"
    assert bytes(tol.property("prefPath")).decode() == "Mod/mfgeom"
    assert abs(tol.value() - 0.01) < 1e-12, tol.value()


@check("classify points from a GUI selection")
def _():
    import numpy as np
    import Points
    import bracket
    App.ParamGet(PARAMS).SetFloat("DefaultTolerance", 0.3)
    doc = App.newDocument("GuiTest")
    part = bracket.make_bracket(doc)
    lx, ly, lz = bracket.PLATE
    gx, gy = np.meshgrid(np.arange(-3.0, lx + 3.0, 1.0), np.arange(-3.0, ly + 3.0, 1.0))
    cloud = doc.addObject("Points::Feature", "Cloud")
    cloud.Points = Points.Points([App.Vector(x, y, lz + 0.02)
                                  for x, y in zip(gx.ravel(), gy.ravel())])
    doc.recompute()
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part, bracket.top_face_name(part))
    Gui.Selection.addSelection(cloud)
    before = len(doc.Objects)
    dialogs.take()
    Gui.runCommand(COMMAND)
    Gui.updateGui()
    assert not dialogs.take(), "the command complained"
    panel = task_panel()
    assert panel is not None, "the command opened no task panel"
    assert len(doc.Objects) == before, "the panel created something before OK"
    # The panel's defaults: the preferences, Strict on (the panel puts the text back in mm
    # just after the box is shown, a zero timer: wait for it, FreeCAD 1.0 is slower)
    assert pump(lambda: panel["tolerance_text"].text() == "0.3 mm", 5), \
        panel["tolerance_text"].text()
    assert panel["strict"].isChecked()
    panel["pointSize"].setValue(7)
    press(panel["ok"])
    assert task_panel() is None, "OK left the panel open"
    new = [o for o in doc.Objects if o.Name.startswith("PointClassification")]
    assert len(doc.Objects) == before + 1 and len(new) == 1, [o.Name for o in doc.Objects]
    obj = new[0]
    assert obj.isValid(), obj.getStatusString()
    assert abs(obj.Tolerance.Value - 0.3) < 1e-12, obj.Tolerance  # from the preference
    assert obj.Strict and obj.ViewObject.PointSize == 7, (obj.Strict, obj.ViewObject.PointSize)
    assert obj.Label == f"Classes of {bracket.top_face_name(part)} of {part.Label}", obj.Label
    summary = (f"mfgeom: {obj.Label}: IN {obj.CountIn}, ON {obj.CountOn}, OUT {obj.CountOut} "
               f"(tolerance 0.3 mm, strict; largest distance to the surface 0.02")  # floats
    assert summary in dock_text("Report view"), dock_text("Report view")[-600:]
    # Echoed to the Python console: replayed as a macro, the line makes the same feature
    console = dock_text("Python console")
    calls = [line[4:] for line in console.splitlines()
             if line.startswith(">>> mfgeom.make_point_classification(")]
    assert len(calls) == 1, console[-800:]
    import mfgeom
    replay = eval(calls[0], {"App": App, "Gui": Gui, "mfgeom": mfgeom})
    assert (replay.Tolerance.Value, replay.Strict, list(replay.Classes)) == \
        (obj.Tolerance.Value, obj.Strict, list(obj.Classes)), calls[0]
    doc.removeObject(replay.Name)
    doc.recompute()
    n = len(cloud.Points.Points)
    assert obj.CountIn + obj.CountOn + obj.CountOut == n
    assert min(obj.CountIn, obj.CountOn, obj.CountOut) > 0, (obj.CountIn, obj.CountOn, obj.CountOut)
    assert obj.ViewObject.Proxy is not None
    # One Coin point set per class, holding exactly that class's points
    shown = obj.ViewObject.Proxy.counts_shown()
    assert shown == {0: obj.CountOut, 1: obj.CountIn, 2: obj.CountOn}, shown
    assert "Touched" not in obj.State, obj.State  # no blue "recompute me" mark
    assert not cloud.ViewObject.Visibility  # the coloured copy replaces it on screen
    state.update(doc=doc, part=part, cloud=cloud, obj=obj)


@check("the view shows the IN / ON / OUT colours")
def _():
    QtCore, QtGui = qt()
    view = Gui.ActiveDocument.ActiveView
    view.viewTop()
    view.fitAll()
    Gui.updateGui()
    path = os.path.join(OUT, "gui_classify.png")
    view.saveImage(path, 800, 600, "White")
    img = QtGui.QImage(path)
    assert not img.isNull() and img.width() == 800, path
    found = {"in": 0, "on": 0, "out": 0}
    distinct = set()
    for y in range(0, img.height(), 3):
        for x in range(0, img.width(), 3):
            c = QtGui.QColor(img.pixel(x, y))
            r, g, b = c.red(), c.green(), c.blue()
            distinct.add((r // 16, g // 16, b // 16))
            # mfgeom.palette: IN (0, 114, 178), ON (102, 204, 238), OUT (136, 34, 85)
            if r < 40 and 90 < g < 140 and 150 < b < 210:
                found["in"] += 1
            elif 80 < r < 130 and g > 180 and b > 215:
                found["on"] += 1
            elif 110 < r < 165 and g < 60 and 60 < b < 110:
                found["out"] += 1
    assert len(distinct) >= 4, f"image looks blank: {len(distinct)} colours"
    assert all(v > 20 for v in found.values()), found
    state["image"] = path


@check("undo removes the feature")
def _():
    doc, obj = state["doc"], state["obj"]
    name = obj.Name
    assert doc.UndoCount > 0
    doc.undo()
    assert doc.getObject(name) is None, "undo kept the feature"
    doc.redo()
    assert doc.getObject(name) is not None and doc.getObject(name).isValid()


@check("Cancel creates nothing; a tolerance in degrees is refused in the panel")
def _():
    doc, part, cloud = state["doc"], state["part"], state["cloud"]
    before = [o.Name for o in doc.Objects]
    undo = doc.UndoCount
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part, bracket_top(part))
    Gui.Selection.addSelection(cloud)
    Gui.runCommand(COMMAND)
    panel = task_panel()
    assert panel is not None
    press(panel["cancel"])
    assert task_panel() is None and [o.Name for o in doc.Objects] == before
    assert doc.UndoCount == undo, "Cancel left an undo step"
    Gui.runCommand(COMMAND)
    panel = task_panel()
    panel["tolerance_text"].setText("5 deg")
    press(panel["ok"])
    panel = task_panel()
    assert panel is not None, "OK with '5 deg' closed the panel"
    assert "must be a length" in panel["message"].text(), panel["message"].text()
    assert [o.Name for o in doc.Objects] == before
    press(panel["cancel"])
    assert task_panel() is None and [o.Name for o in doc.Objects] == before


@check("double click edits the feature in the same panel")
def _():
    doc = state["doc"]
    obj = [o for o in doc.Objects if o.Name.startswith("PointClassification")][0]  # redone
    classes = list(obj.Classes)
    assert obj.ViewObject.Proxy.doubleClicked(obj.ViewObject)
    panel = task_panel()
    assert panel is not None, "no panel on double click"
    assert pump(lambda: panel["tolerance_text"].text() == "0.3 mm", 5), \
        panel["tolerance_text"].text()
    assert panel["strict"].isChecked()
    panel["tolerance_text"].setText("0.1 mm")
    press(panel["cancel"])
    assert task_panel() is None and abs(obj.Tolerance.Value - 0.3) < 1e-12
    assert not Gui.ActiveDocument.getInEdit(), "still in edit mode after Cancel"
    Gui.ActiveDocument.setEdit(obj.Name, 0)
    panel = task_panel()
    panel["tolerance_text"].setText("0.1 mm")
    undo = doc.UndoCount
    press(panel["ok"])
    assert task_panel() is None and abs(obj.Tolerance.Value - 0.1) < 1e-12, obj.Tolerance
    assert obj.isValid() and "Touched" not in obj.State, obj.State
    assert list(obj.Classes) != classes and doc.UndoCount == undo + 1
    doc.undo()  # one step back to 0.3 mm and its results
    doc.recompute()
    assert abs(obj.Tolerance.Value - 0.3) < 1e-12 and list(obj.Classes) == classes


@check("the Report view warns about a cloud far from the surface")
def _():
    import numpy as np
    import Points
    import bracket
    doc, part = state["doc"], state["part"]
    lx, ly, lz = bracket.PLATE
    far = doc.addObject("Points::Feature", "FarCloud")
    far.Points = Points.Points([App.Vector(x, y, lz + 25.0)
                                for x in np.arange(2.0, lx, 10.0) for y in np.arange(2.0, ly, 10.0)])
    doc.recompute()
    n = len(far.Points.Points)
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part, bracket_top(part))
    Gui.Selection.addSelection(far)
    Gui.runCommand(COMMAND)
    panel = task_panel()
    panel["strict"].setChecked(False)
    press(panel["ok"])
    obj = [o for o in doc.Objects if o.Label.startswith("Classes of") and o.PointSource[0] == far]
    assert len(obj) == 1 and not obj[0].Strict, obj
    report = dock_text("Report view")
    assert f"{n} points farther than the tolerance (0.3 mm)" in report, report[-800:]
    assert "largest distance 25 mm" in report and "set Strict" in report, report[-800:]
    doc.removeObject(obj[0].Name)
    doc.removeObject(far.Name)
    doc.recompute()


@check("bad selection shows a message and creates nothing")
def _():
    doc, part = state["doc"], state["part"]
    before = [o.Name for o in doc.Objects]
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part, bracket_top(part))  # a face, but no points
    dialogs.take()
    Gui.runCommand(COMMAND)
    Gui.updateGui()
    texts = dialogs.take()
    assert len(texts) == 1 and "points" in texts[0], texts
    assert [o.Name for o in doc.Objects] == before
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part, "Edge1")
    Gui.Selection.addSelection(state["cloud"])
    Gui.runCommand(COMMAND)
    Gui.updateGui()
    texts = dialogs.take()
    assert len(texts) == 1 and "Edge1" in texts[0], texts
    assert [o.Name for o in doc.Objects] == before
    assert all(o.isValid() for o in doc.Objects)


@check("a saved document reopens with its coloured points")
def _():
    doc = state["doc"]
    path = os.path.join(OUT, "gui_roundtrip.FCStd")
    doc.saveAs(path)
    name = doc.Name
    App.closeDocument(name)
    doc = App.openDocument(path)
    obj = [o for o in doc.Objects if o.Name.startswith("PointClassification")][0]
    assert obj.isValid()
    shown = obj.ViewObject.Proxy.counts_shown()
    assert shown == {0: obj.CountOut, 1: obj.CountIn, 2: obj.CountOn}, shown
    assert sum(shown.values()) == len(obj.Classes) > 0
    assert obj.ViewObject.Proxy.is_shown(obj.ViewObject), obj.ViewObject.DisplayMode
    App.closeDocument(doc.Name)


@check("points of a placed cloud show where they are, also after a reload")
def _():
    import numpy as np
    import Points
    import mfgeom
    doc = App.newDocument("Placed")
    try:
        box = doc.addObject("Part::Box", "Box")
        box.Placement = App.Placement(App.Vector(500, -300, 40), App.Rotation(0, 0, 30))
        local = [App.Vector(x, y, 0) for x in np.arange(-2.0, 13.0, 1.5)
                 for y in np.arange(-2.0, 13.0, 1.5)]
        cloud = doc.addObject("Points::Feature", "Cloud")
        cloud.Points = Points.Points(local)
        cloud.Placement = App.Placement(App.Vector(500, -300, 50), App.Rotation(0, 0, 30))
        doc.recompute()
        want = np.array([tuple(v) for v in cloud.Points.Points])
        lo, hi = want.min(axis=0), want.max(axis=0)
        obj = mfgeom.make_point_classification(doc, (box, "Face6"), cloud, 0.01)
        Gui.updateGui()
        for when in ("after the command", "after a reload"):
            got = obj.ViewObject.Proxy.bound_box()
            assert np.allclose(got[0], lo, atol=1e-3) and np.allclose(got[1], hi, atol=1e-3), \
                (when, got, lo, hi)
            assert sum(obj.ViewObject.Proxy.counts_shown().values()) == len(want), when
            if when == "after the command":
                path, name = os.path.join(OUT, "placed.FCStd"), obj.Name
                doc.saveAs(path)
                App.closeDocument(doc.Name)
                doc = App.openDocument(path)
                obj = doc.getObject(name)
                Gui.updateGui()
    finally:
        App.closeDocument(doc.Name)


@check("a document saved by freecadcmd shows its points once made visible")
def _():
    import subprocess
    path = os.path.join(OUT, "headless.FCStd")
    script = os.path.join(OUT, "headless.py")
    with open(script, "w", encoding="utf-8") as f:
        f.write(f"""import sys
sys.path.append({os.path.join(REPO, "workbench")!r})
import FreeCAD as App, Points, mfgeom
doc = App.newDocument("headless")
box = doc.addObject("Part::Box", "Box")
doc.recompute()
cloud = doc.addObject("Points::Feature", "Cloud")
cloud.Points = Points.Points([(1.0, 1.0, 10.0), (5.0, 0.0, 10.0), (-1.0, 1.0, 10.0)])
mfgeom.make_point_classification(doc, (box, "Face6"), cloud, 0.01, name="PC")
doc.saveAs({path!r})
""")
    run = subprocess.run(["freecadcmd", script], capture_output=True, text=True, timeout=120)
    assert os.path.exists(path), run.stdout[-1000:] + run.stderr[-1000:]
    doc = App.openDocument(path)
    try:
        obj = doc.getObject("PC")
        obj.ViewObject.Visibility = True
        Gui.updateGui()
        assert obj.ViewObject.Proxy.is_shown(obj.ViewObject), obj.ViewObject.DisplayMode
        assert obj.ViewObject.Proxy.counts_shown() == {0: 1, 1: 1, 2: 1}
    finally:
        App.closeDocument(doc.Name)


@check("a version 1 document (points in a compound, Part's display mode) opens shown")
def _():
    import shutil
    # tests/gui/data/pointclass_v1.FCStd was saved by the GUI with mfgeom 92be5eb: Version
    # 1, the 4 points as a compound of vertices in Shape, PointColorArray, DisplayMode
    # "Points".  It must show its points before any recompute, then recompute cleanly.
    path = os.path.join(OUT, "pointclass_v1.FCStd")
    shutil.copyfile(os.path.join(HERE, "data", "pointclass_v1.FCStd"), path)
    doc = App.openDocument(path)
    try:
        obj = doc.getObject("PC")
        vobj = obj.ViewObject
        assert obj.Points.CountPoints == 4 and obj.Shape.isNull(), obj.Points.CountPoints
        assert vobj.Proxy.is_shown(vobj), vobj.DisplayMode
        assert vobj.Proxy.counts_shown() == {0: 1, 1: 2, 2: 1}, vobj.Proxy.counts_shown()
        obj.touch()
        doc.recompute()
        assert obj.isValid() and list(obj.Classes) == [1, 2, 0, 1], list(obj.Classes)
        assert vobj.Proxy.is_shown(vobj) and "Touched" not in obj.State
    finally:
        App.closeDocument(doc.Name)


@check("the bundled example opens with its objects visible")
def _():
    import zipfile
    path = os.path.join(REPO, "examples", "bracket.FCStd")
    with zipfile.ZipFile(path) as archive:
        assert "GuiDocument.xml" in archive.namelist(), archive.namelist()
    doc = App.openDocument(path)
    try:
        shown = [o.Name for o in doc.Objects if o.ViewObject.Visibility]
        assert shown == ["Bracket"], shown  # the result; its construction features hidden
    finally:
        App.closeDocument(doc.Name)


@check("the preferences dialog finds the page's icon")
def _():
    dialogs.take()
    Gui.runCommand("Std_DlgPreferences")
    Gui.updateGui()
    assert dialogs.take(), "the preferences dialog did not open"
    report = dock_text("Report view")
    assert "Cannot find icon" not in report, report[-600:]


@check("the command's creation is echoed to the Python console as a macro line")
def _():
    from mfgeom.gui import macro
    doc = App.newDocument("MacroTest")
    try:
        box = doc.addObject("Part::Box", "Box")
        text = macro.point_classification_call(doc, (box, "Face6"), (box, ["Vertex2", "Vertex1"]),
                                               0.05, strict=False)
        assert text == ("mfgeom.make_point_classification(App.getDocument('MacroTest'), "
                        "(App.getDocument('MacroTest').getObject('Box'), 'Face6'), "
                        "(App.getDocument('MacroTest').getObject('Box'), ['Vertex2', 'Vertex1']), "
                        "'0.05 mm', strict=False)"), text
    finally:
        App.closeDocument(doc.Name)


finish("freecad-gui")
