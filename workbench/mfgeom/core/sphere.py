# SPDX-License-Identifier: LGPL-2.1-or-later
"""Directions on the sphere (the C family libcore/src/sphere/): visibility maps of
normals, maximum / level / minimum intersection of spherical convex sets (Ha 2001), and
the exact ray test of the parting analysis (ray_blocked)."""

import ctypes
from typing import Optional, Sequence, Union

import numpy as np
from numpy.typing import ArrayLike

from mfgeom.core.arrays import (_as_float, _as_float_array, _as_indices, _as_triangles, _as_vector3,
                                _as_vertices, _c_double_p, _c_int64_p, _c_uint8_p, _ptr)
from mfgeom.core.loader import _lib
from mfgeom.core.status import MfgError, ProgressFn, _c_progress_p, _check, _ProgressCall
from mfgeom.names import KIND_CODES, KINDS


class _SPoly(ctypes.Structure):
    _fields_ = [("kind", ctypes.c_int32), ("closed", ctypes.c_int32),
                ("nvertices", ctypes.c_int64), ("vertices", _c_double_p)]


_lib.mfg_visibility_map.restype = ctypes.c_int
_lib.mfg_visibility_map.argtypes = [_c_double_p, ctypes.c_int64, ctypes.c_double,
                                    ctypes.POINTER(ctypes.POINTER(_SPoly))]
_lib.mfg_spoly_free.restype = None
_lib.mfg_spoly_free.argtypes = [ctypes.POINTER(_SPoly)]


class _Regions(ctypes.Structure):
    _fields_ = [("weight", ctypes.c_double), ("nregions", ctypes.c_int64),
                ("kinds", ctypes.POINTER(ctypes.c_int32)),
                ("closed", ctypes.POINTER(ctypes.c_int32)),
                ("vertex_offsets", _c_int64_p), ("vertices", _c_double_p),
                ("cover_offsets", _c_int64_p), ("cover", _c_int64_p),
                ("centres", _c_double_p), ("margins", _c_double_p)]


_REGION_ARGS = [_c_double_p, _c_int64_p, ctypes.POINTER(ctypes.c_int32),
                ctypes.POINTER(ctypes.c_int32), ctypes.c_int64, _c_double_p]
_lib.mfg_max_intersection.restype = ctypes.c_int
_lib.mfg_max_intersection.argtypes = _REGION_ARGS + [ctypes.POINTER(ctypes.POINTER(_Regions))]
_lib.mfg_level_regions.restype = ctypes.c_int
_lib.mfg_level_regions.argtypes = _REGION_ARGS + [ctypes.c_double,
                                                  ctypes.POINTER(ctypes.POINTER(_Regions))]
_lib.mfg_min_intersection.restype = ctypes.c_int
_lib.mfg_min_intersection.argtypes = _REGION_ARGS + [ctypes.POINTER(ctypes.POINTER(_Regions))]
for _name, _extra in (("mfg_max_intersection_p", []),
                      ("mfg_level_regions_p", [ctypes.c_double]),
                      ("mfg_min_intersection_p", [])):
    getattr(_lib, _name).restype = ctypes.c_int
    getattr(_lib, _name).argtypes = (_REGION_ARGS + _extra +
                                     [ctypes.POINTER(ctypes.POINTER(_Regions)), _c_progress_p])
_lib.mfg_regions_free.restype = None
_lib.mfg_regions_free.argtypes = [ctypes.POINTER(_Regions)]


