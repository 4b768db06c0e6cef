# SPDX-License-Identifier: LGPL-2.1-or-later
"""Clearance check of issue 8: will the rotating part (its swept volume) hit anything?
For each other solid, the volume of its interference with the sweep and the minimum
distance between the two.  FreeCAD App only (Part, Mesh), no GUI.

What it reports (all lengths in mm, ``tolerance`` absolute):

* Interference volume = volume of the common of the sweep and the solid.  Two solids that
  touch (a shared face, a box resting on the sweep) and a tessellated sweep whose facets
  stand up to ``tolerance`` proud of the true surface (the library's sweep is
  conservative by that much) give a common that is a film: zero volume, or a sliver no
  thicker than the tolerance.  So the common counts as interference only when it is
  thicker than the tolerance on average: V > tolerance * S / 2, S its surface area (a
  slab of thickness t over a contact area A has V = t A and S ~ 2 A).  Below that floor
  the volume is reported as 0.
* Minimum distance between the two boundaries (0 when the solids touch, overlap or one
  holds the other), with the closest points on the sweep and on the solid.
* Status: "interference" (volume above the floor), else "touching" (distance <= the
  tolerance), else "clear".  The sweep mesh lies on or up to ``tolerance`` outside the
  true swept volume, so a "clear" distance d means the true clearance is in [d, d + tol].
* An object that is not a solid (a sketch, an open shell, an open mesh, a deleted object)
  gets status "invalid" and a message saying what it is; one bad object never stops the
  others.  A sweep that is not a solid raises InputError.

How, for a sweep that is a triangle mesh (the sweep feature's exact double-precision
result, or a closed Mesh): :class:`MeshSweep`, without making the whole mesh a Part solid
(minutes for 10^4 triangles, and OCCT's Booleans against it took minutes each).

* Distance: exact, a branch and bound on the solid's tessellation
  (:func:`mesh_min_distance`): numpy's triangle distances are exact to its planar faces
  and bound the distance to its curved ones; OCCT (``distToShape``) measures only the
  sweep triangles whose bound to a curved face beats the best distance so far, so only
  those become Part faces.
* Apart boundaries (distance > 0): the solid is inside the sweep when a point of it is
  (the parity of a ray's crossings of the mesh, :mod:`mfgeom.geometry.trimesh`), the
  sweep inside the solid when a vertex of it is (OCCT's classifier); the common is then
  the inner one whole, else empty.
* Meeting boundaries: the solid is split by the sweep's triangles in its box that may
  meet its boundary or lie inside it (:func:`_patch`; coplanar ones merged into planar
  faces, :mod:`mfgeom.app.mesh_shapes`; they hold all of the sweep's boundary inside
  the solid, and their own boundary lies outside it) with OCCT's General Fuse; a piece is inside the sweep when its faces on the sweep's
  triangles face the same way as they (else by a point of it), and the common is the
  pieces inside.  Only the solid and the nearby triangles enter OCCT.

A sweep that is a Part solid (curved faces: a Part solid standing in for the swept
volume) is checked with OCCT's Boolean common and the same pruned distance as before.
"""

import csv

import numpy as np

import FreeCAD
import Part

from mfgeom.errors import InputError

INTERFERENCE = "interference"
TOUCHING = "touching"
CLEAR = "clear"
INVALID = "invalid"

# Sewing tolerance of mesh vertices into a shell: far below any machining tolerance, so
# the solid is the mesh's triangles as they are.
_MESH_SEWING = 1e-7


class ClearanceResult:
    """The answer for one object: ``name``, ``label``, ``status`` (INTERFERENCE, TOUCHING,
    CLEAR or INVALID), ``interference_volume`` (mm^3, 0 when none), ``min_distance`` (mm,
    0 when touching or overlapping; None when invalid), ``point_on_sweep`` and
    ``point_on_object`` (App.Vector, the closest points; None when invalid), ``message``
    (why an object is invalid, or a Boolean failure), ``common`` (the interference solid,
    a Part.Shape, or None)."""

    __slots__ = ("name", "label", "status", "interference_volume", "min_distance",
                 "point_on_sweep", "point_on_object", "message", "common")

    def __init__(self, name, label, status, interference_volume=0.0, min_distance=None,
                 point_on_sweep=None, point_on_object=None, message="", common=None):
        self.name = name
        self.label = label
        self.status = status
        self.interference_volume = interference_volume
        self.min_distance = min_distance
        self.point_on_sweep = point_on_sweep
        self.point_on_object = point_on_object
        self.message = message
        self.common = common

    @property
    def interferes(self):
        return self.status == INTERFERENCE

    def __repr__(self):
        return (f"ClearanceResult({self.label!r}, {self.status}, volume="
                f"{self.interference_volume:.6g}, distance={self.min_distance!r})")


def _label(obj):
    try:
        return obj.Label
    except (AttributeError, RuntimeError, ReferenceError):  # a deleted object
        return "<deleted object>"


def _name(obj):
    try:
        return obj.Name
    except (AttributeError, RuntimeError, ReferenceError):
        return ""


def _alive(obj):
    try:
        doc = obj.Document
        return doc is not None and doc.getObject(obj.Name) is not None
    except (AttributeError, RuntimeError, ReferenceError):
        return False


def mesh_solid(mesh):
    """A Part solid of the triangles of closed Mesh kernel ``mesh`` (its placement
    applied), outward oriented; InputError when the mesh does not bound a volume."""
    if mesh.CountFacets == 0:
        raise InputError("the mesh is empty")
    if not mesh.isSolid():
        raise InputError(f"the mesh is not closed ({mesh.CountFacets} triangles with "
                         "free edges or non-manifold edges): it bounds no volume")
    shape = Part.Shape()
    shape.makeShapeFromMesh(mesh.Topology, _MESH_SEWING)
    # one sewn shell for a closed mesh: made solid as it is (re-shelling its faces costs
    # as much again)
    shells = shape.Shells
    solid = Part.Solid(shells[0] if len(shells) == 1 else Part.Shell(shape.Faces))
    if solid.Volume < 0:   # a mesh oriented inward: the same volume, turned out
        solid.reverse()
    return solid


