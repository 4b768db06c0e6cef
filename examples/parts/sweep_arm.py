# SPDX-License-Identifier: LGPL-2.1-or-later
"""Example part for the rotational sweep (issue 8): a stepped crank arm, 10 mm thick, that
turns about its hub axis.  An L-shaped plate (a 90 mm bar along +x with a 38 mm leg along
+y at its hub end) whose tip has a 6 x 4 mm chamfer on its top edge: 9 planar faces (the 6
sides of the L, bottom, top and the chamfer, whose slanted edges sweep into skew
surfaces of revolution).  The hub axis is the z axis through (HUB_X, HUB_Y): the part's
own frame, so a sweep about ``AXIS_POINT`` / ``AXIS_DIR`` is the arm swinging in its plane.
"""

import FreeCAD as App
import Part

THICKNESS = 10.0
# The L outline in z = 0, counter-clockwise (outward normals of the sides point away).
OUTLINE = ((0.0, 0.0), (90.0, 0.0), (90.0, 14.0), (16.0, 14.0), (16.0, 38.0), (0.0, 38.0))
CHAMFER = (6.0, 4.0)           # along -x on the top face, along -z on the tip face
HUB_X, HUB_Y = 8.0, 8.0        # the hub (pivot) centre, inside the bar near its end
AXIS_POINT = (HUB_X, HUB_Y, 0.0)
AXIS_DIR = (0.0, 0.0, 1.0)


def make():
    """The arm as a Part solid with exactly 9 faces."""
    pts = [App.Vector(x, y, 0) for x, y in OUTLINE]
    face = Part.Face(Part.makePolygon(pts + [pts[0]]))
    solid = face.extrude(App.Vector(0, 0, THICKNESS))
    tip_top = [e for e in solid.Edges
               if all(abs(v.Point.x - 90.0) < 1e-9 and abs(v.Point.z - THICKNESS) < 1e-9
                      for v in e.Vertexes)]
    # makeChamfer(d1, d2, edges) puts d1 on the first face of the edge, which OCC picks:
    # checked below (the top face must end at x = 90 - 6), not assumed.
    arm = solid.makeChamfer(CHAMFER[1], CHAMFER[0], tip_top)
    top = [f for f in arm.Faces
           if abs(f.BoundBox.ZMin - THICKNESS) < 1e-9 and abs(f.BoundBox.ZMax - THICKNESS) < 1e-9]
    if (len(arm.Faces) != 9 or len(top) != 1
            or abs(top[0].BoundBox.XMax - (90.0 - CHAMFER[0])) > 1e-9
            or abs(arm.Volume - exact_volume()) > 1e-6):
        raise RuntimeError(f"sweep_arm: unexpected chamfer ({len(arm.Faces)} faces, "
                           f"volume {arm.Volume})")
    return arm


def exact_volume():
    """The arm's own volume (mm^3): the L plate less the chamfer's wedge."""
    plate = 90.0 * 14.0 + 16.0 * 24.0
    return plate * THICKNESS - CHAMFER[0] * CHAMFER[1] * 14.0 / 2


if __name__ == "__main__":
    Part.show(make(), "SweepArm")