class VisibilityMap:
    """A spherical convex set: ``kind`` ("null", "point", "edge", "polygon"),
    ``vertices`` ((k, 3) unit vectors, counter-clockwise seen from outside for a polygon;
    the arc's points in order for an edge; one or two antipodal directions for a point)
    and ``closed`` (an edge that is a whole great circle).  See mfgeom.h for the rules."""

    def __init__(self, kind: str, vertices: ArrayLike, closed: bool = False) -> None:
        self.kind = kind
        self.vertices = _as_float_array(vertices, "vertices").reshape(-1, 3)
        self.closed = bool(closed)

    def __repr__(self):
        return f"VisibilityMap(kind={self.kind!r}, {len(self.vertices)} vertices)"

    def contains(self, directions: ArrayLike, tol: float = 1e-12) -> np.ndarray:
        """Floating-point membership test of unit directions (m, 3) -> bool array; a
        direction within ``tol`` (radians, roughly) of the set counts as inside."""
        d = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
        v = self.vertices
        if self.kind == "null":
            return np.zeros(len(d), dtype=bool)
        if self.kind == "point":
            return np.any(np.linalg.norm(d[:, None, :] - v[None, :, :], axis=2) <= tol, axis=1)
        if self.kind == "polygon":
            inside = np.ones(len(d), dtype=bool)
            for i in range(len(v)):
                n = np.cross(v[i], v[(i + 1) % len(v)])
                n /= np.linalg.norm(n)
                inside &= d @ n >= -tol
            return inside
        # edge: on the great circle and within the arc's consecutive pieces
        n = np.cross(v[0], v[1])
        n /= np.linalg.norm(n)
        on = np.abs(d @ n) <= tol
        pieces = len(v) if self.closed else len(v) - 1
        within = np.zeros(len(d), dtype=bool)
        for i in range(pieces):
            a, b = v[i], v[(i + 1) % len(v)]
            within |= (np.cross(a, d) @ n >= -tol) & (np.cross(d, b) @ n >= -tol)
        return on & within


def visibility_map(normals: ArrayLike, draft_angle: float = 0.0,
                   negative: bool = False) -> VisibilityMap:
    """Visibility map VM(P) = {d : d.p >= 0 for all p} of unit (or any non-zero)
    normals ``(m, 3)``; ``negative=True`` gives -VM(P).  ``draft_angle`` (radians)
    shrinks it to {d : d.p^ >= sin(draft_angle)} (a conservative inscribed polygon)."""
    p = _as_float_array(normals, "normals")
    if p.ndim != 2 or p.shape[1] != 3:
        raise ValueError(f"normals must have shape (m, 3), got {p.shape}")
    if negative:
        p = np.ascontiguousarray(-p)
    res = ctypes.POINTER(_SPoly)()
    _check(_lib.mfg_visibility_map(_ptr(p, ctypes.c_double), len(p),
                                   _as_float(draft_angle, "draft_angle"), ctypes.byref(res)))
    try:
        sp = res.contents
        n = sp.nvertices
        verts = np.ctypeslib.as_array(sp.vertices, shape=(n * 3,)).copy() if n else np.zeros(0)
        return VisibilityMap(KINDS[sp.kind], verts.reshape(-1, 3), sp.closed)
    finally:
        _lib.mfg_spoly_free(res)


class Intersection:
    """Result of :func:`max_intersection` / :func:`level_regions`.

    ``count``: the covered weight; ``regions``: list of (k, 3) vertex arrays (best
    first); ``kinds``: "polygon" / "edge" / "point" per region ("face" for
    :func:`min_intersection`: a face of the arrangement, no vertices); ``covers``: per region,
    the indices of the input maps covering it; ``centres`` (r, 3) and ``margins`` (r,):
    the representative direction of each region and how far (radians) it may move and
    stay inside; ``direction`` and ``margin``: those of the best region; ``closed``: per
    region, True for an edge that is a whole great circle."""

    def __init__(self, count, regions, kinds, covers, centres, margins, closed=None):
        self.count = count
        self.closed = closed if closed is not None else [False] * len(regions)
        self.regions = regions
        self.kinds = kinds
        self.covers = covers
        self.centres = centres
        self.margins = margins
        self.direction = centres[0] if len(centres) else None
        self.margin = float(margins[0]) if len(margins) else 0.0

    def __repr__(self):
        return (f"Intersection(count={self.count}, {len(self.regions)} regions, "
                f"direction={self.direction}, margin={self.margin:.6g})")


# A spherical convex set as the intersection functions take it.
Maps = Union[VisibilityMap, ArrayLike]


