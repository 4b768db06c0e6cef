# SPDX-License-Identifier: LGPL-2.1-or-later
"""The parametric "medial surface" feature (issue 9, section 4): App proxy, the pure
geometry functions and the make function.

The medial surface (locus of centres of maximal inscribed balls) of a solid, computed by
libmfgeom (:func:`mfgeom.core.medial_surface`) from a closed triangle mesh of the solid
in global coordinates (planar faces exactly; curved faces tessellated to ``Deflection``:
the result is then the medial surface of that polyhedron), recomputed whenever the
source or a parameter changes.

What the feature holds (a ``Part::FeaturePython``, as the rotational sweep):

* the sheets (surface pieces equidistant from two boundary elements) as triangle meshes
  in double precision: ``SheetPoints`` (all sheets' vertices), ``SheetFacets`` (flat
  vertex index triples into SheetPoints), ``SheetRadii`` (the radius, distance to the
  boundary, at every vertex: the local wall thickness is 2 x radius),
  ``SheetVertexOffsets`` / ``SheetTriangleOffsets`` (sheet s owns vertices
  [off[s], off[s+1]) and triangles likewise) and ``SheetElements`` (the two boundary
  element ids of every sheet); ``Mesh`` (a FreeCAD mesh of all sheets, for export);
* the seams as data: ``SeamPoints`` (every seam's polyline, global, double precision)
  split by ``SeamPointOffsets``, and ``SeamElements`` (the element ids equidistant
  along each seam) split by ``SeamElementOffsets`` -- a sheet with elements (a, b) is
  bounded by the seams whose elements hold a and b (the mid-surface joins its sheets
  along them);
* ``Shape``: a compound of the seams (curves where three or more elements are
  equidistant) as polyline wires and the junctions (centres of balls touching four or
  more elements) as vertices, usable by Part tools;
* counts and the radius range (``MinRadius`` / ``MaxRadius``).
The view provider (mfgeom.gui.medial_view) draws the sheets coloured by thickness with a
legend of the colour scale, the seams and the junctions.  The FEM mid-surface
(mfgeom.app.mid_surface_feature) is made from the sheets of a MajorOnly medial surface.
"""

import math
import time
from typing import Optional

import numpy as np

import FreeCAD

from mfgeom.app.feature_base import (VERSION_PROPERTY, add_mesh_property, add_properties,
                                     FeatureProxy, Quantity)
from mfgeom import progress
from mfgeom.errors import InputError, MfgeomError

# 1: first release; 2: the seams as data (SeamPoints, SeamPointOffsets, SeamElements,
# SeamElementOffsets: the FEM mid-surface joins its sheets along them).  Bump when
# properties change and migrate in _upgrade().
VERSION = 2
TYPE = "Mfgeom::MedialSurface"
TOLERANCE_FRACTION = 0.005      # default tolerance: 0.5 % of the bounding-box diagonal
DEFAULT_DEFLECTION = 0.1        # mm, curved faces only


class MedialInputError(InputError):
    """A bad source or parameter given to the medial surface."""


# ---------------------------------------------------------------------------- geometry
def default_tolerance(shape):
    """0.5 % of the bounding-box diagonal of ``shape`` (a Part shape, or a
    :class:`MeshSource`: the issue's working tolerance)."""
    return TOLERANCE_FRACTION * shape.BoundBox.DiagonalLength


class MeshSource:
    """A closed triangle mesh given as the source (a Mesh object, issue 22: STL parts come
    into FreeCAD as meshes, and the CLI takes them too): ``vertices`` (n, 3) global,
    ``triangles`` (t, 3), ``BoundBox`` (FreeCAD.BoundBox).  Closedness and orientation are
    the library's check (its message names the problem)."""

    def __init__(self, vertices, triangles):
        self.vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
        self.triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
        lo, hi = self.vertices.min(axis=0), self.vertices.max(axis=0)
        self.BoundBox = FreeCAD.BoundBox(*lo.tolist(), *hi.tolist())


