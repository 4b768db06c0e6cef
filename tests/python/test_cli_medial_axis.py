# SPDX-License-Identifier: LGPL-2.1-or-later
"""``mfgeom medial-axis`` (issue 9 section 3): JSON rings in, JSON axis out, run as a
subprocess.  The printed axis must be the binding's (same branches, points, radii,
junctions), the hand-derived axes of the rectangle and the frame must come out, -o must
write the document and print a summary, and bad input must give exit code 2, one line
{"error": ...} on stderr naming the problem, nothing on stdout and no output file."""

import json
import math
import os
import subprocess

import numpy as np
import pytest

from mfgeom import core

_HERE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.dirname(os.path.dirname(_HERE))
PYTHON = "/usr/bin/python3"
RECT = [[[0, 0], [10, 0], [10, 4], [0, 4]]]
FRAME = [[[0, 0], [10, 0], [10, 10], [0, 10]], [[2, 2], [2, 8], [8, 8], [8, 2]]]


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.join(_REPO, "workbench")
    env["MFGEOM_LIBRARY"] = os.path.abspath(core.library_path)
    return env


def run(args, stdin=None):
    """(exit code, parsed stdout or None, stderr text)."""
    proc = subprocess.run([PYTHON, "-m", "mfgeom.cli"] + [str(a) for a in args],
                          capture_output=True, text=True, env=_env(), timeout=120, cwd=_REPO,
                          input=stdin)
    out = json.loads(proc.stdout) if proc.stdout.strip() else None
    return proc.returncode, out, proc.stderr


def write(tmp_path, doc, name="in.json"):
    path = tmp_path / name
    path.write_text(json.dumps(doc))
    return path


def test_rectangle_hand_derived(tmp_path):
    code, out, err = run(["medial-axis", write(tmp_path, {"rings": RECT}), "--tolerance", 0.01])
    assert code == 0, err
    assert out["tolerance"] == 0.01
    j = out["junctions"]
    # canonical order: junctions by x; each touches 3 edges, radius 2, degree 3
    assert [jj["point"] for jj in j] == [[2.0, 2.0], [8.0, 2.0]]
    assert [jj["radius"] for jj in j] == [2.0, 2.0]
    assert [jj["degree"] for jj in j] == [3, 3]
    assert j[0]["elements"] == [0, 2, 3] and j[1]["elements"] == [0, 1, 2]
    b = out["branches"]
    assert len(b) == 5
    assert b[0] == {"points": [[2.0, 2.0], [8.0, 2.0]], "radii": [2.0, 2.0], "ends": [0, 1]}
    leaves = sorted(tuple(br["points"][-1]) for br in b if br["ends"][1] == -1)
    assert leaves == [(0.0, 0.0), (0.0, 4.0), (10.0, 0.0), (10.0, 4.0)]
    assert all(br["radii"][-1] == 0.0 for br in b[1:])


def test_same_as_binding_frame_and_tolerance_from_input(tmp_path):
    # the frame: parabolic arcs sampled; the tolerance comes from the input document
    code, out, err = run(["medial-axis", write(tmp_path, {"rings": FRAME, "tolerance": 1e-3})])
    assert code == 0, err
    ax = core.medial_axis([np.asarray(r, float) for r in FRAME], 1e-3)
    assert len(out["branches"]) == len(ax.branches) == 8
    assert len(out["junctions"]) == len(ax.junctions) == 4
    for bo, bb in zip(out["branches"], ax.branches):
        assert np.array_equal(np.asarray(bo["points"]), bb.points)
        assert np.array_equal(np.asarray(bo["radii"]), bb.radii)
        assert bo["ends"] == [int(e) for e in bb.ends]
    t = (2 - math.sqrt(2)) * 2
    for jj in out["junctions"]:
        assert abs(jj["radius"] - t) < 1e-9 and jj["degree"] == 3
        assert sum(1 for e in jj["elements"] if e < 0) == 1     # one hole corner each


def test_stdin_bare_list_and_output_file(tmp_path):
    dst = tmp_path / "axis.json"
    code, out, err = run(["medial-axis", "-", "--tolerance", 0.01, "-o", dst],
                         stdin=json.dumps(RECT))
    assert code == 0, err
    assert out["output"] == str(dst)
    assert (out["branches"], out["junctions"], out["points"]) == (5, 2, 10)
    doc = json.loads(dst.read_text())
    assert len(doc["branches"]) == 5 and len(doc["junctions"]) == 2


@pytest.mark.parametrize("doc,args,needle", [
    ({"rings": RECT}, [], "--tolerance"),
    ({"rings": RECT}, ["--tolerance", 0], "positive"),
    ({"rings": RECT}, ["--tolerance", -1], "positive"),
    ({"rings": RECT, "tolerance": "a"}, [], "must be a number"),
    ({"points": []}, ["--tolerance", 0.1], "rings"),
    ({"rings": [[[0, 0], [1, 1], [1, 0], [0, 1]]]}, ["--tolerance", 0.1], "crosses"),
    ({"rings": [[[0, 0], [1, 0]]]}, ["--tolerance", 0.1], "fewer than 3"),
    ({"rings": [[[0, 0], [1, 0], [1]]]}, ["--tolerance", 0.1], "rings[0][2]"),
])
def test_bad_input(tmp_path, doc, args, needle):
    dst = tmp_path / "out.json"
    code, out, err = run(["medial-axis", write(tmp_path, doc)] + args + ["-o", dst])
    assert code == 2
    assert out is None
    assert needle in json.loads(err.strip().splitlines()[-1])["error"]
    assert not dst.exists()
