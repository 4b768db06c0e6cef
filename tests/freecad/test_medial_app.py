# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD App tests of the medial features (issue 9): medial axis of a face, medial
surface, FEM mid-surface and thickness; run by ``freecadcmd``.

Run through tests/run_freecad_tests.sh, or directly:
``MFGEOM_LIBRARY=build/libmfgeom.so freecadcmd tests/freecad/test_medial_app.py``.
Prints ``freecad-medial: N passed, M failed`` last and exits non-zero on any failure.

References are independent of the code under test: the analytic medial axis of a
rectangle (branches to the corners, a centre line, radius half the width) and of a frame
(the largest disc in a corner touches two outer sides and the hole's corner: r = 3 sqrt 2
/ (1 + sqrt 2) for a 3 mm wide frame), distances from the wires' points to the face's
boundary measured by OCCT, FreeCAD's own Placement; the analytic major medial surface of
a cuboid a > b > c (one sheet at mid-height inset by c/2, radius c/2, four seams, four
junctions), which the library's extraction is tested against, and the bundled
thin-walled tray."""

import csv
import math
import os
import sys
import tempfile
import unittest

import numpy as np

import FreeCAD as App
import Part

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
if os.path.join(REPO, "workbench") not in sys.path:
    sys.path.append(os.path.join(REPO, "workbench"))
sys.path.append(HERE)
sys.path.append(os.path.join(REPO, "examples", "parts"))

import mfgeom  # noqa: E402
import thin_wall  # noqa: E402
from fc_testsupport import DocumentTestCase, run_file  # noqa: E402
from isolated_run import isolated  # noqa: E402
from mfgeom import palette  # noqa: E402
from mfgeom.app import medial_axis_feature as maf  # noqa: E402
from mfgeom.app import medial_surface_feature as msf  # noqa: E402
from mfgeom.app import mid_surface_feature as mid  # noqa: E402
from mfgeom.errors import InputError  # noqa: E402

A, B, C = 20.0, 12.0, 4.0        # the cuboid (x, y, z): a > b > c
PLACEMENT = App.Placement(App.Vector(5, -7, 11), App.Rotation(App.Vector(1, 2, 3), 37))


def _np(v):
    return np.array([v.x, v.y, v.z])


def clean(test, obj):
    test.assertTrue(obj.isValid(), obj.getStatusString())
    test.assertNotIn("Touched", obj.State)
    test.assertNotIn("Invalid", obj.State)


# ---------------------------------------------------------------------------- 2-D
class MedialAxisOfFace(unittest.TestCase):

    def setUp(self):
        self.doc = App.newDocument("MedialAxis")
        self.box = self.doc.addObject("Part::Box", "Box")
        self.box.Length, self.box.Width, self.box.Height = 10.0, 4.0, 2.0
        self.doc.recompute()

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def bottom(self):
        """The name of the box's face at z = 0 (its global placement's bottom)."""
        return next(f"Face{i + 1}" for i, f in enumerate(self.box.Shape.Faces)
                    if abs(f.BoundBox.ZMax - self.box.Shape.BoundBox.ZMin) < 1e-9)

    def assert_radii_are_clearances(self, obj, face, tol):
        """Every wire point lies on the face's plane and its radius is its distance to
        the face's boundary (OCCT's distance to the face's wires), within tol."""
        radii = maf.branch_radii(obj)
        wires = obj.Shape.Wires
        self.assertEqual(len(wires), obj.BranchCount)
        boundary = Part.makeCompound(face.Wires)
        plane_n = face.normalAt(0, 0)
        for wire, r in zip(wires, radii):
            pts = [v.Point for v in wire.OrderedVertexes]
            self.assertEqual(len(pts), len(r))
            for p, rad in zip(pts, r):
                self.assertLess(abs((p - face.Vertexes[0].Point).dot(plane_n)), 1e-9)
                d = boundary.distToShape(Part.Vertex(p))[0]
                self.assertLessEqual(abs(d - rad), tol, (p, d, rad))
                self.assertLess(face.distToShape(Part.Vertex(p))[0], 1e-9)   # on the face

    def test_rectangle(self):
        sub = self.bottom()
        obj = mfgeom.make_medial_axis(self.doc, (self.box, sub), 0.01)
        clean(self, obj)
        self.assertEqual(obj.TypeId, "Part::FeaturePython")
        self.assertEqual(obj.Proxy.Type, maf.TYPE)
        # 10 x 4: four branches to the corners and the centre line y = 2 from x = 2 to 8
        self.assertEqual((obj.BranchCount, obj.JunctionCount), (5, 2))
        self.assertAlmostEqual(obj.MaxRadius, 2.0, delta=1e-9)
        self.assertAlmostEqual(obj.MinRadius, 0.0, delta=1e-9)
        junctions = sorted((v.Point.x, v.Point.y, v.Point.z) for v in obj.Shape.Vertexes
                           if not any(v.isSame(w) for e in obj.Shape.Edges
                                      for w in e.Vertexes))
        np.testing.assert_allclose(junctions, [(2, 2, 0), (8, 2, 0)], atol=1e-9)
        np.testing.assert_allclose(obj.JunctionRadii, [2.0, 2.0], atol=1e-9)
        self.assertAlmostEqual(obj.Shape.Length, 8 * math.sqrt(2) + 6, delta=1e-9)
        self.assert_radii_are_clearances(obj, self.box.Shape.getElement(sub), 0.01)
        self.assertEqual(len(obj.Radii), obj.BranchOffsets[-1])

    def test_recompute_on_source_change_and_placement(self):
        sub = self.bottom()
        obj = mfgeom.make_medial_axis(self.doc, (self.box, sub), "0.01 mm")
        self.box.Width = 6.0
        self.doc.recompute()
        clean(self, obj)
        self.assertAlmostEqual(obj.MaxRadius, 3.0, delta=1e-9)
        self.box.Placement = PLACEMENT
        self.doc.recompute()
        clean(self, obj)
        face = self.box.Shape.getElement(sub)
        self.assertAlmostEqual(obj.MaxRadius, 3.0, delta=1e-9)
        self.assert_radii_are_clearances(obj, face, 0.01)
        # the centre line moved with the box: (3, 3, 0) .. (7, 3, 0) in the box's frame
        centre = [e for e in obj.Shape.Edges if abs(e.Length - 4.0) < 1e-9]
        self.assertEqual(len(centre), 1)
        ends = sorted(tuple(np.round(_np(PLACEMENT.inverse().multVec(v.Point)), 9))
                      for v in centre[0].Vertexes)
        np.testing.assert_allclose(ends, [(3, 3, 0), (7, 3, 0)], atol=1e-9)

    def test_frame_with_hole(self):
        outer = Part.makePolygon([App.Vector(x, y, 0) for x, y in
                                  ((0, 0), (10, 0), (10, 10), (0, 10), (0, 0))])
        inner = Part.makePolygon([App.Vector(x, y, 0) for x, y in
                                  ((3, 3), (7, 3), (7, 7), (3, 7), (3, 3))])
        frame = self.doc.addObject("Part::Feature", "Frame")
        frame.Shape = Part.Face(Part.Wire(outer)).cut(Part.Face(Part.Wire(inner))).Faces[0]
        self.doc.recompute()
        self.assertTrue(frame.Shape.isValid())
        self.assertAlmostEqual(frame.Shape.Area, 84.0)
        obj = mfgeom.make_medial_axis(self.doc, (frame, "Face1"), 0.001)
        clean(self, obj)
        # the largest disc sits in a corner: centre (r, r), touching the hole's corner
        # (3, 3): sqrt(2) (3 - r) = r
        exact = 3 * math.sqrt(2) / (1 + math.sqrt(2))
        self.assertAlmostEqual(obj.MaxRadius, exact, delta=0.001)
        self.assert_radii_are_clearances(obj, frame.Shape.Faces[0], 0.001)

    def test_tube_end(self):
        """The end face of a tube (issue 22: "boundary touches or crosses itself" at tol
        0.5, 65 M points and 7 GB at 0.1 - the circles' polylines closed on a vertex 1e-14
        from their first).  Every tolerance: the loop at radius 7.5, no branch into the
        hole or beyond the tube, radii the clearances."""
        tube = self.doc.addObject("Part::Feature", "Tube")
        tube.Shape = Part.makeCylinder(10, 5).cut(Part.makeCylinder(5, 5))
        self.doc.recompute()
        name = next(f"Face{i + 1}" for i, f in enumerate(tube.Shape.Faces)
                    if abs(f.CenterOfMass.z - 5) < 1e-9)
        face = tube.Shape.getElement(name)
        for tol in (0.5, 0.1, 0.01):
            obj = mfgeom.make_medial_axis(self.doc, (tube, name), tol)
            clean(self, obj)
            self.assertAlmostEqual(obj.MaxRadius, 2.5, delta=tol)
            pts = np.array([_np(v.Point) for w in obj.Shape.Wires for v in w.OrderedVertexes])
            rho = np.hypot(pts[:, 0], pts[:, 1])
            self.assertGreaterEqual(rho.min(), 7.5 - tol)
            self.assertLessEqual(rho.max(), 10.0 + 1e-9)
            self.assertLess(len(pts), 20 * 2 * obj.BranchCount)
            self.assert_radii_are_clearances(obj, face, tol)
            # arcs as arcs: the loop's edges are arcs of the circle r 7.5 about the axis
            loop = [e for e in obj.Shape.Edges
                    if all(abs(np.hypot(v.Point.x, v.Point.y) - 7.5) <= tol for v in e.Vertexes)]
            self.assertGreater(len(loop), 0)
            for e in loop:
                self.assertEqual(type(e.Curve).__name__, "Circle", (tol, e.Curve))
                self.assertAlmostEqual(e.Curve.Radius, 7.5, delta=tol)
                self.assertLess(e.Curve.Center.distanceToPoint(App.Vector(0, 0, 5)), tol)
            self.assertAlmostEqual(sum(e.Length for e in loop), 2 * math.pi * 7.5, delta=2 * math.pi * tol)
            self.doc.removeObject(obj.Name)

    def test_wrong_inputs_create_nothing(self):
        cyl = self.doc.addObject("Part::Cylinder", "Cyl")
        self.doc.recompute()
        other = App.newDocument("OtherDoc")
        try:
            obox = other.addObject("Part::Box", "Box")
            other.recompute()
            before = [o.Name for o in self.doc.Objects]
            side = next(f"Face{i + 1}" for i, f in enumerate(cyl.Shape.Faces)
                        if f.Surface.TypeId != "Part::GeomPlane")
            cases = [((cyl, side), 0.01, "not planar"),
                     ((self.box, "Edge1"), 0.01, "not a face"),
                     ((self.box, "Face99"), 0.01, "has no Face99"),
                     ((obox, "Face1"), 0.01, "not in document"),
                     ((self.box, "Face1"), 0.0, "> 0"),
                     ((self.box, "Face1"), "5 deg", "length"),
                     (self.box, 0.01, "FaceN")]
            for ref, tol, text in cases:
                with self.assertRaisesRegex(InputError, text, msg=str((ref, tol))):
                    mfgeom.make_medial_axis(self.doc, ref, tol)
            self.assertEqual([o.Name for o in self.doc.Objects], before)
        finally:
            App.closeDocument(other.Name)

    def test_save_and_reload(self):
        obj = mfgeom.make_medial_axis(self.doc, (self.box, self.bottom()), 0.01)
        name, radii = obj.Name, list(obj.Radii)
        path = os.path.join(tempfile.mkdtemp(), "axis.FCStd")
        self.doc.saveAs(path)
        App.closeDocument(self.doc.Name)
        self.doc = App.openDocument(path)
        again = self.doc.getObject(name)
        self.assertEqual(type(again.Proxy).__name__, "MedialAxis")
        self.assertEqual(list(again.Radii), radii)
        again.touch()
        self.doc.recompute()
        clean(self, again)
        self.assertEqual(list(again.Radii), radii)


