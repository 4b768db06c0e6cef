# SPDX-License-Identifier: LGPL-2.1-or-later
"""Where the workbench's icons and resources are (Init.py and InitGui.py have no __file__)."""

import os

# realpath: the workbench is usually installed as a symlink in FreeCAD's Mod folder,
# and the icons live beside workbench/ in the repository, not beside the link.
PACKAGE_DIR = os.path.dirname(os.path.realpath(__file__))
WORKBENCH_DIR = os.path.dirname(PACKAGE_DIR)
REPO_DIR = os.path.dirname(WORKBENCH_DIR)
RESOURCES_DIR = os.path.join(PACKAGE_DIR, "resources")


def _icon_dirs():
    # The repository layout keeps icons/ at the top; a copy of workbench/ alone may carry
    # them in resources/icons.
    yield os.path.join(REPO_DIR, "icons")
    yield os.path.join(RESOURCES_DIR, "icons")


def icons_dir():
    """The directory that holds the SVG icons (the first that exists)."""
    for directory in _icon_dirs():
        if os.path.isdir(directory):
            return directory
    return os.path.join(REPO_DIR, "icons")


def icon(name):
    """Absolute path of icon ``name`` (e.g. ``"mfgeom_workbench.svg"``)."""
    return os.path.join(icons_dir(), name)


def resource(name):
    """Absolute path of a file in mfgeom/resources (e.g. the preferences .ui)."""
    return os.path.join(RESOURCES_DIR, name)


# ------------------------------------------------------------------ FreeCAD outside FreeCAD
# Where FreeCAD's Python modules (FreeCAD.so, Part.so, ...) are: Debian/Ubuntu's package
# first; MFGEOM_FREECAD_LIB overrides.
FREECAD_LIB_DIRS = ("/usr/lib/freecad-python3/lib", "/usr/lib/freecad/lib",
                    "/usr/local/lib/freecad/lib", "/opt/freecad/lib")


def freecad_lib():
    """FreeCAD's lib directory (the one holding FreeCAD.so), or None."""
    env = os.environ.get("MFGEOM_FREECAD_LIB")
    for d in [env] if env else FREECAD_LIB_DIRS:
        if d and os.path.isdir(d) and any(n.startswith("FreeCAD.") and n.endswith(".so")
                                          for n in os.listdir(d)):
            return d
    return None


def freecad_part_dir(lib):
    """FreeCAD's Mod/Part (the Python half of the Part module) for lib directory ``lib``,
    or None.  FreeCAD 1.0's Part.so imports the Python module PartEnums from there (and
    crashes when it is missing, e.g. Part.makeCompound); inside FreeCAD that directory is
    on sys.path, in plain python3 it is not.  Mod/ sits beside lib/ under the home
    directory, or (Debian) in share/freecad, reached through /usr/lib/freecad/Mod."""
    if not lib:
        return None
    real = os.path.realpath(lib)
    cands = []
    for base in (lib, real):
        home = os.path.dirname(os.path.normpath(base))
        cands += [os.path.join(home, "Mod", "Part"),
                  os.path.join(os.path.dirname(os.path.dirname(home)), "share",
                               os.path.basename(home), "Mod", "Part"),
                  os.path.join(os.path.dirname(os.path.dirname(home)), "share", "freecad",
                               "Mod", "Part")]
    for d in cands:
        if os.path.isfile(os.path.join(d, "PartEnums.py")) or \
                os.path.isfile(os.path.join(d, "Init.py")):
            return d
    return None


def freecad_python_paths(lib=None):
    """The directories plain python3 needs on sys.path to import FreeCAD and Part: FreeCAD's
    lib directory and its Mod/Part ([] when FreeCAD is not found)."""
    lib = lib or freecad_lib()
    if not lib:
        return []
    part = freecad_part_dir(lib)
    return [lib] + ([part] if part else [])


def add_freecad_to_path(lib=None):
    """Appends freecad_python_paths() to sys.path (those not already there); returns the
    lib directory or None.  Call it before ``import FreeCAD`` outside FreeCAD."""
    import sys
    paths = freecad_python_paths(lib)
    for p in paths:
        if p not in sys.path:
            sys.path.append(p)
    return paths[0] if paths else None
