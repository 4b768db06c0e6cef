# SPDX-License-Identifier: LGPL-2.1-or-later
"""View provider of the parting analysis: the source's faces coloured by result, an arrow
along each direction and a visibility sphere beside the part, all drawn with Coin.

* The part: a coloured copy of the source's shape in global coordinates (one triangle
  set, one material per face: the view property ``DiffuseColor``, in the order of the
  source's faces), its edges in black.  The source itself is never recoloured; the task
  panel hides it while the analysis is shown and deleting the analysis shows it again.
  The copy is not a selectable Part shape, so selecting the analysis does not paint it
  green: the colours stay legible.
* Colours: one table, :data:`FACE_CLASSES` (from mfgeom.palette), read by the view and
  by the task panel's legend (:func:`legend_entries`).  Mould core side (+d) blue,
  cavity side (-d) red, zero draft pink, insufficient draft sand, undercuts indigo,
  shadowed (ray check) brown, undercuts with no side core black, other faces grey;
  Draft positive blue, negative red, insufficient pink, straddle sand; NC3Axis set-up k
  in ``setup_color(k)``, unresolved pockets red, faces not considered grey.  Display mode "Surfaces" colours the concave-connected surfaces.
* Arrows: Mould +d (core colour) and -d (cavity colour) from the part's centre, each side
  core from its faces' centre; NC3Axis each set-up from its faces' centre.
* The visibility sphere: an icosphere (2562 vertices, 5120 triangles) beside the part,
  each vertex coloured by how many surfaces' maps contain its direction (Mould: VM(S) or
  -VM(S); NC3Axis: VM(S)), light grey (none) to dark blue; vertices of the highest
  count, the maximum region, and an arrow to the chosen direction in magenta.  For the
  picture only, a vertex counts as inside a map within one mesh spacing (~1.8 deg), so
  point and arc maps (a cylinder's, a hole's) show; the answer itself is the library's
  exact maximum intersection.
"""

import functools
import json
import math

import numpy as np

from mfgeom import palette
from mfgeom.app.ray_check import triangles_by_face
# The sphere's geometry lives in mfgeom.geometry.sphere (FreeCAD-free, tested by pytest);
# its names stay importable from here.
from mfgeom.geometry.sphere import (SPHERE_LEVEL, coverage, icosphere,  # noqa: F401
                                    map_outlines)
from mfgeom.gui.view_base import PanelViewProvider
# The face classes are the task panel's too: they live in mfgeom.parting_legend
# (FreeCAD-free); their names stay importable from here.
from mfgeom.parting_legend import (FACE_CLASSES, class_color, class_label,  # noqa: F401
                                   face_classes, face_colors, legend_entries)

MODES = ("Result", "Part", "Sphere", "Surfaces")
# Surfaces mode: a qualitative cycle (the set-up colours, light ones first)
SURFACE_COLORS = (palette.SETUP_COLORS[0], palette.SETUP_COLORS[4], palette.CAVITY_SIDE,
                  palette.SETUP_COLORS[5], palette.SETUP_COLORS[2], palette.SETUP_COLORS[7],
                  palette.UNDERCUT, palette.SETUP_COLORS[3])


# ------------------------------------------------------------------ pure helpers
def sphere_side(directions):
    """The global axis (+x, -x, +y, -y, in that order of preference) along which the
    sphere sits beside the part: the one the arrows point along least, so no arrow runs
    into it."""
    sides = [np.array(v, float) for v in ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0))]
    dirs = [np.asarray(d, float) for d in directions if np.linalg.norm(d) > 0.5]

    def score(v):
        return max((float(v @ d) / np.linalg.norm(d) for d in dirs), default=0.0)
    return min(sides, key=score)  # min keeps the first of equal scores


