# SPDX-License-Identifier: LGPL-2.1-or-later
"""The workbench's message box: what the commands say when they cannot start (a missing
library, an open task panel, a bad selection).  A module of its own so every command
module imports it from here (commands.py and clearance_command.py imported each other
for it)."""

import FreeCAD
import FreeCADGui


def warn(title: str, text: str) -> None:
    """A warning box titled ``title`` (and the same text in the Report view)."""
    from PySide import QtGui
    FreeCAD.Console.PrintWarning(f"mfgeom: {text}\n")
    QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), title, text)