def mesh_source(source):
    """The :class:`MeshSource` of a Mesh object (``Mesh::Feature`` and the like: a ``Mesh``
    property with facets and no solid Shape) in global coordinates, or None.  A Mesh
    feature's points come with its own Placement applied; containers' placements (an
    App::Part) are applied here."""
    mesh = getattr(source, "Mesh", None)
    if mesh is None or not hasattr(mesh, "Topology") or not getattr(mesh, "CountFacets", 0):
        return None
    points, facets = mesh.Topology
    v = np.array([(p.x, p.y, p.z) for p in points], dtype=np.float64).reshape(-1, 3)
    t = np.array(facets, dtype=np.int64).reshape(-1, 3)
    try:   # the containers' placements: global = containers * own
        extra = source.getGlobalPlacement().multiply(source.Placement.inverse())
    except (AttributeError, RuntimeError):
        extra = None
    if extra is not None and not extra.isIdentity():
        m = extra.toMatrix()
        A = np.array([[m.A11, m.A12, m.A13], [m.A21, m.A22, m.A23], [m.A31, m.A32, m.A33]])
        v = v @ A.T + np.array([m.A14, m.A24, m.A34])
    return MeshSource(v, t)


def solid_shape(source, allow_mesh=False):
    """The solids of ``source`` in global coordinates (the containers' placements
    applied), or with ``allow_mesh`` for a Mesh object its :class:`MeshSource`;
    MedialInputError saying why there is neither."""
    from mfgeom.app import gauss_map
    label = getattr(source, "Label", "?")
    shape = getattr(source, "Shape", None)
    if allow_mesh and (shape is None or shape.isNull() or not shape.Solids):
        ms = mesh_source(source)
        if ms is not None:
            return ms
    if shape is None or shape.isNull():
        raise MedialInputError(f"'{label}' has no shape" + (" and no mesh" if allow_mesh else ""))
    if not shape.Solids:
        raise MedialInputError(f"'{label}' is not a solid (select a closed solid)")
    return gauss_map.shape_of(source)


def medial_of_shape(shape, tolerance, deflection, major_only=True):
    """(result of core.medial_surface, source triangle count, library seconds) for the
    solids of ``shape``: tessellated with :func:`mfgeom.app.sweep_feature.source_mesh`
    (planar faces exactly, curved ones within ``deflection``) and welded; a
    :class:`MeshSource` is taken as it is."""
    from mfgeom import core
    if isinstance(shape, MeshSource):
        vertices, triangles = shape.vertices, shape.triangles
    else:
        from mfgeom.app.sweep_feature import source_mesh
        vertices, triangles, _curved = source_mesh(shape, deflection)
    if not hasattr(core, "medial_surface"):
        raise MfgeomError("this mfgeom build has no medial surface binding "
                          "(core.medial_surface)")
    t0 = time.perf_counter()
    result = core.medial_surface(vertices, triangles, tolerance, major_only=major_only,
                                 progress=progress.current())
    return result, len(triangles), time.perf_counter() - t0


class SheetMesh:
    """All sheets of a medial surface as one triangle mesh (plain data): ``points``
    (n, 3), ``triangles`` (t, 3) global indices, ``radii`` (n,), ``vertex_offsets`` and
    ``triangle_offsets`` (sheet s: [off[s], off[s+1])), ``elements`` (s, 2)."""

    def __init__(self, points, triangles, radii, vertex_offsets, triangle_offsets, elements):
        self.points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        self.triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
        self.radii = np.asarray(radii, dtype=np.float64).reshape(-1)
        self.vertex_offsets = np.asarray(vertex_offsets, dtype=np.int64)
        self.triangle_offsets = np.asarray(triangle_offsets, dtype=np.int64)
        self.elements = np.asarray(elements, dtype=np.int64).reshape(-1, 2)

    def __len__(self):
        return len(self.vertex_offsets) - 1

    def sheet(self, s):
        """(points, local triangles, radii) of sheet ``s``."""
        v0, v1 = self.vertex_offsets[s], self.vertex_offsets[s + 1]
        t0, t1 = self.triangle_offsets[s], self.triangle_offsets[s + 1]
        return self.points[v0:v1], self.triangles[t0:t1] - v0, self.radii[v0:v1]

    def sheet_of_vertex(self):
        """(n,) the sheet index of every vertex."""
        return np.repeat(np.arange(len(self)), np.diff(self.vertex_offsets))

    def area(self):
        p = self.points
        t = self.triangles
        if not len(t):
            return 0.0
        return 0.5 * float(np.linalg.norm(np.cross(p[t[:, 1]] - p[t[:, 0]],
                                                   p[t[:, 2]] - p[t[:, 0]]), axis=1).sum())


