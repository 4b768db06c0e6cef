# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI commands of the Manufacturing Geometry workbench (registered on import)."""

import importlib

import FreeCAD
import FreeCADGui

from mfgeom import paths


class BaseCommand:
    """Supplies GetResources() from class attributes and a default IsActive()."""

    icon = ""
    menu_text = ""
    tooltip = ""

    def GetResources(self):
        return {"Pixmap": paths.icon(self.icon), "MenuText": self.menu_text,
                "ToolTip": self.tooltip}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None


def _warn(title, text):
    from PySide import QtGui
    FreeCAD.Console.PrintWarning(f"mfgeom: {text}\n")
    QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), title, text)


class ClassifyPointsCommand(BaseCommand):
    """Classify the selected points against the selected face (IN / ON / OUT)."""

    icon = "mfgeom_classify_points.svg"
    menu_text = "Classify points"
    tooltip = ("Classify points against a face with a tolerance: IN (green), ON the "
               "boundary (orange) or OUT (red).\nSelect one face (planar or curved) and "
               "the points: a Points object, a Mesh, a sketch, a Part object or vertices.")

    def Activated(self):
        title = "Classify points"
        # Loaded here so a missing libmfgeom.so is reported, not a dead workbench.
        try:
            importlib.import_module("mfgeom.core")
            from mfgeom.app import pointclass as pointclass_feature, preferences, refs
        except ImportError as exc:
            _warn(title, f"The mfgeom library could not be loaded:\n{exc}")
            return
        selection = [(s.Object, list(s.SubElementNames))
                     for s in FreeCADGui.Selection.getSelectionEx()]
        try:
            face_ref, points_ref = refs.refs_from_selection(selection)
        except refs.InputError as exc:
            _warn(title, str(exc))
            return
        doc = face_ref[0].Document
        doc.openTransaction(title)
        try:
            obj = pointclass_feature.make_point_classification(
                doc, face_ref, points_ref, preferences.default_tolerance())
        except (ValueError, TypeError, RuntimeError) as exc:  # core.MfgError is a RuntimeError
            doc.abortTransaction()
            _warn(title, str(exc))
            return
        src = points_ref[0]
        if src.isDerivedFrom("Points::Feature") and src.ViewObject is not None:
            src.ViewObject.Visibility = False  # our coloured copy sits on top of it
        doc.commitTransaction()
        FreeCADGui.Selection.clearSelection()
        FreeCAD.Console.PrintMessage(
            f"mfgeom: {obj.Label}: IN {obj.CountIn}, ON {obj.CountOn}, OUT {obj.CountOut} "
            f"(tolerance {obj.Tolerance.Value:g} mm)\n")


COMMANDS = {"Mfgeom_ClassifyPoints": ClassifyPointsCommand()}

for _name, _command in COMMANDS.items():
    FreeCADGui.addCommand(_name, _command)

COMMAND_NAMES = list(COMMANDS)
