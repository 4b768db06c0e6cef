# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD GUI test of the clearance check (issue 8, section 3), run as a macro under a
virtual X server by tests/gui/run_gui_tests.sh:
``xvfb-run -a freecad tests/gui/test_gui_clearance.py``.

A swept volume (the exact swept box of tests/freecad/test_clearance_app.py as a stand-in
typed as a sweep feature, its references analytic; and the library's sweep feature) and
obstacles: two that interfere (a box, a Mesh), one that touches, one clear at a known
distance, a sketch.  Selecting the sweep and the obstacles (in either order: the sweep is
found by type), the command prints the table in the Report view (values checked), echoes
``mfgeom.check_clearance(...)`` in the Python console, colours exactly the interfering
ones magenta and shows the panel (table, CSV); a save writes the user's colours, not the
highlight; "Restore colours", a second run and a run with nothing selected put back the
colours (per-face colours too); a selection without a sweep or with two shows a message
and changes nothing; a screenshot is saved.  Prints ``freecad-gui-clearance: N passed, M
failed``; leaves with os._exit(rc).
"""

import csv
import math
import os
import sys
import zipfile

import FreeCAD as App
import FreeCADGui as Gui

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
if os.path.join(ROOT, "workbench") not in sys.path:
    sys.path.append(os.path.join(ROOT, "workbench"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_harness import DialogCloser, check, finish, pump, qt, screenshot, state  # noqa: E402

WORKBENCH = "MfgeomWorkbench"
COMMAND = "Mfgeom_ClearanceCheck"
OUT = os.environ.get("MFGEOM_GUI_OUT") or os.path.join(ROOT, "out", "gui-tests")
V = App.Vector
A, B, C = 20.0, 10.0, 5.0
R = math.hypot(A, B)
TOL = 0.01

dialogs = DialogCloser()


def rgb(c):
    return tuple(round(x, 3) for x in c[:3])


def saved_colours(path, name):
    """(ShapeColor, per-face colours) of view provider ``name`` as the FCStd ``path``
    holds them, whichever the FreeCAD version wrote (None for what it did not): 0.20's
    ShapeColor (packed 0xRRGGBBTT) and DiffuseColor (a file: uint32 count, then packed
    colours), or 1.0's ShapeAppearance (a file: uint32 count, then per material the
    packed ambient, diffuse, specular and emissive colours and two floats, then more).
    The face colours as (r, g, b) tuples of 8-bit values / 255."""
    import re
    import struct
    with zipfile.ZipFile(path) as z:
        gui_xml = z.read("GuiDocument.xml").decode()
        block = gui_xml[gui_xml.index(f'<ViewProvider name="{name}"'):]
        block = block[:block.index("</ViewProvider>")]

        def prop(pname):
            m = re.search(rf'<Property name="{pname}" [^>]*>\s*<(\w+) ([^>]*)/>', block)
            return dict(re.findall(r'(\w+)="([^"]*)"', m.group(2))) if m else None

        def unpack(packed):
            return tuple(((packed >> shift) & 255) / 255 for shift in (24, 16, 8))

        shape = prop("ShapeColor")
        shape = int(shape["value"]) if shape else None
        faces = None
        diffuse, appearance = prop("DiffuseColor"), prop("ShapeAppearance")
        if diffuse and diffuse.get("file"):
            data = z.read(diffuse["file"])
            count = struct.unpack_from("<I", data)[0]
            faces = [unpack(v) for v in struct.unpack_from(f"<{count}I", data, 4)]
        elif appearance and appearance.get("file"):
            data = z.read(appearance["file"])
            count = struct.unpack_from("<I", data)[0]
            faces = [unpack(struct.unpack_from("<I", data, 4 + 24 * i + 4)[0])
                     for i in range(count)]
    return shape, faces


class StandInSweep:
    """The proxy of the exact swept box standing in for a sweep feature: typed as one,
    so the command finds it by type, with a Shape whose references are analytic."""

    Type = "Mfgeom::RotationalSweep"

    def execute(self, obj):
        pass

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None


def swept_box_solid():
    import Part
    box0 = Part.makeBox(A, B, C)
    box1 = box0.copy()
    box1.rotate(V(0, 0, 0), V(0, 0, 1), 90)
    sector = Part.makeCylinder(R, C, V(0, 0, 0), V(0, 0, 1), 90)
    sector.rotate(V(0, 0, 0), V(0, 0, 1), math.degrees(math.atan2(B, A)))
    return box0.fuse([box1, sector]).removeSplitter()


def report_text():
    _, QtGui = qt()
    mw = Gui.getMainWindow()
    views = [w for w in mw.findChildren(QtGui.QTextEdit) if w.objectName() == "Report view"]
    return views[0].toPlainText() if views else ""


def console_text():
    _, QtGui = qt()
    mw = Gui.getMainWindow()
    texts = [w.toPlainText() for w in mw.findChildren(QtGui.QPlainTextEdit)
             + mw.findChildren(QtGui.QTextEdit) if w.objectName() == "Python console"]
    return texts[0] if texts else ""


def panel():
    """The clearance panel's widgets by object name, or None."""
    _, QtGui = qt()
    Gui.updateGui()
    mw = Gui.getMainWindow()
    forms = [w for w in mw.findChildren(QtGui.QWidget)
             if w.objectName() == "clearancePanel" and w.isVisible()]
    if not Gui.Control.activeDialog() or not forms:
        return None
    return {w.objectName(): w for w in forms[0].findChildren(QtGui.QWidget) if w.objectName()}


