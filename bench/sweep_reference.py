# SPDX-License-Identifier: LGPL-2.1-or-later
"""sweep_reference.py - the independent side of bench_sweep.py: numpy only, no code shared
with libmfgeom, FreeCAD, CGAL or OpenVDB.

  reference_volume   the volume swept by a closed triangle mesh turning by 0..theta about an
                     axis, integrated per circle about the axis (accurate to ~1e-7 relative,
                     estimated per case from two quadrature orders)
  in_swept           a membership oracle for points (the same per-circle rule, with an
                     (r, z) bin grid so that it runs on 10^5-triangle meshes)
  lower_bound        the issue's lower bound on the output size: input faces kept + the
                     silhouette's surfaces of revolution at the angular step sqrt(8 tol / r)
  turned_samples     points of the input's surface turned by t in [0, theta] (the
                     conservativeness check: each must be inside or on a result)

Conventions (the library's): the axis goes through ``axis_point`` along ``axis_dir``; turning
by t is counter-clockwise seen from the tip of axis_dir (right-hand rule).  In the local
frame (u, v, w) of ``frame`` w is along the axis and angles grow from u towards v.

The rule (issue 20, "directed circles"): on the circle of radius r at height w = h about
the axis, the solid O covers arcs [a, b] (counter-clockwise from an entry a of the
boundary to the next exit b).  Turned by 0..theta they cover [a, b + theta].  So the
covered angle is 2 pi minus, over each gap between an exit and the next entry, max(0, gap
- theta); a circle crossing no boundary is wholly in or out of O.  The swept volume is
V = integral over h and r of r * covered(r, h).
"""

import math

import numpy as np

TWO_PI = 2.0 * math.pi


def frame(axis_dir):
    """Rows e1, e2, a: right-handed, a along the axis (angles grow counter-clockwise about
    a)."""
    a = np.asarray(axis_dir, dtype=np.float64)
    a = a / np.linalg.norm(a)
    helper = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(a, helper)
    e1 /= np.linalg.norm(e1)
    return np.stack([e1, np.cross(a, e1), a])


def to_local(points, axis_point, axis_dir):
    return (np.asarray(points, dtype=np.float64) - np.asarray(axis_point, dtype=np.float64)) \
        @ frame(axis_dir).T


def rotate(points, axis_point, axis_dir, angles):
    """Points (P, 3) each turned by its angle (P,) (or one angle) about the axis."""
    f = frame(axis_dir)
    loc = to_local(points, axis_point, axis_dir)
    ang = np.broadcast_to(np.asarray(angles, dtype=np.float64), (len(loc),))
    c, s = np.cos(ang), np.sin(ang)
    out = np.column_stack([c * loc[:, 0] - s * loc[:, 1], s * loc[:, 0] + c * loc[:, 1],
                           loc[:, 2]])
    return out @ f + np.asarray(axis_point, dtype=np.float64)


def mesh_volume(vertices, triangles):
    """Divergence theorem: the signed volume of a closed, outward triangle mesh."""
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64)
    if not len(t):
        return 0.0
    return float(np.einsum("ij,ij->i", v[t[:, 0]], np.cross(v[t[:, 1]], v[t[:, 2]])).sum() / 6)


