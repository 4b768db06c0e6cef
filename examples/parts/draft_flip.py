# SPDX-License-Identifier: LGPL-2.1-or-later
"""Example part for the parting analysis where the draft angle flips the answer: a
block with three straight-walled pockets on top (+z) and two tapered conical pockets
(walls 10 degrees off their axis) on the +x side.  Without draft the top pockets win
(parting along +-z); with a 3 degree draft their vertical walls fail and the parting
direction moves near +x, where the tapered pockets and all six sides have draft."""

import math

import FreeCAD as App
import Part

SIZE = (80.0, 60.0, 40.0)
TAPER_DEG = 10.0


def make():
    lx, ly, lz = SIZE
    block = Part.makeBox(lx, ly, lz)
    for x in (10.0, 35.0, 60.0):
        block = block.cut(Part.makeBox(10, 10, 8, App.Vector(x, 25, lz - 8)))
    depth, r_floor = 8.0, 5.0
    r_mouth = r_floor + depth * math.tan(math.radians(TAPER_DEG))
    for y in (18.0, 42.0):
        cone = Part.makeCone(r_floor, r_mouth + 2 * math.tan(math.radians(TAPER_DEG)),
                             depth + 2, App.Vector(lx - depth, y, lz / 2), App.Vector(1, 0, 0))
        block = block.cut(cone)
    return block


if __name__ == "__main__":
    Part.show(make(), "DraftFlip")
