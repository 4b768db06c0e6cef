# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD App tests of the parting analysis on the corpus of real parts (issue 17, item
6; tests/corpus: parts the project did not make), run by ``freecadcmd``.

Run through tests/run_freecad_tests.sh, or directly:
``MFGEOM_LIBRARY=build/libmfgeom.so freecadcmd tests/freecad/test_corpus_app.py``.
``MFGEOM_CORPUS_PARTS=bottle,Ball`` restricts the run to those parts (file stems).
Prints one line per failure (``corpus-failure: ...``), per-part timings, and
``freecad-corpus: N passed, M failed`` last; exits non-zero on any failure.

For every part (one test each):

* the loader of the workbench (:func:`mfgeom.app.parting_batch.load_sources`, as the CLI
  batch reads a file) gives the part's number of solids, or refuses a file with no
  solid ("holds no solid");
* every solid is analysed as the PartingAnalysis feature and the batch do (Gaussian maps
  of the real faces, :func:`mfgeom.parting.mould_parting` and
  :func:`mfgeom.parting.nc_setups`, :func:`mfgeom.parting.report`) without an
  exception, and the report is consistent (a unit direction, counts within the total);
* rotation invariance: the solid turned by a random rotation R (seeded by the part's
  name, so runs repeat) gives the same covered weight, the same covered faces and the
  direction R d (within ROTATION_TOL_DEG; in Mould mode up to sign, +d and -d being the
  same parting).  A direction that moved is classified in the message: "tie" when R^T d'
  covers as much on the original part's own normals (both directions are equally good:
  the tie-break is not rotation invariant), "worse" otherwise.
"""

import math
import os
import sys
import time
import traceback
import unittest
import zlib

import numpy as np

import FreeCAD as App

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
for _path in (os.path.join(REPO, "tests", "corpus"), os.path.join(REPO, "workbench")):
    if _path not in sys.path:
        sys.path.append(_path)

import corpus  # noqa: E402
from mfgeom import parting  # noqa: E402
from mfgeom.app import gauss_map, parting_batch  # noqa: E402

ROTATION_TOL_DEG = 0.1
TIMEOUT_S = float(os.environ.get("MFGEOM_CORPUS_TIMEOUT", "60"))   # per part
MEMORY_GB = 3.0               # address space a part's child may add
EPS = math.sin(1e-6)          # the grid peer's (and the library's) angular tolerance
MODES = ("Mould", "NC3Axis")
TIMES = []                    # (part, wall s, status, [solids, faces, B-spline, gauss s, analysis s])
FAILURES = []                 # one line per failure, printed at the end
KNOWN_SEEN = []               # known gaps met, printed at the end
# Known gaps (issue 17, left open): rotation changes which of two equally good answers is
# taken (ties the rounding of the exact maps decides).  Each entry is
# (problem-line prefix, why); a matching problem is reported as "corpus-known:", not a
# failure; any other problem fails.
KNOWN_GAPS = (
    ("I22_2_5_16withEPL22_6_16/Solid2 NC3Axis rotated: direction",
     "tie between two arc regions covering the same 2 surfaces"),
    ("Motor-c/Solid1 NC3Axis rotated: direction",
     "tie: 0.24 deg apart on a sampled surface's region"),
)


def _where(exc):
    """'file:line in function' of the innermost frame of exc's traceback."""
    tb = traceback.extract_tb(exc.__traceback__)
    if not tb:
        return "?"
    f = tb[-1]
    return f"{os.path.relpath(f.filename, REPO)}:{f.lineno} in {f.name}"


def _chain(exc):
    """The traceback's frames as 'file:line function' joined by ' > ' (outermost first,
    this file's frames left out)."""
    frames = [f for f in traceback.extract_tb(exc.__traceback__)
              if os.path.abspath(f.filename) != os.path.abspath(__file__)]
    return " > ".join(f"{os.path.relpath(f.filename, REPO)}:{f.lineno} {f.name}"
                      for f in frames if f.name not in ("<genexpr>", "<listcomp>"))


