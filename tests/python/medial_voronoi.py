# SPDX-License-Identifier: LGPL-2.1-or-later
"""The peer of mfgeom's 2-D medial axis: FreeCAD's Path.Voronoi (PathApp.Voronoi in 1.0;
Boost.Polygon's segment Voronoi diagram), as FreeCAD's V-carve uses it -- no code shared with
libcore/src/axis2d/.

Facts that shape its use (measured): the input is multiplied by `scale`
and truncated to int32 (a 1/scale grid; |coordinate| * scale must stay below 2^31, else the
diagram is silently empty); secondary edges (a segment and its own endpoint) and edges
outside the face or inside holes are not medial axis and are filtered here; curved edges
are parabolas (sampled here to the tolerance).

available() tells whether FreeCAD's Path module can be imported (mfgeom.paths finds FreeCAD)."""
import math
import time

import numpy as np



def available():
    try:
        _path()
        return True
    except Exception:  # no FreeCAD here
        return False


def _path():
    from mfgeom import paths
    if paths.add_freecad_to_path() is None:
        raise ImportError("FreeCAD's Python modules not found (set MFGEOM_FREECAD_LIB)")
    import FreeCAD  # noqa: F401  (Path needs it loaded)
    try:  # FreeCAD 1.0 renamed the C++ module (Path is now CAM's Python package)
        import PathApp as Path
    except ImportError:  # FreeCAD 0.20, 0.21
        import Path
    return Path


