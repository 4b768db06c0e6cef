# SPDX-License-Identifier: LGPL-2.1-or-later
"""View providers of the medial features (issue 9) and the colour legend they share.

* Medial axis of a face: display mode "Width": its wires coloured per point by the
  face's local width (2 x clearance radius) on the same ramp, the junctions as black
  points, and the legend; Part's modes show the plain wires.
* Medial surface: display mode "Thickness": the sheets as one Coin indexed face set
  coloured per vertex by thickness (2 x radius, mfgeom.palette.THICKNESS_RAMP), the seams
  as black lines, the junctions as black points, and the legend of the colour scale.
* FEM mid-surface: display mode "Thickness" (default): its medial surface's sheets
  coloured per point by the mid-surface's Thickness, with the legend; Part's display
  modes show the shell itself.

The legend is drawn in the 3-D view itself (so screenshots carry it): an overlay with its
own orthographic camera at the view's left edge, a bar of the ramp and the thickness at
its ends and quarters in mm, in an SoAnnotation (drawn last, over the model), unpickable
and left out of the bounding box (so View > Fit all ignores it).

Several legends shown at once in a document's views (a medial axis' width and a medial
surface's thickness) are stacked down the left edge, not drawn over each other: each
takes the next free slot when its feature is shown, in the order they were shown; a
feature hidden, switched to another display mode, deleted or undone frees its slot and
the legends below move up.  They share the lone legend's band (with a gap for each
title), so none leaves the view however many are shown (``arrange_legends``).
"""

import math

import numpy as np

from mfgeom import palette
# The tick texts are the panels' too: they live in palette (FreeCAD-free).
from mfgeom.palette import LEGEND_STEPS, legend_labels  # noqa: F401
from mfgeom.gui.view_base import PanelViewProvider

THICKNESS_MODE = "Thickness"
WIDTH_MODE = "Width"
# The bar in the overlay camera's unit square (x, y in [-1, 1] across the whole view).
LEGEND_X = (-0.96, -0.91)
LEGEND_Y = (-0.6, 0.6)      # the lone legend's bar; stacked bars share this band
LEGEND_GAP = 0.2            # between stacked bars: room for the lower one's title
LEGEND_SHORT = 0.4          # a shorter bar is labelled at its ends and middle only


def legend_span(slot, count):
    """(y0, y1) of the bar in ``slot`` (0: the top) of ``count`` stacked legends."""
    y0, y1 = LEGEND_Y
    count = max(int(count), 1)
    height = (y1 - y0 - (count - 1) * LEGEND_GAP) / count
    top = y1 - slot * (height + LEGEND_GAP)
    return top - height, top


