# SPDX-License-Identifier: LGPL-2.1-or-later
"""Closed, outward-oriented triangle meshes of the test and benchmark solids of the 3-D
medial surface (issue 9, design section 7 and 8), in one place: cuboid, cube, square
prism, L-bracket, T-section, n-gon disc (extruded polygons), a ribbed tray (a union of
cells of a rectilinear grid) and a revolved cup.  Numpy only; every function returns
(vertices (n, 3) float64, triangles (m, 3) int64)."""
import math

import numpy as np


def _ear_clip(poly):
    """Triangles (index triples, counter-clockwise) of a simple counter-clockwise polygon
    (k, 2), by ear clipping (O(k^2); the polygons here are small)."""
    pts = np.asarray(poly, float)
    idx = list(range(len(pts)))
    out = []

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    guard = 0
    while len(idx) > 3:
        guard += 1
        if guard > 10 * len(pts) ** 2:
            raise ValueError("ear clipping failed: polygon not simple or not counter-clockwise")
        n = len(idx)
        for k in range(n):
            i0, i1, i2 = idx[k - 1], idx[k], idx[(k + 1) % n]
            a, b, c = pts[i0], pts[i1], pts[i2]
            if cross(a, b, c) <= 0:
                continue                              # reflex or flat corner: no ear
            ok = True
            for j in idx:
                if j in (i0, i1, i2):
                    continue
                p = pts[j]
                if cross(a, b, p) >= 0 and cross(b, c, p) >= 0 and cross(c, a, p) >= 0:
                    ok = False
                    break
            if ok:
                out.append((i0, i1, i2))
                del idx[k]
                break
    out.append(tuple(idx))
    return out


def extrude(poly, z0, z1):
    """The prism over a simple counter-clockwise polygon (k, 2) between heights z0 < z1."""
    poly = np.asarray(poly, float)
    k = len(poly)
    v = np.concatenate([np.c_[poly, np.full(k, z0)], np.c_[poly, np.full(k, z1)]])
    tris = []
    for i in range(k):
        j = (i + 1) % k
        tris += [(i, j, k + j), (i, k + j, k + i)]
    for a, b, c in _ear_clip(poly):
        tris.append((k + a, k + b, k + c))            # top, normal +z
        tris.append((a, c, b))                        # bottom, normal -z
    return v, np.asarray(tris, np.int64)


def cuboid(a=100.0, b=60.0, c=20.0):
    """[0, a] x [0, b] x [0, c]."""
    return extrude([(0, 0), (a, 0), (a, b), (0, b)], 0.0, c)


def cube(s=40.0):
    return cuboid(s, s, s)


def square_prism(w=20.0, h=100.0):
    """[0, w] x [0, w] x [0, h]: the axis (w/2, w/2, z) is a degenerate seam."""
    return cuboid(w, w, h)


def l_bracket(arm=50.0, t=10.0, depth=40.0):
    """Arms [0, t] x [0, arm] and [0, arm] x [0, t], extruded z in [0, depth]; the reflex
    edge is (t, t, z)."""
    return extrude([(0, 0), (arm, 0), (arm, t), (t, t), (t, arm), (0, arm)], 0.0, depth)


def t_section(width=60.0, height=60.0, t=10.0, depth=40.0):
    """Flange [0, width] x [height - t, height], web [(width - t)/2, (width + t)/2] x
    [0, height - t], extruded z in [0, depth]; reflex edges at ((width -+ t)/2,
    height - t, z)."""
    w0, w1 = (width - t) / 2, (width + t) / 2
    f = height - t
    return extrude([(w0, 0), (w1, 0), (w1, f), (width, f), (width, height), (0, height),
                    (0, f), (w0, f)], 0.0, depth)


def ngon_disc(n=48, radius=50.0, thickness=4.0):
    """A regular n-gon of circumradius `radius` (a vertex on +x), z in [0, thickness]."""
    a = 2 * math.pi * np.arange(n) / n
    return extrude(np.c_[radius * np.cos(a), radius * np.sin(a)], 0.0, thickness)