def _describe(shape):
    """What a shape without solids is, for a message."""
    if shape.isNull():
        return "an empty shape"
    if shape.Shells:
        free = sum(1 for s in shape.Shells if not s.isClosed())
        return f"{len(shape.Shells)} shell(s), {free} of them open"
    if shape.Faces:
        return f"{len(shape.Faces)} face(s) without a closed shell"
    if shape.Edges:
        return f"{len(shape.Edges)} edge(s) (a sketch or a wire?)"
    if shape.Vertexes:
        return f"{len(shape.Vertexes)} vertex/vertices"
    return f"a {shape.ShapeType} with no geometry"


def solid_of(obj):
    """The solid(s) of document object ``obj`` in global coordinates, as one Part shape:
    its Shape's solids, its closed shells made solid, or its closed Mesh as a solid.
    InputError (with what the object is instead) otherwise."""
    if not _alive(obj):
        raise InputError(f"{_label(obj)} is not in a document (deleted?)")
    outer = _container_placement(obj)
    shape = None
    if hasattr(obj, "Shape"):
        shape = obj.Shape.copy()
        shape.Placement = outer.multiply(shape.Placement)
    if shape is not None and not shape.isNull():
        solids = list(shape.Solids)
        if not solids:
            solids = [Part.Solid(s) for s in shape.Shells if s.isClosed()]
        if solids:
            for s in solids:
                if s.Volume < 0:
                    s.reverse()
            return solids[0] if len(solids) == 1 else Part.makeCompound(solids)
    mesh = getattr(obj, "Mesh", None)
    if mesh is not None and hasattr(mesh, "Topology"):
        mesh = mesh.copy()
        mesh.Placement = outer.multiply(mesh.Placement)
        try:
            return mesh_solid(mesh)
        except InputError as exc:
            raise InputError(f"{_label(obj)}: {exc}") from None
    if shape is not None:
        raise InputError(f"{_label(obj)} is not a solid: {_describe(shape)}")
    raise InputError(f"{_label(obj)} is not a solid: it has neither a Shape nor a Mesh")


def check_volume_source(obj, what="the sweep"):
    """Raises InputError unless ``obj`` has a solid (or closed-shell) Shape or a closed
    Mesh: the cheap test of :func:`solid_of`, without building a mesh's solid."""
    if obj is None:
        raise InputError("no sweep selected: select the swept volume first, then the "
                         "solids to check against it")
    if not _alive(obj):
        raise InputError(f"{what}: {_label(obj)} is not in a document (deleted?)")
    shape = getattr(obj, "Shape", None)
    if shape is not None and not shape.isNull() and (
            shape.Solids or any(s.isClosed() for s in shape.Shells)):
        return
    mesh = getattr(obj, "Mesh", None)
    if mesh is not None and hasattr(mesh, "isSolid") and mesh.CountFacets and mesh.isSolid():
        return
    try:
        solid_of(obj)
    except InputError as exc:
        raise InputError(f"{what}: {exc}") from None


def _container_placement(obj):
    """The placement of the containers (App::Part, ...) around ``obj``: its global
    placement less its own, which its Shape or Mesh already carries."""
    try:
        return obj.getGlobalPlacement().multiply(obj.Placement.inverse())
    except AttributeError:   # no Placement: nothing around it moves it
        return FreeCAD.Placement()


def interference_floor(common, tolerance):
    """Volume below which a common counts as touching: a film of thickness ``tolerance``
    over half the common's surface (see the module's text)."""
    return tolerance * common.Area / 2.0


class FaceBoxes:
    """The faces of a shape and their bounding boxes ((n, 6) array: xmin, ymin, zmin,
    xmax, ymax, zmax), made once per shape: the pruning of :func:`min_distance`."""

    def __init__(self, shape):
        self.shape = shape
        self.faces = list(shape.Faces)
        self.boxes = np.array([_box(f.BoundBox) for f in self.faces]).reshape(-1, 6)

    def near(self, box, limit):
        """Indices of the faces whose box lies within ``limit`` of ``box``."""
        return np.flatnonzero(_box_gaps(self.boxes, box) <= limit)

    def nearest(self, box, k):
        gaps = _box_gaps(self.boxes, box)
        return np.argsort(gaps, kind="stable")[:k]

    def compound(self, indices):
        return Part.makeCompound([self.faces[i] for i in indices])


def _box(bb):
    return (bb.XMin, bb.YMin, bb.ZMin, bb.XMax, bb.YMax, bb.ZMax)


def _box_gaps(boxes, box):
    """Euclidean gap between each row of ``boxes`` and ``box`` (0 where they meet)."""
    b = np.asarray(box, dtype=np.float64)
    gap = np.maximum(0.0, np.maximum(boxes[:, :3] - b[3:], b[:3] - boxes[:, 3:]))
    return np.sqrt((gap * gap).sum(axis=1))


# Below this many face pairs OCCT's distToShape is fast enough alone.
_DIRECT_PAIRS = 20000
_SEED_FACES = 8


