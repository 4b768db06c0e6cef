# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.core.medial_surface (issue 9 sections 1, 3 and 5; design section 7) against
the independent oracle of medial_oracle.py and the hand-derived medial surfaces of
analytic solids (medial_solids.py):

- soundness: every sheet vertex, seam point and junction is inside the solid, its radius
  is the oracle's distance to the boundary within the tolerance, and >= 2 / 3 / 4 oracle
  elements touch its ball (within 1e-6 of the bbox diagonal L); the elements the result
  names are among them (mapped by face_of_triangle and by geometry); in the major mode
  every sheet's two elements are not adjacent; a sample of the sheet vertices, every seam
  point and junction;
- structure: a seam lists exactly the elements that touch its balls (away from junctions
  and the boundary); seams end at their junctions or at the boundary; every inner
  boundary edge of a sheet lies on a seam (no holes, no loose borders);
- completeness: every medial point the oracle's probe finds (bisection along inward
  normals from area-weighted boundary points) on the major part (full mode: anywhere)
  lies within the tolerance of the result's sheets, seams and junctions;
- analytic solids: cuboid, cube, square prism, L-bracket, T-section, 48-gon disc: counts,
  element sets, positions, radii, sheet areas, major and full;
- invariance: shuffled triangles and 1 / 2 / 7 threads give identical arrays; a rigid
  motion gives the same counts and the moved points within the tolerance;
- bad input: open, flipped, non-manifold, zero-area, NaN, bad tolerances -> MfgError with
  a message.

