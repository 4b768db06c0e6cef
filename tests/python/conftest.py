# SPDX-License-Identifier: LGPL-2.1-or-later
"""pytest configuration: makes the exact reference and (if not already on the path) the workbench package importable."""

import os
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.dirname(os.path.dirname(_HERE))

if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
# Appended, so that PYTHONPATH (e.g. an installed or alternative mfgeom) takes precedence.
_WORKBENCH = os.path.join(_REPO, "workbench")
if _WORKBENCH not in sys.path:
    sys.path.append(_WORKBENCH)