def min_distance(a, b, a_faces=None):
    """(distance, point on a, point on b) between the boundaries of shapes ``a`` and
    ``b``, exact as OCCT's distToShape but on the faces that can matter.

    BRepExtrema compares every face with every face: 14 000 sweep triangles against a
    box took minutes.  Here a branch and bound: a few faces of each nearest the other's
    bounding box give an upper bound U; then the faces of ``a`` in order of their boxes'
    gap to ``b``'s box, in doubling batches, each against the faces of ``b`` within U of
    the batch's box, until the next gap exceeds U.  A face whose box is farther than U
    cannot hold the minimum, so the answer is the minimum over all pairs.  Boundaries
    only: call it for solids that do not overlap (their distance is 0 otherwise)."""
    a_faces = a_faces or FaceBoxes(a)
    b_faces = FaceBoxes(b)
    if len(a_faces.faces) * len(b_faces.faces) <= _DIRECT_PAIRS:
        d, pairs, _ = a.distToShape(b)
        return d, pairs[0][0], pairs[0][1]
    a_box, b_box = _box(a.BoundBox), _box(b.BoundBox)
    seed_a = a_faces.compound(a_faces.nearest(b_box, _SEED_FACES))
    seed_b = b_faces.compound(b_faces.nearest(a_box, _SEED_FACES))
    best, pairs, _ = seed_a.distToShape(seed_b)
    best_pair = pairs[0]
    gaps = _box_gaps(a_faces.boxes, b_box)
    order = np.argsort(gaps, kind="stable")
    start, batch = 0, _SEED_FACES
    while start < len(order) and gaps[order[start]] <= best:
        chunk = [i for i in order[start:start + batch] if gaps[i] <= best]
        start, batch = start + batch, 2 * batch
        part = a_faces.compound(chunk)
        near_b = b_faces.near(_box(part.BoundBox), best)
        if not len(near_b):
            continue
        d, pairs, _ = part.distToShape(b_faces.compound(near_b))
        if d < best:
            best, best_pair = d, pairs[0]
    return best, best_pair[0], best_pair[1]


def _a_point_of(shape):
    if shape.Vertexes:
        return shape.Vertexes[0].Point
    face = shape.Faces[0]
    u0, u1, v0, v1 = face.ParameterRange
    return face.valueAt((u0 + u1) / 2, (v0 + v1) / 2)


def _common(sweep, solid, tolerance, sweep_faces=None):
    """OCCT's Boolean common of the two solids, skipped when no face of the sweep comes
    near the solid's bounding box: then their boundaries do not meet and the sweep is not
    inside the solid (its faces would be in the box), so the common is the whole solid
    when a point of it is inside the sweep, else empty."""
    if sweep_faces is not None and not len(sweep_faces.near(_box(solid.BoundBox),
                                                            tolerance)):
        if sweep.isInside(_a_point_of(solid), 0.0, True):
            return solid.copy()
        return Part.makeCompound([])
    return sweep.common(solid)


_SAMPLES = 4000
_RAY = np.array([0.48, 0.6, 0.64]) / np.linalg.norm([0.48, 0.6, 0.64])


def inside_mesh(points, triangles):
    """Boolean per point: inside the closed triangle soup ``triangles`` ((T, 3, 3)), by
    the parity of a ray's crossings (Moller-Trumbore); needs no valid OCCT solid."""
    p0 = triangles[:, 0]
    e1, e2 = triangles[:, 1] - p0, triangles[:, 2] - p0
    h = np.cross(_RAY, e2)
    det = np.einsum("ij,ij->i", e1, h)
    ok = np.abs(det) > 1e-14
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    out = np.zeros(len(points), dtype=bool)
    for k in range(0, len(points), 32):   # 32 points x T triangles at a time
        sv = points[k:k + 32, None, :] - p0[None]
        u = np.einsum("pij,ij->pi", sv, h) * inv
        q = np.cross(sv, e1[None])
        v = (q @ _RAY) * inv
        t = np.einsum("ij,pij->pi", e2, q) * inv
        hits = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        out[k:k + 32] = (np.count_nonzero(hits, axis=1) & 1).astype(bool)
    return out


def sampled_common_volume(triangles, box, solid, seed=8):
    """(volume, standard error, a point inside both) of the part of ``solid`` inside the
    triangle mesh, by _SAMPLES uniform points in ``box`` (which holds the common); for a
    sweep solid OCCT's Booleans cannot use."""
    lo, hi = np.array(box[:3]), np.array(box[3:])
    size = np.maximum(hi - lo, 0.0)
    box_volume = float(np.prod(size))
    if box_volume <= 0.0:
        return 0.0, 0.0, None
    pts = lo + np.random.default_rng(seed).random((_SAMPLES, 3)) * size
    in_solid = np.array([solid.isInside(FreeCAD.Vector(*p), 0.0, True) for p in pts])
    both = np.zeros(len(pts), dtype=bool)
    both[in_solid] = inside_mesh(pts[in_solid], triangles)
    f = both.mean()
    se = box_volume * np.sqrt(f * (1.0 - f) / len(pts))
    point = FreeCAD.Vector(*pts[np.flatnonzero(both)[0]]) if both.any() else None
    return box_volume * f, se, point


