# SPDX-License-Identifier: LGPL-2.1-or-later
"""Independent oracle for the 3-D medial surface (issue 9 section 5; design section 7).
Numpy only; written from the issue and the design notes, sharing no code with (and
without reading) libcore's medial_*.c.

- Polyhedron(vertices, triangles): its own merge of edge-adjacent coplanar triangles into
  faces; the elements of the merged polyhedron are its faces, its edges (maximal chains of
  mesh edges between the same two faces) and its vertices (the chains' ends), each with
  the set of mesh vertices of its closure (two elements are *adjacent* when their closures
  meet, i.e. these sets intersect).
- distance(P): vectorised point-triangle distances (Ericson, Real-Time Collision
  Detection 5.1.5) with the nearest triangle feature mapped to the element whose relative
  interior holds the nearest point.
- inside(P): winding number (sum of solid angles, Van Oosterom & Strackee).
- touching(P, eps): the elements e whose closed restricted distance (distance to e's
  carrier, counted only when the carrier foot lies in e's closure up to a slack) is within
  D(P) + eps.
- probes(n, margin): the completeness probe: area-weighted boundary points q farther than
  `margin` from the edges of the merged faces; bisection of g(t) = D(q - t n) - t (n the
  outward normal) for its largest zero t*; x* = q - t* n is medial.  x* lies on the major
  part when two of its touching elements are not adjacent.
- distance_to_result(P, result): distance to the union of a result's sheet triangles,
  seam polylines and junction points.
"""
import math

import numpy as np

# --------------------------------------------------------------------- point-triangle


