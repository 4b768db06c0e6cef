# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD App tests of the wall-thickness analysis (issue 21, section 4), run by
``freecadcmd``.

Run through tests/run_freecad_tests.sh, or directly:
``MFGEOM_LIBRARY=build/libmfgeom.so freecadcmd tests/freecad/test_thickness_app.py``.
Prints ``freecad-thickness: N passed, M failed`` last and exits non-zero on any failure.

References independent of the code under test: analytic walls (a plate is its thickness
at every sample, corners and edges included; the bundled tray's floor 3, rib 2 and its
thickest spot, the ball into a wall / wall / floor corner, 2 r = 3 * 2 sqrt 3 / (1 + sqrt
3)); the bundled cup's wall within the tessellation's sag; a part of the corpus (OCCT's
bottle, a shelled solid) against a ray cast with OCCT along the inward normal where the
wall's two sides are parallel; plus the feature's behaviour: moved and turned parts,
recompute on change, save and reload, CSV and histogram, bad input leaving the document
unchanged.
"""

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
for _path in (os.path.join(REPO, "examples", "parts"), os.path.join(REPO, "tests", "corpus"),
              os.path.join(REPO, "workbench")):
    if _path not in sys.path:
        sys.path.append(_path)

import cup  # noqa: E402
import thin_wall  # noqa: E402
import mfgeom  # noqa: E402
from mfgeom.app import thickness_feature as tf  # noqa: E402

sys.path.insert(0, HERE)
from fc_testsupport import DocumentTestCase, run_file  # noqa: E402

CORNER = 3.0 * 2 * math.sqrt(3) / (1 + math.sqrt(3))   # tray: wall / wall / floor corner


def samples(a):
    pts = np.array([(p.x, p.y, p.z) for p in a.SamplePoints]).reshape(-1, 3)
    return pts, np.asarray(a.VertexThickness), np.asarray(a.SampleFaces)


def add(doc, name, shape, placement=None):
    obj = doc.addObject("Part::Feature", name)
    obj.Shape = shape
    if placement is not None:
        obj.Placement = placement
    doc.recompute()
    return obj


class PlateTests(DocumentTestCase):
    def test_plate_everywhere(self):
        """A 100 x 60 x 4 plate is 4 thick at every sample (faces, edges, corners), as
        built and moved and turned; the area fractions follow the thresholds."""
        for k, pl in enumerate((None, App.Placement(App.Vector(300, -20, 7),
                                                    App.Rotation(App.Vector(1, 2, 3), 37)))):
            obj = add(self.doc, f"Plate{k}", Part.makeBox(100, 60, 4), pl)
            a = mfgeom.make_thickness_analysis(self.doc, obj, 3.0, 5.0, name=f"T{k}")
            _p, t, f = samples(a)
            self.assertTrue(a.isValid())
            self.assertLess(np.abs(t - 4.0).max(), 1e-6)
            self.assertEqual(sorted(set(f.tolist())), list(range(6)))
            self.assertAlmostEqual(a.ThinFraction, 0.0)
            self.assertAlmostEqual(a.ThickFraction, 0.0)
            self.assertEqual(list(a.ThinFaces), [])
            a.MinThickness = 4.5
            self.doc.recompute()
            self.assertAlmostEqual(a.ThinFraction, 1.0)
            self.assertEqual(len(a.ThinFaces), 6)


class TrayTests(DocumentTestCase):
    def setUp(self):
        super().setUp()
        self.part = add(self.doc, "Tray", thin_wall.make())
        self.a = mfgeom.make_thickness_analysis(self.doc, self.part, 2.5, 3.6)

    def test_analytic_values(self):
        a = self.a
        tol = a.Tolerance.Value
        self.assertAlmostEqual(a.Thinnest, thin_wall.RIB, delta=1e-6)
        self.assertAlmostEqual(a.Thickest, CORNER, delta=2 * tol)
        pts, t, _f = samples(a)
        L, W = thin_wall.LENGTH, thin_wall.WIDTH
        # the floor's underside away from the walls and the rib: 3 exactly
        floor = ((np.abs(pts[:, 2]) < 1e-9) & (pts[:, 0] > 8) & (pts[:, 0] < 22)
                 & (pts[:, 1] > 8) & (pts[:, 1] < W - 8))
        self.assertGreater(floor.sum(), 20)
        self.assertLess(np.abs(t[floor] - thin_wall.WALL).max(), 1e-6)
        # the rib's sides above the floor's corner region: 2 exactly
        rib = ((np.abs(np.abs(pts[:, 0] - L / 2) - thin_wall.RIB / 2) < 1e-9)
               & (pts[:, 2] > thin_wall.WALL + 3) & (pts[:, 1] > 6) & (pts[:, 1] < W - 6))
        self.assertGreater(rib.sum(), 20)
        self.assertLess(np.abs(t[rib] - thin_wall.RIB).max(), 1e-6)
        # thin: the rib (2 < 2.5), and only where the rib is; thick: the corners (> 3.6)
        rib_faces = {i for i, face in enumerate(self.part.Shape.Faces)
                     if abs(face.CenterOfMass.x - L / 2) < thin_wall.RIB}
        thin = {int(n[4:]) - 1 for n in a.ThinFaces}
        self.assertTrue(rib_faces & thin, (rib_faces, thin))
        self.assertLess(a.ThinFraction, 0.2)
        self.assertGreater(a.ThinFraction, 0.02)
        self.assertGreater(len(a.ThickFaces), 0)

    def test_histogram_and_csv(self):
        a = self.a
        edges, areas = tf.histogram_of(a)
        self.assertEqual(len(edges), len(areas) + 1)
        self.assertAlmostEqual(edges[0], a.Thinnest, places=9)
        self.assertAlmostEqual(edges[-1], a.Thickest, places=9)
        # every sample's area is counted once: the planar part's area exactly
        self.assertAlmostEqual(float(areas.sum()), self.part.Shape.Area,
                               delta=1e-6 * self.part.Shape.Area)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "t.csv")
            rows = tf.write_csv(a, path)
            self.assertEqual(rows, len(a.VertexThickness))
            with open(path, newline="") as f:
                lines = list(csv.reader(f))
            self.assertEqual(lines[0], ["x_mm", "y_mm", "z_mm", "face", "thickness_mm",
                                        "status"])
            body = lines[1:1 + rows]
            self.assertEqual(sum(r[5] == "thin" for r in body),
                             int((np.asarray(a.VertexThickness) < 2.5).sum()))
            self.assertEqual(os.listdir(d), ["t.csv"])
            with self.assertRaises(OSError):   # a folder that is not there: nothing written
                tf.write_csv(a, os.path.join(d, "missing", "t.csv"))
            self.assertEqual(os.listdir(d), ["t.csv"])

    def test_recompute_on_move_and_reload(self):
        a = self.a
        before = a.ThickestPoint
        self.part.Placement = App.Placement(App.Vector(10, 20, 30), App.Rotation())
        self.doc.recompute()
        self.assertTrue(a.isValid())
        self.assertAlmostEqual(a.Thickest, CORNER, delta=2 * a.Tolerance.Value)
        self.assertAlmostEqual(a.Thinnest, thin_wall.RIB, delta=1e-6)
        moved = a.ThickestPoint - before
        self.assertLess((moved - App.Vector(10, 20, 30)).Length, 40)   # a corner, moved
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "tray.FCStd")
            self.doc.saveAs(path)
            name = a.Name
            values = list(a.VertexThickness)
            App.closeDocument(self.doc.Name)
            self.doc = App.openDocument(path)
            b = self.doc.getObject(name)
            self.assertEqual(list(b.VertexThickness), values)
            self.assertTrue(tf.is_thickness_analysis(b))
            b.touch()
            self.doc.recompute()
            self.assertTrue(b.isValid(), b.getStatusString())
            self.assertLess(np.abs(np.asarray(b.VertexThickness) - values).max(), 1e-9)


class CurvedTests(DocumentTestCase):
    def test_cup_wall(self):
        """The cup (R 20, wall 3, bottom 4): samples on the cylinder walls halfway up are
        3 within twice the deflection (each side's chords) and the tolerance."""
        obj = add(self.doc, "Cup", cup.make())
        a = mfgeom.make_thickness_analysis(self.doc, obj, 2.0, 5.0)
        pts, t, _f = samples(a)
        r = np.hypot(pts[:, 0], pts[:, 1])
        allow = 2 * a.Deflection.Value + 2 * a.Tolerance.Value
        wall = (pts[:, 2] > 10) & (pts[:, 2] < 24) & (r > cup.RADIUS - 0.5)
        self.assertGreater(wall.sum(), 50)
        self.assertLess(np.abs(t[wall] - cup.WALL).max(), allow)
        bottom = (np.abs(pts[:, 2]) < 1e-9) & (r < cup.RADIUS - 8)
        self.assertGreater(bottom.sum(), 20)
        self.assertLess(np.abs(t[bottom] - cup.BOTTOM).max(), 2 * a.Tolerance.Value)


def ray_thickness(shape, p, n):
    """The distance from p along -n to the part's boundary (OCCT): the ray-cast peer."""
    length = shape.BoundBox.DiagonalLength
    q = App.Vector(*p)
    d = App.Vector(*(-np.asarray(n)))
    edge = Part.LineSegment(q + d * (1e-6 * length), q + d * length).toShape()
    hits = [v.Point for v in shape.section(edge).Vertexes]
    far = [(h - q).Length for h in hits if (h - q).Length > 1e-5 * length]
    return min(far) if far else float("nan")


class CorpusTests(DocumentTestCase):
    def test_bottle(self):
        """OCCT's bottle (a shelled solid, filleted body, threaded neck): valid result;
        where the wall's sides are parallel (samples on the body's planar side walls
        whose ray along the inward normal meets the other side square), ball and ray
        agree within the tolerance."""
        import corpus
        part = [p for p in corpus.parts() if p.file.startswith("bottle")][0]
        _name, solids = corpus.load(part)
        obj = add(self.doc, "Bottle", solids[0])
        a = mfgeom.make_thickness_analysis(self.doc, obj, 0.5, 3.0)
        self.assertTrue(a.isValid(), a.getStatusString())
        pts, t, f = samples(a)
        # The tutorial shells the body with MakeThickSolid at myThickness / 50 = 0.6 mm
        # (OCCT's MakeBottle): the walls are 0.6 whatever their shape (planes, cylinders,
        # tori, spheres of the fillets); only the thread's knife-edge crests go to 0.
        self.assertAlmostEqual(float(np.median(t)), 0.6, delta=0.01)
        self.assertGreater(float(np.mean(np.abs(t - 0.6) <= 0.015)), 0.85)
        self.assertAlmostEqual(a.Thinnest, 0.0, delta=0.05)
        shape = obj.Shape
        planes = [i for i, face in enumerate(shape.Faces) if face.Surface.TypeId == "Part::GeomPlane"]
        rng = np.random.default_rng(3)
        tol = 2 * a.Tolerance.Value
        agree = shorter = total = 0
        for i in rng.permutation(np.flatnonzero(np.isin(f, planes)))[:100]:
            face = shape.Faces[f[i]]
            u, v = face.Surface.parameter(App.Vector(*pts[i]))
            n = face.normalAt(u, v)
            ray = ray_thickness(shape, pts[i], (n.x, n.y, n.z))
            if not math.isfinite(ray):
                continue
            total += 1
            agree += abs(ray - t[i]) <= tol
            # the maximal ball tangent at a sample lies on its inward normal, so the ray
            # runs through the ball's diameter: a ray shorter than the ball is wrong
            # (only a sample that takes a neighbouring wall's ball may differ)
            shorter += ray < t[i] - tol
        self.assertGreater(total, 30)
        self.assertGreater(agree, 0.5 * total, (agree, total))
        self.assertLess(shorter, 0.05 * total, (shorter, total))


class BadInputTests(DocumentTestCase):
    def test_refusals_leave_the_document(self):
        box = add(self.doc, "Box", Part.makeBox(10, 10, 10))
        plane = add(self.doc, "Face", Part.makePlane(10, 10))
        count = len(self.doc.Objects)
        for args, words in (((plane, 1.0, 2.0), "not a solid"),
                            ((box, 2.0, 1.0), "must be below"),
                            ((box, float("nan"), 2.0), "finite"),
                            ((box, "3 deg", 2.0), "length"),
                            ((None, 1.0, 2.0), "source")):
            with self.assertRaises(Exception) as info:
                mfgeom.make_thickness_analysis(self.doc, *args)
            self.assertIn(words, str(info.exception))
            self.assertEqual(len(self.doc.Objects), count)
        # a spacing far too fine is refused before any sample is made (it once ate 18 GB)
        with self.assertRaises(tf.ThicknessInputError) as info:
            tf.sample_mesh(box.Shape, 0.1, 1e-4)
        self.assertIn("choose a larger spacing", str(info.exception))
        # a working analysis whose source becomes a non-solid: its recompute fails with a
        # message (called directly: FreeCAD 0.20 prints a failed recompute's traceback)
        a = mfgeom.make_thickness_analysis(self.doc, box, 1.0, 20.0)
        values = list(a.VertexThickness)
        a.Source = plane
        with self.assertRaises(Exception) as info:
            a.Proxy._execute(a)
        self.assertIn("not a solid", str(info.exception))
        self.assertEqual(list(a.VertexThickness), values)


sys.exit(run_file(globals(), "freecad-thickness"))
