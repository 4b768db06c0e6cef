# SPDX-License-Identifier: LGPL-2.1-or-later
"""What every mfgeom feature proxy shares: adding its properties, a failed recompute
reported as one line, versioned migration of old documents, giving a document made
headless our view provider, and persistence across FreeCAD versions."""

import importlib
import traceback
from typing import Union

import FreeCAD

from mfgeom import compat, progress
from mfgeom.errors import Cancelled, InputError, MfgeomError

# What the make_* functions take for a length or an angle: a number (mm, degrees), a
# string with its unit ("0.01 mm", "3 deg") or a FreeCAD Quantity.
Quantity = Union[float, str, "FreeCAD.Units.Quantity"]


# Every feature's integer "Version" property (see FeatureProxy), one entry of its spec
VERSION_PROPERTY = ("App::PropertyInteger", "Version", "Base",
                    "Version of this object's properties, for migrating old documents", True)


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


def add_mesh_property(obj, tooltip):
    """Adds the read-only ``Mesh`` output (a FreeCAD mesh kernel: stored binary in the
    FCStd, exported like a Mesh feature's) unless ``obj`` has it, hidden in the property
    editor (its view provider draws it)."""
    if "Mesh" not in obj.PropertiesList:
        import Mesh  # noqa: F401 - registers Mesh::PropertyMeshKernel
        obj.addProperty("Mesh::PropertyMeshKernel", "Mesh", "Result", tooltip, 8, True)
        obj.setEditorMode("Mesh", 2)


def attach_view(obj, view_provider):
    """Gives ``obj`` the view provider ``view_provider`` ("module.Class") when the GUI is
    up and it has none yet (a new object, or a document made headless by freecadcmd,
    which saves no view provider)."""
    if FreeCAD.GuiUp and obj.ViewObject is not None and obj.ViewObject.Proxy is None:
        module, name = view_provider.rsplit(".", 1)
        getattr(importlib.import_module(module), name)(obj.ViewObject)


def one_line_error(obj, exc):
    """The exception a failed recompute raises: an InputError stays one (so callers can
    catch it), so does a Cancelled (as an errors.Cancelled), anything else becomes an MfgeomError naming the original class; the
    message is on one line and names the object once: prefixed with its label where
    FreeCAD does not do so itself (0.20; 1.0 reports "<Label>: <message>")."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    if isinstance(exc, Cancelled):   # the user's own stop: say so, not the C detail
        stage = getattr(exc, "stage", None)
        text = f"cancelled (in {stage})" if stage else text
    message = text if compat.freecad_names_failed_objects() else f"{obj.Label}: {text}"
    if isinstance(exc, (InputError, Cancelled)):
        return (Cancelled if isinstance(exc, Cancelled) else type(exc))(message)
    return MfgeomError(f"{message} ({type(exc).__name__})")


def progress_sink():
    """Where a recompute shows its progress (mfgeom.progress): the GUI's progress dialog
    with its Cancel button, or nothing headless (freecadcmd, a script), where a long
    computation is stopped with Ctrl+C instead."""
    if not FreeCAD.GuiUp:
        return None
    from mfgeom.gui.progress_dialog import ProgressDialog
    return ProgressDialog()


def status_line(obj):
    """Why ``obj``'s recompute failed, naming it: "<Label>: <message>" on every FreeCAD
    version (the status string carries the label only where our message does, see
    one_line_error)."""
    status = obj.getStatusString()
    if compat.freecad_names_failed_objects() and not status.startswith(f"{obj.Label}: "):
        return f"{obj.Label}: {status}"
    return status


class FeatureProxy:
    """Base of the App proxies.  Subclasses set TYPE, VERSION and VIEW_PROVIDER and
    implement ``_add_properties(obj)`` (adds what ``obj`` lacks, see add_properties),
    ``_set_defaults(obj)`` (a new object's values) and ``_execute(obj)``; all their
    state lives in properties (never a C handle), so the proxy persists only its type and
    version.  Every object has an integer ``Version`` property: an object of an older
    version (or none) is migrated on restore and before every recompute."""

    TYPE = ""
    VERSION = 0
    VIEW_PROVIDER = ""   # "module.Class" of the view provider, for attach_view
    OBJECT_TYPE = "Part::FeaturePython"   # the document object the proxy drives

    @classmethod
    def make(cls, doc, name, values, what, error=MfgeomError):
        """Adds an OBJECT_TYPE object ``name`` with this proxy (and its view provider)
        to ``doc``, sets ``values`` (property: value, in this order) and computes it.
        Nothing is left half-made: whatever fails, the object is removed again and the
        error raised (``error`` "<what> failed: <status>" when the recompute failed).
        Returns the object."""
        obj = doc.addObject(cls.OBJECT_TYPE, name)
        try:
            cls(obj).attach_view(obj)
            for prop, value in values.items():
                setattr(obj, prop, value)
            # recompute(True): in FreeCAD 0.20 obj.recompute() leaves the new object Touched
            obj.recompute(True)
            if not obj.isValid():
                raise error(f"{what} failed: {status_line(obj)}")
        except Exception:  # undo the half-made object whatever went wrong, then re-raise
            doc.removeObject(obj.Name)
            raise
        return obj

    def __init__(self, obj):
        obj.Proxy = self
        self.Type = self.TYPE
        self._add_properties(obj)
        self._set_defaults(obj)
        obj.Version = self.VERSION

    @staticmethod
    def _add_properties(obj):
        raise NotImplementedError

    def _set_defaults(self, obj):
        """Hook of __init__: the initial values of a new object's properties."""

    def _outdated(self, obj):
        """Whether ``obj`` was made by an older version of the proxy."""
        return "Version" not in obj.PropertiesList or obj.Version < self.VERSION

    def _migrate(self, obj):
        """Brings an old object up to VERSION: adds the properties it lacks, then lets
        ``_upgrade`` carry over what changed meaning."""
        if self._outdated(obj):
            old_version = obj.Version if "Version" in obj.PropertiesList else 0
            old_properties = set(obj.PropertiesList)
            self._add_properties(obj)
            self._upgrade(obj, old_version, old_properties)
            obj.Version = self.VERSION

    def _upgrade(self, obj, old_version, old_properties):
        """Hook of _migrate, after the new properties are added: ``old_version`` (0 when
        the object had no Version) and the names of the properties it had before."""

    def attach_view(self, obj):
        attach_view(obj, self.VIEW_PROVIDER)

    def onDocumentRestored(self, obj):
        self.Type = self.TYPE
        self._migrate(obj)
        # A document made headless (freecadcmd) has no saved view provider: give it ours.
        self.attach_view(obj)

    def execute(self, obj):
        try:
            self._migrate(obj)
            with progress.task(f"Recomputing {obj.Label}", progress_sink()):
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
