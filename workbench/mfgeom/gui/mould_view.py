# SPDX-License-Identifier: LGPL-2.1-or-later
"""View providers of the mould features (issue 21): the parting line drawn thick in the
parting colour, the parting surface half transparent, the core, cavity and inserts each
in its side's colour (mfgeom.palette).  Double click or Edit opens the task panel."""

from mfgeom import palette
from mfgeom.gui.view_base import PanelViewProvider

LINE_WIDTH = 5.0
SURFACE_TRANSPARENCY = 40
BLOCK_TRANSPARENCY = 30


class _MouldView(PanelViewProvider):
    KIND = ""

    def __init__(self, vobj):
        vobj.Proxy = self
        self.Object = vobj.Object
        self._style(vobj)

    def _style(self, vobj):
        """The look of a new object."""

    def attach(self, vobj):
        self.Object = vobj.Object

    def make_panel(self, obj):
        from mfgeom.gui.mould_panel import MouldPanel
        return MouldPanel(self.KIND, obj=obj)

    def updateData(self, obj, prop):
        pass

    def onChanged(self, vobj, prop):
        pass


class ViewProviderPartingLine(_MouldView):
    icon = "mfgeom_parting_line.svg"
    KIND = "line"

    def _style(self, vobj):
        vobj.LineWidth = LINE_WIDTH
        vobj.LineColor = palette.PARTING_LINE
        vobj.PointColor = palette.PARTING_LINE


class ViewProviderPartingSurface(_MouldView):
    icon = "mfgeom_parting_surface.svg"
    KIND = "surface"

    def _style(self, vobj):
        vobj.ShapeColor = palette.PARTING_SURFACE
        vobj.Transparency = SURFACE_TRANSPARENCY


def block_colours(obj):
    """Per face of a MouldBlocks' Shape (core, cavity, then the inserts) its colour."""
    colours = [palette.MOULD_CORE] * len(obj.Core.Faces)
    colours += [palette.MOULD_CAVITY] * len(obj.Cavity.Faces)
    colours += [palette.MOULD_INSERT] * (len(obj.Shape.Faces) - len(colours))
    return colours


class ViewProviderMouldBlocks(_MouldView):
    icon = "mfgeom_mould_blocks.svg"
    KIND = "blocks"

    def _style(self, vobj):
        vobj.Transparency = BLOCK_TRANSPARENCY

    def updateData(self, obj, prop):
        if prop == "Shape" and obj.ViewObject is not None and not obj.Shape.isNull():
            vobj = obj.ViewObject
            transparency = vobj.Transparency
            vobj.DiffuseColor = [c + (transparency / 100.0,) for c in block_colours(obj)]
            vobj.Transparency = transparency   # setting DiffuseColor resets it in 0.20
