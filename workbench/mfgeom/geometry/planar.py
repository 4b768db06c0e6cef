# SPDX-License-Identifier: LGPL-2.1-or-later
"""The planar faces of a closed triangle mesh, FreeCAD-free (numpy, tested by pytest): the
edge-connected groups of coplanar triangles and the boundary loops of each group, from
which mfgeom.app.mesh_shapes builds B-rep faces that share their edges (the Solid
representation of the sweep, the sweep's faces near an obstacle in the clearance check).

Why groups: the sweep's result has large planar regions (the input's planar faces, and
the planar quads of its surfaces of revolution): 139 k triangles of a swept motor part
make 18 k planar faces, and OCCT's cost grows with the faces.
"""

from typing import List, Tuple

import numpy as np
from numpy.typing import ArrayLike

# Default planarity distance, relative to the largest coordinate: far above rounding,
# far below any tolerance the sweep is run at.
PLANE_RELATIVE = 1e-9


def label_components(n: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Component labels (0 .. k-1) of n nodes joined by the pairs (a[i], b[i]): a
    union-find with path halving (numpy's ufunc.at propagation took seconds on the
    long strips of a sweep's planar faces)."""
    parent = list(range(n))

    def root(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x
    for x, y in zip(a.tolist(), b.tolist()):
        rx, ry = root(x), root(y)
        if rx != ry:
            if rx < ry:
                parent[ry] = rx
            else:
                parent[rx] = ry
    roots = np.array([root(x) for x in range(n)], dtype=np.int64)
    _, compact = np.unique(roots, return_inverse=True)
    return compact.reshape(-1)


def edge_pairs(triangles: ArrayLike) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For a closed, manifold, consistently oriented mesh: (owner, twin, corner) of each
    directed edge k = 3 t + j (from corner j to corner j + 1 of triangle t): ``twin[k]``
    is the directed edge running the other way (-1 on a boundary).  ``corner`` is j."""
    tri = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    t = len(tri)
    start = tri.reshape(-1)
    end = tri[:, [1, 2, 0]].reshape(-1)
    n = int(tri.max()) + 1 if t else 0
    key = start * n + end
    back = end * n + start
    order = np.argsort(key, kind="stable")
    pos = np.searchsorted(key[order], back)
    pos = np.minimum(pos, max(len(key) - 1, 0))
    found = key[order][pos] == back if len(key) else np.zeros(0, bool)
    twin = np.where(found, order[pos], -1)
    return np.repeat(np.arange(t), 3), twin, np.tile(np.arange(3), t)


def planar_groups(vertices: ArrayLike, triangles: ArrayLike, eps: float = None
                  ) -> Tuple[np.ndarray, np.ndarray]:
    """(group (t,) int, normals (g, 3)): the mesh's triangles gathered into edge-connected
    groups of coplanar ones, with each group's unit normal (outward for an outward
    mesh).

    Two neighbours join when their normals agree and each one's far corner lies within
    ``eps`` (default PLANE_RELATIVE times the largest coordinate) of the other's plane;
    a group whose corners then stray more than 4 ``eps`` from its mean plane (slow
    curvature chained along many neighbours) is split back into single triangles.  A
    sliver (height below ``eps``: its normal means nothing) joins the group across its
    longest edge, where its corners lie within ``eps`` of that plane."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    tri = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    t = len(tri)
    if t == 0:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 3))
    if eps is None:
        eps = PLANE_RELATIVE * max(float(np.abs(v).max()), np.finfo(float).tiny)
    p = v[tri]                                          # (t, 3, 3)
    cross = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    double_area = np.linalg.norm(cross, axis=1)
    edge_len = np.linalg.norm(p[:, [1, 2, 0]] - p, axis=2)          # edge j: corner j -> j+1
    longest = edge_len.argmax(axis=1)
    height = double_area / np.maximum(edge_len.max(axis=1), np.finfo(float).tiny)
    sliver = height < eps
    normal = np.zeros_like(cross)
    normal[~sliver] = cross[~sliver] / double_area[~sliver, None]
    owner, twin, corner = edge_pairs(tri)
    k = np.flatnonzero(twin > np.arange(3 * t))          # each shared edge once
    a, b = owner[k], owner[twin[k]]
    ok = ~sliver[a] & ~sliver[b] & (np.einsum("ij,ij->i", normal[a], normal[b]) > 0.0)
    # the corner of each triangle opposite the shared edge: (corner + 2) % 3
    far_a = v[tri[a, (corner[k] + 2) % 3]]
    far_b = v[tri[b, (corner[twin[k]] + 2) % 3]]
    off_b = np.abs(np.einsum("ij,ij->i", far_b - p[a, 0], normal[a]))
    off_a = np.abs(np.einsum("ij,ij->i", far_a - p[b, 0], normal[b]))
    ok &= (off_a <= eps) & (off_b <= eps)
    group = label_components(t, a[ok], b[ok])
    # slivers: the group across the longest edge, repeatedly (a sliver beside a sliver)
    pending = np.flatnonzero(sliver)
    for _ in range(8):
        if not len(pending):
            break
        across = twin[3 * pending + longest[pending]]
        neighbour = np.where(across >= 0, owner[np.maximum(across, 0)], -1)
        take = (neighbour >= 0) & ~sliver[np.maximum(neighbour, 0)]
        group[pending[take]] = group[neighbour[take]]
        sliver[pending[take]] = False
        pending = pending[~take]
    # the groups' planes: area-weighted normals through the area-weighted centroid
    ng = int(group.max()) + 1
    weight = np.where(sliver, 0.0, double_area)
    acc = np.zeros((ng, 3))
    np.add.at(acc, group, cross * (~sliver)[:, None])
    length = np.linalg.norm(acc, axis=1)
    centre = np.zeros((ng, 3))
    np.add.at(centre, group, p.mean(axis=1) * weight[:, None])
    total = np.zeros(ng)
    np.add.at(total, group, weight)
    good = (length > 0) & (total > 0)
    unit = np.where(good[:, None], acc / np.where(length > 0, length, 1.0)[:, None], 0.0)
    centre = np.where(good[:, None], centre / np.where(total > 0, total, 1.0)[:, None], 0.0)
    stray = np.abs(np.einsum("tij,tj->ti", p - centre[group][:, None, :], unit[group])).max(axis=1)
    bad = ~good[group] | (stray > 4.0 * eps)
    bad_groups = np.unique(group[bad])
    if len(bad_groups):
        split = np.isin(group, bad_groups)
        group = group.copy()
        group[split] = ng + np.arange(int(split.sum()))
        _, group = np.unique(group, return_inverse=True)
        group = group.reshape(-1)
        ng = int(group.max()) + 1
        acc = np.zeros((ng, 3))
        np.add.at(acc, group, cross)
        length = np.linalg.norm(acc, axis=1)
        unit = acc / np.where(length > 0, length, 1.0)[:, None]
    return group, unit


