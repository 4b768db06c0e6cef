# SPDX-License-Identifier: LGPL-2.1-or-later
"""The status of a library call: the error classes (MfgError, Cancelled), the status
check every wrapper applies, the library's version, and the progress / cancel helper of
the ``*_p`` entry points (struct mfg_progress)."""

import ctypes
import sys
from typing import Callable, Optional

from mfgeom import errors
from mfgeom.errors import MfgeomError
from mfgeom.core.loader import _lib


class MfgError(MfgeomError, RuntimeError):
    """An error reported by libmfgeom; ``status`` is the C status name."""

    def __init__(self, status, message):
        super().__init__(f"{message} ({status})" if message else status)
        self.status = status
        self.detail = message


class Cancelled(MfgError, errors.Cancelled):
    """A long computation stopped by its ``progress`` callable (C status
    MFG_ERR_CANCELLED, ``status`` "cancelled"); ``stage`` is the stage it stopped in
    (e.g. "sweep: faces").  Nothing was computed: the call has no result.  A progress
    callable that raises does not give Cancelled: its own exception propagates."""

    def __init__(self, status, message, stage=None):
        super().__init__(status, message)
        self.stage = stage


_lib.mfg_status_str.restype = ctypes.c_char_p
_lib.mfg_status_str.argtypes = [ctypes.c_int]
_lib.mfg_last_error.restype = ctypes.c_char_p
_lib.mfg_last_error.argtypes = []
_lib.mfg_version.restype = ctypes.c_char_p
_lib.mfg_version.argtypes = []


def version() -> str:
    """Version string of the loaded C library."""
    return _lib.mfg_version().decode()


def _check(status):
    if status != 0:
        name = _lib.mfg_status_str(status).decode()
        detail = _lib.mfg_last_error().decode()
        raise MfgError(name, detail)


# --------------------------------------------------------------------------- #
# Progress and cancel (mfg_progress): one helper for every long entry point    #
# --------------------------------------------------------------------------- #

# What every ``progress`` argument takes: None or ``progress(fraction, stage)``, a truthy
# return cancelling (see _ProgressCall).
ProgressFn = Optional[Callable[[float, str], object]]

_PROGRESS_FN = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_double,
                                ctypes.c_char_p)


class _Progress(ctypes.Structure):
    """struct mfg_progress (mfgeom.h)."""
    _fields_ = [("callback", _PROGRESS_FN), ("user", ctypes.c_void_p)]


_c_progress_p = ctypes.POINTER(_Progress)


class _ProgressCall:
    """The progress of one call of a ``*_p`` entry point.

    ``progress`` is None or a callable ``progress(fraction, stage)``: fraction a float in
    [0, 1] that never decreases, stage a str such as "sweep: faces" (the stage names of
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
