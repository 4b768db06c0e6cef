# SPDX-License-Identifier: LGPL-2.1-or-later
"""Builds the bundled example part "bracket" that the demo and the FreeCAD tests run on.

A 120 x 60 x 10 mm plate with four through holes and a rectangular pocket, carrying a
cylindrical boss (radius 15 mm, along X) drilled by a vertical hole: its top face is a
planar face with holes and a pocket, the boss is a trimmed cylindrical face (cut by
the plate) with a hole in it.  Everything is a parametric Part feature, so changing a
dimension recomputes the point classifications built on it.

``examples/make_examples.sh`` (re)writes ``examples/bracket.FCStd`` by running this file in
FreeCAD's GUI under a virtual X server: only a document saved from the GUI carries
GuiDocument.xml, without which FreeCAD opens every object hidden.
"""

import os
import sys

import FreeCAD as App

PLATE = (120.0, 60.0, 10.0)
BOSS_R = 15.0
BOSS_AXIS_Z = 17.0  # the boss dips 8 mm into the plate: no tangent faces for the booleans
BOSS_X = (20.0, 70.0)
HOLE_R = 4.0
HOLES = ((10.0, 10.0), (10.0, 50.0), (110.0, 10.0), (110.0, 50.0))
CROSS_HOLE = (45.0, 30.0, 5.0)  # x, y, radius of the hole drilled down through the boss
POCKET = (82.0, 18.0, 22.0, 24.0, 4.0)  # x, y, length, width, depth


def make_bracket(doc, name="Bracket"):
    """Add the bracket's features to ``doc``; returns the final solid feature."""
    lx, ly, lz = PLATE
    plate = doc.addObject("Part::Box", "Plate")
    plate.Length, plate.Width, plate.Height = lx, ly, lz

    boss = doc.addObject("Part::Cylinder", "Boss")
    boss.Radius = BOSS_R
    boss.Height = BOSS_X[1] - BOSS_X[0]
    # Local Z turned onto +X (about Y by +90 deg) leaves the cylinder's seam (local +X)
    # at the bottom, inside the plate: the boss keeps one trimmed face with the hole in it.
    boss.Placement = App.Placement(App.Vector(BOSS_X[0], ly / 2, BOSS_AXIS_Z),
                                   App.Rotation(App.Vector(0, 1, 0), 90))

    body = doc.addObject("Part::MultiFuse", "PlateAndBoss")
    body.Shapes = [plate, boss]

    tools = []
    for i, (x, y) in enumerate(HOLES):
        hole = doc.addObject("Part::Cylinder", f"Hole{i + 1}")
        hole.Radius = HOLE_R
        hole.Height = lz + 2.0
        hole.Placement.Base = App.Vector(x, y, -1.0)
        tools.append(hole)
    cx, cy, cr = CROSS_HOLE
    cross = doc.addObject("Part::Cylinder", "CrossHole")
    cross.Radius = cr
    cross.Height = BOSS_AXIS_Z + BOSS_R + 2.0
    cross.Placement.Base = App.Vector(cx, cy, -1.0)
    tools.append(cross)
    px, py, pl, pw, pd = POCKET
    pocket = doc.addObject("Part::Box", "Pocket")
    pocket.Length, pocket.Width, pocket.Height = pl, pw, pd + 1.0
    pocket.Placement.Base = App.Vector(px, py, lz - pd)
    tools.append(pocket)
    cutters = doc.addObject("Part::MultiFuse", "Cutters")
    cutters.Shapes = tools

    bracket = doc.addObject("Part::Cut", name)
    bracket.Base = body
    bracket.Tool = cutters
    for obj in [body, cutters] + tools + [plate, boss]:
        obj.Visibility = False
    doc.recompute()
    return bracket


def top_face_name(obj):
    """Name of the plate's top face (planar, at z = plate height, the largest one)."""
    best = None
    for i, face in enumerate(obj.Shape.Faces):
        if face.Surface.TypeId != "Part::GeomPlane":
            continue
        bb = face.BoundBox
        if abs(bb.ZMin - PLATE[2]) < 1e-6 and abs(bb.ZMax - PLATE[2]) < 1e-6:
            if best is None or face.Area > best[1]:
                best = (f"Face{i + 1}", face.Area)
    if best is None:
        raise ValueError(f"{obj.Label} has no top face at z = {PLATE[2]}")
    return best[0]


def boss_face_name(obj):
    """Name of the boss's cylindrical face (radius BOSS_R)."""
    for i, face in enumerate(obj.Shape.Faces):
        s = face.Surface
        if s.TypeId == "Part::GeomCylinder" and abs(s.Radius - BOSS_R) < 1e-6:
            return f"Face{i + 1}"
    raise ValueError(f"{obj.Label} has no cylindrical face of radius {BOSS_R}")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    path = os.path.join(here, "bracket.FCStd")
    if not App.GuiUp:
        raise RuntimeError("run examples/make_examples.sh: the example must be saved from "
                           "the GUI, or it opens with every object hidden")
    import FreeCADGui as Gui
    doc = App.newDocument("bracket")
    obj = make_bracket(doc)
    if not obj.isValid() or obj.Shape.isNull() or not obj.Shape.isValid():
        raise RuntimeError("the bracket did not build")
    for o in doc.Objects:
        o.ViewObject.Visibility = o is obj  # the result; its construction features hidden
    Gui.getDocument(doc.Name).ActiveView.viewIsometric()
    Gui.SendMsgToActiveView("ViewFit")
    doc.saveAs(path)
    App.Console.PrintMessage(f"bracket: {len(obj.Shape.Faces)} faces, volume "
                             f"{obj.Shape.Volume:.1f} mm^3, top {top_face_name(obj)}, "
                             f"boss {boss_face_name(obj)} -> {path}\n")
    App.closeDocument(doc.Name)


def _run_as_script():
    # freecadcmd and freecad run a script with its file name as __name__ (or as
    # __main__), and a GUI macro must leave with os._exit or the GUI stays up.
    rc = 0
    try:
        main()
    except Exception:  # reported; the exit code tells make_examples.sh
        import traceback
        traceback.print_exc()
        rc = 1
    if App.GuiUp:
        workbench = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                 "workbench")
        if workbench not in sys.path:
            sys.path.append(workbench)
        from mfgeom import compat
        compat.exit_now(rc)  # output flushed first (FreeCAD 1.0 buffers C stdio in a pipe)
    sys.exit(rc)


if __name__ == "__main__" or any(os.path.basename(a) == "bracket.py" for a in sys.argv):
    _run_as_script()