class Legend:
    """The colour-scale overlay: ``node`` goes into a view provider's root; ``update(lo,
    hi, title)`` redraws it; ``place(slot, count)`` moves it to its slot of the stack
    (``arrange_legends``).  ``order`` is its place in the stack while shown, else None."""

    def __init__(self):
        from pivy import coin
        self.node = coin.SoAnnotation()
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        camera = coin.SoOrthographicCamera()
        # LEAVE_AS_IS (4 in Coin's enum; pivy does not export the name everywhere): the
        # unit square spans the whole view whatever its aspect ratio
        camera.viewportMapping = getattr(coin.SoOrthographicCamera, "LEAVE_AS_IS", 4)
        camera.position.setValue(0, 0, 5)
        camera.height = 2.0
        camera.nearDistance = 1.0
        camera.farDistance = 10.0
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        # its own line width and point size, whatever the view provider's root set
        style = coin.SoDrawStyle()
        style.lineWidth = 1.0
        style.pointSize = 1.0
        self._bar = coin.SoSeparator()
        self._text = coin.SoSeparator()
        # Empties the bounding box the overlay adds: Fit all frames the model only.
        reset = coin.SoResetTransform()
        reset.whatToReset = coin.SoResetTransform.BBOX
        for n in (pick, camera, light, style, self._bar, self._text, reset):
            self.node.addChild(n)
        self.labels = []
        self.slot, self.count, self.order = 0, 1, None
        self._scale = (0.0, 0.0, "Thickness")

    @property
    def span(self):
        """(y0, y1) of the bar in the overlay's unit square."""
        return legend_span(self.slot, self.count)

    def place(self, slot, count):
        if (slot, count) != (self.slot, self.count):
            self.slot, self.count = slot, count
            self._redraw()

    def update(self, lo, hi, title="Thickness", ramp=None, notes=()):
        """``ramp``: the bar's colours (default palette.THICKNESS_RAMP); ``notes``:
        (colour, text) swatches drawn below the bar (the thickness analysis' thin and
        thick colours)."""
        self._scale = (lo, hi, title)
        self._ramp = ramp or palette.THICKNESS_RAMP
        self._notes = list(notes)
        self._redraw()

    def _redraw(self):
        from pivy import coin
        lo, hi, title = self._scale
        self._bar.removeAllChildren()
        self._text.removeAllChildren()
        n = 32
        x0, x1 = LEGEND_X
        y0, y1 = self.span
        steps = LEGEND_STEPS if y1 - y0 >= LEGEND_SHORT else 2
        ys = [y0 + (y1 - y0) * k / n for k in range(n + 1)]
        coords = coin.SoCoordinate3()
        pts = [(x, y, 0.0) for y in ys for x in (x0, x1)]
        coords.point.setValues(0, len(pts), pts)
        colours = coin.SoMaterial()
        ramp = getattr(self, "_ramp", None) or palette.THICKNESS_RAMP
        cols = [palette.ramp_color(k / n, ramp) for k in range(n + 1) for _ in (0, 1)]
        colours.diffuseColor.setValues(0, len(cols), cols)
        binding = coin.SoMaterialBinding()
        binding.value = coin.SoMaterialBinding.PER_VERTEX_INDEXED
        faces = coin.SoIndexedFaceSet()
        index = []
        for k in range(n):
            a, b = 2 * k, 2 * k + 1
            index += [a, b, b + 2, a + 2, -1]
        faces.coordIndex.setValues(0, len(index), index)
        frame = coin.SoSeparator()
        black = coin.SoBaseColor()
        black.rgb.setValue(0.0, 0.0, 0.0)
        outline = coin.SoCoordinate3()
        box = [(x0, y0, 0.001), (x1, y0, 0.001), (x1, y1, 0.001), (x0, y1, 0.001),
               (x0, y0, 0.001)]
        outline.point.setValues(0, len(box), box)
        line = coin.SoLineSet()
        overall = coin.SoMaterialBinding()
        overall.value = coin.SoMaterialBinding.OVERALL
        frame.addChild(overall)
        frame.addChild(black)
        frame.addChild(outline)
        frame.addChild(line)
        for node in (coords, colours, binding, faces, frame):
            self._bar.addChild(node)
        ticks = legend_labels(lo, hi, steps)
        self.labels = [text for _t, text in ticks]
        rows = [((y0 + y1) / 2 if len(self.labels) == 1 else y0 + (y1 - y0) * t, text)
                for t, text in ticks]
        rows.append((y1 + 0.08, f"{title} (2 x radius)"))
        for k, (colour, text) in enumerate(getattr(self, "_notes", ())):
            y = y0 - 0.09 * (k + 1)
            swatch = coin.SoSeparator()
            base = coin.SoBaseColor()
            base.rgb.setValue(*colour)
            corners = coin.SoCoordinate3()
            square = [(x0, y, 0.0), (x1, y, 0.0), (x1, y + 0.05, 0.0), (x0, y + 0.05, 0.0)]
            corners.point.setValues(0, 4, square)
            face = coin.SoFaceSet()
            face.numVertices.setValue(4)
            overall = coin.SoMaterialBinding()
            overall.value = coin.SoMaterialBinding.OVERALL
            for node in (overall, base, corners, face):
                swatch.addChild(node)
            self._bar.addChild(swatch)
            rows.append((y + 0.01, text))
        for y, text in rows:
            sep = coin.SoSeparator()
            colour = coin.SoBaseColor()
            colour.rgb.setValue(0.0, 0.0, 0.0)
            move = coin.SoTranslation()
            move.translation.setValue(x0 if text.startswith(title) else x1 + 0.01,
                                      y - 0.01, 0.0)
            font = coin.SoFont()
            font.size = 14.0
            label = coin.SoText2()
            label.string = text
            for node in (colour, move, font, label):
                sep.addChild(node)
            self._text.addChild(sep)


def _legend_of(obj):
    """The Legend of ``obj``'s view provider (a LegendViewProvider), or None."""
    proxy = getattr(getattr(obj, "ViewObject", None), "Proxy", None)
    legend = getattr(proxy, "legend", None)
    return legend if isinstance(legend, Legend) else None


