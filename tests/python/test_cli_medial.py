# SPDX-License-Identifier: LGPL-2.1-or-later
"""``mfgeom medial-surface`` (issue 9), run as a subprocess, and its file formats
(mfgeom.medialio).  Bad input must give exit code 2, one line {"error": ...} on stderr
naming the problem, nothing on stdout and no output file.  The formats are checked on a
hand-made MedialSurface (no library needed): the JSON document, the PLY header and rows
(per-vertex radius, per-face sheet) and the OBJ groups; a run on a cuboid must print /
write exactly what core.medial_surface returns."""

import json
import math
import os
import subprocess

import numpy as np
import pytest

from mfgeom import core, medialio, meshio
from sweep_oracle import box_mesh

_HERE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.dirname(os.path.dirname(_HERE))
PYTHON = "/usr/bin/python3"
BOX = ((0.0, 0.0, 0.0), (100.0, 60.0, 20.0))


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.join(_REPO, "workbench")
    env["MFGEOM_LIBRARY"] = os.path.abspath(core.library_path)
    return env


def run(args):
    """(exit code, parsed stdout or None, stderr text)."""
    proc = subprocess.run([PYTHON, "-m", "mfgeom.cli"] + [str(a) for a in args],
                          capture_output=True, text=True, env=_env(), timeout=300, cwd=_REPO)
    out = json.loads(proc.stdout) if proc.stdout.strip() else None
    return proc.returncode, out, proc.stderr


