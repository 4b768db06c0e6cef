# SPDX-License-Identifier: LGPL-2.1-or-later
"""What every mfgeom feature proxy shares: adding its properties, a failed recompute
reported as one line, and persistence across FreeCAD versions."""

import traceback

import FreeCAD

from mfgeom.errors import InputError, MfgeomError


def add_properties(obj, spec):
    """Adds the properties of ``spec`` that ``obj`` lacks (so migration can call it on old
    objects).  ``spec``: (type, name, group, tooltip, output?) tuples; an output is
    read-only in the editor and setting it does not touch the object (status 8)."""
    for ptype, name, group, tip, output in spec:
        if name not in obj.PropertiesList:
            if output:
                obj.addProperty(ptype, name, group, tip, 8, True)
            else:
                obj.addProperty(ptype, name, group, tip)


def one_line_error(obj, exc):
    """The exception a failed recompute raises: an InputError stays one (so callers can
    catch it), anything else becomes an MfgeomError naming the original class; the
    message is prefixed with the object's label, on one line."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    message = f"{obj.Label}: {text}"
    if isinstance(exc, InputError):
        return type(exc)(message)
    return MfgeomError(f"{message} ({type(exc).__name__})")


class FeatureProxy:
    """Base of the App proxies.  Subclasses set TYPE and VERSION and implement
    ``_execute(obj)``; all their state lives in properties (never a C handle), so the
    proxy persists only its type and version."""

    TYPE = ""
    VERSION = 0

    def execute(self, obj):
        try:
            self._execute(obj)
        except Exception as exc:  # whatever failed: one clear line, details in the log
            FreeCAD.Console.PrintLog(f"mfgeom: {obj.Label}: {traceback.format_exc()}")
            error = one_line_error(obj, exc)
        else:
            return
        # Raised here, outside the except block and with no context, so the traceback
        # FreeCAD 0.20 prints (it always does) has this one frame only.
        raise error

    def _execute(self, obj):
        raise NotImplementedError

    def _restored(self):
        """Called when the proxy is read back from a file (no object at hand yet)."""

    # Persistence: 0.20 calls __getstate__/__setstate__, 0.21+ dumps/loads.
    def __getstate__(self):
        return {"Type": self.TYPE, "Version": self.VERSION}

    def __setstate__(self, state):
        self.Type = self.TYPE
        self._restored()

    def dumps(self):
        return self.__getstate__()

    def loads(self, state):
        self.__setstate__(state)
