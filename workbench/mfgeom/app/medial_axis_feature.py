# SPDX-License-Identifier: LGPL-2.1-or-later
"""The parametric "medial axis of a face" feature (issue 9, section 4): App proxy, the
pure geometry function and the make function.

The medial axis (locus of centres of maximal inscribed discs) of a planar face, computed
by libmfgeom (:func:`mfgeom.core.medial_axis`) in the face's plane and placed back in 3-D
on the face: the feature's Shape is a compound of one wire per branch (through the
branch's samples: straight edges, arcs where the samples lie on a circle within a tenth
of the tolerance -- the axis between concentric circles is a circle, and comes out as
one) and one vertex per junction.  The clearance radius (distance to the
face's boundary) along every branch is data: ``Radii`` (flat, in the order of the wires'
points) with ``BranchOffsets`` (branch b's radii are Radii[BranchOffsets[b] ..
BranchOffsets[b+1]]; :func:`branch_radii` gives the lists), ``MinRadius`` / ``MaxRadius``
and ``JunctionCount``.  It is recomputed when the face (its object) changes.

The face's boundary comes from :class:`mfgeom.app.face_domain.FaceDomain` (the same 2-D
frame and rings as point classification): straight edges exactly, curved edges as
polylines within 5 % of the tolerance, so the axis of a face with curved edges is that of
the polygon (a short branch runs to every polygon vertex of a convex arc).
"""

import math
import time
from typing import Tuple

import numpy as np

import FreeCAD

from mfgeom.app.feature_base import VERSION_PROPERTY, add_properties, FeatureProxy, Quantity
from mfgeom import progress
from mfgeom.errors import InputError
from mfgeom.geometry.circular_runs import arcs_of_branches

# 1: first release.  Bump when properties change and migrate in _upgrade().
VERSION = 1
TYPE = "Mfgeom::MedialAxis"
DEFAULT_TOLERANCE = 0.01   # mm
# A branch's samples that lie within this fraction of the tolerance of one circle are
# joined by arcs of it (issue 22: "arcs as arcs"): the samples are within the tolerance of
# the axis already; a tenth of it keeps a curve that is not circular (a parabola between
# a line and a circle) from being taken for one except where the two agree anyway.
ARC_FRACTION = 0.1


class MedialAxisInputError(InputError):
    """A bad face or tolerance given to the medial axis of a face."""


# ---------------------------------------------------------------------------- geometry
class FaceAxis:
    """The medial axis of a face in 3-D (plain data): ``branches`` (list of (k, 3)
    arrays), ``radii`` (list of (k,) arrays), ``junctions`` ((j, 3)), ``junction_radii``
    ((j,)), ``seconds`` (library time), ``circles`` (list of (k - 1, 4) arrays: the
    circle -- centre, radius -- each edge is an arc of, NaN for a straight edge; None:
    all straight) and ``normal`` (the face plane's, the circles' axis)."""

    def __init__(self, branches, radii, junctions, junction_radii, seconds, circles=None,
                 normal=None):
        self.branches, self.radii = branches, radii
        self.junctions, self.junction_radii = junctions, junction_radii
        self.seconds = seconds
        self.circles, self.normal = circles, normal


def check_planar_face(face, label="the face"):
    """MedialAxisInputError unless ``face`` is a planar Part face."""
    if getattr(face, "ShapeType", None) != "Face" or face.isNull():
        raise MedialAxisInputError(f"{label} is not a face")
    surface = getattr(face.Surface, "TypeId", type(face.Surface).__name__)
    if surface != "Part::GeomPlane":
        raise MedialAxisInputError(f"{label} is not planar ({surface.replace('Part::Geom', '')}"
                                   "): the medial axis needs a planar face")