def arrange_legends(doc, leaving=None):
    """Stacks the legends shown in ``doc``'s 3-D views (module doc): a legend keeps its
    place while shown, one shown anew takes the next free slot, a hidden one (and that of
    ``leaving``, an object being deleted) frees its slot and the ones below move up.
    Returns the shown legends, top first."""
    shown = []
    for obj in doc.Objects:
        legend = _legend_of(obj)
        if legend is None:
            continue
        vobj = obj.ViewObject
        if (leaving is not None and obj.Name == leaving.Name) \
                or not vobj.Proxy.legend_shown(vobj):
            legend.order = None
        else:
            shown.append(legend)
    free = max((lg.order for lg in shown if lg.order is not None), default=-1) + 1
    for legend in shown:   # shown anew (several at once: in the tree's order)
        if legend.order is None:
            legend.order, free = free, free + 1
    shown.sort(key=lambda lg: lg.order)
    for slot, legend in enumerate(shown):
        legend.place(slot, len(shown))
    return shown


class _UndoWatcher:
    """Undo and redo remove or bring back objects without calling their view providers'
    hooks (FreeCAD keeps a deleted object's view provider aside for redo): re-stack the
    legends of the document after them.  One per session (FreeCAD's observers are)."""

    def slotUndoDocument(self, doc):
        arrange_legends(doc)

    def slotRedoDocument(self, doc):
        arrange_legends(doc)


_WATCHERS = []


def _watch_undo():
    if not _WATCHERS:
        import FreeCAD
        _WATCHERS.append(_UndoWatcher())
        FreeCAD.addDocumentObserver(_WATCHERS[0])


class LegendViewProvider(PanelViewProvider):
    """Base of the view providers whose display mode ``MODE`` draws ``self.legend`` (made
    in ``attach``): keeps its slot in the stack of legends up to date when the object is
    shown, hidden, switched to another display mode or deleted."""

    MODE = THICKNESS_MODE

    def getDisplayModes(self, vobj):
        return [self.MODE]

    def getDefaultDisplayMode(self):
        return self.MODE

    def setDisplayMode(self, mode):
        return mode

    def legend_shown(self, vobj):
        return bool(vobj.Visibility) and vobj.DisplayMode == self.MODE

    def _arrange(self, vobj):
        if getattr(self, "legend", None) is not None and vobj.Object is not None \
                and vobj.Object.Document is not None:
            _watch_undo()
            arrange_legends(vobj.Object.Document)

    def onChanged(self, vobj, prop):
        if prop in ("Visibility", "DisplayMode"):
            self._arrange(vobj)

    def onDelete(self, vobj, subelements):
        if getattr(self, "legend", None) is not None:
            arrange_legends(vobj.Object.Document, leaving=vobj.Object)
        return True