def _check_one(sweep, obj, tolerance, sweep_faces=None, triangles=None):
    name, label = _name(obj), _label(obj)
    try:
        solid = solid_of(obj)
    except InputError as exc:
        return ClearanceResult(name, label, INVALID, message=str(exc))
    message = ""
    common = None
    try:
        common = _common(sweep, solid, tolerance, sweep_faces)
    except (Part.OCCError, RuntimeError) as exc:  # OCCT gave up: say so, keep the distance
        message = f"Boolean common failed: {exc}"
    if common is not None and common.Volume > interference_floor(common, tolerance):
        # BRepExtrema's points for nested solids are not on both shapes; a vertex of the
        # common (the one nearest its centre) is, and shows where they interfere.
        centre = common.BoundBox.Center
        point = min((v.Point for v in common.Vertexes), key=lambda p: (p - centre).Length)
        return ClearanceResult(name, label, INTERFERENCE, common.Volume, 0.0, point, point,
                               message, common)
    try:
        if common is not None and common.Volume > 0.0:
            # a film thinner than the tolerance: they overlap, so the distance is 0 (a
            # sheet inside the sweep is nowhere near its boundary)
            point = common.Vertexes[0].Point
            distance, p_sweep, p_obj = 0.0, point, point
        elif common is not None:
            distance, p_sweep, p_obj = min_distance(sweep, solid, sweep_faces)
        else:   # no common to rule out nesting: OCCT's solid-aware distance
            distance, pairs, _info = sweep.distToShape(solid)
            p_sweep, p_obj = pairs[0]
    except (Part.OCCError, RuntimeError) as exc:
        return ClearanceResult(name, label, INVALID, message=(
            f"{label}: distance failed: {exc}" + (f"; {message}" if message else "")))
    if triangles is not None and distance <= tolerance:
        # the sweep solid is invalid, so an empty Boolean proves nothing: sample
        both = np.array([max(a, b) for a, b in zip(_box(sweep.BoundBox)[:3],
                                                  _box(solid.BoundBox)[:3])]
                        + [min(a, b) for a, b in zip(_box(sweep.BoundBox)[3:],
                                                     _box(solid.BoundBox)[3:])])
        volume, se, point = sampled_common_volume(triangles, both, solid)
        if point is not None and volume > 2.0 * se:
            return ClearanceResult(name, label, INTERFERENCE, volume, 0.0, point, point,
                                   "; ".join(m for m in (message, (
                                       f"volume estimated from {_SAMPLES} samples "
                                       f"(+- {se:.3g} mm^3)")) if m))
    status = TOUCHING if distance <= tolerance else CLEAR
    return ClearanceResult(name, label, status, 0.0, distance, p_sweep, p_obj, message)


# --------------------------------------------------------------------------- mesh sweeps
# Boundaries closer than this (mm) meet: OCCT's Precision::Confusion.
_CONTACT = 1e-7
# The obstacle's tessellation for the distance's lower bounds: its deflection relative to
# the obstacle's size (coarse is fine: it only prunes; OCCT gives the distance).
_OBSTACLE_DEFLECTION = 5e-4


class MeshSweep:
    """The sweep as a closed triangle mesh in double precision: the numpy queries of
    :class:`mfgeom.geometry.trimesh.TriangleMesh` and Part faces of its triangles,
    made only where OCCT must look (kept between obstacles)."""

    def __init__(self, vertices, triangles):
        from mfgeom.app.mesh_shapes import MeshFaces
        from mfgeom.geometry.trimesh import TriangleMesh
        self.mesh = TriangleMesh(vertices, triangles)
        if self.mesh.volume < 0:   # an inward mesh: the same volume, turned out
            self.mesh = TriangleMesh(vertices, np.asarray(triangles)[:, ::-1])
        self.maker = MeshFaces(self.mesh.vertices, self.mesh.triangles)
        self.bbox = self.mesh.bbox

    def compound(self, indices):
        return Part.makeCompound(self.maker.triangle_faces(indices))


def _obstacle_triangles(solid):
    """(planar (m, 3, 3), curved (k, 3, 3), deviation, curved faces, complete): the
    solid's faces tessellated at a deflection of _OBSTACLE_DEFLECTION of its size, split
    into the triangles of its planar faces (exact: they are the faces) and of its curved
    ones, within ``deviation`` (twice the deflection) of which the true surface lies;
    the curved faces themselves; and whether every face tessellated (else these bounds
    are not to be trusted)."""
    deflection = max(_OBSTACLE_DEFLECTION * solid.BoundBox.DiagonalLength, 1e-6)
    flat, round_, curved_faces, complete = [], [], [], True
    copy = solid.copy()
    try:
        # the coarse angular deflection of the sweep's own source mesh: Face.tessellate
        # alone also imposes a fine angle (a sphere of radius 2 at 0.002 mm did not
        # finish in minutes); the bounds need the linear deflection only
        import MeshPart
        MeshPart.meshFromShape(Shape=copy, LinearDeflection=deflection,
                               AngularDeflection=0.5, Relative=False)
    except ImportError:
        pass
    for face in copy.Faces:
        try:
            points, tris = face.tessellate(deflection)
        except (Part.OCCError, RuntimeError):
            points, tris = [], []
        if not tris:
            complete = False
            continue
        xyz = np.array([(q.x, q.y, q.z) for q in points], dtype=np.float64)
        corners = xyz[np.asarray(tris, dtype=np.int64)]
        if type(face.Surface).__name__ == "Plane":
            flat.append(corners)
        else:
            round_.append(corners)
    curved_faces = [f for f in solid.Faces if type(f.Surface).__name__ != "Plane"]

    def stack(parts):
        return np.vstack(parts) if parts else np.zeros((0, 3, 3))
    return (stack(flat), stack(round_), 2.0 * deflection, curved_faces,
            complete and bool(flat or round_))


# Sweep triangles measured by numpy at a time (in the order of their boxes' gaps), so a
# contact found early ends the search: 10^4 triangles inside an obstacle's box are common.
_CHUNK = 2048