def grid_solid(xs, ys, zs, occupied):
    """The union of the occupied cells [xs[i], xs[i+1]] x [ys[j], ys[j+1]] x [zs[k],
    zs[k+1]] (occupied: bool (nx-1, ny-1, nz-1)), each boundary cell side as two
    triangles on the grid nodes (a conforming, closed mesh if no two occupied cells meet
    along an edge or at a corner only)."""
    xs, ys, zs = (np.asarray(q, float) for q in (xs, ys, zs))
    occ = np.pad(np.asarray(occupied, bool), 1)                  # empty frame around
    ny, nz = len(ys), len(zs)

    def node(i, j, k):
        return (i * ny + j) * nz + k

    quads = []
    for axis in range(3):
        a = np.moveaxis(occ, axis, 0)
        diff = a[1:].astype(np.int8) - a[:-1].astype(np.int8)   # +1: occupied after plane
        for s, sign in ((np.argwhere(diff == 1), -1), (np.argwhere(diff == -1), 1)):
            for p, u, w in s:                                   # plane index p, cell (u, w)
                u, w = u - 1, w - 1                              # undo the padding
                if axis == 0:
                    c = [node(p, u, w), node(p, u + 1, w), node(p, u + 1, w + 1), node(p, u, w + 1)]
                elif axis == 1:   # cell (x: u, z: w); (z, x) is right-handed about +y
                    c = [node(u, p, w), node(u, p, w + 1), node(u + 1, p, w + 1), node(u + 1, p, w)]
                else:
                    c = [node(u, w, p), node(u + 1, w, p), node(u + 1, w + 1, p), node(u, w + 1, p)]
                if sign < 0:
                    c = c[::-1]
                quads.append(c)
    quads = np.asarray(quads, np.int64)
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    gx, gy, gz = np.meshgrid(xs, ys, zs, indexing="ij")
    allv = np.c_[gx.ravel(), gy.ravel(), gz.ravel()]
    used, inv = np.unique(tris.ravel(), return_inverse=True)
    return allv[used], inv.reshape(-1, 3).astype(np.int64)


def ribbed_tray(size=(200.0, 150.0, 40.0), wall=3.0, floor=3.0, rib=2.0, rib_top=33.0,
                nx_ribs=8, ny_ribs=5):
    """An open-topped tray (outer size, wall and floor thickness) with a grid of ribs of
    thickness `rib` up to height `rib_top`: nx_ribs ribs parallel to y, ny_ribs parallel
    to x.  With the defaults: 251 planar faces."""
    X, Y, Z = size
    cx = wall + (X - 2 * wall) * (np.arange(nx_ribs) + 1) / (nx_ribs + 1)
    cy = wall + (Y - 2 * wall) * (np.arange(ny_ribs) + 1) / (ny_ribs + 1)
    xs = np.unique(np.r_[0, wall, X - wall, X, cx - rib / 2, cx + rib / 2])
    ys = np.unique(np.r_[0, wall, Y - wall, Y, cy - rib / 2, cy + rib / 2])
    zs = np.array([0, floor, rib_top, Z], float)
    mx, my, mz = ((q[:-1] + q[1:]) / 2 for q in (xs, ys, zs))
    MX, MY, MZ = np.meshgrid(mx, my, mz, indexing="ij")
    wall_cell = (MX < wall) | (MX > X - wall) | (MY < wall) | (MY > Y - wall)
    rib_cell = (np.abs(MX[..., None] - cx).min(-1) < rib / 2) | \
               (np.abs(MY[..., None] - cy).min(-1) < rib / 2)
    occ = wall_cell | (MZ < floor) | (rib_cell & (MZ < rib_top))
    return grid_solid(xs, ys, zs, occ)


