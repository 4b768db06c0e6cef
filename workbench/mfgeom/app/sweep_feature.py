# SPDX-License-Identifier: LGPL-2.1-or-later
"""The parametric "rotational sweep" feature (issue 8): App proxy and make function.

The volume a solid sweeps while it turns about an axis by 0 .. Angle (right-handed about
the axis direction), computed by libmfgeom (:func:`mfgeom.core.rotational_sweep`) from a
closed triangle mesh of the solid, and recomputed whenever the source, the axis or a
parameter changes.

Which FreeCAD object: a ``Part::FeaturePython`` with a ``Mesh`` property
(``Mesh::PropertyMeshKernel``) and its own view provider (mfgeom.gui.sweep_view), not a
``Mesh::FeaturePython``.  In FreeCAD 0.20 a Mesh feature's extra ``Shape`` property is
invisible to Part (``Part.getShape`` returns a null shape, Part's Boolean and export
commands refuse it), so a Mesh feature could not give the Solid representation to Part
tools; a Part feature can, and a Mesh property is stored (binary, in the FCStd), exported
and read back by FreeCAD like a Mesh feature's.  The view provider draws the Mesh
representation itself with one Coin indexed face set (display mode "Mesh": fast for
millions of triangles, no OCCT shape per triangle) and shows the Solid representation
with Part's own display modes.

* Mesh (default): ``Mesh`` holds the result, ``Shape`` is empty.  FreeCAD's mesh kernel
  stores single-precision coordinates (~1e-7 relative); Volume, Area and the bounding box
  are the library's, in double precision.
* Always: ``ExactVertices`` (App::PropertyVectorList) and ``ExactTriangles``
  (App::PropertyFloatList, three vertex indices a triangle), hidden, keep the library's
  result in double precision; FreeCAD saves both as binary doubles in the FCStd (0.20
  and 1.0 alike).  :func:`exact_mesh` reads them.  Rounded to single precision the mesh
  of a curved part gets non-manifold edges and zero-area triangles (FreeCAD's mesh
  kernel merges corners that became equal), so the clearance check, the Solid
  representation and the view use the exact mesh; the Mesh property stays for other
  tools and export.  An App::PropertyFileIncluded was tried first and dropped: FreeCAD
  0.20 copies a new result into the file it made read-only (a failure for a user who is
  not root), and ``copyObject`` shares that file between original and copy until a
  recompute of one deletes it, after which the document cannot be saved.  A document
  of version 1 has no exact mesh until its next recompute (the clearance check then
  falls back to the Mesh).
* Solid: ``Shape`` is a Part solid of the exact triangles with coplanar neighbours
  merged into planar faces built on shared vertices and edges
  (:mod:`mfgeom.app.mesh_shapes`: no sewing); it must be valid and its volume must
  agree with the library's (an error otherwise).  Seconds for 2e4 triangles, about a
  minute for 1.4e5.

Inputs are in global coordinates: the source's global placement (containers included)
is applied to its shape, so the answer moves with the part; an AxisObject (a straight
edge, a datum line, a Part / Body origin axis) is also read in global coordinates and
then overrides AxisPoint / AxisDirection (which show the axis used).  The feature's own
Placement stays the identity (hidden): the result is already placed.

Curved sources are tessellated with ``Deflection`` and the mesh made conservative by
:func:`conservative_offset` (see there); planar faces stay exact.
"""

import math
import time

import numpy as np

import FreeCAD

from mfgeom.app.feature_base import (VERSION_PROPERTY, add_mesh_property, add_properties,
                                     FeatureProxy, Quantity)
from mfgeom import progress
from mfgeom.errors import InputError, MfgeomError
# conservative_offset lives in mfgeom.geometry.mesh (FreeCAD-free, tested by pytest); its
# names stay importable from here.
from mfgeom.geometry.mesh import MAX_OFFSET_FACTOR, conservative_offset  # noqa: F401

