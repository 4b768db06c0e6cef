# SPDX-License-Identifier: LGPL-2.1-or-later
"""The sheets of a medial surface made to share their boundaries (FreeCAD-free, numpy
only): the FEM mid-surface (mfgeom.app.mid_surface_feature) sews its faces on the result.

Why (issue 22, a PartDesign shell box): the library's sheets each lie within the
tolerance of the medial surface and each sheet's boundary within tol/4 of its seams, but
two sheets meeting along a seam do not share their boundary points: each was simplified
on its own, so their vertices sit at different places along the seam (and up to tol/4
off it), and the corner a sheet has at a junction is often cut off (the 2 mm shell
box's floor sheet has a 0.2 mm chamfer where the true corner is; the curved sheet beside
it ends 0.04 mm short of the junction).  OCCT's sewing of such faces with the tolerance
leaves free edges, gaps at the junctions and vertex tolerances that overlap their
neighbours'.

What :func:`conforming_sheets` does: every boundary vertex of a sheet with elements
(a, b) is moved onto the nearest seam whose elements hold both a and b (those seams are
the sheet's true boundary), within ``snap`` (tol/2); points of one seam closer than
``merge`` (tol/4, the seams' own thinning tolerance) along it are one point, seam
vertices and junctions first.  A boundary edge between two snapped vertices then runs
along the seams between them (shortest way through the junctions over the sheet's own
seams), passing every point any sheet has on those seams: sheets that meet get the
same boundary points, bit for bit, and a cut corner gets its junction back.  The route
is taken only when it stays within the tolerance of the edge it replaces.  The triangle
beside a rerouted edge becomes a fan from its opposite corner (from its centroid when
more than one of its edges was rerouted).  Vertices with
no seam of their own within reach stay where they are.
"""

import heapq
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

# A sheet vertex is moved onto its seam when it lies within this fraction of the
# tolerance of it (the library keeps sheet boundaries within tol/4 of their seams).
SNAP_FRACTION = 0.3
# Points of one seam closer than this fraction of the tolerance (along the seam) are one
# point: the library thins seams to tol/4, finer differences mean nothing (and a FEM
# mesher would refine down to them).
MERGE_FRACTION = 0.25
# A rerouted boundary edge must stay within this fraction of the tolerance of the edge.
ROUTE_FRACTION = 1.0
# What the seams did not join is welded within this fraction of the tolerance: the
# library drops a sheet that lies within tol/2 of its seams, and the sheets beside it
# keep their boundaries within tol/4 of theirs, so such gaps are up to a tolerance wide.
WELD_FRACTION = 1.0


class Seam:
    """One seam polyline: ``points`` (m, 3), arc length ``arc`` (m,), its ``elements``,
    the node ids of its two ends and the registered points on it (``marks``: sorted
    (arc, point id))."""

    def __init__(self, points, elements):
        self.points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        steps = np.linalg.norm(np.diff(self.points, axis=0), axis=1)
        self.arc = np.concatenate([[0.0], np.cumsum(steps)])
        self.length = float(self.arc[-1])
        self.elements = frozenset(int(e) for e in np.asarray(elements).reshape(-1))
        self.ends = (-1, -1)
        self.marks: List[Tuple[float, int]] = []

    def point_at(self, s):
        """The point at arc length ``s``."""
        j = int(np.clip(np.searchsorted(self.arc, s, side="right") - 1, 0,
                        len(self.arc) - 2))
        span = self.arc[j + 1] - self.arc[j]
        t = 0.0 if span <= 0 else (s - self.arc[j]) / span
        return self.points[j] + min(max(t, 0.0), 1.0) * (self.points[j + 1] - self.points[j])

    def between(self, s0, s1):
        """The point ids marked strictly between arc lengths s0 and s1, in that order."""
        lo, hi = min(s0, s1), max(s0, s1)
        ids = [pid for s, pid in self.marks if lo < s < hi]
        return ids if s0 <= s1 else ids[::-1]


class _Points:
    """The global point table: every point any sheet ends up with, by id."""

    def __init__(self):
        self.xyz: List[np.ndarray] = []

    def add(self, p):
        self.xyz.append(np.asarray(p, dtype=np.float64))
        return len(self.xyz) - 1