# ----------------------------------------------------------------------------- slices
class _Local:
    """The mesh in the axis frame: triangles (T, 3, 3), their z range and their outward
    normal's in-plane part (which orients each slice segment: the solid on its left)."""

    def __init__(self, vertices, triangles, axis_point, axis_dir):
        loc = to_local(vertices, axis_point, axis_dir)
        self.tri = loc[np.asarray(triangles, dtype=np.int64)]
        self.zmin = self.tri[:, :, 2].min(axis=1)
        self.zmax = self.tri[:, :, 2].max(axis=1)
        n = np.cross(self.tri[:, 1] - self.tri[:, 0], self.tri[:, 2] - self.tri[:, 0])
        self.nuv = n[:, :2]
        r = np.hypot(loc[:, 0], loc[:, 1])
        self.rmax = float(r.max())
        self.span = float(loc[:, 2].max() - loc[:, 2].min())
        self.size = float(np.linalg.norm(loc.max(axis=0) - loc.min(axis=0)))
        self.loc = loc

    def slice(self, h, index=None):
        """The oriented segments (P, D) (each (k, 2): start, direction; the solid on the
        left of D) in which the plane w = h cuts the triangles (all, or those of
        ``index``) that straddle it.  A vertex exactly at h counts as below."""
        if index is None:
            m = (self.zmin <= h) & (self.zmax > h)
            t, nuv = self.tri[m], self.nuv[m]
        else:
            t = self.tri[index]
            nuv = self.nuv[index]
            m = (t[:, :, 2].min(axis=1) <= h) & (t[:, :, 2].max(axis=1) > h)
            t, nuv = t[m], nuv[m]
            index = index[m]
        above = t[:, :, 2] > h
        pts = []
        for i, j in ((0, 1), (1, 2), (2, 0)):
            c = above[:, i] != above[:, j]
            wi, wj = t[:, i, 2], t[:, j, 2]
            f = np.where(c, (h - wi) / np.where(c, wj - wi, 1.0), np.nan)
            pts.append(t[:, i, :2] + f[:, None] * (t[:, j, :2] - t[:, i, :2]))
        p = np.stack(pts, axis=1)                       # (k, 3, 2): one row NaN
        ok = ~np.isnan(p[:, :, 0])
        order = np.argsort(~ok, axis=1, kind="stable")[:, :2]
        ab = np.take_along_axis(p, order[:, :, None], axis=1)
        a, b = ab[:, 0], ab[:, 1]
        d = b - a
        # the solid on the left of d: d along the in-plane normal turned by +90 degrees
        flip = d[:, 0] * -nuv[:, 1] + d[:, 1] * nuv[:, 0] < 0
        a = np.where(flip[:, None], b, a)
        d = np.where(flip[:, None], -d, d)
        return (a, d) if index is None else (a, d, index)


def _seg_radii(a, d):
    """Per segment the smallest and largest distance from the origin."""
    dd = np.einsum("ij,ij->i", d, d)
    f = np.clip(-np.einsum("ij,ij->i", a, d) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    lo = np.hypot(*(a + f[:, None] * d).T)
    hi = np.maximum(np.hypot(*a.T), np.hypot(*(a + d).T))
    return lo, hi


def _crossings(a, d, r, seg):
    """Crossings of circle r[i] with segment seg[i] (pairs): per pair up to two, returned
    as (pair index, angle, entering) with s in [0, 1) (half-open: a vertex shared by two
    chained segments counts once).  Moving counter-clockwise on the circle, it enters the
    solid where q . d > 0 (the larger root)."""
    p0, dv = a[seg], d[seg]
    qa = np.einsum("ij,ij->i", dv, dv)
    qb = np.einsum("ij,ij->i", p0, dv)
    qc = np.einsum("ij,ij->i", p0, p0) - r * r
    disc = qb * qb - qa * qc
    good = (disc > 0) & (qa > 0)
    root = np.sqrt(np.where(good, disc, 0.0))
    safe = np.where(good, qa, 1.0)
    idx, ang, ent = [], [], []
    for sgn in (-1.0, 1.0):
        s = (-qb + sgn * root) / safe
        hit = good & (s >= 0.0) & (s < 1.0)
        k = np.nonzero(hit)[0]
        q = p0[k] + s[k, None] * dv[k]
        idx.append(k)
        ang.append(np.arctan2(q[:, 1], q[:, 0]))
        ent.append(np.full(len(k), sgn > 0))
    return np.concatenate(idx), np.concatenate(ang), np.concatenate(ent)


def _pairs(lo, hi, radii):
    """(radius index, segment index) for every segment and every radius in [lo, hi]
    (radii sorted ascending)."""
    i0 = np.searchsorted(radii, lo, side="left")
    i1 = np.searchsorted(radii, hi, side="right")
    cnt = np.maximum(i1 - i0, 0)
    seg = np.repeat(np.arange(len(lo)), cnt)
    start = np.repeat(i0 - np.concatenate([[0], np.cumsum(cnt)[:-1]]), cnt)
    rad = start + np.arange(len(seg))
    return rad, seg


def _winding_outside(a, d, lo, radii):
    """Per radius: is a circle that crosses no segment inside the solid?  Sum of the
    signed angles that the segments lying wholly outside it (lo > r) subtend at the
    centre: their loops go round the circle 0 or (around the solid) once."""
    b = a + d
    sub = np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], np.einsum("ij,ij->i", a, b))
    order = np.argsort(lo)
    suffix = np.concatenate([np.cumsum(sub[order][::-1])[::-1], [0.0]])
    k = np.searchsorted(lo[order], radii, side="right")
    return np.abs(suffix[k]) > math.pi


