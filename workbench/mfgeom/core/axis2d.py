# SPDX-License-Identifier: LGPL-2.1-or-later
"""The medial axis of a planar face (the C family libcore/src/axis2d/): medial_axis."""

import ctypes

import numpy as np
from numpy.typing import ArrayLike

from mfgeom.core.arrays import _as_float, _c_double_p, _c_int64_p, _flatten_rings, _ptr
from mfgeom.core.loader import _lib
from mfgeom.core.status import ProgressFn, _c_progress_p, _ProgressCall


class _MedialAxis(ctypes.Structure):
    _fields_ = [("nbranches", ctypes.c_int64), ("branch_offsets", _c_int64_p),
                ("npoints", ctypes.c_int64), ("points", _c_double_p), ("radii", _c_double_p),
                ("branch_ends", _c_int64_p), ("njunctions", ctypes.c_int64),
                ("junction_points", _c_double_p), ("junction_radii", _c_double_p),
                ("junction_degree", _c_int64_p), ("junction_offsets", _c_int64_p),
                ("junction_elements", _c_int64_p)]


_lib.mfg_medial_axis.restype = ctypes.c_int
_lib.mfg_medial_axis.argtypes = [_c_double_p, _c_int64_p, ctypes.c_int64, ctypes.c_double,
                                 ctypes.POINTER(ctypes.POINTER(_MedialAxis))]
_lib.mfg_medial_axis_p.restype = ctypes.c_int
_lib.mfg_medial_axis_p.argtypes = _lib.mfg_medial_axis.argtypes + [_c_progress_p]
_lib.mfg_medial_axis_free.restype = None
_lib.mfg_medial_axis_free.argtypes = [ctypes.POINTER(_MedialAxis)]


class MedialBranch:
    """A branch of a medial axis: ``points`` (k, 2), ``radii`` (k,) (distance to the
    boundary at each sample), ``ends`` (2,): the junction index at the first / last
    sample, -1 for a leaf (a convex corner, radius 0)."""

    def __init__(self, points, radii, ends):
        self.points, self.radii, self.ends = points, radii, ends

    def __repr__(self):
        return f"MedialBranch({len(self.points)} points, ends={tuple(self.ends)})"


class MedialJunctions:
    """The junctions of a medial axis: ``points`` (j, 2), ``radii`` (j,), ``degrees`` (j,)
    (branches leaving each), ``elements``: per junction an int64 array of the boundary
    elements its disc touches (edge e -> e, starting at vertex e of the flattened rings;
    reflex vertex k -> -1 - k)."""

    def __init__(self, points, radii, degrees, elements):
        self.points, self.radii, self.degrees, self.elements = points, radii, degrees, elements

    def __len__(self):
        return len(self.radii)


class MedialAxis:
    """Result of :func:`medial_axis`: ``branches`` (list of :class:`MedialBranch`) and
    ``junctions`` (:class:`MedialJunctions`)."""

    def __init__(self, branches, junctions):
        self.branches, self.junctions = branches, junctions

    def __repr__(self):
        return f"MedialAxis({len(self.branches)} branches, {len(self.junctions)} junctions)"


def medial_axis(rings: ArrayLike, tolerance: float, progress: ProgressFn = None) -> MedialAxis:
    """The medial axis of the face bounded by ``rings`` (outer boundary and holes, as
    :func:`classify_points`; a single (k, 2) array is one ring), sampled so that samples
    and linearly interpolated radii are within ``tolerance`` (absolute, > 0) of the true
    axis and clearance.  Junctions joined by a branch shorter than ``tolerance`` are one
    junction; junctions and branches come in the canonical order of mfgeom.h (junctions by
    (x, y), a branch from its lower junction, leaves last), independent of the rings'
    start vertices, orientation and order.  Crossing or touching rings, NaN, rings of
    fewer than 3 distinct vertices and a tolerance <= 0 raise MfgError with the library's
    detail.  ``progress`` as for :func:`rotational_sweep` (stages "axis: setup",
    "axis: branches", "axis: output", "axis: done")."""
    xy, offsets = _flatten_rings(rings)
    res = ctypes.POINTER(_MedialAxis)()
    tolerance = _as_float(tolerance, "tolerance")
    prog = _ProgressCall(progress)
    prog.call(_lib.mfg_medial_axis_p, _ptr(xy, ctypes.c_double), _ptr(offsets, ctypes.c_int64),
                                      len(offsets) - 1, tolerance, ctypes.byref(res), prog.arg)
    try:
        a = res.contents
        nb, npt, nj = int(a.nbranches), int(a.npoints), int(a.njunctions)
        boff = np.ctypeslib.as_array(a.branch_offsets, shape=(nb + 1,)).copy()
        pts = (np.ctypeslib.as_array(a.points, shape=(2 * npt,)).reshape(-1, 2).copy()
               if npt else np.zeros((0, 2)))
        rad = np.ctypeslib.as_array(a.radii, shape=(npt,)).copy() if npt else np.zeros(0)
        ends = (np.ctypeslib.as_array(a.branch_ends, shape=(2 * nb,)).reshape(-1, 2).copy()
                if nb else np.zeros((0, 2), dtype=np.int64))
        jp = (np.ctypeslib.as_array(a.junction_points, shape=(2 * nj,)).reshape(-1, 2).copy()
              if nj else np.zeros((0, 2)))
        jr = np.ctypeslib.as_array(a.junction_radii, shape=(nj,)).copy() if nj else np.zeros(0)
        jd = (np.ctypeslib.as_array(a.junction_degree, shape=(nj,)).copy()
              if nj else np.zeros(0, dtype=np.int64))
        joff = np.ctypeslib.as_array(a.junction_offsets, shape=(nj + 1,)).copy()
        jel = (np.ctypeslib.as_array(a.junction_elements, shape=(int(joff[-1]),)).copy()
               if joff[-1] else np.zeros(0, dtype=np.int64))
    finally:
        _lib.mfg_medial_axis_free(res)
    branches = [MedialBranch(pts[boff[b]:boff[b + 1]], rad[boff[b]:boff[b + 1]], ends[b])
                for b in range(nb)]
    junctions = MedialJunctions(jp, jr, jd, [jel[joff[j]:joff[j + 1]] for j in range(nj)])
    return MedialAxis(branches, junctions)
