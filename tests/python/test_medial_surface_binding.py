# SPDX-License-Identifier: LGPL-2.1-or-later
"""core.medial_surface (issue 9): the binding's argument handling and the library's
refusals, which come through MfgError with their detail; the conversion of a result into
MedialSurface on the L-bracket and a cuboid.  The geometry itself is test_medial_surface.py's
(against the oracle)."""

import ctypes
import math

import numpy as np
import pytest

from mfgeom import core
from mfgeom.core import MfgError
from sweep_oracle import box_mesh

V, T = box_mesh((0.0, 0.0, 0.0), (100.0, 60.0, 20.0))
TOL = 1.0


def l_bracket():
    """Arms [0,10] x [0,50] and [0,50] x [0,10], extruded over z in [0, 40]: 8 faces, 18
    edges (one reflex), 12 vertices."""
    p = [(0, 0), (50, 0), (50, 10), (10, 10), (10, 50), (0, 50)]
    v = np.array([(x, y, 0.0) for x, y in p] + [(x, y, 40.0) for x, y in p])
    tris = []
    for a, b, c in [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)]:
        tris += [[6 + a, 6 + b, 6 + c], [a, c, b]]
    for i in range(6):
        j = (i + 1) % 6
        tris += [[i, j, 6 + j], [i, 6 + j, 6 + i]]
    return v, np.array(tris, dtype=np.int64)


def medial_error(v=V, t=T, tol=TOL, **kw):
    with pytest.raises(MfgError) as info:
        core.medial_surface(v, t, tol, **kw)
    return info.value


# ---- refusals: the library checks its input before anything else ------------------------

def test_open_mesh():
    e = medial_error(t=T[:-1])
    assert e.status == "invalid argument"
    assert "not closed" in e.detail and "3 boundary edges" in e.detail


def test_flipped_and_inward_meshes():
    flipped = T.copy()
    flipped[0] = flipped[0, ::-1]
    assert "inconsistent" in medial_error(t=flipped).detail
    assert "negative volume" in medial_error(t=T[:, ::-1]).detail


def test_nonmanifold_mesh():
    v2, t2 = box_mesh((100, 0, 0), (120, 60, 20))   # shares the face x = 100
    w = core.weld(np.vstack([V, v2])[np.vstack([T, t2 + 8])])
    assert medial_error(*w).status == "invalid argument"


def test_degenerate_meshes():
    assert medial_error(t=np.zeros((0, 3), dtype=np.int64)).status == "degenerate input"
    flat = V.copy()
    flat[:, 2] = 0.0
    assert medial_error(v=flat).status in ("degenerate input", "invalid argument")


def test_nan_and_inf():
    for bad in (math.nan, math.inf):
        v = V.copy()
        v[5, 2] = bad
        assert medial_error(v=v).status == "invalid argument"


@pytest.mark.parametrize("tol", [0.0, -0.0, -1.0, math.inf, math.nan])
def test_tolerance_not_positive_or_finite(tol):
    e = medial_error(tol=tol)
    assert e.status == "invalid argument" and "tolerance" in e.detail


def test_tolerance_against_the_box():
    L = math.sqrt(100.0 ** 2 + 60.0 ** 2 + 20.0 ** 2)
    e = medial_error(tol=L)
    assert "smaller than the bounding-box diagonal" in e.detail
    e = medial_error(tol=L / 2 ** 21)
    assert "2^20" in e.detail


def test_index_out_of_range():
    t = T.copy()
    t[3, 1] = 8
    assert medial_error(t=t).status == "invalid argument"
    t[3, 1] = -1
    assert medial_error(t=t).status == "invalid argument"


def test_negative_threads():
    e = medial_error(threads=-1)
    assert e.status == "invalid argument" and "nthreads" in e.detail


def test_unknown_flags_in_the_library():
    """The binding only passes 0 or MFG_MEDIAL_FULL: the library's own refusal of other
    bits, called directly."""
    xyz = np.ascontiguousarray(V, dtype=np.float64)
    tri = np.ascontiguousarray(T, dtype=np.int64)
    res = ctypes.POINTER(core._Medial)()
    status = core._lib.mfg_medial_surface(core._ptr(xyz, ctypes.c_double), len(xyz),
                                          core._ptr(tri, ctypes.c_int64), len(tri), TOL,
                                          2 | core.MEDIAL_FULL, 0, ctypes.byref(res))
    assert core._lib.mfg_status_str(status).decode() == "invalid argument"
    assert "unknown flags 0x2" in core._lib.mfg_last_error().decode()
    assert not res                                   # *out untouched


