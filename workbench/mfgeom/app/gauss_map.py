# SPDX-License-Identifier: LGPL-2.1-or-later
"""Gaussian maps of a shape's faces and the concave / convex / tangent kind of its edges,
in global coordinates, for mfgeom.parting (FreeCAD App layer).

Every normal comes from OCCT's ``Face.normalAt``, which applies the face's orientation
(reversed faces) and location; ``shape_of`` bakes the object's global placement (its
containers included) into the shape, so every direction is global.

What is exact and what is sampled (``FaceGauss.shrink`` is 0 where exact):

* plane: one normal — exact.
* cylinder: the normals form a great-circle arc over the face's u range.  The cone spanned by an arc
  shorter than pi is spanned by its end normals, and an arc of pi or more has no half of
  the circle containing it; so samples with gaps <= pi/2 span exactly the arc's cone:
  exact (up to the double rounding of normalAt).
* cone: the normals form a small-circle arc, whose cone no finite set of points spans.
  The arc is sampled so that the deviation of the true arc from the great arcs between
  samples (largest at each piece's middle, measured there) is <= ``deflection``;
  shrink = that deviation.
* sphere, torus: normals (cos v cos u, cos v sin u, sin v) in the surface's frame:
  meridians (u fixed) are great circles (exact, gaps <= pi/2), parallels small circles
  (sampled as for cones); a UV grid with shrink = the largest parallel deviation.
* anything else (B-spline, Bezier, offset, revolution, extrusion): a UV grid refined
  until shrink <= ``deflection``, shrink = twice the largest angle of a cell's edge
  midpoint or centre normal from the great arc between the neighbouring samples.  This
  is an estimate that assumes the normal varies smoothly inside a cell (true once cells
  are small against the surface's features); it is not a proof, and the tests check it
  against dense sampling of the true face.

The face's parameter box (ParameterRange) is used: for a trimmed face its Gaussian map
is a superset of the face's, which keeps every reported direction valid (conservative).
"""

import math

import numpy as np

import Part

from mfgeom.parting import FaceGauss

DEFAULT_DEFLECTION = 1e-3   # rad: largest shrink wanted from sampling
DEFAULT_TANGENT_TOL = 1e-4  # rad: edges whose faces' normals differ less are tangent
_MAX_GRID = 129


def shape_of(source):
    """A copy of ``source``'s shape in global coordinates: a Part.Shape is taken as is,
    a document object gets its global placement (containers included)."""
    if isinstance(source, Part.Shape):
        return source.copy()
    shape = source.Shape.copy()
    if hasattr(source, "getGlobalPlacement"):
        shape.Placement = source.getGlobalPlacement()
    return shape


def _vec(v):
    return np.array([v.x, v.y, v.z], dtype=np.float64)


def _normals(face, uv):
    return np.array([_vec(face.normalAt(float(u), float(v))) for u, v in uv])


def _pieces(length, gap):
    return max(1, int(math.ceil(length / gap - 1e-12)))


def _arc_deviation(a, m, b):
    """Angle of the middle sample m from the great circle through a and b."""
    c = np.cross(a, b)
    nc = np.linalg.norm(c)
    if nc < 1e-15:
        return math.acos(max(-1.0, min(1.0, float(a @ m))))
    return math.asin(min(1.0, abs(float(m @ c)) / nc))


def _small_circle_samples(face, u0, u1, v, deflection):
    """u values along a small circle (v fixed) whose pieces deviate <= deflection from
    great arcs; returns (us, deviation)."""
    k = _pieces(u1 - u0, math.pi / 2)
    while True:
        us = np.linspace(u0, u1, k + 1)
        mids = (us[:-1] + us[1:]) / 2
        a = _normals(face, [(u, v) for u in us])
        m = _normals(face, [(u, v) for u in mids])
        dev = max(_arc_deviation(a[i], m[i], a[i + 1]) for i in range(k))
        if dev <= deflection or k >= 4096:
            return us, dev
        k *= 2


def face_gauss(face, deflection=DEFAULT_DEFLECTION, name=""):
    """:class:`mfgeom.parting.FaceGauss` of one face (global, orientation respected)."""
    u0, u1, v0, v1 = face.ParameterRange
    surf = face.Surface
    area = float(face.Area)
    if isinstance(surf, Part.Plane):
        n = _normals(face, [((u0 + u1) / 2, (v0 + v1) / 2)])
        return FaceGauss(n, 0.0, area, name)
    if isinstance(surf, Part.Cylinder):
        us = np.linspace(u0, u1, _pieces(u1 - u0, math.pi / 2) + 1)
        vm = (v0 + v1) / 2
        return FaceGauss(_normals(face, [(u, vm) for u in us]), 0.0, area, name)
    if isinstance(surf, Part.Cone):
        vm = (v0 + v1) / 2
        us, dev = _small_circle_samples(face, u0, u1, vm, deflection)
        return FaceGauss(_normals(face, [(u, vm) for u in us]), dev, area, name)
    if isinstance(surf, (Part.Sphere, Part.Toroid)):
        # meridians are great circles: gaps <= pi/2 are exact along v
        vs = np.linspace(v0, v1, _pieces(v1 - v0, math.pi / 2) + 1)
        # the parallel farthest from both the equator and the pole (|sin v cos v| max)
        # deviates most for a given u step
        v_worst = max(vs.tolist() + [c for c in (math.pi / 4, -math.pi / 4, 3 * math.pi / 4,
                                                 -3 * math.pi / 4) if v0 <= c <= v1],
                      key=lambda v: abs(math.sin(v) * math.cos(v)))
        us, dev = _small_circle_samples(face, u0, u1, v_worst, deflection)
        uv = [(u, v) for u in us for v in vs]
        return FaceGauss(_normals(face, uv), dev, area, name)
    return _grid_gauss(face, deflection, name, area)


