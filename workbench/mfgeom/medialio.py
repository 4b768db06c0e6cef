# SPDX-License-Identifier: LGPL-2.1-or-later
"""Files of a medial surface (core.MedialSurface), with numpy alone (no FreeCAD):

    document(m)          -> a JSON-able dict: the element tables, sheets, seams, junctions
    write_ply(path, m)   the sheets as one ASCII PLY mesh: per vertex x y z and ``radius``
                         (the distance to the boundary), per face its ``sheet`` index
    write_obj(path, m)   the sheets as OBJ groups ``sheet_<i>`` (triangles) and the seams
                         as groups ``seam_<i>`` (``l`` polylines); OBJ has no place for
                         the radii (use PLY or JSON)

Kinds are written as names: elements "face" / "edge" / "vertex", seams and junctions
"branch" / "smooth" / "degenerate"; a sheet's bisector form as its number (1 .. 11) and
name.  Files are written to a temporary file next to the target and renamed over it when
complete: a failed write leaves no half-written file.
"""


import numpy as np

from mfgeom import core
from mfgeom.fileio import write_atomic
from mfgeom.meshio import MeshFileError


def _name(names, k):
    k = int(k)
    return names[k] if 0 <= k < len(names) and names[k] else k


def _sheet_area(s):
    if len(s.triangles) == 0:
        return 0.0
    c = s.vertices[s.triangles]
    return float(0.5 * np.linalg.norm(np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]),
                                      axis=1).sum())


def document(m):
    """The medial surface ``m`` as a dict of lists (json.dump-able): ``elements``
    (``kinds``, ``convex``, ``face_of_triangle``, ``face_planes``, ``edge_segments``,
    ``vertex_points``), ``sheets`` (each ``elements``, ``form``, ``form_name``, ``area``,
    ``vertices``, ``triangles``, ``radii``), ``seams`` (each ``elements``, ``kind``,
    ``points``, ``radii``, ``ends``), ``junctions`` (each ``point``, ``radius``,
    ``elements``, ``kind``) and ``cost`` (``cells_visited``, ``leaves``, ``leaf_size``)."""
    j = m.junctions
    return {
        "elements": {
            "faces": m.nfaces, "edges": m.nedges, "vertices": m.nvertices,
            "kinds": [_name(core.ELEMENT_KINDS, k) for k in m.element_kinds],
            "convex": m.element_convex.tolist(),
            "face_of_triangle": m.face_of_triangle.tolist(),
            "face_planes": m.face_planes.tolist(),
            "edge_segments": m.edge_segments.tolist(),
            "vertex_points": m.vertex_points.tolist(),
        },
        "sheets": [{"elements": s.elements.tolist(), "form": s.form,
                    "form_name": _name(core.BISECTOR_FORMS, s.form), "area": _sheet_area(s),
                    "vertices": s.vertices.tolist(), "triangles": s.triangles.tolist(),
                    "radii": s.radii.tolist()} for s in m.sheets],
        "seams": [{"elements": c.elements.tolist(), "kind": _name(core.MEDIAL_KINDS, c.kind),
                   "points": c.points.tolist(), "radii": c.radii.tolist(),
                   "ends": c.ends.tolist()} for c in m.seams],
        "junctions": [{"point": j.points[i].tolist(), "radius": float(j.radii[i]),
                       "elements": j.elements[i].tolist(),
                       "kind": _name(core.MEDIAL_KINDS, j.kinds[i])} for i in range(len(j))],
        "cost": {"cells_visited": m.cells_visited, "leaves": m.leaves,
                 "leaf_size": m.leaf_size},
    }


def _sheets_merged(m):
    """All sheets as one mesh: vertices (k, 3), radii (k,), triangles (t, 3), sheet (t,)."""
    verts, radii, tris, sheet = [], [], [], []
    base = 0
    for i, s in enumerate(m.sheets):
        verts.append(s.vertices)
        radii.append(s.radii)
        tris.append(s.triangles + base)
        sheet.append(np.full(len(s.triangles), i, dtype=np.int64))
        base += len(s.vertices)
    if not verts:
        return (np.zeros((0, 3)), np.zeros(0), np.zeros((0, 3), dtype=np.int64),
                np.zeros(0, dtype=np.int64))
    return np.vstack(verts), np.concatenate(radii), np.vstack(tris), np.concatenate(sheet)


def _write_atomic(path, text):
    try:
        write_atomic(path, text, encoding="ascii", newline="\n")
    except OSError as exc:
        raise MeshFileError(path, f"cannot write: {exc.strerror or exc}") from None


def ply_text(m):
    v, r, t, sheet = _sheets_merged(m)
    head = ["ply", "format ascii 1.0", "comment medial surface sheets written by mfgeom",
            "comment radius: distance to the boundary; sheet: index of the sheet",
            f"element vertex {len(v)}", "property double x", "property double y",
            "property double z", "property double radius", f"element face {len(t)}",
            "property list uchar int vertex_indices", "property int sheet", "end_header"]
    rows = ["%.17g %.17g %.17g %.17g" % (p[0], p[1], p[2], q)
            for p, q in zip(v.tolist(), r.tolist())]
    rows += ["3 %d %d %d %d" % (f[0], f[1], f[2], s) for f, s in zip(t.tolist(), sheet.tolist())]
    return "\n".join(head + rows) + "\n"


def write_ply(path, m):
    """The sheets of ``m`` as one ASCII PLY mesh with a per-vertex ``radius`` and a
    per-face ``sheet``; MeshFileError if the file cannot be written."""
    _write_atomic(path, ply_text(m))


def obj_text(m):
    out = ["# medial surface written by mfgeom: groups sheet_<i> (triangles), "
           "seam_<i> (polylines)"]
    base = 1
    for i, s in enumerate(m.sheets):
        out.append(f"g sheet_{i}")
        out += ["v %.17g %.17g %.17g" % tuple(p) for p in s.vertices.tolist()]
        out += ["f %d %d %d" % tuple(f) for f in (s.triangles + base).tolist()]
        base += len(s.vertices)
    for i, c in enumerate(m.seams):
        out.append(f"g seam_{i}")
        out += ["v %.17g %.17g %.17g" % tuple(p) for p in c.points.tolist()]
        if len(c.points) >= 2:
            out.append("l " + " ".join(str(base + k) for k in range(len(c.points))))
        base += len(c.points)
    return "\n".join(out) + "\n"


def write_obj(path, m):
    """The sheets of ``m`` as OBJ triangle groups and its seams as polyline groups;
    MeshFileError if the file cannot be written."""
    _write_atomic(path, obj_text(m))