def _cell(p, size):
    """The grid cell (3 ints) of point ``p`` in a grid of spacing ``size``."""
    return tuple(np.floor(p / size).astype(np.int64).tolist())


def _near(grid, key):
    """The ids ``grid`` holds in cell ``key`` and its 26 neighbours: every point within
    the spacing of a point of that cell."""
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dz in (-1, 0, 1):
                yield from grid.get((key[0] + dx, key[1] + dy, key[2] + dz), ())


def _nodes_of_seams(seams, points, eps):
    """Gives every seam end a node id (ends within ``eps`` are one node: the library puts
    the ends of the seams of one junction on the junction's bits), and marks the seams'
    vertices on them."""
    nodes: List[int] = []
    keys: Dict[Tuple[int, int, int], List[int]] = {}
    cell = max(eps, 1e-300) * 4.0

    def node(p):
        key = _cell(p, cell)
        for n in _near(keys, key):
            if np.linalg.norm(points.xyz[n] - p) <= eps:
                return n
        n = points.add(p)
        keys.setdefault(key, []).append(n)
        nodes.append(n)
        return n

    for seam in seams:
        if len(seam.points) < 2:
            continue
        first, last = node(seam.points[0]), node(seam.points[-1])
        seam.ends = (first, last)
        seam.marks = [(0.0, first)]
        for k in range(1, len(seam.points) - 1):
            seam.marks.append((float(seam.arc[k]), points.add(seam.points[k])))
        seam.marks.append((seam.length, last))
    return nodes


def _project(p, seams, candidates):
    """(seam index, arc length, distance) of the point nearest to ``p`` on the seams
    ``candidates``, or None."""
    best = None
    for c in candidates:
        seam = seams[c]
        if len(seam.points) < 2:
            continue
        a, b = seam.points[:-1], seam.points[1:]
        ab = b - a
        l2 = np.einsum("ij,ij->i", ab, ab)
        t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.where(l2 > 0, l2, 1.0), 0.0, 1.0)
        d = np.linalg.norm(a + t[:, None] * ab - p, axis=1)
        j = int(np.argmin(d))
        if best is None or d[j] < best[2]:
            best = (c, float(seam.arc[j] + t[j] * np.sqrt(l2[j])), float(d[j]))
    return best


def _register(seam, s, points, merge):
    """The point id at arc length ``s`` of ``seam``: a marked point within ``merge``
    along the seam, else a new one (marked).  Returns (id, its arc length)."""
    arcs = [m[0] for m in seam.marks]
    k = int(np.searchsorted(arcs, s))
    near = [i for i in (k - 1, k) if 0 <= i < len(arcs)]
    i = min(near, key=lambda i: abs(arcs[i] - s)) if near else None
    if i is not None and abs(arcs[i] - s) <= merge:
        return seam.marks[i][1], seam.marks[i][0]
    pid = points.add(seam.point_at(s))
    seam.marks.insert(k, (s, pid))
    return pid, s


def _end_arc(seam, node):
    """The arc length of ``seam`` at its end ``node``."""
    return 0.0 if node == seam.ends[0] else seam.length


def _route(seams, candidates, start, end):
    """The shortest way along the seams ``candidates`` from ``start`` = (seam, arc) to
    ``end``: legs [(seam, arc from, arc to), ...] joined at seam ends, or None when they
    are not connected."""
    cu, su = start
    cw, sw = end
    direct = abs(su - sw) if cu == cw else np.inf
    # Dijkstra over the seam ends; the start reaches both ends of its own seam
    adjacency: Dict[int, List[Tuple[int, float, int]]] = {}
    for c in candidates:
        n0, n1 = seams[c].ends
        if n0 < 0 or n0 == n1:
            continue
        adjacency.setdefault(n0, []).append((n1, seams[c].length, c))
        adjacency.setdefault(n1, []).append((n0, seams[c].length, c))
    dist: Dict[int, float] = {}
    back: Dict[int, Tuple[int, int]] = {}   # node -> (previous node or -1 at the start, seam)
    heap = []
    for node in seams[cu].ends:
        d = abs(_end_arc(seams[cu], node) - su)
        if node >= 0 and d < dist.get(node, np.inf):
            dist[node] = d
            back[node] = (-1, cu)
            heapq.heappush(heap, (d, node))
    while heap:
        d, node = heapq.heappop(heap)
        if d > dist.get(node, np.inf) or d >= direct:
            continue
        for other, length, c in adjacency.get(node, ()):
            if d + length < dist.get(other, np.inf):
                dist[other] = d + length
                back[other] = (node, c)
                heapq.heappush(heap, (d + length, other))
    best, last = direct, None
    for node in seams[cw].ends:
        if node in dist and dist[node] + abs(_end_arc(seams[cw], node) - sw) < best:
            best, last = dist[node] + abs(_end_arc(seams[cw], node) - sw), node
    if last is None:
        return [(cu, su, sw)] if np.isfinite(direct) else None
    legs = [(cw, _end_arc(seams[cw], last), sw)]
    node = last
    while True:
        prev, c = back[node]
        if prev < 0:
            legs.append((c, su, _end_arc(seams[c], node)))
            break
        legs.append((c, _end_arc(seams[c], prev), _end_arc(seams[c], node)))
        node = prev
    return legs[::-1]


