# SPDX-License-Identifier: LGPL-2.1-or-later
"""The parametric wall-thickness analysis (issue 21, section 4): App proxy, the pure
geometry functions, the histogram and CSV, and the make function.

Local wall thickness at a point of the part's boundary is the diameter of the maximal
inscribed ball that touches it, read from the part's medial surface by libmfgeom
(:func:`mfgeom.core.wall_thickness`, mfgeom.h ``mfg_medial_thickness``): each ball of the
medial surface touches its boundary elements at their foot points; a point takes the
smallest wall ball that touches it, or the ball of the nearest point one touches.  Balls
whose touching points are less than ``MinAngle`` (default 120 degrees) apart seen from
the centre are a convex corner's, not a wall's: left out, so a box is as thick at its
edges as in the middle of its faces.  The full medial surface is used (``MajorOnly``
False) so a wall tapering to a sharp edge (two faces meeting at less than 60 degrees)
reads thin towards its edge.

Where the values are taken: the part's faces are tessellated within ``Deflection`` (the
polyhedron the medial surface is computed for) and each triangle is subdivided until its
sides are at most ``SampleSpacing``; the vertices of that mesh are the samples, each on
one face.  Accuracy: the thickness of the polyhedron within the medial ``Tolerance`` (the
exact value at sheet vertices, linear in between), and the polyhedron lies within
``Deflection`` of a curved face (each wall side), so the part's thickness is within
Tolerance + 2 Deflection.

What the feature holds (``Part::FeaturePython``): the samples (``SamplePoints``,
``SampleFacets``, ``SampleFaces`` (face index per sample), ``VertexThickness``), the
per-face ``FaceMinThickness`` / ``FaceMaxThickness`` / ``FaceMeanThickness``, the
thinnest and thickest spots (``Thinnest``, ``ThinnestPoint``, ``Thickest``,
``ThickestPoint``; ``Shape`` is these two points as vertices), the area-weighted mean and
the area fractions below ``MinThickness`` (thin: fill problems) and above
``MaxThickness`` (thick: sink marks, long cooling), and the names of the faces with thin
or thick spots.  The view provider (mfgeom.gui.thickness_view) draws the samples coloured
per vertex with a legend, thin and thick spots in their highlight colours and the two
extreme spots marked."""

import csv
import io
import math
import time
from typing import Optional

import numpy as np

import FreeCAD

from mfgeom.app.feature_base import (VERSION_PROPERTY, add_mesh_property, add_properties,
                                     FeatureProxy, Quantity)
from mfgeom import progress
from mfgeom.errors import InputError, MfgeomError
from mfgeom.fileio import write_atomic

# 1: first release.  Bump when properties change and migrate in _upgrade().
VERSION = 1
TYPE = "Mfgeom::ThicknessAnalysis"
TOLERANCE_FRACTION = 0.005      # default tolerance and deflection: 0.5 % of the diagonal
SPACING_FRACTION = 0.01         # default sample spacing: 1 % of the diagonal
DEFAULT_MIN_ANGLE = 120.0       # degrees: mfgeom.h MFG_WALL_ANGLE
HISTOGRAM_BINS = 12
# Sample triangles at most this many (a finer SampleSpacing raises instead of eating the
# memory); the default spacing aims at about TARGET_SAMPLES.
MAX_SAMPLES = 2_000_000
TARGET_SAMPLES = 60_000


class ThicknessInputError(InputError):
    """A bad source or parameter given to the thickness analysis."""


# ---------------------------------------------------------------------------- geometry
def _levels(points, triangles, spacing):
    """Per triangle the subdivision level k (k x k similar triangles) making every side
    <= ``spacing``."""
    p = points[triangles]                                   # (t, 3, 3)
    sides = np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).max(axis=1)
    return np.maximum(1, np.ceil(sides / spacing)).astype(np.int64)


