# SPDX-License-Identifier: LGPL-2.1-or-later
"""The parametric "parting analysis" feature (issue 7): App proxy and make function.

An App::FeaturePython linked to a solid; on every recompute it takes the solid's faces in
global coordinates (:mod:`mfgeom.app.gauss_map`) and computes, with
:mod:`mfgeom.parting`, either the mould parting direction with its undercuts and
side cores (Mode "Mould") or a 3-axis set-up plan (Mode "NC3Axis").  Results are plain
properties (directions global, faces named "FaceN" of the source's shape).  The last
analysis (faces, result, options) stays on the proxy, not saved, for the view provider
(mfgeom.gui.parting_view: coloured faces, arrows, visibility sphere) and the reports
(:func:`feature_report`); after a restore it is recomputed on demand without touching
the document (:func:`analysis_of`).
"""

import json
import math
import time
from typing import Optional, Sequence

import FreeCAD

from mfgeom.app.feature_base import VERSION_PROPERTY, add_properties, FeatureProxy, Quantity
from mfgeom.errors import InputError
from mfgeom.parting import DEFAULT_TOL   # mfgeom.parting loads the library lazily

# 1: first release.  2: Draft mode (PullDirection), per-face worst angles and zero-draft
# faces, warnings.  3: the angle "Deflection" renamed NormalDeflection (a deflection in
# mm is RayDeflection's; one word, one unit).  Bump when properties change and migrate
# in _upgrade().
VERSION = 3
TYPE = "Mfgeom::PartingAnalysis"
MODES = ["Mould", "NC3Axis", "Draft"]
WEIGHTINGS = ["Count", "Area"]


class PartingInputError(InputError):
    """A bad source or parameter given to the parting analysis."""


