# SPDX-License-Identifier: LGPL-2.1-or-later
"""The ray check of demouldability (issue 17) on a FreeCAD Part shape: the shape
tessellated to a deflection, face by face into one mesh, and mfgeom.demould's verdict per
face ('core', 'cavity', 'both', 'blocked') for a direction."""

import numpy as np

from mfgeom import demould


def shape_mesh(shape, deflection):
    """(vertices (n, 3), triangles (t, 3), face index (t,), 0-based as shape.Faces) of
    ``shape`` in global coordinates, tessellated within ``deflection`` (mm).  The one
    tessellation helper of the workbench (MeshPart with a segment per face, else
    Face.tessellate face by face), shared with the parting view."""
    from mfgeom.gui.parting_view import triangles_by_face
    points, tris, owner = triangles_by_face(shape, float(deflection))
    return (np.asarray(points, dtype=np.float64), np.asarray(tris, dtype=np.int64),
            np.asarray(owner, dtype=np.int64))


def ray_check(shape, direction, deflection, samples_per_face=64, tolerance=0.0):
    """A list, one per face of ``shape`` (in shape.Faces order; ``face`` is the 0-based
    index, "Face<face + 1>" its name), of :class:`mfgeom.demould.FaceRays`: the
    area-weighted fraction of the face's samples whose ray along +``direction`` (core
    side) / -``direction`` (cavity side) is blocked by the part, and the verdict.  A
    face without triangles (none at this deflection) gets 0 samples and 'both'."""
    d = np.asarray([direction.x, direction.y, direction.z] if hasattr(direction, "x")
                   else direction, dtype=np.float64)
    vertices, triangles, owner = shape_mesh(shape, deflection)
    found = {r.face: r for r in demould.face_demouldability(
        vertices, triangles, owner, d, samples_per_face=samples_per_face,
        tolerance=tolerance)}
    return [found.get(k) or demould.FaceRays(k, 0, 0.0, 0.0, 0.0, 0, 0, "both")
            for k in range(len(shape.Faces))]
