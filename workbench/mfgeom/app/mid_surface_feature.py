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
import Part

from mfgeom.app.feature_base import (VERSION_PROPERTY, add_properties, FeatureProxy,
                                     Quantity, status_line)
from mfgeom.app.medial_surface_feature import (MedialInputError, is_medial_surface,
                                               seams_of, sheet_mesh_of)
from mfgeom.app.mesh_shapes import SharedEdges
from mfgeom.errors import MfgeomError
# boundary_loops lives in mfgeom.geometry.mesh (FreeCAD-free); it stays importable here.
from mfgeom.geometry.mesh import (boundary_loops, mesh_area, straightened,  # noqa: F401
                                  straightened_indices)
from mfgeom.geometry.planar import label_components
from mfgeom.palette import one_value

# 1: first release.  Bump when properties change and migrate in _upgrade().
VERSION = 1
TYPE = "Mfgeom::MidSurface"
DEFAULT_BINS = 10
CSV_HEADER = ("sheet", "x", "y", "z", "radius", "thickness")
# A sheet is planar (one face) when all its vertices lie within this fraction of the
# tolerance of a plane: the library places them on the analytic bisector up to rounding.
PLANAR_FRACTION = 1e-3
# Sewing tolerance of the sheets' faces, relative to the medial surface's tolerance:
# sheet_faces gives neighbouring faces the same boundary points, so only rounding is
# left to sew.
_SEWING_FRACTION = 1e-6


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


def sheet_faces(sheets, tolerance, seams=None, stats=None):
    """Part faces of every sheet; returns (faces, sheet index of each face).

    The sheets are first made to share their boundaries
    (:func:`mfgeom.geometry.conform.conforming_sheets`: boundary vertices onto the
    sheet's own ``seams`` -- [(points, elements), ...] of the medial surface --, edges
    along them through the junctions, zero-area triangles split away, what is left
    welded within the tolerance).  The faces are then built on shared B-rep vertices and
    edges (one per point and per pair of points), oriented alike across every edge two
    faces share: neighbouring sheets meet on the same edge without sewing, and where
    three sheets meet (a rib on a wall) the three faces share it too.  Issue 22: the
    2 mm shell box's sheets, sewn as the library gives them, left 8 shells with free
    edges at every junction, vertex tolerances overlapping their neighbours' and (a
    strip the library left unsimplified) 240 zero-area faces.

    A planar sheet (every vertex within ``PLANAR_FRACTION * tolerance`` of its
    least-squares plane: the mid-plane of a wall, a bisector of two parallel faces)
    becomes one planar face bounded by its boundary loops (outer loop and holes), whose
    collinear runs of points no other sheet has are straightened: fast for any triangle
    count (the library samples a 16 x 8 mm sheet with 1.6e5 triangles at 0.1 mm).  Any
    other sheet becomes one planar face per triangle (~0.4 ms each).  ``stats`` (a
    dict) receives the counts of the conforming pass."""
    from mfgeom.geometry.conform import conforming_sheets
    parts = [sheets.sheet(s) for s in range(len(sheets))]
    conformed = conforming_sheets(
        [(pts, tri, sheets.elements[s]) for s, (pts, tri, _r) in enumerate(parts)],
        seams or [], tolerance, stats)
    xyz = {}
    patches = []   # (sheet, loops of point ids, planar normal or None)
    for s, ((pts, _tri, _r), sheet) in enumerate(zip(parts, conformed)):
        if not len(sheet.triangles):
            continue
        for g, p in zip(sheet.ids.tolist(), sheet.points):
            xyz[g] = p
        loops, normal = _planar_loops(pts, sheet, tolerance)
        if loops is not None:
            patches.append((s, loops, normal))
            continue
        for f in sheet.ids[sheet.triangles].tolist():
            patches.append((s, [f], None))
    flips = _orientation([loops for _s, loops, _n in patches])
    builder = _SharedEdges(xyz)
    faces, owner = [], []
    for (s, loops, normal), flip in zip(patches, flips):
        if flip:
            loops = [loop[::-1] for loop in loops]
            normal = None if normal is None else -normal
        face = builder.face(loops, normal)
        if face is not None:
            faces.append(face)
            owner.append(s)
    return faces, owner


def _planar_loops(original, sheet, tolerance):
    """(loops of global point ids, unit normal) of the one planar face a planar sheet
    becomes, or (None, None): not planar (``original``: its points as the library gave
    them), a conformed point off the plane, or a boundary that is not a set of simple
    loops of the mesh's area.  The loops run as the sheet's triangles do (outer
    counter-clockwise about the normal, holes clockwise); the points no other sheet has
    are left out along straight runs."""
    centre = original.mean(axis=0)
    _u, _s, vt = np.linalg.svd(original - centre, full_matrices=False)
    normal = vt[2]
    flat = PLANAR_FRACTION * tolerance
    if np.abs((original - centre) @ normal).max() > flat:
        return None, None
    pts, tri = sheet.points, sheet.triangles
    # the points the conforming pass put on seams lie on the plane up to rounding; one
    # welded off it would make the face's edges miss its neighbours': triangles then
    if np.abs((pts - centre) @ normal).max() > 1e-9 * max(1.0, float(np.abs(pts).max())):
        return None, None
    loops = boundary_loops(tri)
    if not loops:
        return None, None
    n = np.cross(pts[tri[:, 1]] - pts[tri[:, 0]], pts[tri[:, 2]] - pts[tri[:, 0]]).sum(axis=0)
    if n @ normal < 0:
        normal = -normal
    out, area = [], 0.0
    for loop in loops:
        local = np.asarray(loop, dtype=np.int64)
        ring = local[straightened_indices(pts[local], flat, keep=sheet.shared[local])]
        if len(ring) < 3:
            return None, None
        q = pts[ring]
        area += 0.5 * float(np.cross(q, np.roll(q, -1, axis=0)).sum(axis=0) @ normal)
        out.append(sheet.ids[ring].tolist())
    if abs(area - mesh_area(pts, tri)) > 1e-6 * mesh_area(pts, tri) + flat * \
            sum(np.linalg.norm(np.diff(pts[lp + lp[:1]], axis=0), axis=1).sum() for lp in loops):
        return None, None   # loops crossing or nested oddly: not this face's area
    return out, normal


