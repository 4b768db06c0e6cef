# SPDX-License-Identifier: LGPL-2.1-or-later
"""Example part for the parting analysis: the cup with a blind radial hole in its wall
(along +x, not reaching the pocket).  Mould: parting along +-z, the hole is the one
undercut, side core along +x; NC: two set-ups (+z for the pocket, +x for the hole)."""

import FreeCAD as App
import Part

import cup

HOLE_RADIUS, HOLE_DEPTH, HOLE_Z = 4.0, 2.0, 18.0


def make():
    outside = cup.RADIUS + 5.0
    hole = Part.makeCylinder(HOLE_RADIUS, outside - (cup.RADIUS - HOLE_DEPTH),
                             App.Vector(outside, 0, HOLE_Z), App.Vector(-1, 0, 0))
    return cup.make().cut(hole)


if __name__ == "__main__":
    Part.show(make(), "CupHole")
