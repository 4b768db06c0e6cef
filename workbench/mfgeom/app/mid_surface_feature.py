# SPDX-License-Identifier: LGPL-2.1-or-later
"""The "mid-surface and thickness for FEM" feature (issue 9, section 4): App proxy, the
pure functions (shell, thickness statistics, CSV) and the make function.

From the major sheets of a thin-walled part's medial surface (a MedialSurface feature
with MajorOnly) it builds what a FEM shell model needs and users otherwise model by hand:

* ``Shape``: a shell of Part faces, one or more per sheet: each sheet's triangles made
  into faces and coplanar neighbours merged (``removeSplitter``: a planar sheet, the
  mid-plane of a wall, becomes one face), the sheets sewn where they meet;
* the local thickness (2 x the medial radius) as data: ``Thickness`` at every point of
  ``ThicknessPoints`` (the sheets' vertices, global mm), ``FaceThickness`` (the
  area-weighted mean thickness on every face of the Shape, for a shell section per face),
  ``MinThickness`` / ``MaxThickness`` / ``MeanThickness`` (mean weighted by area) and
  ``Histogram`` (the area share per thickness bin);
* a thickness report in the Report view on every recompute and, when ``CsvFile`` is set,
  a CSV file with one row per point: sheet, x, y, z, radius, thickness.
"""

import os
from typing import Optional

import numpy as np

import FreeCAD

from mfgeom.app.feature_base import (VERSION_PROPERTY, add_properties, FeatureProxy,
                                     Quantity, status_line)
from mfgeom.app.medial_surface_feature import (MedialInputError, is_medial_surface,
                                               sheet_mesh_of)
from mfgeom.errors import MfgeomError
# boundary_loops lives in mfgeom.geometry.mesh (FreeCAD-free); it stays importable here.
from mfgeom.geometry.mesh import boundary_loops, mesh_area, straightened  # noqa: F401
from mfgeom.palette import one_value

# 1: first release.  Bump when properties change and migrate in _upgrade().
VERSION = 1
TYPE = "Mfgeom::MidSurface"
DEFAULT_BINS = 10
CSV_HEADER = ("sheet", "x", "y", "z", "radius", "thickness")
# A sheet is planar (one face) when all its vertices lie within this fraction of the
# tolerance of a plane: the library places them on the analytic bisector up to rounding.
PLANAR_FRACTION = 1e-3
# Non-planar sheets: coplanar triangles are merged (OCCT, slow) up to this many.
MERGE_LIMIT = 2000
# Sewing tolerance of the sheets' faces, relative to the medial surface's tolerance:
# neighbouring sheets meet along a seam sampled within the tolerance.
_SEWING_FRACTION = 1.0


# ---------------------------------------------------------------------------- geometry
def triangle_thickness(sheets):
    """(t,) mean thickness (2 x radius) of every triangle and (t,) its area."""
    p, t = sheets.points, sheets.triangles
    if not len(t):
        return np.zeros(0), np.zeros(0)
    area = 0.5 * np.linalg.norm(np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]]),
                                axis=1)
    return 2.0 * sheets.radii[t].mean(axis=1), area


class ThicknessReport:
    """Thickness statistics of a mid-surface (plain data, mm): ``minimum`` /
    ``maximum`` over the points, ``mean`` weighted by area, ``area``, ``points``,
    ``edges`` (bins + 1,) and ``shares`` (bins,): the fraction of the area whose
    (triangle-mean) thickness falls in each bin."""

    def __init__(self, sheets, bins=DEFAULT_BINS):
        thick = 2.0 * sheets.radii
        tri_thick, area = triangle_thickness(sheets)
        self.points = len(thick)
        self.area = float(area.sum())
        self.minimum = float(thick.min()) if len(thick) else 0.0
        self.maximum = float(thick.max()) if len(thick) else 0.0
        self.mean = (float((tri_thick * area).sum() / self.area) if self.area > 0
                     else (float(thick.mean()) if len(thick) else 0.0))
        lo, hi = self.minimum, self.maximum
        if one_value(lo, hi):   # one thickness up to rounding: one bin
            hi, bins = max(hi, lo + max(1e-9, 1e-9 * abs(lo))), 1
        self.edges = np.linspace(lo, hi, int(bins) + 1)
        counts, _ = np.histogram(np.clip(tri_thick, lo, hi), bins=self.edges, weights=area)
        self.shares = counts / self.area if self.area > 0 else counts

    def lines(self):
        """The report as text lines (Report view, the Histogram property)."""
        out = [f"thickness min {self.minimum:.4g} mm, max {self.maximum:.4g} mm, mean "
               f"{self.mean:.4g} mm (area-weighted) over {self.area:.6g} mm^2, "
               f"{self.points} points"]
        width = 40
        for k, share in enumerate(self.shares):
            bar = "#" * int(round(width * share))
            out.append(f"{self.edges[k]:9.4g} .. {self.edges[k + 1]:<9.4g} mm "
                       f"{100.0 * share:5.1f} % {bar}")
        return out


