# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD App tests of mfgeom.app.gauss_map on B-spline and singular faces (issue 17),
run by ``freecadcmd``:
``MFGEOM_LIBRARY=build/libmfgeom.so freecadcmd tests/freecad/test_gauss_map_app.py``.
Prints ``freecad-gauss-map: N passed, M failed`` last and exits non-zero on any failure.

The reference is OCCT's ``Face.normalAt`` on a dense UV grid (200 x 200) of the face's
parameter box (the box the maps are built for; points where OCCT has no normal are left
out).  Checked for each face:

* containment: the returned normals' visibility map (the library's), shrunk by the
  face's shrink, lies inside the dense normals' one: every vertex v of it, and every one
  of 4 000 Fibonacci directions d inside it, has v.n >= -1e-9 for each dense normal n;
* excess: the draft margin asin(min n.d) that any direction d (of 4 000) seeing all dense
  normals loses on the returned normals is at most EXCESS_BOUND (0.01 rad; the control
  nets are refined to 1e-3 rad along the directions they measure, and the test's
  directions are others).
"""

import math
import os
import sys
import unittest

import numpy as np

import FreeCAD as App
import Part

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.append(os.path.join(REPO, "workbench"))

from mfgeom import core, parting  # noqa: E402
from mfgeom.app import gauss_map  # noqa: E402

PLACEMENT = App.Placement(App.Vector(5, -7, 11), App.Rotation(App.Vector(1, 2, 3), 37))
EXCESS_BOUND = 0.01
DIRS = parting.fibonacci_sphere(4000)


def dense_normals(face, k=200):
    u0, u1, v0, v1 = face.ParameterRange
    out = []
    for u in np.linspace(u0, u1, k):
        for v in np.linspace(v0, v1, k):
            try:
                n = face.normalAt(float(u), float(v))
            except Exception:
                continue
            if math.isfinite(n.x + n.y + n.z) and n.Length > 0.5:
                out.append((n.x, n.y, n.z))
    return np.array(out)


def bspline_face(poles, udeg=3, vdeg=3, uknots=None, vknots=None):
    nu, nv = len(poles), len(poles[0])
    uk = uknots or [0.0] + [i / (nu - udeg) for i in range(1, nu - udeg)] + [1.0]
    vk = vknots or [0.0] + [j / (nv - vdeg) for j in range(1, nv - vdeg)] + [1.0]
    s = Part.BSplineSurface()
    s.buildFromPolesMultsKnots(poles, [udeg + 1] + [1] * (len(uk) - 2) + [udeg + 1],
                               [vdeg + 1] + [1] * (len(vk) - 2) + [vdeg + 1], uk, vk,
                               False, False, udeg, vdeg)
    return s.toShape()


def wave_poles(nu=7, nv=6, amp=2.0):
    return [[App.Vector(3 * i, 3 * j, amp * math.sin(1.3 * i) * math.cos(0.9 * j) + 0.2 * i * j)
             for j in range(nv)] for i in range(nu)]


def twisted_poles(nu=6, nv=4):
    out = []
    for i in range(nu):
        a = math.radians(20 * i)
        out.append([App.Vector(4 * i, (j - 1.5) * 3 * math.cos(a), (j - 1.5) * 3 * math.sin(a))
                    for j in range(nv)])
    return out


def interpolated_face():
    pts = [[App.Vector(2 * i, 2 * j, math.sin(0.7 * i) + 0.5 * math.cos(1.1 * j))
            for j in range(7)] for i in range(8)]
    s = Part.BSplineSurface()
    s.interpolate(pts)
    return s.toShape()


def periodic_loft_faces():
    """A lofted blade through closed (periodic) interpolated B-spline sections."""
    wires = []
    for f, z in ((0.0, 0.0), (0.5, 5.0), (1.0, 10.0)):
        c, s = math.cos(0.4 * f), math.sin(0.4 * f)
        pts = [App.Vector(c * 6 * math.cos(t) - s * 1.2 * math.sin(t),
                          s * 6 * math.cos(t) + c * 1.2 * math.sin(t) + 0.8 * math.cos(t) ** 2, z)
               for t in np.linspace(0, 2 * math.pi, 11)[:-1]]
        curve = Part.BSplineCurve()
        curve.interpolate(pts, PeriodicFlag=True)
        wires.append(Part.Wire([curve.toShape()]))
    loft = Part.makeLoft(wires, True, False)
    return [f for f in loft.Faces if isinstance(f.Surface, Part.BSplineSurface)]


def placed(face):
    face = face.copy()
    face.Placement = PLACEMENT
    return face


class Bounds(unittest.TestCase):
    def assert_holds(self, face, g, excess=EXCESS_BOUND):
        dense = dense_normals(face)
        self.assertGreater(len(dense), 100, g.name)
        vm = core.visibility_map(g.normals, draft_angle=g.shrink)
        if vm.kind != "null":
            self.assertGreaterEqual((vm.vertices @ dense.T).min(), -1e-9, g.name)
        margin_g = (DIRS @ g.normals.T).min(axis=1)
        seen = margin_g >= math.sin(g.shrink)
        if seen.any():
            self.assertGreaterEqual((DIRS[seen] @ dense.T).min(), -1e-9, g.name)
        margin_d = (DIRS @ dense.T).min(axis=1)
        sees = margin_d >= 0
        lost = 0.0
        if sees.any():
            lost = float((np.arcsin(margin_d[sees])
                          - np.arcsin(np.clip(margin_g[sees], -1, 1)) + g.shrink).max())
            self.assertLessEqual(lost, excess, g.name)
        return lost

    def check(self, face, name, bspline=True, **kw):
        warnings = []
        g = gauss_map.face_gauss(face, name=name, warnings=warnings)
        self.assertEqual(warnings, [])
        self.assertIsNotNone(g, name)
        if bspline:
            self.assertEqual(g.shrink, 0.0, name)   # a bound, not samples
        self.assertTrue(np.all(np.isfinite(g.normals)), name)
        return g, self.assert_holds(face, g, **kw)

    def test_bspline_kinds(self):
        big = bspline_face(wave_poles(9, 8))
        u0, u1, v0, v1 = big.ParameterRange
        trimmed = big.Surface.toShape(u0 + 0.2 * (u1 - u0), u0 + 0.65 * (u1 - u0),
                                      v0 + 0.3 * (v1 - v0), v0 + 0.9 * (v1 - v0))
        circle = Part.makeCircle(5, App.Vector(12, 10, -20), App.Vector(0, 0, 1))
        holed = big.cut(Part.Face(Part.Wire(circle)).extrude(App.Vector(0, 0, 40))).Faces[0]
        faces = {
            "wave": bspline_face(wave_poles()),
            "interpolated": interpolated_face(),
            "twisted": bspline_face(twisted_poles()),
            "reversed": bspline_face(wave_poles()).reversed(),
            "placed": placed(bspline_face(twisted_poles())),
            "placed reversed": placed(bspline_face(wave_poles()).reversed()),
            "trimmed box": trimmed,
            "holed": holed,
            "bicubic 1 patch": bspline_face(wave_poles(4, 4)),
            "degree 2 x 5": bspline_face(wave_poles(6, 7), 2, 5),
        }
        self.assertEqual(faces["reversed"].Orientation, "Reversed")
        for name, face in faces.items():
            g, lost = self.check(face, name)
            sys.stdout.write(f"  {name}: {len(g.normals)} normals, excess {lost:.2e} rad\n")

    def test_periodic(self):
        faces = periodic_loft_faces()
        self.assertTrue(faces)
        for k, face in enumerate(faces):
            self.check(face, f"loft {k}")
            self.check(placed(face), f"placed loft {k}")
        # a surface periodic in u, made so explicitly, and a face across its seam
        s = Part.BSplineSurface()
        poles = [[App.Vector(5 * math.cos(2 * math.pi * i / 8), 5 * math.sin(2 * math.pi * i / 8)
                             + (1 if i % 2 else 0), 3 * j + 0.5 * math.sin(i + j))
                  for j in range(4)] for i in range(8)]
        s.buildFromPolesMultsKnots(poles, [1] * 9, [4, 4], list(range(9)), [0.0, 1.0],
                                   True, False, 3, 3)
        self.assertTrue(s.isUPeriodic())
        self.check(s.toShape(), "periodic")
        self.check(s.toShape(6.5, 9.5, 0.0, 1.0), "across the seam")

    def test_bezier_offset_extrusion(self):
        bez = Part.BezierSurface()
        bez.increase(3, 3)
        for i in range(4):
            for j in range(4):
                bez.setPole(i + 1, j + 1, App.Vector(i, j, math.sin(i * 1.7) * math.cos(j)))
        self.check(bez.toShape(), "bezier")
        self.check(bez.toShape(0.2, 0.7, 0.1, 0.6), "bezier part")
        wave = bspline_face(wave_poles()).Surface
        self.check(Part.OffsetSurface(wave, 1.5).toShape(), "offset")
        self.check(placed(Part.OffsetSurface(wave, -0.5).toShape()), "placed offset")
        curve = Part.BSplineCurve()
        curve.interpolate([App.Vector(x, math.sin(x), 0.3 * x) for x in np.linspace(0, 6, 9)])
        prism = Part.Wire([curve.toShape()]).extrude(App.Vector(0.3, -0.2, 4))
        f = prism.Faces[0]
        self.assertIsInstance(f.Surface, Part.SurfaceOfExtrusion)
        self.check(f, "extrusion")
        self.check(placed(f), "placed extrusion")

    def test_fallback_kinds_sampled(self):
        """Rational and revolved faces keep the grid (with its shrink) and hold their
        dense normals."""
        profile = Part.BSplineCurve()
        profile.interpolate([App.Vector(2 + math.sin(z), 0, z) for z in np.linspace(0, 6, 7)])
        rev = Part.Wire([profile.toShape()]).revolve(App.Vector(), App.Vector(0, 0, 1), 270)
        f = rev.Faces[0]
        self.assertIsInstance(f.Surface, Part.SurfaceOfRevolution)
        g, _ = self.check(f, "revolution", bspline=False)
        self.assertGreater(g.shrink, 0.0)
        # a rational B-spline (weights 1 and 2): sampled
        rat = Part.BSplineSurface()
        poles = wave_poles(4, 4)
        weights = [[1.0 + (i * j) % 2 for j in range(4)] for i in range(4)]
        rat.buildFromPolesMultsKnots(poles, [4, 4], [4, 4], [0.0, 1.0], [0.0, 1.0], False,
                                     False, 3, 3, weights)
        self.assertTrue(rat.isURational())
        g, _ = self.check(rat.toShape(), "rational", bspline=False)
        self.assertGreater(g.shrink, 0.0)


class Singular(unittest.TestCase):
    check = Bounds.check
    assert_holds = Bounds.assert_holds

    def test_apex_pole_collapsed_axis(self):
        # a dome: one row of poles collapsed to the apex
        dome = [[App.Vector(i * math.cos(2 * math.pi * j / 3), i * math.sin(2 * math.pi * j / 3),
                            3 - 0.8 * i + 0.3 * math.sin(j)) for j in range(4)] for i in range(4)]
        profile = Part.BSplineCurve()
        profile.interpolate([App.Vector(x, 0, 4 - x * x / 4) for x in np.linspace(0, 4, 6)])
        touching = Part.Wire([profile.toShape()]).revolve(App.Vector(), App.Vector(0, 0, 1), 360)
        cases = [(f, f"cone {k}", False) for k, f in enumerate(Part.makeCone(3, 0, 4).Faces)]
        cases += [(Part.makeSphere(3).Faces[0], "sphere", False),
                  (placed(Part.makeSphere(2, App.Vector(), App.Vector(0, 0, 1), 0, 90)).Faces[0],
                   "half sphere", False),
                  (bspline_face(dome), "collapsed edge", True),
                  (placed(bspline_face(dome)), "placed collapsed edge", True),
                  (touching.Faces[0], "revolved to the axis", False)]
        for face, name, is_bspline in cases:
            # wide faces (a whole sphere) have an empty map: containment is what counts
            self.check(face, name, bspline=is_bspline, excess=math.pi)

    def test_unevaluable_face_skipped_by_name(self):
        shape = Part.makeBox(10, 10, 10).fuse(Part.makeSphere(3, App.Vector(5, 5, 10)))
        spheres = [i for i, f in enumerate(shape.Faces) if isinstance(f.Surface, Part.Sphere)]
        self.assertEqual(len(spheres), 1)
        original = gauss_map._Normals._raw

        def no_normal_on_spheres(self, u, v):   # OCCT failing everywhere on that face
            return None if isinstance(self.surface, Part.Sphere) else original(self, u, v)
        gauss_map._Normals._raw = no_normal_on_spheres
        try:
            warnings = []
            faces, adj, _ = gauss_map.part_gauss(shape, warnings=warnings)
            with self.assertRaises(ValueError):
                gauss_map.part_gauss(shape)
        finally:
            gauss_map._Normals._raw = original
        name = f"Face{spheres[0] + 1}"
        self.assertEqual(len(warnings), 1)
        self.assertTrue(warnings[0].startswith(f"{name}: no normal at (u, v) = ("), warnings[0])
        self.assertTrue(warnings[0].endswith(", skipped"), warnings[0])
        self.assertEqual(len(faces), len(shape.Faces) - 1)
        self.assertNotIn(name, [f.name for f in faces])
        self.assertTrue(all(0 <= i < len(faces) and 0 <= j < len(faces) for i, j, _ in adj))
        full, full_adj, _ = gauss_map.part_gauss(shape)
        self.assertEqual(len(full), len(shape.Faces))
        self.assertGreater(len(full_adj), len(adj))

    def test_unclassifiable_edge_taken_as_concave(self):
        # a spherical dimple in the top face: its rim is convex
        shape = Part.makeBox(10, 10, 10).cut(Part.makeSphere(3, App.Vector(5, 5, 10)))
        sphere = next(i for i, f in enumerate(shape.Faces) if isinstance(f.Surface, Part.Sphere))
        original = gauss_map._FaceNormals.at

        def fails_on_spheres(self, p, edge=None, t=None):
            if isinstance(self.surface, Part.Sphere):
                raise gauss_map.NoNormal(0.0, 0.0)
            return original(self, p, edge, t)
        gauss_map._FaceNormals.at = fails_on_spheres
        try:
            warnings = []
            faces, adj, _ = gauss_map.part_gauss(shape, warnings=warnings)
        finally:
            gauss_map._FaceNormals.at = original
        self.assertEqual(len(faces), len(shape.Faces))
        touching = [(i, j, k) for i, j, k in adj if sphere in (i, j)]
        self.assertTrue(touching)
        self.assertTrue(all(k == "concave" for _, _, k in touching))
        self.assertEqual(len(warnings), len(touching))
        self.assertTrue(all(w.endswith(", taken as concave") and f"Face{sphere + 1}" in w
                            for w in warnings), warnings)
        # without the failure the dimple's rim is convex
        _, adj, _ = gauss_map.part_gauss(shape)
        self.assertEqual({k for i, j, k in adj if sphere in (i, j)}, {"convex"})

    def test_nudged_normals(self):
        """Where OCCT gives no normal (here: at the box's corners), the normal is taken
        slightly inside; the samples stay normals of the face."""
        face = Part.makeCone(3, 1, 4).Faces[0]
        original = gauss_map._Normals._raw
        u0, u1, v0, v1 = face.ParameterRange

        def fails_on_the_border(self, u, v):
            if u in (u0, u1) or v in (v0, v1):
                return None
            return original(self, u, v)
        gauss_map._Normals._raw = fails_on_the_border
        try:
            g = gauss_map.face_gauss(face)
        finally:
            gauss_map._Normals._raw = original
        ref = gauss_map.face_gauss(face)
        self.assertEqual(g.normals.shape, ref.normals.shape)
        np.testing.assert_allclose(g.normals, ref.normals, atol=1e-6)


class Adjacency(unittest.TestCase):
    def test_kinds_against_projected_normals(self):
        """Edge kinds on a part with B-spline faces (blades lofted through periodic
        sections, fused on a plate, placed) against OCCT's Face.normalAt at the edge's
        middle projected onto each face (Surface.parameter), the edge's tangent as it
        runs in the first face."""
        plate = Part.makeBox(40, 40, 4, App.Vector(-20, -20, -4))
        blades = []
        wires = []
        for f, z in ((0.0, -1.0), (0.5, 5.0), (1.0, 10.0)):
            c, s = math.cos(0.5 * f), math.sin(0.5 * f)
            pts = [App.Vector(c * 6 * math.cos(t) - s * 1.2 * math.sin(t),
                              s * 6 * math.cos(t) + c * 1.2 * math.sin(t), z)
                   for t in np.linspace(0, 2 * math.pi, 11)[:-1]]
            curve = Part.BSplineCurve()
            curve.interpolate(pts, PeriodicFlag=True)
            wires.append(Part.Wire([curve.toShape()]))
        blade = Part.makeLoft(wires, True, False)
        for k in range(3):
            b = blade.copy()
            b.translate(App.Vector(-12 + 12 * k, 0, 0))
            blades.append(b)
        part = plate.fuse(blades)
        part.Placement = PLACEMENT
        faces = part.Faces
        self.assertTrue(any(isinstance(f.Surface, Part.BSplineSurface) for f in faces))
        adj = gauss_map.adjacency(part)
        self.assertTrue(adj)
        kinds = set()
        for i, j, kind in adj:
            edges = [e for e in faces[i].Edges if any(e.isSame(x) for x in faces[j].Edges)]
            want = []
            for e in edges:
                t0, t1 = e.ParameterRange
                t = (t0 + t1) / 2
                p = e.valueAt(t)
                n1 = faces[i].normalAt(*faces[i].Surface.parameter(p))
                n2 = faces[j].normalAt(*faces[j].Surface.parameter(p))
                c = n1.cross(n2)
                if math.atan2(c.Length, n1.dot(n2)) <= gauss_map.DEFAULT_TANGENT_TOL:
                    want.append("tangent")
                    continue
                ine = next(x for x in faces[i].Edges if x.isSame(e))
                tan = ine.tangentAt(t) * (-1.0 if ine.Orientation == "Reversed" else 1.0)
                want.append("convex" if c.dot(tan) > 0 else "concave")
            self.assertIn(kind, want, (i, j))
            kinds.add(kind)
        self.assertIn("concave", kinds)   # the blade roots
        self.assertIn("convex", kinds)


sys.path.insert(0, HERE)
from fc_testsupport import run_file  # noqa: E402

sys.exit(run_file(globals(), "freecad-gauss-map"))
