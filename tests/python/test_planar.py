# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.geometry.planar (the coplanar groups of a closed mesh and their boundary loops,
for the B-rep faces of the Solid representation and the clearance check) on meshes whose
planar faces are known: subdivided boxes, a box with a square hole through it (a face
with a hole), a T-junction closed by a zero-area triangle, a curved torus (no two
triangles coplanar), a cube rolled by a random rotation; loops checked against the brute
force boundary between groups and by their signed areas."""

import math

import numpy as np
import pytest

from mfgeom import core
from mfgeom.geometry import planar
from sweep_oracle import box_mesh, torus_mesh

RNG = np.random.default_rng(20)


def grid_box(n, size=(2.0, 3.0, 5.0)):
    """A box whose six faces are cut into n x n squares (two triangles each), outward."""
    quads, points = [], {}

    def vid(p):
        return points.setdefault(tuple(np.round(p, 12)), len(points))
    size = np.asarray(size)
    ticks = np.linspace(0.0, 1.0, n + 1)
    for axis in range(3):
        u, w = (axis + 1) % 3, (axis + 2) % 3
        for side in (0.0, 1.0):
            for i in range(n):
                for j in range(n):
                    quad = []
                    for du, dw in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = np.zeros(3)
                        p[axis], p[u], p[w] = side, ticks[i + du], ticks[j + dw]
                        quad.append(vid(p * size))
                    quads.append(quad[::-1] if side == 0.0 else quad)
    v = np.array(sorted(points, key=points.get))
    t = np.array([(q[0], q[1], q[2]) for q in quads] + [(q[0], q[2], q[3]) for q in quads])
    return v, t


def frame_mesh():
    """A 4 x 4 x 1 slab with a 2 x 2 square hole through its middle: the top and the
    bottom are planar faces with one hole each (10 planar faces in all)."""
    outer = [(0, 0), (4, 0), (4, 4), (0, 4)]
    inner = [(1, 1), (3, 1), (3, 3), (1, 3)]
    v = [(x, y, z) for z in (0.0, 1.0) for x, y in outer + inner]
    idx = {p: i for i, p in enumerate(v)}

    def i(x, y, z):
        return idx[(x, y, z)]
    t = []
    for z, up in ((1.0, True), (0.0, False)):
        ring = [(outer[k], outer[(k + 1) % 4], inner[(k + 1) % 4], inner[k]) for k in range(4)]
        for a, b, c, d in ring:
            q = [i(*a, z), i(*b, z), i(*c, z), i(*d, z)]
            if not up:
                q = q[::-1]
            t += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    for loop, out in ((outer, True), (inner, False)):
        for k in range(4):
            a, b = loop[k], loop[(k + 1) % 4]
            q = [i(*a, 0.0), i(*b, 0.0), i(*b, 1.0), i(*a, 1.0)]
            if not out:
                q = q[::-1]
            t += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    return np.array(v, float), np.array(t)


def boundary_between_groups(t, group):
    directed = {}
    for k, tr in enumerate(t.tolist()):
        for j in range(3):
            directed[(tr[j], tr[(j + 1) % 3])] = k
    return {e for e, k in directed.items()
            if group[directed[(e[1], e[0])]] != group[k]}


def check_loops(v, t, group, normals, loops):
    want = boundary_between_groups(t, group)
    walked = set()
    for g, boundary in enumerate(loops):
        assert boundary, f"group {g} has no loops"
        for n_loop, loop in enumerate(boundary):
            area = float(normals[g] @ np.cross(v[loop], np.roll(v[loop], -1, axis=0)).sum(axis=0))
            assert (area > 0) == (n_loop == 0), (g, n_loop, area)    # outer first, CCW
            walked |= {(loop[i], loop[(i + 1) % len(loop)]) for i in range(len(loop))}
    assert walked == want


@pytest.mark.parametrize("n", [1, 3, 8])
def test_grid_box_has_six_faces_whose_loops_are_the_edges_between_them(n):
    v, t = grid_box(n)
    assert core.mesh_check(v, t, require_closed=True).volume == pytest.approx(30.0)
    group, normals = planar.planar_groups(v, t)
    assert len(normals) == 6 and len(group) == len(t)
    np.testing.assert_allclose(np.sort(np.abs(normals).max(axis=1)), 1.0)
    # each face's triangles in one group whose normal is the face's
    tri_n = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
    tri_n /= np.linalg.norm(tri_n, axis=1)[:, None]
    np.testing.assert_allclose(normals[group], tri_n, atol=1e-12)
    loops = planar.group_loops(v, t, group, normals)
    check_loops(v, t, group, normals, loops)
    assert all(len(b) == 1 and len(b[0]) == 4 * n for b in loops)


def test_frame_top_and_bottom_are_faces_with_a_hole():
    v, t = frame_mesh()
    rep = core.mesh_check(v, t, require_closed=True)
    assert rep.volume == pytest.approx(12.0)
    group, normals = planar.planar_groups(v, t)
    assert len(normals) == 10
    loops = planar.group_loops(v, t, group, normals)
    check_loops(v, t, group, normals, loops)
    holed = [g for g, b in enumerate(loops) if len(b) == 2]
    assert sorted(round(float(normals[g][2])) for g in holed) == [-1, 1]


def test_sliver_closing_a_t_junction_joins_the_face_across_its_longest_edge():
    """A unit cube whose top is split at the midpoint m of its front edge: the front
    face keeps its edge a-b whole, and a zero-area triangle (a, b, m) closes the gap."""
    v, t = box_mesh((0, 0, 0), (1, 1, 1))
    v = np.vstack([v, [0.5, 0.0, 1.0]])
    m = len(v) - 1
    top = [k for k, tr in enumerate(t.tolist()) if all(v[i][2] == 1.0 for i in tr)]
    # the top's front edge (y = 0, z = 1), in the direction the top triangles run it
    edge = None
    for k in top:
        tr = t[k].tolist()
        for j in range(3):
            a, b = tr[j], tr[(j + 1) % 3]
            if v[a][1] == 0.0 and v[b][1] == 0.0:
                edge, owner = (a, b), k
    a, b = edge
    tr = t[owner].tolist()
    c = [x for x in tr if x not in edge][0]
    t = np.array([row for k, row in enumerate(t.tolist()) if k != owner]
                 + [[a, m, c], [m, b, c], [b, m, a]])
    rep = core.mesh_check(v, t, require_closed=True)
    assert rep.volume == pytest.approx(1.0)
    group, normals = planar.planar_groups(v, t)
    assert len(normals) == 6
    loops = planar.group_loops(v, t, group, normals)
    check_loops(v, t, group, normals, loops)
    # the sliver went to the front face (its longest edge a-b), whose loop now runs
    # through m like the top's
    front = group[len(t) - 1]
    assert normals[front] @ np.array([0.0, -1.0, 0.0]) == pytest.approx(1.0)
    assert m in loops[front][0] and len(loops[front][0]) == 5


def test_a_curved_mesh_keeps_every_triangle_its_own_face():
    v, t = torus_mesh(5.0, 1.5, 24, 12)
    group, normals = planar.planar_groups(v, t)
    # the torus's quads are planar (two triangles each) where both rings are circles
    # of the same step: at most pairs merge, never more
    sizes = np.bincount(group)
    assert sizes.max() <= 2 and len(normals) >= len(t) // 2
    check_loops(v, t, group, normals, planar.group_loops(v, t, group, normals))


def test_a_rotated_cube_has_six_faces_and_no_drift_across_a_near_plane():
    v, t = grid_box(4, (1.0, 1.0, 1.0))
    q, _ = np.linalg.qr(RNG.normal(size=(3, 3)))
    v = v @ q.T * 1e3 + 5e3
    group, normals = planar.planar_groups(v, t)
    assert len(normals) == 6
    # bend the cube's top by far less than a degree, but far more than the planarity
    # distance: the grid's rows are no longer coplanar
    v2, t2 = grid_box(4, (1.0, 1.0, 1.0))
    bend = (v2[:, 2] == 1.0) & (v2[:, 0] > 0.0) & (v2[:, 0] < 1.0)
    v2[bend, 2] += 1e-6 * np.sin(math.pi * v2[bend, 0])
    group, normals = planar.planar_groups(v2, t2)
    assert len(normals) > 6
    check_loops(v2, t2, group, normals, planar.group_loops(v2, t2, group, normals))