Element kinds in the result: 0 vertex, 1 edge, 2 face (mfgeom.h mfg_element_kind)."""
import functools
import math

import numpy as np
import pytest

import medial_solids as solids
from medial_oracle import Polyhedron, distance_to_pieces, result_pieces, sheet_area
from mfgeom import core

TOL_FRAC = 0.01                  # tolerance = 1 % of the bbox diagonal (the bench: 0.5 %)
TOUCH_FRAC = 1e-6                # "touches": within 1e-6 L of the radius (design section 7)
SOUND_SHEET_SAMPLE = 5000        # sheet vertices checked per result (all seams, junctions)
BRANCH, SMOOTH, DEGENERATE = 0, 1, 2
VERTEX, EDGE, FACE = 0, 1, 2
RHO = (2 - math.sqrt(2)) * 10    # the L-bracket's corner seam (rho*, rho*, z)

SOLIDS = {
    "cuboid": solids.cuboid, "cube": solids.cube, "square_prism": solids.square_prism,
    "l_bracket": solids.l_bracket, "t_section": solids.t_section, "disc48": solids.ngon_disc,
    "small_tray": solids.small_tray,
    # a tessellated curved part, facets (3.1 wide) finer than the seams' features: the
    # junctions between two wall facets and a floor-corner vertex are missed by the leaf
    # search and recovered where the seams end (issue 9, left item 1)
    "cup64": lambda: solids.cup(64),
    # the same moved off the lattice's axes: its facet / reflex-edge strips (narrower than
    # a leaf) came out as 3 592 one-triangle sheets, up to 33 per pair
    "cup64_moved": lambda: (solids.rigid_motion(solids.cup(64)[0])[0], solids.cup(64)[1]),
}


# Issue 22's real-part size, checked by the same oracle on a sample: the bench's
# 5 000-triangle cup at the bench's tolerance (0.5 % of L), major part (the full mode
# takes minutes).  Only in the soundness, completeness and needle tests.
LARGE = {"cup625": lambda: solids.cup(625)}
LARGE_FRAC = 0.005
LARGE_CASES = [(n, False) for n in LARGE]


@functools.lru_cache(maxsize=None)
def mesh(name):
    v, t = (LARGE[name] if name in LARGE else SOLIDS[name])()
    return v, t, Polyhedron(v, t)


@functools.lru_cache(maxsize=None)
def result(name, full=False):
    v, t, P = mesh(name)
    return core.medial_surface(v, t, _tol(name), major_only=not full)


def _tol(name):
    return (LARGE_FRAC if name in LARGE else TOL_FRAC) * mesh(name)[2].diag


def _elements(x):
    return [int(e) for e in np.asarray(x).ravel()]


def _junction_elements(res):
    return [_elements(e) for e in res.junctions.elements]


# ------------------------------------------------------------------ element mapping
def element_map(res, P):
    """lib element id -> oracle element id (-1: unknown): faces through face_of_triangle;
    edges and vertices by their geometry when the binding exposes it (edge_segments,
    vertex_points), else -1."""
    kinds = np.asarray(res.element_kinds)
    m = np.full(len(kinds), -1, np.int64)
    fot = np.asarray(res.face_of_triangle)
    for tri, f in enumerate(fot):
        if f < 0:
            continue
        o = int(P.tri_face[tri])
        assert m[f] in (-1, o), f"library face {f} holds triangles of two oracle faces"
        m[f] = o
    tol = 1e-9 * P.diag
    segs = getattr(res, "edge_segments", None)
    eids = np.nonzero(kinds == EDGE)[0]
    if segs is not None and len(eids):
        segs = np.asarray(segs, float).reshape(-1, 2, 3)
        for e, (a, b) in zip(eids, segs):
            d = np.minimum(np.abs(P.edge_A - a).max(1) + np.abs(P.edge_B - b).max(1),
                           np.abs(P.edge_A - b).max(1) + np.abs(P.edge_B - a).max(1))
            k = np.nonzero(d <= tol)[0]
            assert len(k) == 1, f"library edge {e} {a}-{b} is no oracle edge"
            m[e] = P.nfaces + int(k[0])
    pts = getattr(res, "vertex_points", None)
    vids = np.nonzero(kinds == VERTEX)[0]
    if pts is not None and len(vids):
        for e, p in zip(vids, np.asarray(pts, float).reshape(-1, 3)):
            k = np.nonzero(np.abs(P.vert_P - p).max(1) <= tol)[0]
            assert len(k) == 1, f"library vertex {e} {p} is no oracle vertex"
            m[e] = P.nfaces + P.nedges + int(k[0])
    return m


def named(res, P, spec):
    """Library element id of a named element: ("F", normal, offset), ("E", A, B) or
    ("V", point), found in the oracle by geometry and mapped to the library."""
    kind = spec[0]
    tol = 1e-9 * P.diag
    if kind == "F":
        k = np.nonzero((np.abs(P.face_normal - np.asarray(spec[1], float)).max(1) < 1e-9)
                       & (np.abs(P.face_offset - spec[2]) < tol))[0]
        o = int(k[0]) if len(k) == 1 else None
    elif kind == "E":
        a, b = np.asarray(spec[1], float), np.asarray(spec[2], float)
        d = np.minimum(np.abs(P.edge_A - a).max(1) + np.abs(P.edge_B - b).max(1),
                       np.abs(P.edge_A - b).max(1) + np.abs(P.edge_B - a).max(1))
        k = np.nonzero(d <= tol)[0]
        o = P.nfaces + int(k[0]) if len(k) == 1 else None
    else:
        k = np.nonzero(np.abs(P.vert_P - np.asarray(spec[1], float)).max(1) <= tol)[0]
        o = P.nfaces + P.nedges + int(k[0]) if len(k) == 1 else None
    assert o is not None, f"no oracle element {spec}"
    m = element_map(res, P)
    k = np.nonzero(m == o)[0]
    assert len(k) == 1, f"element {spec} maps to {len(k)} library elements"
    return int(k[0])


# ------------------------------------------------------------------ soundness
SOUND_CASES = [(n, f) for n in SOLIDS for f in (False, True)]
# Known gaps (issue 9 closing note), kept visible: in the full mode on the moved cup one
# seam ends on the boundary (r = 0) a hair past its edge's end vertex (the oracle sees the
# next edge touch, not its own), and a 5-triangle sheet between two outer facets has a
# boundary side 1.2 off every seam.
_FULL_MOVED_CUP = pytest.param("cup64_moved", True, marks=pytest.mark.xfail(
    strict=True, reason="full mode on the moved cup: a seam's boundary end and a small "
    "convex-wall sheet (known gap)"))
SOUND_CASES_KNOWN = [_FULL_MOVED_CUP if c == ("cup64_moved", True) else c for c in SOUND_CASES]


@pytest.mark.parametrize("name,full", SOUND_CASES_KNOWN + LARGE_CASES)
def test_soundness(name, full):
    v, t, P = mesh(name)
    res = result(name, full)
    tol = _tol(name)
    eps = TOUCH_FRAC * P.diag
    emap = element_map(res, P)
    kinds = np.asarray(res.element_kinds)
    assert ((kinds == FACE).sum(), (kinds == EDGE).sum(), (kinds == VERTEX).sum()) == \
        (P.nfaces, P.nedges, P.nverts)
    groups = []     # (what, points, radii, element lists per point, minimum touching)
    for i, s in enumerate(res.sheets):
        el = _elements(s.elements)
        assert len(el) == 2 and el[0] < el[1], f"sheet {i}: elements {el}"
        if not full:
            a, b = emap[el]
            if a >= 0 and b >= 0:
                assert not P.adjacent(int(a), int(b)), f"major sheet {i} of adjacent {el}"
        groups.append((f"sheet {i}", np.asarray(s.vertices, float).reshape(-1, 3),
                       np.asarray(s.radii, float), el, 2))
    for i, c in enumerate(res.seams):
        el = _elements(c.elements)
        assert len(el) >= 3 and el == sorted(el), f"seam {i}: elements {el}"
        assert len(c.points) >= 2, f"seam {i} has {len(c.points)} points"
        groups.append((f"seam {i}", np.asarray(c.points, float).reshape(-1, 3),
                       np.asarray(c.radii, float), el, 3))
    for j, el in enumerate(_junction_elements(res)):
        assert len(el) >= 4 and el == sorted(el), f"junction {j}: elements {el}"
        groups.append((f"junction {j}", np.asarray(res.junctions.points[j], float).reshape(-1, 3),
                       np.asarray(res.junctions.radii[j], float).reshape(1), el, 4))
    # a seeded sample of the sheet vertices (they all come from one root solver), every
    # seam point and junction; one batch for the oracle
    nsheet = sum(len(g[1]) for g in groups if g[0].startswith("sheet"))
    keep = min(1.0, SOUND_SHEET_SAMPLE / max(1, nsheet))
    rng = np.random.default_rng(5)
    Xs, rs, gs = [], [], []
    for gi, (what, X, r, el, need) in enumerate(groups):
        assert len(r) == len(X), what
        if what.startswith("sheet") and keep < 1:
            sel = rng.random(len(X)) < keep
            X, r = X[sel], r[sel]
        Xs.append(X)
        rs.append(r)
        gs.append(np.full(len(X), gi))
    if not groups:
        return
    X, r, g = np.concatenate(Xs), np.concatenate(rs), np.concatenate(gs)
    D = P.distance(X)
    worst = float(np.abs(D - r).max()) if len(X) else 0.0
    bad = np.nonzero(np.abs(D - r) > tol)[0]
    assert not len(bad), (f"{groups[g[bad[0]]][0]}: point {X[bad[0]]} radius {r[bad[0]]} but its "
                          f"distance to the boundary is {D[bad[0]]} (tolerance {tol})")
    deep = np.nonzero(D > eps)[0]
    ins = P.inside(X[deep])
    assert ins.all(), f"{groups[g[deep[~ins][0]]][0]}: point {X[deep][~ins][0]} outside the solid"
    T = P.touching(X, eps, D=D)
    cnt = T.sum(1)
    need = np.array([grp[4] for grp in groups])[g]
    bad = np.nonzero(cnt < need)[0]
    assert not len(bad), (f"{groups[g[bad[0]]][0]}: point {X[bad[0]]} (r {r[bad[0]]}) touches only "
                          f"{cnt[bad[0]]} elements {np.nonzero(T[bad[0]])[0]}, needs {need[bad[0]]}")
    for gi, (what, _, _, el, _) in enumerate(groups):
        rows = np.nonzero(g == gi)[0]
        o = emap[el]
        o = o[o >= 0]
        miss = rows[~T[np.ix_(rows, o)].all(1)] if len(rows) and len(o) else []
        assert not len(miss), (f"{what} of elements {el} (oracle {o.tolist()}): point "
                               f"{X[miss[0]]} (r {r[miss[0]]}, D {D[miss[0]]}) is not touched "
                               f"by {[int(e) for e in o if not T[miss[0], e]]}")
    # the design expects radii to a few ulps of L; keep an eye on it (not the contract)
    assert worst <= tol


@pytest.mark.parametrize("name,full", SOUND_CASES)
def test_seam_elements_complete(name, full):
    """A seam is tied to every element its balls touch: at its points away from the
    junctions and the boundary (farther than the tolerance), the oracle's touching set (restricted
    distances within 1e-6 L) is exactly the seam's element set."""
    v, t, P = mesh(name)
    res = result(name, full)
    tol = _tol(name)
    emap = element_map(res, P)
    assert not (emap < 0).any(), "library elements the oracle's ids do not map"
    J = np.asarray(res.junctions.points, float).reshape(-1, 3)
    for i, c in enumerate(res.seams):
        X = np.asarray(c.points, float).reshape(-1, 3)
        far = P.distance(X) > tol               # not at the boundary (full mode's corners)
        if len(J):
            far &= np.linalg.norm(X[:, None] - J[None], axis=2).min(1) > tol
        X = X[far]
        if not len(X):
            continue
        T = P.touching(X, TOUCH_FRAC * P.diag)
        want = np.zeros(P.nelements, bool)
        want[emap[_elements(c.elements)]] = True
        bad = np.nonzero((T != want).any(1))[0]
        assert not len(bad), (f"seam {i} lists oracle elements {np.nonzero(want)[0].tolist()} "
                              f"but at {X[bad[0]]} the ball touches "
                              f"{np.nonzero(T[bad[0]])[0].tolist()}")


