# SPDX-License-Identifier: LGPL-2.1-or-later
"""The closed-mesh check and the soup weld through the binding: counts on meshes built to
have them, volume and area against analytic values and an independent numpy sum, under
random rigid motions and reorderings."""

import math

import numpy as np
import pytest

from mfgeom import core
from sweep_oracle import box_mesh, prism_mesh


def soup_of(v, t):
    return np.asarray(v, dtype=np.float64)[np.asarray(t)]          # (t, 3, 3)


def flip(t, rows=slice(None)):
    t = np.array(t)
    t[rows] = t[rows][:, ::-1]
    return t


def icosphere(level):
    """Unit icosphere: the icosahedron, each triangle split in four `level` times, the new
    vertices pushed onto the sphere; triangles outward (turned by their normal's sign
    against the centroid: the shape is convex round the origin)."""
    g = (1 + math.sqrt(5)) / 2
    v = [[-1, g, 0], [1, g, 0], [-1, -g, 0], [1, -g, 0], [0, -1, g], [0, 1, g],
         [0, -1, -g], [0, 1, -g], [g, 0, -1], [g, 0, 1], [-g, 0, -1], [-g, 0, 1]]
    v = [list(np.array(p) / np.linalg.norm(p)) for p in v]
    t = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
         [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
         [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    for _ in range(level):
        cache, out = {}, []

        def mid(i, j):
            key = (min(i, j), max(i, j))
            if key not in cache:
                p = (np.array(v[i]) + np.array(v[j])) / 2
                v.append(list(p / np.linalg.norm(p)))
                cache[key] = len(v) - 1
            return cache[key]
        for a, b, c in t:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            out += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        t = out
    v, t = np.array(v), np.array(t, dtype=np.int64)
    n = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
    inward = np.einsum("ij,ij->i", n, v[t].mean(axis=1)) < 0
    return v, flip(t, inward)


def numpy_volume_area(v, t):
    """Independent reference: signed tetrahedra from the origin, and half cross norms."""
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    vol = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    area = np.linalg.norm(np.cross(b - a, c - a), axis=1).sum() / 2
    return vol, area


def random_rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


CLEAN = dict(boundary_edges=0, nonmanifold_edges=0, inconsistent_edges=0,
             nonmanifold_vertices=0, degenerate_triangles=0, unused_vertices=0)


def assert_counts(rep, **expected):
    got = {k: getattr(rep, k) for k in expected}
    assert got == expected


def test_cube():
    v, t = box_mesh((-1, 0, 2), (2, 5, 6))
    rep = core.mesh_check(v, t)
    assert_counts(rep, nvertices=8, ntriangles=12, components=1, **CLEAN)
    assert rep.volume == 60.0 and rep.area == 2 * (15 + 12 + 20)
    np.testing.assert_array_equal(rep.bbox, [[-1, 0, 2], [2, 5, 6]])
    closed = core.mesh_check(v, t, require_closed=True)
    assert closed.as_dict() == rep.as_dict()
    assert "boundary_edges" in repr(rep)


def test_tetrahedron():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    t = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    rep = core.mesh_check(v, t, require_closed=True)
    assert rep.volume == pytest.approx(1 / 6, rel=1e-15)
    assert rep.area == pytest.approx(1.5 + math.sqrt(3) / 2, rel=1e-15)


def test_torus_genus_one():
    n, k, R, r = 48, 24, 3.0, 1.0
    u = 2 * np.pi * np.arange(n) / n
    w = 2 * np.pi * np.arange(k) / k
    uu, ww = np.meshgrid(u, w, indexing="ij")
    v = np.column_stack([((R + r * np.cos(ww)) * np.cos(uu)).ravel(),
                         ((R + r * np.cos(ww)) * np.sin(uu)).ravel(), (r * np.sin(ww)).ravel()])
    i, j = np.meshgrid(np.arange(n), np.arange(k), indexing="ij")
    a, b = i * k + j, ((i + 1) % n) * k + j
    c, d = ((i + 1) % n) * k + (j + 1) % k, i * k + (j + 1) % k
    t = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    rep = core.mesh_check(v, t, require_closed=True)
    assert_counts(rep, components=1, **CLEAN)
    # Euler characteristic V - E + F = 0 (genus 1), with E = 3F/2 for a closed manifold.
    assert rep.nvertices - 3 * rep.ntriangles // 2 + rep.ntriangles == 0
    vol, area = numpy_volume_area(v, t)
    assert rep.volume == pytest.approx(vol, rel=1e-12)
    assert rep.area == pytest.approx(area, rel=1e-12)
    assert 0.98 * 2 * math.pi ** 2 * R * r * r < rep.volume < 2 * math.pi ** 2 * R * r * r


def test_two_disjoint_cubes_and_a_cavity():
    v1, t1 = box_mesh((0, 0, 0), (1, 1, 1))
    v2, t2 = box_mesh((5, 0, 0), (7, 1, 1))
    v, t = np.vstack([v1, v2]), np.vstack([t1, t2 + 8])
    rep = core.mesh_check(v, t, require_closed=True)
    assert rep.components == 2 and rep.volume == 3.0
    v2, t2 = box_mesh((1, 1, 1), (2, 2, 2))
    outer, _ = box_mesh((0, 0, 0), (4, 4, 4))
    rep = core.mesh_check(np.vstack([outer, v2]), np.vstack([t1, flip(t2) + 8]),
                          require_closed=True)
    assert rep.components == 2 and rep.volume == 63.0


def test_open_cube():
    v, t = box_mesh()
    rep = core.mesh_check(v, t[:-1])
    assert_counts(rep, boundary_edges=3, inconsistent_edges=0, nonmanifold_edges=0)
    with pytest.raises(core.MfgError, match=r"mesh is not closed: 3 boundary edges \(first: vertices 1-5\)") as e:
        core.mesh_check(v, t[:-1], require_closed=True)
    assert e.value.status == "invalid argument"


def test_one_triangle_flipped():
    v, t = box_mesh()
    rep = core.mesh_check(v, flip(t, [4]))
    assert_counts(rep, inconsistent_edges=3, boundary_edges=0, nonmanifold_vertices=0)
    with pytest.raises(core.MfgError, match="inconsistent orientation across 3 edges"):
        core.mesh_check(v, flip(t, [4]), require_closed=True)


def test_inward_cube():
    v, t = box_mesh((0, 0, 0), (2, 2, 2))
    rep = core.mesh_check(v, flip(t))
    assert rep.volume == -8.0 and rep.inconsistent_edges == 0
    with pytest.raises(core.MfgError, match="negative volume -8: the triangles face inward"):
        core.mesh_check(v, flip(t), require_closed=True)


def test_nonmanifold_edge_and_vertex():
    v1, t1 = box_mesh((0, 0, 0), (1, 1, 1))
    v2, t2 = box_mesh((1, 1, 0), (2, 2, 1))              # shares the edge x = y = 1
    v, t = core.weld(np.concatenate([soup_of(v1, t1), soup_of(v2, t2)]))
    assert len(v) == 14
    rep = core.mesh_check(v, t)
    assert_counts(rep, nonmanifold_edges=1, nonmanifold_vertices=2, boundary_edges=0,
                  inconsistent_edges=0, components=1)
    with pytest.raises(core.MfgError, match="non-manifold edge 2-6 shared by 4 triangles"):
        core.mesh_check(v, t, require_closed=True)

    v2, t2 = box_mesh((1, 1, 1), (2, 2, 2))              # touches at the corner (1, 1, 1)
    v, t = core.weld(np.concatenate([soup_of(v1, t1), soup_of(v2, t2)]))
    rep = core.mesh_check(v, t)
    assert_counts(rep, nonmanifold_edges=0, nonmanifold_vertices=1, boundary_edges=0,
                  components=2)
    with pytest.raises(core.MfgError, match="non-manifold vertex 6: its triangles form 2 separate fans"):
        core.mesh_check(v, t, require_closed=True)


def test_degenerate_triangles():
    # A tetrahedron with edge 0-1 split at m = 4 on one side, closed by the zero-area
    # triangle (1, m, 0).
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.5, 0, 0]])
    t = np.array([[0, 2, 1], [0, 4, 3], [4, 1, 3], [0, 3, 2], [1, 2, 3], [1, 4, 0]])
    rep = core.mesh_check(v, t, require_closed=True)
    assert rep.degenerate_triangles == 1 and rep.volume == pytest.approx(1 / 6)
    v[4, 1] = 2.0 ** -60                                   # collinear only up to rounding
    assert core.mesh_check(v, t).degenerate_triangles == 0

    flat = np.array([[0, 0, 0], [1, 1, 1], [3, 3, 3]], dtype=float)
    with pytest.raises(core.MfgError, match="all 2 triangles have zero area") as e:
        core.mesh_check(flat, [[0, 1, 2], [0, 2, 1]], require_closed=True)
    assert e.value.status == "degenerate input"
    flat[2, 0] = 7
    with pytest.raises(core.MfgError, match="zero volume"):
        core.mesh_check(flat, [[0, 1, 2], [0, 2, 1]], require_closed=True)
    vb, tb = box_mesh()
    with pytest.raises(core.MfgError, match="triangle 12 repeats a vertex index"):
        core.mesh_check(vb, np.vstack([tb, [[3, 3, 5]]]), require_closed=True)
    with pytest.raises(core.MfgError, match="no triangles"):
        core.mesh_check(vb, np.zeros((0, 3), dtype=np.int64), require_closed=True)
    rep = core.mesh_check(vb, [])
    assert rep.ntriangles == 0 and rep.unused_vertices == 8 and rep.components == 0


