# SPDX-License-Identifier: LGPL-2.1-or-later
"""The swept-volume oracle (sweep_oracle.py) against analytic swept volumes, by
Monte-Carlo estimates (within 3 sigma) and by points whose membership is known."""

import math

import numpy as np
import pytest

from sweep_oracle import box_mesh, inside_solid, inside_swept, prism_mesh


def monte_carlo(lo, hi, n, seed, *sweep):
    """(estimate, sigma) of the swept volume from n uniform points in the box [lo, hi]."""
    rng = np.random.default_rng(seed)
    lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    pts = lo + (hi - lo) * rng.random((n, 3))
    frac = np.count_nonzero(inside_swept(pts, *sweep)) / n
    box = float(np.prod(hi - lo))
    return box * frac, box * math.sqrt(max(frac * (1 - frac), 1.0 / n) / n)


def random_rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def test_inside_solid_box():
    v, t = box_mesh((0, 0, 0), (1, 2, 3))
    pts = np.array([[0.5, 1, 1.5], [1.5, 1, 1.5], [0.01, 1.99, 2.99], [-0.01, 1, 1]])
    assert inside_solid(pts, v, t).tolist() == [True, False, True, False]


def test_theta_zero_is_the_solid():
    v, t = box_mesh((0.2, -0.3, 0), (1, 0.5, 1))
    rng = np.random.default_rng(1)
    pts = rng.uniform(-1.5, 1.5, (5000, 3))
    np.testing.assert_array_equal(inside_swept(pts, v, t, (0, 0, 0), (0, 0, 1), 0.0),
                                  inside_solid(pts, v, t))


def test_cube_about_its_diagonal_full_turn():
    """A unit cube spun about its long diagonal: volume pi / sqrt(3)."""
    v, t = box_mesh()
    exact = math.pi / math.sqrt(3)
    # The profile integral as a second reference: the slice at height s along the axis
    # reaches farthest at a point of a cube edge; pi * r_max(s)^2 integrated.
    a = np.ones(3) / math.sqrt(3)
    s = (np.arange(20000) + 0.5) / 20000 * math.sqrt(3)
    rmax = np.zeros_like(s)
    for i in range(8):
        for k in range(3):
            if not i & (1 << k):
                p, q = v[i], v[i | (1 << k)]      # a cube edge p -> q
                hp, hq = p @ a, q @ a
                f = np.clip((s - hp) / (hq - hp), 0, 1)
                ok = (s >= min(hp, hq)) & (s <= max(hp, hq))
                x = p + f[:, None] * (q - p)
                r = np.linalg.norm(x - np.outer(x @ a, a), axis=1)
                rmax = np.where(ok, np.maximum(rmax, r), rmax)
    profile = float(np.sum(math.pi * rmax ** 2) * (math.sqrt(3) / len(s)))
    assert profile == pytest.approx(exact, rel=1e-4)
    # The solid lies in the cube's circumscribed sphere (the axis passes its centre).
    c, R = 0.5, math.sqrt(3) / 2
    est, sigma = monte_carlo([c - R] * 3, [c + R] * 3, 200_000, 7, v, t, (0, 0, 0), (1, 1, 1),
                             2 * math.pi)
    assert abs(est - exact) < 3 * sigma, (est, exact, sigma)


def box_about_edge_area(a, b, theta):
    """Area swept in the xy-plane by the rectangle [0, a] x [0, b] turning about its
    corner (the origin) by 0 .. theta, for theta <= 3 pi / 2.

    In polar coordinates the rectangle is r <= r_R(psi), psi in [0, pi/2], with r_R rising
    from a to the diagonal d = sqrt(a^2 + b^2) at psi0 = atan(b/a), then falling to b.  The
    union's radius at angle psi is the largest r_R over the window [psi - theta, psi]:
      psi < psi0:                  r_R(psi)          (the rectangle at t = 0, below its
                                                      diagonal: a triangle of area ab/2)
      psi0 <= psi <= psi0 + theta: d                 (a sector of angle theta: d^2 theta/2)
      psi > psi0 + theta:          r_R(psi - theta)  (the turned rectangle above its
                                                      diagonal: area ab/2)
    and the three pieces do not overlap while theta + pi/2 <= 2 pi.  So the shape is two
    half-rectangles joined by a sector, of area ab + d^2 theta / 2."""
    assert theta <= 1.5 * math.pi
    return a * b + (a * a + b * b) * theta / 2


