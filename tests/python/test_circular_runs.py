# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.geometry.circular_runs: the circular stretches of a polyline (the medial axis
of a face draws them as arcs, issue 22), against curves whose circles are known."""

import numpy as np
import pytest

from mfgeom.geometry.circular_runs import arcs_of_branches, circular_runs, fit_circle


def arc_mids(points, eps, centres=None):
    """Each edge's point halfway round its arc (NaN: straight), one branch on its own."""
    p, circles, _moved = arcs_of_branches([points], eps, centres)
    p, c = p[0], circles[0]
    d = p - np.nan_to_num(np.vstack([c[:, :2], c[-1:, :2]]))
    ang = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    half = 0.5 * (ang[:-1] + ang[1:])
    return c[:, :2] + c[:, 2:] * np.column_stack([np.cos(half), np.sin(half)])


def _circle(c, r, a0, a1, n):
    a = np.linspace(a0, a1, n)
    return np.column_stack([c[0] + r * np.cos(a), c[1] + r * np.sin(a)])


def test_fit_circle_exact_and_collinear():
    c, r = fit_circle(_circle((3.0, -2.0), 7.5, 0.1, 2.0, 9))
    np.testing.assert_allclose(c, [3.0, -2.0], atol=1e-12)
    assert r == pytest.approx(7.5, abs=1e-12)
    assert fit_circle(np.column_stack([np.arange(5.0), 2 * np.arange(5.0)])) is None


def test_full_circle_is_one_run_and_mids_lie_on_it():
    """The axis of a tube's end face: a closed loop at radius 7.5 (first = last)."""
    p = _circle((0.0, 0.0), 7.5, 0.0, 2 * np.pi, 41)
    runs = circular_runs(p, 1e-3)
    assert [(a, b) for a, b, _c, _r in runs] == [(0, 40)]
    mids = arc_mids(p, 1e-3)
    assert not np.isnan(mids).any()
    np.testing.assert_allclose(np.hypot(mids[:, 0], mids[:, 1]), 7.5, atol=1e-12)
    # halfway round: equidistant from its edge's two samples
    np.testing.assert_allclose(np.linalg.norm(mids - p[:-1], axis=1),
                               np.linalg.norm(mids - p[1:], axis=1), atol=1e-12)


def test_straight_line_and_zigzag_have_no_runs():
    line = np.column_stack([np.linspace(0, 10, 12), np.zeros(12)])
    line[:, 1] += 1e-9 * np.sin(np.arange(12))   # rounding noise: chords are the curve
    assert circular_runs(line, 1e-3) == []
    zig = np.column_stack([np.arange(10.0), np.tile([0.0, 1.0], 5)])
    assert circular_runs(zig, 0.1) == []
    assert np.isnan(arc_mids(zig, 0.1)).all()


def test_line_then_arc_then_line():
    """A slot's axis seen as a polyline: straight, a half circle of radius 2 about
    (10, 2), straight back.  Only the half circle's edges are arcs."""
    a = np.column_stack([np.linspace(0, 10, 6), np.zeros(6)])
    arc = _circle((10.0, 2.0), 2.0, -np.pi / 2, np.pi / 2, 13)
    b = np.column_stack([np.linspace(10, 0, 6), np.full(6, 4.0)])
    p = np.vstack([a, arc[1:], b[1:]])
    runs = circular_runs(p, 1e-6)
    assert len(runs) == 1
    first, last, c, r = runs[0]
    assert (first, last) == (5, 17)
    np.testing.assert_allclose(c, [10.0, 2.0], atol=1e-9)
    assert r == pytest.approx(2.0, abs=1e-9)
    mids = arc_mids(p, 1e-6)
    assert np.isnan(mids[:5]).all() and np.isnan(mids[17:]).all()
    assert not np.isnan(mids[5:17]).any()