# 1: first release.  2: ExactVertices, ExactTriangles.  Bump when properties change and
# migrate in _upgrade().
VERSION = 2
TYPE = "Mfgeom::RotationalSweep"
REPRESENTATIONS = ["Mesh", "Solid"]
DEFAULT_ANGLE = 90.0          # degrees
# A new sweep's tolerance and deflection are scaled to its part (part_defaults); these
# absolute values are only the properties' initial values before make_rotational_sweep
# sets them.
DEFAULT_TOLERANCE = 0.01      # mm
DEFAULT_DEFLECTION = 0.01     # mm


class SweepInputError(InputError):
    """A bad source, axis or parameter given to the rotational sweep."""


# ---------------------------------------------------------------------------- geometry
def _meshed_copy(shape, deflection):
    """A copy of ``shape`` (the source's own triangulation is left alone) meshed by
    OCCT's BRepMesh at linear ``deflection`` and BRepMesh's usual angular deflection
    (0.5 rad).  Face.tessellate(deflection) then reuses this triangulation; on its own it
    also imposes a fine angle (~0.05 rad: 4x the triangles of a cylinder at 0.05 mm),
    which only the sweep's run time pays for: the conservative offset covers the linear
    deflection whatever the angle."""
    copy = shape.copy()
    try:
        import MeshPart
        MeshPart.meshFromShape(Shape=copy, LinearDeflection=deflection,
                               AngularDeflection=0.5, Relative=False)
    except ImportError:  # no MeshPart: Face.tessellate meshes it (finer)
        pass
    return copy


def face_meshes(shape, deflection):
    """[(face index in ``shape.Faces``, points (n, 3), triangles (t, 3), planar?)] of the
    faces of the solids of ``shape`` tessellated one by one at ``deflection`` (planar
    faces exactly), as :func:`source_mesh` welds them; faces OCCT gives no triangles are
    left out."""
    shape = _meshed_copy(shape, deflection)
    index = {face.hashCode(): i for i, face in enumerate(shape.Faces)}
    out = []
    for solid in shape.Solids:
        for face in solid.Faces:
            points, tris = face.tessellate(deflection)
            if not tris:
                continue
            p = np.array([(q.x, q.y, q.z) for q in points], dtype=np.float64).reshape(-1, 3)
            out.append((index.get(face.hashCode(), -1), p,
                        np.asarray(tris, dtype=np.int64).reshape(-1, 3),
                        type(face.Surface).__name__ == "Plane"))
    return out


def source_mesh(shape, deflection):
    """(vertices (n, 3), triangles (t, 3), curved (t,) bool) of the solids of ``shape``
    (global coordinates as the shape is placed): its faces tessellated one by one at
    ``deflection`` (planar faces exactly, :func:`face_meshes`), welded where corners
    coincide (OCCT meshes a shared edge once, so neighbouring faces share its nodes) and
    then where they differ by a few ulps (each face's copy of those nodes is moved by the
    face's own location: :func:`mfgeom.geometry.mesh.merge_near_vertices`)."""
    from mfgeom import core
    from mfgeom.geometry.mesh import merge_near_vertices
    soup, curved = [], []
    for _index, p, tris, is_plane in face_meshes(shape, deflection):
        soup.append(p[tris].reshape(-1, 9))
        curved.append(np.full(len(tris), not is_plane))
    if not soup:
        raise SweepInputError("the source has no faces to mesh")
    vertices, triangles = core.weld(np.vstack(soup))
    vertices, triangles, kept = merge_near_vertices(vertices, triangles)
    return vertices, triangles, np.concatenate(curved)[kept]