def face_medial_axis(face, tolerance):
    """The medial axis of the planar ``face`` (global coordinates) within ``tolerance``
    mm, as a :class:`FaceAxis`.  MedialAxisInputError for a non-planar face or a bad
    tolerance; the library's MfgError otherwise."""
    from mfgeom import core
    from mfgeom.app.face_domain import FaceDomain
    check_planar_face(face)
    if not (math.isfinite(tolerance) and tolerance > 0.0):
        raise MedialAxisInputError(f"the tolerance must be a number > 0 mm, got {tolerance!r}")
    domain = FaceDomain(face, tolerance)
    try:
        rings = domain.rings
        t0 = time.perf_counter()
        axis = core.medial_axis(rings, tolerance, progress=progress.current())
        seconds = time.perf_counter() - t0
        # the centres of the boundary's circles: the axis between concentric ones is a
        # circle about them (arcs as arcs, mfgeom.geometry.circular_runs)
        centres = [tuple(e.Curve.Center) for e in face.Edges
                   if type(e.Curve).__name__ == "Circle"]
        centres = (domain.plane_xy(np.array(centres)) if centres else np.zeros((0, 2)))
        flat, radii = [], []
        for b in axis.branches:
            xy = np.asarray(b.points, dtype=np.float64).reshape(-1, 2)
            keep = _distinct_samples(domain.plane_points(xy))
            if keep.sum() >= 2:   # a branch shorter than rounding has no wire
                flat.append(xy[keep])
                radii.append(np.asarray(b.radii, dtype=np.float64)[keep])
        flat, flat_circles, moved = arcs_of_branches(flat, ARC_FRACTION * tolerance, centres)
        branches, circles = [], []
        for xy, c in zip(flat, flat_circles):
            branches.append(domain.plane_points(xy))
            lifted = np.full((len(c), 4), np.nan)
            arc = ~np.isnan(c[:, 0])
            if arc.any():
                lifted[arc, :3] = domain.plane_points(c[arc, :2])
                lifted[arc, 3] = c[arc, 2]
            circles.append(lifted)
        o, u1 = domain.plane_points(np.array([[0.0, 0.0], [1.0, 0.0]]))
        _o, v1 = domain.plane_points(np.array([[0.0, 0.0], [0.0, 1.0]]))
        normal = np.cross(u1 - o, v1 - o)
        jxy = np.asarray(axis.junctions.points, dtype=np.float64).reshape(-1, 2)
        jxy = np.array([moved.get((q[0], q[1]), q) for q in jxy.tolist()],
                       dtype=np.float64).reshape(-1, 2)
        junctions = domain.plane_points(jxy)
        junction_radii = np.asarray(axis.junctions.radii, dtype=np.float64)
    finally:
        domain.close()
    return FaceAxis(branches, radii, junctions, junction_radii, seconds, circles, normal)


