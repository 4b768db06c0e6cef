# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tests of mfgeom.parting (mould parting and 3-axis set-ups) on synthetic Gaussian maps,
without FreeCAD: surfaces, canonicalisation under rotation, the examples' answers, and
a brute-force check against 10^4 sampled directions."""

import math

import numpy as np
import pytest

from mfgeom import core, parting as P

F = P.FaceGauss
RNG = np.random.default_rng(2024)
X, Y, Z = np.eye(3)


def rotation(rng):
    q = rng.normal(size=4)
    a, b, c, d = q / np.linalg.norm(q)
    return np.array([[a*a + b*b - c*c - d*d, 2*(b*c - a*d), 2*(b*d + a*c)],
                     [2*(b*c + a*d), a*a - b*b + c*c - d*d, 2*(c*d - a*b)],
                     [2*(b*d - a*c), 2*(c*d + a*b), a*a - b*b - c*c + d*d]])


def circle(axis, k=4):
    """k normals spread over the whole circle perpendicular to axis (a cylinder's
    full-circle Gaussian map as gauss_map samples it: gaps of pi/2)."""
    axis = np.asarray(axis, float)
    e1 = np.cross(axis, X if abs(axis @ X) < 0.9 else Y)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    t = np.linspace(0, 2 * math.pi, k + 1)
    return np.outer(np.cos(t), e1) + np.outer(np.sin(t), e2)


def cup(R=np.eye(3), hole=False):
    """Faces of the cup (and its radial blind hole along +x) as gauss_map gives them."""
    faces = [F(circle(Z) @ R.T, name="outer"), F([-Z @ R.T], name="bottom"),
             F([Z @ R.T], name="top"), F(-circle(Z) @ R.T, name="inner"),
             F([Z @ R.T], name="floor")]
    adj = [(0, 1, "convex"), (0, 2, "convex"), (2, 3, "convex"), (3, 4, "concave")]
    if hole:
        faces += [F(-circle(X) @ R.T, name="hole wall"), F([X @ R.T], name="hole floor")]
        adj += [(0, 5, "convex"), (5, 6, "concave")]
    return faces, adj


def pocket(axis, R, walls=4):
    """A prismatic pocket opening towards axis: floor normal +axis, walls facing in."""
    return [F([axis @ R.T])] + [F([-w @ R.T]) for w in circle(axis, walls)[:-1]]


def block(R=np.eye(3), sides=(Z, X, -Y), walls=4):
    faces = [F([s @ R.T]) for s in (X, -X, Y, -Y, Z, -Z)]
    adj = [(i, j, "convex") for i in range(6) for j in range(i + 1, 6) if i // 2 != j // 2]
    for axis in sides:
        start = len(faces)
        faces += pocket(np.asarray(axis, float), R, walls)
        adj += [(start, start + k, "concave") for k in range(1, walls + 1)]
        adj += [(start + k, start + k % walls + 1, "concave") for k in range(1, walls + 1)]
        adj += [(start + k, 0, "convex") for k in range(1, walls + 1)]
    return faces, adj


# ------------------------------------------------------------------ surfaces
def test_concave_surfaces_groups_across_concave_and_tangent_only():
    groups, has_concave = P.concave_surfaces(
        6, [(0, 1, "concave"), (1, 2, "tangent"), (2, 3, "convex"), (4, 5, "tangent"),
            (3, 3, "concave")])
    assert groups == [[0, 1, 2], [3], [4, 5]]
    assert has_concave == [True, False, False]


@pytest.mark.parametrize("adj", [[(0, 1, "sharp")], [(0, 5, "convex")]])
def test_concave_surfaces_rejects_bad_adjacency(adj):
    with pytest.raises(ValueError):
        P.concave_surfaces(2, adj)


def test_face_gauss_rejects_bad_input():
    with pytest.raises(ValueError):
        F(np.zeros((0, 3)))
    with pytest.raises(ValueError):
        F([[0, 0, 0]])
    with pytest.raises(ValueError):
        F([[0, 0, 1]], shrink=-1.0)
    faces, adj = cup()
    with pytest.raises(ValueError):
        P.mould_parting(faces, adj, weighting="volume")
    with pytest.raises(ValueError):
        P.mould_parting(faces, adj, draft_angle=-0.1)
    with pytest.raises(ValueError):
        P.nc_setups(faces, adj, tilt=2.0)


# ------------------------------------------------------------------ canonicalisation
def test_rotated_triangular_pocket_keeps_its_point_map():
    """Three walls at 120 degrees and a floor: VM is the floor normal, a POINT that the
    exact library loses on rotated doubles (never exactly on one great circle)."""
    walls = circle(Z, 3)[:-1]
    normals = np.vstack([walls, [Z]])
    raw_point = 0
    for _ in range(50):
        R = rotation(RNG)
        rotated = normals @ R.T
        raw_point += core.visibility_map(rotated).kind == "point"
        vm = P.surface_map(rotated)
        assert vm.kind == "point"
        assert np.allclose(vm.vertices[0], R @ Z, atol=1e-12)
        neg = P.surface_map(rotated, negative=True)
        assert neg.kind == "point" and np.allclose(neg.vertices[0], -R @ Z, atol=1e-12)
    assert raw_point < 50  # the snapping is what makes it work


def test_canonical_normals_move_normals_by_at_most_tol():
    R = rotation(RNG)
    normals = np.vstack([circle(Z, 5)[:-1], [Z], -circle(Z, 5)[:2]]) @ R.T
    normals += RNG.normal(scale=1e-9, size=normals.shape)
    Rl, local = P.canonical_normals(normals, tol=1e-6)
    back = local @ Rl
    back /= np.linalg.norm(back, axis=1)[:, None]
    # every snapped normal is within tol of an input normal and vice versa
    ang = np.arccos(np.clip(back @ (normals / np.linalg.norm(normals, axis=1)[:, None]).T, -1, 1))
    assert ang.min(axis=1).max() <= 1e-6 and ang.min(axis=0).max() <= 1e-6
    assert np.allclose(Rl @ Rl.T, np.eye(3), atol=1e-14)
    circ = np.abs(local[:, 2]) == 0.0
    assert circ.sum() == 7   # the 5 walls and 2 antipodes snapped exactly onto z = 0


# ------------------------------------------------------------------ the examples
def test_cup_everything_covered_along_axis():
    r = P.mould_parting(*cup())
    assert np.allclose(r.direction, Z) and r.covered == [0, 1, 2, 3]
    assert r.count == r.total == 4 and r.undercuts == [] and r.side_cores == []
    # outer wall parallel to d (either side), bottom cavity, top and pocket core
    assert r.side == [0, -1, 1, 1]


def test_cup_with_hole_one_undercut_side_core_and_two_setups():
    r = P.mould_parting(*cup(hole=True))
    assert np.allclose(r.direction, Z) and r.count == 4 and r.total == 5
    assert [r.surfaces[s].faces for s in r.undercuts] == [[5, 6]]
    assert len(r.side_cores) == 1 and np.allclose(r.side_cores[0].direction, X)
    assert r.side_cores[0].faces == [5, 6] and r.unresolved == []
    nc = P.nc_setups(*cup(hole=True))
    assert [s.faces for s in nc.setups] == [[3, 4], [5, 6]]
    assert np.allclose(nc.setups[0].direction, Z) and np.allclose(nc.setups[1].direction, X)


def test_block_with_three_pockets_needs_three_setups():
    nc = P.nc_setups(*block())
    dirs = sorted(tuple(np.round(s.direction, 9)) for s in nc.setups)
    assert dirs == sorted([tuple(Z), tuple(X), tuple(-Y)])
    assert nc.total == 3 and nc.unresolved == []
    every = P.nc_setups(*block(), all_faces=True)
    assert every.total == 9
    assert sum(len(s.surfaces) for s in every.setups) == 9
    # the main set-up covers a pocket and the five outer faces not facing away from it
    assert every.setups[0].weight == 6


@pytest.mark.parametrize("walls", [3, 4, 5, 6])
@pytest.mark.parametrize("seed", range(6))
def test_rotation_same_surfaces_rotated_directions(walls, seed):
    rng = np.random.default_rng(seed)
    R = rotation(rng)
    for build in (lambda M: cup(M, hole=True), lambda M: block(M, walls=walls)):
        a, b = P.mould_parting(*build(np.eye(3))), P.mould_parting(*build(R))
        assert a.covered == b.covered and a.undercuts == b.undercuts
        assert np.allclose(R @ a.direction, b.direction, atol=1e-9)
        assert abs(a.margin - b.margin) < 1e-9
        assert [c.surfaces for c in a.side_cores] == [c.surfaces for c in b.side_cores]
        for ca, cb in zip(a.side_cores, b.side_cores):
            assert np.allclose(R @ ca.direction, cb.direction, atol=1e-9)
        na, nb = P.nc_setups(*build(np.eye(3))), P.nc_setups(*build(R))
        assert [s.surfaces for s in na.setups] == [s.surfaces for s in nb.setups]
        for sa, sb in zip(na.setups, nb.setups):
            assert np.allclose(R @ sa.direction, sb.direction, atol=1e-9)


def cone_pocket(axis, taper, k=64):
    """A tapered round pocket opening towards axis: floor + walls leaning by taper."""
    ring = -circle(axis, k)[:-1]
    walls = math.cos(taper) * ring + math.sin(taper) * np.asarray(axis)
    return [F([axis]), F(walls, shrink=0.0)]


def draft_flip():
    faces, adj = block(sides=(Z, Z, Z))
    for _ in range(2):
        start = len(faces)
        faces += cone_pocket(X, math.radians(10))
        adj += [(start, start + 1, "concave"), (start + 1, 0, "convex")]
    return faces, adj


def test_draft_angle_keeps_the_direction_and_lists_the_walls():
    """The draft classifies faces; it does not move the draw (issue 17: a mould maker
    picks the draw, then drafts the walls).  The draft-flip block keeps +-z at 3 degrees;
    its straight walls (the block's sides, the top pockets' walls) are listed as zero
    draft, the tapered +x pockets stay the undercuts they are along z."""
    faces, adj = draft_flip()
    r0 = P.mould_parting(faces, adj)
    assert np.allclose(r0.direction, Z) and r0.count == 9 and r0.total == 11
    r3 = P.mould_parting(faces, adj, draft_angle=math.radians(3))
    assert np.allclose(r3.direction, Z) and r3.count == 9
    assert r3.covered == r0.covered and r3.undercuts == r0.undercuts
    walls = [f for f, g in enumerate(faces) if np.all(np.abs(g.normals @ Z) < 1e-12)
             and not any(f in r3.surfaces[s].faces for s in r3.undercuts)]
    assert len(walls) == 4 + 3 * 4
    assert r3.zero_draft_faces == walls == r0.zero_draft_faces
    assert r3.insufficient_draft_faces == walls
    # every other covered face has the draft on its side
    for s in r3.covered:
        for f in r3.surfaces[s].faces:
            if f not in walls:
                dots = faces[f].normals @ r3.direction * r3.side[s]
                assert dots.min() >= math.sin(math.radians(3)) - 1e-9
                assert r3.face_role[f] == ("core" if r3.side[s] > 0 else "cavity")
    # the tapered pockets' worst normal leans 80 degrees the wrong way along z
    for s in r3.undercuts:
        fs = r3.surfaces[s].faces
        assert all(r3.face_role[f] == "undercut" for f in fs)
        assert min(r3.face_angle[f] for f in fs) < -math.radians(79)


def test_insufficient_draft_reported_apart_from_undercuts():
    faces, adj = cup()
    r = P.mould_parting(faces, adj, draft_angle=math.radians(1))
    assert r.covered == [0, 1, 2, 3] and r.undercuts == []
    # the outer and the pocket's walls are vertical: zero draft, listed as insufficient
    assert r.zero_draft_faces == [0, 3] and r.insufficient_draft_faces == [0, 3]
    assert [r.face_role[f] for f in (1, 2, 4)] == ["cavity", "core", "core"]
    assert r.face_angle[0] == pytest.approx(0.0, abs=1e-12)
    r0 = P.mould_parting(faces, adj)
    assert r0.zero_draft_faces == [0, 3] and np.allclose(r0.direction, r.direction)


def test_box_gives_its_shortest_draw():
    """A plain 100 x 60 x 20 box: every face is free; the largest projected area (the
    shortest draw) decides: +-z, at 0 and at 1 degree, the four walls listed."""
    dims = np.array([100.0, 60.0, 20.0])
    R = rotation(np.random.default_rng(5))
    for M in (np.eye(3), R):
        faces = []
        for axis in range(3):
            area = float(np.prod(np.delete(dims, axis)))
            for sgn in (-1, 1):
                faces.append(F([sgn * np.eye(3)[axis] @ M.T], area=area))
        adj = [(i, j, "convex") for i in range(6) for j in range(i + 1, 6) if i // 2 != j // 2]
        for draft in (0.0, math.radians(1)):
            r = P.mould_parting(faces, adj, draft_angle=draft)
            assert abs(r.direction @ (M @ Z)) == pytest.approx(1.0, abs=1e-12)
            assert r.count == 6 and r.undercuts == []
            assert r.zero_draft_faces == [0, 1, 2, 3]
            assert P.projected_area(faces, r.direction) == pytest.approx(6000.0)


def test_zero_draft_noise_walls_do_not_make_an_undercut():
    """CAD noise: a floor and walls 'vertical by design' whose sampled normals sit
    1e-5 rad below the floor's plane (a B-spline fit), as a fan blade's walls on its
    disc.  Within the angular tolerance (0.01 deg) they are zero draft, the surface is
    covered along the floor's normal; beyond it (a 1-degree undercut) it is not."""
    rng = np.random.default_rng(3)
    R = rotation(rng)
    ring = circle(Z, 64)[:-1]
    for tilt, covered in ((-1e-5, True), (-math.radians(1), False)):
        walls = math.cos(tilt) * ring + math.sin(tilt) * Z
        walls += rng.normal(scale=2e-6, size=walls.shape) * (tilt > -1e-4)
        faces = [F([Z @ R.T], name="disc"), F(walls[:32] @ R.T, name="wall a"),
                 F(walls[32:] @ R.T, name="wall b"), F([-Z @ R.T], name="bottom")]
        adj = [(0, 1, "concave"), (0, 2, "concave"), (1, 2, "tangent"), (3, 1, "convex"),
               (3, 2, "convex")]
        r = P.mould_parting(faces, adj)
        if covered:
            assert np.allclose(r.direction, R @ Z, atol=1e-9) and r.undercuts == []
            assert r.zero_draft_faces == [1, 2]
            assert all(-math.radians(0.01) <= r.face_angle[f] <= 0 for f in (1, 2))
        else:
            assert r.undercuts, "a 1 degree undercut must stay one"
            worst = min(r.face_angle[f] for f in (1, 2))
            assert worst == pytest.approx(-math.radians(1), abs=1e-4) or r.face_angle[0] < 0


