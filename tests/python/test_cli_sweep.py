# SPDX-License-Identifier: LGPL-2.1-or-later
"""``mfgeom sweep`` (issue 8): mesh file in, swept mesh file out, run as a subprocess.
Bad input must give exit code 2, one line {"error": ...} on stderr naming the problem,
nothing on stdout and no output file; a good run writes a closed mesh whose volume is the
reported one and the binding's, and prints the report (also to --json)."""

import json
import math
import os
import subprocess

import numpy as np
import pytest

from mfgeom import core, meshio
from sweep_oracle import box_mesh

_HERE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.dirname(os.path.dirname(_HERE))
PYTHON = "/usr/bin/python3"


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.join(_REPO, "workbench")
    env["MFGEOM_LIBRARY"] = os.path.abspath(core.library_path)
    return env


def run(args):
    """(exit code, parsed stdout or None, stderr text)."""
    proc = subprocess.run([PYTHON, "-m", "mfgeom.cli"] + [str(a) for a in args],
                          capture_output=True, text=True, env=_env(), timeout=120, cwd=_REPO)
    out = json.loads(proc.stdout) if proc.stdout.strip() else None
    return proc.returncode, out, proc.stderr


A, B, C = 2.0, 1.0, 1.5          # box about its edge on the z axis


@pytest.fixture
def box_stl(tmp_path):
    v, t = box_mesh((0, 0, 0), (A, B, C))
    path = tmp_path / "box.stl"
    meshio.write_mesh(path, v, t)
    return path


def sweep_args(src, out, angle=90, tol=5e-2, point=(0, 0, 0), direction=(0, 0, 1)):
    return (["sweep", src, "--axis-point", *point, "--axis-dir", *direction,
             "--angle", angle, "--tolerance", tol, "-o", out])


def failed(args, *words):
    rc, out, err = run(args)
    assert rc == 2 and out is None
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    message = json.loads(lines[0])["error"]
    for w in words:
        assert w in message, message
    return message


def test_open_mesh(tmp_path):
    v, t = box_mesh()
    src = tmp_path / "open.obj"
    meshio.write_mesh(src, v, t[:-1])
    out = tmp_path / "out.stl"
    failed(sweep_args(src, out), str(src), "not closed", "3 boundary edges")
    assert not out.exists()


@pytest.mark.parametrize("change, words", [
    (dict(direction=(0, 0, 0)), ["--axis-dir", "zero vector"]),
    (dict(angle=0), ["--angle", "(0, 360]"]),
    (dict(angle=360.5), ["--angle", "(0, 360]"]),
    (dict(angle="nan"), ["--angle"]),
    (dict(tol=0), ["--tolerance", "positive"]),
    (dict(tol=-1), ["--tolerance", "positive"]),
    (dict(tol="inf"), ["--tolerance", "positive"]),
    (dict(point=(0, "nan", 0)), ["--axis-point", "finite"]),
])
def test_bad_arguments(tmp_path, box_stl, change, words):
    out = tmp_path / "out.stl"
    failed(sweep_args(box_stl, out, **change), *words)
    assert not out.exists()


def test_bad_files(tmp_path, box_stl):
    out = tmp_path / "out.stl"
    failed(sweep_args(tmp_path / "none.stl", out), "none.stl", "cannot read")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 5\n")
    failed(sweep_args(bad, out), "bad.obj, line 4", "out of range")
    failed(sweep_args(box_stl, tmp_path / "out.ply"), "unknown mesh format '.ply'")
    assert not out.exists()


def test_unwritable_output(tmp_path, box_stl):
    failed(sweep_args(box_stl, tmp_path / "no_dir" / "out.stl"), "no_dir", "cannot write")
    failed(sweep_args(box_stl, tmp_path / "out.stl") + ["--json", tmp_path / "no_dir" / "r.json"],
           "cannot write", "r.json")
    # issue 22: the STL was written before the report failed; a failed command leaves
    # neither (nor a temporary file)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["box.stl"]


def test_failure_keeps_an_existing_output(tmp_path, box_stl):
    """issue 22: outputs are written atomically -- a command failing before its output is
    complete leaves the file that was there untouched."""
    out = tmp_path / "out.stl"
    out.write_bytes(b"previous result")
    open_mesh = tmp_path / "open.stl"
    v, t = box_mesh((0, 0, 0), (A, B, C))
    meshio.write_mesh(open_mesh, v, t[:-1])
    failed(sweep_args(open_mesh, out), "open.stl")
    assert out.read_bytes() == b"previous result"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["box.stl", "open.stl", "out.stl"]


