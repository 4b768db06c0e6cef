# SPDX-License-Identifier: LGPL-2.1-or-later
"""Example part for the parting analysis with B-spline faces: a block whose top is a
B-spline wave (normals within about 25 degrees of +z), with a cylindrical pocket in it.
Its faces are sampled (shrink > 0); mould: parting along +-z, everything covered."""

import FreeCAD as App
import Part

SIZE = (60.0, 40.0, 20.0)
AMPLITUDE = 4.0


def make():
    lx, ly, lz = SIZE
    poles = []
    for i in range(5):
        row = []
        for j in range(4):
            bump = AMPLITUDE * ((i % 2) * 2 - 1) * (0.5 if j in (0, 3) else 1.0)
            row.append(App.Vector(lx * i / 4, ly * j / 3, lz + bump if 0 < i < 4 else lz))
        poles.append(row)
    surf = Part.BSplineSurface()
    surf.buildFromPolesMultsKnots(poles, [4, 1, 4], [4, 4], [0, 0.5, 1], [0, 1], False,
                                  False, 3, 3)
    top = surf.toShape()
    # side walls and bottom from the top face's boundary, closed into a solid
    base = [App.Vector(0, 0, 0), App.Vector(lx, 0, 0), App.Vector(lx, ly, 0), App.Vector(0, ly, 0)]
    bottom = Part.Face(Part.makePolygon(base + [base[0]]))
    sides = []
    for e in top.Edges:
        a, b = e.Vertexes[0].Point, e.Vertexes[-1].Point
        lower = Part.makeLine(App.Vector(b.x, b.y, 0), App.Vector(a.x, a.y, 0))
        sides.append(Part.Face(Part.Wire([e, Part.makeLine(b, App.Vector(b.x, b.y, 0)), lower,
                                          Part.makeLine(App.Vector(a.x, a.y, 0), a)])))
    solid = Part.Solid(Part.Shell([top, bottom] + sides))
    if solid.Volume < 0:
        solid.complement()
    pocket = Part.makeCylinder(6, 30, App.Vector(lx / 2, ly / 2, 8))
    return solid.cut(pocket)


if __name__ == "__main__":
    Part.show(make(), "BSplinePart")
