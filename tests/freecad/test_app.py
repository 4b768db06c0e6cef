# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD App tests of the point-classification feature, run by ``freecadcmd`` (no GUI).

Run through tests/run_freecad_tests.sh, or directly:
``MFGEOM_LIBRARY=build/libmfgeom.so freecadcmd tests/freecad/test_app.py``.
Prints ``freecad-app: N passed, M failed`` last and exits non-zero on any failure.
"""

import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import FreeCAD as App
import Part
import Points

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
for _path in (os.path.join(REPO, "examples"), os.path.join(REPO, "workbench")):
    if _path not in sys.path:
        sys.path.append(_path)

import bracket  # noqa: E402
import mfgeom  # noqa: E402
from mfgeom import core  # noqa: E402
from mfgeom import names, palette  # noqa: E402
from mfgeom.app import face_domain, pointcloud, refs  # noqa: E402
from mfgeom.app.pointclass import VERSION  # noqa: E402

sys.path.insert(0, HERE)
from fc_testsupport import DocumentTestCase, run_file  # noqa: E402

RNG = np.random.default_rng(12345)


# ------------------------------------------------------------------ helpers
def vec(p):
    return App.Vector(*[float(c) for c in p])


def add_cloud(doc, name, pts):
    obj = doc.addObject("Points::Feature", name)
    obj.Points = Points.Points([vec(p) for p in pts])
    return obj


def add_shape(doc, name, shape):
    obj = doc.addObject("Part::Feature", name)
    obj.Shape = shape
    return obj


def real_edges(face):
    """Boundary edges in 3-D: not degenerated, not used twice by the face (a seam)."""
    used = [e for w in face.Wires for e in w.OrderedEdges]
    return [e for e in face.Edges
            if not e.Degenerated and sum(1 for o in used if o.isSame(e)) == 1]


def surface_samples(face, n, margin=0.05):
    """n points on the face's surface, uniform in its parameter range grown by margin."""
    u0, u1, v0, v1 = face.ParameterRange
    du, dv = (u1 - u0) * margin, (v1 - v0) * margin
    uv = np.column_stack([RNG.uniform(u0 - du, u1 + du, n), RNG.uniform(v0 - dv, v1 + dv, n)])
    s = face.Surface
    out = []
    for u, v in uv:
        p = s.value(float(u), float(v))
        out.append((p.x, p.y, p.z))
    return np.array(out)


def occt_compare(test, face, pts, classes, tol):
    """Cross-check against OCCT: for every point whose projection is farther than
    2 * tol from the boundary, ours == Face.isInside (BRepClass); and ON agrees with the
    3-D distance to the boundary (<= 0.9 tol -> ON, >= 1.1 tol -> not ON)."""
    edges = Part.Compound(real_edges(face))
    s = face.Surface
    far = 0
    for p, c in zip(pts, classes):
        u, v = s.parameter(vec(p))
        foot = s.value(u, v)
        d = Part.Vertex(foot).distToShape(edges)[0] if edges.Edges else math.inf
        if d > 2 * tol:
            far += 1
            want = core.IN if face.isInside(foot, 1e-7, True) else core.OUT
            test.assertEqual(int(c), want, f"point {tuple(p)} at {d:.4f} mm from the boundary")
        elif d <= 0.9 * tol:
            test.assertEqual(int(c), core.ON, f"point {tuple(p)} at {d:.4f} mm is not ON")
        elif d >= 1.1 * tol:
            test.assertNotEqual(int(c), core.ON, f"point {tuple(p)} at {d:.4f} mm is ON")
    return far


class DocTestCase(DocumentTestCase):
    def assertDocClean(self, names_before):
        self.assertEqual([o.Name for o in self.doc.Objects], names_before,
                         "a failed make left objects behind")
        for o in self.doc.Objects:
            self.assertTrue(o.isValid(), f"{o.Name} is invalid")

    def classify(self, face_ref, points_ref, tol, name="PC", strict=True):
        obj = mfgeom.make_point_classification(self.doc, face_ref, points_ref, tol, name=name,
                                               strict=strict)
        self.assertTrue(obj.isValid(), obj.getStatusString())
        self.assertEqual(obj.CountIn + obj.CountOn + obj.CountOut, len(obj.Classes))
        self.assertEqual(obj.Points.CountPoints, len(obj.Classes))
        self.assertTrue(obj.Shape.isNull(), "the points belong in Points, not in a compound")
        # FreeCAD 0.20's obj.recompute() leaves a new object Touched (blue mark, redone by
        # the next Ctrl+R); the make function must not.
        self.assertNotIn("Touched", obj.State)
        return obj


def points_of(obj):
    """The classified points of a PointClassification, in the order of its Classes."""
    return pointcloud.kernel_to_array(obj.Points)