@pytest.mark.parametrize("name,full", SOUND_CASES)
def test_seams_join_junctions(name, full):
    """Seams are polylines joining junctions: each end is the junction its `ends` names
    (same point), or, without one, lies at the boundary (radius <= tolerance: the full
    mode's seams out to convex corners) -- no dangling pieces."""
    v, t, P = mesh(name)
    res = result(name, full)
    tol = _tol(name)
    J = np.asarray(res.junctions.points, float).reshape(-1, 3)
    for i, c in enumerate(res.seams):
        X = np.asarray(c.points, float).reshape(-1, 3)
        ends = np.asarray(c.ends).ravel()
        for k, (p, rad) in enumerate(((X[0], c.radii[0]), (X[-1], c.radii[-1]))):
            if ends[k] >= 0:
                assert np.linalg.norm(J[ends[k]] - p) <= 1e-9 * P.diag, \
                    f"seam {i} end {k} at {p}, its junction {ends[k]} at {J[ends[k]]}"
            else:
                assert rad <= tol, (f"seam {i} (elements {_elements(c.elements)}) end {k} at {p} "
                                    f"(r {rad:.4g}) is neither a junction nor at the boundary")


@pytest.mark.parametrize("name,full", SOUND_CASES_KNOWN)
def test_sheets_bounded_by_seams(name, full):
    """Every boundary edge of a sheet's mesh lies on a seam (its midpoint within the
    tolerance of a seam polyline or junction) or at the boundary of the solid (radius
    <= tolerance)."""
    v, t, P = mesh(name)
    res = result(name, full)
    tol = _tol(name)
    _, segs, pts = result_pieces(res)
    for i, s in enumerate(res.sheets):
        tri = np.asarray(s.triangles, np.int64)
        e = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
        u, cnt = np.unique(e, axis=0, return_counts=True)
        b = u[cnt == 1]
        if not len(b):
            continue
        V = np.asarray(s.vertices, float)
        R = np.asarray(s.radii, float)
        mid = (V[b[:, 0]] + V[b[:, 1]]) / 2
        inner = np.maximum(R[b[:, 0]], R[b[:, 1]]) > tol
        d = distance_to_pieces(mid[inner], np.zeros((0, 3, 3)), segs, pts, tol)
        bad = np.nonzero(d > tol)[0]
        assert not len(bad), (f"sheet {i} (elements {_elements(s.elements)}): {len(bad)} of "
                              f"{inner.sum()} inner boundary edges off every seam, e.g. at "
                              f"{mid[inner][bad[0]]} ({d[bad[0]]:.3g} away)")


@pytest.mark.parametrize("name,full", SOUND_CASES + LARGE_CASES)
def test_no_zero_area_triangles(name, full):
    """No sheet triangle is a needle (a corner within 1e-9 L of its opposite side): the
    moved cup's sheets had 2 (major) and 5 (full) with heights of 1e-14 of their sides,
    from the collapses and the pinhole fans -- no normal, a distance query divides by
    zero on them, a FEM mesher refuses them.  Each sheet stays edge-manifold (no side of
    three triangles) and consistently oriented (no directed side twice)."""
    _v, _t, P = mesh(name)
    res = result(name, full)
    for i, s in enumerate(res.sheets):
        V = np.asarray(s.vertices, float).reshape(-1, 3)
        tri = np.asarray(s.triangles, np.int64).reshape(-1, 3)
        assert len(tri), f"sheet {i} is empty"
        side = np.stack([np.linalg.norm(V[tri[:, (k + 2) % 3]] - V[tri[:, (k + 1) % 3]], axis=1)
                         for k in range(3)], axis=1)
        twice = np.linalg.norm(np.cross(V[tri[:, 1]] - V[tri[:, 0]], V[tri[:, 2]] - V[tri[:, 0]]),
                               axis=1)
        height = twice / side.max(axis=1)
        assert height.min() > 1e-9 * P.diag, (f"sheet {i}: a triangle of height "
                                              f"{height.min():.3g} (L {P.diag:.3g})")
        directed = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
        assert len(np.unique(directed, axis=0)) == len(directed), f"sheet {i}: orientation"
        _u, cnt = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
        assert cnt.max() <= 2, f"sheet {i}: a side of {cnt.max()} triangles"


@pytest.mark.parametrize("name", ["cup64", "cup64_moved"])
def test_one_sheet_per_pair(name):
    """A tessellated wall's sheets come out whole: one connected sheet per element pair
    (the cup's medial sheets are each a single patch), none a stray triangle of a strip
    narrower than the tolerance (those are carried by their seams)."""
    res = result(name)
    pairs = [tuple(_elements(s.elements)) for s in res.sheets]
    worst = max(pairs.count(p) for p in set(pairs))
    assert worst == 1, f"a pair has {worst} sheets"
    assert len(res.sheets) <= 300, f"{len(res.sheets)} sheets"


# ------------------------------------------------------------------ completeness
PROBES = 500


@functools.lru_cache(maxsize=None)
def probes(name):
    """The oracle's medial points from PROBES boundary points (shared by both modes) and
    whether each lies on the major part."""
    v, t, P = mesh(name)
    X, tstar, q, face = P.probes(PROBES, margin=2 * _tol(name), seed=11, iters=54)
    T = P.touching(X, TOUCH_FRAC * P.diag, D=tstar)
    return X, tstar, np.array([P.is_major(r) for r in T])


@pytest.mark.parametrize("name,full", SOUND_CASES + LARGE_CASES)
def test_completeness(name, full):
    v, t, P = mesh(name)
    res = result(name, full)
    tol = _tol(name)
    X, tstar, major = probes(name)
    want = np.ones(len(X), bool) if full else major
    tris, segs, pts = result_pieces(res)
    d = distance_to_pieces(X[want], tris, segs, pts, tol)
    bad = np.nonzero(d > tol)[0]
    assert not len(bad), (f"{len(bad)} of {want.sum()} medial probe points farther than the "
                          f"tolerance {tol:.4g} from the result; first {X[want][bad[0]]} "
                          f"(r {tstar[want][bad[0]]:.6g}) at {d[bad[0]]:.4g}")


