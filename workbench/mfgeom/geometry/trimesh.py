# SPDX-License-Identifier: LGPL-2.1-or-later
"""A closed triangle mesh as the clearance check queries it, FreeCAD-free (numpy, tested
by pytest): the triangles' bounding boxes and their gaps to a box or to many boxes (the
pruning of the exact distance and the choice of the triangles that can meet an
obstacle), and whether points lie inside (the parity of a ray's crossings, cast again
along another direction when it passes too close to an edge to tell)."""

from typing import Optional

import numpy as np
from numpy.typing import ArrayLike

# Rays of :meth:`TriangleMesh.contains`: fixed, generic directions (no two coplanar with
# the axes), so the answer does not depend on chance.
_RAYS = np.array([[0.4723, 0.5917, 0.6534], [-0.6262, 0.3421, 0.7006],
                  [0.2977, -0.8165, 0.4946], [-0.5345, -0.2673, -0.8018],
                  [0.8571, -0.4286, 0.2857], [0.1104, 0.9806, -0.1622]])
_RAYS = _RAYS / np.linalg.norm(_RAYS, axis=1)[:, None]
# Barycentric margin within which a crossing is too close to an edge to count.
_EDGE_MARGIN = 1e-9
# Boxes compared with many others are merged into at most this many groups.
_GROUPS = 256


def box_gaps(boxes: np.ndarray, box: ArrayLike) -> np.ndarray:
    """Euclidean gap between each row of ``boxes`` ((n, 6): min x y z, max x y z) and
    ``box`` (6,): 0 where they meet or overlap."""
    b = np.asarray(box, dtype=np.float64)
    gap = np.maximum(0.0, np.maximum(boxes[:, :3] - b[3:], b[:3] - boxes[:, 3:]))
    return np.sqrt((gap * gap).sum(axis=1))