# ------------------------------------------------------------------ planar faces
class PlanarFaceTests(DocTestCase):
    def setUp(self):
        super().setUp()
        self.part = bracket.make_bracket(self.doc)
        self.top = (self.part, bracket.top_face_name(self.part))

    def test_known_points_on_plate_with_holes(self):
        tol = 0.1
        hx, hy = bracket.HOLES[0]
        z = bracket.PLATE[2] + 0.5  # above the face: projected onto it
        pts = [
            (hx, hy, z),                                  # hole centre: OUT
            (hx + bracket.HOLE_R + 0.05, hy, z),          # 0.05 from the hole: ON
            (hx + bracket.HOLE_R + 0.3, hy, z),           # 0.3 into the material: IN
            (0.0, 30.0, z),                               # on the plate's outer edge: ON
            (-0.2, 30.0, z),                              # outside the plate: OUT
            (93.0, 30.0, z),                              # in the pocket: OUT
            (bracket.POCKET[0] - 0.08, 30.0, z),          # 0.08 from the pocket: ON
            (60.0, 30.0, z),                              # under the boss: OUT
            (100.0, 5.0, z),                              # plain material: IN
        ]
        want = [0, 2, 1, 2, 0, 0, 2, 0, 1]
        cloud = add_cloud(self.doc, "Known", np.array(pts))
        obj = self.classify(self.top, cloud, tol, strict=False)  # 0.5 mm off: projected
        self.assertEqual(list(obj.Classes), want)
        self.assertEqual((obj.CountIn, obj.CountOn, obj.CountOut), (2, 3, 4))
        self.assertEqual(obj.Method, "plane")
        self.assertAlmostEqual(obj.MaxDistanceToSurface.Value, 0.5, places=5)
        # circular holes: libmfgeom's band takes the candidates for the exact edge test
        self.assertAlmostEqual(obj.ParameterTolerance, tol * (1 + face_domain.ON_MARGIN))

    def test_grid_agrees_with_occt(self):
        lx, ly, lz = bracket.PLATE
        pts = np.column_stack([RNG.uniform(-2, lx + 2, 1500), RNG.uniform(-2, ly + 2, 1500),
                               np.full(1500, lz)])
        obj = self.classify(self.top, add_cloud(self.doc, "Grid", pts), 0.2)
        face = self.part.Shape.getElement(self.top[1])
        got = points_of(obj)
        far = occt_compare(self, face, got, obj.Classes, 0.2)
        self.assertGreater(far, 1200)
        self.assertGreater(obj.CountOn, 0)

    def test_placed_rotated_face(self):
        # A box turned 30 deg about X and moved: the plane frame must follow the placement.
        box = self.doc.addObject("Part::Box", "Tilted")
        box.Length, box.Width, box.Height = 20, 10, 5
        box.Placement = App.Placement(App.Vector(100, -50, 7),
                                      App.Rotation(App.Vector(1, 0, 0), 30))
        self.doc.recompute()
        up = box.Placement.Rotation.multVec(App.Vector(0, 0, 1))
        names = [f"Face{i + 1}" for i, f in enumerate(box.Shape.Faces)
                 if f.normalAt(0, 0).isEqual(up, 1e-9)]
        self.assertEqual(len(names), 1)
        local = [(10, 5, 5), (0.02, 5, 5), (-1, 5, 5), (19.5, 9.5, 5)]
        pts = np.array([tuple(box.Placement.multVec(vec(p))) for p in local])
        obj = self.classify((box, names[0]), add_cloud(self.doc, "P", pts), 0.05)
        self.assertEqual(list(obj.Classes), [1, 2, 0, 1])

    def test_zero_tolerance(self):
        # A polygon is its own exact boundary: tolerance 0 works on straight edges only.
        box = self.doc.addObject("Part::Box", "Box")
        self.doc.recompute()
        pts = np.array([(0.0, 5.0, 10.0), (1e-9, 5.0, 10.0), (-1e-9, 5.0, 10.0)])
        obj = self.classify((box, "Face6"), add_cloud(self.doc, "Z", pts), 0.0)
        self.assertEqual(list(obj.Classes), [2, 1, 0])
        # The top face has circular holes: ON cannot be decided at tolerance 0 there.
        names = [o.Name for o in self.doc.Objects]
        with self.assertRaises(ValueError) as ctx:
            mfgeom.make_point_classification(self.doc, self.top, add_cloud(self.doc, "Z2", pts),
                                             0.0)
        self.assertIn("cannot be honoured", str(ctx.exception))
        self.assertEqual([o.Name for o in self.doc.Objects], names + ["Z2"])


# ------------------------------------------------------------------ curved faces
class CurvedFaceTests(DocTestCase):
    def check_face(self, shape, pick, tol, n=700, min_far=300):
        obj_shape = add_shape(self.doc, "Solid", shape)
        names = [f"Face{i + 1}" for i, f in enumerate(shape.Faces) if pick(f)]
        self.assertTrue(names, "no face picked")
        face = obj_shape.Shape.getElement(names[0])
        pts = surface_samples(face, n)
        # Samples beyond a B-spline's natural bounds lie off its surface: compared with
        # OCCT through their projection (strict=False)
        obj = self.classify((obj_shape, names[0]), add_cloud(self.doc, "Cloud", pts), tol,
                            strict=False)
        self.assertEqual(obj.Method, "uv")
        got = points_of(obj)
        far = occt_compare(self, face, got, obj.Classes, tol)
        self.assertGreater(far, min_far)
        return obj

    def test_bracket_boss_cylinder(self):
        part = bracket.make_bracket(self.doc)
        name = bracket.boss_face_name(part)
        face = part.Shape.getElement(name)
        pts = surface_samples(face, 700)
        obj = self.classify((part, name), add_cloud(self.doc, "Cloud", pts), 0.2)
        self.assertGreater(occt_compare(self, face, pts, obj.Classes, 0.2), 300)
        self.assertAlmostEqual(obj.Distortion, 1.0, places=6)  # the cylinder is developable
        self.assertGreater(obj.CountIn, 0)
        self.assertGreater(obj.CountOut, 0)

    def test_full_cylinder_hole_through_seam(self):
        cyl = Part.makeCylinder(10, 30)
        hole = Part.makeCylinder(3, 40, App.Vector(-20, 0, 15), App.Vector(1, 0, 0))
        obj = self.check_face(cyl.cut(hole), lambda f: f.Surface.TypeId == "Part::GeomCylinder"
                              and abs(f.Surface.Radius - 10) < 1e-9, 0.2)
        self.assertGreater(obj.CountOut, 0)

    def test_sphere_with_hole(self):
        shape = Part.makeSphere(10).cut(Part.makeCylinder(3, 40, App.Vector(0, -20, 2),
                                                          App.Vector(0, 1, 0)))
        obj = self.check_face(shape, lambda f: f.Surface.TypeId == "Part::GeomSphere", 0.2)
        self.assertGreater(obj.Distortion, 1.0)

    def test_torus_doubly_periodic(self):
        shape = Part.makeTorus(20, 5).cut(Part.makeCylinder(2, 40, App.Vector(-20, 0, -20)))
        self.check_face(shape, lambda f: f.Surface.TypeId == "Part::GeomToroid", 0.3)

    def test_cone_segment_with_hole(self):
        cone = Part.makeCone(10, 3, 20, App.Vector(), App.Vector(0, 0, 1), 200)
        shape = cone.cut(Part.makeCylinder(2, 40, App.Vector(-20, 0, 10), App.Vector(1, 0, 0)))
        self.check_face(shape, lambda f: f.Surface.TypeId == "Part::GeomCone", 0.25)

    def test_bspline_face_with_hole(self):
        grid = [[App.Vector(i * 10, j * 10, 3 * math.sin(i) * math.cos(j)) for j in range(5)]
                for i in range(5)]
        surf = Part.BSplineSurface()
        surf.interpolate(grid)
        face = Part.Face(surf).cut(Part.makeCylinder(6, 40, App.Vector(20, 20, -20)))
        self.check_face(face, lambda f: True, 0.3, n=300, min_far=150)


# ------------------------------------------------------------------ the exact boundary
def near_boundary_points(face, tol, per_edge=3, edges=None):
    """Points on the face's surface at tol * (1 -/+ 1e-3) from the middle part of each
    real edge, on both sides (stepping along the surface, perpendicular to the edge)."""
    s = face.Surface
    pts = []
    for e in edges if edges is not None else real_edges(face):
        for k in range(per_edge):
            t = e.FirstParameter + (e.LastParameter - e.FirstParameter) * (
                0.2 + 0.6 * (k + 0.5) / per_edge)
            p, tangent = e.valueAt(t), e.tangentAt(t)
            u, v = s.parameter(p)
            side = face.normalAt(u, v).cross(tangent)
            side.normalize()
            for sign in (1.0, -1.0):
                for f in (1.0 - 1e-3, 1.0 + 1e-3):
                    q = p + side * (sign * f * tol)
                    uq, vq = s.parameter(q)
                    pts.append(tuple(s.value(uq, vq)))
    return np.array(pts)


