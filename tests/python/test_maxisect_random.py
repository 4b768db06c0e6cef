# SPDX-License-Identifier: LGPL-2.1-or-later
"""Randomised check of the maximum intersection on maps that share boundaries: lunes
about a few common axes with shared meridians, their negations, copies and copies moved
by 1e-16..1e-12, thin triangles with an edge on a shared meridian and arcs along them
(issue 17: a U slot's maps, A and -A sharing their poles, were undercounted).

The reference is direct containment (VisibilityMap.contains, numpy, with the documented
tolerance MFG_SPHERE_TOL = 1e-10: a polygon holds x when x.n >= -1e-10 for every edge)
at candidate directions: every map vertex, every edge midpoint, the centres of
level_regions(1) and of the result itself.  The maximum must equal the best candidate
count (so it is never below a direction the maps visibly share, and its own centres are
covered by what it claims), the best of level_regions(1), and every cover set must hold
its centre."""

import math

import numpy as np
import pytest

from mfgeom import core

TOL = 1e-10  # MFG_SPHERE_TOL (mfgeom.h)


def unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def random_rotation(rng):
    w, x, y, z = unit(rng.normal(size=4))
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def meridian_point(axis, bearing, lat):
    p, e1, e2 = axis
    return math.cos(lat) * (math.cos(bearing) * e1 + math.sin(bearing) * e2) + math.sin(lat) * p


def lune(axis, f1, f2):
    """From the pole p to -p between the meridians at bearings f1 < f2 (< f1 + pi):
    p, m(f1), -p, m(f2), counter-clockwise seen from outside."""
    p = axis[0]
    return np.array([p, meridian_point(axis, f1, 0.0), -p, meridian_point(axis, f2, 0.0)])


def negated(kind, v):
    """-M: every vertex negated; a polygon's order reversed to stay counter-clockwise."""
    return -v[::-1] if kind == "polygon" else -v


def nudged(rng, v):
    return unit(v + 10.0 ** rng.uniform(-16, -12) * rng.normal(size=v.shape))


def random_maps(rng):
    """3..10 maps from 1-2 axes and 2-4 shared meridian bearings."""
    axes = []
    for _ in range(int(rng.integers(1, 3))):
        r = random_rotation(rng)
        axes.append((r[:, 2], r[:, 0], r[:, 1]))
    bearings = list(rng.uniform(0, 2 * math.pi, int(rng.integers(2, 5))))
    lats = list(rng.uniform(-1.4, 1.4, 3)) + [math.pi / 2, -math.pi / 2]
    maps, count = [], int(rng.integers(3, 11))
    while len(maps) < count:
        axis = axes[int(rng.integers(len(axes)))]
        f = bearings[int(rng.integers(len(bearings)))]
        pick = rng.random()
        kind = "polygon"
        if pick < 0.4:  # a lune with a shared meridian, 1e-5 rad .. 2 rad wide
            w = 10.0 ** rng.uniform(-5, 0.3)
            v = lune(axis, f, f + w) if rng.random() < 0.5 else lune(axis, f - w, f)
        elif pick < 0.65:  # a thin triangle with an edge on a shared meridian
            l1, l2 = sorted(rng.choice(lats, 2, replace=False))
            if not 1e-3 < l2 - l1 < 3.0:
                continue
            th = 10.0 ** rng.uniform(-6, -1) * rng.choice([-1.0, 1.0])
            v = np.array([meridian_point(axis, f, l1), meridian_point(axis, f, l2),
                          meridian_point(axis, f + th, 0.5 * (l1 + l2))])
            if np.cross(v[0], v[1]) @ v[2] < 0:
                v = v[::-1]
        elif pick < 0.8:  # an arc along a shared meridian
            l1, l2 = sorted(rng.choice(lats, 2, replace=False))
            if not 1e-3 < l2 - l1 < 3.0:
                continue
            kind = "edge"
            ends = [meridian_point(axis, f, l1), meridian_point(axis, f, l2)]
            v = np.array(ends if rng.random() < 0.5
                         else [ends[0], meridian_point(axis, f, 0.5 * (l1 + l2)), ends[1]])
        elif maps:  # the negation or a copy of a map already there
            src = maps[int(rng.integers(len(maps)))]
            kind = src.kind
            v = negated(kind, src.vertices) if rng.random() < 0.6 else src.vertices.copy()
        else:
            continue
        if rng.random() < 0.4:
            v = nudged(rng, v)
        maps.append(core.VisibilityMap(kind, v))
    return maps