def sheet_mesh(result):
    """The sheets of a core.medial_surface result concatenated into a :class:`SheetMesh`."""
    points, tris, radii, voff, toff, elements = [], [], [], [0], [0], []
    for sheet in result.sheets:
        v = np.asarray(sheet.vertices, dtype=np.float64).reshape(-1, 3)
        t = np.asarray(sheet.triangles, dtype=np.int64).reshape(-1, 3)
        points.append(v)
        tris.append(t + voff[-1])
        radii.append(np.asarray(sheet.radii, dtype=np.float64).reshape(-1))
        voff.append(voff[-1] + len(v))
        toff.append(toff[-1] + len(t))
        el = list(np.asarray(sheet.elements).reshape(-1)[:2])
        elements.append(el + [-1] * (2 - len(el)))
    cat = (lambda xs, shape, dt: np.concatenate(xs).astype(dt) if xs
           else np.zeros(shape, dtype=dt))
    return SheetMesh(cat(points, (0, 3), np.float64), cat(tris, (0, 3), np.int64),
                     cat(radii, (0,), np.float64), voff, toff,
                     np.asarray(elements, dtype=np.int64).reshape(-1, 2))


def sheet_mesh_of(obj):
    """The :class:`SheetMesh` a MedialSurface feature holds (its properties)."""
    pts = np.array([(p.x, p.y, p.z) for p in obj.SheetPoints], dtype=np.float64)
    return SheetMesh(pts, obj.SheetFacets, obj.SheetRadii, obj.SheetVertexOffsets or [0],
                     obj.SheetTriangleOffsets or [0], obj.SheetElements)


def seam_lists(result):
    """([points (k, 3) per seam], [element ids per seam]) of a core.medial_surface
    result."""
    return ([np.asarray(c.points, dtype=np.float64).reshape(-1, 3) for c in result.seams],
            [np.asarray(c.elements, dtype=np.int64).reshape(-1) for c in result.seams])


def seams_of(obj):
    """The seams a MedialSurface feature holds: [(points (k, 3), element ids), ...];
    empty for an object made before version 2 and not recomputed since."""
    poff = list(getattr(obj, "SeamPointOffsets", []) or [])
    eoff = list(getattr(obj, "SeamElementOffsets", []) or [])
    if len(poff) < 2 or len(eoff) != len(poff):
        return []
    pts = np.array([(p.x, p.y, p.z) for p in obj.SeamPoints], dtype=np.float64).reshape(-1, 3)
    els = np.asarray(obj.SeamElements, dtype=np.int64)
    return [(pts[poff[c]:poff[c + 1]], els[eoff[c]:eoff[c + 1]]) for c in range(len(poff) - 1)]


def shape_of_seams(result):
    """A compound of the seams (polyline wires) and the junctions (vertices)."""
    import Part
    parts = []
    for seam in result.seams:
        pts = np.asarray(seam.points, dtype=np.float64).reshape(-1, 3)
        if len(pts) >= 2:
            keep = np.concatenate([[True], np.linalg.norm(np.diff(pts, axis=0), axis=1) > 1e-12])
            pts = pts[keep]
        if len(pts) >= 2:
            parts.append(Part.makePolygon([FreeCAD.Vector(*p) for p in pts.tolist()]))
    junctions = np.asarray(result.junctions.points, dtype=np.float64).reshape(-1, 3)
    parts.extend(Part.Vertex(FreeCAD.Vector(*p)) for p in junctions.tolist())
    return Part.makeCompound(parts)


def check_parameters(tolerance, deflection):
    """MedialInputError unless both are finite lengths > 0 mm."""
    for value, what in ((tolerance, "tolerance"), (deflection, "deflection")):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
            raise MedialInputError(f"the {what} must be a length > 0 mm, got {value!r}")