def occt_reference(face, pts, tol):
    """The expected class of points on the surface from OCCT alone: ON if the exact
    distance to the real edges (BRepExtrema) is <= tol, else Face.isInside (BRepClass)."""
    edges = Part.Compound(real_edges(face))
    want, dist = [], []
    for p in pts:
        d = Part.Vertex(vec(p)).distToShape(edges)[0]
        dist.append(d)
        if d <= tol:
            want.append(core.ON)
        else:
            want.append(core.IN if face.isInside(vec(p), 1e-9, True) else core.OUT)
    return np.array(want), np.array(dist)


class ExactBoundaryTests(DocTestCase):
    """ON means "distance to the true boundary <= tol" at every accepted tolerance: points
    at tol * (1 -/+ 1e-3) from curved edges against OCCT's exact distance."""

    def check_near(self, face, tols=(1e-3, 1e-5), edges=None):
        for tol in tols:
            pts = near_boundary_points(face, tol, edges=edges)
            want, dist = occt_reference(face, pts, tol)
            # The construction is what it claims: every point is 1e-3 * tol off the band's
            # edge, on the side it was meant to be (else the test would prove nothing).
            intended = np.tile([1.0 - 1e-3, 1.0 + 1e-3], len(pts) // 2) * tol
            self.assertLess(float(np.max(np.abs(dist - intended))), 2e-4 * tol)
            got = face_domain.classify_points_on_face(face, pts, tol, strict=True).classes
            bad = np.nonzero(got != want)[0]
            self.assertEqual(len(bad), 0, f"tol {tol}: {len(bad)} of {len(pts)} wrong, e.g. "
                             f"{[(int(got[i]), int(want[i]), dist[i] / tol) for i in bad[:4]]}")
            self.assertGreater(int(np.count_nonzero(want == core.ON)), 0)
            self.assertGreater(int(np.count_nonzero(want != core.ON)), 0)

    def test_points_on_a_cylinder_circle_are_on(self):
        # The case: points from edge.valueAt on the bottom circle of a cylinder
        # R = 5 were OUT at small tolerances (32 of 50 at 1e-5, all at 1e-8).
        cyl = add_shape(self.doc, "Cyl", Part.makeCylinder(5, 10))
        names = {f.Surface.TypeId: f"Face{i + 1}" for i, f in enumerate(cyl.Shape.Faces)}
        lateral = names["Part::GeomCylinder"]
        circle = [e for e in cyl.Shape.getElement(lateral).Edges
                  if e.Curve.TypeId == "Part::GeomCircle" and abs(e.BoundBox.ZMax) < 1e-9][0]
        pts = np.array([tuple(circle.valueAt(circle.FirstParameter + k * (
            circle.LastParameter - circle.FirstParameter) / 50)) for k in range(50)])
        # Vertices, not a Points object: Points stores floats, 2e-7 mm off at R = 5
        cloud = add_shape(self.doc, "OnCircle", Part.Compound([Part.Vertex(*p) for p in pts]))
        bottom = [f"Face{i + 1}" for i, f in enumerate(cyl.Shape.Faces)
                  if f.Surface.TypeId == "Part::GeomPlane" and abs(f.BoundBox.ZMax) < 1e-9][0]
        for face_name in (lateral, bottom):  # curved face; planar face with a curved edge
            for tol in (1e-3, 1e-5, 1e-7):
                obj = self.classify((cyl, face_name), cloud, tol, name="C")
                self.assertEqual(obj.CountOn, 50, f"{face_name} tol {tol}")
                self.doc.removeObject(obj.Name)
        names = [o.Name for o in self.doc.Objects]
        with self.assertRaises(ValueError) as ctx:  # below OCCT's Precision::Confusion
            mfgeom.make_point_classification(self.doc, (cyl, lateral), cloud, 1e-8)
        self.assertIn("cannot be honoured", str(ctx.exception))
        self.assertEqual([o.Name for o in self.doc.Objects], names)

    def test_cylinder(self):
        shape = Part.makeCylinder(5, 10, App.Vector(), App.Vector(0, 0, 1), 250)
        self.check_near([f for f in shape.Faces if f.Surface.TypeId == "Part::GeomCylinder"][0])

    def test_cone(self):
        shape = Part.makeCone(10, 3, 20, App.Vector(), App.Vector(0, 0, 1), 200)
        self.check_near([f for f in shape.Faces if f.Surface.TypeId == "Part::GeomCone"][0])

    def test_sphere_cap(self):
        shape = Part.makeSphere(10).cut(Part.makeBox(30, 30, 30, App.Vector(-15, -15, 6)))
        self.check_near([f for f in shape.Faces if f.Surface.TypeId == "Part::GeomSphere"][0])

    def test_torus(self):
        shape = Part.makeTorus(20, 5).cut(Part.makeBox(60, 60, 30, App.Vector(-30, -30, 2)))
        self.check_near([f for f in shape.Faces if f.Surface.TypeId == "Part::GeomToroid"][0])

    def test_bspline_face(self):
        grid = [[App.Vector(i * 10, j * 10, 3 * math.sin(i) * math.cos(j)) for j in range(5)]
                for i in range(5)]
        surf = Part.BSplineSurface()
        surf.interpolate(grid)
        face = Part.Face(surf).cut(Part.makeCylinder(6, 40, App.Vector(20, 20, -20))).Faces[0]
        # The hole's edges are intersection curves, known to their tolerance (5e-6 mm):
        least = face_domain.minimum_tolerance(face)
        self.assertEqual(least, max(e.Tolerance for e in face.Edges))
        with self.assertRaises(ValueError):
            face_domain.FaceDomain(face, 0.5 * least)
        # Outside the outer edges there is no surface: test the hole's edges.
        hole = [e for e in real_edges(face) if e.Tolerance > 1e-7]
        self.check_near(face, tols=(1e-3, 1e-4), edges=hole)

    def test_planar_face_with_bspline_edges(self):
        # A B-spline side and an elliptic hole (a B-spline after the cut, known to 5e-6 mm)
        spline = Part.BSplineCurve()
        spline.interpolate([App.Vector(0, 0, 0), App.Vector(10, 6, 0), App.Vector(20, -3, 0),
                            App.Vector(30, 4, 0), App.Vector(40, 0, 0)])
        corners = [App.Vector(40, 0, 0), App.Vector(40, 20, 0), App.Vector(0, 20, 0),
                   App.Vector(0, 0, 0)]
        face = Part.Face(Part.Wire([spline.toShape()] + [
            Part.LineSegment(a, b).toShape() for a, b in zip(corners, corners[1:])]))
        self.check_near(face, tols=(1e-3, 1e-5, 1e-7))
        hole = Part.Face(Part.Wire([Part.Ellipse(App.Vector(20, 12, 0), 6, 3).toShape()]))
        face = face.cut(hole.extrude(App.Vector(0, 0, 1)).translated(App.Vector(0, 0, -0.5)))
        self.check_near(face.Faces[0], tols=(1e-3, 1e-5))

    def test_planar_face_with_a_circular_hole(self):
        shape = Part.makeBox(20, 20, 5).cut(Part.makeCylinder(4, 10, App.Vector(10, 10, -1)))
        top = [f for f in shape.Faces
               if f.Surface.TypeId == "Part::GeomPlane" and abs(f.BoundBox.ZMin - 5) < 1e-9][0]
        self.check_near(top, tols=(1e-3, 1e-5, 1e-7))
        self.assertEqual(face_domain.minimum_tolerance(Part.makeBox(1, 1, 1).Faces[0]), 0.0)


# ------------------------------------------------------------------ far points, strict, units
class SurfaceDistanceTests(DocTestCase):
    def setUp(self):
        super().setUp()
        self.cyl = add_shape(self.doc, "Cyl", Part.makeCylinder(10, 30))
        self.lateral = [f"Face{i + 1}" for i, f in enumerate(self.cyl.Shape.Faces)
                        if f.Surface.TypeId == "Part::GeomCylinder"][0]
        # The cloud: 25 mm outside the cylinder's surface, over its height
        a = np.radians(np.arange(0.0, 360.0, 10.0))
        z = np.arange(1.0, 30.0, 10.0)
        ga, gz = np.meshgrid(a, z)
        self.far = np.column_stack([35 * np.cos(ga.ravel()), 35 * np.sin(ga.ravel()), gz.ravel()])
        self.cloud = add_cloud(self.doc, "Far", self.far)

    def test_far_points_projected_unless_strict(self):
        loose = self.classify((self.cyl, self.lateral), self.cloud, 0.01, name="Loose",
                              strict=False)
        self.assertEqual(loose.CountIn, len(self.far))  # by projection: all on the surface
        self.assertAlmostEqual(loose.MaxDistanceToSurface.Value, 25.0, places=5)  # floats
        strict = self.classify((self.cyl, self.lateral), self.cloud, 0.01, name="Strict")
        self.assertTrue(strict.Strict)
        self.assertEqual(strict.CountOut, len(self.far))
        # Near points are unaffected by Strict: 0.005 mm off the surface, tol 0.01
        near = add_cloud(self.doc, "Near", np.array([(10.005, 0.0, 15.0), (9.995, 0.0, 0.004)]))
        obj = self.classify((self.cyl, self.lateral), near, 0.01, name="N")
        self.assertEqual(list(obj.Classes), [core.IN, core.ON])

    def test_strict_at_zero_tolerance_on_a_tilted_plane(self):
        # Points on a tilted plane are 1e-14 mm off it after rounding: not OUT at tol 0
        # (Strict counts from Precision::Confusion, 1e-7 mm, at least).
        box = Part.makeBox(20, 10, 5)
        box.Placement = App.Placement(App.Vector(100, -50, 7),
                                      App.Rotation(App.Vector(1, 0.3, 0), 33))
        up = box.Placement.Rotation.multVec(App.Vector(0, 0, 1))
        top = [f for f in box.Faces if f.normalAt(0, 0).isEqual(up, 1e-9)][0]
        local = np.column_stack([RNG.uniform(1, 19, 200), RNG.uniform(1, 9, 200),
                                 np.full(200, 5.0)])
        pts = np.array([tuple(box.Placement.multVec(vec(p))) for p in local])
        res = face_domain.classify_points_on_face(top, pts, 0.0, strict=True)
        self.assertGreater(res.max_distance_to_surface, 0.0)  # the rounding is there
        self.assertEqual(res.counts, {"in": 200, "on": 0, "out": 0})
        self.assertEqual(res.far_count, 0)

    def test_report_of_far_points(self):
        face = self.cyl.Shape.getElement(self.lateral)
        res = face_domain.classify_points_on_face(face, self.far, 0.01)
        self.assertEqual(res.far_count, len(self.far))
        warn, text = res.surface_report()
        self.assertTrue(warn)
        self.assertIn(f"{len(self.far)} points farther than the tolerance (0.01 mm)", text)
        self.assertIn("largest distance 25 mm", text)
        res = face_domain.classify_points_on_face(face, self.far, 0.01, strict=True)
        self.assertFalse(res.surface_report()[0])
        self.assertTrue(np.all(res.classes == core.OUT))

    def test_label_names_what_is_classified(self):
        obj = self.classify((self.cyl, self.lateral), self.cloud, 0.01)
        self.assertEqual(obj.Label, f"Classes of {self.lateral} of Cyl")

    def test_tolerance_units(self):
        Q = App.Units.Quantity
        for tol, mm in ((Q("10 um"), 0.01), ("0.02 mm", 0.02), (Q(0.03, App.Units.Length), 0.03),
                        ("0.04", 0.04), (Q("0.001 in"), 0.0254), (0.05, 0.05)):
            obj = self.classify((self.cyl, self.lateral), self.cloud, tol, name="U")
            self.assertAlmostEqual(obj.Tolerance.Value, mm, places=12, msg=repr(tol))
            self.doc.removeObject(obj.Name)
        names = [o.Name for o in self.doc.Objects]
        for bad in (Q("5 deg"), "5 deg", "2 kg", "abc", True):
            with self.assertRaises(ValueError, msg=repr(bad)) as ctx:
                mfgeom.make_point_classification(self.doc, (self.cyl, self.lateral),
                                                 self.cloud, bad)
            self.assertIn("tolerance", str(ctx.exception))
            self.assertEqual([o.Name for o in self.doc.Objects], names)

    def test_documents_before_strict_keep_projecting(self):
        obj = self.classify((self.cyl, self.lateral), self.cloud, 0.01, name="Old")
        obj.removeProperty("Strict")
        obj.Version = 1
        obj.touch()
        self.doc.recompute()
        self.assertEqual(obj.Version, VERSION)
        self.assertFalse(obj.Strict)
        self.assertEqual(obj.CountIn, len(self.far))


# ------------------------------------------------------------------ parametric behaviour
class ParametricTests(DocTestCase):
    def setUp(self):
        super().setUp()
        self.part = bracket.make_bracket(self.doc)
        self.top = (self.part, bracket.top_face_name(self.part))
        lx, ly, lz = bracket.PLATE
        gx, gy = np.meshgrid(np.arange(0.25, lx, 1.0), np.arange(0.25, ly, 1.0))
        self.pts = np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, lz)])
        self.cloud = add_cloud(self.doc, "Cloud", self.pts)
        self.obj = self.classify(self.top, self.cloud, 0.1)

    def test_tolerance_change_recomputes(self):
        before = (self.obj.CountIn, self.obj.CountOn, self.obj.CountOut)
        self.obj.Tolerance = 0.6
        self.doc.recompute()
        self.assertTrue(self.obj.isValid())
        self.assertGreater(self.obj.CountOn, before[1])
        self.assertLess(self.obj.CountIn, before[0])

    def test_moving_points_recomputes(self):
        out_before = self.obj.CountOut
        self.cloud.Placement = App.Placement(App.Vector(60, 0, 0), App.Rotation())
        self.doc.recompute()
        self.assertTrue(self.obj.isValid())
        self.assertGreater(self.obj.CountOut, out_before)  # half the cloud is off the plate
        self.assertAlmostEqual(points_of(self.obj)[:, 0].min(), 60.25, places=4)

    def test_changing_the_part_recomputes(self):
        hole = self.doc.getObject("Hole1")
        out_before = self.obj.CountOut
        hole.Radius = 6.0
        self.doc.recompute()
        self.assertTrue(self.obj.isValid(), self.obj.getStatusString())
        self.assertGreater(self.obj.CountOut, out_before)

    def test_save_and_reload(self):
        classes = list(self.obj.Classes)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "saved.FCStd")
            self.doc.saveAs(path)
            name = self.doc.Name
            App.closeDocument(name)
            self.doc = App.openDocument(path)
            obj = self.doc.getObject("PC")
            self.assertEqual(type(obj.Proxy).__module__, "mfgeom.app.pointclass")
            self.assertEqual(list(obj.Classes), classes)
            self.assertEqual(obj.Version, VERSION)
            obj.touch()
            self.doc.recompute()
            self.assertTrue(obj.isValid())
            self.assertEqual(list(obj.Classes), classes)
            obj.Tolerance = 0.5  # still parametric after the reload
            self.doc.recompute()
            self.assertNotEqual(list(obj.Classes), classes)

    def test_document_of_version_0_1_opens(self):
        # mfgeom 0.1 saved its proxies as mfgeom.pointclass_feature.*: such files must
        # still open, recompute and keep their results after the package was layered.
        import zipfile
        classes = list(self.obj.Classes)
        with tempfile.TemporaryDirectory() as tmp:
            new, old = os.path.join(tmp, "new.FCStd"), os.path.join(tmp, "old.FCStd")
            self.doc.saveAs(new)
            with zipfile.ZipFile(new) as zin, zipfile.ZipFile(old, "w") as zout:
                for item in zin.infolist():
                    data = zin.read(item.filename)
                    if item.filename == "Document.xml":
                        self.assertIn(b'module="mfgeom.app.pointclass"', data)
                        data = data.replace(b'module="mfgeom.app.pointclass"',
                                            b'module="mfgeom.pointclass_feature"')
                    zout.writestr(item, data)
            App.closeDocument(self.doc.Name)
            self.doc = App.openDocument(old)
            obj = self.doc.getObject("PC")
            self.assertEqual(type(obj.Proxy).__name__, "PointClassification")
            obj.touch()
            self.doc.recompute()
            self.assertTrue(obj.isValid(), obj.getStatusString())
            self.assertEqual(list(obj.Classes), classes)

    def test_old_version_migrates(self):
        self.obj.Version = 0
        self.obj.touch()
        self.doc.recompute()
        self.assertEqual(self.obj.Version, VERSION)
        self.assertTrue(self.obj.isValid())

    def test_document_with_compound_points_migrates(self):
        # Up to version 2 the points were a Part compound of one vertex each in Shape, with
        # no Points property: such a file must open with its points moved into Points
        # (shown before any recompute) and recompute into the new representation.
        classes = list(self.obj.Classes)
        self.obj.removeProperty("Points")
        self.obj.Shape = Part.makeCompound([Part.Vertex(*p) for p in self.pts.tolist()])
        self.obj.Version = 2
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "v2.FCStd")
            self.doc.saveAs(path)
            App.closeDocument(self.doc.Name)
            self.doc = App.openDocument(path)
            obj = self.doc.getObject("PC")
            self.assertEqual(obj.Version, VERSION)
            self.assertTrue(obj.Shape.isNull())
            self.assertEqual(list(obj.Classes), classes)
            np.testing.assert_allclose(points_of(obj), self.pts, rtol=0, atol=1e-5)
            obj.touch()
            self.doc.recompute()
            self.assertTrue(obj.isValid(), obj.getStatusString())
            self.assertEqual(list(obj.Classes), classes)
            self.assertEqual(obj.Points.CountPoints, len(self.pts))
            self.assertTrue(obj.Shape.isNull())

    def test_file_size_is_a_few_bytes_per_point(self):
        # Points are stored as binary float32 (12 bytes) and classes as a compressed list;
        # the compound of vertices this replaced took 24 bytes per point.
        n = 100_000
        lx, ly, lz = bracket.PLATE
        cloud = add_cloud(self.doc, "Big", np.column_stack([
            RNG.uniform(0, lx, n), RNG.uniform(0, ly, n), np.full(n, lz)]))
        with tempfile.TemporaryDirectory() as tmp:
            before, after = os.path.join(tmp, "a.FCStd"), os.path.join(tmp, "b.FCStd")
            self.doc.saveAs(before)
            obj = self.classify(self.top, cloud, 0.1, name="Big")
            self.doc.saveAs(after)
            per_point = (os.path.getsize(after) - os.path.getsize(before)) / n
        self.assertEqual(obj.Points.CountPoints, n)
        self.assertLess(per_point, 14.0)

    def test_recompute_error_is_one_clear_line(self):
        # A broken face link: the object is invalid, the rest of the document valid, and
        # the Report view says once what is wrong, naming the object once (FreeCAD always
        # adds the traceback of execute() itself: one frame, not the ten of the inner
        # calls).  FreeCAD 0.20 prints only the traceback, whose last line is our
        # "<Label>: <message>"; 1.0 adds its own "<Label>: <message>" line, so our
        # message (the traceback's last line) must not carry the label again.
        script = os.path.join(tempfile.mkdtemp(), "broken_link.py")
        with open(script, "w", encoding="utf-8") as f:
            f.write(BROKEN_LINK_SCRIPT.format(workbench=os.path.join(REPO, "workbench")))
        run = subprocess.run(["freecadcmd", script], stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True, timeout=120)
        out = run.stdout
        self.assertIn("=== end", out, out[-2000:])
        report = out[out.index("=== begin"):out.index("=== end")]
        said = [line for line in report.splitlines() if "has no Face9" in line]
        from mfgeom import compat
        self.assertEqual(len(said), 2 if compat.freecad_names_failed_objects() else 1, report)
        labelled = [line for line in said if "Classes of Face6 of Box" in line]
        self.assertEqual(len(labelled), 1, report)
        self.assertIn("Classes of Face6 of Box: 'Box' has no Face9 (it has 6 faces)",
                      labelled[0])
        self.assertEqual(report.count("Classes of Face6 of Box"), 1, report)
        frames = [line for line in report.splitlines() if line.strip().startswith("File ")]
        self.assertEqual(len(frames), 1, report)
        self.assertIn("feature_base.py", frames[0])  # the shared execute()
        self.assertIn("=== end valid=False others=[True, True, True]", out)