# ---------------------------------------------------------------------------- 3-D
class ThicknessFunctions(unittest.TestCase):
    """The mid-surface's pure functions on a hand-made two-sheet mesh."""

    def sheets(self):
        # sheet 0: unit square at z = 0, thickness 2 (r = 1); sheet 1: 2 x 1 rectangle
        # at z = 5, thickness 4 (r = 2)
        pts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
               (0, 0, 5), (2, 0, 5), (2, 1, 5), (0, 1, 5)]
        tris = [(0, 1, 2), (0, 2, 3), (4, 5, 6), (4, 6, 7)]
        return msf.SheetMesh(pts, tris, [1, 1, 1, 1, 2, 2, 2, 2], [0, 4, 8], [0, 2, 4],
                             [(0, 1), (2, 3)])

    def test_report(self):
        rep = mid.ThicknessReport(self.sheets(), bins=2)
        self.assertEqual((rep.minimum, rep.maximum, rep.points), (2.0, 4.0, 8))
        self.assertAlmostEqual(rep.area, 3.0)
        self.assertAlmostEqual(rep.mean, (2.0 * 1 + 4.0 * 2) / 3.0)   # by area
        np.testing.assert_allclose(rep.shares, [1 / 3, 2 / 3])
        lines = rep.lines()
        self.assertEqual(len(lines), 3)
        self.assertIn("mean 3.333 mm", lines[0])
        self.assertIn("66.7 %", lines[2])

    def test_report_one_thickness_up_to_rounding(self):
        """A plate's radii differ in the last bit only: one bin with all the area, not
        ten bins '2 .. 2' with 100 % in an arbitrary one."""
        sheets = self.sheets()
        sheets.radii[:] = 1.0
        sheets.radii[[1, 5]] = np.nextafter(1.0, 2.0)
        rep = mid.ThicknessReport(sheets, bins=10)
        self.assertEqual(len(rep.shares), 1)
        self.assertAlmostEqual(rep.shares[0], 1.0)
        self.assertEqual(len(rep.lines()), 2)
        self.assertGreater(rep.maximum, rep.minimum)   # the data keep the true values

    def test_csv(self):
        path = os.path.join(tempfile.mkdtemp(), "t.csv")
        self.assertEqual(mid.write_csv(path, self.sheets()), 8)
        with open(path, encoding="utf-8") as f:
            rows = list(csv.reader(f))
        self.assertEqual(tuple(rows[0]), mid.CSV_HEADER)
        self.assertEqual(rows[5], ["1", "0.0", "0.0", "5.0", "2.0", "4.0"])

    def test_faces_and_face_thickness(self):
        sheets = self.sheets()
        faces, owner = mid.sheet_faces(sheets, 0.01)
        self.assertEqual((len(faces), owner), (2, [0, 1]))   # coplanar triangles merged
        shape = mid.shell_of(faces, 0.01)
        self.assertAlmostEqual(shape.Area, 3.0)
        by_z = sorted(zip((f.CenterOfMass.z for f in shape.Faces),
                          mid.face_thickness(shape, sheets, 0.01)))
        np.testing.assert_allclose([t for _z, t in by_z], [2.0, 4.0])

    def test_planar_sheet_with_hole(self):
        """A frame-shaped planar sheet (3 x 3 with a 1 x 1 hole, 8 triangles, tilted in
        space) becomes one planar face of area 8 with two wires; its boundary loops run
        opposite ways."""
        xy = [(0, 0), (3, 0), (3, 3), (0, 3), (1, 1), (2, 1), (2, 2), (1, 2)]
        pts = np.array([_np(PLACEMENT.multVec(App.Vector(x, y, 0))) for x, y in xy])
        tris = [(0, 1, 5), (0, 5, 4), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6),
                (3, 0, 4), (3, 4, 7)]
        loops = sorted(mid.boundary_loops(tris), key=min)
        self.assertEqual([sorted(lp) for lp in loops], [[0, 1, 2, 3], [4, 5, 6, 7]])
        outer = loops[0][loops[0].index(0):] + loops[0][:loops[0].index(0)]
        inner = loops[1][loops[1].index(4):] + loops[1][:loops[1].index(4)]
        self.assertEqual((outer, inner), ([0, 1, 2, 3], [4, 7, 6, 5]))
        sheets = msf.SheetMesh(pts, tris, np.ones(8), [0, 8], [0, 8], [(0, 1)])
        faces, _owner = mid.sheet_faces(sheets, 0.01)
        self.assertEqual(len(faces), 1)
        self.assertEqual(faces[0].Surface.TypeId, "Part::GeomPlane")
        self.assertEqual(len(faces[0].Wires), 2)
        self.assertAlmostEqual(faces[0].Area, 8.0, delta=1e-9)

    def test_ramp_colours(self):
        """The thickness ramp keeps away from FreeCAD's selection and pre-selection
        colours (>= 50 CIELAB units for normal, protan and deutan vision) and its tenths
        stay apart (>= 8), as palette.py claims."""
        ramp = [palette.ramp_color(k / 100) for k in range(101)]
        worst = min(palette.contrast(c, s, v) for c in ramp for v in palette.VISIONS
                    for s in (palette.SELECTION, palette.PRESELECTION))
        self.assertGreaterEqual(worst, 50.0)
        step = min(palette.contrast(palette.ramp_color(k / 10), palette.ramp_color((k + 1) / 10),
                                    v) for k in range(10) for v in palette.VISIONS)
        self.assertGreaterEqual(step, 8.0)
        np.testing.assert_allclose(palette.ramp_colors([0, 1, 2], 0, 2)[[0, 2]],
                                   [palette.THICKNESS_RAMP[0], palette.THICKNESS_RAMP[-1]])
        # values apart by rounding only are one value: the ramp's middle, not its ends
        lo, hi = 2.0, np.nextafter(2.0, 3.0)
        np.testing.assert_allclose(palette.ramp_colors([lo, hi], lo, hi),
                                   [palette.ramp_color(0.5)] * 2)
        self.assertTrue(palette.one_value(lo, hi) and palette.one_value(0.0, 0.0))
        self.assertFalse(palette.one_value(2.0, 2.0 + 1e-6))