class PartingAnalysis(FeatureProxy):
    """App proxy: recomputes the parting analysis of its Source."""

    TYPE = TYPE
    VERSION = VERSION
    VIEW_PROVIDER = "mfgeom.gui.parting_view.ViewProviderPartingAnalysis"
    OBJECT_TYPE = "App::FeaturePython"

    def _set_defaults(self, obj):
        obj.Mode = MODES
        obj.Weighting = WEIGHTINGS
        obj.NormalDeflection = math.degrees(1e-3)
        obj.AngularTolerance = DEFAULT_TOL
        obj.PullDirection = FreeCAD.Vector(0, 0, 1)
        obj.RayCheck = True

    @staticmethod
    def _add_properties(obj):
        # (type, name, group, tooltip, read-only output?)
        spec = [
            ("App::PropertyLink", "Source", "Input", "The solid to analyse", False),
            ("App::PropertyStringList", "Faces", "Input",
             "Only these faces of the source (e.g. Face3); empty: all faces", False),
            ("App::PropertyEnumeration", "Mode", "Input",
             "Mould: parting direction, undercuts, side cores; NC3Axis: set-up plan; "
             "Draft: draft analysis along PullDirection", False),
            ("App::PropertyAngle", "DraftAngle", "Input",
             "Mould, Draft: least angle a face must make with the parting plane (faces "
             "below it are listed as insufficient draft; the direction is chosen without "
             "it); NC3Axis: tool-axis tilt allowance (maps shrunk by it)", False),
            ("App::PropertyVector", "PullDirection", "Input",
             "Draft: the pull direction (global), e.g. a face normal or an edge's "
             "direction", False),
            ("App::PropertyEnumeration", "Weighting", "Input",
             "Count: every concave-connected surface counts 1; Area: by its area", False),
            ("App::PropertyBool", "AllFaces", "Input",
             "NC3Axis: plan for every surface, not only the pockets (surfaces with a "
             "concave edge)", False),
            ("App::PropertyAngle", "NormalDeflection", "Input",
             "An angle (degrees, not a length): how far the normals of a sampled "
             "(non-analytic) face may deviate from its Gaussian map's samples, i.e. the "
             "largest angle by which its map is shrunk (default 0.057 deg = 1e-3 rad). "
             "The ray check's tessellation deflection, a length in mm, is RayDeflection",
             False),
            ("App::PropertyFloat", "AngularTolerance", "Input",
             "Radians (default 0.01 deg): normals closer than this are snapped together, "
             "walls within it of the parting plane are zero draft (CAD noise, not "
             "undercuts); every answer holds up to it", False),
            ("App::PropertyBool", "RayCheck", "Input",
             "Mould: check the answer with rays along +-d from sample points of every face "
             "(a face shadowed by another part of the solid is flagged)", False),
            ("App::PropertyLength", "RayDeflection", "Input",
             "Mould: a length (mm): the chordal deflection of the ray check's "
             "tessellation; 0: 1/500 of the part's bounding-box diagonal. (The angle of "
             "the Gaussian maps is NormalDeflection)", False),
            ("App::PropertyVector", "Direction", "Result",
             "Parting direction (core side +d) or main set-up direction, global", True),
            ("App::PropertyFloat", "MarginDeg", "Result",
             "How far (degrees) Direction may move and keep its surfaces covered", True),
            ("App::PropertyInteger", "CoveredCount", "Result",
             "Number of surfaces covered by Direction", True),
            ("App::PropertyInteger", "TotalCount", "Result",
             "Number of surfaces considered", True),
            ("App::PropertyFloat", "CoveredWeight", "Result",
             "Covered weight (Count: surfaces; Area: mm^2)", True),
            ("App::PropertyStringList", "UncoveredFaces", "Result",
             "Faces not covered by Direction (Mould: undercuts and insufficient draft)", True),
            ("App::PropertyStringList", "CoreFaces", "Result", "Mould: faces demoulded along +d",
             True),
            ("App::PropertyStringList", "CavityFaces", "Result",
             "Mould: faces demoulded along -d", True),
            ("App::PropertyStringList", "InsufficientDraftFaces", "Result",
             "Mould, Draft: faces with less than the draft (zero-draft faces included)",
             True),
            ("App::PropertyStringList", "ZeroDraftFaces", "Result",
             "Mould: faces whose normals all lie within the angular tolerance of the "
             "parting plane", True),
            ("App::PropertyFloatList", "WorstAngles", "Result",
             "Per face of the source (Face1 first; 0 for faces not analysed), degrees: "
             "the angle of its worst normal to the parting plane on its side "
             "(negative: undercut by that much); Draft: the lowest angle along +d", True),
            ("App::PropertyStringList", "PositiveDraftFaces", "Result",
             "Draft: faces drafted along +PullDirection", True),
            ("App::PropertyStringList", "NegativeDraftFaces", "Result",
             "Draft: faces drafted along -PullDirection", True),
            ("App::PropertyStringList", "StraddleFaces", "Result",
             "Draft: faces with normals on both sides of the parting plane", True),
            ("App::PropertyStringList", "ShadowedFaces", "Result",
             "Mould: faces the normals call demouldable whose rays along their side are "
             "blocked by the part (more than 2 % of their area)", True),
            ("App::PropertyStringList", "Warnings", "Result",
             "Faces skipped or approximated (e.g. no normal at a singular point)", True),
            ("App::PropertyVectorList", "SideCoreDirections", "Result",
             "Mould: side-core (slider) directions for the undercuts, global", True),
            ("App::PropertyStringList", "SideCores", "Result",
             "Mould: per side core, JSON {direction, margin_deg, faces}", True),
            ("App::PropertyStringList", "Setups", "Result",
             "NC3Axis: per set-up (main first), JSON {direction, margin_deg, faces}", True),
            ("App::PropertyStringList", "UnresolvedFaces", "Result",
             "Faces no single direction handles (with this draft / tilt)", True),
            ("App::PropertyStringList", "Surfaces", "Result",
             "Concave-connected surfaces, one entry of space-separated face names each", True),
            ("App::PropertyFloat", "MaxShrinkDeg", "Result",
             "Largest shrink (degrees) applied to a sampled face's map", True),
            VERSION_PROPERTY,
        ]
        add_properties(obj, spec)

    def _outdated(self, obj):
        # Faces came after version 1
        return super()._outdated(obj) or "Faces" not in obj.PropertiesList

    def _upgrade(self, obj, old_version, old_properties):
        if "Deflection" in old_properties:
            # versions 1, 2: "Deflection" was this angle (degrees)
            obj.NormalDeflection = _old_angle(obj.Deflection)
            obj.removeProperty("Deflection")
        elif "NormalDeflection" not in old_properties:
            obj.NormalDeflection = math.degrees(1e-3)
        if "PullDirection" not in old_properties:
            obj.PullDirection = FreeCAD.Vector(0, 0, 1)
        if "RayCheck" not in old_properties:
            obj.RayCheck = True
        if "Mode" in old_properties:
            mode = obj.Mode
            obj.Mode = MODES   # the enumeration gained Draft
            obj.Mode = mode

    def _execute(self, obj):
        if obj.Source is None:
            raise PartingInputError("the source is gone; set the Source property again")
        if not obj.Source.Shape.Solids:
            raise PartingInputError(f"'{obj.Source.Label}' holds no solid (a shell or "
                                    "faces only): a mould or a set-up needs a closed part")
        # FreeCAD's progress bar (status bar; a dialog on long runs) in the GUI.
        progress = FreeCAD.Base.ProgressIndicator()
        progress.start(f"Parting analysis of {obj.Source.Label}", 2)
        try:
            last = _compute(obj, progress)
        finally:
            progress.stop()
        self.last = last
        faces, result = last["faces"], last["result"]
        _store(obj, result, faces, len(obj.Source.Shape.Faces))
        obj.Warnings = list(last["warnings"])
        t = last["timings"]
        FreeCAD.Console.PrintLog(
            f"mfgeom: {obj.Label}: {len(faces)} faces, {obj.Mode}, covered "
            f"{obj.CoveredCount}/{obj.TotalCount} (Gauss maps {1e3 * t['gauss_maps']:.1f} ms, "
            f"parting {1e3 * t['parting']:.1f} ms)\n")
        for w in last["warnings"]:
            FreeCAD.Console.PrintWarning(f"mfgeom: {obj.Label}: {w}\n")

    def _restored(self):
        self.last = None