BROKEN_LINK_SCRIPT = """
import sys
sys.path.append({workbench!r})
import FreeCAD as App
import Points
import mfgeom
doc = App.newDocument("broken")
box = doc.addObject("Part::Box", "Box")
other = doc.addObject("Part::Cylinder", "Other")
doc.recompute()
cloud = doc.addObject("Points::Feature", "Cloud")
cloud.Points = Points.Points([(1.0, 1.0, 10.0), (5.0, 5.0, 10.0)])
obj = mfgeom.make_point_classification(doc, (box, "Face6"), cloud, 0.01)
from mfgeom import compat
App.Console.PrintMessage("=== begin\\n")
compat.flush_output()  # FreeCAD 1.0 buffers stdout in a pipe, not stderr: keep the order
obj.Face = (box, ["Face9"])
doc.recompute()
compat.flush_output()
others = [o.isValid() for o in doc.Objects if o is not obj]
App.Console.PrintMessage(f"=== end valid={{obj.isValid()}} others={{others}}\\n")
"""


# ------------------------------------------------------------------ point I/O
class PointCloudTests(DocTestCase):
    def test_kernel_round_trip_far_from_the_origin(self):
        # Stored as float32 relative to the bounding box's centre: a 10 mm cloud 1 km away
        # keeps ~1e-6 mm, not the ~6e-5 mm of float32 coordinates at 1000 mm.
        pts = RNG.uniform(-5, 5, (2000, 3)) + np.array([1000.0, -2000.0, 500.0])
        back = pointcloud.kernel_to_array(pointcloud.array_to_kernel(pts))
        self.assertEqual(back.shape, pts.shape)
        self.assertLess(np.abs(back - pts).max(), 2e-6)
        # ... also through a saved document (which keeps 6 digits of the kernel's matrix)
        holder = self.doc.addObject("App::FeaturePython", "Holder")
        holder.addProperty("Points::PropertyPointKernel", "Points")
        holder.Points = pointcloud.array_to_kernel(pts)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "far.FCStd")
            self.doc.saveAs(path)
            App.closeDocument(self.doc.Name)
            self.doc = App.openDocument(path)
            back = pointcloud.kernel_to_array(self.doc.getObject("Holder").Points)
        self.assertLess(np.abs(back - pts).max(), 2e-6)
        self.assertEqual(pointcloud.kernel_to_array(pointcloud.array_to_kernel(
            np.zeros((0, 3)))).shape, (0, 3))

    def test_placed_sources_match_freecad_per_point_api(self):
        # The numpy readers against FreeCAD's own per-point accessors, placements applied.
        import Mesh
        place = App.Placement(App.Vector(3, -7, 11), App.Rotation(App.Vector(1, 2, 3), 37))
        cloud = add_cloud(self.doc, "C", RNG.uniform(-50, 50, (500, 3)))
        cloud.Placement = place
        mesh = self.doc.addObject("Mesh::Feature", "M")
        mesh.Mesh = Mesh.createSphere(5, 20)
        mesh.Placement = place
        box = self.doc.addObject("Part::Box", "B")
        box.Placement = place
        self.doc.recompute()
        want = {
            "C": [tuple(v) for v in cloud.Points.Points],
            "M": [(p.x, p.y, p.z) for p in mesh.Mesh.Points],
            "B": [tuple(v.Point) for v in box.Shape.Vertexes],
        }
        for obj in (cloud, mesh, box):
            got = refs.resolve_points(obj, [])
            np.testing.assert_allclose(got, np.array(want[obj.Name]), rtol=0, atol=1e-9,
                                       err_msg=obj.Name)
        got = refs.resolve_points(box, ["Vertex3", "Vertex1"])
        np.testing.assert_allclose(got, np.array([want["B"][2], want["B"][0]]), atol=1e-12)
        # A mesh is read through binary PLY (not the per-point fallback) ...
        fallback = pointcloud.vectors_to_array
        pointcloud.vectors_to_array = None
        try:
            np.testing.assert_allclose(pointcloud.mesh_points(mesh.Mesh), np.array(want["M"]),
                                       rtol=0, atol=1e-9)
        finally:
            pointcloud.vectors_to_array = fallback
        # ... and anything unexpected in the file falls back.
        self.assertIsNone(pointcloud._ply_vertices(b"ply\nformat ascii 1.0\nend_header\n"))
        self.assertIsNone(pointcloud._ply_vertices(
            b"ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\n"
            b"property double y\nproperty double z\nend_header\n" + bytes(48)))

    def test_a_classification_is_a_point_source(self):
        box = self.doc.addObject("Part::Box", "Box")
        self.doc.recompute()
        cloud = add_cloud(self.doc, "C", np.array([(1.0, 1.0, 10.0), (-1.0, 1.0, 10.0)]))
        first = self.classify((box, "Face6"), cloud, 0.01, name="First")
        second = self.classify((box, "Face6"), first, 0.01, name="Second")
        self.assertEqual(list(second.Classes), [1, 0])


