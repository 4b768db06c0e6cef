# SPDX-License-Identifier: LGPL-2.1-or-later
# App-side start-up of the Manufacturing Geometry workbench (runs in freecadcmd too).
#
# Nothing to register: FreeCAD has already put this directory on sys.path, which is all
# macros need for `import mfgeom; mfgeom.make_point_classification(...)`.
# __file__ is not defined here, so any path is computed in mfgeom.paths.