def revolve(profile, n):
    """The solid of revolution about z of a closed simple polygon `profile` (k, 2) of
    (r >= 0, z), counter-clockwise in the (r, z) plane, with n segments; points with
    r == 0 lie on the axis (one vertex each)."""
    prof = np.asarray(profile, float)
    ang = 2 * math.pi * np.arange(n) / n
    verts, ids = [], []
    for r, z in prof:
        if r == 0:
            ids.append([len(verts)] * n)
            verts.append((0.0, 0.0, z))
        else:
            ids.append(list(range(len(verts), len(verts) + n)))
            verts += [(r * math.cos(a), r * math.sin(a), z) for a in ang]
    tris = []
    k = len(prof)
    for i in range(k):
        j = (i + 1) % k
        for s in range(n):
            t = (s + 1) % n
            a, b = ids[i][s], ids[i][t]          # ring i at angles s, s+1
            c, d = ids[j][s], ids[j][t]          # ring j
            tris += [(a, b, d), (a, d, c)]       # one of them is empty on the axis
    tris = np.asarray([t for t in tris if len(set(t)) == 3], np.int64)
    verts = np.asarray(verts, float)
    if signed_volume(verts, tris) < 0:
        tris = tris[:, ::-1].copy()
    return verts, tris


def cup(n=625, radius=20.0, height=30.0, wall=3.0, bottom=4.0):
    """examples/parts/cup.py (a cylinder with a blind pocket from the top) tessellated
    with n segments: 8 n triangles (n = 625: 5000)."""
    return revolve([(0, 0), (radius, 0), (radius, height), (radius - wall, height),
                    (radius - wall, bottom), (0, bottom)], n)


def rigid_motion(vertices, seed=3):
    """A rotation (random, fixed by seed) and a translation of the points; also returns
    (R, t) with x' = R x + t."""
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    t = rng.uniform(-100, 100, 3)
    return np.asarray(vertices, float) @ q.T + t, q, t


def signed_volume(vertices, triangles):
    v = np.asarray(vertices, float)[np.asarray(triangles)]
    return float(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6)


def small_tray():
    """A 60 x 40 x 20 tray, walls and floor 3, one rib each way up to z = 15: 23 faces,
    the rib/wall/floor corners of ribbed_tray at a test-sized cost."""
    return ribbed_tray(size=(60.0, 40.0, 20.0), rib_top=15.0, nx_ribs=1, ny_ribs=1)


def bent_ridge(slope=0.01, bend=1e-4, height=0.6):
    """A 2 x 1 x `height` block whose top is two faces meeting at a ridge along x = 1 at a small
    dihedral angle (the right half rises with `slope`), the ridge's middle vertex moved by
    `bend` along x: every top triangle stays within slope * bend of its face's plane (the
    merge threshold eta of a 1 % tolerance is 1.9e-6 > 1e-6), but the chain between the
    two faces bends by `bend` at that vertex -- the tessellation of a gently curved surface
    (issue 22: a fan's "mesh vertex ... off the line of the edge").  Returns (vertices,
    triangles), outward."""
    s, h = slope, height
    v = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0],          # 0-3 bottom
                  [0, 0, h], [0, 1, h],                                # 4-5 top left
                  [1, 0, h], [1 + bend, 0.5, h], [1, 1, h],            # 6-8 ridge
                  [2, 0, h + s], [2, 1, h + s]], float)                # 9-10 top right
    t = [[0, 2, 1], [0, 3, 2],                                         # bottom (z = 0)
         [4, 6, 7], [4, 7, 5], [5, 7, 8],                              # top left
         [6, 9, 7], [7, 9, 10], [7, 10, 8],                            # top right
         [0, 1, 9], [0, 9, 6], [0, 6, 4],                              # y = 0
         [3, 5, 8], [3, 8, 10], [3, 10, 2],                            # y = 1
         [0, 4, 5], [0, 5, 3],                                         # x = 0
         [1, 2, 10], [1, 10, 9]]                                       # x = 2
    return v, np.array(t, np.int64)
