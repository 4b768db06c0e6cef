# SPDX-License-Identifier: LGPL-2.1-or-later
"""An analytic stand-in for core.medial_surface on axis-aligned cuboids, for the workbench
tests while the library's extraction is not built (it then raises "not built yet").

The major medial surface of a cuboid a > b > c (issue 9, section 5): one rectangular sheet
at mid-height (normal along the c side), inset by c/2 from the other four faces, radius
c/2 everywhere; four seams along its edges; four junctions at its corners.  Computed from
the input mesh's bounding box only (numpy), so it moves and grows with the source: the
feature tests can see a recompute.  Never used by the workbench itself."""

import types

import numpy as np

GRID = 4   # the sheet as a GRID x GRID grid of quads (two triangles each)


def cuboid_medial_surface(vertices, triangles, tolerance, major_only=True):
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    lo, hi = v.min(axis=0), v.max(axis=0)
    size = hi - lo
    c_axis = int(np.argmin(size))
    u_axis, w_axis = [k for k in range(3) if k != c_axis]
    r = size[c_axis] / 2.0
    mid = (lo + hi) / 2.0
    us = np.linspace(lo[u_axis] + r, hi[u_axis] - r, GRID + 1)
    ws = np.linspace(lo[w_axis] + r, hi[w_axis] - r, GRID + 1)
    pts = []
    for w in ws:
        for u in us:
            p = mid.copy()
            p[u_axis], p[w_axis] = u, w
            pts.append(p)
    pts = np.array(pts)
    tris = []
    n = GRID + 1
    for j in range(GRID):
        for i in range(GRID):
            a, b, c, d = j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i
            tris += [(a, b, c), (a, c, d)]
    corners = pts[[0, GRID, n * n - 1, n * GRID]]
    sheet = types.SimpleNamespace(vertices=pts, triangles=np.array(tris, dtype=np.int64),
                                  radii=np.full(len(pts), r), elements=np.array([0, 1]))
    seams = [types.SimpleNamespace(points=np.array([corners[k], corners[(k + 1) % 4]]),
                                   radii=np.full(2, r), elements=np.array([0, 1, 2 + k]))
             for k in range(4)]
    junctions = types.SimpleNamespace(points=corners, radii=np.full(4, r),
                                      elements=[np.array([0, 1, 2 + k, 2 + (k + 3) % 4])
                                                for k in range(4)])
    return types.SimpleNamespace(sheets=[sheet], seams=seams, junctions=junctions)