def mesh_min_distance(msweep, solid):
    """(distance, point on the sweep, point on the solid) between the sweep's triangles
    and the solid's boundary, as exact as OCCT's distToShape over all of them.

    A branch and bound on the solid's tessellation (numpy,
    :func:`mfgeom.geometry.trimesh.mesh_distances`): to the triangles of its planar
    faces the distance is exact; to those of its curved faces it is within the
    tessellation's deviation of the true one, a lower bound per sweep triangle.  OCCT
    then measures only the sweep triangles whose lower bound to a curved face beats the
    best distance so far, in that order and in doubling batches against the curved faces
    near them, until the next bound exceeds the best (or the best is 0).  The sweep's
    triangles go to numpy in chunks in the order of their boxes' gaps to the solid's
    box; a contact (distance 0) ends the search.  A parallel planar face (the sweep's
    flat end above a plate: thousands of triangles at the same distance) costs no OCCT
    call."""
    from mfgeom.geometry.trimesh import mesh_distances
    mesh = msweep.mesh
    flat, curved, deviation, curved_faces, complete = _obstacle_triangles(solid)
    gaps = mesh.gaps(_box(solid.BoundBox))
    order = np.argsort(gaps, kind="stable")
    if not complete:   # some face did not tessellate: the boxes' gaps are the only bounds
        targets = list(solid.Faces)
        return _occt_search(msweep, order, gaps[order], np.inf, None, targets)
    # a first bound: corners of the nearest triangles (by box) to the obstacle's
    # tessellation corners, which lie on its surface (every 8th is enough)
    seeds = mesh.corners[order[:_SEED_FACES]].reshape(-1, 3)
    points = np.vstack([flat.reshape(-1, 3), curved.reshape(-1, 3)])[::8]
    upper = float(np.sqrt(((seeds[:, None, :] - points[None, :, :]) ** 2)
                          .sum(axis=2)).min())
    best, best_pair = np.inf, None
    kept, kept_bound = [], []
    for start in range(0, len(order), _CHUNK):
        limit = min(upper, best)
        chunk = order[start:start + _CHUNK]
        chunk = chunk[gaps[chunk] <= limit]
        if not len(chunk):
            break
        d, pa, pb = mesh_distances(mesh.corners[chunk], flat, limit)
        if np.isfinite(d).any():
            k = int(np.argmin(d))
            if d[k] < best:
                best, best_pair = float(d[k]), (FreeCAD.Vector(*pa[k]), FreeCAD.Vector(*pb[k]))
        near = mesh_distances(mesh.corners[chunk], curved, min(upper, best) + deviation)[0]
        if np.isfinite(near).any():
            upper = min(upper, float(near.min()) + deviation)
        bound = near - deviation
        kept.append(chunk[bound < best])
        kept_bound.append(np.maximum(bound[bound < best], 0.0))
        if best <= 0.0:
            break
        if (bound <= 0.0).any():
            # the sweep may cut a curved face here: ask OCCT before measuring more
            cand = np.concatenate(kept)
            bnd = np.concatenate(kept_bound)
            rank = np.argsort(bnd, kind="stable")[:4 * _SEED_FACES]
            best, best_pair = _occt_search(msweep, cand[rank], bnd[rank], best, best_pair,
                                           curved_faces, keep_going=False)
            if best <= 0.0:
                break
    if best > 0.0 and kept:
        cand, bound = np.concatenate(kept), np.concatenate(kept_bound)
        rank = np.argsort(bound, kind="stable")
        best, best_pair = _occt_search(msweep, cand[rank], bound[rank], best, best_pair,
                                       curved_faces, keep_going=False)
    if best_pair is None:   # nothing measured (cannot happen for a closed solid)
        return _occt_search(msweep, order[:_SEED_FACES], np.zeros(_SEED_FACES), np.inf,
                            None, [_boundary(solid)])
    return best, best_pair[0], best_pair[1]


def _occt_search(msweep, cand, bound, best, best_pair, targets, keep_going=True):
    """OCCT's distance from the sweep triangles ``cand`` (ordered by their lower
    ``bound``) to the faces ``targets`` near them, in doubling batches while a bound is
    below the best distance: (best, pair), or (distance, point, point) when
    ``keep_going`` (the search from scratch)."""
    from mfgeom.geometry.trimesh import box_gaps
    mesh = msweep.mesh
    target_boxes = np.array([_box(f.BoundBox) for f in targets]).reshape(-1, 6)
    start, batch = 0, _SEED_FACES
    while start < len(cand) and bound[start] < best and best > 0.0:
        chunk = cand[start:start + batch][bound[start:start + batch] < best]
        start, batch = start + batch, 2 * batch
        box = np.concatenate([mesh.boxes[chunk, :3].min(axis=0),
                              mesh.boxes[chunk, 3:].max(axis=0)])
        close = np.flatnonzero(box_gaps(target_boxes, box) < best)
        if not len(close):
            continue
        target = targets[close[0]] if len(close) == 1 else \
            Part.makeCompound([targets[k] for k in close])
        dist, pairs, _ = msweep.compound(chunk).distToShape(target)
        if dist < best:
            best, best_pair = dist, pairs[0]
    if keep_going:
        return best, best_pair[0], best_pair[1]
    return best, best_pair


def _interior_point(solid, tries=400, seed=3):
    """A point strictly inside ``solid`` (OCCT's classifier), or None: its centre of mass
    when that is inside, else uniform samples of its box."""
    centre = solid.CenterOfMass if hasattr(solid, "CenterOfMass") else solid.BoundBox.Center
    if solid.isInside(centre, 0.0, False):
        return centre
    bb = solid.BoundBox
    rng = np.random.default_rng(seed)
    lo, hi = np.array(_box(bb)[:3]), np.array(_box(bb)[3:])
    for p in rng.uniform(lo, hi, (tries, 3)):
        q = FreeCAD.Vector(*p)
        if solid.isInside(q, 0.0, False):
            return q
    return None


def _np(v):
    return np.array([v.x, v.y, v.z], dtype=np.float64)


def mesh_common(msweep, solid, margin):
    """(volume, area, pieces): the part of ``solid`` inside the mesh sweep, as the pieces
    of the solid that General Fuse splits off along the sweep's triangles near it (see
    the module's text).  ``margin``: how near a triangle's box must come to the solid's
    box to take part (a little above OCCT's tolerance)."""
    idx = msweep.mesh.near(_box(solid.BoundBox), margin)
    if not len(idx):
        return 0.0, 0.0, []
    idx = _patch(msweep, solid, idx, margin)
    faces, normals, _ = msweep.maker.faces(idx)
    pieces_of, face_normal = solid.generalFuse(faces, 0.0)[1], {}
    for k, images in enumerate(pieces_of[1:]):
        for image in images:
            face_normal[image.hashCode()] = normals[k]
    inside = []
    for piece in pieces_of[0]:
        votes = set()
        for face in piece.Faces:
            n = face_normal.get(face.hashCode())
            if n is None:
                continue
            u0, u1, v0, v1 = face.ParameterRange
            outward = face.normalAt(0.5 * (u0 + u1), 0.5 * (v0 + v1))
            votes.add(bool(_np(outward) @ n > 0.0))
        if len(votes) == 1:
            is_in = votes.pop()
        else:   # not split, or the faces disagree: ask a point of it
            point = _interior_point(piece)
            is_in = point is not None and bool(msweep.mesh.contains([_np(point)])[0])
        if is_in:
            inside.append(piece)
    return (sum(p.Volume for p in inside), sum(p.Area for p in inside), inside)


