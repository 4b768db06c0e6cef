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