def select(objs):
    Gui.Selection.clearSelection()
    for o in objs:
        Gui.Selection.addSelection(o)


def run_command():
    dialogs.take()
    Gui.runCommand(COMMAND)
    Gui.updateGui()


@check("workbench activates; command in toolbar with its icon")
def _():
    _, QtGui = qt()
    Gui.activateWorkbench(WORKBENCH)
    assert COMMAND in Gui.listCommands()
    bars = [b for b in Gui.getMainWindow().findChildren(QtGui.QToolBar)
            if b.windowTitle() == "Manufacturing Geometry"]
    texts = [a.text() for a in bars[0].actions()]
    assert "Clearance check" in texts, texts
    icon = Gui.Command.get(COMMAND).getInfo()["pixmap"]
    assert os.path.isfile(icon) and icon.endswith("ClearanceCheck.svg"), icon


@check("document: sweep and obstacles")
def _():
    import Mesh
    import Part
    doc = App.newDocument("ClearanceGui")
    Gui.ActiveDocument = Gui.getDocument(doc.Name)

    def add(name, shape):
        obj = doc.addObject("Part::Feature", name)
        obj.Shape = shape
        return obj
    sweep = doc.addObject("Part::FeaturePython", "Sweep")
    sweep.Proxy = StandInSweep()
    sweep.ViewObject.Proxy = 0     # Part's own view provider draws its Shape
    sweep.Shape = swept_box_solid()
    hit = add("Hit", Part.makeBox(10, 4, 5, V(15, 2, 3)))           # common 5*4*2 = 40
    clear = add("Clear", Part.makeSphere(2, V((R + 3.5) * math.cos(math.radians(70)),
                                              (R + 3.5) * math.sin(math.radians(70)), 2.5)))
    touch = add("Touch", Part.makeBox(5, 5, 5, V(A, 0, 0)))
    mesh = doc.addObject("Mesh::Feature", "MeshHit")                 # inside the box at 90 deg
    mesh.Mesh = Mesh.Mesh(Part.makeBox(4, 3, 1, V(-5, 12, 1)).tessellate(0.1))
    sketch = doc.addObject("Sketcher::SketchObject", "Sketch")
    sketch.addGeometry(Part.Circle(V(40, 40, 0), V(0, 0, 1), 3))
    doc.recompute()
    sweep.ViewObject.Transparency = 60
    hit.ViewObject.ShapeColor = (0.8, 0.6, 0.2)
    # per-face colours on the mesh-free interfering box must come back face by face
    faces = [(0.1 * i, 0.5, 1.0 - 0.1 * i) for i in range(len(hit.Shape.Faces))]
    hit.ViewObject.DiffuseColor = faces
    state.update(doc=doc, sweep=sweep, hit=hit, clear=clear, touch=touch, mesh=mesh,
                 sketch=sketch, hit_faces=[rgb(c) for c in hit.ViewObject.DiffuseColor],
                 before={o.Name: rgb(o.ViewObject.ShapeColor)
                         for o in (hit, clear, touch, mesh)})
    Gui.SendMsgToActiveView("ViewFit")


