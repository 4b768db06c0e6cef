# SPDX-License-Identifier: LGPL-2.1-or-later
"""Moves point sets between numpy arrays and FreeCAD's containers: Points kernels through
their public per-point API, meshes and shapes in bulk.

A Points kernel (``Points.Points``) stores float32 coordinates plus a placement matrix in
double precision.  Only the kernel's public, version-stable API is used (``addPoints``,
``.Points``, ``.Placement``): the serialised form (``dumpContent``) changed between FreeCAD
0.20 and 1.0.  Local (stored) coordinates are read from a copy whose placement is the
identity, so the float32 values come back exactly and the placement is applied here in
double precision.  The results are bit for bit those of the former reader of the
serialised form; 10^6 points take ~1.4 s in and ~0.6 s out (one Python object per point;
the serialised form took ~0.6 s and ~0.3 s).
"""

import itertools

import numpy as np

import FreeCAD
import Points


def kernel_to_array(kernel):
    """The points of a ``Points.Points`` kernel as an (n, 3) float64 array in global
    coordinates (the kernel's placement applied)."""
    local, m = kernel_local(kernel)
    local = local.astype(np.float64)
    if np.array_equal(m, np.eye(4)):
        return local
    return local @ m[:3, :3].T + m[:3, 3]


def kernel_local(kernel):
    """``(local, matrix)``: the kernel's float32 coordinates as stored (an (n, 3) float32
    array) and its 4x4 placement matrix (float64), global = matrix applied to local."""
    m = np.array(kernel.Placement.toMatrix().A, dtype=np.float64).reshape(4, 4)
    if not np.array_equal(m, np.eye(4)):
        # .Points applies the placement; a copy without it yields the stored values
        kernel = kernel.copy()
        kernel.Placement = FreeCAD.Placement()
    count = kernel.CountPoints
    flat = np.fromiter(itertools.chain.from_iterable(kernel.Points), dtype=np.float64,
                       count=3 * count)
    # the stored values are float32: the conversion back is exact
    return flat.astype(np.float32).reshape(count, 3), m


def array_to_kernel(points):
    """A ``Points.Points`` kernel holding ``points`` ((n, 3) array-like).

    The kernel stores float32: the points are stored relative to the first one, which goes
    into the kernel's placement, so a cloud far from the origin keeps float32's relative
    precision of its own extent (~1e-7 of it).  A document saves the placement with 6
    significant digits, so that offset is rounded to 6 digits first: it then reloads
    exactly.  (The first point, not the bounding box's centre: min/max over 10^6 points
    cost more than the rest of this function, for at most a factor 2 in precision.)
    """
    pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3)
    centre = np.array([float(f"{c:.6g}") for c in pts[0]]) if len(pts) else np.zeros(3)
    # rounded to float32 here, as the kernel stores them (addPoints would round the same)
    local = (pts - centre).astype(np.float32).astype(np.float64)
    kernel = Points.Points()
    if len(local):
        # addPoints takes global coordinates (it applies the inverse placement): the new
        # kernel's placement is the identity, so the values are stored as given
        kernel.addPoints(list(zip(*local.T.tolist())))
    if kernel.CountPoints != len(pts):
        raise ValueError(f"adding {len(pts)} points to a kernel gave {kernel.CountPoints}")
    kernel.Placement = FreeCAD.Placement(FreeCAD.Vector(*centre.tolist()), FreeCAD.Rotation())
    return kernel


def vectors_to_array(vectors):
    """(n, 3) float64 array from a sequence of App.Vector (or MeshPoint) objects."""
    flat = np.fromiter((c for v in vectors for c in (v.x, v.y, v.z)), dtype=np.float64)
    return flat.reshape(-1, 3)


def mesh_points(mesh):
    """The vertices of a Mesh kernel (placement applied) as an (n, 3) array.

    A mesh has no binary content to dump, but it writes binary PLY: the vertices of a copy
    without placement are read as stored (float32, exact) and the placement is applied
    here in double precision.  5x faster than ``mesh.Topology``, which stays the fallback
    should the file not look as expected."""
    import os
    import tempfile
    copy = mesh.copy()
    matrix = np.array(copy.Placement.toMatrix().A, dtype=np.float64).reshape(4, 4)
    copy.Placement = FreeCAD.Placement()
    with tempfile.TemporaryDirectory(prefix="mfgeom-mesh-") as tmp:
        path = os.path.join(tmp, "points.ply")
        copy.write(path)
        with open(path, "rb") as f:
            data = f.read()
    local = _ply_vertices(data)
    if local is None:
        return vectors_to_array(mesh.Topology[0])
    return local @ matrix[:3, :3].T + matrix[:3, 3]


def _ply_vertices(data):
    """The vertex block of a binary little-endian PLY whose first element is ``vertex``
    with exactly float32 x, y, z; None for anything else."""
    end = data.find(b"end_header\n")
    if end < 0:
        return None
    lines = data[:end].decode("ascii", "replace").splitlines()
    elements = [i for i, line in enumerate(lines) if line.startswith("element ")]
    if "format binary_little_endian 1.0" not in lines or not elements or \
            not lines[elements[0]].startswith("element vertex "):
        return None
    first = elements[0]
    props = lines[first + 1:elements[1] if len(elements) > 1 else len(lines)]
    if props != ["property float32 x", "property float32 y", "property float32 z"] and \
            props != ["property float x", "property float y", "property float z"]:
        return None
    count = int(lines[first].split()[2])
    start = end + len(b"end_header\n")
    if len(data) < start + 12 * count:
        return None
    return np.frombuffer(data, "<f4", 3 * count, start).reshape(count, 3).astype(np.float64)


def shape_points(shape):
    """The vertices of a Part shape as an (n, 3) array."""
    return vectors_to_array(v.Point for v in shape.Vertexes)
