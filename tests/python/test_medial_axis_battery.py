# SPDX-License-Identifier: LGPL-2.1-or-later
"""A randomized battery for mfgeom.core.medial_axis: jittered stars (needle spikes) with
random convex holes, 100 ... 3 000 segments, coordinates on a 1e-3 grid (so FreeCAD's
Path.Voronoi sees exactly the same input).  Per shape, against references that share no
code with the library:
* topology by Euler: leaves = the star's tips (its convex vertices; the holes' vertices are
  reflex), branches = junctions + leaves - 1 + holes (one cycle per hole), degrees +
  leaves = 2 branches;
* soundness: every sample's radius is its brute-force distance to the boundary
  (medial_reference.dist), every sample is inside, every chord midpoint's interpolated
  radius within tol of its clearance;
* completeness: medial points found by bisection along the inward normals of random
  boundary points lie within tol of a branch;
* the topology of Boost's Voronoi diagram (Path.Voronoi, where FreeCAD is installed), with
  Boost's junctions joined by chains shorter than tol contracted as mfgeom does.
And invariance under translation, scaling and rotation."""
import math

import numpy as np
import pytest

from mfgeom import core
from medial_reference import dist, inside, polyline_nearest, segments
import medial_voronoi

TOL = 1e-2


def shape(nseg, holes, seed):
    """A jittered star of nseg edges (tips radius 100, notches 40, +-15 %) and `holes`
    convex holes (regular 3..8-gons of radius 1.5..4, random rotation) placed without
    overlap inside radius 30; on a 1e-3 grid."""
    rng = np.random.default_rng(seed)
    n = nseg // 2
    ang = np.arange(2 * n) * math.pi / n
    rad = np.where(np.arange(2 * n) % 2 == 0, 100.0, 40.0) * (1 + 0.15 * rng.uniform(-1, 1, 2 * n))
    rings = [np.c_[rad * np.cos(ang), rad * np.sin(ang)]]
    centres = []
    while len(centres) < holes:
        c = rng.uniform(-30, 30, 2)
        rr = rng.uniform(1.5, 4)
        if np.hypot(*c) + rr > 32 or any(np.hypot(*(c - c2)) < rr + r2 + 1 for c2, r2 in centres):
            continue
        centres.append((c, rr))
        k = int(rng.integers(3, 9))
        a = rng.uniform(0, 2 * math.pi) + np.arange(k) * 2 * math.pi / k
        rings.append(c + rr * np.c_[np.cos(a), np.sin(a)])
    return [np.round(r, 3) for r in rings], n


def completeness_points(rings, m, rng, reach=250.0):
    """Medial points by bisection along the inward normal of m random boundary points (no
    farther than reach)."""
    A, B = segments(rings)
    D = B - A
    L = np.linalg.norm(D, axis=1)
    k = rng.choice(len(A), m, p=L / L.sum())
    t = rng.uniform(0.02, 0.98, m)
    Q = A[k] + t[:, None] * D[k]
    N = np.c_[-D[k, 1], D[k, 0]] / L[k, None]
    probe = inside(rings, Q + 1e-6 * N)
    N[~probe] *= -1
    lo, hi = np.zeros(m), np.full(m, float(reach))
    for _ in range(60):
        s = (lo + hi) / 2
        ok = dist(Q + s[:, None] * N, A, B) >= s * (1 - 1e-12)
        lo, hi = np.where(ok, s, lo), np.where(ok, hi, s)
    return Q + lo[:, None] * N, lo


CASES = [(100, 0, s) for s in range(1, 5)] + [(300, 3, s) for s in range(5, 8)] + \
        [(1000, 8, 11), (1000, 12, 12), (3000, 16, 13)]


