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

import FreeCAD

from mfgeom.app.feature_base import FeatureProxy, add_properties
from mfgeom.errors import InputError

# 1: first release.  Bump when properties change and migrate in _upgrade().
VERSION = 1
TYPE = "Mfgeom::PartingAnalysis"
MODES = ["Mould", "NC3Axis"]
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
        obj.Deflection = math.degrees(1e-3)
        obj.AngularTolerance = 1e-6

    @staticmethod
    def _add_properties(obj):
        # (type, name, group, tooltip, read-only output?)
        spec = [
            ("App::PropertyLink", "Source", "Input", "The solid to analyse", False),
            ("App::PropertyStringList", "Faces", "Input",
             "Only these faces of the source (e.g. Face3); empty: all faces", False),
            ("App::PropertyEnumeration", "Mode", "Input",
             "Mould: parting direction, undercuts, side cores; NC3Axis: set-up plan", False),
            ("App::PropertyAngle", "DraftAngle", "Input",
             "Mould: least angle every covered face must make with the parting plane; "
             "NC3Axis: tool-axis tilt allowance (maps shrunk by it)", False),
            ("App::PropertyEnumeration", "Weighting", "Input",
             "Count: every concave-connected surface counts 1; Area: by its area", False),
            ("App::PropertyBool", "AllFaces", "Input",
             "NC3Axis: plan for every surface, not only the pockets (surfaces with a "
             "concave edge)", False),
            ("App::PropertyAngle", "Deflection", "Input",
             "Largest angle by which sampled (non-analytic) faces' maps may be shrunk", False),
            ("App::PropertyFloat", "AngularTolerance", "Input",
             "Radians: normals closer than this are snapped together (rotation-stable "
             "answers); every answer holds up to it", False),
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
             "Mould: faces +-d demoulds only without the draft", True),
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
            ("App::PropertyInteger", "Version", "Base",
             "Version of this object's properties, for migrating old documents", True),
        ]
        add_properties(obj, spec)

    def _outdated(self, obj):
        # Faces came after version 1
        return super()._outdated(obj) or "Faces" not in obj.PropertiesList

    def _execute(self, obj):
        if obj.Source is None:
            raise PartingInputError("the source is gone; set the Source property again")
        # Imported here: it loads libmfgeom, and a document must open without it.
        from mfgeom.app import gauss_map
        # FreeCAD's progress bar (status bar; a dialog on long runs) in the GUI.
        progress = FreeCAD.Base.ProgressIndicator()
        progress.start(f"Parting analysis of {obj.Source.Label}", 2)
        try:
            t0 = time.perf_counter()
            faces, adjacency, _ = gauss_map.part_gauss(obj.Source,
                                                       math.radians(obj.Deflection.Value),
                                                       face_names=list(obj.Faces) or None)
            t1 = time.perf_counter()
            progress.next()
            result = analyse(faces, adjacency, obj.Mode, math.radians(obj.DraftAngle.Value),
                             obj.Weighting.lower(), obj.AllFaces, obj.AngularTolerance)
            t2 = time.perf_counter()
            progress.next()
        finally:
            progress.stop()
        self.last = {"key": _options_key(obj), "faces": faces, "result": result,
                     "timings": {"gauss_maps": t1 - t0, "parting": t2 - t1}}
        _store(obj, result, faces)
        FreeCAD.Console.PrintLog(
            f"mfgeom: {obj.Label}: {len(faces)} faces, {obj.Mode}, covered "
            f"{obj.CoveredCount}/{obj.TotalCount} (Gauss maps {1e3 * (t1 - t0):.1f} ms, "
            f"parting {1e3 * (t2 - t1):.1f} ms)\n")
        sampled = sum(1 for f in faces if f.shrink > 0)
        if sampled:
            FreeCAD.Console.PrintMessage(
                f"mfgeom: {obj.Label}: normals of {sampled} curved faces are sampled; their "
                f"maps are shrunk by up to {obj.MaxShrinkDeg:.3g} deg so every direction "
                "holds on the true faces\n")

    def _restored(self):
        self.last = None


def _options_key(obj):
    """What the last analysis depends on besides the source's geometry."""
    return (obj.Source.Name if obj.Source else None, tuple(obj.Faces), obj.Mode,
            obj.DraftAngle.Value, obj.Weighting, bool(obj.AllFaces), obj.Deflection.Value,
            obj.AngularTolerance)