class MedialSurfaceFeature(DocumentTestCase):
    """The feature on a cuboid: the analytic major medial surface."""

    DOC_NAME = "MedialSurface"

    def setUp(self):
        super().setUp()
        self.box = self.doc.addObject("Part::Box", "Box")
        self.box.Length, self.box.Width, self.box.Height = A, B, C
        self.doc.recompute()

    def assert_cuboid(self, obj, a, b, c, placement=None):
        tol = obj.Tolerance.Value
        self.assertEqual(obj.SheetCount, 1)
        self.assertEqual((obj.SeamCount, obj.JunctionCount), (4, 4))
        self.assertAlmostEqual(obj.MinRadius, c / 2, delta=tol)
        self.assertAlmostEqual(obj.MaxRadius, c / 2, delta=tol)
        self.assertAlmostEqual(obj.SheetArea, (a - c) * (b - c), delta=2 * tol * (a + b))
        pts = np.array([_np(p) for p in obj.SheetPoints])
        if placement is not None:
            pts = np.array([_np(placement.inverse().multVec(App.Vector(*p))) for p in pts])
        np.testing.assert_allclose(pts[:, 2], c / 2, atol=tol)
        self.assertEqual(len(obj.SheetRadii), len(pts))
        self.assertEqual(len(obj.SheetFacets), 3 * obj.SheetTriangleOffsets[-1])
        self.assertEqual(obj.Mesh.CountFacets, obj.SheetTriangleOffsets[-1])
        self.assertEqual((len(obj.Shape.Wires), len(obj.Shape.Vertexes) >= 4), (4, True))

    def test_cuboid(self):
        obj = mfgeom.make_medial_surface(self.doc, self.box)
        clean(self, obj)
        diag = math.sqrt(A * A + B * B + C * C)
        self.assertAlmostEqual(obj.Tolerance.Value, 0.005 * diag, delta=1e-12)
        self.assertTrue(obj.MajorOnly)
        self.assert_cuboid(obj, A, B, C)

    def test_recompute_on_source_change_and_placement(self):
        obj = mfgeom.make_medial_surface(self.doc, self.box, 0.1)
        self.box.Height = 3.0
        self.doc.recompute()
        clean(self, obj)
        self.assert_cuboid(obj, A, B, 3.0)
        self.box.Placement = PLACEMENT
        self.doc.recompute()
        clean(self, obj)
        self.assert_cuboid(obj, A, B, 3.0, PLACEMENT)

    def test_save_and_reload(self):
        obj = mfgeom.make_medial_surface(self.doc, self.box, 0.1)
        name, radii = obj.Name, list(obj.SheetRadii)
        path = os.path.join(tempfile.mkdtemp(), "medial.FCStd")
        self.doc.saveAs(path)
        App.closeDocument(self.doc.Name)
        self.doc = App.openDocument(path)
        again = self.doc.getObject(name)
        self.assertEqual(type(again.Proxy).__name__, "MedialSurface")
        self.assertEqual(list(again.SheetRadii), radii)
        sheets = msf.sheet_mesh_of(again)
        self.assertEqual(len(sheets), 1)
        self.assertAlmostEqual(sheets.area(), again.SheetArea)

    def test_mesh_object_source(self):
        """issue 22: a Mesh object (an STL part) is taken as it is -- its own placement
        and the containers' applied (an open one: LibraryErrors)."""
        import Mesh
        mesh = self.doc.addObject("Mesh::Feature", "BoxMesh")
        mesh.Mesh = Mesh.Mesh(self.box.Shape.tessellate(0.1))
        self.doc.recompute()
        obj = mfgeom.make_medial_surface(self.doc, mesh, 0.1)
        clean(self, obj)
        self.assertEqual(obj.SourceTriangles, 12)
        self.assert_cuboid(obj, A, B, C)
        mesh.Placement = PLACEMENT
        self.doc.recompute()
        clean(self, obj)
        self.assert_cuboid(obj, A, B, C, PLACEMENT)
        part = self.doc.addObject("App::Part", "Container")
        part.addObject(mesh)
        part.Placement = PLACEMENT
        obj.touch()   # a container's move does not touch the mesh (nor, so, the feature)
        self.doc.recompute()
        clean(self, obj)
        self.assert_cuboid(obj, A, B, C, PLACEMENT.multiply(PLACEMENT))
        # an open mesh: LibraryErrors (a failed recompute prints a traceback)

    def test_bad_input_creates_nothing(self):
        face = self.doc.addObject("Part::Feature", "Face")
        face.Shape = Part.makePlane(2, 2)
        self.doc.recompute()
        before = [o.Name for o in self.doc.Objects]
        for args, text in (((None,), "source"), ((face,), "not a solid"),
                           ((self.box, 0.0), "> 0"), ((self.box, "1 deg"), "length")):
            with self.assertRaisesRegex(InputError, text, msg=str(args)):
                mfgeom.make_medial_surface(self.doc, *args)
        with self.assertRaisesRegex(InputError, "deflection"):
            mfgeom.make_medial_surface(self.doc, self.box, 0.1, deflection=-1)
        self.assertEqual([o.Name for o in self.doc.Objects], before)