def _plane_deviation(a, b, m):
    """Angles of normals m from the great circles through a and b (row-wise)."""
    c = np.cross(a, b)
    nc = np.linalg.norm(c, axis=-1)
    far = np.arccos(np.clip(np.sum(a * m, axis=-1), -1.0, 1.0))
    near = np.arcsin(np.clip(np.abs(np.sum(m * c, axis=-1)) / np.maximum(nc, 1e-300), 0, 1))
    return np.where(nc > 1e-12, near, far)


def _grid_gauss(face, deflection, name, area):
    """UV grid of k x k cells; the normals at the cells' edge midpoints and centres (a
    grid twice as fine) measure how far the surface's normals leave the great arcs
    between neighbouring samples; shrink = twice the largest such deviation (the factor
    covers the deviation's peak not being exactly at a midpoint).  k doubles until
    shrink <= deflection (or the grid reaches 128 x 128 cells)."""
    u0, u1, v0, v1 = face.ParameterRange
    k = 8
    while True:
        us = np.linspace(u0, u1, 2 * k + 1)
        vs = np.linspace(v0, v1, 2 * k + 1)
        fine = _normals(face, [(u, v) for u in us for v in vs]).reshape(2 * k + 1, 2 * k + 1, 3)
        n = fine[::2, ::2]
        dev = max(_plane_deviation(n[:-1, :], n[1:, :], fine[1::2, ::2]).max(),
                  _plane_deviation(n[:, :-1], n[:, 1:], fine[::2, 1::2]).max(),
                  np.minimum(_plane_deviation(n[:-1, :-1], n[1:, 1:], fine[1::2, 1::2]),
                             _plane_deviation(n[1:, :-1], n[:-1, 1:], fine[1::2, 1::2])).max())
        shrink = 2.0 * float(dev)
        if shrink <= deflection or k >= _MAX_GRID - 1:
            return FaceGauss(n.reshape(-1, 3), shrink, area, name)
        k *= 2


def _oriented_tangent(edge, face, t):
    """Tangent of ``edge`` at t as the edge runs in ``face`` (face on its left, seen
    from the face's outward normal): OCCT orients a face's edges that way."""
    for e in face.Edges:
        if e.isSame(edge):
            tan = _vec(e.tangentAt(t))
            return -tan if e.Orientation == "Reversed" else tan
    raise ValueError("edge not in face")


def edge_kind(edge, f1, f2, tangent_tol=DEFAULT_TANGENT_TOL):
    """'concave', 'convex' or 'tangent' for the edge shared by faces f1 and f2, from
    their outward normals at the edge's middle: with T the edge's tangent as it runs in
    f1, the dihedral is convex when (n1 x n2) . T > 0 (f2 turns away from the material)."""
    t0, t1 = edge.ParameterRange
    t = (t0 + t1) / 2
    p = edge.valueAt(t)
    n = []
    for f in (f1, f2):
        u, v = f.Surface.parameter(p)
        n.append(_vec(f.normalAt(u, v)))
    c = np.cross(n[0], n[1])
    if math.atan2(np.linalg.norm(c), float(n[0] @ n[1])) <= tangent_tol:
        return "tangent"
    tan = _oriented_tangent(edge, f1, t)
    return "convex" if float(c @ tan) > 0 else "concave"


def adjacency(shape, tangent_tol=DEFAULT_TANGENT_TOL):
    """[(i, j, kind)] for every edge shared by faces i < j of ``shape`` (0-based)."""
    faces = shape.Faces
    # hash code -> [[edge, owner faces], ...]: different edges may share a hash code
    # (OCCT's are pointer-based; seen on a 4999-face part), so isSame decides
    buckets = {}
    for i, f in enumerate(faces):
        for e in f.Edges:
            if e.Degenerated:
                continue
            bucket = buckets.setdefault(e.hashCode(), [])
            entry = next((x for x in bucket if x[0].isSame(e)), None)
            if entry is None:
                entry = [e, []]
                bucket.append(entry)
            if i not in entry[1]:
                entry[1].append(i)
    out = []
    for bucket in buckets.values():
        for edge, lst in bucket:
            for a in range(len(lst)):
                for b in range(a + 1, len(lst)):
                    i, j = lst[a], lst[b]
                    out.append((i, j, edge_kind(edge, faces[i], faces[j], tangent_tol)))
    return sorted(out)


def part_gauss(source, deflection=DEFAULT_DEFLECTION, tangent_tol=DEFAULT_TANGENT_TOL,
               face_names=None):
    """(faces, adjacency, shape): a FaceGauss per face of ``source`` (named "FaceN" as
    in the source's shape), the edge adjacency with kinds (indices into ``faces``), and
    the global shape they were computed on.  ``face_names`` (e.g. ["Face3", "Face7"]):
    only those faces, joined only across edges they share with each other."""
    shape = shape_of(source)
    all_faces = shape.Faces
    if face_names is None:
        chosen = list(range(len(all_faces)))
    else:
        chosen = []
        for name in face_names:
            if not (name.startswith("Face") and name[4:].isdigit()
                    and 1 <= int(name[4:]) <= len(all_faces)):
                raise ValueError(f"{name!r} is not a face of a shape with {len(all_faces)} faces")
            if int(name[4:]) - 1 not in chosen:
                chosen.append(int(name[4:]) - 1)
        chosen.sort()
        if not chosen:
            raise ValueError("no faces given")
    faces = [face_gauss(all_faces[i], deflection, f"Face{i + 1}") for i in chosen]
    index = {i: k for k, i in enumerate(chosen)}
    adj = [(index[i], index[j], kind) for i, j, kind in adjacency(shape, tangent_tol)
           if i in index and j in index]
    return faces, adj, shape
