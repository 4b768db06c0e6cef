# SPDX-License-Identifier: LGPL-2.1-or-later
"""The medial surface of a solid bounded by a closed triangle mesh (the C family
libcore/src/medial/): medial_surface and its sheets, seams and junctions."""

import ctypes
import numbers

import numpy as np
from numpy.typing import ArrayLike

from mfgeom.core.arrays import (_as_float, _as_triangles, _as_vertices, _c_double_p,
                                _c_int32_p, _c_int64_p, _ptr)
from mfgeom.core.loader import _lib
from mfgeom.core.status import MfgError, ProgressFn, _c_progress_p, _ProgressCall


class _Medial(ctypes.Structure):
    """struct mfg_medial (mfgeom.h)."""
    _fields_ = [("nelements", ctypes.c_int64), ("nfaces", ctypes.c_int64),
                ("nedges", ctypes.c_int64), ("nvertices", ctypes.c_int64),
                ("ntriangles", ctypes.c_int64),
                ("element_kinds", _c_int32_p), ("element_convex", _c_int32_p),
                ("face_of_triangle", _c_int64_p), ("face_planes", _c_double_p),
                ("edge_segments", _c_double_p), ("vertex_points", _c_double_p),
                ("nsheets", ctypes.c_int64), ("sheet_elements", _c_int64_p),
                ("sheet_forms", _c_int32_p), ("sheet_vertex_offsets", _c_int64_p),
                ("sheet_triangle_offsets", _c_int64_p), ("sheet_vertices", _c_double_p),
                ("sheet_radii", _c_double_p), ("sheet_triangles", _c_int64_p),
                ("nseams", ctypes.c_int64), ("seam_kinds", _c_int32_p),
                ("seam_point_offsets", _c_int64_p), ("seam_points", _c_double_p),
                ("seam_radii", _c_double_p), ("seam_element_offsets", _c_int64_p),
                ("seam_elements", _c_int64_p), ("seam_ends", _c_int64_p),
                ("njunctions", ctypes.c_int64), ("junction_kinds", _c_int32_p),
                ("junction_points", _c_double_p), ("junction_radii", _c_double_p),
                ("junction_element_offsets", _c_int64_p), ("junction_elements", _c_int64_p),
                ("cells_visited", ctypes.c_int64), ("leaves", ctypes.c_int64),
                ("leaf_size", ctypes.c_double)]


_lib.mfg_medial_surface.restype = ctypes.c_int
_lib.mfg_medial_surface.argtypes = [_c_double_p, ctypes.c_int64, _c_int64_p, ctypes.c_int64,
                                    ctypes.c_double, ctypes.c_uint32, ctypes.c_int32,
                                    ctypes.POINTER(ctypes.POINTER(_Medial))]
_lib.mfg_medial_surface_p.restype = ctypes.c_int
_lib.mfg_medial_surface_p.argtypes = _lib.mfg_medial_surface.argtypes + [_c_progress_p]
_lib.mfg_medial_free.restype = None
_lib.mfg_medial_free.argtypes = [ctypes.POINTER(_Medial)]

MEDIAL_FULL = 1                     # MFG_MEDIAL_FULL
ELEMENT_KINDS = ("vertex", "edge", "face")                 # mfg_element_kind, by value
MEDIAL_KINDS = ("branch", "smooth", "degenerate")          # mfg_medial_kind, by value
BISECTOR_FORMS = (None, "plane-plane parallel", "plane-plane", "plane-line parallel",
                  "plane-line perpendicular", "plane-line oblique", "plane-point",
                  "line-line parallel", "line-line crossing", "line-line skew",
                  "line-point", "point-point")             # forms 1 .. 11, by value


def _copy_array(ptr, count, dtype, width=1):
    """A copy of the library's array ``ptr`` of ``count`` rows of ``width`` values (an
    empty array for count 0, where the pointer may be NULL)."""
    count = int(count)
    if count == 0:
        return np.zeros((0, width) if width > 1 else 0, dtype=dtype)
    if not ptr:
        if count == 1 and width == 1:   # the offsets of no sheets, seams or junctions
            return np.zeros(1, dtype=dtype)
        raise MfgError("internal error", "mfg_medial_surface returned a NULL array")
    arr = np.ctypeslib.as_array(ptr, shape=(count * width,)).astype(dtype, copy=True)
    return arr.reshape(-1, width) if width > 1 else arr


