# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI commands of the Manufacturing Geometry workbench (registered on import)."""

import importlib

import FreeCAD
import FreeCADGui

from mfgeom import paths
from mfgeom.errors import InputError
from mfgeom.gui.messages import warn


class BaseCommand:
    """Supplies GetResources() from class attributes, a default IsActive(), and the
    steps every command takes before its task panel: the library is there (or offered
    to be built), no other panel is open, the selection is usable.  Subclasses set
    ``icon``, ``menu_text``, ``tooltip`` and implement ``panel_for(selection)``, which
    returns the task panel or raises an InputError whose text is shown."""

    icon = ""
    menu_text = ""
    tooltip = ""

    def GetResources(self):
        return {"Pixmap": paths.icon(self.icon), "MenuText": self.menu_text,
                "ToolTip": self.tooltip}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None

    def panel_for(self, selection):
        raise NotImplementedError

    def Activated(self):
        title = self.menu_text
        from mfgeom.gui import library    # no libmfgeom.so: offer to build it, or say why
        if not library.ensure_library(title):
            return
        # Loaded here so a missing libmfgeom.so is reported, not a dead workbench.
        try:
            importlib.import_module("mfgeom.core")
        except ImportError as exc:
            warn(title, f"The mfgeom library could not be loaded:\n{exc}")
            return
        if FreeCADGui.Control.activeDialog():
            warn(title, "A task panel is open: close it first (OK or Cancel).")
            return
        selection = [(s.Object, list(s.SubElementNames))
                     for s in FreeCADGui.Selection.getSelectionEx()]
        try:
            panel = self.panel_for(selection)
        except InputError as exc:
            warn(title, str(exc))
            return
        FreeCADGui.Control.showDialog(panel)


class ClassifyPointsCommand(BaseCommand):
    """Classify the selected points against the selected face (IN / ON / OUT)."""

    icon = "mfgeom_classify_points.svg"
    menu_text = "Classify points"
    tooltip = ("Classify points against a face with a tolerance: IN (blue), ON the "
               "boundary (within the tolerance; light cyan) or OUT (wine).\nSelect one face "
               "(planar or curved) and the points: a Points object, a Mesh, a sketch, a Part "
               "object or vertices;\n"
               "a task panel then asks for the tolerance.")

    def panel_for(self, selection):
        from mfgeom.app import refs
        from mfgeom.gui.pointclass_panel import PointClassificationPanel
        face_ref, points_ref = refs.refs_from_selection(selection)
        # The panel asks for tolerance, Strict and point size; its OK creates the feature.
        return PointClassificationPanel(face_ref, points_ref)


class PartingAnalysisCommand(BaseCommand):
    """Mould parting direction or NC set-up plan of the selected solid (or its faces)."""

    icon = "mfgeom_parting.svg"
    menu_text = "Parting analysis"
    tooltip = ("Mould parting direction (core / cavity sides, undercuts, side cores) or a "
               "3-axis NC set-up plan of a solid.\nSelect a solid, or some of its faces; a "
               "task panel then asks for the mode, draft angle and weighting.\nThe result: "
               "the faces coloured, an arrow per direction and a visibility sphere.")

    def panel_for(self, selection):
        from mfgeom.gui import parting_panel
        source, faces = parting_panel.source_from_selection(selection)
        return parting_panel.PartingPanel(source, faces)


class RotationalSweepCommand(BaseCommand):
    """The volume a solid sweeps turning about an axis (issue 8)."""

    icon = "RotationalSweep.svg"
    menu_text = "Rotational sweep"
    tooltip = ("The volume a solid sweeps while it turns about an axis by an angle.\n"
               "Select a solid and a straight edge or datum line as the axis (or only the "
               "solid and choose a global axis X / Y / Z in the task panel);\nthe panel asks "
               "for the angle, tolerance, deflection of curved faces and Mesh or Solid.")

    def panel_for(self, selection):
        from mfgeom.gui import sweep_panel
        source, axis = sweep_panel.inputs_from_selection(selection)
        return sweep_panel.SweepPanel(source, axis)


class MedialAxisCommand(BaseCommand):
    """The medial axis of a planar face, with the clearance radius along it (issue 9)."""

    icon = "mfgeom_medial_axis.svg"
    menu_text = "Medial axis of face"
    tooltip = ("The medial axis of a planar face (centres of the largest inscribed discs) "
               "as wires on the face,\nwith the clearance radius along them.\nSelect one "
               "planar face; the task panel asks for the tolerance.")

    def panel_for(self, selection):
        from mfgeom.gui import medial_panel
        return medial_panel.MedialAxisPanel(medial_panel.face_from_selection(selection))