class MidSurfaceFeature(DocumentTestCase):
    """The FEM mid-surface of the cuboid: shell, thickness data, report, CSV."""

    DOC_NAME = "MidSurface"

    def setUp(self):
        super().setUp()
        self.box = self.doc.addObject("Part::Box", "Box")
        self.box.Length, self.box.Width, self.box.Height = A, B, C
        self.doc.recompute()
        self.csv = os.path.join(tempfile.mkdtemp(), "thickness.csv")

    def read_csv(self):
        with open(self.csv, encoding="utf-8") as f:
            rows = list(csv.reader(f))
        self.assertEqual(tuple(rows[0]), mid.CSV_HEADER)
        return np.array(rows[1:], dtype=float)

    def test_from_solid(self):
        obj = mfgeom.make_mid_surface(self.doc, self.box, self.csv, 0.1)
        clean(self, obj)
        medial = obj.Source
        self.assertTrue(msf.is_medial_surface(medial) and medial.MajorOnly)
        self.assertEqual(len(self.doc.Objects), 3)
        tol = medial.Tolerance.Value
        self.assertAlmostEqual(obj.Shape.Area, (A - C) * (B - C), delta=2 * tol * (A + B))
        self.assertIn(obj.Shape.ShapeType, ("Face", "Shell"))
        np.testing.assert_allclose(obj.Thickness, C, atol=2 * tol)
        self.assertEqual(len(obj.Thickness), len(obj.ThicknessPoints))
        self.assertEqual(len(obj.FaceThickness), len(obj.Shape.Faces))
        np.testing.assert_allclose(obj.FaceThickness, C, atol=2 * tol)
        for value in (obj.MinThickness, obj.MaxThickness, obj.MeanThickness):
            self.assertAlmostEqual(value, C, delta=2 * tol)
        self.assertIn("thickness min", obj.Histogram[0])
        rows = self.read_csv()
        self.assertEqual(len(rows), len(obj.Thickness))
        np.testing.assert_allclose(rows[:, 5], obj.Thickness)
        np.testing.assert_allclose(rows[:, 5], 2 * rows[:, 4])
        np.testing.assert_allclose(rows[:, 1:4], [_np(p) for p in obj.ThicknessPoints])

    def test_recompute_follows_the_part(self):
        medial = mfgeom.make_medial_surface(self.doc, self.box, 0.1)
        obj = mfgeom.make_mid_surface(self.doc, medial, self.csv)
        self.assertIs(obj.Source, medial)
        self.box.Height = 3.0
        self.doc.recompute()
        clean(self, obj)
        clean(self, medial)
        self.assertAlmostEqual(obj.MeanThickness, 3.0, delta=0.2)
        np.testing.assert_allclose(self.read_csv()[:, 5], obj.Thickness)
        self.assertAlmostEqual(obj.Shape.Area, (A - 3) * (B - 3), delta=0.2 * (A + B))

    def test_bad_input_creates_nothing(self):
        before = [o.Name for o in self.doc.Objects]
        with self.assertRaisesRegex(InputError, "folder does not exist"):
            mfgeom.make_mid_surface(self.doc, self.box, "/no/such/folder/t.csv")
        with self.assertRaisesRegex(InputError, "bins"):
            mfgeom.make_mid_surface(self.doc, self.box, None, 0.1, bins=0)
        face = self.doc.addObject("Part::Feature", "Face")
        face.Shape = Part.makePlane(2, 2)
        self.doc.recompute()
        with self.assertRaisesRegex(InputError, "not a solid"):
            mfgeom.make_mid_surface(self.doc, face)
        self.doc.removeObject("Face")
        self.assertEqual([o.Name for o in self.doc.Objects], before)


