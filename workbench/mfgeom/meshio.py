# SPDX-License-Identifier: LGPL-2.1-or-later
"""Triangle mesh files for the rotational sweep: STL (binary and ASCII) and Wavefront OBJ,
read and written with numpy alone (no FreeCAD).

    read_mesh(path)                          -> (vertices (n, 3) float64, triangles (t, 3) int64)
    write_mesh(path, vertices, triangles, ascii=False)

The format is chosen by the extension (.stl or .obj, any case).
  STL  a triangle soup: binary or ASCII, told apart on reading by the binary layout (80-byte
       header, uint32 count, 50 bytes per triangle: a binary file may also start with
       "solid").  Corners with exactly the same coordinates are welded into one vertex
       (core.weld: nothing else is merged, so a file from a mesh with distinct vertices
       reads back as that mesh).  Written binary by default (float32 coordinates: exact
       only for float32 values) or, with ``ascii=True``, as text with 17 significant
       digits (float64 exact).  Stored normals are ignored on reading and computed from
       the corners on writing (zero for a degenerate triangle).
  OBJ  ``v x y z`` and ``f i j k ...`` lines (1-based indices, negative ones count back from
       the last vertex read; ``i/t/n`` forms use the vertex index); a polygon is split into
       a fan of triangles from its first corner.  Other statements (vt, vn, g, o, s, usemtl,
       comments, ...) are skipped.  Written with 17 significant digits.
A file that cannot be read or parsed raises :class:`MeshFileError` (an InputError) naming
the file and, for text, the line.  Writing goes to a temporary file next to the target,
renamed over it when complete: a failed write leaves no half-written file.
"""

import os

import numpy as np

from mfgeom.errors import InputError
from mfgeom.fileio import write_atomic

FORMATS = (".stl", ".obj")

_STL_RECORD = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)),
                        ("attribute", "<u2")])
assert _STL_RECORD.itemsize == 50


class MeshFileError(InputError):
    """A mesh file that cannot be read or written; ``path`` and ``line`` (1-based, or
    None) say where."""

    def __init__(self, path, message, line=None):
        where = f"{path}, line {line}" if line is not None else f"{path}"
        super().__init__(f"{where}: {message}")
        self.path = path
        self.line = line


def mesh_format(path):
    """The format of ``path`` by its extension, any case: ".stl" or ".obj" (MeshFileError
    otherwise)."""
    ext = os.path.splitext(str(path))[1].lower()
    if ext not in FORMATS:
        raise MeshFileError(path, f"unknown mesh format {ext or '(no extension)'!r}: use "
                                  ".stl or .obj")
    return ext


def _read_bytes(path):
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as exc:
        raise MeshFileError(path, f"cannot read: {exc.strerror or exc}") from None


# --------------------------------------------------------------------------- #
# Reading                                                                     #
# --------------------------------------------------------------------------- #

def _is_binary_stl(data):
    """Binary when the size is exactly that of the count in the header, unless the file is
    plainly text that starts like an ASCII STL (the size coincidence is then a fluke)."""
    if len(data) >= 84:
        count = int(np.frombuffer(data, dtype="<u4", count=1, offset=80)[0])
        if len(data) == 84 + 50 * count:
            head = data[:1024]
            textual = all(32 <= b < 127 or b in (9, 10, 13) for b in head)
            return not (textual and head.lstrip()[:5].lower() == b"solid"
                        and b"facet" in head)
    return not data[:1024].lstrip()[:5].lower() == b"solid"


def _stl_binary_soup(path, data):
    if len(data) < 84:
        raise MeshFileError(path, f"not an STL file: {len(data)} bytes, shorter than a "
                                  "binary STL header (84 bytes) and not starting with 'solid'")
    count = int(np.frombuffer(data, dtype="<u4", count=1, offset=80)[0])
    if len(data) != 84 + 50 * count:
        raise MeshFileError(path, f"binary STL of {count} triangles must have "
                                  f"{84 + 50 * count} bytes, the file has {len(data)} "
                                  "(truncated or not an STL file)")
    records = np.frombuffer(data, dtype=_STL_RECORD, count=count, offset=84)
    soup = records["corners"].astype(np.float64)                     # (t, 3, 3)
    bad = ~np.isfinite(soup).all(axis=(1, 2))
    if bad.any():
        raise MeshFileError(path, f"triangle {int(np.argmax(bad))} (0-based) has a "
                                  "coordinate that is not finite")
    return soup


