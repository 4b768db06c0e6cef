# SPDX-License-Identifier: LGPL-2.1-or-later
"""The parametric "point classification" feature: App proxy and make function (its view
provider is mfgeom.gui.pointclass_view).

The object is a Part::FeaturePython linked to a face and a point source, recomputed when
they or the tolerance change.  Its results are the points (property Points, a Points
kernel: binary float32 in the file, read and written through numpy) and their Classes in
the same order; its Shape stays empty, because a compound of one vertex per point costs
seconds per 10^5 points to build, colour and save.  The geometry lives in
:mod:`mfgeom.app.face_domain`.
"""

from typing import Optional, Tuple

import FreeCAD
import Part

from mfgeom.app import preferences, refs
from mfgeom.app.feature_base import VERSION_PROPERTY, add_properties, FeatureProxy, Quantity

# 1: first release; 2: Strict; 3: points in the Points kernel property, Shape empty.
# Bump when properties change and migrate in _upgrade().
VERSION = 3

TYPE = "Mfgeom::PointClassification"


class PointClassification(FeatureProxy):
    """App proxy: classifies the point source against the face on every recompute."""

    TYPE = TYPE
    VERSION = VERSION
    VIEW_PROVIDER = "mfgeom.gui.pointclass_view.ViewProviderPointClassification"

    def _set_defaults(self, obj):
        obj.Strict = True  # new objects: a point far from the surface is not in the face

    @staticmethod
    def _add_properties(obj):
        # (type, name, group, tooltip, read-only output?)
        spec = [
            ("App::PropertyLinkSub", "Face", "Input", "The face to classify against", False),
            ("App::PropertyLinkSub", "PointSource", "Input",
             "The points: a Points object, a Mesh, a sketch/Part object (its vertices) "
             "or selected vertices", False),
            ("App::PropertyLength", "Tolerance", "Input",
             "Points whose distance to the face boundary is at most this are ON", False),
            ("App::PropertyBool", "Strict", "Input",
             "Points farther than the tolerance from the face's surface are OUT (else they "
             "are classified by their projection onto the surface)", False),
            ("Points::PropertyPointKernel", "Points", "Result",
             "The classified points, in the order of the point source", True),
            ("App::PropertyIntegerList", "Classes", "Result",
             "Class of each point in input order: 0 = OUT, 1 = IN, 2 = ON", True),
            ("App::PropertyInteger", "CountIn", "Result", "Number of points IN the face", True),
            ("App::PropertyInteger", "CountOn", "Result",
             "Number of points ON the boundary (within the tolerance)", True),
            ("App::PropertyInteger", "CountOut", "Result", "Number of points OUT of the face",
             True),
            ("App::PropertyString", "Method", "Result",
             "plane: exact in the plane's frame; uv: in the face's parameter domain", True),
            ("App::PropertyFloat", "ParameterTolerance", "Result",
             "Tolerance handed to libmfgeom in 2-D units (the ON candidate band on curved faces)",
             True),
            ("App::PropertyFloat", "Distortion", "Result",
             "Largest over smallest stretch of the face's parametrisation (1 = isometric)", True),
            ("App::PropertyLength", "MaxDistanceToSurface", "Result",
             "Largest distance of a point to the face's surface (points are projected on it)",
             True),
            VERSION_PROPERTY,
        ]
        add_properties(obj, spec)

    def _upgrade(self, obj, old_version, old_properties):
        if "Strict" not in old_properties:
            obj.Strict = False  # older documents keep their results: projection
        if old_version < 3:
            self._points_out_of_shape(obj)

    @staticmethod
    def _points_out_of_shape(obj):
        """Version < 3 kept the points as a compound of vertices: move them into Points
        (so the results show before any recompute) and empty the Shape."""
        from mfgeom.app import pointcloud
        if not obj.Shape.isNull() and len(obj.Shape.Vertexes) == len(obj.Classes):
            obj.Points = pointcloud.array_to_kernel(pointcloud.shape_points(obj.Shape))
            obj.Classes = list(obj.Classes)  # the view redraws when Classes is written
        obj.Shape = Part.Shape()

    def _execute(self, obj):
        if obj.Face is None or obj.PointSource is None:
            raise refs.InputError("the linked face or point source is gone; "
                                  "set the Face and PointSource properties again")
        face_obj, face_sub = refs.normalize_face_ref(obj.Face)
        face = refs.resolve_face(face_obj, face_sub)
        src_obj, src_subs = refs.normalize_points_ref(obj.PointSource)
        points = refs.resolve_points(src_obj, src_subs)
        # Imported here: it loads libmfgeom, and a document must open (and show its last
        # results) even where the library is missing.
        from mfgeom.app import face_domain
        result = face_domain.classify_points_on_face(face, points, obj.Tolerance.Value,
                                                     strict=obj.Strict)
        from mfgeom.app import pointcloud
        kernel = refs.cloud_kernel(src_obj, src_subs)
        obj.Points = kernel if kernel is not None else pointcloud.array_to_kernel(points)
        if not obj.Shape.isNull():
            obj.Shape = Part.Shape()
        # Handed to the view provider with the Classes it is about to draw, so it need not
        # read them back from the kernel; not saved (see __getstate__).
        self.display_points = points
        obj.Classes = result.classes.tolist()
        self.display_points = None
        obj.CountIn = result.counts["in"]
        obj.CountOn = result.counts["on"]
        obj.CountOut = result.counts["out"]
        obj.Method = result.method
        obj.ParameterTolerance = result.tol_2d
        obj.Distortion = result.distortion
        obj.MaxDistanceToSurface = result.max_distance_to_surface
        FreeCAD.Console.PrintLog(
            f"mfgeom: {obj.Label}: {len(points)} points, IN {obj.CountIn}, ON {obj.CountOn}, "
            f"OUT {obj.CountOut} ({result.method}, {result.seconds * 1e3:.1f} ms)\n")
        warn, text = result.surface_report()
        if warn:
            FreeCAD.Console.PrintWarning(f"mfgeom: {obj.Label}: {text}\n")
        elif result.far_count:
            FreeCAD.Console.PrintMessage(f"mfgeom: {obj.Label}: {text}\n")


