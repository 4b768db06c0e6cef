# SPDX-License-Identifier: LGPL-2.1-or-later
"""ctypes binding to libmfgeom: works in plain python3 with numpy, without FreeCAD."""

import ctypes
import numbers
import os
import struct
import sys
import sysconfig
import threading

import numpy as np

from mfgeom import building, paths
from mfgeom import errors
from mfgeom.errors import LibraryError, MfgeomError
from mfgeom.names import IN, KIND_CODES, KINDS, ON, OUT  # noqa: F401  (core.IN etc.)

class MfgError(MfgeomError, RuntimeError):
    """An error reported by libmfgeom; ``status`` is the C status name."""

    def __init__(self, status, message):
        super().__init__(f"{message} ({status})" if message else status)
        self.status = status
        self.detail = message


class Cancelled(MfgError, errors.Cancelled):
    """A long computation stopped by its ``progress`` callable (C status
    MFG_ERR_CANCELLED, ``status`` "cancelled"); ``stage`` is the stage it stopped in
    (e.g. "sweep: walls").  Nothing was computed: the call has no result.  A progress
    callable that raises does not give Cancelled: its own exception propagates."""

    def __init__(self, status, message, stage=None):
        super().__init__(status, message)
        self.stage = stage


# --------------------------------------------------------------------------- #
# Loading the library: lazily (importing this module never needs it), once,   #
# under a lock, and never a sanitizer build unless asked for by name.         #
# --------------------------------------------------------------------------- #

LIBRARY_NAME = "libmfgeom.so"

# Symbol-name prefixes that mark an instrumented build.  The runtimes of the first four
# must be the first library of the process: loaded later, they abort it (FreeCAD dies
# with "ASan runtime does not come first"), so their init symbol must already be there.
_SANITIZERS = {b"__asan_": ("AddressSanitizer", "__asan_init"),
               b"__hwasan_": ("HWAddressSanitizer", "__hwasan_init"),
               b"__tsan_": ("ThreadSanitizer", "__tsan_init"),
               b"__msan_": ("MemorySanitizer", "__msan_init"),
               b"__ubsan_": ("UndefinedBehaviorSanitizer", None)}