def test_usage_errors(box_stl):
    failed(["sweep", box_stl, "--angle", "90"], "required")
    failed(["sweep", box_stl, "--axis-point", "0", "0", "--axis-dir", "0", "0", "1",
            "--angle", "90", "--tolerance", "1e-3", "-o", "x.stl"], "--axis-point")


@pytest.mark.parametrize("out_name, extra", [("out.stl", []), ("out.obj", []),
                                              ("out.stl", ["--ascii"])])
def test_box_about_an_edge(tmp_path, box_stl, out_name, extra):
    out, report = tmp_path / out_name, tmp_path / "report.json"
    tol = 5e-2
    rc, doc, err = run(sweep_args(box_stl, out, angle=90, tol=tol) + ["--json", report] + extra)
    assert rc == 0 and not err.strip(), err
    assert json.loads(report.read_text()) == doc
    theta = math.pi / 2
    want = C * (A * B + (A * A + B * B) * theta / 2)
    # the boundary within tol of the true one: volume within tol * (curved area) of it
    assert abs(doc["volume"] - want) <= 1.05 * tol * math.hypot(A, B) * theta * C
    assert doc["input_triangles"] == 12 and doc["input_vertices"] == 8
    assert doc["angle_deg"] == 90 and doc["tolerance"] == tol
    assert set(doc["time_s"]) == {"read", "sweep", "write"}
    ref = core.rotational_sweep(*box_mesh((0, 0, 0), (A, B, C)), (0, 0, 0), (0, 0, 1),
                                theta, tol)
    assert doc["volume"] == pytest.approx(ref.volume, rel=1e-12)
    assert (doc["vertices"], doc["triangles"]) == (len(ref.vertices), len(ref.triangles))
    v, t = meshio.read_mesh(out)
    rep = core.mesh_check(v, t, require_closed=True)
    assert len(t) == doc["triangles"]
    if out_name.endswith(".obj"):                # the very same arrays
        assert np.array_equal(v, ref.vertices) and np.array_equal(t, ref.triangles)
    elif extra:                                  # ASCII STL: float64 exact, welded
        # the used vertices, those at the same place (copies) as one
        assert len(v) == len(np.unique(ref.vertices[np.unique(ref.triangles)], axis=0))
        assert np.array_equal(v[t], ref.vertices[ref.triangles])
    else:                                        # binary STL: float32 coordinates
        assert np.array_equal(v[t], ref.vertices[ref.triangles].astype(np.float32))
    assert rep.volume == pytest.approx(doc["volume"], rel=1e-12 if extra or ".obj" in out_name
                                       else 1e-6)
    assert np.allclose(np.array(doc["bbox"]), rep.bbox, atol=1e-6)


def test_360_degrees_is_the_full_turn(tmp_path):
    v, t = box_mesh((1.0, -0.5, 0.0), (2.0, 0.5, 1.0))
    src = tmp_path / "box.obj"
    meshio.write_mesh(src, v, t)
    rc, doc, err = run(sweep_args(src, tmp_path / "ring.obj", angle=360, tol=1e-2))
    assert rc == 0, err
    ref = core.rotational_sweep(v, t, (0, 0, 0), (0, 0, 1), 2 * math.pi, 1e-2)
    assert doc["volume"] == pytest.approx(ref.volume, rel=1e-12)
    annulus = math.pi * (2.0 ** 2 + 0.5 ** 2 - 1.0)
    assert abs(doc["volume"] - annulus) <= 1.05 * 1e-2 * doc["area"]


def test_binary_stl_of_a_finer_result_is_still_closed(tmp_path, box_stl):
    """Binary STL keeps float32 coordinates: vertices of the result closer than float32
    resolution (~1e-7 relative) collapse on reading and leave triangles with a repeated
    vertex.  The written file must still be a closed mesh."""
    out = tmp_path / "fine.stl"
    rc, doc, err = run(sweep_args(box_stl, out, angle=90, tol=1e-2))
    assert rc == 0, err
    v, t = meshio.read_mesh(out)
    rep = core.mesh_check(v, t)
    collapsed = int(np.count_nonzero((t[:, 0] == t[:, 1]) | (t[:, 1] == t[:, 2])
                                     | (t[:, 2] == t[:, 0])))
    ok = (rep.boundary_edges, rep.nonmanifold_edges, collapsed) == (0, 0, 0)
    what = (f"after float32 rounding: {rep.boundary_edges} boundary and {rep.nonmanifold_edges} "
            f"non-manifold edges, {collapsed} of {rep.ntriangles} triangles with a repeated "
            "vertex")
    assert ok, what
