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


def shape_of(source, deep=True):
    """A copy of ``source``'s shape in global coordinates: a Part.Shape is taken as is,
    a document object gets its global placement (containers included).  ``deep=False``:
    a new shape object over the same topology and geometry (its own placement; no copy
    of the geometry, which took 0.2 s for 5000 faces) for callers that only read it."""
    if isinstance(source, Part.Shape):
        return source.copy() if deep else Part.Shape(source)
    shape = source.Shape.copy() if deep else Part.Shape(source.Shape)
    if hasattr(source, "getGlobalPlacement"):
        shape.Placement = source.getGlobalPlacement()
    return shape


def _normals(face, uv):
    """(k, 3) normals at the (u, v) pairs: one array built at the end, not one per
    normal (Face.normalAt's own cost is most of what is left)."""
    normal_at = face.normalAt
    return np.array([(n.x, n.y, n.z) for n in (normal_at(float(u), float(v)) for u, v in uv)],
                    dtype=np.float64).reshape(-1, 3)


def _pieces(length, gap):
    return max(1, int(math.ceil(length / gap - 1e-12)))


def _arc_deviations(a, m, b):
    """Angles of the middle samples m from the great circles through a and b (row-wise
    over (k, 3) arrays; where a and b are parallel, the angle of m from a)."""
    c = np.cross(a, b)
    nc = np.sqrt(np.einsum("ij,ij->i", c, c))
    far = np.arccos(np.clip(np.einsum("ij,ij->i", a, m), -1.0, 1.0))
    near = np.arcsin(np.minimum(1.0, np.abs(np.einsum("ij,ij->i", m, c))
                                / np.maximum(nc, 1e-300)))
    return np.where(nc < 1e-15, far, near)


def _small_circle_samples(face, u0, u1, v, deflection):
    """u values along a small circle (v fixed) whose pieces deviate <= deflection from
    great arcs; returns (us, normals at us, deviation).  Each doubling of the pieces
    keeps the normals already evaluated: linspace(u0, u1, 2k + 1)[::2] equals
    linspace(u0, u1, k + 1) exactly (the step is halved, a power of two), so only the
    new samples and the new middles cost Face.normalAt calls."""
    k = _pieces(u1 - u0, math.pi / 2)
    us = np.linspace(u0, u1, k + 1)
    a = _normals(face, [(u, v) for u in us])
    while True:
        mids = (us[:-1] + us[1:]) / 2
        m = _normals(face, [(u, v) for u in mids])
        dev = float(_arc_deviations(a[:-1], m, a[1:]).max())
        if dev <= deflection or k >= 4096:
            return us, a, dev
        k *= 2
        finer = np.linspace(u0, u1, k + 1)
        fresh = np.empty((k + 1, 3))
        fresh[::2] = a
        fresh[1::2] = _normals(face, [(u, v) for u in finer[1::2]])
        us, a = finer, fresh


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
        _us, normals, dev = _small_circle_samples(face, u0, u1, vm, deflection)
        return FaceGauss(normals, dev, area, name)
    if isinstance(surf, (Part.Sphere, Part.Toroid)):
        # meridians are great circles: gaps <= pi/2 are exact along v
        vs = np.linspace(v0, v1, _pieces(v1 - v0, math.pi / 2) + 1)
        # the parallel farthest from both the equator and the pole (|sin v cos v| max)
        # deviates most for a given u step
        v_worst = max(vs.tolist() + [c for c in (math.pi / 4, -math.pi / 4, 3 * math.pi / 4,
                                                 -3 * math.pi / 4) if v0 <= c <= v1],
                      key=lambda v: abs(math.sin(v) * math.cos(v)))
        us, _, dev = _small_circle_samples(face, u0, u1, v_worst, deflection)
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


def _oriented_tangent(edge, face, t, in_face=None):
    """Tangent of ``edge`` at t as the edge runs in ``face`` (face on its left, seen
    from the face's outward normal): OCCT orients a face's edges that way.
    ``in_face``: the edge as ``face.Edges`` lists it (its first occurrence), when the
    caller already has it (else the face's edges are searched: O(edges of the face))."""
    if in_face is None:
        in_face = next((e for e in face.Edges if e.isSame(edge)), None)
        if in_face is None:
            raise ValueError("edge not in face")
    tan = in_face.tangentAt(t)
    sign = -1.0 if in_face.Orientation == "Reversed" else 1.0
    return (sign * tan.x, sign * tan.y, sign * tan.z)