# ------------------------------------------------------------------ analytic solids
def _F(n, d):
    return ("F", n, d)


X0, X1 = (-1, 0, 0), (1, 0, 0)
Y0, Y1 = (0, -1, 0), (0, 1, 0)
Z0, Z1 = (0, 0, -1), (0, 0, 1)


def _polyline_dist(X, curve):
    """Distance of points X to the dense polyline `curve` (k, 3)."""
    from medial_oracle import point_segment_distance
    return point_segment_distance(X, curve[:-1], curve[1:]).min(1)


def _segment(a, b, k=2):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return a + np.linspace(0, 1, k)[:, None] * (b - a)


def _sets(res, P, specs):
    return frozenset(named(res, P, s) for s in specs)


def check_sheets(name, res, P, expected, tol):
    """expected: list of (element specs, residual(X) -> (k,), radius(X) -> (k,), area).
    Exactly one sheet per expected element pair (in addition: no other sheets)."""
    by = {}
    for i, s in enumerate(res.sheets):
        by.setdefault(frozenset(_elements(s.elements)), []).append(i)
    assert len(res.sheets) == len(expected), (
        f"{name}: {len(res.sheets)} sheets, expected {len(expected)}; got element pairs "
        f"{sorted(tuple(sorted(k)) for k in by)}")
    for specs, resid, radius, area in expected:
        key = _sets(res, P, specs)
        assert len(by.get(key, [])) == 1, f"{name}: sheets of {specs}: {by.get(key)}"
        s = res.sheets[by[key][0]]
        X = np.asarray(s.vertices, float)
        assert np.abs(resid(X)).max() <= tol, f"{name}: sheet {specs} off its bisector"
        assert np.abs(np.asarray(s.radii) - radius(X)).max() <= 1e-6 * P.diag
        if area is not None:
            a = sheet_area(s)
            assert abs(a - area) <= 0.02 * area + 4 * tol * tol, \
                f"{name}: sheet {specs} area {a:.2f}, expected {area:.2f}"


def check_seams(name, res, P, expected, tol, count=None):
    """expected: list of (element specs, curve (k, 3) dense, radius(X), kind or None).
    Each expected seam is exactly one result seam with that element set, its points
    within tol of the curve and its ends within tol of the curve's ends."""
    by = {}
    for i, c in enumerate(res.seams):
        by.setdefault(frozenset(_elements(c.elements)), []).append(i)
    if count is not None:
        assert len(res.seams) == count, (
            f"{name}: {len(res.seams)} seams, expected {count}: "
            f"{sorted(tuple(sorted(k)) for k in by)}")
    for specs, curve, radius, kind in expected:
        key = _sets(res, P, specs)
        assert len(by.get(key, [])) == 1, f"{name}: seams of {specs}: {by.get(key)}"
        c = res.seams[by[key][0]]
        X = np.asarray(c.points, float)
        assert _polyline_dist(X, curve).max() <= tol, f"{name}: seam {specs} off its curve"
        ends = sorted([X[0], X[-1]], key=lambda p: tuple(np.round(p, 6)))
        cend = sorted([curve[0], curve[-1]], key=lambda p: tuple(np.round(p, 6)))
        assert np.linalg.norm(ends[0] - cend[0]) <= tol and \
            np.linalg.norm(ends[1] - cend[1]) <= tol, \
            f"{name}: seam {specs} runs {X[0]} .. {X[-1]}, expected {curve[0]} .. {curve[-1]}"
        assert np.abs(np.asarray(c.radii) - radius(X)).max() <= 1e-6 * P.diag
        if kind is not None:
            assert int(c.kind) == kind, f"{name}: seam {specs} kind {c.kind}, expected {kind}"


def check_junctions(name, res, P, expected, count=None):
    """expected: list of (point, radius, element specs, kind or None)."""
    J = res.junctions
    pts = np.asarray(J.points, float).reshape(-1, 3)
    if count is not None:
        assert len(pts) == count, f"{name}: {len(pts)} junctions {pts.tolist()}, expected {count}"
    els = [frozenset(e) for e in _junction_elements(res)]
    for p, r, specs, kind in expected:
        key = _sets(res, P, specs)
        k = [j for j, e in enumerate(els) if e == key]
        assert len(k) == 1, f"{name}: junctions with elements {specs}: {k}"
        j = k[0]
        assert np.linalg.norm(pts[j] - p) <= 1e-6 * P.diag, \
            f"{name}: junction {specs} at {pts[j]}, expected {p}"
        assert abs(float(J.radii[j]) - r) <= 1e-6 * P.diag
        if kind is not None:
            assert int(J.kinds[j]) == kind, f"{name}: junction {specs} kind {J.kinds[j]}"


def _plane(axis, value):
    return lambda X: X[:, axis] - value


def _const(c):
    return lambda X: np.full(len(X), float(c))


def test_cuboid_major():
    name = "cuboid"
    v, t, P = mesh(name)
    res, tol = result(name), _tol(name)
    z0, z1 = _F(Z0, 0), _F(Z1, 20)
    x0, x1, y0, y1 = _F(X0, 0), _F(X1, 100), _F(Y0, 0), _F(Y1, 60)
    check_sheets(name, res, P, [((z0, z1), _plane(2, 10), _const(10), 3200.0)], tol)
    corners = {(10, 10): (x0, y0), (90, 10): (x1, y0), (90, 50): (x1, y1), (10, 50): (x0, y1)}
    check_junctions(name, res, P, [((x, y, 10), 10, (z0, z1) + f, BRANCH)
                                   for (x, y), f in corners.items()], count=4)
    seams = [((z0, z1, x0), _segment((10, 10, 10), (10, 50, 10)), _const(10), BRANCH),
             ((z0, z1, x1), _segment((90, 10, 10), (90, 50, 10)), _const(10), BRANCH),
             ((z0, z1, y0), _segment((10, 10, 10), (90, 10, 10)), _const(10), BRANCH),
             ((z0, z1, y1), _segment((10, 50, 10), (90, 50, 10)), _const(10), BRANCH)]
    check_seams(name, res, P, seams, tol, count=4)


