# SPDX-License-Identifier: LGPL-2.1-or-later
"""Timing of the clearance check on a real assembly (not part of the suite; run by hand):
one solid of the corpus motor (tests/corpus/Motor-c.brep.gz) swept about the motor's
axis, checked against the other 16 solids.

    MFGEOM_LIBRARY=build/libmfgeom.so freecadcmd tests/freecad/bench_clearance_motor.py

Environment: PART (default 5: a 23 mm part at radius 37-45 mm), ANGLE (deg, 90; 360
makes a ring that interferes with the housing), TOL (mm, 0.1; the deflection too).
Prints the sweep's size and time, the check's wall and CPU time and one line per
obstacle."""

import os
import sys
import time

import FreeCAD as App

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
for path in (os.path.join(REPO, "workbench"), os.path.join(REPO, "tests", "corpus")):
    if path not in sys.path:
        sys.path.append(path)

import corpus  # noqa: E402
import mfgeom  # noqa: E402

PART = int(os.environ.get("PART", "5"))
ANGLE = float(os.environ.get("ANGLE", "90"))
TOL = float(os.environ.get("TOL", "0.1"))


def main():
    motor = next(p for p in corpus.PARTS if p.file.startswith("Motor-c"))
    solids = corpus.load(motor)[1]
    doc = App.newDocument("MotorClearance")
    objs = []
    for i, solid in enumerate(solids):
        obj = doc.addObject("Part::Feature", f"S{i}")
        obj.Shape = solid
        objs.append(obj)
    doc.recompute()
    start = time.perf_counter()
    sweep = mfgeom.make_rotational_sweep(doc, objs[PART], (0, 0, 0), "Z", ANGLE, TOL,
                                         deflection=TOL)
    took = time.perf_counter() - start
    out = [f"sweep of S{PART} by {ANGLE:g} deg at {TOL:g} mm: {sweep.TriangleCount} "
           f"triangles in {took:.1f} s"]
    others = [o for i, o in enumerate(objs) if i != PART]
    wall, cpu = time.perf_counter(), time.process_time()
    results = mfgeom.check_clearance(sweep, others)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    out.append(f"clearance check of {len(others)} solids: {wall:.1f} s wall, {cpu:.1f} s CPU")
    for r in results:
        out.append(f"  {r.label:4s} {r.status:12s} volume {r.interference_volume:10.4f} "
                   f"distance {r.min_distance}")
    sys.stdout.write("\n".join(out) + "\n")
    sys.stdout.flush()


main()