def covered_angles(a, d, radii, theta):
    """Per radius (sorted ascending): the angle of its circle covered by the slice's solid
    turned by 0..theta; also the number of radii whose crossings did not alternate
    entry / exit (0 for a closed, consistently oriented mesh)."""
    lo, hi = _seg_radii(a, d)
    rad, seg = _pairs(lo, hi, radii)
    pair, ang, ent = _crossings(a, d, radii[rad], seg)
    ridx = rad[pair]
    covered = np.where(_winding_outside(a, d, lo, radii), TWO_PI, 0.0)
    if not len(ridx):
        return covered, 0
    order = np.lexsort((ang, ridx))
    ridx, ang, ent = ridx[order], ang[order], ent[order]
    first = np.ones(len(ridx), dtype=bool)
    first[1:] = ridx[1:] != ridx[:-1]
    starts = np.nonzero(first)[0]
    group = np.cumsum(first) - 1
    nxt = np.arange(1, len(ridx) + 1)
    last = np.ones(len(ridx), dtype=bool)
    last[:-1] = first[1:]
    nxt[last] = starts[group[last]]
    gap = ang[nxt] - ang + np.where(last, TWO_PI, 0.0)
    exits = ~ent
    bad_pairs = exits & ~ent[nxt] | ent & ent[nxt]
    bad = np.zeros(len(radii), dtype=bool)
    bad[ridx[bad_pairs]] = True
    has = np.zeros(len(radii), dtype=bool)
    has[ridx] = True
    if theta >= TWO_PI:
        covered[has] = TWO_PI
        return covered, int(bad.sum())
    lost = np.where(exits & ent[nxt], np.maximum(0.0, gap - theta), 0.0)
    lost_r = np.bincount(ridx, weights=lost, minlength=len(radii))
    covered[has] = TWO_PI - lost_r[has]
    return covered, int(bad.sum())


def _gauss_nodes(breaks, n, pieces):
    """Nodes and weights integrating over [breaks[0], breaks[-1]]: per interval [a, b]
    between consecutive breaks, x = a + (b - a) (3 u^2 - 2 u^3) (flat at both ends, so a
    sqrt onset at either end, e.g. where a circle starts to cut a segment, becomes smooth
    in u) with u in ``pieces`` equal parts of [0, 1], n Gauss-Legendre nodes each.
    Returned sorted."""
    g, gw = np.polynomial.legendre.leggauss(n)
    u = ((np.arange(pieces)[:, None] + (g[None, :] + 1) / 2) / pieces).ravel()
    uw = np.tile(gw / (2 * pieces), pieces)
    a, b = np.asarray(breaks[:-1])[:, None], np.asarray(breaks[1:])[:, None]
    return ((a + (b - a) * (3 * u ** 2 - 2 * u ** 3)).ravel(),
            ((b - a) * 6 * u * (1 - u) * uw).ravel())


def _merge(breaks, gap):
    """The sorted unique breaks without those within ``gap`` of the previous one: the
    same point reached from two triangles may differ in the last bits, and a node between
    the two would see a circle through the chain's shared vertex (counted twice or not at
    all)."""
    b = np.unique(breaks)
    keep = np.concatenate([[True], np.diff(b) > gap])
    out = b[keep]
    out[-1] = b[-1]
    return out


def _z_breaks(m, max_vertex_breaks):
    """Heights where the integrand over r may jump or kink: the mesh's extremes, the
    heights of faces perpendicular to the axis (the slice area jumps there), and every
    vertex height when there are at most ``max_vertex_breaks`` of them."""
    z = m.loc[:, 2]
    eps = 1e-12 * max(m.size, 1e-300)
    flat = (m.zmax - m.zmin) <= eps
    hs = [z.min(), z.max()]
    hs += list(np.unique(m.zmin[flat]))
    uz = np.unique(z)
    if len(uz) <= max_vertex_breaks:
        hs += list(uz)
    hs = np.unique(np.asarray(hs))
    keep = np.concatenate([[True], np.diff(hs) > 1e-9 * max(m.span, 1e-300)])
    hs = hs[keep]
    hs[-1] = max(hs[-1], z.max())
    return hs