def _area2(xyz, tri):
    """Twice the area of the triangle ``tri`` (three indices into ``xyz``)."""
    p0, p1, p2 = (np.asarray(xyz[i]) for i in tri)
    return float(np.linalg.norm(np.cross(p1 - p0, p2 - p0)))


def _route_ids(seams, candidates, start, end, points, tol):
    """The point ids along the seams from the snapped vertex ``start`` = (seam, arc, id)
    to ``end`` (both excluded), or None when the seams do not join them within the
    tolerance of the straight edge between them."""
    cu, su, pu = start
    cw, sw, pw = end
    legs = _route(seams, candidates, (cu, su), (cw, sw))
    if legs is None:
        return None
    via = []
    for i, (c, s0, s1) in enumerate(legs):
        seam = seams[c]
        via.extend(seam.between(s0, s1))
        if i + 1 < len(legs):   # the junction where the next leg starts
            via.append(seam.ends[0] if s1 == 0.0 else seam.ends[1])
    via = [g for i, g in enumerate(via) if g not in (pu, pw) and (i == 0 or g != via[i - 1])]
    if via:   # the route must stay within the tolerance of the edge it replaces
        a0, a1 = points.xyz[pu], points.xyz[pw]
        q = np.array([points.xyz[g] for g in via])
        ab = a1 - a0
        l2 = float(ab @ ab)
        t = np.clip((q - a0) @ ab / l2, 0.0, 1.0) if l2 > 0 else np.zeros(len(q))
        if np.linalg.norm(a0 + t[:, None] * ab - q, axis=1).max() > ROUTE_FRACTION * tol:
            return None
    return via


def _cancel_spikes(seq):
    """Removes, in place, from the cyclic sequence ``seq`` of [point id, owners] the
    repeats (x, x -> x) and the spikes (x, y, x -> x: a route that runs past the next
    vertex and comes back, when projections onto a seam are out of order), the owners of
    what goes moving to the entry that stays."""
    changed = True
    while changed and len(seq) > 1:
        changed = False
        i = 0
        while i < len(seq) and len(seq) > 1:
            n = len(seq)
            nxt = (i + 1) % n
            if seq[i][0] == seq[nxt][0]:
                seq[i][1].extend(seq[nxt][1])
                del seq[nxt]
                changed = True
                continue
            if n > 2 and seq[i][0] == seq[(i + 2) % n][0]:
                tip, back = (i + 1) % n, (i + 2) % n
                seq[i][1].extend(seq[tip][1] + seq[back][1])
                for j in sorted((tip, back), reverse=True):
                    del seq[j]
                    if j < i:
                        i -= 1
                changed = True
                continue
            i += 1