def test_cuboid_full():
    name = "cuboid"
    v, t, P = mesh(name)
    res, tol = result(name, True), _tol(name)
    z0, z1 = _F(Z0, 0), _F(Z1, 20)
    x0, x1, y0, y1 = _F(X0, 0), _F(X1, 100), _F(Y0, 0), _F(Y1, 60)
    s2 = math.sqrt(2)
    # bisector of faces f (coordinate a at value va) and g (b, vb), both through the edge
    sheets = [((z0, z1), _plane(2, 10), lambda X: np.minimum(X[:, 2], 20 - X[:, 2]), 3200.0)]
    for zf, zv in ((z0, 0), (z1, 20)):
        for f, a, va, area in ((x0, 0, 0, 50 * 10 * s2), (x1, 0, 100, 50 * 10 * s2),
                               (y0, 1, 0, 90 * 10 * s2), (y1, 1, 60, 90 * 10 * s2)):
            sheets.append(((zf, f),
                           (lambda a, va, zv: lambda X: np.abs(X[:, a] - va) - np.abs(X[:, 2] - zv))(a, va, zv),
                           (lambda zv: lambda X: np.abs(X[:, 2] - zv))(zv), area))
    for fx, vx in ((x0, 0), (x1, 100)):
        for fy, vy in ((y0, 0), (y1, 60)):
            sheets.append(((fx, fy),
                           (lambda vx, vy: lambda X: np.abs(X[:, 0] - vx) - np.abs(X[:, 1] - vy))(vx, vy),
                           (lambda vx: lambda X: np.abs(X[:, 0] - vx))(vx), 20 * 10 * s2 / 2))
    check_sheets(name, res, P, sheets, tol)
    total = sum(sheet_area(s) for s in res.sheets)
    assert abs(total - 11685.3) <= 0.02 * 11685.3
    assert len(res.seams) == 12
    check_junctions(name, res, P, [], count=4)


def test_cube():
    name = "cube"
    v, t, P = mesh(name)
    faces = [_F(X0, 0), _F(X1, 40), _F(Y0, 0), _F(Y1, 40), _F(Z0, 0), _F(Z1, 40)]
    for full in (False, True):
        res = result(name, full)
        check_junctions(name, res, P, [((20, 20, 20), 20, faces, None)], count=1)
        if not full:
            assert len(res.sheets) == 0 and len(res.seams) == 0
        else:
            assert len(res.sheets) == 12 and len(res.seams) == 8
            areas = np.array([sheet_area(s) for s in res.sheets])
            assert np.abs(areas - 40 * 20 * math.sqrt(2) / 2).max() <= 0.02 * 565.7


def test_square_prism():
    name = "square_prism"
    v, t, P = mesh(name)
    tol = _tol(name)
    sides = (_F(X0, 0), _F(X1, 20), _F(Y0, 0), _F(Y1, 20))
    z0, z1 = _F(Z0, 0), _F(Z1, 100)
    res = result(name)
    assert len(res.sheets) == 0
    check_seams(name, res, P, [(sides, _segment((10, 10, 10), (10, 10, 90)), _const(10),
                                DEGENERATE)], tol, count=1)
    check_junctions(name, res, P, [((10, 10, 10), 10, sides + (z0,), None),
                                   ((10, 10, 90), 10, sides + (z1,), None)], count=2)
    res = result(name, True)
    assert len(res.sheets) == 12 and len(res.seams) == 9 and len(res.junctions.points) == 2
    areas = sorted(sheet_area(s) for s in res.sheets)
    s2 = math.sqrt(2)
    exp = sorted([20 * 10 * s2 / 2] * 8 + [90 * 10 * s2] * 4)
    assert np.abs(np.array(areas) - exp).max() <= 0.02 * np.array(exp).max()


def _quad(f, a, b, n=4001):
    x = np.linspace(a, b, n)
    y = f(x)
    return float(((y[1:] + y[:-1]) / 2 * np.diff(x)).sum())


def test_l_bracket():
    name = "l_bracket"
    v, t, P = mesh(name)
    res, tol = result(name), _tol(name)
    Fo, Fi, Go, Gi = _F(X0, 0), _F(X1, 10), _F(Y0, 0), _F(Y1, 10)
    Ty, Tx = _F(Y1, 50), _F(X1, 50)
    z0, z1 = _F(Z0, 0), _F(Z1, 40)
    E = ("E", (10, 10, 0), (10, 10, 40))

    def par(y):                       # the (Fo, E) bisector: x = (100 + (y - 10)^2) / 20
        return (100 + (y - 10) ** 2) / 20

    area_FE = _quad(lambda y: (40 - 2 * par(y)) * np.sqrt(1 + ((y - 10) / 10) ** 2), RHO, 10)
    sheets = [((Fo, Fi), _plane(0, 5), _const(5), 35 * 30.0),
              ((Go, Gi), _plane(1, 5), _const(5), 35 * 30.0),
              ((Fo, E), lambda X: X[:, 0] - par(X[:, 1]), lambda X: X[:, 0], area_FE),
              ((Go, E), lambda X: X[:, 1] - par(X[:, 0]), lambda X: X[:, 1], area_FE)]
    check_sheets(name, res, P, sheets, tol)
    y = np.linspace(RHO, 10, 2001)
    cFE0 = np.c_[par(y), y, par(y)]
    cFE1 = np.c_[par(y), y, 40 - par(y)]
    sw = [1, 0, 2]                    # the mirror x <-> y
    seams = [((Fo, Go, E), _segment((RHO, RHO, RHO), (RHO, RHO, 40 - RHO)), _const(RHO), BRANCH),
             ((Fo, Fi, E), _segment((5, 10, 5), (5, 10, 35)), _const(5), SMOOTH),
             ((Go, Gi, E), _segment((10, 5, 5), (10, 5, 35)), _const(5), SMOOTH),
             ((Fo, Fi, Ty), _segment((5, 45, 5), (5, 45, 35)), _const(5), None),
             ((Go, Gi, Tx), _segment((45, 5, 5), (45, 5, 35)), _const(5), None),
             ((Fo, Fi, z0), _segment((5, 10, 5), (5, 45, 5)), _const(5), None),
             ((Fo, Fi, z1), _segment((5, 10, 35), (5, 45, 35)), _const(5), None),
             ((Go, Gi, z0), _segment((10, 5, 5), (45, 5, 5)), _const(5), None),
             ((Go, Gi, z1), _segment((10, 5, 35), (45, 5, 35)), _const(5), None),
             ((Fo, E, z0), cFE0, lambda X: X[:, 0], None),
             ((Fo, E, z1), cFE1, lambda X: X[:, 0], None),
             ((Go, E, z0), cFE0[:, sw], lambda X: X[:, 1], None),
             ((Go, E, z1), cFE1[:, sw], lambda X: X[:, 1], None)]
    check_seams(name, res, P, seams, tol, count=13)
    junctions = [((5, 45, 5), 5, (Fo, Fi, Ty, z0), BRANCH), ((5, 45, 35), 5, (Fo, Fi, Ty, z1), BRANCH),
                 ((45, 5, 5), 5, (Go, Gi, Tx, z0), BRANCH), ((45, 5, 35), 5, (Go, Gi, Tx, z1), BRANCH),
                 ((5, 10, 5), 5, (Fo, Fi, E, z0), SMOOTH), ((5, 10, 35), 5, (Fo, Fi, E, z1), SMOOTH),
                 ((10, 5, 5), 5, (Go, Gi, E, z0), SMOOTH), ((10, 5, 35), 5, (Go, Gi, E, z1), SMOOTH),
                 ((RHO, RHO, RHO), RHO, (Fo, Go, E, z0), BRANCH),
                 ((RHO, RHO, 40 - RHO), RHO, (Fo, Go, E, z1), BRANCH)]
    check_junctions(name, res, P, junctions, count=10)