def _stl_ascii_soup(path, data):
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError as exc:
        raise MeshFileError(path, f"not an ASCII STL: byte {exc.start} is not ASCII "
                                  "(and the size does not fit a binary STL)") from None
    corners = []
    state = "solid"          # what comes next: solid, facet, outer, vertex, endfacet, end
    nvert = 0
    line_no = 0
    for line_no, line in enumerate(text.splitlines(), 1):
        words = line.split()
        if not words:
            continue
        key = words[0].lower()
        if state == "solid":
            if key != "solid":
                raise MeshFileError(path, f"expected 'solid', found {words[0]!r}", line_no)
            state = "facet"
        elif state == "facet":
            if key == "endsolid":
                state = "end"
            elif key == "facet":
                state = "outer"
            else:
                raise MeshFileError(path, f"expected 'facet' or 'endsolid', found "
                                          f"{words[0]!r}", line_no)
        elif state == "outer":
            if key != "outer":
                raise MeshFileError(path, f"expected 'outer loop', found {words[0]!r}",
                                    line_no)
            state, nvert = "vertex", 0
        elif state == "vertex":
            if key == "vertex":
                if nvert == 3:
                    raise MeshFileError(path, "a facet with more than 3 vertices", line_no)
                if len(words) != 4:
                    raise MeshFileError(path, f"'vertex' needs 3 coordinates, found "
                                              f"{len(words) - 1}", line_no)
                try:
                    xyz = [float(w) for w in words[1:]]
                except ValueError:
                    raise MeshFileError(path, f"bad coordinate in {line.strip()!r}",
                                        line_no) from None
                if not all(np.isfinite(xyz)):
                    raise MeshFileError(path, f"coordinate not finite in {line.strip()!r}",
                                        line_no)
                corners.append(xyz)
                nvert += 1
            elif key == "endloop":
                if nvert != 3:
                    raise MeshFileError(path, f"a facet with {nvert} vertices (3 needed)",
                                        line_no)
                state = "endfacet"
            else:
                raise MeshFileError(path, f"expected 'vertex' or 'endloop', found "
                                          f"{words[0]!r}", line_no)
        elif state == "endfacet":
            if key != "endfacet":
                raise MeshFileError(path, f"expected 'endfacet', found {words[0]!r}", line_no)
            state = "facet"
        else:                # after endsolid: several solids in one file are one mesh
            if key != "solid":
                raise MeshFileError(path, f"unexpected {words[0]!r} after 'endsolid'",
                                    line_no)
            state = "facet"
    if state == "solid":
        raise MeshFileError(path, "empty file: no 'solid'")
    if state != "end":
        expected = {"facet": "'endsolid'", "outer": "'outer loop'", "vertex": "'vertex'",
                    "endfacet": "'endfacet'"}[state]
        raise MeshFileError(path, f"the file ends where {expected} was expected "
                                  "(truncated?)", line_no + 1)
    return np.asarray(corners, dtype=np.float64).reshape(-1, 3, 3)


def _read_stl(path):
    from mfgeom import core
    data = _read_bytes(path)
    soup = _stl_binary_soup(path, data) if _is_binary_stl(data) else _stl_ascii_soup(path, data)
    return core.weld(soup)


def _obj_index(token, nverts, path, line_no):
    head = token.split("/", 1)[0]
    try:
        i = int(head)
    except ValueError:
        raise MeshFileError(path, f"bad vertex index {token!r}", line_no) from None
    if i > 0:
        k = i - 1
    elif i < 0:
        k = nverts + i
    else:
        raise MeshFileError(path, "vertex index 0 (OBJ indices start at 1)", line_no)
    if not 0 <= k < nverts:
        raise MeshFileError(path, f"vertex index {i} out of range: {nverts} vertices "
                                  "read so far", line_no)
    return k