class ColouredSheets:
    """Coin nodes of triangle sheets coloured per vertex by thickness: ``node`` goes into
    a display mode; ``update(points, triangles, thickness)`` redraws and returns the
    thickness range (lo, hi) the colours span."""

    def __init__(self):
        from pivy import coin
        self.node = coin.SoSeparator()
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
        hints.shapeType = coin.SoShapeHints.UNKNOWN_SHAPE_TYPE   # lit from both sides
        hints.creaseAngle = math.radians(30.0)
        # Unlit: a colour reads as the legend's whatever the light falls on the sheet
        # (lit, the pale middle of the ramp turned grey on walls facing away).
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        self._coords = coin.SoCoordinate3()
        self._material = coin.SoMaterial()
        binding = coin.SoMaterialBinding()
        binding.value = coin.SoMaterialBinding.PER_VERTEX_INDEXED
        self._faces = coin.SoIndexedFaceSet()
        for node in (hints, light, self._coords, self._material, binding, self._faces):
            self.node.addChild(node)
        self.triangle_count = 0
        self.colours = np.zeros((0, 3))

    def update(self, points, triangles, thickness, colours=None):
        """``colours`` (n, 3): given per point instead of the ramp's (the thickness
        analysis' window colours)."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        tri = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
        thick = np.asarray(thickness, dtype=np.float64).reshape(-1)
        lo, hi = (float(thick.min()), float(thick.max())) if len(thick) else (0.0, 0.0)
        self.triangle_count = len(tri)
        if colours is not None and len(pts):
            self.colours = np.asarray(colours, dtype=np.float64).reshape(-1, 3)
        else:
            self.colours = (palette.ramp_colors(thick, lo, hi) if len(pts)
                            else np.zeros((0, 3)))
        self._coords.point.setNum(len(pts))
        self._material.diffuseColor.setNum(len(pts))
        if len(pts):
            self._coords.point.setValues(0, len(pts), pts.astype(np.float32))
            self._material.diffuseColor.setValues(0, len(pts),
                                                  self.colours.astype(np.float32))
        index = np.hstack([tri, -np.ones((len(tri), 1), dtype=np.int64)]).ravel()
        self._faces.coordIndex.setNum(len(index))
        if len(index):
            self._faces.coordIndex.setValues(0, len(index), index.astype(np.int32).tolist())
        return lo, hi


class ViewProviderMedialAxis(LegendViewProvider):
    """The medial axis of a face: display mode "Width" (default) draws its wires coloured
    per point by the local width of the face (2 x clearance radius) on the thickness ramp,
    the junctions as black points and the legend; Part's modes show the plain shape."""

    icon = "mfgeom_medial_axis.svg"
    MODE = WIDTH_MODE

    def __init__(self, vobj):
        vobj.Proxy = self
        self.Object = vobj.Object
        vobj.LineColor = (0.05, 0.05, 0.05)
        vobj.LineWidth = 3.0
        vobj.PointColor = palette.JUNCTION
        vobj.PointSize = 5.0

    def attach(self, vobj):
        from pivy import coin
        self.Object = vobj.Object
        root = coin.SoSeparator()
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        style = coin.SoDrawStyle()
        style.lineWidth = 4.0
        style.pointSize = 7.0
        self._coords = coin.SoCoordinate3()
        self._material = coin.SoMaterial()
        binding = coin.SoMaterialBinding()
        binding.value = coin.SoMaterialBinding.PER_VERTEX
        self._lines = coin.SoLineSet()
        junctions = coin.SoSeparator()
        colour = coin.SoBaseColor()
        colour.rgb.setValue(*palette.JUNCTION)
        self._junction_coords = coin.SoCoordinate3()
        junctions.addChild(colour)
        junctions.addChild(self._junction_coords)
        junctions.addChild(coin.SoPointSet())
        self.legend = Legend()
        for node in (light, style, self._coords, self._material, binding, self._lines,
                     junctions, self.legend.node):
            root.addChild(node)
        vobj.addDisplayMode(root, WIDTH_MODE)
        self._draw(vobj.Object)
        self._arrange(vobj)

    def updateData(self, obj, prop):
        if prop == "BranchCount":   # the last result _execute writes
            self._draw(obj)

    def make_panel(self, obj):
        from mfgeom.gui.medial_panel import MedialAxisPanel
        return MedialAxisPanel(obj=obj)

    def _draw(self, obj):
        if getattr(self, "_coords", None) is None or "Radii" not in obj.PropertiesList:
            return
        shape = obj.Shape
        wires = shape.Wires if not shape.isNull() else []
        points = [[(v.Point.x, v.Point.y, v.Point.z) for v in w.OrderedVertexes]
                  for w in wires]
        width = 2.0 * np.asarray(obj.Radii, dtype=np.float64)
        flat = [p for w in points for p in w]
        if len(flat) != len(width):   # not recomputed yet (or an old file): no colours
            flat, points, width = [], [], np.zeros(0)
        lo, hi = (float(width.min()), float(width.max())) if len(width) else (0.0, 0.0)
        self.colours = palette.ramp_colors(width, lo, hi) if len(width) else np.zeros((0, 3))
        self._coords.point.setNum(len(flat))
        self._material.diffuseColor.setNum(len(flat))
        if flat:
            self._coords.point.setValues(0, len(flat), flat)
            self._material.diffuseColor.setValues(0, len(flat),
                                                  self.colours.astype(np.float32))
        self._lines.numVertices.setNum(len(points))
        if points:
            self._lines.numVertices.setValues(0, len(points), [len(w) for w in points])
        loose = ([v.Point for v in shape.SubShapes if v.ShapeType == "Vertex"]
                 if not shape.isNull() else [])
        self._junction_coords.point.setNum(len(loose))
        if loose:
            self._junction_coords.point.setValues(0, len(loose),
                                                  [(p.x, p.y, p.z) for p in loose])
        self.legend.update(lo, hi, "Width")