@check("nothing selected, no sweep among the selection: a message, nothing changed")
def _():
    doc = state["doc"]
    echoed = console_text().count("mfgeom.check_clearance(")
    for objs, want in (([], "Select the rotational sweep and the solids"),
                       ([state["sketch"], state["hit"]], "No rotational sweep selected "
                                                         "(only Sketch, Hit)"),
                       ([state["hit"], state["mesh"]], "No rotational sweep selected")):
        select(objs)
        run_command()
        assert pump(lambda: dialogs.texts, 5), f"no message for {objs}"
        texts = dialogs.take()
        assert any(want in t for t in texts), texts
        assert panel() is None
        for name, colour in state["before"].items():
            assert rgb(doc.getObject(name).ViewObject.ShapeColor) == colour, name
    assert console_text().count("mfgeom.check_clearance(") == echoed


@check("sweep + obstacles: table in the Report view, console echo, colours, panel")
def _():
    from mfgeom import palette
    doc = state["doc"]
    select([state["sweep"], state["hit"], state["clear"], state["touch"], state["mesh"],
            state["sketch"]])
    run_command()
    assert pump(lambda: panel() is not None, 20), f"no panel; dialogs {dialogs.take()}"
    text = report_text()
    assert "Clearance check against 'Sweep' (tolerance 0.01 mm):" in text, text[-2000:]
    table = text[text.rindex("Clearance check against 'Sweep'"):]
    rows = {ln.split()[0]: ln.split() for ln in table.splitlines()[2:] if ln.strip()}
    assert rows["Hit"][1:4] == ["interference", "40.0000", "0.0000"], rows["Hit"]
    assert rows["MeshHit"][1:4] == ["interference", "12.0000", "0.0000"], rows["MeshHit"]
    assert rows["Clear"][1:4] == ["clear", "none", "1.5000"], rows["Clear"]
    assert rows["Touch"][1:4] == ["touching", "none", "0.0000"], rows["Touch"]
    assert rows["Sketch"][1] == "invalid" and "is not a solid" in table, rows["Sketch"]
    assert "2 of 5 object(s) interfere." in table
    call = ("mfgeom.check_clearance(App.getDocument('ClearanceGui').getObject('Sweep'), "
            "[App.getDocument('ClearanceGui').getObject('Hit'), ")
    assert call in console_text(), console_text()[-800:]
    magenta = rgb(palette.INTERFERENCE)
    for name in ("Hit", "MeshHit"):
        assert rgb(doc.getObject(name).ViewObject.ShapeColor) == magenta, name
    assert all(rgb(c) == magenta for c in state["hit"].ViewObject.DiffuseColor)
    for name in ("Clear", "Touch"):
        assert rgb(doc.getObject(name).ViewObject.ShapeColor) == state["before"][name], name
    w = panel()
    assert "2 of 5 object(s) interfere" in w["summary"].text(), w["summary"].text()
    tbl = w["results"]
    assert tbl.rowCount() == 5 and tbl.item(0, 0).text() == "Hit"
    assert tbl.item(0, 2).text() == "40.0000" and tbl.item(1, 3).text() == "1.5000"
    assert w["restoreColours"].isEnabled()
    from mfgeom.gui.clearance_command import ClearancePanel
    os.makedirs(OUT, exist_ok=True)
    path = os.path.join(OUT, "clearance.csv")
    assert ClearancePanel.last.save_csv(path) == path
    rows = list(csv.DictReader(open(path, newline="")))
    assert [r["status"] for r in rows] == ["interference", "clear", "touching",
                                          "interference", "invalid"], rows
    assert abs(float(rows[1]["min_distance_mm"]) - 1.5) < 1e-7