def closest_on_triangles(P, A, B, C):
    """Ericson's closest point of each point P (m, 3) on each triangle (A, B, C) (n, 3)
    (or of P[i, j] (m, n, 3) on triangle j):
    returns (d (m, n) distance, region (m, n) int8): 0 interior, 1/2/3 vertex A/B/C,
    4/5/6 edge AB/BC/CA.  The distance is computed from the region's own carrier
    (plane, line or point) rather than by subtracting the closest point, which keeps it
    accurate to a few ulps of its size."""
    P = np.asarray(P, float)
    P = P[:, None, :] if P.ndim == 2 else P         # or (m, n, 3): a point per pair
    A, B, C = (np.asarray(q, float)[None] for q in (A, B, C))
    ab, ac, ap = B - A, C - A, P - A
    d1 = np.einsum("mnk,mnk->mn", np.broadcast_to(ab, ap.shape), ap)
    d2 = np.einsum("mnk,mnk->mn", np.broadcast_to(ac, ap.shape), ap)
    bp = P - B
    d3 = np.einsum("mnk,mnk->mn", np.broadcast_to(ab, bp.shape), bp)
    d4 = np.einsum("mnk,mnk->mn", np.broadcast_to(ac, bp.shape), bp)
    cp = P - C
    d5 = np.einsum("mnk,mnk->mn", np.broadcast_to(ab, cp.shape), cp)
    d6 = np.einsum("mnk,mnk->mn", np.broadcast_to(ac, cp.shape), cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    region = np.zeros(va.shape, np.int8)
    # the tests in Ericson's order; the first that holds wins
    conds = [
        (d1 <= 0) & (d2 <= 0),                                  # A
        (d3 >= 0) & (d4 <= d3),                                 # B
        (vc <= 0) & (d1 >= 0) & (d3 <= 0),                      # AB
        (d6 >= 0) & (d5 <= d6),                                 # C
        (vb <= 0) & (d2 >= 0) & (d6 <= 0),                      # CA
        (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0),        # BC
    ]
    codes = [1, 2, 4, 3, 6, 5]
    done = np.zeros(va.shape, bool)
    for cond, code in zip(conds, codes):
        hit = cond & ~done
        region[hit] = code
        done |= hit

    def point_dist(Q):
        return np.sqrt(np.einsum("mnk,mnk->mn", P - Q, P - Q))

    def line_dist(Q, R):
        u = np.broadcast_to(R - Q, np.broadcast_shapes(P.shape, (R - Q).shape))
        x = np.cross(P - Q, u)
        return np.sqrt(np.einsum("mnk,mnk->mn", x, x) / np.einsum("mnk,mnk->mn", u, u))

    n = np.cross(ab, ac)
    nn = np.sqrt(np.einsum("mnk,mnk->mn", n, n))
    d = np.abs(np.einsum("mnk,mnk->mn", np.broadcast_to(n, ap.shape), ap)) / nn
    for code, fn in ((1, lambda: point_dist(A)), (2, lambda: point_dist(B)),
                     (3, lambda: point_dist(C)), (4, lambda: line_dist(A, B)),
                     (5, lambda: line_dist(B, C)), (6, lambda: line_dist(C, A))):
        m = region == code
        if m.any():
            d = np.where(m, fn(), d)
    return d, region


def point_segment_distance(P, A, B):
    """(m, n): distance of points P (m, 3) to segments A -> B (n, 3)."""
    P = np.asarray(P, float)[:, None, :]
    A, B = np.asarray(A, float)[None], np.asarray(B, float)[None]
    d = B - A
    dd = np.einsum("mnk,mnk->mn", np.broadcast_to(d, (P.shape[0],) + d.shape[1:]),
                   np.broadcast_to(d, (P.shape[0],) + d.shape[1:]))
    t = np.einsum("mnk,mnk->mn", P - A, np.broadcast_to(d, (P.shape[0],) + d.shape[1:]))
    t = np.clip(t / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    r = P - A - t[..., None] * d
    return np.sqrt(np.einsum("mnk,mnk->mn", r, r))


def _chunks(m, n, budget=400_000):
    step = max(1, budget // max(1, n))
    return range(0, m, step), step


# --------------------------------------------------------------------- the polyhedron


class Polyhedron:
    """The merged polyhedron of a closed, outward-oriented triangle mesh."""

    def __init__(self, vertices, triangles, angle_tol=1e-7):
        V = np.asarray(vertices, float)
        T = np.asarray(triangles, np.int64)
        self.V, self.T = V, T
        a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
        n = np.cross(b - a, c - a)
        area2 = np.linalg.norm(n, axis=1)
        if not (area2 > 0).all():
            raise ValueError("the oracle takes no zero-area triangles")
        self.normals = n / area2[:, None]
        self.areas = area2 / 2
        lo, hi = V.min(0), V.max(0)
        self.diag = float(np.linalg.norm(hi - lo))
        # ---- manifold check and the triangle adjacency across each mesh edge
        half = {}
        for t, tri in enumerate(T):
            for k in range(3):
                u, w = int(tri[k]), int(tri[(k + 1) % 3])
                if (u, w) in half:
                    raise ValueError(f"edge {u}-{w} used twice in one direction")
                half[(u, w)] = t
        self._edge_tris = {}
        for (u, w), t in half.items():
            if (w, u) not in half:
                raise ValueError(f"open or inconsistently oriented at edge {u}-{w}")
            if u < w:
                self._edge_tris[(u, w)] = (t, half[(w, u)])
        # ---- faces: union-find over edge neighbours with the same normal
        parent = list(range(len(T)))

        def find(x):
            while parent[x] != x:
                parent[x] = parent[parent[x]]
                x = parent[x]
            return x

        cos_tol = math.cos(angle_tol)
        for (u, w), (t1, t2) in self._edge_tris.items():
            if float(self.normals[t1] @ self.normals[t2]) >= cos_tol:
                r1, r2 = find(t1), find(t2)
                if r1 != r2:
                    parent[max(r1, r2)] = min(r1, r2)
        roots = [find(t) for t in range(len(T))]
        ids = {}
        self.tri_face = np.array([ids.setdefault(r, len(ids)) for r in roots], np.int64)
        self.nfaces = len(ids)
        nf = self.nfaces
        self.face_tris = [np.nonzero(self.tri_face == f)[0] for f in range(nf)]
        self.face_normal = np.array([
            (self.normals[tt] * self.areas[tt, None]).sum(0) /
            np.linalg.norm((self.normals[tt] * self.areas[tt, None]).sum(0))
            for tt in self.face_tris])
        self.face_offset = np.array([float(self.face_normal[f] @ V[T[self.face_tris[f][0], 0]])
                                     for f in range(nf)])
        self.face_area = np.array([self.areas[tt].sum() for tt in self.face_tris])
        # ---- feature edges (between two faces), chained into edge elements
        feat = {}                                      # mesh edge -> (face pair)
        vert_feat = {}                                 # mesh vertex -> its feature edges
        for (u, w), (t1, t2) in self._edge_tris.items():
            f1, f2 = int(self.tri_face[t1]), int(self.tri_face[t2])
            if f1 != f2:
                feat[(u, w)] = (min(f1, f2), max(f1, f2))
                vert_feat.setdefault(u, []).append((u, w))
                vert_feat.setdefault(w, []).append((u, w))

        def is_corner(v):
            es = vert_feat.get(v, [])
            return len(es) != 2 or feat[es[0]] != feat[es[1]]

        corners = sorted(v for v in vert_feat if is_corner(v))
        seen = set()
        chains = []                                    # (face pair, [mesh vertices])
        for v0 in corners:
            for e in vert_feat[v0]:
                if e in seen:
                    continue
                path, v, cur = [v0], v0, e
                while True:
                    seen.add(cur)
                    v = cur[1] if cur[0] == v else cur[0]
                    path.append(v)
                    if is_corner(v):
                        break
                    nxt = [x for x in vert_feat[v] if x not in seen]
                    cur = nxt[0]
                chains.append((feat[e], path))
        if len(seen) != len(feat):
            raise ValueError("a crease loop without corners (not a planar-faced solid)")
        self.nedges = len(chains)
        self.nverts = len(corners)
        self.nelements = nf + self.nedges + self.nverts
        self.kinds = np.array(["F"] * nf + ["E"] * self.nedges + ["V"] * self.nverts)
        self.edge_pairs = np.array([p for p, _ in chains], np.int64).reshape(-1, 2)
        self.edge_A = np.array([V[path[0]] for _, path in chains]).reshape(-1, 3)
        self.edge_B = np.array([V[path[-1]] for _, path in chains]).reshape(-1, 3)
        self.vert_mesh = np.array(corners, np.int64)
        self.vert_P = V[self.vert_mesh].reshape(-1, 3)
        # convex edge: the second face's far vertex lies strictly inside the first's plane
        self.edge_convex = np.zeros(self.nedges, bool)
        for i, ((f1, f2), path) in enumerate(chains):
            u, w = path[0], path[1]
            t1, t2 = self._edge_tris[(min(u, w), max(u, w))]
            if self.tri_face[t1] != f1:
                t1, t2 = t2, t1
            far = [x for x in T[t2] if x not in (u, w)][0]
            self.edge_convex[i] = float(self.normals[t1] @ (V[far] - V[u])) < 0
        # element closures as mesh-vertex sets; feature maps for the nearest element
        self.closure = [set(T[tt].ravel().tolist()) for tt in self.face_tris]
        self.closure += [set(path) for _, path in chains]
        self.closure += [{int(v)} for v in corners]
        self.mesh_edge_elem = {}
        self.mesh_vertex_elem = {}
        for i, (_, path) in enumerate(chains):
            for p, q in zip(path[:-1], path[1:]):
                self.mesh_edge_elem[(min(p, q), max(p, q))] = nf + i
            for p in path[1:-1]:
                self.mesh_vertex_elem[p] = nf + i
        for j, v in enumerate(corners):
            self.mesh_vertex_elem[v] = nf + self.nedges + j

    # -------------------------------------------------------------- queries
    def adjacent(self, e1, e2):
        """Closures of the two elements meet (they share a mesh vertex)."""
        return bool(self.closure[e1] & self.closure[e2])

    def distance(self, P, with_element=False):
        """Distance of points P (m, 3) to the boundary; with_element: also the element
        whose relative interior holds the nearest point (ties: the first triangle)."""
        P = np.asarray(P, float).reshape(-1, 3)
        V, T = self.V, self.T
        A, B, C = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
        d = np.empty(len(P))
        tri = np.empty(len(P), np.int64)
        reg = np.empty(len(P), np.int8)
        rng, step = _chunks(len(P), len(T))
        for s in rng:
            dd, rr = closest_on_triangles(P[s:s + step], A, B, C)
            k = dd.argmin(axis=1)
            d[s:s + step] = dd[np.arange(len(k)), k]
            tri[s:s + step] = k
            reg[s:s + step] = rr[np.arange(len(k)), k]
        if not with_element:
            return d
        elem = np.empty(len(P), np.int64)
        for i, (t, r) in enumerate(zip(tri, reg)):
            f = int(self.tri_face[t])
            if r == 0:
                elem[i] = f
            elif r <= 3:
                elem[i] = self.mesh_vertex_elem.get(int(T[t, r - 1]), f)
            else:
                k = r - 4
                u, w = int(T[t, k]), int(T[t, (k + 1) % 3])
                elem[i] = self.mesh_edge_elem.get((min(u, w), max(u, w)), f)
        return d, elem

    def inside(self, P):
        """Winding number > 1/2 (solid angles of all triangles seen from each point)."""
        P = np.asarray(P, float).reshape(-1, 3)
        V, T = self.V, self.T
        out = np.empty(len(P))
        rng, step = _chunks(len(P), len(T))
        for s in rng:
            a = V[T[:, 0]][None] - P[s:s + step, None]
            b = V[T[:, 1]][None] - P[s:s + step, None]
            c = V[T[:, 2]][None] - P[s:s + step, None]
            la, lb, lc = (np.linalg.norm(q, axis=2) for q in (a, b, c))
            num = np.einsum("mnk,mnk->mn", a, np.cross(b, c))
            den = (la * lb * lc + np.einsum("mnk,mnk->mn", a, b) * lc
                   + np.einsum("mnk,mnk->mn", a, c) * lb + np.einsum("mnk,mnk->mn", b, c) * la)
            out[s:s + step] = 2 * np.arctan2(num, den).sum(axis=1) / (4 * math.pi)
        return out > 0.5

    def touching(self, P, eps, slack=None, D=None):
        """Bool (m, nelements): element e touches the ball of radius D(p) about p, i.e.
        its carrier distance is <= D(p) + eps with the carrier foot in e's closure (up to
        `slack`, default eps): a face through any of its triangles (foot on the plane
        within `slack` of the triangle, on the inner side up to eps), an edge through its
        segment, a vertex by its distance."""
        P = np.asarray(P, float).reshape(-1, 3)
        slack = eps if slack is None else slack
        D = self.distance(P) if D is None else np.asarray(D, float)
        V, T = self.V, self.T
        A, B, C = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
        out = np.zeros((len(P), self.nelements), bool)
        nf = self.nfaces
        onehot = np.zeros((len(T), nf))
        onehot[np.arange(len(T)), self.tri_face] = 1
        rng, step = _chunks(len(P), len(T))
        for s in rng:
            p = P[s:s + step]
            sgn = np.einsum("nk,mnk->mn", self.normals, A[None] - p[:, None])  # > 0 inside
            foot = p[:, None] + sgn[..., None] * self.normals[None]
            off, _ = closest_on_triangles(foot, A, B, C)      # in the plane: no cancellation
            ok = (sgn >= -eps) & (sgn <= D[s:s + step, None] + eps) & (off <= slack)
            out[s:s + step, :nf] = (ok.astype(float) @ onehot) > 0
        if self.nedges:
            u = self.edge_B - self.edge_A
            ell = np.linalg.norm(u, axis=1)
            u = u / ell[:, None]
            q = P[:, None] - self.edge_A[None]
            t = np.einsum("mnk,nk->mn", q, u)
            r = q - t[..., None] * u[None]
            dl = np.linalg.norm(r, axis=2)
            out[:, nf:nf + self.nedges] = ((t >= -slack) & (t <= ell + slack)
                                           & (dl <= D[:, None] + eps))
        if self.nverts:
            dv = np.linalg.norm(P[:, None] - self.vert_P[None], axis=2)
            out[:, nf + self.nedges:] = dv <= D[:, None] + eps
        return out

    def is_major(self, touch_row):
        """Some two touching elements are not adjacent (disjoint closures)."""
        es = np.nonzero(touch_row)[0]
        return any(not self.adjacent(int(a), int(b))
                   for i, a in enumerate(es) for b in es[i + 1:])

    def boundary_samples(self, n, margin, rng):
        """n area-weighted points on the boundary, each farther than `margin` from every
        edge element (so from its face's edges): (points, their triangles)."""
        V, T = self.V, self.T
        p = self.areas / self.areas.sum()
        pts, tris = [], []
        got = 0
        while got < n:
            m = 4 * (n - got) + 16
            t = rng.choice(len(T), size=m, p=p)
            r1, r2 = rng.random(m), rng.random(m)
            flip = r1 + r2 > 1
            r1, r2 = np.where(flip, 1 - r1, r1), np.where(flip, 1 - r2, r2)
            q = V[T[t, 0]] + r1[:, None] * (V[T[t, 1]] - V[T[t, 0]]) \
                + r2[:, None] * (V[T[t, 2]] - V[T[t, 0]])
            if self.nedges:
                de = point_segment_distance(q, self.edge_A, self.edge_B).min(axis=1)
                keep = de > margin
            else:
                keep = np.ones(m, bool)
            pts.append(q[keep])
            tris.append(t[keep])
            got += int(keep.sum())
        return np.concatenate(pts)[:n], np.concatenate(tris)[:n]

    def probes(self, n, margin, seed=1, tau=None, iters=64):
        """The completeness probe: (x* (n, 3), t* (n,), q (n, 3), face (n,)).  From each
        boundary sample q (inward normal -n of its face) bisect g(t) = D(q - t n) - t,
        which is 0 on [0, t*] and < 0 after (the balls tangent at q are nested), for
        t* with g(t*) >= -tau."""
        rng = np.random.default_rng(seed)
        q, t = self.boundary_samples(n, margin, rng)
        nrm = self.face_normal[self.tri_face[t]]
        tau = 1e-13 * self.diag if tau is None else tau
        lo = np.zeros(len(q))
        hi = np.full(len(q), self.diag)
        for _ in range(iters):
            mid = 0.5 * (lo + hi)
            g = self.distance(q - mid[:, None] * nrm) - mid
            ok = g >= -tau
            lo = np.where(ok, mid, lo)
            hi = np.where(ok, hi, mid)
        return q - lo[:, None] * nrm, lo, q, self.tri_face[t]


# --------------------------------------------------------------------- results


def result_pieces(res):
    """(triangles (k, 3, 3), segments (s, 2, 3), points (j, 3)) of a medial result with
    .sheets (.vertices, .triangles), .seams (.points) and .junctions (.points)."""
    tris = [np.asarray(s.vertices, float)[np.asarray(s.triangles, np.int64)]
            for s in res.sheets if len(s.triangles)]
    segs = [np.stack([np.asarray(c.points, float)[:-1], np.asarray(c.points, float)[1:]], 1)
            for c in res.seams if len(c.points) > 1]
    pts = [np.asarray(c.points, float) for c in res.seams]
    pts.append(np.asarray(res.junctions.points, float).reshape(-1, 3))
    return (np.concatenate(tris) if tris else np.zeros((0, 3, 3)),
            np.concatenate(segs) if segs else np.zeros((0, 2, 3)),
            np.concatenate(pts) if pts else np.zeros((0, 3)))


class _CellIndex:
    """Pieces (triangles or segments, (k, c, 3)) bucketed by the cell of their centroid:
    with cells of side >= (largest centroid-to-corner distance + cutoff), every piece
    within cutoff of a point has its centroid in the point's cell or one of its 26
    neighbours."""

    def __init__(self, pieces, cutoff):
        self.pieces = pieces
        cen = pieces.mean(1)
        ext = np.linalg.norm(pieces - cen[:, None], axis=2).max() if len(pieces) else 0.0
        self.side = float(ext + cutoff) * (1 + 1e-9) + 1e-300
        self.origin = cen.min(0) if len(pieces) else np.zeros(3)
        cell = np.floor((cen - self.origin) / self.side).astype(np.int64) + 1
        self.order = np.argsort(self._key(cell), kind="stable")
        self.keys = self._key(cell)[self.order]

    @staticmethod
    def _key(cell):
        return (cell[..., 0] * 2_097_152 + cell[..., 1]) * 2_097_152 + cell[..., 2]

    def near(self, p):
        c = np.floor((p - self.origin) / self.side).astype(np.int64) + 1
        off = np.stack(np.meshgrid([-1, 0, 1], [-1, 0, 1], [-1, 0, 1], indexing="ij"), -1)
        keys = self._key(c + off.reshape(-1, 3))
        lo = np.searchsorted(self.keys, keys, "left")
        hi = np.searchsorted(self.keys, keys, "right")
        if not (hi > lo).any():
            return self.order[:0]
        return self.order[np.concatenate([np.arange(a, b) for a, b in zip(lo, hi)])]


def distance_to_pieces(P, tris, segs, pts, cutoff):
    """Distance of points P to the union of the pieces, exact where it is below
    `cutoff` (larger values are only known to be >= cutoff and may come back as inf):
    points and segments by brute force in chunks, triangles through a cell index (only
    those near each point are tested)."""
    P = np.asarray(P, float).reshape(-1, 3)
    out = np.full(len(P), np.inf)
    step = max(1, 2_000_000 // max(1, len(segs) + len(pts)))
    for s in range(0, len(P), step):
        p = P[s:s + step]
        if len(pts):
            out[s:s + step] = np.linalg.norm(p[:, None] - pts[None], axis=2).min(1)
        if len(segs):
            out[s:s + step] = np.minimum(out[s:s + step], point_segment_distance(
                p, segs[:, 0], segs[:, 1]).min(1))
    if len(tris):
        ti = _CellIndex(tris, cutoff)
        for i, p in enumerate(P):
            k = ti.near(p)
            if len(k):
                d, _ = closest_on_triangles(p[None], tris[k, 0], tris[k, 1], tris[k, 2])
                out[i] = min(out[i], float(d.min()))
    return out


def sheet_area(sheet):
    v = np.asarray(sheet.vertices, float)[np.asarray(sheet.triangles, np.int64)]
    return 0.5 * float(np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1).sum())
