# SPDX-License-Identifier: LGPL-2.1-or-later
# GUI start-up of the Manufacturing Geometry workbench: registers the workbench only.
#
# Commands and the preferences page are loaded in Initialize(), i.e. when the workbench is
# first activated, so FreeCAD's start-up stays fast.  The C library is loaded on first use;
# when it is missing (an Addon Manager install has none), activating the workbench offers
# to build it (mfgeom.gui.library).  __file__ is not defined here: paths come from
# mfgeom.paths.

import FreeCADGui


class MfgeomWorkbench(FreeCADGui.Workbench):
    """Manufacturing Geometry: tolerance-aware geometry for CAD/CAM (libmfgeom)."""

    MenuText = "Manufacturing Geometry"
    ToolTip = ("Tolerance-aware manufacturing geometry: point classification against faces, "
               "parting analysis (mould core / cavity / undercut, NC set-ups, draft and ray "
               "checks), rotational sweep with clearance check, medial surface, mid-surface "
               "for FEM and medial axis")

    def __init__(self):
        from mfgeom import paths
        self.__class__.Icon = paths.icon("mfgeom_workbench.svg")

    def Initialize(self):
        from mfgeom import paths
        from mfgeom.gui import commands
        FreeCADGui.addIconPath(paths.icons_dir())
        self.appendToolbar("Manufacturing Geometry", commands.COMMAND_NAMES)
        self.appendMenu("&Manufacturing Geometry", commands.COMMAND_NAMES)
        FreeCADGui.addPreferencePage(paths.resource("preferences.ui"), "Manufacturing Geometry")

    def Activated(self):
        from mfgeom.gui import library
        library.offer_on_activation()

    def Deactivated(self):
        pass

    def GetClassName(self):
        return "Gui::PythonWorkbench"


FreeCADGui.addWorkbench(MfgeomWorkbench())