# ------------------------------------------------------------------ palette
class PaletteTests(unittest.TestCase):
    """The result colours stay apart from each other and from FreeCAD's selection and
    pre-selection colours, also under protanopia and deuteranopia (CIELAB distance after
    simulation; ~2.3 is just noticeable)."""

    def min_contrast(self, colours, others=None):
        import itertools
        pairs = (itertools.combinations(colours, 2) if others is None
                 else [(a, b) for a in colours for b in others])
        return min(palette.contrast(a, b, v) for v in palette.VISIONS for a, b in pairs)

    def test_simulation_reference_values(self):
        # Pure red and green look alike to a deuteranope, unlike blue and yellow.
        red, green = (1.0, 0.0, 0.0), (0.0, 0.6, 0.0)
        self.assertGreater(palette.contrast(red, green), 80)
        self.assertLess(palette.contrast(red, green, "deuteranopia"), 25)
        self.assertAlmostEqual(palette.contrast((1, 1, 1), (0, 0, 0)), 100.0, places=3)

    def test_classes(self):
        classes = [palette.CLASS_COLORS[c] for c in (names.IN, names.ON, names.OUT)]
        self.assertGreater(self.min_contrast(classes), 30)
        self.assertGreater(self.min_contrast(classes, [palette.SELECTION,
                                                       palette.PRESELECTION]), 40)

    def test_parting_and_setups(self):
        sides = [palette.CORE_SIDE, palette.CAVITY_SIDE, palette.UNDERCUT]
        fc = [palette.SELECTION, palette.PRESELECTION]
        self.assertGreater(self.min_contrast(sides), 30)
        self.assertGreater(self.min_contrast(sides, fc), 25)
        self.assertGreater(self.min_contrast(palette.SETUP_COLORS), 15)
        self.assertGreater(self.min_contrast(palette.SETUP_COLORS, fc), 20)
        self.assertEqual(palette.setup_color(1), palette.setup_color(1 + len(palette.SETUP_COLORS)))

    def test_mould(self):
        # the parting line is read against both sides (it runs where they meet) and
        # against the selection colours
        sides = [palette.MOULD_CORE, palette.MOULD_CAVITY]
        fc = [palette.SELECTION, palette.PRESELECTION]
        self.assertGreater(self.min_contrast([palette.PARTING_LINE], sides), 40)
        self.assertGreater(self.min_contrast([palette.PARTING_LINE], fc + [palette.SHAPE_GREY]), 40)