def _old_angle(value):
    """Degrees of an old document's angle property (a Quantity or a plain number)."""
    return float(getattr(value, "Value", value))


def _options_key(obj):
    """What the last analysis depends on besides the source's geometry."""
    return (obj.Source.Name if obj.Source else None, tuple(obj.Faces), obj.Mode,
            obj.DraftAngle.Value, obj.Weighting, bool(obj.AllFaces), obj.NormalDeflection.Value,
            obj.AngularTolerance, _tuple(obj.PullDirection), bool(obj.RayCheck),
            obj.RayDeflection.Value)


def _compute(obj, progress=None):
    """The analysis of ``obj`` as its properties ask: {"key", "faces", "result",
    "timings", "warnings"}; touches no property."""
    # Imported here: it loads libmfgeom, and a document must open without it.
    from mfgeom.app import gauss_map
    t0 = time.perf_counter()
    warnings = []
    faces, adjacency, shape = gauss_map.part_gauss(obj.Source,
                                                   math.radians(obj.NormalDeflection.Value),
                                                   face_names=list(obj.Faces) or None,
                                                   warnings=warnings)
    t1 = time.perf_counter()
    if progress is not None:
        progress.next()
    result = analyse(faces, adjacency, obj.Mode, math.radians(obj.DraftAngle.Value),
                     obj.Weighting.lower(), obj.AllFaces, obj.AngularTolerance,
                     _tuple(obj.PullDirection))
    t2 = time.perf_counter()
    timings = {"gauss_maps": t1 - t0, "parting": t2 - t1}
    if obj.Mode == "Mould" and obj.RayCheck and result.direction is not None:
        run_ray_check(result, faces, shape, obj.RayDeflection.Value)
        timings["ray_check"] = time.perf_counter() - t2
    if progress is not None:
        progress.next()
    return {"key": _options_key(obj), "faces": faces, "result": result,
            "timings": timings, "warnings": warnings}


def ray_deflection(shape, deflection=0.0):
    """The ray check's tessellation deflection (mm): ``deflection`` if > 0, else 1/500 of
    the shape's bounding-box diagonal (at least 1e-3 mm)."""
    if deflection > 0:
        return float(deflection)
    return max(1e-3, shape.BoundBox.DiagonalLength / 500.0)


def run_ray_check(result, faces, shape, deflection=0.0):
    """The ray check (:mod:`mfgeom.app.ray_check`) of a Mould result on ``shape`` (global,
    as gauss_map analysed it), applied to ``result`` (:func:`mfgeom.parting.apply_ray_check`)."""
    from mfgeom import parting
    from mfgeom.app import ray_check
    rays = ray_check.ray_check(shape, result.direction, ray_deflection(shape, deflection))
    parting.apply_ray_check(result, faces, {f"Face{r.face + 1}": r for r in rays})