def write_csv(path, sheets):
    """Writes one row per sheet vertex (sheet, x, y, z, radius, thickness; mm) to
    ``path``, with a header line.  Returns the number of rows."""
    sheet_of = sheets.sheet_of_vertex()
    with open(path, "w", encoding="utf-8", newline="") as f:
        f.write(",".join(CSV_HEADER) + "\n")
        for s, (x, y, z), r in zip(sheet_of.tolist(), sheets.points.tolist(),
                                   sheets.radii.tolist()):
            f.write(f"{s},{x!r},{y!r},{z!r},{r!r},{2.0 * r!r}\n")
    return len(sheet_of)


def sheet_faces(sheets, tolerance):
    """Part faces of every sheet; returns (faces, sheet index of each face).

    A planar sheet (every vertex within ``PLANAR_FRACTION * tolerance`` of its
    least-squares plane: the mid-plane of a wall, a bisector of two parallel faces)
    becomes one planar face bounded by the mesh's boundary loops (outer loop and holes),
    whose collinear runs are straightened: fast for any triangle count (the library
    samples a 16 x 8 mm sheet with 1.6e5 triangles at 0.1 mm).  Any other sheet keeps its
    triangles as faces (OCCT's makeShapeFromMesh, ~0.4 ms per triangle), coplanar
    neighbours merged when there are at most MERGE_LIMIT of them."""
    import Part
    faces, owner = [], []
    for s in range(len(sheets)):
        pts, tri, _r = sheets.sheet(s)
        if not len(tri):
            continue
        face = _planar_face(pts, tri, tolerance)
        if face is not None:
            faces.append(face)
            owner.append(s)
            continue
        shape = Part.Shape()
        shape.makeShapeFromMesh(([FreeCAD.Vector(*p) for p in pts.tolist()],
                                 [tuple(t) for t in tri.tolist()]), 1e-7)
        merged = shape
        if len(tri) <= MERGE_LIMIT:
            try:
                merged = shape.removeSplitter()
            except Part.OCCError:
                pass   # keep the triangles: still a valid mid-surface
        for f in merged.Faces:
            faces.append(f)
            owner.append(s)
    return faces, owner


def _planar_face(pts, tri, tolerance):
    """One planar Part face of a planar sheet, or None (not planar, or its boundary is
    not a set of simple loops OCCT makes a valid face of with the mesh's area)."""
    import Part
    centre = pts.mean(axis=0)
    _u, _s, vt = np.linalg.svd(pts - centre, full_matrices=False)
    normal = vt[2]
    flat = PLANAR_FRACTION * tolerance
    if np.abs((pts - centre) @ normal).max() > flat:
        return None
    loops = boundary_loops(tri)
    if not loops:
        return None
    on_plane = pts - np.outer((pts - centre) @ normal, normal)
    wires = []
    for loop in loops:
        ring = straightened(on_plane[loop], flat)
        if len(ring) < 3:
            return None
        vecs = [FreeCAD.Vector(*p) for p in ring.tolist()]
        wires.append(Part.makePolygon(vecs + [vecs[0]]))
    try:
        face = Part.makeFace(wires, "Part::FaceMakerBullseye")
    except Part.OCCError:
        return None
    if face.ShapeType != "Face":
        face = face.Faces[0] if len(face.Faces) == 1 else None
    area = mesh_area(pts, tri)
    if face is None or not face.isValid() or abs(face.Area - area) > 1e-6 * area + \
            flat * sum(w.Length for w in wires):
        return None
    return face


