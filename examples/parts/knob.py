# SPDX-License-Identifier: LGPL-2.1-or-later
"""Example part for the mould tooling (issue 21): a knob — a ball with a round handle
lying across the pull direction, ended by a half ball.  Every curved face's normals cross
the parting plane z = 0, so the parting line runs inside the faces, along their
silhouettes (the ball's and the end cap's equators, the handle's two side lines); the
parting surface is the plane z = 0 with that outline as its hole."""

import FreeCAD as App
import Part

BALL, HANDLE, LENGTH = 15.0, 5.0, 40.0


def make():
    ball = Part.makeSphere(BALL)
    handle = Part.makeCylinder(HANDLE, LENGTH, App.Vector(0, 0, 0), App.Vector(1, 0, 0))
    cap = Part.makeSphere(HANDLE, App.Vector(LENGTH, 0, 0))
    return ball.fuse([handle, cap]).removeSplitter()


if __name__ == "__main__":
    Part.show(make(), "Knob")