def _orientation(patch_loops):
    """Whether to reverse each patch (a face given by loops of point ids) so that every
    edge two patches share runs opposite ways in them (breadth first; an edge of three
    or more patches -- a rib on a wall -- sets nothing)."""
    users = {}
    for k, loops in enumerate(patch_loops):
        for loop in loops:
            for i, a in enumerate(loop):
                b = loop[(i + 1) % len(loop)]
                users.setdefault((min(a, b), max(a, b)), []).append((k, 1 if a < b else -1))
    links = {}
    for pair in users.values():
        if len(pair) == 2 and pair[0][0] != pair[1][0]:
            (p, dp), (q, dq) = pair
            same = dp == dq   # both run the edge the same way: one of them turns
            links.setdefault(p, []).append((q, same))
            links.setdefault(q, []).append((p, same))
    flip = [None] * len(patch_loops)
    for seed in range(len(patch_loops)):
        if flip[seed] is not None:
            continue
        flip[seed] = False
        stack = [seed]
        while stack:
            p = stack.pop()
            for q, same in links.get(p, ()):
                if flip[q] is None:
                    flip[q] = flip[p] != same
                    stack.append(q)
    return flip


class _SharedEdges(SharedEdges):
    """Planar faces on shared vertices and edges (mfgeom.app.mesh_shapes.SharedEdges,
    point ids global to all sheets): faces built here that meet along an edge hold the
    same edge."""

    def face(self, loops, normal=None):
        """A planar face bounded by ``loops`` (point ids; the first the outer one,
        counter-clockwise about ``normal``; a triangle when ``normal`` is None), or
        None when OCCT makes no valid face of them."""
        first = np.array([self._points[g] for g in loops[0]])
        if normal is None:
            n = np.cross(first[1] - first[0], first[2] - first[0])
            length = float(np.linalg.norm(n))
            if length == 0.0:
                return None
            normal = n / length
        try:
            wires = []
            for k, loop in enumerate(loops):
                wire = self.wire(loop)
                # the wire runs as its first edge is stored (lower id first): turn it to
                # run as the loop does (outer counter-clockwise, holes clockwise)
                q = np.array([tuple(v.Point) for v in wire.OrderedVertexes])
                turn = np.cross(q - q.mean(axis=0), np.roll(q, -1, axis=0) - q.mean(axis=0))
                if (turn.sum(axis=0) @ normal > 0) != (k == 0):
                    wire.reverse()
                wires.append(wire)
            face = Part.Face(Part.Plane(FreeCAD.Vector(*first[0].tolist()),
                                        FreeCAD.Vector(*np.asarray(normal).tolist())), wires)
        except Part.OCCError:
            return None
        return face if face.isValid() and face.Area > 0.0 else None


def shell_of(faces, tolerance):
    """One shape of ``faces``.  Faces that share their edges (sheet_faces) are grouped
    into shells, each a set of faces joined through edges exactly two of them have; a
    single shell is returned as it is, several as a compound (they still share the edges
    where three sheets meet, so a FEM mesher joins them there).  Faces that share no
    edge are sewn (OCCT) with a tolerance of ``tolerance * _SEWING_FRACTION``: only
    rounding (a sewing at the medial tolerance raises vertex tolerances above the size
    of the small sheets at a junction, and OCCT's check finds them intersecting)."""
    if not faces:
        return Part.Shape()
    users = {}
    for k, face in enumerate(faces):
        for e in face.Edges:
            users.setdefault(e.hashCode(), set()).add(k)
    if len(faces) > 1 and all(len(u) < 2 for u in users.values()):
        compound = Part.makeCompound(faces)
        try:
            sewn = compound.copy()
            sewn.sewShape(max(tolerance * _SEWING_FRACTION, 1e-7))
        except Part.OCCError:
            return compound
        shells = sewn.Shells
        if len(shells) == 1 and len(shells[0].Faces) == len(faces):
            return shells[0]
        return sewn
    pairs = [sorted(u) for u in users.values() if len(u) == 2]
    label = label_components(len(faces), np.array([a for a, _b in pairs], dtype=np.int64),
                             np.array([b for _a, b in pairs], dtype=np.int64))
    groups = {}
    for k in range(len(faces)):
        groups.setdefault(int(label[k]), []).append(faces[k])
    shells = [Part.Shell(group) for group in groups.values()]
    return shells[0] if len(shells) == 1 else Part.makeCompound(shells)


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
        faces, _owner = sheet_faces(sheets, float(source.Tolerance.Value), seams_of(source))
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