def test_l_bracket_full():
    """Full mode: the 4 major sheets plus one sheet per convex edge (17) and the cones
    (z0, E), (z1, E): 23; seams: the 13 major, the 10 trisectors from the convex corners
    to their junctions and the SMOOTH seams (zk, Fi, E), (zk, Gi, E) from the reflex
    edge's ends: 27; the same 10 junctions."""
    name = "l_bracket"
    v, t, P = mesh(name)
    res = result(name, True)
    assert len(res.sheets) == 23 and len(res.seams) == 27, res
    check_junctions(name, res, P, [], count=10)
    E = named(res, P, ("E", (10, 10, 0), (10, 10, 40)))
    for zk, z in ((_F(Z0, 0), 0), (_F(Z1, 40), 40)):
        key = frozenset((named(res, P, zk), E))
        cones = [s for s in res.sheets if frozenset(_elements(s.elements)) == key]
        assert len(cones) == 1
        X = np.asarray(cones[0].vertices)
        # ball touching the cap and the edge: |z - zk| = distance to the line (10, 10, z)
        assert np.abs(np.abs(X[:, 2] - z) - np.hypot(X[:, 0] - 10, X[:, 1] - 10)).max() <= _tol(name)


def test_t_section():
    """Flange [0, 60] x [50, 60], web [25, 35] x [0, 50], z in [0, 40]: 6 major sheets,
    19 seams.  The web's
    mid-sheet x = 30 (W1, W2) turns at y = 50 into the bisector of the reflex edges E1,
    E2 (still x = 30) and meets the flange's sheets (E1, T), (E2, T) on the BRANCH seam
    {E1, E2, T} at y = 53.75 (25 + (y - 50)^2 = (60 - y)^2), r = 6.25."""
    name = "t_section"
    v, t, P = mesh(name)
    res, tol = result(name), _tol(name)
    W1, W2, T = _F(X0, -25), _F(X1, 35), _F(Y1, 60)
    E1 = ("E", (25, 50, 0), (25, 50, 40))
    E2 = ("E", (35, 50, 0), (35, 50, 40))
    z0, z1 = _F(Z0, 0), _F(Z1, 40)
    # the flange's underside is two faces in one plane (y = 50): tell them apart by x
    under = [f for f in range(P.nfaces) if np.allclose(P.face_normal[f], Y0)
             and abs(P.face_offset[f] + 50) < 1e-9]
    assert len(under) == 2
    emap = element_map(res, P)
    under.sort(key=lambda f: P.V[P.T[P.face_tris[f]]][..., 0].mean())
    lib_under = [int(np.nonzero(emap == f)[0][0]) for f in under]
    yb = 53.75

    def rE(X):
        return np.sqrt(25 + (X[:, 1] - 50) ** 2)

    area_EE = _quad(lambda y: 40 - 2 * np.sqrt(25 + (y - 50) ** 2), 50, yb)
    area_ET = _quad(lambda x: (40 - 2 * (5 + (x - 25) ** 2 / 20)) * np.sqrt(1 + ((x - 25) / 10) ** 2), 25, 30)
    by = {frozenset(_elements(s.elements)): s for s in res.sheets}
    assert len(res.sheets) == 6, sorted(tuple(sorted(k)) for k in by)
    lT = named(res, P, T)
    for f in lib_under:
        s = by.get(frozenset((f, lT)))
        assert s is not None, f"no sheet of the flange underside {f} and the top"
        X = np.asarray(s.vertices)
        assert np.abs(X[:, 1] - 55).max() <= tol and abs(sheet_area(s) - 600) <= 12
        assert np.abs(np.asarray(s.radii) - 5).max() <= 1e-6 * P.diag
    for specs, resid, radius, area in [
            ((W1, W2), _plane(0, 30), _const(5), 45 * 30.0),
            ((E1, E2), _plane(0, 30), rE, area_EE),
            ((E1, T), lambda X: X[:, 1] - (55 - (X[:, 0] - 25) ** 2 / 20), lambda X: 60 - X[:, 1], area_ET),
            ((E2, T), lambda X: X[:, 1] - (55 - (X[:, 0] - 35) ** 2 / 20), lambda X: 60 - X[:, 1], area_ET)]:
        s = by.get(_sets(res, P, specs))
        assert s is not None, f"t_section: no sheet {specs}"
        X = np.asarray(s.vertices)
        assert np.abs(resid(X)).max() <= tol
        assert np.abs(np.asarray(s.radii) - radius(X)).max() <= 1e-6 * P.diag
        assert abs(sheet_area(s) - area) <= 0.02 * area + 4 * tol * tol, (specs, sheet_area(s), area)
    # 19 seams: per sheet its z0 and z1 seams (12), the web's end, the flange's two ends,
    # the two SMOOTH seams (Bi, T) -> (Ei, T), the mark, and where the web's sheet (W1, W2)
    # passes into (E1, E2): at y = 50 all four are equidistant (W1 and E1 touch at one
    # point, as W2 and E2): ONE seam with the four elements
    check_seams(name, res, P, [((E1, E2, T), _segment((30, yb, 6.25), (30, yb, 40 - 6.25)),
                                _const(6.25), BRANCH),
                               ((W1, W2, E1, E2), _segment((30, 50, 5), (30, 50, 35)),
                                _const(5), None)], tol, count=19)
    check_junctions(name, res, P, [((30, yb, 6.25), 6.25, (E1, E2, T, z0), None),
                                   ((30, yb, 40 - 6.25), 6.25, (E1, E2, T, z1), None)])


