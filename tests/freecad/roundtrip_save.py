# SPDX-License-Identifier: LGPL-2.1-or-later
"""Document round trip between FreeCAD versions, first half (run with freecadcmd):
  MFGEOM_ROUNDTRIP_DIR=DIR freecadcmd tests/freecad/roundtrip_save.py
builds a document with one of each of the workbench's FeaturePython objects (point
classification, parting analysis in its three modes with the ray check, rotational sweep
as mesh and as solid, medial axis, medial surface, mid-surface), saves it as
DIR/roundtrip.FCStd and their results (roundtrip_common.summary, plus a clearance check
of the sweep) as DIR/roundtrip.json.  roundtrip_check.py then opens the file on another
FreeCAD version.  Prints "roundtrip-save: N objects, FreeCAD V" and exits 0, or a
traceback and exits 1."""

import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import roundtrip_common as rc  # noqa: E402

import FreeCAD as App  # noqa: E402
import Points  # noqa: E402

import mfgeom  # noqa: E402


def build(doc):
    """The document's objects; returns the mfgeom objects made."""
    import cup_hole
    import draft_flip
    import pocket_block
    import sweep_arm

    made = []
    # point classification of a cloud against the top face of a box
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 10.0, 8.0, 4.0
    doc.recompute()
    cloud = doc.addObject("Points::Feature", "Cloud")
    cloud.Points = Points.Points([(x * 0.5 - 1.0, y * 0.5 - 1.0, 4.0 + (x % 3) * 0.004)
                                  for x in range(25) for y in range(21)])
    made.append(mfgeom.make_point_classification(doc, (box, "Face6"), cloud, 0.005,
                                                 name="Classes"))

    def feature(name, shape):
        obj = doc.addObject("Part::Feature", name)
        obj.Shape = shape
        return obj

    # parting analysis: mould (with the ray check), NC set-ups, draft along +Z
    cup = feature("CupHole", cup_hole.make())
    mould = mfgeom.make_parting_analysis(doc, cup, mode="Mould", draft_angle=1.0,
                                         name="Mould")
    mould.RayCheck = True
    made.append(mould)
    # the mould tooling on it (issue 21): parting line, parting surface, core and cavity
    blocks = mfgeom.make_mould_blocks(doc, mould, 6.0, name="Blocks")
    made += [blocks.PartingSurface.PartingLine, blocks.PartingSurface, blocks]
    made.append(mfgeom.make_parting_analysis(doc, feature("PocketBlock", pocket_block.make()),
                                             mode="NC3Axis", name="Setups"))
    made.append(mfgeom.make_parting_analysis(doc, feature("DraftFlip", draft_flip.make()),
                                             mode="Draft", draft_angle=2.0,
                                             pull_direction=App.Vector(0, 0, 1),
                                             name="Draft"))
    # rotational sweep of the arm as a mesh, of a block as a solid
    arm = feature("Arm", sweep_arm.make())
    made.append(mfgeom.make_rotational_sweep(doc, arm, sweep_arm.AXIS_POINT,
                                             sweep_arm.AXIS_DIR, 90, 0.01,
                                             name="SweepMesh"))
    block = doc.addObject("Part::Box", "Block")
    block.Placement.Base = App.Vector(5.0, 0.0, 0.0)
    doc.recompute()
    made.append(mfgeom.make_rotational_sweep(doc, block, (0, 0, 0), "Z", 60, 0.01,
                                             representation="Solid", name="SweepSolid"))
    obstacle = doc.addObject("Part::Box", "Obstacle")
    obstacle.Placement.Base = App.Vector(sweep_arm.AXIS_POINT[0] + 20.0,
                                         sweep_arm.AXIS_POINT[1] - 5.0, -2.0)
    # medial axis of the box's top face, medial surface and mid-surface of a slab
    made.append(mfgeom.make_medial_axis(doc, (box, "Face6"), 0.01, name="Axis"))
    slab = doc.addObject("Part::Box", "Slab")
    slab.Length, slab.Width, slab.Height = 20.0, 12.0, 4.0
    slab.Placement.Base = App.Vector(0.0, 50.0, 0.0)
    doc.recompute()
    medial = mfgeom.make_medial_surface(doc, slab, name="Medial")
    made.append(medial)
    made.append(mfgeom.make_mid_surface(doc, medial, name="Mid"))
    doc.recompute()
    return made


def main():
    fcstd, results = rc.paths()
    os.makedirs(os.path.dirname(fcstd), exist_ok=True)
    doc = App.newDocument("roundtrip")
    made = build(doc)
    bad = [o.Name for o in made if not o.isValid()]
    if bad:
        raise RuntimeError(f"invalid after recompute: {bad}: "
                           + "; ".join(doc.getObject(n).getStatusString() for n in bad))
    data = {"freecad": rc.freecad_version(),
            "objects": {o.Name: {"type": o.Proxy.Type, "version": o.Version,
                                 "results": rc.summary(o)} for o in made},
            "clearance": rc.clearance_results(doc)}
    doc.saveAs(fcstd)
    with open(results, "w", encoding="utf-8") as f:
        json.dump(data, f, indent=1, sort_keys=True)
    sys.stdout.write(f"roundtrip-save: {len(made)} objects, FreeCAD {data['freecad']}: "
                     f"{fcstd}\n")
    return 0


rc.run_main(main)