def _patch(msweep, solid, idx, margin):
    """Of the sweep's triangles ``idx`` (those in the solid's box), the ones General Fuse
    needs: those that may meet the solid's boundary (their boxes within ``margin`` of its
    tessellation's boxes, grown by the tessellation's deviation) and those inside it.
    The others lie wholly inside or outside; each edge-connected run of them is one or
    the other, told by one point (ray parity against the tessellation, exact that far
    from its surface).  The patch's own boundary then still lies outside the solid."""
    from mfgeom.geometry import planar
    from mfgeom.geometry.trimesh import TriangleMesh, min_box_gaps
    flat, curved, deviation, _faces, complete = _obstacle_triangles(solid)
    if not complete or len(idx) < 256:
        return idx
    corners = np.vstack([flat, curved])
    boxes = np.hstack([corners.min(axis=1) - deviation, corners.max(axis=1) + deviation])
    mesh = msweep.mesh
    far = min_box_gaps(mesh.boxes[idx], boxes) > margin
    rest = idx[far]
    if not len(rest):
        return idx
    owner, twin, _ = planar.edge_pairs(mesh.triangles[rest])
    pair = np.flatnonzero(twin > np.arange(len(twin)))
    run = planar.label_components(len(rest), owner[pair], owner[twin[pair]])
    first = np.unique(run, return_index=True)[1]
    surface = TriangleMesh(corners.reshape(-1, 3), np.arange(3 * len(corners)).reshape(-1, 3))
    inside = surface.contains(mesh.corners[rest[first]].mean(axis=1))
    keep = ~far
    keep[np.flatnonzero(far)] = inside[run]
    return idx[keep]


def _centre_vertex(shapes):
    """The vertex of ``shapes`` nearest their common box centre: a point on both the
    sweep and the solid where they interfere."""
    compound = Part.makeCompound(shapes)
    centre = compound.BoundBox.Center
    return min((v.Point for v in compound.Vertexes), key=lambda p: (p - centre).Length)


def _check_mesh_one(msweep, obj, tolerance):
    name, label = _name(obj), _label(obj)
    try:
        solid = solid_of(obj)
    except InputError as exc:
        return ClearanceResult(name, label, INVALID, message=str(exc))
    try:
        distance, p_sweep, p_obj = mesh_min_distance(msweep, solid)
        if distance > _CONTACT:
            # the boundaries are apart: one holds the other when a point of its
            # boundary is inside the other (an inner point would not tell which)
            if msweep.mesh.contains([_np(_a_point_of(solid))])[0]:
                volume, area, common = solid.Volume, solid.Area, [solid]
            elif solid.isInside(FreeCAD.Vector(*msweep.mesh.vertices[0]), 0.0, False):
                volume, area, common = msweep.mesh.volume, msweep.mesh.area, None
            else:
                volume, area, common = 0.0, 0.0, []
        else:
            volume, area, common = mesh_common(msweep, solid, 10.0 * _CONTACT)
    except (Part.OCCError, RuntimeError) as exc:   # OCCT gave up: say so
        return ClearanceResult(name, label, INVALID,
                               message=f"{label}: the check failed in OCCT: {exc}")
    if volume > tolerance * area / 2.0:
        if common is None:       # the sweep inside the solid
            point = FreeCAD.Vector(*msweep.mesh.vertices[0])
            common_shape = None
        else:
            point = _centre_vertex(common)
            common_shape = common[0] if len(common) == 1 else Part.makeCompound(common)
        return ClearanceResult(name, label, INTERFERENCE, volume, 0.0, point, point, "",
                               common_shape)
    if volume > 0.0:   # a film thinner than the tolerance: they overlap
        point = _centre_vertex(common) if common else FreeCAD.Vector(
            *msweep.mesh.vertices[0])
        return ClearanceResult(name, label, TOUCHING, 0.0, 0.0, point, point)
    status = TOUCHING if distance <= tolerance else CLEAR
    return ClearanceResult(name, label, status, 0.0, distance, p_sweep, p_obj)


def sweep_mesh_of(obj):
    """(vertices, triangles) of the sweep object as a closed mesh in global coordinates,
    or None when it is to be checked as a Part solid: the sweep feature's exact result
    (:func:`mfgeom.app.sweep_feature.exact_mesh`), else a closed Mesh property's points
    (single precision, as stored), else None.  InputError for an open mesh without a
    solid shape."""
    from mfgeom.app.sweep_feature import exact_mesh
    placement = _container_placement(obj)
    exact = exact_mesh(obj) if _is_sweep(obj) else None
    if exact is not None:
        matrix = placement.multiply(obj.Placement).toMatrix()
        vertices, triangles = exact
        if not matrix.isUnity():
            m = np.array(matrix.A).reshape(4, 4)
            vertices = vertices @ m[:3, :3].T + m[:3, 3]
        return vertices, triangles
    shape = getattr(obj, "Shape", None)
    if shape is not None and not shape.isNull() and shape.Solids:
        return None
    mesh = getattr(obj, "Mesh", None)
    if mesh is None or not hasattr(mesh, "Topology"):
        return None
    if mesh.CountFacets == 0:
        raise InputError(f"{_label(obj)}: the mesh is empty")
    if not mesh.isSolid():
        raise InputError(f"{_label(obj)}: the mesh is not closed ({mesh.CountFacets} "
                         "triangles with free edges or non-manifold edges): it bounds no "
                         "volume")
    mesh = mesh.copy()
    mesh.Placement = placement.multiply(mesh.Placement)
    points, facets = mesh.Topology
    return (np.array([(p.x, p.y, p.z) for p in points], dtype=np.float64).reshape(-1, 3),
            np.asarray(facets, dtype=np.int64).reshape(-1, 3))