def test_argument_types():
    with pytest.raises(TypeError, match="major_only"):
        core.medial_surface(V, T, TOL, major_only="yes")
    with pytest.raises(TypeError, match="major_only"):
        core.medial_surface(V, T, TOL, major_only=1)
    with pytest.raises(TypeError, match="threads"):
        core.medial_surface(V, T, TOL, threads=2.0)
    with pytest.raises(TypeError, match="threads"):
        core.medial_surface(V, T, TOL, threads=True)
    with pytest.raises(ValueError, match="int32"):
        core.medial_surface(V, T, TOL, threads=2 ** 31)
    with pytest.raises(TypeError):
        core.medial_surface(V, T.astype(float), TOL)
    with pytest.raises(TypeError):
        core.medial_surface(V, T, "1")
    with pytest.raises(ValueError, match="vertices must have shape"):
        core.medial_surface(V[:, :2], T, TOL)
    with pytest.raises(ValueError, match="triangles must have shape"):
        core.medial_surface(V, T[:, :2], TOL)


# ---- conversion of a result ---------------------------------------------------------------


def check_result(m, v, t):
    """The MedialSurface's arrays: shapes, dtypes and the cross references between them."""
    assert isinstance(m, core.MedialSurface)
    nel = m.nfaces + m.nedges + m.nvertices
    assert m.element_kinds.shape == (nel,) and m.element_convex.shape == (nel,)
    assert m.element_kinds.dtype == np.int32 and m.element_convex.dtype == np.int32
    # ids: faces, then edges, then vertices
    assert np.array_equal(m.element_kinds, [2] * m.nfaces + [1] * m.nedges + [0] * m.nvertices)
    assert np.all(m.element_convex[:m.nfaces] == -1) and np.all(m.element_convex[-m.nvertices:] == -1)
    assert np.all(np.isin(m.element_convex[m.nfaces:m.nfaces + m.nedges], (0, 1)))
    assert m.face_of_triangle.shape == (len(t),) and m.face_of_triangle.dtype == np.int64
    assert m.face_planes.shape == (m.nfaces, 4)
    assert np.allclose(np.linalg.norm(m.face_planes[:, :3], axis=1), 1.0)
    # every input triangle's corners on its face's plane
    for ti, f in enumerate(m.face_of_triangle):
        n, d = m.face_planes[f, :3], m.face_planes[f, 3]
        assert np.allclose(v[t[ti]] @ n, d)
    assert m.edge_segments.shape == (m.nedges, 2, 3) and m.vertex_points.shape == (m.nvertices, 3)
    for s in m.sheets:
        assert s.vertices.ndim == 2 and s.vertices.shape[1] == 3
        assert s.triangles.ndim == 2 and s.triangles.shape[1] == 3
        assert s.radii.shape == (len(s.vertices),)
        assert s.triangles.size == 0 or (s.triangles.min() >= 0 and s.triangles.max() < len(s.vertices))
        assert s.elements.shape == (2,) and s.elements[0] < s.elements[1] < nel
        assert 1 <= s.form <= 11
    for c in m.seams:
        assert c.points.ndim == 2 and c.points.shape[1] == 3 and c.radii.shape == (len(c.points),)
        assert len(c.elements) >= 3 and np.all(np.diff(c.elements) > 0)
        assert c.kind in (0, 1, 2) and c.ends.shape == (2,)
        assert np.all((c.ends >= -1) & (c.ends < len(m.junctions)))
    j = m.junctions
    assert j.points.shape == (len(j), 3) and j.radii.shape == (len(j),)
    assert len(j.elements) == len(j) and j.kinds.shape == (len(j),)
    for e in j.elements:
        assert len(e) >= 4 and np.all(np.diff(e) > 0) and e[-1] < nel
    assert m.cells_visited >= m.leaves >= 0 and m.leaf_size > 0


def test_cuboid_result():
    m = core.medial_surface(V, T, TOL)
    check_result(m, V, T)
    assert (m.nfaces, m.nedges, m.nvertices) == (6, 12, 8)
    # major part: one sheet {z0, z1} at z = 10, radius 10
    assert len(m.sheets) == 1
    s = m.sheets[0]
    assert np.allclose(s.vertices[:, 2], 10.0) and np.allclose(s.radii, 10.0)
    assert s.form == 1                                # parallel planes
    assert len(m.junctions) == 4 and np.allclose(m.junctions.radii, 10.0)


def test_l_bracket_result_and_full():
    v, t = l_bracket()
    major = core.medial_surface(v, t, 0.5, threads=1)
    full = core.medial_surface(v, t, 0.5, major_only=False, threads=2)
    for m in (major, full):
        check_result(m, v, t)
        assert (m.nfaces, m.nedges, m.nvertices) == (8, 18, 12)
        assert np.count_nonzero(m.element_convex == 0) == 1     # the reflex edge
    assert len(full.sheets) > len(major.sheets)
