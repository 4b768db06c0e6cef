# SPDX-License-Identifier: LGPL-2.1-or-later
"""View provider of the rotational sweep (a Part::FeaturePython, see
mfgeom.app.sweep_feature for why).

* Representation "Mesh": display mode "Mesh", the result's triangles as one Coin indexed
  face set (smooth shading across the swept curved surfaces, crisp at creases above
  CREASE_DEG) plus its feature edges (dihedral angle above CREASE_DEG) in a dark line:
  fast for any size, no OCCT shape per triangle.
* Representation "Solid": Part's own display modes ("Flat Lines" by default) of the
  feature's Shape.
The colour is Part's ShapeColor (a light orange) and the sweep is drawn half transparent
(Transparency 50) so the source it contains stays visible.  Double click or Edit opens
the task panel on the feature.
"""

import math

import numpy as np

from mfgeom.gui.view_base import PanelViewProvider

MESH_MODE = "Mesh"
SOLID_MODE = "Flat Lines"
CREASE_DEG = 25.0
SWEEP_COLOR = (1.0, 0.67, 0.25)
EDGE_COLOR = (0.25, 0.15, 0.05)
TRANSPARENCY = 50


def feature_edges(vertices, triangles, crease_deg=CREASE_DEG):
    """(k, 2) vertex pairs of the mesh edges whose two triangles' normals differ by more
    than ``crease_deg`` (and edges with one or more than two triangles).  A zero-area
    triangle (collinear corners) has no normal: its edges are not drawn for it (they
    drew stray dashes across flat faces)."""
    tri = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if not len(tri):
        return np.zeros((0, 2), dtype=np.int64)
    v = np.asarray(vertices, dtype=np.float64)
    e1, e2 = v[tri[:, 1]] - v[tri[:, 0]], v[tri[:, 2]] - v[tri[:, 0]]
    n = np.cross(e1, e2)
    length = np.linalg.norm(n, axis=1)
    scale = np.maximum(np.einsum("ij,ij->i", e1, e1), np.einsum("ij,ij->i", e2, e2))
    flat = length <= 1e-12 * scale
    n /= np.maximum(length, 1e-300)[:, None]
    edges = np.vstack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    owner = np.tile(np.arange(len(tri)), 3)
    edges.sort(axis=1)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    edges, owner = edges[order], owner[order]
    same = (edges[1:] == edges[:-1]).all(axis=1)
    starts = np.flatnonzero(np.concatenate([[True], ~same]))
    counts = np.diff(np.concatenate([starts, [len(edges)]]))
    keep = counts != 2
    pair = starts[counts == 2]
    cos = np.einsum("ij,ij->i", n[owner[pair]], n[owner[pair + 1]])
    sharp = np.zeros(len(starts), dtype=bool)
    sharp[counts == 2] = ((cos < math.cos(math.radians(crease_deg)))
                          & ~flat[owner[pair]] & ~flat[owner[pair + 1]])
    return edges[starts[keep | sharp]]


class ViewProviderRotationalSweep(PanelViewProvider):
    """Mesh or solid of a RotationalSweep (see the module doc)."""

    icon = "RotationalSweep.svg"

    def __init__(self, vobj):
        vobj.Proxy = self
        self.Object = vobj.Object
        vobj.ShapeColor = SWEEP_COLOR
        vobj.Transparency = TRANSPARENCY

    def attach(self, vobj):
        from pivy import coin
        self.Object = vobj.Object
        root = coin.SoSeparator()
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
        hints.shapeType = coin.SoShapeHints.UNKNOWN_SHAPE_TYPE  # lit from both sides
        hints.creaseAngle = math.radians(CREASE_DEG)
        self._material = coin.SoMaterial()
        self._coords = coin.SoCoordinate3()
        self._faces = coin.SoIndexedFaceSet()
        for node in (hints, self._material, self._coords, self._faces):
            root.addChild(node)
        edges = coin.SoSeparator()
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        color = coin.SoBaseColor()
        color.rgb.setValue(*EDGE_COLOR)
        style = coin.SoDrawStyle()
        style.lineWidth = 1.5
        self._edges = coin.SoIndexedLineSet()
        for node in (light, color, style, self._coords, self._edges):
            edges.addChild(node)
        root.addChild(edges)
        self._root = root
        vobj.addDisplayMode(root, MESH_MODE)
        self._set_material(vobj)
        self._draw(vobj.Object)

    def getDisplayModes(self, vobj):
        return [MESH_MODE]

    def getDefaultDisplayMode(self):
        return MESH_MODE

    def setDisplayMode(self, mode):
        return mode

    def updateData(self, obj, prop):
        # Volume is the last result _execute writes
        if prop == "Volume":
            self._draw(obj)
            vobj = obj.ViewObject
            want = MESH_MODE if getattr(obj, "Representation", "Mesh") == "Mesh" else SOLID_MODE
            if vobj is not None and vobj.DisplayMode != want:
                vobj.DisplayMode = want

    def onChanged(self, vobj, prop):
        if prop in ("ShapeColor", "Transparency"):
            self._set_material(vobj)

    def onDelete(self, vobj, subelements):
        return True

    def claimChildren(self):
        return []

    def make_panel(self, obj):
        from mfgeom.gui.sweep_panel import SweepPanel
        return SweepPanel(obj=obj)

    # -------------------------------------------------------------- drawing
    def _set_material(self, vobj):
        if getattr(self, "_material", None) is None:
            return
        c = vobj.ShapeColor
        self._material.diffuseColor.setValue(c[0], c[1], c[2])
        self._material.transparency.setValue(vobj.Transparency / 100.0)

    def _draw(self, obj):
        if getattr(self, "_coords", None) is None or "Mesh" not in obj.PropertiesList:
            return
        from mfgeom.app.sweep_feature import exact_mesh
        last = exact_mesh(obj)
        if last is not None:
            pts, tri = last
        else:   # a document of version 1: the saved mesh (single precision)
            points, facets = obj.Mesh.Topology
            pts = np.array([(p.x, p.y, p.z) for p in points], dtype=np.float64).reshape(-1, 3)
            tri = np.asarray(facets, dtype=np.int64).reshape(-1, 3)
        self.triangle_count = len(tri)
        self._coords.point.setNum(len(pts))
        if len(pts):
            self._coords.point.setValues(0, len(pts), pts.astype(np.float32))
        index = np.hstack([tri, -np.ones((len(tri), 1), dtype=np.int64)]).ravel()
        self._faces.coordIndex.setNum(len(index))
        if len(index):
            self._faces.coordIndex.setValues(0, len(index), index.astype(np.int32).tolist())
        lines = feature_edges(pts, tri)
        self.edge_count = len(lines)
        index = np.hstack([lines, -np.ones((len(lines), 1), dtype=np.int64)]).ravel()
        self._edges.coordIndex.setNum(len(index))
        if len(index):
            self._edges.coordIndex.setValues(0, len(index), index.astype(np.int32).tolist())