def shell_of(faces, tolerance):
    """One shape of ``faces``: sewn into a shell (or a compound of shells when the sheets
    do not all meet), so a FEM mesher sees shared edges where sheets join."""
    import Part
    if not faces:
        return Part.Shape()
    compound = Part.makeCompound(faces)
    try:
        sewn = compound.copy()
        sewn.sewShape(max(tolerance * _SEWING_FRACTION, 1e-7))
    except Part.OCCError:
        return Part.makeShell(faces) if len(faces) else compound
    shells = sewn.Shells
    if len(shells) == 1 and len(shells[0].Faces) == len(faces):
        return shells[0]
    return sewn


def face_thickness(shape, sheets, deflection):
    """The area-weighted mean thickness on each face of ``shape``: the face tessellated
    within ``deflection``, every tessellation triangle given the thickness of the sheet
    triangle whose centroid is nearest to its own (faces are merged from sheet triangles,
    so the nearest one lies on the same face)."""
    tri_thick, _area = triangle_thickness(sheets)
    faces = shape.Faces
    if not faces or not len(tri_thick):
        return [0.0] * len(faces)
    p, t = sheets.points, sheets.triangles
    centroids = (p[t[:, 0]] + p[t[:, 1]] + p[t[:, 2]]) / 3.0
    out = []
    for face in faces:
        pts, tris = face.tessellate(deflection)
        if not tris:
            out.append(0.0)
            continue
        q = np.array([(v.x, v.y, v.z) for v in pts], dtype=np.float64)[np.asarray(tris)]
        c = q.mean(axis=1)
        a = 0.5 * np.linalg.norm(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), axis=1)
        nearest = np.empty(len(c), dtype=np.int64)
        block = max(1, 2_000_000 // max(len(centroids), 1))   # bounds the distance matrix
        for i in range(0, len(c), block):
            d = ((c[i:i + block, None, :] - centroids[None, :, :]) ** 2).sum(axis=2)
            nearest[i:i + block] = d.argmin(axis=1)
        out.append(float((tri_thick[nearest] * a).sum() / a.sum()) if a.sum() > 0
                   else float(tri_thick[nearest].mean()))
    return out


# ---------------------------------------------------------------------------- feature
class MidSurface(FeatureProxy):
    """App proxy: the FEM mid-surface and thickness of its Source (a medial surface)."""

    TYPE = TYPE
    VERSION = VERSION
    VIEW_PROVIDER = "mfgeom.gui.medial_view.ViewProviderMidSurface"

    def _set_defaults(self, obj):
        obj.Bins = DEFAULT_BINS
        obj.setEditorMode("Placement", 2)

    @staticmethod
    def _add_properties(obj):
        # (type, name, group, tooltip, read-only output?)
        spec = [
            ("App::PropertyLink", "Source", "Mid-surface",
             "The medial surface (MajorOnly) of the thin-walled part", False),
            ("App::PropertyFile", "CsvFile", "Mid-surface",
             "When set, every recompute writes the points and their thickness here (CSV)",
             False),
            ("App::PropertyInteger", "Bins", "Mid-surface",
             "Bins of the thickness histogram", False),
            ("App::PropertyVectorList", "ThicknessPoints", "Result",
             "The points where the thickness is known (sheet vertices, global mm)", True),
            ("App::PropertyFloatList", "Thickness", "Result",
             "Local thickness (2 x medial radius, mm) at every point of ThicknessPoints",
             True),
            ("App::PropertyFloatList", "FaceThickness", "Result",
             "Area-weighted mean thickness (mm) on every face of the shape", True),
            ("App::PropertyFloat", "MinThickness", "Result", "Thinnest (mm)", True),
            ("App::PropertyFloat", "MaxThickness", "Result", "Thickest (mm)", True),
            ("App::PropertyFloat", "MeanThickness", "Result",
             "Mean thickness weighted by area (mm)", True),
            ("App::PropertyStringList", "Histogram", "Result",
             "The thickness report: area share per thickness bin", True),
            VERSION_PROPERTY,
        ]
        add_properties(obj, spec)
        obj.setEditorMode("ThicknessPoints", 2)

    def _execute(self, obj):
        source = obj.Source
        if source is None or not is_medial_surface(source):
            raise MedialInputError("the source must be a medial surface feature")
        if not source.isValid():
            raise MfgeomError(f"its medial surface failed: {status_line(source)}")
        if obj.Bins < 1:
            raise MedialInputError(f"Bins must be at least 1, got {obj.Bins}")
        sheets = sheet_mesh_of(source)
        if not len(sheets.triangles):
            raise MfgeomError(f"'{source.Label}' has no sheets: the part has no wall "
                              "whose two sides face each other (not thin-walled?)")
        report = ThicknessReport(sheets, obj.Bins)
        faces, _owner = sheet_faces(sheets, float(source.Tolerance.Value))
        shape = shell_of(faces, float(source.Tolerance.Value))
        if obj.CsvFile:
            write_csv(os.path.expanduser(obj.CsvFile), sheets)
        obj.Shape = shape
        obj.Placement = FreeCAD.Placement()
        obj.ThicknessPoints = [FreeCAD.Vector(*p) for p in sheets.points.tolist()]
        obj.Thickness = (2.0 * sheets.radii).tolist()
        obj.FaceThickness = face_thickness(shape, sheets, float(source.Tolerance.Value))
        obj.MinThickness = report.minimum
        obj.MaxThickness = report.maximum
        obj.Histogram = report.lines()
        obj.MeanThickness = report.mean   # last: the view colours the faces on it
        FreeCAD.Console.PrintMessage(
            f"mfgeom: {obj.Label}: {len(shape.Faces)} faces; "
            + "\n".join(report.lines())
            + (f"\nmfgeom: {obj.Label}: CSV written to {obj.CsvFile}" if obj.CsvFile else "")
            + "\n")


# ---------------------------------------------------------------------------- make
def make_mid_surface(doc: "FreeCAD.Document", source: "FreeCAD.DocumentObject",
                     csv_path: Optional[str] = None,
                     tolerance: Optional[Quantity] = None,
                     bins: int = DEFAULT_BINS,
                     deflection: Optional[Quantity] = None,
                     name: str = "MidSurface") -> "FreeCAD.DocumentObject":
    """Create the FEM mid-surface with its thickness in ``doc``.  ``source``: a medial
    surface feature, or a solid (then its major medial surface is made first with
    ``tolerance`` / ``deflection``, see :func:`make_medial_surface`).  ``csv_path``: write
    the points and thickness there (and on every recompute).  Returns the new object;
    nothing is left behind when it fails (the error, one line, is raised)."""
    from mfgeom.app import medial_surface_feature as msf
    if doc is None or not hasattr(doc, "addObject"):
        raise MedialInputError("no document given")
    if getattr(source, "Document", None) is not doc:
        raise MedialInputError("the source must be an object in this document")
    if not isinstance(bins, int) or isinstance(bins, bool) or bins < 1:
        raise MedialInputError(f"bins must be an integer >= 1, got {bins!r}")
    if csv_path is not None:
        folder = os.path.dirname(os.path.abspath(os.path.expanduser(str(csv_path))))
        if not os.path.isdir(folder):
            raise MedialInputError(f"the CSV file's folder does not exist: {folder}")
    made = None
    if is_medial_surface(source):
        if not source.MajorOnly:
            FreeCAD.Console.PrintWarning(f"mfgeom: '{source.Label}' is the full medial "
                                         "surface: the mid-surface takes all its sheets\n")
        medial = source
    else:
        kwargs = {} if deflection is None else {"deflection": deflection}
        made = medial = msf.make_medial_surface(doc, source, tolerance, True, **kwargs)
    values = {"Label": f"Mid-surface of {getattr(medial.Source, 'Label', medial.Label)}",
              "Source": medial, "Bins": bins}
    if csv_path is not None:
        values["CsvFile"] = os.path.abspath(os.path.expanduser(str(csv_path)))
    try:
        obj = MidSurface.make(doc, name, values, "mid-surface")
    except Exception:  # the medial surface made here goes too, then re-raise
        if made is not None:
            doc.removeObject(made.Name)
        raise
    if FreeCAD.GuiUp and medial.ViewObject is not None:
        # the mid-surface draws the same sheets and legend: one legend in the view
        medial.ViewObject.Visibility = False
    return obj
