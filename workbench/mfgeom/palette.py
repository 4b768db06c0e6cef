# SPDX-License-Identifier: LGPL-2.1-or-later
"""Result colours used by every feature of the workbench (RGB, 0..1).  FreeCAD-free, so
reports and plots outside FreeCAD use the same colours."""

from mfgeom import names

CLASS_COLORS = {names.OUT: (0.85, 0.10, 0.10), names.IN: (0.10, 0.70, 0.15),
                names.ON: (1.00, 0.65, 0.00)}
UNKNOWN = (0.5, 0.5, 0.5)