def reference_volume(vertices, triangles, axis_point, axis_dir, theta, z_intervals=600,
                     nz=4, nr=4, max_vertex_breaks=400, progress=None):
    """The swept volume of the closed outward mesh by the per-circle rule (module doc).

    Heights: Gauss-Legendre, ``nz`` nodes per interval, on the intervals between the
    breaks of ``_z_breaks`` each cut into pieces no longer than span / z_intervals.  Radii,
    per slice: ``nr`` nodes per interval between the slice's own breaks (radii of the
    segments' ends and of the feet of the perpendiculars from the axis; x 4 pieces when
    the slice has < 100 segments).  Returns (volume, diagnostics dict)."""
    m = _Local(vertices, triangles, axis_point, axis_dir)
    hs = _z_breaks(m, max_vertex_breaks)
    step = m.span / z_intervals
    fine = [hs[0]]
    for a, b in zip(hs[:-1], hs[1:]):
        k = max(1, int(math.ceil((b - a) / step)))
        fine += list(a + (b - a) * np.arange(1, k + 1) / k)
    zs, zw = _gauss_nodes(np.asarray(fine), nz, 1)
    total, bad_slices, nodes = 0.0, 0, 0
    for i, (h, wz) in enumerate(zip(zs, zw)):
        if progress and i % 500 == 0:
            progress(i / len(zs))
        a, d = m.slice(h)
        if not len(a):
            continue
        lo, hi = _seg_radii(a, d)
        ends = np.hypot(*a.T)
        br = _merge(np.concatenate([[0.0], lo, hi, ends]), 1e-9 * m.rmax)
        radii, rw = _gauss_nodes(br, nr, 4 if len(a) < 100 else 1)
        cov, bad = covered_angles(a, d, radii, theta)
        bad_slices += bad > 0
        nodes += len(radii)
        total += float(np.sum(rw * radii * cov)) * wz
    return total, {"slices": len(zs), "r_nodes": nodes, "slices_not_alternating": bad_slices,
                   "z_breaks": len(hs)}


def reference_with_error(vertices, triangles, axis_point, axis_dir, theta, fine=(1200, 4, 4),
                         coarse=(600, 3, 3), progress=None):
    """The reference at two quadratures (z intervals, nodes in z, nodes in r): returns
    (fine value, |fine - coarse| as its uncertainty, diagnostics)."""
    vf, df = reference_volume(vertices, triangles, axis_point, axis_dir, theta, *fine,
                              progress=progress)
    vc, _ = reference_volume(vertices, triangles, axis_point, axis_dir, theta, *coarse)
    df["coarse"] = vc
    return vf, abs(vf - vc), df


