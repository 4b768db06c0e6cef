# SPDX-License-Identifier: LGPL-2.1-or-later
"""bench_medial_voronoi.py - the practical peer of the 3-D medial surface (issue 22): sample
the solid's boundary densely and keep the inner Voronoi vertices (scipy.spatial.Voronoi),
as users do, against mfgeom.core.medial_surface on the same solids, at equal accuracy.

Solids: tests/python/medial_solids.py (cuboid, l_bracket, t_section, disc48, tray, cup =
cup(625)); tolerance 0.5 % of the bounding-box diagonal L (as bench_medial.py).  For each
solid and each sample count N (10^4, 3*10^4, 10^5, 3*10^5, 10^6; --quick stops at 10^5):

- peer (timed: sampling + Voronoi + filtering + radii): N area-weighted uniform boundary
  points (seeded) plus the mesh vertices; scipy.spatial.Voronoi (Qhull, one thread) with
  the options "Qbb Qc QJ" (--qhull): Qhull's joggle instead of scipy's default "Qbb Qc
  Qz", because the samples of a planar face, coplanar within rounding, make the default
  merge facets and take 10-70x longer (cuboid, 10^4 samples: 11 s against 1 s; 3*10^4:
  267 s), and without Qz, because Qz with QJ loses the vertices of a whole region
  (cuboid, 10^4 samples: none of the 581 within 8 of the centre of its mid-plane); the
  Voronoi vertices inside the bounding box, then inside the solid by ray parity (a fixed
  direction near the axis that projects the mesh smallest, triangles bucketed in a 2-D
  grid, each edge's side decided in one orientation so a ray never slips between two
  triangles); vertices within 1e-9 L of a crossed triangle's plane are discarded (the
  parity is not decided there and they are not medial); radius = distance to a sample
  generating the vertex (a point of one of its ridges, ridge_points / ridge_vertices), which
  is the distance to the nearest sample (up to the joggle; a cKDTree query of the nearest
  sample took 12-180 s for the cuboid's 10^5-3*10^5 deep vertices, equidistant from two
  parallel faces);
- ours (timed, the library call alone): medial_surface(v, t, tol, major_only=False) (the
  full medial surface, which the Voronoi vertices approximate) and major_only=True.

Every case runs in a fresh python, its address space capped at half the physical memory
(a case that needs more reports "out of memory") and stopped after --timeout seconds; a
solid's larger N are skipped after a failure.  Accuracy, not timed, against the exact
point-to-triangle distance of the independent oracle (tests/python/medial_oracle.py, not
our library), on seeded samples of --sample points:

- radius error |r - D| (D the exact distance to the boundary) at the peer's kept vertices
  and at our sheet vertices, seam points and junctions (median, 95th percentile, max);
- peer -> ours: distance from the peer's kept vertices to our full medial surface (its
  sheet triangles, seam polylines, junctions); ours -> peer: from area-weighted points on
  our major and on our full sheets to the nearest kept Voronoi vertex (95th percentile,
  max); zero-area sheet triangles count as their edges;
- the ray parity against the oracle's winding number on a sample of the candidates.

Equal accuracy (CRITERIA): the smallest N at which the peer's 95th percentiles of
peer -> ours and of the radius error are both within the tolerance (N*); also that of
ours (major) -> peer (N**); also the largest radius error and ours (major) -> peer
(N-max); and the ratio of the peer's time there to ours (issue 22's target: ours >= 10x
faster).

Run with the system interpreter (numpy, scipy):
    MFGEOM_LIBRARY=build/libmfgeom.so /usr/bin/python3 bench/bench_medial_voronoi.py
        [--quick [--full-for NAME[,NAME]]] [--only NAME[,NAME]] [--sizes N,N]
        [--timeout S] [--sample K] [--qhull OPTIONS] [--threads N]
Prints Markdown tables on stdout, progress on stderr.
"""

import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "python"))
import medial_solids as solids   # noqa: E402  (the test solids, one place)

TOL_FRAC = 0.005
TIMEOUT = 600.0                   # s per case
MEMORY_FRACTION = 0.5             # of physical memory, as each child's address-space limit
SIZES = [10_000, 30_000, 100_000, 300_000, 1_000_000]
QUICK_MAX = 100_000
SAMPLE = 4000                     # accuracy sample size (points)
SEED = 2022
TARGET_RATIO = 10.0
QHULL = "Qbb Qc QJ"               # the joggle instead of scipy's Qz (see the docstring)
NEAR_PLANE = 1e-9                 # x L: vertices this close to a crossed plane are dropped