def _normal_at_point(face, p, surface=None):
    """Outward normal of ``face`` at the point p of it (its surface's parameters of p)."""
    u, v = (surface if surface is not None else face.Surface).parameter(p)
    n = face.normalAt(u, v)
    return (n.x, n.y, n.z)


class _FaceNormals:
    """Outward normals of one face at points on it, for :func:`adjacency`: the face's
    Surface is fetched once, and a plane's normal is evaluated once.  Face.normalAt
    builds a surface adaptor that bounds the face's parameters from all of its edges,
    so one call on a cube side with 600 holes costs ~0.1 ms; a plane's normal is the
    same at every point (the cross product of its constant first derivatives, oriented
    by the face)."""

    def __init__(self, face):
        self.face = face
        self.surface = face.Surface
        self.plane = isinstance(self.surface, Part.Plane)
        self.normal = None

    def at(self, p):
        if not self.plane:
            return _normal_at_point(self.face, p, self.surface)
        if self.normal is None:
            self.normal = _normal_at_point(self.face, p, self.surface)
        return self.normal


def edge_kind(edge, f1, f2, tangent_tol=DEFAULT_TANGENT_TOL, in_f1=None, normals=None):
    """'concave', 'convex' or 'tangent' for the edge shared by faces f1 and f2, from
    their outward normals at the edge's middle: with T the edge's tangent as it runs in
    f1, the dihedral is convex when (n1 x n2) . T > 0 (f2 turns away from the material).
    ``in_f1`` (the edge as f1.Edges lists it) and ``normals`` (a :class:`_FaceNormals`
    of f1 and one of f2) spare the searches and repeated OCCT evaluations when the
    caller has them (:func:`adjacency`).  Plain float arithmetic on 3-vectors: numpy's
    per-call overhead was most of the cost."""
    t0, t1 = edge.ParameterRange
    t = (t0 + t1) / 2
    p = edge.valueAt(t)
    n1, n2 = normals if normals is not None else (_FaceNormals(f1), _FaceNormals(f2))
    a, b = n1.at(p), n2.at(p)
    c = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    if math.atan2(math.sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                  a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) <= tangent_tol:
        return "tangent"
    tan = _oriented_tangent(edge, f1, t, in_f1)
    return "convex" if c[0] * tan[0] + c[1] * tan[1] + c[2] * tan[2] > 0 else "concave"


def adjacency(shape, tangent_tol=DEFAULT_TANGENT_TOL):
    """[(i, j, kind)] for every edge shared by faces i < j of ``shape`` (0-based).
    Linear in the number of edges: each face's edges are listed once, and each shared
    edge remembers how it runs in each of its faces (no search of a face's edges per
    shared edge, which was quadratic on faces with many holes)."""
    faces = shape.Faces
    # hash code -> [[edge, {owner face: the edge as that face lists it}], ...]: different
    # edges may share a hash code (OCCT's are pointer-based; seen on a 4999-face part),
    # so isSame decides
    buckets = {}
    for i, f in enumerate(faces):
        for e in f.Edges:
            if e.Degenerated:
                continue
            bucket = buckets.setdefault(e.hashCode(), [])
            entry = next((x for x in bucket if x[0].isSame(e)), None)
            if entry is None:
                entry = [e, {}]
                bucket.append(entry)
            entry[1].setdefault(i, e)   # the first occurrence, as face.Edges lists it
    normals = {}

    def normals_of(i):
        if i not in normals:
            normals[i] = _FaceNormals(faces[i])
        return normals[i]
    out = []
    for bucket in buckets.values():
        for edge, owners in bucket:
            lst = list(owners)
            for a in range(len(lst)):
                for b in range(a + 1, len(lst)):
                    i, j = lst[a], lst[b]
                    out.append((i, j, edge_kind(edge, faces[i], faces[j], tangent_tol,
                                                owners[i], (normals_of(i), normals_of(j)))))
    return sorted(out)


def part_gauss(source, deflection=DEFAULT_DEFLECTION, tangent_tol=DEFAULT_TANGENT_TOL,
               face_names=None):
    """(faces, adjacency, shape): a FaceGauss per face of ``source`` (named "FaceN" as
    in the source's shape), the edge adjacency with kinds (indices into ``faces``), and
    the global shape they were computed on (sharing the source's geometry: copy it before
    changing it).  ``face_names`` (e.g. ["Face3", "Face7"]):
    only those faces, joined only across edges they share with each other."""
    shape = shape_of(source, deep=False)   # only read here
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
