# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.geometry (FreeCAD-free numpy geometry of the features) against analytic values
and brute force: the icosphere and the sphere coverage of the parting view, the
conservative offset of the rotational sweep, the boundary loops, area and polygon
straightening of the mid-surface."""

import math

import numpy as np
import pytest

from mfgeom import core
from mfgeom.geometry import mesh as gm
from mfgeom.geometry import sphere as gs

RNG = np.random.default_rng(19)


def random_directions(n):
    d = RNG.normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1)[:, None]


# --------------------------------------------------------------------------- icosphere
@pytest.mark.parametrize("level", [0, 1, 2, 4])
def test_icosphere_counts_unit_vertices_and_closed_outward_mesh(level):
    v, t = gs.icosphere(level)
    assert v.shape == (10 * 4 ** level + 2, 3) and t.shape == (20 * 4 ** level, 3)
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 1.0, atol=1e-15)
    # every undirected edge used by exactly two triangles, once in each direction
    directed = np.vstack([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]).tolist()
    assert len(set(map(tuple, directed))) == len(directed)
    assert all((b, a) in set(map(tuple, directed)) for a, b in directed[:200])
    # Euler: V - E + F = 2
    assert len(v) - len(directed) // 2 + len(t) == 2
    # outward: each triangle's normal points away from the centre
    n = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
    assert np.all(np.einsum("ij,ij->i", n, v[t].mean(axis=1)) > 0)
    # the library's own check agrees: a closed, outward solid
    report = core.mesh_check(v, t, require_closed=True)
    assert report.boundary_edges == 0 and report.volume > 0


def test_icosahedron_area_and_volume_are_the_analytic_ones():
    v, t = gs.icosphere(0)
    edge = 1.0 / math.sin(2 * math.pi / 5)        # edge of the icosahedron of circumradius 1
    assert gm.mesh_area(v, t) == pytest.approx(5 * math.sqrt(3) * edge ** 2, rel=1e-13)
    volume = 5 * (3 + math.sqrt(5)) / 12 * edge ** 3
    assert core.mesh_check(v, t).volume == pytest.approx(volume, rel=1e-13)


def test_icosphere_area_converges_to_the_sphere():
    areas = [gm.mesh_area(*gs.icosphere(k)) for k in range(5)]
    assert all(a < b < 4 * math.pi for a, b in zip(areas, areas[1:]))
    assert 4 * math.pi - areas[-1] < 4e-3 * 4 * math.pi


def test_default_level_is_the_view_sphere():
    v, _t = gs.icosphere()
    assert len(v) == 2562 and gs.SPHERE_LEVEL == 4


# --------------------------------------------------------------------------- coverage
OCTANTS = {  # counter-clockwise seen from outside; membership: the signs of x, y, z
    (1, 1, 1): [(1, 0, 0), (0, 1, 0), (0, 0, 1)],
    (1, 1, -1): [(0, 1, 0), (1, 0, 0), (0, 0, -1)],
    (-1, 1, 1): [(0, 1, 0), (-1, 0, 0), (0, 0, 1)],
}


def octant(signs):
    return core.VisibilityMap("polygon", np.array(OCTANTS[signs], float))


def in_octant(d, signs):
    return np.all(d * np.array(signs) >= 0, axis=1)


def test_coverage_counts_distinct_surfaces_analytically():
    d = np.vstack([random_directions(4000), gs.icosphere(2)[0]])
    maps = [("a", octant((1, 1, 1))), ("a", octant((1, 1, -1))),   # a: two maps, one surface
            ("b", octant((1, 1, 1))),
            ("c", octant((-1, 1, 1))),
            ("d", None)]                                            # d: the whole sphere
    count = gs.coverage(d, maps, 1e-12)
    expected = ((in_octant(d, (1, 1, 1)) | in_octant(d, (1, 1, -1))).astype(int)
                + in_octant(d, (1, 1, 1)) + in_octant(d, (-1, 1, 1)) + 1)
    assert count.dtype == np.int32
    np.testing.assert_array_equal(count, expected)


def test_coverage_of_library_maps_matches_brute_force_dot_products():
    """VM(P) = {d : d.p >= 0 for all p}: the count per direction equals the number of
    surfaces whose normals all have a non-negative dot product with it (directions
    within 1e-9 of a boundary left out)."""
    surfaces = [random_directions(3) * 0.3 + np.array([0, 0, 1.0]) for _ in range(4)]
    maps = [(k, core.visibility_map(p)) for k, p in enumerate(surfaces)]
    d = random_directions(20000)
    dots = [d @ (p / np.linalg.norm(p, axis=1)[:, None]).T for p in surfaces]
    clear = np.all([np.abs(x).min(axis=1) > 1e-6 for x in dots], axis=0)
    expected = sum((x >= 0).all(axis=1).astype(int) for x in dots)
    count = gs.coverage(d, maps, 1e-12)
    np.testing.assert_array_equal(count[clear], expected[clear])
    assert expected[clear].max() >= 1


def test_great_arc_lies_on_the_great_circle_between_its_ends():
    a, b = random_directions(2)
    p = gs.great_arc(a, b, pieces=16)
    assert len(p) == 17
    np.testing.assert_allclose(p[0], a, atol=1e-15)
    np.testing.assert_allclose(p[-1], b, atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(p, axis=1), 1.0, atol=1e-15)
    normal = np.cross(a, b) / np.linalg.norm(np.cross(a, b))
    assert np.abs(p @ normal).max() < 1e-14
    angle = np.arccos(np.clip(p @ a, -1, 1))
    assert np.all(np.diff(angle) > 0) and angle[-1] == pytest.approx(np.arccos(a @ b))


def test_map_outlines_draw_polygon_edges_and_points():
    point = core.VisibilityMap("point", np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]))
    lines, dots = gs.map_outlines([("a", octant((1, 1, 1))), ("b", None), ("c", point),
                                   ("d", core.VisibilityMap("null", np.zeros((0, 3))))])
    assert len(lines) == 1
    loop = lines[0]
    np.testing.assert_allclose(loop[0], loop[-1], atol=1e-15)     # closed round the polygon
    # on the octant's boundary: one coordinate zero, the others >= 0
    assert np.all(np.abs(loop).min(axis=1) < 1e-15) and np.all(loop > -1e-15)
    np.testing.assert_array_equal(dots, point.vertices)


# --------------------------------------------------------------------------- conservative offset
def prism(n, r, h):
    """A regular n-gon prism inscribed in the cylinder of radius r, 0 <= z <= h: side
    triangles (curved: they stand for the cylinder), fan caps from two centre vertices."""
    a = 2 * math.pi * np.arange(n) / n
    ring = np.column_stack([r * np.cos(a), r * np.sin(a)])
    v = np.vstack([np.column_stack([ring, np.zeros(n)]), np.column_stack([ring, np.full(n, h)]),
                   [[0, 0, 0], [0, 0, h]]])
    tri, curved = [], []
    for i in range(n):
        j = (i + 1) % n
        tri += [(i, j, n + j), (i, n + j, n + i)]
        curved += [True, True]
        tri += [(2 * n, j, i), (2 * n + 1, n + i, n + j)]
        curved += [False, False]
    return v, np.array(tri), np.array(curved)


@pytest.mark.parametrize("n", [12, 48])
def test_offset_of_a_prism_is_the_analytic_one_and_holds_the_cylinder(n):
    r, h = 5.0, 3.0
    v, t, curved = prism(n, r, h)
    assert core.mesh_check(v, t, require_closed=True).volume > 0
    sagitta = r * (1 - math.cos(math.pi / n))       # the chords' depth inside the cylinder
    moved, largest = gm.conservative_offset(v, t, curved, sagitta)
    # rim vertices: pushed radially (kept in the cap planes) by d / cos(pi / n)
    step = sagitta / math.cos(math.pi / n)
    radius = np.linalg.norm(moved[:2 * n, :2], axis=1)
    np.testing.assert_allclose(radius, r + step, rtol=1e-13)
    np.testing.assert_array_equal(moved[:2 * n, 2], v[:2 * n, 2])
    np.testing.assert_array_equal(moved[2 * n:], v[2 * n:])          # cap centres stay
    assert largest == pytest.approx(step, rel=1e-13)
    # the moved polygon contains the true circle: dense samples of it are inside every
    # side's half-plane (up to rounding), and the inradius equals r
    theta = np.linspace(0, 2 * math.pi, 20000)
    circle = r * np.column_stack([np.cos(theta), np.sin(theta)])
    p = moved[:n, :2]
    for i in range(n):
        e = p[(i + 1) % n] - p[i]
        outward = np.array([e[1], -e[0]]) / np.linalg.norm(e)
        assert ((circle - p[i]) @ outward).max() <= 1e-12 * r
    assert (r + step) * math.cos(math.pi / n) == pytest.approx(r, rel=1e-13)


def test_offset_leaves_planar_solids_and_zero_deflection_alone():
    v, t, curved = prism(8, 2.0, 1.0)
    flat = np.zeros(len(t), bool)
    moved, largest = gm.conservative_offset(v, t, flat, 0.1)
    np.testing.assert_array_equal(moved, v)
    assert largest == 0.0
    moved, largest = gm.conservative_offset(v, t, curved, 0.0)
    np.testing.assert_array_equal(moved, v)
    assert largest == 0.0


def test_offset_is_capped_on_a_sharp_curved_crease():
    """Two curved triangles folded almost flat onto each other: N . n_t is tiny, the
    step is MAX_OFFSET_FACTOR * deflection."""
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 1e-3], [0, 1, -1e-3]], float)
    t = np.array([[0, 1, 2], [1, 0, 3]])
    moved, largest = gm.conservative_offset(v, t, [True, True], 0.01)
    assert largest == pytest.approx(gm.MAX_OFFSET_FACTOR * 0.01)
    assert np.linalg.norm(moved - v, axis=1).max() == pytest.approx(largest)


# --------------------------------------------------------------------------- near vertices
def face_soup_cube(jitter):
    """A unit cube meshed face by face as OCCT does (each face its own copy of the
    corner nodes), the copies moved by ``jitter`` (a function of the face index): an
    exact weld leaves it open when the copies differ."""
    quads = [((0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)), ((0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)),
             ((0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)), ((0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)),
             ((0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)), ((1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1))]
    v, t = [], []
    for f, q in enumerate(quads):
        base = len(v)
        v += [np.array(c, float) * 26.0 + jitter(f) for c in q]
        t += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    return np.array(v), np.array(t)


def test_merge_near_vertices_closes_a_mesh_whose_face_copies_differ_by_ulps():
    ulp = np.spacing(26.0)
    v, t = face_soup_cube(lambda f: (f % 3) * ulp * np.array([1.0, -1.0, 2.0]))
    welded, wt = core.weld(v[t].reshape(-1, 9))
    assert core.mesh_check(welded, wt).boundary_edges > 0          # the exact weld fails
    mv, mt, kept = gm.merge_near_vertices(v, t)
    assert len(mv) == 8 and kept.all() and len(mt) == 12
    report = core.mesh_check(mv, mt, require_closed=True)
    assert report.volume == pytest.approx(26.0 ** 3, rel=1e-12)
    # each merged vertex is one of its cluster's own points (the lowest index)
    assert all(np.isin(mv, v).all(axis=1))


def test_merge_near_vertices_keeps_points_apart_and_drops_collapsed_triangles():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1e-9, 0, 0], [0, 0, 1]], float)
    t = np.array([[0, 1, 2], [0, 3, 4], [1, 2, 4]])
    mv, mt, kept = gm.merge_near_vertices(v, t, eps=1e-8)
    assert len(mv) == 4 and kept.tolist() == [True, False, True]
    np.testing.assert_array_equal(mt, [[0, 1, 2], [1, 2, 3]])
    # 1e-9 apart, eps 1e-10: nothing merges, nothing changes
    mv, mt, kept = gm.merge_near_vertices(v, t, eps=1e-10)
    np.testing.assert_array_equal(mv, v)
    np.testing.assert_array_equal(mt, t)
    assert kept.all()


def test_merge_near_vertices_merges_every_pair_within_eps_wherever_the_grid_lies():
    eps = 1e-6
    base = RNG.uniform(-50, 50, (400, 3))
    # the partners straddle cell boundaries of every shifted grid as often as not
    offsets = random_directions(400) * RNG.uniform(0.0, eps, 400)[:, None]
    v = np.vstack([base, base + offsets])
    mv, _, _ = gm.merge_near_vertices(v, np.zeros((0, 3), int), eps)
    assert len(mv) == 400
    # and points 100 eps apart never merge
    far = np.vstack([base, base + random_directions(400) * 100 * eps])
    assert len(gm.merge_near_vertices(far, np.zeros((0, 3), int), eps)[0]) == 800


# --------------------------------------------------------------------------- boundary loops
def grid_with_hole(k):
    """A k x k grid of unit squares (two counter-clockwise triangles each, seen from +z)
    without the centre square: one outer boundary and one hole."""
    idx = lambda i, j: i * (k + 1) + j   # noqa: E731
    v = np.array([(j, i, 0.0) for i in range(k + 1) for j in range(k + 1)])
    tri = []
    for i in range(k):
        for j in range(k):
            if (i, j) == (k // 2, k // 2):
                continue
            a, b, c, d = idx(i, j), idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j)
            tri += [(a, b, c), (a, c, d)]
    return v, np.array(tri)


def signed_area(poly):
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def test_boundary_loops_of_a_grid_with_a_hole():
    k = 5
    v, t = grid_with_hole(k)
    loops = gm.boundary_loops(t)
    assert loops is not None and len(loops) == 2
    # brute force: the boundary edges are the directed edges whose reverse is not used
    directed = {e for tr in t.tolist() for e in ((tr[0], tr[1]), (tr[1], tr[2]), (tr[2], tr[0]))}
    boundary = {e for e in directed if (e[1], e[0]) not in directed}
    walked = {(loop[i], loop[(i + 1) % len(loop)]) for loop in loops for i in range(len(loop))}
    assert walked == boundary
    areas = sorted(signed_area(v[loop]) for loop in loops)
    assert areas == [pytest.approx(-1.0), pytest.approx(k * k)]     # hole runs the other way
    assert gm.mesh_area(v, t) == pytest.approx(k * k - 1)


def test_boundary_loops_of_a_closed_mesh_and_of_nothing():
    assert gm.boundary_loops(gs.icosphere(1)[1]) == []
    assert gm.boundary_loops(np.zeros((0, 3), int)) == []


# --------------------------------------------------------------------------- straightened
def _unit_square_ring():
    """The unit square's outline in z = 0, 10 samples a side (40, 3), counter-clockwise
    from the origin."""
    side = np.linspace(0, 1, 11)[:-1]
    square = np.vstack([np.column_stack([side, 0 * side]),
                        np.column_stack([1 + 0 * side, side]),
                        np.column_stack([1 - side, 1 + 0 * side]),
                        np.column_stack([0 * side, 1 - side])])
    return np.column_stack([square, np.zeros(len(square))])


def test_straightened_square_keeps_the_four_corners():
    square = _unit_square_ring()
    kept = gm.straightened(square, 1e-9)
    corners = {(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)}
    assert {tuple(p[:2]) for p in kept.tolist()} == corners and len(kept) == 4


def test_straightened_drops_only_points_within_eps_of_the_kept_polygon():
    theta = np.linspace(0, 2 * math.pi, 400, endpoint=False)
    ring = np.column_stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)])
    eps = 1e-3
    kept = gm.straightened(ring, eps)
    assert 3 <= len(kept) < len(ring)

    def distance_to_polygon(p, poly):
        best = np.inf
        for i in range(len(poly)):
            a, b = poly[i], poly[(i + 1) % len(poly)]
            s = np.clip((p - a) @ (b - a) / ((b - a) @ (b - a)), 0, 1)
            best = min(best, np.linalg.norm(p - (a + s * (b - a))))
        return best
    assert max(distance_to_polygon(p, kept) for p in ring) <= eps + 1e-12
    # a tighter eps keeps more points
    assert len(gm.straightened(ring, eps / 10)) > len(kept)


def test_straightened_keeps_the_points_it_is_told_to():
    square = _unit_square_ring()
    keep = np.zeros(len(square), dtype=bool)
    keep[[3, 17]] = True   # (0.3, 0) and (1, 0.7): collinear, kept all the same
    idx = gm.straightened_indices(square, 1e-9, keep=keep)
    assert {3, 17} <= set(idx.tolist()) and len(idx) == 6
    assert list(idx) == sorted(idx, key=lambda i: (i - idx[0]) % len(square))   # in order
    np.testing.assert_array_equal(gm.straightened(square, 1e-9, keep=keep), square[idx])


# --------------------------------------------------------------------------- conform
def _edge_use(sheets):
    """{undirected global edge: [sheet, ...]} of conformed sheets."""
    use = {}
    for k, s in enumerate(sheets):
        for f in s.ids[s.triangles].tolist():
            for i in range(3):
                a, b = f[i], f[(i + 1) % 3]
                use.setdefault((min(a, b), max(a, b)), []).append(k)
    return use


def _two_walls(cut=0.0, short=0.0):
    """An L of two planar sheets meeting along the seam x = 0, z = 0 .. 10 (elements
    (0, 1) and (0, 2); the seam holds 0, 1, 2): the floor y = 0 over x in [0, 5] and the
    wall x = 0 over y in [0, 5]; the floor's corner at (0, 0, 10) cut by ``cut`` and the
    wall's side ending ``short`` below the seam's end, as the library's simplification
    leaves them.  Seams: the shared one, split at z = 4 by a junction (two polylines),
    plus the floor's and wall's other sides (own elements)."""
    floor = np.array([[0, 0, 0], [5, 0, 0], [5, 0, 10], [cut, 0, 10], [0, 0, 10 - cut]],
                     dtype=float)
    floor_t = [[0, 1, 2], [0, 2, 3], [0, 3, 4]]
    wall = np.array([[0, 0, 0], [0, 0, 10 - short], [0, 5, 10], [0, 5, 0]], dtype=float)
    wall_t = [[0, 2, 1], [0, 3, 2]]
    seams = [(np.array([[0, 0, 0], [0, 0, 4.0]]), [0, 1, 2]),
             (np.array([[0, 0, 4.0], [0, 0, 10.0]]), [0, 1, 2]),
             (np.array([[0, 0, 0], [5, 0, 0], [5, 0, 10], [0, 0, 10]]), [0, 1, 7]),
             (np.array([[0, 0, 0], [0, 5, 0], [0, 5, 10], [0, 0, 10]]), [0, 2, 8])]
    return [(floor, floor_t, (0, 1)), (wall, wall_t, (0, 2))], seams


def test_conforming_sheets_share_the_seam_points_and_restore_the_cut_corner():
    from mfgeom.geometry.conform import conforming_sheets
    sheets, seams = _two_walls(cut=0.3, short=0.2)
    stats = {}
    out = conforming_sheets(sheets, seams, tolerance=1.0, stats=stats)
    assert stats["snapped"] == 9 and stats["unsnapped"] == 0
    use = _edge_use(out)
    shared = [e for e, who in use.items() if sorted(who) == [0, 1]]
    # both run (0, 0, 0) -> (0, 0, 4) -> (0, 0, 9.7) -> (0, 0, 10) on the same points:
    # the junction at 4, the floor's corner 9.7 (0.3 from the seam's end: more than
    # tol/4), the wall's 9.8 went to the seam's end (0.2: within tol/4)
    pts = {g: p for s in out for g, p in zip(s.ids.tolist(), s.points.tolist())}
    assert sorted(sorted(pts[g][2] for g in e) for e in shared) == \
        [[0, 4], [4, pytest.approx(9.7)], [pytest.approx(9.7), 10]]
    assert all(len(who) <= 2 for who in use.values())
    # the floor's cut corner is back: its area is the full 5 x 10
    for s in out:
        p, t = s.points, s.triangles
        assert gm.mesh_area(p, t) == pytest.approx(50.0)
    assert all(s.shared[s.ids.tolist().index(g)] for s in out for e in shared for g in e)


def test_conforming_sheets_without_seams_weld_within_the_tolerance():
    from mfgeom.geometry.conform import conforming_sheets
    sheets, _seams = _two_walls(cut=0.0, short=0.2)
    near = conforming_sheets(sheets, [], tolerance=0.5)   # the ends 0.2 apart: one point
    pts = {g: p for s in near for g, p in zip(s.ids.tolist(), s.points.tolist())}
    shared = [e for e, who in _edge_use(near).items() if sorted(who) == [0, 1]]
    assert [sorted(pts[g][2] for g in e) for e in shared] == [[0, 10]]
    # tolerance 0.1: the wall's end splits the floor's side, the last 0.2 stay open
    far = conforming_sheets(sheets, [], tolerance=0.1)
    pts = {g: p for s in far for g, p in zip(s.ids.tolist(), s.points.tolist())}
    shared = [e for e, who in _edge_use(far).items() if sorted(who) == [0, 1]]
    assert [sorted(pts[g][2] for g in e) for e in shared] == [[0, pytest.approx(9.8)]]


def test_without_needles_keeps_the_mesh_closed_over_a_row_of_collinear_points():
    from mfgeom.geometry.conform import without_needles
    # a strip 0 <= x <= 4, 0 <= y <= 1: the lower half a fan through the row y = 0.5
    # (x = 0 .. 4), the upper half two triangles on the row's ends, closed between them
    # by three zero-area triangles on the row (as an unsimplified library sheet has)
    p = np.array([[0, 0, 0], [4, 0, 0], [4, 1, 0], [0, 1, 0],
                  [0, 0.5, 0], [1, 0.5, 0], [2, 0.5, 0], [3, 0.5, 0], [4, 0.5, 0]],
                 dtype=float)
    t = np.array([[0, 1, 8], [0, 8, 7], [0, 7, 6], [0, 6, 5], [0, 5, 4],   # lower fan
                  [4, 8, 2], [4, 2, 3],                                    # upper half
                  [4, 5, 8], [5, 6, 8], [6, 7, 8]])                        # flat
    assert gm.boundary_loops(t) is not None
    clean = without_needles(p, t, 1e-12)
    area2 = np.linalg.norm(np.cross(p[clean[:, 1]] - p[clean[:, 0]],
                                    p[clean[:, 2]] - p[clean[:, 0]]), axis=1)
    assert area2.min() > 1e-9
    assert gm.mesh_area(p, clean) == pytest.approx(4.0)
    loops = gm.boundary_loops(clean)
    assert loops is not None and len(loops) == 1 and sorted(loops[0]) == [0, 1, 2, 3, 4, 8]