def _tuple(v):
    return (float(v.x), float(v.y), float(v.z))


def analysis_of(obj):
    """(faces, result, timings) of ``obj``'s last analysis; recomputed (the document is
    left untouched) when the proxy lost it (a restored document) or the options changed."""
    last = getattr(obj.Proxy, "last", None)
    if last is None or last["key"] != _options_key(obj):
        last = _compute(obj)
        last["timings"] = {}
        obj.Proxy.last = last
    return last["faces"], last["result"], last["timings"]


def feature_report(obj):
    """:func:`mfgeom.parting.report` of the feature ``obj`` (a plain dict)."""
    from mfgeom import parting
    faces, result, timings = analysis_of(obj)
    return parting.report(result, faces, math.radians(obj.DraftAngle.Value),
                          obj.Weighting.lower(), bool(obj.AllFaces), obj.AngularTolerance,
                          source=obj.Source.Label if obj.Source else "", timings=timings,
                          warnings=list(obj.Warnings))


def sphere_maps(obj):
    """The visibility maps the analysis intersected, for the view's sphere: a list of
    (surface index, mfgeom.core.VisibilityMap) in global coordinates — Mould: VM(S) and
    -VM(S) of every surface (a surface with one normal: the whole sphere, None);
    NC3Axis: VM(S) of the surfaces considered.  Drafts and shrinks as in the analysis."""
    from mfgeom import parting
    _, result, _ = analysis_of(obj)
    if obj.Mode == "Draft":
        return []   # a given direction: no maps were intersected
    # Mould chooses its direction without the draft; NC shrinks the maps by the tilt
    draft = math.radians(obj.DraftAngle.Value) if obj.Mode == "NC3Axis" else 0.0
    tol = obj.AngularTolerance
    out = []
    for s in result.considered:
        surf = result.surfaces[s]
        if result.mode == "Mould":
            if surf.shrink == 0.0 and parting._is_single_normal(surf.normals, tol):
                out.append((s, None))
                continue
            for negative in (False, True):
                out.append((s, parting.surface_vm(surf, draft, tol, negative)))
        else:
            out.append((s, parting.surface_vm(surf, draft, tol)))
    return out


def analyse(faces, adjacency, mode, draft, weighting, all_faces, tol, pull=(0.0, 0.0, 1.0)):
    """The pure computation behind the feature (FaceGauss list in, PartingResult or,
    Draft, DraftAnalysis out)."""
    from mfgeom import parting
    if mode == "Draft":
        try:
            return parting.draft_analysis(faces, pull, draft, tol)
        except ValueError as exc:
            raise PartingInputError(str(exc)) from None
    if mode == "Mould":
        return parting.mould_parting(faces, adjacency, draft_angle=draft, weighting=weighting,
                                     tol=tol)
    return parting.nc_setups(faces, adjacency, tilt=draft, weighting=weighting,
                             all_faces=all_faces, tol=tol)


def _vector(d):
    return FreeCAD.Vector(*[float(c) for c in d]) if d is not None else FreeCAD.Vector()


def _names(faces, indices):
    return [faces[i].name for i in sorted(indices)]


def _direction_json(entry, faces):
    return json.dumps({"direction": [round(float(c), 15) for c in entry.direction],
                       "margin_deg": math.degrees(entry.margin),
                       "faces": _names(faces, entry.faces)})


