# SPDX-License-Identifier: LGPL-2.1-or-later
"""The medial-surface oracle (medial_oracle.py) against closed-form answers on the cuboid,
the cube, the L-bracket and the 48-gon disc: its face merge and elements, distances with
their nearest elements, the inside test, touching sets and the completeness probe.  Runs
without the library."""
import math

import numpy as np
import pytest

import medial_solids as solids
from medial_oracle import Polyhedron, closest_on_triangles, distance_to_pieces

RHO = (2 - math.sqrt(2)) * 10          # the L-bracket's corner junction


def _face(P, normal, offset):
    """Oracle face id with this outward normal and offset."""
    k = np.nonzero((np.abs(P.face_normal - normal).max(1) < 1e-12)
                   & (np.abs(P.face_offset - offset) < 1e-9))[0]
    assert len(k) == 1
    return int(k[0])


def test_ericson_against_dense_sampling():
    rng = np.random.default_rng(5)
    A, B, C = rng.normal(size=(3, 20, 3))
    P = rng.normal(size=(30, 3)) * 2
    d, region = closest_on_triangles(P, A, B, C)
    u, v = np.meshgrid(np.linspace(0, 1, 301), np.linspace(0, 1, 301))
    keep = u + v <= 1
    u, v = u[keep], v[keep]
    for j in range(20):
        S = A[j] + u[:, None] * (B[j] - A[j]) + v[:, None] * (C[j] - A[j])
        dense = np.linalg.norm(P[:, None] - S[None], axis=2).min(1)
        # the sampled minimum is above the exact one by at most the sampling step
        step = max(np.linalg.norm(B[j] - A[j]), np.linalg.norm(C[j] - A[j])) / 300
        assert np.all(d[:, j] <= dense + 1e-12)
        assert np.all(dense - d[:, j] <= step)
    assert set(np.unique(region)) <= set(range(7))
    # exact regions on a right triangle
    d, region = closest_on_triangles(np.array([[0.2, 0.2, 3.0], [-1, -1, 0], [0.5, -2, 0],
                                               [2, 2, 0], [3, 0, 4]]),
                                     np.array([[0, 0, 0.]]), np.array([[1, 0, 0.]]),
                                     np.array([[0, 1, 0.]]))
    assert region.ravel().tolist() == [0, 1, 4, 5, 2]
    assert np.allclose(d.ravel(), [3, math.sqrt(2), 2, math.sqrt(4.5), math.sqrt(20)], rtol=0, atol=1e-15)


@pytest.mark.parametrize("name,counts,reflex", [
    ("cuboid", (6, 12, 8), 0), ("cube", (6, 12, 8), 0), ("l_bracket", (8, 18, 12), 1),
    ("t_section", (10, 24, 16), 2), ("ngon_disc", (50, 144, 96), 0),
    ("ribbed_tray", (251, None, None), None), ("cup", (1253, None, None), None)])
def test_elements(name, counts, reflex):
    P = Polyhedron(*getattr(solids, name)())
    got = (P.nfaces, P.nedges, P.nverts)
    assert got[0] == counts[0]
    if counts[1] is not None:
        assert got == counts
        assert int((~P.edge_convex).sum()) == reflex
    assert P.nelements == sum(got)


def test_face_merge_tilted_and_shuffled():
    """The cuboid rotated and its triangles shuffled: still 6 faces / 12 / 8, planes moved."""
    v, t = solids.cuboid()
    v2, R, tr = solids.rigid_motion(v)
    rng = np.random.default_rng(2)
    t2 = t[rng.permutation(len(t))]
    t2 = np.roll(t2, 1, axis=1)
    P = Polyhedron(v2, t2)
    assert (P.nfaces, P.nedges, P.nverts) == (6, 12, 8)
    assert P.edge_convex.all()
    assert np.allclose(sorted(P.face_area), sorted([100 * 60] * 2 + [100 * 20] * 2 + [60 * 20] * 2))


def test_cuboid_distance_inside_touching():
    P = Polyhedron(*solids.cuboid())
    rng = np.random.default_rng(1)
    X = rng.uniform([-10, -10, -5], [110, 70, 25], size=(3000, 3))
    inside = np.all((X > 0) & (X < [100, 60, 20]), axis=1)
    assert np.array_equal(P.inside(X), inside)
    Xi = X[inside]
    exact = np.minimum(Xi, [100, 60, 20] - Xi).min(1)
    d, elem = P.distance(Xi, with_element=True)
    assert np.abs(d - exact).max() <= 1e-13
    assert np.all(P.kinds[elem] == "F")       # interior points: nearest in an open face
    z0, z1 = _face(P, (0, 0, -1), 0), _face(P, (0, 0, 1), 20)
    x0, y0 = _face(P, (-1, 0, 0), 0), _face(P, (0, -1, 0), 0)
    T = P.touching([(50, 30, 10), (50, 30, 5), (10, 10, 10), (10, 30, 10), (30, 7, 7)], 1e-9)
    assert [set(np.nonzero(r)[0]) for r in T] == [{z0, z1}, {z0}, {z0, z1, x0, y0},
                                                 {z0, z1, x0}, {z0, y0}]
    assert P.is_major(T[0]) and not P.is_major(T[4]) and P.is_major(T[3])
    assert not P.adjacent(z0, z1) and P.adjacent(z0, x0)