def _error(exc):
    return f"{type(exc).__name__}: {' '.join(str(exc).split())[:200]} (at {_where(exc)})"


def random_rotation(seed):
    """A uniformly random rotation (unit quaternion from 4 normal deviates)."""
    q = np.random.default_rng(seed).normal(size=4)
    q /= np.linalg.norm(q)
    return App.Rotation(*[float(c) for c in q])


def rot_matrix(rot):
    m = rot.toMatrix()
    return np.array([[m.A11, m.A12, m.A13], [m.A21, m.A22, m.A23], [m.A31, m.A32, m.A33]])


def analyse(faces, adj, mode):
    if mode == "Mould":
        return parting.mould_parting(faces, adj)
    return parting.nc_setups(faces, adj)


def covered_faces(r):
    return sorted(f for s in r.covered for f in r.surfaces[s].faces)


def weight_on_samples(r, d, mould):
    """Weight of the considered surfaces whose sampled normals n all satisfy d.n >= -eps
    (or, Mould, all d.n <= eps): the direction d checked on the part's own normals,
    independently of the library."""
    total = 0.0
    for s in r.considered:
        dots = r.surfaces[s].normals @ d
        if dots.min() >= -EPS or (mould and dots.max() <= EPS):
            total += r.surfaces[s].weight
    return total


def _angle_deg(a, b):
    return math.degrees(math.atan2(np.linalg.norm(np.cross(a, b)), float(np.dot(a, b))))


