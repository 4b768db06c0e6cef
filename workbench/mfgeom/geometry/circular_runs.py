# SPDX-License-Identifier: LGPL-2.1-or-later
"""Circular runs of a 2-D polyline (FreeCAD-free, numpy only): the stretches of
consecutive samples that lie on one circle within a distance, so that the medial axis of
a face (mfgeom.app.medial_axis_feature) draws them as arcs of that circle.

Why (issue 22): the medial axis comes out of the library as polylines, even where the
face's boundary is circular and so is its axis (a tube's end face: the axis of two
concentric circles is the circle between them).  A CAD user expects the arc -- a toolpath
along it is a G2/G3 move, a FEM beam along it is curved -- not a polygon of chords.  The
samples stay where they are and keep their radii; only the edges between them become
arcs (through their two samples and the fitted circle's point halfway round).

A run is at least MIN_SAMPLES samples whose distances to the fitted circle (or
KNOWN_MIN_SAMPLES about a known centre: a circular edge's of the face) are all within
``eps``, turning one way about its centre by less than a half turn between neighbours,
and whose circle is not nearly straight (radius at most MAX_RADIUS_RATIO times the run's
extent: there the chords are the curve).  Runs are grown greedily from the start,
doubling then halving their length (O(n log n) fits of O(run) each).
"""

from typing import Dict, List, Optional, Tuple

import numpy as np

MIN_SAMPLES = 4          # a fitted circle (any 3 points have one)
KNOWN_MIN_SAMPLES = 3    # a circle about a known centre
MAX_RADIUS_RATIO = 1e3


def fit_circle(points: np.ndarray) -> Optional[Tuple[np.ndarray, float]]:
    """(centre (2,), radius) of the least-squares (algebraic, Kasa) circle through the
    2-D ``points`` (k >= 3), or None when they are collinear."""
    p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    mean = p.mean(axis=0)
    q = p - mean
    scale = float(np.abs(q).max())
    if not scale > 0.0:
        return None
    q = q / scale
    A = np.column_stack([2.0 * q, np.ones(len(q))])
    b = (q * q).sum(axis=1)
    sol, _res, rank, _sv = np.linalg.lstsq(A, b, rcond=None)
    if rank < 3:
        return None
    r2 = sol[2] + sol[0] ** 2 + sol[1] ** 2
    if not r2 > 0.0:
        return None
    return mean + scale * sol[:2], scale * float(np.sqrt(r2))


def _turns_one_way(d: np.ndarray) -> bool:
    """Do the directions ``d`` (k, 2) from a centre turn one way, less than a half turn
    between neighbours?"""
    turn = np.angle(np.exp(1j * np.diff(np.arctan2(d[:, 1], d[:, 0]))))
    return bool(np.all(turn > 0) or np.all(turn < 0))


def _run_circle(p: np.ndarray, eps: float, centres: np.ndarray
                ) -> Optional[Tuple[np.ndarray, float]]:
    """The circle of the run ``p`` when it is one (see the module), else None: about one
    of the known ``centres`` (m, 2) first, else the fitted circle."""
    for c in centres:
        d = p - c
        rho = np.hypot(d[:, 0], d[:, 1])
        radius = float(rho.mean())
        if radius > 0.0 and np.abs(rho - radius).max() <= eps and _turns_one_way(d):
            return c, radius
    if len(p) < MIN_SAMPLES:
        return None
    fit = fit_circle(p)
    if fit is None:
        return None
    centre, radius = fit
    extent = float(np.linalg.norm(p.max(axis=0) - p.min(axis=0)))
    if not radius <= MAX_RADIUS_RATIO * extent:
        return None
    d = p - centre
    if np.abs(np.hypot(d[:, 0], d[:, 1]) - radius).max() > eps or not _turns_one_way(d):
        return None
    return centre, radius