@pytest.mark.parametrize("bad", [-1, 8, 2**63 - 1, -2**63])
def test_index_out_of_range(bad):
    v, t = box_mesh()
    t[5, 2] = bad
    with pytest.raises(core.MfgError, match="triangle 5 uses vertex index"):
        core.mesh_check(v, t)


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf, 1e300, 1e-300])
def test_bad_coordinates(value):
    v, t = box_mesh()
    v[6, 1] = value
    with pytest.raises(core.MfgError, match="vertex 6 has a NaN"):
        core.mesh_check(v, t)
    with pytest.raises(core.MfgError, match="triangle 0 has a NaN"):
        core.weld(soup_of(v, t[[9]]))


def test_conversion_errors():
    v, t = box_mesh()
    with pytest.raises(TypeError, match="triangles must be integers"):
        core.mesh_check(v, t.astype(float))
    with pytest.raises(TypeError, match="triangles must be integers"):
        core.mesh_check(v, t.astype(bool))
    with pytest.raises(TypeError, match="triangles must be integers"):
        core.mesh_check(v, [[0, 1, 2.5]])
    with pytest.raises(ValueError, match="does not fit in int64"):
        core.mesh_check(v, [[0, 1, 2**70]])
    with pytest.raises(ValueError, match="does not fit in int64"):
        core.mesh_check(v, np.array([[0, 1, 2**64 - 1]], dtype=np.uint64))
    with pytest.raises(ValueError, match=r"shape \(t, 3\)"):
        core.mesh_check(v, t.reshape(-1, 4))
    with pytest.raises(ValueError, match=r"shape \(n, 3\)"):
        core.mesh_check(v[:, :2], t)
    with pytest.raises(TypeError):
        core.mesh_check([["a", "b", "c"]], t)
    with pytest.raises(ValueError, match="soup must have shape"):
        core.weld(np.zeros((4, 4)))
    # Other integer types and nested lists are accepted.
    assert core.mesh_check(v.tolist(), t.astype(np.int32)).volume == 1.0
    assert core.mesh_check(v, t.astype(np.uint16).tolist()).volume == 1.0