def test_eps_decides_on_a_parabola():
    """y = x^2 / 20 over [-5, 5]: with eps above its best circle's largest deviation one
    run; with eps far below what even 4 of its samples deviate, none."""
    x = np.linspace(-5, 5, 21)
    p = np.column_stack([x, x * x / 20])
    c, r = fit_circle(p)
    dev = np.abs(np.linalg.norm(p - c, axis=1) - r).max()
    assert 1e-4 < dev < 1e-1
    assert [(a, b) for a, b, _c, _r in circular_runs(p, 1.5 * dev)] == [(0, 20)]
    assert circular_runs(p, 1e-9) == []


def test_noisy_circle_within_eps_and_long():
    rng = np.random.default_rng(7)
    p = _circle((1.0, 1.0), 5.0, 0.0, 3.0, 2000)
    p += rng.uniform(-1e-4, 1e-4, p.shape)
    runs = circular_runs(p, 1e-3)
    assert [(a, b) for a, b, _c, _r in runs] == [(0, 1999)]
    assert runs[0][3] == pytest.approx(5.0, abs=2e-4)


def test_known_centre_takes_three_samples():
    """A coarse tube axis: 3 samples a quarter turn apart at radius 7.5 about the
    origin (no circle can be fitted to 3 points with any check); about the known centre
    they are a run, about another centre not."""
    p = _circle((0.0, 0.0), 7.5, 0.0, np.pi / 2, 3)
    assert circular_runs(p, 1e-3) == []
    runs = circular_runs(p, 1e-3, centres=[(0.0, 0.0)])
    assert [(a, b) for a, b, _c, _r in runs] == [(0, 2)]
    assert runs[0][3] == pytest.approx(7.5)
    assert circular_runs(p, 1e-3, centres=[(1.0, 0.0)]) == []
    straight = np.array([[7.5, 0.0], [7.5, 1.0], [7.5, 2.0]])   # equal radii? no: a chord
    assert circular_runs(straight, 1e-3, centres=[(0.0, 0.0)]) == []


def test_branches_move_together_onto_the_circle():
    """Two branches of a coarse ring meeting at a junction point, their samples up to
    0.01 off the radius 7.5: both runs about the known centre get one circle (the mean
    of their radii), the shared end stays shared, the junction's copy is reported, a
    straight third branch from the junction moves its end along."""
    def at(r, a):
        return [r * np.cos(a), r * np.sin(a)]
    a = np.array([at(7.49, 0.0), at(7.5, 0.3), at(7.505, 0.6)])
    b = np.array([a[2], at(7.5, 0.9), at(7.495, 1.2)])
    spoke = np.array([a[2], 1.3 * a[2]])
    out, circles, moved = arcs_of_branches([a, b, spoke], 0.05, centres=[(0.0, 0.0)])
    r = 0.5 * (np.mean([7.49, 7.5, 7.505]) + np.mean([7.505, 7.5, 7.495]))
    for p in out[:2]:
        np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 1]), r, atol=1e-12)
    assert np.array_equal(out[0][2], out[1][0]) and np.array_equal(out[2][0], out[0][2])
    np.testing.assert_array_equal(moved[tuple(a[2])], out[0][2])
    for c in circles[:2]:
        np.testing.assert_allclose(c, [[0.0, 0.0, r]] * 2, atol=1e-12)
    assert np.isnan(circles[2]).all()
    np.testing.assert_array_equal(out[2][1], spoke[1])   # the spoke's far end stays


def test_different_circles_at_a_shared_point_leave_the_edge_straight():
    """Two fitted runs (no known centre) of different circles sharing an end: the second
    run's edge at the shared point (moved onto the first circle) is straight."""
    a = _circle((0.0, 0.0), 5.0, 0.0, 1.0, 6)
    b = _circle(a[-1] + 2.0 * a[-1] / 5.0, 2.0, np.pi + 1.0, np.pi + 2.0, 6)
    np.testing.assert_allclose(b[0], a[-1], atol=1e-12)
    b[0] = a[-1]
    b[1:] += 1e-3 * (b[1:] - b[0])     # the second circle slightly off the first's end
    out, circles, _moved = arcs_of_branches([a, b], 1e-2)
    assert not np.isnan(circles[0]).any()
    assert np.array_equal(out[1][0], out[0][-1])
