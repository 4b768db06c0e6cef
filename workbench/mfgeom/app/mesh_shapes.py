# SPDX-License-Identifier: LGPL-2.1-or-later
"""B-rep shapes of a closed triangle mesh in double precision, built from its topology
(FreeCAD App, Part): the planar faces of its coplanar triangle groups
(:mod:`mfgeom.geometry.planar`) made of shared vertices and edges, so neighbouring faces
meet on the same edges without sewing.

Why not ``makeShapeFromMesh`` + ``removeSplitter``: its sewing merges vertices closer than
its tolerance and drops zero-area triangles (the shell of a 17 k triangle sweep came out
open: "did not give one closed shell"), and OCCT's refine of 10^5 faces did not finish.
Here every mesh vertex is one B-rep vertex and every mesh edge between two groups one
B-rep edge used by both faces: the shell is closed by construction.
"""

import numpy as np

import FreeCAD
import Part

from mfgeom.errors import MfgeomError
from mfgeom.geometry import planar


# OCCT takes two points closer than its Precision::Confusion (1e-7, absolute: mm in
# FreeCAD) for one, and refuses an edge between them; each vertex carries that tolerance,
# so two vertices within twice it are merged before the shapes are made.
OCCT_CONFUSION = 1e-7


class SharedEdges:
    """One Part.Vertex per point id and one Part.Edge per pair of ids, each made once:
    faces built on them that meet along an edge hold the same edge (no sewing).
    ``points[i]``: the coordinates of point id i (a list, or a dict of arrays)."""

    def __init__(self, points):
        self._points = points
        self._vertex = {}
        self._edge = {}

    def vertex(self, i):
        vertex = self._vertex.get(i)
        if vertex is None:
            vertex = self._vertex[i] = Part.Vertex(
                FreeCAD.Vector(*(float(c) for c in self._points[i])))
        return vertex

    def edge(self, i, j):
        key = (i, j) if i < j else (j, i)
        edge = self._edge.get(key)
        if edge is None:
            edge = self._edge[key] = Part.Edge(self.vertex(key[0]), self.vertex(key[1]))
        return edge

    def wire(self, loop):
        """The closed wire of the point ids ``loop``, on the shared edges."""
        return Part.Wire([self.edge(loop[k], loop[(k + 1) % len(loop)])
                          for k in range(len(loop))])