def _subdivide(points, triangles, ks):
    """(points, triangles) of the triangles split into k x k similar triangles each
    (``ks`` per triangle, :func:`_levels`); the points shared along a triangle's sides are
    welded (the mesh stays connected for smooth colours)."""
    from mfgeom import core
    p = points[triangles]
    soup = []
    for k in np.unique(ks).tolist():
        tri = p[ks == k]
        # barycentric grid of level k: small triangles (i, j) up and down
        bary = []
        for i in range(k):
            for j in range(k - i):
                bary.append(((i, j), (i + 1, j), (i, j + 1)))
                if j + i + 1 < k:
                    bary.append(((i + 1, j), (i + 1, j + 1), (i, j + 1)))
        w = np.array([[(1 - (a + b) / k, a / k, b / k) for a, b in corners]
                      for corners in bary])                 # (s, 3 corners, 3 weights)
        sub = np.einsum("scw,twx->tscx", w, tri)           # (t, s, 3, 3)
        soup.append(sub.reshape(-1, 9))
    return core.weld(np.vstack(soup))


def sample_mesh(shape, deflection, spacing):
    """(points (n, 3), triangles (t, 3), face index per point (n,)) of the faces of
    ``shape`` tessellated at ``deflection`` and subdivided to ``spacing``; the points of
    each face are its own (a point on an edge appears once per face).  The number of
    triangles is counted before any is made: more than MAX_SAMPLES raise
    ThicknessInputError (a spacing far too fine for the part must not eat the memory)."""
    from mfgeom.app.sweep_feature import face_meshes
    meshes = [(index, p, t, _levels(p, t, spacing))
              for index, p, t, _planar in face_meshes(shape, deflection)]
    if not meshes:
        raise ThicknessInputError("the source has no faces to mesh")
    count = sum(int((ks.astype(np.float64) ** 2).sum()) for _i, _p, _t, ks in meshes)
    if count > MAX_SAMPLES:
        raise ThicknessInputError(
            f"the sample spacing {spacing:.4g} mm gives about {count} samples (at most "
            f"{MAX_SAMPLES}); choose a larger spacing")
    pts, tris, faces, base = [], [], [], 0
    for index, p, t, ks in meshes:
        v, f = _subdivide(p, t, ks)
        pts.append(v)
        tris.append(f + base)
        faces.append(np.full(len(v), index, dtype=np.int64))
        base += len(v)
    return np.vstack(pts), np.vstack(tris), np.concatenate(faces)


def default_spacing(shape, deflection):
    """1 % of the bounding-box diagonal, coarser where that would give more than about
    TARGET_SAMPLES sample triangles on ``shape`` tessellated at ``deflection`` (long thin
    triangles of planar faces are split by their longest side, so the count is taken from
    the tessellation, not the area)."""
    from mfgeom.app.sweep_feature import face_meshes
    spacing = SPACING_FRACTION * shape.BoundBox.DiagonalLength
    meshes = [(p, t) for _i, p, t, _planar in face_meshes(shape, deflection)]
    for _attempt in range(8):
        count = sum(float((_levels(p, t, spacing).astype(np.float64) ** 2).sum())
                    for p, t in meshes)
        if count <= TARGET_SAMPLES:
            break
        spacing *= max(1.1, math.sqrt(count / TARGET_SAMPLES))
    return spacing


def vertex_areas(points, triangles):
    """(n,) a third of the area of the triangles around each point (area weights)."""
    a = points[triangles]
    area = 0.5 * np.linalg.norm(np.cross(a[:, 1] - a[:, 0], a[:, 2] - a[:, 0]), axis=1)
    w = np.zeros(len(points))
    for k in range(3):
        np.add.at(w, triangles[:, k], area / 3.0)
    return w


class ThicknessResult:
    """Plain data of one analysis: ``points``, ``triangles``, ``faces`` (face index per
    point), ``thickness`` (per point, mm), ``centres`` (the balls' centres), ``areas``
    (area weight per point), ``medial_triangles`` (the polyhedron's), ``seconds``."""

    def __init__(self, points, triangles, faces, thickness, centres, areas, medial_triangles,
                 seconds):
        self.points, self.triangles, self.faces = points, triangles, faces
        self.thickness, self.centres, self.areas = thickness, centres, areas
        self.medial_triangles, self.seconds = medial_triangles, seconds