@pytest.mark.parametrize("theta", [0.7, math.pi / 2, math.pi, 4.0])
def test_box_about_its_edge(theta):
    a, b, c = 1.0, 2.0, 1.5
    v, t = box_mesh((0, 0, 0), (a, b, c))
    d = math.hypot(a, b)
    exact = c * box_about_edge_area(a, b, theta)
    est, sigma = monte_carlo([-d, -d, 0], [d, d, c], 200_000, 11, v, t, (0, 0, 0), (0, 0, 1),
                             theta)
    assert abs(est - exact) < 3 * sigma, (theta, est, exact, sigma)
    # Points of known membership: just inside / outside the sector of radius d, in the
    # middle of the turn; the diagonal's end turned by theta (inside) and a bit further.
    psi0 = math.atan2(b, a)
    mid = psi0 + theta / 2
    pts = np.array([[0.999 * d * math.cos(mid), 0.999 * d * math.sin(mid), 0.5 * c],
                    [1.001 * d * math.cos(mid), 1.001 * d * math.sin(mid), 0.5 * c],
                    [0.99 * d * math.cos(psi0 + theta - 0.001), 0.99 * d * math.sin(psi0 + theta - 0.001), 1.0],
                    [0.99 * d * math.cos(psi0 + theta + 0.05), 0.99 * d * math.sin(psi0 + theta + 0.05), 1.0],
                    [0.5 * math.cos(mid), 0.5 * math.sin(mid), c + 0.01]])
    assert inside_swept(pts, v, t, (0, 0, 0), (0, 0, 1), theta).tolist() == \
        [True, False, True, False, False]


def test_box_about_its_edge_full_turn():
    """theta = 2 pi: a cylinder of radius the diagonal."""
    a, b, c = 1.0, 2.0, 1.5
    v, t = box_mesh((0, 0, 0), (a, b, c))
    d = math.hypot(a, b)
    exact = math.pi * d * d * c
    est, sigma = monte_carlo([-d, -d, 0], [d, d, c], 100_000, 12, v, t, (0, 0, 0), (0, 0, 1),
                             2 * math.pi)
    assert abs(est - exact) < 3 * sigma, (est, exact, sigma)


def test_cylinder_off_centre_solid_of_revolution():
    """A 16-gon prism of circumradius r centred at distance D from the axis, a full turn:
    the annulus between D - r and D + r (vertices 0 and n/2 lie on the line through the
    axis, and they are the nearest and farthest points) times the height."""
    D, r, H = 3.0, 1.0, 2.0
    v, t = prism_mesh((D, 0.0), r, H, 16)
    exact = math.pi * ((D + r) ** 2 - (D - r) ** 2) * H
    R = D + r
    est, sigma = monte_carlo([-R, -R, 0], [R, R, H], 200_000, 13, v, t, (0, 0, 0), (0, 0, 1),
                             2 * math.pi)
    assert abs(est - exact) < 3 * sigma, (est, exact, sigma)
    ang = np.linspace(0, 2 * math.pi, 9)[:-1]
    inner = np.column_stack([(D - r) * 1.01 * np.cos(ang), (D - r) * 1.01 * np.sin(ang), np.full(8, 1.0)])
    hole = inner * [0.98 / 1.01, 0.98 / 1.01, 1.0]
    assert inside_swept(inner, v, t, (0, 0, 0), (0, 0, 1), 2 * math.pi).all()
    assert not inside_swept(hole, v, t, (0, 0, 0), (0, 0, 1), 2 * math.pi).any()


def test_rigid_motion_invariance():
    """Moving the solid, the axis and the points together changes no answer."""
    rng = np.random.default_rng(5)
    v, t = box_mesh((0, 0, 0), (1.0, 2.0, 1.5))
    pts = rng.uniform([-2.3, -2.3, 0], [2.3, 2.3, 1.5], (20000, 3))
    base = inside_swept(pts, v, t, (0, 0, 0), (0, 0, 1), 2.0)
    for _ in range(3):
        rot, shift = random_rotation(rng), rng.normal(size=3) * 10
        moved = inside_swept(pts @ rot.T + shift, v @ rot.T + shift, t, shift, rot[:, 2], 2.0)
        # Rounding may move a point lying within ~1e-12 of the boundary: none here.
        assert np.count_nonzero(moved != base) == 0


def test_axis_direction_sets_the_turn():
    """Turning about -a by theta is turning about a by -theta: the mirror image."""
    v, t = box_mesh((0, 0, 0), (1.0, 2.0, 1.5))
    rng = np.random.default_rng(9)
    pts = rng.uniform([-2.3, -2.3, 0], [2.3, 2.3, 1.5], (20000, 3))
    mirror = pts * [1, -1, 1]
    vm = v * [1, -1, 1]
    tm = t[:, ::-1]
    np.testing.assert_array_equal(inside_swept(pts, v, t, (0, 0, 0), (0, 0, -1), 1.0),
                                  inside_swept(mirror, vm, tm, (0, 0, 0), (0, 0, 1), 1.0))