class MedialSheet:
    """A sheet of a medial surface, the points equidistant from two boundary elements:
    a triangle mesh ``vertices`` (k, 3), ``triangles`` (t, 3) (indices into this sheet's
    vertices), ``radii`` (k,) (distance to the boundary at each vertex), ``elements``
    (2,) (the two element ids, ascending) and ``form`` (1 .. 11: the bisector's form,
    :data:`BISECTOR_FORMS`)."""

    def __init__(self, vertices, triangles, radii, elements, form):
        self.vertices, self.triangles, self.radii = vertices, triangles, radii
        self.elements, self.form = elements, int(form)

    def __repr__(self):
        return (f"MedialSheet({len(self.vertices)} vertices, {len(self.triangles)} "
                f"triangles, elements={tuple(int(e) for e in self.elements)}, "
                f"form={BISECTOR_FORMS[self.form] if 0 < self.form < 12 else self.form})")


class MedialSeam:
    """A seam, a curve where three or more elements are equidistant: a polyline
    ``points`` (k, 3) with ``radii`` (k,), ``elements`` (the equidistant element ids,
    ascending), ``kind`` (0 branch, 1 smooth, 2 degenerate: :data:`MEDIAL_KINDS`) and
    ``ends`` (2,): the junction index at the first / last point, or -1."""

    def __init__(self, points, radii, elements, kind, ends):
        self.points, self.radii, self.elements = points, radii, elements
        self.kind, self.ends = int(kind), ends

    def __repr__(self):
        return (f"MedialSeam({len(self.points)} points, elements="
                f"{tuple(int(e) for e in self.elements)}, kind={self.kind}, "
                f"ends={tuple(int(e) for e in self.ends)})")


class MedialSurfaceJunctions:
    """The junctions of a medial surface (centres of maximal balls touching four or more
    elements): ``points`` (j, 3), ``radii`` (j,), ``elements`` (per junction an int64
    array of the touching element ids, ascending) and ``kinds`` (j,) (as
    :attr:`MedialSeam.kind`)."""

    def __init__(self, points, radii, elements, kinds):
        self.points, self.radii, self.elements, self.kinds = points, radii, elements, kinds

    def __len__(self):
        return len(self.radii)

    def __repr__(self):
        return f"MedialSurfaceJunctions({len(self)})"


class MedialSurface:
    """Result of :func:`medial_surface`: ``sheets`` (list of :class:`MedialSheet`),
    ``seams`` (list of :class:`MedialSeam`), ``junctions``
    (:class:`MedialSurfaceJunctions`) and the boundary elements of the merged polyhedron
    that their ``elements`` refer to (ids: faces, then edges, then vertices):
    ``element_kinds`` (n,) (0 vertex, 1 edge, 2 face: :data:`ELEMENT_KINDS`),
    ``element_convex`` (n,) (edges: 1 convex, 0 reflex; others -1), ``face_of_triangle``
    (t,) (the face of each input triangle, -1 for zero area), ``face_planes`` (f, 4)
    (outward unit normal and offset d: n.x = d), ``edge_segments`` (e, 2, 3) (each
    edge's end points), ``vertex_points`` (v, 3); and the cost: ``cells_visited``,
    ``leaves`` (octree cells tested, leaves kept) and ``leaf_size``."""

    def __init__(self, sheets, seams, junctions, element_kinds, element_convex,
                 face_of_triangle, face_planes, edge_segments, vertex_points,
                 cells_visited, leaves, leaf_size):
        self.sheets, self.seams, self.junctions = sheets, seams, junctions
        self.element_kinds, self.element_convex = element_kinds, element_convex
        self.face_of_triangle, self.face_planes = face_of_triangle, face_planes
        self.edge_segments, self.vertex_points = edge_segments, vertex_points
        self.cells_visited, self.leaves = int(cells_visited), int(leaves)
        self.leaf_size = float(leaf_size)

    @property
    def nfaces(self) -> int:
        return len(self.face_planes)

    @property
    def nedges(self) -> int:
        return len(self.edge_segments)

    @property
    def nvertices(self) -> int:
        return len(self.vertex_points)

    def __repr__(self):
        return (f"MedialSurface({len(self.sheets)} sheets, {len(self.seams)} seams, "
                f"{len(self.junctions)} junctions; {self.nfaces} faces, {self.nedges} "
                f"edges, {self.nvertices} vertices)")


