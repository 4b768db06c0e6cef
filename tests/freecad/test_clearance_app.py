# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD App tests of the clearance check (issue 8, section 3), run by ``freecadcmd``.

Run through tests/run_freecad_tests.sh, or directly:
``MFGEOM_LIBRARY=build/libmfgeom.so freecadcmd tests/freecad/test_clearance_app.py``.
Prints ``freecad-clearance: N passed, M failed`` last and exits non-zero on any failure.

The stand-in for the sweep is the exact swept volume of a box a x b x c turned by 90 deg
about its edge on the z axis, built from Part primitives: the box at 0 and at 90 deg and
the cylinder sector of radius sqrt(a^2 + b^2) between them (its volume is
c (a b + (a^2 + b^2) pi / 4), checked).  References are analytic: distances from the box
faces and the cylinder (spheres placed at a known gap), common volumes of axis-aligned
boxes, and the common with a ring around the axis from a dense integral of the swept
angle at each radius.  With the library's sweep (once it lands) the same box is swept by
mfgeom.core.rotational_sweep and checked against the same references."""

import csv
import math
import os
import sys
import tempfile
import unittest

import numpy as np

import FreeCAD as App
import Mesh
import Part

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
if os.path.join(REPO, "workbench") not in sys.path:
    sys.path.append(os.path.join(REPO, "workbench"))

import mfgeom  # noqa: E402
from mfgeom.app import clearance  # noqa: E402
from mfgeom.errors import InputError  # noqa: E402

sys.path.insert(0, HERE)
from fc_testsupport import DocumentTestCase, run_file  # noqa: E402

A, B, C = 20.0, 10.0, 5.0           # the box swept about its edge on the z axis
R = math.hypot(A, B)                 # outer radius of the swept quarter annulus
THETA = math.pi / 2
TOL = 0.01
V = App.Vector


def swept_box_solid():
    """The exact swept volume of [0,A]x[0,B]x[0,C] turned by THETA about the z axis."""
    box0 = Part.makeBox(A, B, C)
    box1 = box0.copy()
    box1.rotate(V(0, 0, 0), V(0, 0, 1), math.degrees(THETA))
    sector = Part.makeCylinder(R, C, V(0, 0, 0), V(0, 0, 1), math.degrees(THETA))
    sector.rotate(V(0, 0, 0), V(0, 0, 1), math.degrees(math.atan2(B, A)))
    return box0.fuse([box1, sector]).removeSplitter()


def swept_angle(r):
    """Angle of the circle of radius r (> A) inside the swept volume: the box meets it on
    [acos(A/r), asin(B/r)], turned by THETA that becomes one arc THETA longer."""
    return math.asin(B / r) + THETA - math.acos(A / r)


def ring_common_volume(r1):
    """C * area of the swept region outside radius r1 (A < r1 < R): the integral of
    r * swept_angle(r) dr, by a dense trapezoid rule."""
    r = np.linspace(r1, R, 200001)
    w = np.array([swept_angle(x) for x in r[:-1]] + [THETA])  # at R the arc is THETA
    f = r * w
    return C * float(np.sum((f[1:] + f[:-1]) * np.diff(r)) / 2.0)


def sphere_beyond_arc(gap, radius=2.0, angle_deg=70.0, z=C / 2):
    """A sphere whose surface is ``gap`` beyond the swept cylinder, in the direction
    angle_deg (inside the sector's angular range) at height z."""
    d = R + gap + radius
    a = math.radians(angle_deg)
    return Part.makeSphere(radius, V(d * math.cos(a), d * math.sin(a), z))


def by_label(results):
    return {r.label: r for r in results}


class Base(DocumentTestCase):
    DOC_NAME = "Clearance"

    def add(self, name, shape, placement=None):
        obj = self.doc.addObject("Part::Feature", name)
        obj.Shape = shape
        if placement is not None:
            obj.Placement = placement
        return obj

    def add_mesh(self, name, mesh):
        obj = self.doc.addObject("Mesh::Feature", name)
        obj.Mesh = mesh
        return obj


class StandIn(unittest.TestCase):
    def test_stand_in_is_the_analytic_swept_volume(self):
        s = swept_box_solid()
        self.assertTrue(s.isValid())
        self.assertAlmostEqual(s.Volume, C * (A * B + (A * A + B * B) * THETA / 2), places=6)


class PartSweep(Base):
    """Part solids around the exact stand-in sweep."""

    def setUp(self):
        super().setUp()
        self.sweep = self.add("Sweep", swept_box_solid())
        self.objs = [
            # beyond the +x face of the box at t = 0: gap 10 (the sector ends at x <= A)
            self.add("FarBox", Part.makeBox(5, 5, 5, V(A + 10, 0, 0))),
            # above the box at t = 0, over it: gap 3
            self.add("AboveBox", Part.makeBox(4, 4, 2, V(2, 2, C + 3))),
            # beyond the cylinder, gap 1.5
            self.add("Sphere", sphere_beyond_arc(1.5)),
            # overlapping the box at t = 0: common [15,20]x[2,6]x[3,5] (the sector stays at
            # x <= 2y <= 12 there)
            self.add("Overlap", Part.makeBox(10, 4, 5, V(15, 2, 3))),
            # wholly inside the box at 90 deg ([-B,0]x[0,A]x[0,C])
            self.add("Inside", Part.makeBox(4, 3, 1, V(-5, 12, 1))),
            # sharing the face x = A
            self.add("Touching", Part.makeBox(5, 5, 5, V(A, 0, 0))),
            # overlapping by 0.004 (< TOL): a film, counted as touching
            self.add("Film", Part.makeBox(5, 5, 5, V(A - 0.004, 0, 0))),
            # overlapping by 0.05 (> TOL): interference 0.05 * 5 * 5
            self.add("Thin", Part.makeBox(5, 5, 5, V(A - 0.05, 0, 0))),
            # a gap of 0.005 (< TOL): touching, at its distance
            self.add("NearGap", Part.makeBox(5, 5, 5, V(A + 0.005, 0, 0))),
            # a ring around the axis from radius 21 out: the outer part of the sweep
            self.add("Ring", Part.makeCylinder(30, C + 2, V(0, 0, -1)).cut(
                Part.makeCylinder(21, C + 2, V(0, 0, -1)))),
        ]
        self.doc.recompute()

    def test_statuses_volumes_and_distances(self):
        res = by_label(clearance.check_clearance(self.sweep, self.objs, tolerance=TOL))
        self.assertEqual(len(res), len(self.objs))
        want = {  # label: (status, volume, distance)
            "FarBox": ("clear", 0.0, 10.0),
            "AboveBox": ("clear", 0.0, 3.0),
            "Sphere": ("clear", 0.0, 1.5),
            "Overlap": ("interference", 5 * 4 * 2, 0.0),
            "Inside": ("interference", 4 * 3 * 1, 0.0),
            "Touching": ("touching", 0.0, 0.0),
            "Film": ("touching", 0.0, 0.0),
            "Thin": ("interference", 0.05 * 5 * 5, 0.0),
            "NearGap": ("touching", 0.0, 0.005),
            "Ring": ("interference", ring_common_volume(21.0), 0.0),
        }
        for label, (status, volume, distance) in want.items():
            r = res[label]
            with self.subTest(label=label):
                self.assertEqual(r.status, status, r)
                self.assertEqual(r.interferes, status == "interference")
                self.assertAlmostEqual(r.interference_volume, volume, delta=1e-6 * max(1, volume))
                self.assertAlmostEqual(r.min_distance, distance, delta=1e-7)
                self.assertEqual(r.message, "")
                self.assertEqual(r.name, label)
        # the ring's reference is not the code's: 5 * integral of r * swept angle
        self.assertGreater(res["Ring"].interference_volume, 100.0)

    def test_closest_points_are_on_both_solids_at_the_distance(self):
        sweep = self.sweep.Shape
        for r in clearance.check_clearance(self.sweep, self.objs, tolerance=TOL):
            with self.subTest(label=r.label):
                p, q = r.point_on_sweep, r.point_on_object
                self.assertAlmostEqual((p - q).Length, r.min_distance, delta=1e-7)
                # in (or on) both solids: where they interfere, a point of the common
                obj = self.doc.getObject(r.name)
                self.assertTrue(sweep.isInside(p, 1e-7, True), p)
                self.assertTrue(obj.Shape.isInside(q, 1e-7, True), q)
                if r.interferes:
                    self.assertTrue(obj.Shape.isInside(p, 1e-7, True), p)
        far = by_label(clearance.check_clearance(self.sweep, self.objs[:1], TOL))["FarBox"]
        self.assertAlmostEqual(far.point_on_sweep.x, A, delta=1e-9)
        self.assertAlmostEqual(far.point_on_object.x, A + 10, delta=1e-9)

    def test_the_floor_follows_the_tolerance(self):
        # with a tolerance of 0.1 the 0.05 overlap is a film and the 0.005 gap touching;
        # with 0.001 the 0.004 film interferes and the 0.005 gap is clear
        coarse = by_label(clearance.check_clearance(self.sweep, self.objs, tolerance=0.1))
        self.assertEqual(coarse["Thin"].status, "touching")
        self.assertEqual(coarse["Thin"].interference_volume, 0.0)
        fine = by_label(clearance.check_clearance(self.sweep, self.objs, tolerance=0.001))
        self.assertEqual(fine["Film"].status, "interference")
        self.assertAlmostEqual(fine["Film"].interference_volume, 0.004 * 25, delta=1e-8)
        self.assertEqual(fine["NearGap"].status, "clear")

    def test_placements_of_objects_and_containers_count(self):
        # a box at the origin moved by its placement and by an App::Part around it
        box = self.add("Moved", Part.makeBox(2, 2, 2),
                       App.Placement(V(A + 3, 0, 0), App.Rotation()))
        part = self.doc.addObject("App::Part", "Container")
        part.addObject(box)
        part.Placement = App.Placement(V(0, 0, C + 4), App.Rotation())
        self.doc.recompute()
        r = clearance.check_clearance(self.sweep, [box], TOL)[0]
        self.assertEqual(r.status, "clear")
        self.assertAlmostEqual(r.min_distance, math.hypot(3, 4), delta=1e-9)

    def test_tolerance_arguments(self):
        one = self.objs[:1]
        for tol in ("0.01 mm", App.Units.Quantity("10 um"), 0.01):
            self.assertEqual(clearance.check_clearance(self.sweep, one, tol)[0].status, "clear")
        for bad in (0, -1, float("nan"), "5 deg", App.Units.Quantity("5 deg")):
            with self.subTest(tol=bad), self.assertRaises(InputError):
                clearance.check_clearance(self.sweep, one, bad)

    def test_report_table_and_csv(self):
        res = clearance.check_clearance(self.sweep, self.objs, tolerance=TOL)
        text = clearance.report_text(res, "Sweep", TOL)
        lines = text.splitlines()
        self.assertIn("Clearance check against 'Sweep' (tolerance 0.01 mm)", lines[0])
        self.assertEqual(len(lines), 1 + 1 + len(res) + 1)
        self.assertEqual(lines[-1], "4 of 10 object(s) interfere.")
        row = [ln for ln in lines if ln.startswith("Overlap ")][0].split()
        self.assertEqual(row[1:4], ["interference", "40.0000", "0.0000"])
        row = [ln for ln in lines if ln.startswith("FarBox ")][0].split()
        self.assertEqual(row[1:4], ["clear", "none", "10.0000"])
        path = os.path.join(tempfile.mkdtemp(), "clearance.csv")
        clearance.write_csv(res, path)
        rows = list(csv.DictReader(open(path, newline="")))
        self.assertEqual([r["label"] for r in rows], [r.label for r in res])
        sphere = [r for r in rows if r["name"] == "Sphere"][0]
        self.assertAlmostEqual(float(sphere["min_distance_mm"]), 1.5, delta=1e-7)
        self.assertEqual(float(sphere["interference_volume_mm3"]), 0.0)


class MeshSweep(Base):
    """A Mesh::Feature as the sweep: planar, so its solid is exact."""

    def box_mesh(self, x0, flip=False):
        mesh = Mesh.Mesh(Part.makeBox(10, 10, 10, V(x0, 0, 0)).tessellate(0.1))
        if flip:
            mesh.flipNormals()
        return mesh

    def test_mesh_sweep_with_placement(self):
        sweep = self.add_mesh("MeshSweep", self.box_mesh(0))
        sweep.Placement = App.Placement(V(0, 0, 100), App.Rotation())
        near = self.add("Near", Part.makeBox(5, 5, 5, V(13, 0, 100)))
        hit = self.add("Hit", Part.makeBox(5, 5, 5, V(8, 2, 103)))
        self.doc.recompute()
        res = by_label(clearance.check_clearance(sweep, [near, hit], TOL))
        self.assertEqual(res["Near"].status, "clear")
        self.assertAlmostEqual(res["Near"].min_distance, 3.0, delta=1e-7)
        self.assertEqual(res["Hit"].status, "interference")
        self.assertAlmostEqual(res["Hit"].interference_volume, 2 * 5 * 5, delta=1e-6)

    def test_mesh_in_a_container(self):
        sweep = self.add_mesh("MeshSweep", self.box_mesh(0))
        sweep.Placement = App.Placement(V(0, 0, 100), App.Rotation())
        part = self.doc.addObject("App::Part", "Container")
        part.addObject(sweep)
        part.Placement = App.Placement(V(0, 50, 0), App.Rotation(V(0, 0, 1), 90))
        # the mesh box lies at [-10,0]x[50,60]x[100,110]; a box 4 beyond its -x face
        box = self.add("Box", Part.makeBox(2, 2, 2, V(-16, 52, 102)))
        self.doc.recompute()
        r = clearance.check_clearance(sweep, [box], TOL)[0]
        self.assertEqual(r.status, "clear")
        self.assertAlmostEqual(r.min_distance, 4.0, delta=1e-7)

    def test_inward_mesh_is_turned_out(self):
        sweep = self.add_mesh("Inward", self.box_mesh(0, flip=True))
        hit = self.add("Hit", Part.makeBox(5, 5, 5, V(8, 0, 0)))
        self.doc.recompute()
        r = clearance.check_clearance(sweep, [hit], TOL)[0]
        self.assertAlmostEqual(r.interference_volume, 2 * 5 * 5, delta=1e-6)

    def test_mesh_obstacle(self):
        sweep = self.add("Solid", Part.makeBox(10, 10, 10))
        obst = self.add_mesh("MeshBox", self.box_mesh(12))
        self.doc.recompute()
        r = clearance.check_clearance(sweep, [obst], TOL)[0]
        self.assertEqual((r.status, r.interference_volume), ("clear", 0.0))
        self.assertAlmostEqual(r.min_distance, 2.0, delta=1e-7)

    def test_open_mesh(self):
        mesh = self.box_mesh(0)
        mesh.removeFacets([0, 1])
        open_mesh = self.add_mesh("Open", mesh)
        solid = self.add("Solid", Part.makeBox(1, 1, 1))
        self.doc.recompute()
        r = clearance.check_clearance(solid, [open_mesh], TOL)[0]
        self.assertEqual(r.status, "invalid")
        self.assertIn("not closed", r.message)
        self.assertIn("Open", r.message)
        with self.assertRaises(InputError) as ctx:
            clearance.check_clearance(open_mesh, [solid], TOL)
        self.assertIn("not closed", str(ctx.exception))


class NonSolids(Base):
    def setUp(self):
        super().setUp()
        self.sweep = self.add("Sweep", Part.makeBox(10, 10, 10))
        box = Part.makeBox(3, 3, 3, V(20, 0, 0))
        self.shell = self.add("OpenShell", Part.Shell(box.Faces[:5]))
        self.face = self.add("Face", box.Faces[0])
        sketch = self.doc.addObject("Sketcher::SketchObject", "Sketch")
        sketch.addGeometry(Part.Circle(V(0, 0, 0), V(0, 0, 1), 4))
        self.sketch = sketch
        self.closed_shell = self.add("ClosedShell", Part.Shell(box.Faces))
        self.group = self.doc.addObject("App::DocumentObjectGroup", "Group")
        self.doc.recompute()

    def test_each_non_solid_gets_a_message(self):
        others = [self.shell, self.face, self.sketch, self.group, self.sweep,
                  self.closed_shell]
        res = by_label(clearance.check_clearance(self.sweep, others, TOL))
        want = {"OpenShell": "1 of them open", "Face": "face(s) without a closed shell",
                "Sketch": "edge(s)", "Group": "neither a Shape nor a Mesh",
                "Sweep": "the sweep itself"}
        for label, text in want.items():
            with self.subTest(label=label):
                self.assertEqual(res[label].status, "invalid")
                self.assertIsNone(res[label].min_distance)
                self.assertIn(text, res[label].message)
        # a closed shell bounds a volume: it is checked as a solid
        self.assertEqual(res["ClosedShell"].status, "clear")
        self.assertAlmostEqual(res["ClosedShell"].min_distance, 10.0, delta=1e-7)
        text = clearance.report_text(list(res.values()))
        self.assertIn("0 of 6 object(s) interfere.", text)

    def test_deleted_object(self):
        box = self.add("Gone", Part.makeBox(1, 1, 1))
        self.doc.removeObject("Gone")
        r = clearance.check_clearance(self.sweep, [box], TOL)[0]
        self.assertEqual(r.status, "invalid")
        self.assertIn("deleted", r.message)

    def test_no_sweep_or_a_sketch_as_sweep(self):
        with self.assertRaises(InputError) as ctx:
            clearance.check_clearance(None, [self.sweep], TOL)
        self.assertIn("select the swept volume first", str(ctx.exception))
        with self.assertRaises(InputError) as ctx:
            clearance.check_clearance(self.sketch, [self.sweep], TOL)
        self.assertIn("the sweep: Sketch is not a solid", str(ctx.exception))


class MacroApi(Base):
    def test_sweep_object_and_document_obstacles(self):
        source = self.add("Source", Part.makeBox(20, 10, 5))
        sweep = self.doc.addObject("Part::Feature", "Sweep")
        sweep.Shape = swept_box_solid()
        # the sweep's source is left out of the default obstacles: make Sweep depend on it
        sweep.addProperty("App::PropertyLink", "Source")
        sweep.Source = source
        a = self.add("A", Part.makeBox(5, 5, 5, V(A + 1, 0, 0)))
        self.add("B", Part.makeBox(5, 5, 5, V(A - 1, 0, 0)))
        cut = self.doc.addObject("Part::Cut", "Cut")
        cut.Base, cut.Tool = a, self.add("Tool", Part.makeBox(1, 1, 1, V(A + 1, 0, 0)))
        sketch = self.doc.addObject("Sketcher::SketchObject", "Sketch")
        sketch.addGeometry(Part.LineSegment(V(0, 0, 0), V(1, 0, 0)))
        # the axis from an edge of the frame: the frame is still an obstacle
        frame = self.add("Frame", Part.makeBox(2, 2, 10, V(-2, -2 - 3, 0)))
        sweep.addProperty("App::PropertyLinkSub", "AxisObject")
        sweep.AxisObject = (frame, ["Edge1"])
        self.doc.recompute()
        res = mfgeom.check_clearance(sweep, tolerance=TOL)
        # Source (the sweep's input), A and Tool (the Cut's inputs) and the sketch are out
        self.assertEqual(sorted(r.name for r in res), ["B", "Cut", "Frame"])
        res = by_label(res)
        self.assertEqual(res["B"].status, "interference")
        self.assertAlmostEqual(res["B"].interference_volume, 25.0, delta=1e-6)
        self.assertAlmostEqual(res["Cut"].min_distance, 1.0, delta=1e-7)
        # explicit others, one object alone
        one = mfgeom.check_clearance(sweep, a, tolerance=TOL)
        self.assertEqual([r.name for r in one], ["A"])
        # a document without a sweep feature
        with self.assertRaises(InputError):
            mfgeom.check_clearance(self.doc)

    def test_the_sweep_is_found_by_type_whatever_the_order(self):
        """The sweep feature given after an obstacle (as a selection made in the other
        order) is still the sweep; two sweeps are refused naming both; without a sweep
        feature the first object stands in only where the caller allows it."""
        block = self.add("Block", Part.makeBox(A, B, C))
        self.doc.recompute()
        sweep = mfgeom.make_rotational_sweep(self.doc, block, (0, 0, 0), (0, 0, 1), 90.0,
                                             SWEEP_TOL)
        inside = self.add("Inside", Part.makeBox(1, 1, 1, V(-5, 12, 1)))  # in the box at 90
        far = self.add("Far", Part.makeBox(1, 1, 1, V(A + 10, 0, 0)))
        self.doc.recompute()
        want = mfgeom.check_clearance(sweep, [inside, far], tolerance=TOL)
        self.assertEqual([(r.name, r.status) for r in want],
                         [("Inside", "interference"), ("Far", "clear")])
        for first, rest in ((inside, [sweep, far]), (inside, [far, sweep]), (far, [sweep, inside])):
            for call in (mfgeom.check_clearance, clearance.check_clearance):
                got = by_label(call(first, rest, tolerance=TOL))
                self.assertEqual(sorted(got), ["Far", "Inside"])
                self.assertEqual(got["Inside"].status, "interference")
                self.assertAlmostEqual(got["Inside"].interference_volume, 1.0, delta=1e-9)
                self.assertAlmostEqual(got["Far"].min_distance,
                                       by_label(want)["Far"].min_distance, delta=1e-12)
        before = [o.Name for o in self.doc.Objects]
        other = mfgeom.make_rotational_sweep(self.doc, block, (0, 0, 0), (1, 0, 0), 30.0,
                                             SWEEP_TOL, name="Other")
        before.append(other.Name)
        for call in (mfgeom.check_clearance, clearance.check_clearance):
            with self.assertRaisesRegex(InputError, "2 rotational sweeps selected") as ctx:
                call(inside, [sweep, other], tolerance=TOL)
            self.assertIn(sweep.Label, str(ctx.exception))
            self.assertIn(other.Label, str(ctx.exception))
        self.assertEqual([o.Name for o in self.doc.Objects], before)
        # the command's rule: no stand-in
        with self.assertRaisesRegex(InputError, "no rotational sweep selected .only Inside, Far"):
            clearance.find_sweep([inside, far], stand_in=False)
        self.assertEqual(clearance.find_sweep([inside, far]), (inside, [far]))
        self.assertEqual(clearance.find_sweep([far, sweep, inside], stand_in=False),
                         (sweep, [far, inside]))

    def test_document_with_one_sweep_feature(self):
        class FakeSweep:   # a FeaturePython whose proxy says it is a sweep
            Type = "Mfgeom::RotationalSweep"

            def execute(self, obj):
                pass
        sweep = self.doc.addObject("Part::FeaturePython", "RotationalSweep")
        sweep.Proxy = FakeSweep()
        sweep.Shape = Part.makeBox(10, 10, 10)
        hit = self.add("Hit", Part.makeBox(5, 5, 5, V(8, 0, 0)))
        self.doc.recompute()
        volume = hit.Shape.Volume
        res = mfgeom.check_clearance(self.doc, tolerance=TOL)
        self.assertEqual([r.name for r in res], ["Hit"])
        self.assertAlmostEqual(res[0].interference_volume, 50.0, delta=1e-6)
        # the App layer changes nothing in the document
        self.assertEqual(len(self.doc.Objects), 2)
        self.assertEqual(hit.Shape.Volume, volume)
        self.assertNotIn("Touched", hit.State)


# The library's sweep at a coarse tolerance: its first version makes 4.7e3 triangles of
# this box at 2 mm and 4e6 at 0.01 mm, and OCCT's Booleans grow with the face count.
SWEEP_TOL = 2.0


def library_sweep(vertices, triangles, angle=THETA, tolerance=SWEEP_TOL):
    """The library's sweep about the z axis."""
    from mfgeom import core
    return core.rotational_sweep(vertices, triangles, (0, 0, 0), (0, 0, 1), angle, tolerance)


def point_mesh_distance(p, vertices, triangles):
    """Distance from point p to a triangle mesh: the closest point of each triangle
    (Ericson's region tests, vectorised), the least of them."""
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    best = np.full(len(t), np.inf)
    # the closest point is in the interior, on an edge or at a vertex: take the least of
    # the interior projection (where inside) and the three edge segments
    n = np.cross(b - a, c - a)
    nn = np.einsum("ij,ij->i", n, n)
    ok = nn > 0
    s = np.einsum("ij,ij->i", p - a, n)
    q = p - (s / np.where(ok, nn, 1.0))[:, None] * n
    inside = ok.copy()
    for u, w in ((a, b), (b, c), (c, a)):
        inside &= np.einsum("ij,ij->i", np.cross(w - u, q - u), n) >= 0
    best[inside] = np.abs(s[inside]) / np.sqrt(nn[inside])
    for u, w in ((a, b), (b, c), (c, a)):
        e = w - u
        ee = np.einsum("ij,ij->i", e, e)
        k = np.clip(np.einsum("ij,ij->i", p - u, e) / np.where(ee > 0, ee, 1.0), 0, 1)
        best = np.minimum(best, np.linalg.norm(p - (u + k[:, None] * e), axis=1))
    return float(best.min())


def sphere_mesh_distance(sphere, vertices, triangles):
    """Gap between a Part sphere (outside the mesh) and a triangle mesh."""
    face = sphere.Solids[0].Faces[0] if sphere.Solids else sphere.Faces[0]
    c = face.Surface.Center
    return point_mesh_distance(np.array([c.x, c.y, c.z]), vertices, triangles) \
        - face.Surface.Radius


def mesh_of(vertices, triangles):
    return Mesh.Mesh([[V(*vertices[i]) for i in tri] for tri in triangles])


class RealSweep(Base):
    """The library's sweep of the box [0,A]x[0,B]x[0,C] turned by 90 deg about z (its
    edge), at tolerance SWEEP_TOL: an obstacle inside the swept quarter annulus interferes
    with its whole volume; spheres GAP beyond the arc and 0.25 under the box at t = 0 are
    clear at the distance from their centres to the sweep's triangles (numpy,
    point-triangle) less their radius.  Separately, the sweep's own contract (conservative
    within its tolerance, planar faces exact): the distance beyond the arc in
    [GAP - tol, GAP], under the bottom exactly 0.25."""

    GAP = 3.0

    def setUp(self):
        super().setUp()
        sys.path.insert(0, os.path.join(REPO, "tests", "python"))
        try:
            from sweep_oracle import box_mesh
        finally:
            sys.path.pop(0)
        self.box_v, self.box_t = box_mesh((0, 0, 0), (A, B, C))
        a = math.radians(60)
        # a unit cube around radius 21 at 60 deg: radii 20.3 .. 21.7 (< R), angles 60 +- 2
        # deg, inside [acos(A/r), asin(B/r) + 90 deg] at every such radius
        self.inside = Part.makeBox(1, 1, 1, V(21 * math.cos(a) - 0.5, 21 * math.sin(a) - 0.5, 2))
        self.beyond = sphere_beyond_arc(self.GAP, angle_deg=60.0)
        self.under = Part.makeSphere(2, V(10, 5, -2.25))   # gap 0.25 below z = 0

    def check(self, sweep_obj, tol=TOL, triangles=None):
        # the check's floor is TOL, not the sweep's coarse tolerance (with 2 mm a 1 mm cube
        # is thinner than the floor: a film)
        objs = [self.add("Inside", self.inside), self.add("Beyond", self.beyond),
                self.add("Under", self.under)]
        self.doc.recompute()
        res = by_label(clearance.check_clearance(sweep_obj, objs, tolerance=tol))
        self.assertEqual(res["Inside"].status, "interference", res["Inside"])
        self.assertAlmostEqual(res["Inside"].interference_volume, 1.0, delta=1e-6)
        self.assertEqual(res["Beyond"].status, "clear", res["Beyond"])
        self.assertEqual(res["Under"].status, "clear")
        if triangles is None:   # the exact stand-in
            refs = {"Beyond": self.GAP, "Under": 0.25}
        else:
            refs = {k: sphere_mesh_distance(getattr(self, k.lower()), *triangles)
                    for k in ("Beyond", "Under")}
        for k, ref in refs.items():
            self.assertAlmostEqual(res[k].min_distance, ref, delta=1e-6, msg=k)
        return res

    def test_references_on_the_exact_sweep(self):
        # the same obstacles against the exact stand-in: the references themselves hold
        self.check(self.add("Exact", swept_box_solid()))

    def test_library_mesh_as_the_sweep(self):
        result = library_sweep(self.box_v, self.box_t)
        sweep = self.add_mesh("LibrarySweep", mesh_of(result.vertices, result.triangles))
        self.check(sweep, triangles=(result.vertices, result.triangles))

    def test_sweep_is_conservative_at_the_obstacle(self):
        # The sweep's contract, not the clearance check's: the true swept volume lies
        # inside the result, whose boundary is within the tolerance of the true one, and
        # the planar faces from the input are exact.  (It failed with the first version of
        # the algorithm, 8c9ac72, and was marked an expected failure; it holds now.)
        result = library_sweep(self.box_v, self.box_t)
        self.assertGreaterEqual(result.volume, C * (A * B + (A * A + B * B) * THETA / 2))
        d = sphere_mesh_distance(self.beyond, result.vertices, result.triangles)
        self.assertLessEqual(d, self.GAP + 1e-9)
        self.assertGreaterEqual(d, self.GAP - SWEEP_TOL)
        d = sphere_mesh_distance(self.under, result.vertices, result.triangles)
        self.assertAlmostEqual(d, 0.25, delta=1e-9)

    def test_sweep_feature(self):
        source = self.add("Block", Part.makeBox(A, B, C))
        self.doc.recompute()
        sweep = mfgeom.make_rotational_sweep(self.doc, source, (0, 0, 0), (0, 0, 1), 90.0,
                                             SWEEP_TOL)
        self.assertTrue(sweep.isValid(), sweep.getStatusString())
        points, facets = sweep.Mesh.Topology   # the feature's (single precision) mesh
        self.check(sweep, triangles=(np.array([(p.x, p.y, p.z) for p in points]),
                                     np.array(facets)))
        self.assertEqual(clearance.default_tolerance(sweep), SWEEP_TOL)   # its own
        # by the document: the source is left out of the obstacles
        names = sorted(r.name for r in mfgeom.check_clearance(self.doc, tolerance=TOL))
        self.assertEqual(names, ["Beyond", "Inside", "Under"])


def grid_box_mesh(size, n, origin=(0.0, 0.0, 0.0)):
    """A cube mesh of side ``size`` with each face cut into n x n squares (2 n^2
    triangles each, outward): many planar triangles, exact distances."""
    o = np.asarray(origin, dtype=np.float64)
    facets = []
    ticks = np.linspace(0.0, size, n + 1)
    for axis in range(3):
        u, w = (axis + 1) % 3, (axis + 2) % 3     # e_u x e_w = e_axis
        for side in (0.0, size):
            for i in range(n):
                for j in range(n):
                    quad = []
                    for du, dw in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = np.zeros(3)
                        p[axis], p[u], p[w] = side, ticks[i + du], ticks[j + dw]
                        quad.append(V(*(o + p)))
                    if side == 0.0:
                        quad.reverse()
                    facets += [[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]]
    return Mesh.Mesh(facets)


class Pruning(Base):
    """The pruned distance (many sweep faces) against OCCT's plain distToShape and
    analytic gaps, and the Boolean skipped when the boundaries are apart."""

    @classmethod
    def setUpClass(cls):
        cls.mesh = grid_box_mesh(10.0, 6)      # 432 triangles

    def setUp(self):
        super().setUp()
        self.sweep = self.add_mesh("Grid", self.mesh)
        self.saved = clearance._DIRECT_PAIRS
        clearance._DIRECT_PAIRS = 0          # always prune

    def tearDown(self):
        clearance._DIRECT_PAIRS = self.saved
        super().tearDown()

    def test_mesh_is_what_it_should_be(self):
        self.assertTrue(self.mesh.isSolid())
        self.assertEqual(self.mesh.CountFacets, 6 * 2 * 6 * 6)
        self.assertAlmostEqual(self.mesh.Volume, 1000.0, delta=0.05)   # float kernel

    def test_analytic_gaps(self):
        objs = [self.add("Side", Part.makeBox(3, 3, 3, V(12.5, 4, 4))),        # 2.5
                self.add("Corner", Part.makeSphere(1, V(13, 14, 10))),          # 5 - 1
                self.add("Edge", Part.makeCylinder(0.5, 4, V(12, 13, 3))),  # to x=y=10
                self.add("Below", Part.makeBox(20, 20, 1, V(-5, -5, -1.75)))]    # 0.75
        self.doc.recompute()
        res = by_label(clearance.check_clearance(self.sweep, objs, TOL))
        for label, d in (("Side", 2.5), ("Corner", 4.0), ("Edge", math.hypot(2, 3) - 0.5),
                         ("Below", 0.75)):
            self.assertEqual(res[label].status, "clear")
            self.assertAlmostEqual(res[label].min_distance, d, delta=1e-6, msg=label)

    def test_pruned_equals_plain_on_random_obstacles(self):
        rng = np.random.default_rng(8)
        sweep = clearance.solid_of(self.sweep)
        faces = clearance.FaceBoxes(sweep)
        for k in range(8):
            centre = rng.uniform(-8, 18, 3)
            if np.all((centre > -1) & (centre < 11)):
                centre[rng.integers(3)] += 13.0
            r = rng.uniform(0.3, 2.0)
            shape = (Part.makeSphere(r, V(*centre)) if k % 2 else
                     Part.makeBox(r, 2 * r, r, V(*centre)))
            if sweep.common(shape).Volume > 0:
                continue
            plain = sweep.distToShape(shape)[0]
            pruned, p, q = clearance.min_distance(sweep, shape, faces)
            self.assertAlmostEqual(pruned, plain, delta=1e-9, msg=str(centre))
            self.assertAlmostEqual((p - q).Length, pruned, delta=1e-9)

    def test_boolean_skipped_when_apart(self):
        inner = self.add("Inner", Part.makeBox(2, 2, 2, V(4, 4, 4)))    # no face near
        outer = self.add("Outer", Part.makeBox(30, 30, 30, V(-10, -10, -10)))
        far = self.add("Far", Part.makeBox(1, 1, 1, V(20, 20, 20)))
        self.doc.recompute()
        sweep = clearance.solid_of(self.sweep)
        faces = clearance.FaceBoxes(sweep)
        # no face of the sweep near Inner's or Far's box: the common without a Boolean
        for obj, volume in ((inner, 8.0), (far, 0.0)):
            self.assertEqual(len(faces.near(clearance._box(obj.Shape.BoundBox), TOL)), 0)
            self.assertAlmostEqual(clearance._common(sweep, obj.Shape, TOL, faces).Volume,
                                   volume, delta=1e-9)
        res = by_label(clearance.check_clearance(self.sweep, [inner, outer, far], TOL))
        self.assertEqual(res["Inner"].status, "interference")
        self.assertAlmostEqual(res["Inner"].interference_volume, 8.0, delta=1e-9)
        self.assertEqual(res["Outer"].status, "interference")
        self.assertAlmostEqual(res["Outer"].interference_volume, 1000.0, delta=1e-6)
        self.assertEqual(res["Far"].status, "clear")
        self.assertAlmostEqual(res["Far"].min_distance, math.sqrt(3) * 10, delta=1e-9)


class MeshEngine(Base):
    """The mesh sweep's own engine (MeshSweep: numpy bounds, OCCT only near, General
    Fuse of the obstacle) against analytic values on a cube mesh of many triangles, and
    against OCCT's Boolean common and distance on the same cube as a Part solid."""

    @classmethod
    def setUpClass(cls):
        cls.mesh = grid_box_mesh(10.0, 6)      # [0, 10]^3, 432 triangles

    def setUp(self):
        super().setUp()
        self.sweep = self.add_mesh("Grid", self.mesh)

    def test_films_contacts_and_curved_commons(self):
        r = 2.0
        objs = [self.add("Touch", Part.makeBox(5, 5, 5, V(10, 2, 2))),          # a face
                self.add("Film", Part.makeBox(5, 5, 5, V(10 - 0.004, 2, 2))),   # < TOL
                self.add("Thin", Part.makeBox(5, 5, 5, V(10 - 0.05, 2, 2))),    # > TOL
                # a cylinder through the cube along x: common pi r^2 10
                self.add("Rod", Part.makeCylinder(r, 30, V(-10, 5, 5), V(1, 0, 0))),
                # a ball half in: common 2/3 pi r^3
                self.add("Ball", Part.makeSphere(r, V(10, 5, 5))),
                # a ball 0.5 above the top, a torus around the cube (it holds the cube's
                # middle: the boundaries never meet, the distance is the gap to its tube)
                self.add("Above", Part.makeSphere(1, V(5, 5, 11.5))),
                self.add("Ring", Part.makeTorus(12, 1, V(5, 5, 5)))]
        self.doc.recompute()
        res = by_label(clearance.check_clearance(self.sweep, objs, TOL))
        want = {"Touch": ("touching", 0.0, 0.0), "Film": ("touching", 0.0, 0.0),
                "Thin": ("interference", 0.05 * 25, 0.0),
                "Rod": ("interference", math.pi * r * r * 10, 0.0),
                "Ball": ("interference", 2.0 / 3.0 * math.pi * r ** 3, 0.0),
                "Above": ("clear", 0.0, 0.5),
                "Ring": ("clear", 0.0, 11.0 - math.hypot(5, 5))}
        for label, (status, volume, distance) in want.items():
            with self.subTest(label=label):
                got = res[label]
                self.assertEqual(got.status, status, got)
                # OCCT's volumes of curved solids hold ~1e-6 relative
                self.assertAlmostEqual(got.interference_volume, volume,
                                       delta=1e-6 * max(1.0, volume))
                self.assertAlmostEqual(got.min_distance, distance, delta=1e-7)
                if got.interferes:
                    obj = self.doc.getObject(label).Shape
                    self.assertTrue(obj.isInside(got.point_on_object, 1e-6, True))
                    self.assertLess(got.common.Volume - got.interference_volume, 1e-9)

    def test_the_same_answers_as_occt_on_the_part_solid(self):
        """Random boxes and balls: the mesh engine and OCCT's Boolean common and
        distance on the cube as a Part solid give the same status, volume and
        distance."""
        rng = np.random.default_rng(9)
        cube = self.add("Cube", Part.makeBox(10, 10, 10))
        objs = []
        for k in range(14):
            c = rng.uniform(-4, 14, 3)
            size = rng.uniform(0.5, 4.0)
            shape = (Part.makeSphere(size / 2, V(*c)) if k % 2 else
                     Part.makeBox(size, 1.5 * size, size, V(*c)))
            objs.append(self.add(f"O{k}", shape))
        self.doc.recompute()
        mesh = by_label(clearance.check_clearance(self.sweep, objs, TOL))
        occt = by_label(clearance.check_clearance(cube, objs, TOL))
        statuses = set()
        for label, want in occt.items():
            got = mesh[label]
            with self.subTest(label=label):
                self.assertEqual(got.status, want.status, (got, want))
                self.assertAlmostEqual(got.interference_volume, want.interference_volume,
                                       delta=1e-6 * max(1.0, want.interference_volume))
                self.assertAlmostEqual(got.min_distance, want.min_distance, delta=1e-7)
            statuses.add(want.status)
        self.assertTrue({"interference", "clear"} <= statuses, statuses)


class Sampling(unittest.TestCase):
    """The fallback for sweep solids OCCT finds invalid: parity of ray crossings and a
    sampled common volume, against a box mesh."""

    @staticmethod
    def box_triangles():
        points, facets = Part.makeBox(10, 10, 10).tessellate(0.1)
        xyz = np.array([(p.x, p.y, p.z) for p in points])
        return xyz[np.array(facets).reshape(-1, 3)]

    def test_inside_mesh(self):
        rng = np.random.default_rng(3)
        pts = rng.uniform(-5, 15, (500, 3))
        want = np.all((pts > 0) & (pts < 10), axis=1)
        np.testing.assert_array_equal(clearance.inside_mesh(pts, self.box_triangles()), want)

    def test_sampled_volume(self):
        obstacle = Part.makeBox(4, 5, 5, V(8, 0, 0))      # common 2 x 5 x 5 = 50
        volume, se, point = clearance.sampled_common_volume(
            self.box_triangles(), (8, 0, 0, 10, 5, 5), obstacle)
        self.assertLess(abs(volume - 50.0), 4 * se + 1e-9)
        self.assertTrue(obstacle.isInside(point, 0, True) and 8 <= point.x <= 10)
        volume, se, point = clearance.sampled_common_volume(
            self.box_triangles(), (11, 0, 0, 12, 5, 5), Part.makeBox(1, 5, 5, V(11, 0, 0)))
        self.assertEqual((volume, point), (0.0, None))


class DefaultTolerance(Base):
    def test_the_sweeps_own_tolerance_sets_the_floor(self):
        sweep = self.add("Sweep", Part.makeBox(10, 10, 10))
        sweep.addProperty("App::PropertyLength", "Tolerance")
        sweep.Tolerance = 0.1
        film = self.add("Film", Part.makeBox(5, 5, 5, V(10 - 0.05, 0, 0)))
        self.doc.recompute()
        self.assertEqual(clearance.default_tolerance(sweep), 0.1)
        r = clearance.check_clearance(sweep, [film])[0]   # 0.05 < 0.1: a film
        self.assertEqual((r.status, r.interference_volume), ("touching", 0.0))
        r = clearance.check_clearance(sweep, [film], tolerance=0.01)[0]
        self.assertAlmostEqual(r.interference_volume, 0.05 * 25, delta=1e-8)
        plain = self.add("Plain", Part.makeBox(1, 1, 1))
        from mfgeom.app import preferences
        self.assertEqual(clearance.default_tolerance(plain), preferences.default_tolerance())


class Palette(unittest.TestCase):
    def test_interference_colour_stands_apart(self):
        from mfgeom import palette

        def worst(others):
            return min(palette.contrast(palette.INTERFERENCE, o, v)
                       for v in palette.VISIONS for o in others)
        self.assertGreater(worst([palette.SELECTION, palette.PRESELECTION]), 100)
        self.assertGreater(worst([palette.SHAPE_GREY, *palette.BACKGROUND]), 40)



sys.exit(run_file(globals(), "freecad-clearance"))