def without_needles(pts, tri, eps):
    """The triangles ``tri`` (t, 3) of the points ``pts`` with the zero-area ones gone
    without opening the mesh: a triangle whose corner lies within ``eps`` of its opposite
    (longest) side is dropped and the neighbour across that side split at the corner, so
    the sides it shared stay shared (a sheet the library left unsimplified has rows of
    collinear vertices: 235 of the 946 triangles of one strip of a 2 mm shell box have
    no area, and dropping them alone leaves slits).  Returns (k, 3)."""
    tris = [list(f) for f in np.asarray(tri, dtype=np.int64).reshape(-1, 3).tolist()]
    alive = [True] * len(tris)

    def flat_corner(f):
        """(j, side) when corner j lies within eps of the side opposite it, else None."""
        q = pts[f]
        sides = [np.linalg.norm(q[(j + 2) % 3] - q[(j + 1) % 3]) for j in range(3)]
        j = int(np.argmax(sides))   # the corner opposite the longest side
        if sides[j] == 0.0:
            return j
        twice_area = np.linalg.norm(np.cross(q[(j + 2) % 3] - q[(j + 1) % 3],
                                             q[j] - q[(j + 1) % 3]))
        return j if twice_area / sides[j] <= eps else None

    by_edge: Dict[Tuple[int, int], int] = {}
    for k, f in enumerate(tris):
        for j in range(3):
            by_edge[(f[j], f[(j + 1) % 3])] = k
    todo = list(range(len(tris)))
    guard = 0
    while todo and guard < 8 * len(tris) + 16:
        guard += 1
        k = todo.pop()
        if not alive[k]:
            continue
        f = tris[k]
        if len(set(f)) < 3:
            alive[k] = False
            continue
        j = flat_corner(f)
        if j is None:
            continue
        # corner b lies on the side c -> a opposite it; the neighbour across has a -> c
        b, c, a = f[j], f[(j + 1) % 3], f[(j + 2) % 3]
        alive[k] = False
        for e in ((b, c), (c, a), (a, b)):
            by_edge.pop(e, None)
        n = by_edge.get((a, c))
        if n is None or not alive[n]:
            continue
        g = tris[n]
        i = g.index(a)
        o = g[(i + 2) % 3]
        for e in ((g[0], g[1]), (g[1], g[2]), (g[2], g[0])):
            by_edge.pop(e, None)
        alive[n] = False
        for new in ([a, b, o], [b, c, o]):
            tris.append(new)
            alive.append(True)
            for m in range(3):
                by_edge[(new[m], new[(m + 1) % 3])] = len(tris) - 1
            todo.append(len(tris) - 1)
    kept = [f for f, live in zip(tris, alive) if live and len(set(f)) == 3]
    return np.array(kept, dtype=np.int64).reshape(-1, 3)