def thickness_of_shape(shape, tolerance, deflection, spacing,
                       min_angle=DEFAULT_MIN_ANGLE, major_only=False):
    """The :class:`ThicknessResult` of the solids of ``shape`` (global coordinates):
    medial surface of the tessellation at ``tolerance`` / ``deflection``, samples at
    ``spacing`` (module doc); ``min_angle`` in degrees."""
    from mfgeom import core
    from mfgeom.app.sweep_feature import source_mesh
    vertices, triangles, _curved = source_mesh(shape, deflection)
    points, tris, faces = sample_mesh(shape, deflection, spacing)
    t0 = time.perf_counter()
    res = core.wall_thickness(vertices, triangles, points, tolerance,
                              min_angle=math.radians(min_angle), major_only=major_only,
                              progress=progress.current())
    seconds = time.perf_counter() - t0
    return ThicknessResult(points, tris, faces, res.thickness, res.centres,
                           vertex_areas(points, tris), len(triangles), seconds)


def check_parameters(min_thickness, max_thickness, tolerance, deflection, spacing,
                     min_angle):
    """ThicknessInputError unless the lengths are finite and > 0, min < max and the angle
    in (0, 180] degrees."""
    for value, what in ((min_thickness, "minimum thickness"),
                        (max_thickness, "maximum thickness"), (tolerance, "tolerance"),
                        (deflection, "deflection"), (spacing, "sample spacing")):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
            raise ThicknessInputError(f"the {what} must be a length > 0 mm, got {value!r}")
    if not min_thickness < max_thickness:
        raise ThicknessInputError(
            f"the minimum thickness ({min_thickness:.4g} mm) must be below the maximum "
            f"({max_thickness:.4g} mm)")
    if not (math.isfinite(min_angle) and 0.0 < min_angle <= 180.0):
        raise ThicknessInputError(f"the wall angle must be in (0, 180] degrees, got "
                                  f"{min_angle!r}")


def face_statistics(faces, thickness, areas, nfaces):
    """(min, max, area-weighted mean) per face index 0 .. nfaces-1 (0 for a face without
    samples)."""
    lo, hi, mean = np.zeros(nfaces), np.zeros(nfaces), np.zeros(nfaces)
    for f in range(nfaces):
        m = faces == f
        if m.any():
            lo[f], hi[f] = thickness[m].min(), thickness[m].max()
            w = areas[m]
            mean[f] = float((thickness[m] * w).sum() / w.sum()) if w.sum() > 0 \
                else float(thickness[m].mean())
    return lo, hi, mean


def histogram(thickness, areas, bins=HISTOGRAM_BINS):
    """(edges (bins + 1,), area per bin (bins,)) of the thickness over the samples'
    area weights (one bin when every value is one up to rounding)."""
    from mfgeom.palette import one_value
    t = np.asarray(thickness, dtype=np.float64)
    w = np.asarray(areas, dtype=np.float64)
    if not len(t):
        return np.zeros(1), np.zeros(0)
    lo, hi = float(t.min()), float(t.max())
    if one_value(lo, hi):
        return np.array([lo, hi]), np.array([float(w.sum())])
    counts, edges = np.histogram(t, bins=bins, range=(lo, hi), weights=w)
    return edges, counts


def histogram_of(obj, bins=HISTOGRAM_BINS):
    """:func:`histogram` of a ThicknessAnalysis feature."""
    pts = np.array([(p.x, p.y, p.z) for p in obj.SamplePoints]).reshape(-1, 3)
    tris = np.asarray(obj.SampleFacets, dtype=np.int64).reshape(-1, 3)
    return histogram(np.asarray(obj.VertexThickness), vertex_areas(pts, tris), bins)


