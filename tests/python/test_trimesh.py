# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.geometry.trimesh (what the clearance check asks of the sweep's mesh): point
containment against boxes analytically and a torus against the independent winding
oracle (tests/python/sweep_oracle.py), points on the grid lines of an axis-aligned mesh
where a ray grazes edges, box gaps against brute force, and the grouped lower bounds
never above the true gaps."""

import numpy as np
import pytest

from mfgeom.geometry import trimesh
from sweep_oracle import box_mesh, inside_solid, torus_mesh
from test_planar import grid_box

RNG = np.random.default_rng(21)


def test_box_containment_is_the_analytic_one():
    v, t = box_mesh((1.0, -2.0, 0.5), (4.0, 3.0, 2.5))
    mesh = trimesh.TriangleMesh(v, t)
    assert mesh.volume == pytest.approx(3 * 5 * 2) and mesh.area == pytest.approx(62.0)
    pts = RNG.uniform((0, -3, 0), (5, 4, 3), (2000, 3))
    want = np.all((pts > [1, -2, 0.5]) & (pts < [4, 3, 2.5]), axis=1)
    np.testing.assert_array_equal(mesh.contains(pts), want)


def test_points_on_grid_lines_of_an_axis_aligned_mesh():
    """Points whose rays along the first direction would pass through the grid's edges
    and corners: the answer must not depend on it."""
    v, t = grid_box(6, (6.0, 6.0, 6.0))
    mesh = trimesh.TriangleMesh(v, t)
    ticks = np.arange(0.5, 6.0, 1.0)
    inner = np.array([(x, y, z) for x in ticks for y in ticks for z in ticks])
    assert mesh.contains(inner).all()
    outer = inner + [7.0, 0.0, 0.0]
    assert not mesh.contains(outer).any()
    # exactly on the grid's vertices and edges (integer coordinates) inside
    lattice = np.array([(x, y, z) for x in range(1, 6) for y in range(1, 6) for z in range(1, 6)],
                       float)
    assert mesh.contains(lattice).all()


def test_torus_containment_agrees_with_the_winding_oracle():
    v, t = torus_mesh(5.0, 1.5, 36, 18)
    mesh = trimesh.TriangleMesh(v, t)
    pts = RNG.uniform((-7, -7, -2), (7, 7, 2), (1500, 3))
    np.testing.assert_array_equal(mesh.contains(pts), inside_solid(pts, v, t))


def test_gaps_and_lower_bounds_against_brute_force():
    v, t = torus_mesh(5.0, 1.5, 24, 12)
    mesh = trimesh.TriangleMesh(v, t)
    box = np.array([6.0, -1.0, -0.5, 9.0, 1.0, 0.5])
    brute = np.array([np.linalg.norm(np.maximum(0, np.maximum(b[:3] - box[3:], box[:3] - b[3:])))
                      for b in mesh.boxes])
    np.testing.assert_allclose(mesh.gaps(box), brute, rtol=0, atol=1e-15)
    assert set(mesh.near(box, 0.2).tolist()) == set(np.flatnonzero(brute <= 0.2).tolist())
    others = RNG.uniform(-10, 10, (3000, 3))
    others = np.hstack([others, others + RNG.uniform(0, 0.5, (3000, 3))])
    idx = np.arange(0, len(t), 7)
    exact = trimesh.min_box_gaps(mesh.boxes[idx], others)
    pair = np.array([[np.linalg.norm(np.maximum(0, np.maximum(a[:3] - o[3:], o[:3] - a[3:])))
                      for o in others] for a in mesh.boxes[idx[:20]]]).min(axis=1)
    np.testing.assert_allclose(exact[:20], pair, atol=1e-12)
    bound = mesh.lower_bounds(idx, others)          # grouped: never above the exact gap
    assert (bound <= exact + 1e-12).all() and (bound < exact).any()


def dense_samples(tri, n=40):
    """Points covering the triangle (n, 3) densely: barycentric grid."""
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1))
    keep = i + j <= n
    u, v = i[keep] / n, j[keep] / n
    return tri[0] + u[:, None] * (tri[1] - tri[0]) + v[:, None] * (tri[2] - tri[0])


def test_triangle_distances_against_dense_sampling():
    """Random triangle pairs: the distance is at most the sampled minimum (samples are
    points of the triangles) and within the sampling step of it; the closest points lie
    on the triangles at that distance; crossing pairs give 0."""
    A = RNG.normal(size=(40, 3, 3))
    B = RNG.normal(size=(40, 3, 3)) + RNG.normal(size=(40, 1, 3)) * 1.5
    d, pa, pb = trimesh.triangle_triangle(A, B)
    np.testing.assert_allclose(np.linalg.norm(pa - pb, axis=1), d, atol=1e-12)
    for k in range(len(A)):
        sa, sb = dense_samples(A[k]), dense_samples(B[k])
        sampled = np.sqrt(((sa[:, None, :] - sb[None, :, :]) ** 2).sum(axis=2)).min()
        step = max(np.ptp(A[k], axis=0).max(), np.ptp(B[k], axis=0).max()) / 40 * 2
        assert d[k] <= sampled + 1e-12
        assert d[k] >= sampled - step or d[k] == 0.0
    # a triangle piercing another: 0, though no corner or edge pair is close
    a = np.array([[[-1.0, -1.0, 0.0], [2.0, -1.0, 0.0], [-1.0, 2.0, 0.0]]])
    b = np.array([[[0.2, 0.2, -1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]]])
    assert trimesh.triangle_triangle(a, b)[0][0] == 0.0
    assert trimesh.triangle_triangle(a, b + [0, 0, 1.5])[0][0] == pytest.approx(0.5)


def test_mesh_distances_are_the_brute_force_minimum_within_the_limit():
    v, t = torus_mesh(5.0, 1.5, 24, 12)
    w, s = box_mesh((-1.0, 6.8, -1.0), (1.0, 9.0, 1.0))      # the torus reaches y = 6.5
    A, B = v[t], w[s]
    got, pa, pb = trimesh.mesh_distances(A, B, limit=2.0)
    brute = np.array([trimesh.triangle_triangle(np.repeat(A[k:k + 1], len(B), 0), B)[0].min()
                      for k in range(len(A))])
    want = np.where(brute <= 2.0, brute, np.inf)
    np.testing.assert_allclose(got, want, atol=1e-12)
    assert np.isfinite(got).any() and np.isinf(got).any()
    hit = np.isfinite(got)
    np.testing.assert_allclose(np.linalg.norm(pa[hit] - pb[hit], axis=1), got[hit], atol=1e-12)
    assert np.isnan(pa[~hit]).all()
