# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD App tests of the parting analysis foundation (Gaussian maps of real faces, edge
kinds, mould / NC answers on the bundled example parts), run by ``freecadcmd``.

Run through tests/run_freecad_tests.sh, or directly:
``MFGEOM_LIBRARY=build/libmfgeom.so freecadcmd tests/freecad/test_parting_app.py``.
Prints ``freecad-parting: N passed, M failed`` last and exits non-zero on any failure.

References are independent of the code under test: dense normals from OCCT's
``Face.normalAt`` on a fine UV grid of each true face (points outside the trimmed face
dropped) and 10^4 Fibonacci directions counted by brute force."""

import json
import math
import os
import sys
import time
import unittest

import numpy as np

import FreeCAD as App
import Part

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
for _path in (os.path.join(REPO, "examples", "parts"), os.path.join(REPO, "workbench")):
    if _path not in sys.path:
        sys.path.append(_path)

import bspline_part  # noqa: E402
import cup  # noqa: E402
import cup_hole  # noqa: E402
import draft_flip  # noqa: E402
import pocket_block  # noqa: E402
from mfgeom import core, parting  # noqa: E402
from mfgeom.app import gauss_map  # noqa: E402

X, Y, Z = np.eye(3)
PLACEMENT = App.Placement(App.Vector(5, -7, 11), App.Rotation(App.Vector(1, 2, 3), 37))
CONTAINER = App.Placement(App.Vector(-3, 2, 1), App.Rotation(App.Vector(0, 1, -1), 71))
EXAMPLES = {"cup": cup, "cup_hole": cup_hole, "pocket_block": pocket_block,
            "draft_flip": draft_flip, "bspline_part": bspline_part}
TIMES = []
_SHAPES = {}
_DENSE = {}


def example(name):
    if name not in _SHAPES:
        _SHAPES[name] = EXAMPLES[name].make()
    return _SHAPES[name]


def rot_matrix(pl):
    m = pl.Rotation.toMatrix()
    return np.array([[m.A11, m.A12, m.A13], [m.A21, m.A22, m.A23], [m.A31, m.A32, m.A33]])


def dense_normals(face, k=48):
    """Normals of the true face on a k x k UV grid (points outside its domain dropped)."""
    u0, u1, v0, v1 = face.ParameterRange
    out = []
    for u in np.linspace(u0, u1, k):
        for v in np.linspace(v0, v1, k):
            if face.isPartOfDomain(float(u), float(v)):
                n = face.normalAt(float(u), float(v))
                out.append((n.x, n.y, n.z))
    return np.array(out)


def _vec(a):
    return App.Vector(*[float(c) for c in a])


def run(source, mode="Mould", draft=0.0, **kw):
    t0 = time.perf_counter()
    faces, adj, shape = gauss_map.part_gauss(source)
    t1 = time.perf_counter()
    if mode == "Mould":
        r = parting.mould_parting(faces, adj, draft_angle=draft, **kw)
    else:
        r = parting.nc_setups(faces, adj, tilt=draft, **kw)
    TIMES.append((len(faces), mode, round(draft, 4), t1 - t0, time.perf_counter() - t1))
    return r, faces, shape


def names(r, surfaces):
    return sorted(f"Face{f + 1}" for f in r.faces_of(surfaces))


def brute_force(test, r, shape, draft, mould, key):
    """No Fibonacci direction covers more (dense normals of the true faces), and the
    returned direction is valid on the dense normals of the surfaces it covers."""
    if key not in _DENSE:
        _DENSE[key] = [dense_normals(f, 40) for f in shape.Faces]
    per_face = _DENSE[key]
    # repeated normals (planar faces) do not change min/max: drop them (memory)
    dense = [np.unique(np.round(np.vstack([per_face[f] for f in s.faces]), 13), axis=0)
             for s in r.surfaces]
    dirs = parting.fibonacci_sphere(10000)
    # Mould chooses its direction without the draft (the draft classifies faces)
    sin_d = 0.0 if mould else math.sin(draft)
    eps = 2 * math.sin(parting.DEFAULT_TOL)   # every answer holds up to the tolerance
    counts = np.zeros(len(dirs))
    for s in r.considered:
        dots = dirs @ dense[s].T
        ok = dots.min(axis=1) >= sin_d
        if mould:
            ok |= dots.max(axis=1) <= -sin_d
        counts += r.surfaces[s].weight * ok
    test.assertLessEqual(counts.max(), r.count + 1e-9)
    for s in r.covered:
        dots = dense[s] @ r.direction
        side = r.side[s] if mould else 1
        if side == 0:
            test.assertLess(np.abs(dots).max(), eps)
        else:
            test.assertGreaterEqual((side * dots).min(), sin_d - eps, f"surface {s}")


class EdgeKinds(unittest.TestCase):
    def test_box_with_pocket(self):
        box = Part.makeBox(10, 10, 10).cut(Part.makeBox(4, 4, 5, App.Vector(3, 3, 5)))
        box.Placement = PLACEMENT
        self.assertTrue(any(f.Orientation == "Reversed" for f in box.Faces))
        adj = gauss_map.adjacency(box)
        kinds = {}
        for i, j, kind in adj:
            kinds.setdefault(kind, []).append((i, j))
        self.assertEqual(len(adj), 12 + 12)
        # the pocket: four walls and a floor, joined by 8 concave edges
        pocket = {i for e in kinds["concave"] for i in e}
        self.assertEqual(len(kinds["concave"]), 8)
        self.assertEqual(len(pocket), 5)
        floor = [i for i in pocket if abs(box.Faces[i].Area - 16) < 1e-9]
        self.assertEqual(len(floor), 1)
        self.assertNotIn("tangent", kinds)

    def test_fillet_is_tangent_and_groove_concave(self):
        box = Part.makeBox(10, 10, 10)
        top_edge = [e for e in box.Edges
                    if abs(e.BoundBox.ZMin - 10) < 1e-9 and abs(e.BoundBox.ZMax - 10) < 1e-9][0]
        filleted = box.makeFillet(2, [top_edge])
        adj = gauss_map.adjacency(filleted)
        self.assertEqual(sum(k == "tangent" for _, _, k in adj), 2)
        self.assertEqual(sum(k == "concave" for _, _, k in adj), 0)
        groove = Part.makeBox(10, 10, 10).cut(
            Part.makeCylinder(2, 10, App.Vector(5, 0, 10), App.Vector(0, 1, 0)))
        adj = gauss_map.adjacency(groove)
        self.assertEqual(sum(k == "concave" for _, _, k in adj), 0)  # a round groove: convex rims
        groups, _ = parting.concave_surfaces(len(groove.Faces), adj)
        self.assertEqual(len(groups), len(groove.Faces))

    def test_adjacency_agrees_with_edge_by_edge_kinds(self):
        """adjacency's linear path (how each shared edge runs in each face recorded while
        listing the faces' edges; a plane's normal evaluated once) finds every shared
        edge once, with the kind edge_kind gives on its own (searching the face's edges,
        normals at the edge's point), on a turned plate with pockets, holes, a drill
        point, a filleted pocket and a boss."""
        plate = Part.makeBox(40, 30, 10)
        cuts = [Part.makeBox(6, 5, 4, App.Vector(3, 3, 7)),
                Part.makeCylinder(2.5, 5, App.Vector(15, 6, 6)),
                Part.makeCylinder(2, 5, App.Vector(25, 6, 6)).fuse(
                    Part.makeCone(0, 2, 1.2, App.Vector(25, 6, 4.8))).removeSplitter(),
                Part.makeCylinder(1.5, 40, App.Vector(5, 20, 5), App.Vector(1, 0, 0.3))]
        box = Part.makeBox(7, 6, 4, App.Vector(28, 18, 7))
        cuts.append(box.makeFillet(1.2, [e for e in box.Edges if e.BoundBox.ZLength > 1]))
        part = plate
        for tool in cuts:
            part = part.cut(tool)
        part = part.fuse(Part.makeCylinder(2.5, 3, App.Vector(15, 22, 10)))
        part.Placement = PLACEMENT
        faces = part.Faces
        adj = gauss_map.adjacency(part)
        shared = [e for e in part.Edges
                  if not e.Degenerated and len(part.ancestorsOfType(e, Part.Face)) == 2]
        self.assertEqual(len(adj), len(shared))
        self.assertEqual({k for _, _, k in adj}, {"concave", "convex", "tangent"})
        found = {}
        for i, j, kind in adj:
            found.setdefault((i, j), []).append(kind)
        for (i, j), kinds in found.items():   # a pair of faces may share several edges
            edges = [e for e in faces[i].Edges if any(e.isSame(x) for x in faces[j].Edges)]
            alone = sorted(gauss_map.edge_kind(e, faces[i], faces[j]) for e in edges)
            self.assertEqual(sorted(kinds), alone, (i, j))


class GaussMaps(unittest.TestCase):
    def assert_valid_bound(self, face, g):
        """Every direction in the samples' map shrunk by g.shrink sees every dense
        normal of the true face: the shrink is a real bound."""
        dense = dense_normals(face)
        dirs = parting.fibonacci_sphere(4000)
        ok = (dirs @ g.normals.T).min(axis=1) >= math.sin(g.shrink)
        if ok.any():
            worst = (dirs[ok] @ dense.T).min()
            self.assertGreaterEqual(worst, -1e-9, g.name)
        # the map's vertices are its extreme directions: the sharpest check
        vm = core.visibility_map(g.normals, draft_angle=g.shrink)
        if vm.kind != "null":
            self.assertGreaterEqual((vm.vertices @ dense.T).min(), -1e-9, g.name)
        # and the samples are normals of the face: none is outside the dense normals'
        # spread by more than the grid's resolution
        self.assertLess(np.arccos(np.clip(g.normals @ dense.T, -1, 1)).min(axis=1).max(), 0.2)

    def test_kinds_and_exactness(self):
        o, z = App.Vector(), App.Vector(0, 0, 1)
        shapes = {"plane": Part.makeBox(1, 2, 3).Faces[0],
                  "cylinder": Part.makeCylinder(2, 5, o, z, 250).Faces[0],
                  "cone": Part.makeCone(3, 1, 4).Faces[0],
                  # patches whose maps are not empty, so the bound check has vertices
                  "sphere": Part.makeSphere(3, o, z, 20, 70, 120).Faces[0],
                  "torus": Part.makeTorus(5, 1, o, z, 20, 70, 120).Faces[0],
                  "bspline": [f for f in example("bspline_part").Faces
                              if isinstance(f.Surface, Part.BSplineSurface)][0]}
        for name, face in shapes.items():
            face = face.copy()
            face.Placement = PLACEMENT
            g = gauss_map.face_gauss(face, name=name)
            if name in ("plane", "cylinder", "bspline"):   # B-spline: its control net's bound
                self.assertEqual(g.shrink, 0.0, name)
            else:
                self.assertGreater(g.shrink, 0.0, name)
                self.assertLessEqual(g.shrink, gauss_map.DEFAULT_DEFLECTION, name)
            if name == "plane":
                self.assertEqual(len(g.normals), 1)
            self.assertNotEqual(core.visibility_map(g.normals, draft_angle=g.shrink).kind, "null")
            self.assert_valid_bound(face, g)

    def test_cone_samples_are_the_normals_at_their_parameters(self):
        """A cone's samples (normals along a parallel from three OCCT normals, turned
        about the axis) are Face.normalAt at the returned parameters to rounding, and
        face_gauss returns them."""
        face = Part.makeCone(3, 1, 4).Faces[0].copy()
        face.Placement = PLACEMENT
        u0, u1, v0, v1 = face.ParameterRange
        vm = (v0 + v1) / 2
        us, normals, dev = gauss_map._small_circle_samples(face, u0, u1, vm, 1e-3)
        self.assertGreater(len(us), 17)   # several doublings
        self.assertLessEqual(dev, 1e-3)
        ref = np.array([tuple(face.normalAt(float(u), vm)) for u in us])
        np.testing.assert_allclose(normals, ref, rtol=0, atol=1e-14)
        np.testing.assert_array_equal(us, np.linspace(u0, u1, len(us)))
        np.testing.assert_allclose(gauss_map.face_gauss(face).normals,
                                   parting.FaceGauss(ref).normals, rtol=0, atol=1e-14)

    def test_every_example_face(self):
        for name in EXAMPLES:
            shape = example(name)
            faces, _, _ = gauss_map.part_gauss(shape)
            for face, g in zip(shape.Faces, faces):
                self.assert_valid_bound(face, g)

    def test_reversed_face_normals_point_out_of_the_material(self):
        shape = example("cup_hole")
        self.assertTrue(any(f.Orientation == "Reversed" for f in shape.Faces))
        for face, g in zip(shape.Faces, gauss_map.part_gauss(shape)[0]):
            u0, u1, v0, v1 = face.ParameterRange
            uv = [(u, v) for u in np.linspace(u0, u1, 7)[1:-1] for v in np.linspace(v0, v1, 7)[1:-1]
                  if face.isPartOfDomain(float(u), float(v))][0]
            p = face.valueAt(*uv)
            n = _vec(g.normals[0]) if len(g.normals) == 1 else face.normalAt(*uv)
            self.assertFalse(shape.isInside(p + n * 0.1, 1e-6, True), g.name)
            self.assertTrue(shape.isInside(p - n * 0.1, 1e-6, True), g.name)


class Examples(unittest.TestCase):
    """The answers on the bundled parts; each also rotated, as geometry and as a
    Placement (of the object and of an App::Part around it)."""

    @classmethod
    def setUpClass(cls):
        cls.doc = App.newDocument("PartingTest")

    @classmethod
    def tearDownClass(cls):
        App.closeDocument(cls.doc.Name)

    def variants(self, name):
        """(label, source, rotation) for the part as built, rotated geometry, a rotated
        object and a rotated object inside a rotated App::Part."""
        shape = example(name)
        geo = shape.copy()
        geo.transformShape(PLACEMENT.toMatrix(), True)
        self.assertTrue(geo.Placement.isIdentity())
        obj = self.doc.addObject("Part::Feature", name)
        obj.Shape = shape
        obj.Placement = PLACEMENT
        inner = self.doc.addObject("Part::Feature", name + "_inner")
        inner.Shape = shape
        inner.Placement = PLACEMENT
        container = self.doc.addObject("App::Part", name + "_container")
        container.addObject(inner)
        container.Placement = CONTAINER
        self.doc.recompute()
        return [("built", shape, np.eye(3)), ("geometry", geo, rot_matrix(PLACEMENT)),
                ("placement", obj, rot_matrix(PLACEMENT)),
                ("container", inner, rot_matrix(CONTAINER.multiply(PLACEMENT)))]

    def check_mould(self, name, direction, covered, undercuts, side_cores, draft=0.0,
                    direction_test=None):
        for label, source, R in self.variants(name):
            with self.subTest(part=name, variant=label):
                r, faces, shape = run(source, "Mould", draft)
                if direction is not None:
                    np.testing.assert_allclose(r.direction, R @ direction, atol=1e-9)
                if direction_test is not None:
                    self.assertTrue(direction_test(R.T @ r.direction), r.direction)
                self.assertEqual((r.count, r.total), covered)
                if undercuts is not None:
                    self.assertEqual([names(r, [s]) for s in r.undercuts], undercuts)
                self.assertEqual(len(r.side_cores), len(side_cores))
                for core_dir, want in zip(r.side_cores, side_cores):
                    # sampled (cone) faces: the region's centre is that of a polygon
                    np.testing.assert_allclose(core_dir.direction, R @ want, atol=1e-6)
                brute_force(self, r, shape, draft, True, (name, label))

    def check_nc(self, name, setups):
        for label, source, R in self.variants(name):
            with self.subTest(part=name, variant=label):
                r, faces, shape = run(source, "NC3Axis")
                got = sorted((tuple(np.round(R.T @ s.direction, 9)), len(s.faces))
                             for s in r.setups)
                self.assertEqual(got, sorted((tuple(float(c) for c in d), k) for d, k in setups))
                self.assertEqual(r.unresolved, [])
                brute_force(self, r, shape, 0.0, False, (name, label))

    def test_cup(self):
        self.check_mould("cup", Z, (4.0, 4.0), [], [])
        self.check_nc("cup", [(Z, 2)])

    def test_cup_with_hole(self):
        self.check_mould("cup_hole", Z, (4.0, 5.0), [["Face2", "Face5"]], [X])
        self.check_nc("cup_hole", [(Z, 2), (X, 2)])

    def test_block_with_three_pockets(self):
        self.check_nc("pocket_block", [(Z, 5), (X, 5), (-Y, 5)])

    def test_draft_keeps_the_direction(self):
        """The draft classifies faces, it does not move the draw: the draft-flip block
        keeps +-z at 3 degrees (it used to jump near +x), the tapered +x pockets stay the
        undercuts with their side core, and the vertical walls are listed (zero draft)."""
        for draft in (0.0, math.radians(3)):
            self.check_mould("draft_flip", Z, (9.0, 11.0),
                             [["Face19", "Face24"], ["Face20", "Face25"]], [X], draft=draft)
        r, faces, shape = run(draft_flip.make(), "Mould", math.radians(3))
        walls = sorted(f"Face{i + 1}" for i, f in enumerate(shape.Faces)
                       if isinstance(f.Surface, Part.Plane)
                       and abs(f.normalAt(0, 0).z) < 1e-12 and f"Face{i + 1}" not in
                       ("Face19", "Face20", "Face24", "Face25"))
        got = sorted(faces[f].name for f in r.zero_draft_faces)
        self.assertEqual(got, walls)
        self.assertEqual(len(walls), 4 + 3 * 4)
        self.assertEqual(sorted(faces[f].name for f in r.insufficient_draft_faces), walls)

    def test_drilled_hole(self):
        """A real drilled blind hole (exact cylinder + sampled 118 degree drill point):
        reachable along +z; the cone's shrink must not empty the cylinder's point map."""
        tip = 3 / math.tan(math.radians(59))
        drill = Part.makeCylinder(3, 12, App.Vector(10, 10, 8)).fuse(
            Part.makeCone(0, 3, tip, App.Vector(10, 10, 8 - tip)))
        shape = Part.makeBox(20, 20, 15).cut(drill)
        types = sorted(type(f.Surface).__name__ for f in shape.Faces)
        self.assertIn("Cone", types)
        self.assertIn("Cylinder", types)
        r, faces, _ = run(shape, "NC3Axis")
        self.assertEqual(len(r.setups), 1)
        self.assertEqual(r.unresolved, [])
        np.testing.assert_allclose(r.direction, Z, atol=1e-9)
        self.assertEqual(len(r.setups[0].faces), 2)
        r, _, _ = run(shape, "Mould")
        self.assertEqual(r.count, r.total)
        np.testing.assert_allclose(r.direction, Z, atol=1e-9)

    def test_bspline_part(self):
        faces, _, _ = gauss_map.part_gauss(example("bspline_part"))
        # the B-spline top is bounded by its control net (exact cone bound, shrink 0)
        shape = example("bspline_part")
        spline = [g for f, g in zip(shape.Faces, faces)
                  if isinstance(f.Surface, Part.BSplineSurface)]
        self.assertTrue(spline)
        self.assertTrue(all(g.shrink == 0.0 for g in spline))
        self.check_mould("bspline_part", Z, (7.0, 7.0), [], [])
        self.check_nc("bspline_part", [(Z, 2)])


class RandomRotations(unittest.TestCase):
    """Every example under random rotations (geometry and Placement): the same surfaces
    covered, undercut, given side cores or set-ups, and the directions rotated — to
    1e-9 without draft (1e-6 with sampled faces), to 1e-4 with 3 degrees (the library's
    draft polygons are inscribed to 1e-4 rad, so symmetric optima differ that much)."""

    def answer(self, shape, R):
        faces, adj, _ = gauss_map.part_gauss(shape)
        out = []
        # sampled faces' maps are draft polygons too: their regions move by ~1e-8
        exact = 1e-9 if all(f.shrink == 0 for f in faces) else 1e-6
        surfaces = parting.build_surfaces(faces, adj)
        for draft, atol in ((0.0, exact), (math.radians(3), 1e-4)):
            r = parting.mould_parting(faces, adj, draft_angle=draft)
            out.append(((r.covered, r.undercuts, r.insufficient_draft, r.unresolved,
                         [c.surfaces for c in r.side_cores]),
                        [R.T @ r.direction] + [R.T @ c.direction for c in r.side_cores], atol,
                        (draft, [R.T @ surfaces[i].normals.T for i in r.covered])))
        nc = parting.nc_setups(faces, adj)
        out.append((([s.surfaces for s in nc.setups], nc.unresolved),
                    [R.T @ s.direction for s in nc.setups], 1e-6, None))
        return out

    def test_examples(self):
        rng = np.random.default_rng(11)
        for name in EXAMPLES:
            shape = example(name)
            reference = self.answer(shape, np.eye(3))
            for k in range(3):
                axis = App.Vector(*rng.normal(size=3))
                pl = App.Placement(App.Vector(*rng.normal(size=3) * 50),
                                   App.Rotation(axis, rng.uniform(0, 360)))
                for how in ("geometry", "placement"):
                    moved = shape.copy()
                    if how == "geometry":
                        moved.transformShape(pl.toMatrix(), True)
                    else:
                        moved.Placement = pl
                    got = self.answer(moved, rot_matrix(pl))
                    for want, have in zip(reference, got):
                        (want_sets, want_dirs, atol, ref), (got_sets, got_dirs, _, _) = want, have
                        with self.subTest(part=name, rotation=k, how=how):
                            self.assertEqual(got_sets, want_sets)
                            if (ref is not None and ref[0] > 0 and len(got_dirs) == 1
                                    and not np.allclose(got_dirs, want_dirs, atol=atol)):
                                # with a draft, equally good directions of a symmetric part
                                # (bspline_part: mirror images) are a tie that rounding of
                                # the normals breaks either way: the direction found must
                                # demould the reference's covered surfaces with the draft
                                draft, covered_normals = ref
                                for n in covered_normals:
                                    dots = got_dirs[0] @ n
                                    self.assertTrue(dots.min() >= math.sin(draft) - 1e-4
                                                    or dots.max() <= -math.sin(draft) + 1e-4)
                                continue
                            np.testing.assert_allclose(got_dirs, want_dirs, atol=atol)


class RandomParts(unittest.TestCase):
    """Blocks cut by random cylinders, cones and rotated boxes (any direction): mould
    (0 and 2 degrees) and NC (all faces) answers against the brute force."""

    def test_brute_force(self):
        rng = np.random.default_rng(3)
        done = 0
        for trial in range(10):
            tools = []
            for _ in range(rng.integers(2, 6)):
                kind = rng.integers(0, 3)
                c = App.Vector(*rng.uniform([10, 10, 10], [50, 50, 30]))
                axis = App.Vector(*rng.normal(size=3))
                if kind == 0:
                    t = Part.makeCylinder(rng.uniform(2, 5), 40, c, axis)
                elif kind == 1:
                    t = Part.makeCone(rng.uniform(3, 6), rng.uniform(0.5, 2), 40, c, axis)
                else:
                    t = Part.makeBox(*rng.uniform(4, 10, 3))
                    t.Placement = App.Placement(c, App.Rotation(axis, rng.uniform(0, 360)))
                tools.append(t)
            shape = Part.makeBox(60, 60, 40).cut(Part.makeCompound(tools))
            if not shape.isValid() or len(shape.Solids) != 1:
                continue
            done += 1
            for mode, draft, kw in (("Mould", 0.0, {}), ("Mould", math.radians(2), {}),
                                    ("NC3Axis", 0.0, {"all_faces": True})):
                with self.subTest(trial=trial, mode=mode, draft=draft):
                    r, _, _ = run(shape, mode, draft, **kw)
                    brute_force(self, r, shape, draft, mode == "Mould", ("random", trial))
        self.assertGreaterEqual(done, 6)


class Feature(unittest.TestCase):
    """The PartingAnalysis FeaturePython: make, results, recompute on change, reload."""

    def setUp(self):
        self.doc = App.newDocument("PartingFeature")
        self.log = []
        self.part = self.doc.addObject("Part::Feature", "CupHole")
        self.part.Shape = example("cup_hole")
        self.part.Placement = PLACEMENT
        self.doc.recompute()

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def assert_clean(self, obj):
        self.assertTrue(obj.isValid(), obj.getStatusString())
        self.assertNotIn("Touched", obj.State)

    def test_mould_results(self):
        import mfgeom
        obj = mfgeom.make_parting_analysis(self.doc, self.part)
        self.assert_clean(obj)
        R = rot_matrix(PLACEMENT)
        np.testing.assert_allclose(_np(obj.Direction), R @ Z, atol=1e-9)
        self.assertEqual((obj.CoveredCount, obj.TotalCount), (4, 5))
        self.assertEqual(list(obj.UncoveredFaces), ["Face2", "Face5"])
        self.assertEqual(len(obj.SideCoreDirections), 1)
        np.testing.assert_allclose(_np(obj.SideCoreDirections[0]), R @ X, atol=1e-9)
        core_faces = json.loads(obj.SideCores[0])["faces"]
        self.assertEqual(core_faces, ["Face2", "Face5"])
        self.assertEqual(list(obj.Setups), [])
        self.assertIn("Face6 Face7", list(obj.Surfaces))
        self.assertEqual(obj.MarginDeg, 0.0)
        # bottom on the cavity side, the pocket's floor and the top on the core side, the
        # walls (outer, pocket) zero draft: listed as insufficient draft, not undercut
        self.assertEqual(list(obj.CavityFaces), ["Face3"])
        self.assertEqual(list(obj.CoreFaces), ["Face4", "Face7"])
        self.assertEqual(list(obj.ZeroDraftFaces), ["Face1", "Face6"])
        self.assertEqual(list(obj.InsufficientDraftFaces), ["Face1", "Face6"])
        angles = list(obj.WorstAngles)
        self.assertEqual(len(angles), 7)
        self.assertAlmostEqual(angles[0], 0.0, places=9)
        self.assertAlmostEqual(angles[6], 90.0, places=9)     # the pocket's floor
        self.assertAlmostEqual(angles[1], -90.0, places=9)    # the hole's wall faces -z
        # the ray check ran and agrees: no face the normals call demouldable is blocked
        self.assertEqual(list(obj.ShadowedFaces), [])
        from mfgeom.app.parting_feature import feature_report
        rep = feature_report(obj)
        self.assertTrue(rep["ray_checked"])
        rays = {row["name"]: row["ray_blocked"] for row in rep["faces"]}
        self.assertEqual(rays["Face4"], 0.0)   # the top along +d
        self.assertEqual(rays["Face7"], 0.0)   # the pocket's floor along +d
        self.assertGreater(rays["Face2"], 0.5)  # the hole's wall: blocked both ways

    def test_recomputes_when_source_or_parameters_change(self):
        from mfgeom.app.parting_feature import make_parting_analysis
        obj = make_parting_analysis(self.doc, self.part, mode="NC3Axis")
        R = rot_matrix(PLACEMENT)
        setups = [json.loads(t) for t in obj.Setups]
        # a tie (one surface each, margin 0) goes to the surface with the lowest faces
        self.assertEqual([s["faces"] for s in setups], [["Face2", "Face5"], ["Face6", "Face7"]])
        np.testing.assert_allclose(_np(obj.Direction), R @ X, atol=1e-9)
        np.testing.assert_allclose(setups[1]["direction"], R @ Z, atol=1e-9)
        self.part.Placement = App.Placement()
        self.doc.recompute()
        self.assert_clean(obj)
        np.testing.assert_allclose(_np(obj.Direction), X, atol=1e-9)
        obj.Mode = "Mould"
        obj.DraftAngle = 2.0
        self.doc.recompute()
        self.assert_clean(obj)
        # with 2 degrees the walls of the cup and of its pocket have no draft: listed,
        # the direction and what it covers stay
        self.assertEqual(obj.CoveredCount, 4)
        self.assertEqual(sorted(obj.InsufficientDraftFaces), ["Face1", "Face6"])

    def test_draft_mode_and_open_shells(self):
        import mfgeom
        from mfgeom.app.parting_feature import PartingInputError
        R = rot_matrix(PLACEMENT)
        obj = mfgeom.make_parting_analysis(self.doc, self.part, mode="Draft",
                                           draft_angle="1 deg",
                                           pull_direction=(self.part, "Face4"))
        self.assert_clean(obj)
        np.testing.assert_allclose(_np(obj.Direction), R @ Z, atol=1e-9)
        self.assertEqual(list(obj.PositiveDraftFaces), ["Face4", "Face7"])
        self.assertEqual(list(obj.NegativeDraftFaces), ["Face3"])
        self.assertEqual(list(obj.InsufficientDraftFaces), ["Face1", "Face5", "Face6"])
        self.assertEqual(list(obj.StraddleFaces), ["Face2"])   # the hole's wall
        from mfgeom.app.parting_feature import feature_report
        rep = feature_report(obj)
        self.assertEqual(rep["mode"], "Draft")
        self.assertEqual(rep["straddle_faces"], ["Face2"])
        for bad in ((0, 0, 0), (math.nan, 0, 1), "up"):
            with self.assertRaises(PartingInputError):
                mfgeom.make_parting_analysis(self.doc, self.part, mode="Draft",
                                             pull_direction=bad)
        with self.assertRaises(PartingInputError):
            mfgeom.make_parting_analysis(self.doc, self.part, mode="Draft")
        shell = self.doc.addObject("Part::Feature", "Shell")
        shell.Shape = Part.Shell(self.part.Shape.Faces[:3])
        count = len(self.doc.Objects)
        with self.assertRaisesRegex(PartingInputError, "holds no solid"):
            mfgeom.make_parting_analysis(self.doc, shell)
        self.assertEqual(len(self.doc.Objects), count)

    def test_some_faces(self):
        import mfgeom
        # the hole's two faces alone: one surface, covered along the hole's axis
        obj = mfgeom.make_parting_analysis(self.doc, self.part, faces=["Face5", "Face2"])
        self.assert_clean(obj)
        self.assertEqual((obj.CoveredCount, obj.TotalCount), (1, 1))
        self.assertEqual(list(obj.Surfaces), ["Face2 Face5"])
        np.testing.assert_allclose(_np(obj.Direction), rot_matrix(PLACEMENT) @ X, atol=1e-9)
        with self.assertRaises(ValueError):
            mfgeom.make_parting_analysis(self.doc, self.part, faces=["Face99"])

    def test_save_and_reload(self):
        import tempfile
        from mfgeom.app.parting_feature import make_parting_analysis
        obj = make_parting_analysis(self.doc, self.part, draft_angle="0 deg", weighting="Area")
        direction, obj_name = _np(obj.Direction), obj.Name
        path = os.path.join(tempfile.mkdtemp(), "parting.FCStd")
        self.doc.saveAs(path)
        name = self.doc.Name
        App.closeDocument(name)
        self.doc = App.openDocument(path)
        again = self.doc.getObject(obj_name)
        self.assertEqual(type(again.Proxy).__name__, "PartingAnalysis")
        np.testing.assert_allclose(_np(again.Direction), direction)
        again.touch()
        self.doc.recompute()
        self.assert_clean(again)
        np.testing.assert_allclose(_np(again.Direction), direction, atol=1e-12)

    def test_version2_document_loads(self):
        """A document saved by version 2 (the angle property was called "Deflection")
        opens with it as NormalDeflection (same degrees), Version 3, no "Deflection"
        left, and recomputes to the same direction."""
        import tempfile
        from mfgeom.app.parting_feature import VERSION, make_parting_analysis
        self.assertEqual(VERSION, 3)
        obj = make_parting_analysis(self.doc, self.part)
        direction, obj_name = _np(obj.Direction), obj.Name
        # the object as version 2 saved it
        obj.removeProperty("NormalDeflection")
        obj.addProperty("App::PropertyAngle", "Deflection", "Input", "old tooltip")
        obj.Deflection = 0.125
        obj.Version = 2
        path = os.path.join(tempfile.mkdtemp(), "parting_v2.FCStd")
        self.doc.saveAs(path)
        App.closeDocument(self.doc.Name)
        self.doc = App.openDocument(path)
        again = self.doc.getObject(obj_name)
        self.assertEqual(again.Version, VERSION)
        self.assertNotIn("Deflection", again.PropertiesList)
        self.assertEqual(again.getTypeIdOfProperty("NormalDeflection"), "App::PropertyAngle")
        self.assertAlmostEqual(again.NormalDeflection.Value, 0.125, places=12)
        np.testing.assert_allclose(_np(again.Direction), direction)
        again.touch()
        self.doc.recompute()
        self.assert_clean(again)
        np.testing.assert_allclose(_np(again.Direction), direction, atol=1e-12)

    def test_bad_input_leaves_the_document_alone(self):
        from mfgeom.app.parting_feature import PartingInputError, make_parting_analysis
        before = len(self.doc.Objects)
        for kwargs in ({"mode": "Milling"}, {"weighting": "Volume"}, {"draft_angle": -1},
                       {"draft_angle": "5 mm"}, {"draft_angle": 90}):
            with self.assertRaises(PartingInputError, msg=str(kwargs)):
                make_parting_analysis(self.doc, self.part, **kwargs)
        with self.assertRaises(PartingInputError):
            make_parting_analysis(self.doc, None)
        self.assertEqual(len(self.doc.Objects), before)


def _np(v):
    return np.array([v.x, v.y, v.z])


def _timings(_result):
    for nfaces, mode, draft, t_gauss, t_part in TIMES:
        sys.stdout.write(f"timing: {nfaces} faces {mode} draft {draft}: "
                         f"gauss {t_gauss * 1e3:.1f} ms, parting {t_part * 1e3:.1f} ms\n")


sys.path.insert(0, HERE)
from fc_testsupport import run_file  # noqa: E402

sys.exit(run_file(globals(), "freecad-parting", before_summary=_timings))
