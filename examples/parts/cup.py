# SPDX-License-Identifier: LGPL-2.1-or-later
"""Example part for the parting analysis: a cup (a cylinder with a blind pocket from the
top).  Mould: parting along +-z (pocket on the core side), every surface covered."""

import FreeCAD as App
import Part

RADIUS, HEIGHT, WALL, BOTTOM = 20.0, 30.0, 3.0, 4.0


def make():
    body = Part.makeCylinder(RADIUS, HEIGHT)
    pocket = Part.makeCylinder(RADIUS - WALL, HEIGHT, App.Vector(0, 0, BOTTOM))
    return body.cut(pocket)


if __name__ == "__main__":
    Part.show(make(), "Cup")
