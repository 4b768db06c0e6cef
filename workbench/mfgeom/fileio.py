# SPDX-License-Identifier: LGPL-2.1-or-later
"""fileio.py - writing output files so that a failure leaves nothing half-written
(issue 22): every file the package writes (CLI outputs, meshes, PLY/OBJ, CSV reports)
goes through :func:`write_atomic` -- a temporary file in the target's folder, renamed
over the target only once it is complete -- and a CLI command collects what it wrote
in an :class:`Outputs` so that a command failing after some of its outputs removes them.
Plain Python: no numpy, no FreeCAD."""
import os
import tempfile


def write_atomic(path, data, encoding="utf-8", newline=None):
    """Writes ``data`` (bytes, or str encoded with ``encoding``; ``newline`` as for
    :func:`open`) to ``path`` through a temporary file in the same folder renamed into
    place: readers see the old file or the complete new one, never a truncated one.  On
    failure (no folder, read-only, disk full, an exception while writing) the temporary
    file is removed, ``path`` is untouched, and the OSError is raised."""
    folder = os.path.dirname(os.path.abspath(path))
    base = os.path.basename(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{base}.", suffix=".partial", dir=folder)
    try:
        if isinstance(data, (bytes, bytearray, memoryview)):
            with os.fdopen(fd, "wb") as f:
                f.write(data)
        else:
            with os.fdopen(fd, "w", encoding=encoding, newline=newline) as f:
                f.write(data)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


class Outputs:
    """The files one command has written, to remove them when it fails later (a sweep
    whose STL was written but whose --json could not be: neither stays)."""

    def __init__(self):
        self.paths = []

    def add(self, path):
        self.paths.append(path)

    def remove_all(self):
        """Removes every file recorded (those already gone are skipped)."""
        for p in reversed(self.paths):
            try:
                os.unlink(p)
            except OSError:
                pass
        self.paths = []