def axis_of(axis_object, sub=""):
    """(point, unit direction) in global coordinates of a straight edge (``sub`` "EdgeN"
    of ``axis_object``), a datum line (PartDesign::Line, a Part object whose shape is one
    straight edge) or an origin axis (App::Line).  The direction runs from the edge's
    start to its end (as parametrised).  SweepInputError if it is not a straight line."""
    import Part
    label = getattr(axis_object, "Label", "?")
    if getattr(axis_object, "TypeId", "") == "App::Line":
        # origin axes have no shape in 0.20: the line runs along their local x axis
        pl = axis_object.getGlobalPlacement()
        d = pl.Rotation.multVec(FreeCAD.Vector(1, 0, 0))
        return _np(pl.Base), _np(d) / d.Length
    # the object's shape at its global placement (a Body's or Part's included), as the
    # source's is (gauss_map.shape_of); Part.getShape(obj) would leave out the container
    try:
        shape = Part.Shape(axis_object.Shape)
        if hasattr(axis_object, "getGlobalPlacement"):
            shape.Placement = axis_object.getGlobalPlacement()
        if sub:
            shape = shape.getElement(sub)
    except Exception as exc:  # noqa: BLE001 - whatever OCCT or FreeCAD says, say it once
        raise SweepInputError(f"axis '{label}{'.' + sub if sub else ''}' has no shape "
                              f"({exc})") from None
    edges = shape.Edges if not shape.isNull() else []
    what = f"'{label}.{sub}'" if sub else f"'{label}'"
    if len(edges) != 1:
        raise SweepInputError(f"the axis {what} must be one straight edge or a datum line, "
                              f"not {len(edges)} edges")
    edge = edges[0]
    if type(edge.Curve).__name__ not in ("Line", "LineSegment"):
        raise SweepInputError(f"the axis {what} is not straight "
                              f"({type(edge.Curve).__name__})")
    a = edge.valueAt(edge.FirstParameter)
    b = edge.valueAt(edge.LastParameter)
    if not math.isfinite(edge.LastParameter - edge.FirstParameter):  # an infinite line
        b = a + edge.Curve.Direction
    d = b - a
    if d.Length <= 1e-12:
        raise SweepInputError(f"the axis {what} has zero length")
    return _np(a), _np(d) / d.Length


def _np(v):
    return np.array([v.x, v.y, v.z], dtype=np.float64)


def _vector(a):
    return FreeCAD.Vector(*[float(c) for c in a])


def check_parameters(point, direction, angle_deg, tolerance, deflection):
    """The numeric inputs checked in one place (the feature's recompute, the make
    function, the task panel before it edits): returns (point, unit direction, angle in
    radians, tolerance, deflection); SweepInputError says what is wrong."""
    point = np.asarray(point, dtype=np.float64)
    direction = np.asarray(direction, dtype=np.float64)
    if not (np.isfinite(point).all() and np.isfinite(direction).all()):
        raise SweepInputError("the axis point and direction must be finite")
    length = float(np.linalg.norm(direction))
    if length <= 1e-12:
        raise SweepInputError("the axis direction is zero: give a direction such as "
                              "(0, 0, 1)")
    if not 0.0 < angle_deg <= 360.0:
        raise SweepInputError(f"the angle must be in (0, 360] degrees, got {angle_deg:g}")
    if not tolerance > 0.0:
        raise SweepInputError(f"the tolerance must be > 0 mm, got {tolerance:g}")
    if not deflection > 0.0:
        raise SweepInputError(f"the deflection must be > 0 mm, got {deflection:g}")
    return point, direction / length, math.radians(angle_deg), tolerance, deflection


