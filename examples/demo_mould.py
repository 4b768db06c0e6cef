# SPDX-License-Identifier: LGPL-2.1-or-later
"""Mould demo (issue 21), run by ``freecadcmd`` after the parting demo: from the Mould
analysis to the parting line, the parting and shut-off surfaces and the core, cavity and
side-core inserts, through the macro API, for two bundled parts:

* the cup with a radial blind hole (examples/parts/cup_hole.py), tilted as in the parting
  demo: a planar parting line at the rim, the hole moulded by a side-core insert;
* the knob (examples/parts/knob.py): every face curved, the parting line runs inside the
  faces along their silhouettes (each face split there).

Checks each result (the feature's own checks: volumes, overlap, validity, demoulding;
plus what the part was built to give) and writes ``mould/<part>_core.step``,
``_cavity.step``, ``_insert<k>.step``, ``demo_mould.txt`` and ``demo_mould.FCStd`` into
$MFGEOM_OUT (default <repo>/out).  Exits non-zero if anything fails.
examples/render_mould.py renders core, cavity and part exploded along the direction.
"""

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

import cup_hole  # noqa: E402
import knob  # noqa: E402
import mfgeom  # noqa: E402
from mfgeom import compat  # noqa: E402

PLACEMENT = App.Placement(App.Vector(5, -3, 2), App.Rotation(App.Vector(1, 2, 0.5), 20))
MARGIN = 8.0


def mould_part(doc, name, label, shape, placement, out, text, problems, mode="Mould",
               pull=None):
    part = doc.addObject("Part::Feature", name)
    part.Shape = shape
    part.Label = label
    part.Placement = placement
    doc.recompute()
    t0 = time.perf_counter()
    analysis = mfgeom.make_parting_analysis(doc, part, mode=mode, pull_direction=pull,
                                            name=f"{name}Analysis")
    t1 = time.perf_counter()
    blocks = mfgeom.make_mould_blocks(doc, analysis, MARGIN, name=f"{name}Mould")
    t2 = time.perf_counter()
    line = blocks.PartingSurface.PartingLine
    surface = blocks.PartingSurface
    for obj in (analysis, line, surface, blocks):
        if not obj.isValid() or "Touched" in obj.State:
            problems.append(f"{obj.Label}: {obj.getStatusString()} {obj.State}")
    failed = [c for c in blocks.Checks if not c.endswith(": ok")]
    if failed:
        problems.append(f"{label}: checks failed: {failed}")
    os.makedirs(os.path.join(out, "mould"), exist_ok=True)
    files = []
    solids = [("core", blocks.Core), ("cavity", blocks.Cavity)]
    solids += [(f"insert{k + 1}", s) for k, s in enumerate(blocks.Inserts.Solids)]
    for what, s in solids:
        path = os.path.join(out, "mould", f"{name}_{what}.step")
        s.exportStep(path)
        files.append(os.path.relpath(path, out))
    v = list(blocks.Volumes)
    d = blocks.Direction
    text += [f"{label} ({len(part.Shape.Faces)} faces): direction "
             f"({d.x:+.6f}, {d.y:+.6f}, {d.z:+.6f}), analysis {t1 - t0:.2f} s, line + "
             f"surfaces + blocks {t2 - t1:.2f} s",
             f"  parting line: {line.LoopCount} loop(s): {'; '.join(line.Loops)}"
             + (f"; split along silhouettes: {' '.join(line.SplitFaces)}"
                if line.SplitFaces else ""),
             f"  surfaces: {surface.PartingSurfaceCount} parting, {surface.ShutOffCount} "
             "shut-off",
             f"  volumes (mm^3): block {v[0]:.6g} = part {v[1]:.6g} + core {v[2]:.6g} + "
             f"cavity {v[3]:.6g}" + "".join(f" + insert {x:.6g}" for x in v[4:]),
             f"  checks: {', '.join(blocks.Checks)}",
             f"  STEP: {', '.join(files)}", ""]
    return part, blocks


def run():
    out = os.path.abspath(os.environ.get("MFGEOM_OUT") or os.path.join(REPO, "out"))
    os.makedirs(out, exist_ok=True)
    doc = App.newDocument("DemoMould")
    problems, text = [], ["mfgeom mould demo (margin {:g} mm)".format(MARGIN), ""]
    cup_part, cup_blocks = mould_part(doc, "CupHole", "Cup with hole", cup_hole.make(),
                                      PLACEMENT, out, text, problems)
    # what the cup was built to give: one planar outer loop at the rim, one insert
    line = cup_blocks.PartingSurface.PartingLine
    if line.LoopCount != 1 or not line.Loops[0].startswith("outer, planar"):
        problems.append(f"cup: parting line {list(line.Loops)}, expected one planar loop")
    if len(cup_blocks.Inserts.Solids) != 1:
        problems.append(f"cup: {len(cup_blocks.Inserts.Solids)} inserts, expected 1")
    axis = PLACEMENT.Rotation.multVec(App.Vector(0, 0, 1))
    if abs(abs(cup_blocks.Direction.dot(axis)) - 1) > 1e-9:
        problems.append(f"cup: direction {cup_blocks.Direction}, expected its axis {axis}")
    # the knob: no direction from the analysis (every face straddles); a Draft analysis
    # along the direction a designer picks (across the handle) gives the mould its pull
    knob_part, knob_blocks = mould_part(
        doc, "Knob", "Knob", knob.make(), App.Placement(App.Vector(90, 0, 0), App.Rotation()),
        out, text, problems, mode="Draft", pull=(0.0, 0.0, 1.0))
    kline = knob_blocks.PartingSurface.PartingLine
    if len(kline.SplitFaces) != len(knob_part.Shape.Faces):
        problems.append(f"knob: split faces {list(kline.SplitFaces)}, expected all")
    if kline.LoopCount != 1 or not kline.Loops[0].startswith("outer, planar"):
        problems.append(f"knob: parting line {list(kline.Loops)}, expected one planar loop")
    text.append("checks: " + ("all passed" if not problems else "; ".join(problems)))
    with open(os.path.join(out, "demo_mould.txt"), "w", encoding="utf-8") as f:
        f.write("\n".join(text) + "\n")
    sys.stdout.write("\n".join(text) + "\n")
    doc.saveAs(os.path.join(out, "demo_mould.FCStd"))
    sys.stdout.write(f"demo_mould: wrote {out}/demo_mould.txt, .FCStd and mould/*.step\n")
    return 1 if problems else 0


try:
    rc = run()
except Exception:
    traceback.print_exc()
    rc = 1
compat.exit_now(rc)