def test_weld_round_trip():
    v, t = icosphere(2)
    # Number the vertices by first appearance: welding the soup must give exactly this.
    order = np.unique(t.ravel(), return_index=True)[1]
    first = t.ravel()[np.sort(order)]
    renum = np.empty(len(v), dtype=np.int64)
    renum[first] = np.arange(len(first))
    vr, tr = v[first], renum[t]
    for soup in (soup_of(v, t), soup_of(v, t).reshape(-1, 9), soup_of(v, t).reshape(-1, 3)):
        vw, tw = core.weld(soup)
        np.testing.assert_array_equal(vw, vr)
        np.testing.assert_array_equal(tw, tr)
        assert tw.dtype == np.int64
    vw, tw = core.weld(np.zeros((0, 3, 3)))
    assert vw.shape == (0, 3) and tw.shape == (0, 3)
    # -0 and +0 weld; one ulp apart does not.
    vw, tw = core.weld([[[-0.0, 0, 0], [1, 0, 0], [0, 1, 0]],
                        [[0.0, -0.0, 0], [0, 1, 0], [np.nextafter(1.0, 2.0), 0, 0]]])
    assert len(vw) == 4 and tw.tolist() == [[0, 1, 2], [0, 2, 3]]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_star_shaped_mesh_under_rigid_motions(seed):
    """An icosphere with random radii (star-shaped about the origin, so still a closed
    solid), moved by random rigid motions and with its triangles shuffled and their
    corners turned: counts unchanged, volume and area invariant and equal to numpy's."""
    rng = np.random.default_rng(seed)
    v, t = icosphere(3)
    v = v * rng.uniform(0.8, 1.2, (len(v), 1))
    rep = core.mesh_check(v, t, require_closed=True)
    assert_counts(rep, components=1, **CLEAN)
    vol, area = numpy_volume_area(v, t)
    assert rep.volume == pytest.approx(vol, rel=1e-13)
    assert rep.area == pytest.approx(area, rel=1e-13)
    for _ in range(3):
        rot, shift = random_rotation(rng), rng.normal(size=3) * 100
        perm = rng.permutation(len(t))
        turned = np.roll(t[perm], rng.integers(0, 3), axis=1)
        moved = core.mesh_check(v @ rot.T + shift, turned, require_closed=True)
        assert_counts(moved, components=1, **CLEAN)
        assert moved.volume == pytest.approx(vol, rel=1e-11)
        assert moved.area == pytest.approx(area, rel=1e-11)
        vw, tw = core.weld(soup_of(v @ rot.T + shift, turned))
        welded = core.mesh_check(vw, tw, require_closed=True)
        assert (welded.nvertices, welded.ntriangles) == (len(v), len(t))
        assert welded.volume == pytest.approx(moved.volume, rel=1e-15)


def test_prism_volume():
    """The oracle's test prism: an n-gon of circumradius r has area n r^2 sin(2 pi/n)/2."""
    n, r, h = 16, 1.0, 2.0
    v, t = prism_mesh((3.0, 0.0), r, h, n)
    rep = core.mesh_check(v, t, require_closed=True)
    assert rep.volume == pytest.approx(n * r * r * math.sin(2 * math.pi / n) / 2 * h, rel=1e-13)