def sweep_inputs(obj):
    """Checked inputs of the feature: (shape (global), axis point, unit axis direction,
    angle rad, tolerance mm, deflection mm).  SweepInputError says what is wrong."""
    from mfgeom.app import gauss_map
    src = obj.Source
    if src is None:
        raise SweepInputError("no source: set the Source property to a solid")
    shape = getattr(src, "Shape", None)
    if shape is None or shape.isNull():
        raise SweepInputError(f"'{src.Label}' has no shape: the source must be a solid")
    if not shape.Solids:
        kind = shape.ShapeType
        raise SweepInputError(f"'{src.Label}' is not a solid (a {kind}"
                              f"{', open' if kind in ('Shell', 'Face') else ''}): the "
                              "source must be a closed solid")
    shape = gauss_map.shape_of(src, deep=False)
    if obj.AxisObject is not None:
        axis_object, subs = obj.AxisObject
        point, direction = axis_of(axis_object, subs[0] if subs else "")
        # show the axis used (global); unchanged values do not touch the object
        if (_np(obj.AxisPoint) != point).any():
            obj.AxisPoint = _vector(point)
        if (_np(obj.AxisDirection) != direction).any():
            obj.AxisDirection = _vector(direction)
    else:
        point, direction = _np(obj.AxisPoint), _np(obj.AxisDirection)
    point, direction, angle, tolerance, deflection = check_parameters(
        point, direction, float(obj.Angle.Value), float(obj.Tolerance.Value),
        float(obj.Deflection.Value))
    if obj.AxisReversed:
        direction = -direction
    return shape, point, direction, angle, tolerance, deflection


def mesh_of(vertices, triangles):
    """A FreeCAD Mesh kernel of these triangles (single precision in FreeCAD), read by
    FreeCAD from a binary STL that mfgeom.meshio writes: the sweep gives 10^5 .. 10^6
    triangles, and Mesh.addFacets from Python lists took 29 s for 10^6 where the STL
    round trip takes 2.6 s.  FreeCAD merges the STL's equal corners into vertices."""
    import os
    import tempfile

    import Mesh
    from mfgeom import meshio
    if not len(triangles):
        return Mesh.Mesh()
    fd, path = tempfile.mkstemp(prefix="mfgeom-sweep-", suffix=".stl")
    os.close(fd)
    try:
        meshio.write_mesh(path, vertices, triangles)
        return Mesh.Mesh(path)
    finally:
        os.remove(path)


def solid_of_mesh(vertices, triangles, volume):
    """The Solid representation: a valid Part solid of the triangles (double precision)
    with coplanar neighbours merged into planar faces that share their edges
    (:func:`mfgeom.app.mesh_shapes.solid_of_mesh`); its volume agrees with ``volume``
    (the library's) to 1e-6 relative.  MfgeomError says which check failed."""
    from mfgeom.app import mesh_shapes
    try:
        return mesh_shapes.solid_of_mesh(vertices, triangles, volume)
    except MfgeomError as exc:
        raise MfgeomError(f"{exc}; use the Mesh representation") from None


