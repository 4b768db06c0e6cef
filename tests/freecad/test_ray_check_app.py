# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD App tests of the ray check of demouldability (issue 17), run by ``freecadcmd``.

Run through tests/run_freecad_tests.sh, or directly:
``MFGEOM_LIBRARY=build/libmfgeom.so freecadcmd tests/freecad/test_ray_check_app.py``.
Prints ``freecad-ray-check: N passed, M failed`` last and exits non-zero on any failure.

References are by construction: on a box every face is free on the side its normal
faces; a pocket's floor is free upward and blocked sideways by the pocket's walls; in a
C shape (floor, post, roof) the part of the floor's upward face under the roof is
blocked upward although its normal says "core side": the blocked fraction is the
shadowed share of its area.  A rotated copy gives the same verdicts for the rotated
direction."""

import os
import sys
import unittest

import numpy as np

import FreeCAD as App
import Part

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
if os.path.join(REPO, "workbench") not in sys.path:
    sys.path.append(os.path.join(REPO, "workbench"))

from mfgeom.app import ray_check  # noqa: E402

V = App.Vector
DEFLECTION = 0.05


def face_normal(face):
    u0, u1, v0, v1 = face.ParameterRange
    n = face.normalAt(0.5 * (u0 + u1), 0.5 * (v0 + v1))
    return np.array([n.x, n.y, n.z])


def planar_face(shape, normal, height):
    """The index of the planar face of ``shape`` with outward ``normal`` at
    normal . x = height."""
    normal = np.asarray(normal, dtype=float)
    for k, f in enumerate(shape.Faces):
        c = f.CenterOfMass
        if (type(f.Surface).__name__ == "Plane" and face_normal(f) @ normal > 0.999
                and abs(np.dot([c.x, c.y, c.z], normal) - height) < 1e-7):
            return k
    raise AssertionError(f"no face with normal {normal} at {height}")


def c_shape():
    """Floor 40 x 10 x 5, post 5 wide up to z = 25, roof 30 long z 25 .. 30."""
    floor = Part.makeBox(40, 10, 5)
    post = Part.makeBox(5, 10, 20, V(0, 0, 5))
    roof = Part.makeBox(30, 10, 5, V(0, 0, 25))
    return floor.fuse([post, roof]).removeSplitter()


class Box(unittest.TestCase):
    def test_faces_free_on_their_side(self):
        box = Part.makeBox(10, 20, 30)
        res = ray_check.ray_check(box, (0, 0, 1), DEFLECTION)
        self.assertEqual(len(res), 6)
        for k, r in enumerate(res):
            nz = face_normal(box.Faces[k])[2]
            expected = "core" if nz > 0.5 else ("cavity" if nz < -0.5 else "both")
            self.assertEqual(r.verdict, expected, f"Face{k + 1}")
            self.assertGreater(r.samples, 10)
        top = res[planar_face(box, (0, 0, 1), 30)]
        self.assertEqual(top.blocked_pos, 0.0)
        self.assertEqual(top.blocked_neg, 1.0)

    def test_mesh_is_global_and_outward(self):
        box = Part.makeBox(10, 20, 30)
        box.translate(V(100, -50, 7))
        v, t, f = ray_check.shape_mesh(box, DEFLECTION)
        np.testing.assert_allclose(v.min(0), [100, -50, 7], atol=1e-5)
        np.testing.assert_allclose(v.max(0), [110, -30, 37], atol=1e-5)
        a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
        volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
        self.assertAlmostEqual(volume, 6000, delta=1e-2)
        self.assertEqual(sorted(set(f.tolist())), list(range(6)))


class Pocket(unittest.TestCase):
    def setUp(self):
        self.part = Part.makeBox(20, 20, 10).cut(Part.makeBox(10, 10, 6, V(5, 5, 4)))
        self.floor = planar_face(self.part, (0, 0, 1), 4)

    def test_floor_core_side_along_z(self):
        res = ray_check.ray_check(self.part, (0, 0, 1), DEFLECTION)
        self.assertEqual(res[self.floor].verdict, "core")
        # the pocket wall at x = 15 slides out upward, but its ray down meets the floor;
        # the outer wall x = 0 is free both ways
        wall = planar_face(self.part, (-1, 0, 0), -15)
        self.assertEqual(res[wall].verdict, "core")
        self.assertEqual(res[wall].blocked_neg, 1.0)
        self.assertEqual(res[planar_face(self.part, (-1, 0, 0), 0)].verdict, "both")
        top = planar_face(self.part, (0, 0, 1), 10)
        self.assertEqual(res[top].verdict, "core")

    def test_floor_blocked_along_x(self):
        res = ray_check.ray_check(self.part, (1, 0, 0), DEFLECTION)
        floor = res[self.floor]
        self.assertEqual(floor.verdict, "blocked")
        self.assertEqual(floor.blocked_pos, 1.0)
        self.assertEqual(floor.blocked_neg, 1.0)
        # the pocket wall at x = 15 faces -x, but across the pocket stands the wall x = 5;
        # the outer wall x = 0 is free along -x
        self.assertEqual(res[planar_face(self.part, (-1, 0, 0), -15)].verdict, "blocked")
        self.assertEqual(res[planar_face(self.part, (-1, 0, 0), 0)].verdict, "cavity")
        self.assertEqual(res[planar_face(self.part, (1, 0, 0), 20)].verdict, "core")


class Shadowed(unittest.TestCase):
    def test_floor_under_the_roof(self):
        part = c_shape()
        floor_top = planar_face(part, (0, 0, 1), 5)
        self.assertGreater(face_normal(part.Faces[floor_top])[2], 0.999)  # normal: core side
        res = ray_check.ray_check(part, V(0, 0, 1), DEFLECTION)
        r = res[floor_top]
        self.assertEqual(r.verdict, "blocked")
        # the floor's top runs x 5 .. 40, the roof covers x < 30: 25 / 35 of it
        self.assertAlmostEqual(r.blocked_pos, 25 / 35, delta=0.05)
        self.assertEqual(r.blocked_neg, 1.0)
        self.assertEqual(res[planar_face(part, (0, 0, 1), 30)].verdict, "core")
        self.assertEqual(res[planar_face(part, (0, 0, -1), -25)].verdict, "blocked")
        self.assertEqual(res[planar_face(part, (0, 0, -1), 0)].verdict, "cavity")

    def test_rotated_copy_same_verdicts(self):
        part = c_shape()
        base = [r.verdict for r in ray_check.ray_check(part, (0, 0, 1), DEFLECTION)]
        rot = App.Rotation(V(0.3, -0.5, 0.8), 37.0)
        turned = part.copy()
        turned.Placement = App.Placement(V(12.5, -3.0, 40.0), rot)
        d = rot.multVec(V(0, 0, 1))
        got = [r.verdict for r in ray_check.ray_check(turned, d, DEFLECTION)]
        self.assertEqual(got, base)
        self.assertIn("blocked", got)
        self.assertIn("both", got)


sys.path.insert(0, HERE)
from fc_testsupport import run_file  # noqa: E402

sys.exit(run_file(globals(), "freecad-ray-check"))
