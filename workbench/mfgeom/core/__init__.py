# SPDX-License-Identifier: LGPL-2.1-or-later
"""ctypes binding to libmfgeom: works in plain python3 with numpy, without FreeCAD.

One module per C family, all re-exported here (``from mfgeom import core; core.X``):

    loader      finding and loading libmfgeom.so (MFGEOM_LIBRARY, then beside the
                package, the repository's build/, the system directories)
    status      MfgError / Cancelled, the status check, version, progress and cancel
    arrays      input conversion and validation shared by every wrapper
    pointclass  classify_points, Region                     (libcore/src/pointclass)
    sphere      visibility_map, max/level/min_intersection,
                ray_blocked                                  (libcore/src/sphere)
    mesh        mesh_check, weld                             (libcore/src/mesh)
    sweep       rotational_sweep                             (libcore/src/sweep)
    axis2d      medial_axis                                  (libcore/src/axis2d)
    medial      medial_surface, wall_thickness               (libcore/src/medial)

Importing this package never loads the library; the first call does.  Callers use the
names re-exported here, not the modules' (``core.medial_surface`` can be replaced in a
test and every caller sees it)."""

import sys
import types

from mfgeom.errors import LibraryError, MfgeomError  # noqa: F401  (core.LibraryError)
from mfgeom.names import IN, KIND_CODES, KINDS, ON, OUT  # noqa: F401  (core.IN etc.)

from mfgeom.core import loader
from mfgeom.core.loader import (  # noqa: F401
    LIBRARY_NAME, _SANITIZERS, _Function, _Library, _elf_dynamic_names, _find_and_open,
    _lib, _load_lock, _not_found, _open, _runtime_missing, _search_places, load, sanitizers)
from mfgeom.core.status import (  # noqa: F401
    _PROGRESS_FN, Cancelled, MfgError, _c_progress_p, _check, _Progress, _ProgressCall,
    version)
from mfgeom.core.arrays import (  # noqa: F401
    _as_float, _as_float_array, _as_indices, _as_points, _as_triangles, _as_vector3,
    _as_vertices, _c_double_p, _c_int32_p, _c_int64_p, _c_uint8_p, _flatten_rings, _ptr)
from mfgeom.core.pointclass import Region, _RegionInfo, classify_points  # noqa: F401
from mfgeom.core.sphere import (  # noqa: F401
    _REGION_ARGS, RAY_BLOCKED_NEG, RAY_BLOCKED_POS, RAY_GRAZES_NEG, RAY_GRAZES_POS,
    Intersection, VisibilityMap, _call_regions, _flatten_maps, _Regions, _SPoly,
    level_regions, max_intersection, min_intersection, ray_blocked, visibility_map)
from mfgeom.core.mesh import (  # noqa: F401
    _MESH_ARGS, _MESH_COUNTS, MeshReport, _Mesh, _MeshReport, mesh_check, weld)
from mfgeom.core.sweep import SweepResult, _SweepStats, rotational_sweep  # noqa: F401
from mfgeom.core.axis2d import (  # noqa: F401
    MedialAxis, MedialBranch, MedialJunctions, _MedialAxis, medial_axis)
from mfgeom.core.medial import (  # noqa: F401
    BISECTOR_FORMS, ELEMENT_KINDS, MEDIAL_FULL, MEDIAL_KINDS, MedialSeam, MedialSheet,
    MedialSurface, MedialSurfaceJunctions, WALL_ANGLE, WallThickness, _convert_medial,
    _copy_array, _Medial, medial_surface, wall_thickness)


__all__ = [
    "BISECTOR_FORMS", "Cancelled", "ELEMENT_KINDS", "IN", "Intersection", "KINDS",
    "KIND_CODES", "LIBRARY_NAME", "LibraryError", "MEDIAL_FULL", "MEDIAL_KINDS",
    "MedialAxis", "MedialBranch", "MedialJunctions", "MedialSeam", "MedialSheet",
    "MedialSurface", "MedialSurfaceJunctions", "MeshReport", "MfgError", "MfgeomError",
    "ON", "OUT", "RAY_BLOCKED_NEG", "RAY_BLOCKED_POS", "RAY_GRAZES_NEG", "RAY_GRAZES_POS",
    "Region", "SweepResult", "VisibilityMap", "classify_points", "level_regions", "load",
    "max_intersection", "medial_axis", "medial_surface", "mesh_check", "min_intersection",
    "ray_blocked", "rotational_sweep", "sanitizers", "version", "visibility_map", "wall_thickness",
    "weld", "WALL_ANGLE", "WallThickness", "library_path"]

# The public classes keep the name they had when core was one module (tracebacks,
# reprs and pickles say mfgeom.core.MfgError, not mfgeom.core.status.MfgError).
for _cls in (Cancelled, MfgError, Region, VisibilityMap, Intersection, MeshReport,
             SweepResult, MedialAxis, MedialBranch, MedialJunctions, MedialSeam, MedialSheet,
             MedialSurface, MedialSurfaceJunctions, WallThickness):
    _cls.__module__ = __name__
del _cls

# The loader's hook that tests replace (``core._find_and_open = f``) is the loader's own.
_LOADER_HOOKS = frozenset({"_find_and_open"})


class _CoreModule(types.ModuleType):
    """mfgeom.core itself: ``core._loaded`` and ``core.library_path`` read the loader's
    state, and replacing a loader hook on core replaces it in the loader, as when core
    was one module."""

    @property
    def _loaded(self):
        """(CDLL, path) once loaded, else None."""
        return loader._loaded

    @property
    def library_path(self) -> str:
        """The path of the loaded library (loads it if needed)."""
        load()
        return loader._loaded[1]

    def __setattr__(self, name, value):
        if name in _LOADER_HOOKS:
            setattr(loader, name, value)
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _CoreModule
