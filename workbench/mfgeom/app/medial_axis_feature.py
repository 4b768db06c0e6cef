# SPDX-License-Identifier: LGPL-2.1-or-later
"""The parametric "medial axis of a face" feature (issue 9, section 4): App proxy, the
pure geometry function and the make function.

The medial axis (locus of centres of maximal inscribed discs) of a planar face, computed
by libmfgeom (:func:`mfgeom.core.medial_axis`) in the face's plane and placed back in 3-D
on the face: the feature's Shape is a compound of one wire per branch (a polyline through
the branch's samples) and one vertex per junction.  The clearance radius (distance to the
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

# 1: first release.  Bump when properties change and migrate in _upgrade().
VERSION = 1
TYPE = "Mfgeom::MedialAxis"
DEFAULT_TOLERANCE = 0.01   # mm


class MedialAxisInputError(InputError):
    """A bad face or tolerance given to the medial axis of a face."""


# ---------------------------------------------------------------------------- geometry
class FaceAxis:
    """The medial axis of a face in 3-D (plain data): ``branches`` (list of (k, 3)
    arrays), ``radii`` (list of (k,) arrays), ``junctions`` ((j, 3)), ``junction_radii``
    ((j,)), ``seconds`` (library time)."""

    def __init__(self, branches, radii, junctions, junction_radii, seconds):
        self.branches, self.radii = branches, radii
        self.junctions, self.junction_radii = junctions, junction_radii
        self.seconds = seconds


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
        branches, radii = [], []
        for b in axis.branches:
            pts, rad = _distinct_samples(domain.plane_points(b.points), b.radii)
            if len(pts) >= 2:   # a branch shorter than rounding has no wire
                branches.append(pts)
                radii.append(rad)
        junctions = domain.plane_points(axis.junctions.points)
        junction_radii = np.asarray(axis.junctions.radii, dtype=np.float64)
    finally:
        domain.close()
    return FaceAxis(branches, radii, junctions, junction_radii, seconds)


def _distinct_samples(points, radii):
    """``points`` and ``radii`` without samples equal to the previous one (OCCT refuses a
    zero-length edge), the last sample kept (it is the branch's end)."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    radii = np.asarray(radii, dtype=np.float64)
    if len(points) < 2:
        return points, radii
    step = np.linalg.norm(np.diff(points, axis=0), axis=1)
    keep = np.concatenate([[True], step > 1e-12 * max(1.0, float(np.abs(points).max()))])
    if not keep[-1]:   # the end replaces the kept sample it coincides with
        last = np.flatnonzero(keep)[-1]
        keep[last], keep[-1] = False, True
    return points[keep], radii[keep]


def shape_of_axis(axis):
    """A compound of one polyline wire per branch and one vertex per junction."""
    import Part
    parts = []
    for pts in axis.branches:
        parts.append(Part.makePolygon([FreeCAD.Vector(*p) for p in pts.tolist()]))
    parts.extend(Part.Vertex(FreeCAD.Vector(*p)) for p in axis.junctions.tolist())
    return Part.makeCompound(parts)


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
