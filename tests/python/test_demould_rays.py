# SPDX-License-Identifier: LGPL-2.1-or-later
"""core.ray_blocked against an independent numpy ray/triangle test (float, clear cases
only), its argument errors, and mfgeom.demould's per-face verdicts on simple solids."""

import numpy as np
import pytest

from mfgeom import core, demould


def brute_force(vertices, triangles, points, own, d, eps=1e-9):
    """Moller-Trumbore in float64 for every point and triangle: (bits, clear) where
    clear is False when some crossing is too close to an edge, to s = 0 or to a plane
    parallel to d for float64 to be trusted."""
    v0 = vertices[triangles[:, 0]]
    e1 = vertices[triangles[:, 1]] - v0
    e2 = vertices[triangles[:, 2]] - v0
    h = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, h)
    bits = np.zeros(len(points), dtype=np.uint8)
    clear = np.ones(len(points), dtype=bool)
    for i, p in enumerate(points):
        s = p - v0
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.einsum("ij,ij->i", s, h) / det
            q = np.cross(s, e1)
            v = (q @ d) / det
            t = np.einsum("ij,ij->i", e2, q) / det
        ok = np.abs(det) > eps
        if own is not None and own[i] >= 0:
            ok[own[i]] = False
        w = 1 - u - v
        inside = ok & (u > eps) & (v > eps) & (w > eps)
        near = ok & ~inside & (u > -eps) & (v > -eps) & (w > -eps)
        if near.any() or (inside & (np.abs(t) < eps)).any():
            clear[i] = False
        if (inside & (t > 0)).any():
            bits[i] |= core.RAY_BLOCKED_POS
        if (inside & (t < 0)).any():
            bits[i] |= core.RAY_BLOCKED_NEG
    return bits, clear


def test_random_soups_agree_with_float_brute_force():
    rng = np.random.default_rng(17)
    compared = 0
    for _ in range(20):
        nt = int(rng.integers(1, 200))
        centres = rng.uniform(-1, 1, (nt, 1, 3))
        vertices = (centres + rng.uniform(-0.4, 0.4, (nt, 3, 3))).reshape(-1, 3)
        triangles = np.arange(3 * nt).reshape(-1, 3)
        points = rng.uniform(-1.2, 1.2, (300, 3))
        own = np.where(rng.random(300) < 0.3, rng.integers(0, nt, 300), -1)
        d = rng.normal(size=3)
        got = core.ray_blocked(vertices, triangles, points, own, d)
        assert got.dtype == np.uint8 and got.shape == (300,)
        ref, clear = brute_force(vertices, triangles, points, own, d / np.linalg.norm(d))
        np.testing.assert_array_equal(got[clear], ref[clear])
        compared += int(clear.sum())
        # the direction's length does not matter, and -d swaps the two bits
        longer = core.ray_blocked(vertices, triangles, points, own, 7 * d)
        np.testing.assert_array_equal(longer, got)
        swapped = core.ray_blocked(vertices, triangles, points, own, -d)
        np.testing.assert_array_equal(swapped & 1, (got >> 1) & 1)
        np.testing.assert_array_equal(swapped & 2, (got & 1) << 1)
    assert compared > 5000


def box_mesh(x0, y0, z0, x1, y1, z1):
    v = np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                  [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]], dtype=float)
    t = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                  [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])
    faces = np.repeat(np.arange(6), 2)      # bottom, top, y0, x1, y1, x0
    return v, t, faces


def test_box_centroids():
    v, t, _ = box_mesh(0, 0, 0, 2, 3, 1)
    pts = v[t].mean(axis=1)
    bits = core.ray_blocked(v, t, pts, np.arange(12), [0, 0, 1])
    # bottom: blocked up (by the top), free down; top: the reverse; walls: free both ways
    np.testing.assert_array_equal(bits[:4] & 3, [1, 1, 2, 2])
    assert not (bits[4:] & 3).any()
    # without own triangles the rounded centroids may hit their own triangle: the library
    # ignores s = 0 only when exact, so own_triangle None is allowed but not used here
    assert core.ray_blocked(v, t, np.zeros((0, 3)), None, [0, 0, 1]).shape == (0,)


def test_errors():
    v, t, _ = box_mesh(0, 0, 0, 1, 1, 1)
    p = np.array([[0.5, 0.5, -1.0]])
    with pytest.raises(core.MfgError, match="zero vector"):
        core.ray_blocked(v, t, p, None, [0, 0, 0])
    with pytest.raises(core.MfgError, match="direction"):
        core.ray_blocked(v, t, p, None, [0, np.nan, 1])
    with pytest.raises(core.MfgError, match="point 0"):
        core.ray_blocked(v, t, [[np.inf, 0, 0]], None, [0, 0, 1])
    with pytest.raises(core.MfgError, match="own_triangle"):
        core.ray_blocked(v, t, p, [12], [0, 0, 1])
    with pytest.raises(core.MfgError, match="own_triangle"):
        core.ray_blocked(v, t, p, [-2], [0, 0, 1])
    with pytest.raises(core.MfgError, match="vertex index"):
        core.ray_blocked(v, t + 5, p, None, [0, 0, 1])
    with pytest.raises(ValueError, match="entries"):
        core.ray_blocked(v, t, p, [0, 1], [0, 0, 1])
    with pytest.raises(TypeError):
        core.ray_blocked(v, t, p, [0.5], [0, 0, 1])
    with pytest.raises(ValueError, match="shape"):
        core.ray_blocked(v, t, p, None, [0, 1])
    with pytest.raises(ValueError, match="points"):
        core.ray_blocked(v, t, [[0, 1]], None, [0, 0, 1])
    # below the bottom face's diagonal: through its edge only (and the top's): grazing
    assert core.ray_blocked(v, t, p, [-1], [0, 0, 1])[0] == core.RAY_GRAZES_POS
    assert core.ray_blocked(v, t, [[0.7, 0.2, -1]], [-1], [0, 0, 1])[0] == core.RAY_BLOCKED_POS


