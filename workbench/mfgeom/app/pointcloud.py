# SPDX-License-Identifier: LGPL-2.1-or-later
"""Moves point sets between numpy arrays and FreeCAD's containers without one Python object
per point: Points kernels through their binary content, meshes and shapes in bulk.

A Points kernel (``Points.Points``) stores float32 coordinates plus a placement matrix in
double precision.  ``dumpContent()``/``restoreContent()`` give the same bytes FreeCAD
writes into a .FCStd file: an XML header and a binary file of ``uint32 count`` followed
by ``count`` little-endian float32 triples.  Reading and writing those bytes with numpy
costs ~0.05 s for 10^6 points, against ~1.5 s through ``App.Vector`` objects.
"""

import io
import re
import zipfile

import numpy as np

import FreeCAD
import Points

_FILE = re.compile(r'\bfile="([^"]*)"')
_CONTENT = "Persistence.xml"
_DATA = "points.bin"


def kernel_to_array(kernel):
    """The points of a ``Points.Points`` kernel as an (n, 3) float64 array in global
    coordinates (the kernel's placement applied)."""
    local, m = kernel_local(kernel)
    local = local.astype(np.float64)
    if np.array_equal(m, np.eye(4)):
        return local
    return local @ m[:3, :3].T + m[:3, 3]


def kernel_local(kernel):
    """``(local, matrix)``: the kernel's float32 coordinates as stored (an (n, 3) read-only
    array) and its 4x4 placement matrix (float64), global = matrix applied to local."""
    # Compression=0: the zip is only a container here, deflating 12 MB would cost 0.3 s.
    archive = zipfile.ZipFile(io.BytesIO(bytes(kernel.dumpContent(Compression=0))))
    header = archive.read(_CONTENT).decode("utf-8", "replace")
    name = _FILE.search(header)
    if name is None:
        raise ValueError("unexpected content of a Points kernel: " + header[:200])
    names = [n for n in archive.namelist() if n != _CONTENT]
    data = archive.read(name.group(1) if name.group(1) in names else names[0])
    count = int(np.frombuffer(data, "<u4", 1)[0])
    if len(data) < 4 + 12 * count:
        raise ValueError(f"a Points kernel of {count} points holds only {len(data)} bytes")
    local = np.frombuffer(data, "<f4", 3 * count, 4).reshape(count, 3)
    # The header's "mtrx" has 6 significant digits; the kernel's Placement is exact.
    m = np.array(kernel.Placement.toMatrix().A, dtype=np.float64).reshape(4, 4)
    return local, m


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
    body = np.uint32(len(pts)).tobytes() + (pts - centre).astype("<f4").tobytes()
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_STORED) as archive:
        archive.writestr(_CONTENT, f'<Content>\n<Points file="{_DATA}" '
                                   f'mtrx="1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"/>\n</Content>\n')
        archive.writestr(_DATA, body)
    kernel = Points.Points()
    kernel.restoreContent(buffer.getvalue())
    if kernel.CountPoints != len(pts):
        raise ValueError(f"restoring {len(pts)} points into a kernel gave {kernel.CountPoints}")
    # restoreContent ignores the matrix of the header (it is read only from documents),
    # so the offset goes in as a placement.
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
