# SPDX-License-Identifier: LGPL-2.1-or-later
"""Writes the tessellated real parts of the sweep battery (test_sweep_battery.c, family
"part") as OFF files next to this script, from the corpus (tests/corpus, licences in
tests/corpus/LICENSES.md), offline with FreeCAD's mesher:

    freecadcmd libcore/tests/sweep/data/make_parts.py

Each file keeps the licence of the part it was made from (data/README.md says which).
The coordinates are FreeCAD's mesh points (float32), printed with 9 significant digits,
which is enough to give each of them back; the C side reads them as doubles and checks
that the mesh is a closed, outward oriented 2-manifold without self-intersections.
"""

import gzip
import os
import tempfile

import FreeCAD  # noqa: F401  (initialises the application for Part / MeshPart)
import MeshPart
import Part

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "..", "..", "..", "..", "tests", "corpus")

# (corpus file, output name, linear deflection in the part's units, what it is)
PARTS = [
    ("TCMT1107_4.stp.gz", "tcmt1107_insert.off", 0.05,
     "TCMT turning insert (machined), FreeCAD's IDF library, LGPL-2.0-or-later"),
    ("Pump_Nut.brep.gz", "pump_nut.off", 0.5,
     "pump nut (cones, tori), Open CASCADE sample data, LGPL-2.1-only with the OCCT exception"),
]
ANGULAR_DEFLECTION = 0.5  # radians: FreeCAD's default for MeshPart


def load_solid(name):
    data = gzip.open(os.path.join(CORPUS, name)).read()
    suffix = "." + name.split(".")[1]
    fd, tmp = tempfile.mkstemp(suffix=suffix)
    try:
        os.write(fd, data)
        os.close(fd)
        shape = Part.Shape()
        shape.read(tmp)
    finally:
        os.remove(tmp)
    return shape.Solids[0]


def main():
    for src, out, deflection, what in PARTS:
        solid = load_solid(src)
        mesh = MeshPart.meshFromShape(Shape=solid, LinearDeflection=deflection,
                                      AngularDeflection=ANGULAR_DEFLECTION, Relative=False)
        points, facets = mesh.Topology
        with open(os.path.join(HERE, out), "w") as f:
            f.write("OFF\n")
            f.write("# %s\n# from tests/corpus/%s, MeshPart.meshFromShape(LinearDeflection=%g, "
                    "AngularDeflection=%g)\n" % (what, src, deflection, ANGULAR_DEFLECTION))
            f.write("%d %d 0\n" % (len(points), len(facets)))
            for p in points:
                f.write("%.9g %.9g %.9g\n" % (p.x, p.y, p.z))
            for a, b, c in facets:
                f.write("3 %d %d %d\n" % (a, b, c))


main()