def _morton_order(points: np.ndarray) -> np.ndarray:
    """An order of ``points`` (n, 3) along a Z-order curve: neighbours in the order are
    near in space, so consecutive runs make tight groups."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    q = ((points - lo) / np.where(hi > lo, hi - lo, 1.0) * 1023).astype(np.int64)
    code = np.zeros(len(points), dtype=np.int64)
    for bit in range(10):
        for axis in range(3):
            code |= ((q[:, axis] >> bit) & 1) << (3 * bit + axis)
    return np.argsort(code, kind="stable")


def grouped_boxes(boxes: np.ndarray, groups: int = _GROUPS) -> np.ndarray:
    """At most ``groups`` boxes, each holding a run of ``boxes`` in Z order: a gap to
    one of them is a lower bound of the gaps to its members."""
    if len(boxes) <= groups:
        return boxes
    order = _morton_order(0.5 * (boxes[:, :3] + boxes[:, 3:]))
    runs = np.array_split(boxes[order], groups)
    return np.array([np.concatenate([r[:, :3].min(axis=0), r[:, 3:].max(axis=0)])
                     for r in runs])


def min_box_gaps(boxes: np.ndarray, others: np.ndarray, chunk: int = 4_000_000
                 ) -> np.ndarray:
    """For each row of ``boxes``, the smallest gap to any row of ``others`` (inf when
    there are none), computed in blocks of at most ``chunk`` pairs."""
    out = np.full(len(boxes), np.inf)
    if not len(others) or not len(boxes):
        return out
    rows = max(1, chunk // len(others))
    for s in range(0, len(boxes), rows):
        a = boxes[s:s + rows, None, :]
        gap = np.maximum(0.0, np.maximum(a[..., :3] - others[None, :, 3:],
                                         others[None, :, :3] - a[..., 3:]))
        out[s:s + rows] = np.sqrt((gap * gap).sum(axis=2)).min(axis=1)
    return out


class TriangleMesh:
    """``vertices`` (n, 3) and ``triangles`` (t, 3) of a closed, outward mesh, with each
    triangle's corners, bounding box (``boxes`` (t, 6)) and the mesh's ``bbox`` (6,),
    ``volume`` and ``area``."""

    def __init__(self, vertices: ArrayLike, triangles: ArrayLike):
        self.vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
        self.triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
        self.corners = self.vertices[self.triangles]                   # (t, 3, 3)
        self.boxes = np.hstack([self.corners.min(axis=1), self.corners.max(axis=1)])
        self.bbox = np.concatenate([self.vertices.min(axis=0), self.vertices.max(axis=0)])
        p0, p1, p2 = (self.corners[:, k] for k in range(3))
        cross = np.cross(p1 - p0, p2 - p0)
        self.volume = float(np.einsum("ij,ij->", p0, cross)) / 6.0
        self.area = 0.5 * float(np.linalg.norm(cross, axis=1).sum())
        self.scale = max(float(np.abs(self.vertices).max()), np.finfo(float).tiny)

    def gaps(self, box: ArrayLike) -> np.ndarray:
        """Each triangle's box gap to ``box`` (6,)."""
        return box_gaps(self.boxes, box)

    def near(self, box: ArrayLike, margin: float) -> np.ndarray:
        """Indices of the triangles whose boxes come within ``margin`` of ``box``."""
        return np.flatnonzero(self.gaps(box) <= margin)

    def lower_bounds(self, indices: np.ndarray, others: np.ndarray) -> np.ndarray:
        """For the triangles ``indices``: a lower bound of their distance to anything
        inside the boxes ``others`` ((m, 6)), the least gap to those boxes (grouped
        into at most _GROUPS boxes first)."""
        return min_box_gaps(self.boxes[indices], grouped_boxes(others))

    def _crossings(self, point: np.ndarray, ray: np.ndarray) -> Optional[int]:
        """How many triangles the ray point + s ray (s > 0) crosses, or None when it
        passes within _EDGE_MARGIN of a triangle's edge or the point lies on one
        (the count would not be trustworthy)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / ray
            t1 = (self.boxes[:, :3] - point) * inv
            t2 = (self.boxes[:, 3:] - point) * inv
        enter = np.minimum(t1, t2).max(axis=1)
        leave = np.maximum(t1, t2).min(axis=1)
        cand = np.flatnonzero(leave >= np.maximum(enter, 0.0))
        if not len(cand):
            return 0
        c = self.corners[cand]
        e1, e2 = c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]
        h = np.cross(ray, e2)
        det = np.einsum("ij,ij->i", e1, h)
        size = np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1)
        flat = np.abs(det) <= 1e-12 * size          # the ray runs along the plane
        det = np.where(flat, 1.0, det)
        sv = point - c[:, 0]
        u = np.einsum("ij,ij->i", sv, h) / det
        q = np.cross(sv, e1)
        v = (q @ ray) / det
        s = np.einsum("ij,ij->i", e2, q) / det
        w = 1.0 - u - v
        eps_s = 1e-12 * self.scale
        inside = (u > _EDGE_MARGIN) & (v > _EDGE_MARGIN) & (w > _EDGE_MARGIN)
        close = (u > -_EDGE_MARGIN) & (v > -_EDGE_MARGIN) & (w > -_EDGE_MARGIN)
        if (~flat & close & ~inside & (s > -eps_s)).any():
            return None                               # through an edge or a corner
        if (~flat & close & (np.abs(s) <= eps_s)).any():
            return None                               # the point is on the surface
        if flat.any():
            # a triangle in the ray's plane: harmless unless the point is in that plane
            n = np.cross(e1[flat], e2[flat])
            dist = np.abs(np.einsum("ij,ij->i", sv[flat], n)) / np.maximum(
                np.linalg.norm(n, axis=1), np.finfo(float).tiny)
            if (dist <= eps_s).any():
                return None
        return int(np.count_nonzero(~flat & inside & (s > eps_s)))

    def contains(self, points: ArrayLike) -> np.ndarray:
        """Whether each point (m, 3) lies inside the closed mesh: an odd number of
        crossings along a ray, cast along the next of _RAYS while a ray grazes an edge.
        A point on the surface (every ray grazes) counts as inside."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        out = np.zeros(len(pts), dtype=bool)
        for i, p in enumerate(pts):
            for ray in _RAYS:
                n = self._crossings(p, ray)
                if n is not None:
                    out[i] = bool(n & 1)
                    break
            else:
                out[i] = True
        return out


