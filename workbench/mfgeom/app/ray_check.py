# SPDX-License-Identifier: LGPL-2.1-or-later
"""The ray check of demouldability (issue 17) on a FreeCAD Part shape: the shape
tessellated to a deflection, face by face into one mesh, and mfgeom.demould's verdict per
face ('core', 'cavity', 'both', 'blocked') for a direction."""

import numpy as np

from mfgeom import demould


def triangles_by_face(shape, deflection, angular=0.5):
    """(points (n, 3), triangles (m, 3), face index of each triangle) of ``shape``.
    MeshPart meshes the whole shape with one segment per face, in face order: ~8x
    faster than Face.tessellate face by face, the fallback (a plate with 225 holes, 456
    faces: 0.43 s against 3.5 s).  ``angular`` (rad): Part's own default, 28.6 deg; 0.25
    doubled the triangles and tripled the time, and smooth shading hides the facets."""
    try:
        import MeshPart
        mesh = MeshPart.meshFromShape(Shape=shape, LinearDeflection=deflection,
                                      AngularDeflection=angular, Relative=False,
                                      Segments=True)
        if mesh.countSegments() == len(shape.Faces):
            points, tris = mesh.Topology
            pts = np.array([(p.x, p.y, p.z) for p in points], dtype=np.float64).reshape(-1, 3)
            tri = np.asarray(tris, dtype=np.int32).reshape(-1, 3)
            own = np.zeros(len(tri), dtype=np.int32)
            for k in range(mesh.countSegments()):
                own[np.asarray(mesh.getSegment(k), dtype=np.int64)] = k
            return pts, tri, own
    except ImportError:
        pass
    points, tris, owner, base = [], [], [], 0
    for i, face in enumerate(shape.Faces):
        p, t = face.tessellate(deflection)
        points.append(np.array([(v.x, v.y, v.z) for v in p], dtype=np.float64).reshape(-1, 3))
        if t:
            tris.append(np.asarray(t, dtype=np.int32) + base)
            owner.append(np.full(len(t), i, dtype=np.int32))
        base += len(p)
    return (np.vstack(points) if points else np.zeros((0, 3)),
            np.vstack(tris) if tris else np.zeros((0, 3), dtype=np.int32),
            np.concatenate(owner) if owner else np.zeros(0, dtype=np.int32))


def shape_mesh(shape, deflection):
    """(vertices (n, 3), triangles (t, 3), face index (t,), 0-based as shape.Faces) of
    ``shape`` in global coordinates, tessellated within ``deflection`` (mm).  The one
    tessellation helper of the workbench (MeshPart with a segment per face, else
    Face.tessellate face by face), shared with the parting view."""
    points, tris, owner = triangles_by_face(shape, float(deflection))
    return (np.asarray(points, dtype=np.float64), np.asarray(tris, dtype=np.int64),
            np.asarray(owner, dtype=np.int64))


def ray_check(shape, direction, deflection, samples_per_face=64, tolerance=0.0):
    """A list, one per face of ``shape`` (in shape.Faces order; ``face`` is the 0-based
    index, "Face<face + 1>" its name), of :class:`mfgeom.demould.FaceRays`: the
    area-weighted fraction of the face's samples whose ray along +``direction`` (core
    side) / -``direction`` (cavity side) is blocked by the part, and the verdict.  A
    face without triangles (none at this deflection) gets 0 samples and 'both'.
    Samples are lifted off their triangles by the deflection (at least demould's own
    lift): the tessellation's chords lie up to that far inside the true faces, and a
    ray from a chord of one face could otherwise clip a neighbour's triangles at their
    common edge (seen on a cylinder wall next to a hole's rim)."""
    d = np.asarray([direction.x, direction.y, direction.z] if hasattr(direction, "x")
                   else direction, dtype=np.float64)
    vertices, triangles, owner = shape_mesh(shape, deflection)
    size = demould.mesh_size(vertices)
    lift = max(demould.LIFT, float(deflection) / size) if size > 0 else demould.LIFT
    found = {r.face: r for r in demould.face_demouldability(
        vertices, triangles, owner, d, samples_per_face=samples_per_face,
        tolerance=tolerance, lift=lift)}
    return [found.get(k) or demould.FaceRays(k, 0, 0.0, 0.0, 0.0, 0, 0, "both")
            for k in range(len(shape.Faces))]