def test_disc48():
    name = "disc48"
    v, t, P = mesh(name)
    res, tol = result(name), _tol(name)
    n = 48
    apo = 50 * math.cos(math.pi / n) - 2
    area = n * apo ** 2 * math.tan(math.pi / n)
    top, bot = _F(Z1, 4), _F(Z0, 0)
    check_sheets(name, res, P, [((bot, top), _plane(2, 2), _const(2), area)], tol)
    assert area / (n * 50 ** 2 * math.sin(2 * math.pi / n) / 2) > 0.92
    J = res.junctions
    pts = np.asarray(J.points, float).reshape(-1, 3)
    assert len(pts) == n and len(res.seams) == n
    rad = np.hypot(pts[:, 0], pts[:, 1])
    assert np.abs(rad - apo / math.cos(math.pi / n)).max() <= 1e-6 * P.diag
    assert np.abs(pts[:, 2] - 2).max() <= 1e-6 * P.diag
    assert np.abs(np.asarray(J.radii) - 2).max() <= 1e-6 * P.diag
    # junction k lies on the bisector of the corner at angle 2 pi k / n (a vertex on +x)
    step = 2 * math.pi / n
    ang = np.arctan2(pts[:, 1], pts[:, 0]) / step
    assert np.abs(ang - np.round(ang)).max() <= 1e-9
    assert sorted(np.mod(np.round(ang).astype(int), n).tolist()) == list(range(n))
    lt, lb = named(res, P, top), named(res, P, bot)
    for c in res.seams:
        el = set(_elements(c.elements))
        assert {lt, lb} < el and len(el) == 3
        assert np.abs(np.asarray(c.radii) - 2).max() <= 1e-6 * P.diag
    for e in _junction_elements(res):
        assert {lt, lb} < set(e) and len(e) == 4


def test_disc48_full():
    """Full mode: the mid-sheet, 96 trapezoids from the rim's top and bottom edges (slant
    height 2 sqrt 2) and 48 triangles from the vertical edges to the junctions: 145
    sheets; 48 + 96 seams; the same 48 junctions; area 9148.99."""
    name = "disc48"
    v, t, P = mesh(name)
    res = result(name, True)
    n = 48
    apo = 50 * math.cos(math.pi / n) - 2
    rj = apo / math.cos(math.pi / n)
    side, inner = 2 * 50 * math.sin(math.pi / n), 2 * rj * math.sin(math.pi / n)
    area = (n * apo ** 2 * math.tan(math.pi / n) + 2 * n * (side + inner) / 2 * 2 * math.sqrt(2)
            + n * 4 * (50 - rj) / 2)
    assert len(res.sheets) == 145 and len(res.seams) == 144
    assert len(np.asarray(res.junctions.points).reshape(-1, 3)) == 48
    got = sum(sheet_area(s) for s in res.sheets)
    assert abs(got - area) <= 0.01 * area, (got, area)


# ------------------------------------------------------------------ invariance
def _arrays(res):
    out = []
    for s in res.sheets:
        out += [np.asarray(s.vertices), np.asarray(s.triangles), np.asarray(s.radii),
                np.asarray(s.elements), np.asarray(getattr(s, "form", -1))]
    for c in res.seams:
        out += [np.asarray(c.points), np.asarray(c.radii), np.asarray(c.elements),
                np.asarray(c.kind)]
    J = res.junctions
    out += [np.asarray(J.points), np.asarray(J.radii), np.asarray(J.kinds)]
    out += [np.asarray(e) for e in J.elements]
    out += [np.asarray(res.element_kinds)]
    return out


def _same(a, b):
    A, B = _arrays(a), _arrays(b)
    return len(A) == len(B) and all(x.shape == y.shape and np.array_equal(x, y)
                                    for x, y in zip(A, B))


@pytest.mark.parametrize("name", ["l_bracket", "disc48", "cup64"])
def test_invariant_under_triangle_order(name):
    v, t, P = mesh(name)
    ref = result(name, True)
    rng = np.random.default_rng(7)
    perm = rng.permutation(len(t))
    t2 = np.array([np.roll(tri, k) for tri, k in zip(t[perm], rng.integers(0, 3, len(t)))])
    res = core.medial_surface(v, t2, TOL_FRAC * P.diag, major_only=False)
    assert _same(ref, res)
    assert np.array_equal(np.asarray(res.face_of_triangle), np.asarray(ref.face_of_triangle)[perm])


@pytest.mark.parametrize("name,full", [("l_bracket", True), ("disc48", False), ("cup64", False)])
def test_invariant_under_threads(name, full):
    v, t, P = mesh(name)
    ref = core.medial_surface(v, t, TOL_FRAC * P.diag, major_only=not full, threads=1)
    for n in (2, 7):
        assert _same(ref, core.medial_surface(v, t, TOL_FRAC * P.diag, major_only=not full,
                                              threads=n)), f"{n} threads"
    assert _same(ref, result(name, full))


@pytest.mark.parametrize("name", ["l_bracket", "t_section"])
def test_rigid_motion(name):
    v, t, P = mesh(name)
    tol = _tol(name)
    ref = result(name)
    v2, R, tr = solids.rigid_motion(v)
    res = core.medial_surface(v2, t, tol, major_only=True)
    assert len(res.sheets) == len(ref.sheets) and len(res.seams) == len(ref.seams)
    assert len(res.junctions.points) == len(ref.junctions.points)
    # points of the moved result lie within tol of the moved reference and vice versa
    tris, segs, pts = result_pieces(ref)
    mv = lambda X: X @ R.T + tr  # noqa: E731
    tris, segs, pts = mv(tris), mv(segs), mv(pts)
    X2 = np.concatenate([np.asarray(s.vertices).reshape(-1, 3) for s in res.sheets]
                        + [np.asarray(c.points).reshape(-1, 3) for c in res.seams]
                        + [np.asarray(res.junctions.points).reshape(-1, 3)])
    sel = X2[np.random.default_rng(1).permutation(len(X2))[:400]]
    assert distance_to_pieces(sel, tris, segs, pts, tol).max() <= tol
    # junctions pair up one to one, radii equal within tol
    J1 = mv(np.asarray(ref.junctions.points).reshape(-1, 3))
    J2 = np.asarray(res.junctions.points).reshape(-1, 3)
    d = np.linalg.norm(J1[:, None] - J2[None], axis=2)
    k = d.argmin(1)
    assert len(set(k.tolist())) == len(J1) and d.min(1).max() <= tol
    assert np.abs(np.asarray(ref.junctions.radii) - np.asarray(res.junctions.radii)[k]).max() <= tol