CASES = {
    "cuboid": ("cuboid 100 x 60 x 20", solids.cuboid),
    "l_bracket": ("L-bracket 50 x 50 x 40, wall 10", solids.l_bracket),
    "t_section": ("T-section 60 x 60 x 40, wall 10", solids.t_section),
    "disc48": ("48-gon disc R 50, thickness 4", lambda: solids.ngon_disc(48)),
    "tray": ("ribbed tray 200 x 150 x 40, walls 3, 8 x 5 ribs", solids.ribbed_tray),
    "cup": ("cup R 20, h 30, wall 3, 625 segments (5000 triangles)", lambda: solids.cup(625)),
}


# ------------------------------------------------------------------ the peer
def sample_boundary(v, t, n, seed):
    """n area-weighted uniform points on the triangles (seeded), then the mesh vertices."""
    rng = np.random.default_rng(seed)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    k = rng.choice(len(t), size=n, p=area / area.sum())
    r1, r2 = rng.random(n), rng.random(n)
    flip = r1 + r2 > 1
    r1, r2 = np.where(flip, 1 - r1, r1), np.where(flip, 1 - r2, r2)
    pts = a[k] + r1[:, None] * (b[k] - a[k]) + r2[:, None] * (c[k] - a[k])
    return np.concatenate([pts, v])