def failed(args, *words):
    rc, out, err = run(args)
    assert rc == 2 and out is None, (rc, out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    message = json.loads(lines[0])["error"]
    for w in words:
        assert w in message, message
    return message


@pytest.fixture
def box_stl(tmp_path):
    path = tmp_path / "box.stl"
    meshio.write_mesh(path, *box_mesh(*BOX))
    return path


# ---- errors --------------------------------------------------------------------------------

def test_open_mesh(tmp_path):
    v, t = box_mesh(*BOX)
    src = tmp_path / "open.obj"
    meshio.write_mesh(src, v, t[:-1])
    out = tmp_path / "out.ply"
    failed(["medial-surface", src, "--tolerance", 1, "--ply", out], str(src), "not closed",
           "3 boundary edges")
    assert not out.exists()


def test_flipped_mesh(tmp_path):
    v, t = box_mesh(*BOX)
    src = tmp_path / "inward.obj"
    meshio.write_mesh(src, v, t[:, ::-1])
    failed(["medial-surface", src, "--tolerance", 1], str(src), "negative volume")


@pytest.mark.parametrize("tol", ["0", "-1", "inf", "nan"])
def test_bad_tolerance(box_stl, tol):
    failed(["medial-surface", box_stl, "--tolerance", tol], "--tolerance", "positive")


def test_tolerance_the_library_refuses(box_stl):
    failed(["medial-surface", box_stl, "--tolerance", 1000], str(box_stl), "tolerance",
           "bounding-box diagonal")


def test_bad_threads(box_stl):
    failed(["medial-surface", box_stl, "--tolerance", 1, "--threads", -2], "--threads", ">= 0")
    failed(["medial-surface", box_stl, "--tolerance", 1, "--threads", "two"], "--threads",
           "invalid int")


def test_bad_files(tmp_path, box_stl):
    failed(["medial-surface", tmp_path / "none.stl", "--tolerance", 1], "none.stl",
           "cannot read")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 5\n")
    failed(["medial-surface", bad, "--tolerance", 1], "bad.obj, line 4", "out of range")
    ply = tmp_path / "in.ply"
    ply.write_text("ply\n")
    failed(["medial-surface", ply, "--tolerance", 1], "unknown mesh format '.ply'")


def test_usage_errors(tmp_path, box_stl):
    failed(["medial-surface", box_stl], "required", "--tolerance")
    failed(["medial-surface", "--tolerance", 1], "required", "IN")
    failed(["medial-surface", box_stl, "--tolerance", 1, "--ply", tmp_path / "a.ply",
            "--obj", tmp_path / "a.obj"], "not allowed with")
    assert not (tmp_path / "a.ply").exists() and not (tmp_path / "a.obj").exists()


@pytest.mark.parametrize("opt, name", [("--json", "r.json"), ("--ply", "m.ply"),
                                       ("--obj", "m.obj")])
def test_unwritable_output_fails_before_the_work(tmp_path, box_stl, opt, name):
    target = tmp_path / "no_dir" / name
    failed(["medial-surface", box_stl, "--tolerance", 1, opt, target], "cannot write",
           name, opt, "no directory")


# ---- formats on a hand-made result ---------------------------------------------------------

def fake_medial():
    """Two sheets (a square of 2 triangles at z = 10, radius 10; one triangle), one seam,
    one junction: enough to check every field's place in the files."""
    sq = core.MedialSheet(np.array([[10.0, 10, 10], [90, 10, 10], [90, 50, 10], [10, 50, 10]]),
                          np.array([[0, 1, 2], [0, 2, 3]]), np.full(4, 10.0),
                          np.array([0, 5]), 1)
    tri = core.MedialSheet(np.array([[0.0, 0, 0], [10, 10, 10], [0, 10, 10]]),
                           np.array([[0, 1, 2]]), np.array([0.0, 10, 7.5]),
                           np.array([0, 2]), 2)
    seam = core.MedialSeam(np.array([[10.0, 10, 10], [90, 10, 10]]), np.array([10.0, 10]),
                           np.array([0, 2, 5]), 0, np.array([0, -1]))
    junctions = core.MedialSurfaceJunctions(np.array([[10.0, 10, 10]]), np.array([10.0]),
                                            [np.array([0, 1, 2, 5])], np.array([0]))
    v, t = box_mesh(*BOX)
    kinds = np.array([2] * 6 + [1] * 12 + [0] * 8, dtype=np.int32)
    convex = np.array([-1] * 6 + [1] * 12 + [-1] * 8, dtype=np.int32)
    planes = np.zeros((6, 4))
    planes[:, 0] = 1.0
    return core.MedialSurface([sq, tri], [seam], junctions, kinds, convex,
                              np.arange(12, dtype=np.int64) // 2, planes,
                              np.zeros((12, 2, 3)), v, 123, 45, 0.75)


def test_document():
    m = fake_medial()
    doc = medialio.document(m)
    text = json.dumps(doc, allow_nan=False)                # plain JSON, no NaN
    assert json.loads(text) == doc
    e = doc["elements"]
    assert (e["faces"], e["edges"], e["vertices"]) == (6, 12, 8)
    assert e["kinds"] == ["face"] * 6 + ["edge"] * 12 + ["vertex"] * 8
    assert e["convex"][6] == 1 and e["face_of_triangle"][11] == 5
    assert np.array(e["edge_segments"]).shape == (12, 2, 3)
    assert np.array(e["vertex_points"]).shape == (8, 3)
    s0, s1 = doc["sheets"]
    assert s0["elements"] == [0, 5] and s0["form"] == 1
    assert s0["form_name"] == "plane-plane parallel" and s1["form_name"] == "plane-plane"
    assert s0["area"] == pytest.approx(80 * 40) and s0["radii"] == [10.0] * 4
    assert s0["triangles"] == [[0, 1, 2], [0, 2, 3]]
    assert s1["area"] == pytest.approx(0.5 * np.linalg.norm(np.cross([10, 10, 10], [0, 10, 10])))
    (c,) = doc["seams"]
    assert c == {"elements": [0, 2, 5], "kind": "branch", "points": [[10, 10, 10], [90, 10, 10]],
                 "radii": [10, 10], "ends": [0, -1]}
    (j,) = doc["junctions"]
    assert j == {"point": [10, 10, 10], "radius": 10, "elements": [0, 1, 2, 5], "kind": "branch"}
    assert doc["cost"] == {"cells_visited": 123, "leaves": 45, "leaf_size": 0.75}


def read_ply(text):
    """A minimal reader of the ASCII PLY medialio writes: header elements and rows."""
    lines = text.splitlines()
    assert lines[0] == "ply" and lines[1] == "format ascii 1.0"
    end = lines.index("end_header")
    head = lines[:end]
    nv = int(next(l for l in head if l.startswith("element vertex")).split()[2])
    nf = int(next(l for l in head if l.startswith("element face")).split()[2])
    props = [l.split()[-1] for l in head if l.startswith("property")]
    rows = lines[end + 1:]
    assert len(rows) == nv + nf
    verts = np.array([[float(x) for x in r.split()] for r in rows[:nv]]).reshape(-1, 4)
    faces = np.array([[int(x) for x in r.split()] for r in rows[nv:]]).reshape(-1, 5)
    return props, verts, faces


def test_ply(tmp_path):
    m = fake_medial()
    path = tmp_path / "m.ply"
    medialio.write_ply(path, m)
    props, verts, faces = read_ply(path.read_text())
    assert props == ["x", "y", "z", "radius", "vertex_indices", "sheet"]
    assert np.array_equal(verts[:, :3], np.vstack([s.vertices for s in m.sheets]))
    assert np.array_equal(verts[:, 3], np.concatenate([s.radii for s in m.sheets]))
    assert np.all(faces[:, 0] == 3)
    assert faces[:, 1:4].tolist() == [[0, 1, 2], [0, 2, 3], [4, 5, 6]]   # second sheet: + 4
    assert faces[:, 4].tolist() == [0, 0, 1]
    assert not list(tmp_path.glob("*.partial"))


def test_obj(tmp_path):
    m = fake_medial()
    path = tmp_path / "m.obj"
    medialio.write_obj(path, m)
    groups, verts, cur = {}, [], None
    for line in path.read_text().splitlines():
        w = line.split()
        if not w or w[0] == "#":
            continue
        if w[0] == "g":
            cur = w[1]
            groups[cur] = []
        elif w[0] == "v":
            verts.append([float(x) for x in w[1:]])
        else:
            groups[cur].append((w[0], [int(x) - 1 for x in w[1:]]))
    verts = np.array(verts)
    assert list(groups) == ["sheet_0", "sheet_1", "seam_0"]
    assert groups["sheet_1"] == [("f", [4, 5, 6])]
    (kind, idx), = groups["seam_0"]
    assert kind == "l" and np.array_equal(verts[idx], m.seams[0].points)
    # the file reads back (the triangles only) with meshio
    v, t = meshio.read_mesh(path)
    assert len(t) == 3


def test_unwritable_ply(tmp_path):
    with pytest.raises(meshio.MeshFileError, match="cannot write"):
        medialio.write_ply(tmp_path / "no_dir" / "m.ply", fake_medial())


# ---- a real run ------------------------------------------------------------------------------

def test_cuboid_run(tmp_path, box_stl):
    ply, report = tmp_path / "m.ply", tmp_path / "m.json"
    rc, summary, err = run(["medial-surface", box_stl, "--tolerance", 1, "--threads", 1,
                            "--json", report, "--ply", ply])
    assert rc == 0 and not err.strip(), err
    doc = json.loads(report.read_text())
    ref = core.medial_surface(*meshio.read_mesh(box_stl), 1.0, threads=1)
    want = medialio.document(ref)
    for key in ("elements", "sheets", "seams", "junctions"):
        assert doc[key] == json.loads(json.dumps(want[key])), key
    assert doc["full"] is False and doc["tolerance"] == 1.0 and doc["input_triangles"] == 12
    assert summary["json"] == str(report) and summary["ply"] == str(ply)
    assert (summary["sheets"], summary["seams"], summary["junctions"]) == (
        len(ref.sheets), len(ref.seams), len(ref.junctions))
    assert set(summary["time_s"]) == {"read", "medial", "write"}
    props, verts, faces = read_ply(ply.read_text())
    assert len(verts) == sum(len(s.vertices) for s in ref.sheets)
    assert np.array_equal(verts[:, 3], np.concatenate([s.radii for s in ref.sheets]))
    # the cuboid's major sheet: z = 10, radius 10
    assert np.allclose(verts[:, 2], 10.0) and np.allclose(verts[:, 3], 10.0)


def test_full_to_stdout(box_stl):
    rc, doc, err = run(["medial-surface", box_stl, "--tolerance", 1, "--full"])
    assert rc == 0, err
    assert doc["full"] is True and len(doc["sheets"]) > 1
    assert all(math.isfinite(r) for s in doc["sheets"] for r in s["radii"])