# ---------------------------------------------------------------------------- feature
class RotationalSweep(FeatureProxy):
    """App proxy: recomputes the swept volume of its Source about the axis."""

    TYPE = TYPE
    VERSION = VERSION
    VIEW_PROVIDER = "mfgeom.gui.sweep_view.ViewProviderRotationalSweep"

    def _set_defaults(self, obj):
        obj.Representation = REPRESENTATIONS
        obj.AxisDirection = FreeCAD.Vector(0, 0, 1)
        obj.Angle = DEFAULT_ANGLE
        obj.Tolerance = DEFAULT_TOLERANCE
        obj.Deflection = DEFAULT_DEFLECTION
        # the result is placed in global coordinates already
        obj.setEditorMode("Placement", 2)

    @staticmethod
    def _add_properties(obj):
        # (type, name, group, tooltip, read-only output?)
        spec = [
            ("App::PropertyLink", "Source", "Sweep", "The solid that turns", False),
            ("App::PropertyLinkSub", "AxisObject", "Sweep",
             "Optional: a straight edge, a datum line or an origin axis; when set it gives "
             "AxisPoint and AxisDirection (global)", False),
            ("App::PropertyVector", "AxisPoint", "Sweep", "A point on the axis (global, mm)",
             False),
            ("App::PropertyVector", "AxisDirection", "Sweep",
             "Axis direction (global); the part turns counter-clockwise seen from its tip",
             False),
            ("App::PropertyBool", "AxisReversed", "Sweep",
             "Turn the other way (about the reversed axis direction)", False),
            ("App::PropertyAngle", "Angle", "Sweep",
             "The part turns by 0 .. Angle, in (0, 360] degrees (360: solid of "
             "revolution)", False),
            ("App::PropertyLength", "Tolerance", "Sweep",
             "The result's boundary lies within this distance of the true swept volume's",
             False),
            ("App::PropertyLength", "Deflection", "Sweep",
             "Curved faces of the source are meshed within this distance and the mesh "
             "pushed out by it (conservative); planar faces are exact", False),
            ("App::PropertyEnumeration", "Representation", "Sweep",
             "Mesh: fast for any size; Solid: a Part solid (coplanar triangles merged), "
             "usable by Part tools", False),
            ("App::PropertyFloat", "Volume", "Result", "Swept volume (mm^3)", True),
            ("App::PropertyFloat", "Area", "Result", "Surface area of the result (mm^2)",
             True),
            ("App::PropertyInteger", "TriangleCount", "Result",
             "Triangles of the result mesh", True),
            ("App::PropertyInteger", "SourceTriangles", "Result",
             "Triangles of the source's mesh", True),
            ("App::PropertyFloat", "SourceOffset", "Result",
             "Largest distance (mm) a source mesh vertex was pushed out to cover the "
             "curved faces (0: all faces planar)", True),
            VERSION_PROPERTY,
        ]
        add_properties(obj, spec)
        add_mesh_property(obj, "The swept volume as a closed triangle mesh (global, single "
                               "precision)")
        for ptype, name, tip in (
                ("App::PropertyVectorList", "ExactVertices",
                 "The swept volume's vertices in double precision (the library's result)"),
                ("App::PropertyFloatList", "ExactTriangles",
                 "The swept volume's triangles: three indices into ExactVertices each")):
            if name not in obj.PropertiesList:
                obj.addProperty(ptype, name, "Result", tip, 8, True)
                obj.setEditorMode(name, 2)

    def _execute(self, obj):
        import Part
        shape, point, direction, angle, tolerance, deflection = sweep_inputs(obj)
        from mfgeom import core
        t0 = time.perf_counter()
        vertices, triangles, curved = source_mesh(shape, deflection)
        vertices, offset = conservative_offset(vertices, triangles, curved, deflection)
        t1 = time.perf_counter()
        result = core.rotational_sweep(vertices, triangles, point, direction, angle,
                                       tolerance, progress=progress.current())
        t2 = time.perf_counter()
        solid = None
        if obj.Representation == "Solid":
            solid = solid_of_mesh(result.vertices, result.triangles, result.volume)
        t3 = time.perf_counter()
        obj.ExactVertices = [tuple(p) for p in result.vertices.tolist()]
        obj.ExactTriangles = result.triangles.ravel().astype(np.float64).tolist()
        obj.Mesh = mesh_of(result.vertices, result.triangles)
        obj.Shape = solid if solid is not None else Part.Shape()
        obj.Placement = FreeCAD.Placement()
        obj.SourceTriangles = len(triangles)
        obj.SourceOffset = float(offset)
        obj.TriangleCount = len(result.triangles)
        obj.Area = result.area
        # the arrays stay on the proxy (onChanged of the Exact* properties drops them)
        self.last_mesh = (result.vertices, result.triangles)
        obj.Volume = result.volume  # last: the view redraws on it
        FreeCAD.Console.PrintLog(
            f"mfgeom: {obj.Label}: {len(triangles)} source triangles (offset "
            f"{offset:.3g} mm), {len(result.triangles)} swept; mesh {1e3 * (t1 - t0):.1f} ms, "
            f"sweep {1e3 * (t2 - t1):.1f} ms, solid {1e3 * (t3 - t2):.1f} ms\n")

    def _restored(self):
        self.last_mesh = None

    def onChanged(self, obj, prop):
        # an undo or a restore brings other arrays: convert them again when asked
        if prop in ("ExactVertices", "ExactTriangles"):
            self.last_mesh = None


