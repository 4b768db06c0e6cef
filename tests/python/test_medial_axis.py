# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.core.medial_axis against the hand-derived axes of docs/design/axis2d.md section 4 (rectangle,
square, frame, L, regular 5-star) and the independent bisection oracle of
medial_reference.py (soundness: every sample inside with radius = clearance; completeness:
every oracle medial point within tol of a branch) on jittered stars with holes."""
import math

import numpy as np
import pytest

from mfgeom import core
from medial_reference import check_axis, dist, segments

TOL = 1e-2
T = (2 - math.sqrt(2)) * 2  # the frame's and the L's corner junction (w = 2)


def star(n, R=10.0, r=4.0, jitter=0.0, seed=1):
    rng = np.random.default_rng(seed)
    ang = np.arange(2 * n) * math.pi / n
    rad = np.where(np.arange(2 * n) % 2 == 0, R, r) * (1 + jitter * rng.uniform(-1, 1, 2 * n))
    return np.c_[rad * np.cos(ang), rad * np.sin(ang)]


def star_with_holes(n, holes, seed):
    rings = [star(n // 2, R=100, r=40, jitter=0.15, seed=seed)]
    for k in range(holes):
        c = 20 * np.array([math.cos(k * 2 * math.pi / holes), math.sin(k * 2 * math.pi / holes)])
        rings.append(c + np.array([(-2, -2), (-2, 2), (2, 2), (2, -2)], float))
    return rings


# name: rings, expected junctions (x, y, r, degree), branches
EXPECTED = {
    "rectangle": ([[(0, 0), (10, 0), (10, 4), (0, 4)]],
                  [(2, 2, 2, 3), (8, 2, 2, 3)], 5),
    "square": ([[(0, 0), (4, 0), (4, 4), (0, 4)]], [(2, 2, 2, 4)], 4),
    "frame": ([[(0, 0), (10, 0), (10, 10), (0, 10)], [(2, 2), (2, 8), (8, 8), (8, 2)]],
              [(T, T, T, 3), (10 - T, T, T, 3), (T, 10 - T, T, 3), (10 - T, 10 - T, T, 3)], 8),
    "L": ([[(0, 0), (10, 0), (10, 2), (2, 2), (2, 8), (0, 8)]],
          [(T, T, T, 3), (1, 7, 1, 3), (9, 1, 1, 3)], 7),
    # the regular 5-star: ONE junction of degree 5 touching the 5 reflex vertices (Boost
    # splits it in two)
    "star5": ([star(5)], [(0, 0, 4, 5)], 5),
}


def _sorted_junctions(ax):
    return sorted((round(float(p[0]), 6), round(float(p[1]), 6), round(float(r), 6), int(d))
                  for p, r, d in zip(ax.junctions.points, ax.junctions.radii, ax.junctions.degrees))


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_hand_derived(name):
    rings, junctions, nbranches = EXPECTED[name]
    ax = core.medial_axis([np.asarray(r, float) for r in rings], TOL)
    assert len(ax.branches) == nbranches
    assert len(ax.junctions) == len(junctions)
    for x, y, r, deg in junctions:
        d = np.hypot(ax.junctions.points[:, 0] - x, ax.junctions.points[:, 1] - y)
        j = int(d.argmin())
        assert d[j] < 1e-9 * 20 and abs(ax.junctions.radii[j] - r) < 1e-9 * 20
        assert ax.junctions.degrees[j] == deg
    chk = check_axis(rings, [(b.points, b.radii) for b in ax.branches], TOL)
    assert chk["max_radius_error"] < 1e-9
    assert chk["max_mid_radius_error"] <= TOL
    assert chk["outside"] == 0 and chk["not_medial"] == 0
    assert chk["ref_missed"] == 0


@pytest.mark.parametrize("n,holes,seed,topology,h", [(20, 0, 1, (17, 8), 0.5), (50, 4, 3, (58, 30), 0.5),
                                                          (200, 8, 5, (220, 113), 2.0)])
def test_against_oracle(n, holes, seed, topology, h):
    """Jittered stars with holes; the branch / junction counts are Path.Voronoi's (Boost)
    on the same shapes, measured once when the axis was built (Boost 1.74, FreeCAD 0.20.2)."""
    rings = star_with_holes(n, holes, seed)
    ax = core.medial_axis(rings, TOL)
    assert (len(ax.branches), len(ax.junctions)) == topology
    chk = check_axis(rings, [(b.points, b.radii) for b in ax.branches], TOL, h=h)
    assert chk["max_radius_error"] < 1e-9 * 230
    assert chk["max_mid_radius_error"] <= TOL
    assert chk["outside"] == 0 and chk["not_medial"] == 0
    assert chk["ref_missed"] == 0


def test_invariant_under_start_vertex_and_orientation():
    rings = star_with_holes(50, 4, 3)
    base = np.array(_sorted_junctions(core.medial_axis(rings, TOL)))
    turned = [np.roll(r, 7, axis=0)[::-1] for r in rings]
    other = np.array(_sorted_junctions(core.medial_axis(turned, TOL)))
    assert other.shape == base.shape
    # the same junctions up to the event accuracy (1e-7 of the diagonal, 230)
    assert np.abs(other - base).max() <= 1e-7 * 230


def test_junction_elements():
    # the L: the corner junction touches edge 0 (y = 0), edge 5 (x = 0) and the reflex
    # vertex 3 (2, 2) -> -4
    ax = core.medial_axis(np.array([(0, 0), (10, 0), (10, 2), (2, 2), (2, 8), (0, 8)], float), TOL)
    j = int(np.argmin(np.hypot(ax.junctions.points[:, 0] - T, ax.junctions.points[:, 1] - T)))
    assert sorted(ax.junctions.elements[j].tolist()) == [-4, 0, 5]


def test_radius_is_clearance_at_every_sample():
    rings = EXPECTED["frame"][0]
    ax = core.medial_axis([np.asarray(r, float) for r in rings], 1e-3)
    A, B = segments(rings)
    for b in ax.branches:
        assert np.abs(dist(b.points, A, B) - b.radii).max() < 1e-9


@pytest.mark.parametrize("rings,tol,needle", [
    ([[(0, 0), (1, 0), (1, 1), (0, 1)]], 0.0, "tolerance"),
    ([[(0, 0), (1, 0), (1, 1), (0, 1)]], -1.0, "tolerance"),
    ([[(0, 0), (1, 0), (float("nan"), 1), (0, 1)]], 1e-3, "NaN"),
    ([[(0, 0), (1, 0)]], 1e-3, "fewer than 3"),
    ([[(0, 0), (1, 1), (1, 0), (0, 1)]], 1e-3, "crosses"),
    ([[(0, 0), (4, 0), (4, 4), (0, 4)], [(0, 2), (1, 1), (1, 3)]], 1e-3, "touches"),
])
def test_bad_input(rings, tol, needle):
    with pytest.raises(core.MfgError) as ex:
        core.medial_axis([np.asarray(r, float) for r in rings], tol)
    assert needle in str(ex.value)
