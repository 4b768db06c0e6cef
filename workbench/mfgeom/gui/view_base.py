# SPDX-License-Identifier: LGPL-2.1-or-later
"""What every mfgeom view provider shares: its icon, editing the object in the feature's
task panel (double click or Edit), and persistence (nothing to save: all state is in
the object's properties)."""

from mfgeom import paths


class PanelViewProvider:
    """Base of the view providers.  Subclasses set ``icon`` and implement
    ``make_panel(obj)``, the task panel that edits ``obj``."""

    icon = ""

    def make_panel(self, obj):
        raise NotImplementedError

    def getIcon(self):
        return paths.icon(self.icon)

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
        FreeCADGui.Control.showDialog(self.make_panel(vobj.Object))
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