@check("screenshot of the coloured result")
def _():
    path = screenshot(OUT, "clearance.png", clear_selection=True)
    assert os.path.getsize(path) > 10000
    state["image"] = path


@check("a save writes the user's colours, and the highlight stays on screen")
def _():
    from mfgeom import palette
    doc = state["doc"]
    path = os.path.join(OUT, "clearance.FCStd")
    doc.saveAs(path)
    shape, faces = saved_colours(path, "Hit")
    # FreeCAD 0.20 saves ShapeColor (packed RGBA, 0.8 0.6 0.2 -> 0xcc993300) and the
    # per-face DiffuseColor; 1.0 one ShapeAppearance material per face
    assert shape is not None or faces is not None, "no colours saved for Hit"
    if shape is not None:
        assert shape == 0xcc993300, hex(shape)
    if faces is not None:  # 8 bits a channel in the file
        assert len(faces) == len(state["hit_faces"]) and all(
            abs(a - b) <= 0.5 / 255 + 1e-3 for f, g in zip(faces, state["hit_faces"])
            for a, b in zip(f, g)), (faces, state["hit_faces"])
    assert rgb(state["hit"].ViewObject.ShapeColor) == rgb(palette.INTERFERENCE)



@check("Restore colours puts back ShapeColor and per-face DiffuseColor")
def _():
    doc = state["doc"]
    w = panel()
    w["restoreColours"].click()
    Gui.updateGui()
    for name, colour in state["before"].items():
        assert rgb(doc.getObject(name).ViewObject.ShapeColor) == colour, name
    assert [rgb(c) for c in state["hit"].ViewObject.DiffuseColor] == state["hit_faces"]
    assert not w["restoreColours"].isEnabled()
    Gui.Control.closeDialog()
    Gui.updateGui()
    assert panel() is None


@check("the sweep selected last: the same table; two sweeps: a message, nothing changed")
def _():
    from mfgeom import palette
    doc = state["doc"]
    select([state["hit"], state["clear"], state["sweep"]])
    run_command()
    assert pump(lambda: panel() is not None, 20), f"no panel; dialogs {dialogs.take()}"
    text = report_text()
    table = text[text.rindex("Clearance check against 'Sweep'"):]
    rows = [ln.split() for ln in table.splitlines()[2:] if ln.strip()][:2]
    assert [r[:4] for r in rows] == [["Hit", "interference", "40.0000", "0.0000"],
                                     ["Clear", "clear", "none", "1.5000"]], rows
    call = ("mfgeom.check_clearance(App.getDocument('ClearanceGui').getObject('Sweep'), "
            "[App.getDocument('ClearanceGui').getObject('Hit'), "
            "App.getDocument('ClearanceGui').getObject('Clear')])")
    assert call in console_text(), console_text()[-600:]
    Gui.Control.closeDialog()
    # a second sweep: the command refuses and leaves the highlight and the document alone
    other = doc.addObject("Part::FeaturePython", "OtherSweep")
    other.Proxy = StandInSweep()
    other.ViewObject.Proxy = 0
    import Part
    other.Shape = Part.makeBox(1, 1, 1, V(100, 0, 0))
    doc.recompute()
    names = [o.Name for o in doc.Objects]
    echoed = console_text().count("mfgeom.check_clearance(")
    select([state["hit"], state["sweep"], other])
    run_command()
    assert pump(lambda: dialogs.texts, 5), "no message for two sweeps"
    texts = dialogs.take()
    assert any("2 rotational sweeps selected (Sweep, OtherSweep)" in t for t in texts), texts
    assert panel() is None
    assert rgb(state["hit"].ViewObject.ShapeColor) == rgb(palette.INTERFERENCE)
    assert console_text().count("mfgeom.check_clearance(") == echoed
    other_name = other.Name
    doc.removeObject(other_name)
    assert [o.Name for o in doc.Objects] == [n for n in names if n != other_name]


