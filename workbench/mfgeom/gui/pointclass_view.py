# SPDX-License-Identifier: LGPL-2.1-or-later
"""View provider of the point classification feature: the points coloured by class."""

from mfgeom import palette
from mfgeom.app import preferences


class ViewProviderPointClassification:
    """Shows the points coloured by class: IN green, ON orange, OUT red."""

    def __init__(self, vobj):
        vobj.Proxy = self
        self.Object = vobj.Object
        vobj.PointSize = preferences.point_size()
        self._colorize(vobj.Object)

    def attach(self, vobj):
        self.Object = vobj.Object

    def updateData(self, obj, prop):
        if prop in ("Classes", "Shape"):
            self._colorize(obj)

    def onChanged(self, vobj, prop):
        if prop == "Visibility" and vobj.Visibility:
            self._colorize(vobj.Object)

    @staticmethod
    def _colorize(obj):
        vobj = getattr(obj, "ViewObject", None)
        if vobj is None:
            return
        classes = list(obj.Classes)
        # Colours per vertex only make sense once Shape and Classes agree (they are set
        # one after the other in execute()).
        if len(classes) != len(obj.Shape.Vertexes):
            return
        vobj.PointColorArray = [palette.CLASS_COLORS.get(c, palette.UNKNOWN) for c in classes] \
            or [palette.UNKNOWN]

    def getIcon(self):
        from mfgeom import paths
        return paths.icon("mfgeom_classify_points.svg")

    # Double click or Edit opens the task panel of the command (default edit mode 0).
    def doubleClicked(self, vobj):
        import FreeCADGui
        FreeCADGui.ActiveDocument.setEdit(vobj.Object.Name, 0)
        return True

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None  # other modes (transform, ...) stay FreeCAD's
        import FreeCADGui
        if FreeCADGui.Control.activeDialog():
            return False
        from mfgeom.gui.pointclass_panel import PointClassificationPanel
        FreeCADGui.Control.showDialog(PointClassificationPanel(obj=vobj.Object))
        return True

    def unsetEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import FreeCADGui
        FreeCADGui.Control.closeDialog()
        return True

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None