def test_cube_centre_touches_six():
    P = Polyhedron(*solids.cube())
    T = P.touching([(20, 20, 20), (20, 20, 19.9)], 1e-9)
    assert T[0].sum() == 6 and np.all(P.kinds[T[0]] == "F")
    assert T[1].sum() == 1


def _l_distance(X):
    """Exact distance to the L-bracket's boundary for interior points: min of the caps
    and the 2-D distance to the L outline (point-segment in the plane)."""
    L = np.array([(0, 0), (50, 0), (50, 10), (10, 10), (10, 50), (0, 50)], float)
    A, B = L, np.roll(L, -1, 0)
    p = X[:, None, :2] - A[None]
    d = B - A
    t = np.clip(np.einsum("mnk,nk->mn", p, d) / np.einsum("nk,nk->n", d, d), 0, 1)
    d2 = np.linalg.norm(p - t[..., None] * d[None], axis=2).min(1)
    return np.minimum(np.minimum(X[:, 2], 40 - X[:, 2]), d2)


def test_l_bracket_distance_inside_touching():
    P = Polyhedron(*solids.l_bracket())
    rng = np.random.default_rng(3)
    X = rng.uniform([-5, -5, -5], [55, 55, 45], size=(3000, 3))
    inside = ((X[:, 2] > 0) & (X[:, 2] < 40) & (X[:, 0] > 0) & (X[:, 1] > 0)
              & (((X[:, 0] < 10) & (X[:, 1] < 50)) | ((X[:, 1] < 10) & (X[:, 0] < 50))))
    assert np.array_equal(P.inside(X), inside)
    d, elem = P.distance(X[inside], with_element=True)
    assert np.abs(d - _l_distance(X[inside])).max() <= 1e-12
    E = P.nfaces + int(np.nonzero(~P.edge_convex)[0][0])
    # points of the (Fo, E) sheet x = (100 + (y - 10)^2) / 20 are nearest to E or Fo
    y = np.linspace(RHO + 0.1, 9.9, 7)
    S = np.c_[(100 + (y - 10) ** 2) / 20, y, np.full(7, 20.0)]
    Fo, Fi = _face(P, (-1, 0, 0), 0), _face(P, (1, 0, 0), 10)
    Go = _face(P, (0, -1, 0), 0)
    T = P.touching(S, 1e-9)
    assert all(set(np.nonzero(r)[0]) == {Fo, E} for r in T)
    assert all(P.is_major(r) for r in T)
    # the SMOOTH seam (5, 10, z) {Fo, Fi, E} and the corner junction {Fo, Go, E, z0}
    T = P.touching([(5, 10, 20), (RHO, RHO, RHO)], 1e-9)
    z0 = _face(P, (0, 0, -1), 0)
    assert set(np.nonzero(T[0])[0]) == {Fo, Fi, E}
    assert set(np.nonzero(T[1])[0]) == {Fo, Go, E, z0}
    d, elem = P.distance(np.array([[9.0, 9.0, 20.0]]), with_element=True)
    assert elem[0] == E and abs(d[0] - math.sqrt(2)) < 1e-15


def test_l_bracket_probes_closed_form():
    """Probes from Fo (x = 0): x* = (t*, y, z) with t* = min(z, 40 - z, y, 50 - y,
    (100 + (y - 10)^2) / 20, 5 if y >= 10) -- the caps, Go, the arm end, E and Fi."""
    P = Polyhedron(*solids.l_bracket())
    X, t, q, face = P.probes(600, margin=0.5, seed=4)
    assert np.all(P.inside(X))
    Fo = _face(P, (-1, 0, 0), 0)
    m = face == Fo
    assert m.sum() > 50
    y, z = q[m, 1], q[m, 2]
    tE = (100 + (y - 10) ** 2) / 20
    expect = np.minimum.reduce([z, 40 - z, y, 50 - y, tE, np.where(y >= 10, 5.0, np.inf)])
    assert np.abs(t[m] - expect).max() <= 1e-9
    # every probe point is medial: >= 2 elements touch, D(x*) = t*
    assert np.abs(P.distance(X) - t).max() <= 1e-9
    T = P.touching(X, 1e-7)
    assert np.all(T.sum(1) >= 2)
    # major exactly where the competitor is Fi or E (not Go, the arm end or a cap: they
    # share an edge with Fo)
    major = np.array([P.is_major(r) for r in T[m]])
    firm = np.minimum.reduce([np.abs(expect - z), np.abs(expect - (40 - z)), np.abs(expect - y),
                              np.abs(expect - (50 - y))])
    other = np.minimum(np.abs(expect - tE), np.where(y >= 10, np.abs(expect - 5), np.inf))
    clear = np.abs(firm - other) > 1e-6
    assert np.array_equal(major[clear], (other < firm)[clear])