def write_csv(obj, path):
    """Writes the samples of a ThicknessAnalysis to ``path`` (CSV: x, y, z, face,
    thickness, status thin / ok / thick), then its histogram (area per bin) after a blank
    line; atomically (a temporary file renamed: a failure leaves no partial file).
    Returns the number of sample rows."""
    pts = np.array([(p.x, p.y, p.z) for p in obj.SamplePoints]).reshape(-1, 3)
    thick = np.asarray(obj.VertexThickness, dtype=np.float64)
    faces = np.asarray(obj.SampleFaces, dtype=np.int64)
    if len(pts) != len(thick) or len(faces) != len(thick):
        raise ThicknessInputError(f"'{obj.Label}' has no result to export (recompute it)")
    lo, hi = float(obj.MinThickness.Value), float(obj.MaxThickness.Value)
    edges, counts = histogram_of(obj)
    out = io.StringIO(newline="")
    w = csv.writer(out)
    w.writerow(["x_mm", "y_mm", "z_mm", "face", "thickness_mm", "status"])
    for p, f, t in zip(pts.tolist(), faces.tolist(), thick.tolist()):
        status = "thin" if t < lo else "thick" if t > hi else "ok"
        w.writerow([f"{p[0]:.6f}", f"{p[1]:.6f}", f"{p[2]:.6f}", f"Face{f + 1}",
                    f"{t:.6f}", status])
    w.writerow([])
    w.writerow(["bin_from_mm", "bin_to_mm", "area_mm2"])
    for a, b, c in zip(edges[:-1].tolist(), edges[1:].tolist(), counts.tolist()):
        w.writerow([f"{a:.6f}", f"{b:.6f}", f"{c:.6f}"])
    write_atomic(path, out.getvalue(), newline="")
    return len(pts)


