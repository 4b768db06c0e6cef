# SPDX-License-Identifier: LGPL-2.1-or-later
"""What differs between the FreeCAD versions the workbench supports (0.20 .. 1.x), in one
place.  Importable without FreeCAD (FreeCAD is imported only by the functions that ask it).

* ``freecad_version()``: FreeCAD's version as a tuple of ints, e.g. ``(1, 0, 0)``;
* ``freecad_names_failed_objects()``: whether FreeCAD itself prefixes a failed recompute's
  message with the object's label (1.0 does, 0.20 does not);
* ``flush_output()`` / ``exit_now(rc)``: FreeCAD 1.0 buffers its console output (C stdio)
  when it goes to a pipe, so a script that leaves with ``os._exit`` (the GUI scripts must:
  a normal exit of the GUI can hang or crash under Xvfb) loses its last lines unless both
  Python's streams and C stdio are flushed first.
"""

import os
import sys


def freecad_version():
    """FreeCAD's (major, minor, patch) as ints (missing or non-numeric parts count 0)."""
    import FreeCAD
    parts = []
    for item in list(FreeCAD.Version())[:3]:
        digits = "".join(ch for ch in str(item) if ch.isdigit())
        parts.append(int(digits) if digits else 0)
    return tuple(parts + [0] * (3 - len(parts)))


def freecad_names_failed_objects():
    """True when FreeCAD reports a failed recompute as ``<Label>: <message>`` itself (1.0
    and later), so the message of our exception must not start with the label again."""
    return freecad_version() >= (1, 0, 0)


def flush_output():
    """Flushes Python's sys.stdout and sys.stderr, then every C stdio stream."""
    for stream in (sys.stdout, sys.stderr, sys.__stdout__, sys.__stderr__):
        try:
            if stream is not None:
                stream.flush()
        except (OSError, ValueError, AttributeError):  # closed or not a real stream
            pass
    try:
        import ctypes
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):  # no C library to ask (not on Linux/macOS)
        pass


def exit_now(rc):
    """Leaves the process at once with exit code ``rc`` (os._exit), output flushed."""
    flush_output()
    os._exit(rc)