# ----------------------------------------------------------------------------- oracle
class Oracle:
    """Point membership in the swept volume (and in O), for 10^5-triangle meshes: the
    triangles are binned by their (r, w) extent (r from the 2-D distance of the projected
    triangle to the axis, 0 when it surrounds it), so a circle only meets the triangles
    of its own bin."""

    def __init__(self, vertices, triangles, axis_point, axis_dir, theta):
        self.m = m = _Local(vertices, triangles, axis_point, axis_dir)
        self.theta = float(theta)
        self.axis_point = np.asarray(axis_point, dtype=np.float64)
        self.axis_dir = np.asarray(axis_dir, dtype=np.float64)
        t = m.tri
        uv = t[:, :, :2]
        rv = np.hypot(uv[..., 0], uv[..., 1])
        rhi = rv.max(axis=1)
        # min distance from the origin to the projected triangle
        dmin = rv.min(axis=1)
        cr = []
        for i, j in ((0, 1), (1, 2), (2, 0)):
            p, q = uv[:, i], uv[:, j]
            e = q - p
            ee = np.einsum("ij,ij->i", e, e)
            f = np.clip(-np.einsum("ij,ij->i", p, e) / np.where(ee > 0, ee, 1.0), 0, 1)
            dmin = np.minimum(dmin, np.hypot(*(p + f[:, None] * e).T))
            cr.append(p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0])
        cr = np.stack(cr, axis=1)
        around = (cr >= 0).all(axis=1) | (cr <= 0).all(axis=1)
        rlo = np.where(around, 0.0, dmin)
        pad = 1e-9 * m.size
        self.rlo, self.rhi = rlo - pad, rhi + pad
        self.zlo, self.zhi = m.zmin - pad, m.zmax + pad
        # bins about two typical triangle extents
        ext = np.median(np.maximum(self.rhi - self.rlo, self.zhi - self.zlo))
        cell = max(2.0 * ext, 1e-6 * m.size)
        self.r0, self.z0 = 0.0, float(self.zlo.min())
        self.cell = cell
        self.nr = int((self.rhi.max() - self.r0) / cell) + 1
        self.nz = int((self.zhi.max() - self.z0) / cell) + 1
        i0 = np.clip(((self.rlo - self.r0) / cell).astype(np.int64), 0, self.nr - 1)
        i1 = np.clip(((self.rhi - self.r0) / cell).astype(np.int64), 0, self.nr - 1)
        j0 = np.clip(((self.zlo - self.z0) / cell).astype(np.int64), 0, self.nz - 1)
        j1 = np.clip(((self.zhi - self.z0) / cell).astype(np.int64), 0, self.nz - 1)
        ni, nj = i1 - i0 + 1, j1 - j0 + 1
        cnt = ni * nj
        tid = np.repeat(np.arange(len(t)), cnt)
        off = np.arange(cnt.sum()) - np.repeat(np.concatenate([[0], np.cumsum(cnt)[:-1]]), cnt)
        ci = np.repeat(i0, cnt) + off % np.repeat(ni, cnt)
        cj = np.repeat(j0, cnt) + off // np.repeat(ni, cnt)
        key = cj * self.nr + ci
        order = np.argsort(key, kind="stable")
        self.bin_tri = tid[order]
        self.bin_start = np.searchsorted(key[order], np.arange(self.nr * self.nz + 1))

    def _candidates(self, r, z):
        ci = np.clip(((r - self.r0) / self.cell).astype(np.int64), 0, self.nr - 1)
        cj = np.clip(((z - self.z0) / self.cell).astype(np.int64), 0, self.nz - 1)
        key = cj * self.nr + ci
        s, e = self.bin_start[key], self.bin_start[key + 1]
        cnt = e - s
        q = np.repeat(np.arange(len(r)), cnt)
        off = np.arange(cnt.sum()) - np.repeat(np.concatenate([[0], np.cumsum(cnt)[:-1]]), cnt)
        tri = self.bin_tri[np.repeat(s, cnt) + off]
        return q, tri

    def classify(self, points, chunk=20000):
        """Per point: (in O, in SV)."""
        loc = to_local(points, self.axis_point, self.axis_dir)
        in_o = np.zeros(len(loc), dtype=bool)
        in_sv = np.zeros(len(loc), dtype=bool)
        for s in range(0, len(loc), chunk):
            o, sv = self._classify(loc[s:s + chunk])
            in_o[s:s + chunk], in_sv[s:s + chunk] = o, sv
        return in_o, in_sv

    def _classify(self, loc):
        m = self.m
        r = np.hypot(loc[:, 0], loc[:, 1])
        h = loc[:, 2]
        phi = np.arctan2(loc[:, 1], loc[:, 0])
        q, ti = self._candidates(r, h)
        # keep the candidates whose triangle straddles the point's height
        t = m.tri[ti]
        st = (t[:, :, 2].min(axis=1) <= h[q]) & (t[:, :, 2].max(axis=1) > h[q])
        q, ti, t = q[st], ti[st], t[st]
        hq = h[q]
        above = t[:, :, 2] > hq[:, None]
        pts = []
        for i, j in ((0, 1), (1, 2), (2, 0)):
            c = above[:, i] != above[:, j]
            wi, wj = t[:, i, 2], t[:, j, 2]
            f = np.where(c, (hq - wi) / np.where(c, wj - wi, 1.0), np.nan)
            pts.append(t[:, i, :2] + f[:, None] * (t[:, j, :2] - t[:, i, :2]))
        p = np.stack(pts, axis=1)
        ok = ~np.isnan(p[:, :, 0])
        order = np.argsort(~ok, axis=1, kind="stable")[:, :2]
        ab = np.take_along_axis(p, order[:, :, None], axis=1)
        a, b = ab[:, 0], ab[:, 1]
        d = b - a
        nuv = m.nuv[ti]
        flip = d[:, 0] * -nuv[:, 1] + d[:, 1] * nuv[:, 0] < 0
        a = np.where(flip[:, None], b, a)
        d = np.where(flip[:, None], -d, d)
        pair, ang, ent = _crossings(a, d, r[q], np.arange(len(q)))
        pq = q[pair]
        n = len(loc)
        has = np.zeros(n, dtype=bool)
        has[pq] = True
        # forward angle from the point to each crossing, and back angle
        fwd = np.mod(ang - phi[pq], TWO_PI)
        back = np.mod(phi[pq] - ang, TWO_PI)
        # in O: the first crossing counter-clockwise from the point is an exit
        in_o = np.zeros(n, dtype=bool)
        if len(pq):
            order = np.lexsort((fwd, pq))
            first = np.ones(len(order), dtype=bool)
            first[1:] = pq[order][1:] != pq[order][:-1]
            f_idx = order[first]
            in_o[pq[f_idx]] = ~ent[f_idx]
        on_arc = np.zeros(n, dtype=bool)
        hit = back <= self.theta if self.theta < TWO_PI else np.ones(len(pq), dtype=bool)
        on_arc[pq[hit]] = True
        # circles with no crossing: wholly in or out (the full slice decides)
        for k in np.nonzero(~has)[0]:
            a2, d2 = m.slice(h[k])
            if not len(a2):
                continue
            lo, _ = _seg_radii(a2, d2)
            in_o[k] = _winding_outside(a2, d2, lo, np.array([r[k]]))[0]
        return in_o, in_o | on_arc


