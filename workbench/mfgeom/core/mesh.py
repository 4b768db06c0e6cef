# SPDX-License-Identifier: LGPL-2.1-or-later
"""Closed triangle meshes, the input of the rotational sweep and the medial surface (the
C family libcore/src/mesh/): mesh_check and weld."""

import ctypes
from typing import Tuple

import numpy as np
from numpy.typing import ArrayLike

from mfgeom.core.arrays import (_as_float_array, _as_triangles, _as_vertices, _c_double_p,
                                _c_int64_p, _ptr)
from mfgeom.core.loader import _lib
from mfgeom.core.status import _check


_MESH_COUNTS = ("nvertices", "ntriangles", "boundary_edges", "nonmanifold_edges",
                "inconsistent_edges", "nonmanifold_vertices", "degenerate_triangles",
                "unused_vertices", "components")


class _MeshReport(ctypes.Structure):
    """struct mfg_mesh_report (mfgeom.h)."""
    _fields_ = ([(name, ctypes.c_int64) for name in _MESH_COUNTS] +
                [("volume", ctypes.c_double), ("area", ctypes.c_double),
                 ("bbox", ctypes.c_double * 6)])


class _Mesh(ctypes.Structure):
    _fields_ = [("nvertices", ctypes.c_int64), ("ntriangles", ctypes.c_int64),
                ("vertices", _c_double_p), ("triangles", _c_int64_p)]


_MESH_ARGS = [_c_double_p, ctypes.c_int64, _c_int64_p, ctypes.c_int64,
              ctypes.POINTER(_MeshReport)]
_lib.mfg_mesh_check.restype = ctypes.c_int
_lib.mfg_mesh_check.argtypes = _MESH_ARGS
_lib.mfg_mesh_check_closed.restype = ctypes.c_int
_lib.mfg_mesh_check_closed.argtypes = _MESH_ARGS
_lib.mfg_mesh_weld.restype = ctypes.c_int
_lib.mfg_mesh_weld.argtypes = [_c_double_p, ctypes.c_int64, ctypes.POINTER(ctypes.POINTER(_Mesh))]
_lib.mfg_mesh_free.restype = None
_lib.mfg_mesh_free.argtypes = [ctypes.POINTER(_Mesh)]


def _take_mesh(res) -> Tuple[np.ndarray, np.ndarray]:
    """Copies of the vertices (n, 3) and triangles (t, 3) of the mfg_mesh result ``res``
    (a POINTER(_Mesh) the library filled), which is freed here, also on error."""
    try:
        m = res.contents
        nv, nt = int(m.nvertices), int(m.ntriangles)
        verts = (np.ctypeslib.as_array(m.vertices, shape=(3 * nv,)).reshape(-1, 3).copy()
                 if nv else np.zeros((0, 3)))
        tris = (np.ctypeslib.as_array(m.triangles, shape=(3 * nt,)).reshape(-1, 3).copy()
                if nt else np.zeros((0, 3), dtype=np.int64))
    finally:
        _lib.mfg_mesh_free(res)
    return verts, tris


class MeshReport:
    """What :func:`mesh_check` found: the counts of mfgeom.h's mfg_mesh_report as int
    attributes (``boundary_edges``, ``nonmanifold_edges``, ``inconsistent_edges``,
    ``nonmanifold_vertices``, ``degenerate_triangles``, ``unused_vertices``,
    ``components``, ``nvertices``, ``ntriangles``), ``volume`` and ``area`` (floats) and
    ``bbox`` ((2, 3) array: min corner, max corner)."""

    def __init__(self, raw):
        for name in _MESH_COUNTS:
            setattr(self, name, int(getattr(raw, name)))
        self.volume = float(raw.volume)
        self.area = float(raw.area)
        self.bbox = np.array(raw.bbox[:], dtype=np.float64).reshape(2, 3)

    def as_dict(self) -> dict:
        d = {name: getattr(self, name) for name in _MESH_COUNTS}
        d.update(volume=self.volume, area=self.area, bbox=self.bbox.tolist())
        return d

    def __repr__(self):
        return f"MeshReport({self.as_dict()})"


def mesh_check(vertices: ArrayLike, triangles: ArrayLike,
               require_closed: bool = False) -> MeshReport:
    """Counts, volume, area and box of the triangle mesh (``vertices`` (n, 3),
    ``triangles`` (t, 3) vertex indices, counter-clockwise seen from outside) as a
    :class:`MeshReport`.  With ``require_closed`` the mesh must bound a solid (closed,
    consistently and outward oriented 2-manifold, positive volume; mfg_mesh_check_closed)
    or MfgError says what is wrong first, e.g. "mesh is not closed: 12 boundary edges
    (first: vertices 3-7)".  Bad counts, indices or coordinates always raise MfgError."""
    xyz = _as_vertices(vertices)
    tri = _as_triangles(triangles)
    raw = _MeshReport()
    fn = _lib.mfg_mesh_check_closed if require_closed else _lib.mfg_mesh_check
    _check(fn(_ptr(xyz, ctypes.c_double), len(xyz), _ptr(tri, ctypes.c_int64), len(tri),
              ctypes.byref(raw)))
    return MeshReport(raw)


def weld(soup: ArrayLike) -> Tuple[np.ndarray, np.ndarray]:
    """A triangle soup (as read from STL: (t, 3, 3), (t, 9) or (3t, 3) corner
    coordinates) as an indexed mesh ``(vertices (k, 3) float64, triangles (t, 3)
    int64)``: corners with exactly the same coordinates become one vertex (nothing
    else is merged), numbered in order of first appearance; triangles keep their order."""
    arr = _as_float_array(soup, "soup")
    if arr.size == 0:
        arr = arr.reshape(0, 9)
    if arr.ndim == 3 and arr.shape[1:] == (3, 3):
        arr = arr.reshape(-1, 9)
    elif arr.ndim == 2 and arr.shape[1] == 3 and len(arr) % 3 == 0:
        arr = arr.reshape(-1, 9)
    if arr.ndim != 2 or arr.shape[1] != 9:
        raise ValueError(f"soup must have shape (t, 3, 3), (t, 9) or (3t, 3), got "
                         f"{np.shape(soup)}")
    arr = np.ascontiguousarray(arr)
    res = ctypes.POINTER(_Mesh)()
    _check(_lib.mfg_mesh_weld(_ptr(arr, ctypes.c_double), len(arr), ctypes.byref(res)))
    return _take_mesh(res)