class RayParity:
    """Inside test of points against a closed triangle mesh by the parity of the crossings
    of a ray from each point along a fixed direction d (near the coordinate axis that
    gives the fewest triangle-cell pairs, tilted by irrational amounts so no structured
    point or edge lines up with it).  The triangles are projected onto the plane normal
    to d and bucketed in a grid (the cells their projection may touch); a point is tested
    only against the triangles of its cell.  Each edge's line is one set of coefficients
    computed from its endpoints in index order (negated for the triangle that runs it
    backwards), so two triangles sharing an edge always disagree on which side a point
    is: a ray through a projected edge is counted once.  A point within `near` of a
    crossed triangle's plane is reported as undecided."""

    def __init__(self, v, t, near):
        v = np.asarray(v, float)
        t = np.asarray(t, np.int64)
        self.near = near
        best = None
        for axis in range(3):            # the estimated count of triangle-cell pairs
            d = np.roll([1e-3 * (math.sqrt(2) - 1), 1e-3 * (math.sqrt(3) - 1), 1.0], axis - 2)
            d /= np.linalg.norm(d)
            x = v[t] - (v[t] @ d)[..., None] * d
            area = 0.5 * np.linalg.norm(np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
            per = np.linalg.norm(x - np.roll(x, 1, axis=1), axis=2).sum(1)
            side = np.sqrt(np.prod(np.sort(np.ptp(v - (v @ d)[:, None] * d, axis=0))[1:])
                           / (4 * len(t)))
            cost = float((area / side ** 2 + per / side + 1).sum())
            if best is None or cost < best[0]:
                best = (cost, d)
        self.__dict__.update(self._grid(v, t, best[1]))

    @staticmethod
    def _grid(v, t, d):
        e1 = np.cross(d, np.roll(d, 1))
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(d, e1)                       # e1 x e2 = d
        q = np.c_[v @ e1, v @ e2]
        n = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
        nd = n @ d
        keep = nd != 0                             # edge-on triangles are never crossed
        t, n, nd = t[keep], n[keep], nd[keep]
        # edge k of a triangle: i0 -> i1; its line a x + b y + c from (lo, hi) in index
        # order, times the sign that makes it > 0 inside (projected area has nd's sign)
        i0, i1 = t, np.roll(t, -1, axis=1)
        lo, hi = q[np.minimum(i0, i1)], q[np.maximum(i0, i1)]
        s = np.where(i0 < i1, 1.0, -1.0) * np.sign(nd)[:, None]
        ea = -(hi[..., 1] - lo[..., 1])
        eb = hi[..., 0] - lo[..., 0]
        ec = -(ea * lo[..., 0] + eb * lo[..., 1])
        ea, eb, ec = ea * s, eb * s, ec * s
        tq = q[t]
        tlo, thi = tq.min(1), tq.max(1)
        glo = tlo.min(0)
        span = np.maximum(thi.max(0) - glo, 1e-300)
        g = int(min(2048, max(1, 2 * math.sqrt(len(t)))))
        cell = span / g
        # the cells each triangle touches, a row of cells at a time: the triangle's x-range
        # within the row's slab is that of its edges clipped to the slab (plus a slack)
        eps = 1e-9 * span.max()
        r0 = np.clip(np.floor((tlo[:, 1] - eps - glo[1]) / cell[1]).astype(np.int64), 0, g - 1)
        r1 = np.clip(np.floor((thi[:, 1] + eps - glo[1]) / cell[1]).astype(np.int64), 0, g - 1)
        nr = r1 - r0 + 1
        tri = np.repeat(np.arange(len(t)), nr)
        row = np.repeat(r0 - (np.cumsum(nr) - nr), nr) + np.arange(nr.sum())
        y0 = glo[1] + row * cell[1] - eps
        y1 = y0 + cell[1] + 2 * eps
        pa, pb = tq[tri], np.roll(tq, -1, axis=1)[tri]             # (k, 3, 2) edges
        ylo = np.maximum(y0[:, None], np.minimum(pa[..., 1], pb[..., 1]))
        yhi = np.minimum(y1[:, None], np.maximum(pa[..., 1], pb[..., 1]))
        dy = pb[..., 1] - pa[..., 1]
        with np.errstate(divide="ignore", invalid="ignore"):
            sl = np.where(dy != 0, (pb[..., 0] - pa[..., 0]) / dy, 0.0)
        xa = np.where(dy != 0, pa[..., 0] + (ylo - pa[..., 1]) * sl, pa[..., 0])
        xb = np.where(dy != 0, pa[..., 0] + (yhi - pa[..., 1]) * sl, pb[..., 0])
        cut = yhi >= ylo
        big = np.inf
        xmin = np.where(cut, np.minimum(xa, xb), big).min(1)
        xmax = np.where(cut, np.maximum(xa, xb), -big).max(1)
        has = xmax >= xmin
        tri, row, xmin, xmax = tri[has], row[has], xmin[has], xmax[has]
        c0 = np.clip(np.floor((xmin - eps - glo[0]) / cell[0]).astype(np.int64), 0, g - 1)
        c1 = np.clip(np.floor((xmax + eps - glo[0]) / cell[0]).astype(np.int64), 0, g - 1)
        cnt = c1 - c0 + 1
        cx = np.repeat(c0 - (np.cumsum(cnt) - cnt), cnt) + np.arange(cnt.sum())
        tri, key = np.repeat(tri, cnt), cx * g + np.repeat(row, cnt)
        order = np.argsort(key, kind="stable")
        return {"d": d, "e1": e1, "e2": e2, "ea": ea, "eb": eb, "ec": ec,
                "a3": v[t[:, 0]], "n": n, "nd": nd,
                "unit_n": n / np.linalg.norm(n, axis=1)[:, None], "glo": glo, "g": g,
                "cell": cell, "cell_tris": tri[order],
                "cell_start": np.searchsorted(key[order], np.arange(g * g + 1))}

    def __call__(self, p, budget=4_000_000):
        """(inside (m,) bool, undecided (m,) bool) for points p (m, 3)."""
        p = np.asarray(p, float)
        inside = np.zeros(len(p), bool)
        undecided = np.zeros(len(p), bool)
        qx, qy = p @ self.e1, p @ self.e2
        cx = np.floor((qx - self.glo[0]) / self.cell[0]).astype(np.int64)
        cy = np.floor((qy - self.glo[1]) / self.cell[1]).astype(np.int64)
        ok = (cx >= 0) & (cx < self.g) & (cy >= 0) & (cy < self.g)
        key = np.where(ok, cx * self.g + cy, 0)
        cnt = np.where(ok, self.cell_start[key + 1] - self.cell_start[key], 0)
        ends = np.cumsum(cnt)
        s = 0
        while s < len(p):
            e = max(s + 1, int(np.searchsorted(ends, (ends[s - 1] if s else 0) + budget,
                                               "right")))
            cn = cnt[s:e]
            tot = int(cn.sum())
            if tot:
                pi = np.repeat(np.arange(s, e), cn)
                ti = self.cell_tris[np.repeat(self.cell_start[key[s:e]] - (np.cumsum(cn) - cn),
                                              cn) + np.arange(tot)]
                for k in range(3):                 # an edge at a time, on the survivors
                    px, py = qx[pi], qy[pi]
                    w = self.ea[ti, k] * px + self.eb[ti, k] * py + self.ec[ti, k]
                    pi, ti = pi[w > 0], ti[w > 0]
                a = self.a3[ti] - p[pi]
                h = np.einsum("ij,ij->i", self.unit_n[ti], a)
                ahead = np.einsum("ij,ij->i", self.n[ti], a) / self.nd[ti] > 0
                inside[s:e] = (np.bincount(pi[ahead] - s, minlength=e - s) % 2).astype(bool)
                close = np.abs(h) <= self.near
                if close.any():
                    undecided[pi[close]] = True
            s = e
        return inside, undecided


def peer(v, t, n, seed=SEED, qhull=QHULL):
    """The Voronoi approximation: (kept vertices (k, 3), radii (k,), stats).  Timed by the
    caller from sampling to radii."""
    import itertools
    from scipy.spatial import Voronoi
    L = float(np.linalg.norm(v.max(0) - v.min(0)))
    st = {}
    t0 = time.perf_counter()
    S = sample_boundary(v, t, n, seed)
    t1 = time.perf_counter()
    vor = Voronoi(S, qhull_options=qhull or None)
    X = vor.vertices
    t2 = time.perf_counter()
    # a generating sample of each vertex: the first point of any ridge holding it
    rv = vor.ridge_vertices
    lens = np.fromiter(map(len, rv), np.int64, count=len(rv))
    flat = np.fromiter(itertools.chain.from_iterable(rv), np.int64, count=int(lens.sum()))
    owner = np.repeat(vor.ridge_points[:, 0], lens)
    gen = np.full(len(X), -1, np.int64)
    gen[flat[flat >= 0]] = owner[flat >= 0]
    del vor, rv, flat, owner
    t3 = time.perf_counter()
    st["voronoi_vertices"] = int(len(X))
    lo, hi = v.min(0), v.max(0)
    box = ((X > lo) & (X < hi)).all(1) & (gen >= 0)
    X, gen = X[box], gen[box]
    st["in_box"] = int(len(X))
    rp = RayParity(v, t, NEAR_PLANE * L)
    inside, undecided = rp(X)
    cand = X
    keep = inside & ~undecided
    X = X[keep]
    st["undecided"] = int(undecided.sum())
    t4 = time.perf_counter()
    r = np.linalg.norm(X - S[gen[keep]], axis=1)
    t5 = time.perf_counter()
    st.update({"samples": int(len(S)), "kept": int(len(X)), "sample_s": t1 - t0,
               "voronoi_s": t2 - t1, "inside_s": t4 - t3, "radius_s": (t3 - t2) + (t5 - t4)})
    return X, r, st, (cand, inside, undecided)


# ------------------------------------------------------------------ accuracy helpers
def _q(x):
    x = np.asarray(x, float)
    if not len(x):
        return None
    return [float(np.median(x)), float(np.percentile(x, 95)), float(x.max())]


def sheet_points(res, k, seed):
    """k area-weighted uniform points on the sheets of a medial result."""
    tris = [np.asarray(s.vertices, float)[np.asarray(s.triangles, np.int64)]
            for s in res.sheets if len(s.triangles)]
    if not tris:
        return np.zeros((0, 3))
    T = np.concatenate(tris)
    area = 0.5 * np.linalg.norm(np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]), axis=1)
    rng = np.random.default_rng(seed)
    i = rng.choice(len(T), size=k, p=area / area.sum())
    r1, r2 = rng.random(k), rng.random(k)
    flip = r1 + r2 > 1
    r1, r2 = np.where(flip, 1 - r1, r1), np.where(flip, 1 - r2, r2)
    return T[i, 0] + r1[:, None] * (T[i, 1] - T[i, 0]) + r2[:, None] * (T[i, 2] - T[i, 0])