# ------------------------------------------------------------------ point sources
class PointSourceTests(DocTestCase):
    def setUp(self):
        super().setUp()
        box = self.doc.addObject("Part::Box", "Box")
        box.Length, box.Width, box.Height = 20, 10, 5
        self.box = box
        self.doc.recompute()
        self.top = (box, "Face6")  # Part::Box: Face6 is the top (z = Height)

    # These tests are about reading points, so points off the face are projected onto it
    # (strict=False).
    def test_vertices_of_a_shape(self):
        obj = self.classify(self.top, (self.box, ["Vertex2", "Vertex1"]), 0.01, strict=False)
        # Vertex1 (0,0,0) and Vertex2 (0,0,5) project to the top face's corner: ON
        self.assertEqual(list(obj.Classes), [2, 2])

    def test_whole_part_object(self):
        obj = self.classify(self.top, self.box, 0.01, strict=False)
        self.assertEqual(len(obj.Classes), 8)
        self.assertEqual(obj.CountOn, 8)

    def test_sketch_vertices(self):
        sk = self.doc.addObject("Sketcher::SketchObject", "Sketch")
        sk.Placement = App.Placement(App.Vector(0, 0, 5), App.Rotation())
        sk.addGeometry(Part.LineSegment(App.Vector(5, 5, 0), App.Vector(30, 5, 0)))
        sk.addGeometry(Part.LineSegment(App.Vector(30, 5, 0), App.Vector(20, 10.005, 0)))
        self.doc.recompute()
        obj = self.classify(self.top, sk, 0.01)
        self.assertEqual(sorted(obj.Classes), [0, 1, 2])

    def test_mesh_points(self):
        import Mesh
        mesh = self.doc.addObject("Mesh::Feature", "Mesh")
        m = Mesh.Mesh()
        m.addFacet(App.Vector(5, 5, 1), App.Vector(25, 5, 1), App.Vector(10, 10.001, 1))
        mesh.Mesh = m
        self.doc.recompute()
        obj = self.classify(self.top, mesh, 0.01, strict=False)
        self.assertEqual(list(obj.Classes), [1, 0, 2])

    def test_points_in_other_types(self):
        pts = np.array([(10.0, 5.0, 5.0)])
        obj = self.classify(self.top, add_cloud(self.doc, "One", pts), 0.01)
        self.assertEqual(list(obj.Classes), [1])


