# SPDX-License-Identifier: LGPL-2.1-or-later
"""An independent membership oracle for the rotational swept volume (issue 8, section 2),
for tests only: numpy, no FreeCAD, and no code shared with libmfgeom.

SV = union over t in [0, theta] of R(t) O, where R(t) turns by t about the axis through
``axis_point`` along ``axis_dir`` (right-hand rule: counter-clockwise seen from the tip
of axis_dir) and O is the solid bounded by a closed triangle mesh.

x is in SV iff R(-t) x lies in O for some t in [0, theta]: iff the arc of x's circle about
the axis from angle phi(x) - theta to phi(x) meets O.  On that circle O is a union of
arcs whose ends are where the circle crosses O's boundary.  So the arc meets O iff
  - x itself is in O (t = 0; a 3-D ray-parity test), or
  - a crossing of the circle with a boundary triangle lies on the arc
(if no crossing lies on the arc, the arc is wholly inside or wholly outside O, like its
end x).  The crossings are solved analytically: the circle lies in the plane through x
perpendicular to the axis; that plane cuts a triangle in a segment (its two edges that
change side), and the segment meets the circle at the roots in [0, 1] of a quadratic.
Points exactly on O's boundary, or circles touching it, are measure-zero events the
Monte-Carlo tests do not meet; the oracle does not try to decide them consistently.
"""

import math

import numpy as np

# A direction in no face, edge or axis-aligned plane of the test shapes (ray parity).
_RAY = np.array([0.5377, 0.3141, 0.7826]) / np.linalg.norm([0.5377, 0.3141, 0.7826])
_CHUNK = 1_000_000  # points x triangles per vectorised block