class LibraryErrors(unittest.TestCase):
    """The real library's refusals reach the user as one line and leave the document as
    it was (in their own freecadcmd: a failed recompute prints a traceback)."""

    def test_refused(self):
        out = isolated("medial_library_errors", LIBRARY_ERRORS_SCRIPT)
        for case in out["cases"]:
            self.assertNotIn("\n", case["error"])
            self.assertEqual(case["objects"], ["Two", "Box", "Open", "Overlap"], case)
            self.assertTrue(case["valid"], case)
        two, box, opened, overlap = out["cases"]
        # open / non-manifold input: the library's input check names it
        self.assertIn("non-manifold", two["error"])
        self.assertEqual(two["error_class"], "MfgeomError")
        self.assertEqual(box["error"], "")
        # issue 22: a Mesh object is taken as it is; an open one is refused, creating nothing
        self.assertIn("not closed", opened["error"])
        # ... and two overlapping boxes in one mesh (every edge test passes) as crossing
        self.assertIn("shells cross", overlap["error"])


LIBRARY_ERRORS_SCRIPT = """
doc = App.newDocument("LibraryErrors")
two = doc.addObject("Part::Feature", "Two")
two.Shape = Part.makeCompound([Part.makeBox(1, 1, 1), Part.makeBox(1, 1, 1, App.Vector(1, 1, 0))])
box = doc.addObject("Part::Box", "Box")
import Mesh
opened = doc.addObject("Mesh::Feature", "Open")
facets = Mesh.Mesh(Part.makeBox(2, 1, 1).tessellate(0.1)).Facets
opened.Mesh = Mesh.Mesh([[tuple(p) for p in f.Points] for f in facets[:-1]])
overlap = doc.addObject("Mesh::Feature", "Overlap")   # two boxes as one mesh, overlapping
pair = Mesh.Mesh(Part.makeBox(2, 1, 1).tessellate(0.1))
pair.addMesh(Mesh.Mesh(Part.makeBox(2, 1, 1, App.Vector(1.5, 0.5, 0)).tessellate(0.1)))
overlap.Mesh = pair
doc.recompute()
result = {"cases": []}
for source in (two, box, opened, overlap):
    case = {"error": "", "error_class": ""}
    try:
        made = mfgeom.make_medial_surface(doc, source, 0.05)
        doc.removeObject(made.Name)
    except Exception as exc:
        case.update(error=str(exc), error_class=type(exc).__name__)
    case.update(objects=[o.Name for o in doc.Objects],
                valid=all(o.isValid() for o in doc.Objects))
    result["cases"].append(case)
print("=== result " + json.dumps(result), flush=True)
"""


