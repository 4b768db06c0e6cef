# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tests of ``mfgeom mould PART --out DIR`` (issue 21): the core, cavity and insert STEP
files of bundled parts written from examples/parts, read back and checked against the
part (volumes add up to the block, each a valid solid), a part that cannot be moulded
leaving no files, and usage errors.

Needs FreeCAD's Python modules (Debian's /usr/lib/freecad-python3/lib, or
MFGEOM_FREECAD_LIB): skipped with the reason otherwise."""

import json
import os
import subprocess
import sys

import pytest

from mfgeom import core, paths

_HERE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.dirname(os.path.dirname(_HERE))
PYTHON = "/usr/bin/python3"

_LIB = paths.add_freecad_to_path()
if _LIB is None:
    pytest.skip("FreeCAD's Python modules not found (set MFGEOM_FREECAD_LIB)",
                allow_module_level=True)
if os.path.join(_REPO, "examples", "parts") not in sys.path:
    sys.path.append(os.path.join(_REPO, "examples", "parts"))
try:
    import FreeCAD as App  # noqa: E402
    import Part  # noqa: E402
except ImportError as _exc:
    pytest.skip(f"FreeCAD not importable from {_LIB}: {_exc}", allow_module_level=True)

import cup_hole  # noqa: E402
import knob  # noqa: E402


def run(args):
    env = dict(os.environ, PYTHONPATH=os.path.join(_REPO, "workbench"),
               MFGEOM_LIBRARY=os.path.abspath(core.library_path))
    p = subprocess.run([PYTHON, "-m", "mfgeom.cli"] + args, env=env, capture_output=True,
                       text=True, timeout=600)
    out = json.loads(p.stdout) if p.stdout.strip() else None
    err = json.loads(p.stderr.strip().splitlines()[-1]) if p.stderr.strip() else None
    return p.returncode, out, err


@pytest.mark.parametrize("name,inserts", [("cup_hole", 1), ("knob", 0)])
def test_step_files_fill_the_block(tmp_path, name, inserts):
    part = {"cup_hole": cup_hole, "knob": knob}[name].make()
    part.Placement = App.Placement(App.Vector(3, -4, 5), App.Rotation(App.Vector(1, 1, 2), 25))
    # the knob as BREP: OCCT's STEP round trip of its spheres gives a valid solid of a
    # seventh of its volume (the CLI reads both)
    path = str(tmp_path / (f"{name}.step" if name != "knob" else f"{name}.brep"))
    (part.exportStep if name != "knob" else part.exportBrep)(path)
    rc, out, err = run(["mould", path, "--out", str(tmp_path / "out"), "--margin", "6"])
    assert rc == 0, err
    (solid,) = out["solids"]
    assert all(solid["checks"].values()), solid["checks"]
    assert len(solid["volumes"]["inserts"]) == inserts
    read = {k: Part.read(f) for k, f in solid["files"].items()}
    assert set(read) == {"core", "cavity"} | {f"insert{k + 1}" for k in range(inserts)}
    total = sum(s.Volume for s in read.values()) + part.Volume
    block = solid["volumes"]["block"]
    assert abs(total - block) <= 1e-6 * block, (total, block)
    for s in read.values():
        assert s.isValid() and len(s.Solids) >= 1
    # no temporary files left beside them
    assert sorted(os.listdir(tmp_path / "out")) == sorted(os.path.basename(f)
                                                         for f in solid["files"].values())


def test_a_part_that_cannot_be_moulded_leaves_no_files(tmp_path):
    """A block with a T-slot across it and a closed inner void: the void cannot be
    reached by any mould (the part has two shells)."""
    box = Part.makeBox(40, 30, 20)
    hollow = box.cut(Part.makeBox(10, 10, 10, App.Vector(15, 10, 5)))
    path = str(tmp_path / "hollow.step")
    hollow.exportStep(path)
    out_dir = tmp_path / "out"
    rc, out, err = run(["mould", path, "--out", str(out_dir)])
    assert rc == 2 and err and "failed" in err["error"], (rc, out, err)
    assert out["failed"] == 1 and "error" in out["solids"][0]
    assert not out_dir.exists() or os.listdir(out_dir) == []


def test_usage_errors(tmp_path):
    for args, words in ((["mould", "x.step", "--out", str(tmp_path), "--margin", "-1"],
                         "margin"),
                        (["mould", str(tmp_path / "missing.step"), "--out", str(tmp_path)],
                         "no such file"),
                        (["mould", "x.step"], "--out")):
        rc, out, err = run(args)
        assert rc == 2 and err and words in err["error"], (args, rc, err)