class MedialSurfaceCommand(BaseCommand):
    """The medial surface of a solid, coloured by wall thickness (issue 9)."""

    icon = "mfgeom_medial_surface.svg"
    menu_text = "Medial surface"
    tooltip = ("The medial surface of a solid (centres of the largest inscribed balls): "
               "sheets coloured by the wall thickness (2 x radius),\nseams and junctions.\n"
               "Select a solid (planar faces; curved ones are tessellated); the task panel "
               "asks for the tolerance, major part only and the deflection.")

    def panel_for(self, selection):
        from mfgeom.gui import medial_panel
        return medial_panel.MedialSurfacePanel(medial_panel.solid_from_selection(selection))


class MidSurfaceCommand(BaseCommand):
    """The FEM mid-surface of a thin-walled part with its thickness (issue 9)."""

    icon = "mfgeom_mid_surface.svg"
    menu_text = "Mid-surface for FEM"
    tooltip = ("The mid-surface of a thin-walled part as a shell, with the local "
               "thickness as data:\na thickness report (min / max / mean / histogram) in the "
               "Report view and a CSV file.\nSelect the solid or its medial surface.")

    def panel_for(self, selection):
        from mfgeom.gui import medial_panel
        return medial_panel.MidSurfacePanel(
            medial_panel.solid_from_selection(selection, allow_medial=True))


class _MouldCommand(BaseCommand):
    """A mould command (issue 21): its task panel on the selected input."""

    KIND = ""

    def panel_for(self, selection):
        from mfgeom.gui import mould_panel
        return mould_panel.command_panel(self.KIND, selection)


class PartingLineCommand(_MouldCommand):
    """The parting line of a Mould parting analysis."""

    KIND = "line"
    icon = "mfgeom_parting_line.svg"
    menu_text = "Parting line"
    tooltip = ("The parting line of a mould: closed loops where the core side (+d) meets "
               "the cavity side (-d),\ncurved faces split along their silhouettes.\n"
               "Select a parting analysis in Mould mode.")


class PartingSurfaceCommand(_MouldCommand):
    """Parting and shut-off surfaces of a parting line."""

    KIND = "surface"
    icon = "mfgeom_parting_surface.svg"
    menu_text = "Parting surface"
    tooltip = ("Parting surfaces from the parting line out to the mould block, and "
               "shut-off surfaces filling through-holes.\nSelect a parting line.")


class MouldBlocksCommand(_MouldCommand):
    """Core, cavity and side-core inserts of a Mould parting analysis."""

    KIND = "blocks"
    icon = "mfgeom_mould_blocks.svg"
    menu_text = "Core and cavity"
    tooltip = ("Split a block around the part into core (+d), cavity (-d) and side-core "
               "inserts, checked (volumes, validity, demoulding).\nSelect a parting "
               "analysis in Mould mode; the parting line and surface are made too.")


class ThicknessAnalysisCommand(BaseCommand):
    """Wall thickness of a solid from its medial surface (issue 21, section 4)."""

    icon = "mfgeom_thickness.svg"
    menu_text = "Thickness analysis"
    tooltip = ("Wall thickness of a moulded part: the diameter of the largest inscribed "
               "ball touching each point,\ncoloured on the part (pink: thinner than the "
               "minimum, brown: thicker than the maximum),\nthe thinnest and thickest spots "
               "marked, a histogram and CSV.\nSelect a solid; the task panel asks for the "
               "thresholds.")

    def panel_for(self, selection):
        from mfgeom.gui import medial_panel, thickness_panel
        return thickness_panel.ThicknessPanel(medial_panel.solid_from_selection(selection))


COMMANDS = {"Mfgeom_PartingAnalysis": PartingAnalysisCommand(),
            "Mfgeom_ClassifyPoints": ClassifyPointsCommand(),
            "Mfgeom_RotationalSweep": RotationalSweepCommand()}

# The clearance check of a swept volume (issue 8); last, after the sweep it checks.
from mfgeom.gui.clearance_command import ClearanceCheckCommand  # noqa: E402
COMMANDS["Mfgeom_ClearanceCheck"] = ClearanceCheckCommand()
# The medial axis and surface (issue 9).
COMMANDS["Mfgeom_MedialAxis"] = MedialAxisCommand()
COMMANDS["Mfgeom_MedialSurface"] = MedialSurfaceCommand()
COMMANDS["Mfgeom_MidSurface"] = MidSurfaceCommand()
# The mould tooling on top of the parting analysis (issue 21).
COMMANDS["Mfgeom_PartingLine"] = PartingLineCommand()
COMMANDS["Mfgeom_PartingSurface"] = PartingSurfaceCommand()
COMMANDS["Mfgeom_MouldBlocks"] = MouldBlocksCommand()
COMMANDS["Mfgeom_ThicknessAnalysis"] = ThicknessAnalysisCommand()

for _name, _command in COMMANDS.items():
    FreeCADGui.addCommand(_name, _command)

COMMAND_NAMES = list(COMMANDS)