def _convert_medial(m):
    """The library's struct mfg_medial as a :class:`MedialSurface` (everything copied)."""
    nel, nf, ne, nv = int(m.nelements), int(m.nfaces), int(m.nedges), int(m.nvertices)
    ns, nc, nj = int(m.nsheets), int(m.nseams), int(m.njunctions)
    kinds = _copy_array(m.element_kinds, nel, np.int32)
    convex = _copy_array(m.element_convex, nel, np.int32)
    fot = _copy_array(m.face_of_triangle, m.ntriangles, np.int64)
    planes = _copy_array(m.face_planes, nf, np.float64, 4)
    segs = _copy_array(m.edge_segments, ne, np.float64, 6).reshape(-1, 2, 3)
    vpts = _copy_array(m.vertex_points, nv, np.float64, 3)

    voff = _copy_array(m.sheet_vertex_offsets, ns + 1, np.int64)
    toff = _copy_array(m.sheet_triangle_offsets, ns + 1, np.int64)
    sel = _copy_array(m.sheet_elements, ns, np.int64, 2)
    forms = _copy_array(m.sheet_forms, ns, np.int32)
    sv = _copy_array(m.sheet_vertices, voff[-1], np.float64, 3)
    sr = _copy_array(m.sheet_radii, voff[-1], np.float64)
    st = _copy_array(m.sheet_triangles, toff[-1], np.int64, 3)
    sheets = [MedialSheet(sv[voff[s]:voff[s + 1]], st[toff[s]:toff[s + 1]],
                          sr[voff[s]:voff[s + 1]], sel[s], forms[s]) for s in range(ns)]

    poff = _copy_array(m.seam_point_offsets, nc + 1, np.int64)
    eoff = _copy_array(m.seam_element_offsets, nc + 1, np.int64)
    cp = _copy_array(m.seam_points, poff[-1], np.float64, 3)
    cr = _copy_array(m.seam_radii, poff[-1], np.float64)
    ce = _copy_array(m.seam_elements, eoff[-1], np.int64)
    ck = _copy_array(m.seam_kinds, nc, np.int32)
    cends = _copy_array(m.seam_ends, nc, np.int64, 2)
    seams = [MedialSeam(cp[poff[c]:poff[c + 1]], cr[poff[c]:poff[c + 1]],
                        ce[eoff[c]:eoff[c + 1]], ck[c], cends[c]) for c in range(nc)]

    jp = _copy_array(m.junction_points, nj, np.float64, 3)
    jr = _copy_array(m.junction_radii, nj, np.float64)
    jk = _copy_array(m.junction_kinds, nj, np.int32)
    joff = _copy_array(m.junction_element_offsets, nj + 1, np.int64)
    je = _copy_array(m.junction_elements, joff[-1], np.int64)
    junctions = MedialSurfaceJunctions(jp, jr, [je[joff[j]:joff[j + 1]] for j in range(nj)],
                                       jk)
    return MedialSurface(sheets, seams, junctions, kinds, convex, fot, planes, segs, vpts,
                         m.cells_visited, m.leaves, m.leaf_size)


def _medial_flags(major_only, threads):
    """The mfg_medial_surface flags of ``major_only``, after checking it and ``threads``
    (TypeError / ValueError as medial_surface documents); shared by the medial entry
    points."""
    if not isinstance(major_only, (bool, np.bool_)):
        raise TypeError(f"major_only must be True or False, got {major_only!r:.40}")
    if isinstance(threads, (bool, np.bool_)) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"threads must be an int, got {threads!r:.40}")
    if not -2**31 <= int(threads) < 2**31:
        raise ValueError(f"threads {int(threads)} does not fit in int32")
    return 0 if major_only else MEDIAL_FULL