def test_draft_analysis_classes():
    faces = [F([Z], name="top"), F([-Z], name="bottom"), F(circle(Z, 8)[:-1], name="wall"),
             F([math.cos(0.1) * X + math.sin(0.1) * Z], name="drafted"),
             F([X + 0.5 * Z, X - 0.5 * Z], name="straddle"),
             F([math.cos(0.01) * X + math.sin(0.01) * Z], name="shallow")]
    a = P.draft_analysis(faces, [0, 0, 2], math.radians(1))
    assert a.classes == ["positive", "negative", "insufficient", "positive", "straddle",
                         "insufficient"]
    assert a.low[3] == pytest.approx(0.1) and a.high[1] == pytest.approx(-math.pi / 2)
    a0 = P.draft_analysis(faces, Z)
    assert a0.classes[2] == "insufficient" and a0.classes[5] == "positive"
    with pytest.raises(ValueError):
        P.draft_analysis(faces, [0, 0, 0])
    with pytest.raises(ValueError):
        P.draft_analysis(faces, Z, draft_angle=-1)


def test_area_weighting_changes_the_answer():
    # two pockets seen from +z (small) against one from +x (large area)
    faces, adj = block(sides=(Z, Z, X))
    nc = P.nc_setups(faces, adj)
    assert np.allclose(nc.direction, Z)
    for f in faces[-5:]:
        f.area = 100.0
    nc = P.nc_setups(faces, adj, weighting="area")
    assert np.allclose(nc.direction, X) and nc.setups[0].weight == 500.0