def check_axis(rings, ax, tips, holes, seed, tol=TOL, voronoi=True, slack=1.0):
    """The battery's checks of one axis: Euler topology (leaves = the convex vertices
    `tips`), soundness of every sample, chord midpoints and completeness against bisection
    probes within slack * tol, and (where FreeCAD is installed and `voronoi`) Boost's
    topology."""
    nb, nj = len(ax.branches), len(ax.junctions)
    leaves = sum(int(e == -1) for b in ax.branches for e in b.ends)
    assert leaves == tips
    assert nb == nj + leaves - 1 + holes
    assert int(np.sum(ax.junctions.degrees)) + leaves == 2 * nb
    A, B = segments(rings)
    size = float(np.ptp(np.concatenate(rings), axis=0).max())
    P = np.concatenate([b.points for b in ax.branches])
    R = np.concatenate([b.radii for b in ax.branches])
    assert np.abs(dist(P, A, B) - R).max() <= 1e-9 * size
    assert inside(rings, P[R > 1e-9 * size]).all()
    M = np.concatenate([(b.points[1:] + b.points[:-1]) / 2 for b in ax.branches])
    MR = np.concatenate([(b.radii[1:] + b.radii[:-1]) / 2 for b in ax.branches])
    assert np.abs(dist(M, A, B) - MR).max() <= slack * tol
    Pref, Rref = completeness_points(rings, 400, np.random.default_rng(seed), reach=size)
    keep = Rref >= tol
    if keep.any():
        dn, _ = polyline_nearest(Pref[keep], [(b.points, b.radii) for b in ax.branches])
        assert dn.max() <= slack * tol
    if voronoi and medial_voronoi.available():
        assert (nb, nj) == medial_voronoi.topology(rings, tol)


@pytest.mark.parametrize("nseg,holes,seed", CASES)
def test_battery(nseg, holes, seed):
    rings, tips = shape(nseg, holes, seed)
    check_axis(rings, core.medial_axis(rings, TOL), tips, holes, seed)


def convex_vertices(ring):
    """The convex vertices of a counter-clockwise ring (the axis' leaves)."""
    r = np.asarray(ring, float)
    a, b = r - np.roll(r, 1, axis=0), np.roll(r, -1, axis=0) - r
    return int(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] > 0))


def thin_wedge(seed):
    """A thin 6-vertex wedge whose long sides each have a middle vertex a hair (1e-9 ..
    1e-3 of the width) off the straight line, convex or reflex: at such a corner the end
    of a segment's window is ill-conditioned (issue 22: "the trace of elements 0 and 4
    reached a convex corner ... (a missed event)" at every tolerance)."""
    rng = np.random.default_rng(seed)
    L = 10 ** rng.uniform(0, 2)
    w = L * 10 ** rng.uniform(-3, -1)
    x1, x2 = sorted(rng.uniform(0.1, 0.9, 2) * L)
    eps = w * 10 ** rng.uniform(-9, -3, 2) * rng.choice([-1, 1], 2)
    return np.array([(0, 0), (x1, w * x1 / L + eps[0]), (L, w), (L, 2 * w),
                     (x2, 2 * w * x2 / L + eps[1]), (0, 1e-3 * w)])


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("tol", [0.1, 0.01, 0.001])
def test_thin_wedge(seed, tol):
    ring = thin_wedge(seed)
    check_axis([ring], core.medial_axis(ring, tol), convex_vertices(ring), 0, seed, tol,
               voronoi=False)


def closed_circle(r, n, miss, clockwise=False):
    """A circle of n segments whose last vertex misses the first by `miss` (as FreeCAD's
    polyline of a closed edge ends at cos(2 pi) = 1 + ulps of its start, which the face
    domain kept as its own vertex)."""
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.c_[r * np.cos(phi), r * np.sin(phi)]
    ring = np.vstack([ring, ring[0] + (0.0, miss)])
    return ring[::-1] if clockwise else ring


