# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD-free geometry of the workbench's features (numpy only): what the App and GUI
layers compute on arrays, kept here so that pytest tests it without FreeCAD.

    mesh    conservative_offset (sweep), mesh_area, boundary_loops, straightened
            (mid-surface)
    sphere  icosphere, coverage, great_arc, map_outlines (the parting view's sphere)
"""