def _store(obj, r, faces, nfaces):
    """The result properties from a PartingResult (Mould, NC3Axis) or a DraftAnalysis."""
    from mfgeom import parting
    angles = [0.0] * nfaces
    index = [int(f.name[4:]) - 1 if f.name.startswith("Face") and f.name[4:].isdigit()
             else -1 for f in faces]
    empty = ("UncoveredFaces", "CoreFaces", "CavityFaces", "InsufficientDraftFaces",
             "ZeroDraftFaces", "SideCores", "Setups", "UnresolvedFaces", "PositiveDraftFaces",
             "NegativeDraftFaces", "StraddleFaces", "ShadowedFaces")
    for prop in empty:
        setattr(obj, prop, [])
    obj.SideCoreDirections = []
    if isinstance(r, parting.DraftAnalysis):
        obj.Direction = _vector(r.direction)
        obj.MarginDeg = 0.0
        by_class = {c: [faces[i].name for i, k in enumerate(r.classes) if k == c]
                    for c in parting.DRAFT_CLASSES}
        obj.PositiveDraftFaces = by_class["positive"]
        obj.NegativeDraftFaces = by_class["negative"]
        obj.StraddleFaces = by_class["straddle"]
        obj.InsufficientDraftFaces = by_class["insufficient"]
        obj.CoveredCount = len(by_class["positive"]) + len(by_class["negative"])
        obj.TotalCount = len(faces)
        obj.CoveredWeight = float(obj.CoveredCount)
        obj.Surfaces = []
        obj.MaxShrinkDeg = math.degrees(max((f.shrink for f in faces), default=0.0))
        for i, lo in zip(index, r.low):
            if 0 <= i < nfaces:
                angles[i] = math.degrees(lo)
        obj.WorstAngles = angles
        return
    surf_faces = [s.faces for s in r.surfaces]
    obj.Direction = _vector(r.direction)
    obj.MarginDeg = math.degrees(r.margin)
    obj.CoveredCount = len(r.covered)
    obj.TotalCount = len(r.considered)
    obj.CoveredWeight = float(r.count)
    uncovered = [s for s in r.considered if s not in set(r.covered)]
    obj.UncoveredFaces = _names(faces, [f for s in uncovered for f in surf_faces[s]])
    if r.mode == "Mould":
        obj.CoreFaces = _names(faces, [f for f, x in enumerate(r.face_role) if x == "core"])
        obj.CavityFaces = _names(faces, [f for f, x in enumerate(r.face_role) if x == "cavity"])
        obj.InsufficientDraftFaces = _names(faces, r.insufficient_draft_faces)
        obj.ZeroDraftFaces = _names(faces, r.zero_draft_faces)
        obj.ShadowedFaces = _names(faces, r.shadowed_faces)
        for i, a in zip(index, r.face_angle):
            if 0 <= i < nfaces:
                angles[i] = math.degrees(a)
    obj.WorstAngles = angles
    obj.SideCoreDirections = [_vector(c.direction) for c in r.side_cores]
    obj.SideCores = [_direction_json(c, faces) for c in r.side_cores]
    obj.Setups = [_direction_json(s, faces) for s in r.setups]
    obj.UnresolvedFaces = _names(faces, [f for s in r.unresolved for f in surf_faces[s]])
    obj.Surfaces = [" ".join(_names(faces, g)) for g in surf_faces]
    obj.MaxShrinkDeg = math.degrees(max((f.shrink for f in faces), default=0.0))


def _angle_deg(value, what):
    """Degrees from a number (degrees), an angle Quantity or a string such as "3 deg"."""
    if isinstance(value, bool):
        raise PartingInputError(f"{what} must be an angle, got {value!r}")
    if isinstance(value, str):
        try:
            value = FreeCAD.Units.Quantity(value)
        except ValueError:
            raise PartingInputError(f"{what} must be an angle such as '3 deg', "
                                    f"got {value!r}") from None
    if isinstance(value, FreeCAD.Units.Quantity):
        if value.Unit == FreeCAD.Units.Angle:
            value = value.getValueAs("deg")
        elif value.Unit == FreeCAD.Units.Unit():
            value = value.Value
        else:
            raise PartingInputError(f"{what} must be an angle, got {value.UserString}")
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise PartingInputError(f"{what} must be a number of degrees, got {value!r}") from None
    if not 0.0 <= value < 90.0:
        raise PartingInputError(f"{what} must be in [0, 90) degrees, got {value!r}")
    return value