def _check_tolerance(tolerance):
    """The tolerance in mm from a number (mm), a length Quantity or a string such as
    "0.01 mm" or "10 um" (no unit: mm); InputError for anything else, e.g. "5 deg"."""
    if tolerance is None:
        return preferences.default_tolerance()
    if isinstance(tolerance, bool):
        raise refs.InputError(f"the tolerance must be a length, got {tolerance!r}")
    if isinstance(tolerance, str):
        try:
            tolerance = FreeCAD.Units.Quantity(tolerance)
        except ValueError:
            raise refs.InputError(f"the tolerance must be a length such as '0.01 mm', "
                                  f"got {tolerance!r}") from None
    if isinstance(tolerance, FreeCAD.Units.Quantity):
        if tolerance.Unit == FreeCAD.Units.Length:
            tolerance = tolerance.getValueAs("mm")
        elif tolerance.Unit == FreeCAD.Units.Unit():  # no unit: mm, as for a plain number
            tolerance = tolerance.Value
        else:
            raise refs.InputError(f"the tolerance must be a length, got {tolerance.UserString} "
                                  f"({tolerance.Unit.Type or 'no known quantity'})")
    try:
        tolerance = float(tolerance)
    except (TypeError, ValueError):
        raise refs.InputError(f"the tolerance must be a number of mm, got {tolerance!r}") from None
    if not tolerance >= 0.0 or tolerance == float("inf"):
        raise refs.InputError(f"the tolerance must be a finite number >= 0 mm, got {tolerance!r}")
    return tolerance


def make_point_classification(doc: "FreeCAD.Document", face_ref: Tuple[object, str],
                              points_ref: object,
                              tolerance: Optional[Quantity] = None,
                              name: str = "PointClassification",
                              strict: bool = True) -> "FreeCAD.DocumentObject":
    """Create a point classification feature in ``doc`` and compute it.

    ``face_ref``: ``(obj, "FaceN")``.  ``points_ref``: a Points, Mesh, Sketch or Part
    object (all its points/vertices) or ``(obj, ["Vertex1", ...])``.  ``tolerance``: a
    number in mm, a length Quantity or a string such as "0.01 mm" (None: the
    DefaultTolerance preference).  ``strict``: points farther than the tolerance from
    the face's surface are OUT (False: classified by their projection onto it).  The
    object's Label names what it classifies ("Classes of Face3 of Box").  The inputs are
    checked before anything is created; if the first recompute still fails, the object
    is removed again, so on an exception the document is left as it was.  Returns the
    new object.
    """
    if doc is None or not hasattr(doc, "addObject"):
        raise refs.InputError("no document given")
    face_obj, face_sub = refs.normalize_face_ref(face_ref)
    src_obj, src_subs = refs.normalize_points_ref(points_ref)
    for obj, what in ((face_obj, "face"), (src_obj, "points")):
        if obj.Document is not doc:
            raise refs.InputError(f"the {what} object '{obj.Label}' is in document "
                                  f"'{obj.Document.Name}', not in '{doc.Name}'")
    tolerance = _check_tolerance(tolerance)
    # Resolve now so a bad reference fails before the document changes.
    face = refs.resolve_face(face_obj, face_sub)
    refs.check_points(src_obj, src_subs)
    from mfgeom.app import face_domain
    least = face_domain.minimum_tolerance(face)
    if tolerance < least:
        raise refs.InputError(f"a tolerance of {tolerance:g} mm cannot be honoured on "
                              f"{face_sub} of '{face_obj.Label}': its boundary is only "
                              f"defined to {least:g} mm; use at least {least:g} mm")

    return PointClassification.make(doc, name, {
        "Label": f"Classes of {face_sub} of {face_obj.Label}", "Face": (face_obj, [face_sub]),
        "PointSource": (src_obj, src_subs), "Tolerance": tolerance, "Strict": bool(strict)},
        "point classification", error=RuntimeError)
