# SPDX-License-Identifier: LGPL-2.1-or-later
"""Triangle-mesh geometry the features need, FreeCAD-free (numpy only, tested by pytest):
the merge of nearly coincident vertices and the conservative offset of a curved solid's
tessellation (rotational sweep), a mesh's area and boundary loops, and the
straightening of a sampled polygon (mid-surface)."""

from typing import List, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

# A vertex is never pushed further than this many deflections (see conservative_offset).
MAX_OFFSET_FACTOR = 10.0
# merge_near_vertices' default distance, relative to the largest coordinate: far above
# the few ulps by which OCCT's per-face nodes of one edge differ, far below any spacing
# a tessellation makes.
NEAR_RELATIVE = 1e-11


def merge_near_vertices(vertices: ArrayLike, triangles: ArrayLike,
                        eps: Optional[float] = None
                        ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(vertices, triangles, kept) with the vertices closer than ``eps`` merged into one
    (the lowest index of each cluster) and the triangles that lost a corner dropped
    (``kept``: which input triangles remain, for data per triangle).

    Why: OCCT meshes an edge shared by two faces once, but each face's triangulation
    carries its own copy of the nodes, moved by the face's location; on real parts (the
    motor of tests/corpus: 12 of its 17 solids) copies of one node differ by an ulp or
    two, so an exact weld leaves the solid's mesh open along those edges and the sweep
    refuses it.  ``eps`` (default NEAR_RELATIVE times the largest coordinate): two
    vertices within ``eps`` are always merged, none farther apart than 4 sqrt(3) eps
    per link.  Eight passes over a grid of cell 4 eps, each shifted by half a cell along
    some of the axes: two points within eps = a quarter cell share a cell in at least
    one of them; the clusters are closed transitively."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    tri = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    n = len(v)
    if n == 0:
        return v.copy(), tri.copy(), np.ones(len(tri), dtype=bool)
    if eps is None:
        eps = NEAR_RELATIVE * max(float(np.abs(v).max()), np.finfo(float).tiny)
    cell = 4.0 * eps
    label = np.arange(n)
    changed = True
    while changed:
        changed = False
        for shift in range(8):
            offset = np.array([(shift >> k) & 1 for k in range(3)]) * (cell / 2.0)
            _, group = np.unique(np.floor((v + offset) / cell).astype(np.int64), axis=0,
                                 return_inverse=True)
            group = group.reshape(-1)
            low = np.full(int(group.max()) + 1, n)
            np.minimum.at(low, group, label)
            new = np.minimum(label, low[group])
            while True:   # follow each label to its cluster's lowest index
                deeper = new[new]
                if (deeper == new).all():
                    break
                new = deeper
            if (new != label).any():
                label, changed = new, True
    if (label == np.arange(n)).all():
        return v.copy(), tri.copy(), np.ones(len(tri), dtype=bool)
    roots, index = np.unique(label, return_inverse=True)
    out = index.reshape(-1)[tri]
    whole = (out[:, 0] != out[:, 1]) & (out[:, 1] != out[:, 2]) & (out[:, 2] != out[:, 0])
    return v[roots], out[whole], whole


def conservative_offset(vertices: ArrayLike, triangles: ArrayLike, curved: ArrayLike,
                        deflection: float) -> Tuple[np.ndarray, float]:
    """The mesh ``vertices`` moved so the tessellation of a curved solid holds the true
    solid: returns (new vertices (n, 3), largest displacement).

    Why: OCCT's tessellation of a curved face lies within ``deflection`` of the face, and
    on convex parts (a cylinder's side, a fillet) its chords cut *inside* the material, so
    the swept volume of the mesh would miss up to ``deflection`` of the true one.  Every
    vertex of a curved (``curved[t]`` true) triangle is pushed outward along its
    angle-weighted normal N (weights: the triangle's corner angle at the vertex; curved
    triangles only) by ``deflection / min(N . n_t)`` over its curved triangles t, so each
    of its curved triangles' corners, hence the whole moved triangle, lies at least
    ``deflection`` beyond that triangle's old plane: the true surface, within
    ``deflection`` of the old triangle, is inside.  A vertex also on planar faces (a
    cylinder's rim) keeps to their planes: N is projected onto the plane (one plane) or
    onto the line of two planes; on three or more planes it stays.  So planar faces stay
    exact and only curved parts grow, by at most ``MAX_OFFSET_FACTOR * deflection``
    (when N . n_t is small, the cap applies: a very sharp curved crease is then not fully
    covered).  On concave parts (a hole) the chords already lie outside the material;
    pushing them further only adds up to ``deflection`` there.
    """
    v = np.asarray(vertices, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.int64)
    curved = np.asarray(curved, dtype=bool)
    out = v.copy()
    if deflection <= 0.0 or not curved.any() or not len(tri):
        return out, 0.0
    p0, p1, p2 = v[tri[:, 0]], v[tri[:, 1]], v[tri[:, 2]]
    normals = np.cross(p1 - p0, p2 - p0)
    lengths = np.linalg.norm(normals, axis=1)
    good = lengths > 0.0
    normals[good] /= lengths[good, None]

    def corner_angle(a, b, c):
        u, w = b - a, c - a
        return np.arctan2(np.linalg.norm(np.cross(u, w), axis=1), np.einsum("ij,ij->i", u, w))
    angles = np.stack([corner_angle(p0, p1, p2), corner_angle(p1, p2, p0),
                       corner_angle(p2, p0, p1)], axis=1)
    n = len(v)
    acc = np.zeros((n, 3))
    is_curved = curved & good
    for k in range(3):
        np.add.at(acc, tri[is_curved, k], normals[is_curved] * angles[is_curved, k, None])
    moved = np.flatnonzero(np.linalg.norm(acc, axis=1) > 0.0)
    # the planes of planar triangles at each moved vertex (distinct normals only)
    planes = {}
    flat = ~curved & good
    for t in np.flatnonzero(flat):
        for k in range(3):
            planes.setdefault(int(tri[t, k]), []).append(normals[t])
    # the curved triangles at each vertex, for min(N . n_t)
    curved_at = {}
    for t in np.flatnonzero(is_curved):
        for k in range(3):
            curved_at.setdefault(int(tri[t, k]), []).append(t)
    largest = 0.0
    for i in moved:
        d = acc[i]
        distinct = []
        for m in planes.get(int(i), []):
            if all(abs(float(m @ q)) < 1.0 - 1e-9 for q in distinct):
                distinct.append(m)
        if len(distinct) == 1:
            d = d - (d @ distinct[0]) * distinct[0]
        elif len(distinct) == 2:
            line = np.cross(distinct[0], distinct[1])
            line /= np.linalg.norm(line)
            d = (d @ line) * line
        elif len(distinct) > 2:
            continue
        norm = np.linalg.norm(d)
        if norm <= 1e-12 * max(1.0, np.linalg.norm(acc[i])):
            continue
        d /= norm
        worst = min(float(normals[t] @ d) for t in curved_at[int(i)])
        step = deflection / max(worst, 1.0 / MAX_OFFSET_FACTOR)
        out[i] = v[i] + step * d
        largest = max(largest, step)
    return out, largest


