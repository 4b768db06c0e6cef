# SPDX-License-Identifier: LGPL-2.1-or-later
"""Input conversion and validation shared by every wrapper: array-likes to C-contiguous
float64 / int64 arrays of the right shape, with TypeError / ValueError for what numpy
would silently convert; and the ctypes pointer types and casts."""

import ctypes
import numbers

import numpy as np

_c_double_p = ctypes.POINTER(ctypes.c_double)
_c_int64_p = ctypes.POINTER(ctypes.c_int64)
_c_uint8_p = ctypes.POINTER(ctypes.c_uint8)
_c_int32_p = ctypes.POINTER(ctypes.c_int32)


def _ptr(array, ctype):
    return array.ctypes.data_as(ctypes.POINTER(ctype))


def _as_float_array(value, what):
    """``value``, an array-like of real numbers, as a C-contiguous float64 ndarray: the
    one conversion every public function applies to its numeric input.

    numpy alone would turn strings into numbers, booleans into 0/1, drop the imaginary
    part of complex arrays and None into NaN: those raise TypeError here.  A number no
    double can hold (an int beyond ~1.8e308, a long double overflowing) raises
    ValueError, as does a ragged nesting.  Arrays already float64 and contiguous are not
    copied."""
    try:
        arr = np.asarray(value)
    except ValueError as exc:                 # ragged nesting
        raise ValueError(f"{what}: {exc}") from None
    kind = arr.dtype.kind
    if kind == "O":                           # Python ints beyond int64, Fractions, None, ...
        out = np.empty(arr.shape, dtype=np.float64)
        for index, x in np.ndenumerate(arr):
            if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Real):
                raise TypeError(f"{what} must be real numbers, got {type(x).__name__} "
                                f"{x!r:.40}")
            try:
                out[index] = float(x)
            except OverflowError:
                raise ValueError(f"{what}: {x!r:.40} is too large for a double") from None
        return out
    if kind in "iu":
        return np.asarray(arr, dtype=np.float64, order="C")
    if kind == "f":
        if arr.dtype.itemsize > 8 and np.count_nonzero(
                np.isfinite(arr) & (np.abs(arr) > np.finfo(np.float64).max)):
            raise ValueError(f"{what}: a value is too large for a double")
        return np.asarray(arr, dtype=np.float64, order="C")
    names = {"b": "booleans", "c": "complex numbers", "U": "strings", "S": "bytes"}
    raise TypeError(f"{what} must be real numbers, got {names.get(kind, arr.dtype.name)}")


def _as_float(value, what):
    """A real number (int, float, numpy scalar) as a Python float; TypeError for
    strings, booleans, complex numbers and arrays, ValueError if too large."""
    arr = _as_float_array(value, what)
    if arr.ndim != 0:
        raise TypeError(f"{what} must be a number, got an array of shape {arr.shape}")
    return float(arr)


def _as_points(points, what="points"):
    arr = _as_float_array(points, what)
    if arr.ndim == 1 and arr.size == 0:
        arr = arr.reshape(0, 2)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"{what} must have shape (m, 2), got {arr.shape}")
    return arr


def _flatten_rings(rings):
    """Rings (sequence of (k, 2) arrays) -> flat xy array and int64 offsets."""
    if isinstance(rings, np.ndarray) and rings.ndim == 2:
        rings = [rings]  # a single ring passed directly
    try:
        rings = list(rings)
    except TypeError:
        raise TypeError("rings must be a sequence of (k, 2) arrays") from None
    arrays = [_as_points(r, "each ring") for r in rings]
    offsets = np.zeros(len(arrays) + 1, dtype=np.int64)
    if arrays:
        offsets[1:] = np.cumsum([len(a) for a in arrays])
        xy = np.ascontiguousarray(np.concatenate(arrays), dtype=np.float64)
    else:
        xy = np.zeros((0, 2), dtype=np.float64)
    return xy, offsets


def _as_vertices(vertices, what="vertices"):
    arr = _as_float_array(vertices, what)
    if arr.size == 0:
        arr = arr.reshape(0, 3)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"{what} must have shape (n, 3), got {arr.shape}")
    return arr


def _as_triangles(triangles):
    """Triangle vertex indices as a C-contiguous (t, 3) int64 array.  Integers only:
    floats, booleans and strings raise TypeError (an index rounded from 2.7 would be a
    silent mix-up); an integer beyond int64 raises ValueError.  Range checks against the
    vertices are the library's."""
    try:
        arr = np.asarray(triangles)
    except ValueError as exc:                 # ragged nesting
        raise ValueError(f"triangles: {exc}") from None
    if arr.size == 0:
        arr = np.zeros((0, 3), dtype=np.int64) if arr.ndim < 2 else arr.astype(np.int64)
    kind = arr.dtype.kind
    if kind == "O":
        out = np.empty(arr.shape, dtype=np.int64)
        for index, x in np.ndenumerate(arr):
            if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Integral):
                raise TypeError(f"triangles must be integers, got {type(x).__name__} "
                                f"{x!r:.40}")
            if not -2**63 <= int(x) < 2**63:
                raise ValueError(f"triangles: index {x!r:.40} does not fit in int64")
            out[index] = int(x)
        arr = out
    elif kind == "u":
        if arr.size and arr.dtype.itemsize >= 8 and int(arr.max()) >= 2**63:
            raise ValueError("triangles: an index does not fit in int64")
    elif kind != "i":
        raise TypeError(f"triangles must be integers, got {arr.dtype.name}")
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"triangles must have shape (t, 3), got {arr.shape}")
    return np.ascontiguousarray(arr, dtype=np.int64)


def _as_vector3(value, what):
    arr = _as_float_array(value, what)
    if arr.shape != (3,):
        raise ValueError(f"{what} must have shape (3,), got {arr.shape}")
    return np.ascontiguousarray(arr)


def _as_indices(value, what):
    """A 1-D int64 array of integers (floats, booleans, strings: TypeError)."""
    try:
        arr = np.asarray(value)
    except ValueError as exc:
        raise ValueError(f"{what}: {exc}") from None
    if arr.size == 0:
        arr = np.zeros(0, dtype=np.int64)
    elif arr.dtype.kind == "u":
        if arr.dtype.itemsize >= 8 and int(arr.max()) >= 2**63:
            raise ValueError(f"{what}: an index does not fit in int64")
    elif arr.dtype.kind != "i":
        raise TypeError(f"{what} must be integers, got {arr.dtype.name}")
    if arr.ndim != 1:
        raise ValueError(f"{what} must have shape (m,), got {arr.shape}")
    return np.ascontiguousarray(arr, dtype=np.int64)