def to_pieces(X, pieces, L, tol):
    """Exact distance of X to the pieces (triangles, segments, points) of our result."""
    from medial_oracle import distance_to_pieces
    d = distance_to_pieces(X, *pieces, 4 * tol)
    far = ~np.isfinite(d)
    if far.any():
        d[far] = distance_to_pieces(X[far], *pieces, L)
    return d


# ------------------------------------------------------------------ the children
def _child_ours(spec, out):
    from mfgeom import core
    from medial_oracle import Polyhedron, result_pieces
    name, full, threads, nsample, pieces_path = spec
    v, t = CASES[name][1]()
    L = float(np.linalg.norm(v.max(0) - v.min(0)))
    tol = TOL_FRAC * L
    kw = {"major_only": not full}
    if threads is not None:
        kw["threads"] = threads
    row = {"library": core.version(), "L": L, "tol": tol}
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    try:
        t0 = time.perf_counter()
        res = core.medial_surface(v, t, tol, **kw)
        row["s"] = time.perf_counter() - t0
    except core.MfgError as exc:
        row["error"] = str(exc)
        res = None
    row["peak_mb"] = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - rss0) / 1024.0
    row["load"] = os.getloadavg()[0]
    if res is not None and not full:
        np.savez(pieces_path, on_sheets=sheet_points(res, nsample, SEED + 1))
    if res is not None:
        row.update({"sheets": len(res.sheets),
                    "sheet_triangles": int(sum(len(s.triangles) for s in res.sheets)),
                    "seams": len(res.seams),
                    "junctions": int(len(np.asarray(res.junctions.points).reshape(-1, 3)))})
    if res is not None and full:
        # our radius error on a sample of sheet vertices, every seam point and junction
        rng = np.random.default_rng(SEED)
        X = np.concatenate([np.asarray(s.vertices, float).reshape(-1, 3) for s in res.sheets])
        r = np.concatenate([np.asarray(s.radii, float) for s in res.sheets])
        pick = rng.permutation(len(X))[:nsample]
        X = np.concatenate([X[pick]] + [np.asarray(c.points, float).reshape(-1, 3)
                                        for c in res.seams]
                           + [np.asarray(res.junctions.points, float).reshape(-1, 3)])
        r = np.concatenate([r[pick]] + [np.asarray(c.radii, float) for c in res.seams]
                           + [np.asarray(res.junctions.radii, float)])
        if len(X) > 2 * nsample:                     # many seams (the cup): sample them too
            pick = rng.permutation(len(X))[:2 * nsample]
            X, r = X[pick], r[pick]
        P = Polyhedron(v, t)
        row["radius_err"] = _q(np.abs(P.distance(X) - r))
        row["radius_points"] = int(len(X))
        tris, segs, pts = result_pieces(res)
        # zero-area (collinear) sheet triangles make the oracle's point-triangle distance
        # 0/0 = NaN (and a NaN hides the triangles tested with it): they go in as their edges
        flat = np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]),
                              axis=1) == 0
        row["flat_sheet_triangles"] = int(flat.sum())
        if flat.any():
            f = tris[flat]
            edges = np.stack([f, np.roll(f, -1, axis=1)], 2).reshape(-1, 2, 3)
            segs = np.concatenate([segs, edges])
            tris = tris[~flat]
        np.savez(pieces_path, tris=tris, segs=segs, pts=pts,
                 on_sheets=sheet_points(res, nsample, SEED + 1))
    with open(out, "w") as f:
        json.dump(row, f)