# ---------------------------------------------------------------------------- feature
class ThicknessAnalysis(FeatureProxy):
    """App proxy: recomputes the wall thickness of its Source."""

    TYPE = TYPE
    VERSION = VERSION
    VIEW_PROVIDER = "mfgeom.gui.thickness_view.ViewProviderThicknessAnalysis"

    def _set_defaults(self, obj):
        obj.MinAngle = DEFAULT_MIN_ANGLE
        obj.MajorOnly = False
        obj.setEditorMode("Placement", 2)   # the result is placed in global coordinates

    @staticmethod
    def _add_properties(obj):
        spec = [
            ("App::PropertyLink", "Source", "Thickness", "The solid", False),
            ("App::PropertyLength", "MinThickness", "Thickness",
             "Walls thinner than this are highlighted (fill problems)", False),
            ("App::PropertyLength", "MaxThickness", "Thickness",
             "Walls thicker than this are highlighted (sink marks, long cooling)", False),
            ("App::PropertyLength", "Tolerance", "Thickness",
             "Medial surface tolerance (default: 0.5 % of the bounding-box diagonal)", False),
            ("App::PropertyLength", "Deflection", "Thickness",
             "Curved faces are tessellated within this distance", False),
            ("App::PropertyLength", "SampleSpacing", "Thickness",
             "Largest distance between samples (default: 1 % of the diagonal)", False),
            ("App::PropertyAngle", "MinAngle", "Thickness",
             "A ball is a wall's when two points it touches are at least this far apart "
             "seen from its centre (120 deg: convex corners are not thin walls)", False),
            ("App::PropertyBool", "MajorOnly", "Thickness",
             "Use only the major medial surface (faster; walls tapering to a sharp edge "
             "then take the thickness of the wall behind them)", False),
            ("App::PropertyFloat", "Thinnest", "Result", "Smallest thickness (mm)", True),
            ("App::PropertyFloat", "Thickest", "Result", "Largest thickness (mm)", True),
            ("App::PropertyVector", "ThinnestPoint", "Result", "Where it is thinnest", True),
            ("App::PropertyVector", "ThickestPoint", "Result", "Where it is thickest", True),
            ("App::PropertyFloat", "MeanThickness", "Result", "Area-weighted mean (mm)",
             True),
            ("App::PropertyFloat", "ThinFraction", "Result",
             "Fraction of the area thinner than MinThickness", True),
            ("App::PropertyFloat", "ThickFraction", "Result",
             "Fraction of the area thicker than MaxThickness", True),
            ("App::PropertyStringList", "ThinFaces", "Result",
             "Faces with a spot thinner than MinThickness", True),
            ("App::PropertyStringList", "ThickFaces", "Result",
             "Faces with a spot thicker than MaxThickness", True),
            ("App::PropertyFloatList", "FaceMinThickness", "Result",
             "Per face of the source (Face1 first): smallest thickness (mm)", True),
            ("App::PropertyFloatList", "FaceMaxThickness", "Result",
             "Per face: largest thickness (mm)", True),
            ("App::PropertyFloatList", "FaceMeanThickness", "Result",
             "Per face: area-weighted mean thickness (mm)", True),
            ("App::PropertyVectorList", "SamplePoints", "Result",
             "The sample points (global, mm)", True),
            ("App::PropertyIntegerList", "SampleFacets", "Result",
             "Triangles of the samples: index triples into SamplePoints", True),
            ("App::PropertyIntegerList", "SampleFaces", "Result",
             "The face index (0 = Face1) of every sample", True),
            ("App::PropertyFloatList", "VertexThickness", "Result",
             "Thickness (mm) at every sample", True),
            ("App::PropertyInteger", "SourceTriangles", "Result",
             "Triangles of the polyhedron the medial surface is computed for", True),
            VERSION_PROPERTY,
        ]
        add_properties(obj, spec)
        for name in ("SamplePoints", "SampleFacets", "SampleFaces", "VertexThickness",
                     "FaceMinThickness", "FaceMaxThickness", "FaceMeanThickness"):
            obj.setEditorMode(name, 2)
        add_mesh_property(obj, "The samples as a mesh (global), for export")

    def _execute(self, obj):
        import Part
        from mfgeom.app.medial_surface_feature import solid_shape
        if obj.Source is None:
            raise ThicknessInputError("the source is gone; set the Source property again")
        shape = solid_shape(obj.Source)
        lo, hi = float(obj.MinThickness.Value), float(obj.MaxThickness.Value)
        tol, defl = float(obj.Tolerance.Value), float(obj.Deflection.Value)
        spacing, angle = float(obj.SampleSpacing.Value), float(obj.MinAngle.Value)
        check_parameters(lo, hi, tol, defl, spacing, angle)
        r = thickness_of_shape(shape, tol, defl, spacing, angle, bool(obj.MajorOnly))
        nfaces = len(shape.Faces)
        fmin, fmax, fmean = face_statistics(r.faces, r.thickness, r.areas, nfaces)
        total = float(r.areas.sum())
        i_min, i_max = int(np.argmin(r.thickness)), int(np.argmax(r.thickness))
        thin = r.thickness < lo
        thick = r.thickness > hi
        from mfgeom.app.sweep_feature import mesh_of
        obj.Mesh = mesh_of(r.points, r.triangles)
        pmin, pmax = (FreeCAD.Vector(*r.points[i].tolist()) for i in (i_min, i_max))
        obj.Shape = Part.makeCompound([Part.Vertex(pmin), Part.Vertex(pmax)])
        obj.Placement = FreeCAD.Placement()
        obj.SamplePoints = [FreeCAD.Vector(*p) for p in r.points.tolist()]
        obj.SampleFacets = r.triangles.reshape(-1).tolist()
        obj.SampleFaces = r.faces.tolist()
        obj.VertexThickness = r.thickness.tolist()
        obj.FaceMinThickness, obj.FaceMaxThickness = fmin.tolist(), fmax.tolist()
        obj.FaceMeanThickness = fmean.tolist()
        obj.ThinnestPoint, obj.ThickestPoint = pmin, pmax
        obj.Thickest = float(r.thickness[i_max])
        obj.MeanThickness = float((r.thickness * r.areas).sum() / total) if total > 0 \
            else float(r.thickness.mean())
        obj.ThinFraction = float(r.areas[thin].sum() / total) if total > 0 else 0.0
        obj.ThickFraction = float(r.areas[thick].sum() / total) if total > 0 else 0.0
        obj.ThinFaces = [f"Face{f + 1}" for f in np.unique(r.faces[thin]).tolist() if f >= 0]
        obj.ThickFaces = [f"Face{f + 1}" for f in np.unique(r.faces[thick]).tolist()
                          if f >= 0]
        obj.SourceTriangles = int(r.medial_triangles)
        obj.Thinnest = float(r.thickness[i_min])   # last: the view redraws on it
        FreeCAD.Console.PrintLog(
            f"mfgeom: {obj.Label}: {len(r.points)} samples on {r.medial_triangles} "
            f"triangles; library {1e3 * r.seconds:.1f} ms\n")