def group_loops(vertices: ArrayLike, triangles: ArrayLike, group: np.ndarray,
                normals: np.ndarray) -> List[List[List[int]]]:
    """For each group of :func:`planar_groups`, its boundary loops as vertex index lists:
    the outer loop first (counter-clockwise about the group's normal), then its holes
    (clockwise).  A boundary edge of a group is a directed edge of its triangles whose
    twin belongs to another group, so neighbouring groups' loops run along the same
    mesh edges in opposite directions.  Where a loop meets itself at a vertex, the walk
    turns most to the left (the region stays on its left), giving simple loops.  A group
    with no or several outer loops gets [] (the caller makes one face per triangle)."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    tri = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    owner, twin, corner = edge_pairs(tri)
    start = tri.reshape(-1)
    end = tri[:, [1, 2, 0]].reshape(-1)
    on_boundary = (twin < 0) | (group[owner] != group[owner[np.maximum(twin, 0)]])
    k = np.flatnonzero(on_boundary)
    ng = len(normals)
    loops: List[List[List[int]]] = [[] for _ in range(ng)]
    order = k[np.lexsort((start[k], group[owner[k]]))]
    g_of = group[owner[order]]
    bounds = np.flatnonzero(np.diff(np.concatenate([[-1], g_of, [ng]])))
    starts_list, ends_list = start.tolist(), end.tolist()
    for gi in range(len(bounds) - 1):
        lo, hi = bounds[gi], bounds[gi + 1]
        if lo >= hi:
            continue
        g = int(g_of[lo])
        outgoing = {}
        for e in order[lo:hi].tolist():
            outgoing.setdefault(starts_list[e], []).append(ends_list[e])
        loops[g] = _walk(outgoing, v, normals[g])
    return loops


def _walk(outgoing, v, normal):
    """Closed loops from the directed boundary edges ``outgoing`` (vertex -> [next
    vertices]) of one group, outer first; [] when the loops do not make one outer loop
    and holes."""
    found = []
    limit = sum(len(n) for n in outgoing.values())
    while outgoing:
        first = next(iter(outgoing))
        loop, prev, here = [first], None, first
        while True:
            nexts = outgoing.get(here)
            if not nexts or len(loop) > limit:
                return []                      # an open chain: not a closed boundary
            nxt = nexts[0] if len(nexts) == 1 or prev is None else \
                _leftmost(prev, here, nexts, v, normal)
            nexts.remove(nxt)
            if not nexts:
                del outgoing[here]
            if nxt == first:
                break
            loop.append(nxt)
            prev, here = here, nxt
        found.append(loop)
    areas = [float(normal @ _newell(v[loop])) for loop in found]
    outer = [i for i, a in enumerate(areas) if a > 0]
    if len(outer) != 1:
        return []
    return [found[outer[0]]] + [f for i, f in enumerate(found) if i != outer[0]]


def _newell(points):
    """Twice the vector area of the closed polygon ``points`` (k, 3)."""
    return np.cross(points, np.roll(points, -1, axis=0)).sum(axis=0) * 0.5


def _leftmost(prev, here, nexts, v, normal):
    """Of the edges leaving ``here``, the one turning most to the left after arriving
    from ``prev`` (seen from the tip of ``normal``): the smallest clockwise angle from
    the way back."""
    back = v[prev] - v[here]
    best, best_angle = nexts[0], None
    for cand in nexts:
        out = v[cand] - v[here]
        # clockwise angle from back to out about normal, in [0, 2 pi)
        angle = -np.arctan2(float(normal @ np.cross(back, out)), float(back @ out))
        if angle <= 0.0:
            angle += 2.0 * np.pi
        if best_angle is None or angle < best_angle:
            best, best_angle = cand, angle
    return best