def medial_surface(vertices: ArrayLike, triangles: ArrayLike, tolerance: float,
                   major_only: bool = True, threads: int = 0,
                   progress: ProgressFn = None) -> MedialSurface:
    """The medial surface (locus of centres of maximal inscribed balls) of the solid
    bounded by the closed triangle mesh (``vertices`` (n, 3), ``triangles`` (t, 3),
    counter-clockwise seen from outside; adjacent coplanar triangles form one face), as a
    :class:`MedialSurface` whose sheets and seams lie within ``tolerance`` (absolute,
    > 0) of the true ones.  ``major_only`` (default) keeps the sheets between elements
    whose closures are disjoint; False gives the full medial surface (also the sheets
    running out to convex edges and corners).  ``threads``: 0 = every CPU; the result
    does not depend on it.  A curved solid comes in tessellated: the result is the medial
    surface of that polyhedron.

    An open, non-manifold or flipped mesh, NaN, a tolerance not finite and > 0 or not
    below the bounding-box diagonal, and a negative thread count raise MfgError with the
    library's detail; a ``major_only`` that is not a bool and a ``threads`` that is not an
    int raise TypeError.  ``progress`` as for :func:`rotational_sweep` (stages
    "medial: elements", "medial: octree", "medial: sheets", "medial: junctions",
    "medial: assembly", "medial: done"; called on this thread only)."""
    flags = _medial_flags(major_only, threads)
    xyz = _as_vertices(vertices)
    tri = _as_triangles(triangles)
    res = ctypes.POINTER(_Medial)()
    tolerance = _as_float(tolerance, "tolerance")
    prog = _ProgressCall(progress)
    prog.call(_lib.mfg_medial_surface_p, _ptr(xyz, ctypes.c_double), len(xyz),
                                         _ptr(tri, ctypes.c_int64), len(tri), tolerance,
                                         flags, int(threads), ctypes.byref(res), prog.arg)
    try:
        return _convert_medial(res.contents)
    finally:
        _lib.mfg_medial_free(res)


_lib.mfg_wall_thickness.restype = ctypes.c_int
_lib.mfg_wall_thickness.argtypes = [_c_double_p, ctypes.c_int64, _c_int64_p, ctypes.c_int64,
                                    ctypes.c_double, ctypes.c_uint32, ctypes.c_int32,
                                    _c_double_p, ctypes.c_int64, ctypes.c_double,
                                    _c_double_p, _c_double_p, _c_double_p, _c_progress_p]

WALL_ANGLE = 2.0943951023931957     # MFG_WALL_ANGLE: 120 degrees, in radians


class WallThickness:
    """Result of :func:`wall_thickness`, per query point: ``thickness`` (m,) the diameter
    of the point's maximal inscribed ball, ``centres`` (m, 3) that ball's centre, ``gaps``
    (m,) the distance from the point to the point the ball touches (0 up to rounding
    where the ball touches the point itself)."""

    def __init__(self, thickness, centres, gaps):
        self.thickness, self.centres, self.gaps = thickness, centres, gaps

    def __len__(self):
        return len(self.thickness)

    def __repr__(self):
        if not len(self):
            return "WallThickness(0 points)"
        return (f"WallThickness({len(self)} points, thickness "
                f"{self.thickness.min():.6g} .. {self.thickness.max():.6g})")


def wall_thickness(vertices: ArrayLike, triangles: ArrayLike, points: ArrayLike,
                   tolerance: float, min_angle: float = WALL_ANGLE, major_only: bool = True,
                   threads: int = 0, progress: ProgressFn = None) -> WallThickness:
    """Local wall thickness at ``points`` (m, 3) on the boundary of the solid bounded by
    the closed mesh (``vertices``, ``triangles`` as :func:`medial_surface`): the diameter
    of the maximal inscribed ball touching each point, from the medial surface at
    ``tolerance`` (``major_only`` as there).  Balls count as a wall's when two of the
    points they touch are at least ``min_angle`` (radians, in (0, pi]; default 120
    degrees) apart seen from the centre, so convex corners are not thin; a point no wall
    ball touches takes the ball of the nearest point one touches (mfgeom.h,
    mfg_medial_thickness).  Errors as :func:`medial_surface`, plus non-finite points and
    a min_angle out of range (MfgError); a medial surface with no wall ball raises
    MfgError (degenerate).  ``progress``: the medial stages, then "thickness: balls",
    "thickness: points", "thickness: done"."""
    flags = _medial_flags(major_only, threads)
    xyz = _as_vertices(vertices)
    tri = _as_triangles(triangles)
    pts = _as_vertices(points, "points")
    tolerance = _as_float(tolerance, "tolerance")
    min_angle = _as_float(min_angle, "min_angle")
    m = len(pts)
    thickness = np.empty(m, dtype=np.float64)
    centres = np.empty((m, 3), dtype=np.float64)
    gaps = np.empty(m, dtype=np.float64)
    prog = _ProgressCall(progress)
    prog.call(_lib.mfg_wall_thickness, _ptr(xyz, ctypes.c_double), len(xyz),
              _ptr(tri, ctypes.c_int64), len(tri), tolerance,
              flags, int(threads),
              _ptr(pts, ctypes.c_double), m, min_angle,
              _ptr(thickness, ctypes.c_double), _ptr(centres, ctypes.c_double),
              _ptr(gaps, ctypes.c_double), prog.arg)
    return WallThickness(thickness, centres, gaps)