# ------------------------------------------------------------------ bad input
class BadInputTests(DocTestCase):
    def setUp(self):
        super().setUp()
        self.box = self.doc.addObject("Part::Box", "Box")
        self.doc.recompute()
        self.cloud = add_cloud(self.doc, "Cloud", np.array([(5.0, 5.0, 10.0)]))
        self.doc.recompute()
        self.names = [o.Name for o in self.doc.Objects]

    def assertRejected(self, face_ref, points_ref, tol=0.01, match=None):
        with self.assertRaises((ValueError, TypeError)) as ctx:
            mfgeom.make_point_classification(self.doc, face_ref, points_ref, tol)
        if match:
            self.assertIn(match, str(ctx.exception))
        self.assertDocClean(self.names)

    def test_edge_instead_of_face(self):
        self.assertRejected((self.box, "Edge1"), self.cloud, match="not a face")

    def test_missing_face(self):
        self.assertRejected((self.box, "Face42"), self.cloud, match="no Face42")

    def test_face_not_a_tuple(self):
        self.assertRejected(self.box, self.cloud, match="(object, \"FaceN\")")

    def test_points_from_an_edge(self):
        self.assertRejected((self.box, "Face6"), (self.box, ["Edge1"]), match="not a vertex")

    def test_empty_cloud(self):
        empty = self.doc.addObject("Points::Feature", "Empty")
        self.names.append("Empty")
        self.assertRejected((self.box, "Face6"), empty, match="no points")

    def test_not_a_point_source(self):
        group = self.doc.addObject("App::DocumentObjectGroup", "Group")
        self.names.append("Group")
        self.assertRejected((self.box, "Face6"), group, match="not a point source")

    def test_bad_tolerances(self):
        for tol in (-0.1, float("nan"), float("inf"), "abc"):
            self.assertRejected((self.box, "Face6"), self.cloud, tol=tol, match="tolerance")

    def test_object_from_another_document(self):
        other = App.newDocument("mfgeom_other")
        try:
            cloud = add_cloud(other, "Cloud", np.array([(1.0, 1.0, 1.0)]))
            self.assertRejected((self.box, "Face6"), cloud, match="document")
        finally:
            App.closeDocument(other.Name)

    def test_selection_rules(self):
        box, cloud = self.box, self.cloud
        ok = refs.refs_from_selection([(box, ["Face6"]), (cloud, [])])
        self.assertEqual(ok, ((box, "Face6"), (cloud, [])))
        ok = refs.refs_from_selection([(box, ["Face6", "Vertex1", "Vertex3"])])
        self.assertEqual(ok, ((box, "Face6"), (box, ["Vertex1", "Vertex3"])))
        bad = [
            ([(cloud, [])], "exactly one face"),
            ([(box, ["Face6"])], "points to classify"),
            ([(box, ["Face1", "Face2"]), (cloud, [])], "exactly one face"),
            ([(box, ["Face6", "Edge2"])], "cannot be used"),
            ([(box, ["Face6", "Vertex1"]), (cloud, [])], "one object only"),
        ]
        for selection, message in bad:
            with self.assertRaises(refs.InputError) as ctx:
                refs.refs_from_selection(selection)
            self.assertIn(message, str(ctx.exception))
        self.assertDocClean(self.names)


