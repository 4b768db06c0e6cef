# SPDX-License-Identifier: LGPL-2.1-or-later
"""Parting-analysis demo (issue 7, the workbench's main job), run by ``freecadcmd``.

Builds the bundled cup with a radial blind hole (examples/parts/cup_hole.py), places it
tilted (the answers are global directions), runs a Mould and an NC 3-axis parting
analysis on it, checks them against what the part was built to give (parting along the
cup's axis with the hole as the one undercut and its side core along the hole's axis;
two set-ups), and writes ``demo_parting.txt``, ``.json``, ``.csv`` and ``.FCStd`` into
$MFGEOM_OUT (default: <repo>/out).  Exits non-zero if anything fails or disagrees.
Use examples/run_demo.sh, which also renders the result with the GUI.
"""

import json
import math
import os
import sys
import time
import traceback

import FreeCAD as App

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
for path in (HERE, os.path.join(HERE, "parts"), os.path.join(REPO, "workbench")):
    if path not in sys.path:
        sys.path.append(path)

import cup_hole  # noqa: E402  (needs the path above)
import mfgeom  # noqa: E402
from mfgeom import compat, parting  # noqa: E402
from mfgeom.app.parting_feature import feature_report  # noqa: E402

# The part's placement: a rotation about an oblique axis, so the directions are not axes.
PLACEMENT = App.Placement(App.Vector(5, -3, 2), App.Rotation(App.Vector(1, 2, 0.5), 20))


def _close(a, b, tol=1e-6):
    return (a - b).Length <= tol


def run():
    out = os.path.abspath(os.environ.get("MFGEOM_OUT") or os.path.join(REPO, "out"))
    os.makedirs(out, exist_ok=True)
    doc = App.newDocument("DemoParting")
    part = doc.addObject("Part::Feature", "CupHole")
    part.Shape = cup_hole.make()
    part.Label = "Cup with hole"
    part.Placement = PLACEMENT
    doc.recompute()
    rot = PLACEMENT.Rotation
    axis, hole_axis = rot.multVec(App.Vector(0, 0, 1)), rot.multVec(App.Vector(1, 0, 0))

    t0 = time.perf_counter()
    mould = mfgeom.make_parting_analysis(doc, part, mode="Mould", draft_angle=0.0,
                                         name="Mould")
    t1 = time.perf_counter()
    nc = mfgeom.make_parting_analysis(doc, part, mode="NC3Axis", name="NC")
    t2 = time.perf_counter()
    doc.recompute()
    problems = []
    for obj in (mould, nc):
        if not obj.isValid() or "Touched" in obj.State:
            problems.append(f"{obj.Label}: {obj.getStatusString()} {obj.State}")
    # what the part was built to give
    if not _close(mould.Direction, axis):
        problems.append(f"mould direction {mould.Direction} is not the cup's axis {axis}")
    hole_faces = [f"Face{i + 1}" for i, f in enumerate(part.Shape.Faces)
                  if abs(abs(f.Surface.Axis.dot(hole_axis)) - 1) < 1e-9
                  and f.Surface.TypeId == "Part::GeomCylinder"
                  or (f.Surface.TypeId == "Part::GeomPlane"
                      and abs(f.normalAt(0, 0).dot(hole_axis) - 1) < 1e-9)]
    if sorted(mould.UncoveredFaces) != sorted(hole_faces):
        problems.append(f"undercuts {mould.UncoveredFaces}, expected the hole {hole_faces}")
    if len(mould.SideCoreDirections) != 1 or not _close(mould.SideCoreDirections[0],
                                                        hole_axis):
        problems.append(f"side cores {mould.SideCoreDirections}, expected {hole_axis}")
    # the pocket and the hole tie (one surface each): either may be the main set-up
    setups = [App.Vector(*json.loads(s)["direction"]) for s in nc.Setups]
    if len(setups) != 2 or not ((_close(setups[0], axis) and _close(setups[1], hole_axis))
                                or (_close(setups[0], hole_axis) and _close(setups[1], axis))):
        problems.append(f"NC set-ups {setups}, expected the cup's and the hole's axes")

    reports = [feature_report(o) for o in (mould, nc)]
    for rep, seconds in zip(reports, (t1 - t0, t2 - t1)):
        rep.setdefault("timings_s", {})["feature_total"] = seconds
    parting.write_report_json(os.path.join(out, "demo_parting.json"), reports)
    parting.write_report_csv(os.path.join(out, "demo_parting.csv"), reports)
    text = [f"mfgeom parting demo: '{part.Label}' ({len(part.Shape.Faces)} faces), placed "
            f"rotated {math.degrees(rot.Angle):.1f} deg about {tuple(round(c, 3) for c in rot.Axis)}",
            f"  cup axis (global) {tuple(round(c, 6) for c in axis)}, hole axis "
            f"{tuple(round(c, 6) for c in hole_axis)}", ""]
    text += [parting.report_text(r) for r in reports]
    text.append("checks: " + ("all passed" if not problems else "; ".join(problems)))
    with open(os.path.join(out, "demo_parting.txt"), "w", encoding="utf-8") as f:
        f.write("\n".join(text) + "\n")
    sys.stdout.write("\n".join(text) + "\n")
    fcstd = os.path.join(out, "demo_parting.FCStd")
    doc.saveAs(fcstd)
    sys.stdout.write(f"demo_parting: wrote {out}/demo_parting.txt, .json, .csv, .FCStd\n")
    return 1 if problems else 0


try:
    rc = run()
except Exception:
    traceback.print_exc()
    rc = 1
compat.exit_now(rc)  # output flushed first (FreeCAD 1.0 buffers C stdio in a pipe)
