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
import Part

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
for _path in (os.path.join(REPO, "tests", "corpus"), os.path.join(REPO, "workbench")):
    if _path not in sys.path:
        sys.path.append(_path)

import corpus  # noqa: E402
from mfgeom import parting  # noqa: E402
from mfgeom.app import gauss_map, parting_batch  # noqa: E402

ROTATION_TOL_DEG = 0.1
# per part: a guard against a hang, not a speed target (bench/bench_parting.py measures
# speed); the part with the most faces (Bottom) takes ~50 s with its reference checks
# on a loaded 2-core machine
TIMEOUT_S = float(os.environ.get("MFGEOM_CORPUS_TIMEOUT", "180"))
MEMORY_GB = 3.0               # address space a part's child may add
EPS = math.sin(1e-6)          # the grid peer's (and the library's) angular tolerance
MODES = ("Mould", "NC3Axis")
TIMES = []   # (part, wall s, status, [solids, faces, B-spline, gauss, analysis, angle check, ray check s])
FAILURES = []                 # one line per failure, printed at the end
KNOWN_SEEN = []               # known gaps met, printed at the end
ANGLE_STATS, RAY_STATS = [], []   # |reported - sampled| per face checked (rad; fraction)
# worst angles against OCCT's dense normals (check_worst_angles): per part at most
# ANGLE_FACES_PER_PART faces, a lattice of ANGLE_GRID^2 (u, v) and ANGLE_EDGE_POINTS per
# edge.  ANGLE_SLACK: how far below the sampled worst the reported one may lie besides
# the face's shrink and the lattice's resolution: the Gaussian map's bound of a B-spline
# face is wider than its true normals by up to 3.4e-3 rad (docs/parting.md; tested on 15 face
# kinds), rounded up to 4e-3.
ANGLE_FACES_PER_PART = 16
ANALYTIC = ("Plane", "Cylinder", "Cone", "Sphere", "Toroid")
ANGLE_GRID = 16
ANGLE_EDGE_POINTS = 12
ANGLE_SLACK = 4e-3
# ray check against exact rays (check_rays): at most RAY_FACES_PER_PART faces per part,
# RAY_GRID^2 lattice points each, lifted RAY_LIFT x the part's diagonal.  The fractions
# are estimates from different samples (64 area-weighted tessellation points against at
# most 9 lattice points of the parameter box), so they may differ by a sampling error;
# RAY_FRACTION_TOL = 0.4 is above the error of 9 samples of a fraction (<= 0.17 standard
# deviation, ~2.4 sigma) and far below the 1.0 of a face that one check finds free and
# the other blocked.
RAY_FACES_PER_PART = 4
RAY_GRID = 3
RAY_LIFT = 1e-4
RAY_FRACTION_TOL = 0.4
# Known gaps (issue 17, left open): rotation changes which of two equally good answers is
# taken (ties the rounding of the exact maps decides).  Each entry is
# (problem-line prefix, why); a matching problem is reported as "corpus-known:", not a
# failure; any other problem fails.
KNOWN_GAPS = (
    ("I22_2_5_16withEPL22_6_16/Solid2 NC3Axis rotated: direction",
     "tie between two arc regions covering the same 2 surfaces"),
    ("Motor-c/Solid1 NC3Axis rotated: direction",
     "tie: 0.24 deg apart on a sampled surface's region"),
    # a B-spline face whose control net's exact normals already see no common direction:
    # the net's cone is the whole space and bounds nothing, so the worst angle comes from
    # those exact normals only (samples, not a bound).  Taking the sampled grid for such
    # faces fixes it but turns closed lofts into grids (tests/freecad/test_gauss_map_app)
    ("Bottom/Solid1 Face117 (BSplineSurface): worst angle",
     "net cone is the whole space: worst angle from exact normals, not a bound "
     "(-5.002 deg against OCCT's -5.064)"),
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
            self.emit({"times": [0, 0, 0, 0.0, 0.0, 0.0, 0.0]})
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
        t = [0.0, 0.0, 0.0, 0.0]   # gauss maps, analysis, worst-angle check, ray check
        self.nsolids = len(solids)
        for k, solid in enumerate(solids):
            self.solid(f"{self.name}/Solid{k + 1}", solid, random_rotation(seed + k), t)
        self.emit({"times": [len(solids), nfaces, nbs] + t})

    def check_worst_angles(self, label, solid, faces, r):
        """The worst angle the analysis reports per face (r.face_angle, as the feature's
        WorstAngles and the report's worst_angle_deg) against OCCT's own normals
        sampled densely on the trimmed face: never above the sampled worst + the
        angular tolerance (the analysis is conservative; the tolerance is the snapping
        it promises), and never more than ANGLE_SLACK + the face's shrink + the
        lattice's resolution below it (how far the true worst may lie from the
        samples; ANGLE_SLACK is the Gaussian map's documented bound looseness) — except
        a control-net bound seen from where its face is an undercut, which is only
        conservative (Bottom Face281: the net reaches -90 deg, OCCT -83.4)."""
        d = np.asarray(r.direction, dtype=np.float64)
        most = max(2, ANGLE_FACES_PER_PART // max(1, self.nsolids))
        for f in angle_faces(r, faces, solid, most):
            face = solid.Faces[int(faces[f].name[4:]) - 1]
            normals, step = dense_normals(face)
            if len(normals) == 0:
                self.problem(f"{label} {faces[f].name}: no OCCT normal sampled")
                continue
            rep = float(r.face_angle[f])
            slack = ANGLE_SLACK + faces[f].shrink + step
            # a control-net bound (B-spline etc., shrink 0) is tight only for the
            # directions that see the face (it is refined for those: docs/parting.md); from
            # where the face is an undercut it is only conservative
            net = faces[f].shrink == 0 and type(face.Surface).__name__ not in ANALYTIC
            fits = []
            for sign in _sides_of(r, f):
                worst = float(np.arcsin(np.clip(sign * (normals @ d), -1, 1)).min())
                tight = not (net and worst < -parting.DEFAULT_TOL)
                fits.append((worst, rep <= worst + parting.DEFAULT_TOL + 1e-12
                             and (rep >= worst - slack or not tight)))
            self.emit({"angle_gap": min(abs(w - rep) for w, _ in fits)})
            if not any(ok for _, ok in fits):
                self.problem(
                    f"{label} {faces[f].name} ({type(face.Surface).__name__}): worst "
                    f"angle {math.degrees(rep):.6g} deg, OCCT sampled "
                    f"{', '.join(f'{math.degrees(w):.6g}' for w, _ in fits)} deg "
                    f"({len(normals)} normals; allowed {math.degrees(slack):.3g} deg below, "
                    f"{math.degrees(parting.DEFAULT_TOL):.3g} above)")

    def check_rays(self, label, solid, faces, r):
        """The ray check (feature's run_ray_check: tessellation + mfg_ray_blocked, then
        apply_ray_check) against exact OCCT rays: from RAY_POINTS interior points of a
        few faces (the shadowed ones first, then demouldable ones), lifted off the face
        along its normal, a segment along the face's side (both for zero or
        insufficient draft: the freer counts, as apply_ray_check does) cut with the
        solid (Shape.common): the blocked fractions must agree within RAY_FRACTION_TOL,
        and a face reported shadowed over half its area or more must have a blocked
        exact ray."""
        from mfgeom.app.parting_feature import run_ray_check
        run_ray_check(r, faces, solid, 0.0)
        d = np.asarray(r.direction, dtype=np.float64)
        size = solid.BoundBox.DiagonalLength
        boxes = []
        for face in solid.Faces:
            box = face.BoundBox
            box.enlarge(1e-6 * size)
            boxes.append(box)
        shadowed = list(r.shadowed_faces)
        demouldable = [f for f, x in enumerate(r.face_role)
                       if x in ("core", "cavity", "zero_draft", "insufficient_draft")
                       and f not in shadowed and r.ray_blocked[f] is not None]
        most = max(1, RAY_FACES_PER_PART // max(1, self.nsolids))
        chosen = _pick(shadowed, max(1, most // 2))
        chosen += _pick(demouldable, most - len(chosen))
        for f in chosen:
            face = solid.Faces[int(faces[f].name[4:]) - 1]
            role = r.face_role[f]
            signs = (1.0,) if role == "core" else (-1.0,) if role == "cavity" else (1.0, -1.0)
            points = interior_points(face)
            if len(points) < 3:   # a thin face: a finer lattice
                points = interior_points(face, 2 * RAY_GRID)
            if not points:
                continue
            exact = min(np.mean([exact_ray_blocked(solid, boxes, p, n, s * d, size)
                                 for p, n in points]) for s in signs)
            ours = float(r.ray_blocked[f])
            self.emit({"ray_gap": abs(exact - ours)})
            bad = (abs(exact - ours) > RAY_FRACTION_TOL
                   or (f in shadowed and ours >= 0.5 and exact == 0))
            if bad:
                self.problem(f"{label} {faces[f].name} ({role}): ray check blocked "
                             f"{ours:.3f} of the face{' (shadowed)' if f in shadowed else ''}"
                             f", exact OCCT rays {exact:.3f} of {len(points)} points")

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
            if mode == "Mould" and r.direction is not None:
                self.stage(f"{label} ({len(solid.Faces)} faces): worst angles, rays")
                try:
                    t0 = time.perf_counter()
                    self.check_worst_angles(label, solid, faces, r)
                    t[2] += time.perf_counter() - t0
                    t0 = time.perf_counter()
                    self.check_rays(label, solid, faces, r)
                    t[3] += time.perf_counter() - t0
                except Exception as exc:  # noqa: BLE001
                    self.failure(label, "reference checks", exc)
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


def _pick(candidates, most):
    """At most ``most`` of ``candidates``, spread evenly over the list (deterministic)."""
    candidates = list(candidates)
    if len(candidates) <= most:
        return candidates
    return [candidates[int(k * len(candidates) / most)] for k in range(most)]


def angle_faces(r, faces, solid, most):
    """The faces whose worst angle is checked: the 2 lowest reported (what a user reads
    first), then curved faces, then the others, spread over the part."""
    order = sorted(range(len(faces)), key=lambda f: r.face_angle[f])
    chosen = order[:2]
    curved = [f for f in range(len(faces)) if f not in chosen and
              type(solid.Faces[int(faces[f].name[4:]) - 1].Surface).__name__ != "Plane"]
    chosen += _pick(curved, most - len(chosen))
    rest = [f for f in range(len(faces)) if f not in chosen]
    return chosen + _pick(rest, most - len(chosen))


def dense_normals(face, grid=ANGLE_GRID, per_edge=ANGLE_EDGE_POINTS):
    """Unit outward normals of ``face`` by OCCT (Face.normalAt, the face's orientation
    applied) at a grid x grid lattice of its parameter box kept where the (u, v) lies in
    the trimmed face (Face.isPartOfDomain), and at ``per_edge`` points of each of its
    edges (the extreme normals of a face often lie on its boundary); and the largest
    angle between neighbouring lattice normals (the lattice's angular resolution)."""
    u0, u1, v0, v1 = face.ParameterRange
    us, vs = np.linspace(u0, u1, grid), np.linspace(v0, v1, grid)
    lattice = np.full((grid, grid, 3), np.nan)
    out = []
    for i, u in enumerate(us):
        for j, v in enumerate(vs):
            if not face.isPartOfDomain(float(u), float(v)):
                continue
            try:
                n = face.normalAt(float(u), float(v))
            except Exception:  # noqa: BLE001 - a singular point has no normal
                continue
            if n.Length > 0.5:
                lattice[i, j] = (n.x, n.y, n.z)
                out.append(lattice[i, j])
    for edge in face.Edges:
        try:
            points = edge.discretize(per_edge)
        except Exception:  # noqa: BLE001
            continue
        for p in points:
            try:
                u, v = face.Surface.parameter(p)
                n = face.normalAt(u, v)
            except Exception:  # noqa: BLE001
                continue
            if n.Length > 0.5:
                out.append((n.x, n.y, n.z))
    step = 0.0
    for a, b in ((lattice[1:], lattice[:-1]), (lattice[:, 1:], lattice[:, :-1])):
        dots = np.einsum("...k,...k", a, b)
        dots = dots[np.isfinite(dots)]
        if dots.size:
            step = max(step, float(np.arccos(np.clip(dots.min(), -1.0, 1.0))))
    return np.array(out, dtype=np.float64).reshape(-1, 3), step


def interior_points(face, n=RAY_GRID):
    """(point, outward normal) at an n x n lattice of the face's parameter box, at the
    cells' centres, kept inside the trimmed face (Face.isPartOfDomain)."""
    u0, u1, v0, v1 = face.ParameterRange
    out = []
    for i in range(n):
        for j in range(n):
            u, v = u0 + (u1 - u0) * (i + 0.5) / n, v0 + (v1 - v0) * (j + 0.5) / n
            if not face.isPartOfDomain(u, v):
                continue
            try:
                nrm = face.normalAt(u, v)
            except Exception:  # noqa: BLE001
                continue
            if nrm.Length > 0.5:
                out.append((face.valueAt(u, v), nrm))
    return out


def exact_ray_blocked(solid, boxes, p, n, d, size):
    """Whether the ray from p (on the solid's face with outward normal n) along d meets
    the solid, by OCCT: the segment from p lifted by RAY_LIFT * size along n, 2 * size
    long, cut with the solid (Shape.common); blocked when a piece longer than
    RAY_LIFT * size lies inside (a ray along a wall or through an edge only grazes).
    ``boxes``: the solid's faces' bounding boxes (slightly enlarged): a ray that meets
    none of them ahead is free without a boolean."""
    start = p + n * (RAY_LIFT * size)
    direction = App.Vector(*d)
    end = start + direction * (2.0 * size)
    # the line meets no face's bounding box ahead of the start: free, no boolean needed
    line_box = App.BoundBox(start, end)
    if not any(box.intersect(line_box) and box.intersect(start, direction) and
               _ahead(box, start, direction) for box in boxes):
        return 0.0
    seg = Part.LineSegment(start, end).toShape()
    return 1.0 if solid.common(seg).Length > RAY_LIFT * size else 0.0


def _ahead(box, start, direction):
    """Whether some corner of ``box`` lies ahead of ``start`` along ``direction``."""
    return any((App.Vector(x, y, z) - start).dot(direction) > 0
               for x in (box.XMin, box.XMax) for y in (box.YMin, box.YMax)
               for z in (box.ZMin, box.ZMax))


def _sides_of(r, f):
    """The side(s) (+1: +d, -1: -d) on which the analysis measured face f's worst
    angle: its surface's side; both when the surface is uncovered or parallel to d
    (there the analysis takes the better side, which the check accepts either way)."""
    s = next(k for k, surf in enumerate(r.surfaces) if f in surf.faces)
    side = r.side[s]
    return (1.0, -1.0) if side in (None, 0) else (float(side),)


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
        ANGLE_STATS.extend(m["angle_gap"] for m in messages if "angle_gap" in m)
        RAY_STATS.extend(m["ray_gap"] for m in messages if "ray_gap" in m)
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

# The ratchet on the known gaps: the corpus meets 3 today (one per KNOWN_GAPS entry).
# This number may only go down: lower it when a gap is closed, never raise it.
MAX_KNOWN_SEEN = 3


class KnownGapRatchet(unittest.TestCase):
    """Runs after Corpus (run_file takes the classes in the file's order): at most
    MAX_KNOWN_SEEN known-gap problems met, however many parts match an entry."""

    def test_known_gaps_do_not_grow(self):
        sys.stdout.write(f"\ncorpus-known-gaps: {len(KNOWN_SEEN)} (at most {MAX_KNOWN_SEEN})\n")
        self.assertLessEqual(len(KNOWN_SEEN), MAX_KNOWN_SEEN, KNOWN_SEEN)


def _report(_result):
    """The corpus's own lines: failures, known gaps seen, timings, reference statistics."""
    total_wall = time.perf_counter() - T0
    for line in FAILURES:
        sys.stdout.write(f"corpus-failure: {line}\n")
    for line in KNOWN_SEEN:
        sys.stdout.write(f"corpus-known: {line}\n")
    for name, wall, status, times in TIMES:
        if times:
            nsolids, nfaces, nbs, tg, ta, tw, tr = times
            what = (f"{nsolids} solids, {nfaces} faces ({nbs} B-spline): gauss maps "
                    f"{tg:.2f} s, analysis {ta:.2f} s (unrotated); checks: worst angles "
                    f"{tw:.2f} s, rays {tr:.2f} s")
        else:
            what = "unfinished"
        sys.stdout.write(f"corpus-timing: {name}: {what}; wall {wall:.1f} s; {status}\n")
    if ANGLE_STATS:
        sys.stdout.write(f"corpus-reference: worst angles of {len(ANGLE_STATS)} faces "
                         f"against OCCT samples: largest |reported - sampled| "
                         f"{math.degrees(max(ANGLE_STATS)):.3g} deg, median "
                         f"{math.degrees(float(np.median(ANGLE_STATS))):.3g} deg\n")
    if RAY_STATS:
        sys.stdout.write(f"corpus-reference: ray check of {len(RAY_STATS)} faces against "
                         f"exact OCCT rays: largest |fraction difference| "
                         f"{max(RAY_STATS):.3f}, {sum(x > 0 for x in RAY_STATS)} differ\n")
    sys.stdout.write(f"corpus: {len(TIMES)} parts in {total_wall:.1f} s wall\n")


sys.path.insert(0, HERE)
from fc_testsupport import run_file  # noqa: E402

T0 = time.perf_counter()
sys.exit(run_file(globals(), "freecad-corpus", before_summary=_report))