class PartRun:
    """The checks of one part, run in a forked child (:func:`corpus.run_isolated`): problems
    and progress go to ``emit`` as JSON-able dicts, never as exceptions."""

    def __init__(self, part, emit):
        self.part, self.emit = part, emit
        self.name = os.path.splitext(corpus._inner_name(part))[0]

    def problem(self, text):
        self.emit({"problem": text})

    def stage(self, text):
        self.emit({"stage": text})

    def failure(self, label, stage, exc, extra=""):
        self.emit({"problem": f"{label}: {stage}: {_error(exc)}{extra}",
                   "traceback": _chain(exc)})

    @staticmethod
    def failing_faces(solid, limit=3):
        """' (FaceN Surface: error, ...)' for the first faces whose own Gauss map
        fails: which face of a failed part_gauss is at fault."""
        bad = []
        for i, face in enumerate(solid.Faces):
            try:
                gauss_map.face_gauss(face)
            except Exception as exc:  # noqa: BLE001
                bad.append(f"Face{i + 1} {type(face.Surface).__name__}: "
                           f"{type(exc).__name__}")
        if not bad:
            return ""
        more = f", {len(bad) - limit} more" if len(bad) > limit else ""
        return f" [faces: {', '.join(bad[:limit])}{more}]"

    def run(self):
        part = self.part
        self.stage("load")
        if part.expect_solids == 0:
            try:
                _, close = corpus.load_sources(part)
                close()
                self.problem(f"{self.name}: the loader accepted a file with no solid")
            except parting_batch.PartError as exc:
                if "holds no solid" not in str(exc):
                    self.problem(f"{self.name}: loader: {exc}")
            self.emit({"times": [0, 0, 0, 0.0, 0.0]})
            return
        try:
            sources, close = corpus.load_sources(part)
            close()
            _, solids = corpus.load(part)
        except Exception as exc:  # noqa: BLE001 - every failure is reported
            self.failure(self.name, "load", exc)
            return
        if len(sources) != part.expect_solids or len(solids) != part.expect_solids:
            self.problem(f"{self.name}: {len(sources)} sources / {len(solids)} solids, "
                         f"expected {part.expect_solids}")
        nfaces = sum(len(s.Faces) for s in solids)
        nbs = corpus.face_kinds(solids).get("BSplineSurface", 0)
        seed = zlib.crc32(self.name.encode())
        t = [0.0, 0.0]
        for k, solid in enumerate(solids):
            self.solid(f"{self.name}/Solid{k + 1}", solid, random_rotation(seed + k), t)
        self.emit({"times": [len(solids), nfaces, nbs, t[0], t[1]]})

    def solid(self, label, solid, rot, t):
        self.stage(f"{label} ({len(solid.Faces)} faces): Gauss maps")
        try:
            t0 = time.perf_counter()
            faces, adj, _ = gauss_map.part_gauss(solid)
            t[0] += time.perf_counter() - t0
        except Exception as exc:  # noqa: BLE001
            self.failure(label, "Gauss maps", exc, self.failing_faces(solid))
            return
        results = {}
        for mode in MODES:
            self.stage(f"{label} ({len(solid.Faces)} faces): {mode}")
            try:
                t0 = time.perf_counter()
                r = analyse(faces, adj, mode)
                t[1] += time.perf_counter() - t0
                rep = parting.report(r, faces, source=label)
            except Exception as exc:  # noqa: BLE001
                self.failure(label, mode, exc)
                continue
            bad = []
            if not 0 <= rep["covered_count"] <= rep["total_count"]:
                bad.append(f"covers {rep['covered_count']} of {rep['total_count']}")
            if rep["face_count"] != len(solid.Faces):
                bad.append(f"{rep['face_count']} faces reported of {len(solid.Faces)}")
            if rep["direction"] is not None:
                if abs(float(np.linalg.norm(rep["direction"])) - 1.0) > 1e-9:
                    bad.append(f"direction {rep['direction']} not unit")
            elif rep["covered_count"] > 0:
                # no direction is an answer only when nothing is covered (a solid of
                # one closed face, a ball: no surface demoulds in one piece)
                bad.append(f"no direction but {rep['covered_count']} surfaces covered")
            if bad:
                self.problem(f"{label} {mode}: report: " + "; ".join(bad))
            results[mode] = r
        if not results:
            return
        turned = solid.copy()
        turned.Placement = App.Placement(App.Vector(0, 0, 0), rot).multiply(turned.Placement)
        self.stage(f"{label} ({len(solid.Faces)} faces): Gauss maps (rotated)")
        try:
            faces2, adj2, _ = gauss_map.part_gauss(turned)
        except Exception as exc:  # noqa: BLE001
            self.failure(label, "Gauss maps (rotated)", exc)
            return
        for mode, r in results.items():
            self.stage(f"{label} ({len(solid.Faces)} faces): {mode} (rotated)")
            try:
                r2 = analyse(faces2, adj2, mode)
            except Exception as exc:  # noqa: BLE001
                self.failure(label, f"{mode} (rotated)", exc)
                continue
            line = rotation_problem(mode, rot_matrix(rot), r, r2)
            if line:
                self.problem(f"{label} {mode} rotated: {line}")


def rotation_problem(mode, R, r, r2):
    """None when r2 (the part turned by R) is r turned by R, else what differs."""
    mould = mode == "Mould"
    if r.direction is None or r2.direction is None:
        if (r.direction is None) != (r2.direction is None):
            return f"direction {r.direction} -> {r2.direction}"
        return None
    d, d2 = np.asarray(r.direction), np.asarray(r2.direction)
    expected = R @ d
    angle = _angle_deg(expected, d2)
    if mould:
        angle = min(angle, _angle_deg(-expected, d2))
    problems = []
    if abs(r.count - r2.count) > 1e-9:
        problems.append(f"covered weight {r.count:g} -> {r2.count:g}")
    if angle > ROTATION_TOL_DEG:
        back = R.T @ d2
        on_orig, own = weight_on_samples(r, back, mould), weight_on_samples(r, d, mould)
        kind = "tie" if on_orig >= own - 1e-9 else "worse"
        problems.append(f"direction R d = {np.round(expected, 6).tolist()} but got "
                        f"{np.round(d2, 6).tolist()} ({angle:.3g} deg off; {kind}: R^T d' "
                        f"covers {on_orig:g} on the original's normals, d {own:g})")
    elif covered_faces(r) != covered_faces(r2):
        a, b = set(covered_faces(r)), set(covered_faces(r2))
        problems.append(f"covered faces differ: only unrotated "
                        f"{sorted(f'Face{i + 1}' for i in a - b)[:8]}, only rotated "
                        f"{sorted(f'Face{i + 1}' for i in b - a)[:8]}")
    return "; ".join(problems) or None