def _flatten_maps(maps, weights):
    verts, offsets, kinds, closed = [], [0], [], []
    for k, m in enumerate(maps):
        if isinstance(m, VisibilityMap):
            v, kind, cl = m.vertices, m.kind, m.closed
        else:
            v, kind, cl = _as_float_array(m, f"map {k}"), "polygon", False
            if v.ndim != 2 or v.shape[1] != 3:
                raise ValueError(f"map {k} must be a VisibilityMap or a (k, 3) array")
            if len(v) == 0:
                kind = "null"
            else:  # a bare array holds directions of any length; the library takes unit
                # vectors (within 1e-6): scale the others, leave unit ones bit for bit
                length = np.linalg.norm(v, axis=1)
                if not np.all(length > 0):
                    raise ValueError(f"map {k} has a zero vertex")
                far = np.abs(length - 1.0) > 1e-6
                v = np.where(far[:, None], v / length[:, None], v)
        if kind not in KIND_CODES:
            raise ValueError(f"map {k} has unknown kind {kind!r}")
        verts.append(_as_float_array(v, f"map {k}").reshape(-1, 3))
        offsets.append(offsets[-1] + len(verts[-1]))
        kinds.append(KIND_CODES[kind])
        closed.append(1 if cl else 0)
    if not verts:
        raise MfgError("degenerate input", "no maps given")
    xyz = np.ascontiguousarray(np.concatenate(verts), dtype=np.float64)
    w = None
    if weights is not None:
        w = _as_float_array(weights, "weights")
        if w.shape != (len(kinds),):
            raise ValueError(f"weights must have shape ({len(kinds)},), got {w.shape}")
    return (xyz, np.asarray(offsets, dtype=np.int64), np.asarray(kinds, dtype=np.int32),
            np.asarray(closed, dtype=np.int32), w)


def _call_regions(fn, maps, weights, *extra, progress=None):
    xyz, off, kinds, closed, w = _flatten_maps(maps, weights)
    res = ctypes.POINTER(_Regions)()
    prog = _ProgressCall(progress)
    prog.call(fn, _ptr(xyz, ctypes.c_double), _ptr(off, ctypes.c_int64),
                  _ptr(kinds, ctypes.c_int32), _ptr(closed, ctypes.c_int32), len(kinds),
                  _ptr(w, ctypes.c_double) if w is not None else None, *extra,
                  ctypes.byref(res), prog.arg)
    try:
        r = res.contents
        n = r.nregions
        voff = np.ctypeslib.as_array(r.vertex_offsets, shape=(n + 1,)).copy()
        coff = np.ctypeslib.as_array(r.cover_offsets, shape=(n + 1,)).copy()
        verts = (np.ctypeslib.as_array(r.vertices, shape=(int(voff[-1]) * 3,)).reshape(-1, 3).copy()
                 if voff[-1] else np.zeros((0, 3)))
        cover = (np.ctypeslib.as_array(r.cover, shape=(int(coff[-1]),)).copy()
                 if coff[-1] else np.zeros(0, dtype=np.int64))
        kinds_out = [KINDS[int(r.kinds[i])] for i in range(n)]
        closed_out = [bool(r.closed[i]) for i in range(n)]
        centres = (np.ctypeslib.as_array(r.centres, shape=(n * 3,)).reshape(-1, 3).copy()
                   if n else np.zeros((0, 3)))
        margins = np.ctypeslib.as_array(r.margins, shape=(n,)).copy() if n else np.zeros(0)
        weight = float(r.weight)
    finally:
        _lib.mfg_regions_free(res)
    regions = [verts[voff[i]:voff[i + 1]] for i in range(n)]
    covers = [cover[coff[i]:coff[i + 1]] for i in range(n)]
    count = int(weight) if weights is None and weight == int(weight) else weight
    return Intersection(count, regions, kinds_out, covers, centres, margins, closed_out)


def max_intersection(maps: Sequence[Maps], weights: Optional[ArrayLike] = None,
                     progress: ProgressFn = None) -> Intersection:
    """All regions of the sphere covered by the greatest total weight of ``maps``
    (VisibilityMap objects or (k, 3) arrays of counter-clockwise convex polygons).
    ``progress``: see :class:`_ProgressCall` (stages "maxisect: sets", "maxisect: search",
    "maxisect: regions", "maxisect: done"; a cancel raises Cancelled)."""
    return _call_regions(_lib.mfg_max_intersection_p, maps, weights, progress=progress)


