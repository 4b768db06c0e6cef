# SPDX-License-Identifier: LGPL-2.1-or-later
"""The second sweep design's envelope, as a numpy reference (issue 20; tests only, no code
shared with libmfgeom).  docs/design/sweep.md "Second design" gives the argument; this
module builds the objects it talks about so that tests can check the claims against the
independent membership oracle (sweep_oracle.inside_swept).

Frame: the axis is the z axis through the origin (callers move the mesh there first), the
solid O turns counter-clockwise by t in [0, theta]; tau(p) = z x p is the velocity.

The envelope soup E' is a set of oriented triangles:
  * F: the parts of O's boundary where the outward normal n has n . tau <= 0 (where a
    circle about the axis enters O: an arc starts), at t = 0;
  * B: the parts with n . tau >= 0, turned by theta.  A triangle whose n . tau changes
    sign is split along the line n . tau(p) = 0 (n . tau is linear in p); a face
    perpendicular to the axis (n . tau = 0 everywhere) counts as F;
  * strips: the contour C = the oriented boundary of the F region, cut into pieces no
    longer than `piece_length`, each piece p->q turned step by step: the quads
    (R_i q, R_i p, R_{i+1} p, R_{i+1} q), t_i = i theta / N, as two triangles.  F + R(theta)B
    + strips is a closed chain (the strips' side edges cancel between neighbouring pieces,
    their ends are -C at t = 0 and R(theta)C at theta), so its winding number w is an
    integer, and w(x) = the number of O's arcs [a, b] on x's circle with x in [a, b + theta]:
    SV = {w >= 1} up to the strips being chords of the true surfaces of revolution;
  * hulls: for each piece and step, conv{R_i p, R_i q, R_{i+1} p, R_{i+1} q, M p, M q} with
    M = the turn by t_i + delta/2 followed by the radial scaling 1 / cos(delta/2): the arc of
    every point of the piece over the step lies in the triangle of its chord and its two
    end tangents, whose apex is M x, so the true swept surface lies in the hull, and so
    does the sliver between it and the chord strip.  A closed convex surface adds 1 to the
    winding inside it and 0 elsewhere, so {w' >= 1} = {w >= 1} u hulls contains SV
    (conservative), and it stays within the hulls' size of the true surface (tight).
The step delta is the largest with r_max (1/cos(delta/2) - 1) <= tol / 2.
"""

import math

import numpy as np

from sweep_oracle import _frame, soup_winding


def turn(points, t):
    """Points (..., 3) turned by t about the z axis."""
    c, s = math.cos(t), math.sin(t)
    p = np.asarray(points, dtype=np.float64)
    return np.stack([c * p[..., 0] - s * p[..., 1], s * p[..., 0] + c * p[..., 1], p[..., 2]], -1)


def to_axis_frame(vertices, axis_point, axis_dir):
    """Vertices in a right-handed frame whose z axis is the rotation axis."""
    return (np.asarray(vertices, dtype=np.float64) - np.asarray(axis_point, dtype=np.float64)) @ \
        _frame(axis_dir).T


def _speed(p, n):
    """n . tau(p) with tau(p) = z x p = (-y, x, 0)."""
    return n[1] * p[0] - n[0] * p[1]


def split_faces(v, tris):
    """F and B polygons (lists of point ids into the returned points array) and, per mesh
    edge, the points where a neighbouring triangle's contour line meets it."""
    ids, pts, fpolys, bpolys, on_edge = {}, [], [], [], {}

    def pid(key, p):
        if key not in ids:
            ids[key] = len(pts)
            pts.append(np.asarray(p, dtype=np.float64))
        return ids[key]

    for ti, t in enumerate(tris):
        corner = [v[i] for i in t]
        n = np.cross(corner[1] - corner[0], corner[2] - corner[0])
        g = [_speed(p, n) for p in corner]
        scale = np.linalg.norm(n) * (1.0 + np.abs(np.asarray(corner)).max())
        if all(abs(x) <= 1e-14 * scale for x in g):
            g = [-1.0, -1.0, -1.0]              # perpendicular to the axis: an F face
        f_poly, b_poly = [], []
        for k in range(3):
            a, b = k, (k + 1) % 3
            here = pid(("v", int(t[a])), corner[a])
            if g[a] <= 0:
                f_poly.append(here)
            if g[a] >= 0:
                b_poly.append(here)
            if (g[a] < 0 < g[b]) or (g[b] < 0 < g[a]):
                i0, i1 = sorted((int(t[a]), int(t[b])))
                s = _speed(v[i0], n) / (_speed(v[i0], n) - _speed(v[i1], n))
                m = pid(("s", ti, i0, i1), v[i0] + s * (v[i1] - v[i0]))
                on_edge.setdefault((i0, i1), []).append((s, m))
                f_poly.append(m)
                b_poly.append(m)
        if len(f_poly) >= 3:
            fpolys.append(f_poly)
        if len(b_poly) >= 3:
            bpolys.append(b_poly)
    vertex_of = {i: key[1] for key, i in ids.items() if key[0] == "v"}
    return np.array(pts), fpolys, bpolys, on_edge, vertex_of


