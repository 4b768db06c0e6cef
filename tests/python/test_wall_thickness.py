# SPDX-License-Identifier: LGPL-2.1-or-later
"""core.wall_thickness (issue 21, section 4) against an independent reference: the
oracle's shrinking ball (medial_oracle.Polyhedron.probes: bisection along the inward
normal of a boundary sample for the largest ball tangent there, by brute-force
point-triangle distances; no code shared with libcore).  Where the library says a wall
ball touches a sample (gap 0), that ball is the sample's only maximal ball, so its
diameter must be the shrinking ball's within the medial tolerance; analytic walls (a
plate everywhere, the T-section's flange and web), a cup tessellated (wall 3 within the
tessellation's sag), invariance under a rigid motion, scaled parts, and the binding's
refusals."""

import math

import numpy as np
import pytest

import medial_solids as ms
from medial_oracle import Polyhedron
from mfgeom import core
from mfgeom.core import MfgError


def diag(v):
    return float(np.linalg.norm(v.max(0) - v.min(0)))


def probe_check(v, t, n=300, major_only=True, seed=2):
    """Thickness at n oracle probes; asserts agreement where touched and returns
    (result, reference diameters, touched mask, tolerance)."""
    tol = 0.005 * diag(v)
    poly = Polyhedron(v, t)
    _x, r_ref, q, _face = poly.probes(n, margin=0.02 * diag(v), seed=seed)
    res = core.wall_thickness(v, t, q, tol, major_only=major_only)
    touched = res.gaps < 1e-9 * diag(v)
    err = np.abs(res.thickness - 2 * r_ref)
    assert touched.sum() >= n // 5, touched.sum()
    assert err[touched].max() <= 2 * tol, (err[touched].max(), tol)
    # Elsewhere the point takes a nearby wall ball, never one larger than the part.
    assert (res.thickness > 0).all() and (res.thickness <= diag(v)).all()
    return res, 2 * r_ref, touched, tol


def test_plate_is_its_thickness_everywhere():
    v, t = ms.cuboid(100.0, 60.0, 4.0)
    rng = np.random.default_rng(5)
    # random points on all six faces, the corners and edge midpoints included
    pts = [v[t[i]].T @ rng.dirichlet((1, 1, 1)) for i in rng.integers(0, len(t), 400)]
    pts = np.vstack([pts, v, (v[t[:, 0]] + v[t[:, 1]]) / 2])
    for major in (True, False):
        res = core.wall_thickness(v, t, pts, 0.5, major_only=major)
        assert np.allclose(res.thickness, 4.0, atol=1e-9), res
        assert np.allclose(res.centres[:, 2], 2.0, atol=1e-9)


def test_t_section_against_shrinking_balls():
    v, t = ms.t_section()
    res, ref, touched, tol = probe_check(v, t)
    # flange and web are 10 thick; the thickest spot, under the web: 2 r = 12.5 where
    # (10 - r)^2 + 5^2 = r^2 (the ball through both reflex edges) -- for t_section's
    # proportions width 60, t 10: r = ((t)^2 + (t/2)^2) / (2 t)
    assert res.thickness.min() >= 10.0 - 2 * tol
    assert res.thickness.max() <= 12.5 + 2 * tol


def test_small_tray_and_full_mode():
    v, t = ms.small_tray()
    for major in (True, False):
        res, _ref, _touched, tol = probe_check(v, t, n=250, major_only=major, seed=4)
        # walls and floor are 3 thick, the ribs 2: nothing thinner; the thickest spots are
        # the corners where walls meet the floor (a ball into the three-face corner)
        assert res.thickness.min() >= 2.0 - 2 * tol
        assert res.thickness.max() <= 3.0 * 2 * math.sqrt(3) / (1 + math.sqrt(3)) + 2 * tol


def test_cup_tessellated_wall():
    """The cup, 200 segments: the wall (R 20, 3 thick) is 3 within the chords' sag and the
    tolerance; the bottom 4."""
    n, radius = 200, 20.0
    v, t = ms.cup(n=n)
    tol = 0.005 * diag(v)
    sag = radius * (1 - math.cos(math.pi / n))
    phi = np.linspace(0.1, 2 * math.pi, 50, endpoint=False) + math.pi / n
    # points on the outer facets' middles (mid-height) and on the bottom's underside
    rm = radius * math.cos(math.pi / n)
    wall = np.c_[rm * np.cos(phi), rm * np.sin(phi), np.full(len(phi), 18.0)]
    bottom = np.c_[8 * np.cos(phi), 8 * np.sin(phi), np.zeros(len(phi))]
    res = core.wall_thickness(v, t, np.vstack([wall, bottom]), tol)
    assert np.abs(res.thickness[:50] - 3.0).max() <= 2 * sag + 2 * tol, res
    assert np.abs(res.thickness[50:] - 4.0).max() <= 2 * tol, res


def test_rigid_motion_and_scale():
    v, t = ms.l_bracket()
    tol = 0.005 * diag(v)
    poly = Polyhedron(v, t)
    _x, _r, q, _f = poly.probes(120, margin=1.0, seed=7)
    base = core.wall_thickness(v, t, q, tol)
    moved, R, shift = ms.rigid_motion(v)
    res = core.wall_thickness(moved, t, q @ R.T + shift, tol)
    assert np.abs(res.thickness - base.thickness).max() <= 2 * tol
    assert np.allclose(res.centres, base.centres @ R.T + shift, atol=2 * tol + 1e-9)
    for s in (1e-9, 1e-3, 1e3, 1e9):
        scaled = core.wall_thickness(v * s, t, q * s, tol * s)
        assert np.abs(scaled.thickness / s - base.thickness).max() <= 2 * tol, s


def test_refusals():
    v, t = ms.cuboid(10.0, 6.0, 2.0)
    p = np.array([[5.0, 3.0, 0.0]])
    with pytest.raises(MfgError) as e:
        core.wall_thickness(v, t, [[np.nan, 0, 0]], 0.1)
    assert e.value.status == "invalid argument" and "point 0" in e.value.detail
    with pytest.raises(MfgError) as e:
        core.wall_thickness(v, t, p, 0.1, min_angle=4.0)
    assert "min_angle" in e.value.detail
    with pytest.raises(MfgError) as e:
        core.wall_thickness(v, t[:-1], p, 0.1)
    assert e.value.detail.startswith("mfg_wall_thickness: ") and "not closed" in e.value.detail
    with pytest.raises(ValueError):
        core.wall_thickness(v, t, [[1.0, 2.0]], 0.1)
    with pytest.raises(TypeError):
        core.wall_thickness(v, t, p, 0.1, major_only=1)
    empty = core.wall_thickness(v, t, np.zeros((0, 3)), 0.1)
    assert len(empty) == 0 and repr(empty) == "WallThickness(0 points)"


def test_progress_and_cancel():
    v, t = ms.l_bracket()
    stages = []
    res = core.wall_thickness(v, t, [[25.0, 0.0, 20.0]], 0.5,
                              progress=lambda f, s: stages.append((f, s)) and False)
    fr = [f for f, _s in stages]
    assert fr == sorted(fr) and stages[-1] == (1.0, "thickness: done")
    assert any(s.startswith("medial:") for _f, s in stages)
    assert not any(s == "medial: done" for _f, s in stages)
    assert abs(res.thickness[0] - 10.0) <= 1.0
    with pytest.raises(core.Cancelled):
        core.wall_thickness(v, t, [[25.0, 0.0, 20.0]], 0.5,
                            progress=lambda f, s: s.startswith("thickness"))