# ---- mfgeom.demould ------------------------------------------------------------------

def test_demould_box_faces():
    v, t, faces = box_mesh(0, 0, 0, 2, 3, 1)
    res = demould.face_demouldability(v, t, faces, [0, 0, 1])
    verdicts = {r.face: r.verdict for r in res}
    assert verdicts == {0: "cavity", 1: "core", 2: "both", 3: "both", 4: "both", 5: "both"}
    bottom = res[0]
    assert bottom.blocked_pos == pytest.approx(1.0) and bottom.blocked_neg == 0.0
    assert bottom.samples >= 2


def test_demould_shadowed_face():
    # a floor slab with a roof slab above part of it, joined by a post on one side: the
    # floor's top face under the roof is blocked along +z, the rest is free
    parts = [box_mesh(0, 0, 0, 4, 1, 1), box_mesh(0, 0, 1, 1, 1, 3), box_mesh(0, 0, 3, 3, 1, 4)]
    verts, tris, faces = [], [], []
    for k, (v, t, f) in enumerate(parts):
        tris.append(t + sum(len(x) for x in verts))
        verts.append(v)
        faces.append(f + 6 * k)
    v, t, f = np.concatenate(verts), np.concatenate(tris), np.concatenate(faces)
    res = {r.face: r for r in demould.face_demouldability(v, t, f, [0, 0, 1])}
    floor_top = res[1]      # z = 1 (x 0..4: partly under the post, the roof covers x < 3)
    assert floor_top.verdict == "blocked"
    assert 0.5 < floor_top.blocked_pos < 1.0    # x 1..3 of the free part 1..4 is shadowed
    roof_top = res[13]
    assert roof_top.verdict == "core"


def test_sampling():
    v, t, faces = box_mesh(0, 0, 0, 2, 3, 1)
    points, own, weight = demould.sample_points(v, t, faces, samples_per_face=64, lift=0.0)
    # each face has 2 equal triangles: L = round(sqrt(32)) = 6, 36 sub-triangles each
    assert len(points) == 12 * 36
    np.testing.assert_array_equal(np.bincount(own), np.full(12, 36))
    area = 0.5 * np.linalg.norm(np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]), axis=1)
    np.testing.assert_allclose(np.bincount(own, weights=weight), area)
    # the samples lie inside their triangles (barycentric coordinates all >= 1/18)
    a, b, c = v[t[own, 0]], v[t[own, 1]], v[t[own, 2]]
    n = np.cross(b - a, c - a)
    for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
        lam = (np.einsum("ij,ij->i", np.cross(q - points, r - points), n)
               / np.einsum("ij,ij->i", n, n))
        assert lam.min() > 1 / 18 - 1e-12
    lifted, _, _ = demould.sample_points(v, t, faces, samples_per_face=64)
    offset = np.einsum("ij,ij->i", lifted - points, n / np.linalg.norm(n, axis=1)[:, None])
    np.testing.assert_allclose(offset, demould.LIFT * np.linalg.norm([2, 3, 1]), rtol=1e-6)


def test_rotated_float32_box_keeps_zero_draft_walls_free():
    expected = ["cavity", "core", "both", "both", "both", "both"]
    unlifted_wrong = 0
    for seed in range(10):
        rng = np.random.default_rng(seed)
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        q *= np.sign(np.linalg.det(q))
        v, t, faces = box_mesh(0, 0, 0, 20, 30, 10)
        # float32 nodes, as FreeCAD's mesh kernel stores them: the walls bend a hair
        vr = (v @ q.T + [100, -40, 7]).astype(np.float32).astype(np.float64)
        res = demould.face_demouldability(vr, t, faces, q @ [0, 0, 1])
        assert [r.verdict for r in res] == expected
        unlifted = demould.face_demouldability(vr, t, faces, q @ [0, 0, 1], lift=0.0)
        unlifted_wrong += [r.verdict for r in unlifted] != expected
    # why the lift: on the exact doubles a bent zero-draft wall blocks itself
    assert unlifted_wrong > 0


def test_scaled_and_moved_inputs_give_the_same_flags():
    """A unit cube and points on/around it, scaled by 1e-9 .. 1e9 and moved: the exact
    predicates give the same flags at every scale (no absolute epsilon anywhere)."""
    import itertools
    corners = np.array(list(itertools.product((0.0, 1.0), repeat=3)))
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4),
             (1, 5, 7, 3)]
    tris = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    pts = np.array([[0.3, 0.4, 1.0], [0.3, 0.4, 0.0], [0.3, 0.4, 0.5], [0.3, 0.4, 2.0],
                    [1.5, 0.5, 0.5]])
    own = np.array([-1, -1, -1, -1, -1])
    d = np.array([0.0, 0.0, 1.0])
    want = core.ray_blocked(corners, tris, pts, own, d)
    assert want[2] == core.RAY_BLOCKED_POS | core.RAY_BLOCKED_NEG   # inside the cube
    assert want[3] & core.RAY_BLOCKED_NEG and not want[3] & core.RAY_BLOCKED_POS
    assert want[4] == 0                                                # beside it
    shift = np.array([3.0, -7.0, 11.0])
    for scale in (1e-9, 1e-3, 1.0, 1e3, 1e9):
        got = core.ray_blocked(corners * scale + shift * scale, tris, pts * scale + shift * scale,
                               own, d * scale)
        np.testing.assert_array_equal(got, want, err_msg=f"scale {scale}")