# ----------------------------------------------------------------------------- lower bound
def angular_step(tol, r):
    """The angle whose chord's sagitta on radius r is tol: r (1 - cos(d / 2)) = tol, i.e.
    ~sqrt(8 tol / r) (exact form; 2 pi when r <= 2 tol... the circle is within tol of
    its centre)."""
    r = np.asarray(r, dtype=np.float64)
    x = np.clip(1.0 - tol / np.maximum(r, 1e-300), -1.0, 1.0)
    return np.where(r > tol, 2.0 * np.arccos(x), TWO_PI)


def _edges(triangles):
    """Unique undirected edges (E, 2) and, per edge, its two faces (E, 2) (-1 if one)."""
    t = np.asarray(triangles, dtype=np.int64)
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    f = np.tile(np.arange(len(t)), 3)
    key = np.sort(e, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, f = key[order], f[order]
    first = np.ones(len(key), dtype=bool)
    first[1:] = (key[1:] != key[:-1]).any(axis=1)
    starts = np.nonzero(first)[0]
    cnt = np.diff(np.concatenate([starts, [len(key)]]))
    faces = np.full((len(starts), 2), -1, dtype=np.int64)
    faces[:, 0] = f[starts]
    two = cnt >= 2
    faces[two, 1] = f[starts[two] + 1]
    return key[starts], faces


def lower_bound(vertices, triangles, axis_point, axis_dir, theta, tol, samples_t=8,
                oracle=None):
    """The issue's lower bound on the size of a result at tolerance tol (module doc of
    bench_sweep.py for the definition).  Returns a dict: lb and its parts."""
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64)
    a_dir = np.asarray(axis_dir, dtype=np.float64)
    a_dir = a_dir / np.linalg.norm(a_dir)
    c = np.asarray(axis_point, dtype=np.float64)
    full = theta >= TWO_PI * (1 - 1e-12)
    orc = oracle or Oracle(v, t, c, a_dir, theta)
    size = orc.m.size
    eps = 1e-6 * size
    tri = v[t]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    nn = np.linalg.norm(n, axis=1)
    good = nn > 0
    n = n / np.where(good, nn, 1.0)[:, None]
    # s(p) = n . (a x (p - c)) = (p - c) . (n x a): linear over each triangle
    mvec = np.cross(n, a_dir)
    axial = np.linalg.norm(mvec, axis=1) <= 1e-12          # n parallel to the axis
    s = np.einsum("tij,tj->ti", tri - c, mvec)              # (T, 3) at the vertices
    scale = np.linalg.norm(mvec, axis=1)[:, None] * size
    s = np.where(np.abs(s) <= 1e-12 * scale, 0.0, s)

    def visible(points, normals, angle):
        q = rotate(points + eps * normals, c, a_dir, angle)
        return ~orc.classify(q)[1]

    # -- input faces kept: the part with s < 0 bounds SV at t = 0, s > 0 at t = theta
    kept = {"start": 0, "end": 0}
    if not full:
        for name, sign, angle in (("start", -1.0, 0.0), ("end", 1.0, theta)):
            cand = np.nonzero(good & ~axial & ((sign * s) > 0).any(axis=1))[0]
            for k in (0, 1, 2, 3):    # the part's centroid, then towards its corners
                if not len(cand):
                    break
                vis = visible(_part_samples(tri[cand], sign * s[cand], k), n[cand], angle)
                kept[name] += int(vis.sum())
                cand = cand[~vis]
    # -- silhouette pieces: zero lines inside triangles, and edges between faces of
    #    opposite sign (the sub-segment where the signs differ)
    pieces = []                                   # (p, q, normal)
    sgn = np.sign(s)
    inner = good & ~axial & (sgn.max(axis=1) > 0) & (sgn.min(axis=1) < 0)
    for k in np.nonzero(inner)[0]:
        ends = []
        for i, j in ((0, 1), (1, 2), (2, 0)):
            if s[k, i] * s[k, j] < 0:
                f = s[k, i] / (s[k, i] - s[k, j])
                ends.append(tri[k, i] + f * (tri[k, j] - tri[k, i]))
            elif s[k, i] == 0 and s[k, j] != 0:
                ends.append(tri[k, i])
        if len(ends) >= 2:
            pieces.append((ends[0], ends[1], n[k]))
    edges, faces = _edges(t)
    two = (faces[:, 1] >= 0)
    e, fa = edges[two], faces[two]
    f1, f2 = fa[:, 0], fa[:, 1]
    ok = good[f1] & good[f2] & ~axial[f1] & ~axial[f2]
    p0, p1 = v[e[:, 0]], v[e[:, 1]]
    s1a, s1b = np.einsum("ij,ij->i", p0 - c, mvec[f1]), np.einsum("ij,ij->i", p1 - c, mvec[f1])
    s2a, s2b = np.einsum("ij,ij->i", p0 - c, mvec[f2]), np.einsum("ij,ij->i", p1 - c, mvec[f2])
    # product (s1a + u ds1)(s2a + u ds2) < 0 on a sub-interval of [0, 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        u1 = np.where(s1a != s1b, s1a / (s1a - s1b), -1.0)
        u2 = np.where(s2a != s2b, s2a / (s2a - s2b), -1.0)
    inside = (u1 > 0) & (u1 < 1) & (u2 > 0) & (u2 < 1) & (u1 != u2)
    cand = np.nonzero(ok & ((s1a * s2a < 0) | (s1b * s2b < 0) | inside))[0]
    for k in cand:
        us = [0.0, 1.0]
        for sa, sb in ((s1a[k], s1b[k]), (s2a[k], s2b[k])):
            if sa != sb:
                u = sa / (sa - sb)
                if 0.0 < u < 1.0:
                    us.append(u)
        us = sorted(us)
        for u0, u1 in zip(us[:-1], us[1:]):
            um = 0.5 * (u0 + u1)
            if (s1a[k] + um * (s1b[k] - s1a[k])) * (s2a[k] + um * (s2b[k] - s2a[k])) < 0:
                pa, pb = p0[k] + u0 * (p1[k] - p0[k]), p0[k] + u1 * (p1[k] - p0[k])
                mid = 0.5 * (pa + pb)
                tau = np.cross(a_dir, mid - c)
                ns = np.cross(tau, pb - pa)
                ref = n[f1[k]] + n[f2[k]]
                if np.linalg.norm(ns) <= 1e-12 * np.linalg.norm(tau) * np.linalg.norm(pb - pa):
                    ns = ref
                if ns @ ref < 0:
                    ns = -ns
                pieces.append((pa, pb, ns / np.linalg.norm(ns)))
    strips = _revolution_count(pieces, orc, c, a_dir, theta, tol, samples_t, eps, full)
    # -- faces perpendicular to the axis: per connected planar region, its swept sector is
    #    bounded by an arc at its largest radius
    sectors, nsec = 0, 0
    ax = np.nonzero(axial & good)[0]
    if len(ax):
        comp = _components(t[ax], np.round(((tri[ax, 0] - c) @ a_dir) / (1e-9 * size)))
        loc = to_local(v, c, a_dir)
        rv = np.hypot(loc[:, 0], loc[:, 1])
        for cid in np.unique(comp):
            idx = ax[comp == cid]
            vs = np.unique(t[idx])
            top = vs[np.argmax(rv[vs])]
            f = _visible_fraction(v[top][None], n[idx[0]][None], orc, c, a_dir, theta,
                                  samples_t, eps, full)[0]
            if f > 0:
                sectors += int(math.ceil(f * theta / float(angular_step(tol, rv[top]))))
                nsec += 1
    lb = kept["start"] + kept["end"] + strips["triangles"] + sectors
    return {"lb": int(lb), "kept_start": kept["start"], "kept_end": kept["end"],
            "strip_triangles": strips["triangles"], "pieces": len(pieces),
            "pieces_visible": strips["visible"], "sector_triangles": sectors,
            "sectors": nsec}