# --------------------------------------------------------------------------- distances
def _dot(a, b):
    return np.einsum("ij,ij->i", a, b)


def segment_segment(p1, q1, p2, q2):
    """(distance, closest point on p1-q1, closest point on p2-q2) of the segment pairs
    ((n, 3) arrays each), as in Ericson, Real-Time Collision Detection, 5.1.9."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e, f = _dot(d1, d1), _dot(d2, d2), _dot(d2, r)
    c, b = _dot(d1, r), _dot(d1, d2)
    tiny = np.finfo(float).tiny
    denom = a * e - b * b
    s = np.where(denom > 1e-14 * np.maximum(a * e, tiny),
                 np.clip((b * f - c * e) / np.where(denom > 0, denom, 1.0), 0.0, 1.0), 0.0)
    t = np.where(e > tiny, (b * s + f) / np.where(e > tiny, e, 1.0), 0.0)
    s = np.where(t < 0.0, np.clip(-c / np.where(a > tiny, a, 1.0), 0.0, 1.0),
                 np.where(t > 1.0, np.clip((b - c) / np.where(a > tiny, a, 1.0), 0.0, 1.0), s))
    s = np.where(a > tiny, s, 0.0)
    t = np.clip(t, 0.0, 1.0)
    c1, c2 = p1 + d1 * s[:, None], p2 + d2 * t[:, None]
    return np.linalg.norm(c1 - c2, axis=1), c1, c2


def point_triangle(p, a, b, c):
    """(distance, closest point) from the points p to the triangles abc ((n, 3) arrays
    each): the triangle's interior when p projects into it, else its nearest edge."""
    n = np.cross(b - a, c - a)
    nn = _dot(n, n)
    ok = nn > 0.0
    s = _dot(p - a, n) / np.where(ok, nn, 1.0)
    q = p - s[:, None] * n
    inside = ok.copy()
    for u, w in ((a, b), (b, c), (c, a)):
        inside &= _dot(np.cross(w - u, q - u), n) >= 0.0
    best = np.where(inside, np.abs(s) * np.sqrt(np.where(ok, nn, 0.0)), np.inf)
    point = np.where(inside[:, None], q, p)
    for u, w in ((a, b), (b, c), (c, a)):
        e = w - u
        ee = _dot(e, e)
        k = np.clip(_dot(p - u, e) / np.where(ee > 0, ee, 1.0), 0.0, 1.0)
        x = u + k[:, None] * e
        d = np.linalg.norm(p - x, axis=1)
        better = d < best
        best = np.where(better, d, best)
        point = np.where(better[:, None], x, point)
    return best, point


def _segments_cross_triangles(p, q, a, b, c):
    """(whether the segments pq cross or touch the triangles abc, where)."""
    d = q - p
    e1, e2 = b - a, c - a
    h = np.cross(d, e2)
    det = _dot(e1, h)
    ok = np.abs(det) > 1e-300
    inv = 1.0 / np.where(ok, det, 1.0)
    sv = p - a
    u = _dot(sv, h) * inv
    qv = np.cross(sv, e1)
    v = _dot(d, qv) * inv
    t = _dot(e2, qv) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0) & (t <= 1)
    return hit, p + t[:, None] * d