def _distinct_samples(points):
    """Which of the samples ``points`` (k, 3) to keep: not those equal to the previous
    one (OCCT refuses a zero-length edge); the last sample is kept (it is the branch's
    end, and replaces the kept sample it coincides with)."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if len(points) < 2:
        return np.ones(len(points), dtype=bool)
    step = np.linalg.norm(np.diff(points, axis=0), axis=1)
    keep = np.concatenate([[True], step > 1e-12 * max(1.0, float(np.abs(points).max()))])
    if not keep[-1]:   # the end replaces the kept sample it coincides with
        last = np.flatnonzero(keep)[-1]
        keep[last], keep[-1] = False, True
    return keep


def shape_of_axis(axis):
    """A compound of one wire per branch and one vertex per junction.  A branch's wire
    has a vertex at every sample (its radius is Radii's); its edges are straight, or arcs
    of the circle the branch runs along there (``axis.circles``, see
    mfgeom.geometry.circular_runs)."""
    import Part
    parts = []
    circles = getattr(axis, "circles", None) or [None] * len(axis.branches)
    for pts, circ in zip(axis.branches, circles):
        vecs = [FreeCAD.Vector(*p) for p in pts.tolist()]
        if circ is None or np.isnan(circ[:, 0]).all():
            parts.append(Part.makePolygon(vecs))
            continue
        edges = []
        for i in range(len(vecs) - 1):
            edge = None
            if not np.isnan(circ[i, 0]):
                edge = _arc_edge(circ[i], axis.normal, vecs[i], vecs[i + 1])
            edges.append(edge if edge is not None else Part.makeLine(vecs[i], vecs[i + 1]))
        parts.append(Part.Wire(edges))
    parts.extend(Part.Vertex(FreeCAD.Vector(*p)) for p in axis.junctions.tolist())
    return Part.makeCompound(parts)


def _arc_edge(circle, normal, a, b):
    """The shorter arc from ``a`` to ``b`` (both on it) of the circle (centre x, y, z,
    radius) about ``normal``, or None when OCCT makes none.  Built on the circle itself,
    not through three points: a short edge's three points are too nearly collinear to
    give back the centre."""
    import Part
    try:
        geom = Part.Circle(FreeCAD.Vector(*circle[:3].tolist()),
                           FreeCAD.Vector(*np.asarray(normal).tolist()), float(circle[3]))
        t0, t1 = geom.parameter(a), geom.parameter(b)
        turn = math.remainder(t1 - t0, 2 * math.pi)   # (-pi, pi]: the shorter way
        if turn == 0.0:
            return None
        lo = t0 if turn > 0 else t0 + turn
        arc = Part.ArcOfCircle(geom, lo, lo + abs(turn)).toShape()
        # its ends as the wire's samples (rounding apart): the wire joins them
        off = max(min(v.Point.distanceToPoint(p) for p in (a, b)) for v in arc.Vertexes)
        return arc if off <= 1e-7 * max(1.0, float(circle[3])) else None
    except Part.OCCError:
        return None


def branch_radii(obj):
    """The clearance radii of a MedialAxis feature's branches, one list per branch (the
    order of its Shape's wires)."""
    off, r = list(obj.BranchOffsets), list(obj.Radii)
    return [r[off[b]:off[b + 1]] for b in range(len(off) - 1)]


def resolve_face(face_link):
    """(face in global coordinates, "Obj.FaceN" label) of a LinkSub value."""
    from mfgeom.app import refs
    if face_link is None:
        raise MedialAxisInputError("the face is gone; set the Face property again")
    obj, subs = face_link
    obj, sub = refs.normalize_face_ref((obj, subs))
    return refs.resolve_face(obj, sub), f"{obj.Label}.{sub}"


# ---------------------------------------------------------------------------- feature
class MedialAxis(FeatureProxy):
    """App proxy: recomputes the medial axis of its Face."""

    TYPE = TYPE
    VERSION = VERSION
    VIEW_PROVIDER = "mfgeom.gui.medial_view.ViewProviderMedialAxis"

    def _set_defaults(self, obj):
        obj.Tolerance = DEFAULT_TOLERANCE
        obj.setEditorMode("Placement", 2)   # the result is placed on the face already

    @staticmethod
    def _add_properties(obj):
        # (type, name, group, tooltip, read-only output?)
        spec = [
            ("App::PropertyLinkSub", "Face", "Medial axis", "The planar face (Object, FaceN)",
             False),
            ("App::PropertyLength", "Tolerance", "Medial axis",
             "The axis' samples and the radii between them are within this distance of the "
             "true axis and clearance", False),
            ("App::PropertyInteger", "BranchCount", "Result", "Branches (wires) of the axis",
             True),
            ("App::PropertyInteger", "JunctionCount", "Result",
             "Junctions (centres of discs touching 3 or more boundary elements)", True),
            ("App::PropertyFloat", "MinRadius", "Result",
             "Smallest clearance radius (mm) along the axis (0 at convex corners)", True),
            ("App::PropertyFloat", "MaxRadius", "Result",
             "Largest clearance radius (mm): the largest inscribed disc", True),
            ("App::PropertyFloatList", "Radii", "Result",
             "Clearance radius (mm) at every point of the wires, branch after branch", True),
            ("App::PropertyIntegerList", "BranchOffsets", "Result",
             "Branch b's radii are Radii[BranchOffsets[b] .. BranchOffsets[b+1]]", True),
            ("App::PropertyFloatList", "JunctionRadii", "Result",
             "Clearance radius (mm) at every junction (the vertices of the shape)", True),
            VERSION_PROPERTY,
        ]
        add_properties(obj, spec)

    def _execute(self, obj):
        face, name = resolve_face(obj.Face)
        check_planar_face(face, name)
        axis = face_medial_axis(face, float(obj.Tolerance.Value))
        sizes = [len(r) for r in axis.radii]
        flat = np.concatenate(axis.radii) if sizes else np.zeros(0)
        obj.Shape = shape_of_axis(axis)
        obj.Placement = FreeCAD.Placement()
        obj.Radii = flat.tolist()
        obj.BranchOffsets = np.concatenate([[0], np.cumsum(sizes)]).astype(int).tolist()
        obj.JunctionRadii = axis.junction_radii.tolist()
        obj.JunctionCount = len(axis.junction_radii)
        obj.MinRadius = float(flat.min()) if len(flat) else 0.0
        obj.MaxRadius = float(flat.max()) if len(flat) else 0.0
        obj.BranchCount = len(sizes)   # last: the view's summary reads it
        FreeCAD.Console.PrintLog(
            f"mfgeom: {obj.Label}: {len(sizes)} branches, {obj.JunctionCount} junctions, "
            f"radius {obj.MinRadius:.4g} .. {obj.MaxRadius:.4g} mm; library "
            f"{1e3 * axis.seconds:.1f} ms\n")


# ---------------------------------------------------------------------------- make
def length_value(value, what, error=None):
    """A length in mm from a number, a length Quantity or a string such as "0.1 mm";
    ``error`` (an InputError class, default MedialAxisInputError) says what is wrong."""
    fail = error or MedialAxisInputError
    if isinstance(value, bool) or value is None:
        raise fail(f"{what} must be a length, got {value!r}")
    if isinstance(value, str):
        try:
            value = FreeCAD.Units.Quantity(value)
        except ValueError:
            raise fail(f"{what}: cannot read {value!r}") from None
    if isinstance(value, FreeCAD.Units.Quantity):
        if value.Unit == FreeCAD.Units.Length:
            value = value.getValueAs("mm")
        elif value.Unit == FreeCAD.Units.Unit():
            value = value.Value
        else:
            raise fail(f"{what} must be a length, got {value.UserString}")
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise fail(f"{what} must be a length in mm, got {value!r}") from None
    if not (math.isfinite(value) and value > 0.0):
        raise fail(f"{what} must be a finite length > 0 mm, got {value!r}")
    return value


def make_medial_axis(doc: "FreeCAD.Document", face_ref: Tuple[object, str],
                     tolerance: Quantity = DEFAULT_TOLERANCE,
                     name: str = "MedialAxis") -> "FreeCAD.DocumentObject":
    """Create the medial axis of the planar face ``face_ref`` = ``(obj, "FaceN")`` in
    ``doc`` within ``tolerance`` (mm, a length Quantity or "0.01 mm") and compute it.
    Inputs are checked before anything is created (a face that is not planar, not a face
    or not in ``doc``: MedialAxisInputError); if the first recompute fails the object is
    removed again and the error (one line) raised.  Returns the new object."""
    from mfgeom.app import refs
    if doc is None or not hasattr(doc, "addObject"):
        raise MedialAxisInputError("no document given")
    obj, sub = refs.normalize_face_ref(face_ref)
    if obj.Document is not doc:
        raise MedialAxisInputError(f"'{obj.Label}' is not in document '{doc.Name}'")
    face = refs.resolve_face(obj, sub)
    check_planar_face(face, f"{obj.Label}.{sub}")
    tol = length_value(tolerance, "the tolerance")
    return MedialAxis.make(doc, name, {"Label": f"Medial axis of {obj.Label} {sub}",
                                       "Face": (obj, [sub]), "Tolerance": tol},
                           "medial axis")