def _read_obj(path):
    data = _read_bytes(path)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise MeshFileError(path, f"not a text file: byte {exc.start} is not UTF-8") from None
    verts, tris = [], []
    pending, first = "", None
    for line_no, raw in enumerate(text.splitlines(), 1):
        if raw.endswith("\\"):                    # continued on the next line
            pending += raw[:-1] + " "
            first = first or line_no
            continue
        line, start = pending + raw, first or line_no
        pending, first = "", None
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        if words[0] == "v":
            if len(words) < 4:
                raise MeshFileError(path, f"'v' needs 3 coordinates, found {len(words) - 1}",
                                    start)
            try:
                xyz = [float(w) for w in words[1:4]]
            except ValueError:
                raise MeshFileError(path, f"bad coordinate in {line.strip()!r}",
                                    start) from None
            if not all(np.isfinite(xyz)):
                raise MeshFileError(path, f"coordinate not finite in {line.strip()!r}", start)
            verts.append(xyz)
        elif words[0] == "f":
            if len(words) < 4:
                raise MeshFileError(path, f"a face needs at least 3 vertices, found "
                                          f"{len(words) - 1}", start)
            idx = [_obj_index(w, len(verts), path, start) for w in words[1:]]
            tris += [[idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1)]
    if pending:
        raise MeshFileError(path, "the file ends in a continued line", first)
    return (np.asarray(verts, dtype=np.float64).reshape(-1, 3),
            np.asarray(tris, dtype=np.int64).reshape(-1, 3))


def read_mesh(path):
    """The triangle mesh in ``path`` (.stl binary or ASCII, .obj) as ``(vertices (n, 3)
    float64, triangles (t, 3) int64)``; MeshFileError naming the file (and the line) if
    it cannot be read."""
    return _read_stl(path) if mesh_format(path) == ".stl" else _read_obj(path)


# --------------------------------------------------------------------------- #
# Writing                                                                     #
# --------------------------------------------------------------------------- #

def _checked(vertices, triangles):
    from mfgeom import core
    v = core._as_vertices(vertices)
    t = core._as_triangles(triangles)
    if not np.isfinite(v).all():
        raise InputError("vertices: a coordinate is not finite")
    if t.size and (t.min() < 0 or t.max() >= len(v)):
        raise InputError(f"triangles: an index is outside 0 .. {len(v) - 1}")
    return v, t


def _unit_normals(corners):
    """Unit normals of (t, 3, 3) corner triangles (zero for a degenerate one)."""
    n = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    length = np.linalg.norm(n, axis=1)
    return np.where(length[:, None] > 0, n / np.where(length > 0, length, 1.0)[:, None], 0.0)


def _stl_binary_bytes(v, t):
    corners = v[t]                                                   # (t, 3, 3)
    records = np.zeros(len(t), dtype=_STL_RECORD)
    records["normal"] = _unit_normals(corners)
    records["corners"] = corners
    header = b"binary STL written by mfgeom".ljust(80, b" ")
    return header + np.uint32(len(t)).astype("<u4").tobytes() + records.tobytes()


_STL_FACET = ("facet normal %.9g %.9g %.9g\n  outer loop\n"
              + "    vertex %.17g %.17g %.17g\n" * 3 + "  endloop\nendfacet\n")


def _stl_ascii_bytes(v, t):
    corners = v[t]
    rows = np.hstack([_unit_normals(corners), corners.reshape(-1, 9)]).tolist()
    body = "".join(_STL_FACET % tuple(row) for row in rows)
    return ("solid mfgeom\n" + body + "endsolid mfgeom\n").encode("ascii")


def _obj_bytes(v, t):
    out = ["# written by mfgeom"]
    out += ["v %.17g %.17g %.17g" % tuple(p) for p in v.tolist()]
    out += ["f %d %d %d" % tuple(f) for f in (t + 1).tolist()]
    return ("\n".join(out) + "\n").encode("ascii")


def write_mesh(path, vertices, triangles, ascii=False):
    """Writes the triangle mesh to ``path`` in the format of its extension (.stl: binary,
    or ASCII with ``ascii=True``; .obj).  Vertices must be finite and every index in
    range (InputError otherwise); MeshFileError if the file cannot be written."""
    ext = mesh_format(path)
    v, t = _checked(vertices, triangles)
    if ext == ".obj":
        data = _obj_bytes(v, t)
    else:
        data = _stl_ascii_bytes(v, t) if ascii else _stl_binary_bytes(v, t)
    try:
        write_atomic(path, data)
    except OSError as exc:
        raise MeshFileError(path, f"cannot write: {exc.strerror or exc}") from None