class OlderDocuments(unittest.TestCase):
    """What the features share (mfgeom.app.feature_base.FeatureProxy): an object saved by
    an older version (Version 0, without a property added since) opens with the property
    back (the Mesh outputs hidden) and Version current, and recomputes to its old
    result."""

    def test_old_objects_migrate_on_restore(self):
        from mfgeom.app import sweep_feature
        doc = App.newDocument("Older")
        try:
            box = doc.addObject("Part::Box", "Box")
            box.Length, box.Width, box.Height = A, B, C
            doc.recompute()
            bottom = next(f"Face{i + 1}" for i, f in enumerate(box.Shape.Faces)
                          if abs(f.BoundBox.ZMax) < 1e-9)
            axis = mfgeom.make_medial_axis(doc, (box, bottom), 0.01)
            surface = mfgeom.make_medial_surface(doc, box, 0.1)
            mid_surface = mfgeom.make_mid_surface(doc, surface)
            sweep = mfgeom.make_rotational_sweep(doc, box, (0, 0, 0), "Z", 30)
            # (object, its module, the property an older version lacked, its result)
            cases = [(axis, maf, "JunctionRadii", lambda o: list(o.JunctionRadii)),
                     (surface, msf, "Mesh", lambda o: o.Mesh.CountFacets),
                     (mid_surface, mid, "FaceThickness", lambda o: list(o.FaceThickness)),
                     (sweep, sweep_feature, "Mesh", lambda o: o.Mesh.CountFacets)]
            before = [(obj.Name, module, prop, result, result(obj))
                      for obj, module, prop, result in cases]
            for obj, _module, prop, _result in cases:
                obj.removeProperty(prop)
                obj.Version = 0
            path = os.path.join(tempfile.mkdtemp(), "older.FCStd")
            doc.saveAs(path)
            App.closeDocument(doc.Name)
            doc = App.openDocument(path)
            for name, module, prop, result, value in before:
                obj = doc.getObject(name)
                self.assertIn(prop, obj.PropertiesList, name)
                self.assertEqual(obj.Version, module.VERSION, name)
                mode = obj.getEditorMode(prop)   # outputs: read-only
                self.assertIn("ReadOnly", mode, name)
                self.assertEqual("Hidden" in mode, prop == "Mesh", name)
                self.assertNotEqual(result(obj), value, name)   # empty until recomputed
                obj.touch()
            doc.recompute()
            for name, _module, prop, result, value in before:
                obj = doc.getObject(name)
                clean(self, obj)
                self.assertEqual(result(obj), value, name)
        finally:
            App.closeDocument(doc.Name)