def coverage_colors(count):
    """Per-vertex colours: SPHERE_LOW at the least count on the sphere (surfaces every
    direction sees, such as planes in Mould mode, add nothing to look at) ..
    SPHERE_HIGH just below the maximum, SPHERE_MAX at the maximum."""
    if not len(count):
        return np.zeros((0, 3))
    low, top = int(count.min()), int(count.max())
    t = ((count - low) / (top - low))[:, None] if top > low else np.zeros((len(count), 1))
    col = (1 - t) * np.array(palette.SPHERE_LOW) + t * np.array(palette.SPHERE_HIGH)
    if top > 0:
        col[count == top] = palette.SPHERE_MAX
    return col




def surface_colors(obj, nfaces):
    cols = [palette.SHAPE_GREY] * nfaces
    for k, surf in enumerate(obj.Surfaces):
        for name in surf.split():
            i = int(name[4:]) - 1
            if 0 <= i < nfaces:
                cols[i] = SURFACE_COLORS[k % len(SURFACE_COLORS)]
    return cols


def arrows_of(obj, shape):
    """[(start, direction, colour)] for the result's directions (see the module doc)."""
    box = shape.BoundBox
    centre = np.array([box.Center.x, box.Center.y, box.Center.z])

    def faces_centre(names):
        pts = []
        for n in names:
            i = int(n[4:]) - 1
            if 0 <= i < len(shape.Faces):
                c = shape.Faces[i].CenterOfMass
                pts.append((c.x, c.y, c.z))
        return np.mean(pts, axis=0) if pts else centre

    def vec(v):
        return np.array([v.x, v.y, v.z]) if hasattr(v, "x") else np.asarray(v, float)
    out = []
    d = vec(obj.Direction)
    if obj.Mode == "Draft":
        if np.linalg.norm(d) > 0.5:
            out.append((centre, d, palette.CORE_SIDE))
    elif obj.Mode == "Mould":
        if np.linalg.norm(d) > 0.5:
            out += [(centre, d, palette.CORE_SIDE), (centre, -d, palette.CAVITY_SIDE)]
        for entry in obj.SideCores:
            e = json.loads(entry)
            out.append((faces_centre(e["faces"]), vec(e["direction"]), palette.UNDERCUT))
    else:
        for k, entry in enumerate(obj.Setups, 1):
            e = json.loads(entry)
            out.append((faces_centre(e["faces"]), vec(e["direction"]), palette.setup_color(k)))
    return out


