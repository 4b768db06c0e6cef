# SPDX-License-Identifier: LGPL-2.1-or-later
"""The one definition of the codes and names shared by the library, the binding, the CLI
and the workbench (they mirror the enums of libcore/include/mfgeom.h).  FreeCAD-free."""

# Point classes (enum mfg_class).
OUT = 0
IN = 1
ON = 2
CLASS_NAMES = {OUT: "OUT", IN: "IN", ON: "ON"}

# Kinds of spherical sets (enum mfg_vm_kind): visibility maps and intersection regions.
# "face" (MFG_VM_FACE) is output only: a region of min_intersection, a face of the
# arrangement whose shape is not computed (no vertices).
KINDS = {0: "null", 1: "point", 2: "edge", 3: "polygon", 4: "face"}
FACE = 4
# The kinds a map given to the library may have.
KIND_CODES = {name: code for code, name in KINDS.items() if code != FACE}
