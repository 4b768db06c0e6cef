# SPDX-License-Identifier: LGPL-2.1-or-later
"""Directions on the unit sphere for drawing the parting analysis's visibility sphere,
FreeCAD-free (numpy only, tested by pytest): an icosphere, how many surfaces' visibility
maps cover each direction, and the outlines of the maps as great-arc polylines."""

from typing import List, Optional, Sequence, Tuple

import numpy as np

SPHERE_LEVEL = 4            # icosphere subdivisions: 10 * 4**4 + 2 = 2562 vertices


def icosphere(level: int = SPHERE_LEVEL) -> Tuple[np.ndarray, np.ndarray]:
    """(vertices (n, 3) unit, triangles (m, 3) counter-clockwise seen from outside)."""
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(level):
        mid, out = {}, []

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                mid[key] = len(verts) - 1
            return mid[key]
        for a, b, c in f:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = out
    return np.array(verts), np.array(f, dtype=np.int32)


def coverage(directions: np.ndarray, maps: Sequence[Tuple[object, Optional[object]]],
             tol: float) -> np.ndarray:
    """Per direction, the number of distinct surfaces whose map (any of their maps; None:
    the whole sphere) contains it within ``tol``.  ``maps``: [(surface, map or None)]."""
    seen = {}
    for s, m in maps:
        inside = np.ones(len(directions), bool) if m is None else m.contains(directions, tol)
        seen[s] = seen.get(s, np.zeros(len(directions), bool)) | inside
    count = np.zeros(len(directions), dtype=np.int32)
    for inside in seen.values():
        count += inside
    return count


def great_arc(a: np.ndarray, b: np.ndarray, pieces: int = 24) -> np.ndarray:
    """Points on the shorter great arc from unit a to unit b (a, b not antipodal)."""
    t = np.linspace(0.0, 1.0, pieces + 1)[:, None]
    p = (1 - t) * a + t * b
    return p / np.linalg.norm(p, axis=1)[:, None]


def map_outlines(maps: Sequence[Tuple[object, Optional[object]]]
                 ) -> Tuple[List[np.ndarray], np.ndarray]:
    """(polylines, dots) drawing the maps on the unit sphere: a polygon's boundary, an
    edge's arc (a closed one all round), a point map's directions.  ``maps`` as for
    :func:`coverage`; the whole-sphere maps (None) draw nothing."""
    lines, dots = [], []
    for _, m in maps:
        if m is None or m.kind == "null":
            continue
        v = m.vertices
        if m.kind == "point":
            dots.extend(v)
            continue
        loop = m.kind == "polygon" or m.closed
        ends = list(range(len(v))) + ([0] if loop else [])
        pts = [great_arc(v[i], v[j]) for i, j in zip(ends[:-1], ends[1:])]
        if pts:
            lines.append(np.vstack(pts))
    return lines, np.array(dots).reshape(-1, 3)