class Corpus(unittest.TestCase):
    """One test per corpus part (added below)."""

    def check_part(self, part):
        name = os.path.splitext(corpus._inner_name(part))[0]
        messages, wall, status = corpus.run_isolated(
            lambda emit: PartRun(part, emit).run(), TIMEOUT_S, MEMORY_GB)
        problems = []
        for m in messages:
            if "problem" not in m:
                continue
            known = next((why for prefix, why in KNOWN_GAPS
                          if m["problem"].startswith(prefix)), None)
            if known is None:
                problems.append(m)
            else:
                KNOWN_SEEN.append(f"{m['problem'][:160]} [known gap: {known}]")
        stages = [m["stage"] for m in messages if "stage" in m]
        times = next((m["times"] for m in messages if "times" in m), None)
        TIMES.append((name, wall, status, times))
        lines = [m["problem"] for m in problems]
        if status != "ok":
            lines.append(f"{name}: {status} after {wall:.0f} s "
                         f"(at: {stages[-1] if stages else 'start'})")
        for m in problems:
            FAILURES.append(m["problem"])
            if "traceback" in m:
                FAILURES.append("    at " + m["traceback"])
        if status != "ok":
            FAILURES.append(lines[-1])
        if lines:
            self.fail("\n".join(lines))


def _add_tests():
    only = {s for s in os.environ.get("MFGEOM_CORPUS_PARTS", "").split(",") if s}
    for part in corpus.parts():
        stem = os.path.splitext(corpus._inner_name(part))[0]
        if only and stem not in only:
            continue
        ident = "".join(c if c.isalnum() else "_" for c in stem)

        def test(self, part=part):
            self.check_part(part)
        test.__doc__ = f"corpus part {part.file}: {part.what}"
        setattr(Corpus, f"test_{ident}", test)


_add_tests()


def main():
    # freecadcmd runs this file with exec(): it is not in sys.modules, so collect by hand
    suite = unittest.defaultTestLoader.loadTestsFromTestCase(Corpus)
    t0 = time.perf_counter()
    result = unittest.TextTestRunner(stream=sys.stdout, verbosity=2).run(suite)
    total_wall = time.perf_counter() - t0
    for line in FAILURES:
        sys.stdout.write(f"corpus-failure: {line}\n")
    for line in KNOWN_SEEN:
        sys.stdout.write(f"corpus-known: {line}\n")
    for name, wall, status, times in TIMES:
        if times:
            nsolids, nfaces, nbs, tg, ta = times
            what = (f"{nsolids} solids, {nfaces} faces ({nbs} B-spline): gauss maps "
                    f"{tg:.2f} s, analysis {ta:.2f} s (unrotated)")
        else:
            what = "unfinished"
        sys.stdout.write(f"corpus-timing: {name}: {what}; wall {wall:.1f} s; {status}\n")
    # a subtest's failure is reported per subtest: count failed tests (parts)
    failed = len({getattr(t, "test_case", t).id() for t, _ in result.failures + result.errors})
    passed = result.testsRun - failed - len(result.skipped)
    sys.stdout.write(f"corpus: {len(TIMES)} parts in {total_wall:.1f} s wall\n")
    sys.stdout.write(f"freecad-corpus: {passed} passed, {failed} failed\n")
    sys.stdout.flush()
    return 0 if failed == 0 and result.testsRun > 0 else 1


sys.exit(main())