@check("a second run restores the first; nothing selected restores without a message")
def _():
    from mfgeom import palette
    doc, hit = state["doc"], state["hit"]
    select([state["sweep"], hit, state["mesh"]])
    run_command()
    assert pump(lambda: panel() is not None, 20)
    Gui.Control.closeDialog()
    assert rgb(hit.ViewObject.ShapeColor) == rgb(palette.INTERFERENCE)
    hit.Placement = App.Placement(V(0, 0, 20), App.Rotation())   # moved clear
    doc.recompute()
    select([state["sweep"], hit, state["mesh"]])
    run_command()
    assert pump(lambda: panel() is not None, 20)
    Gui.Control.closeDialog()
    assert [rgb(c) for c in hit.ViewObject.DiffuseColor] == state["hit_faces"]
    assert rgb(state["mesh"].ViewObject.ShapeColor) == rgb(palette.INTERFERENCE)
    select([])
    run_command()
    Gui.updateGui()
    assert not pump(lambda: dialogs.texts, 1), dialogs.take()
    assert rgb(state["mesh"].ViewObject.ShapeColor) == state["before"]["MeshHit"]
    assert "colours of 1 object(s) restored" in report_text()
    App.closeDocument(doc.Name)


SWEEP_TOL = 2.0   # the algorithm's first version: 4.7e3 triangles here, 4e6 at 0.01 mm


@check("the sweep feature: a block across the swept arc interferes, a sphere beyond is clear")
def _():
    import Part
    import mfgeom
    from mfgeom import palette
    doc = App.newDocument("ClearanceSweep")
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    block = doc.addObject("Part::Feature", "Block")
    block.Shape = Part.makeBox(A, B, C)
    doc.recompute()
    sweep = mfgeom.make_rotational_sweep(doc, block, (0, 0, 0), (0, 0, 1), 90.0, SWEEP_TOL)
    assert sweep.isValid(), sweep.getStatusString()
    a = math.radians(60)
    # radially from 10 to 26 mm at 60 deg, 10 wide, the sweep's height, across the
    # arc: a common of about 10 x 12.4 x 5, thicker than the sweep's 2 mm floor
    across = doc.addObject("Part::Feature", "Across")
    box = Part.makeBox(16, 10, C, V(10, -5, 0))
    box.rotate(V(0, 0, 0), V(0, 0, 1), 60)
    across.Shape = box
    beyond = doc.addObject("Part::Feature", "Beyond")
    gap = 3.0
    d = R + gap + 2
    beyond.Shape = Part.makeSphere(2, V(d * math.cos(a), d * math.sin(a), C / 2))
    doc.recompute()
    select([across, beyond, sweep])      # the obstacles first: the sweep is found by type
    run_command()
    assert pump(lambda: panel() is not None, 120), f"no panel; {dialogs.take()}"
    Gui.Control.closeDialog()
    assert rgb(beyond.ViewObject.ShapeColor) != rgb(palette.INTERFERENCE)
    text = report_text()
    table = text[text.rindex(f"Clearance check against '{sweep.Label}'"):]
    assert "(tolerance 2 mm)" in table.splitlines()[0], table.splitlines()[0]
    rows = {ln.split()[0]: ln.split() for ln in table.splitlines()[2:] if ln.strip()}
    from mfgeom.app import clearance
    assert rgb(across.ViewObject.ShapeColor) == rgb(palette.INTERFERENCE)
    assert rows["Across"][1] == "interference", rows["Across"]
    # the true common: 10 x 5 x (R - 10) less the corners past the arc, ~600 mm^3; the
    # exact mesh is checked as it is (no Part solid of it, no sampling, no warning)
    assert 550 < float(rows["Across"][2]) < 650, rows["Across"]
    assert clearance.SWEEP_NOT_VALID not in table and "samples" not in table, table
    assert rows["Beyond"][1] == "clear", rows["Beyond"]
    assert gap - SWEEP_TOL <= float(rows["Beyond"][3]) <= gap + SWEEP_TOL, rows["Beyond"]
    path = screenshot(OUT, "clearance-sweep.png", clear_selection=True)
    assert os.path.getsize(path) > 10000
    state["image"] = path

finish("freecad-gui-clearance")