def circular_runs(points: np.ndarray, eps: float, centres: Optional[np.ndarray] = None
                  ) -> List[Tuple[int, int, np.ndarray, float]]:
    """The circular runs of the polyline ``points`` (k, 2): [(first, last, centre,
    radius), ...], samples first .. last inclusive, in order; consecutive runs may share
    an end sample.  ``centres`` (m, 2): the centres of the circles of the face's boundary
    -- the axis between concentric circles is a circle about their centre, and at a
    coarse tolerance a branch may have only 3 samples, too few to fit a circle to."""
    p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    known = (np.zeros((0, 2)) if centres is None
             else np.asarray(centres, dtype=np.float64).reshape(-1, 2))
    n = len(p)
    runs = []
    i = 0
    while i + KNOWN_MIN_SAMPLES <= n:
        j = i + KNOWN_MIN_SAMPLES - 1
        circle = _run_circle(p[i:j + 1], eps, known)
        if circle is None and i + MIN_SAMPLES <= n:
            j = i + MIN_SAMPLES - 1
            circle = _run_circle(p[i:j + 1], eps, known)
        if circle is None:
            i += 1
            continue
        # grow: double the step while the longer run still fits, then halve it
        step = 1
        while j + step < n:
            c = _run_circle(p[i:j + step + 1], eps, known)
            if c is None:
                break
            j, circle = j + step, c
            step *= 2
        while step > 1:
            step //= 2
            if j + step < n:
                c = _run_circle(p[i:j + step + 1], eps, known)
                if c is not None:
                    j, circle = j + step, c
        runs.append((i, j, circle[0], circle[1]))
        i = j
    return runs


def _shared_radii(runs: List[List[list]], known: np.ndarray, eps: float) -> None:
    """Gives the runs about one known centre whose radii lie within 2 ``eps`` of each
    other (a ring's branches between its junctions) one radius, their mean: they then
    move the samples they share to the same place."""
    for k in range(len(known)):
        about = sorted(((run[3], run) for branch in runs for run in branch
                        if run[4] == k), key=lambda item: item[0])
        group: List[list] = []
        for radius, run in about + [(np.inf, None)]:
            if group and radius - group[0][3] > 2 * eps:
                mean = float(np.mean([g[3] for g in group]))
                for g in group:
                    g[3] = mean
                group = []
            if run is not None:
                group.append(run)


def arcs_of_branches(branches: List[np.ndarray], eps: float,
                     centres: Optional[np.ndarray] = None
                     ) -> Tuple[List[np.ndarray], List[np.ndarray], Dict[Tuple[float, float], np.ndarray]]:
    """The branches of a medial axis (a list of (k, 2) polylines) with their circular
    runs made arcs: (branches, circles, moved).  The samples of each run are moved onto
    its circle (by at most ``eps``; runs about one known centre with radii within 2 eps
    share one circle) -- every sample of any branch at the same point with them (the
    branches' ends at a junction are one point: they stay one), the first run to reach a
    point deciding.  ``circles`` per branch (k - 1, 3): the circle (centre x, y, radius)
    each edge is an arc of, NaN for a straight edge (also an edge of a run whose end
    another run's circle moved off its own); ``moved``: {(x, y) before: after} for the
    caller's other copies of those points (the junctions).  Why move them: a coarse
    axis has branches of 3 or 4 samples whose distances to the centre differ by up to
    the tolerance's rounding; an arc through two of them and a point on the run's circle
    would have any radius and centre."""
    known = (np.zeros((0, 2)) if centres is None
             else np.asarray(centres, dtype=np.float64).reshape(-1, 2))
    pts = [np.asarray(b, dtype=np.float64).reshape(-1, 2) for b in branches]
    runs = []   # per branch: [first, last, centre, radius, known centre index or -1]
    for p in pts:
        found = []
        for first, last, centre, radius in circular_runs(p, eps, known):
            hit = [k for k in range(len(known)) if np.array_equal(known[k], centre)]
            found.append([first, last, centre, radius, hit[0] if hit else -1])
        runs.append(found)
    _shared_radii(runs, known, eps)
    moved: Dict[Tuple[float, float], np.ndarray] = {}
    for p, found in zip(pts, runs):
        for first, last, centre, radius, _k in found:
            d = p[first:last + 1] - centre
            onto = centre + radius * d / np.hypot(d[:, 0], d[:, 1])[:, None]
            for q, r in zip(p[first:last + 1].tolist(), onto):
                moved.setdefault((q[0], q[1]), r)
    out, circles = [], []
    for p, found in zip(pts, runs):
        p = np.array([moved.get((q[0], q[1]), q) for q in p.tolist()],
                     dtype=np.float64).reshape(-1, 2)
        c = np.full((max(len(p) - 1, 0), 3), np.nan)
        for first, last, centre, radius, _k in found:
            d = p[first:last + 1] - centre
            on = np.abs(np.hypot(d[:, 0], d[:, 1]) - radius) <= 1e-9 * max(radius, 1.0)
            for i in range(first, last):
                if on[i - first] and on[i + 1 - first]:
                    c[i] = (centre[0], centre[1], radius)
        out.append(p)
        circles.append(c)
    return out, circles, moved