def contour(fpolys, on_edge, vertex_of):
    """The oriented boundary of the F region: its edges, each split at the points where
    the neighbouring triangle's contour line meets a shared mesh edge."""
    count = {}
    for poly in fpolys:
        for k in range(len(poly)):
            a, b = poly[k], poly[(k + 1) % len(poly)]
            seq = [a, b]
            if a in vertex_of and b in vertex_of:
                i0, i1 = sorted((vertex_of[a], vertex_of[b]))
                mids = [m for _, m in sorted(on_edge.get((i0, i1), []))]
                seq = [a] + (mids if vertex_of[a] == i0 else mids[::-1]) + [b]
            for x, y in zip(seq, seq[1:]):
                if count.get((y, x), 0) > 0:
                    count[(y, x)] -= 1
                else:
                    count[(x, y)] = count.get((x, y), 0) + 1
    return [e for e, c in count.items() for _ in range(c)]


def angular_step(r_max, theta, tol):
    """N steps of delta = theta / N, the fewest with r_max (1/cos(delta/2) - 1) <= tol/2."""
    delta = 2.0 * math.acos(1.0 / (1.0 + tol / (2.0 * max(r_max, 1e-300))))
    n = max(1, math.ceil(theta / delta))
    return n, theta / n


def envelope(v, tris, theta, tol, hulls=True, piece_length=None):
    """(soup triangles (K, 3, 3), hull point sets [(6, 3)], steps N, contour edges).
    v in the axis frame (see to_axis_frame)."""
    v = np.asarray(v, dtype=np.float64)
    pts, fpolys, bpolys, on_edge, vertex_of = split_faces(v, np.asarray(tris))
    edges = contour(fpolys, on_edge, vertex_of)
    r_max = float(np.max(np.hypot(pts[:, 0], pts[:, 1])))
    n, delta = angular_step(r_max, theta, tol)
    if piece_length is None:
        # a piece skew to the axis sweeps a twisted (hyperboloid) strip; between two steps
        # it leaves its plane by up to ~ length * delta / 4: keep that within tol / 2
        piece_length = 2.0 * tol / delta
    soup = []
    for poly in fpolys:
        soup += [[pts[poly[0]], pts[poly[k]], pts[poly[k + 1]]] for k in range(1, len(poly) - 1)]
    for poly in bpolys:
        q = turn(pts[poly], theta)
        soup += [[q[0], q[k], q[k + 1]] for k in range(1, len(poly) - 1)]
    hull_sets = []
    grow = np.array([1.0 / math.cos(delta / 2), 1.0 / math.cos(delta / 2), 1.0])
    for a, b in edges:
        p, q = pts[a], pts[b]
        m = max(1, math.ceil(np.linalg.norm(q - p) / piece_length))
        for j in range(m):
            pj, qj = p + (q - p) * (j / m), p + (q - p) * ((j + 1) / m)
            for i in range(n):
                a0, b0 = turn(pj, i * delta), turn(qj, i * delta)
                a1, b1 = turn(pj, (i + 1) * delta), turn(qj, (i + 1) * delta)
                soup += [[b0, a0, a1], [b0, a1, b1]]
                if hulls:
                    mid = (i + 0.5) * delta
                    hull_sets.append(np.array([a0, b0, a1, b1, turn(pj, mid) * grow,
                                               turn(qj, mid) * grow]))
    return np.array(soup).reshape(-1, 3, 3), hull_sets, n, len(edges)


def in_hull(points, h):
    """Points inside or on conv(h) for a set h of a few points (brute-force facets); a
    flat set (no volume) holds none."""
    x = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    centre = h.mean(axis=0)
    sv = np.linalg.svd(h - centre, compute_uv=False)
    if sv[2] <= 1e-9 * sv[0]:
        return np.zeros(len(x), dtype=bool)
    inside = np.ones(len(x), dtype=bool)
    k = len(h)
    for i in range(k):
        for j in range(i + 1, k):
            for m in range(j + 1, k):
                n = np.cross(h[j] - h[i], h[m] - h[i])
                size = np.linalg.norm(n)
                if size <= 1e-12 * sv[0] ** 2:
                    continue
                d = (h - h[i]) @ n
                slack = 1e-12 * size * sv[0]
                if np.all(d <= slack) or np.all(d >= -slack):
                    side = -1.0 if (centre - h[i]) @ n > 0 else 1.0   # outward = side
                    inside &= side * ((x - h[i]) @ n) <= slack
    return inside


def covered(points, soup, hull_sets):
    """Membership in the envelope's volume {w' >= 1}: winding >= 1 or inside a hull."""
    x = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    out = soup_winding(x, soup) > 0.5
    for h in hull_sets:
        out |= in_hull(x, h)
    return out