def _frame(axis_dir):
    a = np.asarray(axis_dir, dtype=np.float64)
    a = a / np.linalg.norm(a)
    helper = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(a, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(a, e1)          # (e1, e2, a) is right-handed: angles grow about a
    return np.stack([e1, e2, a])  # rows: local u, v, w axes


def inside_solid(points, vertices, triangles):
    """Boolean per point: inside the closed mesh, by the parity of the crossings of a ray
    from the point (Moller-Trumbore, vectorised)."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64)
    p0, e1, e2 = v[t[:, 0]], v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]
    h = np.cross(_RAY, e2)                      # (T, 3)
    det = np.einsum("ij,ij->i", e1, h)          # (T,)
    ok = np.abs(det) > 1e-300
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    out = np.zeros(len(pts), dtype=bool)
    step = max(1, _CHUNK // max(1, len(t)))
    for s in range(0, len(pts), step):
        x = pts[s:s + step, None, :]            # (P, 1, 3)
        sv = x - p0[None]                       # (P, T, 3)
        u = np.einsum("ptk,tk->pt", sv, h) * inv
        q = np.cross(sv, e1[None])
        w = np.einsum("k,ptk->pt", _RAY, q) * inv
        d = np.einsum("tk,ptk->pt", e2, q) * inv
        hit = ok & (u >= 0) & (w >= 0) & (u + w <= 1) & (d > 0)
        out[s:s + step] = (np.count_nonzero(hit, axis=1) % 2) == 1
    return out


def circle_crossings(points, vertices, triangles, axis_point, axis_dir):
    """Per point: the angles (about the axis, in the frame of ``_frame``) where its circle
    crosses a boundary triangle, as a (P, T, 2) array with NaN where there is none, and
    the point's own angle phi (P,)."""
    frame = _frame(axis_dir)
    c = np.asarray(axis_point, dtype=np.float64)
    pts = (np.asarray(points, dtype=np.float64).reshape(-1, 3) - c) @ frame.T   # (P, 3)
    loc = (np.asarray(vertices, dtype=np.float64) - c) @ frame.T                # (V, 3)
    tri = loc[np.asarray(triangles, dtype=np.int64)]                            # (T, 3, 3)
    phi = np.arctan2(pts[:, 1], pts[:, 0])
    rho2 = pts[:, 0] ** 2 + pts[:, 1] ** 2
    out = np.full((len(pts), len(tri), 2), np.nan)
    step = max(1, _CHUNK // max(1, len(tri)))
    for s in range(0, len(pts), step):
        h = pts[s:s + step, 2][:, None]                     # (P, 1) the circle's plane
        r2 = rho2[s:s + step][:, None]
        above = tri[None, :, :, 2] >= h[:, :, None]         # (P, T, 3) vertex sides
        cross, where = [], []
        for k in range(3):
            i, j = k, (k + 1) % 3
            m = above[:, :, i] != above[:, :, j]
            wi, wj = tri[None, :, i, 2], tri[None, :, j, 2]
            den = np.where(m, wj - wi, 1.0)
            f = np.where(m, (h - wi) / den, 0.0)[..., None]
            where.append(tri[None, :, i, :2] + f * (tri[None, :, j, :2] - tri[None, :, i, :2]))
            cross.append(m)
        m0, m1, m2 = cross
        valid = m0 | m1 | m2                                # then exactly two edges cross
        a_pt = np.where(m0[..., None], where[0], where[1])  # first crossing edge
        b_pt = np.where(m2[..., None], where[2], where[1])  # second crossing edge
        d = b_pt - a_pt
        qa = np.einsum("ptk,ptk->pt", d, d)
        qb = np.einsum("ptk,ptk->pt", a_pt, d)
        qc = np.einsum("ptk,ptk->pt", a_pt, a_pt) - r2
        disc = qb * qb - qa * qc
        good = valid & (qa > 0) & (disc >= 0)
        root = np.sqrt(np.where(good, disc, 0.0))
        safe = np.where(good, qa, 1.0)
        for n, sgn in enumerate((-1.0, 1.0)):
            sol = (-qb + sgn * root) / safe
            hit = good & (sol >= 0) & (sol <= 1)
            q = a_pt + sol[..., None] * d
            ang = np.arctan2(q[..., 1], q[..., 0])
            out[s:s + step, :, n] = np.where(hit, ang, np.nan)
    return out, phi


def inside_swept(points, vertices, triangles, axis_point, axis_dir, theta):
    """Boolean per point: inside the volume swept by the closed mesh (vertices (V, 3),
    triangles (T, 3), any orientation) turning about the axis by 0 .. theta radians
    (theta >= 2 pi: the solid of revolution)."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    in_o = inside_solid(pts, vertices, triangles)
    angles, phi = circle_crossings(pts, vertices, triangles, axis_point, axis_dir)
    two_pi = 2.0 * math.pi
    # A crossing at psi is reached from x by turning x back by (phi - psi) mod 2 pi.
    back = np.mod(phi[:, None, None] - angles, two_pi)
    on_arc = np.isfinite(angles) & ((back <= theta) | (theta >= two_pi))
    return in_o | on_arc.any(axis=(1, 2))


# --------------------------------------------------------------------------- #
# Test shapes (closed, outward): shared by test_sweep_oracle.py and test_mesh.py #
# --------------------------------------------------------------------------- #

_BOX_FACES = np.array([[0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6], [0, 1, 5], [0, 5, 4],
                       [2, 6, 7], [2, 7, 3], [0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5]])


def box_mesh(lo=(0.0, 0.0, 0.0), hi=(1.0, 1.0, 1.0)):
    """Box [lo, hi]: vertex k = (x if k & 1, y if k & 2, z if k & 4), 12 outward
    triangles."""
    lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    v = np.array([[hi[0] if k & 1 else lo[0], hi[1] if k & 2 else lo[1],
                   hi[2] if k & 4 else lo[2]] for k in range(8)])
    return v, _BOX_FACES.copy()


def prism_mesh(centre, radius, height, n):
    """A regular n-gon prism (a tessellated cylinder) along z from 0 to ``height``:
    vertex i at angle 2 pi i / n (vertex 0 at +x) round ``centre`` (x, y)."""
    ang = 2.0 * math.pi * np.arange(n) / n
    ring = np.column_stack([centre[0] + radius * np.cos(ang), centre[1] + radius * np.sin(ang)])
    v = np.vstack([np.column_stack([ring, np.zeros(n)]), np.column_stack([ring, np.full(n, height)]),
                   [[centre[0], centre[1], 0.0], [centre[0], centre[1], height]]])
    bot, top = 2 * n, 2 * n + 1
    tris = []
    for i in range(n):
        j = (i + 1) % n
        tris += [[i, j, n + j], [i, n + j, n + i], [bot, j, i], [top, n + i, n + j]]
    return v, np.array(tris, dtype=np.int64)


def torus_mesh(major, minor, nu, nv):
    """A tessellated torus about the x axis: nu x nv quads (2 nu nv triangles), outward."""
    u = np.arange(nu) * (2.0 * math.pi) / nu
    w = np.arange(nv) * (2.0 * math.pi) / nv
    uu, ww = np.meshgrid(u, w, indexing="ij")
    rho = major + minor * np.cos(ww)
    v = np.stack([(minor * np.sin(ww)).ravel(), (rho * np.cos(uu)).ravel(),
                  (rho * np.sin(uu)).ravel()], axis=1)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a, b = i * nv + j, ((i + 1) % nu) * nv + j
    c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
    t = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                        np.stack([a, c, d], -1).reshape(-1, 3)])
    if soup_winding([[0.0, major, 0.0]], v[t])[0] < 0:   # the tube's centre is inside
        t = t[:, ::-1].copy()
    return v, t


def soup_winding(points, tri, chunk=400_000):
    """Generalised winding number of a set of oriented triangles tri (T, 3, 3) about each
    point: the sum of the triangles' signed solid angles / 4 pi (van Oosterom and
    Strackee).  For a closed outward mesh 1 inside and 0 outside; for any closed chain an
    integer away from its triangles."""
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    tri = np.asarray(tri, dtype=np.float64).reshape(-1, 3, 3)
    out = np.empty(len(p))
    step = max(1, chunk // max(1, len(tri)))
    for s in range(0, len(p), step):
        d = tri[None, :, :, :] - p[s:s + step, None, None, :]      # (P, T, 3, 3)
        a, b, c = d[:, :, 0], d[:, :, 1], d[:, :, 2]
        la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
        num = np.einsum("ptk,ptk->pt", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("ptk,ptk->pt", a, b) * lc
               + np.einsum("ptk,ptk->pt", a, c) * lb + np.einsum("ptk,ptk->pt", b, c) * la)
        out[s:s + step] = 2.0 * np.arctan2(num, den).sum(axis=1) / (4.0 * math.pi)
    return out