@pytest.mark.parametrize("tol", [0.5, 0.1, 0.01])
def test_annulus_with_near_duplicate_vertices(tol):
    """A tube end as the face domain gave it (issue 22): each ring's closing vertex within
    1e-13 of its first.  Between two such vertices the axis runs along their perpendicular
    bisector, whose radius sqrt(s^2 + a^2) was sampled for its curvature 1/a at the apex
    along the whole line: 65 M samples and 7 GB at tol 0.1.  The same checks as the
    battery, and the samples bounded by the boundary's size."""
    rings = [closed_circle(10.0, 100, -9.1e-14), closed_circle(5.0, 71, -1.5e-14, clockwise=True)]
    ax = core.medial_axis(rings, tol)
    # a leaf per outer vertex, the near-duplicate pair being one (the library's documented
    # merge of vertices within 1e-11 of the extent); none into the hole (there was a
    # branch along the pair's bisector: their disc gathered both and the tiny edge)
    check_axis(rings, ax, 100, 1, 7, tol, voronoi=False)
    samples = sum(len(b.points) for b in ax.branches)
    assert samples <= 20 * sum(len(r) for r in rings)


def exact_convex_vertices(ring):
    """The convex vertices of a counter-clockwise ring, by exact rational turns (float
    cross products are wrong at turns of 1e-14, as on a circle's polygon on a grid)."""
    from fractions import Fraction
    r = [tuple(map(Fraction, map(float, p))) for p in ring]
    m, count = len(r), 0
    for i in range(m):
        a, b, c = r[i - 1], r[i], r[(i + 1) % m]
        count += (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) > 0
    return count


@pytest.mark.parametrize("n", [8000, 100000])
def test_regular_circle(n):
    """A ring of n vertices on a circle (a finely tessellated round face; issue 22: 10^5
    did not finish in 5 minutes).  One junction at the centre touching all n edges, n
    leaf branches, the centre's radius R cos(pi / n).  (At 8 000 an early event 1.4e-9
    before the centre made a second junction of 1 658 edges and 1 656 leaves twice.)"""
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = 10.0 * np.c_[np.cos(phi), np.sin(phi)]
    ax = core.medial_axis(ring, TOL)
    assert len(ax.junctions) == 1 and len(ax.branches) == n
    assert int(ax.junctions.degrees[0]) == n
    assert abs(ax.junctions.radii[0] - 10.0 * np.cos(np.pi / n)) <= 1e-9
    assert np.hypot(*ax.junctions.points[0]) <= 1e-9
    if n <= 10000:
        small = ring[::4]   # the battery's checks at 2 000
        check_axis([small], core.medial_axis(small, TOL), len(small), 0, 3, voronoi=False)


def grid_circle(n, R):
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.round(R * np.c_[np.cos(phi), np.sin(phi)])


@pytest.mark.parametrize("n,R,tol,full", [(2000, 2e5, 10.0, True), (10000, 1e6, 10.0, False)])
def test_circle_on_a_grid(n, R, tol, full):
    """A circle's polygon rounded to an integer grid: near-cocircular, turns from 1e-3 down
    to 1e-14 rad either way (nearly flat convex and reflex vertices), every junction near
    the centre.  Issue 22: at a corner turning 1e-14 the trace took the next segment's
    grazing entry for the leaf (the corner appended with r jumping from 187 to 0) and the
    pair of the corner's segments for parallel edges; leaves were reached twice, junctions
    doubled (12 084 branches for 6 548 convex corners at 10 000).  The battery's checks,
    the leaves counted exactly, and Boost's topology at 2 000 (at 10 000 it has ~1 % more
    junctions: groups near the contraction threshold, noted in known-gaps)."""
    ring = grid_circle(n, R)
    ax = core.medial_axis(ring, tol)
    tips = exact_convex_vertices(ring)
    if full:
        check_axis([ring], ax, tips, 0, 3, tol)
        return
    # the battery's topology and soundness (its chord and completeness probes take minutes
    # at this size): leaves, Euler, degrees, every junction's radius its clearance
    nb, nj = len(ax.branches), len(ax.junctions)
    leaves = sum(int(e == -1) for b in ax.branches for e in b.ends)
    assert leaves == tips and nb == nj + leaves - 1
    assert int(np.sum(ax.junctions.degrees)) + leaves == 2 * nb
    A, B = segments([ring])
    assert np.abs(dist(ax.junctions.points, A, B) - ax.junctions.radii).max() <= 1e-9 * 2 * R