def result_text(obj):
    """The one-paragraph summary of a thickness analysis (task panel, Report view)."""
    if obj is None:
        return "No result yet."
    if not obj.isValid():
        return f"Failed: {obj.getStatusString()}"
    if not obj.VertexThickness:
        return "No result yet."
    p, q = obj.ThinnestPoint, obj.ThickestPoint
    return (f"Wall thickness {obj.Thinnest:.4g} .. {obj.Thickest:.4g} mm (mean "
            f"{obj.MeanThickness:.4g} mm) at {len(obj.VertexThickness)} samples; thinnest at "
            f"({p.x:.4g}, {p.y:.4g}, {p.z:.4g}), thickest at ({q.x:.4g}, {q.y:.4g}, "
            f"{q.z:.4g}); {100 * obj.ThinFraction:.1f} % of the area below "
            f"{obj.MinThickness.Value:.4g} mm ({len(obj.ThinFaces)} faces), "
            f"{100 * obj.ThickFraction:.1f} % above {obj.MaxThickness.Value:.4g} mm "
            f"({len(obj.ThickFaces)} faces)")


# ---------------------------------------------------------------------------- make
def is_thickness_analysis(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", "") == TYPE


def make_thickness_analysis(doc: "FreeCAD.Document", source: "FreeCAD.DocumentObject",
                            min_thickness: Quantity, max_thickness: Quantity,
                            tolerance: Optional[Quantity] = None,
                            deflection: Optional[Quantity] = None,
                            sample_spacing: Optional[Quantity] = None,
                            min_angle: float = DEFAULT_MIN_ANGLE,
                            name: str = "ThicknessAnalysis") -> "FreeCAD.DocumentObject":
    """Create the wall-thickness analysis of ``source`` (an object with a solid Shape in
    ``doc``) and compute it.  ``min_thickness`` / ``max_thickness``: the thresholds (mm, a
    length Quantity or "1.5 mm"); ``tolerance`` and ``deflection`` default to 0.5 % and
    ``sample_spacing`` to 1 % of the source's bounding-box diagonal (coarser on a large
    area: about TARGET_SAMPLES samples, :func:`default_spacing`); ``min_angle``
    (degrees): the wall angle (module doc).  Inputs are checked
    before anything is created; if the first recompute fails the object is removed again
    and the error raised.  Returns the new object."""
    from mfgeom.app.medial_axis_feature import length_value
    from mfgeom.app.medial_surface_feature import MedialInputError, solid_shape
    if doc is None or not hasattr(doc, "addObject"):
        raise ThicknessInputError("no document given")
    if (source is None or not hasattr(source, "Shape")
            or getattr(source, "Document", None) is not doc):
        raise ThicknessInputError("the source must be an object with a Shape in this "
                                  "document")
    try:
        shape = solid_shape(source)
    except MedialInputError as exc:
        raise ThicknessInputError(str(exc)) from None
    diag = shape.BoundBox.DiagonalLength

    def length(value, what, default):
        if value is None:
            return default
        return length_value(value, what, error=ThicknessInputError)

    lo = length(min_thickness, "the minimum thickness", None)
    hi = length(max_thickness, "the maximum thickness", None)
    tol = length(tolerance, "the tolerance", TOLERANCE_FRACTION * diag)
    defl = length(deflection, "the deflection", TOLERANCE_FRACTION * diag)
    spacing = length(sample_spacing, "the sample spacing", None)
    if spacing is None:
        spacing = default_spacing(shape, defl)
    if lo is None or hi is None:
        raise ThicknessInputError("give the minimum and the maximum thickness")
    if isinstance(min_angle, bool) or not isinstance(min_angle, (int, float)):
        raise ThicknessInputError(f"the wall angle must be a number of degrees, got "
                                  f"{min_angle!r}")
    check_parameters(lo, hi, tol, defl, spacing, float(min_angle))
    return ThicknessAnalysis.make(doc, name, {
        "Label": f"Thickness of {source.Label}", "Source": source, "MinThickness": lo,
        "MaxThickness": hi, "Tolerance": tol, "Deflection": defl, "SampleSpacing": spacing,
        "MinAngle": float(min_angle)},
        "thickness analysis", error=MfgeomError)