def default_tolerance(sweep_obj):
    """The sweep's own Tolerance (the sweep feature's boundary is only that exact, so a
    finer floor would count its facets as interference), else the preference
    DefaultTolerance."""
    own = getattr(sweep_obj, "Tolerance", None)
    value = getattr(own, "Value", own)
    if isinstance(value, (int, float)) and value > 0.0:
        return float(value)
    from mfgeom.app import preferences
    return preferences.default_tolerance()


def _tolerance(tolerance):
    if hasattr(tolerance, "Unit"):       # a Quantity: must be a length
        if tolerance.Unit != FreeCAD.Units.Length:
            raise InputError(f"the tolerance must be a length, got {tolerance.UserString}")
        tolerance = tolerance.getValueAs("mm")
    elif isinstance(tolerance, str):
        q = FreeCAD.Units.Quantity(tolerance)
        return _tolerance(q if q.Unit != FreeCAD.Units.Unit() else float(q.Value))
    tolerance = float(tolerance)
    if not tolerance > 0.0 or tolerance != tolerance or tolerance == float("inf"):
        raise InputError(f"the tolerance must be a positive length in mm, got {tolerance!r}")
    return tolerance


def check_clearance(sweep_obj, others, tolerance=None):
    """Clearance of each object of ``others`` from the swept volume ``sweep_obj``.

    ``sweep_obj``: a document object with a solid Shape or a closed Mesh (the sweep
    feature, or any solid standing in for it); ``others``: document objects.
    ``tolerance``: mm, a length Quantity or a string such as "0.01 mm" (default:
    :func:`default_tolerance`).  Returns one :class:`ClearanceResult` per object, in
    order; an object that is not a solid (or is the sweep itself) gets status INVALID
    with a message.  Raises InputError when ``sweep_obj`` is missing or not a solid.
    The sweep is found by type (:func:`find_sweep`): a sweep feature among ``others``
    is the sweep, and ``sweep_obj`` one of the objects checked against it."""
    if sweep_obj is not None and not _is_sweep(sweep_obj) and \
            any(_is_sweep(o) for o in others):
        sweep_obj, others = find_sweep([sweep_obj] + list(others))
    elif sweep_obj is not None and _is_sweep(sweep_obj):
        find_sweep([sweep_obj] + list(others))     # two sweeps: say so
    check_volume_source(sweep_obj)
    tol = _tolerance(default_tolerance(sweep_obj) if tolerance is None else tolerance)
    try:
        mesh = sweep_mesh_of(sweep_obj)
    except InputError as exc:
        raise InputError(f"the sweep: {exc}") from None
    if mesh is not None:
        msweep = MeshSweep(*mesh)
        results = []
        for obj in others:
            if obj is sweep_obj:
                results.append(ClearanceResult(_name(obj), _label(obj), INVALID,
                                               message="this is the sweep itself"))
            else:
                results.append(_check_mesh_one(msweep, obj, tol))
        return results
    try:
        sweep = solid_of(sweep_obj)
    except InputError as exc:
        raise InputError(f"the sweep: {exc}") from None
    sweep, warning = valid_sweep(sweep)
    triangles = None
    if warning:   # sample against its triangles where the Boolean cannot be trusted
        points, facets = sweep.tessellate(tol)
        xyz = np.array([(p.x, p.y, p.z) for p in points])
        triangles = xyz[np.array(facets, dtype=np.int64).reshape(-1, 3)]
    results = []
    sweep_faces = FaceBoxes(sweep)
    for obj in others:
        if obj is sweep_obj:
            results.append(ClearanceResult(_name(obj), _label(obj), INVALID,
                                           message="this is the sweep itself"))
            continue
        result = _check_one(sweep, obj, tol, sweep_faces, triangles)
        if warning and result.status != INVALID:
            result.message = "; ".join(m for m in (result.message, warning) if m)
        results.append(result)
    return results


SWEEP_NOT_VALID = "the sweep's solid is not valid (OCCT check): its volume may be wrong"


def valid_sweep(sweep):
    """(solid, warning): the sweep solid, repaired by ShapeFix when OCCT finds it invalid
    (e.g. a mesh whose single-precision vertices left slivers); when it stays invalid
    OCCT's Boolean may return nothing, so every result carries SWEEP_NOT_VALID."""
    if sweep.isValid():
        return sweep, ""
    fixed = sweep.copy()
    try:
        fixed.fix(1e-7, 1e-7, 1e-4)
    except (Part.OCCError, RuntimeError):
        return sweep, SWEEP_NOT_VALID
    if fixed.isValid() and fixed.Solids:
        return fixed, ""
    return sweep, SWEEP_NOT_VALID


def _is_sweep(obj):
    try:
        return "Sweep" in getattr(getattr(obj, "Proxy", None), "Type", "")
    except (AttributeError, RuntimeError, ReferenceError):   # a deleted object
        return False


def _has_volume(obj):
    try:
        solid_of(obj)
    except (InputError, Part.OCCError, RuntimeError, ValueError):
        return False
    return True


