# SPDX-License-Identifier: LGPL-2.1-or-later
"""Finding and loading libmfgeom: lazily (importing mfgeom.core never needs it), once,
under a lock, and never a sanitizer build unless asked for by name.  MFGEOM_LIBRARY
first, then beside the package, the repository's build/, the system directories.

``_lib`` stands for the library: the family modules declare their prototypes on it
before anything is loaded; the first call loads the library and binds them all."""

import ctypes
import os
import struct
import sys
import sysconfig
import threading
from typing import List

from mfgeom import building, paths
from mfgeom.errors import LibraryError


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


def sanitizers(path: str) -> List[str]:
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


def load() -> ctypes.CDLL:
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