def flower(n):
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = 10 * (1 + 0.3 * np.sin(37 * phi))
    return np.c_[r * np.cos(phi), r * np.sin(phi)]


@pytest.mark.parametrize("n", [9000, 10000])
def test_flower(n):
    """Flowers r = 10 (1 + 0.3 sin 37 phi) of 9 000 and 10 000 vertices (the 10 000 failed:
    at its inflections two segments meet at turns of 1e-7 rad, where the end of a
    segment's window is ill-conditioned; issue 22: an internal error "... reached a convex
    corner ... (a missed event)").  Chords and completeness within tol: on the petals'
    tips chains of short branches were contracted into one junction over more than tol,
    so some leaf branches started 1.4-1.6 tol off (fixed with the < tol span rule)."""
    ring = flower(n)
    check_axis([ring], core.medial_axis(ring, TOL), convex_vertices(ring), 0, 5, voronoi=False)


@pytest.mark.parametrize("name", ["shift", "scale", "rotate", "huge"])
def test_invariance(name):
    """The same axis under translation by 1e4, scaling by 1e-3 (tol too; Boost's 1e-3
    input grid would destroy it) and 1e6, rotation by 30 degrees: same branch and junction
    counts, junctions (mapped back) within 1e-9 of the diagonal, same degrees."""
    rings, _ = shape(1000, 8, 11)
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    rot = np.array([[c, -s], [s, c]])
    fwd, back, k = {
        "shift": (lambda r: r + [1e4, -2e4], lambda r: r - [1e4, -2e4], 1.0),
        "scale": (lambda r: r * 1e-3, lambda r: r * 1e3, 1e-3),
        "huge": (lambda r: r * 1e6, lambda r: r * 1e-6, 1e6),
        "rotate": (lambda r: r @ rot.T, lambda r: r @ rot, 1.0)}[name]
    base = core.medial_axis(rings, TOL)
    ax = core.medial_axis([fwd(r) for r in rings], TOL * k)
    assert (len(ax.branches), len(ax.junctions)) == (len(base.branches), len(base.junctions))
    P = back(ax.junctions.points)
    d = np.hypot(P[:, None, 0] - base.junctions.points[None, :, 0],
                 P[:, None, 1] - base.junctions.points[None, :, 1])
    j = d.argmin(axis=1)
    assert d[np.arange(len(j)), j].max() <= 1e-9 * 230
    assert np.array_equal(ax.junctions.degrees, base.junctions.degrees[j])
    assert np.abs(ax.junctions.radii / k - base.junctions.radii[j]).max() <= 1e-9 * 230


def test_topology_100k():
    """Regression: at 100 000 segments junctions at the needle bases lie 1e-4 apart; an
    arriving trace identified its junction by position alone (1e-6 of the diagonal) and
    took a neighbour for it, leaving a true junction out -- four zero-length loops, four
    branches more than Euler allows.  Topology only (Euler, no loops); the brute-force
    checks above would take minutes here."""
    rings, tips = shape(100000, 16, 7)
    ax = core.medial_axis(rings, TOL)
    ends = np.array([b.ends for b in ax.branches])
    leaves = int((ends == -1).sum())
    assert leaves == tips
    assert not np.any((ends[:, 0] == ends[:, 1]) & (ends[:, 0] >= 0))
    assert len(ax.branches) == len(ax.junctions) + leaves - 1 + 16
    assert int(np.sum(ax.junctions.degrees)) + leaves == 2 * len(ax.branches)