def document_obstacles(sweep_obj):
    """The solids of the sweep's document to check by default: every object with a solid
    (or a closed mesh) except the sweep, its Source (the part that turns) and what that is
    made of (without a Source property: everything the sweep depends on), what is made
    from the sweep, and objects used by another candidate (a Cut's inputs, a Body's
    features: only the finished result counts, once)."""
    doc = sweep_obj.Document
    skip = {sweep_obj.Name}
    source = getattr(sweep_obj, "Source", None)
    if hasattr(source, "OutListRecursive"):
        # the part that turns and what it is made of; an axis taken from an edge of the
        # machine frame must not hide the frame
        skip.add(source.Name)
        skip.update(o.Name for o in source.OutListRecursive)
    else:
        skip.update(o.Name for o in sweep_obj.OutListRecursive)
    skip.update(o.Name for o in sweep_obj.InListRecursive)
    candidates = [o for o in doc.Objects if o.Name not in skip and _has_volume(o)]
    names = {o.Name for o in candidates}
    return [o for o in candidates if not any(p.Name in names for p in o.InList)]


def find_sweep(objects, stand_in=True):
    """(sweep, others) of ``objects`` (a selection, in any order): the one rotational
    sweep feature among them wherever it stands, and the others in their order (the
    sweep left out).  Two or more sweep features: InputError naming them (which one
    turns is not for us to guess).  None: with ``stand_in`` the first object stands for
    the swept volume (a solid or a closed mesh from elsewhere, as the macro API allows);
    without (the command, where the first-selected obstacle used to be taken for the
    sweep silently) InputError."""
    objects = [o for o in objects if o is not None]
    sweeps, seen = [], set()
    for o in objects:
        if _is_sweep(o) and _name(o) not in seen:
            seen.add(_name(o))
            sweeps.append(o)
    if len(sweeps) > 1:
        raise InputError(f"{len(sweeps)} rotational sweeps selected "
                         f"({', '.join(_label(o) for o in sweeps)}): select one sweep and "
                         "the solids to check against it")
    if sweeps:
        sweep = sweeps[0]
        first = next(i for i, o in enumerate(objects) if o is sweep)
        return sweep, objects[:first] + objects[first + 1:]
    if not stand_in or not objects:
        labels = ", ".join(_label(o) for o in objects[:4]) + (", ..." if len(objects) > 4
                                                              else "")
        raise InputError("no rotational sweep selected" + (f" (only {labels})" if labels
                                                           else "")
                         + ": select the sweep made by Rotational sweep, and the solids to "
                         "check against it")
    return objects[0], objects[1:]


def resolve(doc_or_sweep, others=None):
    """(sweep object, others) from the macro API's arguments: a document (its one sweep
    feature) or objects in any order (:func:`find_sweep`: the sweep feature among
    ``doc_or_sweep`` and ``others``, else ``doc_or_sweep`` stands in for it); ``others``
    None: :func:`document_obstacles`."""
    if doc_or_sweep is None:
        raise InputError("no sweep given")
    if isinstance(doc_or_sweep, FreeCAD.Document):
        sweeps = [o for o in doc_or_sweep.Objects if _is_sweep(o)]
        if len(sweeps) != 1:
            raise InputError(f"document {doc_or_sweep.Name} has {len(sweeps)} sweep "
                             "features: pass the sweep object instead")
        sweep_obj = sweeps[0]
    else:
        given = None if others is None else (
            [others] if hasattr(others, "TypeId") else list(others))
        sweep_obj, rest = find_sweep([doc_or_sweep] + (given or []))
        if given is not None:
            return sweep_obj, rest
    if others is None:
        others = document_obstacles(sweep_obj)
    elif hasattr(others, "TypeId"):
        others = [others]
    return sweep_obj, list(others)


def _fmt(value, digits=4):
    return "-" if value is None else f"{value:.{digits}f}"


def report_rows(results):
    """Rows (lists of strings) of the results table, the header first."""
    rows = [["Object", "Status", "Interference volume (mm^3)", "Min distance (mm)",
             "Closest point on sweep", "Closest point on object", "Note"]]
    for r in results:
        volume = "none" if r.status != INVALID and r.interference_volume == 0.0 \
            else ("-" if r.status == INVALID else _fmt(r.interference_volume))
        rows.append([r.label, r.status, volume, _fmt(r.min_distance),
                     _point(r.point_on_sweep), _point(r.point_on_object), r.message])
    return rows


def _point(p):
    return "-" if p is None else f"({p.x:.3f}, {p.y:.3f}, {p.z:.3f})"


def report_text(results, sweep_label="", tolerance=None):
    """The results as a fixed-width table (the Report view's text)."""
    rows = report_rows(results)
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]) - 1)]
    lines = []
    if sweep_label:
        tol = "" if tolerance is None else f" (tolerance {tolerance:g} mm)"
        lines.append(f"Clearance check against '{sweep_label}'{tol}:")
    for row in rows:
        cells = [c.ljust(w) for c, w in zip(row[:-1], widths)]
        lines.append("  ".join(cells + [row[-1]]).rstrip())
    n = sum(1 for r in results if r.interferes)
    lines.append(f"{n} of {len(results)} object(s) interfere.")
    return "\n".join(lines) + "\n"


def write_csv(results, path):
    """Writes the results table to a CSV file (the header first; numbers unrounded)."""
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(["name", "label", "status", "interference_volume_mm3",
                    "min_distance_mm", "sweep_x", "sweep_y", "sweep_z", "object_x",
                    "object_y", "object_z", "message"])
        for r in results:
            ps = [r.point_on_sweep.x, r.point_on_sweep.y, r.point_on_sweep.z] \
                if r.point_on_sweep is not None else ["", "", ""]
            po = [r.point_on_object.x, r.point_on_object.y, r.point_on_object.z] \
                if r.point_on_object is not None else ["", "", ""]
            w.writerow([r.name, r.label, r.status, repr(r.interference_volume),
                        "" if r.min_distance is None else repr(r.min_distance)]
                       + [repr(v) if v != "" else "" for v in ps + po] + [r.message])
