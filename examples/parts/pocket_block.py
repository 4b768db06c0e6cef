# SPDX-License-Identifier: LGPL-2.1-or-later
"""Example part for the parting analysis: a block with rectangular pockets on three
sides (+z, +x, -y).  NC 3-axis: three set-ups, one per side."""

import FreeCAD as App
import Part

SIZE = (60.0, 40.0, 30.0)


def make():
    lx, ly, lz = SIZE
    block = Part.makeBox(lx, ly, lz)
    pockets = [Part.makeBox(20, 15, 10, App.Vector(10, 10, lz - 10)),          # from +z
               Part.makeBox(8, 12, 10, App.Vector(lx - 8, 20, 8)),             # from +x
               Part.makeBox(14, 6, 10, App.Vector(38, 0, 12))]                 # from -y
    for p in pockets:
        block = block.cut(p)
    return block


if __name__ == "__main__":
    Part.show(make(), "PocketBlock")