def analysis_of(obj):
    """(faces, result, timings) of ``obj``'s last analysis; recomputed (the document is
    left untouched) when the proxy lost it (a restored document) or the options changed."""
    last = getattr(obj.Proxy, "last", None)
    if last is None or last["key"] != _options_key(obj):
        from mfgeom.app import gauss_map
        faces, adjacency, _ = gauss_map.part_gauss(obj.Source,
                                                   math.radians(obj.Deflection.Value),
                                                   face_names=list(obj.Faces) or None)
        result = analyse(faces, adjacency, obj.Mode, math.radians(obj.DraftAngle.Value),
                         obj.Weighting.lower(), obj.AllFaces, obj.AngularTolerance)
        last = {"key": _options_key(obj), "faces": faces, "result": result, "timings": {}}
        obj.Proxy.last = last
    return last["faces"], last["result"], last["timings"]


def feature_report(obj):
    """:func:`mfgeom.parting.report` of the feature ``obj`` (a plain dict)."""
    from mfgeom import parting
    faces, result, timings = analysis_of(obj)
    return parting.report(result, faces, math.radians(obj.DraftAngle.Value),
                          obj.Weighting.lower(), bool(obj.AllFaces), obj.AngularTolerance,
                          source=obj.Source.Label if obj.Source else "", timings=timings)


def sphere_maps(obj):
    """The visibility maps the analysis intersected, for the view's sphere: a list of
    (surface index, mfgeom.core.VisibilityMap) in global coordinates — Mould: VM(S) and
    -VM(S) of every surface (a surface with one normal: the whole sphere, None);
    NC3Axis: VM(S) of the surfaces considered.  Drafts and shrinks as in the analysis."""
    from mfgeom import parting
    _, result, _ = analysis_of(obj)
    draft = math.radians(obj.DraftAngle.Value)
    tol = obj.AngularTolerance
    out = []
    for s in result.considered:
        surf = result.surfaces[s]
        if result.mode == "Mould":
            if draft + surf.shrink == 0.0 and parting._is_single_normal(surf.normals, tol):
                out.append((s, None))
                continue
            for negative in (False, True):
                out.append((s, parting.surface_vm(surf, draft, tol, negative)))
        else:
            out.append((s, parting.surface_vm(surf, draft, tol)))
    return out


def analyse(faces, adjacency, mode, draft, weighting, all_faces, tol):
    """The pure computation behind the feature (FaceGauss list in, PartingResult out)."""
    from mfgeom import parting
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


def _store(obj, r, faces):
    surf_faces = [s.faces for s in r.surfaces]
    obj.Direction = _vector(r.direction)
    obj.MarginDeg = math.degrees(r.margin)
    obj.CoveredCount = len(r.covered)
    obj.TotalCount = len(r.considered)
    obj.CoveredWeight = float(r.count)
    uncovered = [s for s in r.considered if s not in set(r.covered)]
    obj.UncoveredFaces = _names(faces, [f for s in uncovered for f in surf_faces[s]])
    side = r.side if r.mode == "Mould" else [None] * len(r.surfaces)
    obj.CoreFaces = _names(faces, [f for s, x in enumerate(side) if x == 1 for f in surf_faces[s]])
    obj.CavityFaces = _names(faces, [f for s, x in enumerate(side) if x == -1
                                     for f in surf_faces[s]])
    obj.InsufficientDraftFaces = _names(faces, [f for s in r.insufficient_draft
                                                for f in surf_faces[s]])
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


def make_parting_analysis(doc, source, mode="Mould", draft_angle=0.0, weighting="Count",
                          all_faces=False, name="PartingAnalysis", faces=None):
    """Create a parting analysis of ``source`` (a document object with a solid Shape) in
    ``doc`` and compute it.  ``mode``: "Mould" or "NC3Axis"; ``draft_angle``: degrees (a
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
    faces = [str(f) for f in faces] if faces else []
    count = len(source.Shape.Faces)
    for f in faces:
        if not (f.startswith("Face") and f[4:].isdigit() and 1 <= int(f[4:]) <= count):
            raise PartingInputError(f"{f!r} is not a face of '{source.Label}' "
                                    f"(Face1 .. Face{count})")
    return PartingAnalysis.make(doc, name, {
        "Label": f"{mode} analysis of {source.Label}", "Source": source, "Mode": mode,
        "DraftAngle": draft, "Weighting": weighting, "AllFaces": bool(all_faces),
        "Faces": faces}, "parting analysis")