def mesh_area(pts: np.ndarray, tri: np.ndarray) -> float:
    """The total area of the triangles ``tri`` (t, 3) of the points ``pts`` (n, 3)."""
    return 0.5 * float(np.linalg.norm(np.cross(pts[tri[:, 1]] - pts[tri[:, 0]],
                                               pts[tri[:, 2]] - pts[tri[:, 0]]), axis=1).sum())


def boundary_loops(tri: ArrayLike) -> Optional[List[List[int]]]:
    """The boundary of a triangle mesh as closed loops of vertex indices, each walked in
    the direction its triangles give (so holes run opposite to the outer loop).  A
    boundary edge is a directed edge whose reverse no triangle uses."""
    tri = np.asarray(tri, dtype=np.int64).reshape(-1, 3)
    directed = np.vstack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    n = int(tri.max()) + 1 if len(tri) else 0
    # vectorised: 1.6e5-triangle sheets have ~5e5 directed edges, few on the boundary
    key = directed[:, 0] * n + directed[:, 1]
    reverse = directed[:, 1] * n + directed[:, 0]
    following = {}
    for a, b in directed[~np.isin(reverse, key)].tolist():
        following.setdefault(a, []).append(b)
    loops = []
    while following:
        start = next(iter(following))
        loop, v = [start], start
        while True:
            nxt = following[v].pop()
            if not following[v]:
                del following[v]
            if nxt == start:
                break
            loop.append(nxt)
            v = nxt
            if v not in following:   # an open chain (not a manifold boundary): give up
                return None
        loops.append(loop)
    return loops


def straightened(points: np.ndarray, eps: float,
                 keep: Optional[np.ndarray] = None) -> np.ndarray:
    """The closed polygon ``points`` (k, 3) with the samples along straight runs left
    out: greedily from a surely kept corner (the farthest from the centroid), a run is
    extended while every sample it skips lies within ``eps`` of its chord.  ``keep``
    (k,) bools: points that are never left out (the mid-surface keeps the points a
    neighbouring face shares, or its edge would pass them by)."""
    return points[straightened_indices(points, eps, keep)]


def straightened_indices(points: np.ndarray, eps: float,
                         keep: Optional[np.ndarray] = None) -> np.ndarray:
    """The indices into ``points`` of the corners :func:`straightened` keeps, in order."""
    n = len(points)
    start = int(np.argmax(np.linalg.norm(points - points.mean(axis=0), axis=1)))
    ring = np.roll(points, -start, axis=0)
    ring = np.vstack([ring, ring[:1]])   # closed: the run may end back at the start
    fixed = (np.zeros(n, dtype=bool) if keep is None
             else np.roll(np.asarray(keep, dtype=bool).reshape(-1), -start))
    kept, anchor, j = [0], 0, 1
    while j < n:
        nxt = j + 1
        chord = ring[nxt] - ring[anchor]
        length = np.linalg.norm(chord)
        inner = ring[anchor + 1:nxt]
        if length > 0:
            off = np.linalg.norm(np.cross(inner - ring[anchor], chord), axis=1) / length
        else:
            off = np.linalg.norm(inner - ring[anchor], axis=1)
        if fixed[j] or off.max() > eps:   # ring[j] is a corner
            kept.append(j)
            anchor = j
        j = nxt
    return (np.asarray(kept, dtype=np.int64) + start) % n