def coverage(maps, dirs):
    return sum(m.contains(dirs, TOL).astype(int) for m in maps)


def candidates(maps, *results):
    pts = []
    for m in maps:
        v = m.vertices
        pts.append(v)
        if len(v) > 1:
            nxt = np.roll(v, -1, axis=0) if m.kind == "polygon" else v[1:]
            mid = v + nxt if m.kind == "polygon" else v[:-1] + nxt
            pts.append(unit(mid))
    for r in results:
        pts.append(np.asarray(r.centres, float).reshape(-1, 3))
    return np.vstack(pts)


def check_against_containment(maps):
    res = core.max_intersection(maps)
    lev = core.level_regions(maps, 1)
    dirs = candidates(maps, res, lev)
    counts = coverage(maps, dirs)
    best = int(counts.max())
    assert res.count == best, (
        f"max_intersection says {res.count}, {best} maps hold {dirs[counts.argmax()]}")
    assert max(len(c) for c in lev.covers) == res.count
    for k, cover in enumerate(res.covers):
        assert len(cover) == res.count
        centre = res.centres[k][None, :]
        for i in cover:
            assert maps[int(i)].contains(centre, TOL)[0], f"region {k}: centre not in map {i}"
    for k, cover in enumerate(lev.covers):
        centre = lev.centres[k][None, :]
        assert all(maps[int(i)].contains(centre, TOL)[0] for i in cover)
    # the answer does not depend on the order of the maps
    perm = np.random.default_rng(len(maps)).permutation(len(maps))
    assert core.max_intersection([maps[i] for i in perm]).count == res.count
    return res


@pytest.mark.parametrize("block", range(4))
def test_random_shared_boundaries(block):
    for seed in range(100 * block, 100 * block + 100):
        maps = random_maps(np.random.default_rng(seed))
        try:
            check_against_containment(maps)
        except AssertionError as e:
            raise AssertionError(f"seed {seed}: {e}") from None


A = np.array([(0, 0, 1), (-0.0038461538461550923, -0.999992603522942, 0), (0, 0, -1),
              (0.0038461538461556127, -0.999992603522942, 0)], dtype=np.float64)


@pytest.mark.parametrize("order", [(0, 1, 0), (1, 0, 0), (0, 0, 1)])
def test_issue_lunes(order):
    """The issue's maps: A, -A, A.  +-z are vertices of all three, so the maximum is 3,
    a point at a pole (was 1)."""
    shapes = (A, negated("polygon", A))
    maps = [core.VisibilityMap("polygon", shapes[i]) for i in order]
    for pole in ((0, 0, 1.0), (0, 0, -1.0)):
        assert coverage(maps, np.array([pole]))[0] == 3
    res = check_against_containment(maps)
    assert res.count == 3 and res.kinds[0] == "point"
    assert abs(abs(res.direction[2]) - 1) < 1e-12
    lev = core.level_regions(maps, 2)
    assert max(len(c) for c in lev.covers) == 3


@pytest.mark.parametrize("seed", range(20))
def test_rotated_lune_copies(seed):
    """2..8 copies of a thin lune and its negation, rotated: the maximum is all of them."""
    rng = np.random.default_rng(1000 + seed)
    r = random_rotation(rng)
    axis = (r[:, 2], r[:, 0], r[:, 1])
    h = 10.0 ** rng.uniform(-5, -0.3)
    a = lune(axis, -math.pi / 2 - h, -math.pi / 2 + h)
    n = int(rng.integers(2, 9))
    shapes = [a, negated("polygon", a)] + [a if rng.random() < 0.5 else negated("polygon", a)
                                           for _ in range(n - 2)]
    maps = [core.VisibilityMap("polygon", nudged(rng, s) if rng.random() < 0.5 else s)
            for s in shapes]
    res = check_against_containment(maps)
    assert res.count == n