def pull_vector(pull):
    """A unit FreeCAD.Vector from what a user gives as the pull direction: a vector (or
    3 numbers), a face (its normal at its parameter box's centre, as oriented in the
    solid), a straight edge (its direction), or (object, "FaceN" / "EdgeN") as a
    selection gives it (global placement applied)."""
    import Part
    shape = None
    if isinstance(pull, (tuple, list)) and len(pull) == 2 and hasattr(pull[0], "Shape"):
        obj, sub = pull
        try:
            shape = obj.Shape.getElement(str(sub))
        except Exception:
            raise PartingInputError(f"'{obj.Label}' has no {sub}") from None
        if hasattr(obj, "getGlobalPlacement"):
            shape = shape.copy()
            shape.Placement = obj.getGlobalPlacement().multiply(obj.Placement.inverse()) \
                .multiply(shape.Placement)
    elif isinstance(pull, Part.Shape):
        shape = pull
    if shape is not None:
        if isinstance(shape, Part.Face):
            u0, u1, v0, v1 = shape.ParameterRange
            v = shape.normalAt((u0 + u1) / 2, (v0 + v1) / 2)
        elif isinstance(shape, Part.Edge) and isinstance(shape.Curve, (Part.Line,
                                                                        Part.LineSegment)):
            v = shape.Vertexes[-1].Point - shape.Vertexes[0].Point
        else:
            raise PartingInputError("the pull direction must be a vector, a face or a "
                                    "straight edge")
    else:
        try:
            v = FreeCAD.Vector(*[float(c) for c in pull])
        except (TypeError, ValueError):
            raise PartingInputError(f"the pull direction must be 3 numbers, got {pull!r}") \
                from None
    if not all(math.isfinite(c) for c in (v.x, v.y, v.z)) or v.Length == 0:
        raise PartingInputError("the pull direction must be a finite, non-zero vector")
    return v.normalize()


def make_parting_analysis(doc: "FreeCAD.Document", source: "FreeCAD.DocumentObject",
                          mode: str = "Mould",
                          draft_angle: Quantity = 0.0,
                          weighting: str = "Count", all_faces: bool = False,
                          name: str = "PartingAnalysis", faces: Optional[Sequence[str]] = None,
                          pull_direction: object = None) -> "FreeCAD.DocumentObject":
    """Create a parting analysis of ``source`` (a document object with a solid Shape) in
    ``doc`` and compute it.  ``mode``: "Mould", "NC3Axis" or "Draft" (a draft analysis
    along ``pull_direction``: see :func:`pull_vector`); ``draft_angle``: degrees (a
    number, an angle Quantity or a string such as "3 deg"; NC3Axis: the tilt
    allowance); ``weighting``: "Count" or "Area"; ``all_faces`` (NC3Axis): every
    surface, not only pockets; ``faces``: only these faces of the source (names such as
    "Face3"; None: all).  Inputs are checked before anything is created; if the
    first recompute fails the object is removed again.  Returns the new object."""
    if doc is None or not hasattr(doc, "addObject"):
        raise PartingInputError("no document given")
    if (source is None or not hasattr(source, "Shape")
            or getattr(source, "Document", None) is not doc):
        raise PartingInputError("the source must be an object with a Shape in this document")
    if source.Shape.isNull() or not source.Shape.Faces:
        raise PartingInputError(f"'{source.Label}' has no faces")
    if mode not in MODES:
        raise PartingInputError(f"mode must be one of {MODES}, got {mode!r}")
    if weighting not in WEIGHTINGS:
        raise PartingInputError(f"weighting must be one of {WEIGHTINGS}, got {weighting!r}")
    draft = _angle_deg(draft_angle, "the draft angle")
    if not source.Shape.Solids:
        raise PartingInputError(f"'{source.Label}' holds no solid (a shell or faces only): "
                                "a mould or a set-up needs a closed part")
    if mode == "Draft" and pull_direction is None:
        raise PartingInputError("Draft mode needs a pull direction (a vector, a face or an "
                                "edge)")
    pull = pull_vector(pull_direction) if pull_direction is not None else FreeCAD.Vector(0, 0, 1)
    faces = [str(f) for f in faces] if faces else []
    count = len(source.Shape.Faces)
    for f in faces:
        if not (f.startswith("Face") and f[4:].isdigit() and 1 <= int(f[4:]) <= count):
            raise PartingInputError(f"{f!r} is not a face of '{source.Label}' "
                                    f"(Face1 .. Face{count})")
    return PartingAnalysis.make(doc, name, {
        "Label": f"{mode} analysis of {source.Label}", "Source": source, "Mode": mode,
        "DraftAngle": draft, "Weighting": weighting, "AllFaces": bool(all_faces),
        "PullDirection": pull, "Faces": faces}, "parting analysis")
