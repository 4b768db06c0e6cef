# SPDX-License-Identifier: LGPL-2.1-or-later
"""Reads the workbench preferences (Edit > Preferences > Manufacturing Geometry)."""

import FreeCAD

PARAM_PATH = "User parameter:BaseApp/Preferences/Mod/mfgeom"
DEFAULT_TOLERANCE = 0.01  # mm: typical machining accuracy, well above OCCT's 1e-7 mm


def params():
    return FreeCAD.ParamGet(PARAM_PATH)


def default_tolerance():
    """The default classification tolerance in mm (preference DefaultTolerance)."""
    value = params().GetFloat("DefaultTolerance", DEFAULT_TOLERANCE)
    # A hand-edited user.cfg may hold anything; fall back rather than fail a command.
    if not value >= 0.0:
        return DEFAULT_TOLERANCE
    return value


def point_size():
    """Size in pixels of the classified points in the 3D view (preference PointSize)."""
    return max(1, params().GetInt("PointSize", 6))
