# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.meshio: STL (binary, ASCII) and OBJ round trips against the meshes written, files
written by hand (quads, polygons, negative and slashed indices, binary STL starting with
"solid"), and malformed files whose errors must name the file and the line."""

import math
import os
import struct

import numpy as np
import pytest

from mfgeom import core, meshio
from mfgeom.errors import InputError, MfgeomError
from sweep_oracle import box_mesh, prism_mesh


def same_mesh(got, want):
    """Same vertices (exactly) and the same triangles."""
    (gv, gt), (wv, wt) = got, want
    assert gv.dtype == np.float64 and gt.dtype == np.int64
    assert gv.shape == wv.shape and gt.shape == wt.shape
    assert np.array_equal(gv, wv)
    assert np.array_equal(gt, wt)


def float32_exact_prism():
    """A prism whose coordinates are float32 values (binary STL stores float32)."""
    v, t = prism_mesh((0.25, -1.5), 2.0, 3.0, 7)
    return v.astype(np.float32).astype(np.float64), t


def weld_order(v, t):
    """The mesh renumbered as a weld of its soup numbers it (first appearance), which is
    what reading an STL gives back: an independent renumbering in numpy."""
    order, seen = [], {}
    for i in t.ravel():
        if i not in seen:
            seen[i] = len(order)
            order.append(i)
    return v[order], np.vectorize(seen.get)(t).astype(np.int64)


@pytest.mark.parametrize("ascii", [False, True])
def test_stl_round_trip(tmp_path, ascii):
    v, t = float32_exact_prism()
    path = tmp_path / "p.stl"
    meshio.write_mesh(path, v, t, ascii=ascii)
    if not ascii:
        assert os.path.getsize(path) == 84 + 50 * len(t)
    same_mesh(meshio.read_mesh(path), weld_order(v, t))


def test_stl_ascii_is_float64_exact(tmp_path):
    """ASCII STL carries 17 digits: any double reads back bit for bit; binary rounds to
    float32 (by at most 2^-24 relative)."""
    rng = np.random.default_rng(1)
    v, t = box_mesh()
    v = v * math.pi + rng.normal(size=v.shape) * 1e-3
    meshio.write_mesh(tmp_path / "a.stl", v, t, ascii=True)
    same_mesh(meshio.read_mesh(tmp_path / "a.stl"), weld_order(v, t))
    meshio.write_mesh(tmp_path / "b.stl", v, t)
    bv, bt = meshio.read_mesh(tmp_path / "b.stl")
    wv, wt = weld_order(v, t)
    assert np.array_equal(bt, wt)
    assert np.allclose(bv, wv, rtol=2.0 ** -24, atol=0) and not np.array_equal(bv, wv)


def test_stl_welds_exact_coordinates_only(tmp_path):
    """Two corners 1e-12 apart stay two vertices; equal ones become one."""
    soup = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                     [[1, 0, 0], [0, 1, 0], [1, 1, 1e-12]]], dtype=np.float64)
    path = tmp_path / "s.stl"
    # float(): numpy 2 prints a numpy scalar as np.float64(...)
    text = "solid s\n" + "".join(
        "facet normal 0 0 1\nouter loop\n"
        + "".join(f"vertex {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in tri)
        + "endloop\nendfacet\n" for tri in soup) + "endsolid s\n"
    path.write_text(text)
    v, t = meshio.read_mesh(path)
    assert len(v) == 4 and t.tolist() == [[0, 1, 2], [1, 2, 3]]
    assert v[3].tolist() == [1.0, 1.0, 1e-12]


def test_stl_binary_normals_and_header(tmp_path):
    v, t = box_mesh((0, 0, 0), (2, 3, 4))
    path = tmp_path / "b.stl"
    meshio.write_mesh(path, v, t)
    data = path.read_bytes()
    assert struct.unpack_from("<I", data, 80)[0] == 12
    rec = np.frombuffer(data, dtype=meshio._STL_RECORD, offset=84)
    # independent: the outward unit normal of each box face from its centroid's side
    c = v[t].mean(axis=1) - [1, 1.5, 2]
    axis = np.argmax(np.abs(c) / [1, 1.5, 2], axis=1)
    want = np.zeros((12, 3))
    want[np.arange(12), axis] = np.sign(c[np.arange(12), axis])
    assert np.allclose(rec["normal"], want, atol=1e-7)


def test_binary_stl_whose_header_starts_with_solid(tmp_path):
    """Many exporters put "solid ..." in the binary header: the size decides."""
    v, t = float32_exact_prism()
    path = tmp_path / "s.stl"
    meshio.write_mesh(path, v, t)
    data = bytearray(path.read_bytes())
    data[:80] = b"solid exported by some CAD tool".ljust(80, b" ")
    path.write_bytes(bytes(data))
    same_mesh(meshio.read_mesh(path), weld_order(v, t))


def test_ascii_stl_mixed_case_and_blank_lines_and_two_solids(tmp_path):
    path = tmp_path / "m.STL"
    path.write_text("SOLID a\n\n  FACET NORMAL 0 0 0\n OUTER LOOP\n VERTEX 0 0 0\n"
                    "VERTEX 1 0 0\nVERTEX 0 1 0\nENDLOOP\nENDFACET\nENDSOLID a\n"
                    "solid b\nfacet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 0 1 0\n"
                    "vertex 0 0 1e0\nendloop\nendfacet\nendsolid\n")
    v, t = meshio.read_mesh(path)
    assert v.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
    assert t.tolist() == [[0, 1, 2], [1, 2, 3]]


def test_obj_round_trip(tmp_path):
    rng = np.random.default_rng(2)
    v, t = prism_mesh((0.1, 0.2), 1.0 / 3.0, math.e, 9)
    v = v + rng.normal(size=v.shape) * 1e-7
    meshio.write_mesh(tmp_path / "p.obj", v, t)
    # OBJ keeps the vertex numbering (no weld): the very same arrays
    same_mesh(meshio.read_mesh(tmp_path / "p.obj"), (v, t))


def test_obj_quads_polygons_negative_and_slashed_indices(tmp_path):
    """A unit cube written with quads in all index styles; fan triangulation from the first
    corner, so its volume (an independent numpy sum) is 1 and it is closed."""
    path = tmp_path / "cube.obj"
    path.write_text(
        "# cube\nmtllib none.mtl\no cube\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "vt 0 0\nvn 0 0 1\n"
        "v 0 0 1\nv 1 0 1\nv 1 1 1 1.0\nv 0 1 1 0.5 0.5 0.5\n"  # w and colour extensions
        "g sides\ns off\nusemtl x\n"
        "f 1 4 3 2\n"                       # bottom, outward -z
        "f -4 -3 -2 -1\n"                   # top (5 6 7 8), negative indices
        "f 1/1 2/1 6/1 5/1\n"               # y = 0
        "f 2//1 3//1 7//1 6//1\n"           # x = 1
        "f 3/1/1 4/1/1 8/1/1 7/1/1\n"       # y = 1
        "f 4 1 \\\n 5 8\n")                 # x = 0, continued on the next line
    v, t = meshio.read_mesh(path)
    assert v.shape == (8, 3) and t.shape == (12, 3)
    assert t[:2].tolist() == [[0, 3, 2], [0, 2, 1]]        # fan from the first corner
    assert t[2:4].tolist() == [[4, 5, 6], [4, 6, 7]]       # -4 .. -1 after 8 vertices
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    assert np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6 == pytest.approx(1.0)
    rep = core.mesh_check(v, t, require_closed=True)
    assert rep.volume == pytest.approx(1.0)


def test_obj_pentagon_fan_and_negative_index_relative_to_its_line(tmp_path):
    path = tmp_path / "p.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\nv 0 1 0\nv -1 0.5 0\n"
                    "f 1 2 3 4 5\nf -1 -2 -3\n")
    v, t = meshio.read_mesh(path)
    assert t.tolist() == [[0, 1, 2], [0, 1, 2], [0, 2, 3], [0, 3, 4], [4, 3, 2]]


def test_write_rejects_bad_meshes(tmp_path):
    v, t = box_mesh()
    with pytest.raises(InputError, match="outside 0 .. 7"):
        meshio.write_mesh(tmp_path / "x.stl", v, np.vstack([t, [[0, 1, 8]]]))
    bad = v.copy()
    bad[3, 1] = np.nan
    with pytest.raises(InputError, match="not finite"):
        meshio.write_mesh(tmp_path / "x.obj", bad, t)
    with pytest.raises(InputError, match="unknown mesh format '.ply'"):
        meshio.write_mesh(tmp_path / "x.ply", v, t)
    with pytest.raises(TypeError):
        meshio.write_mesh(tmp_path / "x.obj", v, t.astype(float))
    assert not list(tmp_path.iterdir())


def test_failed_write_leaves_nothing(tmp_path):
    v, t = box_mesh()
    target = tmp_path / "missing_dir" / "x.stl"
    with pytest.raises(meshio.MeshFileError, match="cannot write") as info:
        meshio.write_mesh(target, v, t)
    assert str(target) in str(info.value)
    # an existing file is replaced only by a complete one
    good = tmp_path / "good.obj"
    meshio.write_mesh(good, v, t)
    before = good.read_bytes()
    with pytest.raises(InputError):
        meshio.write_mesh(good, v, t + 100)
    assert good.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["good.obj"]


def err(path):
    with pytest.raises(meshio.MeshFileError) as info:
        meshio.read_mesh(path)
    e = info.value
    assert isinstance(e, InputError) and isinstance(e, MfgeomError) and isinstance(e, ValueError)
    assert str(path) in str(e)
    return e


FACET = ("facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
         "endloop\nendfacet\n")


@pytest.mark.parametrize("text, line, words", [
    ("solid x\n" + FACET.replace("vertex 1 0 0", "vertex 1 zero 0") + "endsolid\n", 5,
     "bad coordinate"),
    ("solid x\n" + FACET.replace("vertex 1 0 0", "vertex 1 0") + "endsolid\n", 5,
     "needs 3 coordinates"),
    ("solid x\n" + FACET.replace("vertex 0 1 0\n", "") + "endsolid\n", 6, "2 vertices"),
    ("solid x\n" + FACET.replace("endloop", "vertex 1 1 0\nendloop") + "endsolid\n", 7,
     "more than 3"),
    ("solid x\n" + FACET.replace("outer loop\n", "") + "endsolid\n", 3, "outer loop"),
    ("solid x\n" + FACET + "".join(FACET.splitlines(True)[:4]), 13, "'vertex' was expected"),
    ("solid x\n" + FACET + FACET[:60], 13, "found 'vert'"),
    ("solid x\n" + FACET, 9, "'endsolid' was expected"),
    ("solid x\n" + FACET.replace("vertex 0 0 0", "vertex nan 0 0") + "endsolid\n", 4,
     "not finite"),
    ("solid x\nfacett normal 0 0 1\n", 2, "expected 'facet'"),
])
def test_malformed_ascii_stl(tmp_path, text, line, words):
    path = tmp_path / "bad.stl"
    path.write_text(text)
    e = err(path)
    assert e.line == line and f"line {line}" in str(e) and words in str(e)


def test_malformed_binary_stl(tmp_path):
    v, t = box_mesh()
    path = tmp_path / "b.stl"
    meshio.write_mesh(path, v, t)
    data = path.read_bytes()
    path.write_bytes(data[:-7])                       # truncated
    assert "must have 684 bytes, the file has 677" in str(err(path))
    path.write_bytes(data[:50])                       # shorter than a header
    assert "shorter than a binary STL header" in str(err(path))
    path.write_bytes(b"")
    assert "0 bytes" in str(err(path))
    nan = bytearray(data)
    struct.pack_into("<f", nan, 84 + 50 * 5 + 12 + 4, float("nan"))   # triangle 5, corner 0 y
    path.write_bytes(bytes(nan))
    assert "triangle 5 (0-based)" in str(err(path))
    path.write_bytes(b"solid \xff\xfe")               # neither binary nor ASCII
    assert "not ASCII" in str(err(path))


@pytest.mark.parametrize("text, line, words", [
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4, "vertex index 4 out of range: 3 vertices"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "index 0"),
    ("v 0 0 0\nv 1 0 0\nf -3 -1 -2\nv 0 1 0\n", 3, "index -3 out of range"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", 4, "at least 3 vertices, found 2"),
    ("v 0 0 0\nv 1 x 0\n", 2, "bad coordinate"),
    ("v 0 0\n", 1, "needs 3 coordinates"),
    ("v 0 0 inf\n", 1, "not finite"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 a/3\n", 4, "bad vertex index 'a/3'"),
    ("v 0 0 0\n\nv 1 0 0 \\\n", 3, "continued line"),
])
def test_malformed_obj(tmp_path, text, line, words):
    path = tmp_path / "bad.obj"
    path.write_text(text)
    e = err(path)
    assert e.line == line and f"line {line}" in str(e) and words in str(e)


def test_unreadable_files(tmp_path):
    e = err(tmp_path / "none.obj")
    assert "cannot read" in str(e) and e.line is None
    (tmp_path / "dir.stl").mkdir()
    assert "cannot read" in str(err(tmp_path / "dir.stl"))
    (tmp_path / "bin.obj").write_bytes(b"v 0 0 0\n\xff\n")
    assert "not UTF-8" in str(err(tmp_path / "bin.obj"))
    (tmp_path / "x.off").write_text("OFF\n")
    assert "unknown mesh format '.off'" in str(err(tmp_path / "x.off"))