# ------------------------------------------------------------------ brute force
def brute_counts(surfaces, dirs, mould, draft=0.0, eps=1e-12):
    s = math.sin(draft)
    out = np.zeros(len(dirs))
    for surf in surfaces:
        dots = dirs @ surf.normals.T
        ok = dots.min(axis=1) >= s - eps
        if mould:
            ok |= dots.max(axis=1) <= -s + eps
        out += surf.weight * ok
    return out


def random_part(rng, nsurf):
    """Surfaces as random caps of normals (a few with one normal or a circle)."""
    faces = []
    for i in range(nsurf):
        kind = rng.integers(0, 4)
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        if kind == 0:
            faces.append(F([axis], area=rng.uniform(1, 3)))
            continue
        if kind == 1:
            faces.append(F(circle(axis), area=rng.uniform(1, 3)))
            continue
        k = rng.integers(3, 9)
        spread = rng.uniform(0.1, 1.2)
        pts = axis + spread * rng.normal(size=(k, 3))
        faces.append(F(pts, area=rng.uniform(1, 3)))
    return faces, []


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("mould", [True, False])
def test_no_sampled_direction_beats_the_answer(seed, mould):
    rng = np.random.default_rng(100 + seed)
    faces, adj = random_part(rng, 12)
    dirs = P.fibonacci_sphere(20000)
    draft = [0.0, math.radians(2)][seed % 2]
    weighting = ["count", "area"][(seed // 2) % 2]
    if mould:
        r = P.mould_parting(faces, adj, draft_angle=draft, weighting=weighting)
    else:
        r = P.nc_setups(faces, adj, tilt=draft, weighting=weighting, all_faces=True)
    # Mould chooses its direction without the draft (the draft classifies faces)
    draft = 0.0 if mould else draft
    counts = brute_counts(r.surfaces, dirs, mould, draft)
    assert counts.max() <= r.count + 1e-9
    # the answer is valid on every normal of its covered surfaces (within tol)
    mine = brute_counts([r.surfaces[s] for s in r.covered], r.direction[None, :], mould,
                        draft, eps=2 * math.sin(P.DEFAULT_TOL))
    assert mine[0] == pytest.approx(r.count)
    assert r.count > 0


def test_antipodal_point_maps_with_weights():
    """Regression for a library bug found by the brute-force test (random_part(100)):
    two antipodal POINT maps among hemispheres and polygons, with weights, made
    core.max_intersection miss the maximum (5.85 instead of 7.77).  mould/nc split such
    maps; the brute-force test above is the end-to-end check, this one pins the case."""
    rng = np.random.default_rng(100)
    faces, adj = random_part(rng, 12)
    r = P.nc_setups(faces, adj, weighting="area", all_faces=True)
    assert r.count == pytest.approx(7.766692871158426)
    maps = [P.surface_map(s.normals) for s in r.surfaces]
    owner = list(range(len(maps)))
    weights = {s: r.surfaces[s].weight for s in owner}
    d, margin, covered = P._best_region(maps, owner, weights)
    assert sorted(covered) == [1, 2, 8, 9, 10]


def test_surfaces_within_tol_share_their_directions():
    """Two pockets whose floors are 1e-8 rad apart (far below tol, far above the library's
    1e-10): one set-up covers both, in both orders and after rotation."""
    tilt = np.array([0.0, 1e-8, 1.0])
    tilt /= np.linalg.norm(tilt)
    faces, adj = [], []
    for floor in (Z, tilt):
        start = len(faces)
        e1 = np.cross(floor, X)
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(floor, e1)
        faces += [F([floor])] + [F([w]) for w in (e1, e2, -e1, -e2)]
        adj += [(start, start + k, "concave") for k in range(1, 5)]
    for R in (np.eye(3), rotation(RNG)):
        rotated = [F(f.normals @ R.T) for f in faces]
        nc = P.nc_setups(rotated, adj)
        assert len(nc.setups) == 1 and nc.setups[0].surfaces == [0, 1]
        assert np.allclose(nc.direction, R @ Z, atol=1e-7)


# Regression: weighted max_intersection used to miss the maximum when two-direction
# POINT maps were among the inputs (the sweep took a point for a short arc); parting
# split such maps as a workaround until the library was fixed (commit 2331822).
def test_library_weighted_two_direction_point_maps():
    rng = np.random.default_rng(100)
    faces, _ = random_part(rng, 12)
    maps = [P.surface_map(f.normals) for f in faces]
    weights = np.array([f.area for f in faces])
    res = core.max_intersection(maps, weights=weights)
    d = P.fibonacci_sphere(20000)
    best = max(weights[[i for i, m in enumerate(maps) if m.contains(x[None], tol=1e-9)[0]]].sum()
               for x in d[::20])
    assert res.count >= best - 1e-9


def test_sampled_face_does_not_shrink_its_exact_neighbours():
    """A drilled blind hole: exact cylinder (POINT map +-z) and a sampled drill-point cone
    joined by a concave edge: the hole is machinable along +z.  Shrinking the whole
    surface by the cone's shrink made it unreachable from every direction."""
    t = np.linspace(0, 2 * math.pi, 65)[:-1]
    radial = np.column_stack([np.cos(t), np.sin(t), np.zeros_like(t)])
    beta = math.radians(31)
    cone = math.cos(beta) * Z - math.sin(beta) * radial
    faces = [F(-circle(Z), name="wall"), F(cone, shrink=1e-3, name="point"),
             F([Z], name="top")]
    adj = [(0, 1, "concave"), (0, 2, "convex")]
    for R in (np.eye(3), rotation(RNG)):
        rotated = [F(f.normals @ R.T, shrink=f.shrink) for f in faces]
        nc = P.nc_setups(rotated, adj)
        assert nc.unresolved == [] and len(nc.setups) == 1
        assert np.allclose(nc.direction, R @ Z, atol=1e-9)
        r = P.mould_parting(rotated, adj)
        assert r.covered == [0, 1] and np.allclose(r.direction, R @ Z, atol=1e-9)


@pytest.mark.parametrize("seed", range(4))
def test_memo_of_equal_surfaces_changes_no_answer(seed, monkeypatch):
    """mould_parting and nc_setups map equal surfaces (repeated features) once and VM and
    -VM of one surface with one canonical frame (a memo per analysis): every answer is
    the one computed without the memo, exactly, on parts with repeated pockets, drilled
    holes (sampled cones) and random caps, at draft 0 and 2 degrees."""
    rng = np.random.default_rng(300 + seed)
    faces, adj = block(rotation(rng), sides=(Z, Z, X, -Y, X))
    caps, _ = random_part(rng, 6)
    t = np.linspace(0, 2 * math.pi, 65)[:-1]
    tip = math.cos(0.5) * Y - math.sin(0.5) * np.column_stack(
        [np.cos(t), np.zeros_like(t), np.sin(t)])
    for copy in range(3):   # three equal drilled holes and three equal caps
        start = len(faces)
        faces += [F(-circle(Y)), F(tip, shrink=1e-3)]
        adj += [(start, start + 1, "concave"), (start, 0, "convex")]
        faces += [F(c.normals) for c in caps[copy % 2::2]]
    plain = P.surface_vm

    def without_memo(surf, draft, tol=P.DEFAULT_TOL, negative=False, memo=None):
        return plain(surf, draft, tol, negative)

    def answers():
        out = []
        for draft in (0.0, math.radians(2)):
            for r in (P.mould_parting(faces, adj, draft_angle=draft),
                      P.nc_setups(faces, adj, tilt=draft, all_faces=True)):
                out.append((r.direction.tolist(), r.margin, r.covered, r.count, r.side,
                            r.undercuts, r.insufficient_draft, r.unresolved,
                            [(d.direction.tolist(), d.margin, d.surfaces)
                             for d in r.side_cores + r.setups]))
        return out
    inner, computed = P._surface_vm, []

    def counted(*args):
        computed.append(1)
        return inner(*args)
    monkeypatch.setattr(P, "_surface_vm", counted)
    with_memo = answers()
    monkeypatch.undo()
    monkeypatch.setattr(P, "surface_vm", without_memo)
    assert answers() == with_memo
    surfaces = P.build_surfaces(faces, adj)
    assert len(computed) < 4 * 2 * len(surfaces)   # equal surfaces were shared