@pytest.mark.parametrize("scale", [1e-12, 1e-6, 1e6, 1e12])
def test_scaled_input(scale):
    """The L-bracket scaled (tolerance with it) gives the same structure, radii and
    sheet area in units of the scale: nothing in the pipeline may depend on absolute
    magnitudes (thresholds are relative to L or tol)."""
    v, t, P = mesh("l_bracket")
    tol = _tol("l_bracket")
    ref = result("l_bracket")
    res = core.medial_surface(v * scale, t, tol * scale, major_only=True)
    assert len(res.sheets) == len(ref.sheets) and len(res.seams) == len(ref.seams)
    assert len(res.junctions.points) == len(ref.junctions.points)
    assert sorted(len(x) for x in res.junctions.elements) == \
        sorted(len(x) for x in ref.junctions.elements)
    J1 = np.asarray(ref.junctions.points).reshape(-1, 3)
    J2 = np.asarray(res.junctions.points).reshape(-1, 3) / scale
    d = np.linalg.norm(J1[:, None] - J2[None], axis=2)
    assert d.min(1).max() <= tol
    r1 = np.sort(np.asarray(ref.junctions.radii))
    r2 = np.sort(np.asarray(res.junctions.radii)) / scale
    assert np.abs(r1 - r2).max() <= 1e-9 * tol
    a1 = sum(sheet_area(x) for x in ref.sheets)
    a2 = sum(sheet_area(x) for x in res.sheets) / scale ** 2
    assert abs(a1 - a2) <= 1e-3 * a1


# ------------------------------------------------------------------ bad input
def _bad_inputs():
    v, t = solids.cuboid()
    L = float(np.linalg.norm(v.max(0) - v.min(0)))
    flipped_one = t.copy()
    flipped_one[0] = flipped_one[0, ::-1]
    nan = v.copy()
    nan[3, 1] = np.nan
    # two cubes sharing one edge: 4 triangles on that edge
    occ = np.zeros((2, 2, 1), bool)
    occ[0, 0, 0] = occ[1, 1, 0] = True
    nmv, nmt = solids.grid_solid([0, 1, 2], [0, 1, 2], [0, 1], occ)
    flat = np.c_[np.arange(8, dtype=float), np.zeros(8), np.zeros(8)]
    return [
        ("open box", v, t[1:], 1.0, "not closed"),
        ("flipped triangle", v, flipped_one, 1.0, "inconsistent orientation"),
        ("flipped box", v, t[:, ::-1].copy(), 1.0, "negative volume"),
        ("non-manifold edge", nmv, nmt, 0.1, "non-manifold"),
        ("zero-area triangles only", flat, t, 0.1, "zero area"),
        ("NaN coordinate", nan, t, 1.0, "NaN"),
        ("tolerance 0", v, t, 0.0, "tolerance"),
        ("tolerance -1", v, t, -1.0, "tolerance"),
        ("tolerance NaN", v, t, float("nan"), "tolerance"),
        ("tolerance = diagonal", v, t, L, "tolerance"),
        ("tolerance > diagonal", v, t, 2 * L, "tolerance"),
        ("tolerance < L / 2^20", v, t, L / 2 ** 21, "tolerance"),
    ]


@pytest.mark.parametrize("what,v,t,tol,words", _bad_inputs(), ids=[b[0] for b in _bad_inputs()])
def test_bad_input(what, v, t, tol, words):
    with pytest.raises(core.MfgError) as info:
        core.medial_surface(v, t, tol)
    msg = str(info.value)
    assert words.lower() in msg.lower(), f"{what}: message {msg!r} does not say {words!r}"


def _radii_against_oracle(v, t, res, tol):
    """Every sheet vertex and junction of res is inside and its radius is the oracle's
    distance to the boundary within tol; returns the number of points checked."""
    P = Polyhedron(v, t)
    pts = ([s.vertices for s in res.sheets] + [s.points for s in res.seams]
           + [res.junctions.points.reshape(-1, 3)])
    rad = [s.radii for s in res.sheets] + [s.radii for s in res.seams] + [res.junctions.radii]
    pts, rad = np.concatenate(pts), np.concatenate(rad)
    if len(pts):
        assert np.all(P.inside(pts))
        assert np.max(np.abs(P.distance(pts) - rad)) <= tol
    return len(pts)


def test_bent_chain_is_split_at_its_bend():
    """issue 22: two faces merged within eta (a gently curved tessellation) meet in a chain
    that bends by more than eta (here 1e-4 >> eta = 1.9e-6): it was refused with "mesh
    vertex ... off the line of the edge" (an internal error); now the bend vertex is a
    vertex element, the ridge two edges, and the result sound."""
    v, t = solids.bent_ridge()
    P = Polyhedron(v, t)
    tol = TOL_FRAC * P.diag
    res = core.medial_surface(v, t, tol)
    kinds = np.asarray(res.element_kinds)
    assert (kinds == FACE).sum() == 7            # the block's 6 faces, the top in two
    assert any(np.allclose(p, v[7]) for p in res.vertex_points)
    ridge = [s for s in np.asarray(res.edge_segments).reshape(-1, 2, 3)
             if np.all(np.abs(s[:, 0] - 1) <= 2e-4) and np.all(np.abs(s[:, 2] - 0.6) <= 1e-9)]
    assert len(ridge) == 2
    assert len(res.sheets) >= 2
    assert _radii_against_oracle(v, t, res, tol) > 20


def test_coincident_vertices_box():
    """issue 22, found by fuzzing the medial surface: a box with moved corners, two of them
    coincident, bent a chain at the pinch (an internal error) and, once split, looped in
    the element build.  The moved corners fold the box through itself (an edge of
    triangle 11 passes through triangle 0: checked here by Moller-Trumbore, independently
    of the library), so the closed check now refuses it, naming the pair."""
    v = np.array([[2, 0.03125, 0], [2.03125, 0.04296875, 0.0625], [2.0859375, 0.03125, 0.125],
                  [2.09375, 0.1875, 0.03125], [2.09375, 0.21875, 0], [2.05078125, 0.0390625, 0],
                  [2, 0.03125, 0], [2.03125, 0.03125, 0]])
    t = np.array([[0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6], [0, 1, 5], [0, 5, 4], [2, 6, 7],
                  [2, 7, 3], [0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5]], np.int64)
    A, (p, q) = v[t[0]], v[[1, 7]]
    e1, e2, d = A[1] - A[0], A[2] - A[0], q - p
    h = np.cross(d, e2)
    f = 1 / (e1 @ h)
    s = p - A[0]
    u, w = f * (s @ h), f * (d @ np.cross(s, e1))
    tt = f * (e2 @ np.cross(s, e1))
    assert u > 0 and w > 0 and u + w < 1 and 0 < tt < 1      # the edge pierces triangle 0
    with pytest.raises(core.MfgError, match="shells cross: triangles 0 and 11"):
        core.medial_surface(v, t, 0.0038135984745637959)