# ---------------------------------------------------------------------------- exact mesh
def exact_mesh(obj):
    """(vertices (n, 3) float64, triangles (t, 3) int64) of the sweep ``obj``'s result in
    double precision, or None when it has none (a document of version 1 not recomputed
    yet, an object that is not a sweep) or when the arrays are not its result (their
    triangle count and volume must be the object's).  Converted once: the proxy keeps
    the arrays until the properties change."""
    if "ExactTriangles" not in getattr(obj, "PropertiesList", ()):
        return None
    proxy = getattr(obj, "Proxy", None)
    kept = getattr(proxy, "last_mesh", None)
    if kept is not None:
        return kept
    flat = np.asarray(obj.ExactTriangles, dtype=np.float64)
    if not len(flat) or len(flat) % 3:
        return None
    vertices = np.array([(p.x, p.y, p.z) for p in obj.ExactVertices],
                        dtype=np.float64).reshape(-1, 3)
    triangles = flat.astype(np.int64).reshape(-1, 3)
    if (len(triangles) != obj.TriangleCount or triangles.min() < 0
            or triangles.max() >= len(vertices)):
        return None
    p0, p1, p2 = (vertices[triangles[:, k]] for k in range(3))
    volume = float(np.einsum("ij,ij->", p0, np.cross(p1, p2))) / 6.0
    # the document keeps Volume to 16 digits, and the sum's order differs from the library's
    if abs(volume - obj.Volume) > 1e-9 * max(abs(obj.Volume), 1e-300):
        FreeCAD.Console.PrintLog(f"mfgeom: {obj.Label}: the exact mesh is not this "
                                 "result: not used\n")
        return None
    if proxy is not None:
        proxy.last_mesh = (vertices, triangles)
    return vertices, triangles


# ---------------------------------------------------------------------------- make
def part_defaults(source):
    """(tolerance, deflection, diagonal) for a sweep of ``source`` (a document object
    with a solid Shape): both lengths a thousandth of the diagonal of its bounding box in
    global coordinates, rounded down to 1, 2 or 5 times a power of ten
    (:func:`mfgeom.geometry.sizes.part_default`; docs/sweep.md says why)."""
    from mfgeom.app import gauss_map
    from mfgeom.geometry.sizes import part_default
    diagonal = float(gauss_map.shape_of(source, deep=False).BoundBox.DiagonalLength)
    if not diagonal > 0.0:
        raise SweepInputError(f"'{source.Label}' has no extent")
    step = part_default(diagonal)
    return step, step, diagonal


def _vector3(value, what):
    if isinstance(value, str):
        axes = {"X": (1, 0, 0), "Y": (0, 1, 0), "Z": (0, 0, 1)}
        if value.upper() not in axes:
            raise SweepInputError(f"{what} must be a vector or 'X', 'Y', 'Z', got {value!r}")
        return np.array(axes[value.upper()], dtype=np.float64)
    if hasattr(value, "x") and hasattr(value, "y") and hasattr(value, "z"):
        value = (value.x, value.y, value.z)
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise SweepInputError(f"{what} must be three numbers, got {value!r}") from None
    if arr.shape != (3,) or not np.isfinite(arr).all():
        raise SweepInputError(f"{what} must be three finite numbers, got {value!r}")
    return arr


def _quantity(value, unit, what):
    """A number in ``unit`` ("deg" or "mm") from a number, a Quantity or a string."""
    if isinstance(value, bool):
        raise SweepInputError(f"{what} must be a number, got {value!r}")
    if isinstance(value, str):
        try:
            value = FreeCAD.Units.Quantity(value)
        except ValueError:
            raise SweepInputError(f"{what}: cannot read {value!r}") from None
    if isinstance(value, FreeCAD.Units.Quantity):
        want = FreeCAD.Units.Angle if unit == "deg" else FreeCAD.Units.Length
        if value.Unit == want:
            value = value.getValueAs(unit)
        elif value.Unit == FreeCAD.Units.Unit():
            value = value.Value
        else:
            raise SweepInputError(f"{what} must be in {unit}, got {value.UserString}")
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise SweepInputError(f"{what} must be a number of {unit}, got {value!r}") from None
    if not math.isfinite(value):
        raise SweepInputError(f"{what} must be finite, got {value!r}")
    return value


