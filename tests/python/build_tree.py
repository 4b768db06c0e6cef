# SPDX-License-Identifier: LGPL-2.1-or-later
"""The CMake build tree of the library the binding loads: where the tests that replay a C
test program (abi_layout, test_implicit) find it."""

import os

from mfgeom import core


def build_dir():
    """The directory holding CMakeCache.txt above the loaded library, or None for a library
    that is not in a build tree (installed)."""
    directory = os.path.dirname(os.path.realpath(core.library_path))
    while True:
        if os.path.isfile(os.path.join(directory, "CMakeCache.txt")):
            return directory
        parent = os.path.dirname(directory)
        if parent == directory:
            return None
        directory = parent