def level_regions(maps: Sequence[Maps], level: float, weights: Optional[ArrayLike] = None,
                  progress: ProgressFn = None) -> Intersection:
    """Every locally maximal region whose covered weight is at least ``level``
    (``progress`` as for :func:`max_intersection`)."""
    return _call_regions(_lib.mfg_level_regions_p, maps, weights,
                         ctypes.c_double(_as_float(level, "level")), progress=progress)


def min_intersection(maps: Sequence[Maps], weights: Optional[ArrayLike] = None,
                     progress: ProgressFn = None) -> Intersection:
    """The least covered weight over the sphere; per least-covered face its cover set
    and a direction inside it (kind "face"; ``regions`` are empty arrays: faces are not
    convex, their shape is not computed).  ``progress`` as for :func:`max_intersection`."""
    return _call_regions(_lib.mfg_min_intersection_p, maps, weights, progress=progress)


# ---- demouldability by rays (the parting analysis's exact check) ----------------------

RAY_BLOCKED_POS = 1   # the ray along +d crosses the interior of a triangle
RAY_BLOCKED_NEG = 2   # the ray along -d likewise
RAY_GRAZES_POS = 4    # the ray along +d passes exactly through an edge or vertex only
RAY_GRAZES_NEG = 8    # the ray along -d likewise

_lib.mfg_ray_blocked.restype = ctypes.c_int
_lib.mfg_ray_blocked.argtypes = [_c_double_p, ctypes.c_int64, _c_int64_p, ctypes.c_int64,
                                 _c_double_p, _c_int64_p, ctypes.c_int64, _c_double_p,
                                 _c_uint8_p]
_lib.mfg_ray_blocked_p.restype = ctypes.c_int
_lib.mfg_ray_blocked_p.argtypes = _lib.mfg_ray_blocked.argtypes + [_c_progress_p]


def ray_blocked(vertices: ArrayLike, triangles: ArrayLike, points: ArrayLike,
                own_triangle: Optional[ArrayLike], direction: ArrayLike,
                progress: ProgressFn = None) -> np.ndarray:
    """For each point (``points`` (m, 3)), whether the open rays p + s d and p - s d
    (s > 0, ``direction`` d non-zero) cross the triangle mesh (``vertices`` (n, 3),
    ``triangles`` (t, 3); any mesh, closed or not), decided exactly (mfg_ray_blocked):
    a uint8 array (m,) of the bits RAY_BLOCKED_POS / RAY_BLOCKED_NEG (the ray crosses a
    triangle's interior) and RAY_GRAZES_POS / RAY_GRAZES_NEG (it passes exactly through
    an edge or vertex only: not counted as blocked).  Triangles parallel to d (walls the
    ray slides along) and crossings at s = 0 do not count.  ``own_triangle`` (m,) gives
    the triangle each point was sampled on (ignored for that point; -1 for none), or
    None.  Bad counts, indices, coordinates or a zero direction raise MfgError.
    ``progress`` as for :func:`rotational_sweep` (stages "rays: index", "rays: queries",
    "rays: done")."""
    xyz = _as_vertices(vertices)
    tri = _as_triangles(triangles)
    pts = _as_vertices(points, "points")
    d = _as_vector3(direction, "direction")
    own = None
    if own_triangle is not None:
        own = _as_indices(own_triangle, "own_triangle")
        if len(own) != len(pts):
            raise ValueError(f"own_triangle has {len(own)} entries for {len(pts)} points")
    out = np.zeros(len(pts), dtype=np.uint8)
    prog = _ProgressCall(progress)
    prog.call(_lib.mfg_ray_blocked_p, _ptr(xyz, ctypes.c_double), len(xyz),
                                      _ptr(tri, ctypes.c_int64), len(tri),
                                      _ptr(pts, ctypes.c_double),
                                      None if own is None else _ptr(own, ctypes.c_int64),
                                      len(pts), _ptr(d, ctypes.c_double),
                                      _ptr(out, ctypes.c_uint8), prog.arg)
    return out