def _child_peer(spec, out):
    name, n, nsample, pieces_path, major_path, qhull = spec
    row = {"n": n}
    try:
        v, t = CASES[name][1]()
        L = float(np.linalg.norm(v.max(0) - v.min(0)))
        tol = TOL_FRAC * L
        rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        t0 = time.perf_counter()
        X, r, st, (cand, inside, undecided) = peer(v, t, n, qhull=qhull)
        row["s"] = time.perf_counter() - t0
        row["peak_mb"] = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - rss0) / 1024.0
        row.update(st)
    except MemoryError:
        row["error"] = "out of memory"
        row["oom"] = True
    except Exception as exc:                     # Qhull errors among them
        msg = str(exc).strip().splitlines()
        row["error"] = f"{type(exc).__name__}: {msg[0] if msg else ''}"
        if "memory" in str(exc).lower():
            row["error"], row["oom"] = "out of memory (Qhull)", True
    if "error" in row:
        with open(out, "w") as f:
            json.dump(row, f)
        return
    # ---- accuracy, not timed
    from medial_oracle import Polyhedron
    from scipy.spatial import cKDTree
    P = Polyhedron(v, t)
    rng = np.random.default_rng(SEED + 2)
    pick = rng.permutation(len(X))[:nsample]
    Xs, rs = X[pick], r[pick]
    D = P.distance(Xs)
    row["radius_err"] = _q(np.abs(rs - D))
    row["depth"] = _q(D / tol)                   # how deep the kept vertices sit, in tol
    z = np.load(pieces_path)
    pieces = (z["tris"], z["segs"], z["pts"])
    if len(pieces[0]) + len(pieces[1]) + len(pieces[2]):
        d = to_pieces(Xs, pieces, L, tol)
        row["peer_to_ours"] = _q(d)
        row["peer_within_tol"] = float((d <= tol).mean())
    tree = cKDTree(X) if len(X) else None
    for key, path in (("ours_to_peer", pieces_path), ("major_to_peer", major_path)):
        on = np.load(path)["on_sheets"] if os.path.exists(path) else np.zeros((0, 3))
        if tree is not None and len(on):
            row[key] = _q(tree.query(on, workers=-1)[0])
    # the ray parity against the oracle's winding number, on candidates off the boundary
    pick = rng.permutation(len(cand))[:min(nsample, 500)]
    C = cand[pick]
    Dc = P.distance(C)
    off = Dc > 1e-6 * L
    wind = P.inside(C[off])
    mine = inside[pick][off] & ~undecided[pick][off]
    row["parity_checked"] = int(off.sum())
    row["parity_disagree"] = int((wind != mine).sum())
    row["load"] = os.getloadavg()[0]
    with open(out, "w") as f:
        json.dump(row, f)