def _part_samples(tri, s, k):
    """Sample k of the part of each triangle where s > 0 (s linear, given at the
    vertices): k = 0 its centroid (of the part's corners), 1..3 halfway from it to the
    part's k-th corner (its last one when it has fewer)."""
    pts, ok = [], []
    for a, b in ((0, 1), (1, 2), (2, 0)):
        pa = s[:, a] > 0
        pts.append(tri[:, a])
        ok.append(pa)
        cross = (pa != (s[:, b] > 0)) & (s[:, a] != s[:, b])
        f = np.where(cross, s[:, a] / np.where(cross, s[:, a] - s[:, b], 1.0), 0.0)
        cross &= (f > 0) & (f < 1)
        pts.append(tri[:, a] + f[:, None] * (tri[:, b] - tri[:, a]))
        ok.append(cross)
    pts = np.stack(pts, axis=1)                     # (T, 6, 3)
    ok = np.stack(ok, axis=1)                       # (T, 6)
    cnt = ok.sum(axis=1)
    cen = (pts * ok[:, :, None]).sum(axis=1) / np.maximum(cnt, 1)[:, None]
    if k == 0:
        return cen
    # the k-th valid corner (or the last valid one)
    rank = np.cumsum(ok, axis=1)
    want = np.minimum(k, np.maximum(cnt, 1))
    sel = ok & (rank == want[:, None])
    idx = np.argmax(sel, axis=1)
    corner = pts[np.arange(len(pts)), idx]
    return 0.5 * (cen + corner)


