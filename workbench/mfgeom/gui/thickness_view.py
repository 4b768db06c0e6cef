# SPDX-License-Identifier: LGPL-2.1-or-later
"""View provider of the wall-thickness analysis (issue 21, section 4): display mode
"Thickness" (default) draws the analysis' samples as a mesh over the part coloured per
vertex -- the blue ramp inside the user's window [MinThickness, MaxThickness], thin walls
pink, thick walls brown (mfgeom.palette.wall_colors) -- with the legend (the window's
scale and the two highlight swatches) and the thinnest and thickest spots marked with
their values; Part's modes show the two spots as plain points."""

import numpy as np

from mfgeom import palette
from mfgeom.gui.medial_view import ColouredSheets, Legend, LegendViewProvider, THICKNESS_MODE

MARKER_SIZE = 9   # Coin's CIRCLE_FILLED_9_9 / CROSS_9_9 markers


class ViewProviderThicknessAnalysis(LegendViewProvider):
    """The samples coloured by wall thickness, the legend and the extreme spots."""

    icon = "mfgeom_thickness.svg"

    def __init__(self, vobj):
        vobj.Proxy = self
        self.Object = vobj.Object

    def attach(self, vobj):
        from pivy import coin
        self.Object = vobj.Object
        root = coin.SoSeparator()
        self.samples = ColouredSheets()
        root.addChild(self.samples.node)
        marks = coin.SoSeparator()
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        colour = coin.SoBaseColor()
        colour.rgb.setValue(*palette.WALL_MARK)
        self._mark_coords = coin.SoCoordinate3()
        self._marks = coin.SoMarkerSet()
        self._marks.markerIndex = getattr(coin.SoMarkerSet, "CIRCLE_FILLED_9_9", 1)
        self._labels = coin.SoSeparator()
        # drawn over the part: a spot inside a pocket stays visible
        annotation = coin.SoAnnotation()
        for node in (light, colour, self._mark_coords, self._marks, self._labels):
            annotation.addChild(node)
        marks.addChild(annotation)
        root.addChild(marks)
        self.legend = Legend()
        root.addChild(self.legend.node)
        vobj.addDisplayMode(root, THICKNESS_MODE)
        self._draw(vobj.Object)
        self._arrange(vobj)

    def updateData(self, obj, prop):
        if prop in ("Thinnest", "MinThickness", "MaxThickness"):   # Thinnest: the last result
            self._draw(obj)

    def make_panel(self, obj):
        from mfgeom.gui.thickness_panel import ThicknessPanel
        return ThicknessPanel(obj=obj)

    def _draw(self, obj):
        if getattr(self, "samples", None) is None or "VertexThickness" not in obj.PropertiesList:
            return
        from pivy import coin
        pts = np.array([(p.x, p.y, p.z) for p in obj.SamplePoints], dtype=np.float64)
        thick = np.asarray(obj.VertexThickness, dtype=np.float64)
        tris = np.asarray(obj.SampleFacets, dtype=np.int64).reshape(-1, 3)
        lo, hi = float(obj.MinThickness.Value), float(obj.MaxThickness.Value)
        if len(pts) != len(thick) or not len(thick):
            self.samples.update([], [], [])
            self.legend.update(lo, hi, "Wall thickness", palette.WALL_RAMP)
            self._mark_coords.point.setNum(0)
            self._labels.removeAllChildren()
            return
        self.samples.update(pts, tris, thick, palette.wall_colors(thick, lo, hi))
        self.legend.update(lo, hi, "Wall thickness", palette.WALL_RAMP,
                           [(palette.THIN_WALL, f"thin < {lo:.3g} mm"),
                            (palette.THICK_WALL, f"thick > {hi:.3g} mm")])
        spots = [(obj.ThinnestPoint, f"thinnest {obj.Thinnest:.3g} mm"),
                 (obj.ThickestPoint, f"thickest {obj.Thickest:.3g} mm")]
        self._mark_coords.point.setValues(0, 2, [(p.x, p.y, p.z) for p, _t in spots])
        self._labels.removeAllChildren()
        self.mark_labels = []
        for p, text in spots:
            sep = coin.SoSeparator()
            move = coin.SoTranslation()
            move.translation.setValue(p.x, p.y, p.z)
            font = coin.SoFont()
            font.size = 14.0
            label = coin.SoText2()
            label.string = "  " + text
            for node in (move, font, label):
                sep.addChild(node)
            self._labels.addChild(sep)
            self.mark_labels.append(text)