# ---------------------------------------------------------------------------- feature
class MedialSurface(FeatureProxy):
    """App proxy: recomputes the medial surface of its Source."""

    TYPE = TYPE
    VERSION = VERSION
    VIEW_PROVIDER = "mfgeom.gui.medial_view.ViewProviderMedialSurface"

    def _set_defaults(self, obj):
        obj.MajorOnly = True
        obj.Deflection = DEFAULT_DEFLECTION
        obj.setEditorMode("Placement", 2)   # the result is placed in global coordinates

    @staticmethod
    def _add_properties(obj):
        # (type, name, group, tooltip, read-only output?)
        spec = [
            ("App::PropertyLink", "Source", "Medial surface", "The solid", False),
            ("App::PropertyLength", "Tolerance", "Medial surface",
             "Sheets and seams lie within this distance of the true medial surface "
             "(default: 0.5 % of the source's bounding-box diagonal)", False),
            ("App::PropertyBool", "MajorOnly", "Medial surface",
             "Only the major part (sheets between elements that share no edge or vertex: "
             "the mid-surface); off: the full medial surface, out to convex edges", False),
            ("App::PropertyLength", "Deflection", "Medial surface",
             "Curved faces are tessellated within this distance (the result is the medial "
             "surface of that polyhedron); planar faces are exact", False),
            ("App::PropertyInteger", "SheetCount", "Result", "Sheets", True),
            ("App::PropertyInteger", "SeamCount", "Result", "Seams (wires of the shape)",
             True),
            ("App::PropertyInteger", "JunctionCount", "Result",
             "Junctions (vertices of the shape)", True),
            ("App::PropertyFloat", "MinRadius", "Result",
             "Smallest radius (mm) on the sheets: half the thinnest wall", True),
            ("App::PropertyFloat", "MaxRadius", "Result",
             "Largest radius (mm) on the sheets: half the thickest wall", True),
            ("App::PropertyFloat", "SheetArea", "Result", "Area of all sheets (mm^2)", True),
            ("App::PropertyInteger", "SourceTriangles", "Result",
             "Triangles of the source's mesh", True),
            ("App::PropertyVectorList", "SheetPoints", "Result",
             "Vertices of all sheets (global, mm)", True),
            ("App::PropertyIntegerList", "SheetFacets", "Result",
             "Triangles of all sheets: vertex index triples into SheetPoints", True),
            ("App::PropertyFloatList", "SheetRadii", "Result",
             "Radius (mm) at every sheet vertex; the local thickness is 2 x radius", True),
            ("App::PropertyIntegerList", "SheetVertexOffsets", "Result",
             "Sheet s owns SheetPoints[off[s] .. off[s+1]]", True),
            ("App::PropertyIntegerList", "SheetTriangleOffsets", "Result",
             "Sheet s owns triangles off[s] .. off[s+1] of SheetFacets", True),
            ("App::PropertyIntegerList", "SheetElements", "Result",
             "The two boundary element ids of every sheet (pairs)", True),
            ("App::PropertyVectorList", "SeamPoints", "Result",
             "The points of every seam's polyline (global, mm)", True),
            ("App::PropertyIntegerList", "SeamPointOffsets", "Result",
             "Seam c owns SeamPoints[off[c] .. off[c+1]]", True),
            ("App::PropertyIntegerList", "SeamElements", "Result",
             "The element ids equidistant along every seam (see SeamElementOffsets)", True),
            ("App::PropertyIntegerList", "SeamElementOffsets", "Result",
             "Seam c's elements are SeamElements[off[c] .. off[c+1]]", True),
            VERSION_PROPERTY,
        ]
        add_properties(obj, spec)
        for name in ("SheetPoints", "SheetFacets", "SheetRadii", "SheetVertexOffsets",
                     "SheetTriangleOffsets", "SheetElements", "SeamPoints",
                     "SeamPointOffsets", "SeamElements", "SeamElementOffsets"):
            obj.setEditorMode(name, 2)   # long lists: hidden in the property editor
        add_mesh_property(obj, "All sheets as one mesh (global), for export")

    def _execute(self, obj):
        if obj.Source is None:
            raise MedialInputError("the source is gone; set the Source property again")
        shape = solid_shape(obj.Source, allow_mesh=True)
        tolerance, deflection = float(obj.Tolerance.Value), float(obj.Deflection.Value)
        check_parameters(tolerance, deflection)
        result, source_triangles, seconds = medial_of_shape(shape, tolerance, deflection,
                                                            bool(obj.MajorOnly))
        sheets = sheet_mesh(result)
        seams = shape_of_seams(result)
        self.last_sheets = sheets   # for the view (not saved)
        from mfgeom.app.sweep_feature import mesh_of
        obj.Mesh = mesh_of(sheets.points, sheets.triangles)
        obj.Shape = seams
        obj.Placement = FreeCAD.Placement()
        obj.SheetPoints = [FreeCAD.Vector(*p) for p in sheets.points.tolist()]
        obj.SheetFacets = sheets.triangles.reshape(-1).tolist()
        obj.SheetRadii = sheets.radii.tolist()
        obj.SheetVertexOffsets = sheets.vertex_offsets.tolist()
        obj.SheetTriangleOffsets = sheets.triangle_offsets.tolist()
        obj.SheetElements = sheets.elements.reshape(-1).tolist()
        seam_points, seam_elements = seam_lists(result)
        obj.SeamPoints = [FreeCAD.Vector(*p) for pts in seam_points for p in pts.tolist()]
        obj.SeamPointOffsets = np.cumsum([0] + [len(p) for p in seam_points]).tolist()
        obj.SeamElements = [int(e) for els in seam_elements for e in els]
        obj.SeamElementOffsets = np.cumsum([0] + [len(e) for e in seam_elements]).tolist()
        obj.SheetCount = len(sheets)
        obj.SeamCount = len(result.seams)
        obj.JunctionCount = len(np.asarray(result.junctions.radii).reshape(-1))
        obj.SourceTriangles = source_triangles
        obj.SheetArea = sheets.area()
        obj.MinRadius = float(sheets.radii.min()) if len(sheets.radii) else 0.0
        obj.MaxRadius = float(sheets.radii.max()) if len(sheets.radii) else 0.0  # last: view
        FreeCAD.Console.PrintLog(
            f"mfgeom: {obj.Label}: {source_triangles} source triangles, {len(sheets)} "
            f"sheets, {obj.SeamCount} seams, {obj.JunctionCount} junctions; library "
            f"{1e3 * seconds:.1f} ms\n")

    def _restored(self):
        self.last_sheets = None


