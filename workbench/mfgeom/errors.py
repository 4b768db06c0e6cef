# SPDX-License-Identifier: LGPL-2.1-or-later
"""The exception classes of mfgeom: one base class, so a macro can catch everything
mfgeom raises with ``except mfgeom.errors.MfgeomError``.  FreeCAD-free."""


class MfgeomError(Exception):
    """Base class of every error mfgeom raises on purpose."""


class InputError(MfgeomError, ValueError):
    """A reference, selection or value that cannot be used; the text says why."""


class LibraryError(MfgeomError, ImportError):
    """libmfgeom.so could not be found or loaded; the text says where it was looked for
    and how to build it."""


class Cancelled(MfgeomError):
    """A long computation was stopped on request (the progress dialog's Cancel, Esc, a
    progress callable asking to stop); nothing was written.  The text names the stage."""