class ViewProviderMedialSurface(LegendViewProvider):
    """Sheets coloured by thickness, seams, junctions and the legend (module doc)."""

    icon = "mfgeom_medial_surface.svg"

    def __init__(self, vobj):
        vobj.Proxy = self
        self.Object = vobj.Object

    def attach(self, vobj):
        from pivy import coin
        self.Object = vobj.Object
        root = coin.SoSeparator()
        self.sheets = ColouredSheets()
        root.addChild(self.sheets.node)
        lines = coin.SoSeparator()
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        colour = coin.SoBaseColor()
        colour.rgb.setValue(*palette.SEAM)
        style = coin.SoDrawStyle()
        style.lineWidth = 2.0
        style.pointSize = 7.0
        self._seam_coords = coin.SoCoordinate3()
        self._seams = coin.SoLineSet()
        self._junction_coords = coin.SoCoordinate3()
        self._junctions = coin.SoPointSet()
        jcolour = coin.SoBaseColor()
        jcolour.rgb.setValue(*palette.JUNCTION)
        for node in (light, colour, style, self._seam_coords, self._seams, jcolour,
                     self._junction_coords, self._junctions):
            lines.addChild(node)
        root.addChild(lines)
        self.legend = Legend()
        root.addChild(self.legend.node)
        vobj.addDisplayMode(root, THICKNESS_MODE)
        self._draw(vobj.Object)
        self._arrange(vobj)

    def updateData(self, obj, prop):
        if prop == "MaxRadius":   # the last result _execute writes
            self._draw(obj)

    def make_panel(self, obj):
        from mfgeom.gui.medial_panel import MedialSurfacePanel
        return MedialSurfacePanel(obj=obj)

    def _draw(self, obj):
        if getattr(self, "sheets", None) is None or "SheetPoints" not in obj.PropertiesList:
            return
        from mfgeom.app.medial_surface_feature import sheet_mesh_of
        sheets = getattr(getattr(obj, "Proxy", None), "last_sheets", None)
        if sheets is None:
            sheets = sheet_mesh_of(obj)
        lo, hi = self.sheets.update(sheets.points, sheets.triangles, 2.0 * sheets.radii)
        # seams (the wires of the Shape) and junctions (its loose vertices)
        shape = obj.Shape
        seams = ([[(x.Point.x, x.Point.y, x.Point.z) for x in w.OrderedVertexes]
                  for w in shape.Wires] if not shape.isNull() else [])
        flat = [p for s in seams for p in s]
        self._seam_coords.point.setNum(len(flat))
        if flat:
            self._seam_coords.point.setValues(0, len(flat), flat)
        self._seams.numVertices.setNum(len(seams))
        if seams:
            self._seams.numVertices.setValues(0, len(seams), [len(s) for s in seams])
        loose = ([s.Point for s in shape.SubShapes if s.ShapeType == "Vertex"]
                 if not shape.isNull() else [])
        self.seam_count, self.junction_count = len(seams), len(loose)
        self._junction_coords.point.setNum(len(loose))
        if loose:
            self._junction_coords.point.setValues(0, len(loose), [(p.x, p.y, p.z)
                                                                  for p in loose])
        self.legend.update(lo, hi)


class ViewProviderMidSurface(LegendViewProvider):
    """The FEM mid-surface: display mode "Thickness" (default) draws its sheets coloured
    per point by thickness with the legend; Part's modes show the shell itself."""

    icon = "mfgeom_mid_surface.svg"

    def __init__(self, vobj):
        vobj.Proxy = self
        self.Object = vobj.Object

    def attach(self, vobj):
        from pivy import coin
        self.Object = vobj.Object
        root = coin.SoSeparator()
        self.sheets = ColouredSheets()
        self.legend = Legend()
        root.addChild(self.sheets.node)
        root.addChild(self.legend.node)
        vobj.addDisplayMode(root, THICKNESS_MODE)
        self._draw(vobj.Object)
        self._arrange(vobj)

    def updateData(self, obj, prop):
        if prop == "MeanThickness":   # the last result _execute writes
            self._draw(obj)

    def claimChildren(self):
        # the medial surface it is made from sits under it in the tree (hidden)
        source = getattr(getattr(self, "Object", None), "Source", None)
        return [source] if source is not None else []

    def make_panel(self, obj):
        from mfgeom.gui.medial_panel import MidSurfacePanel
        return MidSurfacePanel(obj=obj)

    def _draw(self, obj):
        if getattr(self, "sheets", None) is None or "Thickness" not in obj.PropertiesList:
            return
        from mfgeom.app.medial_surface_feature import is_medial_surface, sheet_mesh_of
        source = obj.Source
        if source is None or not is_medial_surface(source) \
                or len(source.SheetPoints) != len(obj.Thickness):
            self.sheets.update([], [], [])
            self.legend.update(0.0, 0.0)
            return
        sheets = sheet_mesh_of(source)
        lo, hi = self.sheets.update(sheets.points, sheets.triangles, obj.Thickness)
        self.legend.update(lo, hi)