# ------------------------------------------------------------------ view provider
class ViewProviderPartingAnalysis(PanelViewProvider):
    """Coloured part, arrows and visibility sphere of a PartingAnalysis (see module doc)."""

    icon = "mfgeom_parting.svg"

    def __init__(self, vobj):
        vobj.Proxy = self
        self.Object = vobj.Object
        self._add_properties(vobj)
        vobj.DisplayMode = MODES[0]

    @staticmethod
    def _add_properties(vobj):
        if "DiffuseColor" not in vobj.PropertiesList:
            vobj.addProperty("App::PropertyColorList", "DiffuseColor", "Display",
                             "Colour of each face of the source (Face1 first), by result",
                             1)  # read-only in the editor: written from the result
        if "ShowSphere" not in vobj.PropertiesList:
            vobj.addProperty("App::PropertyBool", "ShowSphere", "Display",
                             "Show the visibility sphere beside the part")
            vobj.ShowSphere = True

    def attach(self, vobj):
        from pivy import coin
        self.Object = vobj.Object
        self._add_properties(vobj)
        self.sphere_count = np.zeros(0, dtype=np.int32)
        # the part: coordinates and triangles shared by the Result and Surfaces modes
        self._coords = coin.SoCoordinate3()
        self._faces = coin.SoIndexedFaceSet()
        self._material = coin.SoMaterial()
        self._surf_material = coin.SoMaterial()
        self._edge_coords = coin.SoCoordinate3()
        self._edges = coin.SoLineSet()
        self._arrows = coin.SoSeparator()
        self._sphere = coin.SoSeparator()
        self._sphere_switch = coin.SoSwitch()
        self._sphere_switch.addChild(self._sphere)
        self._sphere_switch.whichChild = 0 if vobj.ShowSphere else -1

        def part(material):
            sep = coin.SoSeparator()
            hints = coin.SoShapeHints()
            hints.vertexOrdering = coin.SoShapeHints.UNKNOWN_ORDERING  # lit from both sides
            hints.creaseAngle = 0.6
            binding = coin.SoMaterialBinding()
            binding.value = coin.SoMaterialBinding.PER_FACE_INDEXED
            for node in (hints, material, binding, self._coords, self._faces):
                sep.addChild(node)
            edges = coin.SoSeparator()
            color, style = coin.SoBaseColor(), coin.SoDrawStyle()
            color.rgb.setValue(0.1, 0.1, 0.1)
            style.lineWidth = 1.5
            light = coin.SoLightModel()
            light.model = coin.SoLightModel.BASE_COLOR
            overall = coin.SoMaterialBinding()  # not the faces' per-face binding
            overall.value = coin.SoMaterialBinding.OVERALL
            for node in (light, overall, color, style, self._edge_coords, self._edges):
                edges.addChild(node)
            sep.addChild(edges)
            return sep

        self._part = part(self._material)
        roots = {}
        for mode in MODES:
            roots[mode] = coin.SoSeparator()
        roots["Result"].addChild(self._part)
        roots["Result"].addChild(self._arrows)
        roots["Result"].addChild(self._sphere_switch)
        roots["Part"].addChild(self._part)
        roots["Part"].addChild(self._arrows)
        roots["Sphere"].addChild(self._sphere)
        roots["Surfaces"].addChild(part(self._surf_material))
        self._roots = roots
        for mode in MODES:
            vobj.addDisplayMode(roots[mode], mode)
        self._show(vobj.Object)

    def getDisplayModes(self, vobj):
        return list(MODES)

    def getDefaultDisplayMode(self):
        return MODES[0]

    def setDisplayMode(self, mode):
        return mode if mode in MODES else MODES[0]

    def updateData(self, obj, prop):
        # MaxShrinkDeg is the last result execute() writes (and restored last).
        if prop == "MaxShrinkDeg":
            self._show(obj)

    def onChanged(self, vobj, prop):
        if prop == "DiffuseColor" and getattr(self, "_material", None) is not None:
            self._material.diffuseColor.setValues(0, len(vobj.DiffuseColor),
                                                  [c[:3] for c in vobj.DiffuseColor])
        elif prop == "ShowSphere" and getattr(self, "_sphere_switch", None) is not None:
            self._sphere_switch.whichChild = 0 if vobj.ShowSphere else -1

    def onDelete(self, vobj, subelements):
        # The panel hid the source while the analysis is shown: show it again.
        src = getattr(vobj.Object, "Source", None)
        if src is not None and src.ViewObject is not None:
            src.ViewObject.Visibility = True
        return True

    def claimChildren(self):
        return []

    # -------------------------------------------------------------- drawing
    def _show(self, obj):
        if getattr(self, "_coords", None) is None:
            return
        src = getattr(obj, "Source", None)
        if src is None or not hasattr(src, "Shape") or src.Shape.isNull() \
                or "Surfaces" not in obj.PropertiesList:
            return
        from mfgeom.app import gauss_map
        shape = gauss_map.shape_of(src)
        self._draw_part(obj, shape)
        self._draw_arrows(obj, shape)
        try:
            self._draw_sphere(obj, shape)
        except Exception as exc:  # no library, a stale result: the part still shows
            import FreeCAD
            FreeCAD.Console.PrintWarning(f"mfgeom: {obj.Label}: no visibility sphere ({exc})\n")

    def _draw_part(self, obj, shape):
        import Part
        box = shape.BoundBox
        deflection = max(box.DiagonalLength, 1e-9) * 2e-3
        pts, tri, own = triangles_by_face(shape, deflection)
        self._coords.point.setNum(len(pts))
        if len(pts):
            self._coords.point.setValues(0, len(pts), pts.astype(np.float32))
        index = np.hstack([tri, -np.ones((len(tri), 1), dtype=np.int32)]).ravel()
        self._faces.coordIndex.setNum(len(index))
        if len(index):
            self._faces.coordIndex.setValues(0, len(index), index.tolist())
        self._faces.materialIndex.setNum(len(own))
        if len(own):
            self._faces.materialIndex.setValues(0, len(own), own.tolist())
        self.triangle_faces = own
        # edges
        lines, counts = [], []
        for edge in shape.Edges:
            if edge.Length <= 0:   # a degenerate edge (a cone's apex)
                continue
            try:
                p = edge.discretize(Deflection=deflection)
            except Part.OCCError:  # nothing OCCT can draw
                continue
            if len(p) >= 2:
                lines.append(np.array([(v.x, v.y, v.z) for v in p]))
                counts.append(len(p))
        ep = np.vstack(lines) if lines else np.zeros((0, 3))
        self._edge_coords.point.setNum(len(ep))
        if len(ep):
            self._edge_coords.point.setValues(0, len(ep), ep.astype(np.float32))
        self._edges.numVertices.setNum(len(counts))
        if counts:
            self._edges.numVertices.setValues(0, len(counts), counts)
        n = len(shape.Faces)
        colors = face_colors(obj, n)
        vobj = obj.ViewObject
        vobj.DiffuseColor = [tuple(c) for c in colors]   # onChanged sets the material
        surf = surface_colors(obj, n)
        self._surf_material.diffuseColor.setValues(0, n, [tuple(c) for c in surf])

    def _arrow(self, start, direction, color, length, radius):
        from pivy import coin
        d = np.asarray(direction, float)
        d = d / np.linalg.norm(d)
        sep = coin.SoSeparator()
        mat = coin.SoMaterial()
        mat.diffuseColor.setValue(*color)
        xf = coin.SoTransform()
        xf.translation.setValue(*[float(c) for c in start])
        xf.rotation.setValue(coin.SbRotation(coin.SbVec3f(0, 1, 0),
                                             coin.SbVec3f(*[float(c) for c in d])))
        head = 4 * radius
        shaft_len = max(length - head, 0.0)
        to_mid = coin.SoTranslation()
        to_mid.translation.setValue(0, shaft_len / 2, 0)
        shaft = coin.SoCylinder()
        shaft.radius, shaft.height = radius, shaft_len
        to_head = coin.SoTranslation()
        to_head.translation.setValue(0, shaft_len / 2 + head / 2, 0)
        cone = coin.SoCone()
        cone.bottomRadius, cone.height = 2.2 * radius, head
        for node in (mat, xf, to_mid, shaft, to_head, cone):
            sep.addChild(node)
        return sep

    def _draw_arrows(self, obj, shape):
        self._arrows.removeAllChildren()
        diag = max(shape.BoundBox.DiagonalLength, 1e-9)
        self.arrow_count = 0
        for start, d, color in arrows_of(obj, shape):
            if np.linalg.norm(d) < 0.5:
                continue
            # from the faces' centre out past the part's box
            length = 0.5 * diag + 0.25 * diag
            self._arrows.addChild(self._arrow(start, d, color, length, 0.01 * diag))
            self.arrow_count += 1

    def _draw_sphere(self, obj, shape):
        from pivy import coin
        from mfgeom.app import parting_feature
        self._sphere.removeAllChildren()
        verts, tris = _sphere_mesh()
        spacing = 1.1 * math.pi / (5 * 2 ** SPHERE_LEVEL)   # ~ the longest edge, radians
        maps = parting_feature.sphere_maps(obj)
        count = coverage(verts, maps, spacing)
        self.sphere_count = count
        colors = coverage_colors(count)
        box = shape.BoundBox
        diag = max(box.DiagonalLength, 1e-9)
        radius = 0.3 * diag
        side = sphere_side([d for _, d, _ in arrows_of(obj, shape)])
        mid = np.array([box.Center.x, box.Center.y, box.Center.z])
        half = np.array([box.XLength, box.YLength, box.ZLength]) / 2
        centre = mid + side * (float(np.abs(side) @ half) + 0.35 * diag + radius)
        self.sphere_centre, self.sphere_radius = centre, radius
        xf = coin.SoTranslation()
        xf.translation.setValue(*[float(c) for c in centre])
        coords = coin.SoCoordinate3()
        coords.point.setValues(0, len(verts), (verts * radius).astype(np.float32))
        mat = coin.SoMaterial()
        mat.diffuseColor.setValues(0, len(colors), colors.astype(np.float32))
        binding = coin.SoMaterialBinding()
        binding.value = coin.SoMaterialBinding.PER_VERTEX_INDEXED
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
        hints.shapeType = coin.SoShapeHints.SOLID
        hints.creaseAngle = 1.0
        faces = coin.SoIndexedFaceSet()
        index = np.hstack([tris, -np.ones((len(tris), 1), dtype=np.int32)]).ravel().tolist()
        faces.coordIndex.setValues(0, len(index), index)
        faces.materialIndex.setValues(0, len(index), index)
        self.sphere_faces = faces
        self._sphere.addChild(xf)
        mesh = coin.SoSeparator()  # its per-vertex binding must not reach the lines below
        for node in (hints, mat, binding, coords, faces):
            mesh.addChild(node)
        self._sphere.addChild(mesh)
        # the maximum region's vertices drawn as dots, so a point or arc region shows
        top = int(count.max()) if len(count) else 0
        best = verts[count == top] * radius * 1.003 if top else np.zeros((0, 3))
        if len(best):
            dots = coin.SoSeparator()
            light, color, style = coin.SoLightModel(), coin.SoBaseColor(), coin.SoDrawStyle()
            light.model = coin.SoLightModel.BASE_COLOR
            color.rgb.setValue(*palette.SPHERE_MAX)
            style.pointSize = 9
            pc = coin.SoCoordinate3()
            pc.point.setValues(0, len(best), best.astype(np.float32))
            ps = coin.SoPointSet()
            ps.numPoints = len(best)
            for node in (light, color, style, pc, ps):
                dots.addChild(node)
            self._sphere.addChild(dots)
        # each map's outline (a cylinder's point maps, a hole's, show whatever the mesh)
        lines, map_dots = map_outlines(maps)
        outline = coin.SoSeparator()
        light, color, style = coin.SoLightModel(), coin.SoBaseColor(), coin.SoDrawStyle()
        light.model = coin.SoLightModel.BASE_COLOR
        color.rgb.setValue(0.15, 0.15, 0.15)
        style.lineWidth, style.pointSize = 2, 7
        for node in (light, color, style):
            outline.addChild(node)
        if lines:
            lc = coin.SoCoordinate3()
            pts = np.vstack(lines) * radius * 1.004
            lc.point.setValues(0, len(pts), pts.astype(np.float32))
            ls = coin.SoLineSet()
            ls.numVertices.setValues(0, len(lines), [len(p) for p in lines])
            outline.addChild(lc)
            outline.addChild(ls)
        if len(map_dots):
            dc = coin.SoCoordinate3()
            dc.point.setValues(0, len(map_dots),
                               (map_dots * radius * 1.004).astype(np.float32))
            ds = coin.SoPointSet()
            ds.numPoints = len(map_dots)
            outline.addChild(dc)
            outline.addChild(ds)
        self._sphere.addChild(outline)
        # the chosen direction: an arrow from the centre out through the sphere
        d = np.array([obj.Direction.x, obj.Direction.y, obj.Direction.z])
        if np.linalg.norm(d) > 0.5:
            self._sphere.addChild(self._arrow((0, 0, 0), d, palette.SPHERE_MAX, 1.6 * radius,
                                              0.035 * radius))

    # -------------------------------------------------------------- editing
    def make_panel(self, obj):
        from mfgeom.gui.parting_panel import PartingPanel
        return PartingPanel(obj=obj)


@functools.lru_cache(maxsize=1)
def _sphere_mesh():
    """The icosphere, built once per session (a few ms, not worth redoing per recompute)."""
    return icosphere()
