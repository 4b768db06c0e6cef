# SPDX-License-Identifier: LGPL-2.1-or-later
"""View provider of the point classification feature: the points coloured by class, drawn
as one Coin point set per class (IN, ON, OUT in the colours of mfgeom.palette).

The coordinates reach Coin as numpy arrays (pivy takes them whole, ~0.1 us per point):
right after a recompute the points execute() classified, otherwise the float32 contents of
the feature's Points kernel under its placement matrix.  Per-point colours through a Part
compound's PointColorArray took seconds per 10^5 points.
"""

import numpy as np

from mfgeom import names, palette
from mfgeom.app import preferences
from mfgeom.gui.view_base import PanelViewProvider

DISPLAY_MODE = "Classes"
# Drawn in this order: ON last, so boundary points stay on top where classes overlap.
DRAW_ORDER = (names.OUT, names.IN, names.ON)


class ViewProviderPointClassification(PanelViewProvider):
    """Shows the classified points coloured by class (see mfgeom.palette.CLASS_COLORS)."""

    icon = "mfgeom_classify_points.svg"

    def __init__(self, vobj):
        vobj.Proxy = self
        self.Object = vobj.Object
        vobj.PointSize = preferences.point_size()
        # Also for an object that had no view provider (a document saved by freecadcmd):
        # its DisplayMode is Part's default, and setDisplayMode() is only asked on a change.
        vobj.DisplayMode = DISPLAY_MODE

    def attach(self, vobj):
        from pivy import coin
        self.Object = vobj.Object
        self._root = coin.SoSeparator()
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR  # flat colours: no shading of points
        self._style = coin.SoDrawStyle()
        self._style.pointSize = vobj.PointSize
        # The kernel's placement (points read back from a saved kernel stay local)
        self._placement = coin.SoMatrixTransform()
        self._root.addChild(light)
        self._root.addChild(self._style)
        self._root.addChild(self._placement)
        self._sets = {}
        for cls in DRAW_ORDER:
            group = coin.SoSeparator()
            color = coin.SoBaseColor()
            color.rgb.setValue(*palette.CLASS_COLORS[cls])
            coords = coin.SoCoordinate3()
            points = coin.SoPointSet()
            for node in (color, coords, points):
                group.addChild(node)
            self._root.addChild(group)
            self._sets[cls] = (coords, points)
        vobj.addDisplayMode(self._root, DISPLAY_MODE)
        self._show(vobj.Object)

    def finishRestoring(self, vobj=None):
        # Documents of version < 3 saved Part's modes ("Flat Lines", "Points"); restored
        # before this proxy was attached, they never went through setDisplayMode().
        # (FreeCAD 0.20 passes no argument here.)
        vobj = vobj if vobj is not None else self.Object.ViewObject
        if vobj.DisplayMode != DISPLAY_MODE:
            vobj.DisplayMode = DISPLAY_MODE

    def getDisplayModes(self, vobj):
        return [DISPLAY_MODE]

    def getDefaultDisplayMode(self):
        return DISPLAY_MODE

    def setDisplayMode(self, mode):
        # The Shape is empty: Part's modes ("Flat Lines", "Points", ... saved in older
        # documents) would show nothing, so every mode shows the classified points.
        return DISPLAY_MODE

    def updateData(self, obj, prop):
        # Classes is written after Points in execute(), and after restoring a document:
        # one refresh per recompute.
        if prop == "Classes":
            self._show(obj)

    def onChanged(self, vobj, prop):
        if prop == "PointSize" and getattr(self, "_style", None) is not None:
            self._style.pointSize = vobj.PointSize

    def bound_box(self):
        """(min, max) corners of what the point sets draw, in document coordinates."""
        from pivy import coin
        action = coin.SoGetBoundingBoxAction(coin.SbViewportRegion())
        action.apply(self._root)
        box = action.getBoundingBox()
        return tuple(box.getMin().getValue()), tuple(box.getMax().getValue())

    def is_shown(self, vobj):
        """Whether the 3D view draws our point sets (visible, and our display mode is the
        active child of the object's mode switch)."""
        switch = vobj.SwitchNode
        which = switch.whichChild.getValue()
        return bool(vobj.Visibility) and 0 <= which < switch.getNumChildren() and \
            switch.getChild(which) == self._root

    def counts_shown(self):
        """Number of points drawn per class (for tests and reports)."""
        sets = getattr(self, "_sets", {})
        return {cls: sets[cls][1].numPoints.getValue() if cls in sets else 0
                for cls in DRAW_ORDER}

    def _show(self, obj):
        if getattr(self, "_sets", None) is None or "Points" not in obj.PropertiesList:
            return
        from mfgeom.app import pointcloud
        classes = np.asarray(obj.Classes, dtype=np.uint8)
        matrix = np.eye(4)
        # execute() hands over the points it classified (global coordinates) while it
        # writes Classes; otherwise (a restore, an undo) they come from the kernel.
        points = getattr(obj.Proxy, "display_points", None)
        if points is not None and len(points) == len(classes):
            points = points.astype(np.float32)
        elif obj.Points.CountPoints == len(classes):
            points, matrix = pointcloud.kernel_local(obj.Points)
        else:  # Classes and Points disagree until execute() (or a restore) wrote both
            classes = np.zeros(0, dtype=np.uint8)
            points = np.zeros((0, 3), dtype=np.float32)
        # Coin multiplies row vectors: its matrix is the transpose of FreeCAD's
        from pivy import coin
        self._placement.matrix.setValue(coin.SbMatrix(*matrix.T.ravel().tolist()))
        for cls, (coords, point_set) in self._sets.items():
            selected = points[classes == cls]
            coords.point.setNum(len(selected))
            if len(selected):
                coords.point.setValues(0, len(selected), selected)
            point_set.numPoints = len(selected)

    def make_panel(self, obj):
        from mfgeom.gui.pointclass_panel import PointClassificationPanel
        return PointClassificationPanel(obj=obj)