def free_edges(shape):
    """The edges of ``shape`` that one face only has."""
    return [e for e in shape.Edges if len(shape.ancestorsOfType(e, Part.Face)) == 1]


def shell_box(doc, reverse=True, join="Arc"):
    """issue 22's part: a PartDesign Body, a 60 x 40 x 30 box (AdditiveBox) and a
    Thickness of 2 mm with the top face removed, inward (``reverse``) or outward with the
    ``join`` of its outer edges.  Returns the Body."""
    body = doc.addObject("PartDesign::Body", "Body")
    box = doc.addObject("PartDesign::AdditiveBox", "Box")
    body.addObject(box)
    box.Length, box.Width, box.Height = 60.0, 40.0, 30.0
    doc.recompute()
    top = next(f"Face{i + 1}" for i, f in enumerate(box.Shape.Faces)
               if abs(f.CenterOfMass.z - 30.0) < 1e-9)
    shell = doc.addObject("PartDesign::Thickness", "Thickness")
    body.addObject(shell)
    shell.Base = (box, [top])
    shell.Value, shell.Reversed, shell.Join = 2.0, reverse, join
    doc.recompute()
    return body


class ShellBoxMidSurface(DocumentTestCase):
    """issue 22: the FEM mid-surface of a PartDesign shell box, a 60 x 40 x 30 open box
    with 2 mm walls and floor.  Its mid-surface is one connected wall -- the floor's and
    the four walls' mid-planes joined along their seams through the curved strips at the
    inner edges -- so it is ONE shell, manifold (no seam where three sheets meet: the
    bisector of the two outer faces at each outer edge is not in the major part), whose
    only free edges are the open rim: the seam where the walls' balls touch the top face,
    at z = 30 - 1 = 29, dipping to 30 - 2 sqrt 2 / (1 + sqrt 2) = 28.83 at the corners
    (the ball touching the top, both outer faces and the inner edge), one closed loop of
    about 2 (58 + 38) = 192 mm (2 (62 + 42) made outward).  Faces: the wall thickness 2 mm within 2 tol (the
    corner balls are larger, radius 3 - sqrt 3 = 1.27 at most: within 2 tol too).
    Before this stop: 8 shells, 89 free edges at the junctions, and OCCT's check found
    the vertices' tolerances overlapping; outward with sharp edges: 235 zero-area faces
    of thickness 0 and an invalid shape."""

    DOC_NAME = "ShellBox"

    def assert_mid_surface(self, mid_obj, wall, rim_z, rim_length, check=True):
        clean(self, mid_obj)
        shape = mid_obj.Shape
        tol = mid_obj.Source.Tolerance.Value
        diag = mid_obj.Source.Source.Shape.BoundBox.DiagonalLength
        self.assertTrue(shape.isValid())
        if check:   # OCCT's full check, self-intersections included
            shape.check(True)
        self.assertEqual([f.Area for f in shape.Faces if f.Area < 1e-9 * diag ** 2], [])
        self.assertEqual(len(shape.Shells), 1)
        self.assertEqual(shape.ShapeType, "Shell")
        free = free_edges(shape)
        z = np.array([v.Point.z for e in free for v in e.Vertexes])
        self.assertGreater(len(free), 0)
        self.assertLessEqual(z.max(), rim_z + tol)
        self.assertGreaterEqual(z.min(), rim_z - 1.1716 + 1.0 - tol)   # the corners' dip
        rim = Part.__sortEdges__(free)
        wire = Part.Wire(rim)
        self.assertTrue(wire.isClosed())
        self.assertEqual(len(wire.Edges), len(free))   # one loop
        self.assertAlmostEqual(wire.Length, rim_length, delta=8 * tol)
        np.testing.assert_allclose(mid_obj.FaceThickness, wall, atol=2 * tol)
        self.assertEqual(len(mid_obj.FaceThickness), len(shape.Faces))
        self.assertAlmostEqual(mid_obj.MinThickness, wall, delta=2 * tol)

    def test_inward_shell(self):
        body = shell_box(self.doc)
        self.assertTrue(body.Shape.isValid())
        self.assertAlmostEqual(body.Shape.Volume, 60 * 40 * 30 - 56 * 36 * 28, delta=1e-6)
        mid_obj = mfgeom.make_mid_surface(self.doc, body)
        self.assert_mid_surface(mid_obj, 2.0, 29.0, 2 * (58 + 38))
        # the corners of the floor's face are the junctions (the library cuts them)
        floor = [f for f in mid_obj.Shape.Faces if abs(f.BoundBox.ZLength) < 1e-9 and
                 abs(f.BoundBox.ZMin - 1.0) < 1e-9]
        self.assertEqual(len(floor), 1)
        self.assertAlmostEqual(floor[0].Area, 56 * 36, delta=1e-6)

    def test_outward_shell_sharp_edges(self):
        """The same box made outward with sharp outer edges (Join Intersection): a strip
        the library leaves unsimplified, with 235 zero-area triangles (issue 22's zero-
        area faces of thickness 0)."""
        body = shell_box(self.doc, reverse=False, join="Intersection")
        self.assertAlmostEqual(body.Shape.Volume, 64 * 44 * 32 - 60 * 40 * 30, delta=1e-6)
        mid_obj = mfgeom.make_mid_surface(self.doc, body)
        # (OCCT's self-intersection check takes 15 s on its 10^3 faces: left out)
        self.assert_mid_surface(mid_obj, 2.0, 29.0, 2 * (62 + 42), check=False)
        self.assertGreater(min(f.Area for f in mid_obj.Shape.Faces), 0.0)

    def test_closed_hollow_box(self):
        """A closed box with 2 mm walls all round: its mid-surface is one closed shell."""
        hollow = self.doc.addObject("Part::Feature", "Hollow")
        hollow.Shape = Part.makeBox(60, 40, 30).cut(
            Part.makeBox(56, 36, 26, App.Vector(2, 2, 2)))
        self.doc.recompute()
        mid_obj = mfgeom.make_mid_surface(self.doc, hollow)
        clean(self, mid_obj)
        shape = mid_obj.Shape
        shape.check(True)
        self.assertEqual(shape.ShapeType, "Shell")
        self.assertTrue(shape.isClosed())
        self.assertEqual(free_edges(shape), [])
        tol = mid_obj.Source.Tolerance.Value
        np.testing.assert_allclose(mid_obj.FaceThickness, 2.0, atol=2 * tol)
        # it encloses the mid-box 58 x 38 x 28 (corners rounded within the tolerance)
        self.assertAlmostEqual(abs(Part.Solid(shape).Volume), 58 * 38 * 28,
                               delta=0.02 * 58 * 38 * 28)


