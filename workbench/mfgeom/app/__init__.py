# SPDX-License-Identifier: LGPL-2.1-or-later
"""The FreeCAD App layer of mfgeom: feature proxies, reference resolution and the geometry
that needs FreeCAD's Part module.  Works in freecadcmd; nothing here imports FreeCADGui.

One module per feature (pointclass; parting, rotsweep and medial to come), plus the
shared helpers refs (document references -> geometry) and preferences."""