def test_cuboid_probes_and_result_distance():
    P = Polyhedron(*solids.cuboid())
    X, t, q, face = P.probes(500, margin=0.2, seed=2)
    z0 = _face(P, (0, 0, -1), 0)
    m = face == z0
    exp = np.minimum.reduce([q[m, 0], 100 - q[m, 0], q[m, 1], 60 - q[m, 1], np.full(m.sum(), 10.0)])
    assert np.abs(t[m] - exp).max() <= 1e-9
    T = P.touching(X, 1e-7)
    major = np.array([P.is_major(r) for r in T])
    # major <=> the probe reached the mid-plane z = 10 with both caps touching
    assert np.array_equal(major, np.abs(X[:, 2] - 10) < 1e-6)
    # distance to a hand-made "result": the exact mid-sheet as two triangles, no seams
    sheet = np.array([[[10, 10, 10], [90, 10, 10], [90, 50, 10]],
                      [[10, 10, 10], [90, 50, 10], [10, 50, 10]]], float)
    d = distance_to_pieces(X[major], sheet, np.zeros((0, 2, 3)), np.zeros((0, 3)), 1.0)
    assert d.max() <= 1e-10
    d = distance_to_pieces(np.array([[50, 30, 12.0], [0, 0, 10.0]]), sheet,
                           np.zeros((0, 2, 3)), np.zeros((0, 3)), 50.0)
    assert np.allclose(d, [2, math.sqrt(200)])


def test_disc_probes_major_mid_sheet():
    """The 48-gon disc: the major probes all lie on z = 2 inside the inset 48-gon of
    apothem 50 cos(pi/48) - 2, with radius 2."""
    P = Polyhedron(*solids.ngon_disc())
    X, t, q, face = P.probes(400, margin=0.05, seed=3)
    T = P.touching(X, 1e-7)
    major = np.array([P.is_major(r) for r in T])
    assert major.sum() > 150
    Xm = X[major]
    assert np.abs(Xm[:, 2] - 2).max() <= 1e-9 and np.abs(t[major] - 2).max() <= 1e-9
    apo = 50 * math.cos(math.pi / 48) - 2
    ang = np.arctan2(Xm[:, 1], Xm[:, 0])
    k = np.floor(ang / (2 * math.pi / 48))
    mid = (k + 0.5) * 2 * math.pi / 48
    assert np.all(Xm[:, 0] * np.cos(mid) + Xm[:, 1] * np.sin(mid) <= apo + 1e-9)


def test_oracle_refuses_open_and_flipped():
    v, t = solids.cuboid()
    with pytest.raises(ValueError):
        Polyhedron(v, t[1:])
    t2 = t.copy()
    t2[0] = t2[0, ::-1]
    with pytest.raises(ValueError):
        Polyhedron(v, t2)


def test_distance_to_pieces_against_brute_force():
    rng = np.random.default_rng(9)
    c = rng.uniform(0, 20, (3000, 3))
    tris = c[:, None] + rng.normal(scale=0.3, size=(3000, 3, 3))
    segs = rng.uniform(0, 20, (50, 1, 3)) + rng.normal(scale=0.5, size=(50, 2, 3))
    pts = rng.uniform(0, 20, (5, 3))
    P = rng.uniform(-1, 21, (300, 3))
    cutoff = 0.4
    got = distance_to_pieces(P, tris, segs, pts, cutoff)
    dt, _ = closest_on_triangles(P, tris[:, 0], tris[:, 1], tris[:, 2])
    from medial_oracle import point_segment_distance
    brute = np.minimum.reduce([dt.min(1), point_segment_distance(P, segs[:, 0], segs[:, 1]).min(1),
                               np.linalg.norm(P[:, None] - pts[None], axis=2).min(1)])
    near = brute <= cutoff
    assert near.sum() > 50
    assert np.array_equal(got[near], brute[near])
    assert np.all(got[~near] >= brute[~near])
