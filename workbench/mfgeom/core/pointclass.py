# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tolerance-based point classification against a planar region (Chung & Park; the C
family libcore/src/pointclass/): classify_points and the prepared Region."""

import ctypes

import numpy as np
from numpy.typing import ArrayLike

from mfgeom.core.arrays import (_as_float, _as_points, _c_double_p, _c_int64_p, _c_uint8_p,
                                _flatten_rings, _ptr)
from mfgeom.core.loader import _lib
from mfgeom.core.status import MfgError, _check


_lib.mfg_classify_points.restype = ctypes.c_int
_lib.mfg_classify_points.argtypes = [_c_double_p, _c_int64_p, ctypes.c_int64, _c_double_p,
                                     ctypes.c_int64, ctypes.c_double, _c_uint8_p]
_lib.mfg_region_new.restype = ctypes.c_int
_lib.mfg_region_new.argtypes = [_c_double_p, _c_int64_p, ctypes.c_int64, ctypes.c_double,
                                ctypes.POINTER(ctypes.c_void_p)]
_lib.mfg_region_classify.restype = ctypes.c_int
_lib.mfg_region_classify.argtypes = [ctypes.c_void_p, _c_double_p, ctypes.c_int64, _c_uint8_p]


class _RegionInfo(ctypes.Structure):
    """struct mfg_region_info (mfgeom.h): the shape of a prepared region's index."""
    _fields_ = [(name, ctypes.c_int64) for name in (
        "columns", "rows", "edge_cells", "grid_entries", "edge_entries", "list_entries",
        "ordered_entries", "nodes", "list_leaves", "ordered_leaves", "max_depth", "max_list",
        "bytes")]


_lib.mfg_region_info.restype = ctypes.c_int
_lib.mfg_region_info.argtypes = [ctypes.c_void_p, ctypes.POINTER(_RegionInfo)]
_lib.mfg_region_free.restype = None
_lib.mfg_region_free.argtypes = [ctypes.c_void_p]


def classify_points(rings: ArrayLike, points: ArrayLike, tol: float) -> np.ndarray:
    """Classify points against the region bounded by ``rings`` (even-odd rule).

    Returns a uint8 array of OUT (0), IN (1) or ON (2), one per point; ON means the
    point's distance to the boundary is <= tol, decided exactly.
    """
    xy, offsets = _flatten_rings(rings)
    pts = _as_points(points)
    out = np.empty(len(pts), dtype=np.uint8)
    _check(_lib.mfg_classify_points(_ptr(xy, ctypes.c_double), _ptr(offsets, ctypes.c_int64),
                                    len(offsets) - 1, _ptr(pts, ctypes.c_double), len(pts),
                                    _as_float(tol, "tol"), _ptr(out, ctypes.c_uint8)))
    return out


class Region:
    """A prepared region: build once (grid index), classify many points.

    Gives answers identical to :func:`classify_points`.  The C object is freed when
    the Region is garbage-collected or :meth:`close` is called.
    """

    def __init__(self, rings: ArrayLike, tol: float) -> None:
        xy, offsets = _flatten_rings(rings)
        handle = ctypes.c_void_p()
        _check(_lib.mfg_region_new(_ptr(xy, ctypes.c_double), _ptr(offsets, ctypes.c_int64),
                                   len(offsets) - 1, _as_float(tol, "tol"),
                                   ctypes.byref(handle)))
        self._handle = handle
        self.tol = float(tol)
        self._free = _lib.mfg_region_free  # kept for use during interpreter shutdown

    def classify(self, points: ArrayLike) -> np.ndarray:
        if not self._handle:
            raise MfgError("invalid argument", "Region is closed")
        pts = _as_points(points)
        out = np.empty(len(pts), dtype=np.uint8)
        _check(_lib.mfg_region_classify(self._handle, _ptr(pts, ctypes.c_double), len(pts),
                                        _ptr(out, ctypes.c_uint8)))
        return out

    def stats(self) -> dict:
        """Index statistics (struct mfg_region_info) as a dict: columns, rows (the grid),
        edge_cells, grid_entries, edge_entries, list_entries, ordered_entries, nodes,
        list_leaves, ordered_leaves, max_depth, max_list, bytes."""
        if not self._handle:
            raise MfgError("invalid argument", "Region is closed")
        info = _RegionInfo()
        _check(_lib.mfg_region_info(self._handle, ctypes.byref(info)))
        return {name: int(getattr(info, name)) for name, _ in _RegionInfo._fields_}

    def close(self) -> None:
        if self._handle:
            self._free(self._handle)
            self._handle = ctypes.c_void_p()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown: nothing sensible left to do
            pass