def make_rotational_sweep(doc: "FreeCAD.Document", source: "FreeCAD.DocumentObject",
                          axis_point: object = (0.0, 0.0, 0.0),
                          axis_dir: object = (0.0, 0.0, 1.0),
                          angle_deg: Quantity = DEFAULT_ANGLE,
                          tolerance: Quantity = None,
                          deflection: Quantity = None,
                          representation: str = "Mesh", axis: object = None,
                          reverse: bool = False,
                          name: str = "RotationalSweep") -> "FreeCAD.DocumentObject":
    """Create the rotational sweep of ``source`` (a document object with a solid Shape)
    in ``doc`` and compute it.  Axis: through ``axis_point`` along ``axis_dir`` (global;
    a vector, a 3-tuple or "X" / "Y" / "Z"), or ``axis`` = an object or ``(obj,
    "EdgeN")`` (a straight edge, a datum line, an origin axis) which then overrides
    them; ``reverse`` turns the other way.  ``angle_deg`` in (0, 360] (a number of
    degrees, an angle Quantity or "90 deg"); ``tolerance`` and ``deflection`` in mm
    (None: a thousandth of the part's size, :func:`part_defaults`; a value given is
    kept as it is); ``representation`` "Mesh" or "Solid".  Inputs are checked before anything is
    created; if the first recompute fails the object is removed again and the error
    (one line) raised.  Returns the new object."""
    if doc is None or not hasattr(doc, "addObject"):
        raise SweepInputError("no document given")
    if (source is None or not hasattr(source, "Shape")
            or getattr(source, "Document", None) is not doc):
        raise SweepInputError("the source must be an object with a Shape in this document")
    if source.Shape.isNull() or not source.Shape.Solids:
        raise SweepInputError(f"'{source.Label}' is not a closed solid")
    if axis is None and (axis_point is None or axis_dir is None):
        raise SweepInputError("give the axis: a point and a direction, or axis=(obj, 'EdgeN')")
    point = _vector3(axis_point if axis_point is not None else (0, 0, 0), "the axis point")
    direction = _vector3(axis_dir if axis_dir is not None else (0, 0, 1), "the axis direction")
    angle = _quantity(angle_deg, "deg", "the angle")
    if tolerance is None or deflection is None:
        scaled_tol, scaled_defl, _ = part_defaults(source)
        tolerance = scaled_tol if tolerance is None else tolerance
        deflection = scaled_defl if deflection is None else deflection
    tol = _quantity(tolerance, "mm", "the tolerance")
    defl = _quantity(deflection, "mm", "the deflection")
    # an axis object gives its own direction (checked below)
    check_parameters(point, direction if axis is None else (0, 0, 1), angle, tol, defl)
    if representation not in REPRESENTATIONS:
        raise SweepInputError(f"representation must be one of {REPRESENTATIONS}, "
                              f"got {representation!r}")
    link = None
    if axis is not None:
        axis_obj, sub = (axis if isinstance(axis, (tuple, list)) else (axis, ""))
        if isinstance(sub, (list, tuple)):
            sub = sub[0] if sub else ""
        if getattr(axis_obj, "Document", None) is not doc:
            raise SweepInputError("the axis must be an object (or an edge of one) in this "
                                  "document")
        axis_of(axis_obj, sub)   # a straight line, or say why not
        link = (axis_obj, [sub] if sub else [])
    values = {"Label": f"Sweep of {source.Label}", "Source": source,
              "AxisPoint": _vector(point), "AxisDirection": _vector(direction)}
    if link is not None:
        values["AxisObject"] = link
    values.update(AxisReversed=bool(reverse), Angle=angle, Tolerance=tol, Deflection=defl,
                  Representation=representation)
    return RotationalSweep.make(doc, name, values, "rotational sweep")