# ------------------------------------------------------------------ the driver
def _cap_memory():
    total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    cap = int(total * MEMORY_FRACTION)
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))


def run_child(kind, spec, env, out, timeout):
    cenv = dict(env, MFGEOM_BENCH_VORONOI_CHILD=json.dumps([kind, spec, out]))
    t0 = time.perf_counter()
    try:
        r = subprocess.run([sys.executable, os.path.abspath(__file__)], env=cenv,
                           capture_output=True, text=True, check=False, timeout=timeout,
                           preexec_fn=_cap_memory)
    except subprocess.TimeoutExpired:
        return {"error": f"stopped after {timeout:g} s", "timed_out": True}
    wall = time.perf_counter() - t0
    if r.returncode != 0 or not os.path.exists(out):
        err = r.stderr.strip()
        tail = (err.splitlines() or [f"exit status {r.returncode}"])[-1]
        if ("MemoryError" in err or "memory" in tail.lower() or "bad_alloc" in err
                or r.returncode in (-6, -11) and "alloc" in err.lower()):
            return {"error": "out of memory", "oom": True, "wall": wall}
        return {"error": f"child failed (exit {r.returncode}): {tail}", "wall": wall}
    with open(out) as f:
        row = json.load(f)
    row["wall"] = wall
    return row


def _fs(x):
    if x is None:
        return "-"
    return f"{x:.3f}" if x < 10 else f"{x:.1f}"


def _fe(q, k=1):
    return "-" if not q else f"{q[k]:.2g}"


def _pair(q):
    return "-" if not q else f"{q[1]:.2g} / {q[2]:.2g}"


def _n(n):
    e = int(round(math.log10(n)))
    k = int(math.log10(n))
    return f"10^{e}" if n == 10 ** e else f"{n / 10 ** k:g}·10^{k}"


CRITERIA = [
    ("N*", "95th percentiles of peer -> ours and of the radius error within tol"),
    ("N**", "N* and the 95th percentile of ours (major) -> peer within tol"),
    ("N-max", "N** and the largest radius error and ours (major) -> peer within tol"),
]


def _meets(r, tol, level):
    """Whether a peer row meets criterion `level` (0, 1, 2 of CRITERIA)."""
    def at(key, k):
        return r.get(key) is not None and r[key][k] <= tol
    ok = at("peer_to_ours", 1) and at("radius_err", 1)
    if level >= 1:
        ok = ok and at("major_to_peer", 1)
    if level >= 2:
        ok = ok and at("radius_err", 2) and at("major_to_peer", 2)
    return bool(ok)


def main():
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help=f"sizes up to {QUICK_MAX}")
    ap.add_argument("--only", default=None, help="comma-separated solids: " + ",".join(CASES))
    ap.add_argument("--sizes", default=None, help="comma-separated sample counts N")
    ap.add_argument("--full-for", default="",
                    help="comma-separated solids that get every size even with --quick")
    ap.add_argument("--timeout", type=float, default=TIMEOUT, help="seconds per case")
    ap.add_argument("--sample", type=int, default=SAMPLE, help="accuracy sample size")
    ap.add_argument("--qhull", default=QHULL,
                    help=f"Qhull options of the peer's Voronoi (default {QHULL!r}; '' = scipy's)")
    ap.add_argument("--threads", type=int, default=None,
                    help="threads for the library (default: its own, all online CPUs)")
    args = ap.parse_args()
    names = args.only.split(",") if args.only else list(CASES)
    for nm in names:
        if nm not in CASES:
            ap.error(f"unknown solid {nm!r} (one of {', '.join(CASES)})")
    sizes = [int(float(s)) for s in args.sizes.split(",")] if args.sizes else SIZES
    full_for = set(filter(None, args.full_for.split(",")))
    env = dict(os.environ)
    env.setdefault("MFGEOM_LIBRARY", os.path.join(ROOT, "build", "libmfgeom.so"))
    env["PYTHONPATH"] = os.path.join(ROOT, "workbench")
    ours, peers = {}, {}
    t_start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="mfgeom-bench-voronoi-") as tmp:
        for nm in names:
            pieces = os.path.join(tmp, f"{nm}-pieces.npz")
            major = os.path.join(tmp, f"{nm}-major.npz")
            for full in (True, False):
                out = os.path.join(tmp, f"{nm}-ours-{int(full)}.json")
                ours[(nm, full)] = run_child("ours", [nm, full, args.threads, args.sample,
                                                      pieces if full else major],
                                             env, out, args.timeout)
                r = ours[(nm, full)]
                print(f"bench_medial_voronoi: {nm} ours {'full' if full else 'major'}: "
                      f"{r.get('s')} s ({r.get('wall', 0):.1f} s wall) {r.get('error', '')}",
                      file=sys.stderr, flush=True)
            peers[nm] = []
            if not os.path.exists(pieces):
                continue
            failed = None
            for n in sizes:
                if args.quick and n > QUICK_MAX and nm not in full_for:
                    continue
                if failed:
                    peers[nm].append({"n": n, "error": f"not run ({failed})"})
                    continue
                out = os.path.join(tmp, f"{nm}-peer-{n}.json")
                r = run_child("peer", [nm, n, args.sample, pieces, major, args.qhull], env,
                              out, args.timeout)
                r["n"] = n
                peers[nm].append(r)
                print(f"bench_medial_voronoi: {nm} peer N={n}: {r.get('s')} s "
                      f"({r.get('wall', 0):.1f} s wall) {r.get('error', '')}",
                      file=sys.stderr, flush=True)
                if r.get("error"):
                    failed = f"{_n(n)} failed"
    _print(names, ours, peers, args, time.perf_counter() - t_start)
    return 0


