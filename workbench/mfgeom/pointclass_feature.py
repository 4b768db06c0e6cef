# SPDX-License-Identifier: LGPL-2.1-or-later
"""Compatibility: documents saved by mfgeom 0.1 name their proxies
``mfgeom.pointclass_feature.PointClassification`` and
``...ViewProviderPointClassification``; FreeCAD looks the classes up here when it opens
them.  The code lives in mfgeom.app.pointclass and mfgeom.gui.pointclass_view."""

import FreeCAD

from mfgeom.app.pointclass import PointClassification  # noqa: F401

if FreeCAD.GuiUp:
    from mfgeom.gui.pointclass_view import ViewProviderPointClassification  # noqa: F401