def _elf_dynamic_names(path):
    """The names in ELF file ``path``'s dynamic string table (its imported and exported
    symbols and needed libraries); empty if it is not an ELF file.  Reading it is cheap
    (no process is started) and does not depend on how the build was configured: a
    copied library carries its instrumentation with it."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"\x7fELF" or data[4] not in (1, 2) or data[5] not in (1, 2):
        return []
    is64, order = data[4] == 2, "<" if data[5] == 1 else ">"
    try:
        if is64:
            shoff, = struct.unpack_from(order + "Q", data, 40)
            shentsize, shnum = struct.unpack_from(order + "HH", data, 58)
            section = lambda i: struct.unpack_from(   # noqa: E731  (type, offset, size, link)
                order + "4xI16xQQI", data, shoff + i * shentsize)
        else:
            shoff, = struct.unpack_from(order + "I", data, 32)
            shentsize, shnum = struct.unpack_from(order + "HH", data, 46)
            section = lambda i: struct.unpack_from(   # noqa: E731
                order + "4xI8xIII", data, shoff + i * shentsize)
        for i in range(shnum):
            sh_type, _off, _size, link = section(i)
            if sh_type == 11:                        # SHT_DYNSYM: its strings are in `link`
                _t, off, size, _l = section(link)
                return data[off:off + size].split(b"\0")
    except struct.error:                             # truncated: let the loader judge it
        pass
    return []


def sanitizers(path):
    """Names of the sanitizers ``path`` was built with (empty for a normal build)."""
    names = _elf_dynamic_names(path)
    return [sanitizer for prefix, (sanitizer, _init) in _SANITIZERS.items()
            if any(name.startswith(prefix) for name in names)]


def _runtime_missing(path):
    """The sanitizer runtime ``path`` needs first in the process but is not there, or
    None: loading such a library would abort the process, not raise."""
    names = _elf_dynamic_names(path)
    process = ctypes.CDLL(None)
    for prefix, (sanitizer, init) in _SANITIZERS.items():
        if init and any(n.startswith(prefix) for n in names) and not hasattr(process, init):
            return sanitizer
    return None


def _search_places():
    """Where the library is looked for when MFGEOM_LIBRARY is not set, in order: next
    to the binding (scripts/build.sh links it there), the repository's build/, then the
    system library directories.  Every place is a path, so each can be inspected
    before it is loaded."""
    places = [os.path.join(paths.PACKAGE_DIR, LIBRARY_NAME),
              os.path.join(paths.REPO_DIR, "build", LIBRARY_NAME)]
    dirs = [d for d in os.environ.get("LD_LIBRARY_PATH", "").split(os.pathsep) if d]
    dirs += [os.path.join(sys.prefix, "lib"), "/usr/local/lib", "/usr/lib"]
    multiarch = sysconfig.get_config_var("MULTIARCH")
    if multiarch:
        dirs.append(os.path.join("/usr/lib", multiarch))
    for d in dirs:
        place = os.path.join(d, LIBRARY_NAME)
        if place not in places:
            places.append(place)
    return places


def _not_found(tried, explicit=None):
    """The LibraryError for a missing library: where it was looked for, why each place
    was not used, and the command that builds it."""
    lines = [f"MFGEOM_LIBRARY={explicit} cannot be used." if explicit else
             f"No usable {LIBRARY_NAME} (the mfgeom C library) was found."]
    lines.append("Looked in:")
    lines += [f"  {place}: {why}" for place, why in tried]
    lines.append(building.instructions())
    lines.append("or set MFGEOM_LIBRARY to the path of a libmfgeom.so" +
                 (" that exists." if explicit else "."))
    return LibraryError("\n".join(lines))


def _open(path):
    try:
        return ctypes.CDLL(path)
    except OSError as exc:
        raise LibraryError(f"{path} could not be loaded: {exc}\n"
                           + building.instructions()) from None


def _find_and_open():
    """(CDLL, path) of the library to use, or raises LibraryError."""
    explicit = os.environ.get("MFGEOM_LIBRARY")
    if explicit:
        # An explicit choice that is wrong must not silently load another build.
        if not os.path.isfile(explicit):
            raise _not_found([(explicit, "no such file")], explicit)
        missing = _runtime_missing(explicit)
        if missing:
            raise LibraryError(
                f"MFGEOM_LIBRARY={explicit} is built with {missing}: loading it would abort "
                f"this process, whose first library is not the {missing} runtime.  Run "
                "under LD_PRELOAD=$(gcc -print-file-name=libasan.so) or use a normal "
                "build.\n" + building.instructions())
        return _open(explicit), explicit
    tried = []
    for place in _search_places():
        if not os.path.isfile(place):
            tried.append((place, "no such file"))
            continue
        found = sanitizers(place)
        if found:
            tried.append((place, f"skipped: built with {' + '.join(found)}, loaded only "
                                 "when MFGEOM_LIBRARY names it"))
            continue
        return _open(place), place
    raise _not_found(tried)


class _Function:
    """A C function of the library, declared (restype, argtypes) before the library is
    loaded; the first call loads the library."""

    __slots__ = ("name", "restype", "argtypes", "_cfunc")

    def __init__(self, name):
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "restype", ctypes.c_int)
        object.__setattr__(self, "argtypes", None)
        object.__setattr__(self, "_cfunc", None)

    def __setattr__(self, key, value):
        object.__setattr__(self, key, value)
        object.__setattr__(self, "_cfunc", None)   # re-declared: bind again

    def _bind(self, cdll):
        # A fresh function object of our own: concurrent first calls each bind one,
        # identically, and whichever is stored last is as good as the other.
        cfunc = cdll[self.name]
        cfunc.restype = self.restype
        if self.argtypes is not None:
            cfunc.argtypes = self.argtypes
        object.__setattr__(self, "_cfunc", cfunc)
        return cfunc

    def __call__(self, *args):
        cfunc = self._cfunc
        if cfunc is None:
            cfunc = self._bind(load())
        return cfunc(*args)


class _Library:
    """Stands for the CDLL: ``_lib.mfg_x`` is a :class:`_Function` that loads the
    library on its first call, so declaring the prototypes needs no library."""

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        function = _Function(name)
        setattr(self, name, function)
        return function


_lib = _Library()
_load_lock = threading.Lock()
_loaded = None            # (CDLL, path) once loaded; a failed load is retried next time


def load():
    """The loaded library (a ctypes.CDLL), loading it on the first call (thread-safe).

    Raises :class:`mfgeom.errors.LibraryError` (an ImportError) if it cannot be found
    or loaded, with the places searched and the command that builds it; a later call
    tries again (e.g. after the library was built)."""
    global _loaded
    loaded = _loaded
    if loaded is None:
        with _load_lock:
            if _loaded is None:
                cdll, path = _find_and_open()
                # Bind every declared function now, so that later calls (also those of
                # finalizers at interpreter shutdown) need nothing but their own object,
                # and put the ctypes function itself in its place: no proxy per call.
                for name, function in list(vars(_lib).items()):
                    try:
                        setattr(_lib, name, function._bind(cdll))
                    except AttributeError:   # not in this build: fails when called
                        pass
                _loaded = (cdll, path)
            loaded = _loaded
    return loaded[0]


def __getattr__(name):
    # ``core.library_path``: the path of the loaded library (loads it if needed).
    if name == "library_path":
        load()
        return _loaded[1]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

_c_double_p = ctypes.POINTER(ctypes.c_double)
_c_int64_p = ctypes.POINTER(ctypes.c_int64)
_c_uint8_p = ctypes.POINTER(ctypes.c_uint8)

_lib.mfg_status_str.restype = ctypes.c_char_p
_lib.mfg_status_str.argtypes = [ctypes.c_int]
_lib.mfg_last_error.restype = ctypes.c_char_p
_lib.mfg_last_error.argtypes = []
_lib.mfg_version.restype = ctypes.c_char_p
_lib.mfg_version.argtypes = []
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


# --------------------------------------------------------------------------- #
# Progress and cancel (mfg_progress): one helper for every long entry point    #
# --------------------------------------------------------------------------- #

_PROGRESS_FN = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_double,
                                ctypes.c_char_p)


class _Progress(ctypes.Structure):
    """struct mfg_progress (mfgeom.h)."""
    _fields_ = [("callback", _PROGRESS_FN), ("user", ctypes.c_void_p)]


_c_progress_p = ctypes.POINTER(_Progress)


class _ProgressCall:
    """The progress of one call of a ``*_p`` entry point.

    ``progress`` is None or a callable ``progress(fraction, stage)``: fraction a float in
    [0, 1] that never decreases, stage a str such as "sweep: cells" (the stage names of
    mfgeom.h).  It is called on the calling thread, every few to few tens of
    milliseconds of work.  A truthy return value cancels the call (Cancelled is raised);
    None / False go on.  An exception raised by the callable (KeyboardInterrupt too)
    cancels the call and is raised again, unchanged, once the C call has returned (ctypes
    would otherwise print and swallow it).  With progress None a callback is installed
    anyway: it lets Python deliver a pending signal, so Ctrl-C (KeyboardInterrupt)
    cancels a long call in a script.  The ctypes callback object lives as long as this
    object, which the caller keeps until the C call returns."""

    __slots__ = ("_user", "_error", "_stage", "_cfunc", "_struct", "_old_hook")

    def __init__(self, progress):
        if progress is not None and not callable(progress):
            raise TypeError(f"progress must be callable or None, got {type(progress).__name__}")
        self._user = progress
        self._error = None
        self._stage = None
        self._cfunc = _PROGRESS_FN(self._callback)
        self._struct = _Progress(self._cfunc, None)
        self._old_hook = None

    def _callback(self, _user, fraction, stage):
        if self._error is not None:  # a signal raised on entry (see _hook): stop
            return 1
        try:
            self._stage = stage.decode() if stage else ""
            if self._user is not None and self._user(float(fraction), self._stage):
                return 1
            return 0
        except BaseException as exc:  # noqa: B902 - KeyboardInterrupt must cancel too
            if self._error is None:
                self._error = exc
            return 1

    def _hook(self, unraisable):
        """sys.unraisablehook during the call: an exception raised before _callback's
        try (a pending SIGINT is delivered on entry to Python code) is recorded, not
        printed; the next report then cancels, and call() raises it."""
        if getattr(unraisable.object, "__self__", None) is self:
            if self._error is None:
                self._error = unraisable.exc_value
            return
        self._old_hook(unraisable)

    def call(self, fn, *args):
        """Calls the C function fn(*args) (its last argument self.arg) and checks its
        status as check() does."""
        self._old_hook = sys.unraisablehook
        sys.unraisablehook = self._hook
        try:
            status = fn(*args)
        finally:
            if sys.unraisablehook == self._hook:
                sys.unraisablehook = self._old_hook
            self._old_hook = None
        self.check(status)

    @property
    def arg(self):
        """The const mfg_progress * argument."""
        return ctypes.byref(self._struct)

    def check(self, status):
        """As _check, after the call: re-raises the callable's exception, raises
        Cancelled for a cancel by its return value."""
        if self._error is not None:
            err, self._error = self._error, None
            raise err
        if status != 0 and _lib.mfg_status_str(status).decode() == "cancelled":
            raise Cancelled("cancelled", _lib.mfg_last_error().decode(), self._stage)
        _check(status)


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


def version():
    """Version string of the loaded C library."""
    return _lib.mfg_version().decode()


def _check(status):
    if status != 0:
        name = _lib.mfg_status_str(status).decode()
        detail = _lib.mfg_last_error().decode()
        raise MfgError(name, detail)


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


def classify_points(rings, points, tol):
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

    def __init__(self, rings, tol):
        xy, offsets = _flatten_rings(rings)
        handle = ctypes.c_void_p()
        _check(_lib.mfg_region_new(_ptr(xy, ctypes.c_double), _ptr(offsets, ctypes.c_int64),
                                   len(offsets) - 1, _as_float(tol, "tol"),
                                   ctypes.byref(handle)))
        self._handle = handle
        self.tol = float(tol)
        self._free = _lib.mfg_region_free  # kept for use during interpreter shutdown

    def classify(self, points):
        if not self._handle:
            raise MfgError("invalid argument", "Region is closed")
        pts = _as_points(points)
        out = np.empty(len(pts), dtype=np.uint8)
        _check(_lib.mfg_region_classify(self._handle, _ptr(pts, ctypes.c_double), len(pts),
                                        _ptr(out, ctypes.c_uint8)))
        return out

    def stats(self):
        """Index statistics (struct mfg_region_info) as a dict: columns, rows (the grid),
        edge_cells, grid_entries, edge_entries, list_entries, ordered_entries, nodes,
        list_leaves, ordered_leaves, max_depth, max_list, bytes."""
        if not self._handle:
            raise MfgError("invalid argument", "Region is closed")
        info = _RegionInfo()
        _check(_lib.mfg_region_info(self._handle, ctypes.byref(info)))
        return {name: int(getattr(info, name)) for name, _ in _RegionInfo._fields_}

    def close(self):
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


class VisibilityMap:
    """A spherical convex set: ``kind`` ("null", "point", "edge", "polygon"),
    ``vertices`` ((k, 3) unit vectors, counter-clockwise seen from outside for a polygon;
    the arc's points in order for an edge; one or two antipodal directions for a point)
    and ``closed`` (an edge that is a whole great circle).  See mfgeom.h for the rules."""

    def __init__(self, kind, vertices, closed=False):
        self.kind = kind
        self.vertices = _as_float_array(vertices, "vertices").reshape(-1, 3)
        self.closed = bool(closed)

    def __repr__(self):
        return f"VisibilityMap(kind={self.kind!r}, {len(self.vertices)} vertices)"

    def contains(self, directions, tol=1e-12):
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


def visibility_map(normals, draft_angle=0.0, negative=False):
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


def max_intersection(maps, weights=None, progress=None):
    """All regions of the sphere covered by the greatest total weight of ``maps``
    (VisibilityMap objects or (k, 3) arrays of counter-clockwise convex polygons).
    ``progress``: see :class:`_ProgressCall` (stages "maxisect: sets", "maxisect: search",
    "maxisect: regions", "maxisect: done"; a cancel raises Cancelled)."""
    return _call_regions(_lib.mfg_max_intersection_p, maps, weights, progress=progress)


def level_regions(maps, level, weights=None, progress=None):
    """Every locally maximal region whose covered weight is at least ``level``
    (``progress`` as for :func:`max_intersection`)."""
    return _call_regions(_lib.mfg_level_regions_p, maps, weights,
                         ctypes.c_double(_as_float(level, "level")), progress=progress)


def min_intersection(maps, weights=None, progress=None):
    """The least covered weight over the sphere; per least-covered face its cover set
    and a direction inside it (kind "face"; ``regions`` are empty arrays: faces are not
    convex, their shape is not computed).  ``progress`` as for :func:`max_intersection`."""
    return _call_regions(_lib.mfg_min_intersection_p, maps, weights, progress=progress)


# --------------------------------------------------------------------------- #
# Closed triangle meshes (input of the rotational sweep and the medial surface) #
# --------------------------------------------------------------------------- #

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

    def as_dict(self):
        d = {name: getattr(self, name) for name in _MESH_COUNTS}
        d.update(volume=self.volume, area=self.area, bbox=self.bbox.tolist())
        return d

    def __repr__(self):
        return f"MeshReport({self.as_dict()})"


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


def mesh_check(vertices, triangles, require_closed=False):
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


def weld(soup):
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


# --------------------------------------------------------------------------- #
# Rotational swept volume (issue 8)                                           #
# --------------------------------------------------------------------------- #

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


def _as_vector3(value, what):
    arr = _as_float_array(value, what)
    if arr.shape != (3,):
        raise ValueError(f"{what} must have shape (3,), got {arr.shape}")
    return np.ascontiguousarray(arr)


def rotational_sweep(vertices, triangles, axis_point, axis_direction, angle, tolerance,
                     progress=None):
    """The volume swept by the closed solid (``vertices`` (n, 3), ``triangles`` (t, 3),
    counter-clockwise seen from outside) turning about the axis through ``axis_point``
    along ``axis_direction`` (right-handed) by 0 .. ``angle`` radians (0 < angle <= 2 pi;
    within 1e-12 of 2 pi: the solid of revolution), as a :class:`SweepResult` whose
    boundary lies within ``tolerance`` (absolute, > 0) of the true one.

    An open, non-manifold or flipped mesh, a zero axis direction, an angle or tolerance
    out of range and NaN raise MfgError with the library's detail (e.g. "mesh is not
    closed: 3 boundary edges (first: vertices 1-5)").  ``progress``: None or
    ``progress(fraction, stage)`` (see :class:`_ProgressCall`; stages "sweep: setup",
    "sweep: cells", "sweep: polygons", "sweep: walls", "sweep: check", "sweep: output",
    "sweep: done"); a truthy return raises Cancelled, an exception it raises propagates."""
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
    try:
        m = res.contents
        nv, nt = int(m.nvertices), int(m.ntriangles)
        verts = (np.ctypeslib.as_array(m.vertices, shape=(3 * nv,)).reshape(-1, 3).copy()
                 if nv else np.zeros((0, 3)))
        tris = (np.ctypeslib.as_array(m.triangles, shape=(3 * nt,)).reshape(-1, 3).copy()
                if nt else np.zeros((0, 3), dtype=np.int64))
    finally:
        _lib.mfg_mesh_free(res)
    return SweepResult(verts, tris, stats.volume, stats.area, stats.bbox[:])


# --------------------------------------------------------------------------- #
# Demouldability by rays (issue 17)                                           #
# --------------------------------------------------------------------------- #

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


def ray_blocked(vertices, triangles, points, own_triangle, direction, progress=None):
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


# ---- medial axis of a face (issue 9 section 2) -------------------------------------------

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


def medial_axis(rings, tolerance, progress=None):
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


# ---- medial surface of a solid (issue 9 section 1) ---------------------------------------

_c_int32_p = ctypes.POINTER(ctypes.c_int32)


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
    def nfaces(self):
        return len(self.face_planes)

    @property
    def nedges(self):
        return len(self.edge_segments)

    @property
    def nvertices(self):
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


def medial_surface(vertices, triangles, tolerance, major_only=True, threads=0, progress=None):
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
    if not isinstance(major_only, (bool, np.bool_)):
        raise TypeError(f"major_only must be True or False, got {major_only!r:.40}")
    if isinstance(threads, (bool, np.bool_)) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"threads must be an int, got {threads!r:.40}")
    if not -2**31 <= int(threads) < 2**31:
        raise ValueError(f"threads {int(threads)} does not fit in int32")
    xyz = _as_vertices(vertices)
    tri = _as_triangles(triangles)
    flags = 0 if major_only else MEDIAL_FULL
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