def _visible_fraction(points, normals, orc, c, a_dir, theta, samples_t, eps, full):
    """Per point: the fraction of angles t_j = (j + 1/2) theta / samples_t at which the
    point moved eps along its normal and turned by t_j is outside SV."""
    tj = (np.arange(samples_t) + 0.5) * (min(theta, TWO_PI) / samples_t)
    p = np.repeat(points + eps * normals, samples_t, axis=0)
    ang = np.tile(tj, len(points))
    out = ~orc.classify(rotate(p, c, a_dir, ang))[1]
    return out.reshape(len(points), samples_t).mean(axis=1)


def _revolution_count(pieces, orc, c, a_dir, theta, tol, samples_t, eps, full):
    """Sum over the silhouette pieces of 2 ceil(f theta / step(r_max)): a strip of quads,
    two triangles each, at the angular step of the piece's outer end, over the visible
    fraction f of its turn (sampled at its midpoint)."""
    if not pieces:
        return {"triangles": 0, "visible": 0}
    pa = np.array([p[0] for p in pieces])
    pb = np.array([p[1] for p in pieces])
    ns = np.array([p[2] for p in pieces])
    f = _visible_fraction(0.5 * (pa + pb), ns, orc, c, a_dir, theta, samples_t, eps, full)
    loc_a, loc_b = to_local(pa, c, a_dir), to_local(pb, c, a_dir)
    rmax = np.maximum(np.hypot(loc_a[:, 0], loc_a[:, 1]), np.hypot(loc_b[:, 0], loc_b[:, 1]))
    # a piece within tol of the axis turns into a surface within tol of itself: none
    steps = np.where(rmax > tol, np.ceil(f * min(theta, TWO_PI) / angular_step(tol, rmax)), 0)
    return {"triangles": int(2 * steps.sum()), "visible": int((f > 0).sum())}


def _components(tris, key):
    """Connected components (shared vertex, same key) of the triangles: a label each."""
    parent = np.arange(len(tris))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i
    owner = {}
    for i, (tr, k) in enumerate(zip(tris, key)):
        for vtx in tr:
            j = owner.setdefault((int(vtx), k), i)
            ri, rj = find(i), find(j)
            if ri != rj:
                parent[ri] = rj
    return np.array([find(i) for i in range(len(tris))])


# ----------------------------------------------------------------------------- samples
def turned_samples(vertices, triangles, axis_point, axis_dir, theta, n_vertices=1500,
                   n_area=1500, n_edge=1000, n_t=30, seed=20):
    """Points of the input's surface turned by t in [0, theta]: up to ``n_vertices``
    vertices, ``n_area`` points uniform by area on the triangles and ``n_edge`` points on
    the edges (where silhouettes are), each at t = 0, t = theta and ``n_t`` random t in
    between (theta = 2 pi: t in [0, 2 pi)).  Deterministic (seeded)."""
    rng = np.random.default_rng(seed)
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64)
    vi = np.arange(len(v)) if len(v) <= n_vertices else rng.choice(len(v), n_vertices,
                                                                    replace=False)
    tri = v[t]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    k = rng.choice(len(t), n_area, p=area / area.sum())
    r1, r2 = rng.random(n_area), rng.random(n_area)
    sq = np.sqrt(r1)
    on_tri = ((1 - sq)[:, None] * tri[k, 0] + (sq * (1 - r2))[:, None] * tri[k, 1]
              + (sq * r2)[:, None] * tri[k, 2])
    edges, _ = _edges(t)
    ke = rng.choice(len(edges), n_edge)
    u = rng.random(n_edge)[:, None]
    on_edge = v[edges[ke, 0]] + u * (v[edges[ke, 1]] - v[edges[ke, 0]])
    base = np.concatenate([v[vi], on_tri, on_edge])
    full = theta >= TWO_PI * (1 - 1e-12)
    ts = [np.zeros(len(base))] + ([] if full else [np.full(len(base), theta)])
    ts += [rng.random(len(base)) * min(theta, TWO_PI) for _ in range(n_t)]
    ang = np.concatenate(ts)
    pts = np.tile(base, (len(ts), 1))
    return rotate(pts, axis_point, axis_dir, ang)