def result_text(obj):
    """The one-paragraph summary of a medial surface (task panel, Report view)."""
    if obj is None:
        return "No result yet."
    if not obj.isValid():
        return f"Failed: {obj.getStatusString()}"
    return (f"{obj.SheetCount} sheets ({obj.SheetArea:.6g} mm^2), {obj.SeamCount} seams, "
            f"{obj.JunctionCount} junctions; thickness (2 x radius) "
            f"{2 * obj.MinRadius:.4g} .. {2 * obj.MaxRadius:.4g} mm; "
            f"{obj.SourceTriangles} source triangles")


# ---------------------------------------------------------------------------- make
def is_medial_surface(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", "") == TYPE


def make_medial_surface(doc: "FreeCAD.Document", source: "FreeCAD.DocumentObject",
                        tolerance: Optional[Quantity] = None,
                        major_only: bool = True,
                        deflection: Quantity = DEFAULT_DEFLECTION,
                        name: str = "MedialSurface") -> "FreeCAD.DocumentObject":
    """Create the medial surface of ``source`` (a document object with a solid Shape, or a
    Mesh object with a closed mesh) in
    ``doc`` and compute it.  ``tolerance``: mm, a length Quantity or "0.1 mm" (default
    None: 0.5 % of the source's bounding-box diagonal); ``major_only``: the major part
    (the mid-surface) or the full medial surface; ``deflection``: mm, for curved faces.
    Inputs are checked before anything is created; if the first recompute fails (e.g.
    the library refuses the solid) the object is removed again and the error (one line)
    raised.  Returns the new object."""
    from mfgeom.app.medial_axis_feature import length_value
    if doc is None or not hasattr(doc, "addObject"):
        raise MedialInputError("no document given")
    if (source is None or not (hasattr(source, "Shape") or hasattr(source, "Mesh"))
            or getattr(source, "Document", None) is not doc):
        raise MedialInputError("the source must be an object with a Shape or a Mesh in this "
                               "document")
    shape = solid_shape(source, allow_mesh=True)
    tol = (default_tolerance(shape) if tolerance is None
           else length_value(tolerance, "the tolerance"))
    defl = length_value(deflection, "the deflection")
    return MedialSurface.make(doc, name, {
        "Label": f"Medial surface of {source.Label}", "Source": source, "Tolerance": tol,
        "MajorOnly": bool(major_only), "Deflection": defl}, "medial surface")
