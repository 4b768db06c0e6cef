# SPDX-License-Identifier: LGPL-2.1-or-later
"""The rotational swept volume of a closed solid (the C family libcore/src/sweep/):
rotational_sweep."""

import ctypes

import numpy as np
from numpy.typing import ArrayLike

from mfgeom.core.arrays import (_as_float, _as_triangles, _as_vector3, _as_vertices, _c_double_p,
                                _c_int64_p, _ptr)
from mfgeom.core.loader import _lib
from mfgeom.core.status import ProgressFn, _c_progress_p, _ProgressCall
from mfgeom.core.mesh import _Mesh, _take_mesh


class _SweepStats(ctypes.Structure):
    """struct mfg_sweep_stats (mfgeom.h)."""
    _fields_ = [("volume", ctypes.c_double), ("area", ctypes.c_double),
                ("bbox", ctypes.c_double * 6)]


_lib.mfg_rotational_sweep.restype = ctypes.c_int
_lib.mfg_rotational_sweep.argtypes = [_c_double_p, ctypes.c_int64, _c_int64_p, ctypes.c_int64,
                                      _c_double_p, _c_double_p, ctypes.c_double,
                                      ctypes.c_double, ctypes.POINTER(ctypes.POINTER(_Mesh)),
                                      ctypes.POINTER(_SweepStats)]
_lib.mfg_rotational_sweep_p.restype = ctypes.c_int
_lib.mfg_rotational_sweep_p.argtypes = _lib.mfg_rotational_sweep.argtypes + [_c_progress_p]


class SweepResult:
    """What :func:`rotational_sweep` returns: the swept volume as a closed, outward
    oriented triangle mesh (``vertices`` (k, 3) float64, ``triangles`` (t, 3) int64) with
    its ``volume``, ``area`` (floats) and ``bbox`` ((2, 3) array: min corner, max corner),
    as the library computed them for that mesh."""

    def __init__(self, vertices, triangles, volume, area, bbox):
        self.vertices = vertices
        self.triangles = triangles
        self.volume = float(volume)
        self.area = float(area)
        self.bbox = np.asarray(bbox, dtype=np.float64).reshape(2, 3)

    def __repr__(self):
        return (f"SweepResult({len(self.vertices)} vertices, {len(self.triangles)} "
                f"triangles, volume={self.volume:.6g}, area={self.area:.6g})")


def rotational_sweep(vertices: ArrayLike, triangles: ArrayLike, axis_point: ArrayLike,
                     axis_direction: ArrayLike, angle: float, tolerance: float,
                     progress: ProgressFn = None) -> SweepResult:
    """The volume swept by the closed solid (``vertices`` (n, 3), ``triangles`` (t, 3),
    counter-clockwise seen from outside) turning about the axis through ``axis_point``
    along ``axis_direction`` (right-handed) by 0 .. ``angle`` radians (0 < angle <= 2 pi;
    within 1e-12 of 2 pi: the solid of revolution), as a :class:`SweepResult` whose
    boundary lies within ``tolerance`` (absolute, > 0) of the true one.

    An open, non-manifold or flipped mesh, a zero axis direction, an angle or tolerance
    out of range and NaN raise MfgError with the library's detail (e.g. "mesh is not
    closed: 3 boundary edges (first: vertices 1-5)").  ``progress``: None or
    ``progress(fraction, stage)`` (see :class:`_ProgressCall`; stages "sweep: setup",
    "sweep: contour", "sweep: strips", "sweep: intersections", "sweep: faces",
    "sweep: boundary", "sweep: output", "sweep: done"); a truthy return raises Cancelled, an exception it raises propagates."""
    xyz = _as_vertices(vertices)
    tri = _as_triangles(triangles)
    point = _as_vector3(axis_point, "axis_point")
    direction = _as_vector3(axis_direction, "axis_direction")
    res = ctypes.POINTER(_Mesh)()
    stats = _SweepStats()
    angle = _as_float(angle, "angle")
    tolerance = _as_float(tolerance, "tolerance")
    prog = _ProgressCall(progress)
    prog.call(_lib.mfg_rotational_sweep_p, _ptr(xyz, ctypes.c_double), len(xyz),
                                           _ptr(tri, ctypes.c_int64), len(tri),
                                           _ptr(point, ctypes.c_double),
                                           _ptr(direction, ctypes.c_double), angle, tolerance,
                                           ctypes.byref(res), ctypes.byref(stats), prog.arg)
    verts, tris = _take_mesh(res)
    return SweepResult(verts, tris, stats.volume, stats.area, stats.bbox[:])