def _print(names, ours, peers, args, total):
    lib = next((r["library"] for r in ours.values() if r.get("library")), "?")
    load = " / ".join(f"{x:.1f}" for x in os.getloadavg())
    thr = args.threads if args.threads is not None else "default (online CPUs)"
    print("## Medial surface against the Voronoi approximation (bench_medial_voronoi.py)\n")
    print(f"Peer: N area-weighted boundary samples + the mesh vertices, scipy.spatial.Voronoi "
          f"(Qhull options {args.qhull or 'scipy default'!r}), the vertices inside the solid "
          "(ray parity), radius = distance to a generating sample (= the nearest); its time "
          "covers sampling, "
          "Voronoi, filtering and radii. Ours: "
          f"mfgeom.core.medial_surface (libmfgeom {lib}; threads: {thr}), full medial surface "
          f"(major part in brackets), tolerance tol = {TOL_FRAC * 100:g} % of the bounding-box "
          "diagonal. Each case in a fresh python, one timed run. Accuracy on seeded samples "
          f"of {args.sample} points against the oracle's exact point-to-triangle distance "
          "(tests/python/medial_oracle.py): radius error abs(r - D); peer -> ours = distance "
          "of kept Voronoi vertices to our full medial surface (sheets, seams, junctions); "
          "ours -> peer = distance of area-weighted points on our major (full) sheets to the "
          "nearest kept Voronoi vertex; each as 95th percentile / max. Load average at the "
          f"end: {load} on {os.cpu_count()} CPUs; total {total:.0f} s.\n")
    print("| solid | tol | N | Voronoi vertices / kept | peer s | ours full s (major) | "
          "peer / ours full (major) | peer radius err | our radius err | peer -> ours | "
          "ours (major) -> peer | ours (full) -> peer | peer vertices within tol of ours |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for nm in names:
        of, om = ours[(nm, True)], ours[(nm, False)]
        tol = of.get("tol") or om.get("tol")
        sf, sm = of.get("s"), om.get("s")
        otxt = (f"{_fs(sf)} ({_fs(sm) if sm else om.get('error')})" if sf
                else f"failed: {of.get('error')}")
        if not peers[nm]:
            print(f"| {nm} | {_fg(tol)} | - | | | {otxt} | | | | | | | |")
        for r in peers[nm]:
            if r.get("error"):
                print(f"| {nm} | {_fg(tol)} | {_n(r['n'])} | | {r['error']} | {otxt} | | | "
                      f"{_pair(of.get('radius_err'))} | | | | |")
                continue
            ratio = (f"{r['s'] / sf:.2g} ({r['s'] / sm:.2g})" if sf and sm else "-")
            print(f"| {nm} | {_fg(tol)} | {_n(r['n'])} | {r['voronoi_vertices']} / {r['kept']} | "
                  f"{_fs(r['s'])} | {otxt} | {ratio} | "
                  f"{_pair(r.get('radius_err'))} | {_pair(of.get('radius_err'))} | "
                  f"{_pair(r.get('peer_to_ours'))} | {_pair(r.get('major_to_peer'))} | "
                  f"{_pair(r.get('ours_to_peer'))} | {_fpct(r.get('peer_within_tol'))} |")

    print("\nOurs: time, growth of ru_maxrss, sheets / sheet triangles, zero-area sheet "
          "triangles (full mode; measured as their edges), 1-minute load average after the "
          "call:\n")
    print("| solid | mode | s | peak MB | sheets / triangles | zero-area triangles | load |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for nm in names:
        for full in (True, False):
            o = ours[(nm, full)]
            mode = "full" if full else "major"
            if o.get("s") is None:
                print(f"| {nm} | {mode} | {o.get('error')} | | | | |")
                continue
            print(f"| {nm} | {mode} | {_fs(o['s'])} | {o['peak_mb']:.0f} | "
                  f"{o.get('sheets')} / {o.get('sheet_triangles')} | "
                  f"{o.get('flat_sheet_triangles', '-') if full else ''} | {o['load']:.1f} |")

    print("\nPeer: time split (s) sampling / Voronoi / inside test / radii (generators and "
          "distances), growth of "
          "ru_maxrss, 1-minute load average after the case, vertices left undecided by the "
          "ray parity (within 1e-9 L of a plane), ray parity against the oracle's winding "
          "number (disagreements of candidates checked), depth D / tol of the kept vertices "
          "(median / 95 % / max):\n")
    print("| solid | N | sampling | Voronoi | inside | radii | peak MB | load | undecided | "
          "parity vs winding | depth / tol |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for nm in names:
        for r in peers[nm]:
            if r.get("error"):
                continue
            dq = r.get("depth")
            print(f"| {nm} | {_n(r['n'])} | {r['sample_s']:.2f} | {r['voronoi_s']:.2f} | "
                  f"{r['inside_s']:.2f} | {r['radius_s']:.2f} | {r['peak_mb']:.0f} | "
                  f"{r['load']:.1f} | {r['undecided']} | "
                  f"{r.get('parity_disagree')} of {r.get('parity_checked')} | "
                  f"{'-' if not dq else f'{dq[0]:.2g} / {dq[1]:.2g} / {dq[2]:.2g}'} |")

    print("\n### Equal accuracy\n")
    for key, what in CRITERIA:
        print(f"- {key}: the smallest N with {what};")
    print("\nratio = the peer's time at that N / our time, full (major in brackets); a peer "
          "that never met the criterion shows its largest N's time as a lower bound. "
          f"Target (issue 22): ours >= {TARGET_RATIO:g}x faster.\n")
    print("| solid | tol | " + " | ".join(f"{k} | peer s | ratio" for k, _ in CRITERIA) + " |")
    print("|---|---:|" + "---:|---:|---:|" * len(CRITERIA))
    met = total_cmp = 0
    for nm in names:
        of, om = ours[(nm, True)], ours[(nm, False)]
        sf, sm, tol = of.get("s"), om.get("s"), of.get("tol")
        done = [q for q in peers[nm] if not q.get("error")]
        if not sf or not sm or not done:
            print(f"| {nm} | {_fg(tol)} | " + " | ".join(["-"] * 3 * len(CRITERIA)) + " |")
            continue
        cells = []
        for level in range(len(CRITERIA)):
            r = next((q for q in done if _meets(q, tol, level)), None)
            if r is None:
                last = done[-1]
                cells += [f"not met (≤ {_n(last['n'])})", f"> {_fs(last['s'])}",
                          f"> {last['s'] / sf:.2g} (> {last['s'] / sm:.2g})"]
                ratio = last["s"] / sf
            else:
                cells += [_n(r["n"]), _fs(r["s"]), f"{r['s'] / sf:.2g} ({r['s'] / sm:.2g})"]
                ratio = r["s"] / sf
            if level == 0:
                total_cmp += 1
                met += ratio >= TARGET_RATIO
        print(f"| {nm} | {tol:.3g} | " + " | ".join(cells) + " |")
    print(f"\nOurs (full) >= {TARGET_RATIO:g}x faster than the peer at N*: {met} of {total_cmp} "
          "solids.")


def _fg(x):
    return "-" if x is None else f"{x:.3g}"


def _fpct(x):
    return "-" if x is None else f"{100 * x:.1f} %"


if os.environ.get("MFGEOM_BENCH_VORONOI_CHILD"):
    _kind, _spec, _out = json.loads(os.environ["MFGEOM_BENCH_VORONOI_CHILD"])
    (_child_ours if _kind == "ours" else _child_peer)(_spec, _out)
elif __name__ == "__main__":
    sys.exit(main())