class ThinWallPart(unittest.TestCase):
    """The bundled ribbed tray (examples/parts/thin_wall.py) with the real library."""

    def test_part(self):
        tray = thin_wall.make()
        self.assertTrue(tray.isValid())
        self.assertEqual(len(tray.Solids), 1)
        self.assertTrue(all(f.Surface.TypeId == "Part::GeomPlane" for f in tray.Faces))
        self.assertAlmostEqual(tray.Volume, thin_wall.exact_volume(), delta=1e-6)

    def test_mid_surface_thickness(self):
        doc = App.newDocument("Tray")
        try:
            part = thin_wall.add_to(doc)
            obj = mfgeom.make_mid_surface(doc, part)
            clean(self, obj)
            tol = obj.Source.Tolerance.Value
            # the walls' and floor's mid-planes carry 3 mm, the rib's 2 mm
            thick = np.array(obj.Thickness)
            self.assertAlmostEqual(obj.MinThickness, thin_wall.RIB, delta=2 * tol)
            near_wall = np.abs(thick - thin_wall.WALL) <= 2 * tol
            near_rib = np.abs(thick - thin_wall.RIB) <= 2 * tol
            self.assertGreater(near_wall.mean(), 0.3)
            self.assertGreater(near_rib.sum(), 0)
            self.assertGreater(obj.Shape.Area, 0.5 * part.Shape.Area / 2 * 0.5)
        finally:
            App.closeDocument(doc.Name)


sys.exit(run_file(globals(), "freecad-medial"))
