# SPDX-License-Identifier: LGPL-2.1-or-later
"""The FreeCAD GUI layer of mfgeom: commands, view providers and task panels.  Imported
only when FreeCAD.GuiUp; one view module per feature (pointclass_view, ...)."""