def inside(rings, pts):
    """Even-odd inside test of pts (m, 2) (brute force, in chunks)."""
    pts = np.asarray(pts, float).reshape(-1, 2)
    res = np.zeros(len(pts), bool)
    for r in rings:
        r = np.asarray(r, float)
        a, b = r, np.roll(r, -1, axis=0)
        step = max(1, 4_000_000 // max(len(r), 1))
        for s in range(0, len(pts), step):
            q = pts[s:s + step]
            c = (a[None, :, 1] > q[:, None, 1]) != (b[None, :, 1] > q[:, None, 1])
            with np.errstate(divide='ignore', invalid='ignore'):
                xi = a[None, :, 0] + (q[:, None, 1] - a[None, :, 1]) * (b - a)[None, :, 0] / (b - a)[None, :, 1]
            res[s:s + step] ^= (np.count_nonzero(c & (q[:, None, 0] < xi), axis=1) % 2).astype(bool)
    return res


def construct(rings, scale=1000.0):
    """The Boost diagram of the rings' edges; returns (diagram, seconds of construct())."""
    Path = _path()
    from FreeCAD import Vector
    vd = Path.Voronoi.Diagram(scale)

    def grid(v):
        # FreeCAD multiplies by scale and truncates toward zero (32.108 * 1000 =
        # 32107.99... -> 32107): a quarter step away from zero makes the truncation give
        # the nearest grid value, so Boost sees exactly the grid coordinates
        k = round(float(v) * scale)
        return (k + math.copysign(0.25, k if k else 1.0)) / scale
    for r in rings:
        r = [Vector(grid(x), grid(y), 0) for x, y in r]
        for i in range(len(r)):
            vd.addSegment(r[i], r[(i + 1) % len(r)])
    t = time.perf_counter()
    vd.construct()
    return vd, time.perf_counter() - t


def _parabola(focus, seg, p0, p1, tol):
    a, b = np.asarray(seg[0], float), np.asarray(seg[1], float)
    u = (b - a) / np.linalg.norm(b - a)
    n = np.array([-u[1], u[0]])
    f = np.asarray(focus, float)
    h = np.dot(f - a, n)
    if h < 0:
        n, h = -n, -h
    fx = np.dot(f - a, u)
    x0, x1 = np.dot(np.asarray(p0) - a, u), np.dot(np.asarray(p1) - a, u)
    step = math.sqrt(8 * tol * h) if h > 0 else abs(x1 - x0)
    k = max(2, int(math.ceil(abs(x1 - x0) / max(step, 1e-300))) + 1)
    xs = np.linspace(x0, x1, k)
    ys = ((xs - fx) ** 2 + h * h) / (2 * h)
    pts = a + np.outer(xs, u) + np.outer(ys, n)
    pts[0], pts[-1] = p0, p1
    return pts, ys


def axis_edges(rings, tol, scale=1000.0, vd=None, inside_fn=None):
    """The interior primary finite edges of the diagram: list of (v0, v1, points (k, 2),
    radii (k,)) with v0, v1 Boost vertex indices; and the vertex coordinates.  inside_fn
    (rings, points) -> bool array replaces the brute-force even-odd test (large inputs)."""
    if vd is None:
        vd, _ = construct(rings, scale)
    edges = vd.Edges                      # rebuilt at every access: keep the list
    verts = [(v.X, v.Y) for v in vd.Vertices]
    cand = []
    for e in edges:
        if not e.isPrimary() or not e.isFinite() or e.Twin.Index < e.Index:
            continue
        v0, v1 = e.Vertices
        cand.append((e, v0.Index, v1.Index))
    if not cand:
        return [], verts
    mids = np.array([[(verts[a][0] + verts[b][0]) / 2, (verts[a][1] + verts[b][1]) / 2] for _, a, b in cand])
    keep = (inside_fn or inside)(rings, mids)
    out = []
    for (e, a, b), k in zip(cand, keep):
        if not k:
            continue
        if e.isCurved():
            c0, c1 = e.Cell, e.Twin.Cell
            pc, sc = (c0, c1) if c0.containsPoint() else (c1, c0)
            f = pc.getSource()
            s = sc.getSource()
            pts, rad = _parabola((f.x, f.y), ((s[0].x, s[0].y), (s[1].x, s[1].y)), verts[a], verts[b], tol)
        else:
            d0, d1 = e.getDistances()
            pts, rad = np.array([verts[a], verts[b]]), np.array([d0, d1])
        out.append((a, b, pts, rad))
    return out, verts


def topology(rings, tol, scale=1000.0, edges=None):
    """(branches, junctions) of Boost's axis, with junctions joined by an edge chain
    shorter than tol contracted into one where the group so joined spans less than tol
    (mfgeom's rule): vertices of degree != 2 are
    junctions (degree >= 3) or leaves (degree 1).  `edges`: axis_edges(...)[0] if known."""
    if edges is None:
        edges, _ = axis_edges(rings, tol, scale)
    inc = {}
    for k, (a, b, _, _) in enumerate(edges):
        inc.setdefault(a, []).append(k)
        inc.setdefault(b, []).append(k)
    # chain edges through degree-2 vertices into branches (end vertex ids, length)
    used = [False] * len(edges)
    branches = []
    for v, ks in inc.items():
        if len(ks) == 2:
            continue
        for k in ks:
            if used[k]:
                continue
            cur, length = v, 0.0
            while True:
                used[k] = True
                a, b, pts, _ = edges[k]
                length += float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
                cur = b if cur == a else a
                if len(inc[cur]) != 2:
                    break
                k = inc[cur][0] if inc[cur][0] != k else inc[cur][1]
                if used[k]:
                    break
            branches.append((v, cur, length))
    loops = sum(1 for k in range(len(edges)) if not used[k])
    junc = [v for v, ks in inc.items() if len(ks) >= 3]
    par = {v: v for v in junc}

    def find(v):
        while par[v] != v:
            par[v] = par[par[v]]
            v = par[v]
        return v
    # groups joined by short branches are contracted only where they span < tol (box
    # diagonal of their junctions)
    pos = {}
    for a, b, pts, _ in edges:
        pos.setdefault(a, pts[0])
        pos.setdefault(b, pts[-1])
    short = [(a, b) for a, b, length in branches if a in par and b in par and length < tol]
    for a, b in short:
        if find(a) != find(b):
            par[find(a)] = find(b)
    box = {}
    for v in junc:
        r = find(v)
        lo, hi = box.get(r, (pos[v], pos[v]))
        box[r] = (np.minimum(lo, pos[v]), np.maximum(hi, pos[v]))
    narrow = {v: float(np.hypot(*(box[find(v)][1] - box[find(v)][0]))) < tol for v in junc}
    for v in junc:
        par[v] = v
    kept = 0
    for a, b, length in sorted(branches, key=lambda t: t[2]):
        if a in par and b in par and length < tol and narrow[a] and find(a) != find(b):
            par[find(a)] = find(b)
            continue
        kept += 1
    return kept + (1 if loops else 0), len({find(v) for v in junc})
