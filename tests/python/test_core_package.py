# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.core is a package (loader, status, arrays, one module per C family) that
re-exports every name the one-module core.py had (main 60b4e35): the public API and the
private helpers that tests, benchmarks and the workbench use.  These lists were taken
from that core.py; a name may be added, none may go."""

import inspect
import os
import subprocess
import sys

import pytest

from mfgeom import core

# Every public name of core.py except the modules it imported (ctypes, np, os, ...).
PUBLIC = """BISECTOR_FORMS Cancelled ELEMENT_KINDS IN Intersection KINDS KIND_CODES
LIBRARY_NAME LibraryError MEDIAL_FULL MEDIAL_KINDS MedialAxis MedialBranch MedialJunctions
MedialSeam MedialSheet MedialSurface MedialSurfaceJunctions MeshReport MfgError MfgeomError
ON OUT RAY_BLOCKED_NEG RAY_BLOCKED_POS RAY_GRAZES_NEG RAY_GRAZES_POS Region SweepResult
VisibilityMap classify_points level_regions load max_intersection medial_axis
medial_surface mesh_check min_intersection ray_blocked rotational_sweep sanitizers version
visibility_map weld library_path""".split()
# Added since (a name may be added): the wall thickness (issue 21, section 4).
PUBLIC += ["WALL_ANGLE", "WallThickness", "wall_thickness"]

# Every private name of core.py but its loop variables (_name, _extra).
PRIVATE = """_Function _Library _MESH_ARGS _MESH_COUNTS _Medial _MedialAxis _Mesh _MeshReport
_PROGRESS_FN _Progress _ProgressCall _REGION_ARGS _RegionInfo _Regions _SANITIZERS _SPoly
_SweepStats _as_float _as_float_array _as_indices _as_points _as_triangles _as_vector3
_as_vertices _c_double_p _c_int32_p _c_int64_p _c_progress_p _c_uint8_p _call_regions
_check _convert_medial _copy_array _elf_dynamic_names _find_and_open _flatten_maps
_flatten_rings _lib _load_lock _loaded _not_found _open _ptr _runtime_missing
_search_places""".split()

NAMES = [name for name in PUBLIC if name != "library_path"]   # getattr would load

MODULES = ("loader", "status", "arrays", "pointclass", "sphere", "mesh", "sweep", "axis2d",
           "medial")


def test_every_public_name_of_the_one_module_core_is_there():
    missing = [name for name in NAMES if not hasattr(core, name)]
    assert missing == []
    assert sorted(core.__all__) == sorted(PUBLIC)


def test_every_private_name_of_the_one_module_core_is_there():
    assert [name for name in PRIVATE if not hasattr(core, name)] == []


def test_names_are_one_object_whichever_module_they_are_reached_by():
    import mfgeom.core as other
    assert other is core
    from mfgeom.core import arrays, loader, medial, sphere, status
    assert core._lib is loader._lib and core.load is loader.load
    assert core.MfgError is status.MfgError and core._ptr is arrays._ptr
    assert core.medial_surface is medial.medial_surface
    assert core.VisibilityMap is sphere.VisibilityMap


def test_public_classes_keep_their_module_name():
    for name in NAMES:
        obj = getattr(core, name, None)
        if inspect.isclass(obj) and obj.__module__.startswith("mfgeom.core"):
            assert obj.__module__ == "mfgeom.core", name


def test_family_modules_import_on_their_own():
    """Each module of the package can be imported first, in a fresh interpreter (no
    module relies on another having been imported by __init__), and none loads the
    library."""
    workbench = os.path.join(os.path.dirname(__file__), "..", "..", "workbench")
    for module in MODULES:
        code = (f"import sys; import mfgeom.core.{module} as m; "
                "print('libmfgeom' in open('/proc/self/maps').read())")
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                              env=dict(os.environ, PYTHONPATH=os.path.abspath(workbench)))
        assert proc.returncode == 0, (module, proc.stderr)
        assert proc.stdout.strip() == "False", module


def test_public_functions_have_type_hints():
    for name in NAMES:
        obj = getattr(core, name, None)
        functions = []
        if inspect.isfunction(obj):
            functions = [(name, obj)]
        elif inspect.isclass(obj) and obj.__module__ == "mfgeom.core":
            functions = [(f"{name}.{attr}", fn) for attr, fn in vars(obj).items()
                         if inspect.isfunction(fn) and not attr.startswith("_")]
        for label, fn in functions:
            sig = inspect.signature(fn)
            unhinted = [p.name for p in sig.parameters.values()
                        if p.name != "self" and p.annotation is inspect.Parameter.empty]
            assert unhinted == [], f"{label}: no hint for {unhinted}"
            assert sig.return_annotation is not inspect.Signature.empty, \
                f"{label}: no return hint"


def test_loaded_and_find_and_open_are_the_loaders(monkeypatch):
    from mfgeom.core import loader
    assert core._loaded is loader._loaded
    real = loader._find_and_open
    try:
        core._find_and_open = real      # replacing it on core replaces it in the loader
        assert loader._find_and_open is real
        sentinel = object()
        core._find_and_open = sentinel
        assert loader._find_and_open is sentinel
    finally:
        core._find_and_open = real
    assert loader._find_and_open is real


@pytest.mark.parametrize("name", ["__wrapped__", "no_such_name"])
def test_unknown_names_raise_attribute_error(name):
    with pytest.raises(AttributeError):
        getattr(core, name)
