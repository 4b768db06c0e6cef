# SPDX-License-Identifier: LGPL-2.1-or-later
"""Example part for the medial surface and the FEM mid-surface (issue 9): a ribbed tray,
a thin-walled part with planar faces only.  An open box LENGTH x WIDTH x HEIGHT with a
WALL-thick floor and side walls and one RIB-thick cross rib at mid-length, so its
mid-surface has two wall thicknesses to tell apart by colour (3 mm walls, 2 mm rib).
Run it in FreeCAD (``freecad thin_wall.py`` or exec) to get a document with the tray, or
import it and call :func:`make`.
"""

import FreeCAD as App
import Part

LENGTH, WIDTH, HEIGHT = 60.0, 40.0, 15.0
WALL = 3.0     # floor and side walls
RIB = 2.0      # the cross rib at x = LENGTH / 2


def make():
    """The tray as one Part solid with planar faces only (coplanar faces merged)."""
    outer = Part.makeBox(LENGTH, WIDTH, HEIGHT)
    depth = HEIGHT - WALL + 1.0          # the pockets run out through the open top
    pocket_len = (LENGTH - 2 * WALL - RIB) / 2.0
    pockets = [Part.makeBox(pocket_len, WIDTH - 2 * WALL, depth, App.Vector(x, WALL, WALL))
               for x in (WALL, WALL + pocket_len + RIB)]
    tray = outer.cut(Part.makeCompound(pockets)).removeSplitter()
    solids = tray.Solids
    if len(solids) != 1 or not solids[0].isValid():
        raise RuntimeError(f"thin_wall: {len(solids)} solids, expected one valid solid")
    tray = solids[0]
    if abs(tray.Volume - exact_volume()) > 1e-6 * exact_volume():
        raise RuntimeError(f"thin_wall: volume {tray.Volume}, expected {exact_volume()}")
    return tray


def exact_volume():
    pocket_len = (LENGTH - 2 * WALL - RIB) / 2.0
    return LENGTH * WIDTH * HEIGHT - 2 * pocket_len * (WIDTH - 2 * WALL) * (HEIGHT - WALL)


def add_to(doc, name="ThinWall"):
    """The tray as a Part::Feature in ``doc``."""
    obj = doc.addObject("Part::Feature", name)
    obj.Shape = make()
    obj.Label = "Ribbed tray"
    doc.recompute()
    return obj


if __name__ == "__main__":
    add_to(App.ActiveDocument or App.newDocument("ThinWall"))