class MeshFaces:
    """Builds faces of the triangles of (``vertices``, ``triangles``) that share their
    B-rep vertices and edges: every call of :meth:`faces` reuses the ones made before,
    so faces made for different subsets still meet on common edges.  Vertices closer
    than OCCT can tell apart are merged first (the triangles that collapse are left
    out: they have no area)."""

    def __init__(self, vertices, triangles):
        from mfgeom.geometry.mesh import merge_near_vertices
        v, t, kept = merge_near_vertices(vertices, triangles, 2.0 * OCCT_CONFUSION)
        self.vertices, self.triangles = v, t
        # index of each given triangle among the merged ones, -1 when it collapsed
        self.merged_index = np.where(kept, np.cumsum(kept) - 1, -1)
        self._points = self.vertices.tolist()
        self._shared = SharedEdges(self._points)
        self._wire = self._shared.wire

    def _plane(self, loop, normal):
        return Part.Plane(FreeCAD.Vector(*self._points[loop[0]]), FreeCAD.Vector(*normal))

    def triangle_faces(self, indices):
        """One planar Part face per triangle of ``indices`` (of the given mesh; those that
        collapsed when close vertices were merged are left out), made once and kept."""
        if not hasattr(self, "_triangle_face"):
            self._triangle_face = {}
        out = []
        for t in self.merged_index[np.asarray(indices, dtype=np.int64)].tolist():
            if t < 0:
                continue
            face = self._triangle_face.get(t)
            if face is None:
                loop = self.triangles[t].tolist()
                p = self.vertices[loop]
                n = np.cross(p[1] - p[0], p[2] - p[0])
                length = float(np.linalg.norm(n))
                if length == 0.0:
                    continue
                face = self._triangle_face[t] = Part.Face(self._plane(loop, n / length),
                                                          self._wire(loop))
            out.append(face)
        return out

    def faces(self, subset=None, split=()):
        """(faces, normals, groups): planar Part faces covering the triangles ``subset``
        (indices of the given mesh; all when None) with each group of coplanar neighbours
        in the subset merged into one face (holes included), each face's outward unit
        normal (numpy (k, 3)) and the group it belongs to.  A group whose boundary does
        not make one outer loop and holes, or whose number is in ``split``, gives one
        face per triangle."""
        if subset is None:
            idx = np.arange(len(self.triangles))
        else:
            idx = self.merged_index[np.asarray(subset, dtype=np.int64)]
            idx = idx[idx >= 0]
        tri = self.triangles[idx]
        group, normals = planar.planar_groups(self.vertices, tri)
        loops = planar.group_loops(self.vertices, tri, group, normals)
        faces, face_normals, face_groups, self.doubtful = [], [], [], []
        members = None
        split = set(split)
        p = self.vertices[tri]
        double_area = np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
        longest = np.linalg.norm(p[:, [1, 2, 0]] - p, axis=2).max(axis=1)
        # a needle whose apex lies within OCCT's tolerance of its base edge
        needle = double_area < 2.0 * OCCT_CONFUSION * longest
        needle_groups = set(group[needle].tolist())
        for g, boundary in enumerate(loops):
            if boundary and g not in split:
                surface = self._plane(boundary[0], normals[g])
                faces.append(Part.Face(surface, [self._wire(loop) for loop in boundary]))
                face_normals.append(normals[g])
                face_groups.append(g)
                # a polygon of more than 4 corners (or with holes) may touch itself
                # within OCCT's tolerance; a triangle or a quad of two cannot, unless
                # it holds a needle
                if len(boundary) > 1 or len(boundary[0]) > 4 or g in needle_groups:
                    self.doubtful.append(len(faces) - 1)
                continue
            if members is None:
                order = np.argsort(group, kind="stable")
                cuts = np.searchsorted(group[order], np.arange(len(loops) + 1))
                members = (order, cuts)
            order, cuts = members
            for t in order[cuts[g]:cuts[g + 1]].tolist():
                loop = tri[t].tolist()
                p = self.vertices[loop]
                n = np.cross(p[1] - p[0], p[2] - p[0])
                length = np.linalg.norm(n)
                if length == 0.0:
                    raise MfgeomError(f"triangle {int(idx[t])} has zero area and no "
                                      "neighbour to join")
                faces.append(Part.Face(self._plane(loop, n / length), self._wire(loop)))
                face_normals.append(n / length)
                face_groups.append(g)
                if needle[t]:
                    self.doubtful.append(len(faces) - 1)
        return (faces, np.array(face_normals, dtype=np.float64).reshape(-1, 3),
                np.array(face_groups, dtype=np.int64))


def _shell(faces):
    """(shell, checked): ``Part.Shell`` runs OCCT's analyser (BRepCheck) on the shell and
    sews it when it finds it invalid, which gives new faces: the first face still being
    ours means the shell passed the check.  (A second check of the solid would double
    the time: 20 s for the 18 k faces of a 139 k triangle sweep.)"""
    shell = Part.Shell(faces)
    checked = bool(shell.Faces) and shell.Faces[0].isSame(faces[0]) and \
        len(shell.Faces) == len(faces)
    return shell, checked


def solid_of_mesh(vertices, triangles, volume=None):
    """A valid Part solid bounded by the closed, outward mesh's triangles, coplanar
    neighbours merged into planar faces; its volume must agree with ``volume`` (the
    library's, when given) to 1e-6 relative.  A merged face OCCT finds invalid (a
    boundary that touches itself within OCCT's tolerance) is made of its triangles
    instead.  MfgeomError says which step failed."""
    maker = MeshFaces(vertices, triangles)
    faces, _, groups = maker.faces()
    # an invalid face makes Part.Shell sew (minutes on 10^5 faces): the faces that can
    # be invalid are checked first, and their groups made of triangles
    bad = [int(groups[i]) for i in maker.doubtful if not faces[i].isValid()]
    if bad:
        faces, _, groups = maker.faces(split=bad)
        flat = [i for i in maker.doubtful if not faces[i].isValid()]
        if flat:
            raise MfgeomError(f"{len(flat)} triangle(s) of the mesh make no valid face "
                              "(zero area, or corners closer than 1e-7 mm)")
    shell, checked = _shell(faces)
    if not checked:
        raise MfgeomError(f"the shell of the mesh's {len(faces)} planar faces is not "
                          "valid (OCCT check: does the mesh intersect itself?)")
    if not shell.isClosed():
        raise MfgeomError(f"the {len(faces)} planar faces of the mesh do not close "
                          "(is the mesh closed and manifold?)")
    solid = Part.Solid(shell)
    if solid.Volume < 0:
        solid.reverse()
    if volume is not None and abs(solid.Volume - volume) > 1e-6 * max(abs(volume), 1e-300):
        raise MfgeomError(f"the solid built from the mesh has volume {solid.Volume:.9g}, "
                          f"the mesh {volume:.9g}")
    return solid