def triangle_triangle(A, B):
    """(distance, point on A, point on B) of the triangle pairs A, B ((n, 3, 3) each):
    0 where they meet; else the least of the nine edge pairs and the six corners to
    the other triangle (where the minimum of two disjoint triangles lies)."""
    n = len(A)
    best = np.full(n, np.inf)
    pa, pb = np.zeros((n, 3)), np.zeros((n, 3))

    def take(d, x, y):
        nonlocal best, pa, pb
        better = d < best
        best = np.where(better, d, best)
        pa = np.where(better[:, None], x, pa)
        pb = np.where(better[:, None], y, pb)
    for i in range(3):
        for j in range(3):
            d, x, y = segment_segment(A[:, i], A[:, (i + 1) % 3], B[:, j], B[:, (j + 1) % 3])
            take(d, x, y)
    for i in range(3):
        d, y = point_triangle(A[:, i], B[:, 0], B[:, 1], B[:, 2])
        take(d, A[:, i], y)
        d, x = point_triangle(B[:, i], A[:, 0], A[:, 1], A[:, 2])
        take(d, x, B[:, i])
    for i in range(3):
        for (p, q), (a, b, c) in (((A[:, i], A[:, (i + 1) % 3]), (B[:, 0], B[:, 1], B[:, 2])),
                                  ((B[:, i], B[:, (i + 1) % 3]), (A[:, 0], A[:, 1], A[:, 2]))):
            hit, x = _segments_cross_triangles(p, q, a, b, c)
            take(np.where(hit, 0.0, np.inf), x, x)
    return best, pa, pb


def mesh_distances(corners, other, limit, chunk=200_000):
    """For each triangle of ``corners`` ((n, 3, 3)): (its distance to the nearest
    triangle of ``other`` ((m, 3, 3)), the closest point on it, the closest point on
    that other triangle) when the distance is at most ``limit``, else (inf, nan, nan).
    The pairs whose boxes are farther apart than ``limit`` are never computed (the
    other side is grouped in Z-order runs of 16 first)."""
    n = len(corners)
    out = np.full(n, np.inf)
    pa, pb = np.full((n, 3), np.nan), np.full((n, 3), np.nan)
    if not n or not len(other):
        return out, pa, pb
    boxes = np.hstack([corners.min(axis=1), corners.max(axis=1)])
    oboxes = np.hstack([other.min(axis=1), other.max(axis=1)])
    order = _morton_order(0.5 * (oboxes[:, :3] + oboxes[:, 3:]))
    runs = np.array_split(order, max(1, len(order) // 16))
    gboxes = np.array([np.concatenate([oboxes[r, :3].min(axis=0), oboxes[r, 3:].max(axis=0)])
                       for r in runs])
    lim2 = limit * limit if np.isfinite(limit) else np.inf
    ti, gi = [], []
    rows = max(1, 4_000_000 // len(gboxes))
    for s in range(0, n, rows):
        a = boxes[s:s + rows, None, :]
        gap = np.maximum(0.0, np.maximum(a[..., :3] - gboxes[None, :, 3:],
                                         gboxes[None, :, :3] - a[..., 3:]))
        i, j = np.nonzero((gap * gap).sum(axis=2) <= lim2)
        ti.append(i + s)
        gi.append(j)
    ti, gi = np.concatenate(ti), np.concatenate(gi)
    if not len(ti):
        return out, pa, pb
    sizes = np.array([len(r) for r in runs])
    members = np.concatenate(runs)
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    count = sizes[gi]
    pt = np.repeat(ti, count)
    po = members[np.repeat(starts[gi], count) + (np.arange(count.sum())
                                                 - np.repeat(np.cumsum(count) - count, count))]
    pair_gap = np.maximum(0.0, np.maximum(boxes[pt, :3] - oboxes[po, 3:],
                                          oboxes[po, :3] - boxes[pt, 3:]))
    keep = (pair_gap * pair_gap).sum(axis=1) <= lim2
    pt, po = pt[keep], po[keep]
    for s in range(0, len(pt), chunk):
        t_, o_ = pt[s:s + chunk], po[s:s + chunk]
        d, x, y = triangle_triangle(corners[t_], other[o_])
        # the least per triangle in this chunk: sort by (triangle, distance)
        rank = np.lexsort((d, t_))
        first = rank[np.concatenate([[True], t_[rank][1:] != t_[rank][:-1]])]
        tt, dd = t_[first], d[first]
        better = (dd < out[tt]) & (dd <= limit)
        tt, first = tt[better], first[better]
        out[tt], pa[tt], pb[tt] = d[first], x[first], y[first]
    return out, pa, pb