def without_boundary_slivers(pts, tri, height):
    """The triangles ``tri`` without those that lie along the boundary thinner than
    ``height``: one boundary side, its opposite corner inside the sheet and within
    ``height`` of that side (projecting onto it).  Why: a sheet the library left
    unsimplified can have vertices on its seam behind a boundary side that cuts the
    seam's curve short (the outward 2 mm shell box's bottom strip); moved onto the seam,
    the side would leave them outside the sheet, folded over its neighbour.  Dropped,
    the corner is on the boundary and goes onto the seam with it.  Returns (k, 3)."""
    tri = np.asarray(tri, dtype=np.int64).reshape(-1, 3)
    if not len(tri):
        return tri
    directed = {(int(a), int(b)) for f in tri.tolist() for a, b in
                ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    on_boundary = set()
    for a, b in directed:
        if (b, a) not in directed:
            on_boundary.update((a, b))
    keep = np.ones(len(tri), dtype=bool)
    for k, f in enumerate(tri.tolist()):
        sides = [(f[j], f[(j + 1) % 3], f[(j + 2) % 3]) for j in range(3)]
        outer = [sd for sd in sides if (sd[1], sd[0]) not in directed]
        if len(outer) != 1:
            continue
        a, b, o = outer[0]
        if o in on_boundary:
            continue
        ab = pts[b] - pts[a]
        l2 = float(ab @ ab)
        if l2 <= 0.0:
            continue
        t = float((pts[o] - pts[a]) @ ab) / l2
        if 0.0 < t < 1.0 and np.linalg.norm(pts[a] + t * ab - pts[o]) <= height:
            keep[k] = False
    return tri[keep]


class Conformed:
    """One sheet after :func:`conforming_sheets`: ``points`` (n, 3), ``triangles``
    (t, 3) into them, ``ids`` (n,) the global point id of every point (points of
    different sheets with one id are the same bits) and ``shared`` (n,) whether another
    sheet has the point too."""

    def __init__(self, points, triangles, ids):
        self.points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        self.triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
        self.ids = np.asarray(ids, dtype=np.int64)
        self.shared = np.zeros(len(self.ids), dtype=bool)


def conforming_sheets(sheets: Sequence[Tuple[np.ndarray, np.ndarray, Sequence[int]]],
                      seams: Sequence[Tuple[np.ndarray, Sequence[int]]],
                      tolerance: float,
                      stats: Optional[dict] = None) -> List[Conformed]:
    """The sheets ``[(points (n, 3), triangles (t, 3), (a, b) elements), ...]`` with
    their boundaries moved onto the seams ``[(points (m, 3), elements), ...]`` (see the
    module's docstring).  Returns one :class:`Conformed` per sheet, in order.  ``stats``
    (a dict) receives counts: snapped / unsnapped boundary vertices, rerouted edges,
    routes refused."""
    from mfgeom.geometry.mesh import boundary_loops
    tol = float(tolerance)
    snap, merge = SNAP_FRACTION * tol, MERGE_FRACTION * tol
    seam_list = [Seam(p, e) for p, e in seams]
    scale = max([float(np.abs(s.points).max()) for s in seam_list if len(s.points)] + [1.0])
    points = _Points()
    nodes = _nodes_of_seams(seam_list, points, 1e-12 * scale)
    by_pair: Dict[Tuple[int, int], List[int]] = {}
    for c, seam in enumerate(seam_list):
        if len(seam.points) < 2:
            continue
        els = sorted(seam.elements)
        for i in range(len(els)):
            for j in range(i + 1, len(els)):
                by_pair.setdefault((els[i], els[j]), []).append(c)
    counts = {"snapped": 0, "unsnapped": 0, "rerouted": 0, "refused": 0}

    # pass 1: every boundary vertex onto its seam (registered, so every sheet sees it)
    snapped = []   # per sheet: {local vertex: (seam, arc, point id)}
    loops_of = []
    cleaned = []
    for pts, tri, elements in sheets:
        pts = np.asarray(pts, dtype=np.float64).reshape(-1, 3)
        tri = without_needles(pts, tri, 1e-12 * scale)
        tri = without_boundary_slivers(pts, tri, merge)
        cleaned.append((pts, tri, elements))
    sheets = cleaned
    for pts, tri, elements in sheets:
        a, b = sorted(int(e) for e in list(elements)[:2])
        candidates = by_pair.get((a, b), [])
        loops = boundary_loops(tri) if len(tri) else []
        loops_of.append(loops or [])
        here = {}
        for loop in loops or []:
            for k in loop:
                hit = _project(pts[k], seam_list, candidates) if candidates else None
                if hit is None or hit[2] > snap:
                    counts["unsnapped"] += 1
                    continue
                c, s, _d = hit
                pid, s = _register(seam_list[c], s, points, merge)
                here[k] = (c, s, pid)
                counts["snapped"] += 1
        snapped.append((here, candidates))

    # pass 2: the boundary edges along the seams, the triangles beside them re-made
    out = []
    for (pts, tri, _elements), (here, candidates), loops in zip(sheets, snapped, loops_of):
        pts = np.asarray(pts, dtype=np.float64).reshape(-1, 3)
        tri = np.asarray(tri, dtype=np.int64).reshape(-1, 3)
        ids = np.empty(len(pts), dtype=np.int64)
        for k in range(len(pts)):
            ids[k] = here[k][2] if k in here else points.add(pts[k])
        extra: Dict[Tuple[int, int], List[int]] = {}   # directed boundary edge -> ids
        for loop in loops:
            # the loop as a cyclic sequence of [point id, the sheet's vertices there]
            seq = []
            for i, u in enumerate(loop):
                w = loop[(i + 1) % len(loop)]
                seq.append([int(ids[u]), [u]])
                if u not in here or w not in here or ids[u] == ids[w]:
                    continue
                via = _route_ids(seam_list, candidates, here[u], here[w], points, tol)
                if via is None:
                    counts["refused"] += 1
                    continue
                counts["rerouted"] += 1 if via else 0
                seq.extend([g, []] for g in via)
            _cancel_spikes(seq)
            for g, owners in seq:
                for k in owners:   # a vertex at a spike's tip goes to the spike's base
                    ids[k] = g
            marked = [i for i, (_g, owners) in enumerate(seq) if owners]
            for j, i in enumerate(marked):
                owners = seq[i][1]
                nxt = marked[(j + 1) % len(marked)]
                between = (seq[i + 1:nxt] if nxt > i else seq[i + 1:] + seq[:nxt])
                if between:
                    extra[(owners[-1], seq[nxt][1][0])] = [g for g, _o in between]
        # the sheet's points: its own (moved) and the routes' (global ids)
        local_of: Dict[int, int] = {}
        new_ids: List[int] = []
        for g in list(ids) + [g for via in extra.values() for g in via]:
            if int(g) not in local_of:
                local_of[int(g)] = len(new_ids)
                new_ids.append(int(g))
        xyz = [points.xyz[g] for g in new_ids]
        tris = []
        area_eps = 1e-12 * max(scale, 1.0) ** 2   # twice a triangle's area, flat
        for t3 in tri.tolist():
            ring, rerouted = [], []
            for j in range(3):
                u, w = t3[j], t3[(j + 1) % 3]
                ring.append(local_of[int(ids[u])])
                via = extra.get((u, w), ())
                ring.extend(local_of[g] for g in via)
                if via:
                    rerouted.append(j)
            ring = [p for i, p in enumerate(ring) if p != ring[i - 1]]   # collapsed edges
            if len(ring) < 3:
                continue
            if len(ring) == 3:
                tris.append(ring)
                continue
            fan = None
            corners = [local_of[int(ids[k])] for k in t3]
            if len(rerouted) == 1 and len(set(corners)) == 3:
                # one edge along a seam: a fan from the opposite corner, on the sheet
                apex = corners[(rerouted[0] + 2) % 3]
                k = ring.index(apex)
                rest = ring[k + 1:] + ring[:k]
                fan = [[apex, rest[i], rest[i + 1]] for i in range(len(rest) - 1)]
                if min(_area2(xyz, f) for f in fan) <= area_eps:
                    fan = None
            if fan is None:   # else a fan from the triangle's centroid
                centre = len(new_ids)
                new_ids.append(points.add(np.mean([pts[k] for k in t3], axis=0)))
                xyz.append(points.xyz[new_ids[-1]])
                fan = [[centre, ring[i], ring[(i + 1) % len(ring)]] for i in range(len(ring))]
            tris.extend(fan)
        xyz = np.array(xyz, dtype=np.float64).reshape(-1, 3)
        tris = np.array(tris, dtype=np.int64).reshape(-1, 3)
        # zero-area triangles (a triangle whose corners all went onto one seam segment)
        # go, the neighbour across split, so the seam's points stay on the boundary
        tris = without_needles(xyz, tris, 1e-12 * scale)
        out.append([[new_ids[i] for i in f] for f in tris.tolist()])
    # pass 3: what the seams did not join (a sheet with no seam of its own, a route
    # refused) is welded: open vertices of different sheets within ``snap`` are one
    # point, an open vertex within ``snap`` of another sheet's open edge splits it
    anchored = {g: 0 for g in nodes}
    for seam in seam_list:
        for _s, g in seam.marks:
            anchored.setdefault(g, 1)
    _weld_open(out, points, anchored, WELD_FRACTION * tol, counts)
    out = [_conformed(tris, points) for tris in out]
    # which points more than one sheet has
    owners: Dict[int, int] = {}
    for sheet in out:
        for g in set(sheet.ids.tolist()):
            owners[g] = owners.get(g, 0) + 1
    for sheet in out:
        sheet.shared = np.array([owners[g] > 1 for g in sheet.ids.tolist()], dtype=bool)
    if stats is not None:
        stats.update(counts)
    return out


def _conformed(tris, points):
    """A :class:`Conformed` of triangles given by global point ids."""
    ids = sorted({g for f in tris for g in f})
    local = {g: i for i, g in enumerate(ids)}
    xyz = np.array([points.xyz[g] for g in ids], dtype=np.float64).reshape(-1, 3)
    return Conformed(xyz, [[local[g] for g in f] for f in tris], ids)


def _open_edges(sheets):
    """{(sheet, directed edge (p, q)): apex} of the edges only one triangle has."""
    use: Dict[Tuple[int, int], int] = {}
    for tris in sheets:
        for f in tris:
            for j in range(3):
                key = (min(f[j], f[j - 2]), max(f[j], f[j - 2]))
                use[key] = use.get(key, 0) + 1
    found = {}
    for s, tris in enumerate(sheets):
        for f in tris:
            for j in range(3):
                p, q, o = f[j], f[(j + 1) % 3], f[(j + 2) % 3]
                if use[(min(p, q), max(p, q))] == 1:
                    found[(s, p, q)] = o
    return found


def _weld_open(sheets, points, anchored, delta, counts):
    """Pass 3 of :func:`conforming_sheets`, in place on ``sheets`` (per sheet a list of
    triangles of global point ids): open vertices of different sheets within ``delta``
    become one point (a seam junction, else a seam point, else their mean), then open
    edges are split at the open vertices of other sheets within ``delta`` of them."""
    scale = max(float(np.abs(np.array(points.xyz)).max()) if points.xyz else 1.0, 1.0)
    area_eps = 1e-12 * scale ** 2
    opened = _open_edges(sheets)
    where: Dict[int, set] = {}
    for (s, p, q) in opened:
        where.setdefault(p, set()).add(s)
        where.setdefault(q, set()).add(s)
    # greedy, not transitive: a vertex joins the nearest point already chosen within
    # delta (junctions first, then seam points, then the rest) whose sheets are not its
    # own, else it is chosen itself -- nothing moves farther than delta (a transitive
    # weld chains across the crowded corner of a shell box)
    order = sorted(where, key=lambda g: (anchored.get(g, 2), g))
    cell = max(delta, 1e-300)
    grid: Dict[Tuple[int, int, int], List[int]] = {}
    members: Dict[int, set] = {}
    remap = {}
    for g in order:
        p = points.xyz[g]
        key = _cell(p, cell)
        best, best_d = None, delta
        for h in _near(grid, key):
            d = float(np.linalg.norm(points.xyz[h] - p))
            if d <= best_d and not (members[h] & where[g]):
                best, best_d = h, d
        if best is None:
            grid.setdefault(key, []).append(g)
            members[g] = set(where[g])
        else:
            remap[g] = best
            members[best] |= where[g]
            counts["welded"] = counts.get("welded", 0) + 1
    xyz = np.array(points.xyz, dtype=np.float64).reshape(-1, 3)
    for s, tris in enumerate(sheets):
        moved = [[remap.get(g, g) for g in f] for f in tris]
        sheets[s] = without_needles(xyz, moved, 1e-12 * scale).tolist()
    # T-junctions: an open vertex on (within delta of) another sheet's open edge
    opened = _open_edges(sheets)
    where = {}
    for (s, p, q) in opened:
        where.setdefault(p, set()).add(s)
        where.setdefault(q, set()).add(s)
    verts = sorted(where)
    if not verts:
        return
    vxyz = np.array([points.xyz[g] for g in verts])
    splits: Dict[Tuple[int, int, int], List[Tuple[float, int]]] = {}
    for (s, p, q) in opened:
        a, b = points.xyz[p], points.xyz[q]
        ab = b - a
        l2 = float(ab @ ab)
        if l2 <= 0:
            continue
        t = (vxyz - a) @ ab / l2
        d = np.linalg.norm(a + np.clip(t, 0, 1)[:, None] * ab - vxyz, axis=1)
        for i in np.flatnonzero((d <= delta) & (t > 0) & (t < 1)):
            g = verts[i]
            if g in (p, q) or s in where[g]:
                continue
            if min(np.linalg.norm(points.xyz[g] - a), np.linalg.norm(points.xyz[g] - b)) <= delta:
                continue   # near an end: the weld above had its chance
            splits.setdefault((s, p, q), []).append((float(t[i]), g))
    for (s, p, q), along in splits.items():
        along.sort()
        o = opened[(s, p, q)]
        chain = [p] + [g for _t, g in along] + [q]
        fan = [[chain[i], chain[i + 1], o] for i in range(len(chain) - 1)]
        if min(_area2(points.xyz, f) for f in fan) <= area_eps:
            continue
        tris = sheets[s]
        for k, f in enumerate(tris):
            if set(f) == {p, q, o} and any(f[j] == p and f[(j + 1) % 3] == q for j in range(3)):
                tris[k:k + 1] = fan
                counts["split"] = counts.get("split", 0) + len(along)
                break