# ------------------------------------------------------------------ packaging
class PackagingTests(unittest.TestCase):
    def test_package_xml(self):
        meta = App.Metadata(os.path.join(REPO, "package.xml"))
        self.assertEqual(meta.Name, "Manufacturing Geometry")   # the id is the folder
        urls = {u["type"]: u["location"] for u in meta.Urls}
        self.assertEqual(set(urls), {"repository", "readme", "bugtracker", "documentation"})
        self.assertIn("numpy", [d["package"] for d in meta.Depend])
        self.assertEqual(meta.Version, "0.1.0")
        self.assertTrue(meta.supportsCurrentFreeCAD())
        self.assertTrue(os.path.isfile(os.path.join(REPO, meta.Icon)))
        wb = meta.Content["workbench"][0]
        self.assertEqual(wb.Classname, "MfgeomWorkbench")
        sub = os.path.join(REPO, wb.Subdirectory)
        self.assertTrue(os.path.isfile(os.path.join(sub, "InitGui.py")))
        # FreeCAD 0.20 resolves a content item's icon relative to its subdirectory
        self.assertTrue(os.path.isfile(os.path.normpath(os.path.join(sub, wb.Icon))))
        with open(os.path.join(sub, "InitGui.py"), encoding="utf-8") as f:
            self.assertIn(f"class {wb.Classname}(", f.read())
        # supported from 0.20 on, with no upper bound (a freecadmax would hide the add-on
        # from every newer FreeCAD); the description and tags name every feature
        self.assertEqual(meta.FreeCADMin, "0.20.0")
        self.assertIn(meta.FreeCADMax, ("0.0.0", ""))   # none: 0.20 says 0.0.0, 1.0 ""
        for word in ("point classification", "parting", "NC", "draft", "ray check",
                     "rotational sweep", "clearance", "medial surface", "mid-surface",
                     "medial axis"):
            self.assertIn(word.lower(), meta.Description.lower(), word)
        for tag in ("point classification", "parting", "rotational sweep", "medial surface",
                    "medial axis"):
            self.assertIn(tag, meta.Tag)

    def test_package_xml_as_the_addon_manager_reads_it(self):
        # FreeCAD 1.0's Addon Manager has its own reader (Mod/AddonManager, on the path in
        # freecadcmd); 0.20's has none (its App.Metadata is checked above).
        try:
            import addonmanager_metadata as am
            from Addon import Addon
        except ImportError as exc:
            self.skipTest(f"no Addon Manager metadata reader in this FreeCAD: {exc}")
        meta = am.MetadataReader.from_file(os.path.join(REPO, "package.xml"))
        self.assertEqual(meta.name, "Manufacturing Geometry")
        self.assertEqual(meta.freecadmin.version_as_list[:3], [0, 20, 0])
        self.assertIsNone(meta.freecadmax)
        self.assertEqual(meta.pythonmin.version_as_list[:2], [3, 8])
        self.assertTrue(Addon.version_is_ok(meta))
        self.assertLessEqual(tuple(meta.pythonmin.version_as_list[:2]), sys.version_info[:2])
        self.assertIn("numpy", [d.package for d in meta.depend])
        self.assertTrue(os.path.isfile(os.path.join(REPO, meta.icon)))
        wb = meta.content["workbench"][0]
        self.assertEqual((wb.classname, wb.subdirectory), ("MfgeomWorkbench", "workbench"))
        self.assertTrue(Addon.version_is_ok(wb))

    def test_icons_and_resources_exist(self):
        from mfgeom import paths
        for name in ("mfgeom_workbench.svg", "mfgeom_classify_points.svg",
                     "preferences-manufacturing_geometry.svg"):
            self.assertTrue(os.path.isfile(paths.icon(name)), name)
        self.assertTrue(os.path.isfile(paths.resource("preferences.ui")))

    def test_every_icon_is_a_drawable_svg(self):
        """Every file in icons/ parses as SVG with a positive size and draws something.
        (That each is used, by a registered command, the workbench or the preferences
        page, and loads in Qt is checked by tests/gui/test_gui.py: commands need the GUI.)"""
        import xml.etree.ElementTree as ET
        from mfgeom import paths
        names = sorted(os.listdir(paths.icons_dir()))
        self.assertTrue(names)
        svg = "{http://www.w3.org/2000/svg}"
        drawing = {svg + t for t in ("path", "rect", "circle", "ellipse", "polygon",
                                     "polyline", "line", "text", "use")}
        for name in names:
            with self.subTest(icon=name):
                self.assertTrue(name.endswith(".svg"), name)
                root = ET.parse(paths.icon(name)).getroot()
                self.assertEqual(root.tag, svg + "svg")
                if root.get("viewBox"):
                    box = [float(x) for x in root.get("viewBox").replace(",", " ").split()]
                    self.assertEqual(len(box), 4)
                    self.assertTrue(box[2] > 0 and box[3] > 0, box)
                else:
                    self.assertGreater(float(root.get("width", "0").rstrip("px")), 0)
                    self.assertGreater(float(root.get("height", "0").rstrip("px")), 0)
                self.assertTrue(any(e.tag in drawing for e in root.iter()), name)

    def test_package_imports_without_freecad(self):
        code = ("import sys; import mfgeom, mfgeom.core as c; "
                "assert 'FreeCAD' not in sys.modules, 'mfgeom imported FreeCAD'; "
                "assert callable(mfgeom.make_point_classification); print(c.version())")
        env = dict(os.environ, PYTHONPATH=os.path.join(REPO, "workbench"))
        run = subprocess.run(["/usr/bin/python3", "-c", code], env=env, capture_output=True,
                             text=True, timeout=60)
        self.assertEqual(run.returncode, 0, run.stderr)

    def test_face_domain_rejects_non_faces(self):
        with self.assertRaises(TypeError):
            face_domain.FaceDomain(Part.makeBox(1, 1, 1), 0.1)
        with self.assertRaises(ValueError):
            face_domain.FaceDomain(Part.makeBox(1, 1, 1).Faces[0], -1.0)


sys.exit(run_file(globals(), "freecad-app"))
